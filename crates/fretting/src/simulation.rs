use halfspace_mdr::{CellStressTransform, Material, MdrError, ProfileTransform};
use halfspace_numerics::{diff::derivative_uniform, SquaredGrid};

use crate::limit::{
    annulus_response, initial_profile, limit_contact_radius, limit_wear_volume, limiting_profile,
    stick_radius,
};
use crate::{FrettingError, FrettingParams};

/// `c_N` of the normalized problem: with `q̃ = c̃_N (1 − g̃)`, Eq. 29 (Eq. 17 at `k = 0`) gives
/// `p̃ = p a₀²/F₀`, `p̃ = (c̃_N/π) ∫ g̃'/(x̃² − r̃²)^{(1−k)/2}` with `c̃_N = (1+k)(3+k)/4` (graded Hertz,
/// spec §4.5: `F₀ = 4 c_N a₀^{3+k} / ((1+k)²(3+k)R)`, `a₀² = (1+k)Rd`); `3/4` homogeneous (spec §5).
pub fn normalized_modulus(k: f64) -> f64 {
    0.25 * (1.0 + k) * (3.0 + k)
}

/// The state at one recorded `τ`.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Step index (`τ = step · Δτ`).
    pub step: u64,
    /// Profile `f̃` on the grid nodes.
    pub profile: Vec<f64>,
    /// Pressure `p̃` on the grid nodes (of the step that starts from this profile).
    pub pressure: Vec<f64>,
    /// Slip per cycle `Δũ` on the grid nodes.
    pub slip: Vec<f64>,
    /// Contact radius `a/a₀`.
    pub contact_radius: f64,
}

/// Everything a run needs to continue: the step, the profile, the histories and the snapshots.
/// A run resumed from a state ends bit for bit where the uninterrupted run ends.
#[derive(Debug, Clone, PartialEq)]
pub struct FrettingState {
    /// Steps done.
    pub step: u64,
    /// Profile `f̃` on the grid nodes.
    pub profile: Vec<f64>,
    /// `a/a₀` after each step (index = step − 1).
    pub contact_radius_history: Vec<f64>,
    /// Snapshots taken so far.
    pub snapshots: Vec<Snapshot>,
}

/// The per-cycle loop of spec §5, planned once: no allocation per step.
pub struct FrettingSimulation {
    params: FrettingParams,
    grid: SquaredGrid,
    profile_tf: ProfileTransform,
    stress_tf: CellStressTransform,
    limit: Vec<f64>,
    stick: f64,
    r_star: f64,
    slope: Vec<f64>,
    g: Vec<f64>,
    q: Vec<f64>,
    p: Vec<f64>,
    slip: Vec<f64>,
    state: FrettingState,
    snapshot_steps: Vec<u64>,
    /// Edge node of the current profile when g, p and the slip are up to date with it.
    current_edge: Option<usize>,
    /// `a/a₀` of the current profile (the edge between nodes), valid with `current_edge`.
    contact_radius: f64,
}

impl FrettingSimulation {
    /// A new run from the initial paraboloid `f̃₀ = r̃²/2`.
    pub fn new(params: FrettingParams) -> Result<Self, FrettingError> {
        params.validate()?;
        let grid = SquaredGrid::new(params.nodes, params.length).map_err(MdrError::from)?;
        let profile = grid
            .coordinates()
            .iter()
            .map(|&r| initial_profile(r, params.k))
            .collect();
        let state = FrettingState {
            step: 0,
            profile,
            contact_radius_history: Vec::new(),
            snapshots: Vec::new(),
        };
        Self::with_state(params, grid, state)
    }

    /// Continues a run from a saved state (`--resume`), checked for content first
    /// (`checkpoint::check_state`: shapes, finite values, ranges, monotone history).
    pub fn resume(params: FrettingParams, state: FrettingState) -> Result<Self, FrettingError> {
        params.validate()?;
        let grid = SquaredGrid::new(params.nodes, params.length).map_err(MdrError::from)?;
        crate::checkpoint::check_state(
            &state,
            &params,
            &grid,
            limit_contact_radius(params.chi, params.k),
        )?;
        Self::with_state(params, grid, state)
    }

