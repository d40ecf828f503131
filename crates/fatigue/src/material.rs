//! Material constants of the fatigue criteria, validated (docs/fatigue.md, "Material constants").
use crate::error::FatigueError;

/// Fatigue and elastic constants of one material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Fully reversed bending (tension–compression) endurance limit `f₋₁`, Pa.
    pub f_minus1: f64,
    /// Fully reversed torsion endurance limit `t₋₁`, Pa.
    pub t_minus1: f64,
    /// Young's modulus `E`, Pa (strains of SWT and Fatemi–Socie by Hooke's law).
    pub young: f64,
    /// Poisson's ratio `ν`.
    pub poisson: f64,
    /// Fatemi–Socie normal-stress sensitivity `k` (dimensionless, typically 0.3 … 1).
    pub fs_k: f64,
    /// Yield stress `σ_y` normalising the normal stress in Fatemi–Socie, Pa.
    pub yield_stress: f64,
}

fn positive_finite(name: &'static str, value: f64) -> Result<(), FatigueError> {
    if !value.is_finite() {
        return Err(FatigueError::InvalidMaterial {
            name,
            value,
            reason: "must be finite",
        });
    }
    if value <= 0.0 {
        return Err(FatigueError::InvalidMaterial {
            name,
            value,
            reason: "must be positive",
        });
    }
    Ok(())
}

impl Material {
    /// Checks `f₋₁, t₋₁` for Crossland and Dang Van: finite, positive and
    /// `f₋₁/√3 < t₋₁ ≤ f₋₁`, so that `α_C > 0` and `α_DV > 0` (the criteria are pressure
    /// sensitive; `t₋₁ = f₋₁/√3` is von Mises, `t₋₁ > f₋₁` is met by no metal).
    pub fn validate_limits(&self) -> Result<(), FatigueError> {
        positive_finite("f_minus1", self.f_minus1)?;
        positive_finite("t_minus1", self.t_minus1)?;
        let lower = self.f_minus1 / 3f64.sqrt();
        if !(self.t_minus1 > lower && self.t_minus1 <= self.f_minus1) {
            return Err(FatigueError::TorsionBendingRatio {
                f_minus1: self.f_minus1,
                t_minus1: self.t_minus1,
                lower,
            });
        }
        Ok(())
    }

    /// Checks `E > 0` and `−1 < ν < 1/2` (finite).
    pub fn validate_elastic(&self) -> Result<(), FatigueError> {
        positive_finite("young", self.young)?;
        if !(self.poisson.is_finite() && self.poisson > -1.0 && self.poisson < 0.5) {
            return Err(FatigueError::InvalidMaterial {
                name: "poisson",
                value: self.poisson,
                reason: "must lie in (-1, 0.5)",
            });
        }
        Ok(())
    }

    /// Checks the Fatemi–Socie constants: `k ≥ 0` finite, `σ_y > 0` finite, and the elastic ones.
    pub fn validate_fatemi_socie(&self) -> Result<(), FatigueError> {
        self.validate_elastic()?;
        if !(self.fs_k.is_finite() && self.fs_k >= 0.0) {
            return Err(FatigueError::InvalidMaterial {
                name: "fs_k",
                value: self.fs_k,
                reason: "must be finite and non-negative",
            });
        }
        positive_finite("yield_stress", self.yield_stress)
    }

    /// All of [`Self::validate_limits`], [`Self::validate_elastic`],
    /// [`Self::validate_fatemi_socie`].
    pub fn validate(&self) -> Result<(), FatigueError> {
        self.validate_limits()?;
        self.validate_fatemi_socie()
    }

    /// Crossland's pressure coefficient `α_C = (t₋₁ − f₋₁/√3)/(f₋₁/3)` (docs/fatigue.md, Eq. F3).
    pub fn alpha_crossland(&self) -> f64 {
        (self.t_minus1 - self.f_minus1 / 3f64.sqrt()) / (self.f_minus1 / 3.0)
    }

    /// Dang Van's pressure coefficient `α_DV = (t₋₁ − f₋₁/2)/(f₋₁/3)` (docs/fatigue.md, Eq. F4).
    pub fn alpha_dang_van(&self) -> f64 {
        (self.t_minus1 - 0.5 * self.f_minus1) / (self.f_minus1 / 3.0)
    }

    /// Shear modulus `G = E/(2(1 + ν))`.
    pub fn shear_modulus(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }
}
