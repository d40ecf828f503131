//! Hostile and careless input through the binary (issue 19): crafted files, runaway work,
//! checkpoints that are whole but make no sense, shared output directories, messages. Every case
//! must end with exit code 2 and one line on stderr naming the input and the rule — never a
//! signal (abort), never exit 0 with the bad value in the results, never a lost run.
//!
//! The cases are tables (family, arguments, the text the message must hold); `CASES` counts them.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use halfspace::data::{read_record, write_record, AttrValue, Record};

fn exe() -> Command {
    Command::new(env!("CARGO_BIN_EXE_halfspace"))
}

fn run_in(args: &[String], env: &[(&str, &str)]) -> Output {
    let mut c = exe();
    c.args(args);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("the binary runs")
}

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

/// Exit 2 (not a signal, not 0), one line on stderr, holding every needle.
fn refused(family: &str, args: &[String], env: &[(&str, &str)], needles: &[&str]) -> String {
    let start = Instant::now();
    let out = run_in(args, env);
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(
        out.status.code(),
        Some(2),
        "[{family}] {args:?}: status {:?}, stderr {err}",
        out.status
    );
    assert_eq!(
        err.trim_end().lines().count(),
        1,
        "[{family}] {args:?}: not one line: {err}"
    );
    for n in needles {
        assert!(err.contains(n), "[{family}] {args:?}: {err:?} lacks {n:?}");
    }
    for garbled in ["must be at least", "must be deeper", "must be disjoint"] {
        assert!(!err.contains(garbled), "[{family}] garbled template: {err}");
    }
    assert!(
        start.elapsed() < Duration::from_secs(60),
        "[{family}] {args:?}: took {:?}",
        start.elapsed()
    );
    err
}

/// A `.npy` file with the given header text and data bytes (format 1.0).
fn npy(path: &Path, header: &str, data: &[u8]) {
    let mut h = header.to_string();
    while (10 + h.len() + 1) % 64 != 0 {
        h.push(' ');
    }
    h.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend((h.len() as u16).to_le_bytes());
    out.extend(h.as_bytes());
    out.extend(data);
    std::fs::write(path, out).unwrap();
}

fn f8(shape: &str) -> String {
    format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {shape}, }}")
}

/// The crafted `.npy` files of family A: (file name, header, data bytes, needle).
fn crafted_npy(dir: &Path) -> Vec<(PathBuf, &'static str)> {
    let mut files = Vec::new();
    let mut add = |name: &str, header: String, data: Vec<u8>, needle: &'static str| {
        let p = dir.join(name);
        npy(&p, &header, &data);
        files.push((p, needle));
    };
    add(
        "huge.npy",
        f8("(100000000000, 2)"),
        vec![0; 16],
        "header claims shape",
    );
    add(
        "overflow.npy",
        f8("(18446744073709551615, 2)"),
        vec![0; 16],
        "more values than can be counted",
    );
    add(
        "short.npy",
        f8("(10, 2)"),
        vec![0; 64],
        "header claims shape",
    );
    add("long.npy", f8("(2, 2)"), vec![0; 64], "header claims shape");
    add(
        "int.npy",
        "{'descr': '<i8', 'fortran_order': False, 'shape': (2, 2), }".into(),
        vec![0; 32],
        "wrong dtype",
    );
    add(
        "bigendian.npy",
        "{'descr': '>f8', 'fortran_order': False, 'shape': (2, 2), }".into(),
        vec![0; 32],
        "wrong dtype",
    );
    add("negative.npy", f8("(-2, 2)"), vec![0; 32], "shape");
    add(
        "noshape.npy",
        "{'descr': '<f8', 'fortran_order': False}".into(),
        vec![],
        "no 'shape'",
    );
    add(
        "fortran.npy",
        "{'descr': '<f8', 'fortran_order': Maybe, 'shape': (2, 2), }".into(),
        vec![0; 32],
        "fortran_order",
    );
    add(
        "threed.npy",
        f8("(1000000, 1000000, 1000000)"),
        vec![0; 8],
        "header claims shape",
    );
    let p = dir.join("magic.npy");
    std::fs::write(&p, b"not a numpy file at all").unwrap();
    files.push((p, "magic"));
    let p = dir.join("truncated.npy");
    std::fs::write(&p, b"\x93NUMPY\x01\x00\xff\xff{'descr'").unwrap();
    files.push((p, "truncated"));
    let p = dir.join("empty.npy");
    std::fs::write(&p, b"").unwrap();
    files.push((p, "truncated"));
    let p = dir.join("version9.npy");
    std::fs::write(&p, b"\x93NUMPY\x09\x00\x10\x00{}").unwrap();
    files.push((p, "version"));
    files
}

#[test]
fn a_crafted_npy_is_refused_before_anything_is_allocated() {
    let dir = tempfile::tempdir().unwrap();
    let mut cases = 0;
    for (file, needle) in crafted_npy(dir.path()) {
        let table = format!("table:{}", file.display());
        refused(
            "A npy axisym",
            &strings(&[
                "axisym",
                "--profile",
                &table,
                "--material",
                "homogeneous:E=210e9,nu=0.3",
                "--depth",
                "1e-6",
            ]),
            &[],
            &[needle, file.file_name().unwrap().to_str().unwrap()],
        );
        cases += 1;
    }
    // The 3D indenter table reads the same way (a 2D array); a few of the files.
    for name in [
        "huge.npy",
        "overflow.npy",
        "short.npy",
        "int.npy",
        "magic.npy",
    ] {
        let table = format!("table:{}", dir.path().join(name).display());
        refused(
            "A npy contact3d",
            &strings(&[
                "contact3d",
                "--indenter",
                &table,
                "--material",
                "homogeneous:E=210e9,nu=0.3",
                "--force",
                "0.08",
                "--extent",
                "1e-5",
            ]),
            &[],
            &[name],
        );
        cases += 1;
    }
    assert_eq!(cases, 19);
}

