//! One padded 2D real-FFT plan (spec `sam.md` §2): fields of `N₁ × N₂` values are zero-padded to
//! `2N₁ × 2N₂`, transformed (real-to-complex rows, complex columns) and stored as **spectra** of
//! `2N₁ (N₂ + 1)` complex values, column-major (column `b` at `b · 2N₁`, the layout the column
//! transforms produce). A DC-FFT product is then `IFFT₂(K̂ · X̂)` cropped to `N₁ × N₂`; every
//! operator of the workspace (surface compliances, layered eigenstrain kernels, Love stresses) builds
//! its kernel spectra with [`Fft2d::kernel_spectrum`] and multiplies spectra produced by
//! [`Fft2d::forward`], so one input transformed once serves several operators.
//!
//! Rows and columns are transformed in parallel (rayon) on grids of at least 128² cells, each thread
//! with its own preallocated scratch; below that, sequentially. Transforms do not allocate.

use std::sync::Arc;

use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::{num_complex::Complex, Fft, FftPlanner};

use crate::NumericsError;

/// A complex spectrum value.
pub type C64 = Complex<f64>;

/// A scratch buffer of complex values.
type Scratch = Vec<C64>;
/// One thread's share of a row transform: (chunk index, ((row spectra, padded real row),
/// scratch)).
type RowChunk<'a> = (usize, ((&'a mut [C64], &'a mut Vec<f64>), &'a mut Scratch));
/// One thread's share of a column transform: (chunk index, (columns, scratch)).
type ColChunk<'a> = (usize, (&'a mut [C64], &'a mut Scratch));
/// One thread's share of the inverse row transforms: (chunk index, (((complex rows, output rows),
/// padded real row), scratch)).
type InverseRowChunk<'a> = (
    usize,
    (
        ((&'a mut [C64], &'a mut [f64]), &'a mut Vec<f64>),
        &'a mut Scratch,
    ),
);

/// Columns (rows) gathered together in the transposes between the row and column transforms.
pub(crate) const TRANSPOSE_BLOCK: usize = 8;

/// Grids with at least this many cells are transformed with rayon.
pub const PARALLEL_CELLS: usize = 128 * 128;

/// Kernel of one block: `K(m, n)` for offsets `m ∈ (−N₁, N₁)`, `n ∈ (−N₂, N₂)`.
pub type KernelFn<'a> = &'a dyn Fn(i64, i64) -> f64;

/// The padded 2D FFT of `N₁ × N₂` fields, planned once.
pub struct Fft2d {
    n1: usize,
    n2: usize,
    row_fwd: Arc<dyn RealToComplex<f64>>,
    row_inv: Arc<dyn ComplexToReal<f64>>,
    col_fwd: Arc<dyn Fft<f64>>,
    col_inv: Arc<dyn Fft<f64>>,
    /// One padded real row (`2N₂` values) per worker thread: fields are padded row by row, so no
    /// `2N₁ × 2N₂` real array is held.
    row_real: Vec<Vec<f64>>,
    /// Row transforms, `2N₁ × (N₂+1)` row-major.
    rows: Vec<C64>,
    /// One scratch buffer per worker thread.
    row_scratch: Vec<Scratch>,
    col_scratch: Vec<Scratch>,
}

impl Fft2d {
    /// Plans the transforms of `n1 × n2` fields (`n1, n2 ≥ 2`).
    pub fn new(n1: usize, n2: usize) -> Result<Self, NumericsError> {
        if n1 < 2 || n2 < 2 {
            return Err(NumericsError::TooFewNodes {
                what: "a DC-FFT grid side",
                min: 2,
                n: n1.min(n2),
            });
        }
        let (p1, p2) = (2 * n1, 2 * n2);
        let mut rplanner = RealFftPlanner::<f64>::new();
        let mut cplanner = FftPlanner::<f64>::new();
        let row_fwd = rplanner.plan_fft_forward(p2);
        let row_inv = rplanner.plan_fft_inverse(p2);
        let col_fwd = cplanner.plan_fft_forward(p1);
        let col_inv = cplanner.plan_fft_inverse(p1);
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
        Ok(Self {
            n1,
            n2,
            row_fwd,
            row_inv,
            col_fwd,
            col_inv,
            row_real: vec![vec![0.0; p2]; threads],
            rows: vec![C64::new(0.0, 0.0); p1 * (n2 + 1)],
            row_scratch: vec![vec![C64::new(0.0, 0.0); row_scratch_len]; threads],
            col_scratch: vec![vec![C64::new(0.0, 0.0); col_scratch_len.max(1)]; threads],
        })
    }

    /// Grid shape `(N₁, N₂)`.
    pub fn shape(&self) -> (usize, usize) {
        (self.n1, self.n2)
    }

