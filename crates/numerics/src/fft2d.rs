//! The one real 2D FFT core of the workspace, in two modes ([`Mode`]):
//!
//! * **padded** (DC-FFT, Liu, Wang & Liu 2000; docs/sam.md): fields of `N₁ × N₂` values are
//!   zero-padded to `2N₁ × 2N₂`, transformed (real-to-complex rows, complex columns) and stored as
//!   **spectra** of `2N₁ (N₂ + 1)` complex values. A DC-FFT product is then `IFFT₂(K̂ · X̂)` cropped
//!   to `N₁ × N₂`, the linear (non-periodic) convolution;
//! * **periodic**: no padding, spectra of `N₁ (⌊N₂/2⌋ + 1)` values; `IFFT₂(σ · X̂)` is the circulant
//!   convolution with symbol `σ` ([`crate::circulant::Circulant2d`]).
//!
//! Spectra are column-major (column `b` at `b · P₁`, `P₁` = 2N₁ or N₁: the layout the column
//! transforms produce). Every operator of the workspace (surface compliances, the even normal
//! kernel, layered eigenstrain kernels, Love stresses, the `|k|` preconditioner) builds its kernel
//! spectra and multiplies spectra produced by [`Fft2d::forward`], so one input transformed once
//! serves several operators.
//!
//! **Plans are cached by transform shape** (`P₁ × P₂`) for the whole process: every core of one
//! shape, padded or periodic, uses the same RustFFT/realfft plans. **A core is shared by cloning**:
//! clones of one [`Fft2d`] use the same work buffers (behind a mutex), so the operators of one owner
//! (a contact problem's normal, tangential and coupling operators) hold one core of their shape, not
//! one each. The work buffers are allocated at the first transform.
//!
//! Rows and columns are transformed in parallel (rayon) on grids of at least 128² cells, each thread
//! with its own preallocated scratch; below that, sequentially. Transforms do not allocate (after
//! the first).
//!
//! **Precision.** A core computes in `f64` (`Fft2d`, the default) or in `f32` (`Fft2d<f32>`,
//! [`Fft2d::single`]): the same algorithm on the plans of the other type. Fields in and out are
//! `f64` in both (converted row by row while padding and cropping, no extra pass), so a
//! single-precision product is a drop-in for the early iterations of a solver
//! (docs/performance.md, "Mixed precision").

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::{num_complex::Complex, Fft, FftPlanner};

use crate::NumericsError;

/// A complex spectrum value.
pub type C64 = Complex<f64>;
/// A complex spectrum value in single precision.
pub type C32 = Complex<f32>;

/// The floating-point type a core computes in: `f64` or `f32` (each with its own plan cache).
pub trait Precision: rustfft::FftNum + Copy + Send + Sync + 'static {
    /// `v` rounded to this type.
    fn round_from(v: f64) -> Self;
    /// `self` as `f64` (exact).
    fn widen(self) -> f64;
    /// The process-wide plan cache of this type (`plans`).
    fn cache() -> &'static PlanCache<Self>;
}

/// Plans by transform shape, one cache per [`Precision`].
#[doc(hidden)]
pub type PlanCache<T> = Mutex<HashMap<(usize, usize), Arc<Plans<T>>>>;

impl Precision for f64 {
    #[inline(always)]
    fn round_from(v: f64) -> Self {
        v
    }
    #[inline(always)]
    fn widen(self) -> f64 {
        self
    }
    fn cache() -> &'static PlanCache<f64> {
        static CACHE: OnceLock<PlanCache<f64>> = OnceLock::new();
        CACHE.get_or_init(|| Mutex::new(HashMap::new()))
    }
}

impl Precision for f32 {
    #[inline(always)]
    fn round_from(v: f64) -> Self {
        v as f32
    }
    #[inline(always)]
    fn widen(self) -> f64 {
        self as f64
    }
    fn cache() -> &'static PlanCache<f32> {
        static CACHE: OnceLock<PlanCache<f32>> = OnceLock::new();
        CACHE.get_or_init(|| Mutex::new(HashMap::new()))
    }
}

