//! Convolution with a kernel even in both offsets (the normal compliance of the half-space,
//! docs/sam.md): the kernel's quadrant is tabulated once; the fast operator stores the real
//! spectrum of its padded layout ([`Fft2d::even_kernel_spectrum`], half of a complex one), the twin
//! sums the quadrant's columns directly. The quadrant doubles as the column table of the normal
//! solver's incremental update ([`EvenKernelOperator::add_columns`]).

use rayon::prelude::*;

use super::{check_fields, EvenKernelOperator, GridOperator, OperatorShape};
use crate::fft2d::{Fft2d, SingleProduct, C64, PARALLEL_CELLS};
use crate::NumericsError;

/// `y += Σ_c v_c K(· − x_c)` over the quadrant table (rows in parallel on large grids).
fn add_quadrant_columns(quadrant: &[f64], n2: usize, cells: &[(usize, f64)], y: &mut [f64]) {
    let body = |(i, row): (usize, &mut [f64])| {
        for &(k, v) in cells {
            let (ik, jk) = (k / n2, k % n2);
            let di = i.abs_diff(ik);
            let kr = &quadrant[di * n2..(di + 1) * n2];
            // j < jk: offset jk − j; j ≥ jk: offset j − jk.
            for (j, yj) in row[..jk].iter_mut().enumerate() {
                *yj += v * kr[jk - j];
            }
            for (yj, kv) in row[jk..].iter_mut().zip(kr) {
                *yj += v * kv;
            }
        }
    };
    if y.len() >= PARALLEL_CELLS {
        y.par_chunks_mut(n2).enumerate().for_each(body);
    } else {
        y.chunks_mut(n2).enumerate().for_each(body);
    }
}

fn check_quadrant(fft: &Fft2d, quadrant: &[f64]) -> Result<(usize, usize), NumericsError> {
    let (n1, n2) = fft.shape();
    if quadrant.len() != n1 * n2 {
        return Err(NumericsError::LengthMismatch {
            what: "even kernel quadrant",
            expected: n1 * n2,
            got: quadrant.len(),
        });
    }
    Ok((n1, n2))
}

/// `y = K * x` by DC-FFT with the real spectrum of an even kernel, on a (shared) padded core.
pub struct EvenConvolution2d {
    fft: Fft2d,
    /// `K(m, n)` for `0 ≤ m < N₁`, `0 ≤ n < N₂`, row-major.
    quadrant: Vec<f64>,
    /// Real spectrum of the padded kernel / (4N₁N₂).
    spectrum: Vec<f64>,
    hat: Vec<C64>,
    /// The single-precision product, built at its first use.
    single: Option<SingleProduct>,
}

impl EvenKernelOperator for EvenConvolution2d {
    fn build(fft: &Fft2d, quadrant: Vec<f64>) -> Result<Self, NumericsError> {
        check_quadrant(fft, &quadrant)?;
        let mut fft = fft.clone();
        let mut spectrum = vec![0.0; fft.spectrum_len()];
        let mut hat = fft.new_spectrum();
        fft.even_kernel_spectrum(&quadrant, &mut spectrum, &mut hat)?;
        Ok(Self {
            hat,
            fft,
            quadrant,
            spectrum,
            single: None,
        })
    }

    fn add_columns(&self, cells: &[(usize, f64)], y: &mut [f64]) {
        add_quadrant_columns(&self.quadrant, self.fft.shape().1, cells, y);
    }

    fn apply_field_single(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        check_fields(GridOperator::shape(self), &[x], &[y])?;
        if self.single.is_none() {
            self.single = Some(SingleProduct::new(&self.fft, &self.spectrum)?);
        }
        self.single.as_mut().expect("built above").apply(x, y)
    }

    fn drop_single(&mut self) {
        self.single = None;
    }
}

impl GridOperator for EvenConvolution2d {
    fn shape(&self) -> OperatorShape {
        let (n1, n2) = self.fft.shape();
        OperatorShape::square(n1, n2, 1)
    }

    fn apply(&mut self, x: &[&[f64]], y: &mut [&mut [f64]]) -> Result<(), NumericsError> {
        check_fields(GridOperator::shape(self), x, y)?;
        // Forward transform, product with the real spectrum and inverse, fused (bit for bit).
        self.fft
            .convolve_real(x[0], &self.spectrum, &mut self.hat, y[0])
    }
}

/// The dense twin of [`EvenConvolution2d`]: `y = Σ_c x_c K(· − x_c)` over the nonzero cells, column
/// by column from the quadrant (O(N²) per product).
pub struct DenseEvenConvolution2d {
    n1: usize,
    n2: usize,
    quadrant: Vec<f64>,
    /// The nonzero input cells (capacity `N₁N₂`: no allocation when applying).
    cells: Vec<(usize, f64)>,
}

impl EvenKernelOperator for DenseEvenConvolution2d {
    fn build(fft: &Fft2d, quadrant: Vec<f64>) -> Result<Self, NumericsError> {
        let (n1, n2) = check_quadrant(fft, &quadrant)?;
        if let Some(bad) = quadrant.iter().find(|v| !v.is_finite()) {
            return Err(NumericsError::InvalidParameter {
                name: "DC-FFT kernel value",
                value: *bad,
                allowed: "finite",
            });
        }
        Ok(Self {
            n1,
            n2,
            quadrant,
            cells: Vec::with_capacity(n1 * n2),
        })
    }

