//! Configurations of the library's drivers as plain data, read by serde — TOML for the CLI
//! (`--config`), a Python dict as TOML data ([`from_table`]) — with one spelling of every key, one
//! schema and one conversion to the library's types (validated once, in [`LoopConfig::case`]).
//!
//! A new key of the fretting loop is one field of [`LoopConfig`] (with its default) and its use
//! in `loop_case`; TOML files and Python dicts read it at once. A key [`LoopCase`] shares is
//! declared once, in `halfspace_sam::fretting_loop_keys!`.

use serde::Deserialize;

use crate::fatigue::Material;
use crate::sam::contact::Alternation;
use crate::sam::drivers::fretting_loop::LoopCase;
use crate::sam::drivers::fretting_map::FrettingMap;
use crate::sam::drivers::fretting_wear3d::{
    WearCase, WearLaw, WornBody, DEFAULT_STABILITY_FRACTION, DEFAULT_STEP_FRACTION,
    INHOMOGENEITY_DEPTH_CELLS,
};
use crate::sam::eim::{Axis, FibreLayout, Inhomogeneity, Shape};
use crate::sam::kernels::surface::Body;
use crate::spec::{parse_inhomogeneity, SpecError};

crate::sam::fretting_loop_keys! {
    /// The fretting-loop configuration as read from TOML (`fretting-loop --config`) or from a
    /// Python dict: the keys of [`LoopCase`] in SI units (the shared ones declared once, by
    /// `fretting_loop_keys!`), `[[inhomogeneity]]` tables, the composite preset's `layout` and
    /// `fibre_e_ratio`, and `subsurface_over_a` (defaults: \[LN11\]'s homogeneous case).
    #[derive(Debug, Clone, Deserialize)]
    #[serde(deny_unknown_fields, default)]
    pub struct LoopConfig {
        load {
            /// Normal force W (N); exactly one of `force` and `approach` (neither: W = 80 mN).
            force: Option<f64> = None,
            /// Rigid approach δ (m): normal control by approach instead of force.
            approach: Option<f64> = None,
            /// Young's modulus of the indenter (Pa); with `indenter_nu`, an elastic indenter
            /// (absent: rigid).
            indenter_e: Option<f64> = None,
            /// Poisson ratio of the indenter (with `indenter_e`).
            indenter_nu: Option<f64> = None,
        }
        rest {
            /// `[[inhomogeneity]]` tables: `kind = "sphere" | "cylinder" | "cuboid"` and the keys
            /// of the CLI's `--inhomogeneity` specs (`x, y, z, r, axis, hx, hy, hz, E, nu`), or
            /// such specs.
            inhomogeneity: Vec<InhomogeneityEntry> = Vec::new(),
            /// Composite preset only: `"fibre-centred"` (a fibre axis at x = 0, the default) or
            /// `"gap-centred"`; refused without the preset (it would be ignored).
            layout: Option<String> = None,
            /// Composite preset only: E_I / E_m of the fibres (2 in \[LN11\], the default; 0.5 for
            /// soft fibres); refused without the preset.
            fibre_e_ratio: Option<f64> = None,
            /// Depth of the von Mises fields at the points A–D over a (0: none).
            subsurface_over_a: f64 = 1.0,
            /// `[fatigue]`: the fatigue criteria over the closed cycle (docs/fatigue.md, "On the
            /// fretting loop"; absent: none).
            fatigue: Option<FatigueConfig> = None,
            /// How an inhomogeneous body's surface response enters each increment
            /// (docs/theory-sam.md#surface-response-operator): `"nested"` (the contact ↔ EIM loop
            /// in every increment, the reference and the default) or `"surface-operator"` (built
            /// once).
            inhomogeneous_body: InhomogeneousBody = InhomogeneousBody::Nested,
            /// With `inhomogeneous_body = "surface-operator"`: radius over a of the candidate
            /// region the operator covers (default 1.3); refused with the nested loop.
            surface_operator_radius_over_a: Option<f64> = None,
            /// The nested loop's EIM change factor `η` in (0, 1] (each outer pass's EIM solved to
            /// `η` times the last outer change, docs/theory-sam.md#outer-loop-tolerances; absent:
            /// the library's default); refused without inhomogeneities and with the surface
            /// operator (it would be ignored).
            eim_change_factor: Option<f64> = None,
            /// The nested loop's recycled EIM depth (Anderson differences of the block-Jacobi
            /// EIM iteration kept across an increment's outer passes, 0 to 50; 0: the plain
            /// iteration; docs/theory-sam.md#solving-the-eim-equations; absent: the library's
            /// default, 5); refused without inhomogeneities and with the surface operator.
            eim_recycled_depth: Option<usize> = None,
            /// The normal–tangential alternation of the contact solves: `"plain"` (the
            /// Gauss–Seidel alternation) or `"gauged"` (its early solves gauged by the change
            /// they meet; docs/theory-sam.md#normal-tangential-alternation; absent: the library's
            /// default); for the composite loop and its homogeneous reference alike; refused for
            /// an uncoupled pair (identical bodies: nothing alternates, it would be ignored).
            alternation: Option<String> = None,
        }
    }
}

/// The `inhomogeneous_body` key of [`LoopConfig`].
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum InhomogeneousBody {
    /// The nested contact ↔ EIM loop of \[LN11\] Fig. 2 in every increment (the reference path).
    #[default]
    Nested,
    /// The surface-response operator, built once per body (one EIM solve per column).
    SurfaceOperator,
}

/// The candidate radius over a of the surface-response operator when none is given.
pub const DEFAULT_SURFACE_OPERATOR_RADIUS_OVER_A: f64 = 1.3;

/// Fatigue constants of one material (docs/fatigue.md, "Material constants"): fully reversed
/// bending and torsion limits `f_minus1`, `t_minus1` (Pa), Fatemi–Socie's `fs_k` and
/// `yield_stress` (Pa); the elastic constants are the material's own.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FatigueConstants {
    pub f_minus1: f64,
    pub t_minus1: f64,
    pub fs_k: f64,
    pub yield_stress: f64,
}

/// The `fatigue` table of one `[[inhomogeneity]]` (docs/fatigue.md, "Materials"): that
/// inhomogeneity's own constants; a key left out is the one of `[fatigue.inhomogeneity]` if given,
/// else the matrix's (`[fatigue]`). Read only with a `[fatigue]` table.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Default)]
#[serde(deny_unknown_fields)]
pub struct InhomogeneityFatigue {
    pub f_minus1: Option<f64>,
    pub t_minus1: Option<f64>,
    pub fs_k: Option<f64>,
    pub yield_stress: Option<f64>,
}

impl InhomogeneityFatigue {
    /// `base` with the keys given here.
    pub fn over(&self, base: &FatigueConstants) -> FatigueConstants {
        FatigueConstants {
            f_minus1: self.f_minus1.unwrap_or(base.f_minus1),
            t_minus1: self.t_minus1.unwrap_or(base.t_minus1),
            fs_k: self.fs_k.unwrap_or(base.fs_k),
            yield_stress: self.yield_stress.unwrap_or(base.yield_stress),
        }
    }
}

