use halfspace_numerics::{diff::derivative_uniform, pow_or_sqrt, Backend, PowerSum, SquaredGrid};

use super::{check_fits, check_len};
use crate::{Material, MdrError};

/// Line load `q(x) → σ(r)` of the MDR (paper Eq. 14, discretized as Eq. 17; docs/theory-mdr.md#stress-transform). With
/// `a² = ξ_{M−1}` a grid node and `q̂', q̂''` by the differences of docs/theory-mdr.md#finite-differences on the array cut at the
/// contact edge (docs/theory-mdr.md#p3-one-sided-differences-at-the-edge):
///
/// `σ_j = (2/π) [ −q̂'(a²) √(a² − ρ_j) + h^{3/2} A^{1/2}_j[q̂''] ] + q(a⁻) / (π √(a² − ρ_j))`,
/// `j < M−1`, and `σ_{M−1} = 0` (`+∞` when `q(a⁻) ≠ 0`). The last term is the edge term of docs/theory-mdr.md#stress-transform for
/// a non-vanishing load at the edge (the flat punch's whole pressure). Written for the grading
/// exponent `k` (Eq. 29 with `Q = c_N (δ − g)`), of which the homogeneous medium is `k = 0`.
pub struct StressTransform {
    k: f64,
    sum: PowerSum,
    d1: Vec<f64>,
    d2: Vec<f64>,
    t: Vec<f64>,
}

impl StressTransform {
    /// Builds the transform for contacts of up to `capacity` nodes.
    pub fn new(capacity: usize, material: &Material, backend: Backend) -> Result<Self, MdrError> {
        let k = material.grading_exponent();
        Ok(Self {
            k,
            sum: PowerSum::new(capacity, 0.5 * (1.0 + k), backend)?,
            d1: vec![0.0; capacity],
            d2: vec![0.0; capacity],
            t: vec![0.0; capacity],
        })
    }

    /// Largest contact accepted (nodes `0..M`).
    pub fn capacity(&self) -> usize {
        self.sum.capacity()
    }

    /// Eq. 17: `σ` on the contact nodes `0..M` from `q` on the same nodes (`M = q.len() ≥ 3`,
    /// `q` cut at the edge, `a² = grid.squared(M−1)`) and the edge load `q(a⁻)` (0 for a
    /// non-adhesive contact with a smooth profile).
    pub fn line_load_to_stress(
        &mut self,
        grid: &SquaredGrid,
        q: &[f64],
        edge_load: f64,
        sigma: &mut [f64],
    ) -> Result<(), MdrError> {
        check_fits("stress transform grid", grid, self.capacity())?;
        let m = q.len();
        check_len("stress output", m, sigma.len())?;
        if m < 3 || m > grid.len() {
            return Err(MdrError::Numerics(
                halfspace_numerics::NumericsError::TooFewNodes {
                    what: "the stress transform (contact nodes, at most the grid)",
                    min: 3,
                    n: m,
                },
            ));
        }
        let h = grid.step();
        let (d1, d2, t) = (&mut self.d1[..m], &mut self.d2[..m], &mut self.t[..m]);
        derivative_uniform(q, h, d1)?;
        derivative_uniform(d1, h, d2)?;
        self.sum.anticausal(d2, t)?;
        let gamma = 0.5 * (1.0 + self.k);
        let pref = 2.0 / (std::f64::consts::PI * (1.0 + self.k));
        let scale = h.powf(0.5 * (3.0 + self.k));
        let edge_slope = d1[m - 1];
        // (a² − ρ_j)^γ = h^γ (M−1−j)^γ: the power sum's own kernel, no powf per node.
        let h_gamma = pow_or_sqrt(h, gamma);
        let gap_power = self.sum.kernel();
        for j in 0..m - 1 {
            let gap_gamma = h_gamma * gap_power[m - 1 - j];
            let mut s = pref * (-edge_slope * gap_gamma + scale * t[j]);
            if edge_load != 0.0 {
                // (a² − ρ_j)^{γ−1}, the edge term of docs/theory-mdr.md#stress-transform (flat punch).
                let gap = h * (m - 1 - j) as f64;
                s += edge_load / std::f64::consts::PI * gap_gamma / gap;
            }
            sigma[j] = s;
        }
        sigma[m - 1] = if edge_load == 0.0 {
            0.0
        } else {
            edge_load.signum() * f64::INFINITY
        };
        Ok(())
    }
}
