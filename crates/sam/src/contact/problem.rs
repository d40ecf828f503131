//! Normal and tangential contact together (docs/theory-sam.md#loading-history to #normal-tangential-alternation): the Panagiotopoulos alternation for
//! coupled (dissimilar) bodies, the incremental (history-dependent) friction law, load paths and
//! fretting loops.

use halfspace_numerics::fft2d::{Fft2d, KernelFn};
use halfspace_numerics::op::{BlockConvolution, FftOperators, GridOperator, OperatorSet};

use super::force_control::shift_for_force;
use crate::kernels::InPlane;
use crate::normal::{NormalInfo, NormalLoad, NormalParams, NormalSolver};
use crate::tangential::{is_stick, TangentialInfo, TangentialParams, TangentialSolver};
use crate::{Compliance, SamError, SurfaceGrid};

/// Parameters of a coupled contact problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactParams {
    /// Coulomb friction coefficient `μ ≥ 0`.
    pub friction: f64,
    /// Normal solver stopping rule.
    pub normal: NormalParams,
    /// Tangential solver stopping rule.
    pub tangential: TangentialParams,
    /// Alternation tolerance: `max|Δp|/max p` and `max|Δq|/(μ max p)` (docs/theory-sam.md#normal-tangential-alternation: 1e-7).
    pub alternation_tolerance: f64,
    /// Alternation limit.
    pub max_alternations: usize,
    /// Tangential solves of the early alternations to a hundredth of the alternation's last
    /// change (at most [`INEXACT_CEILING`]; [`TANGENTIAL_GAUGE`] of it and the early normal
    /// solves loosened too with [`Alternation::Gauged`]), the last one to the full tolerance.
    pub inexact_alternation: bool,
    /// How the shear read by the next normal solve is formed from the alternations so far
    /// (docs/theory-sam.md#normal-tangential-alternation).
    pub alternation: Alternation,
}

/// The fixed point of the normal–tangential alternation `q = T(N(q))` (`N`: the normal solve with
/// the shear `q` frozen, `T`: the tangential solve with the resulting pressure frozen;
/// docs/theory-sam.md#normal-tangential-alternation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Alternation {
    /// Gauss–Seidel (Panagiotopoulos 1975): the next normal solve reads the last tangential
    /// solve's shear, `q_in^{k+1} = T(N(q_in^k))`; at least two alternations, the first
    /// tangential solve (coupled, inexact) to [`INEXACT_CEILING`]. The default: the fretting
    /// loop, map and wear run take it unless their config key `alternation` says `"gauged"`
    /// (`LoopCase::alternation`, recorded in their checkpoint fingerprints; docs/performance.md
    /// "The gauged alternation on the command line (issue 21)": as accurate, not measurably
    /// faster on the whole command).
    Plain,
    /// [`Alternation::Plain`] with its inexact solves gauged by the change they meet
    /// (docs/theory-sam.md#normal-tangential-alternation): the early tangential solves to
    /// [`TANGENTIAL_GAUGE`] of the last alternation change instead of 10⁻²; the early normal
    /// solves to [`NORMAL_GAUGE`] of it (at most [`NORMAL_CEILING`]; the plain alternation
    /// solves every normal solve to its full tolerance); in a re-solve of the increment (any
    /// solve after the first since [`ContactProblem::begin`]: the outer passes of a nested
    /// loop) the first alternation's normal solve to the full tolerance and its tangential solve
    /// to [`TANGENTIAL_GAUGE`] of `max(max|Δp|/max p, max|Δb|/max|b|)` (the pressure change of
    /// that normal solve and the change of the tangential right-hand side since the last
    /// solve); and a first alternation at the full tolerances that meets the stopping rule ends
    /// the solve (the plain one always runs a second). After a loose alternation whose change did
    /// not fall below the last one's, the next alternation solves both problems to the full
    /// tolerances (the guard). The stopping rule is the plain one; with
    /// [`ContactProblem::solve_loosely`]'s slack the normal solve's full tolerance is scaled as
    /// the tangential one is (at most to [`NORMAL_CEILING`]). Only coupled problems alternate:
    /// uncoupled ones solve as the plain alternation does.
    Gauged,
}

/// The most alternations [`ContactProblem::alternation_trace`] keeps between two
/// [`ContactProblem::begin`] calls (later ones are not recorded).
pub const TRACE_LIMIT: usize = 1024;

/// [`Alternation::Gauged`]: an early alternation's tangential solve stops at this factor times the
/// last alternation change (the plain alternation's: 10⁻²).
pub const TANGENTIAL_GAUGE: f64 = 3e-3;

/// [`Alternation::Gauged`]: an early alternation's normal solve stops at this factor times the
/// last alternation change …
pub const NORMAL_GAUGE: f64 = 1e-4;
/// … but no looser than this.
pub const NORMAL_CEILING: f64 = 1e-6;

/// Per alternation of the solves since the last [`ContactProblem::begin`]
/// ([`ContactProblem::alternation_trace`]): the changes of the stopping rule, relative to `max p`
/// and `μ max p`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlternationStep {
    /// The solve since the last [`ContactProblem::begin`] (0-based: outer passes of a nested loop,
    /// evaluations of a force control) this alternation belongs to.
    pub solve: usize,
    /// `max|p − p_prev| / max p` between successive normal solves.
    pub pressure_change: f64,
    /// `max|q − q_prev| / (μ max p)` between successive tangential solves.
    pub shear_change: f64,
    /// Iterations of the alternation's normal solve.
    pub normal_iterations: usize,
    /// Block products of the alternation's tangential solve.
    pub tangential_products: usize,
    /// Whether both solves of the alternation ran to their full tolerances (the last alternation
    /// of a solve; with [`Alternation::Gauged`] also the one after a loose alternation whose
    /// change did not fall, the guard).
    pub full_tolerance: bool,
}

/// The loosest KKT tolerance an early alternation's tangential solve uses.
pub const INEXACT_CEILING: f64 = 1e-4;

impl Default for ContactParams {
    fn default() -> Self {
        Self {
            friction: 0.3,
            normal: NormalParams::default(),
            tangential: TangentialParams::default(),
            alternation_tolerance: 1e-7,
            max_alternations: 200,
            inexact_alternation: true,
            alternation: Alternation::Plain,
        }
    }
}

/// The converged state after an increment.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactState {
    /// Pressure `p` per cell.
    pub pressure: Vec<f64>,
    /// Shear `q = (q₁, q₂)` per cell.
    pub shear: [Vec<f64>; 2],
    /// Total relative tangential displacement `Δu` per cell (history variable, docs/theory-sam.md#incremental-friction-law).
    pub tangential_displacement: [Vec<f64>; 2],
    /// Slip of the last increment `S` per cell.
    pub slip: [Vec<f64>; 2],
    /// Rigid tangential displacement `D`.
    pub shift: [f64; 2],
    /// Rigid approach `δ`.
    pub approach: f64,
    /// Normal force `W`.
    pub force: f64,
}