/// The `[fatigue]` table: the matrix's constants, `depth_over_a` (the box below the contact,
/// default 1.5), `screen_fraction` (SWT and Fatemi–Socie are evaluated exactly where their
/// upper bound reaches this fraction of the maximum, default 0.5; 0: everywhere) and
/// `[fatigue.inhomogeneity]`, the constants of every inhomogeneity without its own `fatigue`
/// table (absent: the matrix's), and `process_volume` (m): the side ℓ of the process volume whose
/// averaged stress history the criteria are also evaluated on (docs/fatigue.md, "Process volume";
/// absent: not evaluated).
#[derive(Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FatigueConfig {
    pub f_minus1: f64,
    pub t_minus1: f64,
    pub fs_k: f64,
    pub yield_stress: f64,
    #[serde(default = "default_fatigue_depth")]
    pub depth_over_a: f64,
    #[serde(default = "default_screen_fraction")]
    pub screen_fraction: f64,
    #[serde(default)]
    pub inhomogeneity: Option<FatigueConstants>,
    #[serde(default)]
    pub process_volume: Option<f64>,
    /// Not a key: the `fatigue` tables of the `[[inhomogeneity]]` entries, in their order (the
    /// case's first inhomogeneities), filled by [`LoopConfig::fatigue_config`].
    #[serde(skip)]
    pub own: Vec<Option<InhomogeneityFatigue>>,
}

fn default_fatigue_depth() -> f64 {
    1.5
}

fn default_screen_fraction() -> f64 {
    0.5
}

impl std::fmt::Debug for FatigueConfig {
    /// The fields, [`FatigueConfig::own`] only when an inhomogeneity has its own table: a
    /// fretting map's point fingerprint (`{:?}`) of a configuration without them is the one
    /// its checkpoints were written with before the key existed.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut d = f.debug_struct("FatigueConfig");
        d.field("f_minus1", &self.f_minus1)
            .field("t_minus1", &self.t_minus1)
            .field("fs_k", &self.fs_k)
            .field("yield_stress", &self.yield_stress)
            .field("depth_over_a", &self.depth_over_a)
            .field("screen_fraction", &self.screen_fraction)
            .field("inhomogeneity", &self.inhomogeneity);
        // Only when given: the fingerprints of configurations without it are unchanged.
        if let Some(side) = self.process_volume {
            d.field("process_volume", &side);
        }
        if self.own.iter().any(Option::is_some) {
            d.field("own", &self.own);
        }
        d.finish()
    }
}

impl FatigueConfig {
    /// The matrix's constants (`[fatigue]`).
    pub fn matrix_constants(&self) -> FatigueConstants {
        FatigueConstants {
            f_minus1: self.f_minus1,
            t_minus1: self.t_minus1,
            fs_k: self.fs_k,
            yield_stress: self.yield_stress,
        }
    }

    /// The constants of inhomogeneity `i` of the case (from 0): its own `fatigue` keys, the
    /// others from `[fatigue.inhomogeneity]` if given, else the matrix's.
    pub fn inhomogeneity_constants(&self, i: usize) -> FatigueConstants {
        let matrix = self.matrix_constants();
        let every = self.inhomogeneity.unwrap_or(matrix);
        match self.own.get(i) {
            Some(Some(own)) => own.over(&every),
            _ => every,
        }
    }

    /// The criteria's material of `constants` with the elastic constants `(young, poisson)`.
    pub fn material(constants: &FatigueConstants, young: f64, poisson: f64) -> Material {
        Material {
            f_minus1: constants.f_minus1,
            t_minus1: constants.t_minus1,
            young,
            poisson,
            fs_k: constants.fs_k,
            yield_stress: constants.yield_stress,
        }
    }

    /// The matrix's material `(e, nu)`.
    pub fn matrix(&self, e: f64, nu: f64) -> Material {
        Self::material(&self.matrix_constants(), e, nu)
    }

    /// The material of each of `inclusions` (the case's inhomogeneities, in order): its `E`, `ν`
    /// and [`Self::inhomogeneity_constants`].
    pub fn inhomogeneity_materials(&self, inclusions: &[Inhomogeneity]) -> Vec<Material> {
        inclusions
            .iter()
            .enumerate()
            .map(|(i, inh)| Self::material(&self.inhomogeneity_constants(i), inh.e, inh.nu))
            .collect()
    }
}

/// One inhomogeneity of a configuration: a `[[inhomogeneity]]` table (TOML; a dict in Python)
/// with `kind` and the keys of the `--inhomogeneity` spec, spelled as there (`E` is the
/// inhomogeneity's Young's modulus), or that spec string itself (read by [`parse_inhomogeneity`]).
/// Values are checked once, by [`Inhomogeneity::validate`], when the case is built.
#[derive(Debug, Clone, PartialEq)]
pub enum InhomogeneityEntry {
    /// A table, typed by its `kind`.
    Table(InhomogeneityTable),
    /// A `kind:key=value,...` spec.
    Spec(String),
}

/// The keys of a `[[inhomogeneity]]` table by `kind` (SI units; `z` the depth of the centre).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum InhomogeneityTable {
    /// `kind = "sphere"`: centre `x, y, z`, radius `r`.
    Sphere {
        x: f64,
        y: f64,
        z: f64,
        r: f64,
        #[serde(rename = "E")]
        e: f64,
        nu: f64,
        /// This inhomogeneity's fatigue constants (with `[fatigue]`; docs/fatigue.md,
        /// "Materials").
        #[serde(default)]
        fatigue: Option<InhomogeneityFatigue>,
    },
    /// `kind = "cylinder"`: `axis = "y"` with `x`, or `axis = "x"` with `y`; depth `z`, radius `r`.
    Cylinder {
        axis: String,
        #[serde(default)]
        x: Option<f64>,
        #[serde(default)]
        y: Option<f64>,
        z: f64,
        r: f64,
        #[serde(rename = "E")]
        e: f64,
        nu: f64,
        /// This inhomogeneity's fatigue constants (with `[fatigue]`; docs/fatigue.md,
        /// "Materials").
        #[serde(default)]
        fatigue: Option<InhomogeneityFatigue>,
    },
    /// `kind = "cuboid"`: centre `x, y, z`, half sizes `hx, hy, hz`.
    Cuboid {
        x: f64,
        y: f64,
        z: f64,
        hx: f64,
        hy: f64,
        hz: f64,
        #[serde(rename = "E")]
        e: f64,
        nu: f64,
        /// This inhomogeneity's fatigue constants (with `[fatigue]`; docs/fatigue.md,
        /// "Materials").
        #[serde(default)]
        fatigue: Option<InhomogeneityFatigue>,
    },
}

impl<'de> Deserialize<'de> for InhomogeneityEntry {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        spec_or_table(
            d,
            "a table with kind = \"sphere\" | \"cylinder\" | \"cuboid\", or a kind:key=value spec",
            InhomogeneityEntry::Spec,
            InhomogeneityEntry::Table,
        )
    }
}

/// A value given either as a `kind:key=value` spec string (`spec`) or as a table read by serde
/// into `T` (`table`): an inhomogeneity entry, an `axisym` profile. `expecting` says both forms
/// in the error of anything else.
pub fn spec_or_table<'de, D, T, R>(
    d: D,
    expecting: &'static str,
    spec: fn(String) -> R,
    table: fn(T) -> R,
) -> Result<R, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Deserialize<'de>,
{
    struct Entry<T, R> {
        expecting: &'static str,
        spec: fn(String) -> R,
        table: fn(T) -> R,
    }
    impl<'de, T: Deserialize<'de>, R> serde::de::Visitor<'de> for Entry<T, R> {
        type Value = R;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str(self.expecting)
        }
        fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<R, E> {
            Ok((self.spec)(v.to_string()))
        }
        fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<R, A::Error> {
            T::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(self.table)
        }
    }
    d.deserialize_any(Entry {
        expecting,
        spec,
        table,
    })
}