/// A scratch buffer of complex values.
type Scratch<T> = Vec<Complex<T>>;
/// One thread's share of a row transform: (chunk index, ((row spectra, padded real row),
/// scratch)).
type RowChunk<'a, T> = (
    usize,
    ((&'a mut [Complex<T>], &'a mut Vec<T>), &'a mut Scratch<T>),
);
/// One thread's share of a column transform: (chunk index, (columns, scratch)).
type ColChunk<'a, T> = (usize, (&'a mut [Complex<T>], &'a mut Scratch<T>));
/// One thread's share of the inverse row transforms: (chunk index, (((complex rows, output rows),
/// padded real row), scratch)).
type InverseRowChunk<'a, T> = (
    usize,
    (
        ((&'a mut [Complex<T>], &'a mut [f64]), &'a mut Vec<T>),
        &'a mut Scratch<T>,
    ),
);

/// Columns (rows) gathered together in the transposes between the row and column transforms.
const TRANSPOSE_BLOCK: usize = 8;

/// Grids with at least this many cells are transformed with rayon.
pub const PARALLEL_CELLS: usize = 128 * 128;

/// Kernel of one block: `K(m, n)` for offsets `m ∈ (−N₁, N₁)`, `n ∈ (−N₂, N₂)`.
pub type KernelFn<'a> = &'a dyn Fn(i64, i64) -> f64;

/// How fields are transformed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Mode {
    /// Zero-padded to `2N₁ × 2N₂` (DC-FFT: linear convolution after cropping).
    Padded,
    /// Not padded (circulant: periodic convolution).
    Periodic,
}

/// The RustFFT/realfft plans of one transform shape `P₁ × P₂` (rows of `P₂` real values, columns of
/// `P₁` complex values), shared by every core of that shape.
#[doc(hidden)]
pub struct Plans<T: Precision> {
    row_fwd: Arc<dyn RealToComplex<T>>,
    row_inv: Arc<dyn ComplexToReal<T>>,
    col_fwd: Arc<dyn Fft<T>>,
    col_inv: Arc<dyn Fft<T>>,
}

/// The plans of transform shape `(p1, p2)` in precision `T`, planned at the first request of the
/// process.
fn plans<T: Precision>(p1: usize, p2: usize) -> Arc<Plans<T>> {
    let mut map = T::cache().lock().unwrap_or_else(|e| e.into_inner());
    map.entry((p1, p2))
        .or_insert_with(|| {
            let mut rplanner = RealFftPlanner::<T>::new();
            let mut cplanner = FftPlanner::<T>::new();
            Arc::new(Plans {
                row_fwd: rplanner.plan_fft_forward(p2),
                row_inv: rplanner.plan_fft_inverse(p2),
                col_fwd: cplanner.plan_fft_forward(p1),
                col_inv: cplanner.plan_fft_inverse(p1),
            })
        })
        .clone()
}

/// The work buffers of one core (allocated at the first transform).
struct Work<T: Precision> {
    /// One real row (`P₂` values) per worker thread: fields are padded row by row, so no
    /// `P₁ × P₂` real array is held.
    row_real: Vec<Vec<T>>,
    /// Row transforms, `P₁ × (P₂/2 + 1)` row-major.
    rows: Vec<Complex<T>>,
    /// One scratch buffer per worker thread.
    row_scratch: Vec<Scratch<T>>,
    col_scratch: Vec<Scratch<T>>,
}

/// A real 2D FFT of `N₁ × N₂` fields (padded or periodic) computing in precision `T` (`f64` by
/// default), planned once; clones share it.
pub struct Fft2d<T: Precision = f64> {
    n1: usize,
    n2: usize,
    mode: Mode,
    /// Transform shape `P₁ × P₂`.
    p1: usize,
    p2: usize,
    threads: usize,
    plans: Arc<Plans<T>>,
    work: Arc<Mutex<Option<Work<T>>>>,
}

impl<T: Precision> Clone for Fft2d<T> {
    fn clone(&self) -> Self {
        Self {
            plans: self.plans.clone(),
            work: self.work.clone(),
            ..*self
        }
    }
}

impl Fft2d {
    /// The padded (DC-FFT) core of `n1 × n2` fields (`n1, n2 ≥ 2`).
    pub fn new(n1: usize, n2: usize) -> Result<Self, NumericsError> {
        Self::with_mode(n1, n2, Mode::Padded)
    }

    /// The periodic (circulant) core of `n1 × n2` fields (`n1, n2 ≥ 2`).
    pub fn periodic(n1: usize, n2: usize) -> Result<Self, NumericsError> {
        Self::with_mode(n1, n2, Mode::Periodic)
    }

