//! Convergence studies against the closed forms of [`crate::analytic`], shared by the CLI's
//! `halfspace study` (which draws the docs' figures) and the benches.

use crate::{analytic, Backend, DisplacementMethod, DisplacementTransform, Material, MdrError};
use crate::{SquaredGrid, StressTransform};

/// Eq. 19 mean relative error of Eq. 17 on the Eq. 18 pair `q = 1 − x⁴` (a = L = 1, M = N),
/// excluding the edge node where `σ* = 0` (docs/theory-mdr.md#stress-transform).
pub fn stress_transform_error(n: usize, backend: Backend) -> Result<f64, MdrError> {
    let grid = SquaredGrid::new(n, 1.0)?;
    let q: Vec<f64> = (0..n).map(|i| 1.0 - grid.squared(i).powi(2)).collect();
    let mut t = StressTransform::new(n, &Material::from_e_star(1.0)?, backend)?;
    let mut sigma = vec![0.0; n];
    t.line_load_to_stress(&grid, &q, 0.0, &mut sigma)?;
    let sum: f64 = (0..n - 1)
        .map(|j| {
            let exact = analytic::quartic_load_stress(grid.coordinate(j), 1.0);
            ((sigma[j] - exact) / exact).abs()
        })
        .sum();
    Ok(sum / (n - 1) as f64)
}

/// Max error of the displacement transform on Hertz (docs/theory-mdr.md#displacement-transform test 2: R = 1, a = 0.7, L = 1,
/// `U = a² − x²` on the contact), whole surface. `n − 1` must make `0.49 (n − 1)` an integer for
/// `a²` to be a node; other `n` use the nearest node.
pub fn displacement_hertz_error(n: usize, method: DisplacementMethod) -> Result<f64, MdrError> {
    let grid = SquaredGrid::new(n, 1.0)?;
    let m = (0.49 * (n - 1) as f64).round() as usize;
    let a = grid.coordinate(m);
    let u: Vec<f64> = (0..=m).map(|i| a * a - grid.squared(i)).collect();
    let mut t = DisplacementTransform::new(n, &Material::from_e_star(1.0)?, method)?;
    let mut out = vec![0.0; n];
    t.apply(&grid, &u, 0.0, &mut out)?;
    Ok((0..n)
        .map(|j| (out[j] - analytic::sphere_displacement(grid.coordinate(j), a, 1.0)).abs())
        .fold(0.0, f64::max))
}

/// Mean relative error (over `j ≥ 1`) of the graded displacement transform on the Eq. 27 pair
/// `U = x⁴ ↦ u = (1+k)(3+k)/8 r⁴` (L = 1, no cut; docs/theory-mdr.md#graded-displacements).
pub fn graded_quartic_displacement_error(
    n: usize,
    k: f64,
    method: DisplacementMethod,
) -> Result<f64, MdrError> {
    let grid = SquaredGrid::new(n, 1.0)?;
    let u: Vec<f64> = (0..n).map(|i| grid.squared(i).powi(2)).collect();
    let mut t = DisplacementTransform::new(n, &Material::power_law(1.0, 1.0, 0.3, k)?, method)?;
    let mut out = vec![0.0; n];
    t.apply(&grid, &u, 0.0, &mut out)?;
    let sum: f64 = (1..n)
        .map(|j| {
            let exact = analytic::graded_quartic_displacement(grid.coordinate(j), k);
            ((out[j] - exact) / exact).abs()
        })
        .sum();
    Ok(sum / (n - 1) as f64)
}

/// Observed order of convergence: minus the least-squares slope of `ln error` against `ln N`.
pub fn observed_order(ns: &[usize], errors: &[f64]) -> f64 {
    let xs: Vec<f64> = ns.iter().map(|&n| (n as f64).ln()).collect();
    let ys: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let k = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / k, ys.iter().sum::<f64>() / k);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    -sxy / sxx
}

/// Seconds per application of the profile transform (Eq. 7; Eq. 23 for `k ≠ 0`), "the pure
/// transformation step (without build-up of a priori known matrices or vectors)" of the paper's
/// Fig. 1: the transform is planned once for `n` nodes (`L = 1`), then applied to the slope of
/// `f = r²/2 + r⁴/4` in batches until `budget_seconds` have passed (at least three applications);
/// the result is the smallest batch mean (the least disturbed by other work on the machine).
pub fn profile_transform_seconds(
    n: usize,
    k: f64,
    backend: Backend,
    budget_seconds: f64,
) -> Result<f64, MdrError> {
    let grid = SquaredGrid::new(n, 1.0)?;
    let material = if k == 0.0 {
        Material::from_e_star(1.0)?
    } else {
        Material::power_law(1.0, 1.0, 0.0, k)?
    };
    let mut t = crate::ProfileTransform::new(n, &material, backend)?;
    // df/dρ of f = ρ/2 + ρ²/4 (ρ = r²).
    let slope: Vec<f64> = (0..n).map(|i| 0.5 + 0.5 * grid.squared(i)).collect();
    let mut g = vec![0.0; n];
    t.apply(&grid, &slope, &mut g)?;
    let start = std::time::Instant::now();
    let mut best = f64::INFINITY;
    let mut batch = 1usize;
    let mut total = 0usize;
    while total < 3 || start.elapsed().as_secs_f64() < budget_seconds {
        let t0 = std::time::Instant::now();
        for _ in 0..batch {
            t.apply(&grid, &slope, &mut g)?;
        }
        let mean = t0.elapsed().as_secs_f64() / batch as f64;
        best = best.min(mean);
        total += batch;
        // Batches of about a hundredth of the budget.
        if mean * (batch as f64) < 0.01 * budget_seconds {
            batch *= 2;
        }
    }
    Ok(best)
}