impl InhomogeneityEntry {
    /// The entry's own `fatigue` table (a spec string has none).
    pub fn fatigue(&self) -> Option<&InhomogeneityFatigue> {
        match self {
            InhomogeneityEntry::Spec(_) => None,
            InhomogeneityEntry::Table(
                InhomogeneityTable::Sphere { fatigue, .. }
                | InhomogeneityTable::Cylinder { fatigue, .. }
                | InhomogeneityTable::Cuboid { fatigue, .. },
            ) => fatigue.as_ref(),
        }
    }

    /// The library's inhomogeneity, checked; `index` (from 1) names it in errors.
    pub fn inhomogeneity(&self, index: usize) -> Result<Inhomogeneity, SpecError> {
        let what = format!("[[inhomogeneity]] {index}");
        let table = match self {
            InhomogeneityEntry::Spec(spec) => return parse_inhomogeneity(spec, &what),
            InhomogeneityEntry::Table(t) => t,
        };
        let (shape, e, nu) = match *table {
            InhomogeneityTable::Sphere {
                x, y, z, r, e, nu, ..
            } => (Shape::Sphere { x, y, z, r }, e, nu),
            InhomogeneityTable::Cylinder {
                ref axis,
                x,
                y,
                z,
                r,
                e,
                nu,
                ..
            } => {
                let (axis, position) = match (axis.as_str(), x, y) {
                    ("y", Some(x), None) => (Axis::Y, x),
                    ("x", None, Some(y)) => (Axis::X, y),
                    _ => {
                        return Err(SpecError(format!(
                            "{what}: a cylinder has axis = \"y\" with x, or axis = \"x\" with y \
                             (it lies parallel to the surface), got axis = \"{axis}\""
                        )))
                    }
                };
                (
                    Shape::Cylinder {
                        axis,
                        position,
                        z,
                        r,
                    },
                    e,
                    nu,
                )
            }
            InhomogeneityTable::Cuboid {
                x,
                y,
                z,
                hx,
                hy,
                hz,
                e,
                nu,
                ..
            } => (
                Shape::Cuboid {
                    x,
                    y,
                    z,
                    half: [hx, hy, hz],
                },
                e,
                nu,
            ),
        };
        let inh = Inhomogeneity { shape, e, nu };
        inh.validate()
            .map_err(|e| SpecError(format!("{what}: {e}")))?;
        Ok(inh)
    }
}

impl LoopConfig {
    /// The `[fatigue]` table with the `fatigue` tables of the `[[inhomogeneity]]` entries
    /// ([`FatigueConfig::own`]); what the drivers evaluate the loop's criteria with.
    pub fn fatigue_config(&self) -> Option<FatigueConfig> {
        self.fatigue.as_ref().map(|f| FatigueConfig {
            own: self
                .inhomogeneity
                .iter()
                .map(|e| e.fatigue().copied())
                .collect(),
            ..f.clone()
        })
    }

    /// The library's case: `case` is `homogeneous` or `composite` (the paper's fibres of
    /// `layout`, E_I = `fibre_e_ratio` E, at 4 cells per radius); `grid` overrides the grid.
    pub fn case(&self, case: &str, grid: Option<usize>) -> Result<LoopCase, SpecError> {
        loop_case(self, case, grid)
    }
}

/// The axes of a fretting map: the `[map]` table of `fretting-map --config` (the other keys are
/// the fretting loop's, [`LoopConfig`]).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MapAxes {
    /// Normal loads W (N), the map's rows.
    pub loads: Vec<f64>,
    /// Shift amplitudes A (m), the map's columns.
    pub amplitudes: Vec<f64>,
    /// `homogeneous` (default) or `composite` (as `fretting-loop --case`).
    #[serde(default)]
    pub case: Option<String>,
}

/// A TOML error as one line naming the source, the line and its text (serde's message alone does
/// not name the key of a value of the wrong type: "invalid value: integer `-3`, expected usize").
pub fn toml_message(what: &str, text: &str, e: &toml::de::Error) -> String {
    let message = e.message().replace('\n', " ");
    match toml_line(text, e) {
        Some((line, content)) => format!("{what}: line {line} `{content}`: {message}"),
        None => format!("{what}: {message}"),
    }
}

/// A configuration from TOML data: a file's table, or a Python dict converted to TOML values by
/// the extension (no text, no parser in Python; TOML values, unlike JSON, hold NaN and ±∞, which
/// the schema's checks then refuse by name). serde with the schema's own checks (unknown keys,
/// types); on an error the data is written as TOML to quote the offending key, as
/// [`toml_message`] does. Whether the message is a wrong type is [`is_type_error`].
pub fn from_table<T: serde::de::DeserializeOwned>(
    table: toml::Table,
    what: &str,
) -> Result<T, SpecError> {
    toml::Value::Table(table.clone())
        .try_into()
        .map_err(|e: toml::de::Error| {
            let message = e.message().replace('\n', " ");
            let retext = toml::to_string(&table).unwrap_or_default();
            match toml::from_str::<T>(&retext)
                .err()
                .and_then(|e| toml_line(&retext, &e))
            {
                Some((_, content)) => SpecError(format!("{what}: `{content}`: {message}")),
                None => SpecError(format!("{what}: {message}")),
            }
        })
}

/// Whether a [`from_table`] error is a value of the wrong type (Python's `TypeError`).
pub fn is_type_error(e: &SpecError) -> bool {
    e.0.contains("invalid type:")
}

/// The line (from 1) and the text of the line where a TOML error points.
fn toml_line(text: &str, e: &toml::de::Error) -> Option<(usize, String)> {
    let span = e.span()?;
    let before = text.get(..span.start)?;
    let line = before.matches('\n').count() + 1;
    let content = text.lines().nth(line - 1).unwrap_or("").trim();
    Some((line, content.chars().take(80).collect()))
}

/// Reads a fretting-map configuration: the fretting loop's keys and a `[map]` table
/// (`loads`, `amplitudes`, optional `case`); `what` names the source in errors.
pub fn map_config_from_toml(text: &str, what: &str) -> Result<(LoopConfig, MapAxes), SpecError> {
    let mut table: toml::Table =
        toml::from_str(text).map_err(|e| SpecError(toml_message(what, text, &e)))?;
    let axes = table.remove("map").ok_or_else(|| {
        SpecError(format!(
            "{what}: a fretting map needs a [map] table with loads = [..] (N) and amplitudes = [..] (m)"
        ))
    })?;
    // Read as the other tables are (`from_table`), so that an error names the key and its line.
    let axes: MapAxes = match axes {
        toml::Value::Table(t) => from_table(t, &format!("{what}: [map]"))?,
        other => {
            return Err(SpecError(format!(
                "{what}: invalid type: map = {other} must be the [map] table"
            )))
        }
    };
    let cfg: LoopConfig = from_table(table, what)?;
    Ok((cfg, axes))
}

