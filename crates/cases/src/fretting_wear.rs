//! The MDR fretting-wear case (`halfspace fretting-wear`, the Python `fretting_wear`;
//! docs/fretting-wear.md): its keys read by serde from TOML, JSON or a Python dict, the medium
//! through the one parser ([`crate::spec::parse_wear_medium`]), validated once in
//! [`WearConfig::case`] ([`FrettingParams::validate`]).

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::config::Names;
use crate::data::{read_record, read_text_bounded, AttrValue, DataError, Record};
use crate::fretting::{
    FrettingError, FrettingParams, FrettingSimulation, FrettingState, GapTransform, Snapshot,
    TimeStepping, ADAPTIVE_SCHEME, EDGE_CELL_RULE, EULER_SCHEME, FIXED_STEP_SCHEME,
};
use crate::run_files::MANIFEST;
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
    /// The discretization of Eq. 7 / 23 for the worn profile: `"piecewise-linear"` (default) or
    /// `"central-differences"` ([`GapTransform`]).
    pub gap_transform: Option<String>,
    /// The edge cells' rate as cell means (default true; [`FrettingParams::edge_cells`]).
    pub edge_cells: Option<bool>,
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
            gap_transform: flags.gap_transform.or(self.gap_transform),
            edge_cells: flags.edge_cells.or(self.edge_cells),
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
        if let Some(name) = &self.gap_transform {
            p.gap_transform = GapTransform::from_name(name).ok_or_else(|| {
                SpecError(format!(
                    "{} = {name:?}: expected \"central-differences\" or \"piecewise-linear\"",
                    names.of("gap_transform")
                ))
            })?;
        }
        p.edge_cells = self.edge_cells.unwrap_or(p.edge_cells);
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

/// The command whose run directories hold fretting-wear runs (their manifest's `command`).
pub const WEAR_COMMAND: &str = "fretting-wear";

/// The checkpoint a fretting-wear run directory holds ([`checkpoint_record`]).
pub const CHECKPOINT: &str = "checkpoint.npz";

/// Why a fretting-wear run cannot continue from a run directory or checkpoint. The messages name
/// no front end's flag: the command line adds its own (`--force` starts over), Python's
/// `fretting_wear(resume=)` gives them as they are.
#[derive(Debug, thiserror::Error)]
pub enum ResumeError {
    /// The run was made by another adaptive scheme (`found`; `None`: not recorded, the scheme
    /// before the name was recorded): its steps would not be repeated bit for bit, and nothing
    /// selects another scheme, so only starting over helps.
    #[error(
        "{what} was made by another build's adaptive scheme (adaptive_scheme = {}); this build \
         runs {ADAPTIVE_SCHEME} and cannot resume it bit for bit: only starting the run over \
         helps",
        found.as_deref().unwrap_or("not recorded: the scheme before the hole projection")
    )]
    OtherScheme {
        /// The run directory or checkpoint, in words.
        what: String,
        /// The scheme it records.
        found: Option<String>,
    },
    /// A checkpoint missing, of other parameters, or with a bad field.
    #[error("{}: {reason}", path.display())]
    Checkpoint {
        /// The checkpoint (or the directory without one).
        path: PathBuf,
        /// What is wrong and what to do.
        reason: String,
    },
    /// The checkpoint could not be read.
    #[error(transparent)]
    Data(#[from] DataError),
}