    fn with_state(
        params: FrettingParams,
        grid: SquaredGrid,
        state: FrettingState,
    ) -> Result<Self, FrettingError> {
        let n = params.nodes;
        // The transforms need only k (the stress transform takes q̃ with c̃_N in it).
        let material = if params.k == 0.0 {
            Material::from_e_star(normalized_modulus(0.0))?
        } else {
            Material::power_law(1.0, 1.0, 0.0, params.k)?
        };
        let limit = grid
            .coordinates()
            .iter()
            .map(|&r| limiting_profile(r, params.chi, params.k))
            .collect();
        Ok(Self {
            profile_tf: ProfileTransform::new(n, &material, params.backend)?,
            stress_tf: CellStressTransform::new(n, &material, params.backend)?,
            limit,
            stick: stick_radius(params.chi),
            r_star: limit_contact_radius(params.chi, params.k),
            slope: vec![0.0; n],
            g: vec![0.0; n],
            q: vec![0.0; n],
            p: vec![0.0; n],
            slip: vec![0.0; n],
            snapshot_steps: params.snapshot_steps(),
            grid,
            params,
            state,
            current_edge: None,
            contact_radius: 1.0,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &FrettingParams {
        &self.params
    }

    /// The grid (`r̃_i = √(i h)`).
    pub fn grid(&self) -> &SquaredGrid {
        &self.grid
    }

    /// The current state (for checkpoints and results).
    pub fn state(&self) -> &FrettingState {
        &self.state
    }

    /// `r*/a₀`, the limit of the contact radius.
    pub fn limit_contact_radius(&self) -> f64 {
        self.r_star
    }

    /// Popov's limiting profile `f̃∞` on the grid nodes.
    pub fn limiting_profile(&self) -> &[f64] {
        &self.limit
    }

    /// The final wear volume over `π a₀² d` ([`limit_wear_volume`]).
    pub fn limit_wear_volume(&self) -> f64 {
        limit_wear_volume(self.params.chi, self.params.k)
    }

    /// The wear volume so far over `π a₀² d`: `Ṽ = 2 ∫ (f̃ − f̃₀) r̃ dr̃ = ∫ (f̃ − f̃₀) dξ`, by the
    /// trapezoid rule on the grid (uniform in `ξ = r̃²`).
    pub fn wear_volume(&self) -> f64 {
        let k = self.params.k;
        let worn: Vec<f64> = self
            .grid
            .coordinates()
            .iter()
            .zip(&self.state.profile)
            .map(|(&r, &f)| f - initial_profile(r, k))
            .collect();
        halfspace_numerics::quad::trapezoid_uniform(&worn, self.grid.step())
    }

    /// `max |f̃ − f̃∞|` over `c̃ + margin < r̃ ≤ r*`: how far the worn profile is from Popov's limit
    /// away from the stick edge (where `f̃∞ − f̃₀ ~ (r − c)^{(1−k)/2}` is resolved by one node).
    pub fn limit_deviation(&self, margin: f64) -> f64 {
        let from = self.stick + margin;
        self.grid
            .coordinates()
            .iter()
            .zip(&self.state.profile)
            .zip(&self.limit)
            .filter(|((&r, _), _)| r > from && r <= self.r_star)
            .map(|((_, f), fl)| (f - fl).abs())
            .fold(0.0, f64::max)
    }

    /// Whether all steps are done.
    pub fn is_finished(&self) -> bool {
        self.state.step >= self.params.total_steps()
    }

    /// `f̃(a₀)`, linear in `ξ` between the nodes around `r̃ = 1`.
    pub fn profile_at_a0(&self) -> f64 {
        let t = self.grid.fractional_index(1.0);
        let i = (t.floor() as usize).min(self.grid.len() - 2);
        let w = t - i as f64;
        (1.0 - w) * self.state.profile[i] + w * self.state.profile[i + 1]
    }

    /// One wear step (spec §5, per-cycle loop, with the edge between nodes): `f → g` (Eq. 7 / 23),
    /// the contact edge `a` where the linear interpolant of `g` beyond the outermost node with
    /// `g < d` reaches `d`, `q = c̃_N max(d − g, 0)`, `q → p` by product integration with that
    /// edge ([`CellStressTransform`], clipped ≥ 0), the slip `Δũ`, and `f̃ ← f̃ + Δτ p̃ Δũ`. Takes a
    /// snapshot first when this step is a snapshot step.
    ///
    /// Spec §5 (and the paper) cut `q` at the first node outside and use Eq. 17/29; that pressure
    /// jumps by `O(1)` each time the edge crosses a node and the run does not converge under grid
    /// refinement (docs/fretting-wear.md, "The contact edge between nodes").
    pub fn step(&mut self) -> Result<(), FrettingError> {
        let edge = self.current()?;
        let step = self.state.step;
        if self.snapshot_steps.binary_search(&step).is_ok()
            && !self.state.snapshots.iter().any(|s| s.step == step)
        {
            self.take_snapshot();
        }
        if self.is_finished() {
            return Ok(());
        }
        let dtau = self.params.dtau;
        for i in 0..edge {
            self.state.profile[i] += dtau * self.p[i] * self.slip[i];
        }
        self.state.step += 1;
        self.current_edge = None;
        self.current()?;
        let a = self.contact_radius;
        self.state.contact_radius_history.push(a);
        // Wear only raises f, so a/a₀ approaches r* from below; three cells of slack for the
        // grazing end phase, where g ≈ d on the whole annulus and the edge jitters (measured up to
        // 2.7 cells, k = −0.5, χ = 0.9, N = 2001); an unstable step overshoots further (spec §7 P10).
        let cell = self.grid.step() / (2.0 * self.r_star);
        if a > self.r_star + 3.0 * cell {
            return Err(FrettingError::Unstable {
                tau: self.state.step as f64 * dtau,
                contact_radius: a,
                limit: self.r_star,
                suggested: 0.5 * dtau,
            });
        }
        if self.is_finished() && self.snapshot_steps.binary_search(&self.state.step).is_ok() {
            self.take_snapshot();
        }
        Ok(())
    }

    /// The edge of the current profile, computing g, p and the slip only when the profile changed
    /// (one profile and one stress transform per step).
    fn current(&mut self) -> Result<usize, FrettingError> {
        match self.current_edge {
            Some(edge) => Ok(edge),
            None => {
                let edge = self.contact_state()?;
                self.current_edge = Some(edge);
                Ok(edge)
            }
        }
    }

    /// Computes g, p, the slip and `a/a₀` of the current profile; returns the first node outside
    /// the contact.
    fn contact_state(&mut self) -> Result<usize, FrettingError> {
        let n = self.grid.len();
        let h = self.grid.step();
        derivative_uniform(&self.state.profile, h, &mut self.slope).map_err(MdrError::from)?;
        self.profile_tf
            .slope_to_equivalent(&self.grid, &mut self.slope, &mut self.g)?;
        let outermost = self.g.iter().rposition(|&g| g < 1.0).unwrap_or(0);
        let edge = outermost + 1;
        if edge >= n - 1 {
            return Err(FrettingError::ContactOutsideGrid {
                length: self.params.length,
            });
        }
        // The edge between the last node with g < d and the next one, where the linear
        // interpolant of g reaches d: a² = ξ_last + θh (θ ∈ (0, 1]).
        let last = outermost;
        let theta =
            ((1.0 - self.g[last]) / (self.g[edge] - self.g[last])).clamp(f64::MIN_POSITIVE, 1.0);
        self.contact_radius = (self.grid.squared(last) + theta * h).sqrt();
        let modulus = normalized_modulus(self.params.k);
        for i in 0..=last {
            self.q[i] = modulus * (1.0 - self.g[i]).max(0.0);
        }
        let m = last + 1;
        self.stress_tf
            .line_load_to_stress(&self.grid, &self.q[..m], theta, &mut self.p[..m])?;
        self.p[..m].iter_mut().for_each(|v| *v = v.max(0.0));
        self.p[m..].fill(0.0);
        let (chi, k) = (self.params.chi, self.params.k);
        for i in 0..n {
            let r = self.grid.coordinate(i);
            self.slip[i] = if i < edge && r > self.stick {
                // slip_per_cycle with the stored f̃∞ (same operations).
                let s = 4.0
                    * ((self.state.profile[i] - self.limit[i]) / chi
                        + annulus_response(r, self.stick, k));
                s.max(0.0)
            } else {
                0.0
            };
        }
        Ok(edge)
    }

    fn take_snapshot(&mut self) {
        self.state.snapshots.push(Snapshot {
            step: self.state.step,
            profile: self.state.profile.clone(),
            pressure: self.p.clone(),
            slip: self.slip.clone(),
            contact_radius: self.contact_radius,
        });
    }

    /// Runs until `τ_end` (or until `stop` returns true after a step, for checkpoints and progress).
    pub fn run(&mut self, mut after_step: impl FnMut(&Self) -> bool) -> Result<(), FrettingError> {
        while !self.is_finished() {
            self.step()?;
            if after_step(self) {
                return Ok(());
            }
        }
        // Make sure the final snapshot exists (a run resumed at its last step).
        if !self
            .state
            .snapshots
            .iter()
            .any(|s| s.step == self.state.step)
        {
            self.current()?;
            self.take_snapshot();
        }
        Ok(())
    }
}
