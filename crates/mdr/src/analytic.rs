//! Closed forms of the MDR (docs/theory-mdr.md#profile-transform to #graded-media), shared by tests, docs and benches. `E*` is the contact
//! modulus of a homogeneous medium, `c_N` that of a power-law graded one (docs/theory-mdr.md#graded-constant-cn); all
//! functions are pure and take SI values.

use std::f64::consts::PI;

use halfspace_numerics::quad::tanh_sinh;
use halfspace_numerics::special::{gamma, hyp2f1, incomplete_beta};
use halfspace_numerics::NumericsError;

/// `κ_n = √π Γ(n/2 + 1) / Γ(n/2 + 1/2)`: `f = c rⁿ ↦ g = κ_n c |x|ⁿ` (docs/theory-mdr.md#profile-transform table);
/// `κ₁ = π/2`, `κ₂ = 2`, `κ₃ = 3π/4`, `κ₄ = 8/3`.
pub fn power_law_factor(n: f64) -> f64 {
    graded_power_law_factor(n, 0.0)
}

/// `κ_n(k) = Γ(1 + n/2) Γ((1+k)/2) / Γ((1+k+n)/2)`: `f = c rⁿ ↦ g = κ_n(k) c |x|ⁿ` in a graded
/// medium (docs/theory-mdr.md#graded-profile-transform); `κ₂(k) = 2/(1+k)`, and `κ_n(0) = κ_n`.
pub fn graded_power_law_factor(n: f64, k: f64) -> f64 {
    gamma(1.0 + 0.5 * n) * gamma(0.5 * (1.0 + k)) / gamma(0.5 * (1.0 + k + n))
}

/// Kernel of Eq. 25 (docs/theory-mdr.md#graded-displacements): `K_k(y) = 1 − 2cos(kπ/2)/(π(1+k)) · H(y; k)`,
/// `H(y; k) = y^{(1+k)/2} ₂F₁((1+k)/2, (1+k)/2; (3+k)/2; y)`, `0 ≤ y ≤ 1`; `K_k(0) = 1`,
/// `K_k(1) = 0`, `K_0(y) = (2/π) arccos √y` (Eq. 12's kernel, evaluated so at `k = 0`).
pub fn displacement_kernel(y: f64, k: f64) -> Result<f64, NumericsError> {
    if k == 0.0 {
        return Ok(2.0 / PI * y.sqrt().min(1.0).acos());
    }
    if y <= 0.0 {
        return Ok(1.0);
    }
    let a = 0.5 * (1.0 + k);
    let h = y.powf(a) * hyp2f1(a, a, a + 1.0, y.min(1.0))?;
    Ok(1.0 - 2.0 * (0.5 * k * PI).cos() / (PI * (1.0 + k)) * h)
}

/// `I_k(r, a) = ∫_r^a (x² − r²)^{(k−1)/2} dx` (`= (r^k/2) B_{1−r²/a²}((1+k)/2, −k/2)`), the line
/// integral of Eq. 28 for a constant `g'` (the graded cone); `arccosh(a/r)` at `k = 0`, `a^k/k` at
/// `r = 0` for `k > 0` and `+∞` there for `k ≤ 0`; tanh–sinh quadrature otherwise.
pub fn graded_cone_integral(r: f64, a: f64, k: f64) -> Result<f64, NumericsError> {
    if r >= a {
        return Ok(0.0);
    }
    if r <= 0.0 {
        return Ok(if k > 0.0 {
            a.powf(k) / k
        } else {
            f64::INFINITY
        });
    }
    if k == 0.0 {
        return Ok((a / r).acosh());
    }
    // Tanh–sinh in d = x − r (robust for every k; the incomplete-beta form cancels catastrophically
    // as k → 0, where its 2F1 has c − a − b = −k/2 → 0).
    let e = 0.5 * (k - 1.0);
    Ok(tanh_sinh(
        |_, d, _| (d * (2.0 * r + d)).powf(e),
        0.0,
        a - r,
        1e-13,
    ))
}

