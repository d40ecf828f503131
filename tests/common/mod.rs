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

/// Every array of two results files equal bit for bit (a resumed run against an uninterrupted one).
pub fn arrays_equal(a: &std::path::Path, b: &std::path::Path) {
    let (ra, rb) = (
        halfspace::data::read_record(a).unwrap(),
        halfspace::data::read_record(b).unwrap(),
    );
    assert_eq!(ra.arrays.len(), rb.arrays.len());
    for (name, values) in &ra.arrays {
        let other = rb.get(name).unwrap_or_else(|| panic!("{name} missing"));
        // Bit for bit.
        assert!(
            values
                .iter()
                .zip(other)
                .all(|(x, y)| x.to_bits() == y.to_bits()),
            "{name} differs"
        );
    }
}
