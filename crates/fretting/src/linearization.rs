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
//! for any matrix in its place), so the step keeps its order. The same holds for the experimental
//! edge cells (docs/fretting-wear.md, "Edge cells"): their rate is the cell mean of `p Δu`, `J`
//! keeps the nodal form in those rows.

use halfspace_mdr::transform::{cell_weights, node_powers, stress_scale};
use halfspace_mdr::{CellStressTransform, Material, MdrError, ProfileTransform};
use halfspace_numerics::linop::LinearOperator;
use halfspace_numerics::{
    diff::derivative_uniform, pow_or_sqrt, Backend, NumericsError, Precision, SquaredGrid,
    ToeplitzConvolution,
};

use crate::GapTransform;

/// `g = P[D v]` of profile samples `v` on the grid (Eq. 7 / 23, discretized as `transform`): the
/// one profile transform of the wear run (its rate, its Jacobian and its sliding columns).
/// `slope` (at least `v.len()` values) is scratch.
pub(crate) fn samples_to_gap(
    tf: &mut ProfileTransform,
    transform: GapTransform,
    grid: &SquaredGrid,
    v: &[f64],
    slope: &mut [f64],
    g: &mut [f64],
) -> Result<(), MdrError> {
    let n = grid.len();
    match transform {
        GapTransform::CentralDifferences => {
            derivative_uniform(&v[..n], grid.step(), &mut slope[..n])?;
            tf.slope_to_equivalent(grid, &mut slope[..n], g)?;
        }
        GapTransform::PiecewiseLinear => tf.values_to_equivalent(grid, &v[..n], g)?,
    }
    Ok(())
}