/// `J_k(r, a) = ∫_r^a x² (x² − r²)^{(k−1)/2} dx`, the line integral of Eq. 28 for the cubic part of
/// g (`g' = 3x²`, over 3); at `k = 0` `½[a√(a² − r²) + r² arccosh(a/r)]`, `a^{k+2}/(k+2)` at `r = 0`;
/// tanh–sinh quadrature otherwise.
pub fn graded_cubic_integral(r: f64, a: f64, k: f64) -> Result<f64, NumericsError> {
    if r >= a {
        return Ok(0.0);
    }
    if r <= 0.0 {
        return Ok(a.powf(k + 2.0) / (k + 2.0));
    }
    if k == 0.0 {
        return Ok(0.5 * (a * (a * a - r * r).sqrt() + r * r * (a / r).acosh()));
    }
    // Tanh–sinh in d = x − r (see graded_cone_integral).
    let e = 0.5 * (k - 1.0);
    Ok(tanh_sinh(
        |_, d, _| (r + d) * (r + d) * (d * (2.0 * r + d)).powf(e),
        0.0,
        a - r,
        1e-13,
    ))
}

/// Surface displacement of the 1D displacement `U(x) = x` for `|x| ≤ a`, 0 beyond (Eq. 24):
/// `r/κ₁(k)` inside, `(cos(kπ/2)/π) r B_{a²/r²}((2+k)/2, (1−k)/2)` outside;
/// `(2/π)(r − √(r² − a²))` outside at `k = 0`.
pub fn cut_linear_displacement(r: f64, a: f64, k: f64) -> Result<f64, NumericsError> {
    if r <= a {
        return Ok(r / graded_power_law_factor(1.0, k));
    }
    if k == 0.0 {
        return Ok(2.0 / PI * (r - (r * r - a * a).sqrt()));
    }
    let z = (a / r) * (a / r);
    Ok((0.5 * k * PI).cos() / PI * r * incomplete_beta(0.5 * (2.0 + k), 0.5 * (1.0 - k), z)?)
}

/// Graded Hertz (docs/theory-mdr.md#graded-closed-forms): `a = √((1+k) R δ)`.
pub fn graded_sphere_radius(depth: f64, radius: f64, k: f64) -> f64 {
    ((1.0 + k) * radius * depth).sqrt()
}

/// Graded Hertz: `F = 4 c_N a^{3+k} / ((1+k)² (3+k) R)`.
pub fn graded_sphere_force(a: f64, radius: f64, c_n: f64, k: f64) -> f64 {
    4.0 * c_n * a.powf(3.0 + k) / ((1.0 + k).powi(2) * (3.0 + k) * radius)
}

/// Graded Hertz: `p(r) = 2 c_N (a² − r²)^{(1+k)/2} / (π (1+k)² R)`.
pub fn graded_sphere_pressure(r: f64, a: f64, radius: f64, c_n: f64, k: f64) -> f64 {
    if r >= a {
        0.0
    } else {
        2.0 * c_n * (a * a - r * r).powf(0.5 * (1.0 + k)) / (PI * (1.0 + k).powi(2) * radius)
    }
}

/// Graded flat punch: `F = 2 c_N δ a^{1+k}/(1+k)`.
pub fn graded_flat_punch_force(a: f64, depth: f64, c_n: f64, k: f64) -> f64 {
    2.0 * c_n * depth * a.powf(1.0 + k) / (1.0 + k)
}

/// Graded flat punch: `p(r) = (c_N δ/π) (a² − r²)^{(k−1)/2}`.
pub fn graded_flat_punch_pressure(r: f64, a: f64, depth: f64, c_n: f64, k: f64) -> f64 {
    if r >= a {
        0.0
    } else {
        c_n * depth / PI * (a * a - r * r).powf(0.5 * (k - 1.0))
    }
}

/// Graded power law `f = c rⁿ`: `F = 2n c_N κ_n(k) c a^{n+1+k} / ((1+k)(n+1+k))`.
pub fn graded_power_force(a: f64, c: f64, n: f64, c_n: f64, k: f64) -> f64 {
    2.0 * n * c_n * graded_power_law_factor(n, k) * c * a.powf(n + 1.0 + k)
        / ((1.0 + k) * (n + 1.0 + k))
}

/// Eq. 29 test pair (docs/theory-mdr.md#graded-closed-forms): `g = x⁴ ↦ p(r) = (2c_N/π)[2/(k+3) (a²−r²)^{(k+3)/2}
/// + 2r²/(k+1) (a²−r²)^{(k+1)/2}]`.
pub fn graded_quartic_pressure(r: f64, a: f64, c_n: f64, k: f64) -> f64 {
    if r >= a {
        return 0.0;
    }
    let w = a * a - r * r;
    2.0 * c_n / PI
        * (2.0 / (k + 3.0) * w.powf(0.5 * (k + 3.0))
            + 2.0 * r * r / (k + 1.0) * w.powf(0.5 * (k + 1.0)))
}

