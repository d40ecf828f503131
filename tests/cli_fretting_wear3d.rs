//! `halfspace fretting-wear3d` through the binary (docs/wear3d.md#the-command).

mod common;

use common::{
    arrays_equal, bad, ok_json, resumed_to_the_end, run, run_owned, stopped_and_resumed,
    svg_with_labels,
};

/// The MDR twin of docs/wear3d.md (identical bodies, ν = 0, fixed approach, χ = 0.5) on 16²,
/// N₀ = 1000 cycles, to τ = 1.
const TWIN: &str = "radius = 105e-6\ne = 210e9\nnu = 0.0\nfriction = 0.3\n\
normal_steps = 1\namplitude = 1.5e-8\nshift_step = 1.5e-8\ngrid = 16\nextent_over_a = 3.2\n\
approach = 1e-7\nindenter_e = 210e9\nindenter_nu = 0.0\n\
[wear]\nlaw = \"archard\"\ncoefficient = 1.5430335e-12\nbody = \"gap\"\ncycles = 1000\n\
record_cycles = [100]\n";

/// `fretting-wear3d --config cfg --out out extra…`.
fn wear3d_args(cfg: &std::path::Path, out: &std::path::Path, extra: &[&str]) -> Vec<String> {
    let mut v = vec![
        "fretting-wear3d".to_string(),
        "--config".into(),
        cfg.to_str().unwrap().into(),
        "--out".into(),
        out.to_str().unwrap().into(),
    ];
    v.extend(extra.iter().map(|s| s.to_string()));
    v
}

/// A run's JSON keys, results and figures; a run stopped twice and resumed ends bit for bit where the
/// uninterrupted run ends; a re-run into a directory holding a checkpoint is refused.
#[test]
fn wear3d_runs_and_resumes_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("wear.toml");
    std::fs::write(&cfg, TWIN).unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let args = |out: &std::path::Path, extra: &[&str]| wear3d_args(&cfg, out, extra);
    // Stopped after two wear steps, then after three: the resumed run ends bit for bit where the
    // uninterrupted one ends.
    let (full, resumed) =
        stopped_and_resumed(args, (&a, &b), &["2", "3"], Some("checkpoint.npz"), |_| {});
    for key in [
        "cycles",
        "wear_steps",
        "wear_volume",
        "max_wear_depth",
        "contact_radius",
        "stick_radius",
        "dissipated_energy_total",
        "seconds",
    ] {
        assert!(full[key].is_number(), "{key}: {full}");
    }
    assert_eq!(full["cycles"], 1000);
    assert!(full["wear_volume"].as_f64().unwrap() > 0.0);
    // The figures (docs/wear3d.md#figures).
    for (name, labels) in [
        (
            "wear_depth_map.svg",
            &["x (μm)", "y (μm)", "worn depth h (μm)", "N = 1000"][..],
        ),
        (
            "wear_depth_profiles.svg",
            &[
                "x (μm) left, y (μm) right",
                "worn depth h (μm)",
                "N = 100",
                "N = 1000",
            ],
        ),
        (
            "wear_volume.svg",
            &["cycles N", "wear volume (μm³)", "largest worn depth (μm)"],
        ),
    ] {
        svg_with_labels(&a.join(name), labels);
    }
    assert_eq!(full["wear_volume"], resumed["wear_volume"]);
    assert!(!b.join("checkpoint.npz").exists());
}

/// With an inhomogeneity (a stiff sphere under the contact edge, the indenter wearing, 2 shift
/// steps per quarter) the checkpoint carries the cycle predictor's store
/// (docs/wear3d.md#the-cycle-predictor): a run stopped after four wear steps (both cycles of the
/// store filled) and resumed ends bit for bit where the uninterrupted run ends; the JSON counts
/// the outer passes and EIM applications.
#[test]
fn wear3d_with_an_inhomogeneity_resumes_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("wear.toml");
    let config = TWIN
        .replace("shift_step = 1.5e-8", "shift_step = 0.75e-8")
        .replace("body = \"gap\"", "body = \"indenter\"")
        + "[[inhomogeneity]]\nkind = \"sphere\"\nx = 1.62e-6\ny = 0.0\nz = 1.62e-6\n\
           r = 0.97e-6\nE = 420e9\nnu = 0.0\n";
    std::fs::write(&cfg, config).unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let args = |out: &std::path::Path, extra: &[&str]| {
        wear3d_args(&cfg, out, &[&["--no-animation"], extra].concat())
    };
    let (full, resumed) =
        stopped_and_resumed(args, (&a, &b), &["4"], Some("checkpoint.npz"), |_| {});
    assert!(full["wear_steps"].as_u64().unwrap() >= 6, "{full}");
    assert!(full["outer_passes"].as_u64().unwrap() > 0, "{full}");
    assert!(full["eim_applications"].as_u64().unwrap() > 0, "{full}");
    assert_eq!(full["wear_volume"], resumed["wear_volume"]);
}