#[test]
fn oversized_or_endless_configs_are_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    let big = dir.path().join("big.toml");
    std::fs::write(&big, format!("grid = 16\n#{}\n", "x".repeat(17 << 20))).unwrap();
    let binary = dir.path().join("binary.toml");
    std::fs::write(&binary, [0xffu8, 0xfe, 0x00, 0x12]).unwrap();
    for (command, file, needle) in [
        ("fretting-loop", big.to_str().unwrap(), "larger than"),
        ("fretting-map", big.to_str().unwrap(), "larger than"),
        ("fretting-wear", big.to_str().unwrap(), "larger than"),
        ("fretting-loop", "/dev/zero", "larger than"),
        ("fretting-map", "/dev/zero", "larger than"),
        ("fretting-wear", "/dev/zero", "larger than"),
        ("fretting-loop", binary.to_str().unwrap(), "UTF-8"),
        ("fretting-loop", dir.path().to_str().unwrap(), "--config"),
    ] {
        let out = dir.path().join(format!("out-{command}"));
        refused(
            "A config",
            &strings(&[command, "--config", file, "--out", out.to_str().unwrap()]),
            &[],
            &[needle],
        );
        assert!(
            !out.exists(),
            "a refused config creates no output directory"
        );
    }
}

const SMALL_LOOP: &str =
    "grid = 16\nnormal_steps = 2\nshift_step = 0.02e-6\nsubsurface_over_a = 0.0\n";

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn runaway_work_is_estimated_and_refused_before_it_starts() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = out.to_str().unwrap();
    for (text, needles) in [
        (
            "shift_step = 1e-20\n",
            vec!["increments", "GiB", "shift_step"],
        ),
        ("normal_steps = 1000000000\n", vec!["increments", "GiB"]),
        ("amplitude = 1.0\nshift_step = 1e-12\n", vec!["increments"]),
        ("grid = 1000000\n", vec!["GiB"]),
        ("grid = 20000\nnormal_steps = 1000\n", vec!["GiB"]),
    ] {
        let cfg = write(dir.path(), "runaway.toml", text);
        refused(
            "B loop",
            &strings(&["fretting-loop", "--config", &cfg, "--out", o]),
            &[],
            &needles,
        );
    }
    // A million points of the default loop (64², 180 increments); a map of tiny steps.
    let loads: Vec<String> = (1..=1000).map(|i| format!("{}e-4", i)).collect();
    let amps: Vec<String> = (1..=1000).map(|i| format!("{}e-10", i)).collect();
    let big = format!(
        "subsurface_over_a = 0.0\n[map]\nloads = [{}]\namplitudes = [{}]\n",
        loads.join(","),
        amps.join(",")
    );
    let cfg = write(dir.path(), "million.toml", &big);
    refused(
        "B map",
        &strings(&["fretting-map", "--config", &cfg, "--out", o]),
        &[],
        &[
            "fretting map",
            "1000000 loop(s)",
            "hours of work",
            "HALFSPACE_WORK_LIMIT",
        ],
    );
    let cfg = write(
        dir.path(),
        "tiny.toml",
        "shift_step = 1e-20\n[map]\nloads = [0.08]\namplitudes = [4e-8]\n",
    );
    refused(
        "B map",
        &strings(&["fretting-map", "--config", &cfg, "--out", o]),
        &[],
        &["increments"],
    );
    // The limits are the machine's: a default loop under a 1 MB memory limit is refused with its
    // estimate, a 64-point map under a small work limit too.
    refused(
        "B limit",
        &strings(&["fretting-loop", "--out", o]),
        &[("HALFSPACE_MEMORY_LIMIT", "1e6")],
        &["GiB", "available"],
    );
    let cfg = write(
        dir.path(),
        "sixty-four.toml",
        &format!(
            "{SMALL_LOOP}[map]\nloads = [0.01,0.02,0.03,0.04,0.05,0.06,0.07,0.08]\namplitudes = [1e-8,2e-8,3e-8,4e-8,5e-8,6e-8,7e-8,8e-8]\n"
        ),
    );
    refused(
        "B limit",
        &strings(&["fretting-map", "--config", &cfg, "--out", o]),
        &[("HALFSPACE_WORK_LIMIT", "1e-4")],
        &["HALFSPACE_WORK_LIMIT"],
    );
    for args in [
        vec![
            "fretting-wear",
            "--tau-end",
            "1e9",
            "--dtau",
            "1e-3",
            "--out",
            o,
        ],
        vec![
            "contact3d",
            "--indenter",
            "sphere:R=1e-4",
            "--material",
            "homogeneous:E=210e9,nu=0.3",
            "--force",
            "0.08",
            "--grid",
            "100000",
        ],
        vec![
            "axisym",
            "--profile",
            "sphere:R=1e-4",
            "--material",
            "homogeneous:E=210e9,nu=0.3",
            "--force",
            "0.08",
            "--n",
            "10000000000",
        ],
    ] {
        refused("B other", &strings(&args), &[], &[]);
    }
    // Refused up front with the estimate, before anything of their size is allocated (each used
    // to abort in the allocator or panic on a capacity overflow): a wear grid of 1e10 nodes,
    // subsurface boxes of 1e6 m and 1e300 m, an EIM study of 1e10 and 2⁶⁴ − 1 layers; and a deep
    // inhomogeneity beyond the layers that can be indexed (a scan of every layer above it before).
    let sphere_case = [
        "--indenter",
        "sphere:R=1e-3",
        "--material",
        "homogeneous:E=210e9,nu=0.3",
        "--force",
        "1",
        "--grid",
        "16",
    ];
    let npz = dir.path().join("c.npz");
    let npz = npz.to_str().unwrap();
    for (family, args, needles) in [
        (
            "B wear grid",
            strings(&["fretting-wear", "--n", "10000000000", "--out", o]),
            vec!["MDR wear run", "GiB"],
        ),
        (
            "B subsurface",
            strings(
                &[
                    &["contact3d"][..],
                    &sphere_case,
                    &["--subsurface", "1e6", "--out", npz],
                ]
                .concat(),
            ),
            vec!["subsurface", "8 GiB"],
        ),
        (
            "B subsurface",
            strings(
                &[
                    &["contact3d"][..],
                    &sphere_case,
                    &["--subsurface", "1e300", "--out", npz],
                ]
                .concat(),
            ),
            vec!["subsurface", "8 GiB"],
        ),
        (
            "B EIM layers",
            strings(&[
                "study",
                "eim-operator",
                "--grid",
                "16",
                "--layers",
                "10000000000",
            ]),
            vec!["--layers", "GiB"],
        ),
        (
            "B EIM layers",
            strings(&[
                "study",
                "eim-operator",
                "--grid",
                "16",
                "--layers",
                "18446744073709551615",
            ]),
            vec!["--layers", "GiB"],
        ),
        (
            "B deep inhomogeneity",
            strings(
                &[
                    &["contact3d"][..],
                    &sphere_case,
                    &[
                        "--extent",
                        "1e-3",
                        "--inhomogeneity",
                        "sphere:x=0,y=0,z=1e300,r=1e-4,E=2e9,nu=0.3",
                        "--out",
                        npz,
                    ],
                ]
                .concat(),
            ),
            vec!["1e300", "layers"],
        ),
    ] {
        refused(family, &args, &[], &needles);
    }
    assert!(
        !out.join("run.json").exists(),
        "a refused wear run claimed its directory"
    );
    assert!(!out.join("results.h5").exists());
}

