//! Normal contact by the constrained conjugate gradient of Polonsky & Keer (1999), docs/theory-sam.md#normal-contact, with
//! the DC-FFT operator `K^p_3 *` in place of multi-level summation, and three accelerations, each
//! switchable ([`NormalParams`]) and each giving the same solution:
//!
//! * **one DC-FFT product per iteration**: the displacement `u = K*p` is carried along,
//!   `u ← s(u − τ K*t + K*c)`, where `K*t` is the product the step length needs anyway and `c`
//!   the few cells the projection clipped or re-admitted (added column by column from the
//!   kernel's quadrant table; a full product when many changed, and every
//!   [`REFRESH_INTERVAL`] iterations);
//! * **a spectral preconditioner** on the contact set: the compliance has the symbol
//!   `2/(E*|k|)`, so the direction is `z = Π R P R g` with `P` the circulant of symbol `|k|`
//!   ([`Circulant2d::inverse_half_space`]), `R` the restriction to the contact set and `Π` the
//!   zero-mean projection of force control (preconditioned CG for the bound-constrained QP,
//!   Vollebregt 2014, J. Comput. Phys. 257, 333–351);
//! * **nested-grid continuation** for a cold start: the problem is solved on the grid with
//!   cells twice as large (recursively, down to [`COARSEST_SIDE`] cells per side), and the
//!   bilinear interpolation of that pressure is the fine grid's warm start;
//! * **mixed precision** for a cold start: the DC-FFT products are computed in single precision
//!   (`f32` transforms) until the change of `p` falls below [`SINGLE_PRECISION_SWITCH`]; then the
//!   displacement `u = K*p` is recomputed in double precision (and so is every later full
//!   product) and the iteration goes on to the tolerance, so the gap of the stopping test carries
//!   no single-precision error of `u` itself (the coarse solves of the continuation, whose
//!   tolerance is [`COARSE_TOLERANCE`], stay in single precision). The step products `K*t` stay
//!   in single precision after the switch: `u` then changes by `τ K*t`, steps of relative size
//!   below the switch, so their rounding (`~1e-7` of the step) reaches `u` at `~1e-11` (Hertz
//!   128²–1024² at tol 1e-8: the same iterations, the same distance from a 1e-13 solution,
//!   6–11 % less processor time); below [`SINGLE_STEPS_FLOOR`] (tighter tolerances only) they
//!   go to double precision too. The preconditioner, which only shapes the direction, stays in
//!   single precision for the whole solve. docs/performance.md, "Mixed precision".

use std::marker::PhantomData;

use halfspace_numerics::circulant::Circulant2d;
use halfspace_numerics::fft2d::{Fft2d, PARALLEL_CELLS};
use halfspace_numerics::op::{EvenKernelOperator, FftOperators, OperatorSet};

mod continuation;
pub(crate) mod passes;

use crate::{Compliance, SamError, SurfaceGrid};
use continuation::{coarser, prolong, restrict};
use passes::{sum_lanes, total, Chunks};

/// The exact `u = K*p` replaces the carried one every this many iterations (rounding drift).
pub const REFRESH_INTERVAL: usize = 64;

/// Tolerance of the coarse solves of the nested continuation (they only start the fine solve).
/// On Hertz at tol 1e-8, 1e-4 and 1e-3 gave the same fine iterations on 128²–1024² (12, 13, 12,
/// 12) and 1e-3 fewer coarse ones (128²: 17 → 15 on 64², 1024²: 34 → 27 over four grids); 1e-2
/// cost the fine grid 2–3 iterations more at 512² and 1024² (issue 23; 1e-6 gave the same fine
/// iterations as 1e-4 in issue 10).
pub const COARSE_TOLERANCE: f64 = 1e-3;

/// Cells changed by the projection up to which `K*c` is added column by column; above, the next
/// iteration recomputes `K*p` by a full product (`N` multiply-adds per column: a padded product
/// costs about as much as 8–12 columns on 256²–1024²; 4, 8, 12 and 33 measured on Hertz, and
/// under `perf` the columns took 13 % of a 512² solve at 8).
const SPARSE_COLUMNS: usize = 4;

