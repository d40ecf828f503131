//! `fretting-loop` with an elastic indenter, approach control and a `[fatigue]` table: the keys,
//! their errors, the JSON maxima and the volume fields of results.h5; resumed mid-cycle bit for
//! bit (docs/fatigue.md, "On the fretting loop").
mod common;

use common::{bad, ok_json, run, stopped_and_resumed, svg_with_labels};

const FATIGUE: &str =
    "[fatigue]\nf_minus1 = 400e6\nt_minus1 = 280e6\nfs_k = 0.5\nyield_stress = 600e6\n";

fn config(dir: &std::path::Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn bad_keys_are_refused_with_their_names() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("out");
    let o = o.to_str().unwrap();
    for (text, needle) in [
        ("force = 0.08\napproach = 1e-7\n", "exactly one of force"),
        ("indenter_e = 210e9\n", "indenter_nu"),
        ("indenter_e = -1.0\nindenter_nu = 0.3\n", "indenter_e"),
        ("[fatigue]\nf_minus1 = 400e6\n", "t_minus1"),
        (
            "[fatigue]\nf_minus1 = 400e6\nt_minus1 = 500e6\nfs_k = 0.5\nyield_stress = 6e8\n",
            "[fatigue]",
        ),
        (&format!("{FATIGUE}depth = 1.0\n"), "depth"),
        (
            &format!("{FATIGUE}screen_fraction = 2.0\n"),
            "screen_fraction",
        ),
    ] {
        let c = config(dir.path(), "bad.toml", text);
        bad(&["fretting-loop", "--config", &c, "--out", o], needle);
    }
}

#[test]
fn fatigue_maxima_and_fields_of_an_elastic_indenter_under_approach_control() {
    let dir = tempfile::tempdir().unwrap();
    // Identical steel bodies at the approach of W ≈ 80 mN (a = 3.76 μm, δ = a²/R).
    let text = format!(
        "grid = 16\nnormal_steps = 4\namplitude = 0.02e-6\nshift_step = 0.005e-6\n\
         subsurface_over_a = 0.0\nindenter_e = 210e9\nindenter_nu = 0.3\napproach = 1.35e-7\n\
         {FATIGUE}depth_over_a = 1.0\n"
    );
    let c = config(dir.path(), "loop.toml", &text);
    let (full, killed) = (dir.path().join("full"), dir.path().join("killed"));
    // Killed mid-cycle (4 normal + 4 + 3 shift increments) and resumed: the same results
    // (`stopped_and_resumed`); `j` is the uninterrupted run's JSON.
    let command = |out: &std::path::Path, extra: &[&str]| {
        let mut v = vec!["fretting-loop".to_string(), "--config".into(), c.clone()];
        v.extend(["--out".into(), out.to_str().unwrap().into()]);
        v.extend(extra.iter().map(|s| s.to_string()));
        v
    };
    let (j, j2) = stopped_and_resumed(command, (&full, &killed), &["11"], None, |_| {});
    for key in ["crossland", "dang_van", "swt", "fatemi_socie"] {
        let v = j[format!("{key}_max")].as_f64().unwrap();
        assert!(v.is_finite() && v > 0.0, "{key}_max = {v}");
        let at = j[format!("{key}_max_at")].as_array().unwrap();
        assert_eq!(at.len(), 3);
        assert!(at[2].as_f64().unwrap() >= 0.0, "{key}: z in the body");
    }
    let rec = halfspace::data::read_record(&full.join("results.h5")).unwrap();
    let z = rec.get("z").unwrap();
    let layers = z.len();
    assert!(layers >= 2);
    // The surface layer first (docs/fatigue.md, "The surface layer"), then (2k + 1)Δ.
    assert_eq!(z[0], 0.0);
    assert!((z[2] - 3.0 * z[1]).abs() < 1e-12 * z[2], "{z:?}");
    assert_eq!(j["fatigue"]["surface_layer"], true);
    for key in ["crossland", "dang_van", "swt", "fatemi_socie"] {
        assert_eq!(rec.shape_of(key).unwrap(), vec![layers, 16, 16]);
    }
    let crossland = rec.get("crossland").unwrap();
    let max = crossland.iter().copied().fold(f64::MIN, f64::max);
    assert_eq!(max, j["crossland_max"].as_f64().unwrap());
    let xdmf = std::fs::read_to_string(full.join("results.xdmf")).unwrap();
    assert!(xdmf.contains(&format!(
        r#"TopologyType="3DRectMesh" Dimensions="{layers} 16 16""#
    )));
    assert!(xdmf.contains("results.h5:/z") && xdmf.contains("results.h5:/crossland"));
    // The figures (docs/fatigue.md#figures): sections through each maximum, depth profile.
    for (key, unit) in [
        ("crossland", "Crossland index"),
        ("dang_van", "Dang Van index"),
        ("swt", "SWT σn,max·εa (MPa)"),
        ("fatemi_socie", "Fatemi–Socie parameter"),
    ] {
        svg_with_labels(
            &full.join(format!("fatigue_section_{key}.svg")),
            &[
                "x (μm)",
                "depth z (μm)",
                unit,
                "section through its maximum",
            ],
        );
    }
    svg_with_labels(
        &full.join("fatigue_depth_profile.svg"),
        &[
            "depth z (μm)",
            "layer maximum / overall maximum",
            "Crossland (max",
            "Dang Van (max",
            "Smith–Watson–Topper (max",
            "Fatemi–Socie (max",
        ],
    );
    assert_eq!(j2["fatemi_socie_max"], j["fatemi_socie_max"]);
}

