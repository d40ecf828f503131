//! The graded fretting-wear study (docs/fretting-wear.md, "Graded media"; `halfspace study
//! graded-wear`): the limiting wear depth per grading exponent, the final wear volume against the
//! physical amplitude, the grading with the least final wear per amplitude, and the tangential
//! constant towards the Gibson medium.

use halfspace_mdr::tangential::tangential_constant_ratio;
use halfspace_mdr::MdrError;

use crate::limit::{
    initial_profile, limit_contact_radius, limit_wear_volume, limiting_profile, stick_radius,
};

/// `Ṽ∞` at `u_A/(μd) = u` for a medium of tangential ratio `c_T/c_N = ratio` (`None` in gross
/// slip): [`crate::limit::limit_wear_volume_at_amplitude`] with the ratio computed once.
fn volume_at(u: f64, k: f64, ratio: f64) -> Option<f64> {
    let chi = u * ratio;
    (chi > 0.0 && chi < 1.0).then(|| limit_wear_volume(chi, k))
}

/// One grading exponent's curves.
#[derive(Debug, Clone, PartialEq)]
pub struct GradingCurves {
    /// Grading exponent `k`.
    pub k: f64,
    /// `r*/a₀` at the profiles' χ.
    pub r_star: f64,
    /// `(r̃, (f̃∞ − f̃₀))` on `[0, 1.6]` (zero outside the slip annulus `(c, r*)`).
    pub wear_depth: Vec<(f64, f64)>,
    /// `(u_A/(μd), Ṽ∞)` up to gross slip.
    pub volume_against_amplitude: Vec<(f64, f64)>,
    /// `(χ, Ṽ∞)` for χ = 0.01 … 0.99.
    pub volume_against_chi: Vec<(f64, f64)>,
    /// `c_T/c_N` at the study's ν.
    pub tangential_ratio: f64,
    /// `Ṽ∞` at χ = 0.1, 0.3, 0.5, 0.7, 0.9.
    pub volume_at_chi: [f64; 5],
}

/// The grading with the least final wear at one amplitude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Optimum {
    /// `u_A/(μd)`.
    pub amplitude_over_mu_d: f64,
    /// The best `k` of the scanned grid.
    pub k: f64,
    /// Its `Ṽ∞`.
    pub volume: f64,
}

/// The study's results.
#[derive(Debug, Clone, PartialEq)]
pub struct GradedWearStudy {
    /// χ of the wear-depth curves.
    pub chi: f64,
    /// ν of the amplitude curves.
    pub nu: f64,
    /// One entry per `k`.
    pub curves: Vec<GradingCurves>,
    /// The best `k ∈ [−0.9, 0.95]` (steps of 0.05) per amplitude.
    pub optimum: Vec<Optimum>,
    /// `(k, ν, c_T/c_N)` for `k` = 0.9, 0.99, 0.999 and ν = 0.3, 0.5.
    pub towards_gibson: Vec<(f64, f64, f64)>,
}

/// The χ of the wear-depth curves, ν of the amplitude curves and the exponents of the study.
pub const STUDY_CHI: f64 = 0.5;
/// See [`STUDY_CHI`].
pub const STUDY_NU: f64 = 0.3;
/// See [`STUDY_CHI`].
pub const STUDY_KS: [f64; 7] = [-0.5, -0.25, 0.0, 0.25, 0.5, 0.75, 0.9];

/// Runs the study: `f̃∞ − f̃₀` (closed form) on 301 points, `Ṽ∞(u_A/(μd))` on 121 amplitudes from
/// 0.002 to 2 (logarithmic) through `χ = u_A c_T/(μ c_N d)`, the optimum per amplitude.
pub fn graded_wear_study() -> Result<GradedWearStudy, MdrError> {
    let (chi, nu) = (STUDY_CHI, STUDY_NU);
    let amplitudes: Vec<f64> = (0..=120)
        .map(|i| 0.002 * 10f64.powf(i as f64 / 40.0))
        .collect();
    let c = stick_radius(chi);
    let mut curves = Vec::new();
    for &k in &STUDY_KS {
        let r_star = limit_contact_radius(chi, k);
        let wear_depth = (0..=300)
            .map(|i| {
                let r = 1.6 * i as f64 / 300.0;
                let depth = if r <= c || r >= r_star {
                    0.0
                } else {
                    limiting_profile(r, chi, k) - initial_profile(r, k)
                };
                (r, depth)
            })
            .collect();
        let ratio = tangential_constant_ratio(k, nu)?;
        let volume_against_amplitude = amplitudes
            .iter()
            .filter_map(|&u| volume_at(u, k, ratio).map(|v| (u, v)))
            .collect();
        let volume_against_chi = (1..=99)
            .map(|i| {
                let x = i as f64 / 100.0;
                (x, limit_wear_volume(x, k))
            })
            .collect();
        curves.push(GradingCurves {
            k,
            r_star,
            wear_depth,
            volume_against_amplitude,
            volume_against_chi,
            tangential_ratio: ratio,
            volume_at_chi: [0.1, 0.3, 0.5, 0.7, 0.9].map(|x| limit_wear_volume(x, k)),
        });
    }
    let grid = (0..=37)
        .map(|i| {
            let k = -0.9 + 0.05 * i as f64;
            Ok((k, tangential_constant_ratio(k, nu)?))
        })
        .collect::<Result<Vec<(f64, f64)>, MdrError>>()?;
    let mut optimum = Vec::new();
    for u in [0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5] {
        let mut best: Option<Optimum> = None;
        for &(k, ratio) in &grid {
            if let Some(v) = volume_at(u, k, ratio) {
                if best.is_none_or(|b| v < b.volume) {
                    best = Some(Optimum {
                        amplitude_over_mu_d: u,
                        k: (k * 100.0).round() / 100.0,
                        volume: v,
                    });
                }
            }
        }
        optimum.extend(best);
    }
    let mut towards_gibson = Vec::new();
    for k in [0.9, 0.99, 0.999] {
        for nu in [0.3, 0.5] {
            towards_gibson.push((k, nu, tangential_constant_ratio(k, nu)?));
        }
    }
    Ok(GradedWearStudy {
        chi,
        nu,
        curves,
        optimum,
        towards_gibson,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_study_reproduces_the_papers_claims() {
        let s = graded_wear_study().unwrap();
        let best = |u: f64| {
            s.optimum
                .iter()
                .find(|o| o.amplitude_over_mu_d == u)
                .unwrap()
                .k
        };
        // Very small amplitudes: slightly negative k; large: positive (docs/fretting-wear.md).
        assert!(best(0.005) < 0.0 && best(0.005) > -0.5, "{}", best(0.005));
        assert!(best(0.01) < 0.0);
        assert!(best(0.1) > 0.5 && best(0.5) > 0.5);
        // The Gibson medium (ν = 1/2): c_T/c_N ≈ (1 − k)/2 → 0.
        for &(k, nu, ratio) in &s.towards_gibson {
            if nu == 0.5 {
                assert!(
                    (ratio / (0.5 * (1.0 - k)) - 1.0).abs() < 0.01,
                    "k {k}: {ratio}"
                );
            }
        }
    }
}
