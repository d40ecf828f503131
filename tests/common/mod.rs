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

/// `halfspace ARGS` from owned arguments.
pub fn run_owned(args: &[String]) -> Output {
    run(&args.iter().map(String::as_str).collect::<Vec<_>>())
}

/// [`bad`] with owned arguments.
pub fn bad_owned(args: &[String], needle: &str) {
    bad(&args.iter().map(String::as_str).collect::<Vec<_>>(), needle);
}

/// The resume check of a command: `command(out, extra)` is its arguments writing to `out` with
/// the flags `extra`. The run into `whole` (`--json`) uninterrupted; the run into `parts` stopped
/// after `stops[0]` steps (`--stop-after`), leaving no results (and the file `checkpoint`, when
/// given); a re-run into `parts` without `--resume` refused (exit 2, naming `--resume`); then
/// `between(parts)`; resumed and stopped after each further count of `stops`; resumed to its end
/// (`--resume --json`): every array of the two `results.h5` bit for bit. Returns the JSON of the
/// uninterrupted and of the resumed run.
pub fn stopped_and_resumed(
    command: impl Fn(&std::path::Path, &[&str]) -> Vec<String>,
    (whole, parts): (&std::path::Path, &std::path::Path),
    stops: &[&str],
    checkpoint: Option<&str>,
    between: impl FnOnce(&std::path::Path),
) -> (serde_json::Value, serde_json::Value) {
    let full = ok_json(&run_owned(&command(whole, &["--json"])));
    let mut between = Some(between);
    for (k, stop) in stops.iter().enumerate() {
        let flags: &[&str] = if k == 0 {
            &["--stop-after", stop]
        } else {
            &["--resume", "--stop-after", stop]
        };
        let out = run_owned(&command(parts, flags));
        assert!(
            out.status.success(),
            "stopped after {stop}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(!parts.join("results.h5").exists());
        if let Some(name) = checkpoint {
            assert!(parts.join(name).is_file(), "no {name} after {stop} steps");
        }
        if k == 0 {
            bad_owned(&command(parts, &[]), "--resume continues it");
            if let Some(between) = between.take() {
                between(parts);
            }
        }
    }
    let resumed = resumed_to_the_end(&command, (whole, parts));
    (full, resumed)
}

/// The end of a resume check: the interrupted run in `parts` resumed to its end (`--resume
/// --json`, `command` as in [`stopped_and_resumed`]) holds every array of the uninterrupted run's
/// `results.h5` in `whole` bit for bit; returns the resumed run's JSON.
pub fn resumed_to_the_end(
    command: impl Fn(&std::path::Path, &[&str]) -> Vec<String>,
    (whole, parts): (&std::path::Path, &std::path::Path),
) -> serde_json::Value {
    let resumed = ok_json(&run_owned(&command(parts, &["--resume", "--json"])));
    arrays_equal(&whole.join("results.h5"), &parts.join("results.h5"));
    resumed
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
