use halfspace_numerics::{
    diff::derivative_uniform, pow_or_sqrt, Backend, PowerSum, Precision, SquaredGrid,
};

use super::{check_fits, check_len};
use crate::{Material, MdrError, Profile};

/// Profile transform `f(r) → g(x)` of the MDR (paper Eq. 1, discretized as Eq. 7; docs/theory-mdr.md#profile-transform):
///
/// `Ĝ_i = h^{3/2} S^{1/2}_i[f̂']`, `g_i = 2 √ξ_i D[Ĝ]_i`,
///
/// with `S` the causal trapezoid sum of docs/theory-mdr.md#power-sums and `D` the differences of docs/theory-mdr.md#finite-differences. Written for the
/// grading exponent `k` (Eq. 23: `h^{(3+k)/2} S^{(1+k)/2}`, `g_i = 2/(1+k) ξ_i^{(1−k)/2} D[Ĝ]_i`), of
/// which the homogeneous medium is `k = 0`.
pub struct ProfileTransform {
    k: f64,
    sum: PowerSum,
    big_g: Vec<f64>,
    dg: Vec<f64>,
    slope: Vec<f64>,
    samples: Vec<f64>,
    /// `i^{(1−k)/2}`, so that `ξ_i^{(1−k)/2} = h^{(1−k)/2} i^{(1−k)/2}` costs no `powf` per apply.
    index_power: Vec<f64>,
}

impl ProfileTransform {
    /// Builds the transform for grids of up to `capacity` nodes.
    pub fn new(capacity: usize, material: &Material, backend: Backend) -> Result<Self, MdrError> {
        let k = material.grading_exponent();
        Ok(Self {
            k,
            sum: PowerSum::new(capacity, 0.5 * (1.0 + k), backend)?,
            big_g: vec![0.0; capacity],
            dg: vec![0.0; capacity],
            slope: vec![0.0; capacity],
            samples: vec![0.0; capacity],
            index_power: (0..capacity)
                .map(|i| pow_or_sqrt(i as f64, 0.5 * (1.0 - k)))
                .collect(),
        })
    }

    /// Plans shorter FFT lengths, for grids much shorter than the capacity (the same transform to
    /// rounding; `halfspace_numerics::PowerSum::plan_shorter_lengths`).
    pub fn plan_shorter_lengths(&mut self) {
        self.sum.plan_shorter_lengths();
    }

    /// The precision of [`ProfileTransform::apply`]: with [`Precision::Single`] the derivative
    /// `D[Ĝ]` of Eq. 7 comes from the increments `Ĝ_i − Ĝ_{i−1}` convolved directly in `f32`
    /// (`halfspace_numerics::PowerSum::causal_increments`): the same differences
    /// (docs/theory-mdr.md#finite-differences) written in increments, `D_i = (E_{i+1} + E_i)/(2h)`,
    /// `D_{n−1} = (3E_{n−1} − E_{n−2})/(2h)`, `D_0 = (3E_1 − E_2)/(2h)` (`Ĝ_0 = 0`), to about
    /// `10⁻⁶` of `g` instead of the `f64` sum's rounding. For products inside an iteration
    /// solved to a looser tolerance (docs/performance.md, "The N = 8001 wear run:
    /// single-precision stage products (issue 20)"). No effect with the MVM backend.
    pub fn set_precision(&mut self, precision: Precision) -> Result<(), MdrError> {
        self.sum.set_precision(precision)?;
        Ok(())
    }

    /// Largest grid accepted.
    pub fn capacity(&self) -> usize {
        self.sum.capacity()
    }

