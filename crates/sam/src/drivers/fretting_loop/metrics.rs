//! What a fretting loop measures: dissipated energy, ratchet, regime.

use super::case::{LoadPath, LoopCase};
use super::row::LoopRow;

/// The fretting regime of one loop (the running-condition classes of Vingsbo & Söderberg 1988),
/// from the stick zone over the closed cycle:
///
/// * partial slip: a stick zone at every increment of the cycle;
/// * mixed: the stick zone vanishes, but the sliding (the shift travelled without a stick cell)
///   is at most `GROSS_SLIP_TRAVEL` of the cycle's travel `4A` — the loop just reaches `μW`;
/// * gross slip: a sliding plateau longer than that.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrettingRegime {
    /// Stick everywhere in the cycle.
    PartialSlip = 0,
    /// The transition.
    Mixed = 1,
    /// Sustained sliding.
    GrossSlip = 2,
}

/// The fraction of the cycle's travel `4A` above which sliding makes the regime gross slip.
pub const GROSS_SLIP_TRAVEL: f64 = 0.05;

/// The numbers of a completed loop (\[LN11\] §4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoopMetrics {
    /// Dissipated energy per cycle `E_d = |∮ Q₁ dδx|` (trapezoid over the closed cycle) (J).
    pub dissipated_energy: f64,
    /// `Q₁/μW` at the end of the loop minus at its start, both at `δx = +A` (slight ratcheting).
    pub ratchet: f64,
    /// `Q₁/μW` at the first `δx = +A` (point B).
    pub tangential_force_over_mu_w_at_amplitude: f64,
    /// Peak pressure over Hertz's `p₀` at the end of the normal loading (point A).
    pub max_pressure_over_p0_end_of_normal_loading: f64,
    /// Contact area over `πa²` at point A.
    pub contact_area_over_hertz_end_of_normal_loading: f64,
    /// Approach over Hertz's `a²/R` at point A.
    pub approach_over_hertz_end_of_normal_loading: f64,
    /// Largest `|s₂|` over the loop (m).
    pub max_transverse_slip: f64,
    /// Shift travelled without a stick cell over the cycle, over `4A`.
    pub sliding_fraction: f64,
    /// The regime ([`FrettingRegime`]).
    pub regime: FrettingRegime,
    /// Tangential stiffness on the first step back from `δx = +A` (point B), `ΔQ₁/Δδx` (N/m): the
    /// elastic (all-stick) stiffness of the contact on a load reversal (Mindlin), which sets the
    /// full-slip shift `δ_s = 3μW / (2k)` of Mindlin's theory.
    pub unloading_stiffness: f64,
    /// Fouvry's energy ratio `E_d / (4 Q* δ*)` (`Q*`, `δ*` the cycle's force and shift
    /// amplitudes): below ≈ 0.2 partial slip in the Mindlin limit.
    pub energy_ratio: f64,
}

impl LoopMetrics {
    /// The metrics of the rows of a completed `path`.
    pub fn of(
        case: &LoopCase,
        path: &LoadPath,
        rows: &[LoopRow],
        max_transverse_slip: f64,
    ) -> Self {
        // μW with the loop's W: the prescribed force, or under approach control the force
        // computed at the end of the normal loading.
        let w = if path.by_approach {
            rows[path.normal_steps - 1].w
        } else {
            case.force
        };
        let mu_w = case.friction * w;
        let a = case.hertz_radius();
        let start = path.cycle_start();
        let cycle = &rows[start..];
        let dissipated_energy = cycle
            .windows(2)
            .map(|w| 0.5 * (w[0].q[0] + w[1].q[0]) * (w[1].d - w[0].d))
            .sum::<f64>()
            .abs();
        let sliding: f64 = cycle
            .windows(2)
            .filter(|w| w[1].stick_area == 0.0)
            .map(|w| (w[1].d - w[0].d).abs())
            .sum();
        let travel = 4.0 * case.amplitude;
        let sliding_fraction = sliding / travel;
        let regime = if cycle.iter().all(|r| r.stick_area > 0.0) {
            FrettingRegime::PartialSlip
        } else if sliding_fraction <= GROSS_SLIP_TRAVEL {
            FrettingRegime::Mixed
        } else {
            FrettingRegime::GrossSlip
        };
        let q_star = cycle.iter().map(|r| r.q[0].abs()).fold(0.0, f64::max);
        let d_star = cycle.iter().map(|r| r.d.abs()).fold(0.0, f64::max);
        let end_normal = &rows[path.normal_steps - 1];
        let unloading_stiffness = match (rows.get(start), rows.get(start + 1)) {
            (Some(b), Some(next)) if next.d != b.d => (next.q[0] - b.q[0]) / (next.d - b.d),
            _ => f64::NAN,
        };
        Self {
            dissipated_energy,
            ratchet: (rows[rows.len() - 1].q[0] - rows[start].q[0]) / mu_w,
            tangential_force_over_mu_w_at_amplitude: rows[start].q[0] / mu_w,
            max_pressure_over_p0_end_of_normal_loading: end_normal.max_pressure
                / case.hertz_pressure(),
            contact_area_over_hertz_end_of_normal_loading: end_normal.contact_area
                / (std::f64::consts::PI * a * a),
            approach_over_hertz_end_of_normal_loading: end_normal.approach / (a * a / case.radius),
            max_transverse_slip,
            sliding_fraction,
            regime,
            unloading_stiffness,
            energy_ratio: if q_star > 0.0 && d_star > 0.0 {
                dissipated_energy / (4.0 * q_star * d_star)
            } else {
                0.0
            },
        }
    }
}
