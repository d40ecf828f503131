//! The `halfspace axisym` contract (design.md) through the binary: the worked example of the
//! composite paper, the output files, and exit code 2 with one line on stderr for bad input.

use std::path::Path;
use std::process::Output;

mod common;

use common::run;

use halfspace::data::{read_record, AttrValue};
use halfspace::mdr::analytic;
use ndarray::Array2;
use ndarray_npy::WriteNpyExt;

fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "exit {:?}: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object on stdout")
}

const HERTZ: [&str; 7] = [
    "axisym",
    "--profile",
    "sphere:R=105e-6",
    "--material",
    "homogeneous:E=210e9,nu=0.3",
    "--force",
    "0.08",
];

/// R = 105 μm, E = 210 GPa, ν = 0.3, W = 80 mN → a = 3.011 μm, p0 = 4213 MPa.
#[test]
fn worked_example_of_the_composite_paper() {
    for method in ["fft", "mvm"] {
        let mut args = HERTZ.to_vec();
        args.extend(["--method", method, "--json"]);
        let v = json(&run(&args));
        let a = v["contact_radius"].as_f64().unwrap();
        let p0 = v["max_pressure"].as_f64().unwrap();
        assert!((a / 3.011e-6 - 1.0).abs() < 2e-3, "{method}: a = {a}");
        assert!((p0 / 4213e6 - 1.0).abs() < 5e-3, "{method}: p0 = {p0}");
        // And against the closed form itself, far tighter.
        let e_star = 210e9 / (1.0 - 0.09);
        let a_exact = analytic::sphere_radius_for_force(0.08, 105e-6, e_star);
        assert!((a / a_exact - 1.0).abs() < 1e-10, "{method}");
        for key in [
            "contact_radius",
            "depth",
            "force",
            "max_pressure",
            "mean_pressure",
            "n",
            "method",
            "k",
        ] {
            assert!(v.get(key).is_some(), "missing JSON key {key}");
        }
        assert_eq!(v["method"], method);
        assert_eq!(v["n"], 2001);
        assert_eq!(v["k"], 0.0);
        let mean = v["mean_pressure"].as_f64().unwrap();
        assert!(
            (mean / p0 - 2.0 / 3.0).abs() < 1e-9,
            "Hertz: mean = 2/3 max"
        );
    }
}

fn check_record(path: &Path) {
    let rec = read_record(path).unwrap();
    let r = rec.get("r").unwrap();
    for name in ["pressure", "displacement", "x", "g"] {
        assert_eq!(rec.get(name).unwrap().len(), r.len(), "{name}");
    }
    assert_eq!(
        rec.get_attr("profile"),
        Some(&AttrValue::Text("sphere:R=105e-6".into()))
    );
    let a = match rec.get_attr("contact_radius") {
        Some(AttrValue::Float(a)) => *a,
        other => panic!("contact_radius attribute: {other:?}"),
    };
    // The written fields against Hertz: pressure inside, displacement inside and outside.
    let e_star = 210e9 / 0.91;
    let (p, u) = (
        rec.get("pressure").unwrap(),
        rec.get("displacement").unwrap(),
    );
    let p0 = analytic::sphere_pressure(0.0, a, 105e-6, e_star);
    let depth = analytic::sphere_depth(a, 105e-6);
    for (i, &ri) in r.iter().enumerate() {
        let pe = analytic::sphere_pressure(ri, a, 105e-6, e_star);
        assert!((p[i] - pe).abs() < 1e-9 * p0, "p at r = {ri}");
        let ue = analytic::sphere_displacement(ri, a, 105e-6);
        // Eq. 13 (fft) on the Hertz U: max error 1.2e-6 δ at N = 2001 (tests in crates/mdr).
        assert!(
            (u[i] - ue).abs() < 5e-6 * depth,
            "u at r = {ri}: {} vs {ue}",
            u[i]
        );
    }
}

