//! DC-FFT (Liu, Wang & Liu 2000; spec `sam.md` §2): linear (non-periodic) 2D convolution
//! `u_ij = Σ_{k,l} K_{i−k, j−l} p_kl` on an `N₁ × N₂` grid, for block operators (`n_out × n_in`
//! kernels: the 2 × 2 tangential compliance, …). The kernel is laid out on a `2N₁ × 2N₂` array with
//! offsets `−(N−1)..N−1` and the `N`-th row and column zero, transformed once; inputs are
//! zero-padded, transformed, multiplied and summed per output, transformed back and cropped.
//! [`DenseConvolution2d`] evaluates the same sum directly (O(N⁴)), as the control in tests.

use std::sync::Arc;

use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::{num_complex::Complex, Fft, FftPlanner};

use crate::NumericsError;

/// A linear operator on `n_in` grids of `N₁ × N₂` values (row-major, index `i N₂ + j`), giving
/// `n_out` grids. Applying does not allocate.
pub trait GridOperator {
    /// Grid shape `(N₁, N₂)`.
    fn shape(&self) -> (usize, usize);
    /// `y_o = Σ_i K_{oi} * x_i` for every output `o`.
    fn apply(&mut self, x: &[&[f64]], y: &mut [&mut [f64]]) -> Result<(), NumericsError>;
}

/// A scratch buffer of complex values.
type Scratch = Vec<Complex<f64>>;
/// One thread's share of a row transform: (real rows, complex rows), scratch.
type RowChunk<'a> = ((&'a mut [f64], &'a mut [Complex<f64>]), &'a mut Scratch);
/// One thread's share of a column transform: (first column index / chunk, columns, scratch).
type ColChunk<'a> = (usize, (&'a mut [Complex<f64>], &'a mut Scratch));

/// One thread's share of the inverse row transforms: (first row / chunk, (complex rows, real rows),
/// scratch).
type InverseRowChunk<'a> = (
    usize,
    ((&'a mut [Complex<f64>], &'a mut [f64]), &'a mut Scratch),
);

/// Grids with at least this many cells are transformed with rayon.
const PARALLEL_CELLS: usize = 128 * 128;

/// Kernel of one block: `K(m, n)` for offsets `m ∈ (−N₁, N₁)`, `n ∈ (−N₂, N₂)`.
pub type KernelFn<'a> = &'a dyn Fn(i64, i64) -> f64;

/// The DC-FFT block operator, planned once.
pub struct DcFft2d {
    n1: usize,
    n2: usize,
    n_in: usize,
    n_out: usize,
    /// `spectra[o * n_in + i]`: FFT₂ of the padded kernel / (4 N₁ N₂), column-major, or `None` for a
    /// zero block.
    spectra: Vec<Option<Vec<Complex<f64>>>>,
    row_fwd: Arc<dyn RealToComplex<f64>>,
    row_inv: Arc<dyn ComplexToReal<f64>>,
    col_fwd: Arc<dyn Fft<f64>>,
    col_inv: Arc<dyn Fft<f64>>,
    real: Vec<f64>,
    /// Row transforms, `2N₁ × (N₂+1)` row-major.
    rows: Vec<Complex<f64>>,
    inputs_hat: Vec<Vec<Complex<f64>>>,
    out_hat: Vec<Complex<f64>>,
    /// One scratch buffer per worker thread (rows and columns are transformed in parallel).
    row_scratch: Vec<Vec<Complex<f64>>>,
    col_scratch: Vec<Vec<Complex<f64>>>,
}

