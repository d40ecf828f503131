//! Contact with inhomogeneities below the surface: the outer loop of \[LN11\] Fig. 2 (docs/theory-sam.md#nested-loops).
//! Per increment, until the surface eigen-displacements stop changing:
//!
//! 1. contact solve with `h = h₀ + u₃^eig` and `Δu ∋ u_α^eig` ([`ContactProblem::solve`]);
//! 2. applied strain `ε⁰` at the inclusion cells from `p, q` (Love, docs/theory-sam.md#love-rectangle-stresses);
//! 3. EIM: `ε*` from the equivalency equations (docs/theory-sam.md#solving-the-eim-equations), warm-started;
//! 4. correction pressure and eigen-displacements `u^eig` (docs/theory-sam.md#eigen-displacements);
//! 5. `u^eig ← u^eig_old + ω (u^eig − u^eig_old)`; stop when
//!    `max|u₃^eig − u₃^eig,old| / max|u₃^eig| < tol` (and the same for `u_α^eig` with friction).
//!
//! The friction history is committed only when the increment has converged (docs/theory-sam.md#history-variables).

use crate::contact::{shift_for_force, ContactProblem, IncrementInfo};
use crate::eim::{
    EimFields, EimInfo, EimParams, EimSystem, InclusionSet, Inhomogeneity, SurfaceResponse,
};
use crate::normal::NormalLoad;
use crate::SamError;
use halfspace_numerics::anderson::Anderson;

/// Parameters of the outer loop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NestedParams {
    /// Relative change of the eigen-displacements below which the increment has converged
    /// (docs/theory-sam.md#nested-loops: 1e-6).
    pub tolerance: f64,
    /// Outer iteration limit.
    pub max_outer: usize,
    /// Under-relaxation `ω ∈ (0, 1]`.
    pub relaxation: f64,
    /// EIM solver parameters.
    pub eim: EimParams,
    /// Contact solves of the early outer passes to the looser tolerance that the outer loop's last
    /// change allows ([`ContactProblem::solve_loosely`], alternation tolerance
    /// `clamp(10⁻² · change, tol, 10⁻³)`); the increment converges only after a pass at the full
    /// tolerance.
    pub inexact_contact: bool,
    /// Anderson acceleration of the outer fixed point `u^eig ← G(u^eig)`: history depth (0: the
    /// relaxed Picard iteration of docs/theory-sam.md#nested-loops), mixing `ω` = [`NestedParams::relaxation`]
    /// ([`halfspace_numerics::anderson`]).
    pub anderson_depth: usize,
    /// Start each increment from the secant prediction `2x_n − x_{n−1}` of the eigenstrains and
    /// eigen-displacements of the last two increments (instead of `x_n`): on the loop's equal
    /// steps it removes most of the first outer change.
    pub predictor: bool,
    /// In a fretting-wear run ([`crate::drivers::fretting_wear3d::FrettingWear3d`]), start each
    /// increment of a computed cycle from the same increment of the last two computed cycles
    /// (the cycle predictor, docs/wear3d.md#the-cycle-predictor) instead of the secant
    /// prediction; only with [`NestedParams::predictor`]. Not read by the nested loop itself.
    pub cycle_predictor: bool,
    /// The EIM of an outer pass is solved to this factor `η` times the last outer change
    /// (clamped to `[eim.tolerance, 10⁻³]`; docs/theory-sam.md#outer-loop-tolerances): default
    /// 3·10⁻³ ([`DEFAULT_EIM_CHANGE_FACTOR`]); [`REFERENCE_EIM_CHANGE_FACTOR`] = 10⁻³ on the
    /// reference path it was checked against.
    pub eim_change_factor: f64,
    /// How the body's surface response enters each increment: the nested contact ↔ EIM loop of
    /// \[LN11\] Fig. 2 (the reference), or the surface-response operator built once
    /// (docs/theory-sam.md#surface-response-operator).
    pub body: BodyResponse,
    /// When an increment's outer loop stops (docs/theory-sam.md#the-contraction-stopping-rule):
    /// by default [`OuterStopping::Contraction`] with safety 1.
    pub stopping: OuterStopping,
}

/// The outer loop's stopping rule (docs/theory-sam.md#the-contraction-stopping-rule).
///
/// Pass `k` solves the contact with the eigen-displacements `u_{k−1}`, then the EIM, and measures
/// the change `c_k = max|G(u_{k−1}) − u_{k−1}| / max|G(u_{k−1})|`; the state an increment returns
/// is a contact solve whose `u` the next EIM solve would change by less than the tolerance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OuterStopping {
    /// Stop after the pass whose measured change `c_k` is below the tolerance (its contact solve
    /// at the full tolerance): that pass's EIM solve verified the state returned, its contact
    /// solve (\[LN11\] Fig. 2's loop; the reference).
    Verified,
    /// Also stop when the change the next pass would measure, predicted from the slower of the
    /// last two contractions `ρ = max(c_k / c_{k−1}, c_{k−1} / c_{k−2})` (from the third pass,
    /// `ρ ≤` [`CONTRACTION_MAX_RATE`]) as `ρ c_k`, is below `tolerance / safety`: the next pass's
    /// contact solve (at the full tolerance) is returned without the EIM solve, the surface
    /// fields and the traction strains that would only have verified it
    /// ([`NestedInfo::predicted_stop`]). The state is bit for bit the contact solve that
    /// [`OuterStopping::Verified`]'s next pass makes when that pass runs at the full tolerance.
    Contraction {
        /// Safety factor `s ≥ 1` on the predicted change.
        safety: f64,
    },
}