/// Bad configurations are refused with the key named.
#[test]
fn wear3d_refuses_bad_configs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    for (text, needle) in [
        (TWIN.replace("[wear]\n", "[weer]\n"), "[wear]"),
        (
            TWIN.replace("law = \"archard\"", "law = \"hard\""),
            "wear law",
        ),
        (TWIN.replace("cycles = 1000", "cycles = 0"), "cycles"),
        (
            TWIN.replace("coefficient = 1.5430335e-12", "coefficient = -1"),
            "coefficient",
        ),
        (
            TWIN.replace("body = \"gap\"", "body = \"both\""),
            "wear body",
        ),
        (
            TWIN.replace("approach = 1e-7", "approach = \"x\""),
            "approach",
        ),
        (format!("{TWIN}colour = 1\n"), "colour"),
    ] {
        let cfg = dir.path().join("bad.toml");
        std::fs::write(&cfg, text).unwrap();
        bad(
            &[
                "fretting-wear3d",
                "--config",
                cfg.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            needle,
        );
    }
}

/// A run killed by SIGKILL while it works (not stopped politely: no `--stop-after`) and resumed
/// ends bit for bit where the uninterrupted run ends (docs/wear3d.md#checkpoint-and-resume): the
/// checkpoint is written atomically and the stale run.lock of the killed process is taken over.
#[test]
fn wear3d_killed_by_sigkill_resumes_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("wear.toml");
    // The twin at 32² to τ = 3 (≈ 80 wear steps): long enough to be killed midway.
    let text = TWIN
        .replace("grid = 16", "grid = 32")
        .replace("cycles = 1000", "cycles = 3000");
    std::fs::write(&cfg, text).unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let args = |out: &std::path::Path, extra: &[&str]| wear3d_args(&cfg, out, extra);
    let full = ok_json(&run_owned(&args(&a, &["--json"])));
    let mut killed = 0;
    // Kill as soon as a checkpoint exists; retry with a resumed run until one is killed midway
    // (a fast machine may finish first: then the run is complete and nothing is to resume).
    for attempt in 0..20 {
        let resume: &[&str] = if attempt > 0 { &["--resume"] } else { &[] };
        let flags = [&["--json", "--checkpoint-seconds", "0.05"], resume].concat();
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_halfspace"))
            .args(args(&b, &flags))
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let start = std::time::Instant::now();
        while !b.join("checkpoint.npz").is_file() && start.elapsed().as_secs_f64() < 30.0 {
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        std::thread::sleep(std::time::Duration::from_millis(20 * (attempt as u64 + 1)));
        child.kill().unwrap(); // SIGKILL on Unix
        let status = child.wait().unwrap();
        if !status.success() {
            killed += 1;
        }
        if b.join("results.h5").is_file() || killed >= 2 {
            break;
        }
    }
    assert!(killed >= 1, "no run was killed midway");
    if b.join("results.h5").is_file() {
        // A resumed attempt ran to its end before its kill.
        arrays_equal(&a.join("results.h5"), &b.join("results.h5"));
    } else {
        let resumed = resumed_to_the_end(args, (&a, &b));
        assert_eq!(full["wear_volume"], resumed["wear_volume"]);
        assert_eq!(full["wear_steps"], resumed["wear_steps"]);
    }
}

/// `--estimate` runs nothing and writes nothing; its numbers are the rule of
/// docs/wear3d.md#the-work-estimate by hand for the twin: `p₀ = 2E*a/(πR) = 2.062 GPa`
/// (`E* = 105 GPa`, `a = √(Rδ) = 3.240 μm`), `k p₀ 4A = 1.909e-10 m` per cycle,
/// `ΔN₁ = ⌊0.01 · 0.1 μm / 1.909e-10 m⌋ = ⌊5.24⌋ = 5` (accuracy binds: the stability bound is
/// larger), `1 + ⌈100/5⌉ + ⌈900/5⌉ = 201` steps, `n + q + 201 · 4q = 806` increments (n = q = 1);
/// and it errs towards more steps: the run computes 13 (docs/wear3d.md, measured ratio 15).
#[test]
fn wear3d_estimate_counts_the_computed_cycles_before_running() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("wear.toml");
    std::fs::write(&cfg, TWIN).unwrap();
    let out = dir.path().join("w");
    let go = |extra: &[&str]| {
        let mut v = vec![
            "fretting-wear3d",
            "--config",
            cfg.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--json",
        ];
        v.extend_from_slice(extra);
        ok_json(&run(&v))
    };
    let e = go(&["--estimate"]);
    assert!(!out.exists(), "--estimate writes nothing");
    assert_eq!(e["cycles"], 1000);
    assert_eq!(e["first_delta_cycles"], 5.0);
    assert_eq!(e["wear_steps"], 201.0);
    assert_eq!(e["computed_cycles"], 201.0);
    assert_eq!(e["increments_per_cycle"], 4.0);
    assert_eq!(e["increments"], 806.0);
    assert_eq!(e["cells"], 256.0);
    assert!(e["bytes"].as_f64().unwrap() > 0.0 && e["hours"].as_f64().unwrap() > 0.0);
    let done = go(&[]);
    let steps = done["wear_steps"].as_u64().unwrap();
    assert!(steps as f64 <= 201.0, "the run computed {steps} steps");
    assert_eq!(done["cycles"], 1000);
}
