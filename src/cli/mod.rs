//! Command-line front end: argument parsing (clap), one module per subcommand.

mod axisym;
mod contact3d;
mod fretting;
mod fretting_loop;
mod fretting_map;
mod fretting_wear3d;
mod study;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Contact mechanics of elastic half-spaces.
#[derive(Debug, Parser)]
#[command(name = "halfspace", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Axisymmetric normal contact by the MDR: contact radius, force, pressure, displacement.
    Axisym(axisym::AxisymArgs),
    /// Fretting wear on the MDR (Willert 2021, Section 4): worn profiles, contact growth.
    FrettingWear(fretting::FrettingArgs),
    /// 3D semi-analytical contact (DC-FFT, Polonsky–Keer, stick–slip with Coulomb friction).
    Contact3d(contact3d::Contact3dArgs),
    /// The fretting loop of Leroux & Nélias (2011): normal ramp, then cyclic tangential shift.
    FrettingLoop(fretting_loop::FrettingLoopArgs),
    /// A fretting map (Vingsbo–Söderberg): the fretting loop over loads × amplitudes, its regime
    /// and dissipated energy; points in parallel, checkpointed, resumable.
    FrettingMap(fretting_map::FrettingMapArgs),
    /// 3D fretting wear on the SAM solver: Archard or energy wear over cycles with cycle jumping,
    /// checkpointed, resumable (docs/wear3d.md).
    FrettingWear3d(fretting_wear3d::FrettingWear3dArgs),
    /// Convergence studies against closed forms (the figures of docs/).
    Study(study::StudyArgs),
}

