//! Indenter profiles `f(r)`: the gap between the indenter and the undeformed surface, with
//! `f(0) = 0` (docs/theory-mdr.md#conventions and docs/theory-mdr.md#p6-the-apex-at-zero).
//!
//! For the profile transform each profile is split as `f(r) = s₀ r + f_rem(r)`, where
//! `s₀ = f'(0⁺)` is the conical part, transformed in closed form (`g = (π/2) s₀ |x|`, docs/theory-mdr.md#p5-conical-profiles),
//! and the smooth remainder goes through Eq. 7 with `f̂'_rem(ρ) = f'_rem(r)/(2r)` exact where the
//! profile knows it, by finite differences of `f̂_rem` on the grid otherwise.

use halfspace_numerics::{diff::derivative_uniform, SquaredGrid};

use crate::error::{positive, MdrError};

/// An axisymmetric indenter profile.
#[derive(Debug, Clone, PartialEq)]
pub enum Profile {
    /// Paraboloid `f = r²/(2R)`.
    Sphere {
        /// Radius of curvature `R` in m.
        radius: f64,
    },
    /// Cone `f = r tan θ`, with `slope = tan θ` (θ between surface and cone).
    Cone {
        /// `tan θ`.
        slope: f64,
    },
    /// Flat cylindrical punch of radius `a`: `f = 0` for `r < a`, a wall beyond.
    FlatPunch {
        /// Punch radius `a` in m.
        radius: f64,
    },
    /// Power law `f = c rⁿ`, `n ≥ 1` (convex).
    Power {
        /// Coefficient `c` in m^(1−n).
        c: f64,
        /// Exponent `n`.
        n: f64,
    },
    /// Tabulated `(r, f)`, cubic Hermite interpolation in `r`.
    Tabulated(ProfileTable),
}

impl Profile {
    /// Sphere (paraboloid) of radius `R > 0`.
    pub fn sphere(radius: f64) -> Result<Self, MdrError> {
        Ok(Profile::Sphere {
            radius: positive("sphere radius R", radius)?,
        })
    }

    /// Cone with `slope = tan θ > 0`.
    pub fn cone(slope: f64) -> Result<Self, MdrError> {
        Ok(Profile::Cone {
            slope: positive("cone slope tan θ", slope)?,
        })
    }

    /// Flat punch of radius `a > 0`.
    pub fn flat_punch(radius: f64) -> Result<Self, MdrError> {
        Ok(Profile::FlatPunch {
            radius: positive("punch radius a", radius)?,
        })
    }

    /// Power law `f = c rⁿ` with `c > 0`, `n ≥ 1`.
    pub fn power(c: f64, n: f64) -> Result<Self, MdrError> {
        positive("power-law coefficient c", c)?;
        if !(n.is_finite() && n >= 1.0) {
            return Err(MdrError::InvalidParameter {
                name: "power-law exponent n",
                value: n,
                allowed: "finite and ≥ 1 (n < 1 is not convex)",
            });
        }
        Ok(Profile::Power { c, n })
    }

    /// Tabulated profile; see [`ProfileTable::new`].
    pub fn tabulated(r: Vec<f64>, f: Vec<f64>) -> Result<Self, MdrError> {
        Ok(Profile::Tabulated(ProfileTable::new(r, f)?))
    }