/// Summary of one increment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IncrementInfo {
    /// Panagiotopoulos alternations (1 when uncoupled).
    pub alternations: usize,
    /// Last normal solve.
    pub normal: NormalInfo,
    /// Last tangential solve.
    pub tangential: TangentialInfo,
    /// Normal-solver iterations summed over the alternations. Of a force-controlled increment
    /// (`increment_with_force`): of the returned Brent evaluation only, not the others.
    pub normal_iterations_total: usize,
    /// Tangential block products summed over the alternations (the cost of the tangential
    /// solves; [`TangentialInfo::iterations`] is the last one's). Of a force-controlled
    /// increment: of the returned Brent evaluation only.
    pub tangential_iterations_total: usize,
    /// Tangential force `Q = A Σ q`.
    pub tangential_force: [f64; 2],
    /// Contact area `A · #(p > 0)`.
    pub contact_area: f64,
    /// Stick area `A · #stick`.
    pub stick_area: f64,
    /// Largest pressure.
    pub max_pressure: f64,
}

/// A rectangle of a grid's cells: rows `first[0]..first[0] + cells[0]` (along `x₁`) and columns
/// `first[1]..first[1] + cells[1]` (along `x₂`), the cell `(i, j)` being `k = i N₂ + j` on the grid
/// and `(i − first[0]) cells[1] + (j − first[1])` on the window. A contact problem may solve on a
/// window ([`ContactProblem::set_window`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GridWindow {
    /// The first row and column.
    pub first: [usize; 2],
    /// The rows and columns.
    pub cells: [usize; 2],
}

impl GridWindow {
    /// The central window of `grid` that holds every cell whose centre lies within `half_width`
    /// (m) of the grid's centre along `x₁` and along `x₂`, with as many cells outside it on either
    /// side (so its centres are the grid's central ones) and at least 8 cells a side; `None` when
    /// that is the whole grid.
    pub fn central(grid: &SurfaceGrid, half_width: f64) -> Result<Option<Self>, SamError> {
        if !(half_width.is_finite() && half_width > 0.0) {
            return Err(SamError::InvalidParameter {
                name: "contact window half-width",
                value: half_width,
                allowed: "finite and > 0",
            });
        }
        let side = |n: usize, half: f64| -> usize {
            // Cells from the centre to the last centre within the half-width, on each side
            // (the centres sit at odd multiples of the half cell from the middle when n is even).
            let reach = ((half_width / half - if n % 2 == 0 { 1.0 } else { 0.0 }) / 2.0).floor();
            let m = if n % 2 == 0 {
                2 * (reach.max(0.0) as usize + 1)
            } else {
                2 * reach.max(0.0) as usize + 1
            };
            // At least 8 cells, as many outside on either side (odd n: an odd count).
            m.max(8 + n % 2).min(n)
        };
        if grid.n1 < 8 || grid.n2 < 8 {
            return Ok(None);
        }
        let cells = [side(grid.n1, grid.half1), side(grid.n2, grid.half2)];
        if cells == [grid.n1, grid.n2] {
            return Ok(None);
        }
        Ok(Some(Self {
            first: [(grid.n1 - cells[0]) / 2, (grid.n2 - cells[1]) / 2],
            cells,
        }))
    }

    /// Whether the window lies inside `grid` with at least 8 cells a side.
    fn check(&self, grid: &SurfaceGrid) -> Result<(), SamError> {
        let fits = |a: usize| {
            self.cells[a] >= 8
                && self.first[a]
                    .checked_add(self.cells[a])
                    .is_some_and(|end| end <= [grid.n1, grid.n2][a])
        };
        if fits(0) && fits(1) {
            Ok(())
        } else {
            Err(SamError::InvalidInput(format!(
                "contact window {self:?}: at least 8 cells a side, inside the {} × {} grid",
                grid.n1, grid.n2
            )))
        }
    }

    /// The window as a grid of its own (the same cells).
    fn grid(&self, grid: &SurfaceGrid) -> SurfaceGrid {
        SurfaceGrid {
            n1: self.cells[0],
            n2: self.cells[1],
            ..*grid
        }
    }

    /// The window's values of a field on the grid of `n2` columns (empty stays empty).
    fn gather(&self, n2: usize, field: &[f64]) -> Vec<f64> {
        let mut out = Vec::new();
        self.gather_into(n2, field, &mut out);
        out
    }

    /// [`GridWindow::gather`] into `out` (its allocation kept: the solves' copies allocate
    /// nothing once sized).
    fn gather_into(&self, n2: usize, field: &[f64], out: &mut Vec<f64>) {
        out.clear();
        if field.is_empty() {
            return;
        }
        for i in 0..self.cells[0] {
            let row = (self.first[0] + i) * n2 + self.first[1];
            out.extend_from_slice(&field[row..row + self.cells[1]]);
        }
    }

    /// Writes the window's values `window` into the field on the grid of `n2` columns (the cells
    /// outside untouched; nothing for an empty field).
    fn scatter(&self, n2: usize, window: &[f64], field: &mut [f64]) {
        if field.is_empty() {
            return;
        }
        for (i, values) in window.chunks_exact(self.cells[1]).enumerate() {
            let row = (self.first[0] + i) * n2 + self.first[1];
            field[row..row + self.cells[1]].copy_from_slice(values);
        }
    }

    /// Whether the cell `k` of the grid of `n2` columns lies in the window.
    fn contains(&self, n2: usize, k: usize) -> bool {
        let (i, j) = (k / n2, k % n2);
        (self.first[0]..self.first[0] + self.cells[0]).contains(&i)
            && (self.first[1]..self.first[1] + self.cells[1]).contains(&j)
    }

    /// The state's fields on the window (its scalars as they are).
    fn gather_state(&self, n2: usize, state: &ContactState) -> ContactState {
        let g = |f: &[f64]| self.gather(n2, f);
        ContactState {
            pressure: g(&state.pressure),
            shear: [g(&state.shear[0]), g(&state.shear[1])],
            tangential_displacement: [
                g(&state.tangential_displacement[0]),
                g(&state.tangential_displacement[1]),
            ],
            slip: [g(&state.slip[0]), g(&state.slip[1])],
            ..*state
        }
    }
}

/// A contact problem solved on a window of its grid ([`ContactProblem::set_window`]).
struct Windowed<S: OperatorSet> {
    window: GridWindow,
    /// The problem on the window's cells.
    inner: ContactProblem<S>,
    /// The whole grid's deformed gap of the last solve (the window's check).
    gap: Vec<f64>,
}

