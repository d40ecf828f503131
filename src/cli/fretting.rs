//! `halfspace fretting-wear`: fretting wear on the MDR (docs/theory-mdr.md#fretting-wear), the project's main job.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use halfspace::config::Names;
use halfspace::data::{write_record, AttrValue, Record};
use halfspace::fretting::{FrettingParams, FrettingSimulation};
use halfspace::fretting_wear::{
    check_run_scheme, checkpoint_record, params_attrs, resume_state, ResumeError, WearConfig,
    WearRunCase, CHECKPOINT, WEAR_COMMAND,
};
use halfspace::records::wear_summary;
use halfspace::spec::WearMedium;
use serde_json::json;

use halfspace::run_dir::{RunDir, RunKind, Start};

use super::axisym::Method;
use halfspace::figures::fretting_wear::worn_profiles;

use super::CliError;

/// What a fretting-wear run writes into its directory (`halfspace::run_dir`).
const WEAR_RUN: RunKind = RunKind {
    command: WEAR_COMMAND,
    files: &[CHECKPOINT, "results.h5", "results.npz"],
    figure_extensions: &["svg", "png"],
};

#[derive(Debug, Args)]
pub struct FrettingArgs {
    /// TOML (or .json) file with any of: chi, n, tol, dtau, tau_end, length, snapshots, method,
    /// material, gap_transform, edge_cells; a flag given on the command line overrides its key (docs/architecture.md, "The application layer").
    #[arg(long)]
    config: Option<PathBuf>,
    /// Output directory (results.h5, results.npz, worn_profiles.png/.svg, checkpoint.npz).
    #[arg(long, default_value = "fretting-out")]
    out: PathBuf,
    /// Backend of the transforms.
    #[arg(long, value_enum)]
    method: Option<Method>,
    /// Continue a killed run from DIR/checkpoint.npz.
    #[arg(long)]
    resume: bool,
    /// Overwrite another run's results in DIR.
    #[arg(long)]
    force: bool,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// u_A / u_max, 0 < χ < 1.
    #[arg(long, allow_hyphen_values = true)]
    chi: Option<f64>,
    /// The medium: homogeneous (default), homogeneous:nu=.., or graded:k=..,nu=.. (E ∝ z^k,
    /// −1 < k < 1; the normalized run depends on k alone, ν sets u_max = μ (c_N/c_T) d).
    #[arg(long)]
    material: Option<String>,
    /// Grid nodes N.
    #[arg(long, allow_hyphen_values = true)]
    n: Option<usize>,
    /// Local error tolerance of the adaptive (ROS2) wear steps, max over the nodes in units of d
    /// (default 1e-4).
    #[arg(long, allow_hyphen_values = true)]
    tol: Option<f64>,
    /// Fixed wear step Δτ instead of adaptive steps (ROS2, stable at any step).
    #[arg(long, allow_hyphen_values = true)]
    dtau: Option<f64>,
    /// Final τ = N/N0.
    #[arg(long, allow_hyphen_values = true)]
    tau_end: Option<f64>,
    /// Domain size L/a0 (≥ 1.45 and ≥ 1.02 r*/a0; default 1.6, graded max(1.6, 1.15 r*/a0)).
    #[arg(long, allow_hyphen_values = true)]
    length: Option<f64>,
    /// The discretization of the profile transform (Eq. 7/23) of the worn profile:
    /// piecewise-linear (default: no node-to-node mode near the contact edge) or
    /// central-differences (the paper's Eq. 7 as written; docs/fretting-wear.md, "The profile
    /// transform of the worn profile").
    #[arg(long, value_parser = ["central-differences", "piecewise-linear"])]
    gap_transform: Option<String>,
    /// The wear rate of the cells at the contact edge as cell means of p Δu instead of nodal
    /// samples (default true; docs/fretting-wear.md, "Edge cells"): with the piecewise-linear
    /// transform the fewest steps of the graded runs. `--edge-cells false` turns them off (and
    /// overrides a config's `edge_cells`).
    #[arg(long, num_args = 0..=1, default_missing_value = "true")]
    edge_cells: Option<bool>,
    /// Seconds of work between checkpoints.
    #[arg(long, default_value_t = 2.0, allow_hyphen_values = true)]
    checkpoint_seconds: f64,
    /// Testing hook: stop (as if killed) after this many steps, leaving the checkpoint.
    #[arg(long, hide = true, allow_hyphen_values = true)]
    stop_after: Option<u64>,
}