/// The largest contraction of the outer loop [`OuterStopping::Contraction`] trusts: slower
/// passes (the normal loading's first ones) are verified.
pub const CONTRACTION_MAX_RATE: f64 = 0.5;

/// How [`InhomogeneousContact`] obtains the surface eigen-displacements of the tractions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BodyResponse {
    /// An EIM solve in every outer pass (\[LN11\] Fig. 2; docs/theory-sam.md#nested-loops): the
    /// reference path.
    Nested,
    /// The dense surface-response operator [`SurfaceResponse`] over the cells whose centres lie
    /// within `radius` (m) of the origin, built once (one EIM solve per column); the outer pass
    /// applies it instead of solving the EIM. Tractions outside the region are refused
    /// ([`SamError::ContactOutsideSurfaceOperator`]). The eigenstrains are solved from the
    /// tractions only when asked ([`InhomogeneousContact::sync_eigenstrain`]).
    SurfaceOperator {
        /// Radius of the candidate region (m).
        radius: f64,
    },
}

/// What the next increment of the nested loop starts from: the eigenstrains (6 per inclusion cell)
/// and eigen-displacements of the last increment and, for the predictor, of the one before.
#[derive(Debug, Clone, PartialEq)]
pub struct NestedWarmStart {
    /// Eigenstrains of the last increment.
    pub eigenstrain: Vec<f64>,
    /// Eigen-displacements `(u₁, u₂, u₃)^eig` of the last increment.
    pub eigen_displacement: [Vec<f64>; 3],
    /// Those of the increment before (used by the predictor once two increments are committed).
    pub previous: (Vec<f64>, [Vec<f64>; 3]),
    /// Increments committed.
    pub committed: usize,
    /// The last EIM iterate and its image of the last increment and of the one before
    /// ([`EimIterate`]; `None` where none was kept: the predictor then extrapolates the
    /// eigenstrains and applies the operator once).
    pub iterates: [Option<EimIterate>; 2],
}

/// An iterate `x` of an increment's last EIM solve and its image `A x` under the EIM operator
/// (docs/theory-sam.md#the-predictors-image): the secant predictor extrapolates these pairs, so
/// the next increment's first EIM residual costs no application.
#[derive(Debug, Clone, PartialEq)]
pub struct EimIterate {
    /// The iterate `x_J` (6 per inclusion cell).
    pub iterate: Vec<f64>,
    /// Its image `A x_J` (as the iteration kept it, `b_J − r_J`).
    pub image: Vec<f64>,
}

/// The loosest alternation tolerance of an early outer pass's contact solve.
pub const LOOSE_CONTACT_CEILING: f64 = 1e-3;

/// The default EIM change factor `η` ([`NestedParams::eim_change_factor`]): each outer pass's EIM
/// solved to 3·10⁻³ of the last outer change, with the recycled iterations of
/// [`DEFAULT_EIM_RECYCLED_DEPTH`] (which make the tighter solves cheap). On \[LN11\]'s composite
/// loop it stays within 1.4e-7 p₀ of the reference path ([`REFERENCE_EIM_CHANGE_FACTOR`], plain
/// block Jacobi) at every increment of the whole loop at 64², with 45 % fewer EIM applications;
/// 10⁻² (the default before, plain: 6.9e-7 p₀) with recycling left it (1.07e-6 p₀)
/// (docs/theory-sam.md#outer-loop-tolerances).
pub const DEFAULT_EIM_CHANGE_FACTOR: f64 = 3e-3;

/// The EIM change factor of the reference nested loop (10⁻³: each pass's EIM converged well below
/// the outer change), against which [`DEFAULT_EIM_CHANGE_FACTOR`] is checked.
pub const REFERENCE_EIM_CHANGE_FACTOR: f64 = 1e-3;

/// The default recycled EIM depth of the nested loop ([`EimParams::recycled_depth`] in
/// [`NestedParams::default`]): the block-Jacobi iteration Anderson-mixed with 5 differences kept
/// across an increment's outer passes (docs/theory-sam.md#solving-the-eim-equations; measured
/// against the reference path in docs/performance.md, "Issue 21: recycled EIM iterations by
/// default"). `EimParams::default()` alone stays the plain iteration.
pub const DEFAULT_EIM_RECYCLED_DEPTH: usize = 5;

