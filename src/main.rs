//! The `halfspace` command line. Subcommands live in `cli/`; each parses, calls a crate and
//! writes. Exit code 0 on success, 2 on bad input (one line on stderr naming the bad value).
use std::process::ExitCode;

mod cli;

fn main() -> ExitCode {
    cli::run()
}
