//! The 3D contact case (`halfspace contact3d`, the Python `contact3d`; docs/architecture.md, "The
//! application layer"): its keys read by serde from TOML, JSON or a Python dict, the
//! `kind:key=value` indenter, bodies and inhomogeneities through the one parser
//! ([`crate::spec`]), validated once in [`Contact3dConfig::case`] and by
//! [`solve_contact`](crate::sam::drivers::one_contact::solve_contact).

use serde::Deserialize;

use crate::config::{InhomogeneityEntry, Names};
use crate::sam::drivers::one_contact::{ContactCase, TangentialLoad};
use crate::sam::normal::NormalLoad;
use crate::sam::Body;
use crate::spec::{parse_body, parse_indenter, parse_inhomogeneity, SpecError};

/// The keys of one 3D contact, as the flags of `halfspace contact3d` (`--shift-x` is `shift_x`,
/// `--inhomogeneity` is the list `inhomogeneity`): every key optional here, required ones
/// checked by [`Self::case`].
#[derive(Debug, Clone, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct Contact3dConfig {
    /// `sphere:R=..`, `ellipsoid:Rx=..,Ry=..`, `cone:slope=..`, `flat:a=..`, `table:FILE.npy`.
    pub indenter: Option<String>,
    /// The half-space: `homogeneous:E=..,nu=..`.
    pub material: Option<String>,
    /// The indenter's body: `rigid` (default) or `homogeneous:E=..,nu=..`.
    pub indenter_material: Option<String>,
    /// Normal force W (N); exactly one of `force` and `depth`.
    pub force: Option<f64>,
    /// Rigid approach δ (m).
    pub depth: Option<f64>,
    /// Rigid tangential shift along x (m) after the normal load; at most one of `shift_x` and
    /// `tangential_force`.
    pub shift_x: Option<f64>,
    /// Tangential force along x (N) after the normal load.
    pub tangential_force: Option<f64>,
    /// Coulomb friction coefficient μ (default 0; a tangential load needs μ > 0).
    pub friction: Option<f64>,
    /// Inhomogeneities: `kind:key=value` specs or tables by `kind` (as in the fretting loop's
    /// `[[inhomogeneity]]`).
    pub inhomogeneity: Vec<InhomogeneityEntry>,
    /// Depth (m) of the stress field below the surface.
    pub subsurface: Option<f64>,
    /// Cells per side (default 128).
    pub grid: Option<usize>,
    /// Side of the square domain (m; default: 4 estimated contact radii).
    pub extent: Option<f64>,
    /// Relative tolerance of the solvers (default 1e-10).
    pub tol: Option<f64>,
}

impl Contact3dConfig {
    /// `flags` over `self` key by key (the command line over its `--config` file); the
    /// inhomogeneities of `flags` follow those of `self`.
    pub fn overlay(mut self, flags: Contact3dConfig) -> Self {
        self.inhomogeneity.extend(flags.inhomogeneity);
        Self {
            indenter: flags.indenter.or(self.indenter),
            material: flags.material.or(self.material),
            indenter_material: flags.indenter_material.or(self.indenter_material),
            force: flags.force.or(self.force),
            depth: flags.depth.or(self.depth),
            shift_x: flags.shift_x.or(self.shift_x),
            tangential_force: flags.tangential_force.or(self.tangential_force),
            friction: flags.friction.or(self.friction),
            inhomogeneity: self.inhomogeneity,
            subsurface: flags.subsurface.or(self.subsurface),
            grid: flags.grid.or(self.grid),
            extent: flags.extent.or(self.extent),
            tol: flags.tol.or(self.tol),
        }
    }

    /// Whether the indenter is a height table (`table:FILE.npy`, which needs `extent`).
    pub fn is_table(&self) -> bool {
        self.indenter
            .as_deref()
            .is_some_and(|s| s.trim_start().starts_with("table:"))
    }