/// The largest recycled EIM depth accepted ([`NestedParams::validate`]): the history holds two
/// vectors of the EIM system's size per difference.
pub const MAX_EIM_RECYCLED_DEPTH: usize = 50;

impl Default for NestedParams {
    fn default() -> Self {
        Self {
            tolerance: 1e-6,
            max_outer: 60,
            relaxation: 1.0,
            eim: EimParams {
                recycled_depth: DEFAULT_EIM_RECYCLED_DEPTH,
                ..EimParams::default()
            },
            inexact_contact: true,
            anderson_depth: 3,
            predictor: true,
            cycle_predictor: true,
            eim_change_factor: DEFAULT_EIM_CHANGE_FACTOR,
            body: BodyResponse::Nested,
            stopping: OuterStopping::Contraction { safety: 1.0 },
        }
    }
}

impl NestedParams {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), SamError> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(SamError::InvalidParameter {
                name: "outer-loop tolerance",
                value: self.tolerance,
                allowed: "finite and > 0",
            });
        }
        if !(self.relaxation > 0.0 && self.relaxation <= 1.0) {
            return Err(SamError::InvalidParameter {
                name: "under-relaxation ω",
                value: self.relaxation,
                allowed: "in (0, 1]",
            });
        }
        if !(self.eim_change_factor > 0.0 && self.eim_change_factor <= 1.0) {
            return Err(SamError::InvalidParameter {
                name: "EIM change factor",
                value: self.eim_change_factor,
                allowed: "in (0, 1]",
            });
        }
        if self.eim.recycled_depth > MAX_EIM_RECYCLED_DEPTH {
            return Err(SamError::InvalidParameter {
                name: "eim_recycled_depth (recycled EIM depth)",
                value: self.eim.recycled_depth as f64,
                allowed: "0 (plain block Jacobi) to 50",
            });
        }
        if let BodyResponse::SurfaceOperator { radius } = self.body {
            if !(radius.is_finite() && radius > 0.0) {
                return Err(SamError::InvalidParameter {
                    name: "surface-operator radius",
                    value: radius,
                    allowed: "finite and > 0",
                });
            }
        }
        if let OuterStopping::Contraction { safety } = self.stopping {
            if !(safety.is_finite() && safety >= 1.0) {
                return Err(SamError::InvalidParameter {
                    name: "contraction stopping rule's safety factor",
                    value: safety,
                    allowed: "finite and ≥ 1",
                });
            }
        }
        if self.max_outer == 0 {
            return Err(SamError::InvalidParameter {
                name: "outer iteration limit",
                value: 0.0,
                allowed: "≥ 1",
            });
        }
        Ok(())
    }
}

/// What an increment with inhomogeneities did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NestedInfo {
    /// The contact solve of the last outer iteration.
    pub contact: IncrementInfo,
    /// Outer iterations.
    pub outer_iterations: usize,
    /// EIM iterations summed over the outer iterations.
    pub eim_iterations: usize,
    /// The last EIM solve.
    pub last_eim: EimInfo,
    /// Final relative change of the eigen-displacements: measured by the last EIM solve, or
    /// predicted (`ρ c_k`) when [`NestedInfo::predicted_stop`].
    pub change: f64,
    /// Whether the increment stopped by [`OuterStopping::Contraction`]'s prediction (its last
    /// contact solve not followed by an EIM solve).
    pub predicted_stop: bool,
    /// `min u₃^eig` (m; negative: the surface rises above a stiff inhomogeneity under load).
    pub min_eigen_displacement: f64,
    /// Contact solves summed over the outer iterations: Panagiotopoulos alternations, normal
    /// (Polonsky–Keer) and tangential iterations.
    pub contact_work: ContactWork,
    /// Wall time of the parts (not deterministic: excluded from comparisons of results).
    pub seconds: NestedSeconds,
}

/// Contact-solve work of one increment with inhomogeneities, summed over its outer iterations.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactWork {
    /// Contact solves (= outer iterations).
    pub solves: usize,
    /// Panagiotopoulos alternations.
    pub alternations: usize,
    /// Normal-solver iterations (of the last alternation of each solve).
    pub normal_iterations: usize,
    /// Tangential block products (of the last alternation of each solve).
    pub tangential_iterations: usize,
    /// Normal-solver iterations summed over every alternation of each solve (of a
    /// force-controlled increment: of the returned Brent evaluation only).
    pub normal_iterations_total: usize,
    /// Tangential block products summed over every alternation of each solve (of a
    /// force-controlled increment: of the returned Brent evaluation only).
    pub tangential_iterations_total: usize,
}

/// Wall time of one increment with inhomogeneities, by part (s).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NestedSeconds {
    /// The contact solves.
    pub contact: f64,
    /// The applied strain of the surface tractions (Love) at the inclusion layers.
    pub traction_strain: f64,
    /// The EIM solves (their operator applications).
    pub eim: f64,
    /// The disturbance of the converged eigenstrains and the surface eigen-displacements.
    pub disturbance: f64,
}