    /// Short name for summaries.
    pub fn kind(&self) -> &'static str {
        match self {
            Profile::Sphere { .. } => "sphere",
            Profile::Cone { .. } => "cone",
            Profile::FlatPunch { .. } => "flat",
            Profile::Power { .. } => "power",
            Profile::Tabulated(_) => "table",
        }
    }

    /// `f(r)`. A table is extended linearly beyond its last row (the contact solve refuses
    /// contact radii there); a flat punch is `0` inside and `+∞` beyond its radius.
    pub fn height(&self, r: f64) -> f64 {
        let r = r.abs();
        match self {
            Profile::Sphere { radius } => r * r / (2.0 * radius),
            Profile::Cone { slope } => slope * r,
            Profile::FlatPunch { radius } => {
                if r <= *radius {
                    0.0
                } else {
                    f64::INFINITY
                }
            }
            Profile::Power { c, n } => c * r.powf(*n),
            Profile::Tabulated(t) => t.height(r),
        }
    }

    /// Conical part `s₀ = f'(0⁺)`, transformed in closed form (docs/theory-mdr.md#p5-conical-profiles).
    pub fn conical_slope(&self) -> f64 {
        match self {
            Profile::Cone { slope } => *slope,
            Profile::Power { c, n } if *n == 1.0 => *c,
            Profile::Tabulated(t) => t.slope_at_origin(),
            _ => 0.0,
        }
    }

    /// Largest radius where the profile is defined (tables, punches); `None` if unbounded.
    pub fn max_radius(&self) -> Option<f64> {
        match self {
            Profile::FlatPunch { radius } => Some(*radius),
            Profile::Tabulated(t) => Some(t.max_radius()),
            _ => None,
        }
    }

    /// Cubic part `c₃` of `f = s₀ r + c₀ r² + c₃ r³ + …` at the apex, transformed in closed form
    /// (`κ₃(k) c₃ |x|³`): an `r³` term left in Eq. 7 makes `ĝ'' ~ ξ^{−1/2}` at the origin, where the
    /// pressure sums then converge slowly. `c` for `f = c r³`; for a table, the `r³` coefficient of
    /// its interpolant on the first interval.
    pub fn cubic_coefficient(&self) -> f64 {
        match self {
            Profile::Power { c, n } if *n == 3.0 => *c,
            Profile::Tabulated(t) => t.cubic_at_origin(),
            _ => 0.0,
        }
    }

    /// Writes `f̂'_rem(ξ_i)`, the derivative with respect to `ρ = r²` of the profile without its
    /// conical and cubic parts, at every grid node (the input of Eq. 7). Exact for spheres and
    /// power laws with `n ≥ 2`; otherwise the second-order differences of docs/theory-mdr.md#finite-differences of the sampled
    /// remainder (`scratch` holds the samples).
    pub fn squared_slope(
        &self,
        grid: &SquaredGrid,
        out: &mut [f64],
        scratch: &mut [f64],
    ) -> Result<(), MdrError> {
        let n = grid.len();
        let out = &mut out[..n];
        match *self {
            Profile::Sphere { radius } => out.fill(0.5 / radius),
            Profile::Cone { .. }
            | Profile::FlatPunch { .. }
            | Profile::Power { n: 1.0, .. }
            | Profile::Power { n: 3.0, .. } => out.fill(0.0),
            Profile::Power { c, n: p } if p >= 2.0 => {
                for (i, o) in out.iter_mut().enumerate() {
                    let rho = grid.squared(i);
                    *o = 0.5
                        * c
                        * p
                        * if p == 2.0 {
                            1.0
                        } else {
                            rho.powf(0.5 * p - 1.0)
                        };
                }
            }
            _ => {
                let s0 = self.conical_slope();
                let c3 = self.cubic_coefficient();
                let samples = &mut scratch[..n];
                for (i, s) in samples.iter_mut().enumerate() {
                    let r = grid.coordinate(i);
                    *s = self.height(r) - s0 * r - c3 * r * r * r;
                }
                derivative_uniform(samples, grid.step(), out)?;
            }
        }
        Ok(())
    }
}

/// A validated table `(r_k, f_k)`: at least 3 rows, `r_0 = 0`, `r` strictly increasing, all
/// finite; `f` is shifted so that `f(0) = 0` (docs/theory-mdr.md#p6-the-apex-at-zero). Interpolated by cubic Hermite
/// polynomials with second-order three-point slopes.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileTable {
    r: Vec<f64>,
    f: Vec<f64>,
    slope: Vec<f64>,
    shift: f64,
}

impl ProfileTable {
    /// Minimum number of rows.
    pub const MIN_ROWS: usize = 3;