    /// The core of `n1 × n2` fields in `mode`, with the cached plans of its transform shape; its
    /// work buffers are allocated at the first transform.
    pub fn with_mode(n1: usize, n2: usize, mode: Mode) -> Result<Self, NumericsError> {
        Fft2d::<f64>::in_precision(n1, n2, mode)
    }

    /// The single-precision core of this one's shape and mode (its own work buffers, the cached
    /// `f32` plans): products on it carry a relative error of order `1e-7` (docs/performance.md,
    /// "Mixed precision").
    pub fn single(&self) -> Fft2d<f32> {
        Fft2d::<f32>::in_precision(self.n1, self.n2, self.mode).expect("the shape of a valid core")
    }

    /// The spectrum of the DC-FFT kernel layout of `k` (offsets `−(N−1)..N−1` wrapped, the `N`-th
    /// row and column zero; docs/sam.md), divided by `4N₁N₂` so that [`Fft2d::inverse`] needs no
    /// normalisation. Padded cores only; non-finite kernel values are an error.
    pub fn kernel_spectrum(
        &mut self,
        k: KernelFn<'_>,
        out: &mut [C64],
    ) -> Result<(), NumericsError> {
        self.require_padded()?;
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
            None,
        );
        let scale = 1.0 / (p1 * p2) as f64;
        out.iter_mut().for_each(|s| *s *= scale);
        Ok(())
    }

    /// The spectrum of a kernel even in both offsets, `K(m, n) = K(|m|, |n|)`, from its quadrant
    /// `quadrant[m N₂ + n] = K(m, n)` (`0 ≤ m < N₁`, `0 ≤ n < N₂`). The DFT of a real sequence even
    /// in both indices is real, so only the real part is stored (`out.len()` =
    /// [`Fft2d::spectrum_len`]), divided by `4N₁N₂` as in [`Fft2d::kernel_spectrum`]. `work` is
    /// space for the complex spectrum (overwritten; the operator's product buffer, so that setup
    /// touches no memory the products do not). Padded cores only.
    pub fn even_kernel_spectrum(
        &mut self,
        quadrant: &[f64],
        out: &mut [f64],
        work: &mut [C64],
    ) -> Result<(), NumericsError> {
        self.require_padded()?;
        self.check_spectrum(work)?;
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
        self.forward_padded(&fill, work, 0..p1, None);
        let scale = 1.0 / (p1 * p2) as f64;
        for (o, s) in out.iter_mut().zip(&*work) {
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

    /// The real symbol `σ(m, n) / (N₁N₂)` of a periodic core at the DFT indices `m ∈ [0, N₁)`,
    /// `n ∈ [0, ⌊N₂/2⌋]`, in the spectrum layout (`[n N₁ + m]`), so that `IFFT₂(σ · FFT₂ x)` is
    /// [`multiply_real`] between [`Fft2d::forward`] and [`Fft2d::inverse`]. Periodic cores only;
    /// non-finite values are an error.
    pub fn symbol_spectrum(
        &self,
        sigma: &dyn Fn(usize, usize) -> f64,
    ) -> Result<Vec<f64>, NumericsError> {
        if self.mode != Mode::Periodic {
            return Err(NumericsError::InvalidParameter {
                name: "FFT core mode for a circulant symbol (padded given)",
                value: 0.0,
                allowed: "periodic",
            });
        }
        let (n1, n2) = (self.n1, self.n2);
        let h2 = n2 / 2 + 1;
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
                symbol[n * n1 + m] = s * scale;
            }
        }
        Ok(symbol)
    }

    /// `out = FFT₂(x)` (zero-padded in the padded mode) for a field `x` of `N₁ × N₂` values
    /// (row-major).
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
        self.forward_padded(&fill, out, rows, None);
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
}

impl<T: Precision> Fft2d<T> {
    /// The core of `n1 × n2` fields in `mode` computing in precision `T` (`n1, n2 ≥ 2`), with the
    /// cached plans of its transform shape; its work buffers are allocated at the first transform.
    pub fn in_precision(n1: usize, n2: usize, mode: Mode) -> Result<Self, NumericsError> {
        if n1 < 2 || n2 < 2 {
            return Err(NumericsError::TooFewNodes {
                what: match mode {
                    Mode::Padded => "a DC-FFT grid side",
                    Mode::Periodic => "a circulant grid side",
                },
                min: 2,
                n: n1.min(n2),
            });
        }
        let (p1, p2) = match mode {
            Mode::Padded => (2 * n1, 2 * n2),
            Mode::Periodic => (n1, n2),
        };
        // Threads pay only on large grids: below 128² the rayon hand-offs cost more than they save.
        let threads = if n1 * n2 >= PARALLEL_CELLS {
            rayon::current_num_threads().max(1)
        } else {
            1
        };
        Ok(Self {
            n1,
            n2,
            mode,
            p1,
            p2,
            threads,
            plans: plans(p1, p2),
            work: Arc::new(Mutex::new(None)),
        })
    }

