//! `halfspace fretting-wear` through the binary: the default (reference) run, outputs, resume after
//! a simulated kill (bit for bit), configs and bad input.

mod common;

use std::path::Path;

use common::{arrays_equal, bad, bad_owned, ok_json, run, stopped_and_resumed};

use halfspace::data::{read_record, write_record, AttrValue};

#[test]
fn default_run_is_the_reference_run_and_writes_everything() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("run");
    let o = out_dir.to_str().unwrap();
    let v = ok_json(&run(&["fretting-wear", "--out", o, "--json"]));
    for key in [
        "tau_final",
        "steps",
        "contact_radius_over_a0",
        "loaded_radius_over_a0",
        "profile_at_a0_over_d",
        "limit_contact_radius_over_a0",
        "seconds",
        "method",
        "n",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["tau_final"].as_f64().unwrap(), 30.0);
    assert_eq!(v["n"], 2001);
    // The adaptive scheme that took the steps (as results and checkpoints record it).
    assert_eq!(v["adaptive_scheme"], halfspace::fretting::ADAPTIVE_SCHEME);
    assert_eq!(v["method"], "fft");
    // By τ = 30 the run is at Popov's limit: a/a0 (the touching region) = 1.13947 against
    // r*/a0 = 1.13970 (one cell is 5.6e-4), f(a0)/d = 0.59109 (f∞(a0) = 0.590845); the loaded
    // radius is the stick radius √0.5 (the annulus carries no pressure). Adaptive steps:
    // 670 against explicit Euler's 30 000 (docs/fretting-wear.md, "Time integration").
    let a = v["contact_radius_over_a0"].as_f64().unwrap();
    assert!((a - 1.13970).abs() < 5.6e-4, "a/a0 = {a}");
    let stick = 0.5f64.sqrt();
    assert!((v["loaded_radius_over_a0"].as_f64().unwrap() - stick).abs() < 2e-3);
    assert!(v["steps"].as_u64().unwrap() <= 3000);
    assert_eq!(v["stepping"], "adaptive");
    assert!((v["profile_at_a0_over_d"].as_f64().unwrap() / 0.590845 - 1.0).abs() < 1e-3);
    assert!((v["limit_contact_radius_over_a0"].as_f64().unwrap() - 1.1397).abs() < 1e-4);
    let ratio = v["wear_volume"].as_f64().unwrap() / v["limit_wear_volume"].as_f64().unwrap();
    assert!((1.0..1.01).contains(&ratio), "V/V∞ = {ratio}");
    for f in [
        "results.h5",
        "results.npz",
        "worn_profiles.png",
        "worn_profiles.svg",
        "checkpoint.npz",
    ] {
        assert!(out_dir.join(f).is_file(), "{f} missing");
    }
    let png = std::fs::read(out_dir.join("worn_profiles.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let rec = read_record(&out_dir.join("results.h5")).unwrap();
    assert_eq!(
        rec.get("snapshot_tau").unwrap(),
        &[0.1, 1.0, 3.0, 10.0, 30.0]
    );
    for k in 0..5 {
        assert_eq!(rec.get(&format!("f_{k}")).unwrap().len(), 2001);
    }
    // Another run's results are not overwritten without --force.
    bad(&["fretting-wear", "--out", o], "--resume");
    let v = ok_json(&run(&[
        "fretting-wear",
        "--out",
        o,
        "--force",
        "--tau-end",
        "0.2",
        "--dtau",
        "1e-3",
        "--json",
    ]));
    assert_eq!(v["steps"], 200);
}

/// `fretting-wear --out out` with the flags `common`, then `extra`.
fn fretting_wear(out: &Path, common: &[&str], extra: &[&str]) -> Vec<String> {
    let mut v = vec!["fretting-wear".to_string(), "--out".into()];
    v.push(out.to_str().unwrap().into());
    v.extend(common.iter().chain(extra).map(|s| s.to_string()));
    v
}

/// The checkpoint's text attribute `name` (the build's scheme, `recorded`) taken out, then set to
/// `other`: each time `resume` is refused with every one of `needles`; then the intact checkpoint
/// is put back.
fn checkpoint_scheme_is_checked(
    checkpoint: &Path,
    (name, recorded, other): (&str, &str, &str),
    resume: &[String],
    needles: &[&str],
) {
    let original = read_record(checkpoint).unwrap();
    assert_eq!(
        original.get_attr(name),
        Some(&AttrValue::Text(recorded.into()))
    );
    for other in [None, Some(other)] {
        let mut rec = original.clone();
        match other {
            None => rec.attributes.retain(|(n, _)| n != name),
            Some(value) => {
                for (n, v) in rec.attributes.iter_mut() {
                    if n == name {
                        *v = AttrValue::Text(value.into());
                    }
                }
            }
        }
        write_record(checkpoint, &rec).unwrap();
        for needle in needles {
            bad_owned(resume, needle);
        }
    }
    write_record(checkpoint, &original).unwrap();
}

/// A fixed-step run stopped after 137 steps (only the checkpoint is there, as after a kill) and
/// resumed gives the uninterrupted run's results bit for bit ([`stopped_and_resumed`]); in
/// between, a resume with other parameters is refused naming the parameter, and one from a
/// checkpoint without the fixed-step ROS2 path (`fixed_scheme`, made before the rate's shorter
/// plans, whose rounding this build would not repeat) or of another path, naming the attribute;
/// `--resume` without a checkpoint is refused.
#[test]
fn resume_after_a_kill_gives_the_same_results_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let common = ["--n", "401", "--dtau", "4e-3", "--tau-end", "2"];
    let command = |out: &Path, extra: &[&str]| fretting_wear(out, &common, extra);
    let between = |b: &Path| {
        bad_owned(&command(b, &["--resume", "--chi", "0.4"]), "chi");
        checkpoint_scheme_is_checked(
            &b.join("checkpoint.npz"),
            (
                "fixed_scheme",
                halfspace::fretting::FIXED_STEP_SCHEME,
                "ros2-fixed",
            ),
            &command(b, &["--resume", "--json"]),
            &["fixed_scheme"],
        );
    };
    let (_, v) = stopped_and_resumed(command, (&a, &b), &["137"], Some("checkpoint.npz"), between);
    assert_eq!(v["steps"], 500);
    arrays_equal(&a.join("results.npz"), &b.join("results.npz"));
    // --resume without a checkpoint.
    let empty = dir.path().join("empty");
    bad(
        &[
            "fretting-wear",
            "--out",
            empty.to_str().unwrap(),
            "--resume",
        ],
        "checkpoint",
    );
}

