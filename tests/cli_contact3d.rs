//! `halfspace contact3d` and `halfspace fretting-loop` through the binary.

mod common;

use common::{bad, ok_json, run, stopped_and_resumed};

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
    // a = 3.0111 μm, p0 = 4213 MPa, δ = 0.086348 μm (docs/theory-sam.md#hertz-reference); 64² over 4a.
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
    args.extend([
        "--force",
        "0.08",
        "--grid",
        "48",
        "--shift-x",
        "0.01e-6",
        "--friction",
        "0.3",
    ]);
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
        "enlarge the domain extent (--extent)",
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
            "--friction",
            "0.3",
        ],
        "gross slip",
    );
    // A tangential load needs a friction coefficient (the default is frictionless).
    bad(
        &[
            "contact3d",
            "--indenter",
            "sphere:R=105e-6",
            "--material",
            m,
            "--force",
            "0.08",
            "--shift-x",
            "1e-8",
        ],
        "--friction",
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
        "profiles_x.svg",
        "profiles_y.svg",
        "slip_B.svg",
        "shear_x_map_B.svg",
        "transverse_slip_map_B.svg",
        "von_mises_A.svg",
        "von_mises_D.svg",
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

/// `contact3d` on the Hertz case of the composite paper, 64² over 4a, with extra arguments.
fn hertz_with(extra: &[&str]) -> std::process::Output {
    let mut args = BASE.to_vec();
    args.extend(["--force", "0.08", "--grid", "64"]);
    args.extend(extra);
    run(&args)
}

#[test]
fn a_stiff_sphere_below_the_contact_with_subsurface_stresses_and_volume_output() {
    // docs/theory-sam.md#inhomogeneity-references (Leroux-2010-type case): r = 0.3a, centre depth 0.5a, E_I = 2E, a = 3.0111 μm:
    // p_max/p₀ = 1.277 at 2Δ = a/16 (the library test reproduces it to 4 digits).
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("inh.h5");
    let v = ok_json(&hertz_with(&[
        "--inhomogeneity",
        "sphere:x=0,y=0,z=1.50554e-6,r=0.90332e-6,E=420e9,nu=0.3",
        "--subsurface",
        "3e-6",
        "--out",
        out.to_str().unwrap(),
    ]));
    let p0 = 4212.98e6;
    assert!(
        (v["max_pressure"].as_f64().unwrap() / p0 - 1.2773).abs() < 5e-4,
        "{v}"
    );
    for key in [
        "inclusion_cells",
        "layers",
        "eim_iterations",
        "outer_iterations",
        "min_eigen_displacement",
        "max_von_mises",
        "max_von_mises_at",
        "max_tresca",
        "max_tresca_at",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["inclusion_cells"], 480);
    // A Σ p_c / W: −0.5 % on this ±2a domain (the truncation monitor of docs/theory-sam.md#domain-size-and-truncation).
    assert!(
        v["correction_pressure_integral_over_force"]
            .as_f64()
            .unwrap()
            .abs()
            < 0.02
    );
    assert!(v["min_eigen_displacement"].as_f64().unwrap() < 0.0);
    let rec = halfspace::data::read_record(&out).unwrap();
    let layers = v["subsurface_layers"].as_u64().unwrap() as usize;
    assert_eq!(rec.shape_of("von_mises").unwrap(), vec![layers, 64, 64]);
    let eig = rec.get("eigenstrain_zz").unwrap();
    assert_eq!(eig.iter().filter(|e| **e != 0.0).count(), 480);
    assert!(out.with_extension("xdmf").is_file());
}

#[test]
fn hertz_subsurface_maximum_shear_is_johnsons() {
    // τ₁max = σ_Tresca/2 = 0.31 p₀ at z = 0.48a (Johnson 1985, Eq. 3.45; ν = 0.3).
    let v = ok_json(&hertz_with(&["--subsurface", "2.5e-6"]));
    let p0 = 4212.98e6;
    let a = 3.0111e-6;
    let tau = 0.5 * v["max_tresca"].as_f64().unwrap() / p0;
    let z = v["max_tresca_at"][2].as_f64().unwrap() / a;
    assert!((tau - 0.310).abs() < 3e-3, "τ1max/p0 = {tau}");
    assert!((z - 0.48).abs() < 0.05, "at z/a = {z}");
    assert!(v.get("inclusion_cells").is_none());
}

#[test]
fn bad_inhomogeneities_exit_2_with_the_reason() {
    for (spec, needle) in [
        ("blob:x=0", "unknown inhomogeneity"),
        ("sphere:x=0,y=0,z=1e-6,E=4e11,nu=0.3", "missing key 'r'"),
        (
            "sphere:x=0,y=0,z=-1e-6,r=1e-7,E=4e11,nu=0.3",
            "above the surface",
        ),
        ("sphere:x=0,y=0,z=1e-6,r=-1e-7,E=4e11,nu=0.3", "size"),
        ("sphere:x=0,y=0,z=1e-6,r=1e-7,E=4e11,nu=0.6", "Poisson"),
        ("sphere:x=5.9e-6,y=0,z=1e-6,r=5e-7,E=4e11,nu=0.3", "domain"),
        ("cylinder:axis=z,x=0,z=1e-6,r=1e-7,E=4e11,nu=0.3", "axis"),
        (
            "cuboid:x=0,y=0,z=1e-6,hx=1e-7,hy=1e-7,E=4e11,nu=0.3",
            "missing key 'hz'",
        ),
        (
            "sphere:x=0,y=0,z=1e-6,r=3e-7,E=4e11,nu=0.3,w=1",
            "unknown key 'w'",
        ),
    ] {
        let mut args = BASE.to_vec();
        args.extend(["--force", "0.08", "--grid", "64", "--inhomogeneity", spec]);
        bad(&args, needle);
    }
    let mut args = BASE.to_vec();
    args.extend([
        "--force",
        "0.08",
        "--grid",
        "64",
        "--inhomogeneity",
        "sphere:x=0,y=0,z=1.5e-6,r=8e-7,E=4e11,nu=0.3",
        "--inhomogeneity",
        "sphere:x=5e-7,y=0,z=1.5e-6,r=8e-7,E=1e11,nu=0.3",
    ]);
    bad(&args, "overlapping");
    let mut args = BASE.to_vec();
    args.extend(["--force", "0.08", "--grid", "64", "--subsurface", "-1"]);
    bad(&args, "--subsurface");
}

/// Requests that cannot fit in memory are refused up front with the estimate (exit 2), instead of
/// aborting in the allocator or being killed; a tight `HALFSPACE_MEMORY_LIMIT` refuses a grid that
/// would otherwise run.
#[test]
fn requests_beyond_memory_are_refused_with_the_estimate() {
    let m = "homogeneous:E=210e9,nu=0.3";
    let base = [
        "--indenter",
        "sphere:R=105e-6",
        "--material",
        m,
        "--force",
        "0.08",
    ];
    let mut args = vec!["contact3d", "--grid", "100000"];
    args.extend(base);
    bad(&args, "needs about");
    bad(
        &[
            "axisym",
            "--profile",
            "sphere:R=1e-2",
            "--material",
            m,
            "--force",
            "10",
            "--n",
            "2000000000",
        ],
        "needs about",
    );
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_halfspace"))
        .env("HALFSPACE_MEMORY_LIMIT", "1e6")
        .args(["contact3d", "--grid", "128"])
        .args(base)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("needs about") && err.contains("GiB"), "{err}");
}

