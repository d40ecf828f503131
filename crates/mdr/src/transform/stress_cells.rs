use halfspace_numerics::{Backend, Precision, SquaredGrid, ToeplitzConvolution};

use super::{check_fits, check_len};
use crate::{Material, MdrError};

/// Line load `q(x) → σ(r)` of the MDR (Eq. 14 / Eq. 28) by product integration, with the contact
/// edge **between** grid nodes. In `ξ = x²` the pressure is
///
/// `σ(ρ) = −(1/π) ∫_ρ^{a²} q̂'(ξ) (ξ − ρ)^{γ−1} dξ`, `γ = (1+k)/2`, `q(a) = 0`
///
/// (docs/theory-mdr.md#stress-transform / docs/theory-mdr.md#graded-pressure before their integration by parts). Here `q` is taken linear on every cell
/// `[ξ_i, ξ_{i+1}]` of the contact nodes `0..M` and on the partial cell `[ξ_{M−1}, a²]`,
/// `a² = ξ_{M−1} + θh`, `θ ∈ (0, 1]`, where it falls to `q(a) = 0`; each cell is integrated
/// exactly:
///
/// `σ_j = (h^{γ−1}/(πγ)) [ −Σ_{i=j}^{M−2} (q_{i+1} − q_i) w_{i−j} + (q_{M−1}/θ) ((M−1−j+θ)^γ − (M−1−j)^γ) ]`,
/// `w_m = (m+1)^γ − m^γ`, for `j = 0..M` (the sum is one anti-causal Toeplitz product).
///
/// Why a second discretization of Eq. 17/29: those take `q̂'` and `q̂''` by finite differences on
/// an array cut at a node. When the edge moves between nodes (fretting wear), the load clipped at
/// the edge node gives a one-sided `q̂'(a²)` off by up to `1.5|q̂'|`, which Eq. 17/29 spread over the
/// whole contact as `q̂'(a²)(a² − ρ)^γ`: an `O(1)` pressure error, not `O(h)`, that comes back
/// every time the edge crosses a cell (docs/fretting-wear.md, "The contact edge between nodes").
/// Here `σ` is continuous in `θ` and exact for a load linear in `ξ` (Hertz: `q ∝ a² − ξ`).
pub struct CellStressTransform {
    gamma: f64,
    /// `m^γ`, `m = 0..capacity` (for the partial cell).
    powers: Vec<f64>,
    conv: ToeplitzConvolution,
    reversed: Vec<f64>,
    sums: Vec<f64>,
    /// `(n + θ)^γ − n^γ` for `n < edge_cells` at `θ = edge_theta` (kept while `θ` stays: the
    /// implicit wear steps apply the transform many times at one frozen edge).
    edge_powers: Vec<f64>,
    edge_theta: f64,
    edge_cells: usize,
    /// The binomial series' factors `(γ − m)/(m + 1)`, `m = 0..SERIES_TERMS`
    /// ([`CellStressTransform::partial_cell_power`]), divided once here instead of per node.
    series_factors: [f64; SERIES_TERMS],
}

/// Beyond this distance (in cells) from the edge `(n + θ)^γ − n^γ` is summed as a series.
const SERIES_FROM: usize = 64;
/// Terms of that series (`(θ/n)^10 ≤ 64^{−10}`: below one ulp).
const SERIES_TERMS: usize = 10;

impl CellStressTransform {
    /// Builds the transform for contacts of up to `capacity` nodes.
    pub fn new(capacity: usize, material: &Material, backend: Backend) -> Result<Self, MdrError> {
        let gamma = 0.5 * (1.0 + material.grading_exponent());
        let powers: Vec<f64> = (0..=capacity).map(|m| (m as f64).powf(gamma)).collect();
        let weights = powers.windows(2).map(|w| w[1] - w[0]).collect();
        Ok(Self {
            gamma,
            conv: ToeplitzConvolution::new(weights, backend)?,
            powers,
            reversed: vec![0.0; capacity],
            sums: vec![0.0; capacity],
            edge_powers: vec![0.0; capacity + 1],
            edge_theta: f64::NAN,
            edge_cells: 0,
            series_factors: std::array::from_fn(|m| (gamma - m as f64) / (m as f64 + 1.0)),
        })
    }

    /// Plans shorter FFT lengths, for contacts much shorter than the capacity (the same transform
    /// to rounding; `halfspace_numerics::ToeplitzConvolution::plan_shorter_lengths`).
    pub fn plan_shorter_lengths(&mut self) {
        self.conv.plan_shorter_lengths();
    }

    /// The precision of the cells' convolution
    /// (`halfspace_numerics::ToeplitzConvolution::set_precision`; for products inside an
    /// iteration solved to a looser tolerance, docs/performance.md, "The N = 8001 wear run:
    /// single-precision stage products (issue 20)").
    pub fn set_precision(&mut self, precision: Precision) {
        self.conv.set_precision(precision);
    }

    /// Largest contact accepted (nodes `0..M`).
    pub fn capacity(&self) -> usize {
        self.conv.capacity()
    }

    /// `(n + θ)^γ − n^γ` for `θ ∈ (0, 1]`: `n^γ [(1 + θ/n)^γ − 1]` by its binomial series when
    /// `n ≥ 64` (ten terms, `θ/n ≤ 1/64`: below one ulp), `powf` closer to the edge. The term
    /// `m + 1` is the term `m` times `((γ − m)/(m + 1)) · (θ/n)`, the factor's quotient taken
    /// from [`CellStressTransform::series_factors`] (the same value as dividing here: the same
    /// bits, one division a node instead of eleven).
    fn partial_cell_power(&self, n: usize, theta: f64) -> f64 {
        if n < SERIES_FROM {
            return (n as f64 + theta).powf(self.gamma) - self.powers[n];
        }
        let x = theta / n as f64;
        let (mut term, mut sum) = (1.0, 0.0);
        for factor in &self.series_factors {
            term *= factor * x;
            sum += term;
        }
        self.powers[n] * sum
    }