/// A contact problem on one grid: geometry, bodies, friction, solvers and the current state, on the
/// operators of `S` (the DC-FFT ones by default, or their dense twins). Every operator of the
/// problem uses one padded and one periodic FFT core of the grid.
pub struct ContactProblem<S: OperatorSet = FftOperators> {
    grid: SurfaceGrid,
    params: ContactParams,
    coupled: bool,
    normal: NormalSolver<S>,
    /// The tangential operator and solver; `None` without friction (`μ = 0`: `q = 0`, and a
    /// frictionless problem allocates only the normal operator).
    tangential: Option<TangentialSolver<S>>,
    /// q → Δu₃: `κ ⟦P_B^{(α)}⟧ *` (1 × 2 blocks).
    shear_to_normal: Option<S::Blocks>,
    /// p → Δu_α: `−κ ⟦P_B^{(α)}⟧ *` (2 × 1 blocks).
    pressure_to_tangential: Option<S::Blocks>,
    geometry: Vec<f64>,
    state: ContactState,
    h: Vec<f64>,
    c: [Vec<f64>; 2],
    b: [Vec<f64>; 2],
    bound: Vec<f64>,
    p_prev: Vec<f64>,
    q_prev: [Vec<f64>; 2],
    tq: [Vec<f64>; 2],
    w: [Vec<f64>; 2],
    u3: Vec<f64>,
    /// Cells that slipped in the state a tangential solve starts from (`|q| = μp` there): their
    /// shear is carried onto the new circle `μp` before the solve (the rim warm start).
    rim: Vec<bool>,
    /// Known eigen-displacements `(u₁, u₂, u₃)^eig` of the half-space (docs/theory-sam.md#eigen-displacements), if any.
    eigen: Option<[Vec<f64>; 3]>,
    /// `Δuⁿ⁺¹` of the last [`ContactProblem::solve`], committed by [`ContactProblem::commit`].
    trial_displacement: [Vec<f64>; 2],
    trial_shift: [f64; 2],
    /// The changes of every alternation of the solves since the last `begin`, and their count.
    trace: Vec<AlternationStep>,
    solves: usize,
    /// The pair's compliance (a window's problem is built from it).
    compliance: Compliance,
    /// The contact solved on a window of the grid, if set ([`ContactProblem::set_window`]), and
    /// the solves it did not take.
    window: Option<Box<Windowed<S>>>,
    window_misses: usize,
    /// Set while a force-controlled increment the window did not take runs on the whole grid
    /// (its evaluations then skip the window).
    whole_grid_only: bool,
}

impl ContactProblem {
    /// A problem with initial separation `geometry` (per cell, m) on `grid` (DC-FFT operators).
    pub fn new(
        grid: SurfaceGrid,
        compliance: Compliance,
        geometry: Vec<f64>,
        params: ContactParams,
    ) -> Result<Self, SamError> {
        Self::with_operators(grid, compliance, geometry, params)
    }
}

impl<S: OperatorSet> ContactProblem<S> {
    /// [`ContactProblem::new`] on the operators of `S`.
    pub fn with_operators(
        grid: SurfaceGrid,
        compliance: Compliance,
        geometry: Vec<f64>,
        params: ContactParams,
    ) -> Result<Self, SamError> {
        if !(params.friction.is_finite() && params.friction >= 0.0) {
            return Err(SamError::InvalidParameter {
                name: "friction coefficient μ",
                value: params.friction,
                allowed: "finite and ≥ 0",
            });
        }
        let n = grid.len();
        if geometry.len() != n {
            return Err(SamError::Numerics(
                halfspace_numerics::NumericsError::LengthMismatch {
                    what: "geometry",
                    expected: n,
                    got: geometry.len(),
                },
            ));
        }
        let coupled = compliance.is_coupled(params.friction);
        // Refused before anything is built (docs/architecture.md, "Memory is checked before
        // allocating"). Without friction the tangential fields are empty (q = 0, nothing to
        // store): a frictionless problem holds the geometry, h and p only
        // (docs/theory-sam.md#normal-contact), 24 B per cell.
        let frictional = params.friction > 0.0;
        crate::memory::check_problem(&grid, frictional, coupled)?;
        let (d1, d2) = (2.0 * grid.half1, 2.0 * grid.half2);
        let kappa = compliance.coupling;
        let shape = |alpha: InPlane, sign: f64| {
            move |m: i64, n: i64| {
                sign * kappa * compliance.coupling_shape(&grid, alpha, m as f64 * d1, n as f64 * d2)
            }
        };
        let (x1, x2) = (InPlane::X1, InPlane::X2);
        let (c1p, c2p, c1m, c2m) = (
            shape(x1, 1.0),
            shape(x2, 1.0),
            shape(x1, -1.0),
            shape(x2, -1.0),
        );
        // One padded and one periodic core for every operator of the problem.
        let fft = Fft2d::new(grid.n1, grid.n2)?;
        let periodic = Fft2d::periodic(grid.n1, grid.n2)?;
        let (shear_to_normal, pressure_to_tangential) = if coupled {
            let a: [Option<KernelFn>; 2] = [Some(&c1p), Some(&c2p)];
            let b: [Option<KernelFn>; 2] = [Some(&c1m), Some(&c2m)];
            (
                Some(S::Blocks::build(&fft, 2, 1, &a)?),
                Some(S::Blocks::build(&fft, 1, 2, &b)?),
            )
        } else {
            (None, None)
        };
        let z = || vec![0.0; n];
        let t = || if frictional { vec![0.0; n] } else { Vec::new() };
        let c_only = || if coupled { vec![0.0; n] } else { Vec::new() };
        Ok(Self {
            normal: NormalSolver::on_cores(grid, &compliance, &fft, &periodic)?,
            tangential: if params.friction > 0.0 {
                Some(TangentialSolver::on_cores(
                    grid,
                    &compliance,
                    &fft,
                    &periodic,
                )?)
            } else {
                None
            },
            shear_to_normal,
            pressure_to_tangential,
            grid,
            params,
            coupled,
            geometry,
            state: ContactState {
                pressure: z(),
                shear: [t(), t()],
                tangential_displacement: [t(), t()],
                slip: [t(), t()],
                shift: [0.0; 2],
                approach: 0.0,
                force: 0.0,
            },
            h: Vec::new(),
            c: [t(), t()],
            b: [t(), t()],
            bound: t(),
            p_prev: c_only(),
            q_prev: [c_only(), c_only()],
            tq: [t(), t()],
            w: [t(), t()],
            u3: c_only(),
            rim: if frictional {
                vec![false; n]
            } else {
                Vec::new()
            },
            eigen: None,
            trial_displacement: [t(), t()],
            trial_shift: [0.0; 2],
            trace: Vec::with_capacity(TRACE_LIMIT),
            solves: 0,
            compliance,
            window: None,
            window_misses: 0,
            whole_grid_only: false,
        })
    }