    /// Eq. 7 (Eq. 23 for `k ≠ 0`): `g` on every node from `f̂' = df/dρ` on every node.
    pub fn apply(
        &mut self,
        grid: &SquaredGrid,
        f_hat_slope: &[f64],
        g: &mut [f64],
    ) -> Result<(), MdrError> {
        check_fits("profile transform grid", grid, self.capacity())?;
        let n = grid.len();
        check_len("profile slope f̂'", n, f_hat_slope.len())?;
        check_len("equivalent profile g", n, g.len())?;
        let h = grid.step();
        let big_g = &mut self.big_g[..n];
        let scale = h.powf(0.5 * (3.0 + self.k));
        let dg = &mut self.dg[..n];
        if self.sum.precision() == Precision::Single && n >= 3 {
            // E_i = Ĝ_i − Ĝ_{i−1} (see `set_precision`).
            self.sum.causal_increments(f_hat_slope, big_g)?;
            big_g.iter_mut().for_each(|v| *v *= scale);
            let inv2h = 0.5 / h;
            dg[0] = (3.0 * big_g[1] - big_g[2]) * inv2h;
            for (d, w) in dg[1..n - 1].iter_mut().zip(big_g[1..n].windows(2)) {
                *d = (w[1] + w[0]) * inv2h;
            }
            dg[n - 1] = (3.0 * big_g[n - 1] - big_g[n - 2]) * inv2h;
        } else {
            self.sum.causal(f_hat_slope, big_g)?;
            big_g.iter_mut().for_each(|v| *v *= scale);
            derivative_uniform(big_g, h, dg)?;
        }
        let factor = 2.0 / (1.0 + self.k) * pow_or_sqrt(h, 0.5 * (1.0 - self.k));
        for ((gi, di), wi) in g.iter_mut().zip(dg.iter()).zip(&self.index_power) {
            *gi = factor * wi * di;
        }
        g[0] = 0.0;
        Ok(())
    }

    /// `g(x)` of a profile on every node, by Eq. 7 (Eq. 23) with two closed-form splits (docs/theory-mdr.md#p4-the-origin, #p5-conical-profiles):
    /// `f = s₀ r + c₀ r² + f_rest`, where `s₀ = f'(0⁺)` and `c₀ = f̂'_rem(0)`, so that
    /// `g = κ₁(k) s₀ |x| + κ₂(k) c₀ x² + Eq.7[f_rest]` (`κ₁(0) = π/2`, `κ₂(k) = 2/(1+k)`). The cone part makes `f̂'` bounded (P5); the
    /// parabolic part removes the `ξ^{3/2}` behaviour of `Ĝ` at the origin that makes `D[Ĝ]` first
    /// order there (P4), so a paraboloid is transformed exactly and smooth profiles lose the
    /// `O(h)` error at the first nodes. Returns the split `(s₀, c₀)`.
    /// A flat punch has `g = 0` inside its radius and `+∞` beyond (a wall).
    pub fn profile_to_equivalent(
        &mut self,
        profile: &Profile,
        grid: &SquaredGrid,
        g: &mut [f64],
    ) -> Result<EquivalentSplit, MdrError> {
        check_fits("profile transform grid", grid, self.capacity())?;
        let n = grid.len();
        check_len("equivalent profile g", n, g.len())?;
        if let Profile::FlatPunch { radius } = *profile {
            for (i, gi) in g.iter_mut().enumerate() {
                *gi = if grid.coordinate(i) <= radius * (1.0 + 1e-12) {
                    0.0
                } else {
                    f64::INFINITY
                };
            }
            return Ok(EquivalentSplit::default());
        }
        let mut slope = std::mem::take(&mut self.slope);
        let result = profile
            .squared_slope(grid, &mut slope[..n], &mut self.samples[..n])
            .and_then(|_| self.split_apply(grid, &mut slope[..n], g));
        self.slope = slope;
        let parabolic = result?;
        let conical = profile.conical_slope();
        let cubic = profile.cubic_coefficient();
        let kappa1 = crate::analytic::graded_power_law_factor(1.0, self.k);
        let kappa2 = 2.0 / (1.0 + self.k);
        let kappa3 = crate::analytic::graded_power_law_factor(3.0, self.k);
        for (i, gi) in g.iter_mut().enumerate() {
            let x = grid.coordinate(i);
            *gi += kappa1 * conical * x
                + kappa2 * parabolic * grid.squared(i)
                + kappa3 * cubic * x * x * x;
        }
        Ok(EquivalentSplit {
            conical,
            parabolic,
            cubic,
        })
    }
}