    /// Length of one spectrum, `2N₁ (N₂ + 1)`.
    pub fn spectrum_len(&self) -> usize {
        2 * self.n1 * (self.n2 + 1)
    }

    /// A zeroed spectrum buffer.
    pub fn new_spectrum(&self) -> Vec<C64> {
        vec![C64::new(0.0, 0.0); self.spectrum_len()]
    }

    /// The spectrum of the DC-FFT kernel layout of `k` (spec §2 step 1–2: offsets `−(N−1)..N−1`
    /// wrapped, the `N`-th row and column zero), divided by `4N₁N₂` so that [`Fft2d::inverse`]
    /// needs no normalisation. Non-finite kernel values are an error.
    pub fn kernel_spectrum(
        &mut self,
        k: KernelFn<'_>,
        out: &mut [C64],
    ) -> Result<(), NumericsError> {
        self.check_spectrum(out)?;
        let (n1, n2) = (self.n1, self.n2);
        let (p1, p2) = (2 * n1, 2 * n2);
        // Setup only: the padded kernel is tabulated once (the kernel need not be thread-safe).
        let mut table = vec![0.0; p1 * p2];
        for a in 0..p1 {
            for b in 0..p2 {
                table[a * p2 + b] = match (wrap(a, n1), wrap(b, n2)) {
                    (Some(m), Some(n)) => k(m, n),
                    _ => 0.0,
                };
            }
        }
        if let Some(bad) = table.iter().find(|v| !v.is_finite()) {
            return Err(NumericsError::InvalidParameter {
                name: "DC-FFT kernel value",
                value: *bad,
                allowed: "finite",
            });
        }
        self.forward_padded(
            &|a, row| row.copy_from_slice(&table[a * p2..(a + 1) * p2]),
            out,
            0..p1,
        );
        let scale = 1.0 / (p1 * p2) as f64;
        out.iter_mut().for_each(|s| *s *= scale);
        Ok(())
    }

    /// The spectrum of a kernel even in both offsets, `K(m, n) = K(|m|, |n|)`, from its quadrant
    /// `quadrant[m N₂ + n] = K(m, n)` (`0 ≤ m < N₁`, `0 ≤ n < N₂`). The DFT of a real sequence even
    /// in both indices is real, so only the real part is stored (`out.len()` =
    /// [`Fft2d::spectrum_len`]), divided by `4N₁N₂` as in [`Fft2d::kernel_spectrum`].
    pub fn even_kernel_spectrum(
        &mut self,
        quadrant: &[f64],
        out: &mut [f64],
    ) -> Result<(), NumericsError> {
        let (n1, n2) = (self.n1, self.n2);
        if quadrant.len() != n1 * n2 || out.len() != self.spectrum_len() {
            return Err(NumericsError::LengthMismatch {
                what: "even kernel quadrant (or its real spectrum)",
                expected: n1 * n2,
                got: quadrant.len(),
            });
        }
        if let Some(bad) = quadrant.iter().find(|v| !v.is_finite()) {
            return Err(NumericsError::InvalidParameter {
                name: "DC-FFT kernel value",
                value: *bad,
                allowed: "finite",
            });
        }
        let (p1, p2) = (2 * n1, 2 * n2);
        let fill = |a: usize, row: &mut [f64]| {
            for (b, v) in row.iter_mut().enumerate() {
                *v = match (wrap(a, n1), wrap(b, n2)) {
                    (Some(m), Some(n)) => {
                        quadrant[m.unsigned_abs() as usize * n2 + n.unsigned_abs() as usize]
                    }
                    _ => 0.0,
                };
            }
        };
        let mut spec = self.new_spectrum();
        self.forward_padded(&fill, &mut spec, 0..p1);
        let scale = 1.0 / (p1 * p2) as f64;
        for (o, s) in out.iter_mut().zip(&spec) {
            *o = s.re * scale;
        }
        Ok(())
    }

    /// Like [`Fft2d::kernel_spectrum`] from a tabulated kernel: `table[(m + N₁ − 1)(2N₂ − 1) + n +
    /// N₂ − 1] = K(m, n)`.
    pub fn table_spectrum(&mut self, table: &[f64], out: &mut [C64]) -> Result<(), NumericsError> {
        let (n1, n2) = (self.n1, self.n2);
        let w = 2 * n2 - 1;
        if table.len() != (2 * n1 - 1) * w {
            return Err(NumericsError::LengthMismatch {
                what: "tabulated DC-FFT kernel",
                expected: (2 * n1 - 1) * w,
                got: table.len(),
            });
        }
        let k =
            |m: i64, n: i64| table[(m + n1 as i64 - 1) as usize * w + (n + n2 as i64 - 1) as usize];
        self.kernel_spectrum(&k, out)
    }