/// `W = I − β J` (`β = γ Δτ`) at a frozen contact state, as a [`LinearOperator`] on all `N` nodes.
pub(crate) struct RosenbrockMatrix {
    grid: SquaredGrid,
    profile_tf: ProfileTransform,
    /// The discretization of Eq. 7 / 23 ([`samples_to_gap`]).
    gap_transform: GapTransform,
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
    /// The sliding node's constraint row `(s, 1/G_ss)`: row `s` of the operator is
    /// `(G x)_s/G_ss` instead of `(x − βJx)_s` ([`RosenbrockMatrix::apply_constraint_row`]).
    pub(crate) constraint: Option<(usize, f64)>,
    /// The dimension the operator presents ([`RosenbrockMatrix::set_dim`]): `N`, or the
    /// leading block of [`RosenbrockMatrix::support`] nodes.
    dim: usize,
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
        gap_transform: GapTransform,
    ) -> Result<Self, MdrError> {
        let n = grid.len();
        // The Jacobian runs on the contact nodes only (about half the grid and less): shorter
        // FFT plans for them.
        let mut profile_tf = ProfileTransform::new(n, material, backend)?;
        profile_tf.plan_shorter_lengths();
        let mut stress_tf = CellStressTransform::new(n, material, backend)?;
        stress_tf.plan_shorter_lengths();
        Ok(Self {
            profile_tf,
            gap_transform,
            stress_tf,
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
            constraint: None,
            dim: n,
            slope: vec![0.0; n],
            g: vec![0.0; n],
            q: vec![0.0; n],
            sigma: vec![0.0; n],
        })
    }

    /// Freezes the linearization point: the slip, the clipped pressure, the unclipped stress
    /// `σ` (for `1[σ > 0]`) and `g` (for `1[g < 1]`) on the grid, the contact nodes `0..m` and
    /// the edge `θ`; `∂σ/∂θ` by a central difference in `θ` (the difference of the stress at two
    /// edges without a convolution, `CellStressTransform::line_load_edge_difference`).
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
        // The cells' sums do not depend on θ: no convolution for the difference.
        self.stress_tf.line_load_edge_difference(
            &self.grid,
            &self.q[..m],
            (hi, lo),
            &mut self.stress_theta[..m],
        )?;
        for d in self.stress_theta[..m].iter_mut() {
            *d /= hi - lo;
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

    /// The precision of the product's FFT transforms (profile and stress; `Double` by default):
    /// `Single` evaluates `W x` with `f32` transforms, for GMRES on the stages
    /// (docs/performance.md, "The N = 8001 wear run: single-precision stage products (issue 20)").
    pub(crate) fn set_precision(&mut self, precision: Precision) -> Result<(), MdrError> {
        self.profile_tf.set_precision(precision)?;
        self.stress_tf.set_precision(precision);
        Ok(())
    }

    /// Whether a contact node of the frozen state is closed (`g ≥ 1`: no load from its profile).
    pub(crate) fn has_closed_nodes(&self) -> bool {
        self.open_gap[..self.contact_nodes].iter().any(|&o| !o)
    }

    /// The contact nodes `m` of the frozen state.
    pub(crate) fn contact_nodes(&self) -> usize {
        self.contact_nodes
    }

    /// The leading nodes `0..s` outside which `W = I − βJ` is the identity and `J v` reads no
    /// entry of `v`: `s = m + 3` (the nodes [`RosenbrockMatrix::equivalent_near_contact`]
    /// reads; `J v` vanishes from `m` on), at least the grid's smallest and at most `N`.
    pub(crate) fn support(&self) -> usize {
        (self.contact_nodes + 3)
            .max(SquaredGrid::MIN_NODES)
            .min(self.grid.len())
    }

    /// Presents `W` as an operator on the first `dim` nodes (`support() ≤ dim ≤ N`): on vectors
    /// that vanish beyond them it is the whole `W`'s leading block, bit for bit (GMRES on the
    /// stage's support, docs/fretting-wear.md, "Cost per step").
    pub(crate) fn set_dim(&mut self, dim: usize) {
        debug_assert!(dim >= self.support() && dim <= self.grid.len());
        self.dim = dim;
    }

    /// `J v` at the frozen state (see the module docs).
    pub(crate) fn jacobian(&mut self, v: &[f64], out: &mut [f64]) -> Result<(), MdrError> {
        self.pressure_response(v, out)?;
        // The contact nodes that `out` holds (all of them: its length is the operator's
        // dimension, at least `m + 3`).
        let m = self.contact_nodes.min(out.len());
        let slip_slope = self.slip_slope;
        for (((o, &slip), &p), &vi) in out[..m]
            .iter_mut()
            .zip(&self.slip[..m])
            .zip(&self.pressure[..m])
            .zip(&v[..m])
        {
            // A select, not a branch (the same value per node; the loop vectorizes).
            let sum = *o + slip_slope * p * vi;
            *o = if slip > 0.0 { sum } else { *o };
        }
        Ok(())
    }

    /// The pressure part of `J v`, `Δu ⊙ δp` with `δp = 1[σ > 0] ⊙ (S_θ[−c̃_N 1[g < 1] ⊙ P[D v]]
    /// + ∂_θσ δθ)`.
    fn pressure_response(&mut self, v: &[f64], out: &mut [f64]) -> Result<(), MdrError> {
        let m = self.contact_nodes;
        self.masked_stress(v)?;
        // δθ = −(δg_L + θ (δg_E − δg_L)) / (g_E − g_L), unless θ sits at its clamp.
        let d_theta = if self.theta < 1.0 && self.gap_edge > self.gap_last {
            -(self.g[m - 1] + self.theta * (self.g[m] - self.g[m - 1]))
                / (self.gap_edge - self.gap_last)
        } else {
            0.0
        };
        let (contact, outside) = out.split_at_mut(m.min(out.len()));
        for ((((o, &slip), &loaded), &sigma), &stress_theta) in contact
            .iter_mut()
            .zip(&self.slip[..m])
            .zip(&self.loaded[..m])
            .zip(&self.sigma[..m])
            .zip(&self.stress_theta[..m])
        {
            let response = slip * (sigma + stress_theta * d_theta);
            *o = if (slip > 0.0) & loaded { response } else { 0.0 };
        }
        outside.fill(0.0);
        Ok(())
    }

    /// `S_θ[−c̃_N 1[g < 1] ⊙ P[D v]]` on the contact nodes `0..m` of the frozen state into
    /// `self.sigma[..m]` (`δg = P[D v]` into `self.g`): the masked stress response, the stiff part
    /// of `J` before its row scaling `Δu ⊙ 1[σ > 0]` (see the module docs).
    fn masked_stress(&mut self, v: &[f64]) -> Result<(), MdrError> {
        let m = self.contact_nodes;
        self.equivalent_near_contact(m, v)?;
        let modulus = self.modulus;
        for ((q, &open), &g) in self.q[..m]
            .iter_mut()
            .zip(&self.open_gap[..m])
            .zip(&self.g[..m])
        {
            *q = if open { -modulus * g } else { 0.0 };
        }
        self.stress_tf.line_load_to_stress(
            &self.grid,
            &self.q[..m],
            self.theta,
            &mut self.sigma[..m],
        )?;
        Ok(())
    }

    /// The band `|i − j| ≤ w` of the masked stress response `S_θ[−c̃_N 1[g < 1] ⊙ P[D ·]]` at the
    /// frozen state (its contact nodes, edge `θ` and closed nodes), in closed form
    /// ([`MaskedBand::assemble`]) into `bands.band`. Measured as the preconditioner's band alone
    /// (docs/performance.md, "The N = 8001 wear run: the exact masked band"): not kept, the
    /// stages take the probed band less the closed part ([`RosenbrockMatrix::closed_band`]).
    #[cfg(test)]
    pub(crate) fn masked_band(&self, bands: &mut MaskedBand) -> Result<(), NumericsError> {
        bands.assemble(
            self.contact_nodes,
            self.theta,
            &self.open_gap,
            self.modulus,
            false,
        )
    }

    /// The band of the closed nodes' part `S_θ[−c̃_N 1[g ≥ 1] ⊙ P[D ·]]` at the frozen state
    /// ([`MaskedBand::assemble`] with `closed`) into `bands.band`: the masked response is the
    /// all-open one less this part.
    pub(crate) fn closed_band(&self, bands: &mut MaskedBand) -> Result<(), NumericsError> {
        bands.assemble(
            self.contact_nodes,
            self.theta,
            &self.open_gap,
            self.modulus,
            true,
        )
    }

    /// `δg = P[D v]` on the nodes `0..=m` (`m` contact nodes and the next), from `v` on the first
    /// `m + 3` nodes only: the central difference `D` reaches one node out, the causal sum of `P`
    /// (Eq. 7 / 23) none (its kernel `b_0 = 0`), and `P`'s own difference one more, so these
    /// nodes are those of the whole grid's `P[D v]` (to the FFT's rounding: the transform runs
    /// on `m + 3` nodes, with a shorter plan). `self.g[..m + 3]` holds it.
    fn equivalent_near_contact(&mut self, m: usize, v: &[f64]) -> Result<(), MdrError> {
        let h = self.grid.step();
        let len = (m + 3).max(SquaredGrid::MIN_NODES).min(self.grid.len());
        let prefix = SquaredGrid::with_step(len, h)?;
        samples_to_gap(
            &mut self.profile_tf,
            self.gap_transform,
            &prefix,
            &v[..len],
            &mut self.slope[..len],
            &mut self.g[..len],
        )?;
        Ok(())
    }

    /// `K v = S₁[−c̃_N P[D v]]` on the contact nodes `0..m` (0 beyond): the stress response to a
    /// profile change with the edge at the node `m − 1` (`θ = 1`) and every contact node open
    /// (`g < 1`), a function of `m` and the grid alone. `J` without the moving-edge term is
    /// `diag(Δu ⊙ 1[σ > 0]) K + diag((4/χ) p)` up to `θ` and the closed nodes.
    pub(crate) fn edge_node_response(
        &mut self,
        m: usize,
        v: &[f64],
        out: &mut [f64],
    ) -> Result<(), MdrError> {
        self.equivalent_near_contact(m, v)?;
        for (q, g) in self.q[..m].iter_mut().zip(&self.g) {
            *q = -self.modulus * g;
        }
        self.stress_tf
            .line_load_to_stress(&self.grid, &self.q[..m], 1.0, &mut out[..m])?;
        out[m..].fill(0.0);
        Ok(())
    }

    /// The band `|i − j| ≤ w` of `K` ([`RosenbrockMatrix::edge_node_response`]) for `m` contact
    /// nodes, by probing (Curtis, Powell & Reid 1974): with `C > 2w` colours (`colours`), `K e_c`
    /// for `e_c = Σ_{j ≡ c mod C} e_j` gives `K_ij` for `|i − j| ≤ w` up to the entries of the
    /// same colour, `C` and more columns from `j` (`|i − j'| ≥ C − w`; `f ↦ p` is of order
    /// `1 − k`: its kernel decays like `|i − j|^{k − 2}`). Row `i` holds `K_{i, i−w..=i+w}` at
    /// `band[i (2w+1) ..]` (columns outside the grid 0). `C` profile and stress transforms.
    pub(crate) fn probe_band(
        &mut self,
        m: usize,
        width: usize,
        colours: usize,
        probe: &mut [f64],
        response: &mut [f64],
        band: &mut [f64],
    ) -> Result<(), MdrError> {
        debug_assert!(colours > 2 * width);
        let n = self.grid.len();
        let row_len = 2 * width + 1;
        band.fill(0.0);
        for c in 0..colours {
            probe.fill(0.0);
            for p in probe.iter_mut().skip(c).step_by(colours) {
                *p = 1.0;
            }
            self.edge_node_response(m, probe, response)?;
            for (i, r) in response.iter().enumerate().take(m) {
                // The column j ≡ c of the row's band (at most one: colours > 2w).
                let lo = i.saturating_sub(width);
                let j = lo + (c + colours - lo % colours) % colours;
                if j < n && j <= i + width {
                    band[i * row_len + (j + width - i)] = *r;
                }
            }
        }
        Ok(())
    }

    /// The rows of `J_w = diag(Δu ⊙ 1[σ > 0]) K_w + diag((4/χ) p)` at the frozen state from the
    /// band `K_w` of [`RosenbrockMatrix::probe_band`] (probed for this state's contact nodes).
    pub(crate) fn scale_band(&self, width: usize, stress_band: &[f64], band: &mut [f64]) {
        let colours = 2 * width + 1;
        band.fill(0.0);
        for i in 0..self.contact_nodes {
            if self.slip[i] > 0.0 {
                let row = &mut band[i * colours..(i + 1) * colours];
                if self.loaded[i] {
                    for (b, k) in row.iter_mut().zip(&stress_band[i * colours..]) {
                        *b = self.slip[i] * k;
                    }
                }
                row[width] += self.slip_slope * self.pressure[i];
            }
        }
    }
}