impl ProfileTransform {
    /// `g` from samples of `f̂' = df/dρ` with the parabolic split of
    /// [`ProfileTransform::profile_to_equivalent`]: `c₀ = f̂'_0` is taken out, transformed to
    /// `κ₂(k) c₀ x²`, the rest goes through Eq. 7. `slope` is used as scratch (left with `c₀`
    /// subtracted). Returns `c₀`. For evolving profiles (fretting wear) given as samples.
    pub fn slope_to_equivalent(
        &mut self,
        grid: &SquaredGrid,
        slope: &mut [f64],
        g: &mut [f64],
    ) -> Result<f64, MdrError> {
        let c0 = self.split_apply(grid, slope, g)?;
        let kappa2 = 2.0 / (1.0 + self.k);
        for (i, gi) in g.iter_mut().enumerate() {
            *gi += kappa2 * c0 * grid.squared(i);
        }
        Ok(c0)
    }

    /// `g` on every node from samples `v_i = f(√ξ_i)` of a profile, exact for the profile
    /// linear in `ξ = r²` between nodes (docs/theory-mdr.md#profile-transform, "Piecewise-linear
    /// profiles"): with the cell slopes `s_{t+½} = (v_{t+1} − v_t)/h`,
    ///
    /// `g_j = (1/γ) h j^{1−γ} Σ_{t=0}^{j−1} s_{t+½} e_{j−t}`, `e_m = m^γ − (m−1)^γ`, `γ = (1+k)/2`,
    ///
    /// the exact `(1/γ) ξ^{1−γ} dĜ/dξ` of Eq. 7 / 23 for that profile (`∫` over a cell of
    /// `γ(ξ_j − ρ)^{γ−1}` is `h^γ e_{j−t}`). No difference is taken at the nodes, so no profile
    /// mode is invisible to it (the interior stencils of the central differences of
    /// [`ProfileTransform::slope_to_equivalent`] have `(−1)^i` in their null space); a paraboloid
    /// (`v` linear in `ξ`) is exact without a split, and a smooth profile converges at order
    /// `1 + γ`, as the trapezoid rule of Eq. 7 (P1). `g_j` depends on `v_0 … v_j` only. `g` sees
    /// differences of `v` only (as Eq. 7, which needs `f(0) = 0`).
    pub fn values_to_equivalent(
        &mut self,
        grid: &SquaredGrid,
        values: &[f64],
        g: &mut [f64],
    ) -> Result<(), MdrError> {
        check_fits("profile transform grid", grid, self.capacity())?;
        let n = grid.len();
        check_len("profile samples", n, values.len())?;
        check_len("equivalent profile g", n, g.len())?;
        let h = grid.step();
        let inv_h = 1.0 / h;
        let slope = &mut self.slope[..n];
        for t in 0..n - 1 {
            slope[t] = (values[t + 1] - values[t]) * inv_h;
        }
        // The causal sum halves its first entry (trapezoid): doubled here, so that its
        // increments are the plain sums over the cells 0..j.
        slope[0] *= 2.0;
        slope[n - 1] = 0.0;
        let increments = &mut self.big_g[..n];
        self.sum.causal_increments(slope, increments)?;
        let factor = h / (0.5 * (1.0 + self.k));
        for ((gi, e), wi) in g.iter_mut().zip(increments.iter()).zip(&self.index_power) {
            *gi = factor * wi * e;
        }
        g[0] = 0.0;
        Ok(())
    }

    fn split_apply(
        &mut self,
        grid: &SquaredGrid,
        slope: &mut [f64],
        g: &mut [f64],
    ) -> Result<f64, MdrError> {
        let c0 = slope[0];
        slope.iter_mut().for_each(|v| *v -= c0);
        self.apply(grid, slope, g)?;
        Ok(c0)
    }
}

/// The closed-form parts of `f = s₀ r + c₀ r² + f_rest` split off by
/// [`ProfileTransform::profile_to_equivalent`].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EquivalentSplit {
    /// `s₀ = f'(0⁺)`, transformed to `κ₁(k) s₀ |x|`.
    pub conical: f64,
    /// `c₀`, transformed to `κ₂(k) c₀ x²`.
    pub parabolic: f64,
    /// `c₃`, transformed to `κ₃(k) c₃ |x|³`.
    pub cubic: f64,
}
