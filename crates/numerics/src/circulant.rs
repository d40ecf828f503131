//! Circulant (periodic) operators on an `N₁ × N₂` grid with a real, even symbol:
//! `y = IFFT₂(σ · FFT₂(x))` without padding, on the periodic mode of the one FFT core
//! ([`crate::fft2d::Fft2d::periodic`]). Used as preconditioners: the half-space compliance has the
//! symbol `2/(E*|k|)` (docs/sam.md), so the circulant with symbol `|k|` flattens its spectrum
//! ([`Circulant2d::inverse_half_space`]; Vollebregt 2014, J. Comput. Phys. 257, §4).
//! Applying does not allocate.

use crate::fft2d::{Fft2d, Mode, SingleProduct, C64};
use crate::op::{GridOperator, OperatorShape};
use crate::NumericsError;

/// A periodic convolution with a real symbol on a (shared) periodic FFT core.
pub struct Circulant2d {
    fft: Fft2d,
    /// `σ(m, n) / (N₁N₂)` in the spectrum layout ([`Fft2d::symbol_spectrum`]).
    symbol: Vec<f64>,
    hat: Vec<C64>,
    /// The single-precision product, built at its first use.
    single: Option<SingleProduct>,
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
        Self::on(Fft2d::periodic(n1, n2)?, sigma)
    }

    /// [`Circulant2d::new`] on a given periodic core (shared with other operators of its shape).
    pub fn on(fft: Fft2d, sigma: &dyn Fn(usize, usize) -> f64) -> Result<Self, NumericsError> {
        if fft.mode() != Mode::Periodic {
            return Err(NumericsError::InvalidParameter {
                name: "FFT core mode of a circulant (padded given)",
                value: 0.0,
                allowed: "periodic",
            });
        }
        Ok(Self {
            symbol: fft.symbol_spectrum(sigma)?,
            hat: fft.new_spectrum(),
            fft,
            single: None,
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
        Self::inverse_half_space_on(Fft2d::periodic(n1, n2)?, d1, d2)
    }

    /// [`Circulant2d::inverse_half_space`] on a given periodic core.
    pub fn inverse_half_space_on(fft: Fft2d, d1: f64, d2: f64) -> Result<Self, NumericsError> {
        let (n1, n2) = fft.shape();
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
        Self::on(fft, &|m, n| {
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
        self.fft.shape()
    }

    /// `y = IFFT₂(σ · FFT₂(x))` (periodic). `x` and `y` may not alias.
    pub fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        let (n1, n2) = self.fft.shape();
        for v in [x.len(), y.len()] {
            if v != n1 * n2 {
                return Err(NumericsError::LengthMismatch {
                    what: "circulant field",
                    expected: n1 * n2,
                    got: v,
                });
            }
        }
        // Forward transform, product with the symbol and inverse, fused (bit for bit).
        self.fft.convolve_real(x, &self.symbol, &mut self.hat, y)
    }

    /// [`Circulant2d::apply`] in single precision (relative error of order `1e-7`; the `f32` core
    /// planned at the first call), for the early iterations of a solver (docs/performance.md,
    /// "Mixed precision").
    pub fn apply_single(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        let (n1, n2) = self.fft.shape();
        for v in [x.len(), y.len()] {
            if v != n1 * n2 {
                return Err(NumericsError::LengthMismatch {
                    what: "circulant field",
                    expected: n1 * n2,
                    got: v,
                });
            }
        }
        if self.single.is_none() {
            self.single = Some(SingleProduct::new(&self.fft, &self.symbol)?);
        }
        self.single.as_mut().expect("built above").apply(x, y)
    }

    /// [`Circulant2d::apply`] to the field whose value at cell `c` is `x(c)`, evaluated while it
    /// is transformed ([`Fft2d::convolve_real_of`]; the same result bit for bit).
    pub fn apply_of<F: Fn(usize) -> f64 + Sync>(
        &mut self,
        x: F,
        y: &mut [f64],
    ) -> Result<(), NumericsError> {
        self.fft.convolve_real_of(x, &self.symbol, &mut self.hat, y)
    }

    /// [`Circulant2d::apply_single`] to the field `x(c)` ([`Circulant2d::apply_of`]).
    pub fn apply_single_of<F: Fn(usize) -> f64 + Sync>(
        &mut self,
        x: F,
        y: &mut [f64],
    ) -> Result<(), NumericsError> {
        if self.single.is_none() {
            self.single = Some(SingleProduct::new(&self.fft, &self.symbol)?);
        }
        self.single.as_mut().expect("built above").apply_of(x, y)
    }

    /// Frees what [`Circulant2d::apply_single`] holds.
    pub fn drop_single(&mut self) {
        self.single = None;
    }
}

impl GridOperator for Circulant2d {
    fn shape(&self) -> OperatorShape {
        let (n1, n2) = self.fft.shape();
        OperatorShape::square(n1, n2, 1)
    }

    fn apply(&mut self, x: &[&[f64]], y: &mut [&mut [f64]]) -> Result<(), NumericsError> {
        crate::op::check_fields(GridOperator::shape(self), x, y)?;
        Circulant2d::apply(self, x[0], y[0])
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
            let mut single = vec![0.0; n1 * n2];
            op.apply_single(&x, &mut single).unwrap();
            // The field given cell by cell: the same products bit for bit.
            let (mut of, mut single_of) = (vec![0.0; n1 * n2], vec![0.0; n1 * n2]);
            op.apply_of(|k| x[k], &mut of).unwrap();
            op.apply_single_of(|k| x[k], &mut single_of).unwrap();
            let same =
                |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits());
            assert!(
                same(&y, &of) && same(&single, &single_of),
                "{n1}×{n2} by cell"
            );
            let (mut worst, mut worst_single): (f64, f64) = (0.0, 0.0);
            for i in 0..n1 as isize {
                for j in 0..n2 as isize {
                    let s = a * at(i, j)
                        + b * (at(i - 1, j) + at(i + 1, j))
                        + c * (at(i, j - 1) + at(i, j + 1))
                        + d * (at(i - 1, j - 1)
                            + at(i - 1, j + 1)
                            + at(i + 1, j - 1)
                            + at(i + 1, j + 1));
                    let k = i as usize * n2 + j as usize;
                    worst = worst.max((s - y[k]).abs());
                    worst_single = worst_single.max((s - single[k]).abs());
                }
            }
            assert!(worst < 1e-12, "{n1}×{n2}: {worst:e}");
            // The single-precision product: f32 rounding of values up to ~40 (ε·40·log₂N ≈ 3e-5).
            assert!(worst_single < 1e-4, "{n1}×{n2} single: {worst_single:e}");
        }
    }
}
