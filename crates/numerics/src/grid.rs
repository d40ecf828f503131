//! The grid uniform in the square of the coordinate (docs/theory-mdr.md#squared-grid, paper Eq. 6):
//! `ξ_i = i h`, `x_i = √(i h)`, `h = L²/(N−1)`, `i = 0..N−1` (zero-based).

use crate::NumericsError;

/// Grid of `n` nodes, uniform in `ξ = x²` with step `h`: `ξ_i = i h`, `x_i = √ξ_i`.
///
/// The nodes crowd toward the outer end, where the contact edge of an axisymmetric contact lies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SquaredGrid {
    n: usize,
    h: f64,
}

impl SquaredGrid {
    /// Smallest grid accepted anywhere in the project.
    pub const MIN_NODES: usize = 8;

    /// Grid of `n` nodes on `0 ≤ x ≤ length`, so `h = length²/(n−1)` (Eq. 6).
    pub fn new(n: usize, length: f64) -> Result<Self, NumericsError> {
        check_n(n)?;
        if !(length.is_finite() && length > 0.0) {
            return Err(NumericsError::InvalidParameter {
                name: "grid length",
                value: length,
                allowed: "finite and > 0",
            });
        }
        Self::with_step(n, length * length / (n - 1) as f64)
    }

    /// Grid of `n` nodes whose node `index` (zero-based) lies exactly at `x = radius`:
    /// `h = radius²/index`. Used to put the contact edge `a² = (M−1)h` on a node (docs/theory-mdr.md#profile-transform).
    pub fn with_node_at(n: usize, radius: f64, index: usize) -> Result<Self, NumericsError> {
        check_n(n)?;
        if index == 0 || index >= n {
            return Err(NumericsError::InvalidParameter {
                name: "node index",
                value: index as f64,
                allowed: "in 1..n",
            });
        }
        if !(radius.is_finite() && radius > 0.0) {
            return Err(NumericsError::InvalidParameter {
                name: "node radius",
                value: radius,
                allowed: "finite and > 0",
            });
        }
        Self::with_step(n, radius * radius / index as f64)
    }

    /// Grid of `n` nodes with squared step `h`.
    pub fn with_step(n: usize, h: f64) -> Result<Self, NumericsError> {
        check_n(n)?;
        if !(h.is_finite() && h > 0.0) {
            return Err(NumericsError::InvalidParameter {
                name: "grid step h",
                value: h,
                allowed: "finite and > 0",
            });
        }
        Ok(Self { n, h })
    }

    /// Number of nodes `N`.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Always false: a grid has at least [`Self::MIN_NODES`] nodes.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Step `h` in the squared coordinate.
    pub fn step(&self) -> f64 {
        self.h
    }

    /// Largest coordinate `L = √((N−1) h)`.
    pub fn length(&self) -> f64 {
        ((self.n - 1) as f64 * self.h).sqrt()
    }

    /// `ξ_i = i h`.
    pub fn squared(&self, i: usize) -> f64 {
        i as f64 * self.h
    }

    /// `x_i = √(i h)`.
    pub fn coordinate(&self, i: usize) -> f64 {
        self.squared(i).sqrt()
    }

    /// All `x_i`.
    pub fn coordinates(&self) -> Vec<f64> {
        (0..self.n).map(|i| self.coordinate(i)).collect()
    }

    /// All `ξ_i`.
    pub fn squared_coordinates(&self) -> Vec<f64> {
        (0..self.n).map(|i| self.squared(i)).collect()
    }

    /// Fractional node index of the point `x`: `x²/h`.
    pub fn fractional_index(&self, x: f64) -> f64 {
        x * x / self.h
    }
}

fn check_n(n: usize) -> Result<(), NumericsError> {
    if n < SquaredGrid::MIN_NODES {
        return Err(NumericsError::TooFewNodes {
            what: "the squared grid",
            min: SquaredGrid::MIN_NODES,
            n,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nodes_are_uniform_in_the_square() {
        let g = SquaredGrid::new(11, 2.0).unwrap();
        assert_eq!(g.step(), 0.4);
        assert!((g.coordinate(10) - 2.0).abs() < 1e-15);
        assert!((g.squared(5) - 2.0).abs() < 1e-15);
        assert!((g.length() - 2.0).abs() < 1e-15);
        let g = SquaredGrid::with_node_at(101, 0.5, 40).unwrap();
        assert!((g.coordinate(40) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn bad_grids_are_errors() {
        assert!(SquaredGrid::new(7, 1.0).is_err());
        assert!(SquaredGrid::new(8, f64::NAN).is_err());
        assert!(SquaredGrid::new(8, -1.0).is_err());
        assert!(SquaredGrid::with_node_at(8, 1.0, 8).is_err());
        assert!(SquaredGrid::with_node_at(8, 1.0, 0).is_err());
    }
}