    /// `out = FFT₂(x zero-padded)` for a field `x` of `N₁ × N₂` values (row-major).
    pub fn forward(&mut self, x: &[f64], out: &mut [C64]) -> Result<(), NumericsError> {
        let (n1, n2) = (self.n1, self.n2);
        if x.len() != n1 * n2 {
            return Err(NumericsError::LengthMismatch {
                what: "grid field",
                expected: n1 * n2,
                got: x.len(),
            });
        }
        self.check_spectrum(out)?;
        self.forward_rows(x, 0..n1, out)
    }

    /// [`Fft2d::forward`] of a field that is zero outside the rows `rows` (only those rows of `x` are
    /// read): the row transforms of the zero rows are skipped.
    pub fn forward_rows(
        &mut self,
        x: &[f64],
        rows: std::ops::Range<usize>,
        out: &mut [C64],
    ) -> Result<(), NumericsError> {
        let (n1, n2) = (self.n1, self.n2);
        if x.len() != n1 * n2 || rows.end > n1 || rows.start > rows.end {
            return Err(NumericsError::LengthMismatch {
                what: "grid field (or its row range)",
                expected: n1 * n2,
                got: x.len(),
            });
        }
        self.check_spectrum(out)?;
        let fill = |a: usize, row: &mut [f64]| {
            row[..n2].copy_from_slice(&x[a * n2..(a + 1) * n2]);
            row[n2..].fill(0.0);
        };
        self.forward_padded(&fill, out, rows);
        Ok(())
    }

    /// `y = IFFT₂(spec)` cropped to `N₁ × N₂` (the spectrum is overwritten). With spectra of
    /// [`Fft2d::kernel_spectrum`] times spectra of [`Fft2d::forward`] this is the DC-FFT product.
    pub fn inverse(&mut self, spec: &mut [C64], y: &mut [f64]) -> Result<(), NumericsError> {
        let (n1, n2) = (self.n1, self.n2);
        if y.len() != n1 * n2 {
            return Err(NumericsError::LengthMismatch {
                what: "grid field",
                expected: n1 * n2,
                got: y.len(),
            });
        }
        self.inverse_rows(spec, 0..n1, y)
    }

    /// [`Fft2d::inverse`] written only on the rows `rows` of `y` (the other rows are left as they
    /// are): the row transforms of the other rows are skipped.
    pub fn inverse_rows(
        &mut self,
        spec: &mut [C64],
        rows: std::ops::Range<usize>,
        y: &mut [f64],
    ) -> Result<(), NumericsError> {
        let (n1, n2) = (self.n1, self.n2);
        if y.len() != n1 * n2 || rows.end > n1 || rows.start > rows.end {
            return Err(NumericsError::LengthMismatch {
                what: "grid field (or its row range)",
                expected: n1 * n2,
                got: y.len(),
            });
        }
        self.check_spectrum(spec)?;
        self.inverse_cropped(spec, rows, y);
        Ok(())
    }

    fn check_spectrum(&self, s: &[C64]) -> Result<(), NumericsError> {
        if s.len() != self.spectrum_len() {
            return Err(NumericsError::LengthMismatch {
                what: "spectrum",
                expected: self.spectrum_len(),
                got: s.len(),
            });
        }
        Ok(())
    }