impl DcFft2d {
    /// Plans the operator for kernels `kernels[o * n_in + i]` (`None` = zero block).
    pub fn new(
        n1: usize,
        n2: usize,
        n_in: usize,
        n_out: usize,
        kernels: &[Option<KernelFn<'_>>],
    ) -> Result<Self, NumericsError> {
        if n1 < 2 || n2 < 2 {
            return Err(NumericsError::TooFewNodes {
                what: "a DC-FFT grid side",
                min: 2,
                n: n1.min(n2),
            });
        }
        if kernels.len() != n_in * n_out {
            return Err(NumericsError::LengthMismatch {
                what: "DC-FFT kernel blocks",
                expected: n_in * n_out,
                got: kernels.len(),
            });
        }
        let (p1, p2) = (2 * n1, 2 * n2);
        let mut rplanner = RealFftPlanner::<f64>::new();
        let mut cplanner = FftPlanner::<f64>::new();
        let row_fwd = rplanner.plan_fft_forward(p2);
        let row_inv = rplanner.plan_fft_inverse(p2);
        let col_fwd = cplanner.plan_fft_forward(p1);
        let col_inv = cplanner.plan_fft_inverse(p1);
        let spec_len = p1 * (n2 + 1);
        let row_scratch_len = row_fwd.get_scratch_len().max(row_inv.get_scratch_len());
        let col_scratch_len = col_fwd
            .get_inplace_scratch_len()
            .max(col_inv.get_inplace_scratch_len());
        // Threads pay only on large grids: below 128² the rayon hand-offs cost more than they save.
        let threads = if n1 * n2 >= PARALLEL_CELLS {
            rayon::current_num_threads().max(1)
        } else {
            1
        };
        let mut op = Self {
            n1,
            n2,
            n_in,
            n_out,
            spectra: Vec::new(),
            row_fwd,
            row_inv,
            col_fwd,
            col_inv,
            real: vec![0.0; p1 * p2],
            rows: vec![Complex::new(0.0, 0.0); spec_len],
            inputs_hat: vec![vec![Complex::new(0.0, 0.0); spec_len]; n_in],
            out_hat: vec![Complex::new(0.0, 0.0); spec_len],
            row_scratch: vec![vec![Complex::new(0.0, 0.0); row_scratch_len]; threads],
            col_scratch: vec![vec![Complex::new(0.0, 0.0); col_scratch_len.max(1)]; threads],
        };
        let scale = 1.0 / (p1 * p2) as f64;
        for kernel in kernels {
            let spectrum = match kernel {
                None => None,
                Some(k) => {
                    for a in 0..p1 {
                        for b in 0..p2 {
                            let m = wrap(a, n1);
                            let n = wrap(b, n2);
                            op.real[a * p2 + b] = match (m, n) {
                                (Some(m), Some(n)) => k(m, n),
                                _ => 0.0,
                            };
                        }
                    }
                    if let Some(bad) = op.real.iter().find(|v| !v.is_finite()) {
                        return Err(NumericsError::InvalidParameter {
                            name: "DC-FFT kernel value",
                            value: *bad,
                            allowed: "finite",
                        });
                    }
                    let mut spec = vec![Complex::new(0.0, 0.0); spec_len];
                    op.forward_real(&mut spec, p1);
                    spec.iter_mut().for_each(|s| *s *= scale);
                    Some(spec)
                }
            };
            op.spectra.push(spectrum);
        }
        Ok(op)
    }

    /// Spectrum of `self.real` (overwritten), stored column-major (`(N₂+1) × 2N₁`, column `b` at
    /// `b · 2N₁`); only its first `nonzero_rows` rows may be nonzero (the zero padding is skipped).
    /// Rows and then columns are transformed in parallel, one preallocated scratch per thread.
    fn forward_real(&mut self, spec: &mut [Complex<f64>], nonzero_rows: usize) {
        let (p1, p2, h2) = (2 * self.n1, 2 * self.n2, self.n2 + 1);
        let threads = self.row_scratch.len();
        let chunk = nonzero_rows.div_ceil(threads).max(1);
        let fwd = &self.row_fwd;
        let body = |((real, rows), scratch): RowChunk<'_>| {
            for (r, c) in real.chunks_mut(p2).zip(rows.chunks_mut(h2)) {
                fwd.process_with_scratch(r, c, scratch)
                    .expect("lengths from the plan");
            }
        };
        let (real, rows) = (
            &mut self.real[..nonzero_rows * p2],
            &mut self.rows[..nonzero_rows * h2],
        );
        if threads > 1 {
            real.par_chunks_mut(chunk * p2)
                .zip(rows.par_chunks_mut(chunk * h2))
                .zip(self.row_scratch.par_iter_mut())
                .for_each(body);
        } else {
            body(((real, rows), &mut self.row_scratch[0]));
        }
        self.rows[nonzero_rows * h2..].fill(Complex::new(0.0, 0.0));
        // Transpose to columns and transform them.
        let rows = &self.rows;
        let col = &self.col_fwd;
        let chunk = h2.div_ceil(threads).max(1);
        let body = |(t, (cols, scratch)): ColChunk<'_>| {
            for (k, column) in cols.chunks_mut(p1).enumerate() {
                let b = t * chunk + k;
                for (a, v) in column.iter_mut().enumerate() {
                    *v = rows[a * h2 + b];
                }
                col.process_with_scratch(column, scratch);
            }
        };
        if threads > 1 {
            spec.par_chunks_mut(chunk * p1)
                .zip(self.col_scratch.par_iter_mut())
                .enumerate()
                .for_each(body);
        } else {
            body((0, (spec, &mut self.col_scratch[0])));
        }
    }

    /// Writes the first `N₁` rows of the inverse transform of `self.out_hat` (column-major) into
    /// `self.real` (only those rows are kept by the crop).
    fn inverse_to_real(&mut self) {
        let (n1, p1, p2, h2) = (self.n1, 2 * self.n1, 2 * self.n2, self.n2 + 1);
        let threads = self.col_scratch.len();
        let inv = &self.col_inv;
        let chunk = h2.div_ceil(threads).max(1);
        let body = |(cols, scratch): (&mut [Complex<f64>], &mut Scratch)| {
            for column in cols.chunks_mut(p1) {
                inv.process_with_scratch(column, scratch);
            }
        };
        if threads > 1 {
            self.out_hat
                .par_chunks_mut(chunk * p1)
                .zip(self.col_scratch.par_iter_mut())
                .for_each(body);
        } else {
            body((&mut self.out_hat, &mut self.col_scratch[0]));
        }
        let out = &self.out_hat;
        let rinv = &self.row_inv;
        let chunk = n1.div_ceil(threads).max(1);
        let body = |(t, ((rows, real), scratch)): InverseRowChunk<'_>| {
            for (k, (row, r)) in rows.chunks_mut(h2).zip(real.chunks_mut(p2)).enumerate() {
                let a = t * chunk + k;
                for (b, v) in row.iter_mut().enumerate() {
                    *v = out[b * p1 + a];
                }
                row[0].im = 0.0;
                row[h2 - 1].im = 0.0;
                rinv.process_with_scratch(row, r, scratch)
                    .expect("lengths from the plan");
            }
        };
        let (rows, real) = (&mut self.rows[..n1 * h2], &mut self.real[..n1 * p2]);
        if threads > 1 {
            rows.par_chunks_mut(chunk * h2)
                .zip(real.par_chunks_mut(chunk * p2))
                .zip(self.row_scratch.par_iter_mut())
                .enumerate()
                .for_each(body);
        } else {
            body((0, ((rows, real), &mut self.row_scratch[0])));
        }
    }

    /// The block spectra (for bounds such as the largest eigenvalue of the operator).
    pub fn spectrum(&self, out: usize, input: usize) -> Option<&[Complex<f64>]> {
        self.spectra[out * self.n_in + input].as_deref()
    }
}