impl LoopConfig {
    /// The fretting map of this configuration over `loads × amplitudes` ([`FrettingMap`]): the
    /// case (`homogeneous` or `composite`, `grid` overriding) is built with `force` = the largest
    /// load, so the domain (`extent_over_a · a(W_max)`) and any composite fibres serve every point;
    /// with `[fatigue]`, the fatigue box (`depth_over_a` at every point; the crack risk is computed
    /// by [`crate::fretting_map::run_map_with`]).
    pub fn map(
        &self,
        case: &str,
        grid: Option<usize>,
        loads: Vec<f64>,
        amplitudes: Vec<f64>,
    ) -> Result<FrettingMap, SpecError> {
        if self.approach.is_some() {
            return Err(SpecError(
                "fretting map config: the map's rows are normal loads ([map] loads): approach \
                 is not read by a map; remove it"
                    .into(),
            ));
        }
        if self
            .fatigue
            .as_ref()
            .is_some_and(|f| f.process_volume.is_some())
        {
            return Err(SpecError(
                "fretting map config: [fatigue] process_volume is read by fretting-loop only (the \
                 map's crack risk is the pointwise maxima); remove it"
                    .into(),
            ));
        }
        let largest = loads.iter().copied().fold(f64::NAN, f64::max);
        let mut cfg = self.clone();
        if largest.is_finite() && largest > 0.0 {
            cfg.force = Some(largest);
        }
        let base = cfg.case(case, grid)?;
        FrettingMap::new(base, loads, amplitudes).map_err(|e| SpecError(e.to_string()))
    }
}

/// The `[wear]` table of a 3D fretting-wear run (`fretting-wear3d --config`, the Python
/// `fretting_wear3d`; docs/wear3d.md#the-command): the wear law (`"archard"` | `"energy"`) and its
/// coefficient (m²/N), the worn body (`"gap"` | `"flat"` | `"indenter"`), the cycles N, the
/// cycles at which the wear depth and pressure are recorded, and the step controls of
/// [`WearCase`] (defaults: the driver's).
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WearTable {
    #[serde(default = "default_wear_law")]
    pub law: String,
    pub coefficient: f64,
    #[serde(default = "default_worn_body")]
    pub body: String,
    pub cycles: u64,
    #[serde(default)]
    pub record_cycles: Vec<u64>,
    #[serde(default = "default_step_fraction")]
    pub step_fraction: f64,
    #[serde(default = "default_stability_fraction")]
    pub stability_fraction: f64,
    #[serde(default = "default_depth_cells")]
    pub inhomogeneity_depth_cells: f64,
}

fn default_wear_law() -> String {
    "archard".into()
}
fn default_worn_body() -> String {
    "gap".into()
}
fn default_step_fraction() -> f64 {
    DEFAULT_STEP_FRACTION
}
fn default_stability_fraction() -> f64 {
    DEFAULT_STABILITY_FRACTION
}
fn default_depth_cells() -> f64 {
    INHOMOGENEITY_DEPTH_CELLS
}

/// The configuration of a 3D fretting-wear run: the fretting loop's keys ([`LoopConfig`]; the
/// normal load by `force` or `approach`, an elastic indenter by `indenter_e`, `indenter_nu`) and
/// the `[wear]` table ([`WearTable`]). Read from a TOML table (a file's, or a Python dict's
/// data) by taking `wear` out and reading the rest as the loop's configuration (serde's `flatten`
/// does not combine with `deny_unknown_fields`).
#[derive(Debug, Clone)]
pub struct Wear3dConfig {
    pub fretting: LoopConfig,
    pub wear: WearTable,
}

impl Wear3dConfig {
    /// The configuration of TOML data; `what` names the source in errors. A missing `[wear]`
    /// table, an unknown key or a value of the wrong type is refused naming the key
    /// ([`from_table`]; a wrong type is [`is_type_error`]).
    pub fn from_table(mut table: toml::Table, what: &str) -> Result<Self, SpecError> {
        let wear = match table.remove("wear") {
            Some(toml::Value::Table(t)) => from_table(t, &format!("{what}: [wear]"))?,
            Some(other) => {
                return Err(SpecError(format!(
                    "{what}: invalid type: wear = {other} must be the [wear] table"
                )))
            }
            None => {
                return Err(SpecError(format!(
                    "{what}: a [wear] table is required (law, coefficient, body, cycles)"
                )))
            }
        };
        let fretting = from_table(table, what)?;
        Ok(Self { fretting, wear })
    }

    /// The configuration of a TOML text ([`Self::from_table`]).
    pub fn from_toml(text: &str, what: &str) -> Result<Self, SpecError> {
        let table: toml::Table =
            toml::from_str(text).map_err(|e| SpecError(toml_message(what, text, &e)))?;
        Self::from_table(table, what)
    }

    /// The library's case, validated ([`WearCase::validate`]); `grid` overrides the grid. The
    /// surface is homogeneous or holds the `[[inhomogeneity]]` entries, or — when `layout` or
    /// `fibre_e_ratio` is given — the composite preset of `fretting-loop --case composite`
    /// (docs/wear3d.md#the-composite-case); `[fatigue]` is refused (the wear run evaluates no
    /// fatigue criteria).
    pub fn case(&self, grid: Option<usize>) -> Result<WearCase, SpecError> {
        if let Some(i) = self
            .fretting
            .inhomogeneity
            .iter()
            .position(|e| e.fatigue().is_some())
        {
            return Err(SpecError(format!(
                "fretting-wear3d config: [[inhomogeneity]] {}: its fatigue table belongs to \
                 fretting-loop (the wear run does not evaluate fatigue criteria); remove it",
                i + 1
            )));
        }
        if self.fretting.fatigue.is_some() {
            return Err(SpecError(
                "fretting-wear3d config: [fatigue] belongs to fretting-loop (the wear run does \
                 not evaluate fatigue criteria); remove it"
                    .into(),
            ));
        }
        let preset = if self.fretting.layout.is_some() || self.fretting.fibre_e_ratio.is_some() {
            "composite"
        } else {
            "homogeneous"
        };
        let fretting = self.fretting.case(preset, grid)?;
        let w = &self.wear;
        let sam = |e: crate::sam::SamError| SpecError(e.to_string());
        let law = WearLaw::from_name(&w.law, w.coefficient).map_err(sam)?;
        let mut case = WearCase::new(fretting, law, w.cycles);
        case.body = WornBody::from_name(&w.body).map_err(sam)?;
        case.record_cycles = w.record_cycles.clone();
        case.step_fraction = w.step_fraction;
        case.stability_fraction = w.stability_fraction;
        case.inhomogeneity_depth_cells = w.inhomogeneity_depth_cells;
        case.validate().map_err(sam)?;
        Ok(case)
    }
}

/// The `alternation` key's scheme: `"plain"` or `"gauged"`
/// (docs/theory-sam.md#normal-tangential-alternation).
fn alternation_of(name: &str) -> Result<Alternation, SpecError> {
    match name {
        "plain" => Ok(Alternation::Plain),
        "gauged" => Ok(Alternation::Gauged),
        other => Err(SpecError(format!(
            "fretting loop config: alternation = \"{other}\": \"plain\" or \"gauged\" (the \
             normal-tangential alternation scheme)"
        ))),
    }
}