    /// Spectrum (column-major) of the padded field whose row `a` (`2N₂` values) `fill(a, row)`
    /// writes; only the rows `nonzero` may be nonzero (the row transforms of the others, and of
    /// the zero padding, are skipped).
    fn forward_padded(
        &mut self,
        fill: &(dyn Fn(usize, &mut [f64]) + Sync),
        spec: &mut [C64],
        nonzero: std::ops::Range<usize>,
    ) {
        let (p1, h2) = (2 * self.n1, self.n2 + 1);
        let threads = self.row_scratch.len();
        let chunk = nonzero.len().div_ceil(threads).max(1);
        let first = nonzero.start;
        let fwd = &self.row_fwd;
        let body = |(t, ((rows, real), scratch)): RowChunk<'_>| {
            for (k, c) in rows.chunks_mut(h2).enumerate() {
                fill(first + t * chunk + k, real);
                fwd.process_with_scratch(real, c, scratch)
                    .expect("lengths from the plan");
            }
        };
        let rows = &mut self.rows[nonzero.start * h2..nonzero.end * h2];
        if threads > 1 {
            rows.par_chunks_mut(chunk * h2)
                .zip(self.row_real.par_iter_mut())
                .zip(self.row_scratch.par_iter_mut())
                .enumerate()
                .for_each(body);
        } else {
            body((0, ((rows, &mut self.row_real[0]), &mut self.row_scratch[0])));
        }
        self.rows[..nonzero.start * h2].fill(C64::new(0.0, 0.0));
        self.rows[nonzero.end * h2..].fill(C64::new(0.0, 0.0));
        // Transpose to columns and transform them.
        let rows = &self.rows;
        let col = &self.col_fwd;
        let chunk = h2.div_ceil(threads).max(1);
        let body = |(t, (cols, scratch)): ColChunk<'_>| {
            // Gathered TRANSPOSE_BLOCK columns at a time: each row contributes a contiguous run
            // (the column-by-column gather read one value per cache line).
            let first = t * chunk;
            let ncols = cols.len() / p1;
            for g in (0..ncols).step_by(TRANSPOSE_BLOCK) {
                let w = TRANSPOSE_BLOCK.min(ncols - g);
                let block = &mut cols[g * p1..(g + w) * p1];
                gather_block(rows, h2, first + g, p1, block);
                for column in block.chunks_mut(p1) {
                    col.process_with_scratch(column, scratch);
                }
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

    /// Writes the rows `keep` (within the first `N₁`) of the inverse transform of `spec`
    /// (column-major, overwritten), cropped to `N₂` columns, into `y`.
    fn inverse_cropped(&mut self, spec: &mut [C64], keep: std::ops::Range<usize>, y: &mut [f64]) {
        let (p1, n2, h2) = (2 * self.n1, self.n2, self.n2 + 1);
        let threads = self.col_scratch.len();
        let inv = &self.col_inv;
        let chunk = h2.div_ceil(threads).max(1);
        let body = |(cols, scratch): (&mut [C64], &mut Scratch)| {
            for column in cols.chunks_mut(p1) {
                inv.process_with_scratch(column, scratch);
            }
        };
        if threads > 1 {
            spec.par_chunks_mut(chunk * p1)
                .zip(self.col_scratch.par_iter_mut())
                .for_each(body);
        } else {
            body((spec, &mut self.col_scratch[0]));
        }
        let out = &*spec;
        let rinv = &self.row_inv;
        let chunk = keep.len().div_ceil(threads).max(1);
        let first = keep.start;
        let body = |(t, (((rows, ys), real), scratch)): InverseRowChunk<'_>| {
            let nrows = rows.len() / h2;
            for g in (0..nrows).step_by(TRANSPOSE_BLOCK) {
                let w = TRANSPOSE_BLOCK.min(nrows - g);
                let a0 = first + t * chunk + g;
                let block = &mut rows[g * h2..(g + w) * h2];
                gather_block(out, p1, a0, h2, block);
                let yblock = &mut ys[g * n2..(g + w) * n2];
                for (row, yrow) in block.chunks_mut(h2).zip(yblock.chunks_mut(n2)) {
                    row[0].im = 0.0;
                    row[h2 - 1].im = 0.0;
                    rinv.process_with_scratch(row, real, scratch)
                        .expect("lengths from the plan");
                    yrow.copy_from_slice(&real[..n2]);
                }
            }
        };
        let (rows, ys) = (
            &mut self.rows[keep.start * h2..keep.end * h2],
            &mut y[keep.start * n2..keep.end * n2],
        );
        if threads > 1 {
            rows.par_chunks_mut(chunk * h2)
                .zip(ys.par_chunks_mut(chunk * n2))
                .zip(self.row_real.par_iter_mut())
                .zip(self.row_scratch.par_iter_mut())
                .enumerate()
                .for_each(body);
        } else {
            body((
                0,
                (
                    ((rows, ys), &mut self.row_real[0]),
                    &mut self.row_scratch[0],
                ),
            ));
        }
    }
}

/// One block of a transpose: `dst[r·len + b] = src[b·stride + start + r]` for `r < dst.len()/len`,
/// `b < len` — the `w` consecutive values of each of `len` strided source lines are read together
/// (one cache line), not one line at a time.
#[inline]
pub(crate) fn gather_block(src: &[C64], stride: usize, start: usize, len: usize, dst: &mut [C64]) {
    let w = dst.len() / len;
    for b in 0..len {
        let from = b * stride + start;
        for (r, v) in src[from..from + w].iter().enumerate() {
            dst[r * len + b] = *v;
        }
    }
}

/// `x *= k` elementwise, for a real spectrum `k` ([`Fft2d::even_kernel_spectrum`]).
#[inline]
pub fn multiply_real(x: &mut [C64], k: &[f64]) {
    for (s, k) in x.iter_mut().zip(k) {
        *s *= *k;
    }
}

/// `acc += a · b` elementwise over spectra.
#[inline]
pub fn multiply_accumulate(acc: &mut [C64], a: &[C64], b: &[C64]) {
    for ((s, x), y) in acc.iter_mut().zip(a).zip(b) {
        *s += x * y;
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
