//! The axisymmetric contact case (`halfspace axisym`, the Python `axisym`; docs/architecture.md,
//! "The application layer"): its keys read by serde from TOML, JSON or a Python dict, the
//! `kind:key=value` profile and material through the one parser ([`crate::spec`]), validated once
//! in [`AxisymConfig::case`].

use serde::Deserialize;

use crate::config::Names;
use crate::mdr::{
    Backend, ContactParams, ContactSolution, ContactSolver, Load, Material, MdrError, Profile,
};
use crate::spec::{parse_material, parse_profile, SpecError};

/// The keys of an axisymmetric contact, as the flags of `halfspace axisym` (`--domain-ratio` is
/// `domain_ratio`): every key optional here, required ones checked by [`Self::case`].
#[derive(Debug, Clone, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct AxisymConfig {
    /// `sphere:R=..`, `cone:slope=..`, `flat:a=..`, `power:c=..,n=..`, `table:FILE.npy`, or a
    /// table `{ r = [..], f = [..] }` (nodes and heights in m).
    pub profile: Option<ProfileEntry>,
    /// `homogeneous:E=..,nu=..`, `homogeneous:Estar=..`, `graded:E0=..,z0=..,nu=..,k=..`.
    pub material: Option<String>,
    /// Indentation depth δ (m); exactly one of `depth` and `force`.
    pub depth: Option<f64>,
    /// Normal force F (N).
    pub force: Option<f64>,
    /// Grid nodes N (default 2001).
    pub n: Option<usize>,
    /// `"fft"` (default) or `"mvm"`.
    pub method: Option<String>,
    /// Domain size over contact radius L/a (default 1.5).
    pub domain_ratio: Option<f64>,
}

/// A profile: a `kind:key=value` spec or the nodes and heights of a tabulated profile.
#[derive(Debug, Clone, PartialEq)]
pub enum ProfileEntry {
    /// A spec string ([`parse_profile`]).
    Spec(String),
    /// `{ r = [..], f = [..] }`: nodes r (m, increasing from 0) and heights f (m).
    Table(ProfileTable),
}

/// The arrays of a tabulated profile.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProfileTable {
    pub r: Vec<f64>,
    pub f: Vec<f64>,
}

impl<'de> Deserialize<'de> for ProfileEntry {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        crate::config::spec_or_table(
            d,
            "a kind:key=value profile spec, or a table { r = [..], f = [..] }",
            ProfileEntry::Spec,
            ProfileEntry::Table,
        )
    }
}

/// An axisymmetric contact, validated: what [`ContactSolver`] needs, and the profile and material
/// as given (the summary's `profile` and `material`; `"table"` for a tabulated profile).
#[derive(Debug, Clone)]
pub struct AxisymCase {
    pub profile: Profile,
    pub material: Material,
    pub load: Load,
    pub params: ContactParams,
    pub profile_spec: String,
    pub material_spec: String,
}

impl AxisymConfig {
    /// `flags` over `self` key by key (the command line over its `--config` file).
    pub fn overlay(self, flags: AxisymConfig) -> Self {
        Self {
            profile: flags.profile.or(self.profile),
            material: flags.material.or(self.material),
            depth: flags.depth.or(self.depth),
            force: flags.force.or(self.force),
            n: flags.n.or(self.n),
            method: flags.method.or(self.method),
            domain_ratio: flags.domain_ratio.or(self.domain_ratio),
        }
    }

    /// The case, every key checked once; errors name the keys as `names` spells them.
    pub fn case(&self, names: Names) -> Result<AxisymCase, SpecError> {
        let missing = |key: &str| SpecError(format!("give {}", names.of(key)));
        let (profile, profile_spec) =
            match self.profile.as_ref().ok_or_else(|| missing("profile"))? {
                ProfileEntry::Spec(spec) => {
                    (parse_profile(spec, &names.of("profile"))?, spec.clone())
                }
                ProfileEntry::Table(t) => (
                    Profile::tabulated(t.r.clone(), t.f.clone())
                        .map_err(|e| SpecError(format!("{} table: {e}", names.of("profile"))))?,
                    "table".to_string(),
                ),
            };
        let material_spec = self.material.clone().ok_or_else(|| missing("material"))?;
        let material = parse_material(&material_spec, &names.of("material"))?;
        let load = match (self.depth, self.force) {
            (Some(d), None) => Load::Depth(d),
            (None, Some(f)) => Load::Force(f),
            _ => {
                return Err(SpecError(format!(
                    "give exactly one of {} and {}",
                    names.arg("force"),
                    names.arg("depth")
                )))
            }
        };
        let defaults = ContactParams::default();
        let params = ContactParams {
            nodes: self.n.unwrap_or(defaults.nodes),
            backend: backend(self.method.as_deref(), names)?,
            domain_ratio: self.domain_ratio.unwrap_or(defaults.domain_ratio),
            ..defaults
        };
        Ok(AxisymCase {
            profile,
            material,
            load,
            params,
            profile_spec,
            material_spec,
        })
    }
}

/// The transforms' backend of a `method` key: `"fft"` (default) or `"mvm"`.
pub fn backend(method: Option<&str>, names: Names) -> Result<Backend, SpecError> {
    match method {
        None | Some("fft") => Ok(Backend::Fft),
        Some("mvm") => Ok(Backend::Mvm),
        Some(other) => Err(SpecError(format!(
            "{} '{other}': use fft or mvm",
            names.of("method")
        ))),
    }
}

impl AxisymCase {
    /// Solves the contact (Willert et al. 2021, Eqs. 7, 12/13, 17; graded media Eqs. 23–29).
    pub fn solve(&self) -> Result<ContactSolution, MdrError> {
        let mut solver = ContactSolver::new(self.material, self.params)?;
        solver.solve(&self.profile, self.load)
    }

    /// The summary of a solution of this case ([`crate::records::axisym_summary`]).
    pub fn summary(&self, sol: &ContactSolution) -> serde_json::Value {
        crate::records::axisym_summary(
            sol,
            &self.material,
            self.params.backend,
            self.params.nodes,
            &self.profile_spec,
            &self.material_spec,
        )
    }
}
