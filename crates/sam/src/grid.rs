//! The surface grid: `N₁ × N₂` cells of size `2Δ₁ × 2Δ₂`, centred on the origin (docs/theory-sam.md#conventions).

use crate::error::positive;
use crate::SamError;

/// Cell-centred surface grid, row-major (`i N₂ + j`, `i` along `x₁`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceGrid {
    /// Cells along `x₁`.
    pub n1: usize,
    /// Cells along `x₂`.
    pub n2: usize,
    /// Half cell width along `x₁`, `Δ₁`.
    pub half1: f64,
    /// Half cell width along `x₂`, `Δ₂`.
    pub half2: f64,
}

impl SurfaceGrid {
    /// Square domain of side `extent` centred on 0 with `n × n` cells (`n ≥ 8`).
    pub fn square(n: usize, extent: f64) -> Result<Self, SamError> {
        positive("domain extent", extent)?;
        if n < 8 {
            return Err(SamError::InvalidParameter {
                name: "grid cells per side",
                value: n as f64,
                allowed: "≥ 8",
            });
        }
        let half = extent / (2 * n) as f64;
        Ok(Self {
            n1: n,
            n2: n,
            half1: half,
            half2: half,
        })
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.n1 * self.n2
    }

    /// Always false (a grid has cells).
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Cell area `4Δ₁Δ₂`.
    pub fn cell_area(&self) -> f64 {
        4.0 * self.half1 * self.half2
    }

    /// Centre of cell `(i, j)`.
    pub fn centre(&self, i: usize, j: usize) -> (f64, f64) {
        (
            (2 * i + 1) as f64 * self.half1 - self.n1 as f64 * self.half1,
            (2 * j + 1) as f64 * self.half2 - self.n2 as f64 * self.half2,
        )
    }

    /// Whether cell `k` lies on the boundary of the domain.
    pub fn on_boundary(&self, k: usize) -> bool {
        let (i, j) = (k / self.n2, k % self.n2);
        i == 0 || j == 0 || i == self.n1 - 1 || j == self.n2 - 1
    }
}

/// Checks that `padded` and `periodic` are FFT cores of `grid`'s shape in those modes (the cores a
/// contact problem shares among its operators).
pub(crate) fn check_cores(
    grid: &SurfaceGrid,
    padded: &halfspace_numerics::fft2d::Fft2d,
    periodic: &halfspace_numerics::fft2d::Fft2d,
) -> Result<(), SamError> {
    use halfspace_numerics::fft2d::Mode;
    for (core, mode) in [(padded, Mode::Padded), (periodic, Mode::Periodic)] {
        if core.shape() != (grid.n1, grid.n2) || core.mode() != mode {
            return Err(SamError::Numerics(
                halfspace_numerics::NumericsError::LengthMismatch {
                    what: "FFT core cells (or mode) for the surface grid",
                    expected: grid.len(),
                    got: core.shape().0 * core.shape().1,
                },
            ));
        }
    }
    Ok(())
}