/// An adaptive run's checkpoint records the adaptive scheme (`adaptive_scheme`,
/// `halfspace_fretting::ADAPTIVE_SCHEME`): one without it (made by the scheme before the hole
/// projection, whose steps this build would not repeat) or of another scheme is refused, naming
/// the attribute and saying that only `--force` (starting over) helps, and so is a manifest
/// (`run.json`) of another scheme; the intact one resumes to the uninterrupted run's results bit
/// for bit ([`stopped_and_resumed`], stopped after 30 steps).
#[test]
fn adaptive_checkpoints_record_the_scheme() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let common = ["--n", "401", "--tau-end", "0.5"];
    let command = |out: &Path, extra: &[&str]| fretting_wear(out, &common, extra);
    let between = |b: &Path| {
        let resume = command(b, &["--resume", "--json"]);
        checkpoint_scheme_is_checked(
            &b.join("checkpoint.npz"),
            (
                "adaptive_scheme",
                halfspace::fretting::ADAPTIVE_SCHEME,
                "ros2",
            ),
            &resume,
            &[
                "adaptive_scheme",
                "another build's adaptive scheme",
                "cannot resume it bit for bit: only starting the run over helps",
                "(--force starts over)",
            ],
        );
        // The manifest of a run of another scheme (or of none recorded) is refused the same
        // way, before the run directory's check (which would ask for parameters no flag sets).
        manifest_scheme_is_checked(
            &b.join("run.json"),
            ("adaptive_scheme", "ros2-hole-projection"),
            &resume,
            &["another build's adaptive scheme", "--force starts over"],
        );
    };
    stopped_and_resumed(command, (&a, &b), &["30"], Some("checkpoint.npz"), between);
    arrays_equal(&a.join("results.npz"), &b.join("results.npz"));
}