    /// Solves the contact on the cells of `window` only (`None`: on the whole grid again): the
    /// compliance restricted to the window is the same block of the same operators (the DC-FFT
    /// convolution of the window's cells), so while the deformed gap stays open outside the
    /// window its solution is the whole grid's (to the solvers' tolerances: their
    /// preconditioners and iterates are the window's; docs/performance.md, "A contact window
    /// for the 3D loops"). Every solve checks that on the whole grid: the deformed gap
    /// `h₀ + u₃^eig − δ + K p + κ⟦P_B⟧ * q` positive at every cell outside the window (one
    /// product of the whole grid's operators; [`SamError::ContactOutsideWindow`] inside). The problem's fields stay the whole grid's
    /// ([`ContactProblem::state`], [`ContactProblem::geometry`], the eigen-displacements):
    /// pressure, shear and slip are 0 outside the window, and the tangential displacement
    /// `Δu = T q + c` (the friction history) is computed on the whole grid after every solve
    /// (one product of the whole grid's tangential operators). A solve whose contact reaches
    /// the window's edge or whose deformed gap closes outside it is solved again on the whole
    /// grid from the window's result, and a solve whose warm start has pressure or shear outside
    /// the window runs on the whole grid (counted by [`ContactProblem::window_misses`]): which
    /// grid a solve takes is a function of the state and the load, so a restored state
    /// continues bit for bit. Refused when the state has pressure or shear outside the window.
    pub fn set_window(&mut self, window: Option<GridWindow>) -> Result<(), SamError> {
        let Some(window) = window else {
            self.window = None;
            return Ok(());
        };
        window.check(&self.grid)?;
        let n2 = self.grid.n2;
        self.check_outside(&window, &self.state)?;
        let mut inner = ContactProblem::<S>::with_operators(
            window.grid(&self.grid),
            self.compliance,
            window.gather(n2, &self.geometry),
            self.params,
        )?;
        if let Some(eig) = &self.eigen {
            let e = [
                window.gather(n2, &eig[0]),
                window.gather(n2, &eig[1]),
                window.gather(n2, &eig[2]),
            ];
            inner.set_eigen_displacements(Some([&e[0], &e[1], &e[2]]))?;
        }
        inner.restore_state(&window.gather_state(n2, &self.state))?;
        self.window = Some(Box::new(Windowed {
            window,
            inner,
            gap: vec![0.0; self.grid.len()],
        }));
        Ok(())
    }

    /// The window the contact is solved on, if any ([`ContactProblem::set_window`]).
    pub fn window(&self) -> Option<GridWindow> {
        self.window.as_ref().map(|w| w.window)
    }

    /// Refuses a state with pressure or shear outside `window`.
    fn check_outside(&self, window: &GridWindow, state: &ContactState) -> Result<(), SamError> {
        let n2 = self.grid.n2;
        let outside = |f: &[f64]| {
            f.iter()
                .enumerate()
                .any(|(k, v)| *v != 0.0 && !window.contains(n2, k))
        };
        if outside(&state.pressure) || outside(&state.shear[0]) || outside(&state.shear[1]) {
            return Err(SamError::InvalidInput(format!(
                "the contact state has pressure or shear outside the contact window {window:?}"
            )));
        }
        Ok(())
    }

    /// After a solve on the window: its pressure, shear and slip into the whole grid's state,
    /// the check of the whole grid's deformed gap outside the window, then the whole grid's
    /// trial tangential displacement `Δuⁿ⁺¹ = T q + c` (what [`ContactProblem::commit`] makes the
    /// history; with `committed`, the window's solve committed it already: into the state now).
    fn finish_window_solve(&mut self, committed: bool) -> Result<(), SamError> {
        let w = self.window.as_mut().expect("a window");
        self.trace.clone_from(&w.inner.trace);
        let n2 = self.grid.n2;
        let (win, inner) = (w.window, &w.inner.state);
        win.scatter(n2, &inner.pressure, &mut self.state.pressure);
        for a in 0..2 {
            win.scatter(n2, &inner.shear[a], &mut self.state.shear[a]);
            win.scatter(n2, &inner.slip[a], &mut self.state.slip[a]);
        }
        self.state.approach = inner.approach;
        self.state.force = inner.force;
        self.trial_shift = if committed {
            inner.shift
        } else {
            w.inner.trial_shift
        };
        // g = h₀ + u₃^eig − δ + K p + κ⟦P_B⟧ * q on the whole grid.
        let coupled = self.shear_coupling()?;
        let w = self.window.as_mut().expect("a window");
        self.normal.displacement(&self.state.pressure, &mut w.gap)?;
        if coupled {
            w.gap.iter_mut().zip(&self.u3).for_each(|(g, u)| *g += u);
        }
        let delta = self.state.approach;
        let mut closest = f64::INFINITY;
        for (k, g) in w.gap.iter_mut().enumerate() {
            *g += self.geometry[k] - delta;
            if let Some(eig) = &self.eigen {
                *g += eig[2][k];
            }
            if !win.contains(n2, k) {
                closest = closest.min(*g);
            }
        }
        if closest <= 0.0 {
            return Err(SamError::ContactOutsideWindow {
                cells: win.cells,
                gap: closest,
            });
        }
        // Δuⁿ⁺¹ = T q + c, c = −κ⟦P_B⟧ * p + u_α^eig, on the whole grid (as a whole-grid solve ends).
        if let Some(solver) = &mut self.tangential {
            let [t0, t1] = &mut self.tq;
            solver.displacement([&self.state.shear[0], &self.state.shear[1]], [t0, t1])?;
            self.tangential_known_part()?;
            for a in 0..2 {
                for k in 0..self.trial_displacement[a].len() {
                    self.trial_displacement[a][k] = self.tq[a][k] + self.c[a][k];
                }
            }
            // The slip `S = b − T q = (Δuⁿ − Dⁿ) + D − c − T q` on the whole grid (outside the
            // contact the relative displacement's change, as a whole-grid solve writes it); the
            // window's own values on its cells.
            let shift = self.trial_shift;
            for a in 0..2 {
                let history = &self.state.tangential_displacement[a];
                let previous = self.state.shift[a];
                for (k, s) in self.state.slip[a].iter_mut().enumerate() {
                    *s = (history[k] - previous) + shift[a] - self.c[a][k] - self.tq[a][k];
                }
                let w = self.window.as_ref().expect("a window");
                w.window
                    .scatter(n2, &w.inner.state.slip[a], &mut self.state.slip[a]);
            }
        }
        if committed {
            for a in 0..2 {
                self.state.tangential_displacement[a].copy_from_slice(&self.trial_displacement[a]);
            }
            self.state.shift = self.trial_shift;
        }
        Ok(())
    }

    /// Whether this solve runs on the window: set, and the state's pressure and shear (its warm
    /// start) vanish outside it. Then the window's problem starts from the whole grid's state
    /// (the same values when its last solve was the window's: a function of the state alone,
    /// so a resumed loop takes the same path).
    fn enter_window(&mut self) -> bool {
        let Some(w) = &self.window else {
            return false;
        };
        if self.check_outside(&w.window, &self.state).is_err() {
            self.window_misses += 1;
            return false;
        }
        let n2 = self.grid.n2;
        let w = self.window.as_mut().expect("a window");
        let (win, inner) = (w.window, &mut w.inner.state);
        let copy = |field: &[f64], out: &mut Vec<f64>| win.gather_into(n2, field, out);
        copy(&self.state.pressure, &mut inner.pressure);
        for a in 0..2 {
            copy(&self.state.shear[a], &mut inner.shear[a]);
            copy(&self.state.slip[a], &mut inner.slip[a]);
        }
        inner.approach = self.state.approach;
        inner.force = self.state.force;
        true
    }

