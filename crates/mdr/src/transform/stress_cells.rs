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
    /// `(n + θ)^γ − n^γ` at one of the two edges of
    /// [`CellStressTransform::line_load_edge_difference`] (work array).
    two_edge_powers: Vec<f64>,
    /// The binomial series' factors `(γ − m)/(m + 1)`, `m = 0..SERIES_TERMS`
    /// ([`partial_cell_powers`]), divided once here instead of per node.
    series_factors: [f64; SERIES_TERMS],
}

/// `m^γ` for `m = 0..len`: the powers of the partial cell and, by differences
/// ([`cell_weights`]), of the cells' weights (the type's docs). One table for the transform and
/// for the closed form of its matrix (the wear steps' masked band, crates/fretting).
pub fn node_powers(len: usize, gamma: f64) -> Vec<f64> {
    (0..len).map(|m| (m as f64).powf(gamma)).collect()
}

/// The cells' weights `w_m = (m+1)^γ − m^γ`, `m = 0..powers.len() − 1`, from
/// `powers[m] = m^γ` ([`node_powers`]).
pub fn cell_weights(powers: &[f64]) -> Vec<f64> {
    powers.windows(2).map(|w| w[1] - w[0]).collect()
}

/// The factor `h^{γ−1}/(πγ)` of `σ` (the type's docs), for the node spacing `h` in `ξ = x²`.
pub fn stress_scale(h: f64, gamma: f64) -> f64 {
    h.powf(gamma - 1.0) / (std::f64::consts::PI * gamma)
}

/// Beyond this distance (in cells) from the edge `(n + θ)^γ − n^γ` is summed as a series.
const SERIES_FROM: usize = 64;
/// Terms of that series (`(θ/n)^10 ≤ 64^{−10}`: below one ulp).
const SERIES_TERMS: usize = 10;

/// `out[i] = P(from + i) = (n + θ)^γ − n^γ`, `n = from + i`, for `θ ∈ (0, 1]` (`powers[n] = n^γ`):
/// `n^γ [(1 + θ/n)^γ − 1]` by its binomial series when `n ≥ 64` (ten terms, `θ/n ≤ 1/64`: below
/// one ulp), `powf` closer to the edge. The term `m + 1` is the term `m` times
/// `((γ − m)/(m + 1)) · (θ/n)`, the factor's quotient taken from `series_factors` (the same value
/// as dividing here, one division a node instead of eleven). The series runs on SIMD lanes,
/// several nodes side by side (the same operations on each node in the same order as one node at
/// a time: the same bits).
fn partial_cell_powers(
    powers: &[f64],
    series_factors: &[f64; SERIES_TERMS],
    gamma: f64,
    from: usize,
    theta: f64,
    out: &mut [f64],
) {
    let split = SERIES_FROM.clamp(from, from + out.len());
    let (near, far) = out.split_at_mut(split - from);
    for (i, o) in near.iter_mut().enumerate() {
        let n = from + i;
        *o = (n as f64 + theta).powf(gamma) - powers[n];
    }
    // The widest SIMD level of this CPU (pulp's runtime dispatch: AVX2 on x86-64-v3). Each lane
    // takes the scalar operations in the scalar order (separate multiplies and adds, no fused
    // multiply-add, IEEE division), so every level gives the same bits.
    pulp::Arch::new().dispatch(SeriesLanes {
        powers,
        series_factors,
        first: split,
        theta,
        out: far,
    });
}

/// The series part of [`partial_cell_powers`]: `out[i] = P(first + i)`, the SIMD level's lanes
/// side by side.
struct SeriesLanes<'a> {
    powers: &'a [f64],
    series_factors: &'a [f64; SERIES_TERMS],
    first: usize,
    theta: f64,
    out: &'a mut [f64],
}