/// A run directory whose manifest (`run.json`) records no `key` or the `other` value is refused on
/// `resume` with every one of `messages`; the intact manifest is restored after.
fn manifest_scheme_is_checked(
    manifest: &Path,
    (key, other): (&str, &str),
    resume: &[String],
    messages: &[&str],
) {
    let intact = std::fs::read_to_string(manifest).unwrap();
    for replacement in [None, Some(other)] {
        let mut m: serde_json::Value = serde_json::from_str(&intact).unwrap();
        let parameters = m["parameters"].as_object_mut().unwrap();
        match replacement {
            None => {
                parameters.remove(key);
            }
            Some(name) => {
                parameters.insert(key.into(), serde_json::json!(name));
            }
        }
        std::fs::write(manifest, m.to_string()).unwrap();
        for message in messages {
            bad_owned(resume, message);
        }
    }
    std::fs::write(manifest, intact).unwrap();
}

#[test]
fn configs_and_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("run.toml");
    std::fs::write(
        &cfg,
        "chi = 0.3\nn = 401\ndtau = 4e-3\ntau_end = 0.4\nsnapshots = [0.2]\nmethod = \"mvm\"\n",
    )
    .unwrap();
    let out = dir.path().join("cfg");
    let v = ok_json(&run(&[
        "fretting-wear",
        "--config",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]));
    assert_eq!(v["chi"], 0.3);
    assert_eq!(v["method"], "mvm");
    assert_eq!(v["n"], 401);
    // A fixed step (`dtau`) records no adaptive scheme.
    assert!(v.get("adaptive_scheme").is_none(), "{v}");
    // Flags override the config.
    let out2 = dir.path().join("cfg2");
    let v = ok_json(&run(&[
        "fretting-wear",
        "--config",
        cfg.to_str().unwrap(),
        "--chi",
        "0.6",
        "--method",
        "fft",
        "--out",
        out2.to_str().unwrap(),
        "--json",
    ]));
    assert_eq!(v["chi"], 0.6);
    assert_eq!(v["method"], "fft");
    // Unknown key, unreadable file, bad values.
    let bad_cfg = dir.path().join("bad.toml");
    std::fs::write(&bad_cfg, "chi = 0.3\nfrobnicate = 1\n").unwrap();
    let o = dir.path().join("x");
    let o = o.to_str().unwrap();
    bad(
        &[
            "fretting-wear",
            "--config",
            bad_cfg.to_str().unwrap(),
            "--out",
            o,
        ],
        "frobnicate",
    );
    bad(
        &["fretting-wear", "--config", "/nonexistent.toml", "--out", o],
        "nonexistent.toml",
    );
    std::fs::write(&bad_cfg, "chi = \"half\"\n").unwrap();
    bad(
        &[
            "fretting-wear",
            "--config",
            bad_cfg.to_str().unwrap(),
            "--out",
            o,
        ],
        "--config",
    );
    bad(&["fretting-wear", "--chi", "1.2", "--out", o], "chi");
    bad(&["fretting-wear", "--chi", "0", "--out", o], "chi");
    bad(&["fretting-wear", "--dtau", "0", "--out", o], "dtau");
    bad(&["fretting-wear", "--tol", "0", "--out", o], "tol");
    bad(
        &[
            "fretting-wear",
            "--tol",
            "1e-4",
            "--dtau",
            "1e-3",
            "--out",
            o,
        ],
        "not both",
    );
}

