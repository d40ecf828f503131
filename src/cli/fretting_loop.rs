//! `halfspace fretting-loop`: the fretting loop of [LN11] (parse → `sam::drivers::fretting_loop` → write).

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use halfspace::config::LoopConfig;
use halfspace::data::{read_record, write_record};
use halfspace::loop_fatigue::evaluate_loop_fatigue;
use halfspace::records::{
    case_parameters, loop_results_record, snapshot_from_record, snapshot_record,
};
use halfspace::sam::drivers::fretting_loop::{FrettingLoop, LoopMetrics};
use serde_json::{json, Value};

use halfspace::run_dir::{RunDir, RunKind, Start};

/// What a fretting-loop run writes into its directory (`halfspace::run_dir`).
const LOOP_RUN: RunKind = RunKind {
    command: "fretting-loop",
    files: &["checkpoint.npz", "results.h5"],
    figure_extensions: &["svg", "png", "gif"],
};

use halfspace::figures::fretting_loop::{fatigue_figures, loop_figures, CycleFrames};

use super::CliError;

#[derive(Debug, Args)]
pub struct FrettingLoopArgs {
    /// TOML file with any of: radius, e, nu, friction, force or approach, indenter_e and indenter_nu
    /// (elastic sphere; absent: rigid), normal_steps, amplitude, shift_step, grid,
    /// extent_over_a, subsurface_over_a, [[inhomogeneity]], layout, fibre_e_ratio; [fatigue]
    /// (the fatigue criteria over the closed cycle, docs/fatigue.md); with inhomogeneities
    /// inhomogeneous_body ("nested", the default, or "surface-operator") and
    /// surface_operator_radius_over_a (default 1.3), and for the nested loop eim_change_factor
    /// (in (0, 1]; default 3e-3) and eim_recycled_depth (0 to 50; default 5;
    /// docs/theory-sam.md); alternation ("plain", the default, or "gauged": the contact solves'
    /// normal–tangential alternation, docs/theory-sam.md#normal-tangential-alternation).
    #[arg(long)]
    config: Option<PathBuf>,
    /// Output directory (results.h5, the figures of [LN11] Figs. 6–9, checkpoint.npz while running).
    #[arg(long, default_value = "fretting-loop-out")]
    out: PathBuf,
    /// Cells per side (overrides the config).
    #[arg(long, allow_hyphen_values = true)]
    grid: Option<usize>,
    /// Preset: `homogeneous` ([LN11]'s homogeneous half-space, the default) or `composite` (its
    /// unidirectional composite: fibres along y, r = 0.13a, spacing 3r, axes at depth 1.5r,
    /// E_I = 2E_m (config `fibre_e_ratio`), ν_I = ν_m, 4 cells per fibre radius; config `layout`).
    #[arg(long, default_value = "homogeneous")]
    case: String,
    /// Continue a killed run from OUT/checkpoint.npz (the same configuration), bit for bit.
    #[arg(long)]
    resume: bool,
    /// Replace another run in OUT (its files are removed before this run starts).
    #[arg(long)]
    force: bool,
    /// Seconds of work between checkpoints (written atomically to OUT/checkpoint.npz; removed when
    /// the loop completes).
    #[arg(long, default_value_t = 5.0, allow_hyphen_values = true)]
    checkpoint_seconds: f64,
    /// Testing hook: stop (as if killed) after this many increments, leaving the checkpoint.
    #[arg(long, hide = true, allow_hyphen_values = true)]
    stop_after: Option<usize>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Do not write the animation loop_pq.gif.
    #[arg(long)]
    no_animation: bool,
}