/// The discretization options as `(attribute, this run's value, the value a record without the
/// attribute means)`: the [`GapTransform`] by name and the edge cells as 1 / 0
/// ([`FrettingParams::edge_cells`]); an absent one is [`GapTransform::LEGACY`] and no edge cells,
/// the defaults of the runs made before the options were recorded.
fn discretization_attrs(p: &FrettingParams) -> [(&'static str, AttrValue, AttrValue); 2] {
    let text = |t: GapTransform| AttrValue::Text(t.name().into());
    [
        (
            "gap_transform",
            text(p.gap_transform),
            text(GapTransform::LEGACY),
        ),
        (
            "edge_cells",
            AttrValue::Int(i64::from(p.edge_cells)),
            AttrValue::Int(0),
        ),
    ]
}

/// The run's parameters as a run directory's manifest, its checkpoints and its results record
/// them (the adaptive scheme's name, [`ADAPTIVE_SCHEME`], with adaptive steps, and the fixed-step
/// ROS2 path's, [`FIXED_STEP_SCHEME`], with fixed steps, and with the edge cells their rule's,
/// [`EDGE_CELL_RULE`]: a checkpoint of another scheme or rule or of none recorded is refused,
/// since its steps would not be repeated bit for bit).
pub fn params_attrs(p: &FrettingParams) -> Vec<(&'static str, AttrValue)> {
    let mut attrs = vec![
        ("chi", AttrValue::Float(p.chi)),
        ("k", AttrValue::Float(p.k)),
        ("n", AttrValue::Int(p.nodes as i64)),
        ("stepping", AttrValue::Text(p.stepping.name().into())),
        (
            match p.stepping {
                TimeStepping::Adaptive { .. } => "tol",
                _ => "dtau",
            },
            AttrValue::Float(match p.stepping {
                TimeStepping::Adaptive { tolerance } => tolerance,
                TimeStepping::Fixed { dtau } | TimeStepping::ExplicitEuler { dtau } => dtau,
            }),
        ),
        ("tau_end", AttrValue::Float(p.tau_end)),
        ("length", AttrValue::Float(p.length)),
        ("method", AttrValue::Text(p.backend.name().into())),
        ("snapshots", AttrValue::Text(format!("{:?}", p.snapshots))),
    ];
    // The discretization options where they differ from the legacy ones (the central differences
    // without the edge cells, which every run recorded nothing of before the options existed:
    // those run directories and checkpoints resume as before; [`state_from_checkpoint`] reads
    // an absent one as the legacy value). The default run (both options) records both.
    attrs.extend(
        discretization_attrs(p)
            .into_iter()
            .filter(|(_, value, default)| value != default)
            .map(|(name, value, _)| (name, value)),
    );
    if p.edge_cells {
        attrs.push(("edge_cell_rule", AttrValue::Text(EDGE_CELL_RULE.into())));
    }
    match p.stepping {
        TimeStepping::Adaptive { .. } => {
            attrs.push(("adaptive_scheme", AttrValue::Text(ADAPTIVE_SCHEME.into())));
        }
        TimeStepping::Fixed { .. } => {
            attrs.push(("fixed_scheme", AttrValue::Text(FIXED_STEP_SCHEME.into())));
        }
        TimeStepping::ExplicitEuler { .. } => {
            attrs.push(("euler_scheme", AttrValue::Text(EULER_SCHEME.into())));
        }
    }
    attrs
}

/// Why a run of the edge cells' rule `found` (`None`: not recorded, the rule before the last
/// node's floor) cannot be resumed by this build ([`EDGE_CELL_RULE`]).
fn other_edge_cell_rule(found: Option<&str>) -> String {
    format!(
        "the run was made by another rule of the edge cells ({}); this build runs \
         {EDGE_CELL_RULE} and cannot resume it bit for bit: only starting the run over helps",
        found.unwrap_or("not recorded: the rule before the last node's floor")
    )
}

/// An adaptive run's directory `dir` whose manifest ([`MANIFEST`]) records a fretting-wear run of
/// another adaptive scheme than this build's: refused ([`ResumeError::OtherScheme`]); a run with
/// the edge cells (any stepping) whose manifest records another rule of them than
/// [`EDGE_CELL_RULE`], or none: refused ([`ResumeError::Checkpoint`], saying so). Anything else —
/// no manifest, another command, fixed steps, other parameters — is left to the caller's checks
/// (the run directory's, [`state_from_checkpoint`]'s).
pub fn check_run_scheme(dir: &Path, params: &FrettingParams) -> Result<(), ResumeError> {
    let Some(manifest) = read_text_bounded(&dir.join(MANIFEST), 1 << 20)
        .ok()
        .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok())
    else {
        return Ok(());
    };
    let parameters = &manifest["parameters"];
    if manifest["command"] != WEAR_COMMAND {
        return Ok(());
    }
    // A run with the edge cells of another rule (or of none recorded: the rule before the last
    // node's floor), whatever its stepping; a run without them is left to the parameters' check.
    if params.edge_cells && parameters["edge_cells"] == 1 {
        let found = parameters["edge_cell_rule"].as_str();
        if found != Some(EDGE_CELL_RULE) {
            return Err(ResumeError::Checkpoint {
                path: dir.to_path_buf(),
                reason: other_edge_cell_rule(found),
            });
        }
    }
    if !matches!(params.stepping, TimeStepping::Adaptive { .. })
        || parameters["stepping"] != "adaptive"
    {
        return Ok(());
    }
    let found = parameters["adaptive_scheme"].as_str();
    if found == Some(ADAPTIVE_SCHEME) {
        return Ok(());
    }
    Err(ResumeError::OtherScheme {
        what: format!("the run in {}", dir.display()),
        found: found.map(String::from),
    })
}