    /// The library's case, every key checked once; errors name the keys as `names` spells them.
    pub fn case(&self, names: Names) -> Result<ContactCase, SpecError> {
        let n = |key: &str| names.of(key);
        let indenter_spec = self
            .indenter
            .as_deref()
            .ok_or_else(|| SpecError(format!("give {}", n("indenter"))))?;
        if self.is_table() && self.extent.is_none() {
            return Err(SpecError(format!(
                "{} table: give {} (the side of the grid in m)",
                n("indenter"),
                n("extent")
            )));
        }
        let indenter = parse_indenter(indenter_spec, &n("indenter"))?;
        let material = self
            .material
            .as_deref()
            .ok_or_else(|| SpecError(format!("give {}", n("material"))))?;
        let half_space = parse_body(material, &n("material"))?;
        if matches!(half_space, Body::Rigid) {
            return Err(SpecError(format!(
                "{}: the half-space must be elastic",
                n("material")
            )));
        }
        let indenter_body = parse_body(
            self.indenter_material.as_deref().unwrap_or("rigid"),
            &n("indenter_material"),
        )?;
        let load = match (self.force, self.depth) {
            (Some(w), None) => NormalLoad::Force(w),
            (None, Some(d)) => NormalLoad::Approach(d),
            _ => {
                return Err(SpecError(format!(
                    "give exactly one of {} and {}",
                    names.arg("force"),
                    names.arg("depth")
                )))
            }
        };
        for (key, v) in [("force", self.force), ("depth", self.depth)] {
            if let Some(v) = v {
                if !(v.is_finite() && v > 0.0) {
                    return Err(SpecError(format!(
                        "{} must be finite and > 0, got {v}",
                        n(key)
                    )));
                }
            }
        }
        let tangential = match (self.shift_x, self.tangential_force) {
            (Some(dx), None) => Some(TangentialLoad::Shift(dx)),
            (None, Some(q)) => Some(TangentialLoad::Force(q)),
            (None, None) => None,
            (Some(_), Some(_)) => {
                return Err(SpecError(format!(
                    "give at most one of {} and {}",
                    names.arg("shift_x"),
                    names.arg("tangential_force")
                )))
            }
        };
        let tangential_keys = format!("{} / {}", n("shift_x"), n("tangential_force"));
        let friction = match self.friction {
            Some(mu) if !(mu.is_finite() && mu >= 0.0) => {
                return Err(SpecError(format!(
                    "{} must be finite and ≥ 0, got {mu}",
                    n("friction")
                )))
            }
            Some(mu) => mu,
            None if tangential.is_some() => {
                return Err(SpecError(format!(
                    "{tangential_keys} need a friction coefficient: give {} MU",
                    n("friction")
                )))
            }
            None => 0.0,
        };
        if tangential.is_some() && friction == 0.0 {
            return Err(SpecError(format!(
                "{tangential_keys} with {} 0: a frictionless contact carries no tangential load",
                n("friction")
            )));
        }
        if let Some(d) = self.subsurface {
            if !(d.is_finite() && d > 0.0) {
                return Err(SpecError(format!(
                    "{} must be a depth > 0 in m, got {d}",
                    n("subsurface")
                )));
            }
        }
        if let Some(k) = self
            .inhomogeneity
            .iter()
            .position(|e| e.fatigue().is_some())
        {
            return Err(SpecError(format!(
                "[[inhomogeneity]] {} has a fatigue table, which contact3d does not read \
                 (fatigue criteria are evaluated over a fretting cycle: fretting-loop with a \
                 [fatigue] table); remove it",
                k + 1
            )));
        }
        let inhomogeneities = self
            .inhomogeneity
            .iter()
            .enumerate()
            .map(|(k, entry)| match entry {
                InhomogeneityEntry::Spec(spec) => parse_inhomogeneity(spec, &n("inhomogeneity")),
                table => table.inhomogeneity(k + 1),
            })
            .collect::<Result<Vec<_>, _>>()?;
        let tolerance = self.tol.unwrap_or(1e-10);
        if !(tolerance.is_finite() && tolerance > 0.0 && tolerance < 1e-2) {
            return Err(SpecError(format!(
                "{} must be in (0, 1e-2), got {tolerance}",
                n("tol")
            )));
        }
        Ok(ContactCase {
            indenter,
            indenter_body,
            half_space,
            load,
            tangential,
            friction,
            grid: self.grid.unwrap_or(128),
            extent: self.extent,
            tolerance,
            inhomogeneities,
            subsurface_depth: self.subsurface,
        })
    }
}
