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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axisym::{AxisymConfig, ProfileEntry};
    use crate::config::{from_json, from_toml};
    use crate::contact3d::Contact3dConfig;

    /// TOML and JSON read the same keys into the same case; flags override key by key; every
    /// refusal names the key as the front end spells it.
    #[test]
    fn one_case_from_toml_json_and_flags() {
        let toml: WearConfig = from_toml(
            "chi = 0.4\nn = 301\ndtau = 0.01\nmaterial = \"graded:k=0.5,nu=0.3\"\n",
            "t",
        )
        .unwrap();
        let json: WearConfig = from_json(
            r#"{"chi": 0.4, "n": 301, "dtau": 0.01, "material": "graded:k=0.5,nu=0.3"}"#,
            "j",
        )
        .unwrap();
        assert_eq!(toml, json);
        let case = toml.case(Names::Keys).unwrap();
        assert_eq!(
            (case.params.chi, case.params.nodes, case.medium.k),
            (0.4, 301, 0.5)
        );
        // The axisym material spec gives the same medium (E0, z0 set scales only).
        let full = WearConfig {
            material: Some("graded:E0=2e11,z0=1e-3,nu=0.3,k=0.5".into()),
            ..toml.clone()
        };
        assert_eq!(full.case(Names::Keys).unwrap(), case);
        let both = toml.clone().overlay(WearConfig {
            tol: Some(1e-5),
            ..WearConfig::default()
        });
        let e = both.case(Names::Flags).unwrap_err().0;
        assert!(
            e.contains("(--tol, adaptive steps)") && e.contains("(--dtau)"),
            "{e}"
        );
        let e = both.case(Names::Keys).unwrap_err().0;
        assert!(e.contains("(tol, adaptive steps)"), "{e}");
        let e = from_toml::<WearConfig>("tau = 3.0\n", "t").unwrap_err().0;
        assert!(e.contains("unknown field `tau`"), "{e}");

        let a: AxisymConfig = from_toml(
            "profile = { r = [0.0, 0.5, 1.0], f = [0.0, 0.25, 1.0] }\nmaterial = \"homogeneous:E=1e9,nu=0.3\"\nforce = 1.0\n",
            "t",
        )
        .unwrap();
        assert!(matches!(a.profile, Some(ProfileEntry::Table(_))));
        assert_eq!(a.case(Names::Keys).unwrap().profile_spec, "table");
        let e = a
            .overlay(AxisymConfig {
                depth: Some(1e-6),
                ..AxisymConfig::default()
            })
            .case(Names::Keys)
            .unwrap_err()
            .0;
        assert!(e.contains("exactly one of force= and depth="), "{e}");

        let c: Contact3dConfig = from_toml(
            "indenter = \"sphere:R=1e-4\"\nmaterial = \"homogeneous:E=2e11,nu=0.3\"\nforce = 0.08\n\
             inhomogeneity = [\"sphere:x=0,y=0,z=2e-6,r=1e-6,E=4e11,nu=0.3\"]\n",
            "t",
        )
        .unwrap();
        let flags = Contact3dConfig {
            inhomogeneity: c.inhomogeneity.clone(),
            ..Contact3dConfig::default()
        };
        let case = c.overlay(flags).case(Names::Flags).unwrap();
        assert_eq!((case.inhomogeneities.len(), case.grid), (2, 128));
    }
}
