//! The MDR cross-check of 3D fretting wear (docs/wear3d.md#the-mdr-cross-check): the SAM wear run
//! of `WearCase::mdr_twin` against `FrettingSimulation` (N = 2001, the reference run of
//! docs/theory-mdr.md#reference-run) at χ = 0.5 and τ = 0.1, 1, 3.
//!
//! `cargo run --release --example wear3d_mdr -- GRID [STEP_FRACTION] [QUARTER] [TAU_END] [STABILITY_FRACTION]`
//! prints one JSON object per record τ and one for the run (time per computed cycle).

use std::time::Instant;

use halfspace::fretting::{FrettingParams, FrettingSimulation};
use halfspace::sam::drivers::fretting_wear3d::{FrettingWear3d, WearCase};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: f64| -> f64 {
        args.get(i)
            .and_then(|s| s.parse::<f64>().ok())
            .unwrap_or(default)
    };
    let grid = arg(0, 64.0) as usize;
    let eta = arg(
        1,
        halfspace::sam::drivers::fretting_wear3d::DEFAULT_STEP_FRACTION,
    );
    let quarter = arg(2, 2.0) as usize;
    let tau_end = arg(3, 3.0);
    let beta = arg(
        4,
        halfspace::sam::drivers::fretting_wear3d::DEFAULT_STABILITY_FRACTION,
    );
    let chi = 0.5;
    let n0 = 1e5;
    let taus: Vec<f64> = [0.1, 1.0, 3.0]
        .into_iter()
        .filter(|t| *t <= tau_end)
        .collect();
    let mdr_start = Instant::now();
    let mut mdr = FrettingSimulation::new(FrettingParams {
        chi,
        tau_end,
        snapshots: taus.clone(),
        ..FrettingParams::default()
    })?;
    mdr.run(|_| false)?;
    let mdr_seconds = mdr_start.elapsed().as_secs_f64();
    let mut case = WearCase::mdr_twin(grid, chi, n0, tau_end, &taus, quarter)?;
    case.step_fraction = eta;
    case.stability_fraction = beta;
    let radius = case.fretting.radius;
    let d = case.approach.unwrap_or(0.0);
    let a0 = (radius * d).sqrt();
    if std::env::var("WEAR3D_PROBE").is_ok() {
        let mut probe = FrettingWear3d::new(case.clone())?;
        probe.step()?;
        let g = *probe.grid();
        let st = probe.solver().problem().state();
        let e_star = case.e_star();
        let p0 = 2.0 * e_star * a0 / (std::f64::consts::PI * radius);
        let f0 = 4.0 * e_star * a0.powi(3) / (3.0 * radius);
        eprintln!(
            "force {} F0 {} approach {} d {} p0 {}",
            st.force, f0, st.approach, d, p0
        );
        let line: Vec<String> = (g.n1 / 2..g.n1)
            .map(|i| {
                let k = i * g.n2 + g.n2 / 2;
                format!(
                    "{:.2}:{:.3}/{:.3}",
                    g.centre(i, g.n2 / 2).0 / a0,
                    st.pressure[k] / p0,
                    st.shear[0][k] / (0.3 * p0)
                )
            })
            .collect();
        eprintln!("{}", line.join(" "));
        return Ok(());
    }
    let start = Instant::now();
    let mut run = FrettingWear3d::new(case)?;
    let verbose = std::env::var("WEAR3D_VERBOSE").is_ok();
    let c_min = run.checkerboard_compliance();
    run.run(|r| {
        if verbose {
            if let Some(row) = r.history().last() {
                eprintln!(
                    "N={} dN={} V~={:.5} hmax/d={:.4} a/a0={:.4} c/a0={:.4} maxrate/d={:.3e} maxpath={:.3e} Cmin={:.3e}",
                    row.cycles,
                    row.delta_cycles,
                    row.wear_volume / (std::f64::consts::PI * a0 * a0 * d),
                    row.max_wear_depth / d,
                    row.contact_radius / a0,
                    row.stick_radius / a0,
                    row.max_rate / d,
                    row.max_slip_path,
                    c_min
                );
            }
        }
        std::ops::ControlFlow::Continue(())
    })?;
    let seconds = start.elapsed().as_secs_f64();
    if verbose {
        let g = *run.grid();
        for rec in run.records() {
            let line: Vec<String> = (g.n1 / 2..g.n1)
                .map(|i| {
                    let k = i * g.n2 + g.n2 / 2;
                    format!(
                        "{:.2}:{:.4}/{:.3}",
                        g.centre(i, g.n2 / 2).0 / a0,
                        rec.wear_depth[k] / d,
                        rec.pressure[k] / 1e9
                    )
                })
                .collect();
            eprintln!("N={} {}", rec.cycles, line.join(" "));
        }
    }
    let g = *run.grid();
    let mgrid = mdr.grid().clone();
    let interp = |profile: &[f64], r: f64| -> f64 {
        let t = mgrid.fractional_index(r).max(0.0);
        let i = (t.floor() as usize).min(mgrid.len() - 2);
        let w = t - i as f64;
        (1.0 - w) * profile[i] + w * profile[i + 1]
    };
    for snap in &mdr.state().snapshots {
        let n = (snap.tau * n0).round() as u64;
        let Some(rec) = run.records().iter().find(|r| r.cycles == n) else {
            continue;
        };
        let Some(row) = run.history().iter().find(|r| r.cycles == n) else {
            continue;
        };
        // The worn profile f̃ = (r²/2R + h)/d cell by cell against the MDR's at the same r̃.
        let (mut max_dev, mut sum_sq, mut count) = (0.0f64, 0.0, 0usize);
        let mut band: Vec<(f64, f64)> = Vec::new();
        let h = 2.0 * g.half1 / a0;
        for i in 0..g.n1 {
            for j in 0..g.n2 {
                let (x, y) = g.centre(i, j);
                let r = x.hypot(y) / a0;
                if r > 1.3 {
                    continue;
                }
                let f3 = (0.5 * r * r * a0 * a0 / radius + rec.wear_depth[i * g.n2 + j]) / d;
                let fm = interp(&snap.profile, r);
                max_dev = max_dev.max((f3 - fm).abs());
                sum_sq += (f3 - fm).powi(2);
                count += 1;
                if (r - 1.0).abs() < h {
                    // Least squares of f̃ = α + β (r̃ − 1) over the band |r̃ − 1| < h: α = f̃(1).
                    band.push((r - 1.0, f3));
                }
            }
        }
        let m = band.len().max(1) as f64;
        let (sx, sy) = band
            .iter()
            .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
        let (mx, my) = (sx / m, sy / m);
        let (sxy, sxx) = band.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
            (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
        });
        let at_a0 = my - (sxy / sxx) * mx;
        // MDR wear volume over π a₀² d: ∫ (f̃ − ξ/2) dξ by the trapezoid rule in ξ = r̃².
        let hx = mgrid.step();
        let worn: Vec<f64> = mgrid
            .coordinates()
            .iter()
            .zip(&snap.profile)
            .map(|(r, f)| f - 0.5 * r * r)
            .collect();
        let v_mdr = hx * (worn.iter().sum::<f64>() - 0.5 * (worn[0] + worn[worn.len() - 1]));
        let v3 = row.wear_volume / (std::f64::consts::PI * a0 * a0 * d);
        println!(
            "{{\"grid\": {grid}, \"step_fraction\": {eta}, \"stability_fraction\": {beta}, \"quarter\": {quarter}, \"tau\": {}, \
             \"a_3d\": {:.5}, \"a_mdr\": {:.5}, \"c_3d\": {:.5}, \"c_exact\": {:.5}, \
             \"f_a0_3d\": {:.5}, \"f_a0_mdr\": {:.5}, \"volume_3d\": {:.5}, \"volume_mdr\": {:.5}, \
             \"profile_max_dev\": {:.5}, \"profile_rms_dev\": {:.5}, \"cell_over_a0\": {:.5}}}",
            snap.tau,
            row.contact_radius / a0,
            snap.contact_radius,
            row.stick_radius / a0,
            (1.0 - chi).sqrt(),
            at_a0,
            interp(&snap.profile, 1.0),
            v3,
            v_mdr,
            max_dev,
            (sum_sq / count.max(1) as f64).sqrt(),
            h,
        );
    }
    let s = run.seconds();
    println!(
        "{{\"grid\": {grid}, \"wear_steps\": {}, \"computed_cycles\": {}, \"seconds\": {seconds:.2}, \
         \"seconds_per_computed_cycle\": {:.4}, \"loading_seconds\": {:.3}, \"mdr_seconds\": {mdr_seconds:.2}, \
         \"final_volume\": {:.6e}, \"limit_volume\": {:.6}}}",
        run.history().len(),
        s.computed,
        s.cycles / s.computed.max(1) as f64,
        s.loading,
        run.wear_volume() / (std::f64::consts::PI * a0 * a0 * d),
        mdr.limit_wear_volume(),
    );
    Ok(())
}