/// A contact problem on a half-space with inhomogeneities.
pub struct InhomogeneousContact {
    problem: ContactProblem,
    system: EimSystem,
    params: NestedParams,
    friction: bool,
    eps_star: Vec<f64>,
    applied: Vec<Vec<f64>>,
    u_eig: [Vec<f64>; 3],
    u_new: [Vec<f64>; 3],
    /// The outer iteration's accelerator and its flat iterates (the components that enter the
    /// contact: `u₃`, and `u₁, u₂` with friction).
    anderson: Anderson,
    x_flat: Vec<f64>,
    g_flat: Vec<f64>,
    /// The previous increment's eigenstrains and eigen-displacements (predictor), and the number
    /// of increments committed.
    eps_prev: Vec<f64>,
    u_prev: [Vec<f64>; 3],
    committed: usize,
    /// The last EIM iterate and its image of the last two increments (now, before), the
    /// predicted start's image for the increment under way, and whether the start was given
    /// ([`InhomogeneousContact::set_prediction`]: not extrapolated).
    iterates: [Option<EimIterate>; 2],
    predicted_image: Option<Vec<f64>>,
    prediction_given: bool,
    /// The surface-response operator ([`BodyResponse::SurfaceOperator`]).
    response: Option<SurfaceResponse>,
    /// Whether `eps_star` is the EIM solution of the current tractions (on the nested path
    /// always, to the outer tolerance: [`InhomogeneousContact::eigenstrain`]; on the operator
    /// path after [`InhomogeneousContact::sync_eigenstrain`]).
    eigenstrain_current: bool,
}

impl InhomogeneousContact {
    /// Plans the EIM operators for `inhomogeneities` in the half-space `(e, nu)` under `problem`'s
    /// grid (cubic cells of the surface cell size).
    pub fn new(
        problem: ContactProblem,
        e: f64,
        nu: f64,
        inhomogeneities: &[Inhomogeneity],
        params: NestedParams,
    ) -> Result<Self, SamError> {
        params.validate()?;
        let grid = *problem.grid();
        let set = InclusionSet::new(&grid, inhomogeneities)?;
        if set.is_empty() {
            return Err(SamError::InvalidParameter {
                name: "inhomogeneity count",
                value: 0.0,
                allowed: "≥ 1 (use ContactProblem without inhomogeneities)",
            });
        }
        let fields = EimFields::for_inclusions(grid, e, nu, &set)?;
        let n = grid.len();
        let layers = set.layers.len();
        let cells = set.len();
        let wl = set.window.len();
        let friction = problem.friction() > 0.0;
        let components = if friction { 3 } else { 1 };
        let mut system = EimSystem::new(fields, set, e, nu)?;
        let response = match params.body {
            BodyResponse::Nested => None,
            BodyResponse::SurfaceOperator { radius } => {
                let cells = (0..n)
                    .filter(|&k| {
                        let (x, y) = grid.centre(k / grid.n2, k % grid.n2);
                        x * x + y * y <= radius * radius
                    })
                    .collect();
                // One solve per column, each to the full tolerance: the plain iteration (the
                // recycled history is for an increment's outer passes).
                Some(SurfaceResponse::build(
                    &mut system,
                    cells,
                    friction,
                    &EimParams {
                        recycled_depth: 0,
                        ..params.eim
                    },
                )?)
            }
        };
        Ok(Self {
            system,
            response,
            eigenstrain_current: true,
            problem,
            params,
            friction,
            eps_star: vec![0.0; 6 * cells],
            applied: vec![vec![0.0; wl]; layers * 6],
            u_eig: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            u_new: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            anderson: Anderson::new(components * n, params.anderson_depth),
            x_flat: vec![0.0; components * n],
            g_flat: vec![0.0; components * n],
            eps_prev: vec![0.0; 6 * cells],
            u_prev: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            committed: 0,
            iterates: [None, None],
            predicted_image: None,
            prediction_given: false,
        })
    }

    /// One increment to normal load `load` and shift `shift` (docs/theory-sam.md#nested-loops), the friction history
    /// committed at convergence.
    pub fn increment(&mut self, load: NormalLoad, shift: [f64; 2]) -> Result<NestedInfo, SamError> {
        self.problem.begin();
        self.predict();
        let info = self.solve(load, shift)?;
        self.problem.commit();
        self.committed += 1;
        self.keep_iterate()?;
        Ok(info)
    }

    /// After an increment: its last EIM iterate and image become the predictor's newest pair
    /// (`None` on the operator path or when the solve kept none).
    fn keep_iterate(&mut self) -> Result<(), SamError> {
        let previous = self.iterates[1].take();
        self.iterates[1] = self.iterates[0].take();
        if self.response.is_some() || !self.params.predictor {
            return Ok(());
        }
        // Reuse the oldest pair's vectors.
        let mut pair = previous.unwrap_or_else(|| EimIterate {
            iterate: vec![0.0; self.eps_star.len()],
            image: vec![0.0; self.eps_star.len()],
        });
        if self
            .system
            .last_iterate_image(&mut pair.iterate, &mut pair.image)?
        {
            self.iterates[0] = Some(pair);
        }
        Ok(())
    }

