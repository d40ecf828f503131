//! Batches of 2D transforms of one shape (docs/performance.md, "One EIM application on two
//! cores"): the forward transforms of many fields, or the inverse transforms of many spectra, run
//! one transform per task on rayon's pool, each on a core of its own that transforms on its
//! thread alone ([`Fft2d::sequential`]). A core that splits every transform over the threads
//! ([`Fft2d`] on grids of at least [`crate::fft2d::PARALLEL_CELLS`] cells) hands work to the other
//! thread twice per transform (rows, then columns): at 128² a transform is ≈ 0.1 ms, and on two
//! threads those hand-offs cost as much as they save. A batch hands off once.
//!
//! The results are those of the core's own [`Fft2d::forward_rows`] / [`Fft2d::inverse_rows`]
//! bit for bit (each row and column is transformed alone in either case); only where the
//! transforms run differs. The cores are kept between calls (their work buffers are allocated at
//! their first transform only).

use std::ops::Range;
use std::sync::Mutex;

use rayon::prelude::*;

use crate::fft2d::{Fft2d, C64};
use crate::NumericsError;

/// Batched transforms on the plans of one [`Fft2d`] core.
pub struct FftBatch {
    /// The core the batch stands for (a clone: its transforms split over the threads).
    core: Fft2d,
    /// Sequential cores of the same shape, one per task running at once.
    cores: Mutex<Vec<Fft2d>>,
}

/// A sequential core borrowed from the batch, returned when dropped.
struct Borrowed<'a> {
    cores: &'a Mutex<Vec<Fft2d>>,
    core: Option<Fft2d>,
}

impl Drop for Borrowed<'_> {
    fn drop(&mut self) {
        if let (Some(c), Ok(mut cores)) = (self.core.take(), self.cores.lock()) {
            cores.push(c);
        }
    }
}

/// Batches of fewer transforms are transformed one after the other on the splitting core (one
/// transform alone keeps its split over the threads).
const MIN_BATCH: usize = 2;

impl FftBatch {
    /// Batches on `core`'s plans (the core is cloned: its work buffers are shared). A core that
    /// splits its transforms gets one sequential core per thread of the pool here, their work
    /// buffers allocated by a first transform, so that batches do not allocate: a task finds a
    /// core in stock unless more tasks run at once than the pool has threads (a task stolen into
    /// a nested join), when it makes one more (kept for later batches).
    pub fn new(core: &Fft2d) -> Self {
        let mut cores = Vec::new();
        if core.is_parallel() {
            let (n1, n2) = core.shape();
            let zero = vec![0.0; n1 * n2];
            let mut spectrum = core.new_spectrum();
            for _ in 0..rayon::current_num_threads() {
                let mut c = core.sequential();
                // Allocates the work buffers (a zero field: no error on a valid core's shape).
                let _ = c.forward(&zero, &mut spectrum);
                cores.push(c);
            }
        }
        Self {
            core: core.clone(),
            cores: Mutex::new(cores),
        }
    }

    /// Grid shape `(N₁, N₂)` of the core.
    pub fn shape(&self) -> (usize, usize) {
        self.core.shape()
    }

    /// Whether `count` transforms run one per task: on a core that splits its transforms, from
    /// two on (a 128² transform split over the threads does not pay even on two:
    /// docs/performance.md, "One EIM application on two cores").
    fn batched(&self, count: usize) -> bool {
        self.core.is_parallel() && count >= MIN_BATCH
    }

    /// Sequential cores in stock (tests: the batched path ran and returned them).
    #[cfg(test)]
    fn stock(&self) -> usize {
        self.cores.lock().map_or(0, |c| c.len())
    }

