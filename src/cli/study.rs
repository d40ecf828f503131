//! `halfspace study`: convergence studies against closed forms (the docs' figures).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use halfspace::mdr::{studies, Backend, DisplacementMethod};
use serde_json::json;

use super::{plot, CliError};

/// Named error series of one study.
type Series = Vec<(&'static str, Vec<f64>)>;

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum Study {
    /// Eq. 17 on the Eq. 18 pair q = 1 − x⁴: mean relative error (Eq. 19) against N.
    Eq17,
    /// Eqs. 12 and 13 on Hertz (spec §2 test 2): max error against N.
    Displacement,
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
}

pub fn run(args: StudyArgs) -> Result<(), CliError> {
    let (title, ns, series): (&str, Vec<usize>, Series) = match args.study {
        Study::Eq17 => {
            let ns = vec![11, 101, 1001, 2001, 10001, 100001];
            let e: Result<Vec<f64>, _> = ns
                .iter()
                .map(|&n| studies::stress_transform_error(n, Backend::Fft))
                .collect();
            (
                "Eq. 17 on q = 1 − x⁴: mean relative error ε (Eq. 19)",
                ns,
                vec![("Eq. 17 (FFT)", e?)],
            )
        }
        Study::Displacement => {
            let ns = vec![101, 301, 1001, 4001, 10001];
            let mut series = Vec::new();
            for (name, method) in [
                ("Eq. 12 (arccos kernel)", DisplacementMethod::DenseKernel),
                (
                    "Eq. 13 (FFT, parabolic split)",
                    DisplacementMethod::Convolution(Backend::Fft),
                ),
            ] {
                let e: Result<Vec<f64>, _> = ns
                    .iter()
                    .map(|&n| studies::displacement_hertz_error(n, method))
                    .collect();
                series.push((name, e?));
            }
            ("Hertz displacement (a = 0.7, L = 1): max error", ns, series)
        }
    };
    let orders: Vec<f64> = series
        .iter()
        .map(|(_, e)| studies::observed_order(&ns, e))
        .collect();
    if let Some(path) = &args.plot {
        plot::convergence(path, title, &ns, &series)
            .map_err(|e| CliError::Plot(format!("{}: {e}", path.display())))?;
    }
    if args.json {
        let s: Vec<_> = series
            .iter()
            .zip(&orders)
            .map(|((name, e), order)| json!({"name": name, "errors": e, "observed_order": order}))
            .collect();
        println!("{}", json!({"study": title, "n": ns, "series": s}));
    } else {
        println!("{title}");
        for ((name, e), order) in series.iter().zip(&orders) {
            println!("{name}: observed order {order:.3}");
            for (n, err) in ns.iter().zip(e) {
                println!("  N = {n:>7}  {err:.3e}");
            }
        }
    }
    Ok(())
}