    /// The predictor of [`NestedParams::predictor`]: `x ← 2x − x_prev`, `x_prev ← x` (only the
    /// latter before two increments are committed). With the last two increments' last EIM
    /// iterates kept ([`EimIterate`]), the eigenstrains start from `2 x_J − x_J'` instead and its
    /// image `2 A x_J − A x_J'` is declared to the EIM iteration, whose first residual then costs
    /// no application (docs/theory-sam.md#the-predictors-image).
    fn predict(&mut self) {
        let image = self.predicted_image.take();
        let given = std::mem::take(&mut self.prediction_given);
        if !self.params.predictor || self.committed == 0 {
            return;
        }
        let extrapolate = self.committed >= 2;
        let from_iterates = extrapolate
            && !given
            && self.response.is_none()
            && self.iterates.iter().all(Option::is_some);
        // The operator path solves no eigenstrains per increment: only u^eig is predicted.
        let eps = (self.response.is_none() && !from_iterates)
            .then_some((&mut self.eps_star, &mut self.eps_prev));
        let pairs = eps
            .into_iter()
            .chain(self.u_eig.iter_mut().zip(self.u_prev.iter_mut()));
        for (x, prev) in pairs {
            for (v, p) in x.iter_mut().zip(prev.iter_mut()) {
                let current = *v;
                if extrapolate {
                    *v = 2.0 * current - *p;
                }
                *p = current;
            }
        }
        if let [Some(now), Some(before)] = &self.iterates {
            if from_iterates {
                self.eps_prev.copy_from_slice(&self.eps_star);
                let mut image = image.unwrap_or_else(|| vec![0.0; now.image.len()]);
                for (((x, v), (a, b)), (ia, ib)) in self
                    .eps_star
                    .iter_mut()
                    .zip(image.iter_mut())
                    .zip(now.iterate.iter().zip(&before.iterate))
                    .zip(now.image.iter().zip(&before.image))
                {
                    *x = 2.0 * a - b;
                    *v = 2.0 * ia - ib;
                }
                self.predicted_image = Some(image);
            }
        }
    }

    /// The state the next increment starts from (for a checkpoint).
    pub fn warm_start(&self) -> NestedWarmStart {
        NestedWarmStart {
            eigenstrain: self.eps_star.clone(),
            eigen_displacement: self.u_eig.clone(),
            previous: (self.eps_prev.clone(), self.u_prev.clone()),
            committed: self.committed,
            iterates: self.iterates.clone(),
        }
    }

    /// Restores [`InhomogeneousContact::warm_start`]; with [`ContactProblem::restore_state`] this
    /// is all the state an increment reads, so a resumed loop repeats the uninterrupted one bit
    /// for bit.
    pub fn set_warm_start(&mut self, w: &NestedWarmStart) -> Result<(), SamError> {
        check_len("previous eigenstrain", &w.previous.0, self.eps_prev.len())?;
        for u in &w.previous.1 {
            check_len("previous eigen-displacement", u, self.u_prev[0].len())?;
        }
        for it in w.iterates.iter().flatten() {
            check_len("EIM iterate", &it.iterate, self.eps_star.len())?;
            check_len("EIM iterate's image", &it.image, self.eps_star.len())?;
        }
        let u = &w.eigen_displacement;
        self.restore(&w.eigenstrain, [&u[0], &u[1], &u[2]])?;
        self.eps_prev.copy_from_slice(&w.previous.0);
        for (mine, theirs) in self.u_prev.iter_mut().zip(&w.previous.1) {
            mine.copy_from_slice(theirs);
        }
        self.committed = w.committed;
        self.iterates = w.iterates.clone();
        Ok(())
    }

    /// Sets the next increment's start to `(eigenstrain, u^eig)` instead of the predictor of
    /// [`NestedParams::predictor`] (e.g. the same increment of an earlier fretting cycle,
    /// [`crate::drivers::fretting_wear3d::FrettingWear3d`]): the current and the previous
    /// values both become `x`, so the secant predictor's `2x − x` returns `x` exactly (Sterbenz)
    /// and the increment starts from it. Nothing is solved; the committed count is kept.
    pub fn set_prediction(
        &mut self,
        eigenstrain: &[f64],
        u_eig: [&[f64]; 3],
    ) -> Result<(), SamError> {
        check_len("predicted eigenstrain", eigenstrain, self.eps_star.len())?;
        for u in u_eig {
            check_len("predicted eigen-displacement", u, self.u_eig[0].len())?;
        }
        self.eps_star.copy_from_slice(eigenstrain);
        self.eps_prev.copy_from_slice(eigenstrain);
        self.prediction_given = true;
        for ((x, prev), v) in self.u_eig.iter_mut().zip(self.u_prev.iter_mut()).zip(u_eig) {
            x.copy_from_slice(v);
            prev.copy_from_slice(v);
        }
        Ok(())
    }

