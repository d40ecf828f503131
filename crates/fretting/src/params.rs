use halfspace_numerics::{Backend, SquaredGrid};

use crate::FrettingError;

/// How the wear law `∂f̃/∂τ = p̃ Δũ` is integrated in `τ` (docs/fretting-wear.md, "Time
/// integration").
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TimeStepping {
    /// ROS2 (Verwer et al. 1999, linearly implicit, L-stable) with error control: the embedded
    /// first-order estimate `Δτ/2 |k₁ + k₂|`, largest over the nodes, is kept ≤ `tolerance`
    /// (units of `d`); steps land on the snapshot times.
    Adaptive {
        /// Local error per step, `max_i |f̃_i − f̂_i|` (units of `d`).
        tolerance: f64,
    },
    /// ROS2 at the fixed step `dtau` (no error control; stable at any step).
    Fixed {
        /// The step `Δτ`.
        dtau: f64,
    },
    /// Explicit Euler at the fixed step `dtau` (the reference path; stable only below
    /// [`FrettingParams::step_limit`]).
    ExplicitEuler {
        /// The step `Δτ`.
        dtau: f64,
    },
}

impl TimeStepping {
    /// The default local error tolerance of [`TimeStepping::Adaptive`].
    pub const DEFAULT_TOLERANCE: f64 = 1e-4;

    /// The fixed step, if any.
    pub fn fixed_step(&self) -> Option<f64> {
        match *self {
            Self::Adaptive { .. } => None,
            Self::Fixed { dtau } | Self::ExplicitEuler { dtau } => Some(dtau),
        }
    }

    /// Short name: `adaptive`, `fixed` (ROS2) or `explicit-euler`.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Adaptive { .. } => "adaptive",
            Self::Fixed { .. } => "fixed",
            Self::ExplicitEuler { .. } => "explicit-euler",
        }
    }
}

/// How the wear run evaluates Eq. 7 / 23 (`g` from the worn profile's samples `f̃_i`;
/// docs/fretting-wear.md, "The profile transform of the worn profile").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GapTransform {
    /// The paper's Eq. 7 as written: the slope `f̂' = D[f̃]` by second-order central differences,
    /// the trapezoid power sum and its central difference, with the parabolic split
    /// (`ProfileTransform::slope_to_equivalent`; docs/theory-mdr.md#profile-transform). Its
    /// central differences do not see the node-to-node mode `(−1)^i` of `f̃`, which the wear then
    /// leaves undamped near the contact edge (the default before stop 45, and what a record
    /// without the option means: [`GapTransform::LEGACY`]).
    CentralDifferences,
    /// Exact for a profile linear in `ξ = r²` between nodes (`ProfileTransform::values_to_equivalent`):
    /// cell slopes and the integrated kernel, no difference at the nodes, so every mode of `f̃`
    /// moves `g` and is worn down; the same order `1 + γ` on smooth profiles. The default (with
    /// the edge cells, [`FrettingParams::edge_cells`]; docs/fretting-wear.md, "The defaults").
    #[default]
    PiecewiseLinear,
}

impl GapTransform {
    /// The transform of a run directory, checkpoint or manifest that records none: those were
    /// made before the option was recorded for every run, when the central differences were the
    /// default (and the edge cells off).
    pub const LEGACY: Self = Self::CentralDifferences;

    /// The name in configs, results and checkpoints: `central-differences` or `piecewise-linear`.
    pub fn name(&self) -> &'static str {
        match self {
            Self::CentralDifferences => "central-differences",
            Self::PiecewiseLinear => "piecewise-linear",
        }
    }

    /// The explicit Euler step bound's factor against [`FrettingParams::step_limit`] (the
    /// central differences'): 1, and 0.35 for the piecewise-linear transform, whose largest
    /// eigenvalue is the node-to-node mode's (measured at N = 801 to τ = 1: stable and within
    /// 2e-4 of smaller steps at 0.4 of the bound for k = 0 and 0.5 and at 0.39 for k = −0.5,
    /// χ = 0.9; at 0.67 (k = 0) off by 2e-3 in a/a₀, at 0.9 (k = −0.5) unstable; 0.35 keeps a
    /// margin below the smallest stable factor measured).
    pub fn explicit_step_factor(&self) -> f64 {
        match self {
            Self::CentralDifferences => 1.0,
            Self::PiecewiseLinear => 0.35,
        }
    }

    /// The transform named `name` ([`GapTransform::name`]).
    pub fn from_name(name: &str) -> Option<Self> {
        [Self::CentralDifferences, Self::PiecewiseLinear]
            .into_iter()
            .find(|t| t.name() == name)
    }
}

