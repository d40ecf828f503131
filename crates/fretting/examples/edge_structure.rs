//! The structure near the contact edge that sets the adaptive steps of the MDR wear run
//! (docs/fretting-wear.md, "What sets the step"):
//!
//! * `profile N K CHI TAU [DTAU]`: runs to `τ` (adaptive at tol 1e-4, or explicit Euler at `DTAU`)
//!   and prints, on the 40 nodes inside the last contact node and 8 beyond, `g̃ − 1`, `p̃`, the
//!   slip, the second difference of `f̃` and of `g̃`, after a line counting the "holes" (annulus
//!   nodes inside the last contact node with `g̃ ≥ 1`) and the annulus nodes with `p̃ = 0`
//!   (inside the last contact node and inside the outermost loaded node); `DTAU` may be
//!   `ros2:DTAU` for fixed ROS2 steps; `--no-hole-estimate` runs the adaptive steps without the
//!   opened-hole estimate (the scheme before it), `--first-order-fallback` takes the first-order
//!   solution where the result opens holes (experimental), `--no-hole-projection` rejects an
//!   attempt whose result opens holes instead of projecting it onto the closed set;
//! * `rate N K CHI DTAU TAU0 TAU1 NODES`: explicit Euler from 0 to `TAU1`, printing from `TAU0` on
//!   every step's `τ`, last contact node and wear rate `(f̃ⁿ⁺¹ − f̃ⁿ)/Δτ` at the comma-separated
//!   `NODES`.
//!
//! `cargo run --release -p halfspace-fretting --example edge_structure -- profile 2001 0 0.5 0.5 5e-4`

use halfspace_fretting::{FrettingParams, FrettingSimulation, TimeStepping};

type Failure = Box<dyn std::error::Error>;

fn parse<T: std::str::FromStr>(args: &[String], i: usize, what: &str) -> Result<T, Failure> {
    args.get(i)
        .ok_or_else(|| format!("missing {what}"))?
        .parse()
        .map_err(|_| format!("{what}: not a number").into())
}

fn params(nodes: usize, k: f64, chi: f64, tau: f64, dtau: Option<TimeStepping>) -> FrettingParams {
    FrettingParams {
        nodes,
        k,
        chi,
        length: FrettingParams::default_length(chi, k),
        tau_end: tau,
        snapshots: vec![tau],
        stepping: dtau.unwrap_or(TimeStepping::Adaptive { tolerance: 1e-4 }),
        ..FrettingParams::default()
    }
}

/// The last node with `g̃ < 1`.
fn last_contact_node(sim: &mut FrettingSimulation) -> Result<usize, Failure> {
    let g = sim.equivalent_profile()?;
    Ok(g.iter().rposition(|&x| x < 1.0).unwrap_or(0))
}

fn profile(args: &[String]) -> Result<(), Failure> {
    let (nodes, k, chi, tau) = (
        parse(args, 0, "N")?,
        parse(args, 1, "K")?,
        parse(args, 2, "CHI")?,
        parse(args, 3, "TAU")?,
    );
    let stepping = match args.get(4).map(String::as_str) {
        None
        | Some("--no-hole-estimate")
        | Some("--first-order-fallback")
        | Some("--no-hole-projection") => None,
        Some(s) => Some(match s.strip_prefix("ros2:") {
            Some(dtau) => TimeStepping::Fixed {
                dtau: dtau.parse()?,
            },
            None => TimeStepping::ExplicitEuler { dtau: s.parse()? },
        }),
    };
    let mut sim = FrettingSimulation::new(params(nodes, k, chi, tau, stepping))?;
    sim.set_hole_estimate(!args.iter().any(|a| a == "--no-hole-estimate"));
    sim.set_first_order_fallback(args.iter().any(|a| a == "--first-order-fallback"));
    sim.set_hole_projection(!args.iter().any(|a| a == "--no-hole-projection"));
    let start = std::time::Instant::now();
    sim.run(|_| false)?;
    let seconds = start.elapsed().as_secs_f64();
    let snapshot = sim.state().snapshots.last().ok_or("no snapshot")?.clone();
    let last = last_contact_node(&mut sim)?;
    let g = sim.equivalent_profile()?.to_vec();
    let stick = halfspace_fretting::limit::stick_radius(chi);
    let first = sim
        .grid()
        .coordinates()
        .iter()
        .position(|&r| r > stick)
        .unwrap_or(0);
    let holes = (first..last).filter(|&i| g[i] >= 1.0).count();
    let unloaded = (first..last)
        .filter(|&i| snapshot.pressure[i] == 0.0)
        .count();
    let loaded_last = snapshot
        .pressure
        .iter()
        .rposition(|&p| p > 0.0)
        .unwrap_or(0);
    let unloaded_inside_loaded = (first..loaded_last)
        .filter(|&i| snapshot.pressure[i] == 0.0)
        .count();
    println!(
        "τ {tau}: {} steps ({} rejected), {seconds:.2} s, last contact node {last}, annulus nodes {}, holes (g ≥ d inside) {holes}, p = 0 {unloaded}, p = 0 inside the outermost loaded node {unloaded_inside_loaded}",
        sim.state().step,
        sim.state().rejected_steps,
        last.saturating_sub(first)
    );
    let f = &snapshot.profile;
    for i in last.saturating_sub(40).max(1)..(last + 8).min(g.len() - 1) {
        println!(
            "{i} g-1 {:+.4e} p {:.4e} slip {:.4e} d2f {:+.3e} d2g {:+.3e}",
            g[i] - 1.0,
            snapshot.pressure[i],
            snapshot.slip[i],
            f[i + 1] - 2.0 * f[i] + f[i - 1],
            g[i + 1] - 2.0 * g[i] + g[i - 1]
        );
    }
    Ok(())
}

fn rate(args: &[String]) -> Result<(), Failure> {
    let (nodes, k, chi, dtau, from, to) = (
        parse(args, 0, "N")?,
        parse(args, 1, "K")?,
        parse(args, 2, "CHI")?,
        parse::<f64>(args, 3, "DTAU")?,
        parse::<f64>(args, 4, "TAU0")?,
        parse(args, 5, "TAU1")?,
    );
    let watched: Vec<usize> = args
        .get(6)
        .ok_or("missing NODES")?
        .split(',')
        .map(str::parse)
        .collect::<Result<_, _>>()?;
    let mut sim = FrettingSimulation::new(params(
        nodes,
        k,
        chi,
        to,
        Some(TimeStepping::ExplicitEuler { dtau }),
    ))?;
    if let Some(&j) = watched.iter().find(|&&j| j >= nodes) {
        return Err(format!("node {j} is not on the grid of {nodes}").into());
    }
    while sim.tau() < from && !sim.is_finished() {
        sim.step()?;
    }
    let mut before = sim.state().profile.clone();
    while !sim.is_finished() {
        sim.step()?;
        let last = last_contact_node(&mut sim)?;
        let after = &sim.state().profile;
        let rates: Vec<String> = watched
            .iter()
            .map(|&j| format!("{:.5e}", (after[j] - before[j]) / dtau))
            .collect();
        println!("{:.5} {last} {}", sim.tau(), rates.join(" "));
        before.copy_from_slice(after);
    }
    Ok(())
}

fn main() -> Result<(), Failure> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("profile") => profile(&args[1..]),
        Some("rate") => rate(&args[1..]),
        _ => Err(
            "usage: edge_structure profile N K CHI TAU [DTAU | ros2:DTAU | --no-hole-estimate | --first-order-fallback | --no-hole-projection] | rate N K CHI DTAU TAU0 TAU1 NODES"
                .into(),
        ),
    }
}