/// Errors of the CLI. Every one is reported as one line on stderr with exit code 2.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A malformed specification string or option.
    #[error("{0}")]
    Spec(String),
    /// The MDR refused the input.
    #[error(transparent)]
    Mdr(#[from] halfspace::mdr::MdrError),
    /// The 3D contact solvers refused the input or did not converge.
    #[error(transparent)]
    Sam(#[from] halfspace::sam::SamError),
    /// Reading or writing data failed.
    #[error(transparent)]
    Data(#[from] halfspace::data::DataError),
    /// The output directory belongs to another run or process.
    #[error(transparent)]
    RunDir(#[from] halfspace::run_dir::RunDirError),
    /// Plotting failed.
    #[error("plot: {0}")]
    Plot(String),
}

impl From<halfspace::figures::FigureError> for CliError {
    fn from(e: halfspace::figures::FigureError) -> Self {
        match e {
            halfspace::figures::FigureError::Extension(m) => CliError::Spec(m),
            halfspace::figures::FigureError::Draw(m) => CliError::Plot(m),
        }
    }
}

impl From<halfspace::spec::SpecError> for CliError {
    fn from(e: halfspace::spec::SpecError) -> Self {
        CliError::Spec(e.0)
    }
}

/// The largest configuration file read (bytes): a TOML config is a few hundred bytes.
pub const CONFIG_LIMIT: u64 = 16 << 20;

/// A configuration file (unknown keys refused by the type): TOML, or JSON when the file ends in
/// `.json` (the same keys); the defaults without one.
pub fn read_config<T: serde::de::DeserializeOwned + Default>(
    path: Option<&std::path::Path>,
) -> Result<T, CliError> {
    let Some(path) = path else {
        return Ok(T::default());
    };
    let text = halfspace::data::read_text_bounded(path, CONFIG_LIMIT)
        .map_err(|e| CliError::Spec(format!("--config {e}")))?;
    let what = format!("--config {}", path.display());
    let json = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    Ok(if json {
        halfspace::config::from_json(&text, &what)?
    } else {
        halfspace::config::from_toml(&text, &what)?
    })
}

/// The periodic checkpoints of a long run (fretting-wear, fretting-loop, fretting-wear3d): a
/// checkpoint every `--checkpoint-seconds` of work and when the testing hook `--stop-after`
/// stops the run (as if killed); the run stops at the first write that fails.
pub struct Checkpoints<'a> {
    path: &'a std::path::Path,
    every: std::time::Duration,
    last: std::time::Instant,
    /// The write that failed, if one did (the run stopped there).
    pub error: Option<halfspace::data::DataError>,
    /// Whether `--stop-after` stopped the run.
    pub stopped: bool,
}

impl<'a> Checkpoints<'a> {
    /// `--checkpoint-seconds` checked (finite, > 0), before the run claims its directory.
    pub fn interval(seconds: f64) -> Result<std::time::Duration, CliError> {
        if !(seconds.is_finite() && seconds > 0.0) {
            return Err(CliError::Spec(format!(
                "--checkpoint-seconds must be finite and > 0, got {seconds}"
            )));
        }
        std::time::Duration::try_from_secs_f64(seconds).map_err(|_| {
            CliError::Spec(format!(
                "--checkpoint-seconds {seconds} is beyond what a duration can hold"
            ))
        })
    }

    /// Checkpoints written to `path` every `every` of work ([`Self::interval`]).
    pub fn new(path: &'a std::path::Path, every: std::time::Duration) -> Self {
        Self {
            path,
            every,
            last: std::time::Instant::now(),
            error: None,
            stopped: false,
        }
    }

    /// After a step of the run: writes `record()` when a checkpoint is due or `stop` is set;
    /// whether the run stops (`stop`, or a failed write).
    pub fn after_step(
        &mut self,
        stop: bool,
        record: impl FnOnce() -> halfspace::data::Record,
    ) -> bool {
        if stop || self.last.elapsed() >= self.every {
            if let Err(e) = halfspace::data::write_record(self.path, &record()) {
                self.error = Some(e);
                return true;
            }
            self.last = std::time::Instant::now();
        }
        self.stopped = stop;
        stop
    }

    /// The first failed write as the run's error.
    pub fn check(&mut self) -> Result<(), CliError> {
        match self.error.take() {
            Some(e) => Err(e.into()),
            None => Ok(()),
        }
    }
}

/// An observer's answer: stop or go on.
pub fn flow(stop: bool) -> std::ops::ControlFlow<()> {
    if stop {
        std::ops::ControlFlow::Break(())
    } else {
        std::ops::ControlFlow::Continue(())
    }
}

/// The library's errors name parameters, not flags (the Python package shows them too); on the
/// command line each remedy is followed by the flag that applies it — only flags the command has.
fn with_flag_hints(message: &str, flags: &[&str]) -> String {
    const HINTS: [(&str, &str); 6] = [
        ("the MVM backend", "--method mvm"),
        ("the FFT backend", "--method fft"),
        ("time step dtau", "--dtau"),
        ("domain length L", "--length"),
        ("the domain extent", "--extent"),
        ("subsurface depth", "--subsurface"),
    ];
    let mut out = message.to_string();
    for (phrase, flag) in HINTS {
        let name = flag.split_whitespace().next().unwrap_or(flag);
        if !flags.contains(&name) {
            continue;
        }
        if let Some(at) = out.find(phrase) {
            let end = at + phrase.len();
            out.insert_str(end, &format!(" ({flag})"));
        }
    }
    out
}

pub fn run() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // clap prints help/version to stdout (exit 0); a usage error is one line on stderr
            // (exit 2), like every other refusal.
            if e.use_stderr() {
                let text = e.render().to_string();
                let line: Vec<&str> = text
                    .lines()
                    .map(str::trim)
                    .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more"))
                    .filter(|l| !l.is_empty())
                    .collect();
                eprintln!("{}", line.join(" "));
            } else {
                let _ = e.print();
            }
            return ExitCode::from(e.exit_code() as u8);
        }
    };
    let flags: &[&str] = match &cli.command {
        Command::Axisym(_) => &["--method"],
        Command::FrettingWear(_) => &["--method", "--dtau", "--length"],
        Command::Contact3d(_) => &["--extent", "--subsurface"],
        Command::FrettingLoop(_) | Command::FrettingMap(_) | Command::FrettingWear3d(_) => &[],
        Command::Study(_) => &["--method", "--dtau", "--length", "--extent"],
    };
    let result = match cli.command {
        Command::Axisym(args) => axisym::run(args),
        Command::Study(args) => study::run(args),
        Command::FrettingWear(args) => fretting::run(args),
        Command::Contact3d(args) => contact3d::run(args),
        Command::FrettingLoop(args) => fretting_loop::run_loop(args),
        Command::FrettingMap(args) => fretting_map::run(args),
        Command::FrettingWear3d(args) => fretting_wear3d::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", with_flag_hints(&e.to_string(), flags));
            ExitCode::from(2)
        }
    }
}