/// Padded index → offset: `a < N` ↦ `a`, `a > N` ↦ `a − 2N`, `a = N` ↦ none (zero row).
fn wrap(a: usize, n: usize) -> Option<i64> {
    if a < n {
        Some(a as i64)
    } else if a == n {
        None
    } else {
        Some(a as i64 - 2 * n as i64)
    }
}

fn check_io(
    n_in: usize,
    n_out: usize,
    len: usize,
    x: &[&[f64]],
    y: &[&mut [f64]],
) -> Result<(), NumericsError> {
    if x.len() != n_in {
        return Err(NumericsError::LengthMismatch {
            what: "grid operator inputs (fields)",
            expected: n_in,
            got: x.len(),
        });
    }
    if y.len() != n_out {
        return Err(NumericsError::LengthMismatch {
            what: "grid operator outputs (fields)",
            expected: n_out,
            got: y.len(),
        });
    }
    for v in x.iter().map(|v| v.len()).chain(y.iter().map(|v| v.len())) {
        if v != len {
            return Err(NumericsError::LengthMismatch {
                what: "grid operator field",
                expected: len,
                got: v,
            });
        }
    }
    Ok(())
}

impl GridOperator for DcFft2d {
    fn shape(&self) -> (usize, usize) {
        (self.n1, self.n2)
    }