    /// One increment to normal load `load` and a prescribed tangential force `Q₁` (`Q₂` free at
    /// `D₂ = 0`): the shift `D₁` by [`shift_for_force`], each evaluation the nested loop of
    /// [`InhomogeneousContact::increment`] from the same history and the same warm start
    /// (contact state, eigenstrains, eigen-displacements); the history committed once, at the
    /// found shift. `|Q₁| ≥ μW` is gross slip and refused. Returns the report and `D₁`.
    pub fn increment_with_force(
        &mut self,
        load: NormalLoad,
        force: f64,
        bracket: f64,
    ) -> Result<(NestedInfo, f64), SamError> {
        let mu = self.problem.friction();
        let NormalLoad::Force(w) = load else {
            return Err(SamError::InvalidInput(
                "a prescribed tangential force with inhomogeneities needs a prescribed normal force"
                    .into(),
            ));
        };
        if !force.is_finite() || force.abs() >= mu * w {
            return Err(SamError::GrossSlip {
                force: force.abs(),
                limit: mu * w,
            });
        }
        self.problem.begin();
        self.predict();
        let warm_state = self.problem.state().clone();
        let warm_eps = self.eps_star.clone();
        let warm_u = self.u_eig.clone();
        let start = warm_state.shift;
        let mut eval = |d: f64| -> Result<(f64, NestedInfo), SamError> {
            self.problem.restore_state(&warm_state)?;
            self.restore(&warm_eps, [&warm_u[0], &warm_u[1], &warm_u[2]])?;
            let info = self.solve(load, [d, start[1]])?;
            Ok((info.contact.tangential_force[0] - force, info))
        };
        let (info, d) = shift_for_force(start[0], bracket, 1e-6 * mu * w, &mut eval)?;
        self.problem.commit();
        self.committed += 1;
        // The last evaluation's iterate and image: a pair `(x, A x)` whichever evaluation it was.
        self.keep_iterate()?;
        Ok((info, d))
    }

    /// The nested loop of one increment after `problem.begin()`, without committing.
    fn solve(&mut self, load: NormalLoad, shift: [f64; 2]) -> Result<NestedInfo, SamError> {
        // On one of rayon's worker threads, the EIM products with the contact solves
        // ([`halfspace_numerics::parallel::on_pool`]).
        halfspace_numerics::parallel::on_pool(self.problem.grid().len(), || {
            self.solve_here(load, shift)
        })
    }

