//! Influence coefficients of uniform tractions on a `2Δ₁ × 2Δ₂` rectangle (docs/theory-sam.md#influence-coefficients, Love 1929,
//! Johnson 1985 §3.2), written as corner sums `⟦P⟧(x) = Σ s₁s₂ P(x₁ + s₁Δ₁, x₂ + s₂Δ₂)` of the
//! primitives of docs/theory-sam.md#corner-primitives, for one half-space and for a pair of bodies (docs/theory-sam.md#two-bodies: compliances add, the
//! normal–tangential coupling `κ` is a difference).

use std::f64::consts::PI;

use super::InPlane;
use crate::error::positive;
use crate::{SamError, SurfaceGrid};

/// `P_A`: `∂²P/∂c₁∂c₂ = 1/ρ`; `c₁ asinh(c₂/|c₁|) + c₂ asinh(c₁/|c₂|)` (zero prefactor → 0).
pub fn primitive_a(c1: f64, c2: f64) -> f64 {
    let t1 = if c1 == 0.0 {
        0.0
    } else {
        c1 * (c2 / c1.abs()).asinh()
    };
    let t2 = if c2 == 0.0 {
        0.0
    } else {
        c2 * (c1 / c2.abs()).asinh()
    };
    t1 + t2
}

/// `P_B`: `∂²P/∂c₁∂c₂ = c₁/ρ²`; `c₁ arctan(c₂/c₁) + ½ c₂ ln(c₁² + c₂²)`.
pub fn primitive_b(c1: f64, c2: f64) -> f64 {
    let t1 = if c1 == 0.0 {
        0.0
    } else {
        c1 * (c2 / c1).atan()
    };
    let t2 = if c2 == 0.0 {
        0.0
    } else {
        0.5 * c2 * (c1 * c1 + c2 * c2).ln()
    };
    t1 + t2
}

/// `c₁ asinh(c₂/|c₁|)` (part of the tangential primitive).
fn primitive_a1(c1: f64, c2: f64) -> f64 {
    if c1 == 0.0 {
        0.0
    } else {
        c1 * (c2 / c1.abs()).asinh()
    }
}

/// The corner sum `⟦P⟧(x)` over a cell of half-widths `(d1, d2)` centred at 0.
pub fn corner_sum(p: impl Fn(f64, f64) -> f64, x1: f64, x2: f64, d1: f64, d2: f64) -> f64 {
    p(x1 + d1, x2 + d2) - p(x1 + d1, x2 - d2) - p(x1 - d1, x2 + d2) + p(x1 - d1, x2 - d2)
}

/// One body of a contact pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Body {
    /// Rigid (the indenter of Leroux & Nélias).
    Rigid,
    /// Isotropic elastic, Young's modulus `e` and Poisson ratio `nu ∈ (−1, 0.5]`.
    Elastic {
        /// Young's modulus in Pa.
        e: f64,
        /// Poisson ratio.
        nu: f64,
    },
}

impl Body {
    /// An elastic body, checked.
    pub fn elastic(e: f64, nu: f64) -> Result<Self, SamError> {
        positive("Young's modulus", e)?;
        if !(nu.is_finite() && nu > -1.0 && nu <= 0.5) {
            return Err(SamError::InvalidParameter {
                name: "Poisson ratio",
                value: nu,
                allowed: "in (−1, 0.5]",
            });
        }
        Ok(Body::Elastic { e, nu })
    }

    /// `(1−ν²)/(πE)`, `(1−2ν)/(4πG)`, `(1−ν)/(2πG)`, `1/(2πG)`, `ν/(2πG)` (zeros when rigid).
    fn constants(&self) -> [f64; 5] {
        match *self {
            Body::Rigid => [0.0; 5],
            Body::Elastic { e, nu } => {
                let g = e / (2.0 * (1.0 + nu));
                [
                    (1.0 - nu * nu) / (PI * e),
                    (1.0 - 2.0 * nu) / (4.0 * PI * g),
                    (1.0 - nu) / (2.0 * PI * g),
                    1.0 / (2.0 * PI * g),
                    nu / (2.0 * PI * g),
                ]
            }
        }
    }

    /// `(2 − ν)/G` (the Cattaneo–Mindlin compliance term; 0 when rigid).
    pub fn mindlin_term(&self) -> f64 {
        match *self {
            Body::Rigid => 0.0,
            Body::Elastic { e, nu } => (2.0 - nu) * 2.0 * (1.0 + nu) / e,
        }
    }