    /// A core of this one's shape, mode and plans that transforms on the calling thread alone,
    /// with work buffers of its own (not a clone: it shares none): for batches of transforms run
    /// one per task on the pool (`crate::fft_batch`), where splitting each transform again would
    /// only add hand-offs. Its results are this core's bit for bit (rows and columns are
    /// transformed one by one either way).
    pub fn sequential(&self) -> Self {
        Self {
            threads: 1,
            plans: self.plans.clone(),
            work: Arc::new(Mutex::new(None)),
            ..*self
        }
    }

    /// Whether this core splits its transforms over the pool's threads.
    pub fn is_parallel(&self) -> bool {
        self.threads > 1
    }

    /// Grid shape `(N₁, N₂)`.
    pub fn shape(&self) -> (usize, usize) {
        (self.n1, self.n2)
    }

    /// Padded or periodic.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Whether `other` is a clone of this core (the same work buffers).
    pub fn shares_work_with(&self, other: &Fft2d<T>) -> bool {
        Arc::ptr_eq(&self.work, &other.work)
    }

    /// Length of one spectrum, `P₁ (P₂/2 + 1)`: `2N₁ (N₂ + 1)` padded, `N₁ (⌊N₂/2⌋ + 1)` periodic.
    pub fn spectrum_len(&self) -> usize {
        self.p1 * (self.p2 / 2 + 1)
    }

    /// A zeroed spectrum buffer. On a transform that runs on threads it is written (and its pages
    /// first touched) by the pool's threads in parallel: a 256² padded spectrum is 2 MiB, ≈ 500
    /// page faults that one thread would take alone (docs/performance.md, "A partner that does not
    /// sleep").
    pub fn new_spectrum(&self) -> Vec<Complex<T>> {
        let zero = Complex::new(T::zero(), T::zero());
        let n = self.spectrum_len();
        if self.threads > 1 {
            let mut spectrum = Vec::with_capacity(n);
            spectrum.par_extend(rayon::iter::repeat_n(zero, n));
            spectrum
        } else {
            vec![zero; n]
        }
    }

    fn require_padded(&self) -> Result<(), NumericsError> {
        match self.mode {
            Mode::Padded => Ok(()),
            Mode::Periodic => Err(NumericsError::InvalidParameter {
                name: "FFT core mode for a DC-FFT kernel (periodic given)",
                value: 0.0,
                allowed: "padded",
            }),
        }
    }

    /// `y = IFFT₂(k · FFT₂(x))` cropped to `N₁ × N₂` for a real spectrum `k` (in the layout of
    /// [`Fft2d::spectrum_len`]: [`Fft2d::even_kernel_spectrum`] on a padded core, the DC-FFT product
    /// with an even kernel; [`Fft2d::symbol_spectrum`] on a periodic core, the circulant product).
    /// Equal bit for bit to [`Fft2d::forward`], [`multiply_real`], [`Fft2d::inverse`], fused: each
    /// block of columns is transformed, multiplied and transformed back while it is in cache (two
    /// passes over the spectrum fewer), and the zero padding is never read. `spec` is work space of
    /// [`Fft2d::spectrum_len`] values (overwritten). On a single-precision core the fields are
    /// rounded to `f32` as they are padded and the result widened as it is cropped.
    pub fn convolve_real(
        &mut self,
        x: &[f64],
        k: &[T],
        spec: &mut [Complex<T>],
        y: &mut [f64],
    ) -> Result<(), NumericsError> {
        let n2 = self.n2;
        self.check_field(x.len())?;
        let fill = |a: usize, row: &mut [T]| {
            for (r, v) in row[..n2].iter_mut().zip(&x[a * n2..(a + 1) * n2]) {
                *r = T::round_from(*v);
            }
            row[n2..].fill(T::zero());
        };
        self.convolve_real_rows(&fill, k, spec, y)
    }

