//! `halfspace fretting-wear3d`: 3D fretting wear on the SAM solver (parse → `sam::drivers::
//! fretting_wear3d` → write). The configuration is the fretting loop's TOML (`fretting-loop
//! --config` keys) plus `approach`, `indenter_e`, `indenter_nu` and a `[wear]` table
//! (docs/wear3d.md#the-command).

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use clap::Args;
use halfspace::config::LoopConfig;
use halfspace::data::{read_record, write_record, AttrValue, Record};
use halfspace::run_dir::{RunDir, RunKind, Start};
use halfspace::sam::contact::ContactState;
use halfspace::sam::drivers::fretting_wear3d::{
    FrettingWear3d, WearCase, WearLaw, WearRecord, WearRow, WearSnapshot, WornBody,
    DEFAULT_STABILITY_FRACTION, DEFAULT_STEP_FRACTION, INHOMOGENEITY_DEPTH_CELLS,
};
use serde::Deserialize;
use serde_json::json;

use super::CliError;

const WEAR_RUN: RunKind = RunKind {
    command: "fretting-wear3d",
    files: &["checkpoint.npz", "results.h5"],
    figure_extensions: &["svg"],
};

#[derive(Debug, Args)]
pub struct FrettingWear3dArgs {
    /// TOML file: the fretting-loop keys, `approach` (m; normal control by approach instead of
    /// `force`), `indenter_e`, `indenter_nu` (absent: rigid), and `[wear]` with `law` ("archard" |
    /// "energy"), `coefficient` (m²/N), `body` ("gap" | "flat" | "indenter"), `cycles`, and
    /// optionally `record_cycles`, `step_fraction`, `stability_fraction`,
    /// `inhomogeneity_depth_cells`.
    #[arg(long)]
    config: PathBuf,
    /// Output directory (results.h5, the figures wear_depth_map.svg, wear_depth_profiles.svg,
    /// wear_volume.svg; checkpoint.npz while running).
    #[arg(long, default_value = "fretting-wear3d-out")]
    out: PathBuf,
    /// Cells per side (overrides the config).
    #[arg(long, allow_hyphen_values = true)]
    grid: Option<usize>,
    /// Continue a killed run from OUT/checkpoint.npz (the same configuration), bit for bit.
    #[arg(long)]
    resume: bool,
    /// Replace another run in OUT.
    #[arg(long)]
    force: bool,
    /// Seconds of work between checkpoints.
    #[arg(long, default_value_t = 5.0, allow_hyphen_values = true)]
    checkpoint_seconds: f64,
    /// Testing hook: stop (as if killed) after this many wear steps, leaving the checkpoint.
    #[arg(long, hide = true)]
    stop_after: Option<usize>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
}

/// The `[wear]` table.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct WearTable {
    #[serde(default = "archard")]
    law: String,
    coefficient: f64,
    #[serde(default = "gap")]
    body: String,
    cycles: u64,
    #[serde(default)]
    record_cycles: Vec<u64>,
    #[serde(default = "step_fraction")]
    step_fraction: f64,
    #[serde(default = "stability_fraction")]
    stability_fraction: f64,
    #[serde(default = "depth_cells")]
    inhomogeneity_depth_cells: f64,
}

fn archard() -> String {
    "archard".into()
}
fn gap() -> String {
    "gap".into()
}
fn step_fraction() -> f64 {
    DEFAULT_STEP_FRACTION
}
fn stability_fraction() -> f64 {
    DEFAULT_STABILITY_FRACTION
}
fn depth_cells() -> f64 {
    INHOMOGENEITY_DEPTH_CELLS
}