/// `M = I − β J_w`, the preconditioner of `W = I − β J`: `J_w` the band `|i − j| ≤ w` of `J` without
/// the moving-edge term ([`RosenbrockMatrix::probe_band`]), factored by banded Gaussian
/// elimination without pivoting (`O(N w²)`; `M` is an M-matrix-like perturbation of `I`: the
/// stiff part `−J` has a positive diagonal). Applied as `M⁻¹` on the right of GMRES, so GMRES's
/// residual test is the one of `W k = b` (docs/fretting-wear.md, "Time integration").
pub(crate) struct BandPreconditioner {
    n: usize,
    width: usize,
    /// `J_w`, row-major, `2w + 1` entries a row (column `j = i − w + l`).
    pub(crate) band: Vec<f64>,
    /// `K_w` in the same layout and the contact nodes it was probed for (0: none yet). A function
    /// of the contact nodes alone, so it is probed again only when they change, and a resumed run
    /// rebuilds the same one.
    pub(crate) stress_band: Vec<f64>,
    pub(crate) probed_for: usize,
    /// The LU factors of `M` in the same layout: the unit lower part's multipliers `l_ij` below
    /// the diagonal, the upper part stored scaled by its pivot, `U'_ij = U_ij/U_ii` (`j > i`), on
    /// the rows `0..active` ([`BandPreconditioner::factor`]).
    lu: Vec<f64>,
    /// Whether `lu` holds a usable factorization (false: `M⁻¹ = I`).
    factored: bool,
    /// `π_i = 1/U_ii` (the back substitution starts each row at `x_i π_i`).
    inverse_pivot: Vec<f64>,
    /// Rows `0..active` of `J_w` may be nonzero (the contact nodes); `M` is the identity on the
    /// rows beyond, where factoring and substituting leave every value as it is, so both stop there.
    pub(crate) active: usize,
    pub(crate) probe: Vec<f64>,
    pub(crate) response: Vec<f64>,
    /// The sliding node's row of `M` (`2w + 1` entries) and its node, if any
    /// ([`BandPreconditioner::set_constraint_row`]).
    constraint_row: Vec<f64>,
    constraint_node: Option<usize>,
    /// The dimension the operator presents (as [`RosenbrockMatrix::set_dim`]; `active + w` and
    /// more: the rows `0..active` reach `w` columns beyond).
    pub(crate) dim: usize,
}

impl BandPreconditioner {
    pub(crate) fn new(n: usize, width: usize) -> Self {
        let colours = 2 * width + 1;
        Self {
            n,
            width,
            band: vec![0.0; n * colours],
            stress_band: vec![0.0; n * colours],
            probed_for: 0,
            lu: vec![0.0; n * colours],
            factored: false,
            inverse_pivot: vec![1.0; n],
            active: n,
            probe: vec![0.0; n],
            response: vec![0.0; n],
            constraint_row: vec![0.0; colours],
            constraint_node: None,
            dim: n,
        }
    }

    /// The half bandwidth `w`.
    pub(crate) fn width(&self) -> usize {
        self.width
    }

    /// Whether the last [`BandPreconditioner::factor`] kept every pivot (else `M⁻¹ = I`).
    pub(crate) fn is_factored(&self) -> bool {
        self.factored
    }

    /// Factors `M = I − β J_w`. A pivot that is not positive and finite (`M` far from `I`) leaves
    /// the preconditioner off (`M⁻¹ = I`) for this `β`.
    ///
    /// Banded Gaussian elimination without pivoting: for each pivot row `k`, `π_k = 1/M_kk`,
    /// `l_ik = M_ik π_k` and `M_ij ← fma(−l_ik, M_kj, M_ij)`; then row `k`'s upper part is stored
    /// scaled, `U'_kj = U_kj π_k` (`j > k`), so that the back substitution is
    /// `y_k = x_k π_k − Σ_j U'_kj y_j` with one fused multiply-add per term
    /// ([`BandPreconditioner::substitute`]; docs/performance.md, "The band substitutions on fused
    /// multiply-adds (issue 20)").
    pub(crate) fn factor(&mut self, beta: f64) {
        let (n, w) = (self.n, self.width);
        let colours = 2 * w + 1;
        let active = self.active.min(n);
        // Rows from `active` on are never read (the elimination and the substitutions stop
        // there): only the active rows are formed.
        let rows = active * colours;
        for (l, b) in self.lu[..rows].iter_mut().zip(&self.band[..rows]) {
            *l = -beta * b;
        }
        for i in 0..active {
            self.lu[i * colours + w] += 1.0;
        }
        self.put_constraint_row();
        self.factored = pulp::Arch::new().dispatch(Elimination {
            lu: &mut self.lu,
            inverse_pivot: &mut self.inverse_pivot,
            n,
            width: w,
            active,
        });
    }
}

/// [`BandPreconditioner::factor`]'s elimination, compiled for the CPU's level (pulp's runtime
/// dispatch) so that `f64::mul_add` is one instruction where the CPU has it (the same bits
/// everywhere: a fused multiply-add is exactly rounded on every level). Returns whether every
/// pivot was kept.
struct Elimination<'a> {
    lu: &'a mut [f64],
    inverse_pivot: &'a mut [f64],
    n: usize,
    width: usize,
    active: usize,
}

impl pulp::WithSimd for Elimination<'_> {
    type Output = bool;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> bool {
        let Self {
            lu,
            inverse_pivot,
            n,
            width: w,
            active,
        } = self;
        let colours = 2 * w + 1;
        for k in 0..active {
            let pivot = lu[k * colours + w];
            if !(pivot.is_finite() && pivot > 1e-8) {
                return false;
            }
            let inverse = 1.0 / pivot;
            inverse_pivot[k] = inverse;
            let last = (k + w).min(n - 1);
            // Rows from `active` on have no entries left of the diagonal: nothing to eliminate.
            for i in k + 1..=last.min(active - 1) {
                // Row i, column k sits at l = k + w − i.
                let lik = lu[i * colours + (k + w - i)] * inverse;
                lu[i * colours + (k + w - i)] = lik;
                if lik != 0.0 {
                    for j in k + 1..=last {
                        let ij = i * colours + (j + w - i);
                        lu[ij] = (-lik).mul_add(lu[k * colours + (j + w - k)], lu[ij]);
                    }
                }
            }
            // Row k is not read again by the elimination: store its upper part as U/U_kk.
            for u in &mut lu[k * colours + w + 1..(k + 1) * colours] {
                *u *= inverse;
            }
        }
        true
    }
}

impl BandPreconditioner {
    /// The sliding node's row of `M`: the band of `G = P D`'s row `s` (`gap_row`, `2w + 1`
    /// entries, columns `s − w ..= s + w`) times `scale = 1/G_ss`, as in the stages' operator
    /// ([`RosenbrockMatrix::apply_constraint_row`]; docs/fretting-wear.md, "The sliding mode in
    /// the stages"). Taken by the next [`BandPreconditioner::factor`].
    pub(crate) fn set_constraint_row(&mut self, s: usize, gap_row: &[f64], scale: f64) {
        for (r, g) in self.constraint_row.iter_mut().zip(gap_row) {
            *r = g * scale;
        }
        self.constraint_node = Some(s);
    }

