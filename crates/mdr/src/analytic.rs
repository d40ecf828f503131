//! Closed forms of the homogeneous MDR (spec §1–§3), shared by tests, docs and benches.
//! `E*` is the contact modulus; all functions are pure and take SI values.

use std::f64::consts::PI;

use halfspace_numerics::special::gamma;

/// `κ_n = √π Γ(n/2 + 1) / Γ(n/2 + 1/2)`: `f = c rⁿ ↦ g = κ_n c |x|ⁿ` (spec §1 table);
/// `κ₁ = π/2`, `κ₂ = 2`, `κ₃ = 3π/4`, `κ₄ = 8/3`.
pub fn power_law_factor(n: f64) -> f64 {
    PI.sqrt() * gamma(0.5 * n + 1.0) / gamma(0.5 * n + 0.5)
}

/// Sphere (paraboloid `f = r²/2R`): `g = x²/R`.
pub fn sphere_equivalent(x: f64, radius: f64) -> f64 {
    x * x / radius
}

/// Sphere: `δ = a²/R`.
pub fn sphere_depth(a: f64, radius: f64) -> f64 {
    a * a / radius
}

/// Sphere: `F = (4/3) E* a³/R`.
pub fn sphere_force(a: f64, radius: f64, e_star: f64) -> f64 {
    4.0 / 3.0 * e_star * a * a * a / radius
}

/// Hertz contact radius for a force: `a = (3 F R / (4 E*))^{1/3}`.
pub fn sphere_radius_for_force(force: f64, radius: f64, e_star: f64) -> f64 {
    (3.0 * force * radius / (4.0 * e_star)).cbrt()
}

/// Sphere: `p(r) = (2E*/(πR)) √(a² − r²)` inside, 0 outside; `p₀ = 2E* a/(πR) = 3F/(2πa²)`.
pub fn sphere_pressure(r: f64, a: f64, radius: f64, e_star: f64) -> f64 {
    if r >= a {
        0.0
    } else {
        2.0 * e_star / (PI * radius) * (a * a - r * r).sqrt()
    }
}

/// Sphere: surface displacement `u = δ − r²/2R` inside and
/// `u = [(2a² − r²) arcsin(a/r) + a √(r² − a²)] / (πR)` outside (spec §2 test 2).
pub fn sphere_displacement(r: f64, a: f64, radius: f64) -> f64 {
    if r <= a {
        a * a / radius - r * r / (2.0 * radius)
    } else {
        ((2.0 * a * a - r * r) * (a / r).asin() + a * (r * r - a * a).sqrt()) / (PI * radius)
    }
}

/// Cone `f = r tan θ`: `δ = (π/2) a tan θ`.
pub fn cone_depth(a: f64, slope: f64) -> f64 {
    0.5 * PI * a * slope
}

/// Cone: `F = (π/2) E* a² tan θ`.
pub fn cone_force(a: f64, slope: f64, e_star: f64) -> f64 {
    0.5 * PI * e_star * a * a * slope
}

/// Cone: `p(r) = (E* tan θ / 2) arccosh(a/r)` inside.
pub fn cone_pressure(r: f64, a: f64, slope: f64, e_star: f64) -> f64 {
    if r >= a {
        0.0
    } else {
        0.5 * e_star * slope * (a / r).acosh()
    }
}

/// Power law `f = c rⁿ`: `δ = κ_n c aⁿ`.
pub fn power_depth(a: f64, c: f64, n: f64) -> f64 {
    power_law_factor(n) * c * a.powf(n)
}

/// Power law: `F = 2E* n/(n+1) κ_n c a^{n+1}`.
pub fn power_force(a: f64, c: f64, n: f64, e_star: f64) -> f64 {
    2.0 * e_star * n / (n + 1.0) * power_law_factor(n) * c * a.powf(n + 1.0)
}

/// Power law `f = c rⁿ`, pressure `p(r) = (E* n κ_n c/π) ∫_r^a x^{n−1} dx / √(x² − r²)` in
/// closed form for `n = 2, 3, 4`; `None` for other `n`.
pub fn power_pressure(r: f64, a: f64, c: f64, n: f64, e_star: f64) -> Option<f64> {
    if r >= a {
        return Some(0.0);
    }
    let w = (a * a - r * r).sqrt();
    let integral = if n == 2.0 {
        w
    } else if n == 3.0 {
        // r² arccosh(a/r) → 0 as r → 0.
        let tail = if r > 0.0 {
            r * r * (a / r).acosh()
        } else {
            0.0
        };
        0.5 * (a * w + tail)
    } else if n == 4.0 {
        w * (a * a + 2.0 * r * r) / 3.0
    } else {
        return None;
    };
    Some(e_star * n * power_law_factor(n) * c / PI * integral)
}

