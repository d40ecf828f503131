//! Convergence studies against the closed forms of [`crate::analytic`], shared by the CLI's
//! `halfspace study` (which draws the docs' figures) and the benches.

use crate::{analytic, Backend, DisplacementMethod, DisplacementTransform, Material, MdrError};
use crate::{SquaredGrid, StressTransform};

/// Eq. 19 mean relative error of Eq. 17 on the Eq. 18 pair `q = 1 − x⁴` (a = L = 1, M = N),
/// excluding the edge node where `σ* = 0` (spec §3).
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

/// Max error of the displacement transform on Hertz (spec §2 test 2: R = 1, a = 0.7, L = 1,
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
/// `U = x⁴ ↦ u = (1+k)(3+k)/8 r⁴` (L = 1, no cut; spec §4.3).
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
