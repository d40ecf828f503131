//! The MDR against scipy quadrature references (datasets/quadrature.h5 and datasets/npy/quad_*,
//! written by `python -m verify quad`; see verify/quadrature.py): three profiles without closed
//! forms × k ∈ {0, −0.5, −0.2, 0.3, 0.6}, for the profile transform, the contact radius and force,
//! the pressure and the surface displacement inside and outside the contact. Both file formats are
//! read, and every file's sha256 is checked against datasets/MANIFEST.json.

use std::path::Path;

use halfspace::data::{read_h5_group, read_npy_1d, read_npy_2d, AttrValue, Manifest, Record};
use halfspace::mdr::{
    Backend, ContactParams, ContactSolver, Load, Material, Profile, ProfileTransform, SquaredGrid,
};

const KS: [f64; 5] = [0.0, -0.5, -0.2, 0.3, 0.6];
const PROFILES: [&str; 3] = ["sphere_quartic", "worn", "table"];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn attr(rec: &Record, name: &str) -> f64 {
    match rec.get_attr(name) {
        Some(AttrValue::Float(v)) => *v,
        Some(AttrValue::Int(v)) => *v as f64,
        other => panic!("attribute {name}: {other:?}"),
    }
}

/// The profile as the library sees it: a dense table sampled from the fixture's formula (cubic
/// Hermite interpolation error < 1e-12 at 3001 rows), or the fixture's own table.
fn profile(name: &str, manifest: &Manifest) -> Profile {
    if name == "table" {
        let path = manifest
            .verified("datasets/npy/quad_profile_table__table.npy")
            .unwrap();
        let (rows, cols, v) = read_npy_2d(&path).unwrap();
        assert_eq!(cols, 2);
        let r = (0..rows).map(|i| v[2 * i]).collect();
        let f = (0..rows).map(|i| v[2 * i + 1]).collect();
        return Profile::tabulated(r, f).unwrap();
    }
    let f = |r: f64| match name {
        "sphere_quartic" => r * r / 2.0 + 0.5 * r.powi(4),
        _ => r * r / 2.0 - 0.02 * (1.0 - (-r * r / 0.09).exp()),
    };
    let r: Vec<f64> = (0..3001).map(|i| 1.5 * i as f64 / 3000.0).collect();
    let h: Vec<f64> = r.iter().map(|&x| f(x)).collect();
    Profile::tabulated(r, h).unwrap()
}

/// Bounds of the comparison, from the measured errors at N = 2001 with a margin below 2×: 1e-4 (the
/// issue's target) everywhere but the pressure at k = −0.5, where Eq. 29's trapezoid rule is
/// O(h^{1.25}) (docs/theory-mdr.md#p1-singular-kernels; measured 1.6e-4 on the worn profile) and, for the 301-row table, the
/// table's own interpolation error dominates (2.6e-4, flat in N; the same profile sampled at 3001
/// rows gives 4.2e-5 at order 1.27, `odd_table_profile_converges_at_the_trapezoid_order`).
fn bounds(profile: &str, k: f64) -> (f64, f64) {
    match (profile, k) {
        ("table", k) if k < -0.3 => (5e-4, 1e-4),
        (_, k) if k < -0.3 => (3e-4, 1e-4),
        _ => (1e-4, 1e-4),
    }
}

