//! The wear laws and the body the wear is booked to (docs/wear3d.md#wear-laws).

use crate::SamError;

/// A local wear law per fretting cycle, integrated over the computed cycle's increments `k`
/// (docs/wear3d.md#wear-laws; `S_k` the slip of increment `k`, `p_k`, `q_k` its pressure and shear):
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WearLaw {
    /// Archard: `dh/dN = k Σ_k p_k |S_k|` (`k` = wear coefficient over hardness, m²/N, i.e.
    /// m³/(N·m)); Willert 2021 Eq. 30, docs/theory-mdr.md#archard-wear-per-cycle.
    Archard {
        /// `k` (m²/N).
        coefficient: f64,
    },
    /// Fouvry's dissipated-energy law: `dh/dN = α Σ_k |q_k| |S_k|` (`α` in m³/J = m²/N): the worn
    /// volume is `α` times the dissipated energy.
    Energy {
        /// `α` (m³/J).
        coefficient: f64,
    },
}

impl WearLaw {
    /// The coefficient (`k` or `α`).
    pub fn coefficient(&self) -> f64 {
        match *self {
            Self::Archard { coefficient } | Self::Energy { coefficient } => coefficient,
        }
    }

    /// `archard` or `energy` (the configuration's `law`).
    pub fn name(&self) -> &'static str {
        match self {
            Self::Archard { .. } => "archard",
            Self::Energy { .. } => "energy",
        }
    }

    /// The law of configuration name `name` (`archard` or `energy`) with `coefficient`.
    pub fn from_name(name: &str, coefficient: f64) -> Result<Self, SamError> {
        let law = match name {
            "archard" => Self::Archard { coefficient },
            "energy" => Self::Energy { coefficient },
            other => {
                return Err(SamError::InvalidInput(format!(
                    "wear law '{other}': archard or energy"
                )))
            }
        };
        law.validate()?;
        Ok(law)
    }

    /// The coefficient is finite and > 0.
    pub fn validate(&self) -> Result<(), SamError> {
        crate::error::positive(
            "wear coefficient (k of Archard or α of the energy law, m²/N)",
            self.coefficient(),
        )?;
        Ok(())
    }

    /// The local depth rate per cycle of one increment: `k p |S|` or `α |q| |S|`.
    pub fn rate(&self, pressure: f64, shear: f64, slip: f64) -> f64 {
        match *self {
            Self::Archard { coefficient } => coefficient * pressure * slip,
            Self::Energy { coefficient } => coefficient * shear * slip,
        }
    }

    /// The rate's sensitivity to the pressure per unit slip, `∂(dh/dN)/∂p / |Δu|`: `k`, or `αμ`
    /// (in the slip zone `|q| = μp`): the stiffness of the explicit wear step
    /// (docs/wear3d.md#the-wear-step-and-cycle-jumping).
    pub fn pressure_coefficient(&self, friction: f64) -> f64 {
        match *self {
            Self::Archard { coefficient } => coefficient,
            Self::Energy { coefficient } => coefficient * friction,
        }
    }
}

/// The body the worn depth is booked to. The gap grows by the depth in all three cases; with
/// inhomogeneities in the flat, the depth over them is what moves them toward the surface
/// (docs/wear3d.md#inhomogeneities-under-wear).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WornBody {
    /// The gap (the total over both bodies; counted as the flat's for the inhomogeneities: the
    /// conservative reading).
    Gap,
    /// The flat (the half-space).
    Flat,
    /// The indenter.
    Indenter,
}

impl WornBody {
    /// `gap`, `flat` or `indenter` (the configuration's `body`).
    pub fn name(&self) -> &'static str {
        match self {
            Self::Gap => "gap",
            Self::Flat => "flat",
            Self::Indenter => "indenter",
        }
    }

    /// The body of configuration name `name`.
    pub fn from_name(name: &str) -> Result<Self, SamError> {
        match name {
            "gap" => Ok(Self::Gap),
            "flat" => Ok(Self::Flat),
            "indenter" => Ok(Self::Indenter),
            other => Err(SamError::InvalidInput(format!(
                "wear body '{other}': gap, flat or indenter"
            ))),
        }
    }

    /// Whether the flat's inhomogeneities come closer to the surface as it wears.
    pub fn wears_flat(&self) -> bool {
        !matches!(self, Self::Indenter)
    }
}