/// The state to continue the run of `params` from, in the run directory `dir`:
/// [`check_run_scheme`], then its checkpoint ([`CHECKPOINT`], [`state_from_checkpoint`]). The
/// command line's `fretting-wear --resume` and Python's `fretting_wear(..., resume=dir)`.
pub fn resume_state(dir: &Path, params: &FrettingParams) -> Result<FrettingState, ResumeError> {
    check_run_scheme(dir, params)?;
    let checkpoint = dir.join(CHECKPOINT);
    if !checkpoint.exists() {
        return Err(ResumeError::Checkpoint {
            path: dir.to_path_buf(),
            reason: format!("no {CHECKPOINT} to resume from"),
        });
    }
    state_from_checkpoint(&checkpoint, params)
}

/// The checkpoint of a run (its state and [`params_attrs`]): [`state_from_checkpoint`] reads it
/// back bit for bit.
pub fn checkpoint_record(sim: &FrettingSimulation) -> Record {
    let state = sim.state();
    let mut rec = Record::default()
        .array("profile", state.profile.clone())
        .array(
            "contact_radius_history",
            state.contact_radius_history.clone(),
        )
        .array("loaded_radius_history", state.loaded_radius_history.clone())
        .array("tau_history", state.tau_history.clone())
        .attr("step", AttrValue::Int(state.step as i64))
        .attr("tau", AttrValue::Float(state.tau))
        .attr("next_step", AttrValue::Float(state.next_step))
        .attr("previous_error", AttrValue::Float(state.previous_error))
        .attr(
            "rejected_steps",
            AttrValue::Int(state.rejected_steps as i64),
        )
        .attr(
            "snapshot_count",
            AttrValue::Int(state.snapshots.len() as i64),
        );
    for (k, s) in state.snapshots.iter().enumerate() {
        rec = rec
            .array(&format!("snapshot{k}_profile"), s.profile.clone())
            .array(&format!("snapshot{k}_pressure"), s.pressure.clone())
            .array(&format!("snapshot{k}_slip"), s.slip.clone())
            .attr(&format!("snapshot{k}_step"), AttrValue::Int(s.step as i64))
            .attr(&format!("snapshot{k}_tau"), AttrValue::Float(s.tau))
            .attr(
                &format!("snapshot{k}_contact_radius"),
                AttrValue::Float(s.contact_radius),
            )
            .attr(
                &format!("snapshot{k}_loaded_radius"),
                AttrValue::Float(s.loaded_radius),
            );
    }
    for (name, value) in params_attrs(sim.params()) {
        rec = rec.attr(name, value);
    }
    rec
}

