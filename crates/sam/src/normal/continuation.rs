//! Nested-grid continuation of a cold normal solve: the grid with cells twice as large, the
//! restriction of the separation to it and the prolongation of its pressure (the fine grid's warm
//! start).

use super::COARSEST_SIDE;
use crate::SurfaceGrid;

/// The grid with cells twice as large over the same domain, if both sides are even and the
/// result keeps at least [`COARSEST_SIDE`] cells per side.
pub(super) fn coarser(grid: &SurfaceGrid) -> Option<SurfaceGrid> {
    let even = grid.n1 % 2 == 0 && grid.n2 % 2 == 0;
    (even && grid.n1 / 2 >= COARSEST_SIDE && grid.n2 / 2 >= COARSEST_SIDE).then_some(SurfaceGrid {
        n1: grid.n1 / 2,
        n2: grid.n2 / 2,
        half1: 2.0 * grid.half1,
        half2: 2.0 * grid.half2,
    })
}

/// The mean of each 2 × 2 block of fine cells (the coarse cell's value of a smooth field).
pub(super) fn restrict(fine: &SurfaceGrid, h: &[f64]) -> Vec<f64> {
    let (c1, c2) = (fine.n1 / 2, fine.n2 / 2);
    let n2 = fine.n2;
    let mut out = vec![0.0; c1 * c2];
    for i in 0..c1 {
        for j in 0..c2 {
            let at = |a: usize, b: usize| h[(2 * i + a) * n2 + 2 * j + b];
            out[i * c2 + j] = 0.25 * (at(0, 0) + at(0, 1) + at(1, 0) + at(1, 1));
        }
    }
    out
}

/// Bilinear interpolation of the coarse cell values at the fine cell centres (clamped at the
/// domain edge); the fine cell `i` sits at coarse index coordinate `i/2 − 1/4`.
pub(super) fn prolong(coarse: &SurfaceGrid, pc: &[f64], fine: &SurfaceGrid, p: &mut [f64]) {
    let (c1, c2) = (coarse.n1, coarse.n2);
    let weights = |i: usize, nc: usize| -> (usize, usize, f64) {
        let x = (i as f64 * 0.5 - 0.25).clamp(0.0, (nc - 1) as f64);
        let lo = (x.floor() as usize).min(nc - 2);
        (lo, lo + 1, x - lo as f64)
    };
    for i in 0..fine.n1 {
        let (a0, a1, wa) = weights(i, c1);
        for j in 0..fine.n2 {
            let (b0, b1, wb) = weights(j, c2);
            let v = (1.0 - wa) * ((1.0 - wb) * pc[a0 * c2 + b0] + wb * pc[a0 * c2 + b1])
                + wa * ((1.0 - wb) * pc[a1 * c2 + b0] + wb * pc[a1 * c2 + b1]);
            p[i * fine.n2 + j] = v.max(0.0);
        }
    }
}
