//! What the outer contact ↔ EIM loop of the composite fretting loop costs with each setting of
//! its inner solves (docs/performance.md#the-composite-fretting-loop-issue-11, issue 21): [LN11]'s stiff
//! fibres (fibre-centred, `E_I = 2E`) at `N²`, the reference nested loop and variants of the
//! Anderson depth `m`, the EIM change factor `η` (each pass's EIM solved to `η` × the last outer
//! change, docs/theory-sam.md#outer-loop-tolerances) and the EIM method, stepped in lockstep
//! (interleaved, so the machine's load falls on all alike; the reference is the nested loop with
//! the EIM factor 10⁻³, `REFERENCE_EIM_CHANGE_FACTOR`; the default is 3·10⁻³): per variant the outer passes, EIM
//! applications, process CPU seconds of the increments, the largest `|Δp|, |Δq|` against the
//! reference over every increment (in `p₀`) and a hash of the final state's bits (equal hashes
//! from two binaries: bit for bit the same loop).
//!
//! Run: `cargo run --release -p halfspace-sam --example composite_outer -- N [increments] [m,η[,g][,t<tol>][,r<depth>][,plain|,gauged][,v|,c<s>] ...]`
//! (`increments` 0: the whole loop; `g`: GMRES; `t<tol>`: the outer tolerance, default 1e-6;
//! `v`: the verified stopping rule, `c<s>`: the contraction rule with safety `s`
//! (`OuterStopping`; default the library's, the contraction rule with safety 1);
//! `plain`, `gauged`: the contact solves' alternation scheme, `LoopCase::alternation`, default the
//! library's — the reference variant always runs the plain one;
//! `r<depth>`: block Jacobi with Anderson mixing recycled across an increment's passes,
//! `EimParams::recycled_depth`, default `DEFAULT_EIM_RECYCLED_DEPTH` = 5, `r0` the plain
//! iteration; default variant `3,3e-3`, the library's defaults). The reference is the plain
//! block Jacobi with the EIM factor 10⁻³. Single thread for CPU
//! comparisons: `RAYON_NUM_THREADS=1`.
//!
//! With `COMPOSITE_OUTER_DUMP=DIR` every variant's state after every increment is appended to
//! `DIR/variant<i>.bin` (`p`, `q₁`, `q₂` as little-endian f64, `N²` values each) and `p₀` written
//! to `DIR/p0.txt`: two binaries' paths can then be compared increment by increment.
//!
//! With `COMPOSITE_OUTER_TRACE=1` the last variant's alternations are printed after every
//! increment: per outer pass (`solve`) and alternation the changes `max|Δp|/max p` and
//! `max|Δq|/(μ max p)` ([`halfspace_sam::contact::ContactProblem::alternation_trace`]).

use halfspace_sam::contact::{
    Alternation, NestedParams, OuterStopping, REFERENCE_EIM_CHANGE_FACTOR,
};
use halfspace_sam::drivers::fretting_loop::{FrettingLoop, LoopCase};
use halfspace_sam::eim::{EimMethod, EimParams, FibreLayout};