/// Change of `p` (`Σ|Δp|/Σp`) below which a mixed-precision solve leaves the single-precision
/// products for the double-precision ones. The `f32` products carry relative errors of order
/// 1e-7; the switch restarts the conjugate directions, which costs iterations when it comes late.
/// On Hertz at tol 1e-8, fine iterations (of which in single precision) at 128² / 256² / 512² /
/// 1024²: double only 12 / 13 / 12 / 12; switch at 1e-3: 12 (5) / 13 (4) / 12 (3) / 12 (1);
/// 1e-4: 12 (6) / 13 (6) / 12 (5) / 13 (5); 3e-5: 12 (7) / 13 (8) / 13 (6) / 13 (6); 1e-5:
/// 12 (7) / 14 (9) / 16 (10) / 16 (9); 1e-6: 13 (9) / 15 (10) / 21 (15) / 17 (10) (issue 23).
pub const SINGLE_PRECISION_SWITCH: f64 = 1e-4;

/// Change of `p` below which a mixed-precision solve computes its step products `K*t` in double
/// precision too (after an exact `u = K*p`). Above it they stay single after the switch: their
/// rounding, `~1e-7` of each step, accumulates in `u` to a floor of `~3e-11` of `p_max` (Hertz
/// 128², tol 1e-13, measured), below what a tolerance down to this floor asks for; tighter
/// tolerances then finish in double precision as before (issue 23).
pub const SINGLE_STEPS_FLOOR: f64 = 1e-10;

/// Nested continuation stops coarsening below this many cells per side. 32 rather than 64: on
/// Hertz at tol 1e-8 the 64² grid then starts warm (7 iterations instead of 17, 13 of them with a
/// second product), so a 128² solve does 15 % fewer products counted in fine-grid products
/// (24.5 → 20.8; 256²: −6 %), the fine iterations unchanged (issue 23).
pub const COARSEST_SIDE: usize = 32;

/// What is prescribed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NormalLoad {
    /// Total normal force `W = A Σ p` in N.
    Force(f64),
    /// Rigid approach `δ` in m.
    Approach(f64),
}

/// Stopping rule and accelerations of the normal solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalParams {
    /// `Σ|p_new − p_old| / Σ p_new` below which the iteration stops (in `(0, 1)`).
    pub tolerance: f64,
    /// Iteration limit (≥ 1).
    pub max_iterations: usize,
    /// Spectral (`|k|`) preconditioner on the contact set.
    pub preconditioned: bool,
    /// One DC-FFT product per iteration (the displacement carried along); otherwise two.
    pub incremental: bool,
    /// Nested-grid continuation when the solve starts cold (no usable warm start).
    pub nested: bool,
    /// Single-precision products until the change falls below [`SINGLE_PRECISION_SWITCH`] when
    /// the solve starts cold (warm starts are solved in double precision throughout).
    pub mixed_precision: bool,
}

impl Default for NormalParams {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 10_000,
            preconditioned: true,
            incremental: true,
            nested: true,
            mixed_precision: true,
        }
    }
}

impl NormalParams {
    /// The plain Polonsky–Keer iteration of docs/theory-sam.md#normal-contact (two products per iteration, no
    /// preconditioner, no continuation): the reference the accelerations are tested against.
    pub fn plain() -> Self {
        Self {
            preconditioned: false,
            incremental: false,
            nested: false,
            mixed_precision: false,
            ..Self::default()
        }
    }

    /// Checks the stopping rule: `0 < tolerance < 1`, `max_iterations ≥ 1`.
    pub fn validate(&self) -> Result<(), SamError> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(SamError::InvalidParameter {
                name: "normal solver tolerance",
                value: self.tolerance,
                allowed: "in (0, 1)",
            });
        }
        if self.max_iterations == 0 {
            return Err(SamError::InvalidParameter {
                name: "normal solver iteration limit",
                value: 0.0,
                allowed: "≥ 1",
            });
        }
        Ok(())
    }
}

/// Whether a mixed-precision solve may stop while its products are still in single precision.
#[derive(Debug, Clone, Copy)]
enum Finish {
    /// Only in double precision (every solve a caller asks for).
    Double,
    /// Also in single precision (the coarse solves of the continuation).
    Single,
}

/// What the solve did and found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalInfo {
    /// CG iterations on the finest grid.
    pub iterations: usize,
    /// CG iterations on the coarser grids of the nested continuation (0 without it).
    pub coarse_iterations: usize,
    /// Grids solved (1 without nested continuation).
    pub levels: usize,
    /// Final relative change of `p`.
    pub residual: f64,
    /// Rigid approach `δ` (computed under force control).
    pub approach: f64,
    /// Normal force `W` (computed under approach control).
    pub force: f64,
    /// Cells in contact.
    pub contact_cells: usize,
}

