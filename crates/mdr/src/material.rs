//! The elastic half-space. Homogeneous: `E* = E/(1−ν²)` for a rigid indenter, or the combined
//! modulus `1/E* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂` given directly (docs/theory-mdr.md#conventions). Power-law graded:
//! `E(z) = E₀ (z/z₀)^k`, `−1 < k < 1`, constant `ν`, with the MDR constant `c_N` of docs/theory-mdr.md#graded-constant-cn.

use std::f64::consts::PI;

use halfspace_numerics::special::gamma;

use crate::error::{positive, MdrError};

/// An elastic half-space as the MDR sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    /// Homogeneous, isotropic, with contact modulus `E*`.
    Homogeneous {
        /// Contact modulus `E*` in Pa.
        e_star: f64,
    },
    /// Power-law graded, `E(z) = E₀ (z/z₀)^k` (docs/theory-mdr.md#graded-media; the paper's `c₀` is `z₀`).
    PowerLaw {
        /// `E₀` in Pa, the modulus at depth `z₀`.
        e0: f64,
        /// Reference depth `z₀` in m.
        z0: f64,
        /// Poisson ratio `ν ∈ (−1, 0.5]`.
        nu: f64,
        /// Grading exponent `k ∈ (−1, 1)`.
        k: f64,
    },
}

impl Material {
    /// Homogeneous half-space of Young's modulus `e` and Poisson ratio `nu ∈ (−1, 0.5]` under a
    /// rigid indenter: `E* = E/(1−ν²)`.
    pub fn homogeneous(e: f64, nu: f64) -> Result<Self, MdrError> {
        positive("Young's modulus E", e)?;
        check_poisson(nu)?;
        Self::from_e_star(e / (1.0 - nu * nu))
    }

    /// Homogeneous half-space with the contact modulus `E*` given directly.
    pub fn from_e_star(e_star: f64) -> Result<Self, MdrError> {
        positive("contact modulus E*", e_star)?;
        Ok(Material::Homogeneous { e_star })
    }

    /// Power-law graded half-space `E(z) = E₀ (z/z₀)^k` with `E₀, z₀ > 0`, `ν ∈ (−1, 0.5]`,
    /// `k ∈ (−1, 1)` (docs/theory-mdr.md#p12-special-functions: `|k| ≥ 1` is refused). `k = 0` is the homogeneous medium with
    /// `E* = E₀/(1−ν²)`, through the same code.
    pub fn power_law(e0: f64, z0: f64, nu: f64, k: f64) -> Result<Self, MdrError> {
        positive("modulus E0", e0)?;
        positive("reference depth z0", z0)?;
        check_poisson(nu)?;
        if !(k.is_finite() && k > -1.0 && k < 1.0) {
            return Err(MdrError::InvalidParameter {
                name: "grading exponent k",
                value: k,
                allowed: "in (−1, 1)",
            });
        }
        Ok(Material::PowerLaw { e0, z0, nu, k })
    }

    /// The modulus of the MDR's Winkler bed, `c_N` (docs/theory-mdr.md#graded-constant-cn); `= E*` for a homogeneous medium.
    /// Its unit is Pa·m^{−k}: the bed's line load is `q = c_N |x|^k (δ − g)`.
    pub fn contact_modulus(&self) -> f64 {
        match *self {
            Material::Homogeneous { e_star } => e_star,
            Material::PowerLaw { e0, z0, nu, k } => {
                e0 / ((1.0 - nu * nu) * z0.powf(k)) * graded_constant_factor(k, nu)
            }
        }
    }

    /// Grading exponent `k` of `E(z) = E₀ (z/z₀)^k`; 0 for a homogeneous medium.
    pub fn grading_exponent(&self) -> f64 {
        match *self {
            Material::Homogeneous { .. } => 0.0,
            Material::PowerLaw { k, .. } => k,
        }
    }
}

/// The dimensionless factor of `c_N` (docs/theory-mdr.md#graded-constant-cn, derived and verified there):
/// `c_N (1−ν²) z₀^k / E₀ = (1+k)² cos(πk/2) Γ(1+k/2)² / (β sin(πβ/2) Γ((3+k+β)/2) Γ((3+k−β)/2))`,
/// `β = √((1+k)(1 − kν/(1−ν)))`; 1 at `k = 0` (then `β = 1`). For `−1 < k < 1`, `ν ∈ (−1, 0.5]`,
/// `β ∈ (0, 2)` and every Γ argument is positive.
pub fn graded_constant_factor(k: f64, nu: f64) -> f64 {
    if k == 0.0 {
        // Exactly 1, so that k = 0 reproduces the homogeneous medium bit for bit.
        return 1.0;
    }
    let beta = ((1.0 + k) * (1.0 - k * nu / (1.0 - nu))).sqrt();
    let g = gamma(1.0 + 0.5 * k);
    (1.0 + k).powi(2) * (0.5 * PI * k).cos() * g * g
        / (beta
            * (0.5 * PI * beta).sin()
            * gamma(0.5 * (3.0 + k + beta))
            * gamma(0.5 * (3.0 + k - beta)))
}