    /// No constraint row ([`BandPreconditioner::set_constraint_row`]).
    pub(crate) fn clear_constraint_row(&mut self) {
        self.constraint_node = None;
    }

    /// Writes the constraint row into the factors before the elimination.
    fn put_constraint_row(&mut self) {
        let colours = 2 * self.width + 1;
        if let Some(s) = self.constraint_node {
            self.lu[s * colours..(s + 1) * colours].copy_from_slice(&self.constraint_row);
        }
    }

    /// The forward and back substitutions of [`LinearOperator::apply`] on the rows `0..active`:
    /// `y_i ← fma(−l_ij, y_j, y_i)` over `j = i − w … i − 1`, then `y_i ← x_i π_i` and
    /// `y_i ← fma(−U'_ij, y_j, y_i)` over `j = i + w … i + 1` (farthest first: the row just solved
    /// enters last, one fused multiply-add on the recurrence's chain; [`BandPreconditioner::factor`]
    /// stores `U'_ij = U_ij/U_ii` and `π_i = 1/U_ii`).
    fn substitute(&self, y: &mut [f64], active: usize) {
        pulp::Arch::new().dispatch(Substitution {
            lu: &self.lu,
            inverse_pivot: &self.inverse_pivot,
            width: self.width,
            y,
            active,
            unrolled: false,
        });
    }

    /// The substitutions of [`LinearOperator::apply`] for the half bandwidth 5
    /// ([`crate::simulation::PRECONDITIONER_WIDTH`]): the interior rows unrolled, the rows at the
    /// ends as in the general loop; the same operations in the same order (the same bits as the
    /// general loop, [`BandPreconditioner::substitute`]). The five values a row reads from the
    /// rows just solved are carried in scalar locals (registers), not loaded back from `y`: a
    /// (vector) load of the value stored on the previous row cannot be forwarded from that store
    /// and waits for it on every row (docs/fretting-wear.md, "Cost per step"; an array window with
    /// `copy_within` was tried and is kept on the stack by the compiler, the same stall: the
    /// substitution's share of a perf profile of the N = 8001 run 21.6 % against 8.5 % with the
    /// locals).
    fn substitute_width_5(&self, y: &mut [f64], active: usize) {
        debug_assert_eq!(self.width, 5);
        pulp::Arch::new().dispatch(Substitution {
            lu: &self.lu,
            inverse_pivot: &self.inverse_pivot,
            width: self.width,
            y,
            active,
            unrolled: true,
        });
    }
}

/// The substitutions of [`BandPreconditioner::substitute`] (`unrolled`: those of
/// [`BandPreconditioner::substitute_width_5`]), compiled for the CPU's level (pulp's runtime
/// dispatch) so that `f64::mul_add` is one instruction where the CPU has it; a fused multiply-add
/// is exactly rounded on every level, so the bits are the same everywhere.
struct Substitution<'a> {
    lu: &'a [f64],
    inverse_pivot: &'a [f64],
    width: usize,
    y: &'a mut [f64],
    active: usize,
    unrolled: bool,
}

impl pulp::WithSimd for Substitution<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        if self.unrolled {
            substitute_width_5(self.lu, self.inverse_pivot, self.y, self.active);
        } else {
            substitute_general(self.lu, self.inverse_pivot, self.width, self.y, self.active);
        }
    }
}

/// [`BandPreconditioner::substitute`]'s loops (see there).
#[inline(always)]
fn substitute_general(lu: &[f64], inverse_pivot: &[f64], w: usize, y: &mut [f64], active: usize) {
    let n = y.len();
    let colours = 2 * w + 1;
    for i in 0..active {
        let lo = i.saturating_sub(w);
        let lower = &lu[i * colours + lo + w - i..i * colours + w];
        let mut s = y[i];
        for (l, yj) in lower.iter().zip(&y[lo..i]) {
            s = (-l).mul_add(*yj, s);
        }
        y[i] = s;
    }
    for i in (0..active).rev() {
        let hi = (i + w + 1).min(n);
        let row = &lu[i * colours..(i + 1) * colours];
        let mut s = y[i] * inverse_pivot[i];
        for (u, yj) in row[w + 1..w + hi - i].iter().zip(&y[i + 1..hi]).rev() {
            s = (-u).mul_add(*yj, s);
        }
        y[i] = s;
    }
}

/// [`BandPreconditioner::substitute_width_5`]'s loops (see there).
#[inline(always)]
fn substitute_width_5(lu: &[f64], inverse_pivot: &[f64], y: &mut [f64], active: usize) {
    const W: usize = 5;
    let n = y.len();
    let colours = 2 * W + 1;
    let (mut y5, mut y4, mut y3, mut y2, mut y1) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for i in 0..active {
        let row = &lu[i * colours..(i + 1) * colours];
        let mut s = y[i];
        if i >= W {
            s = (-row[0]).mul_add(y5, s);
            s = (-row[1]).mul_add(y4, s);
            s = (-row[2]).mul_add(y3, s);
            s = (-row[3]).mul_add(y2, s);
            s = (-row[4]).mul_add(y1, s);
        } else {
            for j in 0..i {
                s = (-row[j + W - i]).mul_add(y[j], s);
            }
        }
        y[i] = s;
        (y5, y4, y3, y2, y1) = (y4, y3, y2, y1, s);
    }
    let at = |j: usize| y.get(j).copied().unwrap_or(0.0);
    let (mut z1, mut z2, mut z3, mut z4, mut z5) = (
        at(active),
        at(active + 1),
        at(active + 2),
        at(active + 3),
        at(active + 4),
    );
    for i in (0..active).rev() {
        let row = &lu[i * colours..(i + 1) * colours];
        let mut s = y[i] * inverse_pivot[i];
        if i + W < n {
            s = (-row[W + 5]).mul_add(z5, s);
            s = (-row[W + 4]).mul_add(z4, s);
            s = (-row[W + 3]).mul_add(z3, s);
            s = (-row[W + 2]).mul_add(z2, s);
            s = (-row[W + 1]).mul_add(z1, s);
        } else {
            for j in (i + 1..n).rev() {
                s = (-row[j + W - i]).mul_add(y[j], s);
            }
        }
        y[i] = s;
        (z5, z4, z3, z2, z1) = (z4, z3, z2, z1, s);
    }
}