#[path = "probe/mod.rs"]
mod probe;
use probe::process_cpu_seconds as thread_cpu;

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n = args.first().and_then(|v| v.parse().ok()).unwrap_or(32);
    let limit = args.get(1).and_then(|v| v.parse().ok()).unwrap_or(0);
    // Variants `m,η[,g][,t<tol>][,r<depth>]`: Anderson depth, EIM change factor, `g` for GMRES
    // instead of the automatic EIM method (block Jacobi for these fibres), `t<tol>` for the outer
    // tolerance (default 1e-6), `r<depth>` for the EIM's recycled Anderson depth (default:
    // `NestedParams::default()`'s, 5; `r0` the plain block Jacobi).
    let specs: Vec<(usize, f64, bool, f64, usize, Option<Alternation>)> = args
        .iter()
        .skip(2)
        .map(|v| {
            let f: Vec<&str> = v.split(',').collect();
            let tolerance = f[2..]
                .iter()
                .find_map(|x| x.strip_prefix('t'))
                .map_or(NestedParams::default().tolerance, |t| t.parse().unwrap());
            let recycled = f[2..]
                .iter()
                .find_map(|x| x.strip_prefix('r'))
                .map_or(NestedParams::default().eim.recycled_depth, |t| {
                    t.parse().unwrap()
                });
            (
                f[0].parse().unwrap(),
                f[1].parse().unwrap(),
                f[2..].contains(&"g"),
                tolerance,
                recycled,
                if f[2..].contains(&"gauged") {
                    Some(Alternation::Gauged)
                } else if f[2..].contains(&"plain") {
                    Some(Alternation::Plain)
                } else {
                    None
                },
            )
        })
        .collect();
    let specs = if specs.is_empty() {
        let base = NestedParams::default();
        vec![(
            3,
            base.eim_change_factor,
            false,
            base.tolerance,
            base.eim.recycled_depth,
            None,
        )]
    } else {
        specs
    };
    let mut case = LoopCase::default()
        .composite(FibreLayout::FibreCentred, 2.0)
        .unwrap();
    case.grid = n;
    let p0 = case.hertz_pressure();
    let mut variants: Vec<(String, FrettingLoop)> = vec![(
        "reference (per-increment Anderson, depth 3, EIM factor 1e-3, verified stopping)".into(),
        FrettingLoop::with_params(
            LoopCase {
                alternation: Some(Alternation::Plain),
                ..case.clone()
            },
            NestedParams {
                eim_change_factor: REFERENCE_EIM_CHANGE_FACTOR,
                eim: EimParams::default(),
                stopping: OuterStopping::Verified,
                ..NestedParams::default()
            },
        )
        .unwrap(),
    )];
    for (&(m, eta, gmres, tolerance, recycled, alternation), spec) in specs
        .iter()
        .zip(args.iter().skip(2).chain(std::iter::repeat(&String::new())))
    {
        // `c<safety>`: the contraction stopping rule with that safety; `v`: the verified rule;
        // neither: the library's default (`NestedParams::default().stopping`).
        let stop: Option<f64> = spec
            .split(',')
            .skip(2)
            .find_map(|x| x.strip_prefix('c'))
            .map(|t| t.parse().unwrap());
        let base = NestedParams::default();
        let params = NestedParams {
            eim: EimParams {
                method: if gmres {
                    EimMethod::Gmres
                } else {
                    base.eim.method
                },
                recycled_depth: recycled,
                ..base.eim
            },
            anderson_depth: m,
            eim_change_factor: eta,
            tolerance,
            stopping: match stop {
                Some(safety) => OuterStopping::Contraction { safety },
                None if spec.split(',').any(|x| x == "v") => OuterStopping::Verified,
                None => base.stopping,
            },
            ..base
        };
        variants.push((
            format!(
                "depth {m}, EIM factor {eta:e}, GMRES {gmres}, outer tolerance {tolerance:e}, EIM recycled depth {recycled}, alternation {:?}, stopping {:?}",
                alternation.unwrap_or(case.alternation_scheme()),
                params.stopping
            ),
            FrettingLoop::with_params(
                LoopCase {
                    alternation,
                    ..case.clone()
                },
                params,
            )
            .unwrap(),
        ));
    }
    // Optional dump of every increment's state (module docs).
    let dump = std::env::var_os("COMPOSITE_OUTER_DUMP").map(std::path::PathBuf::from);
    let mut files: Vec<std::io::BufWriter<std::fs::File>> = Vec::new();
    if let Some(dir) = &dump {
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(dir.join("p0.txt"), format!("{p0:e}\n")).unwrap();
        for i in 0..variants.len() {
            let f = std::fs::File::create(dir.join(format!("variant{i}.bin"))).unwrap();
            files.push(std::io::BufWriter::new(f));
        }
    }
    let mut cpu = vec![0.0; variants.len()];
    let mut worst = vec![0.0f64; variants.len()];
    let mut steps = 0;
    loop {
        if limit > 0 && steps == limit {
            break;
        }
        let mut done = false;
        for (i, (_, lp)) in variants.iter_mut().enumerate() {
            let t = thread_cpu();
            done |= lp.step().unwrap().is_none();
            cpu[i] += thread_cpu() - t;
        }
        if done {
            break;
        }
        steps += 1;
        if std::env::var_os("COMPOSITE_OUTER_TRACE").is_some() {
            let (_, lp) = variants.last().expect("the reference at least");
            println!("increment {steps}");
            for s in lp.solver().problem().alternation_trace() {
                println!(
                    "  pass {} dp {:.2e} dq {:.2e} normal {} tangential {}",
                    s.solve + 1,
                    s.pressure_change,
                    s.shear_change,
                    s.normal_iterations,
                    s.tangential_products
                );
            }
        }
        for ((_, lp), f) in variants.iter().zip(files.iter_mut()) {
            use std::io::Write;
            let s = lp.solver().problem().state();
            for v in s.pressure.iter().chain(&s.shear[0]).chain(&s.shear[1]) {
                f.write_all(&v.to_le_bytes()).unwrap();
            }
        }
        let reference = variants[0].1.solver().problem().state().clone();
        for (i, (_, lp)) in variants.iter().enumerate().skip(1) {
            let s = lp.solver().problem().state();
            worst[i] = worst[i]
                .max(max_diff(&s.pressure, &reference.pressure))
                .max(max_diff(&s.shear[0], &reference.shear[0]))
                .max(max_diff(&s.shear[1], &reference.shear[1]));
        }
    }
    println!("composite loop (stiff fibres, fibre-centred) at {n}², {steps} increments");
    println!(
        "| variant | outer passes | EIM applications | CPU (s) | contact / EIM / surface fields (s) | alternations / normal / tangential iterations (last alternation) | normal / tangential iterations (all alternations) | max |Δp|, |Δq| / p₀ | state bits |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---|");
    for (i, (name, lp)) in variants.iter().enumerate() {
        let outer: usize = lp.rows().iter().map(|r| r.outer_iterations).sum();
        let eim: usize = lp.rows().iter().map(|r| r.eim_iterations).sum();
        // The final state's bits (FNV-1a of p, q₁, q₂): equal across binaries = bit for bit.
        let s = lp.solver().problem().state();
        let bits = s
            .pressure
            .iter()
            .chain(&s.shear[0])
            .chain(&s.shear[1])
            .fold(0xcbf2_9ce4_8422_2325u64, |h, v| {
                (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3)
            });
        // Wall seconds of the parts (docs/performance.md: one thread, so close to CPU).
        let t = lp.seconds();
        let w = lp.contact_work();
        println!(
            "| {name} | {outer} | {eim} | {:.1} | {:.1} / {:.1} / {:.1} | {} / {} / {} | {} / {} | {:.2e} | {bits:016x} |",
            cpu[i],
            t.contact,
            t.eim + t.traction_strain,
            t.disturbance,
            w.alternations,
            w.normal_iterations,
            w.tangential_iterations,
            w.normal_iterations_total,
            w.tangential_iterations_total,
            worst[i] / p0
        );
    }
}