    /// `(1 − ν²)/E` (0 when rigid).
    pub fn normal_term(&self) -> f64 {
        match *self {
            Body::Rigid => 0.0,
            Body::Elastic { e, nu } => (1.0 - nu * nu) / e,
        }
    }
}

/// The compliance constants of a pair (docs/theory-sam.md#two-bodies): normal `k₁ + k₂`, tangential sums, and the
/// coupling `κ = (1−2ν₂)/(4πG₂) − (1−2ν₁)/(4πG₁)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Compliance {
    /// `Σ (1−ν²)/(πE)`.
    pub normal: f64,
    /// `κ` (set to 0 to switch the normal–tangential coupling off).
    pub coupling: f64,
    /// `Σ (1−ν)/(2πG)`: coefficient of `c₁ asinh(c₂/|c₁|)` in `K^{q₁}_1`.
    pub tangential_a1: f64,
    /// `Σ 1/(2πG)`: coefficient of `c₂ asinh(c₁/|c₂|)` in `K^{q₁}_1`.
    pub tangential_a2: f64,
    /// `Σ ν/(2πG)`: `K^{q₁}_2 = −(Σ ν/(2πG)) ⟦ρ⟧`.
    pub tangential_cross: f64,
}

impl Compliance {
    /// Body 1 (indenter) on body 2 (half-space). At least one must be elastic.
    pub fn pair(indenter: Body, halfspace: Body) -> Result<Self, SamError> {
        let (c1, c2) = (indenter.constants(), halfspace.constants());
        if c1[0] + c2[0] == 0.0 {
            return Err(SamError::InvalidParameter {
                name: "both bodies rigid: normal compliance",
                value: 0.0,
                allowed: "> 0 (make one body elastic)",
            });
        }
        Ok(Self {
            normal: c1[0] + c2[0],
            coupling: c2[1] - c1[1],
            tangential_a1: c1[2] + c2[2],
            tangential_a2: c1[3] + c2[3],
            tangential_cross: c1[4] + c2[4],
        })
    }

    /// Whether a contact of this pair with friction `μ = friction` is coupled
    /// (docs/theory-sam.md#normal-tangential-alternation): `κ ≠ 0` and `μ > 0`. Its problem then
    /// alternates and holds the two coupling operators ([`crate::memory::problem_bytes`]).
    pub fn is_coupled(&self, friction: f64) -> bool {
        self.coupling != 0.0 && friction > 0.0
    }

    /// The same pair with the coupling switched off (`κ = 0`), as Cattaneo–Mindlin assumes.
    pub fn uncoupled(mut self) -> Self {
        self.coupling = 0.0;
        self
    }

    /// `K^p_3` (relative normal displacement per unit pressure) at offset `(x1, x2)`.
    pub fn normal_from_pressure(&self, g: &SurfaceGrid, x1: f64, x2: f64) -> f64 {
        self.normal * corner_sum(primitive_a, x1, x2, g.half1, g.half2)
    }

    /// `K(m, n)` = [`Compliance::normal_from_pressure`] at the offsets `(m d₁, n d₂)` of the
    /// quadrant `0 ≤ m < N₁`, `0 ≤ n < N₂` (row-major), from one table of the primitive at the
    /// `(N₁+1)(N₂+1)` cell corners `((2i − 1)Δ₁, (2j − 1)Δ₂)`: each corner value serves four
    /// offsets, so `P_A` is evaluated 4× less often; the four terms are combined in the order of
    /// [`corner_sum`] (the values agree with it to rounding: the corners are `(2i − 1)Δ` here,
    /// `mΔ·2 ± Δ` there). Rows in parallel (rayon) from `threshold` cells on.
    pub fn normal_quadrant(&self, g: &SurfaceGrid, threshold: usize) -> Vec<f64> {
        use rayon::prelude::*;
        let (n1, n2) = (g.n1, g.n2);
        let (c1, c2) = (n1 + 1, n2 + 1);
        let mut corners = vec![0.0; c1 * c2];
        // `P_A(c₁, c₂) = P_A(c₂, c₁)` bit for bit (the two terms swap, and `+` commutes): on square
        // cells of a square grid the corner table is symmetric, and its lower triangle is copied.
        let symmetric = n1 == n2 && g.half1 == g.half2;
        let fill_corners = |(i, row): (usize, &mut [f64])| {
            let x = (2.0 * i as f64 - 1.0) * g.half1;
            let from = if symmetric { i } else { 0 };
            for (j, v) in row.iter_mut().enumerate().skip(from) {
                *v = primitive_a(x, (2.0 * j as f64 - 1.0) * g.half2);
            }
        };
        let mut quadrant = vec![0.0; n1 * n2];
        let parallel = n1 * n2 >= threshold;
        if parallel {
            corners
                .par_chunks_mut(c2)
                .enumerate()
                .for_each(fill_corners);
        } else {
            corners.chunks_mut(c2).enumerate().for_each(fill_corners);
        }
        if symmetric {
            for i in 1..c1 {
                for j in 0..i {
                    corners[i * c2 + j] = corners[j * c2 + i];
                }
            }
        }
        let c = &corners;
        let fill = |(m, row): (usize, &mut [f64])| {
            for (n, v) in row.iter_mut().enumerate() {
                let at = |i: usize, j: usize| c[i * c2 + j];
                *v = self.normal * (at(m + 1, n + 1) - at(m + 1, n) - at(m, n + 1) + at(m, n));
            }
        };
        if parallel {
            quadrant.par_chunks_mut(n2).enumerate().for_each(fill);
        } else {
            quadrant.chunks_mut(n2).enumerate().for_each(fill);
        }
        quadrant
    }