/// The band `|i − j| ≤ w` of the masked stress response `A = S_θ[−c̃_N 1[g < 1] ⊙ P[D ·]]` on the
/// contact nodes `0..m` (rows `i < m`), exactly (to the rounding of its closed form), from the
/// matrices of the two transforms (docs/performance.md, "The N = 8001 wear run: the exact masked
/// band (issue 20)"):
///
/// - `S_θ` (the cell stress transform, `CellStressTransform`): `S_ik = c_σ s_{k−i}` for
///   `i ≤ k < m − 1`, `s_0 = w_0`, `s_δ = w_δ − w_{δ−1}`, `w_δ = (δ+1)^γ − δ^γ`, and the edge column
///   `S_{i,m−1} = c_σ [((m−1−i+θ)^γ − (m−1−i)^γ)/θ − w_{m−2−i}]` (`w_{−1} = 0`),
///   `c_σ = h^{γ−1}/(πγ)`;
/// - `G = P D` (the central difference and the profile transform with its parabolic split,
///   `ProfileTransform::slope_to_equivalent`, Eq. 7 / 23): `G_kj = ρ_k τ_{k−j} + C_kj`,
///   `ρ_k = k^{(1−k_g)/2}/(2(1+k_g))`, `τ_δ = β_{δ+1} − β_{δ−1}`, `β_δ = b_{δ+1} − b_{δ−1}`
///   (`β_0 = 1`, `β_δ = 0` for `δ < 0`), `b_δ = δ^γ`, with the columns `0..=2` corrected by the split
///   `c₀ = (D v)_0`: `C_k0 = −ρ_k β_{k+1} − 3e_k`, `C_k1 = −ρ_k β_k + 4e_k`, `C_k2 = −e_k`,
///   `e_k = k/(1+k_g) − ρ_k (b_k + b_{k−1})`; with the piecewise-linear transform
///   (`GapTransform::PiecewiseLinear`, `ProfileTransform::values_to_equivalent`)
///   `G_kj = ρ̃_k τ̃_{k−j}`, `ρ̃_k = 2k^{(1−k_g)/2}/(1+k_g)`, `τ̃_δ = e_{δ+1} − e_δ` for `δ ≥ 0`
///   and 0 for `δ < 0` (`e_m = b_m − b_{m−1}`, `e_0 = 0`), column 0 `−ρ̃_k e_k` (`C_k0 =
///   −ρ̃_k e_{k+1}`, no other correction);
///
/// `A_{i,i+l} = −c̃_N Σ_{k=i}^{m−1} S_ik o_k G_{k,i+l}` (`o_k = 1[g_k < 1]`): for `k < m − 1` the
/// Toeplitz part is the correlation `c_σ Σ_δ s_δ τ_{δ−l} x_{i+δ}` of `x_k = o_k ρ_k` with one kernel
/// per diagonal `l` (`2w + 1` FFT convolutions), the columns `0..=2` add `C` directly (`O(w m)`),
/// and the edge column `k = m − 1` (the only part that depends on `θ`) adds `S_{i,m−1} o_{m−1}
/// G_{m−1,j}` (`O(w m)`). The convolutions depend on `m` and the mask alone and are kept until
/// either changes (a function of them: a resumed run rebuilds the same band). The closed nodes'
/// part (`1 − o_k` in place of `o_k`, what the stages' preconditioner takes) is summed directly,
/// column by column, on the `reach` rows above each closed node ([`CLOSED_REACH`]).
pub(crate) struct MaskedBand {
    /// The discretization of Eq. 7 / 23 whose `G` the band holds.
    transform: GapTransform,
    /// The piecewise-linear `G`'s column-0 correction `C_k0 = −ρ̃_k e_{k+1}`.
    first_column: Vec<f64>,
    width: usize,
    n: usize,
    gamma: f64,
    /// `c_σ = h^{γ−1}/(πγ)`.
    stress_scale: f64,
    /// `w_δ`, `δ = 0..n`.
    weights: Vec<f64>,
    /// `s_δ`, `δ = 0..n`.
    stress_kernel: Vec<f64>,
    /// `β_δ`, `δ = 0..n + w + 3`.
    beta: Vec<f64>,
    /// `τ_δ` at `δ + 1`, `δ = −1..n + w + 1`.
    tau: Vec<f64>,
    /// `ρ_k` and `e_k`, `k = 0..n`.
    rho: Vec<f64>,
    split: Vec<f64>,
    /// The correlation kernels `s_δ τ_{δ−l}`, `l = −w..=w` (causal convolutions of the reversed
    /// `x`), planned at the first band of the open nodes (the exact masked band).
    convolutions: Vec<ToeplitzConvolution>,
    /// The same kernels interleaved, `s_δ τ_{δ−l}` at `δ (2w + 1) + l + w` (the direct sum).
    kernels: Vec<f64>,
    /// The nodes summed (`k < m − 1`).
    taken: Vec<usize>,
    x: Vec<f64>,
    out: Vec<f64>,
    /// `c_σ Σ_{k<m−1} s_{k−i} o_k G_{k,i+l}` (no `−c̃_N`), `2w + 1` entries a row, and the `m` and
    /// mask it holds (`nodes = 0`: none).
    core: Vec<f64>,
    nodes: usize,
    closed: bool,
    open: Vec<bool>,
    /// The band of `A`, rows `0..m` (`2w + 1` entries a row, columns outside the grid 0), the
    /// layout of [`BandPreconditioner::stress_band`]; rows from `rows` on are 0 (beyond `m`
    /// not written).
    pub(crate) band: Vec<f64>,
    rows: std::ops::Range<usize>,
    /// How far above a closed node its column is summed (`k − reach ≤ i ≤ k`; `usize::MAX`:
    /// every row, the exact band).
    reach: usize,
    /// Convolution builds so far (a diagnostic).
    pub(crate) builds: u64,
}

/// The rows above a closed node on which the preconditioner sums its column's part
/// ([`MaskedBand::assemble`]): the kernel `s_δ τ_{δ−l}` falls like `δ^{2γ−4}` (`δ^{−3}` at
/// `k_g = 0`), so the rows beyond it get ≈ `64^{−3}` of a diagonal entry from each node
/// (docs/performance.md, "The N = 8001 wear run: the exact masked band").
pub(crate) const CLOSED_REACH: usize = 64;

impl MaskedBand {
    /// The closed forms for the grid of `n` nodes and step `h`, grading exponent `k_g`
    /// (`γ = (1 + k_g)/2`), half bandwidth `w`; a closed node's column is summed on the `reach`
    /// rows above it (`usize::MAX`: all, the exact band; [`CLOSED_REACH`]).
    pub(crate) fn new(
        grid: &SquaredGrid,
        grading: f64,
        width: usize,
        reach: usize,
        transform: GapTransform,
    ) -> Self {
        let (n, h, w) = (grid.len(), grid.step(), width);
        let gamma = 0.5 * (1.0 + grading);
        let alpha = 0.5 * (1.0 - grading);
        let long = n + w + 4;
        let b = node_powers(long + 1, gamma);
        let weights = cell_weights(&b[..=n]);
        let stress_kernel: Vec<f64> = (0..n)
            .map(|d| {
                if d == 0 {
                    weights[0]
                } else {
                    weights[d] - weights[d - 1]
                }
            })
            .collect();
        let beta: Vec<f64> = (0..long - 1)
            .map(|d| if d == 0 { b[1] } else { b[d + 1] - b[d - 1] })
            .collect();
        let beta_at = |d: isize| if d < 0 { 0.0 } else { beta[d as usize] };
        // The piecewise-linear transform: `G_kj = ρ̃_k τ̃_{k−j}`, `τ̃_δ = e_{δ+1} − e_δ` (`δ ≥ 0`,
        // `e_m = b_m − b_{m−1}`, `e_0 = 0`), `ρ̃_k = 2k^α/(1+k_g)`, column 0 `−ρ̃_k e_k`.
        let increment = |m: isize| {
            if m <= 0 {
                0.0
            } else {
                b[m as usize] - b[m as usize - 1]
            }
        };
        let tau: Vec<f64> = (-1..(n + w + 1) as isize)
            .map(|d| match transform {
                GapTransform::CentralDifferences => beta_at(d + 1) - beta_at(d - 1),
                GapTransform::PiecewiseLinear if d < 0 => 0.0,
                GapTransform::PiecewiseLinear => increment(d + 1) - increment(d),
            })
            .collect();
        let rho_scale = match transform {
            GapTransform::CentralDifferences => 1.0 / (2.0 * (1.0 + grading)),
            GapTransform::PiecewiseLinear => 2.0 / (1.0 + grading),
        };
        let rho: Vec<f64> = (0..n)
            .map(|k| pow_or_sqrt(k as f64, alpha) * rho_scale)
            .collect();
        let first_column: Vec<f64> = (0..n)
            .map(|k| -rho[k] * increment(k as isize + 1))
            .collect();
        let split = (0..n)
            .map(|k| {
                let below = if k > 0 { b[k - 1] } else { 0.0 };
                k as f64 / (1.0 + grading) - rho[k] * (b[k] + below)
            })
            .collect();
        let tau_at = |d: isize| if d < -1 { 0.0 } else { tau[(d + 1) as usize] };
        let row = 2 * w + 1;
        let mut kernels = vec![0.0; n * row];
        for (d, kernel) in kernels.chunks_exact_mut(row).enumerate() {
            for (c, u) in kernel.iter_mut().enumerate() {
                *u = stress_kernel[d] * tau_at(d as isize + w as isize - c as isize);
            }
        }
        Self {
            transform,
            first_column,
            width: w,
            n,
            gamma,
            stress_scale: stress_scale(h, gamma),
            weights,
            stress_kernel,
            beta,
            tau,
            rho,
            split,
            convolutions: Vec::new(),
            kernels,
            taken: Vec::with_capacity(n),
            x: vec![0.0; n],
            out: vec![0.0; n],
            core: vec![0.0; n * row],
            nodes: 0,
            closed: false,
            open: vec![false; n],
            band: vec![0.0; n * row],
            rows: 0..0,
            reach,
            builds: 0,
        }
    }

