//! Circulant (periodic) operators on an `N₁ × N₂` grid with a real, even symbol:
//! `y = IFFT₂(σ · FFT₂(x))` without padding. Used as preconditioners: the half-space compliance has
//! the symbol `2/(E*|k|)` (spec `sam.md` §3.2), so the circulant with symbol `|k|` flattens its
//! spectrum ([`Circulant2d::inverse_half_space`]; Vollebregt 2014, J. Comput. Phys. 257, §4).
//!
//! Rows are transformed real-to-complex (`N₂ → N₂/2 + 1`), columns complex; rows and columns run
//! in parallel (rayon) from [`crate::fft2d::PARALLEL_CELLS`] cells on. Applying does not allocate.

use std::sync::Arc;

use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::{Fft, FftPlanner};

use crate::fft2d::{gather_block, C64, PARALLEL_CELLS, TRANSPOSE_BLOCK};
use crate::NumericsError;

/// One thread's share of the forward rows: (chunk index, ((row spectra, real row), scratch)).
type RowChunk<'a> = (usize, ((&'a mut [C64], &'a mut Vec<f64>), &'a mut Vec<C64>));
/// One thread's share of the inverse rows: (chunk index, ((row spectra, output rows), scratch)).
type InverseChunk<'a> = (usize, ((&'a mut [C64], &'a mut [f64]), &'a mut Vec<C64>));

/// A periodic convolution with a real symbol, planned once.
pub struct Circulant2d {
    n1: usize,
    n2: usize,
    row_fwd: Arc<dyn RealToComplex<f64>>,
    row_inv: Arc<dyn ComplexToReal<f64>>,
    col_fwd: Arc<dyn Fft<f64>>,
    col_inv: Arc<dyn Fft<f64>>,
    /// `σ(m, n) / (N₁N₂)`, row-major `N₁ × (N₂/2 + 1)`.
    symbol: Vec<f64>,
    /// Row spectra, row-major `N₁ × (N₂/2 + 1)`.
    rows: Vec<C64>,
    /// Column-major copy for the column transforms, `(N₂/2 + 1) × N₁`.
    cols: Vec<C64>,
    /// One real row per worker thread (the row transform overwrites its input).
    row_real: Vec<Vec<f64>>,
    scratch: Vec<Vec<C64>>,
    parallel: bool,
}

impl Circulant2d {
    /// Plans the operator with symbol `sigma(m, n)` at the DFT indices `m ∈ [0, N₁)`,
    /// `n ∈ [0, N₂/2]` (wavenumbers `k₁ = 2π m̃/(N₁ d₁)` with `m̃` the signed index). The symbol
    /// must be real and even (`σ(−k) = σ(k)`), so that the operator is symmetric.
    pub fn new(
        n1: usize,
        n2: usize,
        sigma: &dyn Fn(usize, usize) -> f64,
    ) -> Result<Self, NumericsError> {
        if n1 < 2 || n2 < 2 {
            return Err(NumericsError::TooFewNodes {
                what: "a circulant grid side",
                min: 2,
                n: n1.min(n2),
            });
        }
        let h2 = n2 / 2 + 1;
        let mut rplanner = RealFftPlanner::<f64>::new();
        let mut cplanner = FftPlanner::<f64>::new();
        let row_fwd = rplanner.plan_fft_forward(n2);
        let row_inv = rplanner.plan_fft_inverse(n2);
        let col_fwd = cplanner.plan_fft_forward(n1);
        let col_inv = cplanner.plan_fft_inverse(n1);
        let scratch_len = row_fwd
            .get_scratch_len()
            .max(row_inv.get_scratch_len())
            .max(col_fwd.get_inplace_scratch_len())
            .max(col_inv.get_inplace_scratch_len())
            .max(1);
        let parallel = n1 * n2 >= PARALLEL_CELLS;
        let threads = if parallel {
            rayon::current_num_threads().max(1)
        } else {
            1
        };
        let scale = 1.0 / (n1 * n2) as f64;
        let mut symbol = vec![0.0; n1 * h2];
        for m in 0..n1 {
            for n in 0..h2 {
                let s = sigma(m, n);
                if !s.is_finite() {
                    return Err(NumericsError::InvalidParameter {
                        name: "circulant symbol value",
                        value: s,
                        allowed: "finite",
                    });
                }
                symbol[m * h2 + n] = s * scale;
            }
        }
        Ok(Self {
            n1,
            n2,
            row_fwd,
            row_inv,
            col_fwd,
            col_inv,
            symbol,
            rows: vec![C64::new(0.0, 0.0); n1 * h2],
            cols: vec![C64::new(0.0, 0.0); n1 * h2],
            row_real: vec![vec![0.0; n2]; threads],
            scratch: vec![vec![C64::new(0.0, 0.0); scratch_len]; threads],
            parallel,
        })
    }