/// Flat punch of radius `a`: `F = 2E* a δ`.
pub fn flat_punch_force(a: f64, depth: f64, e_star: f64) -> f64 {
    2.0 * e_star * a * depth
}

/// Flat punch: `p(r) = E* δ / (π √(a² − r²))` inside.
pub fn flat_punch_pressure(r: f64, a: f64, depth: f64, e_star: f64) -> f64 {
    if r >= a {
        0.0
    } else {
        e_star * depth / (PI * (a * a - r * r).sqrt())
    }
}

/// Flat punch: `u = δ` inside, `u = (2δ/π) arcsin(a/r)` outside.
pub fn flat_punch_displacement(r: f64, a: f64, depth: f64) -> f64 {
    if r <= a {
        depth
    } else {
        2.0 * depth / PI * (a / r).asin()
    }
}

/// Eq. 18 pair of Eq. 14: `q = a⁴ − x⁴ ↦ σ(r) = (4/(3π)) √(a² − r²) (a² + 2r²)`.
pub fn quartic_load_stress(r: f64, a: f64) -> f64 {
    if r >= a {
        0.0
    } else {
        4.0 / (3.0 * PI) * (a * a - r * r).sqrt() * (a * a + 2.0 * r * r)
    }
}

/// Eq. 8 pair (spec §2 test 1): `U = x⁴ ↦ u = (3/8) r⁴`.
pub fn quartic_displacement(r: f64) -> f64 {
    0.375 * r.powi(4)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_numbers_of_spec_section_1() {
        assert!((power_law_factor(1.0) - PI / 2.0).abs() < 1e-14);
        assert!((power_law_factor(2.0) - 2.0).abs() < 1e-14);
        assert!((power_law_factor(3.0) - 0.75 * PI).abs() < 1e-14);
        assert!((power_law_factor(4.0) - 8.0 / 3.0).abs() < 1e-14);
        // R = 1, a = 0.5, E* = 1.
        assert!((sphere_force(0.5, 1.0, 1.0) - 0.166_666_7).abs() < 1e-7);
        assert!((sphere_pressure(0.0, 0.5, 1.0, 1.0) - std::f64::consts::FRAC_1_PI).abs() < 1e-15);
        assert!((cone_depth(0.5, 0.1) - 0.078_539_8).abs() < 1e-7);
        assert!((cone_force(0.5, 0.1, 1.0) - 0.039_269_9).abs() < 1e-7);
        assert!((cone_pressure(0.25, 0.5, 0.1, 1.0) - 0.065_847_9).abs() < 1e-7);
        assert!((power_depth(0.5, 1.0, 3.0) - 0.294_524_3).abs() < 1e-7);
        assert!((power_force(0.5, 1.0, 3.0, 1.0) - 0.220_893_2).abs() < 1e-7);
        assert!((power_force(0.5, 1.0, 4.0, 1.0) - 0.133_333_3).abs() < 1e-7);
        assert!((sphere_displacement(1.0, 0.5, 1.0) - 0.054_498_9).abs() < 1e-7);
        assert!((quartic_load_stress(0.5, 1.0) - 0.551_328_9).abs() < 1e-7);
        assert!((quartic_load_stress(0.75f64.sqrt(), 1.0) - 0.530_516_5).abs() < 1e-7);
        assert!((quartic_load_stress(0.0, 1.0) - 0.424_413_2).abs() < 1e-7);
        // r = √0.25 etc.: spec gives σ at ρ = r².
        assert!((quartic_load_stress(0.5f64.sqrt(), 1.0) - 0.600_210_9).abs() < 1e-7);
        // n = 2 is the sphere with R = 1/(2c); n = 3 at r = 0 is finite (acosh term → 0).
        let p2 = power_pressure(0.1, 0.5, 0.5, 2.0, 1.0).unwrap();
        assert!((p2 - sphere_pressure(0.1, 0.5, 1.0, 1.0)).abs() < 1e-15);
        assert!(power_pressure(1e-300, 0.5, 1.0, 3.0, 1.0)
            .unwrap()
            .is_finite());
        // Continuity of the Hertz displacement at r = a.
        let a = 0.7;
        assert!(
            (sphere_displacement(a, a, 1.0) - sphere_displacement(a + 1e-12, a, 1.0)).abs() < 1e-9
        );
    }
}