    /// `τ_δ` (0 for `δ < −1`).
    fn tau(&self, d: isize) -> f64 {
        if d < -1 {
            0.0
        } else {
            self.tau[(d + 1) as usize]
        }
    }

    /// `G_kj = ρ_k τ_{k−j} + C_kj` (see the type's docs).
    fn gap_entry(&self, k: usize, j: usize) -> f64 {
        let toeplitz = self.rho[k] * self.tau(k as isize - j as isize);
        if self.transform == GapTransform::PiecewiseLinear {
            return toeplitz + if j == 0 { self.first_column[k] } else { 0.0 };
        }
        let beta = |d: usize| self.beta[d];
        toeplitz
            + match j {
                0 => -self.rho[k] * beta(k + 1) - 3.0 * self.split[k],
                1 => -self.rho[k] * beta(k) + 4.0 * self.split[k],
                2 => -self.split[k],
                _ => 0.0,
            }
    }

    /// The correction `C_kj` of the columns `j ≤ 2` (see the type's docs).
    fn split_entry(&self, k: usize, j: usize) -> f64 {
        self.gap_entry(k, j) - self.rho[k] * self.tau(k as isize - j as isize)
    }

    /// Adds the columns `j ≤ 2`' correction `c_σ Σ_k s_{k−i} C_kj` over the nodes summed
    /// (`taken`, `k < m − 1`) to `core`.
    fn add_split_columns(&mut self, m: usize) {
        let (w, n) = (self.width, self.n);
        let row = 2 * w + 1;
        for j in 0..=2usize.min(n - 1) {
            for i in j.saturating_sub(w)..(j + w + 1).min(m) {
                let mut sum = 0.0;
                for &k in self
                    .taken
                    .iter()
                    .filter(|&&k| k >= i && k - i <= self.reach)
                {
                    sum += self.stress_kernel[k - i] * self.split_entry(k, j);
                }
                self.core[i * row + (j + w - i)] += self.stress_scale * sum;
            }
        }
    }

    /// `S_{i,m−1}` at the edge `θ` (see the type's docs).
    fn edge_stress(&self, i: usize, m: usize, theta: f64) -> f64 {
        let d = m - 1 - i;
        let partial = ((d as f64 + theta).powf(self.gamma) - (d as f64).powf(self.gamma)) / theta;
        let cell = if d >= 1 { self.weights[d - 1] } else { 0.0 };
        self.stress_scale * (partial - cell)
    }

    /// The band of `A` for `m ≥ 2` contact nodes, the edge `θ ∈ (0, 1]` and the mask `open`
    /// (`1[g < 1]`, at least `m` entries) into the rows `0..m` of [`MaskedBand::band`].
    ///
    /// With `closed`, the band of the closed nodes' part instead: `o_k` replaced by `1 − o_k`
    /// (the masked band is the all-open one less this part), each column summed on the `reach`
    /// rows above its node.
    pub(crate) fn assemble(
        &mut self,
        m: usize,
        theta: f64,
        open: &[bool],
        modulus: f64,
        closed: bool,
    ) -> Result<(), NumericsError> {
        let (w, n) = (self.width, self.n);
        let row = 2 * w + 1;
        debug_assert!(m >= 2 && m <= n);
        let len = m - 1;
        // The nodes summed: the open ones, or with `closed` the closed ones.
        let taken = |k: usize| open[k] != closed;
        self.taken.clear();
        self.taken.extend((0..len).filter(|&k| taken(k)));
        let scale = self.stress_scale;
        // The rows `first..` that the nodes summed reach (`S` is anti-causal).
        let reach = self.reach;
        let first = self.taken.first().map_or(len, |&k| k.saturating_sub(reach));
        if closed {
            // The closed nodes' columns summed directly, `c_σ ρ_k s_{k−i} τ_{k−i−l}` from the
            // interleaved kernels on the rows `k − reach ..= k`, in the order of `k` (every row
            // cleared when the edge column, below, reaches them all).
            let cleared = if taken(len) { 0 } else { first };
            self.core[cleared * row..m * row].fill(0.0);
            for &k in &self.taken {
                let c = scale * self.rho[k];
                for i in k.saturating_sub(reach)..=k {
                    let kernel = &self.kernels[(k - i) * row..(k - i + 1) * row];
                    for (b, u) in self.core[i * row..(i + 1) * row].iter_mut().zip(kernel) {
                        *b += c * u;
                    }
                }
            }
            self.add_split_columns(m);
            self.nodes = 0;
        } else if self.nodes != m || self.closed != closed || self.open[..len] != open[..len] {
            if self.convolutions.is_empty() {
                self.convolutions = (0..row)
                    .map(|c| {
                        let kernel = (0..n).map(|d| self.kernels[d * row + c]).collect();
                        let mut conv = ToeplitzConvolution::new(kernel, Backend::Fft)?;
                        conv.plan_shorter_lengths();
                        Ok(conv)
                    })
                    .collect::<Result<_, NumericsError>>()?;
            }
            // From the last node summed on, the rows vanish (`S` is anti-causal).
            let span = self.taken.last().map_or(0, |&k| k + 1);
            for (p, x) in self.x[..span].iter_mut().enumerate() {
                let k = span - 1 - p;
                *x = if taken(k) { self.rho[k] } else { 0.0 };
            }
            self.core[..m * row].fill(0.0);
            if span > 0 {
                for (c, conv) in self.convolutions.iter_mut().enumerate() {
                    conv.apply(&self.x[..span], &mut self.out[..span])?;
                    for i in 0..span {
                        self.core[i * row + c] = scale * self.out[span - 1 - i];
                    }
                }
            }
            self.add_split_columns(m);
            self.nodes = m;
            self.closed = closed;
            self.open[..len].copy_from_slice(&open[..len]);
            self.builds += 1;
        }
        let edge = m - 1;
        let edge_taken = taken(edge);
        // Beyond the last node summed the rows vanish; before `first` they are not summed.
        let (first, rows) = if edge_taken {
            (0, m)
        } else if closed {
            (first.min(len), self.taken.last().map_or(0, |&k| k + 1))
        } else {
            (0, self.taken.last().map_or(0, |&k| k + 1))
        };
        let first = first.min(rows);
        self.rows = first..rows;
        self.band[first * row..rows * row].copy_from_slice(&self.core[first * row..rows * row]);
        for i in first..rows {
            let s = if edge_taken {
                self.edge_stress(i, m, theta)
            } else {
                0.0
            };
            for c in 0..row {
                self.band[i * row + c] = match (i + c).checked_sub(w).filter(|&j| j < n) {
                    Some(j) if edge_taken => {
                        -modulus * (self.band[i * row + c] + s * self.gap_entry(edge, j))
                    }
                    Some(_) => -modulus * self.band[i * row + c],
                    None => 0.0,
                };
            }
        }
        self.band[..first * row].fill(0.0);
        self.band[rows * row..m * row].fill(0.0);
        Ok(())
    }

