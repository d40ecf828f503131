//! Closed forms of spec §5 in normalized variables (`a₀ = d = 1`, so `R = 1` and `f̃₀ = r̃²/2`).

use std::f64::consts::PI;

/// Stick radius `c̃ = √(1 − χ)` of the paraboloid.
pub fn stick_radius(chi: f64) -> f64 {
    (1.0 - chi).sqrt()
}

/// Initial profile `f̃₀ = r̃²/2`.
pub fn initial_profile(r: f64) -> f64 {
    0.5 * r * r
}

/// Popov's limiting no-wear profile (spec §5): `f̃₀` for `r ≤ c`, and for `r > c`
/// `f̃∞ = (1/π)[r² arcsin(c/r) − c √(r² − c²)] + (2/π) arccos(c/r)`.
pub fn limiting_profile(r: f64, chi: f64) -> f64 {
    let c = stick_radius(chi);
    if r <= c {
        return initial_profile(r);
    }
    let ratio = (c / r).min(1.0);
    (r * r * ratio.asin() - c * (r * r - c * c).sqrt()) / PI + 2.0 / PI * ratio.acos()
}

/// `r*/a₀`, where `f̃₀(r*) = f̃∞(r*)` beyond the stick zone: the limit of the contact radius
/// (bisection on `(c, √2]`; the supremum over χ is √2).
pub fn limit_contact_radius(chi: f64) -> f64 {
    let c = stick_radius(chi);
    let gap = |r: f64| limiting_profile(r, chi) - initial_profile(r);
    // f∞ − f₀ is positive just beyond c (wear raises f) and negative at large r.
    let (mut lo, mut hi) = (c.max(1e-12) * (1.0 + 1e-9) + 1e-12, 2.0f64);
    if gap(lo) <= 0.0 {
        return c;
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

/// Monotonic Cattaneo–Mindlin slip of the paraboloid at the amplitude, over `u_A` (spec §5,
/// "Hertz check"): `s̃ = (1/(πχ))[(r² − 2c²) arccos(c/r) + c √(r² − c²)]` for `c < r ≤ 1`, else 0.
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

/// Slip per cycle over `u_A` in the worn state (spec §5): `Δũ = 4[(f̃ − f̃∞)/χ + (2/π) arccos(c/r)]`
/// for `c < r ≤ a`, 0 elsewhere; the steady cycle's slip path is four times the monotonic slip.
pub fn slip_per_cycle(r: f64, profile: f64, chi: f64) -> f64 {
    let c = stick_radius(chi);
    if r <= c {
        return 0.0;
    }
    4.0 * ((profile - limiting_profile(r, chi)) / chi + 2.0 / PI * (c / r).min(1.0).acos())
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
            let got = limit_contact_radius(chi);
            assert!((got - want).abs() < 6e-5, "χ={chi}: {got} vs {want}");
        }
        assert!((limiting_profile(1.0, 0.5) - 0.590845).abs() < 1e-6);
        assert!(limit_contact_radius(0.999999) < 2f64.sqrt());
    }

    #[test]
    fn worn_slip_formula_is_the_hertz_slip_on_the_initial_profile() {
        // Δũ/4 at f = f₀ must equal the monotonic Hertz slip s̃ (spec §5, both derived there).
        for chi in [0.3, 0.5, 0.9] {
            for i in 1..100 {
                let r = i as f64 / 100.0;
                let from_formula = slip_per_cycle(r, initial_profile(r), chi) / 4.0;
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