#[test]
fn graded_runs_report_k_the_wear_volume_and_the_tangential_constant() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let common = [
        "--n",
        "501",
        "--dtau",
        "0.002",
        "--tau-end",
        "2",
        "--chi",
        "0.5",
    ];
    let graded = |m: &str, name: &str| {
        let o = out(name);
        let mut args = vec!["fretting-wear", "--material", m, "--out", &o, "--json"];
        args.extend(common);
        ok_json(&run(&args))
    };
    let k05 = graded("graded:k=0.5,nu=0.3", "k05");
    assert_eq!(k05["k"], 0.5);
    assert_eq!(k05["nu"], 0.3);
    // c_T/c_N from the P–SV integration (docs/fretting-wear.md table: 0.474486 at k = 0.5, ν = 0.3).
    assert!((k05["tangential_constant_ratio"].as_f64().unwrap() - 0.474486).abs() < 1e-6);
    let (v, v_inf) = (
        k05["wear_volume"].as_f64().unwrap(),
        k05["limit_wear_volume"].as_f64().unwrap(),
    );
    assert!(v > 0.0 && v < v_inf, "V {v} V∞ {v_inf}");
    // r*(χ = 0.5, k = 0.5) of the quadrature fixture.
    assert!((k05["limit_contact_radius_over_a0"].as_f64().unwrap() - 1.0657470764).abs() < 1e-9);
    // k = 0 is the homogeneous run bit for bit (also named as a material).
    let k0 = graded("graded:k=0,nu=0.3", "k0");
    let o = out("plain");
    let mut args = vec!["fretting-wear", "--out", &o, "--json"];
    args.extend(common);
    let plain = ok_json(&run(&args));
    assert_eq!(k0["wear_volume"], plain["wear_volume"]);
    assert_eq!(plain["k"], 0.0);
    arrays_equal(
        &dir.path().join("k0/results.h5"),
        &dir.path().join("plain/results.h5"),
    );
    // Homogeneous: c_T/c_N = G*/E* = 2(1 − ν)/(2 − ν).
    assert!((k0["tangential_constant_ratio"].as_f64().unwrap() - 1.4 / 1.7).abs() < 1e-15);
}

#[test]
fn bad_media_exit_2_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("bad");
    let o = o.to_str().unwrap();
    for (m, needle) in [
        ("graded:k=1.2,nu=0.3", "k = 1.2 must be in (−1, 1)"),
        ("graded:k=-1,nu=0.3", "must be in (−1, 1)"),
        ("graded:k=0.5,nu=0.7", "nu = 0.7 must be in (−1, 0.5]"),
        ("graded:k=0.5,nu=-1", "must be in (−1, 0.5]"),
        ("graded:k=0.5", "missing key 'nu'"),
        ("graded:k=0.5,nu=0.3,E0=1", "E0 and z0 go together"),
        (
            "graded:k=0.5,nu=0.3,E0=1,z0=-1",
            "z0 must be finite and > 0",
        ),
        ("homogeneous:Estar=1e9", "Estar is not used"),
        ("graded:k=0.5,nu=0.3,E=1", "unknown key 'E'"),
        ("foam:k=0.5", "unknown medium 'foam'"),
    ] {
        bad(&["fretting-wear", "--material", m, "--out", o], needle);
    }
    // A domain too small for the graded contact's growth.
    bad(
        &[
            "fretting-wear",
            "--material",
            "graded:k=-0.5,nu=0.3",
            "--chi",
            "0.9",
            "--length",
            "1.5",
            "--out",
            o,
        ],
        "the contact grows to r* = 1.5501",
    );
}