    /// `base − A` into [`MaskedBand::band`] on the rows `0..m` (`base` a band of the same layout,
    /// `A` the band of the last [`MaskedBand::assemble`]: outside its rows that may be nonzero,
    /// `base`'s rows).
    pub(crate) fn subtract_from(&mut self, base: &[f64], m: usize) {
        let row = 2 * self.width + 1;
        let (first, rows) = (self.rows.start.min(m), self.rows.end.min(m));
        self.band[..first * row].copy_from_slice(&base[..first * row]);
        for (b, k) in self.band[first * row..rows * row]
            .iter_mut()
            .zip(&base[first * row..])
        {
            *b = k - *b;
        }
        self.band[rows * row..m * row].copy_from_slice(&base[rows * row..m * row]);
    }
}

impl LinearOperator for BandPreconditioner {
    fn dim(&self) -> usize {
        self.dim
    }

    /// `y = M⁻¹ x` (forward and back substitution; `y = x` when not factored) on the first
    /// [`LinearOperator::dim`] nodes: the rows `0..active` and the `w` columns they reach lie in
    /// them, the rest is the identity (the same bits as on all `N`).
    fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        halfspace_numerics::linop::check_lengths(self.dim, x, y)?;
        y.copy_from_slice(x);
        if !self.factored {
            return Ok(());
        }
        let (n, w) = (self.dim, self.width);
        // Rows from `active` on are those of the identity (`y_i = x_i`).
        let active = self.active.min(n);
        if w == 5 {
            self.substitute_width_5(y, active);
        } else {
            self.substitute(y, active);
        }
        Ok(())
    }
}

impl LinearOperator for RosenbrockMatrix {
    fn dim(&self) -> usize {
        self.dim
    }

    /// `y = x − β J x` (on the first [`LinearOperator::dim`] nodes).
    fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        halfspace_numerics::linop::check_lengths(self.dim, x, y)?;
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
        self.apply_constraint_row(y);
        Ok(())
    }
}