    /// [`InhomogeneousContact::solve`] on the calling thread.
    fn solve_here(&mut self, load: NormalLoad, shift: [f64; 2]) -> Result<NestedInfo, SamError> {
        self.anderson.reset();
        // The EIM history recycled across this increment's passes starts empty: the increment
        // depends only on the checkpointed state ([`InhomogeneousContact::set_warm_start`]).
        self.system.forget_recycled();
        // The predicted start's image (when the predictor made one): the first pass's first EIM
        // residual without an application.
        if let Some(image) = &self.predicted_image {
            self.system
                .set_known_start(&self.eps_star, image, &self.params.eim)?;
        }
        let mut eim_iterations = 0;
        let mut work = ContactWork::default();
        let mut seconds = NestedSeconds::default();
        let clock = std::time::Instant::now;
        let omega = self.params.relaxation;
        // Inexact inner solves: the EIM is solved to `eim_change_factor` (3e-3) of the last outer
        // change (never looser than 1e-3, never tighter than its own tolerance), so early outer
        // passes are cheap and the last ones are converged well below the outer tolerance
        // (docs/theory-sam.md#outer-loop-tolerances).
        let mut last_change: f64 = 1.0;
        let mut final_pass = false;
        let mut predicted_change = f64::NAN;
        let mut rates = [f64::INFINITY; 2];
        let mut previous_eim: Option<EimInfo> = None;
        for outer in 1..=self.params.max_outer {
            self.problem.set_eigen_displacements(Some([
                &self.u_eig[0],
                &self.u_eig[1],
                &self.u_eig[2],
            ]))?;
            let t = clock();
            let slack = if self.params.inexact_contact {
                let tight = self.problem.params().alternation_tolerance;
                (1e-2 * last_change).clamp(tight, LOOSE_CONTACT_CEILING.max(tight)) / tight
            } else {
                1.0
            };
            let slack = if final_pass { 1.0 } else { slack };
            let contact = self.problem.solve_loosely(load, shift, slack)?;
            seconds.contact += t.elapsed().as_secs_f64();
            work.solves += 1;
            work.alternations += contact.alternations;
            work.normal_iterations += contact.normal.iterations;
            work.tangential_iterations += contact.tangential.iterations;
            work.normal_iterations_total += contact.normal_iterations_total;
            work.tangential_iterations_total += contact.tangential_iterations_total;
            if final_pass {
                if let Some(last_eim) = previous_eim {
                    // The contraction rule's last pass: the contact solve with the mixed u^eig,
                    // whose EIM verification is predicted to pass.
                    return Ok(NestedInfo {
                        contact,
                        outer_iterations: outer,
                        eim_iterations,
                        last_eim,
                        change: predicted_change,
                        predicted_stop: true,
                        min_eigen_displacement: self.u_eig[2].iter().cloned().fold(0.0, f64::min),
                        contact_work: work,
                        seconds,
                    });
                }
            }
            let last_eim = match &self.response {
                Some(response) => {
                    let t = clock();
                    let state = self.problem.state();
                    let q = if self.friction {
                        Some([state.shear[0].as_slice(), state.shear[1].as_slice()])
                    } else {
                        None
                    };
                    let [a, b, c] = &mut self.u_new;
                    response.apply(&state.pressure, q, [a, b, c])?;
                    self.eigenstrain_current = false;
                    seconds.disturbance += t.elapsed().as_secs_f64();
                    EimInfo {
                        iterations: 0,
                        residual: 0.0,
                        method: self.params.eim.method,
                    }
                }
                None => {
                    let t = clock();
                    self.applied_strain_of_tractions()?;
                    let eim = EimParams {
                        tolerance: (self.params.eim_change_factor * last_change)
                            .clamp(self.params.eim.tolerance, 1e-3),
                        ..self.params.eim
                    };
                    seconds.traction_strain += t.elapsed().as_secs_f64();
                    let t = clock();
                    let last_eim = self.system.solve(&self.applied, &mut self.eps_star, &eim)?;
                    eim_iterations += last_eim.iterations;
                    seconds.eim += t.elapsed().as_secs_f64();
                    let t = clock();
                    // The surface fields alone: u^eig reads nothing else (bit for bit the same).
                    self.system.surface_disturbance(&self.eps_star)?;
                    {
                        let [a, b, c] = &mut self.u_new;
                        self.system.fields().eigen_displacements([a, b, c])?;
                    }
                    seconds.disturbance += t.elapsed().as_secs_f64();
                    last_eim
                }
            };
            let components = if self.friction { 0..3 } else { 2..3 };
            let mut change: f64 = 0.0;
            for c in components {
                let scale = self.u_new[c].iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let diff = self.u_new[c]
                    .iter()
                    .zip(&self.u_eig[c])
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                if scale > 0.0 {
                    change = change.max(diff / scale);
                }
            }
            // The next iterate: Anderson-mixed on the components that enter the contact (relaxed
            // Picard with depth 0), relaxed Picard on the others.
            let n = self.u_eig[0].len();
            let first = if self.friction { 0 } else { 2 };
            for (slot, c) in (first..3).enumerate() {
                self.x_flat[slot * n..(slot + 1) * n].copy_from_slice(&self.u_eig[c]);
                self.g_flat[slot * n..(slot + 1) * n].copy_from_slice(&self.u_new[c]);
            }
            self.anderson.step(&mut self.x_flat, &self.g_flat, omega)?;
            for c in 0..3 {
                if c >= first {
                    let slot = c - first;
                    self.u_eig[c].copy_from_slice(&self.x_flat[slot * n..(slot + 1) * n]);
                } else {
                    for (u, v) in self.u_eig[c].iter_mut().zip(&self.u_new[c]) {
                        *u += omega * (v - *u);
                    }
                }
            }
            let previous_change = last_change;
            last_change = change;
            previous_eim = Some(last_eim);
            // The contraction rule: the slower of the last two contractions predicts the next
            // pass's change (`rates[0]` this pass's, `rates[1]` the one before).
            rates = [change / previous_change, rates[0]];
            if let OuterStopping::Contraction { safety } = self.params.stopping {
                let rate = rates[0].max(rates[1]);
                if outer >= 3
                    && rate <= CONTRACTION_MAX_RATE
                    && change >= self.params.tolerance
                    && rate * change * safety < self.params.tolerance
                    && outer < self.params.max_outer
                {
                    final_pass = true;
                    predicted_change = rate * change;
                    continue;
                }
            }
            if change < self.params.tolerance && slack == 1.0 {
                // The state is the contact solve with the previous u_eig, which agrees with the
                // new one to `tol`.
                return Ok(NestedInfo {
                    contact,
                    outer_iterations: outer,
                    eim_iterations,
                    last_eim,
                    change,
                    predicted_stop: false,
                    min_eigen_displacement: self.u_eig[2].iter().cloned().fold(0.0, f64::min),
                    contact_work: work,
                    seconds,
                });
            }
            if outer == self.params.max_outer {
                return Err(SamError::NoConvergence {
                    solver: "contact ↔ EIM outer loop (try under-relaxation)",
                    iterations: outer,
                    residual: change,
                });
            }
        }
        unreachable!("the loop returns")
    }

