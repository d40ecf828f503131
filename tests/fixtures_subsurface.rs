//! Subsurface stresses against an independent reference: scipy cubature of the Boussinesq and
//! Cerruti point-force solutions over a Hertz pressure, with and without the shear μp
//! (datasets/subsurface.h5 and datasets/npy/hertz_subsurface_*, `python -m verify subsurface`;
//! verify/subsurface.py). halfspace evaluates Love's rectangle stresses of the pressure sampled at
//! the cell centres of n × n grids over 4a at the same off-axis points; the error converges at
//! second order in the cell size. Both file formats are read; checksums are verified.

use std::path::Path;

use halfspace::data::{read_h5_group, read_npy_1d, Manifest};
use halfspace::sam::subsurface::stress_at_points;
use halfspace::sam::SurfaceGrid;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Max error over the fixture points (relative to p₀ = 1) on an n × n grid.
fn max_error(n: usize, friction: f64, points: &[[f64; 3]], reference: &[f64]) -> f64 {
    let grid = SurfaceGrid::square(n, 4.0).unwrap();
    let mut p = vec![0.0; grid.len()];
    for i in 0..n {
        for j in 0..n {
            let (x, y) = grid.centre(i, j);
            let r2 = x * x + y * y;
            if r2 < 1.0 {
                p[i * n + j] = (1.0 - r2).sqrt();
            }
        }
    }
    let q1: Vec<f64> = p.iter().map(|v| friction * v).collect();
    let zero = vec![0.0; grid.len()];
    let q = (friction > 0.0).then_some([q1.as_slice(), zero.as_slice()]);
    let got = stress_at_points(&grid, 1.0, 0.3, &p, q, None, points).unwrap();
    got.iter()
        .flatten()
        .zip(reference)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
}

#[test]
fn hertz_subsurface_stresses_match_the_cubature_fixture_at_second_order() {
    let manifest = Manifest::load(root()).expect("datasets/MANIFEST.json");
    let h5 = manifest.verified("datasets/subsurface.h5").unwrap();
    for (case, friction) in [
        ("hertz_subsurface_pressure", 0.0),
        ("hertz_subsurface_pressure_and_shear", 0.3),
    ] {
        let rec = read_h5_group(&h5, case).unwrap();
        let pts = rec.get("points").unwrap().to_vec();
        let reference = rec.get("stress").unwrap().to_vec();
        // The NPY twin holds the same numbers.
        let npy = manifest
            .verified(&format!("datasets/npy/{case}__stress.npy"))
            .unwrap();
        assert_eq!(read_npy_1d(&npy).unwrap(), reference);
        let points: Vec<[f64; 3]> = pts.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        assert_eq!(points.len() * 6, reference.len());
        let errors: Vec<f64> = [32, 64, 128]
            .iter()
            .map(|&n| max_error(n, friction, &points, &reference))
            .collect();
        let orders: Vec<f64> = errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
        eprintln!("{case}: max errors {errors:?}, orders {orders:?}");
        // Measured: 3.5e-3, 7.6e-4, 2.0e-4 p₀ (pressure) and 4.3e-3, 9.2e-4, 2.1e-4 (with μp) at
        // n = 32, 64, 128: orders 2.2, 1.9 and 2.2, 2.1.
        assert!(
            orders.iter().all(|o| *o > 1.7),
            "{case}: {errors:?} {orders:?}"
        );
        assert!(errors[2] < 3e-4, "{case}: {errors:?}");
    }
}