impl RosenbrockMatrix {
    /// The sliding node's row of the stages (docs/fretting-wear.md, "The sliding mode in the
    /// stages"): `y_s = (G x)_s/G_ss`, the ROS2 form `−γΔτ (∂c/∂f) k = c` of the index-1
    /// constraint `c = g_s − g*` scaled to a unit diagonal. `δg = G x` is the one the product
    /// has just computed ([`RosenbrockMatrix::equivalent_near_contact`], `s` < the contact nodes).
    fn apply_constraint_row(&self, y: &mut [f64]) {
        if let Some((s, inverse)) = self.constraint {
            y[s] = self.g[s] * inverse;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulation::PRECONDITIONER_WIDTH;

    /// The band `|i − j| ≤ w` of the frozen state's masked stress response on its contact rows
    /// (`2w + 1` entries a row), assembled column by column through the transforms (the dense
    /// twin).
    fn dense_band(matrix: &mut RosenbrockMatrix, w: usize) -> Vec<f64> {
        let (n, m) = (matrix.grid.len(), matrix.contact_nodes);
        let row = 2 * w + 1;
        let mut dense = vec![0.0; m * row];
        let mut v = vec![0.0; n];
        for j in 0..n {
            v.fill(0.0);
            v[j] = 1.0;
            matrix.masked_stress(&v).unwrap();
            for i in j.saturating_sub(w)..(j + w + 1).min(m) {
                dense[i * row + (j + w - i)] = matrix.sigma[i];
            }
        }
        dense
    }

    /// The closed-form band of the masked stress response ([`MaskedBand`]) against the band of the
    /// operator itself assembled column by column (`S_θ[−c̃_N 1[g < 1] ⊙ P[D e_j]]` by the
    /// transforms, the dense twin), homogeneous and graded, with closed nodes at the origin's
    /// split columns, inside and next to the edge, for several edges `θ` and contacts `m`; the
    /// kept convolutions are rebuilt when the mask or `m` change and reused otherwise. To
    /// rounding: `1e-12` of the band's largest entry (the FFT sums' rounding at `N = 121`; observed
    /// ≤ 2.6e-13). The closed nodes' part (summed directly) against its own dense twin (the
    /// operator with the mask inverted) to the same bound, and with the masked band (by the
    /// convolutions) it adds up to the all-open band; summed on [`CLOSED_REACH`] rows above each
    /// closed node, the part differs from the exact one by at most the terms left out (their
    /// absolute sum; 8e-4 of the band's largest entry with 68 closed nodes at `N = 121`), and not
    /// at all when no closed node lies that far.
    #[test]
    fn masked_band_is_the_operators_band() {
        let n = 121;
        let w = PRECONDITIONER_WIDTH;
        let row = 2 * w + 1;
        let grid = SquaredGrid::new(n, 2.0).unwrap();
        let cases = [0.0, -0.5, 0.3].into_iter().flat_map(|grading| {
            [
                GapTransform::CentralDifferences,
                GapTransform::PiecewiseLinear,
            ]
            .map(|transform| (grading, transform))
        });
        for (grading, transform) in cases {
            let material = Material::power_law(1.0, 1.0, 0.3, grading).unwrap();
            let modulus = 1.7;
            let mut matrix =
                RosenbrockMatrix::new(grid, &material, Backend::Fft, modulus, 0.5, transform)
                    .unwrap();
            let mut bands = MaskedBand::new(&grid, grading, w, usize::MAX, transform);
            let mut near = MaskedBand::new(&grid, grading, w, CLOSED_REACH, transform);
            let zeros = vec![0.0; n];
            let mut last = None;
            for (m, theta, closed) in [
                (40usize, 1.0, vec![]),
                (40, 0.37, vec![]),
                (40, 0.37, vec![0usize, 2, 17, 18, 19, 37, 38]),
                (40, 0.81, vec![0, 2, 17, 18, 19, 37, 38]),
                (33, 0.05, vec![1, 3, 4, 20, 31]),
                (2, 0.5, vec![]),
                (7, 0.5, vec![0, 1, 2, 3, 4, 5]),
                // The edge node closed (its column reaches every row).
                (40, 0.5, vec![30, 39]),
                // Closed nodes more than CLOSED_REACH rows above the first rows.
                (110, 0.6, (2..40).chain(50..80).collect()),
                // And the edge node closed with them.
                (110, 0.6, vec![75, 76, 109]),
            ] {
                let g: Vec<f64> = (0..n)
                    .map(|i| {
                        if closed.contains(&i) || i >= m {
                            1.5
                        } else {
                            0.5
                        }
                    })
                    .collect();
                matrix.freeze(&zeros, &zeros, &zeros, &g, m, theta).unwrap();
                let before = bands.builds;
                matrix.masked_band(&mut bands).unwrap();
                // The convolutions are kept when only θ changed since they were built (the
                // all-open band of the case before, below).
                let kept = closed.is_empty() && last == Some(m);
                assert_eq!(bands.builds - before, u64::from(!kept));
                last = Some(m);
                let dense = dense_band(&mut matrix, w);
                let largest = dense.iter().fold(0.0f64, |a, b| a.max(b.abs()));
                assert!(largest > 0.0);
                let error = dense
                    .iter()
                    .zip(&bands.band)
                    .fold(0.0f64, |a, (d, b)| a.max((d - b).abs()));
                assert!(
                    error <= 1e-12 * largest,
                    "k = {grading}, {transform:?}, m = {m}, θ = {theta}: {error:e} of {largest:e}"
                );
                // The closed nodes' part: the all-open band less the masked one.
                let masked = bands.band.clone();
                matrix.closed_band(&mut bands).unwrap();
                let closed_part = bands.band.clone();
                matrix.closed_band(&mut near).unwrap();
                let tail = near.band[..m * row]
                    .iter()
                    .zip(&closed_part)
                    .fold(0.0f64, |a, (t, c)| a.max((t - c).abs()));
                // The terms left out: `|c̃_N S_ik G_kj|` summed over the closed `k` more than
                // CLOSED_REACH rows below the row `i` (a bound by the triangle inequality).
                let mut bound = 0.0f64;
                for i in 0..m {
                    for j in i.saturating_sub(w)..(i + w + 1).min(n) {
                        let left_out: f64 = closed
                            .iter()
                            .filter(|&&k| k < m - 1 && k > i + CLOSED_REACH)
                            .map(|&k| {
                                (modulus
                                    * near.stress_scale
                                    * near.stress_kernel[k - i]
                                    * near.gap_entry(k, j))
                                .abs()
                            })
                            .sum();
                        bound = bound.max(left_out);
                    }
                }
                assert!(
                    tail <= bound + 1e-12 * largest,
                    "tail {tail:e}, bound {bound:e}"
                );
                if m <= CLOSED_REACH {
                    assert_eq!(tail, 0.0);
                } else {
                    assert!(tail > 0.0);
                }
                // The closed part against its own dense twin: the operator with the mask
                // inverted on the contact nodes, column by column.
                let inverted: Vec<f64> = (0..n)
                    .map(|i| {
                        if i < m && closed.contains(&i) {
                            0.5
                        } else {
                            1.5
                        }
                    })
                    .collect();
                if !closed.is_empty() {
                    matrix
                        .freeze(&zeros, &zeros, &zeros, &inverted, m, theta)
                        .unwrap();
                    let twin = dense_band(&mut matrix, w);
                    let twin_error = twin
                        .iter()
                        .zip(&closed_part)
                        .fold(0.0f64, |a, (d, c)| a.max((d - c).abs()));
                    assert!(
                        twin_error <= 1e-12 * largest,
                        "closed part: {twin_error:e} of {largest:e}"
                    );
                }
                let open_g: Vec<f64> = (0..n).map(|i| if i < m { 0.5 } else { 1.5 }).collect();
                matrix
                    .freeze(&zeros, &zeros, &zeros, &open_g, m, theta)
                    .unwrap();
                matrix.masked_band(&mut bands).unwrap();
                let sum_error = masked[..m * row]
                    .iter()
                    .zip(&closed_part)
                    .zip(&bands.band)
                    .fold(0.0f64, |a, ((o, c), all)| a.max((o + c - all).abs()));
                assert!(sum_error <= 1e-12 * largest, "{sum_error:e} of {largest:e}");
                if closed.is_empty() {
                    assert!(closed_part[..m * row].iter().all(|&b| b == 0.0));
                }
            }
        }
    }

    /// The unrolled substitutions of the preconditioner's width (5) give the general loop's bits, on
    /// a diagonally dominant random band (fixed seed), with all rows active and with a part, and
    /// `M⁻¹x` against the dense `M = I − β J_w` (`M M⁻¹x = x` to rounding).
    #[test]
    fn fixed_width_substitution_is_the_general_one_bit_for_bit() {
        {
            let w = PRECONDITIONER_WIDTH;
            let n = 53;
            let mut p = BandPreconditioner::new(n, w);
            let mut state = 12345u64;
            let mut next = || {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            };
            for (i, row) in p.band.chunks_mut(2 * w + 1).enumerate() {
                for (l, b) in row.iter_mut().enumerate() {
                    let j = (i + l).checked_sub(w).filter(|&j| j < n);
                    *b = if j.is_some() { next() } else { 0.0 };
                }
                row[w] = -4.0 - next();
            }
            let x: Vec<f64> = (0..n).map(|_| next()).collect();
            for active in [n, n - 1, n - 2, 31, 3, 2] {
                for row in p.band.chunks_mut(2 * w + 1).skip(active) {
                    row.fill(0.0);
                }
                p.active = active;
                p.factor(0.7);
                assert!(p.factored);
                let (mut fixed, mut general) = (x.clone(), x.clone());
                p.substitute_width_5(&mut fixed, active);
                p.substitute(&mut general, active);
                assert!(fixed
                    .iter()
                    .zip(&general)
                    .all(|(a, b)| a.to_bits() == b.to_bits()));
                assert!(fixed.iter().zip(&x).any(|(a, b)| a != b));
                // The dense twin: M = I − β J_w applied to M⁻¹x gives x back.
                let colours = 2 * w + 1;
                let mut back = vec![0.0; n];
                for (i, b) in back.iter_mut().enumerate() {
                    for (l, entry) in p.band[i * colours..(i + 1) * colours].iter().enumerate() {
                        if let Some(j) = (i + l).checked_sub(w).filter(|&j| j < n) {
                            let identity = if i == j { 1.0 } else { 0.0 };
                            *b += (identity - 0.7 * entry) * fixed[j];
                        }
                    }
                }
                let residual = back
                    .iter()
                    .zip(&x)
                    .map(|(b, x)| (b - x).abs())
                    .fold(0.0, f64::max);
                assert!(
                    residual < 1e-13,
                    "active {active}: |M M⁻¹x − x| = {residual:e}"
                );
                // On the leading block of `active + w` nodes (the stages' support) with a zero tail:
                // the block of the whole vector's answer.
                let block = (active + w).min(n);
                let mut tail_free = x.clone();
                tail_free[block..].fill(0.0);
                let mut short = tail_free[..block].to_vec();
                p.substitute_width_5(&mut short, active);
                p.substitute(&mut tail_free, active);
                assert!(short
                    .iter()
                    .zip(&tail_free)
                    .all(|(a, b)| a.to_bits() == b.to_bits()));
            }
        }
    }
}
