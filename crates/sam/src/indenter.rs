//! Rigid or elastic indenter shapes on the surface grid: the initial gap `h₀(x, y)` and the
//! contact radius a normal load is expected to give (Hertz / Sneddon), which sizes a default domain.

use crate::normal::NormalLoad;
use crate::{SamError, SurfaceGrid};

/// An indenter's shape.
#[derive(Debug, Clone, PartialEq)]
pub enum Indenter {
    /// `h₀ = x²/(2R_x) + y²/(2R_y)` (a sphere when `R_x = R_y`).
    Ellipsoid {
        /// Radius of curvature in the x–z plane (m).
        rx: f64,
        /// Radius of curvature in the y–z plane (m).
        ry: f64,
    },
    /// `h₀ = s √(x² + y²)`.
    Cone {
        /// Slope `s = tan` of the cone's inclination.
        slope: f64,
    },
    /// A flat punch of radius `a`: `h₀ = 0` inside, a wall (10³ × the domain side) outside.
    Flat {
        /// Punch radius (m).
        a: f64,
    },
    /// Heights on the grid, `(n1, n2)` row-major with x slow.
    Table {
        /// Rows (x).
        n1: usize,
        /// Columns (y).
        n2: usize,
        /// `h₀` per cell (m).
        heights: Vec<f64>,
    },
}

impl Indenter {
    /// A sphere of radius `r`.
    pub fn sphere(r: f64) -> Self {
        Self::Ellipsoid { rx: r, ry: r }
    }

    /// Checks sizes (finite and > 0) and tables (finite heights).
    pub fn validate(&self) -> Result<(), SamError> {
        match self {
            Self::Ellipsoid { rx, ry } => {
                crate::error::positive("indenter radius R_x", *rx)?;
                crate::error::positive("indenter radius R_y", *ry)?;
            }
            Self::Cone { slope } => {
                crate::error::positive("cone slope", *slope)?;
            }
            Self::Flat { a } => {
                crate::error::positive("punch radius", *a)?;
            }
            Self::Table { heights, n1, n2 } => {
                if heights.len() != n1 * n2 {
                    return Err(SamError::InvalidInput(format!(
                        "height table of {} values for a {n1} × {n2} shape",
                        heights.len()
                    )));
                }
                if let Some(bad) = heights.iter().find(|h| !h.is_finite()) {
                    return Err(SamError::InvalidInput(format!(
                        "height table: non-finite height {bad}"
                    )));
                }
            }
        }
        Ok(())
    }

    /// The contact radius expected under `load` on a half-space of contact modulus `e_star`
    /// (Hertz `a = (3WR/4E*)^{1/3}` with `R = √(R_x R_y)`, `a = √(δR)`; Sneddon's cone
    /// `a = √(2W/(πE*s))`, `a = 2δ/(πs)`; `0.75a` for a punch); `None` for a table.
    pub fn contact_radius_estimate(&self, e_star: f64, load: NormalLoad) -> Option<f64> {
        match (self, load) {
            (Self::Ellipsoid { rx, ry }, NormalLoad::Force(w)) => Some(
                halfspace_mdr::analytic::sphere_radius_for_force(w, (rx * ry).sqrt(), e_star),
            ),
            (Self::Ellipsoid { rx, ry }, NormalLoad::Approach(d)) => {
                Some((d * (rx * ry).sqrt()).sqrt())
            }
            (Self::Cone { slope }, NormalLoad::Force(w)) => {
                Some((2.0 * w / (std::f64::consts::PI * e_star * slope)).sqrt())
            }
            (Self::Cone { slope }, NormalLoad::Approach(d)) => {
                Some(2.0 * d / (std::f64::consts::PI * slope))
            }
            (Self::Flat { a }, _) => Some(0.75 * a),
            (Self::Table { .. }, _) => None,
        }
    }

    /// The initial gap `h₀` at the cell centres of `grid`.
    pub fn gap(&self, grid: &SurfaceGrid) -> Result<Vec<f64>, SamError> {
        self.validate()?;
        if let Self::Table { n1, n2, heights } = self {
            if *n1 != grid.n1 || *n2 != grid.n2 {
                return Err(SamError::InvalidInput(format!(
                    "height table has shape ({n1}, {n2}); the grid is ({}, {})",
                    grid.n1, grid.n2
                )));
            }
            return Ok(heights.clone());
        }
        let wall = 1e3 * 2.0 * grid.half1 * grid.n1 as f64;
        Ok((0..grid.len())
            .map(|k| {
                let (x, y) = grid.centre(k / grid.n2, k % grid.n2);
                match self {
                    Self::Ellipsoid { rx, ry } => x * x / (2.0 * rx) + y * y / (2.0 * ry),
                    Self::Cone { slope } => slope * (x * x + y * y).sqrt(),
                    Self::Flat { a } => {
                        if x * x + y * y <= a * a {
                            0.0
                        } else {
                            wall
                        }
                    }
                    Self::Table { .. } => unreachable!("returned above"),
                }
            })
            .collect())
    }
}
