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

/// Asserts that `path` is a non-empty SVG document (`<svg` … `</svg>`, its tags well nested, no
/// bare `&`) whose text holds every one of `labels` (axis labels, titles).
pub fn svg_with_labels(path: &std::path::Path, labels: &[&str]) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let body = text.trim();
    assert!(body.starts_with("<svg"), "{}: not an SVG", path.display());
    assert!(body.ends_with("</svg>"), "{}: unterminated", path.display());
    // Well-formedness of the element structure: every tag closed in order.
    let mut open: Vec<String> = Vec::new();
    let mut rest = body;
    while let Some(start) = rest.find('<') {
        let end = rest[start..]
            .find('>')
            .unwrap_or_else(|| panic!("{}: unclosed tag", path.display()))
            + start;
        let tag = &rest[start + 1..end];
        assert!(!tag.contains('<'), "{}: '<' inside a tag", path.display());
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(
                open.pop().as_deref(),
                Some(name.trim()),
                "{}",
                path.display()
            );
        } else if !(tag.starts_with('?') || tag.starts_with('!') || tag.ends_with('/')) {
            let name = tag.split_whitespace().next().unwrap_or("");
            open.push(name.to_string());
        }
        rest = &rest[end + 1..];
    }
    assert!(open.is_empty(), "{}: unclosed {open:?}", path.display());
    for (k, _) in body.match_indices('&') {
        let entity = &body[k..body.len().min(k + 12)];
        assert!(
            entity.contains(';'),
            "{}: bare '&' at {k}: {entity:?}",
            path.display()
        );
    }
    for label in labels {
        assert!(
            body.contains(label),
            "{}: lacks the label {label:?}",
            path.display()
        );
    }
}
