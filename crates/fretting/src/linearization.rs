//! The Jacobian of the wear rate for the linearly implicit (Rosenbrock) steps
//! (docs/fretting-wear.md, "Time integration").
//!
//! The rate is `F_i(f) = p_i(f) Δu_i(f)` with `p = max(σ, 0)`, `σ = S_θ[c̃_N max(1 − g, 0)]`
//! (the cell stress transform, Eq. 14 / 28, with the edge `θ` between nodes), `g = P[D f]`
//! (the profile transform, Eq. 7 / 23, of the finite-difference slope) and
//! `Δu_i = 4[(f_i − f∞_i)/χ + J(r_i)]` on the slip annulus (clipped ≥ 0). With the contact nodes,
//! the edge `θ` and the clipping pattern frozen at the linearization point, `f ↦ p` is linear and
//!
//! `J v = Δu ⊙ 1[σ > 0] ⊙ (S_θ[−c̃_N 1[g < 1] ⊙ δg] + ∂_θσ δθ) + (4/χ) p ⊙ v`, `δg = P[D v]`,
//! `δθ = −(δg_L + θ(δg_E − δg_L))/(g_E − g_L)`
//!
//! (`L`, `E`: the last contact node and the next; `θ = (1 − g_L)/(g_E − g_L)`; `∂_θσ` by a central
//! difference at the linearization point), applied matrix-free by the same transforms (FFT
//! `O(N log N)` or MVM). The first term is the stiff one: `f ↦ p` is of order `1 − k` in the
//! radius, so its largest eigenvalue grows as `(L/h)^{1−k}`. Freezing the contact nodes and the
//! clipping pattern makes `J` an approximation where they switch; ROS2 is a W-method (second order
//! for any matrix in its place), so the step keeps its order.

use halfspace_mdr::{CellStressTransform, Material, MdrError, ProfileTransform};
use halfspace_numerics::linop::LinearOperator;
use halfspace_numerics::{diff::derivative_uniform, Backend, NumericsError, SquaredGrid};

/// `W = I − β J` (`β = γ Δτ`) at a frozen contact state, as a [`LinearOperator`] on all `N` nodes.
pub(crate) struct RosenbrockMatrix {
    grid: SquaredGrid,
    profile_tf: ProfileTransform,
    stress_tf: CellStressTransform,
    /// `c̃_N` of the normalized problem.
    modulus: f64,
    /// `4/χ`.
    slip_slope: f64,
    /// Frozen state: slip `Δu`, pressure `p`, `1[σ > 0]`, `1[g < 1]` on the contact nodes.
    slip: Vec<f64>,
    pressure: Vec<f64>,
    loaded: Vec<bool>,
    open_gap: Vec<bool>,
    /// Contact nodes `0..m` and the edge position `θ ∈ (0, 1]` in the last cell.
    contact_nodes: usize,
    theta: f64,
    /// `∂σ/∂θ` on the contact nodes and `g` at the last contact node and the next one (the edge
    /// `θ = (1 − g_L)/(g_E − g_L)` moves with `f`).
    stress_theta: Vec<f64>,
    gap_last: f64,
    gap_edge: f64,
    /// `β = γ Δτ`.
    pub(crate) beta: f64,
    slope: Vec<f64>,
    g: Vec<f64>,
    q: Vec<f64>,
    sigma: Vec<f64>,
}

impl RosenbrockMatrix {
    pub(crate) fn new(
        grid: SquaredGrid,
        material: &Material,
        backend: Backend,
        modulus: f64,
        chi: f64,
    ) -> Result<Self, MdrError> {
        let n = grid.len();
        Ok(Self {
            profile_tf: ProfileTransform::new(n, material, backend)?,
            stress_tf: CellStressTransform::new(n, material, backend)?,
            grid,
            modulus,
            slip_slope: 4.0 / chi,
            slip: vec![0.0; n],
            pressure: vec![0.0; n],
            loaded: vec![false; n],
            open_gap: vec![false; n],
            contact_nodes: 2,
            theta: 1.0,
            stress_theta: vec![0.0; n],
            gap_last: 0.0,
            gap_edge: 1.0,
            beta: 0.0,
            slope: vec![0.0; n],
            g: vec![0.0; n],
            q: vec![0.0; n],
            sigma: vec![0.0; n],
        })
    }