#[test]
fn out_files_hold_the_fields_and_the_inputs() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["hertz.npz", "hertz.h5"] {
        let path = dir.path().join(name);
        let mut args = HERTZ.to_vec();
        let p = path.to_str().unwrap().to_string();
        args.extend(["--out", &p, "--json"]);
        json(&run(&args));
        check_record(&path);
    }
}

#[test]
fn plot_is_an_svg() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.svg");
    let mut args = HERTZ.to_vec();
    let p = path.to_str().unwrap().to_string();
    args.extend(["--plot", &p]);
    let out = run(&args);
    assert!(out.status.success());
    let svg = std::fs::read_to_string(&path).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("polyline"));
}

fn table(dir: &Path, name: &str, rows: &[[f64; 2]]) -> String {
    let path = dir.join(name);
    let arr =
        Array2::from_shape_vec((rows.len(), 2), rows.iter().flatten().copied().collect()).unwrap();
    arr.write_npy(std::fs::File::create(&path).unwrap())
        .unwrap();
    path.to_str().unwrap().to_string()
}

fn assert_bad(args: &[&str], needle: &str) {
    let out = run(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
    assert!(out.stdout.is_empty(), "{args:?} printed to stdout");
    assert!(
        stderr.contains(needle),
        "{args:?}: stderr {stderr:?} lacks {needle:?}"
    );
    if !needle.starts_with("--") && !stderr.contains("Usage") {
        assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
    }
}

#[test]
fn bad_input_exits_2_with_one_line() {
    let base = |profile: &str, material: &str, load: &[&str]| -> Vec<String> {
        let mut v: Vec<String> = ["axisym", "--profile", profile, "--material", material]
            .iter()
            .map(|s| s.to_string())
            .collect();
        v.extend(load.iter().map(|s| s.to_string()));
        v
    };
    let steel = "homogeneous:E=210e9,nu=0.3";
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            base("sphere:R=-1", steel, &["--force", "0.08"]),
            "sphere radius R",
        ),
        (
            base("sphere:R=nan", steel, &["--force", "0.08"]),
            "sphere radius R",
        ),
        (
            base("sphere:R=inf", steel, &["--force", "0.08"]),
            "sphere radius R",
        ),
        (
            base("sphere:R=1e-4", "homogeneous:E=0,nu=0.3", &["--force", "1"]),
            "Young's modulus",
        ),
        (
            base("sphere:R=1e-4", "homogeneous:Estar=-5", &["--force", "1"]),
            "contact modulus",
        ),
        (
            base(
                "sphere:R=1e-4",
                "homogeneous:E=1e9,nu=0.6",
                &["--force", "1"],
            ),
            "Poisson",
        ),
        (
            base(
                "sphere:R=1e-4",
                "homogeneous:E=1e9,nu=-1",
                &["--force", "1"],
            ),
            "Poisson",
        ),
        (
            base("sphere:R=1e-4", steel, &["--force", "0"]),
            "normal force",
        ),
        (
            base("sphere:R=1e-4", steel, &["--force", "-1"]),
            "normal force",
        ),
        (
            base("sphere:R=1e-4", steel, &["--depth", "nan"]),
            "indentation depth",
        ),
        (
            base("sphere:R=1e-4", steel, &["--depth", "1e-6", "--n", "7"]),
            "at least 8",
        ),
        (
            base("cone:slope=0", steel, &["--depth", "1e-6"]),
            "cone slope",
        ),
        (
            base("flat:a=-1", steel, &["--depth", "1e-6"]),
            "punch radius",
        ),
        (
            base("power:c=1,n=0.5", steel, &["--depth", "1e-6"]),
            "exponent n",
        ),
        (
            base("sphere:R=1e-4,X=1", steel, &["--depth", "1e-6"]),
            "unknown key 'X'",
        ),
        (
            base("ellipse:R=1", steel, &["--depth", "1e-6"]),
            "unknown profile",
        ),
        (
            base(
                "sphere:R=1e-4",
                steel,
                &["--depth", "1e-6", "--out", "x.csv"],
            ),
            "unknown format",
        ),
        (
            base("table:/nonexistent/t.npy", steel, &["--depth", "1e-6"]),
            "/nonexistent/t.npy",
        ),
    ];
    for (args, needle) in &cases {
        let args: Vec<&str> = args.iter().map(|s| s.as_str()).collect();
        assert_bad(&args, needle);
    }
    // Both loads, or none: clap's usage error, also exit 2.
    assert_bad(
        &base("sphere:R=1", steel, &["--depth", "1", "--force", "1"])
            .iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>(),
        "--depth",
    );
    assert_bad(
        &base("sphere:R=1", steel, &[])
            .iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>(),
        "--depth",
    );
}

