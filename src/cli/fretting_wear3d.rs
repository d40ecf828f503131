//! `halfspace fretting-wear3d`: 3D fretting wear on the SAM solver — parse
//! (`halfspace::config::Wear3dConfig`: the fretting loop's `--config` keys and a `[wear]` table,
//! docs/wear3d.md#the-command) → run (`sam::drivers::fretting_wear3d`, checkpointed) → write
//! (`halfspace::records::wear3d_*`: the summary, results.h5 and checkpoint.npz).

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use halfspace::config::Wear3dConfig;
use halfspace::data::{read_record, write_record};
use halfspace::records::{
    wear3d_estimate_summary, wear3d_results_record, wear3d_snapshot_from_record,
    wear3d_snapshot_record, wear3d_summary,
};
use halfspace::run_dir::{RunDir, RunKind, Start};
use halfspace::sam::drivers::fretting_wear3d::{FrettingWear3d, WearCase};
use serde_json::json;

use super::CliError;

const WEAR_RUN: RunKind = RunKind {
    command: "fretting-wear3d",
    files: &["checkpoint.npz", "results.h5"],
    figure_extensions: &["svg", "gif"],
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
    /// wear_volume.svg, the animation wear_depth.gif; checkpoint.npz while running).
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
    /// Print the estimate of the run and run nothing: wear steps (computed cycles, each one
    /// fretting cycle of 4q increments standing for ΔN cycles), increments, memory and hours of
    /// work (docs/wear3d.md#the-work-estimate; the step count errs towards more steps).
    #[arg(long)]
    estimate: bool,
    /// Do not write the animation wear_depth.gif (one frame per record — each record_cycles
    /// entry and the end — up to 60; with more records, 60 frames evenly spaced over them,
    /// the first and the last always included).
    #[arg(long)]
    no_animation: bool,
}

/// The case of a config file (`halfspace::config::Wear3dConfig`).
fn read_case(path: &Path, grid: Option<usize>) -> Result<WearCase, CliError> {
    let text = halfspace::data::read_text_bounded(path, super::CONFIG_LIMIT)
        .map_err(|e| CliError::Spec(format!("--config {e}")))?;
    let what = format!("--config {}", path.display());
    Ok(Wear3dConfig::from_toml(&text, &what)?.case(grid)?)
}

pub fn run(args: FrettingWear3dArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let case = read_case(&args.config, args.grid)?;
    if args.estimate {
        let summary = wear3d_estimate_summary(&case, &case.estimate()?);
        if args.json {
            println!("{summary}");
        } else {
            println!("{summary:#}");
        }
        return Ok(());
    }
    // Refused before the run directory is claimed (`FrettingWear3d::new` checks the same): a
    // refused request leaves no directory behind.
    case.estimate()?.run.check_memory("the wear run")?;
    let every = super::Checkpoints::interval(args.checkpoint_seconds)?;
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
                "--resume: {} has no checkpoint.npz (the run stopped before its first \
                 checkpoint was written): --force starts it over",
                args.out.display()
            )));
        }
        let snapshot = wear3d_snapshot_from_record(&read_record(&checkpoint)?)
            .map_err(|m| CliError::Spec(format!("--resume {}: {m}", checkpoint.display())))?;
        FrettingWear3d::resume(case, snapshot)?
    } else {
        FrettingWear3d::new(case)?
    };
    let mut checkpoints = super::Checkpoints::new(&checkpoint, every);
    let mut steps = 0usize;
    let outcome = run.run(|r| {
        steps += 1;
        let stop = args.stop_after.is_some_and(|m| steps >= m) && !r.is_done();
        super::flow(checkpoints.after_step(stop, || wear3d_snapshot_record(&r.snapshot())))
    });
    checkpoints.check()?;
    if let Err(e) = outcome {
        // What was done stays: the results so far, and the checkpoint of the last whole step
        // (the failing step's cycle is not in it).
        write_record(&args.out.join("results.h5"), &wear3d_results_record(&run))?;
        let e = CliError::from(e);
        run_dir.fail(&e.to_string())?;
        return Err(e);
    }
    if checkpoints.stopped {
        return Ok(());
    }
    write_record(&args.out.join("results.h5"), &wear3d_results_record(&run))?;
    // The figures (docs/wear3d.md#figures): worn-depth map, profiles, volume against cycles.
    halfspace::figures::wear3d::wear3d_figures(&args.out, &run)?;
    if !args.no_animation {
        halfspace::figures::wear3d::wear3d_animation(&args.out, &run)?;
    }
    if checkpoint.exists() {
        std::fs::remove_file(&checkpoint)
            .map_err(|e| CliError::Spec(format!("removing {}: {e}", checkpoint.display())))?;
    }
    run_dir.complete_present()?;
    let mut summary = wear3d_summary(&run, start.elapsed().as_secs_f64());
    summary["out"] = json!(args.out.display().to_string());
    if args.json {
        println!("{summary}");
    } else {
        println!("{summary:#}");
    }
    Ok(())
}