/// ((pressure error, contact radius error, force error), displacement error) of a contact solve on
/// N nodes with the edge on node 0.48 (N − 1): pressure points at every (N−1)/50-th node, displacement
/// points at every (N−1)/20-th.
fn contact_errors(
    prof: &Profile,
    material: Material,
    backend: Backend,
    rec: &Record,
    n: usize,
) -> ((f64, f64, f64), f64) {
    let params = ContactParams {
        nodes: n,
        backend,
        domain_ratio: (2000.0f64 / 960.0).sqrt(),
        ..ContactParams::default()
    };
    let depth = attr(rec, "depth");
    let sol = ContactSolver::new(material, params)
        .unwrap()
        .solve(prof, Load::Depth(depth))
        .unwrap();
    assert_eq!(sol.edge_index * 2000, 960 * (n - 1));
    let e_a = (sol.contact_radius / 0.8 - 1.0).abs();
    let e_f = (sol.force / attr(rec, "force") - 1.0).abs();
    let p_ref = rec.get("pressure").unwrap();
    let step_p = (n - 1) / 50;
    let p_here: Vec<f64> = (0..p_ref.len()).map(|j| sol.pressure[step_p * j]).collect();
    let p_scale = p_ref.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let u_ref = rec.get("displacement").unwrap();
    let step_u = (n - 1) / 20;
    let u_here: Vec<f64> = (0..u_ref.len())
        .map(|j| sol.displacement[step_u * j])
        .collect();
    (
        (max_rel(&p_here, p_ref, p_scale), e_a, e_f),
        max_rel(&u_here, u_ref, depth),
    )
}

fn max_rel(got: &[f64], want: &[f64], scale: f64) -> f64 {
    got.iter()
        .zip(want)
        .map(|(g, w)| (g - w).abs() / scale)
        .fold(0.0, f64::max)
}

#[test]
fn mdr_matches_scipy_quadrature() {
    let manifest = Manifest::load(root()).expect("datasets/MANIFEST.json");
    let h5 = manifest.verified("datasets/quadrature.h5").unwrap();
    let mut report = Vec::new();
    let mut failures: Vec<String> = Vec::new();
    for name in PROFILES {
        let prof = profile(name, &manifest);
        for k in KS {
            let case = format!("quad_{name}/k{k:+.1}");
            let rec = read_h5_group(&h5, &case).unwrap();
            // The .npy copies hold the same numbers.
            for array in ["g", "pressure", "displacement"] {
                let stem = case.replace('/', "__");
                let p = manifest
                    .verified(&format!("datasets/npy/{stem}__{array}.npy"))
                    .unwrap();
                assert_eq!(
                    read_npy_1d(&p).unwrap(),
                    rec.get(array).unwrap(),
                    "{case} {array}"
                );
            }
            let material = Material::power_law(1.0, 1.0, 0.3, k).unwrap();
            assert!(
                (material.contact_modulus() / attr(&rec, "contact_modulus") - 1.0).abs() < 1e-13
            );
            let reference_error = attr(&rec, "estimated_relative_error");
            assert!(
                reference_error < 1e-11,
                "{case}: reference error {reference_error:e}"
            );

            // Profile transform alone: N = 2001, L = 1, fixture points at nodes 80 j.
            let grid = SquaredGrid::new(2001, 1.0).unwrap();
            let mut g = vec![0.0; 2001];
            ProfileTransform::new(2001, &material, Backend::Fft)
                .unwrap()
                .profile_to_equivalent(&prof, &grid, &mut g)
                .unwrap();
            let g_ref = rec.get("g").unwrap();
            let g_here: Vec<f64> = (0..g_ref.len()).map(|j| g[80 * j]).collect();
            let g_scale = g_ref.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            let e_g = max_rel(&g_here, g_ref, g_scale);

            // Contact by depth: N = 2001 with the edge on node 960, pressure points at nodes 40 j,
            // displacement points at nodes 100 j.
            for backend in [Backend::Fft, Backend::Mvm] {
                let (e_p, e_u) = contact_errors(&prof, material, backend, &rec, 2001);
                let e_f = e_p.2;
                let e_a = e_p.1;
                let e_p = e_p.0;
                report.push(format!(
                    "{case:28} {backend:?}: g {e_g:.1e}  a {e_a:.1e}  F {e_f:.1e}  p {e_p:.1e}  u {e_u:.1e}"
                ));
                let (bound_p, bound_u) = bounds(name, k);
                if !(e_g < 1e-4 && e_a < 1e-4 && e_f < 1e-4 && e_p < bound_p && e_u < bound_u) {
                    failures.push(report.last().unwrap().clone());
                }
            }
        }
    }
    eprintln!("{}", report.join("\n"));
    assert!(
        failures.is_empty(),
        "beyond the bounds:\n{}",
        failures.join("\n")
    );
}