/// Eq. 27 pair: `U = x⁴ ↦ u = (1+k)(3+k)/8 · r⁴`.
pub fn graded_quartic_displacement(r: f64, k: f64) -> f64 {
    (1.0 + k) * (3.0 + k) / 8.0 * r.powi(4)
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
/// `u = [(2a² − r²) arcsin(a/r) + a √(r² − a²)] / (πR)` outside (docs/theory-mdr.md#displacement-transform test 2).
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

/// Eq. 8 pair (docs/theory-mdr.md#displacement-transform test 1): `U = x⁴ ↦ u = (3/8) r⁴`.
pub fn quartic_displacement(r: f64) -> f64 {
    0.375 * r.powi(4)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn graded_closed_forms() {
        // κ₂(k) = 2/(1+k), κ_n(0) = κ_n.
        for k in [-0.5, 0.3, 0.9] {
            assert!((graded_power_law_factor(2.0, k) - 2.0 / (1.0 + k)).abs() < 1e-14);
        }
        // Eq. 25 kernel: K_k(0) = 1, K_k(1) = 0, K_0 = (2/π) arccos √y through the 2F1 path too.
        for k in [-0.9, -0.5, 0.5, 0.9] {
            assert!((displacement_kernel(0.0, k).unwrap() - 1.0).abs() < 1e-15);
            assert!(displacement_kernel(1.0, k).unwrap().abs() < 1e-13, "k={k}");
        }
        for y in [0.1f64, 0.5, 0.9] {
            let a = 0.5;
            let h = y.powf(a) * hyp2f1(a, a, a + 1.0, y).unwrap();
            let via_2f1 = 1.0 - 2.0 / PI * h;
            assert!((via_2f1 - displacement_kernel(y, 0.0).unwrap()).abs() < 1e-14);
        }
        // I_k by Gauss–Legendre-free check: for k = 1/2 substitute x = r cosh t? Use a fine midpoint
        // rule on x = r + s², which removes the endpoint singularity.
        let (r, a, k) = (0.3f64, 1.0f64, 0.5f64);
        let smax = (a - r).sqrt();
        let m = 200_000;
        let mut sum = 0.0;
        for i in 0..m {
            let s = (i as f64 + 0.5) * smax / m as f64;
            let x = r + s * s;
            sum += (x * x - r * r).powf(0.5 * (k - 1.0)) * 2.0 * s * smax / m as f64;
        }
        assert!((graded_cone_integral(r, a, k).unwrap() / sum - 1.0).abs() < 1e-8);
        assert!(
            (graded_cone_integral(0.3, 1.0, 0.0).unwrap() - (1.0f64 / 0.3).acosh()).abs() < 1e-15
        );
        // The cut linear displacement is continuous at r = a and matches k = 0 from both sides.
        for k in [-0.5, 0.5] {
            let inside = cut_linear_displacement(0.7, 0.7, k).unwrap();
            let outside = cut_linear_displacement(0.7 * (1.0 + 1e-12), 0.7, k).unwrap();
            // The outside branch approaches like (1 − a²/r²)^{(1−k)/2}.
            let tol = 10.0 * (2e-12f64).powf(0.5 * (1.0 - k));
            assert!((inside - outside).abs() < tol, "k={k}: {inside} {outside}");
        }
        // Graded Hertz table (docs/theory-mdr.md#graded-closed-forms), E₀ = z₀ = R = 1, ν = 0.3, δ = 0.01.
        for (k, c_n, a, f, p0) in [
            (-0.5, 0.4017282, 0.0707107, 3.4184152e-3, 0.27202884),
            (0.5, 1.2542952, 0.1224745, 4.0960844e-4, 1.5211282e-2),
        ] {
            assert!((graded_sphere_radius(0.01, 1.0, k) - a).abs() < 1e-7);
            assert!((graded_sphere_force(a, 1.0, c_n, k) / f - 1.0).abs() < 1e-5);
            assert!((graded_sphere_pressure(0.0, a, 1.0, c_n, k) / p0 - 1.0).abs() < 1e-5);
        }
    }

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