    /// A solve of an increment begun on the window that runs on the whole grid (the window did
    /// not take it): the window's next solve is a first one (its last `b` is not this solve's).
    fn on_whole_grid(&mut self) {
        if let Some(w) = &mut self.window {
            w.inner.solves = 0;
        }
    }

    /// Sets the known surface eigen-displacements `u^eig = (u₁, u₂, u₃)` of the half-space (
    /// docs/theory-sam.md#eigen-displacements, \[LN11\] Eqs. 14–15): `u₃^eig` enters the initial separation `h = h₀ + u₃^eig`, `u_α^eig`
    /// the relative tangential displacement (and so the slip and the friction history). They apply
    /// to the next [`ContactProblem::solve`]; `None` removes them.
    pub fn set_eigen_displacements(&mut self, u: Option<[&[f64]; 3]>) -> Result<(), SamError> {
        let n = self.grid.len();
        match u {
            None => self.eigen = None,
            Some(fields) => {
                for f in fields {
                    if f.len() != n {
                        return Err(SamError::Numerics(
                            halfspace_numerics::NumericsError::LengthMismatch {
                                what: "eigen-displacement field",
                                expected: n,
                                got: f.len(),
                            },
                        ));
                    }
                    if let Some(v) = f.iter().find(|v| !v.is_finite()) {
                        return Err(SamError::InvalidParameter {
                            name: "eigen-displacement",
                            value: *v,
                            allowed: "finite",
                        });
                    }
                }
                let store = self
                    .eigen
                    .get_or_insert_with(|| [vec![0.0; n], vec![0.0; n], vec![0.0; n]]);
                for (s, f) in store.iter_mut().zip(fields) {
                    s.copy_from_slice(f);
                }
            }
        }
        if let Some(w) = &mut self.window {
            let n2 = self.grid.n2;
            match &self.eigen {
                None => w.inner.set_eigen_displacements(None)?,
                Some(eig) => {
                    let e = [
                        w.window.gather(n2, &eig[0]),
                        w.window.gather(n2, &eig[1]),
                        w.window.gather(n2, &eig[2]),
                    ];
                    w.inner
                        .set_eigen_displacements(Some([&e[0], &e[1], &e[2]]))?;
                }
            }
        }
        Ok(())
    }

    /// The initial separation `h₀` per cell (m): the geometry the problem was made with, or the
    /// last one given to [`ContactProblem::set_geometry`].
    pub fn geometry(&self) -> &[f64] {
        &self.geometry
    }

    /// Replaces the initial separation `h₀` (a worn gap, docs/wear3d.md#the-worn-gap): it applies
    /// to the next [`ContactProblem::solve`]; the state and the friction history are kept. The
    /// field must have one finite value per cell.
    pub fn set_geometry(&mut self, geometry: &[f64]) -> Result<(), SamError> {
        if geometry.len() != self.geometry.len() {
            return Err(SamError::Numerics(
                halfspace_numerics::NumericsError::LengthMismatch {
                    what: "geometry",
                    expected: self.geometry.len(),
                    got: geometry.len(),
                },
            ));
        }
        if let Some(v) = geometry.iter().find(|v| !v.is_finite()) {
            return Err(SamError::InvalidParameter {
                name: "geometry (initial separation)",
                value: *v,
                allowed: "finite",
            });
        }
        self.geometry.copy_from_slice(geometry);
        if let Some(w) = &mut self.window {
            w.inner
                .set_geometry(&w.window.gather(self.grid.n2, geometry))?;
        }
        Ok(())
    }

    /// The deformed gap of the current state, `g = h₀ + u₃^eig − δ + K p` per cell
    /// (docs/theory-sam.md#normal-contact; without the coupling term `κ⟦P_B⟧ * q`, zero for
    /// `κ = 0`): `≈ 0` where `p > 0`, `> 0` outside. Written into `out` (one value per cell).
    pub fn deformed_gap(&mut self, out: &mut [f64]) -> Result<(), SamError> {
        self.normal.displacement(&self.state.pressure, out)?;
        let delta = self.state.approach;
        for (k, g) in out.iter_mut().enumerate() {
            *g += self.geometry[k] - delta;
        }
        if let Some(eig) = &self.eigen {
            out.iter_mut().zip(&eig[2]).for_each(|(g, u)| *g += u);
        }
        Ok(())
    }

    /// The grid.
    pub fn grid(&self) -> &SurfaceGrid {
        &self.grid
    }

    /// The parameters.
    pub fn params(&self) -> &ContactParams {
        &self.params
    }

    /// The friction coefficient μ.
    pub fn friction(&self) -> f64 {
        self.params.friction
    }

    /// Whether the normal–tangential coupling is active (`κ ≠ 0` and `μ > 0`).
    pub fn is_coupled(&self) -> bool {
        self.coupled
    }

    /// The changes of each alternation of the solves since the last [`ContactProblem::begin`], in
    /// order (for observers: the contraction of the alternation, docs/performance.md).
    pub fn alternation_trace(&self) -> &[AlternationStep] {
        &self.trace
    }

    /// The converged state of the last increment.
    pub fn state(&self) -> &ContactState {
        &self.state
    }

    /// Restores a converged state (a checkpoint's): every field must have this problem's length
    /// (empty tangential fields for a frictionless problem) and be finite. The next increment then
    /// starts from it exactly as it would have after the increment that produced it. The next
    /// solve is a first solve of its increment, as after [`ContactProblem::begin`] (the gauged
    /// alternation gauges only re-solves from the same start, docs/theory-sam.md#normal-tangential-alternation):
    /// a nested force control restores its warm start before every evaluation
    /// ([`super::InhomogeneousContact::increment_with_force`]), and each evaluation is a function
    /// of its shift alone.
    pub fn restore_state(&mut self, state: &ContactState) -> Result<(), SamError> {
        let fields = |s: &ContactState| {
            [
                s.pressure.len(),
                s.shear[0].len(),
                s.shear[1].len(),
                s.tangential_displacement[0].len(),
                s.tangential_displacement[1].len(),
                s.slip[0].len(),
                s.slip[1].len(),
            ]
        };
        if fields(state) != fields(&self.state) {
            return Err(SamError::Numerics(
                halfspace_numerics::NumericsError::LengthMismatch {
                    what: "restored contact state fields",
                    expected: self.state.pressure.len(),
                    got: state.pressure.len(),
                },
            ));
        }
        let all = [
            &state.pressure,
            &state.shear[0],
            &state.shear[1],
            &state.tangential_displacement[0],
            &state.tangential_displacement[1],
            &state.slip[0],
            &state.slip[1],
        ];
        let scalars = [state.shift[0], state.shift[1], state.approach, state.force];
        if let Some(bad) = all
            .iter()
            .flat_map(|v| v.iter())
            .chain(scalars.iter())
            .find(|v| !v.is_finite())
        {
            return Err(SamError::InvalidParameter {
                name: "restored contact state value",
                value: *bad,
                allowed: "finite",
            });
        }
        self.state.clone_from(state);
        self.solves = 0;
        if let Some(w) = &mut self.window {
            w.inner
                .restore_state(&w.window.gather_state(self.grid.n2, state))?;
        }
        Ok(())
    }