/// With inhomogeneities the homogeneous reference loop runs beside the nested one, so the
/// up-front memory check counts both: a limit between the nested loop's estimate and the sum is
/// refused, saying so, before the output directory is touched.
#[test]
fn the_composite_loop_with_its_reference_beside_is_checked_for_memory_up_front() {
    let cfg: halfspace::cases::config::LoopConfig = serde_json::from_str("{}").unwrap();
    let case = cfg.case("composite", Some(32)).unwrap();
    let own = case.estimate().bytes;
    let both = own + case.homogeneous().estimate().bytes;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_halfspace"))
        .env(
            "HALFSPACE_MEMORY_LIMIT",
            format!("{:e}", 0.5 * (own + both)),
        )
        .args([
            "fretting-loop",
            "--case",
            "composite",
            "--grid",
            "32",
            "--json",
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{err}");
    assert!(
        err.contains("homogeneous reference loop beside it"),
        "{err}"
    );
    assert!(!out.exists());
}

/// The composite fretting loop ([LN11]'s fibres, `--case composite`) on a reduced case (32², 14
/// increments; the paper's case is 128² and 180 increments): the stiff fibres raise the peak
/// pressure and shrink the contact against the homogeneous loop of the same config, the new JSON
/// keys are there; `[[inhomogeneity]]` tables go through the CLI's spec parser.
#[test]
fn composite_fretting_loop_on_a_reduced_case() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("loop.toml");
    std::fs::write(
        &cfg,
        "normal_steps = 4\namplitude = 0.04e-6\nshift_step = 0.02e-6\n",
    )
    .unwrap();
    let run_case = |case: &str| {
        let out = dir.path().join(case);
        ok_json(&run(&[
            "fretting-loop",
            "--case",
            case,
            "--grid",
            "32",
            "--config",
            cfg.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--json",
        ]))
    };
    let (hom, comp) = (run_case("homogeneous"), run_case("composite"));
    // The paper's figures, with and without the fibres, and the fields at A–D in the results.
    for f in [
        "shear_x_map_B.svg",
        "shear_x_map_B_homogeneous.svg",
        "transverse_slip_map_B_homogeneous.svg",
        "von_mises_B.svg",
    ] {
        assert!(dir.path().join("composite").join(f).is_file(), "{f}");
    }
    let rec =
        halfspace::data::read_record(&dir.path().join("composite").join("results.h5")).unwrap();
    for name in [
        "pressure_A",
        "homogeneous_pressure_A",
        "slip_y_B",
        "eigen_displacement_3_D",
        "pressure_along_y_C",
        "homogeneous_tangential_force",
    ] {
        assert!(rec.get(name).is_some(), "{name}");
    }
    assert_eq!(rec.shape_of("pressure_A"), Some(vec![32, 32]));
    assert_eq!(
        rec.shape_of("von_mises_B").map(|s| s[1..].to_vec()),
        Some(vec![32, 32])
    );
    let b = comp["breakdown"].as_object().unwrap();
    assert!(b["outer_iterations"].as_u64().unwrap() >= comp["increments"].as_u64().unwrap());
    assert!(b["eim_operator_applications"].as_u64().unwrap() > 0);
    for key in [
        "contact_area_over_hertz_end_of_normal_loading",
        "max_transverse_slip",
        "ratchet",
        "dissipated_energy",
    ] {
        assert!(comp[key].as_f64().unwrap().is_finite(), "{key}");
        assert!(hom[key].as_f64().unwrap().is_finite(), "{key}");
    }
    assert!(comp["inclusion_cells"].as_u64().unwrap() > 0);
    assert!(comp["layers"].as_u64().unwrap() >= 1);
    assert!(hom.get("inclusion_cells").is_none());
    let ratio = |key: &str| comp[key].as_f64().unwrap() / hom[key].as_f64().unwrap();
    // Measured at 32²: p_max ×1.064, contact area ×0.957 (the paper at 128²: > 1.2, ~0.93).
    assert!(ratio("max_pressure_over_p0_end_of_normal_loading") > 1.04);
    assert!(ratio("contact_area_over_hertz_end_of_normal_loading") < 0.99);
    // The composite run carries its homogeneous reference (the same loop without fibres).
    let own = |key: &str| comp[key].as_f64().unwrap();
    let r = ratio("max_pressure_over_p0_end_of_normal_loading");
    assert!((own("max_pressure_ratio_to_homogeneous") - r).abs() < 1e-12 * r);
    let r = ratio("dissipated_energy");
    assert!((own("dissipated_energy_ratio_to_homogeneous") - r).abs() < 1e-12 * r);
    assert_eq!(comp["homogeneous"]["ratchet"], hom["ratchet"]);
    // One stiff sphere from a TOML table; a table without kind is refused.
    std::fs::write(
        &cfg,
        "grid = 32\nnormal_steps = 2\nshift_step = 0.02e-6\n\n[[inhomogeneity]]\nkind = \"sphere\"\nx = 0.0\ny = 0.0\nz = 2e-6\nr = 0.9e-6\nE = 420e9\nnu = 0.3\n",
    )
    .unwrap();
    let out = dir.path().join("sphere");
    let v = ok_json(&run(&[
        "fretting-loop",
        "--config",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]));
    assert!(v["inclusion_cells"].as_u64().unwrap() > 0);
    std::fs::write(&cfg, "grid = 32\n[[inhomogeneity]]\nx = 0.0\n").unwrap();
    bad(
        &[
            "fretting-loop",
            "--config",
            cfg.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        "[[inhomogeneity]]`: missing field `kind`",
    );
    bad(
        &[
            "fretting-loop",
            "--case",
            "laminate",
            "--out",
            out.to_str().unwrap(),
        ],
        "--case",
    );
}

/// A composite fretting loop killed twice (during the normal ramp, then during the cycle) and
/// resumed gives the uninterrupted run's results bit for bit; a re-run into a directory holding a
/// checkpoint is refused, as is a resume with another configuration.
#[test]
fn composite_loop_resumes_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("loop.toml");
    std::fs::write(
        &cfg,
        "normal_steps = 4\namplitude = 0.04e-6\nshift_step = 0.02e-6\n",
    )
    .unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let args = |out: &std::path::Path, extra: &[&str]| {
        let mut v = vec![
            "fretting-loop".to_string(),
            "--case".into(),
            "composite".into(),
            "--grid".into(),
            "32".into(),
            "--config".into(),
            cfg.to_str().unwrap().into(),
            "--out".into(),
            out.to_str().unwrap().into(),
        ];
        v.extend(extra.iter().map(|s| s.to_string()));
        v
    };
    // Stopped during the normal ramp (3), then during the cycle (9); in between, a resume with
    // another configuration (grid 34) is refused.
    let another = |b: &std::path::Path| {
        bad(
            &[
                "fretting-loop",
                "--case",
                "composite",
                "--grid",
                "34",
                "--config",
                cfg.to_str().unwrap(),
                "--out",
                b.to_str().unwrap(),
                "--resume",
            ],
            "another configuration",
        )
    };
    let (full, resumed) =
        stopped_and_resumed(args, (&a, &b), &["3", "9"], Some("checkpoint.npz"), another);
    assert!(!a.join("checkpoint.npz").exists());
    for key in [
        "dissipated_energy",
        "ratchet",
        "max_transverse_slip",
        "max_pressure_over_p0_end_of_normal_loading",
    ] {
        assert_eq!(full[key], resumed[key], "{key}");
    }
    assert!(!b.join("checkpoint.npz").exists());
}

/// `contact3d` with an inhomogeneity, friction and a prescribed tangential force (issue 11): the
/// nested loop under force control reaches Q within the search tolerance, and a displacement-
/// controlled run to the shift it found gives the same Q and pressure.
#[test]
fn a_stiff_sphere_under_a_tangential_force() {
    let sphere = "sphere:x=0,y=0,z=1.50554e-6,r=0.90332e-6,E=420e9,nu=0.3";
    let with = |extra: &[&str]| {
        let mut args = BASE.to_vec();
        args.extend([
            "--force",
            "0.08",
            "--grid",
            "32",
            "--friction",
            "0.3",
            "--inhomogeneity",
            sphere,
        ]);
        args.extend(extra);
        ok_json(&run(&args))
    };
    let q = 0.5 * 0.3 * 0.08;
    let v = with(&["--tangential-force", "0.012"]);
    let got = v["tangential_force"].as_f64().unwrap();
    assert!((got - q).abs() <= 1e-6 * 0.3 * 0.08 * 1.01, "{got} vs {q}");
    assert!(v["outer_iterations"].as_u64().unwrap() >= 1);
    let shift = v["shift_x"].as_f64().unwrap();
    let d = with(&["--shift-x", &format!("{shift:e}")]);
    let dq = (d["tangential_force"].as_f64().unwrap() - got).abs();
    assert!(dq < 1e-4 * q, "Q at the found shift differs by {dq:e}");
    let dp =
        (d["max_pressure"].as_f64().unwrap() / v["max_pressure"].as_f64().unwrap() - 1.0).abs();
    assert!(dp < 1e-5, "{dp:e}");
}