#[test]
fn bad_tables_exit_2_naming_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let steel = "homogeneous:E=210e9,nu=0.3";
    let cases = [
        (table(d, "empty.npy", &[]), "at least 3 rows"),
        (
            table(d, "order.npy", &[[0.0, 0.0], [2e-6, 1e-9], [1e-6, 2e-9]]),
            "increase",
        ),
        (
            table(d, "start.npy", &[[1e-7, 0.0], [1e-6, 1e-9], [2e-6, 2e-9]]),
            "start at r = 0",
        ),
        (
            table(d, "nan.npy", &[[0.0, 0.0], [1e-6, f64::NAN], [2e-6, 2e-9]]),
            "non-finite",
        ),
    ];
    for (path, needle) in &cases {
        let spec = format!("table:{path}");
        assert_bad(
            &[
                "axisym",
                "--profile",
                &spec,
                "--material",
                steel,
                "--depth",
                "1e-9",
            ],
            needle,
        );
    }
    // Wrong shape and dtype.
    let shape = d.join("shape.npy");
    Array2::<f64>::zeros((4, 3))
        .write_npy(std::fs::File::create(&shape).unwrap())
        .unwrap();
    let dtype = d.join("dtype.npy");
    Array2::<i32>::zeros((4, 2))
        .write_npy(std::fs::File::create(&dtype).unwrap())
        .unwrap();
    for (path, needle) in [(shape, "shape"), (dtype, "dtype")] {
        let spec = format!("table:{}", path.display());
        assert_bad(
            &[
                "axisym",
                "--profile",
                &spec,
                "--material",
                steel,
                "--depth",
                "1e-9",
            ],
            needle,
        );
    }
    // Contact beyond the table, and a non-convex table.
    let rows: Vec<[f64; 2]> = (0..51)
        .map(|i| {
            let r = i as f64 * 1e-7;
            [r, r * r / 2e-4]
        })
        .collect();
    let short = table(d, "short.npy", &rows);
    assert_bad(
        &[
            "axisym",
            "--profile",
            &format!("table:{short}"),
            "--material",
            steel,
            "--depth",
            "1e-6",
        ],
        "table",
    );
    let rows: Vec<[f64; 2]> = (0..121)
        .map(|i| {
            let r = i as f64 * 0.01;
            [r, r * r - r.powi(4)]
        })
        .collect();
    let bump = table(d, "bump.npy", &rows);
    assert_bad(
        &[
            "axisym",
            "--profile",
            &format!("table:{bump}"),
            "--material",
            "homogeneous:Estar=1",
            "--depth",
            "0.6",
        ],
        "non-convex",
    );
}

#[test]
fn a_table_sampled_from_a_sphere_matches_hertz() {
    let dir = tempfile::tempdir().unwrap();
    let rows: Vec<[f64; 2]> = (0..401)
        .map(|i| {
            let r = i as f64 * 2e-8;
            [r, r * r / (2.0 * 105e-6)]
        })
        .collect();
    let path = table(dir.path(), "sphere.npy", &rows);
    let mut args = HERTZ.to_vec();
    let spec = format!("table:{path}");
    args[2] = &spec;
    args.push("--json");
    let v = json(&run(&args));
    let a = v["contact_radius"].as_f64().unwrap();
    let a_exact = analytic::sphere_radius_for_force(0.08, 105e-6, 210e9 / 0.91);
    // Cubic Hermite interpolation is exact for a quadratic; the paraboloid split makes it exact.
    assert!((a / a_exact - 1.0).abs() < 1e-9, "a = {a} vs {a_exact}");
}