    /// One increment to normal load `load` and rigid shift `shift` (docs/theory-sam.md#loading-history):
    /// [`ContactProblem::begin`], [`ContactProblem::solve`], [`ContactProblem::commit`].
    pub fn increment(
        &mut self,
        load: NormalLoad,
        shift: [f64; 2],
    ) -> Result<IncrementInfo, SamError> {
        self.begin();
        let info = self.solve(load, shift)?;
        self.commit();
        Ok(info)
    }

    /// Starts an increment: the friction history `w = Δuⁿ − Dⁿ` from the committed state (
    /// docs/theory-sam.md#incremental-friction-law). Any number of [`ContactProblem::solve`] calls may follow (an outer loop re-solving the
    /// increment with new eigen-displacements, a force control searching the shift); only
    /// [`ContactProblem::commit`] changes the history.
    pub fn begin(&mut self) {
        self.trace.clear();
        self.solves = 0;
        if let Some(w) = &mut self.window {
            w.inner.begin();
        }
        let n = self.state.tangential_displacement[0].len();
        for a in 0..2 {
            for k in 0..n {
                self.w[a][k] = self.state.tangential_displacement[a][k] - self.state.shift[a];
            }
        }
    }

    /// Makes the last [`ContactProblem::solve`] the converged state of the increment: `Δuⁿ⁺¹` and
    /// `Dⁿ⁺¹` become the history of the next one (docs/theory-sam.md#history-variables).
    pub fn commit(&mut self) {
        if let Some(w) = &mut self.window {
            w.inner.commit();
        }
        for a in 0..2 {
            self.state.tangential_displacement[a].copy_from_slice(&self.trial_displacement[a]);
        }
        self.state.shift = self.trial_shift;
        self.sync_window_history();
    }

    /// The window's friction history made the whole grid's (its values on the window's cells):
    /// the window's next increment starts from exactly what a problem restored from this state
    /// would (a resumed loop repeats the uninterrupted one bit for bit).
    fn sync_window_history(&mut self) {
        if let Some(w) = &mut self.window {
            let n2 = self.grid.n2;
            for a in 0..2 {
                let field = &self.state.tangential_displacement[a];
                if !field.is_empty() {
                    w.window
                        .gather_into(n2, field, &mut w.inner.state.tangential_displacement[a]);
                }
            }
            w.inner.state.shift = self.state.shift;
        }
    }

    /// The solves of this problem that its window ([`ContactProblem::set_window`]) did not take
    /// (their contact reached the window's edge or beyond, or their warm start had contact
    /// outside it) and that ran on the whole grid instead.
    pub fn window_misses(&self) -> usize {
        self.window_misses
    }

    /// Solves the current increment (after [`ContactProblem::begin`]) to normal load `load` and
    /// rigid shift `shift`: Panagiotopoulos alternation of the normal solve (shear frozen) and the
    /// tangential solve (pressure frozen) until both stop changing (docs/theory-sam.md#normal-tangential-alternation); one pass when
    /// uncoupled. The eigen-displacements enter `h` and `Δu`. Pressure and shear are updated (and
    /// serve as warm starts); the history is not.
    pub fn solve(&mut self, load: NormalLoad, shift: [f64; 2]) -> Result<IncrementInfo, SamError> {
        self.solve_loosely(load, shift, 1.0)
    }

    /// [`ContactProblem::solve`] with the alternation and tangential tolerances multiplied by
    /// `slack ≥ 1` (the tangential one at most [`INEXACT_CEILING`]): for an outer loop whose next
    /// pass re-solves the increment anyway (the EIM loop of docs/theory-sam.md#nested-loops far from convergence), as the
    /// inexact alternation does for its own early passes. `slack = 1` is [`ContactProblem::solve`].
    /// Runs on one of rayon's worker threads ([`halfspace_numerics::parallel::on_pool`]: one
    /// hand-off per solve, not one per parallel section).
    pub fn solve_loosely(
        &mut self,
        load: NormalLoad,
        shift: [f64; 2],
        slack: f64,
    ) -> Result<IncrementInfo, SamError> {
        if !self.whole_grid_only && self.enter_window() {
            let w = self.window.as_mut().expect("a window");
            let solved = w.inner.solve_loosely(load, shift, slack);
            let outcome = solved.and_then(|info| self.finish_window_solve(false).map(|()| info));
            match outcome {
                Ok(info) => return Ok(info),
                // The contact reaches the window's edge or beyond: this solve on the whole grid
                // (below), from the window's result.
                Err(SamError::ContactOutsideWindow { .. } | SamError::ContactAtDomainEdge) => {
                    self.window_misses += 1;
                }
                Err(e) => return Err(e),
            }
        }
        if self.window.is_some() {
            self.on_whole_grid();
        }
        halfspace_numerics::parallel::on_pool(self.grid.len(), || {
            self.solve_loosely_here(load, shift, slack)
        })
    }

    /// [`ContactProblem::solve_loosely`] on the calling thread.
    /// `c = −κ⟦P_B⟧ * p + u_α^eig` of the current pressure into `self.c` (0 when neither term is
    /// present): the known part of the tangential displacement (docs/theory-sam.md#incremental-friction-law).
    fn tangential_known_part(&mut self) -> Result<(), SamError> {
        if let Some(op) = &mut self.pressure_to_tangential {
            let [c0, c1] = &mut self.c;
            op.apply(&[&self.state.pressure], &mut [c0, c1])?;
        }
        if let Some(eig) = &self.eigen {
            for a in 0..2 {
                if self.pressure_to_tangential.is_none() {
                    self.c[a].copy_from_slice(&eig[a]);
                } else {
                    self.c[a].iter_mut().zip(&eig[a]).for_each(|(c, u)| *c += u);
                }
            }
        } else if self.pressure_to_tangential.is_none() {
            self.c[0].fill(0.0);
            self.c[1].fill(0.0);
        }
        Ok(())
    }

    /// `κ⟦P_B⟧ * q` of the current shear into `self.u3`; whether the coupling is present (else
    /// `u3` is not written).
    fn shear_coupling(&mut self) -> Result<bool, SamError> {
        let Some(op) = &mut self.shear_to_normal else {
            return Ok(false);
        };
        op.apply(
            &[&self.state.shear[0], &self.state.shear[1]],
            &mut [&mut self.u3],
        )?;
        Ok(true)
    }

