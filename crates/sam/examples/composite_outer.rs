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
//! Run: `cargo run --release -p halfspace-sam --example composite_outer -- N [increments] [m,η[,g][,t<tol>][,r<depth>][,plain|,gauged] ...]`
//! (`increments` 0: the whole loop; `g`: GMRES; `t<tol>`: the outer tolerance, default 1e-6;
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

// MEASUREMENT CODE (issue 21, "Fewer outer passes: a better predictor of each increment",
// docs/performance.md; reverted by the next commit, not for merge). A variant's field `p<opts>`,
// options joined by `:`: `r<v>` the load-step ratio predictor (`r` = 0 at the first tangential
// increment, `v` at the reversals); `g<m>` guided by the homogeneous loop (run in lockstep);
// `g<m>:own` the same change fitted by the composite's own last `m` traction changes (and
// `:ref` with the reference's converged tractions of the increment as the guide, an oracle);
// `q` quadratic with restarts; `m` mirror of the second quarter; `o<α>` oracle `s + α (r − s)`
// towards the reference's converged state; `f<F>` first pass gauged by F × the previous first
// change; `h<H>` only when that is below H; `s<S>` contact factor S instead of 10⁻²; `j1`/`j2`
// joint scales of the stopping rule (u₁, u₂ / all). COMPOSITE_OUTER_PHASES=1: passes, EIM
// applications and first change per class of increment; =2: per increment the pass changes;
// =3: per pass the component that set the change.
use halfspace_sam::contact::{Alternation, NestedParams, REFERENCE_EIM_CHANGE_FACTOR};
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
    let modes: Vec<Option<String>> = args
        .iter()
        .skip(2)
        .map(|v| {
            v.split(',')
                .find_map(|x| x.strip_prefix('p'))
                .map(String::from)
        })
        .collect();
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
        "reference (per-increment Anderson, depth 3, EIM factor 1e-3)".into(),
        FrettingLoop::with_params(
            LoopCase {
                alternation: Some(Alternation::Plain),
                ..case.clone()
            },
            NestedParams {
                eim_change_factor: REFERENCE_EIM_CHANGE_FACTOR,
                eim: EimParams::default(),
                ..NestedParams::default()
            },
        )
        .unwrap(),
    )];
    for &(m, eta, gmres, tolerance, recycled, alternation) in &specs {
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
            ..base
        };
        variants.push((
            format!(
                "depth {m}, EIM factor {eta:e}, GMRES {gmres}, outer tolerance {tolerance:e}, EIM recycled depth {recycled}, alternation {:?}",
                alternation.unwrap_or(case.alternation_scheme())
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
    // EXPERIMENT: predictor modes per variant (index 0: the reference, secant).
    let mut modes: Vec<Option<String>> = std::iter::once(None).chain(modes).collect();
    modes.resize(variants.len(), None);
    let path = *variants[0].1.path();
    let (nn, qq) = (path.normal_steps, path.quarter);
    let reversals = [nn + qq, nn + 3 * qq];
    let need_guide = modes
        .iter()
        .any(|m| m.as_deref().is_some_and(|m| m.starts_with('g')));
    let mut hom = need_guide.then(|| FrettingLoop::new(case.homogeneous()).unwrap());
    let mut hom_cpu = 0.0;
    for (i, (_, lp)) in variants.iter_mut().enumerate() {
        for opt in modes[i].clone().unwrap_or_default().split(':') {
            let nested = lp.solver_mut().nested_mut().unwrap();
            if let Some(f) = opt.strip_prefix('f') {
                nested.xp_first = Some(f.parse().unwrap());
            }
            if opt == "own" {
                nested.xp_own = true;
            }
            if let Some(f) = opt.strip_prefix('j') {
                nested.xp_joint = f.parse().unwrap();
            }
            if let Some(f) = opt.strip_prefix('h') {
                nested.xp_threshold = f.parse().unwrap();
            }
            if let Some(f) = opt.strip_prefix('s') {
                nested.xp_slackf = f.parse().unwrap();
            }
        }
        if let Some(m) = modes[i].as_deref().and_then(|m| m.strip_prefix('g')) {
            let nested = lp.solver_mut().nested_mut().unwrap();
            nested.xp_mode = halfspace_sam::contact::XpMode::Guided(
                m.split(':').next().unwrap().parse().unwrap(),
            );
            nested.xp_guide.push_back(vec![0.0; 3 * n * n]);
        }
    }
    // Per variant: per class (normal, first tangential, tangential, reversal, after reversal)
    // passes, increments, sum of log10 first change, EIM applications.
    let classes = [
        "normal (first 5)",
        "normal",
        "first tangential",
        "tangential",
        "reversal",
        "after reversal",
    ];
    let mut stats = vec![vec![(0usize, 0usize, 0.0f64, 0usize); classes.len()]; variants.len()];
    let phases = std::env::var("COMPOSITE_OUTER_PHASES").ok();
    let mut cpu = vec![0.0; variants.len()];
    let mut variants_ref_state: Option<(Vec<f64>, [Vec<f64>; 3])> = None;
    let mut ref_tractions: Option<Vec<f64>> = None;
    type State = (Vec<f64>, [Vec<f64>; 3]);
    let mut own: Vec<Option<(State, State)>> = vec![None; variants.len()];
    let mut own2: Vec<Option<State>> = vec![None; variants.len()];
    let mut stored: Vec<Vec<State>> = vec![Vec::new(); variants.len()];
    let mut worst = vec![0.0f64; variants.len()];
    let mut steps = 0;
    loop {
        if limit > 0 && steps == limit {
            break;
        }
        let mut done = false;
        let k = steps;
        if let Some(h) = hom.as_mut() {
            let t = thread_cpu();
            done |= h.step().unwrap().is_none();
            hom_cpu += thread_cpu() - t;
        }
        for (i, (_, lp)) in variants.iter_mut().enumerate() {
            if done {
                break;
            }
            let t = thread_cpu();
            match modes[i].as_deref() {
                Some(m) if m.starts_with('o') && i > 0 && k >= 2 => {
                    // Oracle: the secant prediction moved by α towards the reference's converged
                    // state of this increment (the reference is stepped first).
                    let alpha: f64 = m[1..].split(':').next().unwrap().parse().unwrap();
                    let (eps_ref, u_ref) = {
                        let r = variants_ref_state.as_ref().unwrap();
                        (r.0.clone(), r.1.clone())
                    };
                    let nested = lp.solver_mut().nested_mut().unwrap();
                    let (last, before) = own[i].as_ref().unwrap();
                    let w = halfspace_sam::contact::NestedWarmStart {
                        eigenstrain: last.0.clone(),
                        eigen_displacement: last.1.clone(),
                        previous: before.clone(),
                        committed: 0,
                    };
                    let mix = |x: &[f64], prev: &[f64], r: &[f64]| -> Vec<f64> {
                        x.iter()
                            .zip(prev)
                            .zip(r)
                            .map(|((x, p), r)| {
                                let s = 2.0 * x - p;
                                s + alpha * (r - s)
                            })
                            .collect()
                    };
                    let eps = mix(&w.eigenstrain, &w.previous.0, &eps_ref);
                    let u: Vec<Vec<f64>> = (0..3)
                        .map(|c| mix(&w.eigen_displacement[c], &w.previous.1[c], &u_ref[c]))
                        .collect();
                    nested.set_prediction(&eps, [&u[0], &u[1], &u[2]]).unwrap();
                }
                Some(m) if m.starts_with('m') && k >= nn + 3 * qq => {
                    // Mirror predictor: the state of increment k − 2q reflected x₁ → −x₁.
                    let (se, su) = &stored[i][k - 2 * qq];
                    let nested = lp.solver_mut().nested_mut().unwrap();
                    let g = *nested.problem().grid();
                    let set = nested.inclusions();
                    let index: std::collections::HashMap<(usize, usize), usize> = set
                        .cells
                        .iter()
                        .enumerate()
                        .map(|(c, cell)| ((cell.layer, cell.flat), c))
                        .collect();
                    let mut eps = vec![0.0; se.len()];
                    for (c, cell) in set.cells.iter().enumerate() {
                        let (ii, jj) = (cell.flat / g.n2, cell.flat % g.n2);
                        let mf = (g.n1 - 1 - ii) * g.n2 + jj;
                        let mc = index[&(cell.layer, mf)];
                        for v in 0..6 {
                            let sign = if v == 4 || v == 5 { -1.0 } else { 1.0 };
                            eps[6 * c + v] = sign * se[6 * mc + v];
                        }
                    }
                    let mut u = [vec![0.0; g.len()], vec![0.0; g.len()], vec![0.0; g.len()]];
                    for f in 0..g.len() {
                        let (ii, jj) = (f / g.n2, f % g.n2);
                        let mf = (g.n1 - 1 - ii) * g.n2 + jj;
                        u[0][f] = -su[0][mf];
                        u[1][f] = su[1][mf];
                        u[2][f] = su[2][mf];
                    }
                    nested.set_prediction(&eps, [&u[0], &u[1], &u[2]]).unwrap();
                }
                Some(m) if m.starts_with('q') && k >= 3 => {
                    // Quadratic 3x_n − 3x_{n−1} + x_{n−2}, the secant at the first tangential
                    // increment, at the reversals and the increment after each.
                    let restart = k == nn
                        || k == nn + 1
                        || reversals.contains(&k)
                        || reversals.contains(&(k - 1));
                    let (last, before) = own[i].as_ref().unwrap();
                    let b2 = own2[i].as_ref().unwrap();
                    let ex = |x: &[f64], p: &[f64], pp: &[f64]| -> Vec<f64> {
                        x.iter()
                            .zip(p)
                            .zip(pp)
                            .map(|((x, p), pp)| {
                                if restart {
                                    2.0 * x - p
                                } else {
                                    3.0 * x - 3.0 * p + pp
                                }
                            })
                            .collect()
                    };
                    let eps = ex(&last.0, &before.0, &b2.0);
                    let u: Vec<Vec<f64>> = (0..3)
                        .map(|c| ex(&last.1[c], &before.1[c], &b2.1[c]))
                        .collect();
                    lp.solver_mut()
                        .nested_mut()
                        .unwrap()
                        .set_prediction(&eps, [&u[0], &u[1], &u[2]])
                        .unwrap();
                }
                Some(m) if m.starts_with('g') => {
                    let g = if m.contains("ref") {
                        ref_tractions.clone().unwrap()
                    } else {
                        let s = hom.as_ref().unwrap().solver().problem().state();
                        let mut g = s.pressure.clone();
                        g.extend_from_slice(&s.shear[0]);
                        g.extend_from_slice(&s.shear[1]);
                        g
                    };
                    lp.solver_mut().nested_mut().unwrap().xp_guide.push_back(g);
                }
                Some(m) if m.starts_with('r') => {
                    let rev: f64 = m[1..].split(':').next().unwrap().parse().unwrap();
                    let r = if k == nn {
                        0.0
                    } else if reversals.contains(&k) {
                        rev
                    } else {
                        1.0
                    };
                    lp.solver_mut().nested_mut().unwrap().xp_mode =
                        halfspace_sam::contact::XpMode::Ratio(r);
                }
                _ => {}
            }
            done |= lp.step().unwrap().is_none();
            cpu[i] += thread_cpu() - t;
            if done {
                break;
            }
            {
                let nested = lp.solver().nested().unwrap();
                let now = (
                    nested.eigenstrain().to_vec(),
                    nested.eigen_displacements().clone(),
                );
                if modes[i].as_deref().is_some_and(|m| m.starts_with('m')) {
                    stored[i].push(now.clone());
                    if k + 1 >= nn + 3 * qq {
                        let g = *nested.problem().grid();
                        let src = &stored[i][k - 2 * qq].1;
                        let mut d = [0.0f64; 3];
                        let mut sc = [0.0f64; 3];
                        for f in 0..g.len() {
                            let (ii, jj) = (f / g.n2, f % g.n2);
                            let mf = (g.n1 - 1 - ii) * g.n2 + jj;
                            for c in 0..3 {
                                let sign = if c == 0 { -1.0 } else { 1.0 };
                                d[c] = d[c].max((now.1[c][f] - sign * src[c][mf]).abs());
                                sc[c] = sc[c].max(now.1[c][f].abs());
                            }
                        }
                        println!(
                            "mirror k {k} rel diff u1 {:.2e} u2 {:.2e} u3 {:.2e}",
                            d[0] / sc[0],
                            d[1] / sc[1],
                            d[2] / sc[2]
                        );
                    }
                }
                own[i] = Some(match own[i].take() {
                    Some((last, before)) => {
                        own2[i] = Some(before);
                        (now, last)
                    }
                    None => (now.clone(), now),
                });
            }
            if i == 0 {
                let st = lp.solver().problem().state();
                let mut g = st.pressure.clone();
                g.extend_from_slice(&st.shear[0]);
                g.extend_from_slice(&st.shear[1]);
                ref_tractions = Some(g);
                let nested = lp.solver().nested().unwrap();
                variants_ref_state = Some((
                    nested.eigenstrain().to_vec(),
                    nested.eigen_displacements().clone(),
                ));
            }
            let class = if k < 5 {
                0
            } else if k < nn {
                1
            } else if k == nn {
                2
            } else if reversals.contains(&k) {
                4
            } else if reversals.contains(&(k - 1)) {
                5
            } else {
                3
            };
            let row = lp.rows().last().unwrap();
            let ch = lp.solver().nested().unwrap().pass_changes().to_vec();
            let st = &mut stats[i][class];
            st.0 += row.outer_iterations;
            st.1 += 1;
            st.2 += ch[0].max(1e-300).log10();
            st.3 += row.eim_iterations;
            if phases.as_deref() == Some("3") {
                let pc = &lp.solver().nested().unwrap().xp_pass_comp;
                println!(
                    "v{i} k {k} class {class} passes {} argmax {:?} last-pass diffs/scales {:?}",
                    row.outer_iterations,
                    pc.iter().map(|x| x.0).collect::<Vec<_>>(),
                    pc.last().map(|x| x
                        .1
                        .iter()
                        .map(|(d, s)| format!("{:.1e}/{:.1e}", d, s))
                        .collect::<Vec<_>>())
                );
                if let Some(first) = pc.first() {
                    println!(
                        "   first-pass diffs/scales {:?}",
                        first
                            .1
                            .iter()
                            .map(|(d, s)| format!("{:.1e}/{:.1e}={:.1e}", d, s, d / s))
                            .collect::<Vec<_>>()
                    );
                }
            }
            if phases.as_deref() == Some("2") {
                let coeffs = &lp.solver().nested().unwrap().xp_coeffs;
                println!(
                    "v{i} k {k} class {class} passes {} eim {} changes {} coeffs {:?}",
                    row.outer_iterations,
                    row.eim_iterations,
                    ch.iter()
                        .map(|c| format!("{c:.1e}"))
                        .collect::<Vec<_>>()
                        .join(" "),
                    coeffs.iter().map(|c| format!("{c:.3}")).collect::<Vec<_>>()
                );
            }
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
    if phases.is_some() {
        println!("homogeneous guide CPU {hom_cpu:.1} s");
        println!("| variant | class | increments | passes | passes/incr | EIM/incr | geo-mean first change |");
        for (i, st) in stats.iter().enumerate() {
            for (c, s) in st.iter().enumerate() {
                if s.1 > 0 {
                    println!(
                        "| {i} {:?} | {} | {} | {} | {:.2} | {:.2} | {:.1e} |",
                        modes[i],
                        classes[c],
                        s.1,
                        s.0,
                        s.0 as f64 / s.1 as f64,
                        s.3 as f64 / s.1 as f64,
                        10f64.powf(s.2 / s.1 as f64)
                    );
                }
            }
        }
    }
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