    /// `σ` on the contact nodes `0..M` (`M = q.len() ≥ 2`) from `q` on the same nodes and the edge
    /// `a² = ξ_{M−1} + θh`, `θ ∈ (0, 1]`, where `q(a) = 0` (see the type's docs for the formula).
    pub fn line_load_to_stress(
        &mut self,
        grid: &SquaredGrid,
        q: &[f64],
        theta: f64,
        sigma: &mut [f64],
    ) -> Result<(), MdrError> {
        self.check(grid, q, theta, sigma)?;
        self.cell_sums(q)?;
        let m = q.len();
        let cells = m - 1;
        let h = grid.step();
        let scale = h.powf(self.gamma - 1.0) / (std::f64::consts::PI * self.gamma);
        let edge_slope = q[m - 1] / theta;
        if theta.to_bits() != self.edge_theta.to_bits() {
            self.edge_theta = theta;
            self.edge_cells = 0;
        }
        for n in self.edge_cells..=cells {
            let power = self.partial_cell_power(n, theta);
            self.edge_powers[n] = power;
        }
        self.edge_cells = self.edge_cells.max(cells + 1);
        self.stress_from_sums(scale, edge_slope, |n| self.edge_powers[n], sigma);
        Ok(())
    }

    /// [`CellStressTransform::line_load_to_stress`] for one `q` at two edges `θ_a`, `θ_b`
    /// (`σ_a`, `σ_b`): the cells' sums do not depend on `θ`, so they are convolved once, and each
    /// `σ` is the one `line_load_to_stress` gives at its `θ`, bit for bit (the θ-derivative of the
    /// implicit wear steps' Jacobian, docs/fretting-wear.md, "Time integration").
    pub fn line_load_to_stress_at_two_edges(
        &mut self,
        grid: &SquaredGrid,
        q: &[f64],
        thetas: (f64, f64),
        sigmas: (&mut [f64], &mut [f64]),
    ) -> Result<(), MdrError> {
        self.check(grid, q, thetas.0, sigmas.0)?;
        self.check(grid, q, thetas.1, sigmas.1)?;
        self.cell_sums(q)?;
        let cells = q.len() - 1;
        let h = grid.step();
        let scale = h.powf(self.gamma - 1.0) / (std::f64::consts::PI * self.gamma);
        for (theta, sigma) in [(thetas.0, sigmas.0), (thetas.1, sigmas.1)] {
            let edge_slope = q[cells] / theta;
            self.stress_from_sums(
                scale,
                edge_slope,
                |n| self.partial_cell_power(n, theta),
                sigma,
            );
        }
        Ok(())
    }

    /// `σ_j = scale · (edge_slope · P(M − 1 − j) − S_j)` (`S_j` the cell sums of
    /// [`CellStressTransform::cell_sums`], 0 at `j = M − 1`; `P(n) = (n + θ)^γ − n^γ`).
    fn stress_from_sums(
        &self,
        scale: f64,
        edge_slope: f64,
        power: impl Fn(usize) -> f64,
        sigma: &mut [f64],
    ) {
        let cells = sigma.len() - 1;
        for (j, s) in sigma.iter_mut().enumerate() {
            let cell_sum = if j < cells {
                self.sums[cells - 1 - j]
            } else {
                0.0
            };
            *s = scale * (edge_slope * power(cells - j) - cell_sum);
        }
    }

    /// The checks of [`CellStressTransform::line_load_to_stress`] for one edge `θ`.
    fn check(
        &self,
        grid: &SquaredGrid,
        q: &[f64],
        theta: f64,
        sigma: &[f64],
    ) -> Result<(), MdrError> {
        check_fits("cell stress transform grid", grid, self.capacity())?;
        let m = q.len();
        check_len("stress output", m, sigma.len())?;
        if m < 2 || m > grid.len() {
            return Err(MdrError::Numerics(
                halfspace_numerics::NumericsError::TooFewNodes {
                    what: "the cell stress transform (contact nodes, at most the grid)",
                    min: 2,
                    n: m,
                },
            ));
        }
        if !(theta > 0.0 && theta <= 1.0) {
            return Err(MdrError::Numerics(
                halfspace_numerics::NumericsError::InvalidParameter {
                    name: "edge position θ in its cell",
                    value: theta,
                    allowed: "in (0, 1]",
                },
            ));
        }
        Ok(())
    }

    /// The anti-causal sums `Σ_{i≥j} (q_{i+1} − q_i) w_{i−j}` of the cells `0..M−1` into
    /// `sums` (reversed: `sums[M − 2 − j]` is cell `j`'s), by one causal convolution.
    fn cell_sums(&mut self, q: &[f64]) -> Result<(), MdrError> {
        let m = q.len();
        let cells = m - 1;
        // Anti-causal Σ_{i≥j} Δq_i w_{i−j}: reverse, convolve causally, read back reversed.
        for (l, v) in self.reversed[..cells].iter_mut().enumerate() {
            let i = cells - 1 - l;
            *v = q[i + 1] - q[i];
        }
        self.conv
            .apply(&self.reversed[..cells], &mut self.sums[..cells])?;
        Ok(())
    }
}
