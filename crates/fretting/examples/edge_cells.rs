//! The MDR wear run with and without the experimental edge cells (docs/fretting-wear.md,
//! "Edge cells"): steps, rejections, GMRES iterations, final radii and volume, seconds.
//!
//! `cargo run --release -p halfspace-fretting --example edge_cells -- N K CHI on|off [TAU_END]`
//! (the default run: `2001 0 0.5 on`; CPU time: run it under `/usr/bin/time`;
//! `GAP_TRANSFORM=piecewise-linear` for that profile transform).

use halfspace_fretting::{FrettingParams, FrettingSimulation, GapTransform};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let get = |i: usize, default: &str| args.get(i).cloned().unwrap_or_else(|| default.into());
    let nodes: usize = get(0, "2001").parse()?;
    let k: f64 = get(1, "0").parse()?;
    let chi: f64 = get(2, "0.5").parse()?;
    let on = get(3, "on") == "on";
    let tau_end: f64 = get(4, "30").parse()?;
    let params = FrettingParams {
        nodes,
        k,
        chi,
        length: FrettingParams::default_length(chi, k),
        tau_end,
        gap_transform: match std::env::var("GAP_TRANSFORM") {
            Ok(name) => GapTransform::from_name(&name).ok_or("GAP_TRANSFORM: unknown name")?,
            Err(_) => GapTransform::CentralDifferences,
        },
        ..FrettingParams::default()
    };
    let start = std::time::Instant::now();
    let mut sim = FrettingSimulation::new(params)?;
    sim.set_edge_cell_rates(on);
    sim.run(|_| false)?;
    let seconds = start.elapsed().as_secs_f64();
    let state = sim.state();
    let r_star = sim.limit_contact_radius();
    let cell = sim.grid().step() / (2.0 * r_star);
    let a = *state.contact_radius_history.last().unwrap_or(&0.0);
    println!(
        "{{\"n\":{nodes},\"k\":{k},\"chi\":{chi},\"edge_cells\":{on},\"steps\":{},\"rejected_steps\":{},\
         \"krylov_iterations\":{},\"contact_radius_over_a0\":{a},\"cells_beyond_limit\":{:.3},\
         \"max_contact_radius_over_a0\":{},\"loaded_radius_over_a0\":{},\"profile_at_a0_over_d\":{},\"volume_over_limit\":{},\
         \"seconds\":{seconds}}}",
        state.step,
        state.rejected_steps,
        sim.krylov_iterations(),
        (a - r_star) / cell,
        state
            .contact_radius_history
            .iter()
            .copied()
            .fold(0.0, f64::max),
        state.loaded_radius_history.last().unwrap_or(&0.0),
        sim.profile_at_a0(),
        sim.wear_volume() / sim.limit_wear_volume()
    );
    Ok(())
}