    /// Relative floor under which a table's apex slope counts as zero (see
    /// [`Self::slope_at_origin`]).
    pub const APEX_SLOPE_FLOOR: f64 = 1e-4;

    /// Validates and prepares a table.
    pub fn new(r: Vec<f64>, f: Vec<f64>) -> Result<Self, MdrError> {
        if r.len() != f.len() {
            return Err(MdrError::InvalidTable(format!(
                "r has {} rows but f has {}",
                r.len(),
                f.len()
            )));
        }
        if r.len() < Self::MIN_ROWS {
            return Err(MdrError::InvalidTable(format!(
                "needs at least {} rows, got {}",
                Self::MIN_ROWS,
                r.len()
            )));
        }
        if let Some(k) = r.iter().chain(&f).position(|v| !v.is_finite()) {
            let (col, row) = if k < r.len() {
                ("r", k)
            } else {
                ("f", k - r.len())
            };
            return Err(MdrError::InvalidTable(format!(
                "non-finite value in column {col} at row {row}"
            )));
        }
        if r[0] != 0.0 {
            return Err(MdrError::InvalidTable(format!(
                "must start at r = 0, starts at r = {}",
                r[0]
            )));
        }
        if let Some(k) = r.windows(2).position(|w| w[1] <= w[0]) {
            return Err(MdrError::InvalidTable(format!(
                "r must increase strictly; row {} (r = {}) follows r = {}",
                k + 1,
                r[k + 1],
                r[k]
            )));
        }
        let shift = f[0];
        let f: Vec<f64> = f.iter().map(|v| v - shift).collect();
        let slope = hermite_slopes(&r, &f);
        Ok(Self { r, f, slope, shift })
    }

    /// The radii.
    pub fn radii(&self) -> &[f64] {
        &self.r
    }

    /// The heights, shifted so that `f(0) = 0`.
    pub fn heights(&self) -> &[f64] {
        &self.f
    }

    /// The value subtracted from the given heights to make `f(0) = 0`.
    pub fn shift(&self) -> f64 {
        self.shift
    }

    /// Last tabulated radius.
    pub fn max_radius(&self) -> f64 {
        *self.r.last().expect("validated: at least 3 rows")
    }

    /// `f'(0⁺)` from the interpolant, or 0 when it is below [`Self::APEX_SLOPE_FLOOR`] times the
    /// table's mean slope `f(r_max)/r_max`: a smooth apex sampled in a table gives a slope estimate
    /// of the size of the interpolation error (`O(h²)` times the third derivative), which the
    /// conical split would turn into a spurious infinite pressure at the apex (docs/theory-mdr.md#p5-conical-profiles).
    pub fn slope_at_origin(&self) -> f64 {
        let mean = (self.f[self.f.len() - 1] / self.max_radius()).abs();
        if self.slope[0].abs() <= Self::APEX_SLOPE_FLOOR * mean {
            0.0
        } else {
            self.slope[0]
        }
    }

    /// The `r³` coefficient at the apex: `f − s₀ r = c₀ r² + c₃ r³ + c₄ r⁴` fitted through rows 1–3
    /// (exact for such polynomials; the first interval's Hermite cubic cannot be used, its end
    /// slopes are only second-order estimates). 0 for tables of fewer than 4 rows, or when below
    /// `1e-4 f(r_max)/r_max³`.
    pub fn cubic_at_origin(&self) -> f64 {
        if self.r.len() < 4 {
            return 0.0;
        }
        let s0 = self.slope_at_origin();
        let z = |i: usize| (self.f[i] - s0 * self.r[i]) / (self.r[i] * self.r[i]);
        let (r1, r2, r3) = (self.r[1], self.r[2], self.r[3]);
        let d12 = (z(2) - z(1)) / (r2 - r1);
        let d23 = (z(3) - z(2)) / (r3 - r2);
        let c4 = (d23 - d12) / (r3 - r1);
        let c3 = d12 - c4 * (r1 + r2);
        let rmax = self.max_radius();
        let scale = (self.f[self.f.len() - 1] / (rmax * rmax * rmax)).abs();
        if c3.abs() <= Self::APEX_SLOPE_FLOOR * scale {
            0.0
        } else {
            c3
        }
    }