/// An inhomogeneity's own `fatigue` table through the CLI (docs/fatigue.md, "Materials"): against
/// the same loop without it, Crossland and Dang Van change exactly at the cells whose centre the
/// sphere holds, every other cell and SWT and Fatemi–Socie (whose constants the table leaves to
/// the matrix) are bit for bit the same.
#[test]
fn an_inhomogeneitys_own_limits_change_exactly_its_cells() {
    let dir = tempfile::tempdir().unwrap();
    let (z0, r) = (1.566e-6, 0.903e-6);
    let sphere = format!(
        "[[inhomogeneity]]\nkind = \"sphere\"\nx = 0.0\ny = 0.0\nz = {z0}\nr = {r}\nE = 420e9\n\
         nu = 0.3\n"
    );
    let head = "grid = 16\nnormal_steps = 4\namplitude = 0.02e-6\nshift_step = 0.005e-6\n\
                subsurface_over_a = 0.0\n";
    let tail = format!("{FATIGUE}depth_over_a = 0.7\nscreen_fraction = 0.0\n");
    let own = "fatigue = { f_minus1 = 250e6, t_minus1 = 160e6 }\n";
    let mut records = Vec::new();
    for (name, text) in [
        ("plain", format!("{head}{sphere}{tail}")),
        ("own", format!("{head}{sphere}{own}{tail}")),
    ] {
        let c = config(dir.path(), &format!("{name}.toml"), &text);
        let out = dir.path().join(name);
        ok_json(&run(&[
            "fretting-loop",
            "--config",
            &c,
            "--out",
            out.to_str().unwrap(),
            "--json",
        ]));
        records.push(halfspace::data::read_record(&out.join("results.h5")).unwrap());
    }
    let (x, y, z) = (
        records[0].get("x").unwrap(),
        records[0].get("y").unwrap(),
        records[0].get("z").unwrap(),
    );
    let inside = |p: usize| {
        let (k, i, j) = (p / 256, (p / 16) % 16, p % 16);
        x[i] * x[i] + y[j] * y[j] + (z[k] - z0).powi(2) <= r * r
    };
    let cells = (0..z.len() * 256).filter(|&p| inside(p)).count();
    assert!(cells > 0);
    for key in ["crossland", "dang_van", "swt", "fatemi_socie"] {
        let (a, b) = (records[0].get(key).unwrap(), records[1].get(key).unwrap());
        let changes = key == "crossland" || key == "dang_van";
        for p in 0..a.len() {
            if changes && inside(p) {
                assert_ne!(a[p], b[p], "{key} cell {p}");
            } else {
                assert_eq!(a[p].to_bits(), b[p].to_bits(), "{key} cell {p}");
            }
        }
    }
}

/// `fretting-loop --help` names every key of its `--config` file: the list serde gives for an
/// unknown key (`expected one of …`) against the help text.
#[test]
fn the_help_names_every_config_key() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("out");
    let c = config(dir.path(), "unknown.toml", "no_such_key = 1\n");
    let out = run(&[
        "fretting-loop",
        "--config",
        &c,
        "--out",
        o.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    let list = err
        .split("expected one of")
        .nth(1)
        .unwrap_or_else(|| panic!("no key list in {err:?}"));
    let keys: Vec<&str> = list.split('`').skip(1).step_by(2).collect();
    assert!(keys.len() >= 20, "{keys:?}");
    for key in ["eim_change_factor", "eim_recycled_depth", "fatigue", "grid"] {
        assert!(keys.contains(&key), "{key} not in {keys:?}");
    }
    let help = run(&["fretting-loop", "--help"]);
    assert!(help.status.success());
    let help = String::from_utf8_lossy(&help.stdout);
    let missing: Vec<&&str> = keys.iter().filter(|k| !help.contains(**k)).collect();
    assert!(missing.is_empty(), "--help lacks {missing:?}");
}
