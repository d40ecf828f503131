//! What each acceleration of the normal solve buys (docs/performance.md, issue 10): frictionless
//! Hertz (R = 105 μm, E = 210 GPa, ν = 0.3, W = 80 mN, domain 4a, tolerance 1e-10) solved from a
//! cold start with the plain Polonsky–Keer iteration, each acceleration alone, and all together;
//! fine-grid and coarse-grid iterations, the fastest of three solves on one planned solver, and
//! the L2 error against Hertz (equal for all: the same discrete solution).
//!
//! Run: `cargo run --release -p halfspace-sam --example normal_variants -- 256 512 1024`

use std::time::Instant;

use halfspace_sam::normal::{NormalLoad, NormalParams, NormalSolver};
use halfspace_sam::{Body, Compliance, SurfaceGrid};

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|s| s.parse().ok())
        .collect();
    let sizes = if sizes.is_empty() {
        vec![256, 512]
    } else {
        sizes
    };
    let (r, w): (f64, f64) = (105e-6, 0.08);
    let e_star = 210e9 / 0.91;
    let a = halfspace_mdr::analytic::sphere_radius_for_force(w, r, e_star);
    let p0 = 3.0 * w / (2.0 * std::f64::consts::PI * a * a);
    let compliance = Compliance::pair(Body::Rigid, Body::elastic(210e9, 0.3).unwrap()).unwrap();
    println!("| N² | variant | fine iterations | coarse iterations | solve | L2 vs Hertz |");
    println!("|---:|---|---:|---:|---:|---:|");
    for n in sizes {
        let grid = SurfaceGrid::square(n, 4.0 * a).unwrap();
        let mut solver = NormalSolver::new(grid, &compliance).unwrap();
        solver.plan().unwrap();
        let h: Vec<f64> = (0..grid.len())
            .map(|k| {
                let (x, y) = grid.centre(k / n, k % n);
                (x * x + y * y) / (2.0 * r)
            })
            .collect();
        let plain = NormalParams::plain();
        for (name, params) in [
            ("plain (docs/theory-sam.md#normal-contact)", plain),
            (
                "one product per iteration",
                NormalParams {
                    incremental: true,
                    ..plain
                },
            ),
            (
                "\\|k\\| preconditioner",
                NormalParams {
                    preconditioned: true,
                    ..plain
                },
            ),
            (
                "nested grids",
                NormalParams {
                    nested: true,
                    ..plain
                },
            ),
            ("all three (default)", NormalParams::default()),
        ] {
            let mut p = vec![0.0; grid.len()];
            let mut best = f64::INFINITY;
            let mut info = None;
            for _ in 0..3 {
                p.fill(0.0);
                let t = Instant::now();
                info = Some(
                    solver
                        .solve(&h, NormalLoad::Force(w), &mut p, &params)
                        .unwrap(),
                );
                best = best.min(t.elapsed().as_secs_f64());
            }
            let info = info.unwrap();
            let (mut e2, mut r2) = (0.0, 0.0);
            for (k, pk) in p.iter().enumerate() {
                let (x, y) = grid.centre(k / n, k % n);
                let rho2 = (x * x + y * y) / (a * a);
                let ph = if rho2 < 1.0 {
                    p0 * (1.0 - rho2).sqrt()
                } else {
                    0.0
                };
                e2 += (pk - ph).powi(2);
                r2 += ph * ph;
            }
            println!(
                "| {n}² | {name} | {} | {} | {:.3} s | {:.3} % |",
                info.iterations,
                info.coarse_iterations,
                best,
                100.0 * (e2 / r2).sqrt()
            );
        }
    }
}