/// [`LoopConfig::case`].
fn loop_case(
    cfg: &LoopConfig,
    case_name: &str,
    grid: Option<usize>,
) -> Result<LoopCase, SpecError> {
    let (force, approach) = match (cfg.force, cfg.approach) {
        (Some(_), Some(_)) => {
            return Err(SpecError(
                "fretting loop config: give exactly one of force (N) and approach (m)".into(),
            ))
        }
        (f, None) => (f.unwrap_or(LoopCase::default().force), None),
        (None, Some(d)) => (0.0, Some(d)),
    };
    let indenter = match (cfg.indenter_e, cfg.indenter_nu) {
        (None, None) => Body::Rigid,
        (Some(e), Some(nu)) => Body::Elastic { e, nu },
        _ => {
            return Err(SpecError(
                "fretting loop config: an elastic indenter needs both indenter_e (Pa) and \
                 indenter_nu (absent both: rigid)"
                    .into(),
            ))
        }
    };
    let mut case = LoopCase {
        force,
        approach,
        indenter,
        inhomogeneities: cfg
            .inhomogeneity
            .iter()
            .enumerate()
            .map(|(i, entry)| entry.inhomogeneity(i + 1))
            .collect::<Result<Vec<_>, _>>()?,
        ..LoopCase::default()
    };
    case.set_loop_keys(cfg.loop_keys());
    if !(cfg.subsurface_over_a.is_finite() && cfg.subsurface_over_a >= 0.0) {
        return Err(SpecError(format!(
            "fretting loop config: subsurface_over_a must be finite and ≥ 0, got {}",
            cfg.subsurface_over_a
        )));
    }
    match case_name {
        "homogeneous" => {
            for (key, given) in [
                ("layout", cfg.layout.is_some()),
                ("fibre_e_ratio", cfg.fibre_e_ratio.is_some()),
            ] {
                if given {
                    return Err(SpecError(format!(
                        "fretting loop config: {key} is read only by the composite preset \
                         (case = composite); without it the key would be ignored: remove it or \
                         choose the composite case"
                    )));
                }
            }
        }
        "composite" => {
            let layout = match cfg.layout.as_deref().unwrap_or("fibre-centred") {
                "fibre-centred" => FibreLayout::FibreCentred,
                "gap-centred" => FibreLayout::GapCentred,
                other => {
                    return Err(SpecError(format!(
                        "fretting loop config: layout = '{other}': fibre-centred or gap-centred"
                    )))
                }
            };
            case = case
                .composite(layout, cfg.fibre_e_ratio.unwrap_or(2.0))
                .map_err(|e| SpecError(format!("fretting loop config: {e}")))?;
        }
        other => {
            return Err(SpecError(format!(
                "case '{other}': homogeneous or composite"
            )))
        }
    }
    if let Some(g) = grid {
        case.grid = g;
    }
    match (cfg.inhomogeneous_body, cfg.surface_operator_radius_over_a) {
        (InhomogeneousBody::Nested, Some(_)) => {
            return Err(SpecError(
                "fretting loop config: surface_operator_radius_over_a is read only with \
                 inhomogeneous_body = \"surface-operator\"; without it the key would be ignored"
                    .into(),
            ))
        }
        (InhomogeneousBody::Nested, None) => {}
        (InhomogeneousBody::SurfaceOperator, _) if case.inhomogeneities.is_empty() => {
            return Err(SpecError(
                "fretting loop config: inhomogeneous_body = \"surface-operator\" needs \
                 inhomogeneities (case = composite or [[inhomogeneity]]); without them the key \
                 would be ignored"
                    .into(),
            ))
        }
        (InhomogeneousBody::SurfaceOperator, r) => {
            case.surface_operator_over_a =
                Some(r.unwrap_or(DEFAULT_SURFACE_OPERATOR_RADIUS_OVER_A));
        }
    }
    // The nested loop's keys: refused where no nested loop would read them.
    let nested_only = |case: &crate::sam::drivers::fretting_loop::LoopCase, key: &str| {
        if case.inhomogeneities.is_empty() || case.surface_operator_over_a.is_some() {
            Err(SpecError(format!(
                "fretting loop config: {key} is read only by the nested contact ↔ EIM loop \
                 (inhomogeneities with inhomogeneous_body = \"nested\"); without it the key \
                 would be ignored"
            )))
        } else {
            Ok(())
        }
    };
    if let Some(eta) = cfg.eim_change_factor {
        nested_only(&case, "eim_change_factor")?;
        if !(eta > 0.0 && eta <= 1.0) {
            return Err(SpecError(format!(
                "fretting loop config: eim_change_factor must lie in (0, 1], got {eta}"
            )));
        }
        case.eim_change_factor = Some(eta);
    }
    if let Some(depth) = cfg.eim_recycled_depth {
        nested_only(&case, "eim_recycled_depth")?;
        if depth > crate::sam::contact::MAX_EIM_RECYCLED_DEPTH {
            return Err(SpecError(format!(
                "fretting loop config: eim_recycled_depth must lie in 0..={}, got {depth}",
                crate::sam::contact::MAX_EIM_RECYCLED_DEPTH
            )));
        }
        case.eim_recycled_depth = Some(depth);
    }
    if let Some(name) = cfg.alternation.as_deref() {
        case.alternation = Some(alternation_of(name)?);
        if !case.is_coupled() {
            return Err(SpecError(format!(
                "fretting loop config: alternation = \"{name}\" is read only by a coupled pair \
                 (dissimilar bodies, e.g. a rigid sphere with nu < 0.5); these bodies have no \
                 normal-tangential coupling and solve each increment without alternating, so \
                 the key would be ignored"
            )));
        }
    }
    case.validate()
        .map_err(|e| SpecError(format!("fretting loop config: {e}")))?;
    if cfg.subsurface_over_a > 0.0 {
        case.subsurface_depth = Some(cfg.subsurface_over_a * case.hertz_radius());
    }
    if cfg.fatigue.is_none() {
        if let Some(i) = cfg.inhomogeneity.iter().position(|e| e.fatigue().is_some()) {
            return Err(SpecError(format!(
                "fretting loop config: [[inhomogeneity]] {} has a fatigue table, read only with \
                 a [fatigue] table; without it the key would be ignored",
                i + 1
            )));
        }
    }
    if let Some(f) = &cfg.fatigue {
        if !(f.depth_over_a.is_finite() && f.depth_over_a > 0.0) {
            return Err(SpecError(format!(
                "fretting loop config: [fatigue] depth_over_a must be finite and > 0, got {}",
                f.depth_over_a
            )));
        }
        if !(0.0..=1.0).contains(&f.screen_fraction) {
            return Err(SpecError(format!(
                "fretting loop config: [fatigue] screen_fraction must lie in [0, 1], got {}",
                f.screen_fraction
            )));
        }
        if let Some(side) = f.process_volume {
            if !(side.is_finite() && side > 0.0) {
                return Err(SpecError(format!(
                    "fretting loop config: [fatigue] process_volume must be finite and > 0 m, \
                     got {side}"
                )));
            }
        }
        f.matrix(case.e, case.nu)
            .validate()
            .map_err(|e| SpecError(format!("fretting loop config: [fatigue]: {e}")))?;
        let f = cfg.fatigue_config().unwrap_or_else(|| f.clone());
        for (i, m) in f
            .inhomogeneity_materials(&case.inhomogeneities)
            .iter()
            .enumerate()
        {
            let table = match cfg.inhomogeneity.get(i).and_then(|e| e.fatigue()) {
                Some(_) => format!("[[inhomogeneity]] {} fatigue", i + 1),
                None if f.inhomogeneity.is_some() => "[fatigue.inhomogeneity]".to_string(),
                None => format!("[fatigue] (for inhomogeneity {})", i + 1),
            };
            m.validate()
                .map_err(|e| SpecError(format!("fretting loop config: {table}: {e}")))?;
        }
        case.fatigue_depth = Some(f.depth_over_a * case.hertz_radius());
    }
    Ok(case)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn first(text: &str) -> Result<Inhomogeneity, String> {
        let cfg: LoopConfig = toml::from_str(text).map_err(|e| e.message().to_string())?;
        cfg.inhomogeneity[0].inhomogeneity(1).map_err(|e| e.0)
    }

    #[test]
    fn an_inhomogeneity_table_and_its_spec_are_one_input() {
        let table = first(
            "[[inhomogeneity]]\nkind = \"cylinder\"\naxis = \"y\"\nx = 1e-6\nz = 2e-6\nr = 0.5e-6\nE = 420e9\nnu = 0.3\n",
        )
        .unwrap();
        let spec =
            first("inhomogeneity = [\"cylinder:axis=y,x=1e-6,z=2e-6,r=0.5e-6,E=420e9,nu=0.3\"]\n")
                .unwrap();
        assert_eq!(table, spec);
        // Integers are numbers; the spec's spelling `E` is the table's.
        let sphere = first(
            "[[inhomogeneity]]\nkind = \"sphere\"\nx = 0\ny = 0\nz = 2e-6\nr = 1e-6\nE = 420e9\nnu = 0.3\n",
        )
        .unwrap();
        assert_eq!(sphere.e, 420e9);
        let e = first(
            "[[inhomogeneity]]\nkind = \"sphere\"\nx = 0\ny = 0\nz = 2e-6\nr = 1e-6\ne = 420e9\nnu = 0.3\n",
        )
        .unwrap_err();
        assert!(e.contains("unknown field `e`"), "{e}");
        let e = first(
            "[[inhomogeneity]]\nkind = \"cylinder\"\naxis = \"y\"\ny = 1e-6\nz = 2e-6\nr = 0.5e-6\nE = 1e9\nnu = 0.3\n",
        )
        .unwrap_err();
        assert!(
            e.starts_with("[[inhomogeneity]] 1: a cylinder has axis"),
            "{e}"
        );
        let e =
            first("inhomogeneity = [\"sphere:x=0,y=0,z=2e-6,r=abc,E=1e9,nu=0.3\"]\n").unwrap_err();
        assert!(e.contains("r='abc' is not a number"), "{e}");
    }

    /// The shared keys are declared by `fretting_loop_keys!`: serde's messages are the ones of
    /// the plain struct (checked against the release binary of f6b6632, before the macro) — the
    /// unknown key with every expected key in order, the wrong type and the out-of-range value
    /// with the TOML line; and the default is [`LoopCase::default`]'s case, key for key.
    #[test]
    fn the_shared_keys_keep_serdes_messages_and_the_defaults() {
        let expected = "expected one of `radius`, `e`, `nu`, `friction`, `force`, `approach`, \
             `indenter_e`, `indenter_nu`, `normal_steps`, `amplitude`, `shift_step`, `grid`, \
             `extent_over_a`, `inhomogeneity`, `layout`, `fibre_e_ratio`, `subsurface_over_a`, \
             `fatigue`, `inhomogeneous_body`, `surface_operator_radius_over_a`, \
             `eim_change_factor`, `eim_recycled_depth`, `alternation`";
        let e =
            from_toml::<LoopConfig>("radius = 1e-4\nfoo = 3\n", "--config unk.toml").unwrap_err();
        assert_eq!(
            e.0,
            format!("--config unk.toml: line 2 `foo = 3`: unknown field `foo`, {expected}")
        );
        let e = from_json::<LoopConfig>(r#"{"radius": 1e-4, "foo": 3}"#, "--config unk.json")
            .unwrap_err();
        assert_eq!(
            e.0,
            format!("--config unk.json: unknown field `foo`, {expected} at line 1 column 22")
        );
        let e = map_config_from_toml(
            "grid = 16\nbogus = 2\n[map]\nloads=[0.01]\namplitudes=[1e-8]\n",
            "--config m.toml",
        )
        .unwrap_err();
        assert_eq!(
            e.0,
            format!("--config m.toml: `bogus = 2`: unknown field `bogus`, {expected}")
        );
        let e = from_toml::<LoopConfig>("grid = \"big\"\n", "--config ty.toml").unwrap_err();
        assert_eq!(
            e.0,
            "--config ty.toml: line 1 `grid = \"big\"`: invalid type: string \"big\", expected usize"
        );
        let e = from_toml::<LoopConfig>("normal_steps = -1\n", "--config neg.toml").unwrap_err();
        assert_eq!(
            e.0,
            "--config neg.toml: line 1 `normal_steps = -1`: invalid value: integer `-1`, \
             expected usize"
        );
        let cfg = from_toml::<LoopConfig>("friction = -0.3\n", "t").unwrap();
        assert_eq!(
            cfg.case("homogeneous", None).unwrap_err().0,
            "fretting loop config: friction (Coulomb μ; a fretting loop needs μ > 0) must be \
             finite and > 0, got -0.3"
        );
        let default = LoopConfig::default();
        assert_eq!(default.loop_keys(), LoopCase::default().loop_keys());
        assert_eq!(
            default.case("homogeneous", None).unwrap(),
            LoopCase {
                subsurface_depth: Some(LoopCase::default().hertz_radius()),
                ..LoopCase::default()
            }
        );
    }

    #[test]
    fn a_config_from_data_names_the_offending_key() {
        let mut table = toml::Table::new();
        table.insert("grid".into(), toml::Value::String("big".into()));
        let e = from_table::<LoopConfig>(table, "config").unwrap_err();
        assert!(is_type_error(&e), "{e}");
        assert!(
            e.0.starts_with("config: `grid = \"big\"`: invalid type"),
            "{e}"
        );
        let mut table = toml::Table::new();
        table.insert("normal_steps".into(), toml::Value::Integer(-1));
        let e = from_table::<LoopConfig>(table, "config").unwrap_err();
        assert!(
            !is_type_error(&e) && e.0.contains("normal_steps = -1"),
            "{e}"
        );
    }

    #[test]
    fn a_wear3d_config_takes_its_wear_table_out_and_names_bad_keys() {
        let base = "approach = 1e-7\ngrid = 16\n[wear]\ncoefficient = 1e-12\ncycles = 10\n";
        let cfg = Wear3dConfig::from_toml(base, "cfg").unwrap();
        assert_eq!(cfg.wear.law, "archard");
        assert_eq!(cfg.fretting.approach, Some(1e-7));
        let case = cfg.case(Some(8)).unwrap();
        assert_eq!((case.cycles, case.fretting.grid), (10, 8));
        let e = Wear3dConfig::from_toml("grid = 16\n", "cfg").unwrap_err();
        assert!(e.0.contains("a [wear] table is required"), "{e}");
        let e = Wear3dConfig::from_toml(&base.replace("cycles = 10", "cycles = \"x\""), "cfg")
            .unwrap_err();
        assert!(
            is_type_error(&e) && e.0.starts_with("cfg: [wear]: `cycles"),
            "{e}"
        );
        let e = Wear3dConfig::from_toml(&format!("colour = 1\n{base}"), "cfg").unwrap_err();
        assert!(e.0.contains("colour"), "{e}");
        let e = Wear3dConfig::from_toml(
            &base.replace(
                "[wear]",
                "[fatigue]\nf_minus1 = 1\nt_minus1 = 1\nfs_k = 1\nyield_stress = 1\n[wear]",
            ),
            "cfg",
        )
        .unwrap()
        .case(None)
        .unwrap_err();
        assert!(e.0.contains("[fatigue] belongs to fretting-loop"), "{e}");
    }

    #[test]
    fn the_body_response_key_selects_the_surface_operator_and_the_composite_wear_preset() {
        let base = "grid = 8\n[wear]\nlaw = \"archard\"\ncoefficient = 1e-15\nbody = \"indenter\"\ncycles = 10\n";
        let text = format!(
            "layout = \"gap-centred\"\ninhomogeneous_body = \"surface-operator\"\n\
             surface_operator_radius_over_a = 1.5\n{base}"
        );
        let case = Wear3dConfig::from_toml(&text, "cfg")
            .unwrap()
            .case(Some(16))
            .unwrap();
        assert_eq!(case.fretting.surface_operator_over_a, Some(1.5));
        assert!(!case.fretting.inhomogeneities.is_empty());
        let text =
            format!("fibre_e_ratio = 0.5\ninhomogeneous_body = \"surface-operator\"\n{base}");
        let case = Wear3dConfig::from_toml(&text, "cfg")
            .unwrap()
            .case(Some(16))
            .unwrap();
        assert_eq!(
            case.fretting.surface_operator_over_a,
            Some(DEFAULT_SURFACE_OPERATOR_RADIUS_OVER_A)
        );
        let plain = Wear3dConfig::from_toml(base, "cfg")
            .unwrap()
            .case(None)
            .unwrap();
        assert!(plain.fretting.inhomogeneities.is_empty());
        assert_eq!(plain.fretting.surface_operator_over_a, None);
        let e = Wear3dConfig::from_toml(&format!("inhomogeneous_body = \"fast\"\n{base}"), "cfg")
            .unwrap_err();
        assert!(
            e.0.contains("inhomogeneous_body") || e.0.contains("surface-operator"),
            "{e}"
        );
        let e = Wear3dConfig::from_toml(
            &format!("surface_operator_radius_over_a = 1.2\n{base}"),
            "cfg",
        )
        .unwrap()
        .case(None)
        .unwrap_err();
        assert!(
            e.0.contains("surface_operator_radius_over_a is read only"),
            "{e}"
        );
        let e = Wear3dConfig::from_toml(
            &format!("layout = \"fibre-centred\"\ninhomogeneous_body = \"surface-operator\"\nsurface_operator_radius_over_a = -1\n{base}"),
            "cfg",
        )
        .unwrap()
        .case(Some(16))
        .unwrap_err();
        assert!(e.0.contains("surface_operator_radius_over_a"), "{e}");
        // The operator path on a homogeneous body would be ignored: refused by name.
        let e = Wear3dConfig::from_toml(
            &format!("inhomogeneous_body = \"surface-operator\"\n{base}"),
            "cfg",
        )
        .unwrap()
        .case(None)
        .unwrap_err();
        assert!(e.0.contains("needs inhomogeneities"), "{e}");
    }

    #[test]
    fn the_eim_change_factor_key_reaches_the_nested_loop_and_is_refused_where_ignored() {
        let base = "grid = 8\n[wear]\nlaw = \"archard\"\ncoefficient = 1e-15\nbody = \"indenter\"\ncycles = 10\n";
        let case = |text: &str| Wear3dConfig::from_toml(text, "cfg").unwrap().case(Some(16));
        let c = case(&format!(
            "layout = \"fibre-centred\"\neim_change_factor = 1e-2\n{base}"
        ))
        .unwrap();
        assert_eq!(c.fretting.eim_change_factor, Some(1e-2));
        let nested = c
            .fretting
            .nested_params(crate::sam::contact::NestedParams::default());
        assert_eq!(nested.eim_change_factor, 1e-2);
        // Absent: the library's default.
        let c = case(&format!("layout = \"fibre-centred\"\n{base}")).unwrap();
        assert_eq!(c.fretting.eim_change_factor, None);
        for bad in ["0", "-1e-2", "1.5", "nan"] {
            let e = case(&format!(
                "layout = \"fibre-centred\"\neim_change_factor = {bad}\n{base}"
            ))
            .unwrap_err();
            assert!(e.0.contains("eim_change_factor must lie in (0, 1]"), "{e}");
        }
        // Read by nothing on a homogeneous body or on the surface operator: refused by name.
        for extra in [
            "",
            "layout = \"fibre-centred\"\ninhomogeneous_body = \"surface-operator\"\n",
        ] {
            let e = case(&format!("{extra}eim_change_factor = 1e-2\n{base}")).unwrap_err();
            assert!(e.0.contains("eim_change_factor is read only"), "{e}");
        }
    }

    /// `alternation = "plain" | "gauged"` reaches the loop's case (for the composite loop and its
    /// homogeneous reference alike) and the wear run's; absent, the library's default; another
    /// value is refused naming the key and the values; an uncoupled pair (identical bodies) would
    /// ignore it and is refused.
    #[test]
    fn the_alternation_key_reaches_the_loops_and_is_refused_where_ignored() {
        use crate::sam::contact::ContactParams;
        let loop_case = |text: &str, preset: &str| {
            from_toml::<LoopConfig>(text, "cfg")
                .unwrap()
                .case(preset, Some(16))
        };
        for (name, scheme) in [
            ("plain", Alternation::Plain),
            ("gauged", Alternation::Gauged),
        ] {
            for preset in ["homogeneous", "composite"] {
                let c = loop_case(&format!("alternation = \"{name}\"\n"), preset).unwrap();
                assert_eq!(c.alternation, Some(scheme));
                assert_eq!(c.alternation_scheme(), scheme);
                assert_eq!(c.homogeneous().alternation_scheme(), scheme);
            }
            let w = Wear3dConfig::from_toml(
                &format!(
                    "alternation = \"{name}\"\ngrid = 8\n[wear]\nlaw = \"archard\"\ncoefficient = 1e-15\ncycles = 10\n"
                ),
                "cfg",
            )
            .unwrap()
            .case(None)
            .unwrap();
            assert_eq!(w.fretting.alternation, Some(scheme));
        }
        let c = loop_case("", "composite").unwrap();
        assert_eq!(c.alternation, None);
        assert_eq!(c.alternation_scheme(), ContactParams::default().alternation);
        for bad in ["anderson", "Gauged", ""] {
            let e = loop_case(&format!("alternation = \"{bad}\"\n"), "homogeneous").unwrap_err();
            assert_eq!(
                e.0,
                format!(
                    "fretting loop config: alternation = \"{bad}\": \"plain\" or \"gauged\" (the \
                     normal-tangential alternation scheme)"
                )
            );
        }
        let e = from_toml::<LoopConfig>("alternation = 2\n", "cfg").unwrap_err();
        assert!(e.0.contains("alternation = 2"), "{e}");
        // Identical bodies do not alternate: the key would be ignored.
        let e = loop_case(
            "indenter_e = 210e9\nindenter_nu = 0.3\nalternation = \"gauged\"\n",
            "homogeneous",
        )
        .unwrap_err();
        assert!(
            e.0.contains("alternation = \"gauged\" is read only by a coupled pair"),
            "{e}"
        );
    }

    #[test]
    fn the_eim_recycled_depth_key_reaches_the_nested_loop_and_is_refused_where_ignored() {
        use crate::sam::contact::{NestedParams, DEFAULT_EIM_RECYCLED_DEPTH};
        let base = "grid = 8\n[wear]\nlaw = \"archard\"\ncoefficient = 1e-15\nbody = \"indenter\"\ncycles = 10\n";
        let case = |text: &str| Wear3dConfig::from_toml(text, "cfg").unwrap().case(Some(16));
        for depth in [0, 3] {
            let c = case(&format!(
                "layout = \"fibre-centred\"\neim_recycled_depth = {depth}\n{base}"
            ))
            .unwrap();
            assert_eq!(c.fretting.eim_recycled_depth, Some(depth));
            let nested = c.fretting.nested_params(NestedParams::default());
            assert_eq!(nested.eim.recycled_depth, depth);
        }
        // Absent: the library's default.
        let c = case(&format!("layout = \"fibre-centred\"\n{base}")).unwrap();
        assert_eq!(c.fretting.eim_recycled_depth, None);
        let nested = c.fretting.nested_params(NestedParams::default());
        assert_eq!(nested.eim.recycled_depth, DEFAULT_EIM_RECYCLED_DEPTH);
        let e = case(&format!(
            "layout = \"fibre-centred\"\neim_recycled_depth = 51\n{base}"
        ))
        .unwrap_err();
        assert!(e.0.contains("eim_recycled_depth must lie in 0..=50"), "{e}");
        // Not a count: refused when the file is read, with its line.
        let e = Wear3dConfig::from_toml(
            &format!("layout = \"fibre-centred\"\neim_recycled_depth = -1\n{base}"),
            "cfg",
        )
        .expect_err("refused");
        assert!(e.0.contains("eim_recycled_depth = -1"), "{e}");
        for extra in [
            "",
            "layout = \"fibre-centred\"\ninhomogeneous_body = \"surface-operator\"\n",
        ] {
            let e = case(&format!("{extra}eim_recycled_depth = 5\n{base}")).unwrap_err();
            assert!(e.0.contains("eim_recycled_depth is read only"), "{e}");
        }
    }
}

/// How the errors of a case name its keys: as the command line's flags (`--tau-end`) or as the
/// keys of a file and Python's keyword arguments (`tau_end`). A configuration file's key is the
/// flag's name with `_` for `-`, so one message serves both.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Names {
    /// `--tau-end`.
    Flags,
    /// `tau_end`.
    Keys,
}