/// Parameters of a fretting-wear run, in the normalized variables of docs/theory-mdr.md#fretting-wear.
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
    /// The time integration: error-controlled ROS2 (default), ROS2 at a fixed step, or explicit
    /// Euler (the reference).
    pub stepping: TimeStepping,
    /// Final `τ`.
    pub tau_end: f64,
    /// Domain size `L/a₀ ≥ 1.45` (the contact grows to `r* < √2 a₀`, docs/theory-mdr.md#p8-domain-size).
    pub length: f64,
    /// `τ` at which the state is recorded (`τ_end` is always recorded).
    pub snapshots: Vec<f64>,
    /// Backend of the profile and stress transforms.
    pub backend: Backend,
    /// The discretization of Eq. 7 / 23 for the worn profile.
    pub gap_transform: GapTransform,
    /// The wear rate of the cells at the contact edge as the cell mean of `p Δu` (the edge
    /// pressure `π (a² − ξ)^γ` integrated over the cell) instead of the nodal `p Δu`
    /// (docs/fretting-wear.md, "Edge cells"); on by default (off in a record that does not
    /// name it, made before stop 45).
    pub edge_cells: bool,
}

impl Default for FrettingParams {
    /// The reference run of docs/theory-mdr.md#fretting-wear: χ = 0.5, N = 2001, L = 1.6 a₀, τ_end = 30, adaptive steps at
    /// the default tolerance.
    fn default() -> Self {
        Self {
            chi: 0.5,
            k: 0.0,
            nodes: 2001,
            stepping: TimeStepping::Adaptive {
                tolerance: TimeStepping::DEFAULT_TOLERANCE,
            },
            tau_end: 30.0,
            length: 1.6,
            snapshots: vec![0.1, 1.0, 3.0, 10.0, 30.0],
            backend: Backend::Fft,
            gap_transform: GapTransform::PiecewiseLinear,
            edge_cells: true,
        }
    }
}

/// Bytes a node of the wear run takes, rounded up from the measured ≈ 3.7 kB
/// ([`FrettingParams::validate`] refuses a grid that would not fit).
const WEAR_BYTES_PER_NODE: f64 = 5000.0;

impl FrettingParams {
    /// Smallest domain accepted (docs/theory-mdr.md#p8-domain-size).
    pub const MIN_LENGTH: f64 = 1.45;

    /// The largest `τ_end`: the worn contact reaches Popov's limit by `τ ≈ 5` (k = 0) to
    /// `τ ≈ 30` (graded, k = −0.5, χ = 0.9; docs/fretting-wear.md), so `τ_end ≤ 1e6` leaves four
    /// decades and refuses an absurd request up front (adaptive steps have no step count to
    /// bound it, and their smallest step, `1e-14 τ_end`, would grow with it).
    pub const MAX_TAU_END: f64 = 1e6;

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
        // Refused up front, with the estimate, instead of aborting in the allocator: the run's
        // vectors, band, plans and kernels take ≈ 3.7 kB a node (`/usr/bin/time` of
        // `halfspace fretting-wear --n 8001 / 64001 --tau-end 0.001`: 48.6 / 245.9 MB peak RSS
        // since the shorter plans' rungs at the fast lengths, 47.4 / 216.9 MB before; 43.8 /
        // 197.9 MB before the packed FFTs); the estimate rounds up.
        halfspace_numerics::memory::check_fits(
            "the MDR wear run",
            WEAR_BYTES_PER_NODE * self.nodes as f64,
        )
        .map_err(halfspace_mdr::MdrError::from)?;
        if !(self.tau_end.is_finite() && self.tau_end > 0.0 && self.tau_end <= Self::MAX_TAU_END) {
            return Err(bad(
                "tau_end",
                self.tau_end,
                "finite, > 0 and ≤ 1e6 (the contact reaches Popov's limit by τ ≈ 10–100)",
            ));
        }
        match self.stepping {
            TimeStepping::Adaptive { tolerance } => {
                if !(1e-12..=0.1).contains(&tolerance) {
                    return Err(bad(
                        "tol",
                        tolerance,
                        "in [1e-12, 0.1] (local error, units of d)",
                    ));
                }
            }
            TimeStepping::Fixed { dtau } | TimeStepping::ExplicitEuler { dtau } => {
                if !(dtau.is_finite() && dtau > 0.0) {
                    return Err(bad("dtau", dtau, "finite and > 0"));
                }
                if self.tau_end / dtau > 1e9 {
                    return Err(bad("tau_end/dtau", self.tau_end / dtau, "≤ 1e9 steps"));
                }
            }
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
        // (docs/theory-mdr.md#p10-explicit-wear-step; `step_limit`).
        let grid =
            SquaredGrid::new(self.nodes, self.length).map_err(halfspace_mdr::MdrError::from)?;
        let limit = Self::step_limit(&grid, self.k) * self.gap_transform.explicit_step_factor();
        match self.stepping {
            TimeStepping::ExplicitEuler { dtau } if dtau > limit => Err(bad(
                "dtau",
                dtau,
                &format!(
                    "≤ {limit:.2e} for N = {}, L = {}, k = {}, the {} transform (explicit wear \
                     step stability; the implicit steps have no such bound)",
                    self.nodes,
                    self.length,
                    self.k,
                    self.gap_transform.name()
                ),
            )),
            _ => Ok(()),
        }
    }