impl pulp::WithSimd for SeriesLanes<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) {
        let lanes = std::mem::size_of::<S::f64s>() / std::mem::size_of::<f64>();
        let theta = simd.splat_f64s(self.theta);
        let factors = self.series_factors.map(|f| simd.splat_f64s(f));
        let mut nodes = [0.0f64; 16];
        for (c, chunk) in self.out.chunks_mut(lanes).enumerate() {
            let first = self.first + c * lanes;
            for (l, node) in nodes[..chunk.len()].iter_mut().enumerate() {
                *node = (first + l) as f64;
            }
            // Lanes beyond the chunk divide by 1 (their values are not stored).
            nodes[chunk.len()..lanes].fill(1.0);
            let x = simd.div_f64s(theta, simd.partial_load_f64s(&nodes[..lanes]));
            let (mut term, mut sum) = (simd.splat_f64s(1.0), simd.splat_f64s(0.0));
            for factor in factors {
                term = simd.mul_f64s(term, simd.mul_f64s(factor, x));
                sum = simd.add_f64s(sum, term);
            }
            let n_gamma = simd.partial_load_f64s(&self.powers[first..first + chunk.len()]);
            simd.partial_store_f64s(chunk, simd.mul_f64s(n_gamma, sum));
        }
    }
}

impl CellStressTransform {
    /// Builds the transform for contacts of up to `capacity` nodes.
    pub fn new(capacity: usize, material: &Material, backend: Backend) -> Result<Self, MdrError> {
        let gamma = 0.5 * (1.0 + material.grading_exponent());
        let powers = node_powers(capacity + 1, gamma);
        let weights = cell_weights(&powers);
        Ok(Self {
            gamma,
            conv: ToeplitzConvolution::new(weights, backend)?,
            powers,
            reversed: vec![0.0; capacity],
            sums: vec![0.0; capacity],
            edge_powers: vec![0.0; capacity + 1],
            two_edge_powers: vec![0.0; capacity + 1],
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
        let scale = stress_scale(h, self.gamma);
        let edge_slope = q[m - 1] / theta;
        if theta.to_bits() != self.edge_theta.to_bits() {
            self.edge_theta = theta;
            self.edge_cells = 0;
        }
        if self.edge_cells <= cells {
            partial_cell_powers(
                &self.powers,
                &self.series_factors,
                self.gamma,
                self.edge_cells,
                theta,
                &mut self.edge_powers[self.edge_cells..=cells],
            );
        }
        self.edge_cells = self.edge_cells.max(cells + 1);
        self.stress_from_sums(scale, edge_slope, &self.edge_powers[..=cells], sigma);
        Ok(())
    }

    /// `σ(θ_a) − σ(θ_b)` of [`CellStressTransform::line_load_to_stress`] for one `q` at two edges:
    /// the cells' sums `S_j` do not depend on `θ` and cancel, so
    ///
    /// `σ_j(θ_a) − σ_j(θ_b) = scale · q_{M−1} · (P_a(M − 1 − j)/θ_a − P_b(M − 1 − j)/θ_b)`,
    /// `P_θ(n) = (n + θ)^γ − n^γ`,
    ///
    /// with no convolution and without the cancellation of the sums that the difference of two
    /// transforms suffers (the θ-derivative of the implicit wear steps' Jacobian,
    /// docs/fretting-wear.md, "Time integration"). Only `q`'s last value enters; `q` fixes `M`.
    pub fn line_load_edge_difference(
        &mut self,
        grid: &SquaredGrid,
        q: &[f64],
        thetas: (f64, f64),
        difference: &mut [f64],
    ) -> Result<(), MdrError> {
        self.check(grid, q, thetas.0, difference)?;
        self.check(grid, q, thetas.1, difference)?;
        let cells = q.len() - 1;
        let scale = stress_scale(grid.step(), self.gamma);
        let mut powers = std::mem::take(&mut self.two_edge_powers);
        difference.fill(0.0);
        for (sign, theta) in [(1.0, thetas.0), (-1.0, thetas.1)] {
            partial_cell_powers(
                &self.powers,
                &self.series_factors,
                self.gamma,
                0,
                theta,
                &mut powers[..=cells],
            );
            let slope = sign * scale * q[cells] / theta;
            // Node j reads P(M − 1 − j): reversed.
            for (d, &power) in difference.iter_mut().zip(powers[..=cells].iter().rev()) {
                *d += slope * power;
            }
        }
        self.two_edge_powers = powers;
        Ok(())
    }

    /// `σ_j = scale · (edge_slope · P(M − 1 − j) − S_j)` (`S_j` the cell sums of
    /// [`CellStressTransform::cell_sums`], 0 at `j = M − 1`; `P(n) = (n + θ)^γ − n^γ`).
    fn stress_from_sums(&self, scale: f64, edge_slope: f64, powers: &[f64], sigma: &mut [f64]) {
        let cells = sigma.len() - 1;
        // Node j reads P(M − 1 − j) and S_j = sums[M − 2 − j]: both reversed.
        let (inner, last) = sigma.split_at_mut(cells);
        for ((s, &power), &cell_sum) in inner
            .iter_mut()
            .zip(powers[1..=cells].iter().rev())
            .zip(self.sums[..cells].iter().rev())
        {
            *s = scale * (edge_slope * power - cell_sum);
        }
        last[0] = scale * (edge_slope * powers[0] - 0.0);
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
        for (v, pair) in self.reversed[..cells].iter_mut().zip(q.windows(2).rev()) {
            *v = pair[1] - pair[0];
        }
        self.conv
            .apply(&self.reversed[..cells], &mut self.sums[..cells])?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One node at a time: the series as it was summed before the lanes (the control).
    fn partial_cell_power(
        powers: &[f64],
        factors: &[f64],
        gamma: f64,
        n: usize,
        theta: f64,
    ) -> f64 {
        if n < SERIES_FROM {
            return (n as f64 + theta).powf(gamma) - powers[n];
        }
        let x = theta / n as f64;
        let (mut term, mut sum) = (1.0, 0.0);
        for factor in factors {
            term *= factor * x;
            sum += term;
        }
        powers[n] * sum
    }

    /// [`partial_cell_powers`] over lanes against the node-at-a-time control bit for bit, for
    /// γ of k = −0.5, 0, 0.3 and seeded θ ∈ (0, 1] (and θ = 1), on ranges that start below,
    /// at and beyond `SERIES_FROM` and end inside a chunk of lanes; and against `powf` directly
    /// to 4e-16 relative (the series' truncation below one ulp).
    #[test]
    fn lanes_give_the_node_at_a_time_series_bit_for_bit() {
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut uniform = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for k in [-0.5, 0.0, 0.3] {
            let gamma = 0.5 * (1.0 + k);
            let powers: Vec<f64> = (0..=700).map(|m| (m as f64).powf(gamma)).collect();
            let factors: [f64; SERIES_TERMS] =
                std::array::from_fn(|m| (gamma - m as f64) / (m as f64 + 1.0));
            for theta in [1.0, 1.0 - uniform(), 1.0 - uniform(), 1e-3] {
                for (from, to) in [(0, 700), (5, 64), (63, 66), (64, 71), (64, 64), (100, 683)] {
                    let mut out = vec![f64::NAN; to - from + 1];
                    partial_cell_powers(&powers, &factors, gamma, from, theta, &mut out);
                    for (i, v) in out.iter().enumerate() {
                        let n = from + i;
                        let control = partial_cell_power(&powers, &factors, gamma, n, theta);
                        assert_eq!(
                            v.to_bits(),
                            control.to_bits(),
                            "k = {k}, θ = {theta}, n = {n}"
                        );
                        let exact = (n as f64 + theta).powf(gamma) - powers[n];
                        let scale = powers[n].max(1.0);
                        assert!(
                            (v - exact).abs() <= 4e-16 * scale,
                            "k = {k}, θ = {theta}, n = {n}"
                        );
                    }
                }
            }
        }
    }
}