    fn borrow(&self) -> Borrowed<'_> {
        let core = self.cores.lock().ok().and_then(|mut c| c.pop());
        Borrowed {
            cores: &self.cores,
            core: Some(core.unwrap_or_else(|| self.core.sequential())),
        }
    }

    /// For every field `x[v]` (`N₁ × N₂`, zero outside the rows `rows`): `skip[v]` = whether it is
    /// zero everywhere, and otherwise `x_hat[v]` = its spectrum ([`Fft2d::forward_rows`]; a
    /// skipped field's spectrum is left as it was).
    pub fn forward<X: AsRef<[f64]> + Sync>(
        &self,
        x: &[X],
        rows: Range<usize>,
        x_hat: &mut [Vec<C64>],
        skip: &mut [bool],
    ) -> Result<(), NumericsError> {
        if x_hat.len() < x.len() || skip.len() < x.len() {
            return Err(NumericsError::LengthMismatch {
                what: "batched forward transforms (spectra, skip flags)",
                expected: x.len(),
                got: x_hat.len().min(skip.len()),
            });
        }
        let one = |core: &mut Fft2d, xi: &X, hat: &mut Vec<C64>, sk: &mut bool| {
            let xi = xi.as_ref();
            *sk = xi.iter().all(|v| *v == 0.0);
            if *sk {
                Ok(())
            } else {
                core.forward_rows(xi, rows.clone(), hat)
            }
        };
        if !self.batched(x.len()) {
            let mut core = self.core.clone();
            for ((xi, hat), sk) in x.iter().zip(x_hat.iter_mut()).zip(skip.iter_mut()) {
                one(&mut core, xi, hat, sk)?;
            }
            return Ok(());
        }
        x.par_iter()
            .zip(x_hat.par_iter_mut())
            .zip(skip.par_iter_mut())
            .with_max_len(1)
            .try_for_each_init(
                || self.borrow(),
                |b, ((xi, hat), sk)| match b.core.as_mut() {
                    Some(core) => one(core, xi, hat, sk),
                    None => unreachable!("a borrowed core is held until dropped"),
                },
            )
    }

    /// `y[v]` = the inverse transform of `spectra[v]` (overwritten) on the rows `rows`
    /// ([`Fft2d::inverse_rows`]), for every `v < y.len()`.
    pub fn inverse<Y: AsMut<[f64]> + Send>(
        &self,
        spectra: &mut [Vec<C64>],
        rows: Range<usize>,
        y: &mut [Y],
    ) -> Result<(), NumericsError> {
        if spectra.len() < y.len() {
            return Err(NumericsError::LengthMismatch {
                what: "batched inverse transforms (spectra)",
                expected: y.len(),
                got: spectra.len(),
            });
        }
        if !self.batched(y.len()) {
            let mut core = self.core.clone();
            for (hat, yo) in spectra.iter_mut().zip(y.iter_mut()) {
                core.inverse_rows(hat, rows.clone(), yo.as_mut())?;
            }
            return Ok(());
        }
        spectra[..y.len()]
            .par_iter_mut()
            .zip(y.par_iter_mut())
            .with_max_len(1)
            .try_for_each_init(
                || self.borrow(),
                |b, (hat, yo)| match b.core.as_mut() {
                    Some(core) => core.inverse_rows(hat, rows.clone(), yo.as_mut()),
                    None => unreachable!("a borrowed core is held until dropped"),
                },
            )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fields(n: usize, count: usize, seed: u64) -> Vec<Vec<f64>> {
        let mut rng = crate::testkit::Lcg::new(seed);
        (0..count)
            .map(|v| {
                if v % 5 == 3 {
                    vec![0.0; n * n]
                } else {
                    (0..n * n).map(|_| rng.unit() - 0.5).collect()
                }
            })
            .collect()
    }

    /// The batch's transforms equal the splitting core's bit for bit, zero fields skipped, on a
    /// grid that runs on threads (128²) and one that does not, with a row range.
    #[test]
    fn batched_transforms_equal_the_core_bit_for_bit() {
        // In a pool of two threads (whatever the machine's), so that 128² cores split their
        // transforms and the batch runs one per task.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        pool.install(batched_transforms_check);
    }

    /// A task that finds the stock empty (more tasks at once than the pool has threads: a task
    /// stolen into a nested join) makes a sequential core of its own, which transforms as the
    /// splitting core does, bit for bit, and is kept for later batches; a batch of one transform
    /// runs on the splitting core and leaves the stock alone.
    #[test]
    fn a_core_made_past_the_stock_transforms_alike_and_is_kept() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        pool.install(|| {
            let n = 128;
            let mut core = Fft2d::new(n, n).unwrap();
            let batch = FftBatch::new(&core);
            assert_eq!(batch.stock(), 2);
            let x = fields(n, 2, 11);
            let mut expected = core.new_spectrum();
            core.forward_rows(&x[0], 0..n, &mut expected).unwrap();
            let mut back = vec![0.0; n * n];
            core.inverse_rows(&mut expected.clone(), 0..n, &mut back)
                .unwrap();
            let same = |a: &[C64], b: &[C64]| {
                a.iter().zip(b).all(|(a, b)| {
                    a.re.to_bits() == b.re.to_bits() && a.im.to_bits() == b.im.to_bits()
                })
            };
            {
                let held = [batch.borrow(), batch.borrow()];
                assert_eq!(batch.stock(), 0);
                let mut extra = batch.borrow();
                let made = extra.core.as_mut().expect("a core");
                assert!(!made.is_parallel());
                let mut hat = made.new_spectrum();
                made.forward_rows(&x[0], 0..n, &mut hat).unwrap();
                assert!(same(&hat, &expected));
                let mut y = vec![f64::NAN; n * n];
                made.inverse_rows(&mut hat, 0..n, &mut y).unwrap();
                assert_eq!(
                    y.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                    back.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
                );
                drop(held);
            }
            assert_eq!(batch.stock(), 3);
            // One transform: on the splitting core, the stock untouched.
            let mut hat = vec![core.new_spectrum()];
            let mut skip = [true];
            batch.forward(&x[..1], 0..n, &mut hat, &mut skip).unwrap();
            assert!(!skip[0] && same(&hat[0], &expected));
            assert_eq!(batch.stock(), 3);
        });
    }

    fn batched_transforms_check() {
        for (n, rows) in [(128usize, 0..128usize), (128, 17..90), (16, 3..11)] {
            let mut core = Fft2d::new(n, n).unwrap();
            let batch = FftBatch::new(&core);
            // The 128² core splits (the batch has its sequential cores); the 16² one does not.
            assert_eq!(core.is_parallel(), n == 128);
            assert_eq!(batch.stock(), if n == 128 { 2 } else { 0 });
            let mut x = fields(n, 12, 7 + n as u64);
            for f in &mut x {
                for (i, v) in f.iter_mut().enumerate() {
                    if !rows.contains(&(i / n)) {
                        *v = 0.0;
                    }
                }
            }
            let mut hat: Vec<Vec<C64>> = (0..12).map(|_| core.new_spectrum()).collect();
            let mut skip = vec![false; 12];
            batch
                .forward(&x, rows.clone(), &mut hat, &mut skip)
                .unwrap();
            let mut y = vec![vec![f64::NAN; n * n]; 12];
            let mut hat2 = hat.clone();
            batch.inverse(&mut hat2, rows.clone(), &mut y).unwrap();
            // The batched path ran on the stock's cores and returned them.
            assert_eq!(batch.stock(), if n == 128 { 2 } else { 0 });
            for v in 0..12 {
                assert_eq!(skip[v], v % 5 == 3);
                if skip[v] {
                    continue;
                }
                let mut h = core.new_spectrum();
                core.forward_rows(&x[v], rows.clone(), &mut h).unwrap();
                assert!(h
                    .iter()
                    .zip(&hat[v])
                    .all(|(a, b)| a.re.to_bits() == b.re.to_bits()
                        && a.im.to_bits() == b.im.to_bits()));
                let mut yv = vec![f64::NAN; n * n];
                core.inverse_rows(&mut h, rows.clone(), &mut yv).unwrap();
                for (i, (a, b)) in yv.iter().zip(&y[v]).enumerate() {
                    assert_eq!(a.to_bits(), b.to_bits(), "field {v} value {i}");
                }
                // The round trip is the field times 4N² (the inverse is not normalised), on the
                // rows kept.
                let scale = (4 * n * n) as f64;
                for i in rows.start * n..rows.end * n {
                    assert!((y[v][i] / scale - x[v][i]).abs() < 1e-13);
                }
            }
        }
    }
}
