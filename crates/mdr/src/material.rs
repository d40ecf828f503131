//! The elastic half-space. Homogeneous: `E* = E/(1−ν²)` for a rigid indenter, or the combined
//! modulus `1/E* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂` given directly (spec conventions).

use crate::error::{positive, MdrError};

/// An elastic half-space as the MDR sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    /// Homogeneous, isotropic, with contact modulus `E*`.
    Homogeneous {
        /// Contact modulus `E*` in Pa.
        e_star: f64,
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

    /// The modulus of the MDR's Winkler bed, `c_N` (spec §4.2); `= E*` for a homogeneous medium.
    pub fn contact_modulus(&self) -> f64 {
        match *self {
            Material::Homogeneous { e_star } => e_star,
        }
    }

    /// Grading exponent `k` of `E(z) = E₀ (z/z₀)^k`; 0 for a homogeneous medium.
    pub fn grading_exponent(&self) -> f64 {
        match self {
            Material::Homogeneous { .. } => 0.0,
        }
    }
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