    /// The applied strain `ε⁰` at the inclusion cells from the current tractions `p` (and `q`
    /// with friction), Love's solution (docs/theory-sam.md#love-rectangle-stresses), into
    /// `self.applied`.
    fn applied_strain_of_tractions(&mut self) -> Result<(), SamError> {
        let state = self.problem.state();
        let q = if self.friction {
            Some([state.shear[0].as_slice(), state.shear[1].as_slice()])
        } else {
            None
        };
        self.system
            .fields()
            .traction_strain(&state.pressure, q, &mut self.applied)
    }

    /// Brings the eigenstrains up to the current tractions (docs/theory-sam.md#surface-response-operator):
    /// on the operator path ([`BodyResponse::SurfaceOperator`]), one EIM solve from the tractions
    /// of the last increment to the full tolerance, warm-started from the last eigenstrains, when
    /// the tractions changed since (`None` when nothing was solved); on the nested path the
    /// eigenstrains are always current. Call it before reading [`InhomogeneousContact::eigenstrain`]
    /// for stresses ([`crate::contact::ContactSolver::subsurface`] does).
    pub fn sync_eigenstrain(&mut self) -> Result<Option<EimInfo>, SamError> {
        if self.eigenstrain_current {
            return Ok(None);
        }
        self.applied_strain_of_tractions()?;
        let plain = EimParams {
            recycled_depth: 0,
            ..self.params.eim
        };
        let info = self
            .system
            .solve(&self.applied, &mut self.eps_star, &plain)?;
        self.system.disturbance(&self.eps_star)?;
        self.eigenstrain_current = true;
        Ok(Some(info))
    }

    /// The surface-response operator, on the operator path.
    pub fn surface_response(&self) -> Option<&SurfaceResponse> {
        self.response.as_ref()
    }

    /// The contact problem (state, grid).
    pub fn problem(&self) -> &ContactProblem {
        &self.problem
    }

    /// The contact problem, mutable (to restore its state from a checkpoint).
    pub fn problem_mut(&mut self) -> &mut ContactProblem {
        &mut self.problem
    }

    /// Restores the warm starts of a checkpoint: the eigenstrains (6 per inclusion cell) and the
    /// surface eigen-displacements. With [`ContactProblem::restore_state`] this is all the state an
    /// increment reads, so a resumed loop repeats the uninterrupted one bit for bit.
    pub fn restore(&mut self, eigenstrain: &[f64], u_eig: [&[f64]; 3]) -> Result<(), SamError> {
        check_len("eigenstrain", eigenstrain, self.eps_star.len())?;
        for u in u_eig {
            check_len("eigen-displacement", u, self.u_eig[0].len())?;
        }
        self.eps_star.copy_from_slice(eigenstrain);
        for (mine, theirs) in self.u_eig.iter_mut().zip(u_eig) {
            mine.copy_from_slice(theirs);
        }
        self.system.disturbance(&self.eps_star)?;
        // On the operator path the restored eigenstrains are a warm start, not the solution of
        // the restored tractions.
        self.eigenstrain_current = self.response.is_none();
        Ok(())
    }

    /// The inclusion cells.
    pub fn inclusions(&self) -> &InclusionSet {
        self.system.set()
    }

    /// The eigenstrains, 6 per inclusion cell (Voigt, tensor shear): on the nested path those of
    /// the increment's last EIM solve — of the current tractions, or after a stop by
    /// [`OuterStopping::Contraction`] of the pass before the returned contact solve (apart from
    /// the current tractions' by the predicted change, below the outer tolerance); of the last
    /// [`InhomogeneousContact::sync_eigenstrain`] on the operator path.
    pub fn eigenstrain(&self) -> &[f64] {
        &self.eps_star
    }

    /// The surface eigen-displacements `(u₁, u₂, u₃)^eig`.
    pub fn eigen_displacements(&self) -> &[Vec<f64>; 3] {
        &self.u_eig
    }

    /// The correction pressure `p_c` on the grid (its integral should vanish: docs/theory-sam.md#domain-size-and-truncation; a large
    /// `A Σ p_c` relative to the load means the domain truncates it — enlarge the extent).
    pub fn correction_pressure(&self) -> &[f64] {
        self.system.correction_pressure()
    }

    /// Bytes of the stored EIM kernel spectra.
    pub fn spectra_bytes(&self) -> usize {
        self.system.spectra_bytes()
    }
}

fn check_len(what: &'static str, v: &[f64], expected: usize) -> Result<(), SamError> {
    if v.len() != expected {
        return Err(SamError::Numerics(
            halfspace_numerics::NumericsError::LengthMismatch {
                what,
                expected,
                got: v.len(),
            },
        ));
    }
    if let Some(bad) = v.iter().find(|x| !x.is_finite()) {
        return Err(SamError::InvalidParameter {
            name: what,
            value: *bad,
            allowed: "finite",
        });
    }
    Ok(())
}