    /// [`Fft2d::convolve_real`] of the field whose value at cell `c = i N₂ + j` is `x(c)`,
    /// evaluated while the rows are padded: a field written only to be transformed need not be
    /// stored (the preconditioner's input of the normal solver, docs/performance.md). Equal bit
    /// for bit to [`Fft2d::convolve_real`] of the stored field.
    pub fn convolve_real_of<F: Fn(usize) -> f64 + Sync>(
        &mut self,
        x: F,
        k: &[T],
        spec: &mut [Complex<T>],
        y: &mut [f64],
    ) -> Result<(), NumericsError> {
        let n2 = self.n2;
        let fill = |a: usize, row: &mut [T]| {
            for (b, r) in row[..n2].iter_mut().enumerate() {
                *r = T::round_from(x(a * n2 + b));
            }
            row[n2..].fill(T::zero());
        };
        self.convolve_real_rows(&fill, k, spec, y)
    }

    fn check_field(&self, len: usize) -> Result<(), NumericsError> {
        if len != self.n1 * self.n2 {
            return Err(NumericsError::LengthMismatch {
                what: "grid field",
                expected: self.n1 * self.n2,
                got: len,
            });
        }
        Ok(())
    }

    /// The fused product of the field whose padded row `a` `fill(a, row)` writes.
    fn convolve_real_rows(
        &mut self,
        fill: &(dyn Fn(usize, &mut [T]) + Sync),
        k: &[T],
        spec: &mut [Complex<T>],
        y: &mut [f64],
    ) -> Result<(), NumericsError> {
        let n1 = self.n1;
        self.check_field(y.len())?;
        self.check_spectrum(spec)?;
        if k.len() != spec.len() {
            return Err(NumericsError::LengthMismatch {
                what: "real spectrum",
                expected: spec.len(),
                got: k.len(),
            });
        }
        self.forward_padded(fill, spec, 0..n1, Some(k));
        self.inverse_row_phase(spec, 0..n1, y);
        Ok(())
    }

    fn check_spectrum(&self, s: &[Complex<T>]) -> Result<(), NumericsError> {
        if s.len() != self.spectrum_len() {
            return Err(NumericsError::LengthMismatch {
                what: "spectrum",
                expected: self.spectrum_len(),
                got: s.len(),
            });
        }
        Ok(())
    }

    /// Runs `f` on the work buffers (allocated here at the first call). The buffers are taken out
    /// of the lock for the duration of `f` and put back after it: `f` forks onto rayon's workers,
    /// and a worker waiting in that join may run another caller's solve on a clone of this
    /// transform ([`crate::parallel::on_pool`]), which must not find the lock held by its own
    /// thread. A clone used concurrently allocates its own buffers (only then); results do not
    /// depend on which buffers a call gets.
    fn with_work<R>(&self, f: impl FnOnce(&mut Work<T>) -> R) -> R {
        let taken = self.work.lock().unwrap_or_else(|e| e.into_inner()).take();
        let mut work = taken.unwrap_or_else(|| {
            let p = &self.plans;
            let zero = Complex::new(T::zero(), T::zero());
            let row_scratch_len = p.row_fwd.get_scratch_len().max(p.row_inv.get_scratch_len());
            let col_scratch_len = p
                .col_fwd
                .get_inplace_scratch_len()
                .max(p.col_inv.get_inplace_scratch_len());
            Work {
                row_real: vec![vec![T::zero(); self.p2]; self.threads],
                rows: self.new_spectrum(),
                row_scratch: vec![vec![zero; row_scratch_len.max(1)]; self.threads],
                col_scratch: vec![vec![zero; col_scratch_len.max(1)]; self.threads],
            }
        });
        let result = f(&mut work);
        *self.work.lock().unwrap_or_else(|e| e.into_inner()) = Some(work);
        result
    }