    fn solve_loosely_here(
        &mut self,
        load: NormalLoad,
        shift: [f64; 2],
        slack: f64,
    ) -> Result<IncrementInfo, SamError> {
        if !(slack.is_finite() && slack >= 1.0) {
            return Err(SamError::InvalidParameter {
                name: "contact tolerance slack",
                value: slack,
                allowed: "finite and ≥ 1",
            });
        }
        for s in shift {
            if !s.is_finite() {
                return Err(SamError::InvalidParameter {
                    name: "tangential shift",
                    value: s,
                    allowed: "finite",
                });
            }
        }
        let n = self.grid.len();
        let mu = self.params.friction;
        let mut alternations = 0;
        // Inexact alternation: while the alternation is still moving by `change`, the tangential
        // solve need not be tighter than a hundredth of it (it is re-solved anyway); the
        // alternation stops only after a pass at the full tolerance.
        let mut change: f64 = f64::INFINITY;
        let tight = if slack > 1.0 {
            let base = self.params.tangential;
            let kkt = (base.kkt_tolerance * slack).min(INEXACT_CEILING.max(base.kkt_tolerance));
            TangentialParams {
                kkt_tolerance: kkt,
                tolerance: base.tolerance * kkt / base.kkt_tolerance,
                ..base
            }
        } else {
            self.params.tangential
        };
        let alternation_tolerance = self.params.alternation_tolerance * slack;
        let (mut normal_info, mut tangential_info);
        let mut normal_full;
        let (mut normal_total, mut tangential_total) = (0, 0);
        let solve_index = self.solves;
        // The gauged first alternation: only in a re-solve, whose last b is this increment's.
        let gauged = self.coupled && self.params.alternation == Alternation::Gauged;
        let gauge_first = gauged && solve_index > 0;
        // The normal solve's full tolerance: scaled by the slack (at most to the loosest early
        // solve's) when gauged, the plain one's otherwise.
        let normal_tight = if gauged {
            let base = self.params.normal;
            NormalParams {
                tolerance: (base.tolerance * slack).min(NORMAL_CEILING.max(base.tolerance)),
                ..base
            }
        } else {
            self.params.normal
        };
        self.solves += 1;
        // Gauged: after an alternation whose change did not fall below the last one's, the next
        // alternation solves both problems to the full tolerances (the plain step's guard).
        let (mut full_next, mut last_change) = (false, f64::INFINITY);
        loop {
            alternations += 1;
            if self.tangential.is_some() && self.params.tangential.warm_start {
                // The rim of the state the tangential solve starts from, before the normal solve
                // moves p (docs/theory-sam.md#warm-starts-of-the-tangential-solve).
                for k in 0..n {
                    self.rim[k] = !is_stick(
                        mu * self.state.pressure[k],
                        self.state.shear[0][k],
                        self.state.shear[1][k],
                    ) && self.state.pressure[k] > 0.0;
                }
            }
            if self.coupled {
                self.p_prev.copy_from_slice(&self.state.pressure);
                self.q_prev[0].copy_from_slice(&self.state.shear[0]);
                self.q_prev[1].copy_from_slice(&self.state.shear[1]);
            }
            // Normal solve with q frozen: h = h₀ + u₃^eig + κ⟦P_B⟧ * q (h₀ itself when neither
            // term is present: no copy is held then).
            let h = if self.eigen.is_none() && self.shear_to_normal.is_none() {
                &self.geometry
            } else {
                self.h.resize(n, 0.0);
                self.h.copy_from_slice(&self.geometry);
                if let Some(eig) = &self.eigen {
                    self.h.iter_mut().zip(&eig[2]).for_each(|(h, u)| *h += u);
                }
                if self.shear_coupling()? {
                    self.h.iter_mut().zip(&self.u3).for_each(|(h, u)| *h += u);
                }
                &self.h
            };
            // Gauged: the normal solves of the early alternations to 10⁻⁴ of the last change
            // (full when it is below 10⁻⁶, as the tangential solve's), except the first of a
            // re-solve, whose change is not known yet; the full tolerance scaled by the slack
            // as the tangential one is.
            let normal_params = if gauged && self.params.inexact_alternation && !full_next {
                let loose = if gauge_first && alternations == 1 {
                    normal_tight.tolerance
                } else {
                    (NORMAL_GAUGE * change).clamp(
                        normal_tight.tolerance,
                        NORMAL_CEILING.max(normal_tight.tolerance),
                    )
                };
                NormalParams {
                    tolerance: loose,
                    ..normal_tight
                }
            } else {
                normal_tight
            };
            normal_full = normal_params == normal_tight;
            normal_info = self
                .normal
                .solve(h, load, &mut self.state.pressure, &normal_params)?;
            normal_total += normal_info.iterations;
            // The change the first alternation meets (Alternation::Gauged): the normal solve's.
            let mut first_change = 0.0f64;
            if gauge_first && alternations == 1 {
                let pmax = max_of(&self.state.pressure);
                let dp = max_gap(&self.state.pressure, &self.p_prev);
                first_change = if pmax > 0.0 { dp / pmax } else { f64::INFINITY };
            }
            if self.tangential.is_none() {
                // μ = 0: no shear and no tangential fields (docs/theory-sam.md#normal-contact alone).
                tangential_info = TangentialInfo::frictionless(normal_info.contact_cells);
                break;
            }
            // Tangential solve with p frozen: c = −κ⟦P_B⟧ * p + u_α^eig, b = w + D − c.
            self.tangential_known_part()?;
            let tangential = self.tangential.as_mut().expect("μ > 0");
            // b and the bound; in a gauged re-solve's first alternation also the change of b
            // since the last alternation of the last solve (the change it meets).
            let measure_b = gauge_first && alternations == 1;
            let (mut db, mut bmax) = (0.0f64, 0.0f64);
            for k in 0..n {
                self.bound[k] = mu * self.state.pressure[k];
                for a in 0..2 {
                    let b = self.w[a][k] + shift[a] - self.c[a][k];
                    if measure_b {
                        db = db.max((b - self.b[a][k]).abs());
                        bmax = bmax.max(b.abs());
                    }
                    self.b[a][k] = b;
                }
            }
            if measure_b {
                first_change = first_change.max(if bmax > 0.0 { db / bmax } else { 0.0 });
            }
            let [q0, q1] = &mut self.state.shear;
            // Rim warm start: a cell that slipped starts on its new circle `|q| = μp`
            // (docs/theory-sam.md#warm-starts-of-the-tangential-solve; no cell is marked
            // without `TangentialParams::warm_start`).
            for k in 0..n {
                if self.rim[k] && self.bound[k] > 0.0 {
                    let m = q0[k].hypot(q1[k]);
                    if m > 0.0 {
                        q0[k] *= self.bound[k] / m;
                        q1[k] *= self.bound[k] / m;
                    }
                }
            }
            let [s0, s1] = &mut self.state.slip;
            let gauge = if gauge_first && alternations == 1 {
                first_change
            } else {
                change
            };
            // The plain alternation's early tangential solves to a hundredth of the last change,
            // the gauged one's to TANGENTIAL_GAUGE of it (its first of a re-solve: of the change
            // it meets).
            let factor = if gauged { TANGENTIAL_GAUGE } else { 0.01 };
            let loose = (factor * gauge).clamp(tight.kkt_tolerance, INEXACT_CEILING);
            let tangential_params = if self.coupled
                && self.params.inexact_alternation
                && loose > tight.kkt_tolerance
                && !full_next
            {
                TangentialParams {
                    kkt_tolerance: loose,
                    tolerance: tight.tolerance * loose / tight.kkt_tolerance,
                    ..tight
                }
            } else {
                tight
            };
            let at_full_tolerance = tangential_params == tight && normal_full;
            tangential_info = tangential.solve(
                &self.bound,
                [&self.b[0], &self.b[1]],
                [q0, q1],
                [s0, s1],
                &tangential_params,
            )?;
            tangential_total += tangential_info.iterations;
            if !self.coupled {
                break;
            }
            let pmax = max_of(&self.state.pressure);
            let dp = max_gap(&self.state.pressure, &self.p_prev);
            let dq = max_gap(&self.state.shear[0], &self.q_prev[0])
                .max(max_gap(&self.state.shear[1], &self.q_prev[1]));
            let tol = alternation_tolerance;
            change = (dp / pmax).max(dq / (mu * pmax));
            full_next = gauged && !at_full_tolerance && change >= last_change;
            last_change = change;
            let converged = (alternations > 1 || gauged)
                && at_full_tolerance
                && dp <= tol * pmax
                && dq <= tol * mu * pmax;
            let step = AlternationStep {
                solve: solve_index,
                pressure_change: dp / pmax,
                shear_change: dq / (mu * pmax),
                normal_iterations: normal_info.iterations,
                tangential_products: tangential_info.iterations,
                full_tolerance: at_full_tolerance,
            };
            if self.trace.len() < TRACE_LIMIT {
                self.trace.push(step);
            }
            if converged {
                break;
            }
            if alternations >= self.params.max_alternations {
                return Err(SamError::NoConvergence {
                    solver: "Panagiotopoulos alternation",
                    iterations: alternations,
                    residual: (dp / pmax).max(dq / (mu * pmax)),
                });
            }
        }
        // Δuⁿ⁺¹ = T q + c (the trial history, committed by `commit`).
        {
            let [t0, t1] = &mut self.tq;
            match &mut self.tangential {
                Some(solver) => {
                    solver.displacement([&self.state.shear[0], &self.state.shear[1]], [t0, t1])?
                }
                None => {
                    t0.fill(0.0);
                    t1.fill(0.0);
                }
            }
        }
        for a in 0..2 {
            for k in 0..self.trial_displacement[a].len() {
                self.trial_displacement[a][k] = self.tq[a][k] + self.c[a][k];
            }
        }
        self.trial_shift = shift;
        self.state.approach = normal_info.approach;
        self.state.force = normal_info.force;
        let area = self.grid.cell_area();
        let stick = (0..self.bound.len())
            .filter(|&k| {
                is_stick(
                    self.bound[k],
                    self.state.shear[0][k],
                    self.state.shear[1][k],
                )
            })
            .count();
        Ok(IncrementInfo {
            alternations,
            normal: normal_info,
            tangential: tangential_info,
            normal_iterations_total: normal_total,
            tangential_iterations_total: tangential_total,
            tangential_force: [
                area * self.state.shear[0].iter().sum::<f64>(),
                area * self.state.shear[1].iter().sum::<f64>(),
            ],
            contact_area: area * normal_info.contact_cells as f64,
            stick_area: area * stick as f64,
            max_pressure: self.state.pressure.iter().cloned().fold(0.0, f64::max),
        })
    }

