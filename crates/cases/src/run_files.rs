//! The names of a run directory's files that the application layer reads as well as the command
//! line's `run_dir` (which owns the directory): a front end that continues a run from its
//! directory (Python's `fretting_wear(resume=)`) reads them without claiming it.

/// A run directory's manifest: the command, its parameters, whether it completed, its files
/// (`halfspace::run_dir`).
pub const MANIFEST: &str = "run.json";