    /// Spectrum (column-major) of the (padded) field whose row `a` (`P₂` values) `fill(a, row)`
    /// writes; only the rows `nonzero` may be nonzero (the row transforms of the others, and of
    /// the zero padding, are skipped, and those rows are not read). With a real spectrum `k`, each
    /// column is then multiplied by `k`'s column and inverse-transformed in place (the column half
    /// of [`Fft2d::convolve_real`]).
    fn forward_padded(
        &mut self,
        fill: &(dyn Fn(usize, &mut [T]) + Sync),
        spec: &mut [Complex<T>],
        nonzero: std::ops::Range<usize>,
        k: Option<&[T]>,
    ) {
        let (p1, h2) = (self.p1, self.p2 / 2 + 1);
        let threads = self.threads;
        let plans = &self.plans;
        self.with_work(|work| {
            let chunk = nonzero.len().div_ceil(threads).max(1);
            let first = nonzero.start;
            let fwd = &plans.row_fwd;
            let body = |(t, ((rows, real), scratch)): RowChunk<'_, T>| {
                for (k, c) in rows.chunks_mut(h2).enumerate() {
                    fill(first + t * chunk + k, real);
                    fwd.process_with_scratch(real, c, scratch)
                        .expect("lengths from the plan");
                }
            };
            let rows = &mut work.rows[nonzero.start * h2..nonzero.end * h2];
            if threads > 1 {
                rows.par_chunks_mut(chunk * h2)
                    .zip(work.row_real.par_iter_mut())
                    .zip(work.row_scratch.par_iter_mut())
                    .enumerate()
                    .for_each(body);
            } else {
                body((0, ((rows, &mut work.row_real[0]), &mut work.row_scratch[0])));
            }
            // Transpose to columns and transform them (the rows outside `nonzero` are zero and
            // not read).
            let rows = &work.rows;
            let (col, col_inv) = (&plans.col_fwd, &plans.col_inv);
            let chunk = h2.div_ceil(threads).max(1);
            let nonzero = &nonzero;
            let body = |(t, (cols, scratch)): ColChunk<'_, T>| {
                // Gathered TRANSPOSE_BLOCK columns at a time: each row contributes a contiguous run
                // (the column-by-column gather read one value per cache line).
                let first = t * chunk;
                let ncols = cols.len() / p1;
                for g in (0..ncols).step_by(TRANSPOSE_BLOCK) {
                    let w = TRANSPOSE_BLOCK.min(ncols - g);
                    let block = &mut cols[g * p1..(g + w) * p1];
                    gather_block_rows(rows, h2, first + g, nonzero.clone(), p1, block);
                    for (c, column) in block.chunks_mut(p1).enumerate() {
                        col.process_with_scratch(column, scratch);
                        if let Some(k) = k {
                            let b = first + g + c;
                            multiply_real(column, &k[b * p1..(b + 1) * p1]);
                            col_inv.process_with_scratch(column, scratch);
                        }
                    }
                }
            };
            if threads > 1 {
                spec.par_chunks_mut(chunk * p1)
                    .zip(work.col_scratch.par_iter_mut())
                    .enumerate()
                    .for_each(body);
            } else {
                body((0, (spec, &mut work.col_scratch[0])));
            }
        });
    }

    /// Writes the rows `keep` (within the first `N₁`) of the inverse transform of `spec`
    /// (column-major, overwritten), cropped to `N₂` columns, into `y`.
    fn inverse_cropped(
        &mut self,
        spec: &mut [Complex<T>],
        keep: std::ops::Range<usize>,
        y: &mut [f64],
    ) {
        let p1 = self.p1;
        let h2 = self.p2 / 2 + 1;
        let threads = self.threads;
        let plans = &self.plans;
        self.with_work(|work| {
            let inv = &plans.col_inv;
            let chunk = h2.div_ceil(threads).max(1);
            let body = |(cols, scratch): (&mut [Complex<T>], &mut Scratch<T>)| {
                for column in cols.chunks_mut(p1) {
                    inv.process_with_scratch(column, scratch);
                }
            };
            if threads > 1 {
                spec.par_chunks_mut(chunk * p1)
                    .zip(work.col_scratch.par_iter_mut())
                    .for_each(body);
            } else {
                body((spec, &mut work.col_scratch[0]));
            }
        });
        self.inverse_row_phase(spec, keep, y);
    }

    /// The row half of the inverse transform: the rows `keep` of `spec` (column-major, columns
    /// already inverse-transformed) transposed, inverse real-transformed and cropped into `y`.
    fn inverse_row_phase(
        &mut self,
        spec: &[Complex<T>],
        keep: std::ops::Range<usize>,
        y: &mut [f64],
    ) {
        let (p1, p2, n2) = (self.p1, self.p2, self.n2);
        let h2 = p2 / 2 + 1;
        let threads = self.threads;
        let plans = &self.plans;
        self.with_work(|work| {
            let out = spec;
            let rinv = &plans.row_inv;
            let chunk = keep.len().div_ceil(threads).max(1);
            let first = keep.start;
            let body = |(t, (((rows, ys), real), scratch)): InverseRowChunk<'_, T>| {
                let nrows = rows.len() / h2;
                for g in (0..nrows).step_by(TRANSPOSE_BLOCK) {
                    let w = TRANSPOSE_BLOCK.min(nrows - g);
                    let a0 = first + t * chunk + g;
                    let block = &mut rows[g * h2..(g + w) * h2];
                    gather_block(out, p1, a0, h2, block);
                    let yblock = &mut ys[g * n2..(g + w) * n2];
                    for (row, yrow) in block.chunks_mut(h2).zip(yblock.chunks_mut(n2)) {
                        row[0].im = T::zero();
                        if p2 % 2 == 0 {
                            row[h2 - 1].im = T::zero();
                        }
                        rinv.process_with_scratch(row, real, scratch)
                            .expect("lengths from the plan");
                        for (o, r) in yrow.iter_mut().zip(&real[..n2]) {
                            *o = r.widen();
                        }
                    }
                }
            };
            let (rows, ys) = (
                &mut work.rows[keep.start * h2..keep.end * h2],
                &mut y[keep.start * n2..keep.end * n2],
            );
            if threads > 1 {
                rows.par_chunks_mut(chunk * h2)
                    .zip(ys.par_chunks_mut(chunk * n2))
                    .zip(work.row_real.par_iter_mut())
                    .zip(work.row_scratch.par_iter_mut())
                    .enumerate()
                    .for_each(body);
            } else {
                body((
                    0,
                    (
                        ((rows, ys), &mut work.row_real[0]),
                        &mut work.row_scratch[0],
                    ),
                ));
            }
        });
    }
}