/// A small fretting-wear run stopped after 40 steps (a snapshot at step 25): its directory (manifest, checkpoint).
fn interrupted_wear(dir: &Path) -> (PathBuf, Vec<String>) {
    let out = dir.join("wear");
    let common = strings(&[
        "fretting-wear",
        "--out",
        out.to_str().unwrap(),
        "--n",
        "401",
        "--dtau",
        "4e-3",
        "--tau-end",
        "0.4",
        "--json",
    ]);
    let mut first = common.clone();
    first.extend(strings(&["--stop-after", "40"]));
    let o = run_in(&first, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut resume = common;
    resume.push("--resume".into());
    (out, resume)
}

/// Rewrites `checkpoint.npz` with `edit` applied, runs `resume`, expects the refusal naming
/// `needles`, and checks that the tampered checkpoint is still there, unchanged, and no results.
fn tampered_resume(
    family: &str,
    out: &Path,
    resume: &[String],
    original: &Record,
    edit: impl FnOnce(&mut Record),
    needles: &[&str],
) {
    let checkpoint = out.join("checkpoint.npz");
    let mut rec = original.clone();
    edit(&mut rec);
    write_record(&checkpoint, &rec).unwrap();
    let before = std::fs::read(&checkpoint).unwrap();
    refused(family, resume, &[], needles);
    assert_eq!(
        std::fs::read(&checkpoint).unwrap(),
        before,
        "[{family}] a refused resume leaves the checkpoint as it was"
    );
    assert!(!out.join("results.h5").exists(), "[{family}] no results");
}

fn set(rec: &mut Record, name: &str, f: impl FnOnce(&mut Vec<f64>)) {
    let (_, v) = rec
        .arrays
        .iter_mut()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no {name}"));
    f(v);
}

fn set_attr(rec: &mut Record, name: &str, value: AttrValue) {
    let slot = rec.attributes.iter_mut().find(|(n, _)| n == name).unwrap();
    slot.1 = value;
}

#[test]
fn wear_checkpoints_are_checked_for_sense_and_kept_when_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (out, resume) = interrupted_wear(dir.path());
    assert!(out.join("checkpoint.npz").is_file());
    let original = read_record(&out.join("checkpoint.npz")).unwrap();
    let fam = "C wear";
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "contact_radius_history", |v| v[3] = f64::NAN),
        &["contact_radius_history", "NaN"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "contact_radius_history", |v| v[7] = 5.0),
        &["contact_radius_history", "5"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "contact_radius_history", |v| v[7] = -1.0),
        &["contact_radius_history"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "contact_radius_history", |v| v[10] = 0.5),
        &["contact_radius_history", "never smaller than the unworn"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| {
            set(r, "contact_radius_history", |v| {
                v.pop();
            })
        },
        &["contact_radius_history", "entries"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "profile", |v| v[100] = f64::INFINITY),
        &["profile", "inf"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "profile", |v| v.truncate(10)),
        &["profile", "10 values"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "snapshot0_profile", |v| v.truncate(10)),
        &["snapshot0_profile", "N = 401"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "snapshot0_pressure", |v| v[0] = -1e30),
        &["snapshot0_pressure", "≥ 0"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "snapshot0_slip", |v| v[5] = f64::NAN),
        &["snapshot0_slip"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set_attr(r, "snapshot0_step", AttrValue::Int(7)),
        &["snapshot0_step"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set_attr(r, "snapshot0_contact_radius", AttrValue::Float(7.0)),
        &["snapshot0_contact_radius"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set_attr(r, "step", AttrValue::Int(-3)),
        &["step"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set_attr(r, "step", AttrValue::Int(10_000_000)),
        &["step"],
    );
    // The members of the adaptive-stepping state (issue 20): τ and its history, the loaded
    // radius, the step controller's memory, the snapshots' τ and loaded radius. (A non-finite
    // attribute is stored as JSON null and refused when read, naming it; the library's own check
    // of the values is for states passed to `FrettingSimulation::resume` directly.)
    let attr =
        |name: &'static str, value: AttrValue| move |r: &mut Record| set_attr(r, name, value);
    type Edit = Box<dyn FnOnce(&mut Record)>;
    let cases: Vec<(Edit, Vec<&str>)> = vec![
        (
            Box::new(|r| set(r, "tau_history", |v| v[4] = f64::NAN)),
            vec!["tau_history", "NaN"],
        ),
        (
            Box::new(|r| set(r, "tau_history", |v| v.swap(3, 4))),
            vec!["tau_history", "increases"],
        ),
        (
            Box::new(|r| set(r, "tau_history", |v| v[2] += 1e-3)),
            vec!["tau_history", "fixed step"],
        ),
        (
            Box::new(|r| {
                set(r, "tau_history", |v| {
                    v.pop();
                })
            }),
            vec!["tau_history", "entries"],
        ),
        (
            Box::new(|r| set(r, "loaded_radius_history", |v| v[5] = -0.5)),
            vec!["loaded_radius_history", "-0.5"],
        ),
        (
            Box::new(|r| set(r, "loaded_radius_history", |v| v[5] = f64::INFINITY)),
            vec!["loaded_radius_history", "inf"],
        ),
        (
            Box::new(|r| {
                set(r, "loaded_radius_history", |v| {
                    v.push(1.0);
                })
            }),
            vec!["loaded_radius_history", "entries"],
        ),
        (
            Box::new(attr("tau", AttrValue::Float(f64::NAN))),
            vec!["tau", "null"],
        ),
        (
            Box::new(attr("tau", AttrValue::Float(0.3))),
            vec!["tau_history", "0.3"],
        ),
        (
            Box::new(attr("next_step", AttrValue::Float(f64::NAN))),
            vec!["next_step", "null"],
        ),
        (
            Box::new(attr("next_step", AttrValue::Float(-1.0))),
            vec!["next_step", "-1"],
        ),
        (
            Box::new(attr("previous_error", AttrValue::Float(3.0))),
            vec!["previous_error", "3"],
        ),
        (
            Box::new(attr("rejected_steps", AttrValue::Int(-1))),
            vec!["rejected_steps", "≥ 0"],
        ),
        (
            Box::new(attr("snapshot0_tau", AttrValue::Float(0.37))),
            vec!["snapshot0_tau", "0.37"],
        ),
        (
            Box::new(attr("snapshot0_loaded_radius", AttrValue::Float(f64::NAN))),
            vec!["snapshot0_loaded_radius", "null"],
        ),
    ];
    for (edit, needles) in cases {
        tampered_resume(fam, &out, &resume, &original, edit, &needles);
    }
    // A crafted member header inside the checkpoint: refused, not an abort.
    let checkpoint = out.join("checkpoint.npz");
    let zipped = std::fs::read(&checkpoint).unwrap();
    let marker = b"'shape': (";
    let at = zipped
        .windows(marker.len())
        .position(|w| w == marker)
        .unwrap()
        + marker.len();
    let mut crafted = zipped.clone();
    // The first member's first dimension "4..." becomes "9...": a claim beyond its bytes.
    crafted[at] = b'9';
    std::fs::write(&checkpoint, &crafted).unwrap();
    refused(
        "A checkpoint member",
        &resume,
        &[],
        &["member", "header claims shape"],
    );
    std::fs::write(&checkpoint, b"PK\x03\x04 not really a zip").unwrap();
    refused("A checkpoint zip", &resume, &[], &["checkpoint.npz"]);
    // The untampered checkpoint still resumes.
    write_record(&checkpoint, &original).unwrap();
    let o = run_in(&resume, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// An adaptive run's checkpoint (issue 20): the step controller's memory is checked too.
#[test]
fn adaptive_wear_checkpoints_check_the_step_controller() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("adaptive");
    let common = strings(&[
        "fretting-wear",
        "--out",
        out.to_str().unwrap(),
        "--n",
        "401",
        "--tol",
        "1e-3",
        "--tau-end",
        "0.4",
        "--json",
    ]);
    let mut first = common.clone();
    first.extend(strings(&["--stop-after", "4"]));
    let o = run_in(&first, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut resume = common;
    resume.push("--resume".into());
    let original = read_record(&out.join("checkpoint.npz")).unwrap();
    let fam = "C adaptive wear";
    for (name, value, needles) in [
        ("next_step", 0.0, vec!["next_step", "> 0"]),
        ("next_step", f64::INFINITY, vec!["next_step", "null"]),
        ("previous_error", 0.0, vec!["next_step", "> 0"]),
        ("previous_error", f64::NAN, vec!["previous_error", "null"]),
    ] {
        tampered_resume(
            fam,
            &out,
            &resume,
            &original,
            |r| set_attr(r, name, AttrValue::Float(value)),
            &needles,
        );
    }
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "tau_history", |v| v[1] = v[0]),
        &["tau_history", "increases"],
    );
    // The untampered checkpoint still resumes.
    write_record(&out.join("checkpoint.npz"), &original).unwrap();
    let o = run_in(&resume, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// A small fretting loop stopped after 8 increments.
fn interrupted_loop(dir: &Path) -> (PathBuf, Vec<String>) {
    let out = dir.join("loop");
    let cfg = write(dir, "loop.toml", SMALL_LOOP);
    let common = strings(&[
        "fretting-loop",
        "--config",
        &cfg,
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    let mut first = common.clone();
    first.extend(strings(&["--stop-after", "8"]));
    let o = run_in(&first, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut resume = common;
    resume.push("--resume".into());
    (out, resume)
}

#[test]
fn loop_checkpoints_are_checked_for_sense_and_kept_when_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (out, resume) = interrupted_loop(dir.path());
    let original = read_record(&out.join("checkpoint.npz")).unwrap();
    let fam = "C loop";
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "tangential_force", |v| v[5] = f64::NAN),
        &["tangential_force", "NaN"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "alternations", |v| v[1] = f64::NAN),
        &["alternations"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "normal_force", |v| v[1] = 0.07),
        &["normal_force", "increment 1"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "shift_x", |v| v[4] = 1.0),
        &["shift_x"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "stick_area", |v| v[3] = 1.0),
        &["stick_area"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "max_pressure", |v| v[0] = -1.0),
        &["max_pressure"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "tangential_force", |v| v[6] = 1e3),
        &["tangential_force"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "state_pressure", |v| v[0] = -5.0),
        &["state_pressure"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "state_pressure", |v| v.truncate(3)),
        &["state"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "point_stick_A", |v| v[0] = 0.5),
        &["point_stick_A"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set(r, "point_pressure_A", |v| v[0] = f64::NAN),
        &["point_pressure_A"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set_attr(r, "point_increment_A", AttrValue::Int(1)),
        &["point_increment_A"],
    );
    tampered_resume(
        fam,
        &out,
        &resume,
        &original,
        |r| set_attr(r, "max_transverse_slip", AttrValue::Float(-1.0)),
        &["max_transverse_slip"],
    );
    // A checkpoint written before fingerprints recorded the alternation scheme (the plain
    // alternation): refused under alternation = "gauged", naming the key; resumed under the
    // plain one (the default), below.
    let mut legacy = original.clone();
    let slot = legacy
        .attributes
        .iter_mut()
        .find(|(n, _)| n == "config")
        .expect("the fingerprint");
    match &mut slot.1 {
        AttrValue::Text(t) => {
            assert!(t.contains(", alternation: Some(Plain)"), "{t}");
            *t = t.replacen(", alternation: Some(Plain)", "", 1);
        }
        other => panic!("config attribute {other:?}"),
    }
    let cfg = dir.path().join("loop.toml");
    std::fs::write(&cfg, format!("{SMALL_LOOP}alternation = \"gauged\"\n")).unwrap();
    tampered_resume(
        fam,
        &out,
        &resume,
        &legacy,
        |_| {},
        &["alternation = \"plain\""],
    );
    std::fs::write(&cfg, SMALL_LOOP).unwrap();
    let o2 = run_in(&resume, &[]);
    assert!(
        o2.status.success(),
        "{}",
        String::from_utf8_lossy(&o2.stderr)
    );
}

const SMALL_MAP: &str = "grid = 16\nnormal_steps = 2\nshift_step = 0.02e-6\nsubsurface_over_a = 0.0\n[map]\nloads = [0.04, 0.08]\namplitudes = [0.01e-6, 0.06e-6]\n";

#[test]
fn map_point_checkpoints_are_checked_for_sense() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write(dir.path(), "map.toml", SMALL_MAP);
    let out = dir.path().join("map");
    let common = strings(&[
        "fretting-map",
        "--config",
        &cfg,
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    let mut first = common.clone();
    first.extend(strings(&["--stop-after", "1"]));
    assert!(run_in(&first, &[]).status.success());
    let mut resume = common;
    resume.push("--resume".into());
    let point = std::fs::read_dir(out.join("points"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .find(|p| p.extension().is_some_and(|e| e == "json"))
        .unwrap();
    let original = std::fs::read_to_string(&point).unwrap();
    let json: serde_json::Value = serde_json::from_str(&original).unwrap();
    let with = |f: usize, v: serde_json::Value| {
        let mut j = json.clone();
        j["values"][f] = v;
        j.to_string()
    };
    for (text, needle) in [
        (with(3, serde_json::json!(-1e30)), "dissipated_energy"),
        (with(0, serde_json::json!(0.5)), "load"),
        (with(1, serde_json::json!(1e-3)), "amplitude"),
        (with(5, serde_json::json!(2.0)), "sliding_fraction"),
        (with(4, serde_json::json!(-0.5)), "energy_ratio"),
        (with(2, serde_json::json!(7)), "regime"),
        (
            with(6, serde_json::json!(40.0)),
            "tangential_force_over_mu_w",
        ),
        (with(8, serde_json::json!(-2.0)), "seconds"),
        ("{".to_string(), "EOF"),
        (
            format!("{{\"pad\": \"{}\"}}", "x".repeat(2 << 20)),
            "larger than",
        ),
    ] {
        std::fs::write(&point, &text).unwrap();
        refused("C map", &resume, &[], &[needle]);
        assert_eq!(
            std::fs::read_to_string(&point).unwrap(),
            text,
            "kept as it was"
        );
        assert!(!out.join("results.h5").exists());
    }
    std::fs::write(&point, &original).unwrap();
    let o = run_in(&resume, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn a_run_owns_its_output_directory() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write(dir.path(), "loop.toml", SMALL_LOOP);
    let other = write(
        dir.path(),
        "other.toml",
        &format!("{SMALL_LOOP}friction = 0.5\n"),
    );
    let out = dir.path().join("loop");
    let o = out.to_str().unwrap();
    let args = |c: &str, extra: &[&str]| {
        let mut a = strings(&["fretting-loop", "--config", c, "--out", o, "--json"]);
        a.extend(strings(extra));
        a
    };
    assert!(run_in(&args(&cfg, &[]), &[]).status.success());
    assert!(out.join("run.json").is_file() && !out.join("run.lock").exists());
    // A complete run is not overwritten silently, by the same or another configuration.
    refused(
        "D loop",
        &args(&cfg, &[]),
        &[],
        &["complete fretting-loop run", "--force"],
    );
    refused("D loop", &args(&other, &[]), &[], &["friction", "--force"]);
    refused(
        "D loop",
        &args(&other, &["--resume"]),
        &[],
        &["other parameters"],
    );
    refused(
        "D loop",
        &args(&cfg, &["--resume", "--force"]),
        &[],
        &["not both"],
    );
    // An earlier figure that this run does not draw is gone after --force.
    std::fs::write(out.join("von_mises_A.svg"), "<svg/>").unwrap();
    let v = common::ok_json(&run_in(&args(&other, &["--force"]), &[]));
    assert!(v["dissipated_energy"].as_f64().unwrap() > 0.0);
    assert!(
        !out.join("von_mises_A.svg").exists(),
        "stale figure removed"
    );
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(manifest["status"], "complete");
    assert_eq!(manifest["parameters"]["friction"], 0.5);
    // Another command's directory.
    refused(
        "D wear",
        &strings(&["fretting-wear", "--out", o, "--resume"]),
        &[],
        &["fretting-loop run"],
    );
    // A directory that was not made by a run.
    let foreign = dir.path().join("thesis");
    std::fs::create_dir(&foreign).unwrap();
    std::fs::write(foreign.join("chapter1.tex"), "x").unwrap();
    for command in ["fretting-loop", "fretting-wear"] {
        refused(
            "D foreign",
            &strings(&[command, "--out", foreign.to_str().unwrap()]),
            &[],
            &["no run manifest"],
        );
    }
    assert_eq!(std::fs::read_dir(&foreign).unwrap().count(), 1);
}

#[test]
fn a_second_process_on_the_same_directory_is_refused_naming_the_holder() {
    let dir = tempfile::tempdir().unwrap();
    let mut holder = Command::new("sleep").arg("30").spawn().unwrap();
    let cfg = write(dir.path(), "loop.toml", SMALL_LOOP);
    let map_cfg = write(dir.path(), "map.toml", SMALL_MAP);
    for (command, config) in [
        ("fretting-loop", Some(cfg.as_str())),
        ("fretting-map", Some(map_cfg.as_str())),
        ("fretting-wear", None),
    ] {
        let out = dir.path().join(command);
        std::fs::create_dir(&out).unwrap();
        std::fs::write(out.join("run.lock"), format!("{}\n", holder.id())).unwrap();
        let mut args = strings(&[command, "--out", out.to_str().unwrap()]);
        if let Some(c) = config {
            args.extend(strings(&["--config", c]));
        }
        refused("D lock", &args, &[], &[&format!("pid {}", holder.id())]);
        // A lock left by a process that is gone is taken over.
        std::fs::write(out.join("run.lock"), "4194304 1\n").unwrap();
        if command == "fretting-wear" {
            args.extend(strings(&[
                "--n",
                "401",
                "--dtau",
                "4e-3",
                "--tau-end",
                "0.1",
            ]));
        }
        let o = run_in(&args, &[]);
        assert!(
            o.status.success(),
            "{command}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let _ = holder.kill();
    let _ = holder.wait();
}

#[test]
fn two_maps_on_one_directory_do_not_both_succeed() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write(dir.path(), "map.toml", SMALL_MAP);
    let out = dir.path().join("map");
    let args = strings(&[
        "fretting-map",
        "--config",
        &cfg,
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    let a = exe()
        .args(&args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(30));
    let b = exe().args(&args).output().unwrap();
    let a = a.wait_with_output().unwrap();
    let ok = [a.status.success(), b.status.success()];
    assert!(
        ok.iter().filter(|s| **s).count() == 1,
        "{ok:?}: {}",
        String::from_utf8_lossy(&b.stderr)
    );
    let loser = if a.status.success() { &b } else { &a };
    let err = String::from_utf8_lossy(&loser.stderr);
    assert!(err.contains("pid") || err.contains("holds"), "{err}");
    assert!(out.join("results.h5").is_file());
}

#[test]
fn messages_name_the_input_the_rule_and_the_value() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = out.to_str().unwrap();
    let m = "homogeneous:E=210e9,nu=0.3";
    let c3_bare = |extra: &[&str]| {
        let mut a = strings(&["contact3d", "--indenter", "sphere:R=1e-4", "--material", m]);
        a.extend(strings(extra));
        a
    };
    let c3 = |extra: &[&str]| {
        let mut a = c3_bare(&["--force", "0.08", "--grid", "32"]);
        a.extend(strings(extra));
        a
    };
    let ax = |extra: &[&str]| {
        let mut a = strings(&["axisym", "--profile", "sphere:R=1e-4", "--material", m]);
        a.extend(strings(extra));
        a
    };
    let cases: Vec<(Vec<String>, Vec<&str>)> = vec![
        (ax(&["--depth", "-1"]), vec!["depth", "-1"]),
        (ax(&["--force", "-0.5"]), vec!["force", "-0.5"]),
        (ax(&["--depth", "1e-6", "--n", "-5"]), vec!["--n", "-5"]),
        (ax(&["--depth", "1e-6", "--domain-ratio", "-2"]), vec!["-2"]),
        (
            ax(&["--depth", "1e-6", "--plot", &format!("{o}.pdf")]),
            vec!["--plot", ".pdf", ".svg"],
        ),
        (c3_bare(&["--force", "-1"]), vec!["--force", "-1"]),
        (c3_bare(&["--depth", "-1e-6"]), vec!["--depth"]),
        (c3(&["--extent", "-1"]), vec!["-1"]),
        (c3(&["--subsurface", "-1e-6"]), vec!["subsurface"]),
        (
            c3(&["--friction", "-0.3", "--shift-x", "1e-8"]),
            vec!["--friction", "-0.3"],
        ),
        (c3(&["--shift-x", "-1e-8"]), vec!["friction"]),
        (c3(&["--plot", &format!("{o}.pdf")]), vec!["--plot", ".pdf"]),
        (
            c3_bare(&["--force", "0.08", "--grid", "-4"]),
            vec!["--grid", "-4"],
        ),
        (
            c3(&[
                "--inhomogeneity",
                "sphere:x=nan,y=0,z=5e-6,r=1e-6,E=420e9,nu=0.3",
            ]),
            vec!["centre x", "finite", "NaN"],
        ),
        (
            c3(&[
                "--inhomogeneity",
                "sphere:x=0,y=inf,z=5e-6,r=1e-6,E=420e9,nu=0.3",
            ]),
            vec!["centre y", "finite"],
        ),
        (
            c3(&[
                "--inhomogeneity",
                "cylinder:axis=y,x=nan,z=5e-6,r=1e-6,E=420e9,nu=0.3",
            ]),
            vec!["axis position x"],
        ),
        (
            c3(&[
                "--inhomogeneity",
                "sphere:x=0,y=0,z=5e-6,r=1e-9,E=420e9,nu=0.3",
            ]),
            vec!["inhomogeneity 1", "no cell centre", "refine the grid"],
        ),
        (
            c3(&[
                "--inhomogeneity",
                "sphere:x=0,y=0,z=-5e-6,r=1e-6,E=420e9,nu=0.3",
            ]),
            vec!["centre depth z", "-0.000005"],
        ),
        (
            c3(&[
                "--inhomogeneity",
                "sphere:x=0,y=0,z=5e-6,r=1e-6,E=-1,nu=0.3",
            ]),
            vec!["Young", "-1"],
        ),
        (
            strings(&["fretting-wear", "--chi", "-0.5", "--out", o]),
            vec!["chi", "-0.5"],
        ),
        (
            strings(&["fretting-wear", "--dtau", "-1e-3", "--out", o]),
            vec!["dtau", "-0.001"],
        ),
        (
            strings(&["fretting-wear", "--tol", "-1e-4", "--out", o]),
            vec!["--tol", "-0.0001"],
        ),
        (
            strings(&["fretting-wear", "--tol", "0", "--out", o]),
            vec!["--tol", "got 0"],
        ),
        (
            strings(&["fretting-wear", "--tol", "NaN", "--out", o]),
            vec!["--tol", "NaN"],
        ),
        (
            strings(&["fretting-wear", "--tol", "inf", "--out", o]),
            vec!["--tol", "inf"],
        ),
        (
            strings(&["fretting-wear", "--tol", "1e300", "--out", o]),
            vec!["--tol", "0.1"],
        ),
        (
            strings(&["fretting-wear", "--tol", "1e-300", "--out", o]),
            vec!["--tol", "1e-12"],
        ),
        (
            strings(&[
                "fretting-wear",
                "--tol",
                "1e-4",
                "--dtau",
                "1e-3",
                "--out",
                o,
            ]),
            vec!["--tol", "--dtau", "not both"],
        ),
        (
            strings(&["fretting-wear", "--length", "-2", "--out", o]),
            vec!["length", "-2"],
        ),
        (
            strings(&["fretting-wear", "--n", "-5", "--out", o]),
            vec!["--n", "-5"],
        ),
        (
            strings(&["fretting-wear", "--gap-transform", "linear", "--out", o]),
            vec!["--gap-transform", "linear", "piecewise-linear"],
        ),
        (
            strings(&["fretting-wear", "--edge-cells", "maybe", "--out", o]),
            vec!["--edge-cells", "maybe"],
        ),
        // A [map] key of the wrong type is named with its line (it was "[map]: invalid type"
        // alone), and a map that is not a table says so.
        (
            strings(&[
                "fretting-map",
                "--config",
                &write(
                    dir.path(),
                    "map_type.toml",
                    "[map]\nloads = [0.08]\namplitudes = \"1e-8\"\n",
                ),
                "--out",
                o,
            ]),
            vec!["[map]", "amplitudes = \"1e-8\"", "expected a sequence"],
        ),
        (
            strings(&[
                "fretting-map",
                "--config",
                &write(dir.path(), "map_value.toml", "map = 3\n"),
                "--out",
                o,
            ]),
            vec!["map = 3", "[map] table"],
        ),
        // A study's flag given to another study is refused (it was ignored, exit 0).
        (
            strings(&[
                "study",
                "eq17",
                "--layers",
                "0",
                "--datasets",
                "/nonexistent",
            ]),
            vec!["--datasets", "fe-comparison", "eq17"],
        ),
        (
            strings(&["study", "fe-comparison", "--grid", "5"]),
            vec!["--grid", "eim-operator", "fe-comparison"],
        ),
    ];
    for (args, needles) in &cases {
        let err = refused("E message", args, &[], needles);
        assert!(!err.contains("unexpected argument"), "{err}");
    }
    assert!(
        !Path::new(&format!("{o}.pdf")).exists(),
        "no SVG bytes under a .pdf name"
    );
    // Fretting-loop: a subnormal force names the force, not an option the command lacks; keys of
    // the composite preset alone are refused without it; the preset's own keys are checked.
    for (text, needles, case) in [
        (
            "force = 1e-310\n",
            vec!["force", "Hertz radius"],
            "homogeneous",
        ),
        (
            "force = 5e-324\n",
            vec!["force", "Hertz radius"],
            "homogeneous",
        ),
        ("radius = 5e-324\n", vec!["radius"], "homogeneous"),
        (
            "shift_step = -1e-9\n",
            vec!["shift_step", "-0.000000001"],
            "homogeneous",
        ),
        ("normal_steps = -3\n", vec!["normal_steps"], "homogeneous"),
        ("grid = 1\n", vec!["grid", "≥ 8"], "homogeneous"),
        ("nu = 0.5\n", vec!["nu", "0.5"], "homogeneous"),
        (
            "layout = \"gap-centred\"\n",
            vec!["layout", "composite"],
            "homogeneous",
        ),
        (
            "fibre_e_ratio = -2\n",
            vec!["fibre_e_ratio", "composite"],
            "homogeneous",
        ),
        (
            "fibre_e_ratio = -2\n",
            vec!["fibre_e_ratio", "-2"],
            "composite",
        ),
        (
            "layout = \"diagonal\"\n",
            vec!["layout", "diagonal"],
            "composite",
        ),
        (
            "extent_over_a = 1e300\n",
            vec!["fibres", "extent_over_a"],
            "composite",
        ),
        ("frictoin = 0.3\n", vec!["frictoin"], "homogeneous"),
        (
            "subsurface_over_a = -1\n",
            vec!["subsurface_over_a", "-1"],
            "homogeneous",
        ),
    ] {
        let cfg = write(dir.path(), "msg.toml", text);
        let err = refused(
            "E loop",
            &strings(&[
                "fretting-loop",
                "--config",
                &cfg,
                "--case",
                case,
                "--out",
                o,
            ]),
            &[],
            &needles,
        );
        assert!(!err.contains("--subsurface"), "{err}");
    }
    assert!(!out.exists(), "refused inputs create no output directory");
}

/// The inputs added with the elastic indenter, approach control, `[fatigue]` and `fretting-wear3d`:
/// each bad value is refused before any work, exit 2, one line naming the key.
#[test]
fn indenter_approach_fatigue_and_wear3d_keys_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = out.to_str().unwrap();
    let fatigue = "[fatigue]\nf_minus1 = 3e8\nt_minus1 = 2e8\nfs_k = 0.5\nyield_stress = 8e8\n";
    let wear = "[wear]\nlaw = \"archard\"\ncoefficient = 1e-15\ncycles = 10\n";
    let sphere = "[[inhomogeneity]]\nkind = \"sphere\"\nx = 0.0\ny = 0.0\nz = 1.6e-6\nr = 0.9e-6\n\
                  E = 4.2e11\nnu = 0.3\n";
    let loop_cases: Vec<(&str, String, Vec<&str>)> = vec![
        (
            "both",
            "force = 0.08\napproach = 1e-7\n".into(),
            vec!["force", "approach"],
        ),
        (
            "half indenter",
            "indenter_e = 2e11\n".into(),
            vec!["indenter_nu"],
        ),
        (
            "bad indenter nu",
            "indenter_e = 2e11\nindenter_nu = 0.7\n".into(),
            vec!["Poisson"],
        ),
        (
            "negative approach",
            "approach = -1e-7\n".into(),
            vec!["approach"],
        ),
        (
            "fatigue depth",
            format!("{fatigue}depth_over_a = -1\n"),
            vec!["depth_over_a", "-1"],
        ),
        (
            "fatigue screen",
            format!("{fatigue}screen_fraction = 2\n"),
            vec!["screen_fraction", "2"],
        ),
        (
            "fatigue process volume",
            format!("{fatigue}process_volume = -1e-6\n"),
            vec!["process_volume", "> 0 m"],
        ),
        (
            "fatigue key",
            format!("{fatigue}f_minus_one = 1\n"),
            vec!["f_minus_one"],
        ),
        (
            "fatigue limit",
            fatigue.replace("f_minus1 = 3e8", "f_minus1 = -3e8"),
            vec!["fatigue"],
        ),
        (
            "inhomogeneity fatigue limits",
            format!("{fatigue}{sphere}fatigue = {{ t_minus1 = 5e8 }}\n"),
            vec!["[[inhomogeneity]] 1 fatigue", "t_minus1"],
        ),
        (
            "inhomogeneity fatigue key",
            format!("{fatigue}{sphere}fatigue = {{ f_minus_one = 1 }}\n"),
            vec!["f_minus_one"],
        ),
        (
            "inhomogeneity fatigue without the fatigue table",
            format!("{sphere}fatigue = {{ f_minus1 = 3e8 }}\n"),
            vec!["[[inhomogeneity]] 1", "[fatigue]", "ignored"],
        ),
        (
            "surface operator without inhomogeneities",
            "inhomogeneous_body = \"surface-operator\"\n".into(),
            vec!["inhomogeneous_body", "needs inhomogeneities"],
        ),
        (
            "EIM factor without inhomogeneities",
            "eim_change_factor = 1e-2\n".into(),
            vec!["eim_change_factor", "read only"],
        ),
        (
            "EIM recycled depth without inhomogeneities",
            "eim_recycled_depth = 5\n".into(),
            vec!["eim_recycled_depth", "read only"],
        ),
        (
            "alternation scheme",
            "alternation = \"anderson\"\n".into(),
            vec!["alternation = \"anderson\"", "\"plain\" or \"gauged\""],
        ),
        (
            "alternation scheme type",
            "alternation = 1\n".into(),
            vec!["alternation = 1", "invalid type"],
        ),
        (
            "alternation of identical bodies",
            "indenter_e = 210e9\nindenter_nu = 0.3\nalternation = \"gauged\"\n".into(),
            vec!["alternation = \"gauged\"", "coupled pair", "ignored"],
        ),
    ];
    // contact3d has no fatigue: an inhomogeneity's fatigue table is refused, not ignored.
    let cfg = write(
        dir.path(),
        "contact3d_fatigue.toml",
        &format!(
            "indenter = \"sphere:R=1e-4\"\nmaterial = \"homogeneous:E=210e9,nu=0.3\"\nforce = 0.08\n\
             grid = 16\n{sphere}fatigue = {{ f_minus1 = 3e8 }}\n"
        ),
    );
    refused(
        "contact3d inhomogeneity fatigue",
        &strings(&["contact3d", "--config", &cfg, "--out", &format!("{o}.npz")]),
        &[],
        &["[[inhomogeneity]] 1", "fatigue", "does not read"],
    );
    for (name, text, needles) in &loop_cases {
        let cfg = write(
            dir.path(),
            &format!("{}.toml", name.replace(' ', "_")),
            text,
        );
        refused(
            &format!("fretting-loop {name}"),
            &strings(&["fretting-loop", "--config", &cfg, "--out", o]),
            &[],
            needles,
        );
    }
    let wear_cases: Vec<(&str, String, Vec<&str>)> = vec![
        ("no wear table", "friction = 0.3\n".into(), vec!["[wear]"]),
        ("law", wear.replace("archard", "hardness"), vec!["hardness"]),
        (
            "coefficient",
            wear.replace("1e-15", "-1e-15"),
            vec!["coefficient"],
        ),
        (
            "cycles",
            wear.replace("cycles = 10", "cycles = 0"),
            vec!["cycles"],
        ),
        (
            "inhomogeneity fatigue in wear",
            format!("{sphere}fatigue = {{ f_minus1 = 3e8 }}\n{wear}"),
            vec!["[[inhomogeneity]] 1", "fretting-loop"],
        ),
        (
            "fatigue in wear",
            format!("{fatigue}{wear}"),
            vec!["[fatigue]"],
        ),
        (
            "both loads",
            format!("force = 0.08\napproach = 1e-7\n{wear}"),
            vec!["approach"],
        ),
        (
            "EIM factor",
            format!("layout = \"fibre-centred\"\neim_change_factor = 2\n{wear}"),
            vec!["eim_change_factor", "(0, 1]", "2"],
        ),
        (
            "EIM recycled depth",
            format!("layout = \"fibre-centred\"\neim_recycled_depth = 1000\n{wear}"),
            vec!["eim_recycled_depth", "0..=50", "1000"],
        ),
        (
            "negative EIM recycled depth",
            format!("layout = \"fibre-centred\"\neim_recycled_depth = -1\n{wear}"),
            vec!["eim_recycled_depth"],
        ),
        (
            "alternation scheme",
            format!("alternation = \"fast\"\n{wear}"),
            vec!["alternation = \"fast\"", "\"plain\" or \"gauged\""],
        ),
    ];
    // A checkpoint interval beyond what a duration holds: refused, not a panic.
    let cfg = write(dir.path(), "plain.toml", "friction = 0.3\n");
    refused(
        "fretting-loop checkpoint interval",
        &strings(&[
            "fretting-loop",
            "--config",
            &cfg,
            "--out",
            o,
            "--checkpoint-seconds",
            "1e20",
        ]),
        &[],
        &["--checkpoint-seconds", "duration"],
    );
    for (name, text, needles) in &wear_cases {
        let cfg = write(
            dir.path(),
            &format!("w_{}.toml", name.replace(' ', "_")),
            text,
        );
        refused(
            &format!("fretting-wear3d {name}"),
            &strings(&["fretting-wear3d", "--config", &cfg, "--out", o]),
            &[],
            needles,
        );
        // The work estimate reads the same case: the same one-line refusal, nothing run.
        refused(
            &format!("fretting-wear3d --estimate {name}"),
            &strings(&[
                "fretting-wear3d",
                "--config",
                &cfg,
                "--out",
                o,
                "--estimate",
            ]),
            &[],
            needles,
        );
    }
    // A grid beyond the machine's memory is refused before the run directory is claimed.
    let cfg = write(dir.path(), "w_grid.toml", wear);
    refused(
        "fretting-wear3d grid",
        &strings(&[
            "fretting-wear3d",
            "--config",
            &cfg,
            "--out",
            o,
            "--grid",
            "100000",
        ]),
        &[],
        &["GiB"],
    );
    assert!(!out.join("run.json").exists());
    assert!(!out.join("results.h5").exists());
}
