//! The graded limiting worn profile (halfspace::fretting::limit, incomplete-beta closed forms)
//! against the scipy quadrature fixture (datasets/graded_wear.h5 and datasets/npy/graded_wear__*,
//! written by `python -m verify graded-wear`; verify/graded_wear.py integrates the graded inverse
//! transform Eq. 24 directly): r*(χ, k), f̃∞(r) at 12 radii in (c, r*], and the final wear volume,
//! for k ∈ {−0.5, −0.25, 0.25, 0.5, 0.75, 0.9} × χ ∈ {0.1, 0.3, 0.5, 0.7, 0.9}. Both file formats
//! are read; every file's sha256 is checked against datasets/MANIFEST.json.

use std::path::Path;

use halfspace::data::{read_h5_group, read_npy_1d, Manifest, Record};
use halfspace::fretting::limit::{limit_contact_radius, limit_wear_volume, limiting_profile};

fn attr(rec: &Record, name: &str) -> f64 {
    rec.float_attr(name)
        .unwrap_or_else(|| panic!("attribute {name}: {:?}", rec.get_attr(name)))
}

#[test]
fn limiting_profiles_match_the_quadrature_fixture() {
    let manifest = Manifest::load(Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap();
    let h5 = manifest.verified("datasets/graded_wear.h5").unwrap();
    let (mut worst_r, mut worst_f, mut worst_v) = (0.0f64, 0.0f64, 0.0f64);
    let mut cases = 0;
    for k in ["-0.50", "-0.25", "+0.25", "+0.50", "+0.75", "+0.90"] {
        for chi in ["0.1", "0.3", "0.5", "0.7", "0.9"] {
            let case = format!("graded_wear/k{k}_chi{chi}");
            let rec = read_h5_group(&h5, &case).unwrap();
            let (kv, chiv) = (attr(&rec, "k"), attr(&rec, "chi"));
            let stem = case.replace('/', "__");
            for array in ["r", "limiting_profile"] {
                let npy = manifest
                    .verified(&format!("datasets/npy/{stem}__{array}.npy"))
                    .unwrap();
                assert_eq!(read_npy_1d(&npy).unwrap(), rec.get(array).unwrap());
            }
            worst_r = worst_r.max((limit_contact_radius(chiv, kv) - attr(&rec, "r_star")).abs());
            for (r, f) in rec
                .get("r")
                .unwrap()
                .iter()
                .zip(rec.get("limiting_profile").unwrap())
            {
                worst_f = worst_f.max((limiting_profile(*r, chiv, kv) - f).abs());
            }
            worst_v =
                worst_v.max((limit_wear_volume(chiv, kv) / attr(&rec, "wear_volume") - 1.0).abs());
            cases += 1;
        }
    }
    assert_eq!(cases, 30);
    println!("worst |Δr*| {worst_r:.2e}, |Δf̃∞| {worst_f:.2e}, ΔV/V {worst_v:.2e}");
    // The issue asks 1e-4; the closed forms and the quadrature agree to rounding.
    assert!(worst_r < 1e-12, "r*: {worst_r:e}");
    assert!(worst_f < 1e-12, "f∞: {worst_f:e}");
    assert!(worst_v < 1e-10, "V∞: {worst_v:e}");
}
