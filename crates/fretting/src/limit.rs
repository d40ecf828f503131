//! Closed forms of docs/theory-mdr.md#fretting-wear in normalized variables (`a₀ = d = 1`), for the homogeneous medium and
//! the power-law graded medium `E ∝ z^k` (docs/fretting-wear.md, "Graded media"): the paraboloid
//! `f = r²/(2R)` has `g = x²/((1+k)R)` (docs/theory-mdr.md#graded-profile-transform), so `a₀² = (1+k)Rd` and `f̃₀ = (1+k) r̃²/2`,
//! `g̃₀ = x̃²`. Every function reduces at `k = 0` to the homogeneous formula, evaluated by the same
//! operations (bit for bit).

use std::f64::consts::PI;

use halfspace_numerics::special::incomplete_beta;

/// Stick radius `c̃ = √(1 − χ)`: where `g̃₀(c̃) = 1 − χ` (the 1D stick condition
/// `c_T u_A ≤ μ c_N (d − g)` of the graded MDR has the same `|x|^k` on both sides, so it does not
/// depend on `k`).
pub fn stick_radius(chi: f64) -> f64 {
    (1.0 - chi).sqrt()
}

/// Initial profile `f̃₀ = (1+k) r̃²/2` (`= r̃²/2` homogeneous).
pub fn initial_profile(r: f64, k: f64) -> f64 {
    0.5 * (1.0 + k) * r * r
}

/// `(cos(πk/2)/π) B_z(p, (1−k)/2)`: the incomplete beta integrals of the graded inverse transform
/// (docs/theory-mdr.md#graded-displacements, Eq. 24, with `x = r sin θ`), normalized so that `p = (1+k)/2`, `z = 1` gives 1.
fn graded_beta(p: f64, k: f64, z: f64) -> f64 {
    // z ∈ [0, 1] and p > 0 by construction (callers pass z = c²/r² with r > c).
    (0.5 * PI * k).cos() / PI * incomplete_beta(p, 0.5 * (1.0 - k), z).unwrap_or(f64::NAN)
}

/// The 3D displacement `(2/π) cos(kπ/2) ∫_c^r x^k (r² − x²)^{−(1+k)/2} dx` of a unit 1D
/// displacement on `|x| > c` (Eq. 24 / Eq. 8), for `r > c`:
/// `J = 1 − (cos(πk/2)/π) B_{c²/r²}((1+k)/2, (1−k)/2)`; homogeneous `J = (2/π) arccos(c/r)`.
pub fn annulus_response(r: f64, c: f64, k: f64) -> f64 {
    let ratio = (c / r).min(1.0);
    if k == 0.0 {
        2.0 / PI * ratio.acos()
    } else {
        1.0 - graded_beta(0.5 * (1.0 + k), k, ratio * ratio)
    }
}

/// Popov's limiting no-wear profile for grading exponent `k` (docs/theory-mdr.md#fretting-wear; graded: docs/fretting-wear.md):
/// zero pressure in the slip annulus, so `g̃∞ = g̃₀ = x̃²` for `x̃ ≤ c̃` and `g̃∞ = 1` beyond; by
/// Eq. 24 `f̃∞ = f̃₀` for `r̃ ≤ c̃` and for `r̃ > c̃`
/// `f̃∞ = (cos(πk/2)/π) r̃² B_{c²/r²}((3+k)/2, (1−k)/2) + J(r̃)` ([`annulus_response`]); homogeneous
/// `f̃∞ = (1/π)[r² arcsin(c/r) − c √(r² − c²)] + (2/π) arccos(c/r)`.
pub fn limiting_profile(r: f64, chi: f64, k: f64) -> f64 {
    let c = stick_radius(chi);
    if r <= c {
        return initial_profile(r, k);
    }
    let ratio = (c / r).min(1.0);
    if k == 0.0 {
        (r * r * ratio.asin() - c * (r * r - c * c).sqrt()) / PI + 2.0 / PI * ratio.acos()
    } else {
        r * r * graded_beta(0.5 * (3.0 + k), k, ratio * ratio) + annulus_response(r, c, k)
    }
}