    /// An a-priori bound on the explicit step, `Δτ ≤ 1.5 (h/L)` for `k ≥ 0` and
    /// `Δτ ≤ 1.5 · 2^k (h/L)^{1−k}` for `k < 0`, with `h = L²/(N−1)`. The map `f → p` is of order
    /// `1 − k` in the radius (`f → g` and `g → p` are each of order `(1−k)/2`, docs/theory-mdr.md#graded-profile-transform and docs/theory-mdr.md#graded-pressure),
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

    /// The explicit step of the central differences: the reference run's `Δτ = 10⁻³`, or
    /// [`FrettingParams::step_limit`] where that is smaller (fine grids, `k < 0`). An explicit
    /// Euler run of another transform (the default piecewise-linear one) takes it times
    /// [`GapTransform::explicit_step_factor`]; [`FrettingParams::validate`] refuses more.
    pub fn default_step(nodes: usize, length: f64, k: f64) -> f64 {
        SquaredGrid::new(nodes, length)
            .map(|grid| Self::step_limit(&grid, k).min(1e-3))
            .unwrap_or(1e-3)
    }

    /// Number of wear steps of a fixed-step run, `round(τ_end/Δτ)` (`None` when adaptive).
    pub fn total_steps(&self) -> Option<u64> {
        self.stepping
            .fixed_step()
            .map(|dtau| (self.tau_end / dtau).round() as u64)
    }

    /// The times at which snapshots are taken (sorted, unique, ending with `τ_end`). With a fixed
    /// step each is rounded to the nearest step, `round(τ/Δτ) Δτ`; adaptive steps land on them.
    pub fn snapshot_times(&self) -> Vec<f64> {
        let round = |t: f64| match self.stepping.fixed_step() {
            Some(dtau) => ((t / dtau).round() * dtau).min(self.fixed_end()),
            None => t.min(self.tau_end),
        };
        let mut times: Vec<f64> = self
            .snapshots
            .iter()
            .map(|&t| round(t))
            .chain(std::iter::once(self.fixed_end()))
            .collect();
        times.sort_by(f64::total_cmp);
        times.dedup();
        times
    }

    /// `τ` after `steps` fixed steps, `steps · Δτ`, landing exactly on [`Self::fixed_end`] at the
    /// last step (`None` when adaptive).
    pub fn fixed_tau(&self, steps: u64) -> Option<f64> {
        let dtau = self.stepping.fixed_step()?;
        Some(if Some(steps) == self.total_steps() {
            self.fixed_end()
        } else {
            steps as f64 * dtau
        })
    }

    /// The final `τ`: `τ_end`, or `round(τ_end/Δτ) Δτ` with a fixed step.
    pub fn fixed_end(&self) -> f64 {
        match (self.stepping.fixed_step(), self.total_steps()) {
            (Some(dtau), Some(steps)) => steps as f64 * dtau,
            _ => self.tau_end,
        }
    }
}
