//! Shared numerical engine of halfspace.
//!
//! * [`conv1d`]: zero-padded linear convolution by real FFT, planned once and applied without
//!   allocating, with a dense (O(N²)) twin that evaluates the same sum.
//! * [`power_sum`]: the causal and anti-causal trapezoid sums with the kernel `m^γ` of
//!   docs/theory-mdr.md#power-sums, the single engine behind every MDR transform.
//! * [`grid`]: the grid uniform in the square of the coordinate (docs/theory-mdr.md#squared-grid, paper Eq. 6).
//! * [`diff`]: second-order finite differences, one-sided at both ends (docs/theory-mdr.md#finite-differences).
//! * [`quad`]: trapezoid rules on uniform grids.
//! * [`fft2d`]: the one real 2D FFT core (padded for DC-FFT, periodic for circulants), plans cached
//!   by shape, one core shared by the operators of one owner.
//! * [`op`]: the one operator trait ([`op::GridOperator`]; the flat [`linop::LinearOperator`] is a
//!   blanket adapter), the even-kernel (normal) operator, and the operator sets solvers run on
//!   (fast or dense twins). [`conv2d`] (DC-FFT block operators), [`layered`] (the layered 3D
//!   DC-FFT, kernels by layer difference and layer sum) and [`circulant`] (periodic operators with
//!   a real symbol: the `|k|` preconditioner) implement it, each fast operator with a dense twin.
//! * [`testkit`]: fixed-seed inputs and the one check of a fast operator against its twin.
//! * [`memory`]: footprint estimates checked before allocating.
//! * [`parallel`]: a solve run on rayon's worker threads (one hand-off per solve, not per section).
//! * [`anderson`]: Anderson acceleration of fixed-point iterations.
//! * [`linop`], [`krylov`]: a flat linear-operator trait; restarted GMRES and the preconditioned
//!   Richardson (block-Jacobi) iteration on it.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod anderson;
pub mod circulant;
pub mod conv1d;
pub mod conv2d;
pub mod diff;
mod error;
pub mod fft2d;
pub mod fft_batch;
pub mod grid;
pub mod krylov;
pub mod layered;
pub mod linop;
pub mod memory;
pub mod op;
pub mod parallel;
pub mod power_sum;
pub mod quad;
pub mod special;
pub mod testkit;

pub use conv1d::{Backend, Precision, ToeplitzConvolution};
pub use error::NumericsError;
pub use grid::SquaredGrid;
pub use power_sum::PowerSum;

/// `x^p`, by `sqrt` when `p = 1/2` (the homogeneous exponent: several times cheaper than `powf`).
#[inline]
pub fn pow_or_sqrt(x: f64, p: f64) -> f64 {
    if p == 0.5 {
        x.sqrt()
    } else {
        x.powf(p)
    }
}