    /// Freezes the linearization point: the slip, the clipped pressure, the unclipped stress
    /// `σ` (for `1[σ > 0]`) and `g` (for `1[g < 1]`) on the grid, the contact nodes `0..m` and
    /// the edge `θ`; `∂σ/∂θ` by a central difference in `θ` (two stress transforms).
    pub(crate) fn freeze(
        &mut self,
        slip: &[f64],
        pressure: &[f64],
        stress: &[f64],
        g: &[f64],
        contact_nodes: usize,
        theta: f64,
    ) -> Result<(), MdrError> {
        let m = contact_nodes;
        for (q, gi) in self.q[..m].iter_mut().zip(g) {
            *q = self.modulus * (1.0 - gi).max(0.0);
        }
        let delta = 1e-6;
        let (lo, hi) = ((theta - delta).max(0.5 * theta), (theta + delta).min(1.0));
        self.stress_tf
            .line_load_to_stress(&self.grid, &self.q[..m], hi, &mut self.sigma[..m])?;
        self.stress_theta[..m].copy_from_slice(&self.sigma[..m]);
        self.stress_tf
            .line_load_to_stress(&self.grid, &self.q[..m], lo, &mut self.sigma[..m])?;
        for (d, s) in self.stress_theta[..m].iter_mut().zip(&self.sigma[..m]) {
            *d = (*d - s) / (hi - lo);
        }
        self.gap_last = g[m - 1];
        self.gap_edge = g[m];
        self.slip.copy_from_slice(slip);
        self.pressure.copy_from_slice(pressure);
        for (l, &s) in self.loaded.iter_mut().zip(stress) {
            *l = s > 0.0;
        }
        for (o, &gi) in self.open_gap.iter_mut().zip(g) {
            *o = gi < 1.0;
        }
        self.contact_nodes = contact_nodes;
        self.theta = theta;
        Ok(())
    }

    /// `J v` at the frozen state (see the module docs).
    pub(crate) fn jacobian(&mut self, v: &[f64], out: &mut [f64]) -> Result<(), MdrError> {
        let h = self.grid.step();
        derivative_uniform(v, h, &mut self.slope)?;
        self.profile_tf
            .slope_to_equivalent(&self.grid, &mut self.slope, &mut self.g)?;
        let m = self.contact_nodes;
        for i in 0..m {
            self.q[i] = if self.open_gap[i] {
                -self.modulus * self.g[i]
            } else {
                0.0
            };
        }
        self.stress_tf.line_load_to_stress(
            &self.grid,
            &self.q[..m],
            self.theta,
            &mut self.sigma[..m],
        )?;
        // δθ = −(δg_L + θ (δg_E − δg_L)) / (g_E − g_L), unless θ sits at its clamp.
        let d_theta = if self.theta < 1.0 && self.gap_edge > self.gap_last {
            -(self.g[m - 1] + self.theta * (self.g[m] - self.g[m - 1]))
                / (self.gap_edge - self.gap_last)
        } else {
            0.0
        };
        for (i, o) in out.iter_mut().enumerate() {
            *o = if i < m && self.slip[i] > 0.0 {
                let dp = if self.loaded[i] {
                    self.sigma[i] + self.stress_theta[i] * d_theta
                } else {
                    0.0
                };
                self.slip[i] * dp + self.slip_slope * self.pressure[i] * v[i]
            } else {
                0.0
            };
        }
        Ok(())
    }
}

impl LinearOperator for RosenbrockMatrix {
    fn dim(&self) -> usize {
        self.grid.len()
    }

    /// `y = x − β J x`.
    fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        halfspace_numerics::linop::check_lengths(self.grid.len(), x, y)?;
        self.jacobian(x, y).map_err(|e| match e {
            MdrError::Numerics(n) => n,
            _ => NumericsError::InvalidParameter {
                name: "Rosenbrock matrix (an MDR transform refused its input)",
                value: f64::NAN,
                allowed: "the frozen contact state of the step",
            },
        })?;
        let beta = self.beta;
        for (yi, xi) in y.iter_mut().zip(x) {
            *yi = xi - beta * *yi;
        }
        Ok(())
    }
}
