//! Where a cold normal solve spends its time (docs/performance.md, issue 23): frictionless Hertz
//! (R = 105 μm, E = 210 GPa, ν = 0.3, W = 80 mN, domain 4a, tolerance 1e-8) as `contact3d` runs it
//! (a new solver: kernel quadrant, spectra, plans, the nested continuation, the fine solve), the
//! same solve on a planned solver (the continuation's coarse grids still built); the fastest of
//! `repeat` runs each. On a loaded machine run it with `RAYON_NUM_THREADS=1`.
//!
//! Run: `cargo run --release -p halfspace-sam --example normal_breakdown -- 128 256 512 1024`

use std::time::Instant;

use halfspace_sam::normal::{NormalLoad, NormalParams, NormalSolver};
use halfspace_sam::{Body, Compliance, SurfaceGrid};

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|s| s.parse().ok())
        .collect();
    let sizes = if sizes.is_empty() {
        vec![128, 256, 512]
    } else {
        sizes
    };
    let (r, w): (f64, f64) = (105e-6, 0.08);
    let a = halfspace_mdr::analytic::sphere_radius_for_force(w, r, 210e9 / 0.91);
    let compliance = Compliance::pair(Body::Rigid, Body::elastic(210e9, 0.3).unwrap()).unwrap();
    let params = NormalParams {
        tolerance: 1e-8,
        ..NormalParams::default()
    };
    println!("| N² | new solver + solve | plan | solve (planned) | fine it | coarse it |");
    println!("|---:|---:|---:|---:|---:|---:|");
    for n in sizes {
        let grid = SurfaceGrid::square(n, 4.0 * a).unwrap();
        let h: Vec<f64> = (0..grid.len())
            .map(|k| {
                let (x, y) = grid.centre(k / n, k % n);
                (x * x + y * y) / (2.0 * r)
            })
            .collect();
        let repeat = if n <= 512 { 7 } else { 3 };
        let (mut fresh, mut plan, mut planned) = (f64::MAX, f64::MAX, f64::MAX);
        let mut info = None;
        for _ in 0..repeat {
            let mut p = vec![0.0; grid.len()];
            let t = Instant::now();
            let mut solver = NormalSolver::new(grid, &compliance).unwrap();
            solver
                .solve(&h, NormalLoad::Force(w), &mut p, &params)
                .unwrap();
            fresh = fresh.min(t.elapsed().as_secs_f64());
            let t = Instant::now();
            let mut solver = NormalSolver::new(grid, &compliance).unwrap();
            solver.plan().unwrap();
            plan = plan.min(t.elapsed().as_secs_f64());
            p.fill(0.0);
            let t = Instant::now();
            let i = solver
                .solve(&h, NormalLoad::Force(w), &mut p, &params)
                .unwrap();
            planned = planned.min(t.elapsed().as_secs_f64());
            info = Some(i);
        }
        let info = info.unwrap();
        println!(
            "| {n}² | {:.2} ms | {:.2} ms | {:.2} ms | {} | {} |",
            fresh * 1e3,
            plan * 1e3,
            planned * 1e3,
            info.iterations,
            info.coarse_iterations
        );
    }
}