    fn apply(&mut self, x: &[&[f64]], y: &mut [&mut [f64]]) -> Result<(), NumericsError> {
        let (n1, n2) = (self.n1, self.n2);
        check_io(self.n_in, self.n_out, n1 * n2, x, y)?;
        let p2 = 2 * n2;
        for (i, xi) in x.iter().enumerate() {
            for a in 0..n1 {
                self.real[a * p2..a * p2 + n2].copy_from_slice(&xi[a * n2..(a + 1) * n2]);
                self.real[a * p2 + n2..(a + 1) * p2].fill(0.0);
            }
            let mut spec = std::mem::take(&mut self.inputs_hat[i]);
            self.forward_real(&mut spec, n1);
            self.inputs_hat[i] = spec;
        }
        for (o, yo) in y.iter_mut().enumerate() {
            self.out_hat.fill(Complex::new(0.0, 0.0));
            let mut any = false;
            for i in 0..self.n_in {
                if let Some(k) = &self.spectra[o * self.n_in + i] {
                    any = true;
                    for ((s, a), b) in self.out_hat.iter_mut().zip(k).zip(&self.inputs_hat[i]) {
                        *s += a * b;
                    }
                }
            }
            if !any {
                yo.fill(0.0);
                continue;
            }
            self.inverse_to_real();
            for a in 0..n1 {
                yo[a * n2..(a + 1) * n2].copy_from_slice(&self.real[a * p2..a * p2 + n2]);
            }
        }
        Ok(())
    }
}

/// The direct sum `u_ij = Σ_kl K_{i−k, j−l} p_kl` (O(N⁴)), with the kernels tabulated once.
pub struct DenseConvolution2d {
    n1: usize,
    n2: usize,
    n_in: usize,
    n_out: usize,
    /// `tables[o * n_in + i][(m + N₁ − 1)(2N₂ − 1) + n + N₂ − 1]`.
    tables: Vec<Option<Vec<f64>>>,
}

impl DenseConvolution2d {
    /// Tabulates the kernels.
    pub fn new(
        n1: usize,
        n2: usize,
        n_in: usize,
        n_out: usize,
        kernels: &[Option<KernelFn<'_>>],
    ) -> Result<Self, NumericsError> {
        if kernels.len() != n_in * n_out {
            return Err(NumericsError::LengthMismatch {
                what: "dense kernel blocks",
                expected: n_in * n_out,
                got: kernels.len(),
            });
        }
        let w = 2 * n2 - 1;
        let tables = kernels
            .iter()
            .map(|k| {
                k.map(|k| {
                    let mut t = vec![0.0; (2 * n1 - 1) * w];
                    for m in -(n1 as i64 - 1)..n1 as i64 {
                        for n in -(n2 as i64 - 1)..n2 as i64 {
                            t[(m + n1 as i64 - 1) as usize * w + (n + n2 as i64 - 1) as usize] =
                                k(m, n);
                        }
                    }
                    t
                })
            })
            .collect();
        Ok(Self {
            n1,
            n2,
            n_in,
            n_out,
            tables,
        })
    }
}

impl GridOperator for DenseConvolution2d {
    fn shape(&self) -> (usize, usize) {
        (self.n1, self.n2)
    }