/// Graded Hertz through the binary (docs/theory-mdr.md#graded-closed-forms: E0 = z0 = R = 1, ν = 0.3, δ = 0.01).
#[test]
fn graded_hertz_through_the_binary() {
    for (k, a, f, p0) in [
        ("-0.5", 0.0707107, 3.4184152e-3, 0.27202884),
        ("0.5", 0.1224745, 4.0960844e-4, 1.5211282e-2),
    ] {
        for method in ["fft", "mvm"] {
            let material = format!("graded:E0=1,z0=1,nu=0.3,k={k}");
            let v = json(&run(&[
                "axisym",
                "--profile",
                "sphere:R=1",
                "--material",
                &material,
                "--depth",
                "0.01",
                "--n",
                "4001",
                "--method",
                method,
                "--json",
            ]));
            assert!((v["contact_radius"].as_f64().unwrap() / a - 1.0).abs() < 1e-6);
            assert!((v["force"].as_f64().unwrap() / f - 1.0).abs() < 1e-6);
            assert!((v["max_pressure"].as_f64().unwrap() / p0 - 1.0).abs() < 1e-6);
            assert_eq!(v["k"].as_f64().unwrap(), k.parse::<f64>().unwrap());
            assert!(v["c_n"].as_f64().is_some());
            let eq = if method == "fft" { "eq26" } else { "eq25" };
            assert_eq!(v["displacement_method"], eq);
        }
    }
    for bad in ["k=1", "k=-1", "k=nan", "k=2"] {
        let material = format!("graded:E0=1,z0=1,nu=0.3,{bad}");
        assert_bad(
            &[
                "axisym",
                "--profile",
                "sphere:R=1",
                "--material",
                &material,
                "--depth",
                "0.01",
            ],
            "grading exponent k",
        );
    }
    assert_bad(
        &[
            "axisym",
            "--profile",
            "sphere:R=1",
            "--material",
            "graded:E0=1,z0=0,nu=0.3,k=0.5",
            "--depth",
            "0.01",
        ],
        "reference depth z0",
    );
    assert_bad(
        &[
            "axisym",
            "--profile",
            "sphere:R=1",
            "--material",
            "graded:E0=-1,z0=1,nu=0.3,k=0.5",
            "--depth",
            "0.01",
        ],
        "modulus E0",
    );
    assert_bad(
        &[
            "axisym",
            "--profile",
            "sphere:R=1",
            "--material",
            "graded:E0=1,z0=1,nu=0.6,k=0.5",
            "--depth",
            "0.01",
        ],
        "Poisson",
    );
    // Eq. 13/26 cannot take a profile r^{3/2}: the error names the Eq. 12/25 alternative.
    assert_bad(
        &[
            "axisym",
            "--profile",
            "power:c=1,n=1.5",
            "--material",
            "graded:E0=1,z0=1,nu=0.3,k=0.5",
            "--depth",
            "0.01",
        ],
        "--method mvm",
    );
    let ok = run(&[
        "axisym",
        "--profile",
        "power:c=1,n=1.5",
        "--material",
        "graded:E0=1,z0=1,nu=0.3,k=0.5",
        "--depth",
        "0.01",
        "--method",
        "mvm",
        "--json",
    ]);
    json(&ok);
    // Eq. 25's tabulated kernel has a size limit; the error names Eq. 26 as the alternative.
    assert_bad(
        &[
            "axisym",
            "--profile",
            "sphere:R=1",
            "--material",
            "graded:E0=1,z0=1,nu=0.3,k=0.5",
            "--depth",
            "0.01",
            "--n",
            "9000",
            "--method",
            "mvm",
        ],
        "Eq. 26",
    );
}

/// The JSON summary without the wall-clock keys.
fn without_times(mut v: serde_json::Value) -> serde_json::Value {
    if let Some(o) = v.as_object_mut() {
        o.retain(|k, _| !k.contains("seconds"));
    }
    v
}

