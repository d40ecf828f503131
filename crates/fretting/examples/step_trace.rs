//! Where the adaptive steps of the MDR wear run go (docs/fretting-wear.md, "Time integration"):
//! every attempt of the error-controlled ROS2 steps through the attempt observer, written as CSV
//! (τ, Δτ, error ratio, accepted, the node of the largest error and the contact edge at the
//! start, the second stage's trial and the end, GMRES iterations, the holes the result opens, the
//! three parts of the error estimate, whether the result is the first-order solution, the
//! projection's `λ` and the sub-cell edge `a/a₀` at the start and of the result), and a
//! summary on stdout (with the holes at the end).
//!
//! `cargo run --release -p halfspace-fretting --example step_trace -- N K CHI [TOL] [TAU_END] [CSV]`
//! (switches by environment: `PERTURB=SEED`, `HOLE_ESTIMATE=off`, `FIRST_ORDER_FALLBACK=on`,
//! `HOLE_PROJECTION=off`, `RECYCLED_STAGE2=on`, `PREFIX_RATE=off`, `MASKED_BAND=off`,
//! `GAP_TRANSFORM=piecewise-linear`, `EDGE_CELLS=on`)

use std::io::Write;
use std::sync::{Arc, Mutex};

use halfspace_fretting::{
    FrettingParams, FrettingSimulation, GapTransform, StepAttempt, TimeStepping,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let get = |i: usize, default: &str| args.get(i).cloned().unwrap_or_else(|| default.into());
    let nodes: usize = get(0, "2001").parse()?;
    let k: f64 = get(1, "0").parse()?;
    let chi: f64 = get(2, "0.5").parse()?;
    let tolerance: f64 = get(3, "1e-4").parse()?;
    let tau_end: f64 = get(4, "30").parse()?;
    let csv = get(5, "step_trace.csv");
    let params = FrettingParams {
        nodes,
        k,
        chi,
        length: FrettingParams::default_length(chi, k),
        tau_end,
        stepping: TimeStepping::Adaptive { tolerance },
        gap_transform: match std::env::var("GAP_TRANSFORM") {
            Ok(name) => GapTransform::from_name(&name).ok_or("GAP_TRANSFORM: unknown name")?,
            Err(_) => GapTransform::CentralDifferences,
        },
        edge_cells: match std::env::var("EDGE_CELLS").as_deref() {
            Ok("on") => true,
            Ok("off") | Err(_) => false,
            Ok(_) => return Err("EDGE_CELLS: on or off".into()),
        },
        ..FrettingParams::default()
    };
    let attempts: Arc<Mutex<Vec<StepAttempt>>> = Arc::default();
    let mut sim = FrettingSimulation::new(params.clone())?;
    // `PERTURB=SEED`: the start profile multiplied by `1 + 1e-13 u_i`, `u_i` uniform in [−1, 1)
    // from the seed — another step sequence, as another rounding gives (docs/fretting-wear.md,
    // "The grazing-phase stepping tests over perturbed step sequences").
    if let Ok(seed) = std::env::var("PERTURB") {
        let mut state = sim.state().clone();
        let mut x: u64 = seed
            .parse::<u64>()?
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        for f in state.profile.iter_mut() {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let u = (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
            *f *= 1.0 + 1e-13 * u;
        }
        sim = FrettingSimulation::resume(params, state)?;
    }
    // `HOLE_ESTIMATE=off`: the adaptive steps without the opened-hole estimate.
    sim.set_hole_estimate(std::env::var("HOLE_ESTIMATE").map_or(true, |v| v != "off"));
    // `FIRST_ORDER_FALLBACK=on`: an attempt whose result opens holes takes its first-order
    // solution (experimental, off by default).
    sim.set_first_order_fallback(std::env::var("FIRST_ORDER_FALLBACK").is_ok_and(|v| v == "on"));
    // `HOLE_PROJECTION=off`: an attempt whose result opens holes above the tolerance is
    // rejected instead of projected onto the closed set (the scheme before).
    sim.set_hole_projection(std::env::var("HOLE_PROJECTION").map_or(true, |v| v != "off"));
    // `RECYCLED_STAGE2=on`: the second stage's GMRES continues the first stage's Krylov space
    // (experimental, off by default).
    sim.set_recycled_second_stage(std::env::var("RECYCLED_STAGE2").is_ok_and(|v| v == "on"));
    // `MASKED_BAND=off`: the preconditioner's band without the closed nodes' part taken out
    // (the path before).
    sim.set_masked_band(std::env::var("MASKED_BAND").map_or(true, |v| v != "off"));
    // `PREFIX_RATE=off`: the rate's `g` on the whole grid (the prefix is the default).
    sim.set_prefix_rate(!std::env::var("PREFIX_RATE").is_ok_and(|v| v == "off"));
    // `SLIDING=on|off`: the sliding mode of the contact edge's last node in the stages
    // (`FrettingSimulation::set_sliding_edge`; unset: the library's default).
    if let Ok(v) = std::env::var("SLIDING") {
        sim.set_sliding_edge(v == "on");
    }
    let sink = Arc::clone(&attempts);
    let start = std::time::Instant::now();
    // The wall time since the run's start at each attempt's end (the time of a phase of the run
    // is the difference across it).
    let clock: Arc<Mutex<Vec<f64>>> = Arc::default();
    let ticks = Arc::clone(&clock);
    sim.set_attempt_observer(Box::new(move |a| {
        sink.lock().expect("lock").push(*a);
        ticks
            .lock()
            .expect("lock")
            .push(start.elapsed().as_secs_f64());
    }));
    // The attempts are written also when the run fails.
    let run = sim.run(|_| false);
    let seconds = start.elapsed().as_secs_f64();
    let attempts = attempts.lock().expect("lock");
    let clock = clock.lock().expect("lock");
    let mut out = std::io::BufWriter::new(std::fs::File::create(&csv)?);
    writeln!(
        out,
        "tau,dtau,ratio,accepted,worst,edge_start,edge_trial,edge_end,gmres1,gmres2,opened_holes,err_ros2,err_outside,err_hole,first_order,projection,edge_radius_start,edge_radius_end,seconds,sliding_node"
    )?;
    for (a, t) in attempts.iter().zip(clock.iter()) {
        writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            a.tau,
            a.dtau,
            a.error_ratio,
            u8::from(a.accepted),
            a.worst_node,
            a.edge_start,
            a.edge_trial,
            a.edge_end,
            a.krylov_iterations.0,
            a.krylov_iterations.1,
            a.opened_holes,
            a.error_terms[0],
            a.error_terms[1],
            a.error_terms[2],
            u8::from(a.first_order),
            a.projection,
            a.edge_radius_start,
            a.edge_radius_end,
            t,
            a.sliding_node.map_or(-1, |s| s as i64)
        )?;
    }
    run?;
    // Holes at the end: annulus nodes inside the last contact node with g ≥ d.
    let stick = halfspace_fretting::limit::stick_radius(chi);
    let first = sim
        .grid()
        .coordinates()
        .iter()
        .position(|&r| r > stick)
        .unwrap_or(0);
    let evaluations = sim.rate_evaluations();
    let g = sim.equivalent_profile()?;
    let last = g.iter().rposition(|&x| x < 1.0).unwrap_or(0);
    let holes = (first..last).filter(|&i| g[i] >= 1.0).count();
    let state = sim.state();
    let r_star = sim.limit_contact_radius();
    let cell = sim.grid().step() / (2.0 * r_star);
    let a = *state.contact_radius_history.last().unwrap_or(&0.0);
    println!(
        "steps {} ({} rejected), attempts {}, GMRES {} ({:.3} an attempt), a/a0 {a:.6} ({:+.2} cells from r*), V {:.5e}, V/V∞ − 1 {:+.3e}, holes {holes}, {seconds:.2} s, probes {}, rate evaluations {} ({} on a prefix)",
        state.step,
        state.rejected_steps,
        attempts.len(),
        sim.krylov_iterations(),
        sim.krylov_iterations() as f64 / attempts.len() as f64,
        (a - r_star) / cell,
        sim.wear_volume(),
        sim.wear_volume() / sim.limit_wear_volume() - 1.0,
        sim.band_probes(),
        evaluations.0,
        evaluations.1
    );
    Ok(())
}
