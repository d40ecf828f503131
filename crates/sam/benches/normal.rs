//! Frictionless Hertz by DC-FFT + Polonsky–Keer (tolerance 1e-10), grids 128²…512²: one full solve
//! from a cold start per iteration of the benchmark (operator planned beforehand), the plain
//! iteration of docs/theory-sam.md#normal-contact and the accelerated default (|k| preconditioner, one product per
//! iteration, nested grids) side by side; and the setup plus cold solve at tolerance 1e-8 that
//! `contact3d` runs (issue 23).
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use halfspace_sam::normal::{NormalLoad, NormalParams, NormalSolver};
use halfspace_sam::{Body, Compliance, SurfaceGrid};

fn hertz(c: &mut Criterion) {
    let (r, w): (f64, f64) = (105e-6, 0.08);
    let a = halfspace_mdr::analytic::sphere_radius_for_force(w, r, 210e9 / 0.91);
    let mut group = c.benchmark_group("hertz_normal_solve");
    for n in [128usize, 256, 512] {
        let grid = SurfaceGrid::square(n, 4.0 * a).unwrap();
        let comp = Compliance::pair(Body::Rigid, Body::elastic(210e9, 0.3).unwrap()).unwrap();
        let mut solver = NormalSolver::new(grid, &comp).unwrap();
        let h: Vec<f64> = (0..grid.len())
            .map(|k| {
                let (x, y) = grid.centre(k / n, k % n);
                (x * x + y * y) / (2.0 * r)
            })
            .collect();
        let mut p = vec![0.0; grid.len()];
        for (name, params) in [
            ("plain", NormalParams::plain()),
            ("accelerated", NormalParams::default()),
        ] {
            group.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                b.iter(|| {
                    p.fill(0.0);
                    solver
                        .solve(&h, NormalLoad::Force(w), &mut p, &params)
                        .unwrap()
                })
            });
        }
    }
    group.finish();
}

/// What `contact3d` and `verify/peers_3d.py` time (issue 23): a new solver (kernel quadrant,
/// spectra, plans from the process cache) and one cold solve with the nested continuation,
/// tolerance 1e-8, 128²…512².
fn hertz_cold(c: &mut Criterion) {
    let (r, w): (f64, f64) = (105e-6, 0.08);
    let a = halfspace_mdr::analytic::sphere_radius_for_force(w, r, 210e9 / 0.91);
    let comp = Compliance::pair(Body::Rigid, Body::elastic(210e9, 0.3).unwrap()).unwrap();
    let params = NormalParams {
        tolerance: 1e-8,
        ..NormalParams::default()
    };
    let mut group = c.benchmark_group("hertz_normal_setup_and_solve_1e-8");
    for n in [128usize, 256, 512] {
        let grid = SurfaceGrid::square(n, 4.0 * a).unwrap();
        let h: Vec<f64> = (0..grid.len())
            .map(|k| {
                let (x, y) = grid.centre(k / n, k % n);
                (x * x + y * y) / (2.0 * r)
            })
            .collect();
        let mut p = vec![0.0; grid.len()];
        group.bench_with_input(BenchmarkId::new("cold", n), &n, |b, _| {
            b.iter(|| {
                p.fill(0.0);
                let mut solver = NormalSolver::new(grid, &comp).unwrap();
                solver
                    .solve(&h, NormalLoad::Force(w), &mut p, &params)
                    .unwrap()
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3)).without_plots();
    targets = hertz, hertz_cold
}
criterion_main!(benches);