/// The single-precision twin of a real-spectrum product `y = IFFT₂(k · FFT₂(x))`
/// ([`Fft2d::convolve_real`]): the spectrum `k` rounded to `f32` once, the product on the `f32`
/// core of the same shape ([`Fft2d::single`]). Fields stay `f64`; the result carries a relative
/// error of order `1e-7` (measured against the dense twin in `op::even` and `circulant`), so it
/// serves the early iterations of a solver whose final iterations use the `f64` product
/// (docs/performance.md, "Mixed precision").
pub struct SingleProduct {
    fft: Fft2d<f32>,
    k: Vec<f32>,
    hat: Vec<C32>,
}

impl SingleProduct {
    /// The twin of the product with the real spectrum `k` on `core` (work buffers of its own).
    pub fn new(core: &Fft2d, k: &[f64]) -> Result<Self, NumericsError> {
        let fft = core.single();
        if k.len() != fft.spectrum_len() {
            return Err(NumericsError::LengthMismatch {
                what: "real spectrum",
                expected: fft.spectrum_len(),
                got: k.len(),
            });
        }
        Ok(Self {
            k: k.iter().map(|v| *v as f32).collect(),
            hat: fft.new_spectrum(),
            fft,
        })
    }

    /// `y ≈ IFFT₂(k · FFT₂(x))` in single precision (`x`, `y` of `N₁ × N₂` values).
    pub fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        self.fft.convolve_real(x, &self.k, &mut self.hat, y)
    }

    /// [`SingleProduct::apply`] to the field `x(c)` ([`Fft2d::convolve_real_of`]).
    pub fn apply_of<F: Fn(usize) -> f64 + Sync>(
        &mut self,
        x: F,
        y: &mut [f64],
    ) -> Result<(), NumericsError> {
        self.fft.convolve_real_of(x, &self.k, &mut self.hat, y)
    }
}

/// One block of a transpose: `dst[r·len + b] = src[b·stride + start + r]` for `r < dst.len()/len`,
/// `b < len` — the `w` consecutive values of each of `len` strided source lines are read together
/// (one cache line), not one line at a time.
#[inline]
fn gather_block<V: Copy>(src: &[V], stride: usize, start: usize, len: usize, dst: &mut [V]) {
    let w = dst.len() / len;
    for b in 0..len {
        let from = b * stride + start;
        for (r, v) in src[from..from + w].iter().enumerate() {
            dst[r * len + b] = *v;
        }
    }
}