    fn apply(&mut self, x: &[&[f64]], y: &mut [&mut [f64]]) -> Result<(), NumericsError> {
        let (n1, n2) = (self.n1, self.n2);
        check_io(self.n_in, self.n_out, n1 * n2, x, y)?;
        let w = 2 * n2 - 1;
        for (o, yo) in y.iter_mut().enumerate() {
            for i in 0..n1 {
                for j in 0..n2 {
                    let mut s = 0.0;
                    for (inp, xi) in x.iter().enumerate() {
                        let Some(t) = &self.tables[o * self.n_in + inp] else {
                            continue;
                        };
                        for k in 0..n1 {
                            let row = (i + n1 - 1 - k) * w + (j + n2 - 1);
                            for l in 0..n2 {
                                s += t[row - l] * xi[k * n2 + l];
                            }
                        }
                    }
                    yo[i * n2 + j] = s;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(seed: u64, n: usize) -> Vec<f64> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
            })
            .collect()
    }

    #[test]
    fn dcfft_equals_the_direct_sum_with_fixed_seeds() {
        let k1 = |m: i64, n: i64| 1.0 / (1.0 + (m * m + 2 * n * n) as f64).sqrt() + 0.1 * m as f64;
        let k2 = |m: i64, n: i64| (m as f64 * 0.3).sin() * (n as f64 * 0.7).cos();
        for (n1, n2) in [(2usize, 2usize), (5, 7), (16, 16), (13, 8)] {
            let kernels: [Option<KernelFn>; 4] = [Some(&k1), Some(&k2), None, Some(&k1)];
            let mut fast = DcFft2d::new(n1, n2, 2, 2, &kernels).unwrap();
            let mut dense = DenseConvolution2d::new(n1, n2, 2, 2, &kernels).unwrap();
            let (a, b) = (lcg(n1 as u64, n1 * n2), lcg(n2 as u64 + 9, n1 * n2));
            let (mut f0, mut f1) = (vec![0.0; n1 * n2], vec![0.0; n1 * n2]);
            let (mut d0, mut d1) = (vec![0.0; n1 * n2], vec![0.0; n1 * n2]);
            fast.apply(&[&a, &b], &mut [&mut f0, &mut f1]).unwrap();
            dense.apply(&[&a, &b], &mut [&mut d0, &mut d1]).unwrap();
            let scale = d0.iter().chain(&d1).fold(0.0f64, |m, v| m.max(v.abs()));
            let err = f0
                .iter()
                .zip(&d0)
                .chain(f1.iter().zip(&d1))
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            assert!(err <= 1e-13 * scale, "{n1}×{n2}: {err:e} of {scale:e}");
        }
    }

    #[test]
    fn bad_shapes_are_errors() {
        let k = |_: i64, _: i64| 1.0;
        assert!(DcFft2d::new(1, 4, 1, 1, &[Some(&k)]).is_err());
        assert!(DcFft2d::new(4, 4, 1, 1, &[]).is_err());
        let mut op = DcFft2d::new(4, 4, 1, 1, &[Some(&k)]).unwrap();
        let mut y = vec![0.0; 15];
        assert!(op.apply(&[&[0.0; 16]], &mut [&mut y]).is_err());
        let nan = |_: i64, _: i64| f64::NAN;
        assert!(DcFft2d::new(4, 4, 1, 1, &[Some(&nan)]).is_err());
    }
}