/// Checks `ν ∈ (−1, 0.5]` and finiteness.
pub fn check_poisson(nu: f64) -> Result<f64, MdrError> {
    if nu.is_finite() && nu > -1.0 && nu <= 0.5 {
        Ok(nu)
    } else {
        Err(MdrError::InvalidParameter {
            name: "Poisson ratio ν",
            value: nu,
            allowed: "in (−1, 0.5]",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn c_n_table_of_spec_section_4_2() {
        // c_N z₀^k / E₀ for ν = 0, 0.3, 0.5 and k = −0.75 … 0.75.
        let ks = [-0.75, -0.5, -0.25, 0.0, 0.25, 0.5, 0.75];
        let table = [
            (
                0.0,
                [
                    0.143724, 0.437416, 0.752595, 1.0, 1.104151, 1.000894, 0.641755,
                ],
            ),
            (
                0.3,
                [
                    0.120215, 0.401728, 0.758891, 1.098901, 1.305763, 1.254295, 0.838920,
                ],
            ),
            (
                0.5,
                [
                    0.111028, 0.402833, 0.833598, 1.333333, 1.793896, 2.105909, 2.205635,
                ],
            ),
        ];
        for (nu, row) in table {
            for (k, want) in ks.iter().zip(row) {
                let m = Material::power_law(1.0, 1.0, nu, *k).unwrap();
                let got = m.contact_modulus();
                assert!((got - want).abs() < 1e-6, "ν={nu} k={k}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn c_n_limits() {
        // k = 0: c_N = E*.
        for nu in [-0.5, 0.0, 0.3, 0.5] {
            let m = Material::power_law(2.0e11, 1e-6, nu, 0.0).unwrap();
            let h = Material::homogeneous(2.0e11, nu).unwrap();
            assert!((m.contact_modulus() / h.contact_modulus() - 1.0).abs() < 1e-14);
        }
        // Gibson limit (k → 1, ν = 1/2): c_N → 2π E₀/(3 z₀); the approach is linear in 1 − k.
        let (e0, z0) = (3.0, 2.0);
        let want = 2.0 * PI * e0 / (3.0 * z0);
        let at = |k: f64| {
            Material::power_law(e0, z0, 0.5, k)
                .unwrap()
                .contact_modulus()
        };
        let (e1, e2) = (
            (at(1.0 - 1e-4) / want - 1.0).abs(),
            (at(1.0 - 1e-5) / want - 1.0).abs(),
        );
        assert!(e2 < 1e-4, "{e2}");
        assert!((e1 / e2 - 10.0).abs() < 1.0, "linear approach: {e1} {e2}");
        // Scaling with z₀: c_N ∝ z₀^{−k}.
        let a = Material::power_law(1.0, 1.0, 0.3, 0.5)
            .unwrap()
            .contact_modulus();
        let b = Material::power_law(1.0, 4.0, 0.3, 0.5)
            .unwrap()
            .contact_modulus();
        assert!((a / b - 2.0).abs() < 1e-14);
    }

    #[test]
    fn graded_parameters_are_checked() {
        for k in [-1.0, 1.0, 1.5, f64::NAN] {
            let e = Material::power_law(1.0, 1.0, 0.3, k).unwrap_err();
            assert!(e.to_string().contains("grading exponent k"), "{e}");
        }
        assert!(Material::power_law(0.0, 1.0, 0.3, 0.5).is_err());
        assert!(Material::power_law(1.0, -1.0, 0.3, 0.5).is_err());
        assert!(Material::power_law(1.0, 1.0, 0.7, 0.5).is_err());
    }

    #[test]
    fn e_star_of_the_composite_paper() {
        let m = Material::homogeneous(210e9, 0.3).unwrap();
        assert!((m.contact_modulus() - 210e9 / 0.91).abs() < 1e-3);
        assert!(Material::homogeneous(210e9, 0.5).is_ok());
        for nu in [-1.0, 0.51, f64::NAN] {
            assert!(Material::homogeneous(1.0, nu).is_err());
        }
        for e in [0.0, -1.0, f64::INFINITY] {
            assert!(Material::homogeneous(e, 0.3).is_err());
            assert!(Material::from_e_star(e).is_err());
        }
    }
}