    /// The circulant approximating the inverse of the half-space compliance on cells of size
    /// `d₁ × d₂`: symbol `|k| = (k₁² + k₂²)^{1/2}` at the signed wavenumbers `k_α = 2π m̃_α/(N_α d_α)`,
    /// and at `k = 0` the smallest nonzero `|k|` (the symbol of the compliance is infinite there;
    /// the constant mode keeps a finite weight so that the approach-controlled solve can move it).
    pub fn inverse_half_space(
        n1: usize,
        n2: usize,
        d1: f64,
        d2: f64,
    ) -> Result<Self, NumericsError> {
        let k1 = |m: usize| {
            let s = if m <= n1 / 2 {
                m as f64
            } else {
                m as f64 - n1 as f64
            };
            2.0 * std::f64::consts::PI * s / (n1 as f64 * d1)
        };
        let k2 = |n: usize| 2.0 * std::f64::consts::PI * n as f64 / (n2 as f64 * d2);
        let k_min = k1(1).min(k2(1));
        Self::new(n1, n2, &|m, n| {
            let k = k1(m).hypot(k2(n));
            if m == 0 && n == 0 {
                k_min
            } else {
                k
            }
        })
    }

    /// Grid shape `(N₁, N₂)`.
    pub fn shape(&self) -> (usize, usize) {
        (self.n1, self.n2)
    }

