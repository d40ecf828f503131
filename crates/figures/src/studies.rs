//! The figures of `halfspace study` (the docs' convergence and comparison figures), from the
//! studies' series in `halfspace_cases::studies`.

use std::path::Path;

use halfspace_cases::studies::{
    Convergence, FrettingLimit, ProfileComparison, TransformTiming, TRANSFORM_TIMING_TITLE,
};
use halfspace_fretting::studies::GradedWearStudy;

use crate::draw::{self, Curves, DrawResult};
use crate::FigureError;

fn named(path: &Path, r: DrawResult) -> Result<(), FigureError> {
    r.map_err(|e| FigureError::Draw(format!("{}: {e}", path.display())))
}

/// The errors against N (log–log) with a reference slope of the study's order.
pub fn convergence(path: &Path, study: &Convergence) -> Result<(), FigureError> {
    named(
        path,
        draw::convergence(
            path,
            study.title,
            &study.n,
            &study.series,
            study.reference_order,
        ),
    )
}

/// The paper's Fig. 1: seconds per transform against N, log–log with slopes 1 and 2.
pub fn transform_timing(path: &Path, study: &TransformTiming) -> Result<(), FigureError> {
    named(
        path,
        draw::loglog(
            path,
            TRANSFORM_TIMING_TITLE,
            "seconds per transform",
            &study.n,
            &study.series,
            &[1.0, 2.0],
        ),
    )
}

/// Graded Hertz: p(r) and u(r) for each k, two panels.
pub fn graded_hertz(path: &Path, study: &ProfileComparison) -> Result<(), FigureError> {
    named(
        path,
        draw::curves(
            path,
            "Graded Hertz: E(z) = E0 (z/z0)^k, E0 = z0 = R = 1, ν = 0.3, δ = 0.01",
            "r",
            ("pressure p", &study.pressures),
            ("surface displacement u", &study.displacements),
            false,
        ),
    )
}

/// MDR (lines) against the FE references (markers): pressure and displacement, two panels.
pub fn fe_comparison(path: &Path, study: &ProfileComparison) -> Result<(), FigureError> {
    named(
        path,
        draw::curves(
            path,
            "MDR (lines) against scikit-fem (FE): sphere R = 10a, E0 = 1, ν = 0.3",
            "r / a",
            ("contact pressure p", &study.pressures),
            ("surface displacement u", &study.displacements),
            true,
        ),
    )
}

/// a/a0 against τ for each χ, each followed by its limit r*/a0 (paired: one colour per χ).
pub fn fretting_limit(path: &Path, study: &FrettingLimit) -> Result<(), FigureError> {
    let mut all = Vec::new();
    for (c, l) in study.radii.iter().zip(&study.limits) {
        all.push(c.clone());
        all.push(l.clone());
    }
    named(
        path,
        draw::curves(
            path,
            "Fretting wear: contact radius a/a0 against τ = N/N0 (limits r*/a0)",
            "τ",
            ("a / a0", &all),
            ("a / a0", &[]),
            true,
        ),
    )
}

/// The graded-wear figures: the limiting wear depths at `path`, the final wear volume against
/// the amplitude (log–log) at `STEM-volume.EXT` and against χ at `STEM-volume-chi.EXT`.
pub fn graded_wear(path: &Path, s: &GradedWearStudy) -> Result<(), FigureError> {
    let profiles: Vec<(String, Vec<(f64, f64)>)> = s
        .curves
        .iter()
        .map(|c| {
            (
                format!("k = {:+.2}, r*/a0 = {:.4}", c.k, c.r_star),
                c.wear_depth.clone(),
            )
        })
        .collect();
    let volumes: Vec<(String, Vec<(f64, f64)>)> = s
        .curves
        .iter()
        .map(|c| {
            let pts = c
                .volume_against_amplitude
                .iter()
                .map(|(u, v)| (u.log10(), v.log10()))
                .collect();
            (format!("k = {:+.2}", c.k), pts)
        })
        .collect();
    let none: &Curves = &[];
    named(
        path,
        draw::curves(
            path,
            &format!(
                "Graded fretting wear: limiting wear depth (f∞ − f0)/d at χ = {} (E ∝ z^k)",
                s.chi
            ),
            "r / a0",
            ("(f∞ − f0) / d", &profiles),
            ("", none),
            false,
        ),
    )?;
    let stem = path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("graded-wear");
    let ext = path.extension().and_then(|s| s.to_str()).unwrap_or("svg");
    let volume_path = path.with_file_name(format!("{stem}-volume.{ext}"));
    named(
        &volume_path,
        draw::curves(
            &volume_path,
            &format!(
                "Final wear volume log10 V∞/(π a0² d) against log10 u_A/(μ d) (ν = {}; curves end at gross slip)",
                s.nu
            ),
            "log10 u_A / (μ d)",
            ("log10 V∞ / (π a0² d)", &volumes),
            ("", none),
            false,
        ),
    )?;
    let by_chi: Vec<(String, Vec<(f64, f64)>)> = s
        .curves
        .iter()
        .map(|c| (format!("k = {:+.2}", c.k), c.volume_against_chi.clone()))
        .collect();
    let chi_path = path.with_file_name(format!("{stem}-volume-chi.{ext}"));
    named(
        &chi_path,
        draw::curves(
            &chi_path,
            "Final wear volume V∞/(π a0² d) against χ = u_A/u_max (u_max = μ (c_N/c_T) d depends on k, ν)",
            "χ",
            ("V∞ / (π a0² d)", &by_chi),
            ("", none),
            false,
        ),
    )
}