    /// One increment to a prescribed tangential force `Q₁` (with `Q₂` left free at `D₂ = 0`): the
    /// shift `D₁` is found by Brent's method on the monotone map `D₁ ↦ Q₁(D₁)` (docs/theory-sam.md#stick-slip-solver-and-force-control), each
    /// evaluation a displacement-controlled increment from the same history. `|Q₁| ≥ μW` is gross
    /// slip and refused.
    pub fn increment_with_force(
        &mut self,
        load: NormalLoad,
        force: f64,
        bracket: f64,
    ) -> Result<(IncrementInfo, f64), SamError> {
        if !self.whole_grid_only && self.window.is_some() {
            // On the window when it takes the increment; otherwise every evaluation on the whole
            // grid, from the committed history and the increment's warm start.
            if self.enter_window() {
                let (warm_p, warm_q) = (self.state.pressure.clone(), self.state.shear.clone());
                let w = self.window.as_mut().expect("a window");
                let solved = w.inner.increment_with_force(load, force, bracket);
                let outcome = solved.and_then(|done| self.finish_window_solve(true).map(|()| done));
                match outcome {
                    Ok(done) => {
                        self.sync_window_history();
                        return Ok(done);
                    }
                    // The history is not yet overwritten (the check comes first); the
                    // window's own back to the whole grid's (its solve committed).
                    Err(SamError::ContactOutsideWindow { .. } | SamError::ContactAtDomainEdge) => {
                        self.window_misses += 1;
                        self.sync_window_history();
                        self.state.pressure = warm_p;
                        self.state.shear = warm_q;
                    }
                    Err(e) => return Err(e),
                }
            }
            self.on_whole_grid();
            self.whole_grid_only = true;
            let done = self.increment_with_force(load, force, bracket);
            self.whole_grid_only = false;
            return done;
        }
        let mu = self.params.friction;
        // Every evaluation solves the same increment from the same history and warm start.
        self.begin();
        let start_shift = self.state.shift;
        let warm_p = self.state.pressure.clone();
        let warm_q = self.state.shear.clone();
        let w_force = match load {
            NormalLoad::Force(w) => w,
            NormalLoad::Approach(_) => {
                let info = self.solve(load, start_shift)?;
                self.state.pressure.copy_from_slice(&warm_p);
                info.normal.force
            }
        };
        if !force.is_finite() || force.abs() >= mu * w_force {
            return Err(SamError::GrossSlip {
                force: force.abs(),
                limit: mu * w_force,
            });
        }
        let tol_q = 1e-6 * mu * w_force;
        let mut eval = |d: f64| -> Result<(f64, IncrementInfo), SamError> {
            // Every evaluation a first solve of the increment: a function of `D₁` alone (the
            // gauged alternation gauges re-solves by the last solve's `b`).
            self.solves = 0;
            self.state.pressure.copy_from_slice(&warm_p);
            self.state.shear[0].copy_from_slice(&warm_q[0]);
            self.state.shear[1].copy_from_slice(&warm_q[1]);
            let info = self.solve(load, [d, start_shift[1]])?;
            Ok((info.tangential_force[0] - force, info))
        };
        let (info, d) = shift_for_force(start_shift[0], bracket, tol_q, &mut eval)?;
        self.commit();
        Ok((info, d))
    }
}

/// `max_k a_k` (0 for an empty or non-positive field).
fn max_of(a: &[f64]) -> f64 {
    a.iter().cloned().fold(0.0, f64::max)
}

/// `max_k |a_k − b_k|`.
fn max_gap(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}
