//! `halfspace fretting-map`: the fretting loop over loads × amplitudes (parse →
//! `halfspace::fretting_map::run_map` → write).

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use halfspace::config::map_config_from_toml;
use halfspace::data::{write_atomic, write_record, DataError};
use halfspace::fretting_map::{
    has_checkpoints, map_csv, map_record, material_response, run_map_with, CRACK_RISK_THRESHOLD,
    WEAR_ENERGY_RATIO_THRESHOLD,
};
use serde_json::json;

use halfspace::run_dir::{RunDir, RunKind, Start};

use halfspace::figures::fretting_map::map_figures;

use super::CliError;

/// What a fretting-map run writes into its directory (`halfspace::run_dir`).
const MAP_RUN: RunKind = RunKind {
    command: "fretting-map",
    files: &["points", "results.h5", "results.csv"],
    figure_extensions: &["svg", "png"],
};

#[derive(Debug, Args)]
pub struct FrettingMapArgs {
    /// TOML file: a [map] table with loads = [..] (N), amplitudes = [..] (m) and optionally
    /// case = "homogeneous" | "composite"; the other keys are those of `fretting-loop --config`.
    /// The domain (and any composite fibres) is sized for the largest load.
    #[arg(long)]
    config: PathBuf,
    /// Output directory: results.h5, results.csv, fretting_map.svg/.png; points/ while running.
    #[arg(long, default_value = "fretting-map-out")]
    out: PathBuf,
    /// Cells per side (overrides the config).
    #[arg(long, allow_hyphen_values = true)]
    grid: Option<usize>,
    /// Continue a killed map from OUT/points (the same configuration): completed points are read
    /// back, the others run.
    #[arg(long)]
    resume: bool,
    /// Replace another run in OUT (its files are removed before this map starts).
    #[arg(long)]
    force: bool,
    /// Testing hook: stop (as if killed) after this many new points, leaving their checkpoints.
    #[arg(long, hide = true, allow_hyphen_values = true)]
    stop_after: Option<usize>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
}

pub fn run(args: FrettingMapArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let what = format!("--config {}", args.config.display());
    let text = halfspace::data::read_text_bounded(&args.config, super::CONFIG_LIMIT)
        .map_err(|e| CliError::Spec(format!("--config {e}")))?;
    let (cfg, axes) = map_config_from_toml(&text, &what)?;
    let case = axes.case.as_deref().unwrap_or("homogeneous");
    let map = cfg.map(case, args.grid, axes.loads, axes.amplitudes)?;
    let start_mode = Start::of_flags(args.resume, args.force)?;
    let mut manifest = halfspace::records::case_parameters(map.base());
    manifest["preset"] = json!(case);
    manifest["loads"] = json!(map.loads());
    manifest["amplitudes"] = json!(map.amplitudes());
    let run_dir = RunDir::claim(&args.out, MAP_RUN, manifest, start_mode)?;
    let points_dir = run_dir.join("points");
    if args.resume && !has_checkpoints(&points_dir) {
        return Err(CliError::Spec(format!(
            "--resume: {} has no checkpoints",
            points_dir.display()
        )));
    }
    std::fs::create_dir_all(&points_dir)
        .map_err(|e| CliError::Spec(format!("--out {}: {e}", args.out.display())))?;
    let bar = (std::io::stderr().is_terminal() && !args.json)
        .then(|| indicatif::ProgressBar::new(map.len() as u64));
    let fatigue = cfg.fatigue_config();
    let result = run_map_with(
        &map,
        fatigue.as_ref(),
        Some(&points_dir),
        args.stop_after,
        |done, _| {
            if let Some(bar) = &bar {
                bar.set_position(done as u64);
            }
        },
        &|| false,
    )
    .map_err(|e| CliError::Spec(e.to_string()))?;
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    let Some(points) = result.complete() else {
        return Ok(()); // --stop-after: the checkpoints stay for --resume.
    };
    write_record(&args.out.join("results.h5"), &map_record(&map, &points))?;
    let csv_path = args.out.join("results.csv");
    let csv = map_csv(&points);
    write_atomic(&csv_path, |tmp| {
        std::fs::write(tmp, &csv).map_err(|source| DataError::Io {
            path: tmp.to_path_buf(),
            source,
        })
    })?;
    let column = |f: usize| -> Vec<f64> { points.iter().map(|p| p.values()[f]).collect() };
    let (regime, energy) = (column(2), column(3));
    let (crack_risk, response): (Vec<f64>, Vec<f64>) = points
        .iter()
        .map(|p| (p.crack_risk, material_response(p)))
        .unzip();
    let with_risk = cfg.fatigue.is_some();
    map_figures(
        &args.out,
        &map,
        &regime,
        &energy,
        with_risk.then_some((&response[..], &crack_risk[..])),
    )?;
    // Complete, figures written: the per-point checkpoints are no longer needed (removed only
    // now, so that a figure that fails leaves `--resume`).
    std::fs::remove_dir_all(&points_dir)
        .map_err(|e| CliError::Spec(format!("removing {}: {e}", points_dir.display())))?;
    let base = map.base();
    run_dir.complete_present()?;
    let (rows, cols) = map.shape();
    let grid_of = |v: &[f64]| -> Vec<Vec<f64>> { v.chunks(cols).map(<[f64]>::to_vec).collect() };
    let mut summary = json!({
        "loads": map.loads(),
        "amplitudes": map.amplitudes(),
        "shape": [rows, cols],
        "regime": grid_of(&regime).iter().map(|r| r.iter().map(|&v| v as i64).collect::<Vec<_>>()).collect::<Vec<_>>(),
        "dissipated_energy": grid_of(&energy),
        "energy_ratio": grid_of(&column(4)),
        "points": map.len(),
        "resumed_points": result.resumed,
        "point_seconds": column(8).iter().sum::<f64>(),
        "seconds": start.elapsed().as_secs_f64(),
        "grid": base.grid,
        "extent": base.extent(),
        "inclusion_count": base.inhomogeneities.len(),
    });
    if with_risk {
        let codes = |v: &[f64]| -> Vec<Vec<i64>> {
            grid_of(v)
                .iter()
                .map(|r| r.iter().map(|&x| x as i64).collect())
                .collect()
        };
        summary["crack_risk"] = json!(grid_of(&crack_risk));
        summary["crack_risk_definition"] =
            json!("max(crossland_max, dang_van_max) over the fatigue box of the closed cycle");
        summary["material_response"] = json!(codes(&response));
        summary["material_response_codes"] = json!("0 no damage, 1 cracking, 2 wear, 3 both");
        summary["crack_risk_threshold"] = json!(CRACK_RISK_THRESHOLD);
        summary["wear_energy_ratio_threshold"] = json!(WEAR_ENERGY_RATIO_THRESHOLD);
    }
    if args.json {
        println!("{summary}");
    } else {
        println!("{summary:#}");
    }
    Ok(())
}
