//! The MDR cross-check of 3D fretting wear (docs/wear3d.md#the-mdr-cross-check): the SAM wear run
//! of [`WearCase::mdr_twin`] (two identical bodies, `ν = 0`, fixed approach, Archard on the gap)
//! against the axisymmetric MDR wear run of `fretting-wear` ([`FrettingSimulation`], the reference
//! run of docs/theory-mdr.md#reference-run: N = 2001, `L = 1.6a₀`, adaptive ROS2) at the same `χ`
//! and `τ = N/N₀`.

use std::ops::ControlFlow;
use std::time::Instant;

use halfspace_fretting::{FrettingError, FrettingParams, FrettingSimulation};
use halfspace_sam::drivers::fretting_wear3d::{FrettingWear3d, WearCase};
use halfspace_sam::SamError;

/// A failure of either run.
#[derive(Debug, thiserror::Error)]
pub enum CrossCheckError {
    /// The 3D run.
    #[error("3D wear run: {0}")]
    Sam(#[from] SamError),
    /// The MDR run.
    #[error("MDR wear run: {0}")]
    Mdr(#[from] FrettingError),
}

/// The cross-check's settings.
#[derive(Debug, Clone, PartialEq)]
pub struct CrossCheckParams {
    /// Cells per side of the 3D run (over `±1.6a₀`).
    pub grid: usize,
    /// `χ = u_A / u_max`.
    pub chi: f64,
    /// `N₀` (cycles per unit `τ`).
    pub n0: f64,
    /// The `τ` compared (the run ends at the largest).
    pub taus: Vec<f64>,
    /// The 3D run's `η` ([`WearCase::step_fraction`]).
    pub step_fraction: f64,
    /// The 3D run's `β` ([`WearCase::stability_fraction`]).
    pub stability_fraction: f64,
    /// Shift steps per quarter cycle of the computed cycle.
    pub quarter: usize,
}

impl Default for CrossCheckParams {
    /// The check: χ = 0.5, τ = 0.1, 1, 3, 64², default steps, two shift steps per quarter,
    /// `N₀ = 10⁵` (the cycle counts are whole numbers to 10⁻⁵ of `τ`).
    fn default() -> Self {
        Self {
            grid: 64,
            chi: 0.5,
            n0: 1e5,
            taus: vec![0.1, 1.0, 3.0],
            step_fraction: halfspace_sam::drivers::fretting_wear3d::DEFAULT_STEP_FRACTION,
            stability_fraction: halfspace_sam::drivers::fretting_wear3d::DEFAULT_STABILITY_FRACTION,
            quarter: 2,
        }
    }
}

/// One compared `τ` (lengths over `a₀`, depths over `d`, volumes over `π a₀² d`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrossCheckRow {
    /// `τ = N/N₀`.
    pub tau: f64,
    /// 3D contact (touching) radius `√(A/π)`.
    pub contact_radius_3d: f64,
    /// MDR contact (touching) radius.
    pub contact_radius_mdr: f64,
    /// 3D stick radius `√(A_s/π)`.
    pub stick_radius_3d: f64,
    /// `f̃(a₀)` of the 3D run: the least-squares line in `r̃` through the cells within one cell of
    /// `r̃ = 1`, at 1.
    pub profile_at_a0_3d: f64,
    /// MDR `f̃(a₀)`.
    pub profile_at_a0_mdr: f64,
    /// 3D worn volume.
    pub volume_3d: f64,
    /// MDR worn volume `∫ (f̃ − ξ/2) dξ` (trapezoid rule, `ξ = r̃²`).
    pub volume_mdr: f64,
    /// `max |f̃_3D − f̃_MDR|` over the cells with `r̃ ≤ 1.3` (the MDR profile interpolated at each
    /// cell centre's `r̃`).
    pub profile_max_deviation: f64,
    /// The root mean square of the same.
    pub profile_rms_deviation: f64,
}

/// The cross-check's result.
#[derive(Debug, Clone, PartialEq)]
pub struct CrossCheck {
    /// One row per `τ`.
    pub rows: Vec<CrossCheckRow>,
    /// The cell size over `a₀`.
    pub cell_over_a0: f64,
    /// Wear steps (computed cycles) of the 3D run.
    pub wear_steps: usize,
    /// Wall time of the 3D run (s).
    pub seconds_3d: f64,
    /// Wall time per computed cycle (s).
    pub seconds_per_cycle: f64,
    /// Wall time of the MDR run (s).
    pub seconds_mdr: f64,
    /// Popov's limit of the worn volume over `π a₀² d`.
    pub limit_volume: f64,
}

/// Runs both and compares them at `params.taus`.
pub fn mdr_cross_check(params: &CrossCheckParams) -> Result<CrossCheck, CrossCheckError> {
    let tau_end = params.taus.iter().cloned().fold(0.0, f64::max);
    let t = Instant::now();
    let mut mdr = FrettingSimulation::new(FrettingParams {
        chi: params.chi,
        tau_end,
        snapshots: params.taus.clone(),
        ..FrettingParams::default()
    })?;
    mdr.run(|_| false)?;
    let seconds_mdr = t.elapsed().as_secs_f64();
    let mut case = WearCase::mdr_twin(
        params.grid,
        params.chi,
        params.n0,
        tau_end,
        &params.taus,
        params.quarter,
    )?;
    case.step_fraction = params.step_fraction;
    case.stability_fraction = params.stability_fraction;
    let radius = case.fretting.radius;
    let d = case.fretting.approach.unwrap_or(f64::NAN);
    let a0 = case.reference_radius();
    let t = Instant::now();
    let mut run = FrettingWear3d::new(case)?;
    run.run(|_| ControlFlow::Continue(()))?;
    let seconds_3d = t.elapsed().as_secs_f64();
    let g = *run.grid();
    let h = 2.0 * g.half1 / a0;
    let mgrid = *mdr.grid();
    let interp = |profile: &[f64], r: f64| -> f64 {
        let t = mgrid.fractional_index(r).max(0.0);
        let i = (t.floor() as usize).min(mgrid.len() - 2);
        let w = t - i as f64;
        (1.0 - w) * profile[i] + w * profile[i + 1]
    };
    let mut rows = Vec::new();
    for snap in &mdr.state().snapshots {
        let n = (snap.tau * params.n0).round() as u64;
        let (Some(rec), Some(row)) = (
            run.records().iter().find(|r| r.cycles == n),
            run.history().iter().find(|r| r.cycles == n),
        ) else {
            continue;
        };
        let (mut max_dev, mut sum_sq, mut count) = (0.0f64, 0.0, 0usize);
        let mut band: Vec<(f64, f64)> = Vec::new();
        for i in 0..g.n1 {
            for j in 0..g.n2 {
                let (x, y) = g.centre(i, j);
                let r = x.hypot(y) / a0;
                if r > 1.3 {
                    continue;
                }
                let f3 = (0.5 * r * r * a0 * a0 / radius + rec.wear_depth[i * g.n2 + j]) / d;
                let dev = f3 - interp(&snap.profile, r);
                max_dev = max_dev.max(dev.abs());
                sum_sq += dev * dev;
                count += 1;
                if (r - 1.0).abs() < h {
                    band.push((r - 1.0, f3));
                }
            }
        }
        let m = band.len().max(1) as f64;
        let (mx, my) = band
            .iter()
            .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / m, b + y / m));
        let (sxy, sxx) = band.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
            (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
        });
        let worn: Vec<f64> = mgrid
            .coordinates()
            .iter()
            .zip(&snap.profile)
            .map(|(r, f)| f - 0.5 * r * r)
            .collect();
        let volume_mdr =
            mgrid.step() * (worn.iter().sum::<f64>() - 0.5 * (worn[0] + worn[worn.len() - 1]));
        rows.push(CrossCheckRow {
            tau: snap.tau,
            contact_radius_3d: row.contact_radius / a0,
            contact_radius_mdr: snap.contact_radius,
            stick_radius_3d: row.stick_radius / a0,
            profile_at_a0_3d: my - (sxy / sxx) * mx,
            profile_at_a0_mdr: interp(&snap.profile, 1.0),
            volume_3d: row.wear_volume / (std::f64::consts::PI * a0 * a0 * d),
            volume_mdr,
            profile_max_deviation: max_dev,
            profile_rms_deviation: (sum_sq / count.max(1) as f64).sqrt(),
        });
    }
    let s = run.seconds();
    Ok(CrossCheck {
        rows,
        cell_over_a0: h,
        wear_steps: run.history().len(),
        seconds_3d,
        seconds_per_cycle: s.cycles / s.computed.max(1) as f64,
        seconds_mdr,
        limit_volume: mdr.limit_wear_volume(),
    })
}