#[test]
fn fixture_readers_name_the_file_and_the_problem() {
    let manifest = Manifest::load(root()).unwrap();
    // Not in the manifest.
    let e = manifest.verified("datasets/npy/nope.npy").unwrap_err();
    assert!(e.to_string().contains("not listed"), "{e}");
    // Checksum mismatch: a copy of the manifest's directory with one byte changed.
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("datasets/npy")).unwrap();
    std::fs::copy(
        root().join("datasets/MANIFEST.json"),
        dir.path().join("datasets/MANIFEST.json"),
    )
    .unwrap();
    let rel = "datasets/npy/quad_worn__k+0.3__g.npy";
    let mut bytes = std::fs::read(root().join(rel)).unwrap();
    let last = bytes.len() - 1;
    bytes[last] ^= 1;
    std::fs::write(dir.path().join(rel), bytes).unwrap();
    let copy = Manifest::load(dir.path()).unwrap();
    let e = copy.verified(rel).unwrap_err();
    assert!(
        e.to_string().contains("checksum mismatch") && e.to_string().contains("quad_worn"),
        "{e}"
    );
    // Missing file.
    let e = copy.verified("datasets/quadrature.h5").unwrap_err();
    assert!(e.to_string().contains("quadrature.h5"), "{e}");
    // Missing group.
    let h5 = manifest.verified("datasets/quadrature.h5").unwrap();
    let e = read_h5_group(&h5, "quad_nope/k+0.0").unwrap_err();
    assert!(e.to_string().contains("no group"), "{e}");
    // Wrong dimensionality.
    let e = read_npy_1d(
        &manifest
            .verified("datasets/npy/quad_profile_table__table.npy")
            .unwrap(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("table.npy"), "{e}");
}

/// The table profile (c₁r² + c₂r³ + c₃r⁴, with an r³ term) sampled densely from its formula: with the
/// cubic part split off in closed form, the pressure at k = −0.5 converges at the trapezoid order
/// (3 + k)/2 = 1.25 (measured 9.9e-5, 4.2e-5, 1.7e-5 at N = 1001/2001/4001: order 1.27).
#[test]
fn odd_table_profile_converges_at_the_trapezoid_order() {
    let manifest = Manifest::load(root()).unwrap();
    let h5 = manifest.verified("datasets/quadrature.h5").unwrap();
    let rec = read_h5_group(&h5, "quad_table/k-0.5").unwrap();
    let Some(AttrValue::Text(description)) = rec.get_attr("description") else {
        panic!("the table case describes its formula");
    };
    // "f = A r^2 + B r^3 + C r^4, given as …"
    let words: Vec<&str> = description.split_whitespace().collect();
    let c: Vec<f64> = [2, 5, 8]
        .iter()
        .map(|&i| words[i].parse().unwrap())
        .collect();
    let r: Vec<f64> = (0..3001).map(|i| 1.5 * i as f64 / 3000.0).collect();
    let f: Vec<f64> = r
        .iter()
        .map(|&x| c[0] * x * x + c[1] * x.powi(3) + c[2] * x.powi(4))
        .collect();
    let prof = Profile::tabulated(r, f).unwrap();
    let material = Material::power_law(1.0, 1.0, 0.3, -0.5).unwrap();
    let ns = [1001usize, 2001, 4001];
    let errs: Vec<f64> = ns
        .iter()
        .map(|&n| contact_errors(&prof, material, Backend::Fft, &rec, n).0 .0)
        .collect();
    let order = halfspace::mdr::studies::observed_order(&ns, &errs);
    eprintln!("pressure errors {errs:?}, order {order:.2}");
    assert!(errs[1] < 1e-4, "{errs:?}");
    assert!((order - 1.25).abs() < 0.15, "order {order}, {errs:?}");
}
