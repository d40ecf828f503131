use halfspace_numerics::{Backend, SquaredGrid};

use crate::FrettingError;

/// Parameters of a fretting-wear run, in the normalized variables of spec §5.
#[derive(Debug, Clone, PartialEq)]
pub struct FrettingParams {
    /// `χ = u_A / u_max`, `0 < χ < 1` (partial slip).
    pub chi: f64,
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
        if let Some(&t) = self
            .snapshots
            .iter()
            .find(|t| !(t.is_finite() && **t > 0.0))
        {
            return Err(bad("snapshots", t, "finite and > 0"));
        }
        // Explicit Euler: the stable step scales with the smallest radial spacing near the edge,
        // h/(2L) (spec §7 P10: N = 2001, L = 1.6: 2e-3 diverged, 1e-3 was stable).
        let grid =
            SquaredGrid::new(self.nodes, self.length).map_err(halfspace_mdr::MdrError::from)?;
        let limit = Self::step_limit(&grid);
        if self.dtau > limit {
            return Err(bad(
                "dtau",
                self.dtau,
                &format!(
                    "≤ {limit:.2e} for N = {}, L = {} (explicit wear step stability)",
                    self.nodes, self.length
                ),
            ));
        }
        Ok(())
    }

    /// An a-priori bound on the explicit step: `3 h/(2L)` with `h = L²/(N−1)` — the observed
    /// stability limit of spec §7 P10 lies between 1 and 2.5 times `h/(2L)`, so larger steps are
    /// refused before the run; the run itself watches the contact radius (`FrettingError::Unstable`).
    pub fn step_limit(grid: &SquaredGrid) -> f64 {
        1.5 * grid.step() / grid.length()
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
