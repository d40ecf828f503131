//! DC-FFT (Liu, Wang & Liu 2000; docs/theory-sam.md#dc-fft): linear (non-periodic) 2D convolution
//! `u_ij = Σ_{k,l} K_{i−k, j−l} p_kl` on an `N₁ × N₂` grid, for block operators (`n_out × n_in`
//! kernels: the 2 × 2 tangential compliance, …). The kernel is laid out on a `2N₁ × 2N₂` array with
//! offsets `−(N−1)..N−1` and the `N`-th row and column zero, transformed once; inputs are
//! zero-padded, transformed, multiplied and summed per output, transformed back and cropped.
//! [`DenseConvolution2d`] evaluates the same sum directly (O(N⁴)), as the control in tests.

use std::borrow::Cow;

pub use crate::fft2d::KernelFn;
use rayon::prelude::*;

use crate::fft2d::{multiply_accumulate, Fft2d, C64, PARALLEL_CELLS};
pub use crate::op::GridOperator;
use crate::op::{check_fields, BlockConvolution, OperatorShape};
use crate::NumericsError;

/// The DC-FFT block operator: kernel spectra built once on one (shared) padded [`Fft2d`] core.
pub struct DcFft2d {
    fft: Fft2d,
    n_in: usize,
    n_out: usize,
    /// `spectra[o * n_in + i]`: FFT₂ of the padded kernel / (4 N₁ N₂), or `None` for a zero block.
    spectra: Vec<Option<Vec<C64>>>,
    inputs_hat: Vec<Vec<C64>>,
    out_hat: Vec<C64>,
    /// Whether the spectrum products run on rayon's threads (the grid has at least
    /// [`PARALLEL_CELLS`] cells and the pool more than one thread, as the transforms).
    parallel: bool,
}

/// Spectrum values per chunk of the parallel spectrum product (64 KiB): 9 chunks at 128².
const SPECTRUM_CHUNK: usize = 4096;

