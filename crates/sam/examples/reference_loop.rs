//! What the homogeneous reference loop of the composite fretting loop costs (issue 21,
//! docs/performance.md "The 128² composite command outside the EIM (issue 21)"): [LN11]'s case
//! without the fibres at `N²` (the `fretting-loop --case composite` command's reference loop),
//! its increments solved one by one with the contact problem's own solve, reporting per phase
//! (normal loading, fretting) the alternations, the normal iterations and tangential products
//! summed over every alternation, and the wall and process CPU seconds.
//!
//! Run: `cargo run --release -p halfspace-sam --example reference_loop -- N [increments] [plain|gauged] [exact]`
//! (the alternation: `plain`, the Gauss–Seidel alternation; `gauged`, its gauged early solves;
//! default the library's, docs/theory-sam.md#normal-tangential-alternation; `exact`: every
//! tangential solve to the full tolerance, `ContactParams::inexact_alternation` off). With
//! `REFERENCE_LOOP_TRACE=1` one line per increment; `=2` also every alternation's changes
//! (`max|Δp|/max p`, `max|Δq|/(μ max p)`) and the ratio of the larger to the last alternation's
//! (the contraction). With `REFERENCE_LOOP_DUMP=FILE` the state after every
//! increment is appended to `FILE` (`p`, `q₁`, `q₂` as little-endian f64) and `p₀` printed. With
//! `REFERENCE_LOOP_TOLERANCE=T` the alternation stops at `T` instead of 1e-7
//! (`ContactParams::alternation_tolerance`: a tighter-converged reference path). With
//! `REFERENCE_LOOP_WINDOW=M` the loop runs on the central `M × M` cells of the `N²` grid (same
//! cell size): the problem on the window alone, without the whole grid's checks
//! (`ContactProblem::set_window` adds them; docs/performance.md, "A contact window for the 3D
//! loops"); the dump then holds `M²` cells per field.

use halfspace_sam::contact::{Alternation, ContactParams, ContactProblem};
use halfspace_sam::drivers::fretting_loop::LoopCase;
use halfspace_sam::eim::FibreLayout;
use halfspace_sam::kernels::surface::{Body, Compliance};
use halfspace_sam::SurfaceGrid;

#[path = "probe/mod.rs"]
mod probe;
use probe::process_cpu_seconds as cpu;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.first().and_then(|v| v.parse().ok()).unwrap_or(64);
    let limit: usize = args.get(1).and_then(|v| v.parse().ok()).unwrap_or(0);
    let alternation = match args.get(2).map(String::as_str) {
        None => ContactParams::default().alternation,
        Some("plain") => Alternation::Plain,
        Some("gauged") => Alternation::Gauged,
        Some(v) => panic!("{v}: plain or gauged"),
    };
    let mut case = LoopCase::default()
        .composite(FibreLayout::FibreCentred, 2.0)
        .unwrap()
        .homogeneous();
    case.grid = n;
    let a = case.hertz_radius();
    // `REFERENCE_LOOP_WINDOW=M`: the loop on the central `M²` cells only (the same cells: extent
    // scaled by `M/N`), the contact solve a windowed one would run.
    let window: usize = std::env::var("REFERENCE_LOOP_WINDOW").ok().map_or(n, |m| {
        m.parse().expect("REFERENCE_LOOP_WINDOW: a number of cells")
    });
    let grid =
        SurfaceGrid::square(window, case.extent_over_a * a * window as f64 / n as f64).unwrap();
    let geometry = (0..grid.len())
        .map(|k| {
            let (x, y) = grid.centre(k / grid.n2, k % grid.n2);
            (x * x + y * y) / (2.0 * case.radius)
        })
        .collect();
    let compliance =
        Compliance::pair(case.indenter, Body::elastic(case.e, case.nu).unwrap()).unwrap();
    let params = ContactParams {
        friction: case.friction,
        alternation,
        inexact_alternation: args.get(3).map(String::as_str) != Some("exact"),
        alternation_tolerance: std::env::var("REFERENCE_LOOP_TOLERANCE")
            .ok()
            .map_or(ContactParams::default().alternation_tolerance, |t| {
                t.parse().expect("REFERENCE_LOOP_TOLERANCE: a number")
            }),
        ..ContactParams::default()
    };
    let trace = std::env::var("REFERENCE_LOOP_TRACE").unwrap_or_default();
    let mut dump = std::env::var_os("REFERENCE_LOOP_DUMP")
        .map(|f| std::io::BufWriter::new(std::fs::File::create(f).expect("dump file")));
    if dump.is_some() {
        println!("p0 {:e}", case.hertz_pressure());
    }
    let mut problem = ContactProblem::new(grid, compliance, geometry, params).unwrap();
    let path = case.path();
    let total = if limit > 0 {
        limit.min(path.len())
    } else {
        path.len()
    };
    // Per phase: increments, alternations, normal iterations, tangential products, wall, CPU.
    let mut sums = [[0.0f64; 6]; 2];
    for k in 0..total {
        let (load, shift) = path.load(k).unwrap();
        let (t, c) = (std::time::Instant::now(), cpu());
        let info = problem.increment(load, shift).unwrap();
        let phase = usize::from(k >= path.normal_steps);
        let s = &mut sums[phase];
        s[0] += 1.0;
        s[1] += info.alternations as f64;
        s[2] += info.normal_iterations_total as f64;
        s[3] += info.tangential_iterations_total as f64;
        s[4] += t.elapsed().as_secs_f64();
        s[5] += cpu() - c;
        if !trace.is_empty() {
            println!(
                "{k} alternations {} normal {} tangential {} {:.1} ms",
                info.alternations,
                info.normal_iterations_total,
                info.tangential_iterations_total,
                t.elapsed().as_secs_f64() * 1e3
            );
        }
        if trace == "2" {
            print_trace(problem.alternation_trace());
        }
        if let Some(f) = dump.as_mut() {
            use std::io::Write;
            let s = problem.state();
            for v in s.pressure.iter().chain(&s.shear[0]).chain(&s.shear[1]) {
                f.write_all(&v.to_le_bytes()).unwrap();
            }
        }
    }
    let s = problem.state();
    let bits = s
        .pressure
        .iter()
        .chain(&s.shear[0])
        .chain(&s.shear[1])
        .fold(0xcbf2_9ce4_8422_2325u64, |h, v| {
            (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3)
        });
    println!("homogeneous reference loop at {n}², {total} increments, state bits {bits:016x}");
    println!("| phase | increments | alternations | normal iterations | tangential products | wall (s) | CPU (s) |");
    println!("|---|---:|---:|---:|---:|---:|---:|");
    for (name, s) in ["normal loading", "fretting"].iter().zip(&sums) {
        println!(
            "| {name} | {} | {} | {} | {} | {:.2} | {:.2} |",
            s[0], s[1], s[2], s[3], s[4], s[5]
        );
    }
}

/// One line per alternation: its solve, the changes, and the ratio of the larger change to the
/// last alternation's (the observed contraction).
fn print_trace(steps: &[halfspace_sam::contact::AlternationStep]) {
    let mut last = f64::NAN;
    for (i, s) in steps.iter().enumerate() {
        let change = s.pressure_change.max(s.shear_change);
        println!(
            "  solve {} alternation {} dp {:.2e} dq {:.2e} ratio {:.3} normal {} tangential {}",
            s.solve,
            i + 1,
            s.pressure_change,
            s.shear_change,
            change / last,
            s.normal_iterations,
            s.tangential_products,
        );
        last = change;
    }
}