/// `r*/a₀`, where `f̃₀(r*) = f̃∞(r*)` beyond the stick zone: the limit of the contact radius
/// (bisection; homogeneous on `(c, 2]`, the supremum over χ being √2; graded on `(c, 2^m]`
/// doubled until the bracket holds — `r*` grows without bound as `k → −1`).
pub fn limit_contact_radius(chi: f64, k: f64) -> f64 {
    let c = stick_radius(chi);
    let gap = |r: f64| limiting_profile(r, chi, k) - initial_profile(r, k);
    // f∞ − f₀ is positive just beyond c (wear raises f) and negative at large r.
    let (mut lo, mut hi) = (c.max(1e-12) * (1.0 + 1e-9) + 1e-12, 2.0f64);
    if gap(lo) <= 0.0 {
        return c;
    }
    while k != 0.0 && gap(hi) > 0.0 && hi < 1e6 {
        lo = hi;
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if gap(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The final wear volume over `π a₀² d`: `Ṽ∞ = 2 ∫_c^{r*} (f̃∞ − f̃₀) r̃ dr̃ = ∫_{c²}^{r*²} (f̃∞ − f̃₀) dξ`
/// (`ξ = r̃²`; tanh–sinh quadrature, which absorbs the algebraic behaviour of the integrand at
/// both ends).
pub fn limit_wear_volume(chi: f64, k: f64) -> f64 {
    let r_star = limit_contact_radius(chi, k);
    let f = |xi: f64, _: f64, _: f64| {
        let r = xi.sqrt();
        limiting_profile(r, chi, k) - initial_profile(r, k)
    };
    halfspace_numerics::quad::tanh_sinh(f, 1.0 - chi, r_star * r_star, 1e-13)
}

/// The final wear volume over `π a₀² d` at the physical amplitude `ũ = u_A / (μ d)` of a medium
/// `(k, ν)`: `χ = u_A / u_max = ũ c_T/c_N` (`u_max = μ (c_N/c_T) d`, the graded tangential constant
/// of `halfspace_mdr::tangential`), then [`limit_wear_volume`]; `None` in gross slip (`χ ≥ 1`).
/// This is the comparison of gradings at one indentation depth and one displacement amplitude.
pub fn limit_wear_volume_at_amplitude(
    amplitude_over_mu_d: f64,
    k: f64,
    nu: f64,
) -> Result<Option<f64>, halfspace_mdr::MdrError> {
    let chi = amplitude_over_mu_d * halfspace_mdr::tangential::tangential_constant_ratio(k, nu)?;
    Ok((chi > 0.0 && chi < 1.0).then(|| limit_wear_volume(chi, k)))
}

/// Monotonic Cattaneo–Mindlin slip of the paraboloid at the amplitude, over `u_A` (docs/theory-mdr.md#fretting-wear,
/// "Hertz check"): `s̃ = (1/(πχ))[(r² − 2c²) arccos(c/r) + c √(r² − c²)]` for `c < r ≤ 1`, else 0
/// (homogeneous).
pub fn hertz_slip(r: f64, chi: f64) -> f64 {
    let c = stick_radius(chi);
    if r <= c || r > 1.0 {
        return 0.0;
    }
    ((r * r - 2.0 * c * c) * (c / r).acos() + c * (r * r - c * c).sqrt()) / (PI * chi)
}

/// `ds̃/dr` of [`hertz_slip`] (for finite-difference checks).
pub fn hertz_slip_derivative(r: f64, chi: f64) -> f64 {
    let c = stick_radius(chi);
    if r <= c || r > 1.0 {
        return 0.0;
    }
    let w = (r * r - c * c).sqrt();
    (2.0 * r * (c / r).acos() + (r * r - 2.0 * c * c) * c / (r * w) + c * r / w) / (PI * chi)
}

/// Slip per cycle over `u_A` in the worn state (docs/theory-mdr.md#fretting-wear; graded: docs/fretting-wear.md):
/// `Δũ = 4[(f̃ − f̃∞)/χ + J(r̃)]` for `c < r ≤ a`, 0 elsewhere — the graded inverse transform
/// (Eq. 24) of the 1D slip `(u_A/χ)(g̃ − (1 − χ))` on `c < |x| < a`, with `g = g₀` in the stick zone
/// (wear never reaches it); the steady cycle's slip path is four times the monotonic slip.
pub fn slip_per_cycle(r: f64, profile: f64, chi: f64, k: f64) -> f64 {
    let c = stick_radius(chi);
    if r <= c {
        return 0.0;
    }
    4.0 * ((profile - limiting_profile(r, chi, k)) / chi + annulus_response(r, c, k))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limit_radius_table_of_spec_section_5() {
        let table = [
            (0.1, 1.0255),
            (0.3, 1.0796),
            (0.5, 1.1397),
            (0.7, 1.2097),
            (0.9, 1.3032),
            (0.99, 1.3813),
        ];
        for (chi, want) in table {
            let got = limit_contact_radius(chi, 0.0);
            assert!((got - want).abs() < 6e-5, "χ={chi}: {got} vs {want}");
        }
        assert!((limiting_profile(1.0, 0.5, 0.0) - 0.590845).abs() < 1e-6);
        assert!(limit_contact_radius(0.999999, 0.0) < 2f64.sqrt());
    }

    #[test]
    fn worn_slip_formula_is_the_hertz_slip_on_the_initial_profile() {
        // Δũ/4 at f = f₀ must equal the monotonic Hertz slip s̃ (docs/theory-mdr.md#fretting-wear, both derived there).
        for chi in [0.3, 0.5, 0.9] {
            for i in 1..100 {
                let r = i as f64 / 100.0;
                let from_formula = slip_per_cycle(r, initial_profile(r, 0.0), chi, 0.0) / 4.0;
                let want = hertz_slip(r, chi);
                assert!(
                    (from_formula - want).abs() < 1e-13,
                    "χ={chi} r={r}: {from_formula} {want}"
                );
            }
        }
    }

    #[test]
    fn hertz_slip_derivative_matches_central_differences() {
        for chi in [0.3, 0.5, 0.9] {
            let c = stick_radius(chi);
            for t in [0.1, 0.4, 0.7, 0.95] {
                let r = c + t * (1.0 - c);
                let eps = 1e-6;
                let fd = (hertz_slip(r + eps, chi) - hertz_slip(r - eps, chi)) / (2.0 * eps);
                let exact = hertz_slip_derivative(r, chi);
                assert!(
                    (fd - exact).abs() < 1e-7 * exact.abs().max(1.0),
                    "χ={chi} r={r}: {fd} vs {exact}"
                );
            }
        }
    }
}