impl DcFft2d {
    /// Plans the operator for kernels `kernels[o * n_in + i]` (`None` = zero block) on a core of
    /// its own.
    pub fn new(
        n1: usize,
        n2: usize,
        n_in: usize,
        n_out: usize,
        kernels: &[Option<KernelFn<'_>>],
    ) -> Result<Self, NumericsError> {
        Self::on(Fft2d::new(n1, n2)?, n_in, n_out, kernels)
    }

    /// [`DcFft2d::new`] on a given padded core (shared with the other operators of its shape).
    pub fn on(
        mut fft: Fft2d,
        n_in: usize,
        n_out: usize,
        kernels: &[Option<KernelFn<'_>>],
    ) -> Result<Self, NumericsError> {
        if kernels.len() != n_in * n_out {
            return Err(NumericsError::LengthMismatch {
                what: "DC-FFT kernel blocks",
                expected: n_in * n_out,
                got: kernels.len(),
            });
        }
        let mut spectra = Vec::with_capacity(kernels.len());
        for kernel in kernels {
            spectra.push(match kernel {
                None => None,
                Some(k) => {
                    let mut spec = fft.new_spectrum();
                    fft.kernel_spectrum(*k, &mut spec)?;
                    Some(spec)
                }
            });
        }
        Ok(Self {
            inputs_hat: vec![fft.new_spectrum(); n_in],
            out_hat: fft.new_spectrum(),
            parallel: {
                let (n1, n2) = fft.shape();
                n1 * n2 >= PARALLEL_CELLS && rayon::current_num_threads() > 1
            },
            fft,
            n_in,
            n_out,
            spectra,
        })
    }

    /// The block spectra (for bounds such as the largest eigenvalue of the operator).
    pub fn spectrum(&self, out: usize, input: usize) -> Option<&[C64]> {
        self.spectra[out * self.n_in + input].as_deref()
    }
}

impl GridOperator for DcFft2d {
    fn shape(&self) -> OperatorShape {
        let (n1, n2) = self.fft.shape();
        OperatorShape {
            n1,
            n2,
            inputs: self.n_in,
            outputs: self.n_out,
        }
    }

    fn apply(&mut self, x: &[&[f64]], y: &mut [&mut [f64]]) -> Result<(), NumericsError> {
        check_fields(GridOperator::shape(self), x, y)?;
        for (xi, hat) in x.iter().zip(self.inputs_hat.iter_mut()) {
            self.fft.forward(xi, hat)?;
        }
        let inputs = &self.inputs_hat;
        for (o, yo) in y.iter_mut().enumerate() {
            let blocks = &self.spectra[o * self.n_in..(o + 1) * self.n_in];
            if blocks.iter().all(Option::is_none) {
                yo.fill(0.0);
                continue;
            }
            // ŷ_o = Σ_i K̂_oi x̂_i, chunk by chunk (each value summed from zero in input order as
            // before: the same bits on one or more threads); on threads as the transforms are
            // (docs/performance.md, "The contact solves on two threads").
            let product = |(c, acc): (usize, &mut [C64])| {
                let range = c * SPECTRUM_CHUNK..c * SPECTRUM_CHUNK + acc.len();
                acc.fill(C64::new(0.0, 0.0));
                for (k, x) in blocks.iter().zip(inputs) {
                    if let Some(k) = k {
                        multiply_accumulate(acc, &k[range.clone()], &x[range.clone()]);
                    }
                }
            };
            if self.parallel {
                self.out_hat
                    .par_chunks_mut(SPECTRUM_CHUNK)
                    .enumerate()
                    .for_each(product);
            } else {
                self.out_hat
                    .chunks_mut(SPECTRUM_CHUNK)
                    .enumerate()
                    .for_each(product);
            }
            self.fft.inverse(&mut self.out_hat, yo)?;
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
    fn shape(&self) -> OperatorShape {
        OperatorShape {
            n1: self.n1,
            n2: self.n2,
            inputs: self.n_in,
            outputs: self.n_out,
        }
    }

    fn apply(&mut self, x: &[&[f64]], y: &mut [&mut [f64]]) -> Result<(), NumericsError> {
        let (n1, n2) = (self.n1, self.n2);
        check_fields(GridOperator::shape(self), x, y)?;
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

impl BlockConvolution for DcFft2d {
    fn build(
        fft: &Fft2d,
        n_in: usize,
        n_out: usize,
        kernels: &[Option<KernelFn<'_>>],
    ) -> Result<Self, NumericsError> {
        Self::on(fft.clone(), n_in, n_out, kernels)
    }

    fn block_spectrum(
        &self,
        out: usize,
        input: usize,
    ) -> Result<Option<Cow<'_, [C64]>>, NumericsError> {
        Ok(self.spectrum(out, input).map(Cow::Borrowed))
    }
}

impl BlockConvolution for DenseConvolution2d {
    fn build(
        fft: &Fft2d,
        n_in: usize,
        n_out: usize,
        kernels: &[Option<KernelFn<'_>>],
    ) -> Result<Self, NumericsError> {
        let (n1, n2) = fft.shape();
        Self::new(n1, n2, n_in, n_out, kernels)
    }

    fn block_spectrum(
        &self,
        out: usize,
        input: usize,
    ) -> Result<Option<Cow<'_, [C64]>>, NumericsError> {
        let Some(table) = &self.tables[out * self.n_in + input] else {
            return Ok(None);
        };
        let mut fft = Fft2d::new(self.n1, self.n2)?;
        let mut spec = fft.new_spectrum();
        fft.table_spectrum(table, &mut spec)?;
        Ok(Some(Cow::Owned(spec)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testkit::{lcg, twin_error};

    #[test]
    fn dcfft_equals_the_direct_sum_with_fixed_seeds() {
        let k1 = |m: i64, n: i64| 1.0 / (1.0 + (m * m + 2 * n * n) as f64).sqrt() + 0.1 * m as f64;
        let k2 = |m: i64, n: i64| (m as f64 * 0.3).sin() * (n as f64 * 0.7).cos();
        for (n1, n2) in [(2usize, 2usize), (5, 7), (16, 16), (13, 8)] {
            let kernels: [Option<KernelFn>; 4] = [Some(&k1), Some(&k2), None, Some(&k1)];
            let mut fast = DcFft2d::new(n1, n2, 2, 2, &kernels).unwrap();
            let mut dense = DenseConvolution2d::new(n1, n2, 2, 2, &kernels).unwrap();
            let err = twin_error(&mut fast, &mut dense, &[n1 as u64, 9]).unwrap();
            assert!(err <= 1e-13, "{n1}×{n2}: {err:e}");
            for (o, i) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let (f, d) = (
                    fast.block_spectrum(o, i).unwrap(),
                    dense.block_spectrum(o, i).unwrap(),
                );
                assert_eq!(f, d, "block ({o}, {i}) spectrum");
            }
        }
    }

    /// Operators built on one core share its work buffers and give what operators on cores of
    /// their own give, bit for bit; the flat adapter stacks the fields.
    #[test]
    fn operators_on_a_shared_core_and_the_flat_view() {
        use crate::linop::LinearOperator;
        let k1 = |m: i64, n: i64| 1.0 / (1.0 + (m * m + 2 * n * n) as f64).sqrt();
        let k2 = |m: i64, n: i64| (m as f64 * 0.3).sin() * (n as f64 * 0.7).cos();
        let kernels: [Option<KernelFn>; 4] = [Some(&k1), Some(&k2), Some(&k2), Some(&k1)];
        let core = Fft2d::new(13, 8).unwrap();
        let mut a = DcFft2d::on(core.clone(), 2, 2, &kernels).unwrap();
        let mut b = <DcFft2d as BlockConvolution>::build(&core, 2, 2, &kernels).unwrap();
        assert!(a.fft.shares_work_with(&b.fft));
        let mut own = DcFft2d::new(13, 8, 2, 2, &kernels).unwrap();
        let x = lcg(4, 2 * 13 * 8);
        let (mut ya, mut yb, mut yo) = (vec![0.0; x.len()], vec![0.0; x.len()], vec![0.0; x.len()]);
        LinearOperator::apply(&mut a, &x, &mut ya).unwrap();
        LinearOperator::apply(&mut own, &x, &mut yo).unwrap();
        LinearOperator::apply(&mut b, &x, &mut yb).unwrap();
        assert_eq!(ya, yo);
        assert_eq!(yb, yo);
        assert_eq!(LinearOperator::dim(&a), 2 * 13 * 8);
        let mut split = [vec![0.0; 13 * 8], vec![0.0; 13 * 8]];
        {
            let [s0, s1] = &mut split;
            GridOperator::apply(&mut a, &[&x[..104], &x[104..]], &mut [s0, s1]).unwrap();
        }
        assert_eq!([&ya[..104], &ya[104..]], [&split[0][..], &split[1][..]]);
        // The flat view of a non-square operator is refused.
        let one: [Option<KernelFn>; 2] = [Some(&k1), Some(&k2)];
        let mut rect = DcFft2d::new(4, 4, 2, 1, &one).unwrap();
        assert!(LinearOperator::apply(&mut rect, &[0.0; 32], &mut [0.0; 32]).is_err());
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