/// The case of a config file: the keys of this command taken out, the rest read as the fretting
/// loop's configuration.
fn read_case(path: &Path, grid: Option<usize>) -> Result<WearCase, CliError> {
    let text = halfspace::data::read_text_bounded(path, super::CONFIG_LIMIT)
        .map_err(|e| CliError::Spec(format!("--config {e}")))?;
    let what = format!("--config {}", path.display());
    let mut table: toml::Table = toml::from_str(&text)
        .map_err(|e| CliError::Spec(halfspace::config::toml_message(&what, &text, &e)))?;
    let wear: WearTable = table
        .remove("wear")
        .ok_or_else(|| CliError::Spec(format!("{what}: a [wear] table is required")))?
        .try_into()
        .map_err(|e| CliError::Spec(format!("{what}: [wear]: {e}")))?;
    let loop_cfg: LoopConfig = toml::Value::Table(table)
        .try_into()
        .map_err(|e| CliError::Spec(format!("{what}: {e}")))?;
    if loop_cfg.fatigue.is_some() {
        return Err(CliError::Spec(format!(
            "{what}: [fatigue] belongs to fretting-loop (the wear run does not evaluate fatigue criteria)"
        )));
    }
    let fretting = loop_cfg.case("homogeneous", grid)?;
    let law = WearLaw::from_name(&wear.law, wear.coefficient)?;
    let mut case = WearCase::new(fretting, law, wear.cycles);
    case.body = WornBody::from_name(&wear.body)?;
    case.record_cycles = wear.record_cycles;
    case.step_fraction = wear.step_fraction;
    case.stability_fraction = wear.stability_fraction;
    case.inhomogeneity_depth_cells = wear.inhomogeneity_depth_cells;
    case.validate()?;
    Ok(case)
}