/// The config file: every key optional, unknown keys refused by name.
/// The run's parameters: the `--config` file's keys ([`WearConfig`]) with the flags over them key
/// by key, validated once by the case.
fn params_of(args: &FrettingArgs) -> Result<(FrettingParams, WearMedium), CliError> {
    let file: WearConfig = super::read_config(args.config.as_deref())?;
    let flags = WearConfig {
        chi: args.chi,
        n: args.n,
        tol: args.tol,
        dtau: args.dtau,
        tau_end: args.tau_end,
        length: args.length,
        snapshots: None,
        method: args.method.map(|m| m.name().to_string()),
        material: args.material.clone(),
        gap_transform: args.gap_transform.clone(),
        edge_cells: args.edge_cells,
    };
    let WearRunCase { params, medium } = file.overlay(flags).case(Names::Flags)?;
    Ok((params, medium))
}

fn fretting_error(e: halfspace::fretting::FrettingError) -> CliError {
    CliError::Spec(e.to_string())
}

/// A refused resume, with the flag it concerns and the one that starts over.
fn resume_error(e: ResumeError) -> CliError {
    CliError::Spec(format!("--resume: {e} (--force starts over)"))
}

pub fn run(args: FrettingArgs) -> Result<(), CliError> {
    let (params, medium) = params_of(&args)?;
    let every = super::Checkpoints::interval(args.checkpoint_seconds)?;
    let start_mode = Start::of_flags(args.resume, args.force)?;
    let mut manifest = serde_json::Map::new();
    for (name, value) in params_attrs(&params) {
        manifest.insert(name.into(), value.to_json());
    }
    manifest.insert("medium".into(), json!(format!("{medium:?}")));
    if start_mode == Start::Resume {
        // Before the run directory's own check, whose message would ask for parameters no flag
        // sets.
        check_run_scheme(&args.out, &params).map_err(resume_error)?;
    }
    let run_dir = RunDir::claim(&args.out, WEAR_RUN, manifest.into(), start_mode)?;
    let dir = run_dir.path();
    let checkpoint = dir.join(CHECKPOINT);
    let results = dir.join("results.h5");
    let start = Instant::now();
    let mut sim = if args.resume {
        let state = resume_state(dir, &params).map_err(resume_error)?;
        FrettingSimulation::resume(params.clone(), state).map_err(|e| {
            CliError::Spec(format!(
                "--resume {}: {e}; the checkpoint is left as it is (--force starts over)",
                checkpoint.display()
            ))
        })?
    } else {
        FrettingSimulation::new(params.clone()).map_err(fretting_error)?
    };
    // Progress in thousandths of τ_end (adaptive steps are not known in advance).
    let progress = |s: &FrettingSimulation| (1000.0 * s.tau() / s.params().tau_end) as u64;
    let bar = if std::io::stderr().is_terminal() && !args.json {
        let bar = indicatif::ProgressBar::new(1000);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} τ = {msg}  ETA {eta}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar.set_position(progress(&sim));
        Some(bar)
    } else {
        None
    };
    let mut checkpoints = super::Checkpoints::new(&checkpoint, every);
    let result = sim.run(|s| {
        let step = s.state().step;
        if let Some(bar) = &bar {
            if step % 16 == 0 {
                bar.set_position(progress(s));
                bar.set_message(format!("{:.3} ({step} steps)", s.tau()));
            }
        }
        let stop = args.stop_after.is_some_and(|k| step >= k);
        checkpoints.after_step(stop, || checkpoint_record(s))
    });
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    checkpoints.check()?;
    if let Err(e) = result {
        // Keep what was done: the checkpoint holds the last good state.
        let _ = write_record(&checkpoint, &checkpoint_record(&sim));
        let e = fretting_error(e);
        run_dir.fail(&e.to_string())?;
        return Err(e);
    }
    if checkpoints.stopped {
        return Ok(());
    }
    write_record(&checkpoint, &checkpoint_record(&sim))?;
    let seconds = start.elapsed().as_secs_f64();
    let rec = results_record(&sim);
    write_record(&results, &rec)?;
    write_record(&dir.join("results.npz"), &rec)?;
    for ext in ["svg", "png"] {
        let path = dir.join(format!("worn_profiles.{ext}"));
        worn_profiles(&path, &sim)?;
    }
    run_dir.complete(&[
        "checkpoint.npz",
        "results.h5",
        "results.npz",
        "worn_profiles.svg",
        "worn_profiles.png",
    ])?;
    let state = sim.state();
    let mut summary = wear_summary(&sim, &medium);
    summary["seconds"] = json!(seconds);
    // A diagnostic of this process (not part of the state): GMRES iterations of the implicit steps.
    summary["krylov_iterations"] = json!(sim.krylov_iterations());
    summary["out"] = json!(dir.display().to_string());
    if args.json {
        println!("{summary}");
    } else {
        println!(
            "τ = {:.3}: a/a0 = {:.4} (limit r*/a0 = {:.4}, loaded radius {:.4}), f(a0)/d = {:.4}; {} steps in {seconds:.2} s; results in {}",
            state.tau,
            summary["contact_radius_over_a0"].as_f64().unwrap_or(f64::NAN),
            sim.limit_contact_radius(),
            summary["loaded_radius_over_a0"].as_f64().unwrap_or(f64::NAN),
            sim.profile_at_a0(),
            state.step,
            dir.display()
        );
    }
    Ok(())
}

