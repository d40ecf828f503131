//! The MDR cross-check of 3D fretting wear (docs/wear3d.md#the-mdr-cross-check,
//! `halfspace::wear3d_mdr`): prints one JSON object per compared τ and one for the run.
//!
//! `cargo run --release --example wear3d_mdr -- GRID [STEP_FRACTION] [QUARTER] [TAU_END] [STABILITY_FRACTION]`

use halfspace::wear3d_mdr::{mdr_cross_check, CrossCheckParams};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let defaults = CrossCheckParams::default();
    let arg = |i: usize, default: f64| -> f64 {
        args.get(i)
            .and_then(|s| s.parse::<f64>().ok())
            .unwrap_or(default)
    };
    let tau_end = arg(3, 3.0);
    let params = CrossCheckParams {
        grid: arg(0, defaults.grid as f64) as usize,
        step_fraction: arg(1, defaults.step_fraction),
        quarter: arg(2, defaults.quarter as f64) as usize,
        taus: defaults
            .taus
            .iter()
            .copied()
            .filter(|t| *t <= tau_end)
            .collect(),
        stability_fraction: arg(4, defaults.stability_fraction),
        ..defaults
    };
    let c = mdr_cross_check(&params)?;
    for r in &c.rows {
        println!(
            "{{\"grid\": {}, \"step_fraction\": {}, \"stability_fraction\": {}, \"quarter\": {}, \
             \"tau\": {}, \"a_3d\": {:.5}, \"a_mdr\": {:.5}, \"c_3d\": {:.5}, \"c_exact\": {:.5}, \
             \"f_a0_3d\": {:.5}, \"f_a0_mdr\": {:.5}, \"volume_3d\": {:.5}, \"volume_mdr\": {:.5}, \
             \"profile_max_dev\": {:.5}, \"profile_rms_dev\": {:.5}, \"cell_over_a0\": {:.5}}}",
            params.grid,
            params.step_fraction,
            params.stability_fraction,
            params.quarter,
            r.tau,
            r.contact_radius_3d,
            r.contact_radius_mdr,
            r.stick_radius_3d,
            (1.0 - params.chi).sqrt(),
            r.profile_at_a0_3d,
            r.profile_at_a0_mdr,
            r.volume_3d,
            r.volume_mdr,
            r.profile_max_deviation,
            r.profile_rms_deviation,
            c.cell_over_a0,
        );
    }
    println!(
        "{{\"grid\": {}, \"wear_steps\": {}, \"seconds_3d\": {:.2}, \"seconds_per_computed_cycle\": {:.4}, \
         \"seconds_mdr\": {:.2}, \"limit_volume\": {:.6}}}",
        params.grid, c.wear_steps, c.seconds_3d, c.seconds_per_cycle, c.seconds_mdr, c.limit_volume
    );
    Ok(())
}
