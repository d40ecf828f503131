//! The MDR fretting-wear case (`halfspace fretting-wear`, the Python `fretting_wear`;
//! docs/fretting-wear.md): its keys read by serde from TOML, JSON or a Python dict, the medium
//! through the one parser ([`crate::spec::parse_wear_medium`]), validated once in
//! [`WearConfig::case`] ([`FrettingParams::validate`]).

use serde::Deserialize;

use crate::config::Names;
use crate::fretting::{FrettingError, FrettingParams, TimeStepping};
use crate::spec::{parse_wear_medium, SpecError, WearMedium};

/// The keys of a normalized MDR fretting-wear run, as the flags of `halfspace fretting-wear`
/// (`--tau-end` is `tau_end`) plus `snapshots` (the τ of the recorded profiles): every key
/// optional, defaults [`FrettingParams::default`].
#[derive(Debug, Clone, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct WearConfig {
    /// u_A / u_max, 0 < χ < 1.
    pub chi: Option<f64>,
    /// Grid nodes N.
    pub n: Option<usize>,
    /// Local error tolerance of the adaptive (ROS2) steps (default 1e-4); not with `dtau`.
    pub tol: Option<f64>,
    /// Fixed wear step Δτ.
    pub dtau: Option<f64>,
    /// Final τ = N/N₀.
    pub tau_end: Option<f64>,
    /// Domain size L/a₀ (default [`FrettingParams::default_length`]).
    pub length: Option<f64>,
    /// τ of the recorded profiles (those ≤ `tau_end` are kept).
    pub snapshots: Option<Vec<f64>>,
    /// `"fft"` (default) or `"mvm"`.
    pub method: Option<String>,
    /// The medium ([`parse_wear_medium`]): `homogeneous` (default), `homogeneous:nu=..`,
    /// `graded:k=..,nu=..`.
    pub material: Option<String>,
}

/// A validated MDR fretting-wear run: the library's parameters and the medium.
#[derive(Debug, Clone, PartialEq)]
pub struct WearRunCase {
    pub params: FrettingParams,
    pub medium: WearMedium,
}

impl WearConfig {
    /// `flags` over `self` key by key (the command line over its `--config` file).
    pub fn overlay(self, flags: WearConfig) -> Self {
        Self {
            chi: flags.chi.or(self.chi),
            n: flags.n.or(self.n),
            tol: flags.tol.or(self.tol),
            dtau: flags.dtau.or(self.dtau),
            tau_end: flags.tau_end.or(self.tau_end),
            length: flags.length.or(self.length),
            snapshots: flags.snapshots.or(self.snapshots),
            method: flags.method.or(self.method),
            material: flags.material.or(self.material),
        }
    }

    /// The run's parameters, every key checked once ([`FrettingParams::validate`]); errors name
    /// the keys as `names` spells them.
    pub fn case(&self, names: Names) -> Result<WearRunCase, SpecError> {
        let medium = match &self.material {
            Some(spec) => parse_wear_medium(spec, &names.of("material"))?,
            None => WearMedium { k: 0.0, nu: None },
        };
        let mut p = FrettingParams {
            backend: crate::axisym::backend(self.method.as_deref(), names)?,
            ..FrettingParams::default()
        };
        p.chi = self.chi.unwrap_or(p.chi);
        p.nodes = self.n.unwrap_or(p.nodes);
        p.tau_end = self.tau_end.unwrap_or(p.tau_end);
        p.k = medium.k;
        p.length = self
            .length
            .unwrap_or_else(|| FrettingParams::default_length(p.chi, p.k));
        p.stepping = match (self.dtau, self.tol) {
            (Some(_), Some(_)) => {
                return Err(SpecError(format!(
                    "give a tolerance ({}, adaptive steps) or a fixed step ({}), not both",
                    names.of("tol"),
                    names.of("dtau")
                )))
            }
            (Some(dtau), None) => TimeStepping::Fixed { dtau },
            (None, tol) => TimeStepping::Adaptive {
                tolerance: tol.unwrap_or(TimeStepping::DEFAULT_TOLERANCE),
            },
        };
        if let Some(s) = &self.snapshots {
            p.snapshots = s.clone();
        }
        p.snapshots.retain(|t| *t <= p.tau_end + 1e-12);
        p.validate().map_err(|e| parameter_error(e, names))?;
        Ok(WearRunCase { params: p, medium })
    }
}

/// A parameter error naming the key it came from (`--tau-end` on the command line); the others
/// (`snapshots`, `k`, …) and Python's as the library names them.
fn parameter_error(e: FrettingError, names: Names) -> SpecError {
    match e {
        FrettingError::InvalidParameter {
            name,
            value,
            allowed,
        } if names == Names::Flags
            && ["chi", "n", "tol", "dtau", "tau_end", "length"].contains(&name) =>
        {
            SpecError(format!("{} must be {allowed}, got {value}", names.of(name)))
        }
        e => SpecError(e.to_string()),
    }
}