fn results_record(sim: &FrettingSimulation) -> Record {
    let p = sim.params();
    let state = sim.state();
    let mut rec = Record::default()
        .array("r", sim.grid().coordinates())
        .array("limiting_profile", sim.limiting_profile().to_vec())
        .array("tau_history", state.tau_history.clone())
        .array(
            "contact_radius_history",
            state.contact_radius_history.clone(),
        )
        .array("loaded_radius_history", state.loaded_radius_history.clone())
        .array(
            "snapshot_tau",
            state.snapshots.iter().map(|s| s.tau).collect(),
        )
        .array(
            "snapshot_contact_radius",
            state.snapshots.iter().map(|s| s.contact_radius).collect(),
        )
        .array(
            "snapshot_loaded_radius",
            state.snapshots.iter().map(|s| s.loaded_radius).collect(),
        );
    for (k, s) in state.snapshots.iter().enumerate() {
        rec = rec
            .array(&format!("f_{k}"), s.profile.clone())
            .array(&format!("p_{k}"), s.pressure.clone())
            .array(&format!("slip_{k}"), s.slip.clone());
    }
    for (name, value) in params_attrs(p) {
        rec = rec.attr(name, value);
    }
    rec.attr(
        "limit_contact_radius",
        AttrValue::Float(sim.limit_contact_radius()),
    )
    .attr(
        "units",
        AttrValue::Text(
            "normalized (docs/theory-mdr.md#fretting-wear): r/a0, f/d, p a0²/F0, slip per cycle / u_A, tau = N/N0; \
                 f_k, p_k, slip_k at snapshot_tau[k]; contact radius = extent of the touching \
                 region, loaded radius = outermost node with p > 1e-3 max p"
                .into(),
        ),
    )
    .attr(
        "generator",
        AttrValue::Text(format!(
            "halfspace {} fretting-wear",
            env!("CARGO_PKG_VERSION")
        )),
    )
}
