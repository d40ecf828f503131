//! `halfspace contact3d` and `halfspace fretting-loop` through the binary.

mod common;

use common::{bad, ok_json, run};

const BASE: [&str; 6] = [
    "contact3d",
    "--indenter",
    "sphere:R=105e-6",
    "--material",
    "homogeneous:E=210e9,nu=0.3",
    "--json",
];

#[test]
fn hertz_frictionless_and_with_a_tangential_force() {
    let mut args = BASE.to_vec();
    args.extend(["--force", "0.08", "--friction", "0", "--grid", "64"]);
    let v = ok_json(&run(&args));
    for key in [
        "contact_radius",
        "contact_area",
        "max_pressure",
        "force",
        "depth",
        "tangential_force",
        "stick_radius",
        "iterations",
        "residual",
        "seconds",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    // a = 3.0111 μm, p0 = 4213 MPa, δ = 0.086348 μm (spec §7.1); 64² over 4a.
    assert!((v["max_pressure"].as_f64().unwrap() / 4213.0e6 - 1.0).abs() < 2e-3);
    assert!((v["depth"].as_f64().unwrap() / 0.086348e-6 - 1.0).abs() < 1e-3);
    assert!((v["contact_radius"].as_f64().unwrap() / 3.0111e-6 - 1.0).abs() < 0.02);
    // Depth control gives the force back.
    let mut args = BASE.to_vec();
    args.extend(["--depth", "0.086348e-6", "--friction", "0", "--grid", "64"]);
    let v = ok_json(&run(&args));
    assert!((v["force"].as_f64().unwrap() / 0.08 - 1.0).abs() < 2e-3);
    // Shift and force control with friction, coupling on (rigid sphere).
    let mut args = BASE.to_vec();
    args.extend(["--force", "0.08", "--grid", "48", "--shift-x", "0.01e-6"]);
    let v = ok_json(&run(&args));
    assert!(v["tangential_force"].as_f64().unwrap() > 0.0);
    assert!(v["stick_radius"].as_f64().unwrap() < v["contact_radius"].as_f64().unwrap());
    assert_eq!(v["coupled"], true);
}

#[test]
fn other_indenters_and_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("f.npz");
    let v = ok_json(&run(&[
        "contact3d",
        "--indenter",
        "ellipsoid:Rx=100e-6,Ry=200e-6",
        "--material",
        "homogeneous:E=210e9,nu=0.3",
        "--force",
        "0.05",
        "--grid",
        "48",
        "--friction",
        "0",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]));
    assert!(v["contact_area"].as_f64().unwrap() > 0.0);
    let rec = halfspace::data::read_record(&out).unwrap();
    assert_eq!(rec.get("pressure").unwrap().len(), 48 * 48);
    for spec in ["cone:slope=0.05", "flat:a=5e-6"] {
        ok_json(&run(&[
            "contact3d",
            "--indenter",
            spec,
            "--material",
            "homogeneous:E=210e9,nu=0.3",
            "--force",
            "0.05",
            "--grid",
            "48",
            "--friction",
            "0",
            "--json",
        ]));
    }
}

#[test]
fn bad_input_exits_2() {
    let m = "homogeneous:E=210e9,nu=0.3";
    bad(
        &[
            "contact3d",
            "--indenter",
            "sphere:R=-1",
            "--material",
            m,
            "--force",
            "0.08",
        ],
        "R must be",
    );
    bad(
        &[
            "contact3d",
            "--indenter",
            "sphere:R=1e-4",
            "--material",
            "homogeneous:E=210e9,nu=0.7",
            "--force",
            "0.08",
        ],
        "Poisson",
    );
    bad(
        &[
            "contact3d",
            "--indenter",
            "sphere:R=1e-4",
            "--material",
            m,
            "--force",
            "0",
        ],
        "--force",
    );
    bad(
        &[
            "contact3d",
            "--indenter",
            "sphere:R=1e-4",
            "--material",
            m,
            "--force",
            "0.08",
            "--friction",
            "-1",
        ],
        "--friction",
    );
    bad(
        &[
            "contact3d",
            "--indenter",
            "sphere:R=1e-4",
            "--material",
            m,
            "--force",
            "0.08",
            "--grid",
            "4",
        ],
        "≥ 8",
    );
    bad(
        &[
            "contact3d",
            "--indenter",
            "sphere:R=105e-6",
            "--material",
            m,
            "--force",
            "0.08",
            "--grid",
            "32",
            "--extent",
            "4e-6",
        ],
        "enlarge --extent",
    );
    bad(
        &[
            "contact3d",
            "--indenter",
            "sphere:R=105e-6",
            "--material",
            m,
            "--force",
            "0.08",
            "--grid",
            "32",
            "--tangential-force",
            "0.05",
        ],
        "gross slip",
    );
    bad(
        &[
            "contact3d",
            "--indenter",
            "table:/nonexistent.npy",
            "--material",
            m,
            "--force",
            "0.08",
            "--extent",
            "1e-5",
        ],
        "nonexistent.npy",
    );
    bad(
        &[
            "contact3d",
            "--indenter",
            "table:x.npy",
            "--material",
            m,
            "--force",
            "0.08",
        ],
        "--extent",
    );
    bad(
        &[
            "contact3d",
            "--indenter",
            "blob:R=1",
            "--material",
            m,
            "--force",
            "0.08",
        ],
        "unknown indenter",
    );
}

#[test]
fn fretting_loop_runs_on_a_small_grid() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("loop.toml");
    std::fs::write(&cfg, "grid = 32\nnormal_steps = 4\nshift_step = 0.01e-6\n").unwrap();
    let out = dir.path().join("loop");
    let v = ok_json(&run(&[
        "fretting-loop",
        "--config",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]));
    assert_eq!(v["increments"], 4 + 4 + 8 + 8);
    assert!(v["dissipated_energy"].as_f64().unwrap() > 0.0);
    for f in [
        "results.h5",
        "fretting_loop.png",
        "fretting_loop.svg",
        "fretting_profiles.svg",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    std::fs::write(&cfg, "grid = 32\nbogus = 1\n").unwrap();
    bad(
        &[
            "fretting-loop",
            "--config",
            cfg.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        "bogus",
    );
}