/// `--config FILE.toml` / `FILE.json` hold the flags' keys (docs/architecture.md, "The application
/// layer"): the same run as the flags, bit for bit; a flag overrides its key; unknown keys,
/// conflicting keys and wrong types are refused naming the key.
#[test]
fn config_files_are_the_flags_keys() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    // axisym: TOML and JSON equal the flags.
    let flags = without_times(json(&run(&[&HERTZ[..], &["--json"]].concat())));
    std::fs::write(
        path("a.toml"),
        "profile = \"sphere:R=105e-6\"\nmaterial = \"homogeneous:E=210e9,nu=0.3\"\nforce = 0.08\n",
    )
    .unwrap();
    std::fs::write(
        path("a.json"),
        r#"{"profile": "sphere:R=105e-6", "material": "homogeneous:E=210e9,nu=0.3", "force": 0.08}"#,
    )
    .unwrap();
    for file in ["a.toml", "a.json"] {
        let got = json(&run(&["axisym", "--config", &path(file), "--json"]));
        assert_eq!(without_times(got), flags, "{file}");
    }
    // A flag over the file's key.
    let over = json(&run(&[
        "axisym",
        "--config",
        &path("a.toml"),
        "--n",
        "801",
        "--json",
    ]));
    assert_eq!(over["n"], 801);
    assert_eq!(over["profile"], "sphere:R=105e-6");
    std::fs::write(
        path("t.toml"),
        "profile = { r = [0.0, 1e-4, 2e-4], f = [0.0, 1e-8, 4e-8] }\n\
         material = \"homogeneous:E=210e9,nu=0.3\"\ndepth = 1e-8\n",
    )
    .unwrap();
    let table = json(&run(&["axisym", "--config", &path("t.toml"), "--json"]));
    assert_eq!(table["profile"], "table");
    // contact3d: a file with an inhomogeneity table equals the flags with its spec.
    let c3 = [
        "contact3d",
        "--indenter",
        "sphere:R=105e-6",
        "--material",
        "homogeneous:E=210e9,nu=0.3",
        "--force",
        "0.08",
        "--grid",
        "32",
        "--json",
    ];
    let flags = without_times(json(&run(&[
        &c3[..],
        &[
            "--friction",
            "0.3",
            "--shift-x",
            "5e-9",
            "--inhomogeneity",
            "sphere:x=0,y=0,z=2.5e-6,r=1e-6,E=420e9,nu=0.3",
        ],
    ]
    .concat())));
    std::fs::write(
        path("c.toml"),
        "friction = 0.3\nshift_x = 5e-9\n\n[[inhomogeneity]]\nkind = \"sphere\"\n\
         x = 0.0\ny = 0.0\nz = 2.5e-6\nr = 1e-6\nE = 420e9\nnu = 0.3\n",
    )
    .unwrap();
    let got = json(&run(&[&c3[..], &["--config", &path("c.toml")]].concat()));
    assert_eq!(without_times(got), flags);
    // Refusals name the key.
    std::fs::write(path("u.toml"), "profile = \"sphere:R=1e-4\"\nforse = 1.0\n").unwrap();
    assert_bad(
        &["axisym", "--config", &path("u.toml")],
        "unknown field `forse`",
    );
    std::fs::write(path("w.toml"), "n = \"many\"\n").unwrap();
    assert_bad(&["axisym", "--config", &path("w.toml")], "n = \"many\"");
    assert_bad(
        &["axisym", "--config", &path("a.toml"), "--depth", "1e-7"],
        "exactly one of --force and --depth",
    );
    assert_bad(
        &[
            "contact3d",
            "--config",
            &path("c.toml"),
            "--material",
            "rigid",
        ],
        "give --indenter",
    );
}

/// The errors of a `study --json` series by name, and its observed order.
fn study_series(v: &serde_json::Value, name: &str) -> (Vec<f64>, f64) {
    let s = v["series"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["name"] == name)
        .unwrap_or_else(|| panic!("no series {name}: {v}"));
    let errors = s["errors"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e.as_f64().unwrap())
        .collect();
    (errors, s["observed_order"].as_f64().unwrap())
}

