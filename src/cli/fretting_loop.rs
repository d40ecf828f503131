//! `halfspace fretting-loop`: the fretting loop of [LN11] (parse → `sam::drivers::fretting_loop` → write).

use std::io::IsTerminal;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use halfspace::config::LoopConfig;
use halfspace::data::{read_record, write_record};
use halfspace::loop_fatigue::{evaluate_loop_fatigue, FATIGUE_FIELDS};
use halfspace::records::{
    case_parameters, loop_results_record, snapshot_from_record, snapshot_record,
};
use halfspace::sam::drivers::fretting_loop::{FrettingLoop, LoopMetrics, PointFields};
use serde_json::{json, Value};

use halfspace::run_dir::{RunDir, RunKind, Start};

use super::plot::Curves;

/// What a fretting-loop run writes into its directory (`halfspace::run_dir`).
const LOOP_RUN: RunKind = RunKind {
    command: "fretting-loop",
    files: &["checkpoint.npz", "results.h5"],
    figure_extensions: &["svg", "png", "gif"],
};

/// One labelled curve.
type Labelled = (String, Vec<(f64, f64)>);
use super::{plot, CliError};

#[derive(Debug, Args)]
pub struct FrettingLoopArgs {
    /// TOML file with any of: radius, e, nu, friction, force or approach, indenter_e and indenter_nu
    /// (elastic sphere; absent: rigid), normal_steps, amplitude, shift_step, grid,
    /// extent_over_a, subsurface_over_a, [[inhomogeneity]], layout, fibre_e_ratio.
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
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    checkpoints.check()?;
    if let Err(e) = outcome {
        // Keep what was done: the checkpoint holds the increments before the failing one.
        let _ = write_record(&checkpoint, &snapshot_record(&lp.snapshot(), (n, n)));
        return Err(e.into());
    }
    if checkpoints.stopped {
        return Ok(());
    }
    let metrics = lp.metrics()?;
    // With inhomogeneities: the homogeneous loop of the same case, for the comparison ([LN11]
    // Figs. 6–9 show both); cheap beside the nested loop.
    let reference_start = Instant::now();
    let reference = if case.inhomogeneities.is_empty() {
        None
    } else {
        let mut r = FrettingLoop::new(case.homogeneous())?;
        r.run(|_| ControlFlow::Continue(()))?;
        let m = r.metrics()?;
        Some((r, m))
    };
    let reference_seconds = reference_start.elapsed().as_secs_f64();
    let fatigue = match &cfg.fatigue {
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
            &FATIGUE_FIELDS,
            "halfspace fretting-loop fatigue indices; XDMF axes Z Y X = depth (into the body), x, y (m)",
        )?;
    }
    // Complete: the checkpoint is no longer needed (a re-run into the same directory starts over).
    if checkpoint.exists() {
        std::fs::remove_file(&checkpoint)
            .map_err(|e| CliError::Spec(format!("removing {}: {e}", checkpoint.display())))?;
    }
    draw_loop_figures(&args.out, &lp, reference.as_ref().map(|(r, _)| r))?;
    if let Some(f) = &frames {
        f.write(&args.out.join("loop_pq.gif"), &lp)?;
    }
    if let Some(f) = &fatigue {
        plot::fatigue_figures(&args.out, f)?;
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

/// The figures of [LN11] from a completed loop (and its homogeneous reference): the loops (Fig. 8),
/// p and q along x and y at A–D (Fig. 6), the slips at B (Fig. 7), the map of q_x at B (Fig. 9),
/// the map of the transverse slip s₂ at B, and the von Mises sections at A–D.
fn draw_loop_figures(
    out: &Path,
    lp: &FrettingLoop,
    reference: Option<&FrettingLoop>,
) -> Result<(), CliError> {
    let case = lp.case();
    let grid = *lp.solver().problem().grid();
    let (n1, n2) = (grid.n1, grid.n2);
    let a = case.hertz_radius();
    let p0 = case.hertz_pressure();
    let mu_w = case.friction * case.hertz_force();
    let mu_p0 = case.friction * p0;
    let fail =
        |p: &Path, e: Box<dyn std::error::Error>| CliError::Plot(format!("{}: {e}", p.display()));
    let with = if reference.is_some() {
        " (with the inhomogeneities)"
    } else {
        ""
    };
    let sets: Vec<(&str, &FrettingLoop)> = std::iter::once((with, lp))
        .chain(reference.map(|r| (" (homogeneous)", r)))
        .collect();
    // Fig. 8: the loops.
    let loops: Vec<Labelled> = sets
        .iter()
        .map(|(suffix, l)| {
            let rows = &l.rows()[l.path().cycle_start()..];
            (
                format!("Q/μW{suffix}"),
                rows.iter().map(|r| (r.d * 1e6, r.q[0] / mu_w)).collect(),
            )
        })
        .collect();
    for ext in ["svg", "png"] {
        let p = out.join(format!("fretting_loop.{ext}"));
        plot::curves(
            &p,
            "Fretting loop (SAM, coupled): Q/μW against δx",
            "δx (μm)",
            ("Q / μW", &loops),
            ("", &[]),
            false,
        )
        .map_err(|e| fail(&p, e))?;
    }
    let xs: Vec<f64> = (0..n1).map(|i| grid.centre(i, n2 / 2).0 / a).collect();
    let ys: Vec<f64> = (0..n2).map(|j| grid.centre(n1 / 2, j).1 / a).collect();
    let along_x = |v: &[f64], s: f64| -> Vec<(f64, f64)> {
        (0..n1).map(|i| (xs[i], v[i * n2 + n2 / 2] / s)).collect()
    };
    let along_y = |v: &[f64], s: f64| -> Vec<(f64, f64)> {
        (0..n2).map(|j| (ys[j], v[(n1 / 2) * n2 + j] / s)).collect()
    };
    // Fig. 6: p and q along x (a) and y (b) at A–D.
    type Line<'a> = &'a dyn Fn(&[f64], f64) -> Vec<(f64, f64)>;
    for (axis, line) in [("x", &along_x as Line), ("y", &along_y as Line)] {
        let (mut left, mut right): (Vec<Labelled>, Vec<Labelled>) = (Vec::new(), Vec::new());
        for (suffix, l) in &sets {
            for p in l.points() {
                left.push((format!("p, {}{suffix}", p.label), line(&p.pressure, p0)));
                right.push((
                    format!("q_x, {}{suffix}", p.label),
                    line(&p.shear[0], mu_p0),
                ));
                if axis == "y" {
                    right.push((
                        format!("q_y, {}{suffix}", p.label),
                        line(&p.shear[1], mu_p0),
                    ));
                }
            }
        }
        let p = out.join(format!("profiles_{axis}.svg"));
        plot::curves(
            &p,
            &format!("[LN11] Fig. 6: p/p0 and q/(μ p0) along {axis} at A–D"),
            &format!("{axis} / a"),
            ("p / p0", &left),
            ("q / (μ p0)", &right),
            false,
        )
        .map_err(|e| fail(&p, e))?;
    }
    // Fig. 7: slips at B along x (a) and y (b).
    let at = |l: &FrettingLoop, label: &str| -> Option<PointFields> {
        l.points().iter().find(|p| p.label == label).cloned()
    };
    let mut slip_x: Vec<Labelled> = Vec::new();
    let mut slip_y: Vec<Labelled> = Vec::new();
    for (suffix, l) in &sets {
        if let Some(b) = at(l, "B") {
            for (c, name) in [(0, "s_x"), (1, "s_y")] {
                slip_x.push((format!("{name} along x{suffix}"), along_x(&b.slip[c], 1e-9)));
                slip_y.push((format!("{name} along y{suffix}"), along_y(&b.slip[c], 1e-9)));
            }
        }
    }
    let p = out.join("slip_B.svg");
    plot::curves(
        &p,
        "[LN11] Fig. 7: slip of the last increment at B (nm), along x and along y",
        "x / a (left), y / a (right)",
        ("slip along x (nm)", &slip_x as &Curves),
        ("slip along y (nm)", &slip_y),
        false,
    )
    .map_err(|e| fail(&p, e))?;
    // Fig. 9 and the transverse slip: surface maps at B over |x|, |y| ≤ 1.3a.
    let window: Vec<usize> = (0..n1).filter(|&i| xs[i].abs() <= 1.3).collect();
    let cols: Vec<usize> = (0..n2).filter(|&j| ys[j].abs() <= 1.3).collect();
    let map = |name: &str, title: &str, unit: &str, v: &[f64], s: f64| -> Result<(), CliError> {
        let values: Vec<Vec<f64>> = cols
            .iter()
            .map(|&j| window.iter().map(|&i| v[i * n2 + j] / s).collect())
            .collect();
        let p = out.join(name);
        plot::heatmap(
            &p,
            title,
            ("x / a", "y / a", unit),
            &window.iter().map(|&i| xs[i]).collect::<Vec<_>>(),
            &cols.iter().map(|&j| ys[j]).collect::<Vec<_>>(),
            &values,
        )
        .map_err(|e| fail(&p, e))
    };
    for (suffix, l) in &sets {
        let tag = if suffix.contains("homogeneous") {
            "_homogeneous"
        } else {
            ""
        };
        if let Some(b) = at(l, "B") {
            map(
                &format!("shear_x_map_B{tag}.svg"),
                &format!("[LN11] Fig. 9: q_x/(μ p0) on the surface at B{suffix}"),
                "q_x / (μ p0)",
                &b.shear[0],
                mu_p0,
            )?;
            map(
                &format!("transverse_slip_map_B{tag}.svg"),
                &format!("Transverse slip s_y at B (nm){suffix}"),
                "s_y (nm)",
                &b.slip[1],
                1e-9,
            )?;
        }
    }
    // Von Mises sections (x–z through y = 0) at A–D.
    let half = grid.half1;
    for p in lp.points() {
        let Some(vm) = &p.von_mises else { continue };
        let layers = vm.len() / (n1 * n2);
        let zs: Vec<f64> = (0..layers).map(|k| (2 * k + 1) as f64 * half / a).collect();
        let window: Vec<usize> = (0..n1).filter(|&i| xs[i].abs() <= 1.5).collect();
        let values: Vec<Vec<f64>> = (0..layers)
            .map(|k| {
                window
                    .iter()
                    .map(|&i| vm[k * n1 * n2 + i * n2 + n2 / 2] / p0)
                    .collect()
            })
            .collect();
        let path = out.join(format!("von_mises_{}.svg", p.label));
        plot::heatmap(
            &path,
            &format!(
                "Von Mises stress / p0 at {} (x–z section through y = 0){with}",
                p.label
            ),
            ("x / a", "depth / a", "σ_vM / p0"),
            &window.iter().map(|&i| xs[i]).collect::<Vec<_>>(),
            &zs,
            &values,
        )
        .map_err(|e| fail(&path, e))?;
    }
    Ok(())
}

/// A map `[row][col]` of the window.
type WindowMap = Vec<Vec<f64>>;
/// A frame of `loop_pq.gif`: its key (increment or title), `p/p0` and `|q|/(μ p0)`.
type PqFrame<K> = (K, WindowMap, WindowMap);

/// The frames of `loop_pq.gif` (docs/composite.md#animation): the pressure `p/p0` and the shear
/// magnitude `|q|/(μ p0)` over `|x|, |y| ≤ 1.3a` at every increment of the cycle (the loop's
/// rows from `cycle_start`), kept as the loop runs (`2 × window cells × (4q + 1)` values).
struct CycleFrames {
    /// Columns (x) and rows (y) of the window.
    cols: Vec<usize>,
    rows: Vec<usize>,
    /// `(increment, p/p0, |q|/(μ p0))`, each `[row][col]`.
    frames: Vec<PqFrame<usize>>,
}

impl CycleFrames {
    fn new(lp: &FrettingLoop) -> Self {
        let grid = *lp.solver().problem().grid();
        let a = lp.case().hertz_radius();
        let cols = (0..grid.n1)
            .filter(|&i| (grid.centre(i, 0).0 / a).abs() <= 1.3)
            .collect();
        let rows = (0..grid.n2)
            .filter(|&j| (grid.centre(0, j).1 / a).abs() <= 1.3)
            .collect();
        Self {
            cols,
            rows,
            frames: Vec::new(),
        }
    }

    /// After an increment: its fields, if it belongs to the cycle.
    fn observe(&mut self, lp: &FrettingLoop) {
        let k = lp.rows().len() - 1;
        if k < lp.path().cycle_start() {
            return;
        }
        let n2 = lp.solver().problem().grid().n2;
        let p0 = lp.case().hertz_pressure();
        let mu_p0 = lp.case().friction * p0;
        let st = lp.solver().problem().state();
        let field = |f: &dyn Fn(usize) -> f64| -> Vec<Vec<f64>> {
            self.rows
                .iter()
                .map(|&j| self.cols.iter().map(|&i| f(i * n2 + j)).collect())
                .collect()
        };
        let p = field(&|c| st.pressure[c] / p0);
        let q = field(&|c| st.shear[0][c].hypot(st.shear[1][c]) / mu_p0);
        self.frames.push((k, p, q));
    }

    /// Writes the animation: one frame per increment of the cycle when all were observed; after
    /// a resume that missed some, one frame per loop point A–D (the fields the loop keeps).
    fn write(&self, path: &Path, lp: &FrettingLoop) -> Result<(), CliError> {
        let grid = *lp.solver().problem().grid();
        let n2 = grid.n2;
        let a = lp.case().hertz_radius();
        let p0 = lp.case().hertz_pressure();
        let mu_p0 = lp.case().friction * p0;
        let mu_w = lp.case().friction * lp.case().hertz_force();
        let complete = self.frames.len() == lp.path().len() - lp.path().cycle_start();
        let field = |v: &[f64], s: f64| -> Vec<Vec<f64>> {
            self.rows
                .iter()
                .map(|&j| self.cols.iter().map(|&i| v[i * n2 + j] / s).collect())
                .collect()
        };
        let frames: Vec<PqFrame<String>> = if complete {
            let start = lp.path().cycle_start();
            self.frames
                .iter()
                .map(|(k, p, q)| {
                    let row = &lp.rows()[*k];
                    (
                        format!(
                            "Increment {} of {}: δx = {:.4} μm, Q/μW = {:.3}",
                            k - start,
                            self.frames.len() - 1,
                            row.d * 1e6,
                            row.q[0] / mu_w
                        ),
                        p.clone(),
                        q.clone(),
                    )
                })
                .collect()
        } else {
            lp.points()
                .iter()
                .map(|f| {
                    let q: Vec<f64> = f.shear[0]
                        .iter()
                        .zip(&f.shear[1])
                        .map(|(a, b)| a.hypot(*b))
                        .collect();
                    (
                        format!("Point {} (increment {})", f.label, f.increment),
                        field(&f.pressure, p0),
                        field(&q, mu_p0),
                    )
                })
                .collect()
        };
        let top = |pick: fn(&PqFrame<String>) -> &WindowMap| {
            frames
                .iter()
                .flat_map(|f| pick(f).iter().flatten().copied())
                .fold(0.0, f64::max)
        };
        let (pmax, qmax) = (top(|f| &f.1), top(|f| &f.2));
        let xs: Vec<f64> = self.cols.iter().map(|&i| grid.centre(i, 0).0 / a).collect();
        let ys: Vec<f64> = self.rows.iter().map(|&j| grid.centre(0, j).1 / a).collect();
        let fail =
            |e: Box<dyn std::error::Error>| CliError::Plot(format!("{}: {e}", path.display()));
        let images = frames
            .into_iter()
            .map(|(title, p, q)| {
                plot::render_frame(
                    &title,
                    ("x / a", "y / a"),
                    &[
                        plot::FrameMap {
                            caption: &format!("p / p0 (0 to {pmax:.3})"),
                            xs: &xs,
                            ys: &ys,
                            values: p,
                            range: (0.0, pmax),
                        },
                        plot::FrameMap {
                            caption: &format!("|q| / (μ p0) (0 to {qmax:.3})"),
                            xs: &xs,
                            ys: &ys,
                            values: q,
                            range: (0.0, qmax),
                        },
                    ],
                )
                .map_err(fail)
            })
            .collect::<Result<Vec<_>, _>>()?;
        plot::write_gif(path, images, 150)
    }
}