    /// `⟦P_B^{(α)}⟧`: the shape of the coupling terms (`Δu₃ ∋ κ⟦P_B^{(α)}⟧ q_α`,
    /// `Δu_α ∋ −κ⟦P_B^{(α)}⟧ p`).
    pub fn coupling_shape(&self, g: &SurfaceGrid, alpha: InPlane, x1: f64, x2: f64) -> f64 {
        match alpha {
            InPlane::X1 => corner_sum(primitive_b, x1, x2, g.half1, g.half2),
            InPlane::X2 => corner_sum(|a, b| primitive_b(b, a), x1, x2, g.half1, g.half2),
        }
    }

    /// `K^{q_β}_α`: relative tangential displacement `α` per unit shear `β` (symmetric).
    pub fn tangential(
        &self,
        g: &SurfaceGrid,
        alpha: InPlane,
        beta: InPlane,
        x1: f64,
        x2: f64,
    ) -> f64 {
        let (d1, d2) = (g.half1, g.half2);
        match (alpha, beta) {
            (InPlane::X1, InPlane::X1) => corner_sum(
                |a, b| {
                    self.tangential_a1 * primitive_a1(a, b)
                        + self.tangential_a2 * primitive_a1(b, a)
                },
                x1,
                x2,
                d1,
                d2,
            ),
            (InPlane::X2, InPlane::X2) => corner_sum(
                |a, b| {
                    self.tangential_a1 * primitive_a1(b, a)
                        + self.tangential_a2 * primitive_a1(a, b)
                },
                x1,
                x2,
                d1,
                d2,
            ),
            (InPlane::X1, InPlane::X2) | (InPlane::X2, InPlane::X1) => {
                -self.tangential_cross * corner_sum(|a, b| (a * a + b * b).sqrt(), x1, x2, d1, d2)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On square cells of a square grid the corner table is filled on one triangle and mirrored:
    /// bit for bit the quadrant of every corner evaluated (sequential and parallel).
    #[test]
    fn the_mirrored_corner_table_is_exact() {
        let c = Compliance::pair(Body::Rigid, Body::elastic(210e9, 0.3).unwrap()).unwrap();
        for (n, threshold) in [(9, usize::MAX), (131, 0)] {
            let h = 0.9e-6;
            let g = SurfaceGrid::square(n, 2.0 * h * n as f64).unwrap();
            let h = g.half1;
            let q = c.normal_quadrant(&g, threshold);
            let pa = |i: usize, j: usize| {
                primitive_a((2.0 * i as f64 - 1.0) * h, (2.0 * j as f64 - 1.0) * h)
            };
            for m in 0..n {
                for k in 0..n {
                    let all =
                        c.normal * (pa(m + 1, k + 1) - pa(m + 1, k) - pa(m, k + 1) + pa(m, k));
                    assert_eq!(q[m * n + k].to_bits(), all.to_bits(), "({m}, {k})");
                }
            }
        }
    }

    /// The corner-table quadrant equals the corner sums cell by cell to rounding, sequential and
    /// parallel, on unequal cell sides. Far from the cell the four corner terms (~ r ln r) cancel
    /// to ~1/r, so both forms carry rounding of ~1e-16 · (r/Δ) ln(r/Δ) of the self term: measured
    /// 1.04e-14 at 130 cells, bound 1e-13.
    #[test]
    fn normal_quadrant_is_the_corner_sum() {
        let c = Compliance::pair(Body::Rigid, Body::elastic(210e9, 0.3).unwrap()).unwrap();
        for (n1, n2, threshold) in [(7, 12, usize::MAX), (140, 130, 0)] {
            let g = SurfaceGrid {
                n1,
                n2,
                half1: 1.3e-6,
                half2: 0.7e-6,
            };
            let q = c.normal_quadrant(&g, threshold);
            let scale = q[0];
            for m in 0..n1 {
                for n in 0..n2 {
                    let direct = c.normal_from_pressure(
                        &g,
                        2.0 * g.half1 * m as f64,
                        2.0 * g.half2 * n as f64,
                    );
                    let e = (q[m * n2 + n] - direct).abs() / scale;
                    assert!(e <= 1e-13, "({m}, {n}): {e:e}");
                }
            }
        }
    }

    #[test]
    fn surface_coefficients_of_spec_7_5() {
        // E = 1, ν = 0.3, rectangle half-widths (1, 0.6), observed at (1.7, −0.4).
        let one = Compliance::pair(Body::Rigid, Body::elastic(1.0, 0.3).unwrap()).unwrap();
        let g = SurfaceGrid {
            n1: 8,
            n2: 8,
            half1: 1.0,
            half2: 0.6,
        };
        let (x1, x2) = (1.7, -0.4);
        let want = [
            (one.normal_from_pressure(&g, x1, x2), 0.43606728),
            (
                -one.coupling * one.coupling_shape(&g, InPlane::X1, x1, x2),
                -0.11680032,
            ),
            (
                one.tangential(&g, InPlane::X1, InPlane::X1, x1, x2),
                0.60150760,
            ),
            (
                one.tangential(&g, InPlane::X2, InPlane::X2, x1, x2),
                0.45751292,
            ),
            (
                one.tangential(&g, InPlane::X2, InPlane::X1, x1, x2),
                -0.03982511,
            ),
            (
                one.coupling * one.coupling_shape(&g, InPlane::X1, x1, x2),
                0.11680032,
            ),
        ];
        for (k, (got, want)) in want.iter().enumerate() {
            assert!((got - want).abs() < 5e-8, "#{k}: {got} vs {want}");
        }
    }

    #[test]
    fn self_values_and_symmetry() {
        let c = Compliance::pair(Body::Rigid, Body::elastic(2.0, 0.25).unwrap()).unwrap();
        let g = SurfaceGrid {
            n1: 8,
            n2: 8,
            half1: 0.5,
            half2: 0.5,
        };
        let asinh1 = 1f64.asinh();
        assert!(
            (c.normal_from_pressure(&g, 0.0, 0.0) - c.normal * 8.0 * 0.5 * asinh1).abs() < 1e-14
        );
        let gmod = 2.0 / 2.5;
        let want = (2.0 - 0.25) * 4.0 * 0.5 * asinh1 / (2.0 * PI * gmod);
        assert!((c.tangential(&g, InPlane::X1, InPlane::X1, 0.0, 0.0) - want).abs() < 1e-14);
        assert_eq!(c.coupling_shape(&g, InPlane::X1, 0.0, 0.0), 0.0);
        assert_eq!(c.tangential(&g, InPlane::X1, InPlane::X2, 0.0, 0.0), 0.0);
        for (x1, x2) in [(1.0, 2.0), (-3.0, 1.0), (2.0, -5.0)] {
            // Even kernels: K(x) = K(−x); the coupling shape is odd in x_α.
            assert!(
                (c.normal_from_pressure(&g, x1, x2) - c.normal_from_pressure(&g, -x1, -x2)).abs()
                    < 1e-15
            );
            assert!(
                (c.coupling_shape(&g, InPlane::X1, x1, x2)
                    + c.coupling_shape(&g, InPlane::X1, -x1, x2))
                .abs()
                    < 1e-14
            );
            assert!(
                (c.tangential(&g, InPlane::X1, InPlane::X2, x1, x2)
                    - c.tangential(&g, InPlane::X2, InPlane::X1, x1, x2))
                .abs()
                    < 1e-15
            );
        }
    }
}
