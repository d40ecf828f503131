//! Helpers of the CLI tests: run the binary, read its JSON, expect exit 2.
#![allow(dead_code)]

use std::process::{Command, Output};

/// Runs `halfspace ARGS`.
pub fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_halfspace"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// The one JSON object a successful `--json` run prints.
pub fn ok_json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "exit {:?}: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object on stdout")
}

/// Expects exit code 2 with `needle` on stderr.
pub fn bad(args: &[&str], needle: &str) {
    let out = run(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(err.contains(needle), "{args:?}: {err:?} lacks {needle:?}");
}