    /// Interpolated `f(r)`; linear extension beyond the last row.
    pub fn height(&self, r: f64) -> f64 {
        let n = self.r.len();
        if r >= self.r[n - 1] {
            return self.f[n - 1] + self.slope[n - 1] * (r - self.r[n - 1]);
        }
        let k = match self.r.binary_search_by(|v| v.total_cmp(&r)) {
            Ok(k) => return self.f[k],
            Err(k) => k - 1,
        };
        let h = self.r[k + 1] - self.r[k];
        let t = (r - self.r[k]) / h;
        let (t2, t3) = (t * t, t * t * t);
        (2.0 * t3 - 3.0 * t2 + 1.0) * self.f[k]
            + (t3 - 2.0 * t2 + t) * h * self.slope[k]
            + (-2.0 * t3 + 3.0 * t2) * self.f[k + 1]
            + (t3 - t2) * h * self.slope[k + 1]
    }
}

/// Second-order three-point slopes on a non-uniform grid (one-sided at the ends).
fn hermite_slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let d: Vec<f64> = (0..n - 1)
        .map(|k| (y[k + 1] - y[k]) / (x[k + 1] - x[k]))
        .collect();
    let h: Vec<f64> = (0..n - 1).map(|k| x[k + 1] - x[k]).collect();
    let mut m = vec![0.0; n];
    for k in 1..n - 1 {
        m[k] = (h[k] * d[k - 1] + h[k - 1] * d[k]) / (h[k - 1] + h[k]);
    }
    m[0] = ((2.0 * h[0] + h[1]) * d[0] - h[0] * d[1]) / (h[0] + h[1]);
    let (a, b) = (h[n - 2], h[n - 3]);
    m[n - 1] = ((2.0 * a + b) * d[n - 2] - a * d[n - 3]) / (a + b);
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_interpolation_is_third_order_exact_for_quadratics() {
        let r: Vec<f64> = (0..11).map(|k| 0.1 * k as f64).collect();
        let f: Vec<f64> = r.iter().map(|x| 1.0 + x * x + 0.5 * x).collect();
        let t = ProfileTable::new(r, f).unwrap();
        assert_eq!(t.shift(), 1.0);
        for x in [0.0, 0.05, 0.33, 0.77, 0.999] {
            assert!((t.height(x) - (x * x + 0.5 * x)).abs() < 1e-14);
        }
        assert!((t.slope_at_origin() - 0.5).abs() < 1e-13);
    }

    #[test]
    fn bad_tables_are_errors() {
        let ok = vec![0.0, 1.0, 2.0];
        assert!(ProfileTable::new(vec![], vec![]).is_err());
        assert!(ProfileTable::new(vec![0.0, 1.0], vec![0.0, 1.0]).is_err());
        assert!(ProfileTable::new(vec![0.1, 1.0, 2.0], ok.clone()).is_err());
        assert!(ProfileTable::new(vec![0.0, 2.0, 1.0], ok.clone()).is_err());
        assert!(ProfileTable::new(vec![0.0, 1.0, 1.0], ok.clone()).is_err());
        assert!(ProfileTable::new(ok.clone(), vec![0.0, f64::NAN, 1.0]).is_err());
        assert!(ProfileTable::new(ok.clone(), vec![0.0, 1.0]).is_err());
        let e = ProfileTable::new(vec![0.0, 2.0, 1.0], ok).unwrap_err();
        assert!(e.to_string().contains("increase"), "{e}");
    }

    #[test]
    fn bad_parameters_are_errors() {
        assert!(Profile::sphere(0.0).is_err());
        assert!(Profile::sphere(f64::NAN).is_err());
        assert!(Profile::cone(-1.0).is_err());
        assert!(Profile::flat_punch(f64::INFINITY).is_err());
        assert!(Profile::power(1.0, 0.5).is_err());
        assert!(Profile::power(-1.0, 2.0).is_err());
    }
}