    /// `y = IFFT₂(σ · FFT₂(x))` (periodic). `x` and `y` may not alias.
    pub fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        let (n1, n2) = (self.n1, self.n2);
        for v in [x.len(), y.len()] {
            if v != n1 * n2 {
                return Err(NumericsError::LengthMismatch {
                    what: "circulant field",
                    expected: n1 * n2,
                    got: v,
                });
            }
        }
        let h2 = n2 / 2 + 1;
        // Rows: real → complex.
        let fwd = &self.row_fwd;
        let threads = self.scratch.len();
        let chunk = n1.div_ceil(threads);
        let row_body = |(t, ((c, buf), s)): RowChunk<'_>| {
            for (k, cc) in c.chunks_mut(h2).enumerate() {
                let a = t * chunk + k;
                buf.copy_from_slice(&x[a * n2..(a + 1) * n2]);
                fwd.process_with_scratch(buf, cc, s)
                    .expect("lengths from the plan");
            }
        };
        if self.parallel {
            self.rows
                .par_chunks_mut(chunk * h2)
                .zip(self.row_real.par_iter_mut())
                .zip(self.scratch.par_iter_mut())
                .enumerate()
                .for_each(row_body);
        } else {
            row_body((
                0,
                (
                    (&mut self.rows, &mut self.row_real[0]),
                    &mut self.scratch[0],
                ),
            ));
        }
        // Columns: transpose, forward, multiply by the symbol, inverse, transpose back.
        let (rows, symbol) = (&self.rows, &self.symbol);
        let (cf, ci) = (&self.col_fwd, &self.col_inv);
        let cchunk = h2.div_ceil(threads);
        let col_body = |(t, (cols, s)): (usize, (&mut [C64], &mut Vec<C64>))| {
            let first = t * cchunk;
            let ncols = cols.len() / n1;
            for g in (0..ncols).step_by(TRANSPOSE_BLOCK) {
                let w = TRANSPOSE_BLOCK.min(ncols - g);
                let block = &mut cols[g * n1..(g + w) * n1];
                gather_block(rows, h2, first + g, n1, block);
                for (c, column) in block.chunks_mut(n1).enumerate() {
                    let b = first + g + c;
                    cf.process_with_scratch(column, s);
                    for (a, v) in column.iter_mut().enumerate() {
                        *v *= symbol[a * h2 + b];
                    }
                    ci.process_with_scratch(column, s);
                }
            }
        };
        if self.parallel {
            self.cols
                .par_chunks_mut(cchunk * n1)
                .zip(self.scratch.par_iter_mut())
                .enumerate()
                .for_each(col_body);
        } else {
            col_body((0, (&mut self.cols, &mut self.scratch[0])));
        }
        // Rows back: complex → real.
        let cols = &self.cols;
        let inv = &self.row_inv;
        let inv_body = |(t, ((c, out), s)): InverseChunk<'_>| {
            let nrows = c.len() / h2;
            for g in (0..nrows).step_by(TRANSPOSE_BLOCK) {
                let w = TRANSPOSE_BLOCK.min(nrows - g);
                let a0 = t * chunk + g;
                let block = &mut c[g * h2..(g + w) * h2];
                gather_block(cols, n1, a0, h2, block);
                let oblock = &mut out[g * n2..(g + w) * n2];
                for (cc, yy) in block.chunks_mut(h2).zip(oblock.chunks_mut(n2)) {
                    cc[0].im = 0.0;
                    if n2 % 2 == 0 {
                        cc[h2 - 1].im = 0.0;
                    }
                    inv.process_with_scratch(cc, yy, s)
                        .expect("lengths from the plan");
                }
            }
        };
        if self.parallel {
            self.rows
                .par_chunks_mut(chunk * h2)
                .zip(y.par_chunks_mut(chunk * n2))
                .zip(self.scratch.par_iter_mut())
                .enumerate()
                .for_each(inv_body);
        } else {
            inv_body((0, ((&mut self.rows, y), &mut self.scratch[0])));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the direct periodic convolution with an even stencil whose DFT is the symbol in
    /// closed form (`a + 2b cos θ₁ + 2c cos θ₂ + 4d cos θ₁ cos θ₂`); the largest grid runs the
    /// parallel path.
    #[test]
    fn matches_direct_periodic_convolution() {
        let (a, b, c, d) = (4.0, -0.7, 0.3, 0.2);
        for (n1, n2) in [(6, 8), (7, 5), (130, 129)] {
            let tau = 2.0 * std::f64::consts::PI;
            let sigma = |m: usize, n: usize| {
                let (t1, t2) = (tau * m as f64 / n1 as f64, tau * n as f64 / n2 as f64);
                a + 2.0 * b * t1.cos() + 2.0 * c * t2.cos() + 4.0 * d * t1.cos() * t2.cos()
            };
            let mut op = Circulant2d::new(n1, n2, &sigma).unwrap();
            let x: Vec<f64> = (0..n1 * n2).map(|k| ((k * 37 % 11) as f64) - 5.0).collect();
            let mut y = vec![0.0; n1 * n2];
            op.apply(&x, &mut y).unwrap();
            let at = |i: isize, j: isize| {
                x[(i.rem_euclid(n1 as isize) as usize) * n2 + j.rem_euclid(n2 as isize) as usize]
            };
            let mut worst: f64 = 0.0;
            for i in 0..n1 as isize {
                for j in 0..n2 as isize {
                    let s = a * at(i, j)
                        + b * (at(i - 1, j) + at(i + 1, j))
                        + c * (at(i, j - 1) + at(i, j + 1))
                        + d * (at(i - 1, j - 1)
                            + at(i - 1, j + 1)
                            + at(i + 1, j - 1)
                            + at(i + 1, j + 1));
                    worst = worst.max((s - y[i as usize * n2 + j as usize]).abs());
                }
            }
            assert!(worst < 1e-12, "{n1}×{n2}: {worst:e}");
        }
    }
}
