//! Normal contact by the constrained conjugate gradient of Polonsky & Keer (1999), spec §3, with
//! the DC-FFT operator `K^p_3 *` in place of multi-level summation.

use halfspace_numerics::conv2d::{DcFft2d, GridOperator, KernelFn};

use crate::{Compliance, SamError, SurfaceGrid};

/// What is prescribed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NormalLoad {
    /// Total normal force `W = A Σ p` in N.
    Force(f64),
    /// Rigid approach `δ` in m.
    Approach(f64),
}

/// Stopping rule of the normal solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalParams {
    /// `Σ|p_new − p_old| / Σ p_new` below which the iteration stops.
    pub tolerance: f64,
    /// Iteration limit.
    pub max_iterations: usize,
}

impl Default for NormalParams {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 10_000,
        }
    }
}

/// What the solve did and found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalInfo {
    /// CG iterations.
    pub iterations: usize,
    /// Final relative change of `p`.
    pub residual: f64,
    /// Rigid approach `δ` (computed under force control).
    pub approach: f64,
    /// Normal force `W` (computed under approach control).
    pub force: f64,
    /// Cells in contact.
    pub contact_cells: usize,
}

/// The Polonsky–Keer solver on one grid, planned once (operator spectrum, work arrays).
pub struct NormalSolver {
    grid: SurfaceGrid,
    op: DcFft2d,
    u: Vec<f64>,
    g: Vec<f64>,
    t: Vec<f64>,
    r: Vec<f64>,
    p_old: Vec<f64>,
}

impl NormalSolver {
    /// Plans `K^p_3 *` for the pair's normal compliance on `grid`.
    pub fn new(grid: SurfaceGrid, compliance: &Compliance) -> Result<Self, SamError> {
        let (d1, d2) = (2.0 * grid.half1, 2.0 * grid.half2);
        let kernel =
            |m: i64, n: i64| compliance.normal_from_pressure(&grid, m as f64 * d1, n as f64 * d2);
        let kernels: [Option<KernelFn>; 1] = [Some(&kernel)];
        let n = grid.len();
        Ok(Self {
            op: DcFft2d::new(grid.n1, grid.n2, 1, 1, &kernels)?,
            grid,
            u: vec![0.0; n],
            g: vec![0.0; n],
            t: vec![0.0; n],
            r: vec![0.0; n],
            p_old: vec![0.0; n],
        })
    }

    /// The grid.
    pub fn grid(&self) -> &SurfaceGrid {
        &self.grid
    }

    /// `u = K^p_3 * p` (relative normal displacement of the pressure field).
    pub fn displacement(&mut self, p: &[f64], u: &mut [f64]) -> Result<(), SamError> {
        self.op.apply(&[p], &mut [u])?;
        Ok(())
    }