pub fn run(args: FrettingWear3dArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let case = read_case(&args.config, args.grid)?;
    if !(args.checkpoint_seconds.is_finite() && args.checkpoint_seconds > 0.0) {
        return Err(CliError::Spec(format!(
            "--checkpoint-seconds must be finite and > 0, got {}",
            args.checkpoint_seconds
        )));
    }
    let manifest = json!({ "case": format!("{case:?}") });
    let run_dir = RunDir::claim(
        &args.out,
        WEAR_RUN,
        manifest,
        Start::of_flags(args.resume, args.force)?,
    )?;
    let checkpoint = run_dir.join("checkpoint.npz");
    let mut run = if args.resume {
        if !checkpoint.exists() {
            return Err(CliError::Spec(format!(
                "--resume: {} has no checkpoint.npz",
                args.out.display()
            )));
        }
        let snapshot = snapshot_from_record(&read_record(&checkpoint)?)
            .map_err(|m| CliError::Spec(format!("--resume {}: {m}", checkpoint.display())))?;
        FrettingWear3d::resume(case, snapshot)?
    } else {
        FrettingWear3d::new(case)?
    };
    let every = Duration::from_secs_f64(args.checkpoint_seconds);
    let mut last = Instant::now();
    let mut write_error = None;
    let mut stopped = false;
    let mut steps = 0usize;
    let outcome = run.run(|r| {
        steps += 1;
        let stop = args.stop_after.is_some_and(|m| steps >= m) && !r.is_done();
        if stop || last.elapsed() >= every {
            if let Err(e) = write_record(&checkpoint, &snapshot_record(&r.snapshot())) {
                write_error = Some(e);
                return ControlFlow::Break(());
            }
            last = Instant::now();
        }
        stopped = stop;
        if stop {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    if let Some(e) = write_error {
        return Err(e.into());
    }
    if let Err(e) = outcome {
        // What was done stays: the results so far, and the checkpoint of the last whole step
        // (the failing step's cycle is not in it).
        write_record(&args.out.join("results.h5"), &results_record(&run))?;
        return Err(e.into());
    }
    if stopped {
        return Ok(());
    }
    write_record(&args.out.join("results.h5"), &results_record(&run))?;
    // The figures (docs/wear3d.md#figures): worn-depth map, profiles, volume against cycles.
    super::plot::wear3d_figures(&args.out, &run)?;
    if checkpoint.exists() {
        std::fs::remove_file(&checkpoint)
            .map_err(|e| CliError::Spec(format!("removing {}: {e}", checkpoint.display())))?;
    }
    run_dir.complete_present()?;
    let last = run.history().last().copied();
    let summary = json!({
        "cycles": run.cycles(),
        "wear_steps": run.history().len(),
        "wear_volume": run.wear_volume(),
        "max_wear_depth": last.map(|r| r.max_wear_depth),
        "contact_radius": last.map(|r| r.contact_radius),
        "stick_radius": last.map(|r| r.stick_radius),
        "dissipated_energy_total": last.map(|r| r.dissipated_energy_total),
        "seconds": start.elapsed().as_secs_f64(),
        "seconds_per_computed_cycle": run.seconds().cycles / run.seconds().computed.max(1) as f64,
        "out": args.out.display().to_string(),
    });
    if args.json {
        println!("{summary}");
    } else {
        println!("{summary:#}");
    }
    Ok(())
}

/// results.h5: `x`, `y` (cell centres, m), `wear_depth` (N₁ × N₂, m), the history per computed
/// cycle ([`WearRow::FIELDS`]) and the records (`record_cycles`, `record_wear_depth_{N}`,
/// `record_pressure_{N}`).
fn results_record(run: &FrettingWear3d) -> Record {
    let g = *run.grid();
    let (n1, n2) = (g.n1, g.n2);
    let mut rec = Record::default()
        .array("x", (0..n1).map(|i| g.centre(i, 0).0).collect())
        .array("y", (0..n2).map(|j| g.centre(0, j).1).collect())
        .shaped("wear_depth", run.wear_depth().to_vec(), &[n1, n2])
        .attr("config", AttrValue::Text(run.fingerprint()));
    rec = rows_into(rec, run.history());
    rec = rec.array(
        "record_cycles",
        run.records().iter().map(|r| r.cycles as f64).collect(),
    );
    for r in run.records() {
        rec = rec
            .shaped(
                &format!("record_wear_depth_{}", r.cycles),
                r.wear_depth.clone(),
                &[n1, n2],
            )
            .shaped(
                &format!("record_pressure_{}", r.cycles),
                r.pressure.clone(),
                &[n1, n2],
            );
    }
    rec
}

fn rows_into(mut rec: Record, rows: &[WearRow]) -> Record {
    for (f, name) in WearRow::FIELDS.iter().enumerate() {
        rec = rec.array(name, rows.iter().map(|r| r.values()[f]).collect());
    }
    rec
}

/// The checkpoint: the snapshot's members by name.
fn snapshot_record(s: &WearSnapshot) -> Record {
    let st = &s.state;
    let mut rec = rows_into(Record::default(), &s.history)
        .attr("config", AttrValue::Text(s.fingerprint.clone()))
        .array(
            "progress",
            vec![
                s.cycles as f64,
                f64::from(u8::from(s.started)),
                f64::from(u8::from(s.done)),
            ],
        )
        .array("wear_depth", s.wear_depth.clone())
        .array("state_pressure", st.pressure.clone())
        .array("state_shear_x", st.shear[0].clone())
        .array("state_shear_y", st.shear[1].clone())
        .array("state_history_x", st.tangential_displacement[0].clone())
        .array("state_history_y", st.tangential_displacement[1].clone())
        .array("state_slip_x", st.slip[0].clone())
        .array("state_slip_y", st.slip[1].clone())
        .array(
            "state_scalars",
            vec![st.shift[0], st.shift[1], st.approach, st.force],
        )
        .array(
            "record_cycles",
            s.records.iter().map(|r| r.cycles as f64).collect(),
        );
    for (k, r) in s.records.iter().enumerate() {
        rec = rec
            .array(&format!("record_wear_depth_{k}"), r.wear_depth.clone())
            .array(&format!("record_pressure_{k}"), r.pressure.clone());
    }
    if let Some(w) = &s.eigen {
        let u = &w.eigen_displacement;
        let (eps_prev, u_prev) = &w.previous;
        rec = rec
            .array("eigenstrain", w.eigenstrain.clone())
            .array("eigen_displacement_1", u[0].clone())
            .array("eigen_displacement_2", u[1].clone())
            .array("eigen_displacement_3", u[2].clone())
            .array("eigenstrain_previous", eps_prev.clone())
            .array("eigen_displacement_previous_1", u_prev[0].clone())
            .array("eigen_displacement_previous_2", u_prev[1].clone())
            .array("eigen_displacement_previous_3", u_prev[2].clone())
            .attr("committed", AttrValue::Int(w.committed as i64));
    }
    rec
}

/// The snapshot of a checkpoint (its content is checked by [`FrettingWear3d::resume`]).
fn snapshot_from_record(rec: &Record) -> Result<WearSnapshot, String> {
    let array = |name: &str| {
        rec.get(name)
            .map(|v| v.to_vec())
            .ok_or_else(|| format!("member {name} is missing"))
    };
    let count = |name: &str, x: f64| -> Result<u64, String> {
        if x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x < 9.0e15 {
            Ok(x as u64)
        } else {
            Err(format!("member {name}: {x} is not a whole count ≥ 0"))
        }
    };
    let fingerprint = match rec.get_attr("config") {
        Some(AttrValue::Text(t)) => t.clone(),
        other => return Err(format!("attribute config is {other:?}")),
    };
    let columns = WearRow::FIELDS
        .iter()
        .map(|f| array(f))
        .collect::<Result<Vec<_>, _>>()?;
    let rows = columns[0].len();
    if columns.iter().any(|c| c.len() != rows) {
        return Err("member cycles: the history columns differ in length".into());
    }
    let history = (0..rows)
        .map(|k| {
            let mut v = [0.0; 10];
            for (f, c) in columns.iter().enumerate() {
                v[f] = c[k];
            }
            WearRow::from_values(v).ok_or_else(|| format!("member cycles: row {k} = {v:?}"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let progress = array("progress")?;
    if progress.len() != 3 || progress[1..].iter().any(|v| *v != 0.0 && *v != 1.0) {
        return Err(format!("member progress: {progress:?}"));
    }
    let scalars = array("state_scalars")?;
    if scalars.len() != 4 {
        return Err(format!(
            "member state_scalars: {} values, 4 expected",
            scalars.len()
        ));
    }
    let state = ContactState {
        pressure: array("state_pressure")?,
        shear: [array("state_shear_x")?, array("state_shear_y")?],
        tangential_displacement: [array("state_history_x")?, array("state_history_y")?],
        slip: [array("state_slip_x")?, array("state_slip_y")?],
        shift: [scalars[0], scalars[1]],
        approach: scalars[2],
        force: scalars[3],
    };
    let records = array("record_cycles")?
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            Ok(WearRecord {
                cycles: count("record_cycles", c)?,
                wear_depth: array(&format!("record_wear_depth_{k}"))?,
                pressure: array(&format!("record_pressure_{k}"))?,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let eigen = match rec.get("eigenstrain") {
        None => None,
        Some(_) => Some(halfspace::sam::contact::NestedWarmStart {
            eigenstrain: array("eigenstrain")?,
            eigen_displacement: [
                array("eigen_displacement_1")?,
                array("eigen_displacement_2")?,
                array("eigen_displacement_3")?,
            ],
            previous: (
                array("eigenstrain_previous")?,
                [
                    array("eigen_displacement_previous_1")?,
                    array("eigen_displacement_previous_2")?,
                    array("eigen_displacement_previous_3")?,
                ],
            ),
            committed: match rec.get_attr("committed") {
                Some(AttrValue::Int(v)) if *v >= 0 => *v as usize,
                other => return Err(format!("attribute committed is {other:?}")),
            },
        }),
    };
    Ok(WearSnapshot {
        fingerprint,
        cycles: count("progress", progress[0])?,
        started: progress[1] == 1.0,
        done: progress[2] == 1.0,
        wear_depth: array("wear_depth")?,
        history,
        records,
        state,
        eigen,
    })
}