impl Names {
    /// The name of `key` (spelled with `_`).
    pub fn of(self, key: &str) -> String {
        match self {
            Names::Flags => format!("--{}", key.replace('_', "-")),
            Names::Keys => key.to_string(),
        }
    }

    /// The name of `key` as an argument set to a value: `--force` or `force=`.
    pub fn arg(self, key: &str) -> String {
        match self {
            Names::Flags => self.of(key),
            Names::Keys => format!("{key}="),
        }
    }
}

/// A case's keys from a TOML text (a `--config` file); `what` names the source in errors.
pub fn from_toml<T: serde::de::DeserializeOwned>(text: &str, what: &str) -> Result<T, SpecError> {
    toml::from_str(text).map_err(|e| SpecError(toml_message(what, text, &e)))
}

/// A case's keys from a JSON text (the same keys as TOML; JSON holds no NaN or ±∞).
pub fn from_json<T: serde::de::DeserializeOwned>(text: &str, what: &str) -> Result<T, SpecError> {
    serde_json::from_str(text).map_err(|e| SpecError(format!("{what}: {e}")))
}

#[cfg(test)]
mod entry_tests {
    use super::*;

    /// An inhomogeneity entry is a spec string or a table by `kind`; anything else is refused
    /// naming both forms.
    #[test]
    fn inhomogeneity_entries_are_specs_or_tables() {
        let cfg: LoopConfig = from_toml(
            "inhomogeneity = [\"sphere:x=0,y=0,z=2e-6,r=1e-6,E=4e11,nu=0.3\", \
             { kind = \"sphere\", x = 0.0, y = 0.0, z = 2e-6, r = 1e-6, E = 4e11, nu = 0.3 }]\n",
            "t",
        )
        .unwrap();
        let [a, b] = [0, 1].map(|k| cfg.inhomogeneity[k].inhomogeneity(k + 1).unwrap());
        assert_eq!(a, b);
        assert!(matches!(cfg.inhomogeneity[1], InhomogeneityEntry::Table(_)));
        let e = from_toml::<LoopConfig>("inhomogeneity = [3]\n", "t")
            .unwrap_err()
            .0;
        assert!(e.contains("or a kind:key=value spec"), "{e}");
    }

