//! `halfspace study`: convergence studies against closed forms (the docs' figures). Parse →
//! `halfspace_cases::studies` (the series and the summary) → `halfspace_figures::studies` (the
//! figure) → stdout.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use halfspace::cases::studies::{self, StudyError};
use halfspace::figures::studies as figures;

use super::CliError;

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum Study {
    /// Eq. 17 on the Eq. 18 pair q = 1 − x⁴: mean relative error (Eq. 19) against N.
    Eq17,
    /// Eqs. 12 and 13 on Hertz (docs/theory-mdr.md#displacement-transform test 2): max error against N.
    Displacement,
    /// Eqs. 25 and 26 on the Eq. 27 pair U = x⁴ at k = ±0.5: mean relative error against N.
    Eq27,
    /// Graded Hertz (E0 = z0 = R = 1, ν = 0.3, δ = 0.01) for k = −0.5, 0, 0.5: p(r) and u(r).
    GradedHertz,
    /// MDR against the scikit-fem references in datasets/fe.h5 (k = 0, ±0.3).
    FeComparison,
    /// Fretting wear: a/a0 against τ for χ = 0.3, 0.5, 0.9 and their limits r*/a0 (docs/theory-mdr.md#fretting-wear).
    FrettingLimit,
    /// Fretting wear of graded media E ∝ z^k: the limiting worn profiles (χ = 0.5) for k = −0.5 … 0.9
    /// and the final wear volume against the amplitude u_A/(μd) (ν = 0.3), the optimal grading.
    GradedWear,
    /// Timing of one application of the EIM volume operator (eigenstrain on every layer → strain on
    /// every layer, half-space) on --grid² cells × --layers layers: build and apply seconds.
    EimOperator,
    /// The paper's Fig. 1: seconds per profile transform (Eq. 7 / Eq. 23, planned beforehand)
    /// against N, MVM against FFT, homogeneous and graded (k = 0.5), one run, log–log.
    TransformTiming,
}

#[derive(Debug, Args)]
pub struct StudyArgs {
    /// Which study.
    #[arg(value_enum)]
    study: Study,
    /// Plot the errors against N (log–log) to FILE.svg.
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Directory of the reference fixtures (fe-comparison; default `datasets`).
    #[arg(long)]
    datasets: Option<PathBuf>,
    /// Cells per side (eim-operator; default 128).
    #[arg(long, allow_hyphen_values = true)]
    grid: Option<usize>,
    /// Layers (eim-operator; default 8).
    #[arg(long, allow_hyphen_values = true)]
    layers: Option<usize>,
}

pub fn run(args: StudyArgs) -> Result<(), CliError> {
    // A flag the chosen study does not read is refused, not ignored.
    let name = args
        .study
        .to_possible_value()
        .map(|v| v.get_name().to_string())
        .unwrap_or_default();
    for (flag, given, reader) in [
        ("--datasets", args.datasets.is_some(), Study::FeComparison),
        ("--grid", args.grid.is_some(), Study::EimOperator),
        ("--layers", args.layers.is_some(), Study::EimOperator),
    ] {
        if given && std::mem::discriminant(&args.study) != std::mem::discriminant(&reader) {
            let reader = reader
                .to_possible_value()
                .map(|v| v.get_name().to_string())
                .unwrap_or_default();
            return Err(CliError::Spec(format!(
                "{flag} is read only by the {reader} study, not by {name}: leave it out"
            )));
        }
    }
    let plot = args.plot.as_deref();
    match args.study {
        Study::Eq17 | Study::Displacement | Study::Eq27 => {
            let study = match args.study {
                Study::Eq17 => studies::eq17(),
                Study::Displacement => studies::displacement(),
                _ => studies::eq27(),
            }?;
            if let Some(path) = plot {
                figures::convergence(path, &study)?;
            }
            if args.json {
                println!("{}", study.summary());
            } else {
                print!("{}", study.text());
            }
        }
        Study::TransformTiming => {
            let study = studies::transform_timing()?;
            if let Some(path) = plot {
                figures::transform_timing(path, &study)?;
            }
            println!("{}", study.summary());
        }
        Study::GradedHertz => {
            let study = studies::graded_hertz()?;
            if let Some(path) = plot {
                figures::graded_hertz(path, &study)?;
            }
            if args.json {
                println!("{}", study.summary());
            } else {
                for row in &study.cases {
                    println!("{row}");
                }
            }
        }
        Study::FeComparison => {
            let study = studies::fe_comparison(
                args.datasets
                    .as_deref()
                    .unwrap_or(std::path::Path::new("datasets")),
            )?;
            if let Some(path) = plot {
                figures::fe_comparison(path, &study)?;
            }
            println!("{}", study.summary());
        }
        Study::FrettingLimit => {
            let study = studies::fretting_limit()?;
            if let Some(path) = plot {
                figures::fretting_limit(path, &study)?;
            }
            println!("{}", study.summary());
        }
        Study::GradedWear => {
            let study = studies::graded_wear()?;
            if let Some(path) = plot {
                figures::graded_wear(path, &study)?;
            }
            println!("{}", studies::graded_wear_summary(&study));
        }
        Study::EimOperator => {
            let timing = studies::eim_operator(args.grid.unwrap_or(128), args.layers.unwrap_or(8))
                .map_err(|e| match e {
                    // The one input of this study a user gives besides the grid: its flag named.
                    StudyError::Input(m) if m.starts_with("layers") => {
                        CliError::Spec(format!("--layers: {m}"))
                    }
                    e => e.into(),
                })?;
            if args.json {
                println!("{}", timing.summary());
            } else {
                println!("{}", timing.text());
            }
        }
    }
    Ok(())
}

impl From<StudyError> for CliError {
    fn from(e: StudyError) -> Self {
        match e {
            StudyError::Mdr(e) => CliError::Mdr(e),
            StudyError::Sam(e) => CliError::Sam(e),
            StudyError::Data(e) => CliError::Data(e),
            StudyError::Fretting(e) => CliError::Spec(e.to_string()),
            StudyError::Input(m) => CliError::Spec(m),
        }
    }
}