pub fn run_loop(args: FrettingLoopArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let cfg: LoopConfig = super::read_config(args.config.as_deref())?;
    let every = super::Checkpoints::interval(args.checkpoint_seconds)?;
    if !matches!(args.case.as_str(), "homogeneous" | "composite") {
        return Err(CliError::Spec(format!(
            "--case '{}': homogeneous or composite",
            args.case
        )));
    }
    let case = cfg.case(&args.case, args.grid)?;
    // Refused before the directory is touched: runaway work (the loop checks it again).
    case.estimate().check("the fretting loop")?;
    if !case.inhomogeneities.is_empty() {
        case.estimate_with_reference()
            .check_memory("the fretting loop with its homogeneous reference loop beside it")?;
    }
    let start_mode = Start::of_flags(args.resume, args.force)?;
    let mut manifest = case_parameters(&case);
    manifest["preset"] = json!(args.case);
    let run_dir = RunDir::claim(&args.out, LOOP_RUN, manifest, start_mode)?;
    let checkpoint = run_dir.join("checkpoint.npz");
    if args.resume && !checkpoint.exists() {
        return Err(CliError::Spec(format!(
            "--resume: {} has no checkpoint.npz",
            args.out.display()
        )));
    }
    let n = case.grid;
    let mut lp = if args.resume {
        let snapshot = snapshot_from_record(&read_record(&checkpoint)?, &checkpoint)?;
        FrettingLoop::resume(case.clone(), snapshot).map_err(|e| {
            CliError::Spec(format!(
                "--resume {}: {e}; resume with the same --config, --case and --grid (or remove it to start over)",
                checkpoint.display()
            ))
        })?
    } else {
        FrettingLoop::new(case.clone())?
    };
    let total = lp.path().len();
    let bar = (std::io::stderr().is_terminal() && !args.json).then(|| {
        let bar = indicatif::ProgressBar::new(total as u64);
        bar.set_position(lp.rows().len() as u64);
        bar
    });
    let mut checkpoints = super::Checkpoints::new(&checkpoint, every);
    // The animation's frames: p and |q| over the window at every increment of the cycle, taken
    // from the solver's state after each increment (docs/composite.md#animation).
    let mut frames = (!args.no_animation).then(|| CycleFrames::new(&lp));
    let mut run_loop = || {
        let outcome = lp.run(|l| {
            if let Some(bar) = &bar {
                bar.inc(1);
            }
            if let Some(f) = frames.as_mut() {
                f.observe(l);
            }
            let done = l.rows().len();
            let stop = args.stop_after.is_some_and(|m| done >= m) && done < total;
            super::flow(checkpoints.after_step(stop, || snapshot_record(&l.snapshot(), (n, n))))
        });
        (outcome, checkpoints.stopped)
    };
    // With inhomogeneities: the homogeneous loop of the same case, for the comparison ([LN11]
    // Figs. 6–9 show both), run beside the nested loop (kept only when that one completes).
    let ((outcome, stopped), reference) = if case.inhomogeneities.is_empty() {
        (run_loop(), None)
    } else {
        // Kept only when the nested loop ran to its end (not stopped, no error, no checkpoint
        // write that failed: `Ok(false)`).
        FrettingLoop::run_beside(case.homogeneous(), run_loop, |(outcome, stopped)| {
            matches!(outcome, Ok(true)) && !stopped
        })
    };
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    checkpoints.check()?;
    if let Err(e) = outcome {
        // Keep what was done: the checkpoint holds the increments before the failing one.
        let _ = write_record(&checkpoint, &snapshot_record(&lp.snapshot(), (n, n)));
        let e = CliError::from(e);
        run_dir.fail(&e.to_string())?;
        return Err(e);
    }
    if stopped {
        return Ok(());
    }
    let metrics = lp.metrics()?;
    let reference = match reference.transpose()? {
        Some(r) => {
            let m = r.metrics()?;
            Some((r, m))
        }
        None => None,
    };
    // The reference's own increments (run beside the nested loop, they overlap its time).
    let reference_seconds = reference
        .as_ref()
        .map_or(0.0, |(r, _)| r.seconds().increments);
    let fatigue = match &cfg.fatigue_config() {
        Some(f) => Some(evaluate_loop_fatigue(&lp, f)?),
        None => None,
    };
    let mut rec = loop_results_record(&lp, &metrics, reference.as_ref().map(|(r, m)| (r, m)));
    if let Some(f) = &fatigue {
        rec = f.record(rec);
    }
    let results = args.out.join("results.h5");
    write_record(&results, &rec)?;
    if let Some(f) = &fatigue {
        halfspace::data::write_xdmf_rectilinear(
            &results.with_extension("xdmf"),
            &results,
            &f.volume(),
            &f.volume_fields()
                .iter()
                .map(String::as_str)
                .collect::<Vec<_>>(),
            "halfspace fretting-loop fatigue indices; XDMF axes Z Y X = depth (into the body), x, y (m)",
        )?;
    }
    loop_figures(&args.out, &lp, reference.as_ref().map(|(r, _)| r))?;
    if let Some(f) = &frames {
        f.write(&args.out.join("loop_pq.gif"), &lp)?;
    }
    if let Some(f) = &fatigue {
        fatigue_figures(&args.out, f)?;
    }
    // Complete, figures written: the checkpoint is no longer needed (a re-run into the same
    // directory starts over). Removed only now, so that a figure that fails leaves `--resume`.
    if checkpoint.exists() {
        std::fs::remove_file(&checkpoint)
            .map_err(|e| CliError::Spec(format!("removing {}: {e}", checkpoint.display())))?;
    }
    run_dir.complete_present()?;
    let mut summary = loop_summary(
        &lp,
        &metrics,
        reference.as_ref(),
        &args,
        start,
        reference_seconds,
    );
    if let (Some(f), Some(out)) = (&fatigue, summary.as_object_mut()) {
        if let Value::Object(keys) = f.summary() {
            out.extend(keys);
        }
    }
    if args.json {
        println!("{summary}");
    } else {
        println!("{summary:#}");
    }
    Ok(())
}