    /// An inhomogeneity's `fatigue` table (docs/fatigue.md, "Materials"): its keys over
    /// `[fatigue.inhomogeneity]` over the matrix's; the same from TOML data (a Python dict's
    /// path); refused without `[fatigue]`, with an unknown key, or with bad constants, naming the
    /// entry.
    #[test]
    fn an_inhomogeneitys_fatigue_table_overrides_key_by_key() {
        let sphere = "[[inhomogeneity]]\nkind = \"sphere\"\nx = 0.0\ny = 0.0\nz = 1.6e-6\n\
                      r = 0.9e-6\nE = 4.2e11\nnu = 0.3\n";
        let fatigue = "[fatigue]\nf_minus1 = 400e6\nt_minus1 = 280e6\nfs_k = 0.5\n\
                       yield_stress = 600e6\n";
        let every = "[fatigue.inhomogeneity]\nf_minus1 = 450e6\nt_minus1 = 300e6\nfs_k = 0.6\n\
                     yield_stress = 700e6\n";
        let text = format!(
            "{sphere}fatigue = {{ t_minus1 = 320e6, fs_k = 0.9 }}\n{sphere}{fatigue}{every}"
        );
        let cfg = toml::from_str::<LoopConfig>(&text)
            .map_err(|e| SpecError(e.message().to_string()))
            .unwrap();
        let case = cfg.case("homogeneous", None).unwrap();
        let f = cfg.fatigue_config().unwrap();
        let own = f.inhomogeneity_constants(0);
        assert_eq!(
            own,
            FatigueConstants {
                f_minus1: 450e6,
                t_minus1: 320e6,
                fs_k: 0.9,
                yield_stress: 700e6
            }
        );
        assert_eq!(f.inhomogeneity_constants(1), f.inhomogeneity.unwrap());
        let m = f.inhomogeneity_materials(&case.inhomogeneities);
        assert_eq!(
            (m[0].young, m[0].t_minus1, m[1].t_minus1),
            (4.2e11, 320e6, 300e6)
        );
        // Without [fatigue.inhomogeneity]: the matrix's.
        let text = format!("{sphere}fatigue = {{ t_minus1 = 320e6 }}\n{fatigue}");
        let f = toml::from_str::<LoopConfig>(&text)
            .map_err(|e| SpecError(e.message().to_string()))
            .unwrap()
            .fatigue_config()
            .unwrap();
        assert_eq!(f.inhomogeneity_constants(0).f_minus1, 400e6);
        assert_eq!(f.inhomogeneity_constants(0).t_minus1, 320e6);
        // The Python dict path: TOML data, not text.
        let table: toml::Table = toml::from_str(&text).unwrap();
        let from_data: LoopConfig = from_table(table, "dict").unwrap();
        assert_eq!(from_data.fatigue_config(), Some(f));
        // Refused, naming the entry and the key.
        let refused = |text: String| {
            toml::from_str::<LoopConfig>(&text)
                .map_err(|e| SpecError(e.message().to_string()))
                .and_then(|c| c.case("homogeneous", None))
                .unwrap_err()
                .0
        };
        let e = refused(format!(
            "{sphere}fatigue = {{ t_minus1 = 500e6 }}\n{fatigue}"
        ));
        assert!(
            e.contains("[[inhomogeneity]] 1 fatigue") && e.contains("t_minus1"),
            "{e}"
        );
        let e = refused(format!(
            "{sphere}fatigue = {{ yield_stress = -1.0 }}\n{fatigue}"
        ));
        assert!(
            e.contains("[[inhomogeneity]] 1") && e.contains("yield_stress"),
            "{e}"
        );
        let e = refused(format!(
            "{sphere}fatigue = {{ f_minus_one = 1.0 }}\n{fatigue}"
        ));
        assert!(e.contains("f_minus_one"), "{e}");
        let e = refused(format!("{sphere}fatigue = {{ f_minus1 = 5e8 }}\n"));
        assert!(
            e.contains("[[inhomogeneity]] 1") && e.contains("[fatigue]"),
            "{e}"
        );
        assert!(!e.contains('\n'), "{e}");
    }
}
