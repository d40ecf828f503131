use halfspace_numerics::{Backend, SquaredGrid};

use crate::FrettingError;

/// Parameters of a fretting-wear run, in the normalized variables of spec §5.
#[derive(Debug, Clone, PartialEq)]
pub struct FrettingParams {
    /// `χ = u_A / u_max`, `0 < χ < 1` (partial slip).
    pub chi: f64,
    /// Grading exponent `k ∈ (−1, 1)` of `E(z) = E₀ (z/z₀)^k` (0: homogeneous). The normalized run
    /// depends on `k` alone: `E₀`, `z₀`, `ν`, `R`, `d` and `μ` enter only the scales `a₀`, `F₀`,
    /// `u_max`, `N₀` (docs/fretting-wear.md, "Graded media").
    pub k: f64,
    /// Grid nodes `N`.
    pub nodes: usize,
    /// Wear step `Δτ > 0`.
    pub dtau: f64,
    /// Final `τ`.
    pub tau_end: f64,
    /// Domain size `L/a₀ ≥ 1.45` (the contact grows to `r* < √2 a₀`, spec §7 P8).
    pub length: f64,
    /// `τ` at which the state is recorded (`τ_end` is always recorded).
    pub snapshots: Vec<f64>,
    /// Backend of the profile and stress transforms.
    pub backend: Backend,
}

impl Default for FrettingParams {
    /// The reference run of spec §5: χ = 0.5, N = 2001, L = 1.6 a₀, Δτ = 1e-3, τ_end = 30.
    fn default() -> Self {
        Self {
            chi: 0.5,
            k: 0.0,
            nodes: 2001,
            dtau: 1e-3,
            tau_end: 30.0,
            length: 1.6,
            snapshots: vec![0.1, 1.0, 3.0, 10.0, 30.0],
            backend: Backend::Fft,
        }
    }
}

impl FrettingParams {
    /// Smallest domain accepted (spec §7 P8).
    pub const MIN_LENGTH: f64 = 1.45;

    /// The domain a run of `chi`, `k` gets when none is given: the reference run's `L = 1.6 a₀`
    /// (homogeneous, `r* < √2 a₀`), or `1.15 r*` when the graded contact grows further.
    pub fn default_length(chi: f64, k: f64) -> f64 {
        if k == 0.0 {
            1.6
        } else {
            (1.15 * crate::limit::limit_contact_radius(chi, k)).max(1.6)
        }
    }

    /// Checks every parameter.
    pub fn validate(&self) -> Result<(), FrettingError> {
        let bad = |name, value, allowed: &str| FrettingError::InvalidParameter {
            name,
            value,
            allowed: allowed.to_string(),
        };
        if !(self.chi.is_finite() && self.chi > 0.0 && self.chi < 1.0) {
            return Err(bad("chi", self.chi, "in (0, 1) (partial slip)"));
        }
        if !(self.k.is_finite() && self.k > -1.0 && self.k < 1.0) {
            return Err(bad(
                "grading exponent k",
                self.k,
                "in (−1, 1) (E ∝ z^k; k = 0 homogeneous)",
            ));
        }
        if self.nodes < 64 {
            return Err(bad("n", self.nodes as f64, "≥ 64"));
        }
        if !(self.dtau.is_finite() && self.dtau > 0.0) {
            return Err(bad("dtau", self.dtau, "finite and > 0"));
        }
        if !(self.tau_end.is_finite() && self.tau_end > 0.0) {
            return Err(bad("tau_end", self.tau_end, "finite and > 0"));
        }
        if self.tau_end / self.dtau > 1e9 {
            return Err(bad("tau_end/dtau", self.tau_end / self.dtau, "≤ 1e9 steps"));
        }
        if !(self.length.is_finite() && self.length >= Self::MIN_LENGTH) {
            return Err(bad(
                "length",
                self.length,
                "≥ 1.45 (L/a0; the contact grows to r* < √2 a0)",
            ));
        }
        let r_star = crate::limit::limit_contact_radius(self.chi, self.k);
        if self.length < 1.02 * r_star {
            return Err(bad(
                "length",
                self.length,
                &format!(
                    "≥ {:.4} (L/a0 ≥ 1.02 r*/a0: the contact grows to r* = {r_star:.4} a0 at χ = {}, k = {})",
                    1.02 * r_star,
                    self.chi,
                    self.k
                ),
            ));
        }
        if let Some(&t) = self
            .snapshots
            .iter()
            .find(|t| !(t.is_finite() && **t > 0.0))
        {
            return Err(bad("snapshots", t, "finite and > 0"));
        }
        // Explicit Euler: the stable step scales with the radial spacing near the edge
        // (spec §7 P10; `step_limit`).
        let grid =
            SquaredGrid::new(self.nodes, self.length).map_err(halfspace_mdr::MdrError::from)?;
        let limit = Self::step_limit(&grid, self.k);
        if self.dtau > limit {
            return Err(bad(
                "dtau",
                self.dtau,
                &format!(
                    "≤ {limit:.2e} for N = {}, L = {}, k = {} (explicit wear step stability)",
                    self.nodes, self.length, self.k
                ),
            ));
        }
        Ok(())
    }

    /// An a-priori bound on the explicit step, `Δτ ≤ 1.5 (h/L)` for `k ≥ 0` and
    /// `Δτ ≤ 1.5 · 2^k (h/L)^{1−k}` for `k < 0`, with `h = L²/(N−1)`. The map `f → p` is of order
    /// `1 − k` in the radius (`f → g` and `g → p` are each of order `(1−k)/2`, spec §4.1 and §4.4),
    /// so the stable explicit step scales as `(h/L)^{1−k}`. Measured with the edge between nodes
    /// (runs to τ = 3, χ = 0.5 and 0.9, N = 1001 and 2001): `k = 0` and `0.5` stable at
    /// `1.5 h/L`; the largest stable steps at χ = 0.9 were 5.5e-4 / 2.5e-4 (k = −0.25, N = 1001 /
    /// 2001) and 1.4e-4 / 4.2e-5 (k = −0.5), 1.4 to 1.7 times this bound (χ = 0.5 tolerates
    /// more). Larger steps are refused before the run; the run itself watches the contact radius
    /// (`FrettingError::Unstable`).
    pub fn step_limit(grid: &SquaredGrid, k: f64) -> f64 {
        let ratio = grid.step() / grid.length();
        if k < 0.0 {
            1.5 * 2f64.powf(k) * ratio.powf(1.0 - k)
        } else {
            1.5 * ratio
        }
    }

    /// The step a run gets when none is given: the reference run's `Δτ = 10⁻³`, or
    /// [`FrettingParams::step_limit`] where that is smaller (fine grids, `k < 0`).
    pub fn default_step(nodes: usize, length: f64, k: f64) -> f64 {
        SquaredGrid::new(nodes, length)
            .map(|grid| Self::step_limit(&grid, k).min(1e-3))
            .unwrap_or(1e-3)
    }

    /// Number of wear steps, `round(τ_end/Δτ)`.
    pub fn total_steps(&self) -> u64 {
        (self.tau_end / self.dtau).round() as u64
    }

    /// Steps at which snapshots are taken (sorted, unique, including the last step).
    pub fn snapshot_steps(&self) -> Vec<u64> {
        let mut steps: Vec<u64> = self
            .snapshots
            .iter()
            .map(|t| ((t / self.dtau).round() as u64).min(self.total_steps()))
            .chain(std::iter::once(self.total_steps()))
            .collect();
        steps.sort_unstable();
        steps.dedup();
        steps
    }
}