/// The operator, preconditioner and work fields of one grid, allocated at the first solve (after
/// the coarse grids of the nested continuation are done and dropped, so that they never coexist
/// with the fine grid's).
struct Work<Op> {
    op: Op,
    preconditioner: Option<Circulant2d>,
    u: Vec<f64>,
    g: Vec<f64>,
    z: Vec<f64>,
    t: Vec<f64>,
    /// `K*t`, then `p` of the iteration's start.
    r: Vec<f64>,
    /// Cells clipped or re-admitted in one iteration (capacity fixed: no allocation in the loop).
    changed: Vec<(usize, f64)>,
    /// Partial sums of the chunks of a pass ([`passes::CHUNK`] cells each).
    sums: Vec<[f64; 4]>,
    /// What the projection did in each chunk.
    projected: Vec<Projected>,
}

/// The projection (steps 7–8) in one chunk: the sum of the new `p`, whether a cell re-entered the
/// contact, how many cells changed and the first [`SPARSE_COLUMNS`] of them.
#[derive(Debug, Clone, Copy, Default)]
struct Projected {
    sum: f64,
    overlap: bool,
    changes: usize,
    cells: [(usize, f64); SPARSE_COLUMNS],
}

/// The Polonsky–Keer solver on one grid, planned once (operator spectrum, work arrays), on the
/// operators of `S`: the DC-FFT ones ([`FftOperators`], the default) or their dense twins
/// ([`halfspace_numerics::op::DenseOperators`], every `K*` product, here and on the coarse grids,
/// a direct O(N²) sum over the kernel's quadrant; tests compare the two solvers).
pub struct NormalSolver<S: OperatorSet = FftOperators> {
    grid: SurfaceGrid,
    compliance: Compliance,
    /// The padded FFT core of the grid (the operator's; shared with the owner's other operators).
    fft: Fft2d,
    /// The periodic FFT core of the grid (the preconditioner's).
    periodic: Fft2d,
    work: Option<Box<Work<S::Even>>>,
    operators: PhantomData<S>,
}

impl NormalSolver {
    /// A solver for the pair's normal compliance on `grid` with the DC-FFT operator; `K^p_3 *` is
    /// planned (and the memory checked) here, its arrays allocated at the first use.
    pub fn new(grid: SurfaceGrid, compliance: &Compliance) -> Result<Self, SamError> {
        Self::with_operators(grid, compliance)
    }
}

impl<S: OperatorSet> NormalSolver<S> {
    /// [`NormalSolver::new`] on the operators of `S`, with FFT cores of its own.
    pub fn with_operators(grid: SurfaceGrid, compliance: &Compliance) -> Result<Self, SamError> {
        let fft = Fft2d::new(grid.n1, grid.n2)?;
        let periodic = Fft2d::periodic(grid.n1, grid.n2)?;
        Self::on_cores(grid, compliance, &fft, &periodic)
    }

    /// [`NormalSolver::with_operators`] on given padded and periodic cores of the grid's shape
    /// (shared with the other operators of a contact problem).
    pub fn on_cores(
        grid: SurfaceGrid,
        compliance: &Compliance,
        fft: &Fft2d,
        periodic: &Fft2d,
    ) -> Result<Self, SamError> {
        halfspace_numerics::memory::check_fits(
            "the normal contact solver",
            crate::memory::NORMAL_BYTES_PER_CELL * grid.len() as f64,
        )?;
        crate::grid::check_cores(&grid, fft, periodic)?;
        Ok(Self {
            grid,
            compliance: *compliance,
            fft: fft.clone(),
            periodic: periodic.clone(),
            work: None,
            operators: PhantomData,
        })
    }

    /// The operator and work fields, built on first use.
    fn work(&mut self) -> Result<&mut Work<S::Even>, SamError> {
        if self.work.is_none() {
            let n = self.grid.len();
            let quadrant = self.compliance.normal_quadrant(&self.grid, PARALLEL_CELLS);
            self.work = Some(Box::new(Work {
                op: S::Even::build(&self.fft, quadrant)?,
                preconditioner: None,
                u: vec![0.0; n],
                g: vec![0.0; n],
                z: vec![0.0; n],
                t: vec![0.0; n],
                r: vec![0.0; n],
                changed: Vec::with_capacity(SPARSE_COLUMNS),
                sums: vec![[0.0; 4]; Chunks::new(n).count()],
                projected: vec![Projected::default(); Chunks::new(n).count()],
            }));
        }
        Ok(self.work.as_mut().expect("built above"))
    }