/// The state of the checkpoint at `path` ([`checkpoint_record`]) for a run of `params`: refused
/// when it was made by another adaptive scheme ([`ResumeError::OtherScheme`]) or with other
/// parameters, or when a field is missing or not a count where one is needed. The state's own
/// content is checked by `FrettingSimulation::resume`.
pub fn state_from_checkpoint(
    path: &Path,
    params: &FrettingParams,
) -> Result<FrettingState, ResumeError> {
    let rec = read_record(path)?;
    let bad = |reason: String| ResumeError::Checkpoint {
        path: path.to_path_buf(),
        reason,
    };
    for (name, value) in params_attrs(params) {
        if name == "adaptive_scheme" && rec.get_attr(name) != Some(&value) {
            return Err(ResumeError::OtherScheme {
                what: format!("the checkpoint {}", path.display()),
                found: match rec.get_attr(name) {
                    Some(AttrValue::Text(s)) => Some(s.clone()),
                    Some(other) => Some(format!("{other:?}")),
                    None => None,
                },
            });
        }
        if matches!(name, "euler_scheme" | "fixed_scheme") && rec.get_attr(name) != Some(&value) {
            return Err(bad(format!(
                "the checkpoint was made by another build's {} path ({name} = {:?}; this build \
                 runs {value:?}) and cannot be resumed bit for bit: only starting the run over \
                 helps (--force starts over)",
                if name == "euler_scheme" {
                    "explicit Euler"
                } else {
                    "fixed-step"
                },
                rec.get_attr(name),
            )));
        }
        if name == "edge_cell_rule" && rec.get_attr(name) != Some(&value) {
            return Err(bad(other_edge_cell_rule(match rec.get_attr(name) {
                Some(AttrValue::Text(s)) => Some(s.as_str()),
                _ => None,
            })));
        }
        if rec.get_attr(name) != Some(&value) {
            return Err(bad(format!(
                "the checkpoint was made with {name} = {:?}, this run has {:?}; resume with the same \
                 parameters or start the run over",
                rec.get_attr(name),
                value
            )));
        }
    }
    // The discretization options, an absent one the legacy value (a record made before them).
    for (name, value, default) in discretization_attrs(params) {
        let recorded = rec.get_attr(name).unwrap_or(&default);
        if recorded != &value {
            return Err(bad(format!(
                "the checkpoint was made with {name} = {recorded:?}, this run has {value:?}; \
                 resume with the same parameters or start the run over"
            )));
        }
    }
    // Step counts: an integer ≥ 0 (a negative one would wrap as u64).
    let int = |name: &str| match rec.get_attr(name) {
        Some(AttrValue::Int(v)) if *v >= 0 => Ok(*v as u64),
        other => Err(bad(format!(
            "attribute {name} is {other:?}, not a count ≥ 0"
        ))),
    };
    let array = |name: &str| {
        rec.get(name)
            .map(|v| v.to_vec())
            .ok_or_else(|| bad(format!("array {name} is missing")))
    };
    let float = |name: &str| {
        rec.float_attr(name)
            .ok_or_else(|| bad(format!("attribute {name} is {:?}", rec.get_attr(name))))
    };
    let mut snapshots = Vec::new();
    for k in 0..int("snapshot_count")? {
        snapshots.push(Snapshot {
            step: int(&format!("snapshot{k}_step"))?,
            tau: float(&format!("snapshot{k}_tau"))?,
            loaded_radius: float(&format!("snapshot{k}_loaded_radius"))?,
            profile: array(&format!("snapshot{k}_profile"))?,
            pressure: array(&format!("snapshot{k}_pressure"))?,
            slip: array(&format!("snapshot{k}_slip"))?,
            contact_radius: {
                let name = format!("snapshot{k}_contact_radius");
                rec.float_attr(&name).ok_or_else(|| {
                    bad(format!(
                        "snapshot {k} contact radius is {:?}",
                        rec.get_attr(&name)
                    ))
                })?
            },
        });
    }
    Ok(FrettingState {
        step: int("step")?,
        tau: float("tau")?,
        profile: array("profile")?,
        tau_history: array("tau_history")?,
        contact_radius_history: array("contact_radius_history")?,
        loaded_radius_history: array("loaded_radius_history")?,
        next_step: float("next_step")?,
        previous_error: float("previous_error")?,
        rejected_steps: int("rejected_steps")?,
        snapshots,
    })
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

    /// An explicit Euler checkpoint records its rounding (`euler_scheme`): one without it (the
    /// real FFTs' build) or of another is refused saying that only starting over helps.
    #[test]
    fn euler_checkpoints_record_their_scheme() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(CHECKPOINT);
        let params = FrettingParams {
            nodes: 101,
            tau_end: 0.01,
            snapshots: vec![],
            stepping: TimeStepping::ExplicitEuler { dtau: 1e-3 },
            ..FrettingParams::default()
        };
        let mut sim = FrettingSimulation::new(params.clone()).unwrap();
        sim.run(|_| false).unwrap();
        let intact = checkpoint_record(&sim);
        crate::data::write_record(&path, &intact).unwrap();
        assert_eq!(state_from_checkpoint(&path, &params).unwrap().step, 10);
        for other in [None, Some("euler")] {
            let mut rec = intact.clone();
            rec.attributes.retain(|(n, _)| n != "euler_scheme");
            if let Some(name) = other {
                rec = rec.attr("euler_scheme", AttrValue::Text(name.into()));
            }
            crate::data::write_record(&path, &rec).unwrap();
            let e = state_from_checkpoint(&path, &params)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("explicit Euler") && e.contains("only starting the run over helps"),
                "{e}"
            );
        }
    }

    /// The discretization options in checkpoints: a run of the legacy ones (the central
    /// differences without the edge cells, the defaults before stop 45) records none, as every
    /// checkpoint before they existed, and an absent one reads as the legacy value; the default
    /// run records both; a checkpoint of another option is refused naming it, either way round.
    #[test]
    fn checkpoints_record_the_discretization_options_unless_the_legacy_ones() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(CHECKPOINT);
        let params = FrettingParams {
            nodes: 101,
            tau_end: 0.05,
            snapshots: vec![],
            gap_transform: GapTransform::LEGACY,
            edge_cells: false,
            ..FrettingParams::default()
        };
        let options = FrettingParams {
            gap_transform: GapTransform::PiecewiseLinear,
            edge_cells: true,
            ..params.clone()
        };
        let names: Vec<&str> = params_attrs(&params).iter().map(|(n, _)| *n).collect();
        assert!(!names.contains(&"gap_transform") && !names.contains(&"edge_cells"));
        let defaults = FrettingParams {
            nodes: 101,
            ..FrettingParams::default()
        };
        let names: Vec<&str> = params_attrs(&defaults).iter().map(|(n, _)| *n).collect();
        assert!(names.contains(&"gap_transform") && names.contains(&"edge_cells"));
        for (made, resumed, refused) in [
            (&params, &options, Some("gap_transform")),
            (&options, &params, Some("gap_transform")),
            (&options, &options, None),
            (&params, &params, None),
        ] {
            let mut sim = FrettingSimulation::new(made.clone()).unwrap();
            sim.run(|_| false).unwrap();
            crate::data::write_record(&path, &checkpoint_record(&sim)).unwrap();
            match (state_from_checkpoint(&path, resumed), refused) {
                (Ok(state), None) => assert_eq!(state.step, sim.state().step),
                (Err(e), Some(name)) => assert!(e.to_string().contains(name), "{e}"),
                (other, _) => panic!("{:?}", other.map(|s| s.step)),
            }
        }
        // Only the edge cells differ, either way round: refused naming them.
        let without = FrettingParams {
            edge_cells: false,
            ..options.clone()
        };
        for (made, resumed) in [(&options, &without), (&without, &options)] {
            let mut sim = FrettingSimulation::new(made.clone()).unwrap();
            sim.run(|_| false).unwrap();
            crate::data::write_record(&path, &checkpoint_record(&sim)).unwrap();
            let e = state_from_checkpoint(&path, resumed).unwrap_err();
            assert!(e.to_string().contains("edge_cells"), "{e}");
        }
    }
}