    fn add_columns(&self, cells: &[(usize, f64)], y: &mut [f64]) {
        add_quadrant_columns(&self.quadrant, self.n2, cells, y);
    }
}

impl GridOperator for DenseEvenConvolution2d {
    fn shape(&self) -> OperatorShape {
        OperatorShape::square(self.n1, self.n2, 1)
    }

    fn apply(&mut self, x: &[&[f64]], y: &mut [&mut [f64]]) -> Result<(), NumericsError> {
        check_fields(GridOperator::shape(self), x, y)?;
        let mut cells = std::mem::take(&mut self.cells);
        cells.clear();
        cells.extend(
            x[0].iter()
                .enumerate()
                .filter(|(_, v)| **v != 0.0)
                .map(|(k, v)| (k, *v)),
        );
        y[0].fill(0.0);
        self.add_columns(&cells, y[0]);
        self.cells = cells;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conv2d::DenseConvolution2d;
    use crate::fft2d::KernelFn;
    use crate::op::BlockConvolution;
    use crate::testkit::{lcg, twin_error};

    /// An even kernel with the decay of the normal compliance.
    fn quadrant(n1: usize, n2: usize) -> Vec<f64> {
        (0..n1 * n2)
            .map(|k| {
                let (m, n) = ((k / n2) as f64, (k % n2) as f64);
                1.0 / (0.5 + m * m + 1.7 * n * n).sqrt()
            })
            .collect()
    }

    /// Fast against twin, and the twin against the general block convolution of the full kernel
    /// (fixed seeds), on grids below and above the parallel threshold and with unequal sides.
    #[test]
    fn the_fast_operator_equals_its_twin_and_the_full_kernel_sum() {
        for (n1, n2) in [(9, 14), (130, 128)] {
            let fft = Fft2d::new(n1, n2).unwrap();
            let q = quadrant(n1, n2);
            let mut fast = EvenConvolution2d::build(&fft, q.clone()).unwrap();
            let mut twin = DenseEvenConvolution2d::build(&fft, q.clone()).unwrap();
            let err = twin_error(&mut fast, &mut twin, &[1, 2]).unwrap();
            assert!(err < 1e-13, "{n1}×{n2}: {err:e}");
            let k = |m: i64, n: i64| q[m.unsigned_abs() as usize * n2 + n.unsigned_abs() as usize];
            let kernels: [Option<KernelFn>; 1] = [Some(&k)];
            let mut full = DenseConvolution2d::build(&fft, 1, 1, &kernels).unwrap();
            let err = twin_error(&mut twin, &mut full, &[3]).unwrap();
            assert!(err < 1e-13, "{n1}×{n2}: {err:e}");
        }
    }

    /// The single-precision product against the dense twin (fixed seeds), below and above the
    /// parallel threshold: within 2e-6 of max |y| (f32 rounding, ε = 6e-8, grown over the
    /// log₂(4N₁N₂) ≈ 16 stages of the transforms; measured 1.6e-7 at 130×128).
    #[test]
    fn the_single_precision_product_equals_the_twin_to_f32_rounding() {
        struct Single(EvenConvolution2d);
        impl GridOperator for Single {
            fn shape(&self) -> OperatorShape {
                GridOperator::shape(&self.0)
            }
            fn apply(&mut self, x: &[&[f64]], y: &mut [&mut [f64]]) -> Result<(), NumericsError> {
                self.0.apply_field_single(x[0], y[0])
            }
        }
        for (n1, n2) in [(9, 14), (130, 128)] {
            let fft = Fft2d::new(n1, n2).unwrap();
            let q = quadrant(n1, n2);
            let mut single = Single(EvenConvolution2d::build(&fft, q.clone()).unwrap());
            let mut twin = DenseEvenConvolution2d::build(&fft, q).unwrap();
            let err = twin_error(&mut single, &mut twin, &[1, 2]).unwrap();
            assert!(err < 2e-6 && err > 1e-12, "{n1}×{n2}: {err:e}");
            single.0.drop_single();
            let err = twin_error(&mut single, &mut twin, &[3]).unwrap();
            assert!(err < 2e-6, "{n1}×{n2} rebuilt: {err:e}");
        }
    }

    /// The column-by-column update equals the product of the change.
    #[test]
    fn added_columns_equal_the_product() {
        for (n1, n2) in [(12, 9), (130, 128)] {
            let fft = Fft2d::new(n1, n2).unwrap();
            let mut op = EvenConvolution2d::build(&fft, quadrant(n1, n2)).unwrap();
            let v = lcg(7, 4);
            let cells = [
                (0, v[0]),
                (n1 * n2 - 1, v[1]),
                (5 * n2 + 3, v[2]),
                (n2 + 8, v[3]),
            ];
            let mut x = vec![0.0; n1 * n2];
            for &(k, v) in &cells {
                x[k] += v;
            }
            let mut by_product = vec![0.0; n1 * n2];
            op.apply_field(&x, &mut by_product).unwrap();
            let mut by_columns = vec![0.0; n1 * n2];
            op.add_columns(&cells, &mut by_columns);
            let scale = by_product.iter().map(|v| v.abs()).fold(0.0, f64::max);
            let worst = by_product
                .iter()
                .zip(&by_columns)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(worst < 1e-13 * scale, "{n1}×{n2}: {:e}", worst / scale);
        }
    }
}