    /// Plans the operator now (otherwise done by the first solve): separates the setup from the
    /// solve in timings.
    pub fn plan(&mut self) -> Result<(), SamError> {
        self.work().map(|_| ())
    }

    /// The grid.
    pub fn grid(&self) -> &SurfaceGrid {
        &self.grid
    }

    /// `u = K^p_3 * p` (relative normal displacement of the pressure field).
    pub fn displacement(&mut self, p: &[f64], u: &mut [f64]) -> Result<(), SamError> {
        Ok(self.work()?.op.apply_field(p, u)?)
    }

    /// Solves `p ≥ 0, g = K*p + h − δ ≥ 0, p g = 0` with `h` the initial separation (geometry plus
    /// any known displacement such as the coupling term), under force or approach control
    /// (docs/theory-sam.md#normal-contact). `p` is the warm start and the result; an all-zero or invalid `p` is a cold start
    /// (the nested continuation, if enabled, provides the start).
    pub fn solve(
        &mut self,
        h: &[f64],
        load: NormalLoad,
        p: &mut [f64],
        params: &NormalParams,
    ) -> Result<NormalInfo, SamError> {
        // On one of rayon's worker threads: one hand-off per solve, not one per parallel section
        // (docs/performance.md, "The solve on the pool's threads").
        halfspace_numerics::parallel::on_pool(self.grid.len(), || {
            self.solve_in(h, load, p, params, Finish::Double)
        })
    }

    /// [`NormalSolver::solve`]; `finish` says whether a mixed-precision solve may stop in single
    /// precision (the coarse solves of the continuation, which only start the fine one).
    fn solve_in(
        &mut self,
        h: &[f64],
        load: NormalLoad,
        p: &mut [f64],
        params: &NormalParams,
        finish: Finish,
    ) -> Result<NormalInfo, SamError> {
        params.validate()?;
        let n = self.grid.len();
        if h.len() != n || p.len() != n {
            return Err(SamError::Numerics(
                halfspace_numerics::NumericsError::LengthMismatch {
                    what: "normal solve fields",
                    expected: n,
                    got: h.len().min(p.len()),
                },
            ));
        }
        if let Some(v) = h.iter().find(|v| !v.is_finite()) {
            return Err(SamError::InvalidParameter {
                name: "initial separation",
                value: *v,
                allowed: "finite",
            });
        }
        let (force_control, target) = match load {
            NormalLoad::Force(w) => (true, crate::error::positive("normal force", w)?),
            NormalLoad::Approach(d) => (false, crate::error::positive("approach", d)?),
        };
        let cold = p.iter().all(|v| *v <= 0.0) || p.iter().any(|v| !v.is_finite() || *v < 0.0);
        let (mut coarse_iterations, mut levels) = (0, 1);
        if cold {
            p.fill(0.0);
            if let (true, Some(coarse)) = (params.nested, coarser(&self.grid)) {
                let hc = restrict(&self.grid, h);
                let mut pc = vec![0.0; coarse.len()];
                let mut solver = NormalSolver::<S>::with_operators(coarse, &self.compliance)?;
                // The coarse solve only starts the fine one: its discretisation error (O(Δ)) is
                // far above its tolerance.
                let coarse_params = NormalParams {
                    tolerance: params.tolerance.max(COARSE_TOLERANCE),
                    ..*params
                };
                match solver.solve_in(&hc, load, &mut pc, &coarse_params, Finish::Single) {
                    Ok(info) => {
                        coarse_iterations = info.iterations + info.coarse_iterations;
                        levels += info.levels;
                        prolong(&coarse, &pc, &self.grid, p);
                    }
                    // The coarse grid may resolve the contact too poorly (a few cells, or its
                    // wider boundary cells touched): start as without continuation.
                    Err(_) => p.fill(0.0),
                }
            }
        }
        let single = cold && params.mixed_precision;
        let result = self.iterate(h, force_control, target, p, params, single, finish);
        if single {
            // The single-precision copy of the operator serves cold solves only.
            if let Some(w) = self.work.as_mut() {
                w.op.drop_single();
            }
        }
        let mut info = result?;
        info.coarse_iterations = coarse_iterations;
        info.levels = levels;
        Ok(info)
    }