#[test]
fn the_fretting_limit_study_reaches_every_limit_from_below() {
    // `halfspace study fretting-limit` (docs/fretting-wear.md, "Approach to the limiting contact
    // radius"): χ = 0.3, 0.5, 0.9, N = 2001, adaptive steps, τ ≤ 5.
    let dir = tempfile::tempdir().unwrap();
    let plot = dir.path().join("limit.svg");
    let v = ok_json(&run(&[
        "study",
        "fretting-limit",
        "--plot",
        plot.to_str().unwrap(),
    ]));
    let cases = v["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 3);
    let mut previous = 0.0;
    for c in cases {
        let (top, r_star) = (c["max_a"].as_f64().unwrap(), c["r_star"].as_f64().unwrap());
        // The touching region reaches r* within a cell or two (one cell 5.6e-4 at r* = 1.14).
        assert!((top - r_star).abs() < 1.5e-3, "{c}");
        // 95 % of the final volume by τ = 1.47, 1.97, 2.94 (the independent solver: 0.949 V∞ at
        // τ = 2 for χ = 0.5); wider amplitudes take longer.
        let t95 = c["tau_95_volume"].as_f64().unwrap();
        assert!(t95 > previous && t95 < 3.5, "{c}");
        previous = t95;
        let ratio = c["wear_volume"].as_f64().unwrap() / c["limit_wear_volume"].as_f64().unwrap();
        assert!((0.99..1.015).contains(&ratio), "{c}");
    }
    assert!(plot.is_file());
}

/// `--gap-transform` and the config key `gap_transform` (and `--edge-cells`, whose checkpoints
/// also record the edge cells' rule): the run reports the transform it used (the default since
/// stop 45: piecewise-linear with the edge cells), a resume under the other one is refused naming
/// it, and an unknown name is refused up front. (A record without the options is a run of the
/// central differences without the edge cells, made before they were recorded: the unit test
/// `checkpoints_record_the_discretization_options_unless_the_legacy_ones`.)
#[test]
fn the_gap_transform_is_chosen_recorded_and_checked_on_resume() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cd");
    let common = ["--n", "401", "--tau-end", "0.3", "--json"];
    let central = [
        "--gap-transform",
        "central-differences",
        "--edge-cells",
        "false",
    ];
    let plain = fretting_wear(&out, &common, &central);
    let plain: Vec<&str> = plain.iter().map(String::as_str).collect();
    let v = ok_json(&run(&plain));
    assert_eq!(v["gap_transform"], "central-differences");
    assert_eq!(v["edge_cells"], false);
    let v = ok_json(&run(&[
        "fretting-wear",
        "--n",
        "401",
        "--tau-end",
        "0.3",
        "--json",
        "--out",
        dir.path().join("default").to_str().unwrap(),
    ]));
    assert_eq!(v["gap_transform"], "piecewise-linear");
    assert_eq!(v["edge_cells"], true);
    // Stopped early, then resumed with the default transform: refused, naming the key.
    let stopped = fretting_wear(
        &out,
        &common,
        &[&central[..], &["--force", "--stop-after", "20"]].concat(),
    );
    let stopped: Vec<&str> = stopped.iter().map(String::as_str).collect();
    run(&stopped);
    let resume = fretting_wear(&out, &common, &["--resume", "--edge-cells", "false"]);
    bad_owned(&resume, "gap_transform");
    let resume = fretting_wear(&out, &common, &[&["--resume"][..], &central].concat());
    let resumed: Vec<&str> = resume.iter().map(String::as_str).collect();
    let v = ok_json(&run(&resumed));
    assert_eq!(v["gap_transform"], "central-differences");
    assert_eq!(v["edge_cells"], false);
    // The edge cells the same way: reported, and a resume without them refused naming them; with
    // them (the default) it completes.
    let stopped = fretting_wear(&out, &common, &["--force", "--stop-after", "20"]);
    let stopped: Vec<&str> = stopped.iter().map(String::as_str).collect();
    run(&stopped);
    bad_owned(
        &fretting_wear(&out, &common, &["--resume", "--edge-cells", "false"]),
        "edge_cells",
    );
    let resume = fretting_wear(&out, &common, &["--resume"]);
    // The checkpoint records the edge cells' rule: one without it (the rule before the last
    // node's floor) or of another rule is refused, saying why.
    checkpoint_scheme_is_checked(
        &out.join("checkpoint.npz"),
        (
            "edge_cell_rule",
            halfspace::fretting::EDGE_CELL_RULE,
            "own-floor",
        ),
        &resume,
        &[
            "another rule of the edge cells",
            "only starting the run over helps",
        ],
    );
    // So is a run directory whose manifest records another rule or none (checked before the
    // run directory's own check, whose message would ask for a parameter no flag sets).
    manifest_scheme_is_checked(
        &out.join("run.json"),
        ("edge_cell_rule", "own-floor"),
        &resume,
        &[
            "another rule of the edge cells",
            "only starting the run over helps",
        ],
    );
    let resumed: Vec<&str> = resume.iter().map(String::as_str).collect();
    let v = ok_json(&run(&resumed));
    assert_eq!(v["edge_cells"], true);
    assert_eq!(v["edge_cell_rule"], halfspace::fretting::EDGE_CELL_RULE);
    let cfg = dir.path().join("bad.toml");
    std::fs::write(&cfg, "n = 401\ngap_transform = \"linear\"\n").unwrap();
    bad(
        &[
            "fretting-wear",
            "--config",
            cfg.to_str().unwrap(),
            "--out",
            dir.path().join("bad").to_str().unwrap(),
        ],
        "\"linear\": expected \"central-differences\" or \"piecewise-linear\"",
    );
}