/// `halfspace study eq17` (docs/theory-mdr.md, the stress transform Eq. 17 on q = 1 − x⁴, mean
/// relative error Eq. 19): the FFT transform converges at order ≈ 1.5 (measured 1.49), reaching
/// 1.8e-8 at N = 100 001; the plot is an SVG.
#[test]
fn study_eq17_converges_at_order_one_and_a_half() {
    let dir = tempfile::tempdir().unwrap();
    let plot = dir.path().join("eq17.svg");
    let out = run(&["study", "eq17", "--json", "--plot", plot.to_str().unwrap()]);
    let v = json(&out);
    assert_eq!(
        v["n"],
        serde_json::json!([11, 101, 1001, 2001, 10001, 100001])
    );
    let (errors, order) = study_series(&v, "Eq. 17 (FFT)");
    assert!((1.4..1.6).contains(&order), "{order}");
    assert!(errors.windows(2).all(|w| w[1] < w[0]), "{errors:?}");
    assert!((1.0e-2..2.0e-2).contains(&errors[0]), "{errors:?}");
    assert!((1.0e-8..3.0e-8).contains(&errors[5]), "{errors:?}");
    assert!(std::fs::read_to_string(&plot).unwrap().starts_with("<svg"));
}

/// `halfspace study displacement` (Eqs. 12 and 13 on Hertz, a = 0.7, L = 1): both converge at
/// order ≈ 1.5 (measured 1.48), the FFT with the parabolic split at half the error of the dense
/// arccos kernel (max errors 1.8e-7 and 9.2e-8 at N = 10 001).
#[test]
fn study_displacement_converges_for_both_transforms() {
    let v = json(&run(&["study", "displacement", "--json"]));
    assert_eq!(v["n"], serde_json::json!([101, 301, 1001, 4001, 10001]));
    let (dense, dense_order) = study_series(&v, "Eq. 12 (arccos kernel)");
    let (fft, fft_order) = study_series(&v, "Eq. 13 (FFT, parabolic split)");
    for order in [dense_order, fft_order] {
        assert!((1.4..1.6).contains(&order), "{order}");
    }
    assert!((1.5e-7..2.2e-7).contains(&dense[4]), "{dense:?}");
    assert!((7.0e-8..1.1e-7).contains(&fft[4]), "{fft:?}");
    assert!(
        fft.iter().zip(&dense).all(|(f, d)| f < d),
        "{fft:?} {dense:?}"
    );
}

/// `halfspace study eq27` (Eqs. 25 and 26 on the graded pair U = x⁴, k = ±0.5): first order
/// (measured 0.95–1.00), mean relative errors at N = 4001 between 2.2e-4 and 9.6e-4; the FFT
/// (Eq. 26) below the 2F1 kernel (Eq. 25) at both k.
#[test]
fn study_eq27_converges_at_first_order() {
    let v = json(&run(&["study", "eq27", "--json"]));
    assert_eq!(v["n"], serde_json::json!([101, 301, 1001, 2001, 4001]));
    for k in ["−0.5", "0.5"] {
        let (fft, fft_order) = study_series(&v, &format!("Eq. 26 (FFT), k = {k}"));
        let (kernel, kernel_order) = study_series(&v, &format!("Eq. 25 (2F1 kernel), k = {k}"));
        for order in [fft_order, kernel_order] {
            assert!((0.9..1.1).contains(&order), "k = {k}: {order}");
        }
        assert!((2.0e-4..1.0e-3).contains(&fft[4]), "k = {k}: {fft:?}");
        assert!(fft[4] < kernel[4], "k = {k}: {fft:?} {kernel:?}");
    }
}

/// `study eim-operator --layers 0` names the flag; the library's message names the parameter.
#[test]
fn study_eim_operator_refuses_zero_layers_naming_the_flag() {
    assert_bad(
        &["study", "eim-operator", "--layers", "0"],
        "--layers: layers must be ≥ 1, got 0",
    );
}
