//! The graded run's state at the chattering edge (docs/performance.md, "What sets the graded run's
//! steps"): runs k = −0.5, χ = 0.9 (or K, CHI) adaptively (tol 1e-4) to `TAU` and prints, on the 40 nodes
//! before the last contact node and 8 after it, `g − d`, the wear depth `f − f₀` and its second
//! difference (whose alternating sign is the odd–even mode that the central differences of
//! `g = P[D f]` do not see).
//!
//! `cargo run --release -p halfspace-fretting --example annulus_probe -- [N] [TAU] [euler|ros2]
//! [K] [CHI]` (`euler`: explicit Euler at half its stability bound, the reference path; K and
//! CHI default to the graded run's −0.5 and 0.9)

use halfspace_fretting::{FrettingParams, FrettingSimulation, TimeStepping};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let nodes: usize = args.first().map_or(Ok(2001), |a| a.parse())?;
    let tau: f64 = args.get(1).map_or(Ok(5.0), |a| a.parse())?;
    let k: f64 = args.get(3).map_or(Ok(-0.5), |a| a.parse())?;
    let chi: f64 = args.get(4).map_or(Ok(0.9), |a| a.parse())?;
    let length = FrettingParams::default_length(chi, k);
    let stepping = if args.get(2).is_some_and(|a| a == "euler") {
        TimeStepping::ExplicitEuler {
            dtau: 0.5 * FrettingParams::default_step(nodes, length, k),
        }
    } else {
        TimeStepping::Adaptive { tolerance: 1e-4 }
    };
    let params = FrettingParams {
        nodes,
        k,
        chi,
        length,
        tau_end: tau,
        stepping,
        ..FrettingParams::default()
    };
    let mut sim = FrettingSimulation::new(params)?;
    let start = sim.state().profile.clone();
    sim.run(|_| false)?;
    let r = sim.grid().coordinates().to_vec();
    let r_star = sim.limit_contact_radius();
    let g = sim.equivalent_profile()?.to_vec();
    let last = g.iter().rposition(|&x| x < 1.0).unwrap_or(0);
    let wear: Vec<f64> = sim
        .state()
        .profile
        .iter()
        .zip(&start)
        .map(|(f, f0)| f - f0)
        .collect();
    println!(
        "tau {tau}: {} steps, last contact node {last} (r/a0 {:.5}), r* {r_star:.5}",
        sim.state().step,
        r[last]
    );
    println!("node,r,g_minus_d,wear,wear_second_difference");
    for i in last.saturating_sub(40).max(1)..(last + 9).min(g.len() - 1) {
        let second = wear[i + 1] - 2.0 * wear[i] + wear[i - 1];
        println!(
            "{i},{:.6},{:+.4e},{:+.5e},{:+.3e}",
            r[i],
            g[i] - 1.0,
            wear[i],
            second
        );
    }
    Ok(())
}