/// [`gather_block`] of a source whose lines outside `nonzero` are zero: those are not read, their
/// values in `dst` are set to zero.
#[inline]
fn gather_block_rows<T: Precision>(
    src: &[Complex<T>],
    stride: usize,
    start: usize,
    nonzero: std::ops::Range<usize>,
    len: usize,
    dst: &mut [Complex<T>],
) {
    let w = dst.len() / len;
    let zero = Complex::new(T::zero(), T::zero());
    for r in 0..w {
        dst[r * len..r * len + nonzero.start].fill(zero);
        dst[r * len + nonzero.end..(r + 1) * len].fill(zero);
    }
    for b in nonzero {
        let from = b * stride + start;
        for (r, v) in src[from..from + w].iter().enumerate() {
            dst[r * len + b] = *v;
        }
    }
}

/// `x *= k` elementwise, for a real spectrum `k` ([`Fft2d::even_kernel_spectrum`]).
#[inline]
pub fn multiply_real<T: Precision>(x: &mut [Complex<T>], k: &[T]) {
    for (s, k) in x.iter_mut().zip(k) {
        // As `Complex *= real`: both parts scaled.
        *s = Complex::new(s.re * *k, s.im * *k);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testkit::lcg;

    /// Clones sharing one set of work buffers, solved at once from several threads through
    /// [`crate::parallel::on_pool`] (a worker waiting in a join may pick up another caller's solve
    /// on a clone): every product finishes and equals the serial one bit for bit.
    #[test]
    fn clones_solved_at_once_on_the_pool_agree() {
        let (n1, n2) = (130, 128);
        let mut fft = Fft2d::new(n1, n2).unwrap();
        let x = lcg(21, n1 * n2);
        let k = lcg(22, fft.spectrum_len());
        let mut spec = fft.new_spectrum();
        let mut serial = vec![0.0; n1 * n2];
        fft.convolve_real(&x, &k, &mut spec, &mut serial).unwrap();
        std::thread::scope(|s| {
            for _ in 0..4 {
                let mut fft = fft.clone();
                let (x, k, serial) = (&x, &k, &serial);
                s.spawn(move || {
                    let mut spec = fft.new_spectrum();
                    let mut y = vec![0.0; n1 * n2];
                    for _ in 0..20 {
                        crate::parallel::on_pool(n1 * n2, || {
                            fft.convolve_real(x, k, &mut spec, &mut y)
                        })
                        .unwrap();
                        assert!(y
                            .iter()
                            .zip(serial)
                            .all(|(a, b)| a.to_bits() == b.to_bits()));
                    }
                });
            }
        });
    }

    /// The fused product equals forward, real product and inverse done apart, bit for bit, padded
    /// and periodic, below and above the parallel threshold, with unequal (and odd) sides.
    #[test]
    fn the_fused_product_equals_the_three_steps_bit_for_bit() {
        for (n1, n2) in [(9, 14), (7, 5), (130, 128)] {
            for mode in [Mode::Padded, Mode::Periodic] {
                let mut fft = Fft2d::with_mode(n1, n2, mode).unwrap();
                let x = lcg(11, n1 * n2);
                let k = lcg(12, fft.spectrum_len());
                let mut spec = fft.new_spectrum();
                let mut apart = vec![0.0; n1 * n2];
                fft.forward(&x, &mut spec).unwrap();
                multiply_real(&mut spec, &k);
                fft.inverse(&mut spec, &mut apart).unwrap();
                let mut fused = vec![0.0; n1 * n2];
                fft.convolve_real(&x, &k, &mut spec, &mut fused).unwrap();
                let same =
                    |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits());
                assert!(same(&apart, &fused), "{n1}×{n2} {mode:?}");
                // The field given cell by cell.
                let mut of = vec![0.0; n1 * n2];
                fft.convolve_real_of(|c| x[c], &k, &mut spec, &mut of)
                    .unwrap();
                assert!(same(&fused, &of), "{n1}×{n2} {mode:?} (by cell)");
            }
        }
    }

    /// Wrong lengths are errors, not panics.
    #[test]
    fn the_fused_product_checks_lengths() {
        let mut fft = Fft2d::new(6, 5).unwrap();
        let mut spec = fft.new_spectrum();
        let k = vec![1.0; fft.spectrum_len()];
        let (x, mut y) = (vec![0.0; 30], vec![0.0; 30]);
        assert!(fft.convolve_real(&x[..29], &k, &mut spec, &mut y).is_err());
        assert!(fft.convolve_real(&x, &k[1..], &mut spec, &mut y).is_err());
        assert!(fft.convolve_real(&x, &k, &mut spec[1..], &mut y).is_err());
    }
}