    /// Solves `p ≥ 0, g = K*p + h − δ ≥ 0, p g = 0` with `h` the initial separation (geometry plus
    /// any known displacement such as the coupling term), under force or approach control
    /// (spec §3). `p` is the warm start and the result.
    pub fn solve(
        &mut self,
        h: &[f64],
        load: NormalLoad,
        p: &mut [f64],
        params: &NormalParams,
    ) -> Result<NormalInfo, SamError> {
        let n = self.grid.len();
        if h.len() != n || p.len() != n {
            return Err(SamError::Numerics(
                halfspace_numerics::NumericsError::LengthMismatch {
                    what: "normal solve fields",
                    expected: n,
                    got: h.len().min(p.len()),
                },
            ));
        }
        if let Some(v) = h.iter().find(|v| !v.is_finite()) {
            return Err(SamError::InvalidParameter {
                name: "initial separation",
                value: *v,
                allowed: "finite",
            });
        }
        let area = self.grid.cell_area();
        let (force_control, target) = match load {
            NormalLoad::Force(w) => (true, crate::error::positive("normal force", w)?),
            NormalLoad::Approach(d) => (false, crate::error::positive("approach", d)?),
        };
        // Initial guess: keep a usable warm start, else uniform (force) or small where h < δ.
        if p.iter().all(|v| *v <= 0.0) || p.iter().any(|v| !v.is_finite() || *v < 0.0) {
            if force_control {
                p.fill(target / (area * n as f64));
            } else {
                let hmin = h.iter().cloned().fold(f64::INFINITY, f64::min);
                if hmin >= target {
                    return Err(SamError::NoContact);
                }
                let scale = (target - hmin) / (self.grid.half1 * 1e3);
                for (pi, hi) in p.iter_mut().zip(h) {
                    *pi = if *hi < target {
                        scale * (target - hi)
                    } else {
                        0.0
                    };
                }
            }
        } else if force_control {
            let s: f64 = p.iter().sum();
            p.iter_mut().for_each(|v| *v *= target / (area * s));
        }
        let mut g_old = 1.0;
        let mut conjugate = false;
        let mut approach = target;
        self.t.fill(0.0);
        for it in 1..=params.max_iterations {
            self.p_old.copy_from_slice(p);
            // 1–2: gap and its mean over the contact set (the approach, under force control).
            self.op.apply(&[p], &mut [&mut self.u])?;
            let mut count = 0usize;
            let mut mean = 0.0;
            for k in 0..n {
                self.g[k] = self.u[k] + h[k] - if force_control { 0.0 } else { target };
                if p[k] > 0.0 {
                    mean += self.g[k];
                    count += 1;
                }
            }
            if count == 0 {
                return Err(SamError::NoContact);
            }
            mean /= count as f64;
            if force_control {
                approach = mean;
                self.g.iter_mut().for_each(|v| *v -= mean);
            }
            // 3–4: conjugate direction on the contact set.
            let big_g: f64 = (0..n)
                .filter(|&k| p[k] > 0.0)
                .map(|k| self.g[k] * self.g[k])
                .sum();
            let beta = if conjugate { big_g / g_old } else { 0.0 };
            for k in 0..n {
                self.t[k] = if p[k] > 0.0 {
                    self.g[k] + beta * self.t[k]
                } else {
                    0.0
                };
            }
            g_old = big_g;
            // 5–6: step length.
            self.op.apply(&[&self.t], &mut [&mut self.r])?;
            if force_control {
                let rmean = (0..n)
                    .filter(|&k| p[k] > 0.0)
                    .map(|k| self.r[k])
                    .sum::<f64>()
                    / count as f64;
                self.r.iter_mut().for_each(|v| *v -= rmean);
            }
            let (mut num, mut den) = (0.0, 0.0);
            for k in 0..n {
                if p[k] > 0.0 {
                    num += self.g[k] * self.t[k];
                    den += self.r[k] * self.t[k];
                }
            }
            let tau = if den != 0.0 { num / den } else { 0.0 };
            // 7: update and project.
            for k in 0..n {
                if p[k] > 0.0 {
                    p[k] = (p[k] - tau * self.t[k]).max(0.0);
                }
            }
            // 8: cells with penetration outside the contact re-enter.
            let mut overlap = false;
            for k in 0..n {
                if self.p_old[k] <= 0.0 && self.g[k] < 0.0 {
                    p[k] -= tau * self.g[k];
                    overlap = true;
                }
            }
            conjugate = !overlap;
            // 9: the force.
            let sum: f64 = p.iter().sum();
            if sum <= 0.0 {
                return Err(SamError::NoContact);
            }
            if force_control {
                let s = target / (area * sum);
                p.iter_mut().for_each(|v| *v *= s);
            }
            // 10: convergence.
            let change: f64 = p.iter().zip(&self.p_old).map(|(a, b)| (a - b).abs()).sum();
            let residual = change / p.iter().sum::<f64>();
            if residual < params.tolerance {
                let contact_cells = p.iter().filter(|v| **v > 0.0).count();
                if (0..n).any(|k| p[k] > 0.0 && self.grid.on_boundary(k)) {
                    return Err(SamError::ContactAtDomainEdge);
                }
                return Ok(NormalInfo {
                    iterations: it,
                    residual,
                    approach,
                    force: area * p.iter().sum::<f64>(),
                    contact_cells,
                });
            }
            if it == params.max_iterations {
                return Err(SamError::NoConvergence {
                    solver: "Polonsky–Keer normal contact",
                    iterations: it,
                    residual,
                });
            }
        }
        unreachable!("the loop returns")
    }
}