/// The JSON summary: the metrics, the run's work and time by part, and with inhomogeneities the
/// homogeneous reference and the ratios to it.
fn loop_summary(
    lp: &FrettingLoop,
    m: &LoopMetrics,
    reference: Option<&(FrettingLoop, LoopMetrics)>,
    args: &FrettingLoopArgs,
    start: Instant,
    reference_seconds: f64,
) -> Value {
    let rows = lp.rows();
    let s = lp.seconds();
    let sum = |f: fn(&halfspace::sam::drivers::fretting_loop::LoopRow) -> usize| {
        rows.iter().map(f).sum::<usize>()
    };
    let mut summary = halfspace::records::loop_summary(lp, m);
    summary["seconds"] = json!(start.elapsed().as_secs_f64());
    summary["breakdown"] = json!({
        "increment_seconds": s.increments,
        "contact_seconds": s.contact,
        "traction_strain_seconds": s.traction_strain,
        "eim_seconds": s.eim,
        "disturbance_seconds": s.disturbance,
        "subsurface_seconds": s.subsurface,
        "cycle_stress_seconds": s.cycle_stress,
        "homogeneous_reference_seconds": reference_seconds,
        "alternations": sum(|r| r.alternations),
        "outer_iterations": sum(|r| r.outer_iterations),
        "eim_operator_applications": sum(|r| r.eim_iterations),
    });
    summary["out"] = json!(args.out.display().to_string());
    if lp.solver().nested().is_some() {
        let extra = summary.as_object_mut().expect("object");
        extra.insert("case".into(), json!(args.case));
        if let Some((r, rm)) = reference {
            let (a, b) = (
                &rows[lp.path().normal_steps - 1],
                &r.rows()[r.path().normal_steps - 1],
            );
            let mut homogeneous = halfspace::records::metrics_summary(rm);
            // The reference's summary has always omitted its approach (kept: outputs bit for bit).
            if let Some(h) = homogeneous.as_object_mut() {
                h.remove("approach_over_hertz_end_of_normal_loading");
            }
            extra.insert("homogeneous".into(), homogeneous);
            extra.insert(
                "max_pressure_ratio_to_homogeneous".into(),
                json!(a.max_pressure / b.max_pressure),
            );
            extra.insert(
                "contact_area_ratio_to_homogeneous".into(),
                json!(a.contact_area / b.contact_area),
            );
            extra.insert(
                "dissipated_energy_ratio_to_homogeneous".into(),
                json!(m.dissipated_energy / rm.dissipated_energy),
            );
        }
    }
    summary
}