    /// The (preconditioned, incremental) Polonsky–Keer iteration from `p` (docs/theory-sam.md#normal-contact steps 1–10).
    ///
    /// With `single`, the `K*` products are single-precision ones until the change falls below
    /// [`SINGLE_PRECISION_SWITCH`] (or the tolerance, if larger); then `u = K*p` is recomputed in
    /// double precision (and so is every later full product), unless `finish` allows stopping in
    /// single. The step products `K*t` stay in single precision until the change falls below
    /// [`SINGLE_STEPS_FLOOR`] (after the switch `u` changes by `τ K*t`, a change of relative
    /// size below the switch, so their `f32` rounding, `~1e-7` of the step, enters `u` at
    /// `~1e-11`), the preconditioner's for the whole of such a solve.
    #[allow(clippy::too_many_arguments)]
    fn iterate(
        &mut self,
        h: &[f64],
        force_control: bool,
        target: f64,
        p: &mut [f64],
        params: &NormalParams,
        single: bool,
        finish: Finish,
    ) -> Result<NormalInfo, SamError> {
        let grid = self.grid;
        let (n, area) = (grid.len(), grid.cell_area());
        // Initial guess: keep a usable warm start, else uniform (force) or small where h < δ.
        if p.iter().all(|v| *v <= 0.0) {
            if force_control {
                p.fill(target / (area * n as f64));
            } else {
                let hmin = h.iter().cloned().fold(f64::INFINITY, f64::min);
                if hmin >= target {
                    return Err(SamError::NoContact);
                }
                let scale = (target - hmin) / (grid.half1 * 1e3);
                for (pi, hi) in p.iter_mut().zip(h) {
                    *pi = if *hi < target {
                        scale * (target - hi)
                    } else {
                        0.0
                    };
                }
            }
        } else if force_control {
            let s: f64 = p.iter().sum();
            p.iter_mut().for_each(|v| *v *= target / (area * s));
        }
        let periodic = self.periodic.clone();
        let w = self.work()?;
        if params.preconditioned && w.preconditioner.is_none() {
            let (d1, d2) = (2.0 * grid.half1, 2.0 * grid.half2);
            w.preconditioner = Some(Circulant2d::inverse_half_space_on(periodic, d1, d2)?);
        }
        let chunks = Chunks::new(n);
        // `u = K*p` in single precision until the switch, the step products `K*t` until the
        // change falls below SINGLE_STEPS_FLOOR, the preconditioner for the whole of a
        // mixed-precision solve.
        let (mut single_u, mut single_steps) = (single, single);
        let mut g_old = 1.0;
        let mut conjugate = false;
        let mut approach = target;
        w.t.fill(0.0);
        let mut exact_u = false;
        let offset = if force_control { 0.0 } else { target };
        let preconditioned = params.preconditioned && w.preconditioner.is_some();
        // Six passes over the grid per iteration (each field read as few times as possible; seven
        // unpreconditioned), in chunks on rayon's threads on large grids with per-chunk sums
        // (`passes`).
        for it in 1..=params.max_iterations {
            // 1–2: gap and its mean over the contact set I (the approach, under force control).
            if !params.incremental || !exact_u || it % REFRESH_INTERVAL == 1 {
                if single_u {
                    w.op.apply_field_single(p, &mut w.u)?;
                } else {
                    w.op.apply_field(p, &mut w.u)?;
                }
            }
            let (u, pp) = (&w.u, &*p);
            chunks.run(&mut w.sums, [&mut w.g], |r, [g]| {
                let (u, h, pc) = (&u[r.clone()], &h[r.clone()], &pp[r]);
                let [s, c] = sum_lanes(g.len(), |i| {
                    g[i] = u[i] + h[i] - offset;
                    if pc[i] > 0.0 {
                        [g[i], 1.0]
                    } else {
                        [0.0, 0.0]
                    }
                });
                [s, c, 0.0, 0.0]
            });
            let [gsum, count, _, _] = total(&w.sums);
            if count == 0.0 {
                return Err(SamError::NoContact);
            }
            let mut mean = gsum / count;
            if force_control {
                approach = mean;
            } else {
                mean = 0.0;
            }
            // 3–4: (preconditioned) conjugate direction z on I, G = Σ_I g·z, with z̄ (force
            // control) taken out of z: Σ_I g (z − z̄) = Σ_I g z − z̄ Σ_I g. The gap minus its mean,
            // `g − shift`, enters every later pass: preconditioned, `g` keeps the mean and the
            // preconditioner's input `R(g − ḡ)` is evaluated as it is transformed (no pass that
            // only writes it); unpreconditioned, a pass subtracts the mean and writes `R g`.
            let (big_g, zmean, shift) = if preconditioned {
                let pre = w.preconditioner.as_mut().expect("preconditioned");
                let g = &w.g;
                let restricted = |k: usize| if pp[k] > 0.0 { g[k] - mean } else { 0.0 };
                if single {
                    pre.apply_single_of(restricted, &mut w.z)?;
                } else {
                    pre.apply_of(restricted, &mut w.z)?;
                }
                let z = &w.z;
                chunks.run(&mut w.sums, [], |r, []| {
                    let (z, g, pc) = (&z[r.clone()], &g[r.clone()], &pp[r]);
                    let [sz, sgz, sg] = sum_lanes(z.len(), |i| {
                        if pc[i] > 0.0 {
                            let gi = g[i] - mean;
                            [z[i], gi * z[i], gi]
                        } else {
                            [0.0, 0.0, 0.0]
                        }
                    });
                    [sz, sgz, sg, 0.0]
                });
                let [sz, sgz, sg, _] = total(&w.sums);
                let zmean = if force_control { sz / count } else { 0.0 };
                (sgz - zmean * sg, zmean, mean)
            } else {
                chunks.run(&mut w.sums, [&mut w.g, &mut w.r], |r, [g, rr]| {
                    let pc = &pp[r];
                    let [gg] = sum_lanes(g.len(), |i| {
                        g[i] -= mean;
                        let inside = pc[i] > 0.0;
                        rr[i] = if inside { g[i] } else { 0.0 };
                        [if inside { g[i] * g[i] } else { 0.0 }]
                    });
                    [gg, 0.0, 0.0, 0.0]
                });
                (total(&w.sums)[0], 0.0, 0.0)
            };
            let beta = if conjugate { big_g / g_old } else { 0.0 };
            g_old = big_g;
            // t = z − z̄ + β t on I, 0 outside (z = g unpreconditioned).
            let z = if preconditioned { &w.z } else { &w.r };
            chunks.run(&mut w.sums, [&mut w.t], |r, [t]| {
                let (z, pc) = (&z[r.clone()], &pp[r]);
                for i in 0..t.len() {
                    t[i] = if pc[i] > 0.0 {
                        (z[i] - zmean) + beta * t[i]
                    } else {
                        0.0
                    };
                }
                [0.0; 4]
            });
            // 5–6: step length τ = Σ g t / Σ (r − r̄) t with r = K*t (the product of the
            // iteration); Σ(r − r̄)t = Σ r t − r̄ Σ t.
            if single_steps {
                w.op.apply_field_single(&w.t, &mut w.r)?;
            } else {
                w.op.apply_field(&w.t, &mut w.r)?;
            }
            let (t, rk, g) = (&w.t, &w.r, &w.g);
            chunks.run(&mut w.sums, [], |r, []| {
                let (t, rk, g, pc) = (&t[r.clone()], &rk[r.clone()], &g[r.clone()], &pp[r]);
                sum_lanes(t.len(), |i| {
                    if pc[i] > 0.0 {
                        [(g[i] - shift) * t[i], rk[i] * t[i], rk[i], t[i]]
                    } else {
                        [0.0; 4]
                    }
                })
            });
            let [num, rt, rs, ts] = total(&w.sums);
            let den = if force_control {
                rt - rs / count * ts
            } else {
                rt
            };
            let tau = if den != 0.0 { num / den } else { 0.0 };
            // 7: update and project; 8: cells with penetration outside the contact re-enter.
            // The cells where p departs from p_old − τt are recorded for the displacement update
            // (the first SPARSE_COLUMNS in cell order; more is an overflow); u takes −τ K*t here,
            // and K*t's field then keeps p_old (one field fewer).
            let (t, g) = (&w.t, &w.g);
            chunks.run(
                &mut w.projected,
                [&mut w.u, &mut w.r, &mut *p],
                |r, [u, rk, pc]| {
                    let (t, g) = (&t[r.clone()], &g[r.clone()]);
                    let mut out = Projected::default();
                    let mut overlap = false;
                    let mut note = |k: usize, v: f64| {
                        if out.changes < SPARSE_COLUMNS {
                            out.cells[out.changes] = (k, v);
                        }
                        out.changes += 1;
                    };
                    let [sum] = sum_lanes(u.len(), |i| {
                        u[i] -= tau * rk[i];
                        let old = pc[i];
                        rk[i] = old;
                        if old > 0.0 {
                            let free = old - t[i] * tau;
                            if free < 0.0 {
                                pc[i] = 0.0;
                                note(r.start + i, -free);
                                [0.0]
                            } else {
                                pc[i] = free;
                                [free]
                            }
                        } else if g[i] - shift < 0.0 {
                            pc[i] = -tau * (g[i] - shift);
                            note(r.start + i, pc[i]);
                            overlap = true;
                            [pc[i]]
                        } else {
                            [0.0]
                        }
                    });
                    out.sum = sum;
                    out.overlap = overlap;
                    out
                },
            );
            w.changed.clear();
            let (mut changes, mut overlap, mut sum) = (0, false, 0.0);
            for c in &w.projected {
                for &cell in &c.cells[..c.changes.min(SPARSE_COLUMNS)] {
                    if w.changed.len() < SPARSE_COLUMNS {
                        w.changed.push(cell);
                    }
                }
                changes += c.changes;
                overlap |= c.overlap;
                sum += c.sum;
            }
            let overflow = changes > SPARSE_COLUMNS;
            conjugate = !overlap;
            if sum <= 0.0 {
                return Err(SamError::NoContact);
            }
            // 9: the force; u ← s (u − τ K*t + K*c), exact in exact arithmetic (a full product
            // next iteration when many cells changed); 10: the change of p.
            let s = if force_control {
                target / (area * sum)
            } else {
                1.0
            };
            exact_u = params.incremental && !overflow;
            let rk = &w.r;
            chunks.run(&mut w.sums, [&mut *p, &mut w.u], |r, [pc, u]| {
                let rk = &rk[r];
                let [change] = sum_lanes(pc.len(), |i| {
                    pc[i] *= s;
                    if exact_u {
                        u[i] *= s;
                    }
                    [(pc[i] - rk[i]).abs()]
                });
                [change, 0.0, 0.0, 0.0]
            });
            let change = total(&w.sums)[0];
            if exact_u {
                for c in w.changed.iter_mut() {
                    c.1 *= s;
                }
                w.op.add_columns(&w.changed, &mut w.u);
            }
            let residual = change / (s * sum);
            let converged =
                residual < params.tolerance && (!single_u || matches!(finish, Finish::Single));
            if single_u && !converged && residual < SINGLE_PRECISION_SWITCH.max(params.tolerance) {
                // u to double precision: the exact u = K*p next, and the direction restarted
                // (kept conjugate, the directions built on single-precision gaps stalled the
                // solve: 512², 12 → 50 iterations). The steps τ K*t stay single: their rounding
                // is relative to the step, which is small from here on.
                single_u = false;
                exact_u = false;
                conjugate = false;
            } else if single_steps && !single_u && !converged && residual < SINGLE_STEPS_FLOOR {
                // A tolerance below the floor: the steps to double precision too, from an exact
                // u (the single-precision steps' rounding in u is gone) and a new direction.
                single_steps = false;
                exact_u = false;
                conjugate = false;
            }
            if converged {
                let contact_cells = p.iter().filter(|v| **v > 0.0).count();
                if (0..n).any(|k| p[k] > 0.0 && grid.on_boundary(k)) {
                    return Err(SamError::ContactAtDomainEdge);
                }
                return Ok(NormalInfo {
                    iterations: it,
                    coarse_iterations: 0,
                    levels: 1,
                    residual,
                    approach,
                    force: area * p.iter().sum::<f64>(),
                    contact_cells,
                });
            }
            if it == params.max_iterations {
                return Err(SamError::NoConvergence {
                    solver: "Polonsky–Keer normal contact",
                    iterations: it,
                    residual,
                });
            }
        }
        Err(SamError::NoConvergence {
            solver: "Polonsky–Keer normal contact",
            iterations: 0,
            residual: f64::INFINITY,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Body;

    fn setup(n1: usize, n2: usize) -> (SurfaceGrid, Compliance) {
        let grid = SurfaceGrid {
            n1,
            n2,
            half1: 1e-6,
            half2: 1.5e-6,
        };
        let c = Compliance::pair(Body::Rigid, Body::elastic(210e9, 0.3).unwrap()).unwrap();
        (grid, c)
    }

    /// The quadrant-tabulated operator against the direct sum of the full kernel (every offset
    /// evaluated), with the shared fixed-seed check, on grids below and above the parallel
    /// threshold and with unequal sides: a wrong quadrant or parity fails it.
    #[test]
    fn the_quadrant_operator_equals_the_full_kernel_sum() {
        use halfspace_numerics::conv2d::{DenseConvolution2d, KernelFn};
        use halfspace_numerics::op::EvenConvolution2d;
        use halfspace_numerics::testkit::twin_error;
        for (n1, n2) in [(9, 14), (130, 128)] {
            let (grid, c) = setup(n1, n2);
            let fft = Fft2d::new(n1, n2).unwrap();
            let quadrant = c.normal_quadrant(&grid, PARALLEL_CELLS);
            let mut op = EvenConvolution2d::build(&fft, quadrant).unwrap();
            let (d1, d2) = (2.0 * grid.half1, 2.0 * grid.half2);
            let k = |m: i64, n: i64| c.normal_from_pressure(&grid, m as f64 * d1, n as f64 * d2);
            let kernels: [Option<KernelFn>; 1] = [Some(&k)];
            let mut dense = DenseConvolution2d::new(n1, n2, 1, 1, &kernels).unwrap();
            let err = twin_error(&mut op, &mut dense, &[1]).unwrap();
            // Signed inputs: rounding of the O(N log N) product relative to a partly cancelled
            // max |y| (measured 3.6e-13 at 130×128).
            assert!(err < 1e-12, "{n1}×{n2}: {err:e}");
        }
    }

    /// The chunked passes (`passes`) give the same solve bit for bit on 1 and 2 threads, under
    /// force and approach control, on a grid above the parallel threshold (a Hertz-like gap).
    #[test]
    fn the_solve_is_the_same_on_one_and_two_threads() {
        let n = 132;
        let grid = SurfaceGrid::square(n, 12e-6).unwrap();
        let c = Compliance::pair(Body::Rigid, Body::elastic(210e9, 0.3).unwrap()).unwrap();
        let h: Vec<f64> = (0..grid.len())
            .map(|k| {
                let (x, y) = grid.centre(k / n, k % n);
                (x * x + 0.8 * y * y) / (2.0 * 105e-6)
            })
            .collect();
        let params = NormalParams {
            tolerance: 1e-9,
            ..NormalParams::default()
        };
        for load in [NormalLoad::Force(0.08), NormalLoad::Approach(8e-8)] {
            let run = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                pool.install(|| {
                    let mut solver = NormalSolver::new(grid, &c).unwrap();
                    let mut p = vec![0.0; grid.len()];
                    let info = solver.solve(&h, load, &mut p, &params).unwrap();
                    (p, info)
                })
            };
            let (p1, i1) = run(1);
            let (p2, i2) = run(2);
            assert_eq!(i1, i2);
            assert!(p1.iter().zip(&p2).all(|(a, b)| a.to_bits() == b.to_bits()));
        }
    }

    /// Restriction and prolongation keep a (positive) linear field exact away from the clamped edge.
    #[test]
    fn transfers_are_exact_for_linear_fields() {
        let (fine, _) = setup(128, 130);
        let coarse = coarser(&fine).unwrap();
        assert_eq!((coarse.n1, coarse.n2), (64, 65));
        let lin = |g: &SurfaceGrid, i: usize, j: usize| {
            let (x, y) = g.centre(i, j);
            100.0 + 2e5 * x - 3e5 * y
        };
        let hf: Vec<f64> = (0..fine.len())
            .map(|k| lin(&fine, k / fine.n2, k % fine.n2))
            .collect();
        let hc = restrict(&fine, &hf);
        for k in 0..coarse.len() {
            assert!((hc[k] - lin(&coarse, k / coarse.n2, k % coarse.n2)).abs() < 1e-12);
        }
        let mut back = vec![0.0; fine.len()];
        prolong(&coarse, &hc, &fine, &mut back);
        for i in 1..fine.n1 - 1 {
            for j in 1..fine.n2 - 1 {
                assert!((back[i * fine.n2 + j] - hf[i * fine.n2 + j]).abs() < 1e-12);
            }
        }
    }
}
