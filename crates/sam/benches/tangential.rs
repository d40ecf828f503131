//! Cattaneo–Mindlin 128² (docs/theory-sam.md#cattaneo-mindlin-reference; rigid sphere on steel, W = 80 mN, μ = 0.3, Q/μP = 0.6), one
//! tangential solve from a cold start per benchmark iteration: FISTA and the active-set method
//! side by side (issue 10). The pressure is solved once beforehand.
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use halfspace_sam::normal::{NormalLoad, NormalParams, NormalSolver};
use halfspace_sam::tangential::{TangentialMethod, TangentialParams, TangentialSolver};
use halfspace_sam::{Body, Compliance, SurfaceGrid};

fn cattaneo(c: &mut Criterion) {
    let (r, w, mu): (f64, f64, f64) = (105e-6, 0.08, 0.3);
    let a = halfspace_mdr::analytic::sphere_radius_for_force(w, r, 210e9 / 0.91);
    let mut group = c.benchmark_group("cattaneo_tangential_solve");
    for n in [64usize, 128] {
        let grid = SurfaceGrid::square(n, 4.0 * a).unwrap();
        let comp = Compliance::pair(Body::Rigid, Body::elastic(210e9, 0.3).unwrap())
            .unwrap()
            .uncoupled();
        let h: Vec<f64> = (0..grid.len())
            .map(|k| {
                let (x, y) = grid.centre(k / n, k % n);
                (x * x + y * y) / (2.0 * r)
            })
            .collect();
        let mut p = vec![0.0; grid.len()];
        NormalSolver::new(grid, &comp)
            .unwrap()
            .solve(&h, NormalLoad::Force(w), &mut p, &NormalParams::default())
            .unwrap();
        let bound: Vec<f64> = p.iter().map(|v| mu * v).collect();
        let k_cm = 3.0 * mu * w / (16.0 * a) * ((2.0 - 0.3) / (210e9 / 2.6));
        let d1 = k_cm * (1.0 - 0.4f64.powf(2.0 / 3.0));
        let (b0, b1) = (vec![d1; grid.len()], vec![0.0; grid.len()]);
        let mut solver = TangentialSolver::new(grid, &comp).unwrap();
        let (mut q0, mut q1) = (vec![0.0; grid.len()], vec![0.0; grid.len()]);
        let (mut s0, mut s1) = (vec![0.0; grid.len()], vec![0.0; grid.len()]);
        for (name, method) in [
            ("fista", TangentialMethod::Fista),
            ("active_set", TangentialMethod::ActiveSet),
        ] {
            let params = TangentialParams {
                method,
                ..Default::default()
            };
            group.bench_with_input(BenchmarkId::new(name, n), &n, |bench, _| {
                bench.iter(|| {
                    q0.fill(0.0);
                    q1.fill(0.0);
                    solver
                        .solve(
                            &bound,
                            [&b0, &b1],
                            [&mut q0, &mut q1],
                            [&mut s0, &mut s1],
                            &params,
                        )
                        .unwrap()
                })
            });
        }
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3)).without_plots();
    targets = cattaneo
}
criterion_main!(benches);
