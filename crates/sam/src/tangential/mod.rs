//! Stick–slip tangential contact with Coulomb friction (docs/theory-sam.md#tangential-contact): one increment is the convex QP
//! `min ½ q·Tq − b·q` subject to `|q_i| ≤ g_i = μ p_i` (docs/theory-sam.md#convex-quadratic-program), solved by accelerated projected
//! gradient (FISTA with gradient restart, Beck & Teboulle 2009, O'Donoghue & Candès 2015; docs/theory-sam.md#stick-slip-solver-and-force-control)
//! and stopped on the KKT residual. The slip of the increment is `S = b − Tq`.
//!
//! The default method is a primal active-set (inexact semismooth Newton) iteration
//! ([`TangentialMethod::ActiveSet`]). A round: the slip `S = b − Tq`; on the stick cells the
//! equations `S = 0`, on the slip ("rim") cells `|q| = g` with `S = λq`, `λ = (S·q̂)/g ≥ 0`. The
//! free part — stick cells, and the rotation `δ_t` of rim cells with `λ ≤ STIFF_RIM·T(0)` — is
//! solved to `INNER_REDUCTION` of the round's KKT residual (after a round whose set update changed
//! no cell: to [`FINAL_REDUCTION`] of the KKT tolerance, in every solve, cold or warm; never below
//! a tenth of the tolerance) by conjugate gradients on
//! `(M T M + Λ) δ = M S` (linearising `S − λq = 0` along the rim's tangent adds `λ δ_t`), with the
//! `|k|` circulant preconditioner `M P M` (the 2 × 2 symbol of `T` is ∝ 1/|k|, docs/theory-sam.md#two-bodies, like the
//! normal compliance's); rim cells are put back on their circle. Then the sets: stick cells beyond
//! their disc slip (direction `q̂`); when none did, rim cells whose slip opposes their shear stick
//! again; stiff rim cells (`λ > STIFF_RIM·T(0)`, held fixed in the solve) turn to `g Ŝ`. It stops on
//! FISTA's KKT residual and falls back to FISTA (warm) after [`ACTIVE_SET_ROUNDS`] rounds. A
//! start that already meets that rule, with no rim cell whose slip opposes its shear, is returned
//! after its one slip product. On
//! Cattaneo–Mindlin 128² from a cold start it needs 89–126 block products (Q/μP = 0.3–0.99) where
//! FISTA needs 451–514. Warm starts (docs/theory-sam.md#warm-starts-of-the-tangential-solve) need far fewer.

use halfspace_numerics::circulant::Circulant2d;
use halfspace_numerics::fft2d::{Fft2d, KernelFn};
use halfspace_numerics::op::{BlockConvolution, FftOperators, GridOperator, OperatorSet};

mod active_set;

use crate::kernels::InPlane;
use crate::normal::passes::Chunks;
use crate::{Compliance, SamError, SurfaceGrid};

/// Rounds (set updates) of the active-set method before the solve falls back to FISTA.
pub const ACTIVE_SET_ROUNDS: usize = 60;

/// Slip cells whose rim multiplier `λ = (S·q̂)/g` exceeds this many self-compliances `T(0)` are
/// held fixed in the inner solve and turned to their slip `g Ŝ` between solves (their direction is
/// set by their own slip); the others rotate inside the solve. Measured on Cattaneo–Mindlin 128²
/// (CG iterations + 2 products per round at Q/μP = 0.3/0.6/0.9/0.99): 3 → rounds cap hit at 0.9;
/// 10 → 67/77/114/135; 30 → 84/102/110/117; 100 → ~150.
pub const STIFF_RIM: f64 = 30.0;

/// Inexact Newton: each inner solve reduces the slip on the free cells to this fraction of the
/// round's KKT residual (0.01 took 1.3–1.8× the CG iterations of 0.1 for the same rounds).
pub const INNER_REDUCTION: f64 = 0.1;

/// Once a round's set update changed no cell, the next inner solve reduces the free part's slip
/// to this fraction of the KKT tolerance at once instead of to [`INNER_REDUCTION`] of the round's
/// residual (each restart costs a slip product and the Krylov space). On the first 3 increments of
/// the 128² composite loop (tangential products over every alternation, both paths of
/// `examples/composite_outer.rs`, with the rim warm start of `ContactProblem`): 0.1 → 1759,
/// 0.3 → 1667, 0.5 → 1640, 0.9 → 1569 products; 1834 with neither this rule nor the return of a
/// warm start that already meets the stopping rule. On cold Cattaneo–Mindlin 128² solves
/// (Q/μP = 0.3 / 0.6 / 0.9 / 0.99) 87 / 105 / 113 / 120 → 89 / 96 / 105 / 126 products.
///
/// The rule holds in every solve, cold or warm, with [`TangentialParams::warm_start`] (without it:
/// [`INNER_REDUCTION`] of the round's residual in every round). For a round residual between the tolerance and
/// 5× it, `0.5·tol` is looser than `INNER_REDUCTION·kkt`; the stopping rule (the whole problem's
/// KKT residual) is unchanged, so a loose inner solve costs at most another round. The tighter
/// `min(INNER_REDUCTION·kkt, 0.5·tol)` was measured and costs more on the same cold cases:
/// 95 / 103 / 111 / 129 products. 0.5 rather than 0.9 (fewer products on the composite loop):
/// it keeps a factor 2 below the tolerance for the rim re-projection and the drift of CG's
/// recursively updated residual; that margin is a choice, not a measured optimum.
pub const FINAL_REDUCTION: f64 = 0.5;

/// Algorithm of the tangential solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TangentialMethod {
    /// Accelerated projected gradient with gradient restart (docs/theory-sam.md#stick-slip-solver-and-force-control).
    Fista,
    /// Primal active set (inexact semismooth Newton) with `|k|`-preconditioned CG (module docs);
    /// FISTA as the fallback.
    ActiveSet,
}

/// Stopping rule of the tangential solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TangentialParams {
    /// `Σ|q_new − q_old| / Σ|q_new|` below which the iteration may stop.
    pub tolerance: f64,
    /// KKT residual (relative to `max |b|`) required as well.
    pub kkt_tolerance: f64,
    /// Limit on the block products `T·x` (FISTA iterations; CG iterations and slip evaluations
    /// of the active-set method).
    pub max_iterations: usize,
    /// Algorithm.
    pub method: TangentialMethod,
    /// The warm-start rules (docs/theory-sam.md#warm-starts-of-the-tangential-solve), on by
    /// default: an active-set start that already meets the stopping rule (no slipping cell whose
    /// slip opposes its shear) is returned on its one slip product; once a round's set update
    /// changed no cell, the inner solve aims at [`FINAL_REDUCTION`] of the KKT tolerance; and
    /// `ContactProblem` carries the cells that slipped onto their new circle `|q| = μp` before
    /// each solve. `false`: the plain solve — every round's inner solve to [`INNER_REDUCTION`] of
    /// its residual, no early return, the last shear as the start (projected onto the discs).
    /// Both stop on the same rule (`kkt_tolerance`), so they reach the same minimiser to it; the
    /// switch is there to compare them (crates/sam/tests/loops.rs, the load reversals). Only the
    /// active-set method and `ContactProblem` read it: [`TangentialMethod::Fista`] has no such
    /// rules. A library switch: the fretting loop and the wear run take the default, so no
    /// configuration key selects it and their checkpoints need not record it.
    pub warm_start: bool,
}

impl Default for TangentialParams {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            kkt_tolerance: 1e-8,
            max_iterations: 50_000,
            method: TangentialMethod::ActiveSet,
            warm_start: true,
        }
    }
}

impl TangentialParams {
    /// Checks the stopping rule: tolerances in `(0, 1)`, `max_iterations ≥ 1`.
    pub fn validate(&self) -> Result<(), SamError> {
        for (name, v) in [
            ("tangential solver tolerance", self.tolerance),
            ("tangential KKT tolerance", self.kkt_tolerance),
        ] {
            if !(v.is_finite() && v > 0.0 && v < 1.0) {
                return Err(SamError::InvalidParameter {
                    name,
                    value: v,
                    allowed: "in (0, 1)",
                });
            }
        }
        if self.max_iterations == 0 {
            return Err(SamError::InvalidParameter {
                name: "tangential solver iteration limit",
                value: 0.0,
                allowed: "≥ 1",
            });
        }
        Ok(())
    }
}

/// What the solve did and found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TangentialInfo {
    /// Block products `T·x` the solve made (FISTA: one per iteration; active set: one per CG
    /// iteration and per slip evaluation), the measure of its cost.
    pub iterations: usize,
    /// Final relative change of `q`.
    pub residual: f64,
    /// Final KKT residual (relative).
    pub kkt: f64,
    /// Cells that stick (`|q| < g (1 − 1e-9)`, in contact).
    pub stick_cells: usize,
    /// Cells that slip (in contact, on the friction cone).
    pub slip_cells: usize,
}

impl TangentialInfo {
    /// The (trivial) solve without friction: `q = 0`, every contact cell slips.
    pub fn frictionless(contact_cells: usize) -> Self {
        Self {
            iterations: 0,
            residual: 0.0,
            kkt: 0.0,
            stick_cells: 0,
            slip_cells: contact_cells,
        }
    }
}

/// The 2 × 2 block tangential compliance `T` as a block convolution of `S` (the DC-FFT operator by
/// default, or its dense twin), with the active-set and FISTA solvers.
pub struct TangentialSolver<S: OperatorSet = FftOperators> {
    grid: SurfaceGrid,
    op: S::Blocks,
    /// The periodic FFT core of the grid (the preconditioner's).
    periodic: Fft2d,
    lipschitz: f64,
    self_term: f64,
    s: [Vec<f64>; 2],
    y: [Vec<f64>; 2],
    q_old: [Vec<f64>; 2],
    tq: [Vec<f64>; 2],
    /// Active set: CG direction, `T` of it, preconditioned residual; cell states.
    dir: [Vec<f64>; 2],
    t_dir: [Vec<f64>; 2],
    z: [Vec<f64>; 2],
    stick: Vec<bool>,
    preconditioner: Option<Circulant2d>,
    /// Per-chunk sums and maxima of the active set's passes (crate::normal::passes: fixed chunks,
    /// so the same bits on one or more threads).
    sums: Vec<f64>,
}

impl TangentialSolver {
    /// Plans `T` for the pair's tangential compliance on `grid` (DC-FFT).
    pub fn new(grid: SurfaceGrid, compliance: &Compliance) -> Result<Self, SamError> {
        Self::with_operators(grid, compliance)
    }
}

impl<S: OperatorSet> TangentialSolver<S> {
    /// [`TangentialSolver::new`] on the operators of `S`, with FFT cores of its own.
    pub fn with_operators(grid: SurfaceGrid, compliance: &Compliance) -> Result<Self, SamError> {
        let fft = Fft2d::new(grid.n1, grid.n2)?;
        let periodic = Fft2d::periodic(grid.n1, grid.n2)?;
        Self::on_cores(grid, compliance, &fft, &periodic)
    }

    /// [`TangentialSolver::with_operators`] on given padded and periodic cores of the grid's shape
    /// (shared with the other operators of a contact problem).
    pub fn on_cores(
        grid: SurfaceGrid,
        compliance: &Compliance,
        fft: &Fft2d,
        periodic: &Fft2d,
    ) -> Result<Self, SamError> {
        crate::grid::check_cores(&grid, fft, periodic)?;
        let (d1, d2) = (2.0 * grid.half1, 2.0 * grid.half2);
        let k = |a: InPlane, b: InPlane| {
            move |m: i64, n: i64| compliance.tangential(&grid, a, b, m as f64 * d1, n as f64 * d2)
        };
        let (x1, x2) = (InPlane::X1, InPlane::X2);
        let (k11, k12, k21, k22) = (k(x1, x1), k(x1, x2), k(x2, x1), k(x2, x2));
        let kernels: [Option<KernelFn>; 4] = [Some(&k11), Some(&k12), Some(&k21), Some(&k22)];
        let op = S::Blocks::build(fft, 2, 2, &kernels)?;
        // L ≥ λ_max(T): the largest eigenvalue of the 2 × 2 symbol over the padded frequencies.
        let scale = (4 * grid.n1 * grid.n2) as f64;
        let block = |o: usize, i: usize| {
            op.block_spectrum(o, i)?.ok_or(SamError::InvalidParameter {
                name: "tangential compliance block (zero)",
                value: 0.0,
                allowed: "a nonzero kernel",
            })
        };
        let (s11, s12, s22) = (block(0, 0)?, block(0, 1)?, block(1, 1)?);
        let mut lipschitz: f64 = 0.0;
        for k in 0..s11.len() {
            let (a, b, c) = (s11[k].re * scale, s12[k].norm() * scale, s22[k].re * scale);
            let lam = 0.5 * (a + c) + (0.25 * (a - c) * (a - c) + b * b).sqrt();
            lipschitz = lipschitz.max(lam);
        }
        let n = grid.len();
        let z = || [vec![0.0; n], vec![0.0; n]];
        drop((s11, s12, s22));
        Ok(Self {
            grid,
            op,
            periodic: periodic.clone(),
            lipschitz,
            self_term: compliance.tangential(&grid, InPlane::X1, InPlane::X1, 0.0, 0.0),
            s: z(),
            y: z(),
            q_old: z(),
            tq: z(),
            dir: z(),
            t_dir: z(),
            z: z(),
            stick: vec![false; n],
            preconditioner: None,
            sums: vec![0.0; Chunks::new(n).count()],
        })
    }

    /// The grid.
    pub fn grid(&self) -> &SurfaceGrid {
        &self.grid
    }

    /// `Δu = T q` (relative tangential displacement of a shear field).
    pub fn displacement(&mut self, q: [&[f64]; 2], u: [&mut [f64]; 2]) -> Result<(), SamError> {
        let [u0, u1] = u;
        self.op.apply(&q, &mut [u0, u1])?;
        Ok(())
    }

    /// Solves one increment: `q` (warm start in, result out) with `|q_i| ≤ bound_i`, for the known
    /// part `b = w + D − c` of the slip; writes the slip `S = b − Tq`.
    pub fn solve(
        &mut self,
        bound: &[f64],
        b: [&[f64]; 2],
        q: [&mut [f64]; 2],
        slip: [&mut [f64]; 2],
        params: &TangentialParams,
    ) -> Result<TangentialInfo, SamError> {
        params.validate()?;
        let n = self.grid.len();
        let [q0, q1] = q;
        let [s_out0, s_out1] = slip;
        crate::error::check_lengths(
            "tangential solve fields",
            n,
            [bound, b[0], b[1], &*q0, &*q1, &*s_out0, &*s_out1],
        )?;
        let b_scale = b[0]
            .iter()
            .chain(b[1])
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        project(bound, q0, q1);
        if bound.iter().all(|g| *g <= 0.0) {
            // No contact: no shear; the slip is b.
            s_out0.copy_from_slice(b[0]);
            s_out1.copy_from_slice(b[1]);
            return Ok(TangentialInfo {
                iterations: 0,
                residual: 0.0,
                kkt: 0.0,
                stick_cells: 0,
                slip_cells: 0,
            });
        }
        let mut done = 0;
        if params.method == TangentialMethod::ActiveSet {
            match self.active_set(bound, b, [q0, q1], [s_out0, s_out1], params, b_scale)? {
                Ok(info) => return Ok(info),
                Err(iterations) => done = iterations,
            }
        }
        let [q0, q1] = [&mut *q0, &mut *q1];
        self.y[0].copy_from_slice(q0);
        self.y[1].copy_from_slice(q1);
        let inv_l = 1.0 / self.lipschitz;
        let mut t = 1.0f64;
        let mut residual = f64::INFINITY;
        for it in 1..=params.max_iterations {
            // S = b − T y, gradient step, projection.
            {
                let [t0, t1] = &mut self.tq;
                self.op.apply(&[&self.y[0], &self.y[1]], &mut [t0, t1])?;
            }
            self.q_old[0].copy_from_slice(q0);
            self.q_old[1].copy_from_slice(q1);
            for k in 0..n {
                self.s[0][k] = b[0][k] - self.tq[0][k];
                self.s[1][k] = b[1][k] - self.tq[1][k];
                q0[k] = self.y[0][k] + inv_l * self.s[0][k];
                q1[k] = self.y[1][k] + inv_l * self.s[1][k];
            }
            project(bound, q0, q1);
            let tn = 0.5 * (1.0 + (1.0 + 4.0 * t * t).sqrt());
            // Gradient restart: (y − q_new)·(q_new − q_old) > 0.
            let mut dot = 0.0;
            for k in 0..n {
                dot += (self.y[0][k] - q0[k]) * (q0[k] - self.q_old[0][k])
                    + (self.y[1][k] - q1[k]) * (q1[k] - self.q_old[1][k]);
            }
            let (t_now, tn) = if dot > 0.0 { (1.0, 1.0) } else { (t, tn) };
            let mom = (t_now - 1.0) / tn;
            let (mut change, mut size) = (0.0, 0.0);
            for k in 0..n {
                let d0 = q0[k] - self.q_old[0][k];
                let d1 = q1[k] - self.q_old[1][k];
                self.y[0][k] = q0[k] + mom * d0;
                self.y[1][k] = q1[k] + mom * d1;
                change += d0.abs() + d1.abs();
                size += q0[k].abs() + q1[k].abs();
            }
            t = tn;
            residual = if size > 0.0 { change / size } else { 0.0 };
            if residual < params.tolerance || it == params.max_iterations {
                // KKT at q: slip S = b − Tq.
                {
                    let [t0, t1] = &mut self.tq;
                    self.op.apply(&[&*q0, &*q1], &mut [t0, t1])?;
                }
                for k in 0..n {
                    s_out0[k] = b[0][k] - self.tq[0][k];
                    s_out1[k] = b[1][k] - self.tq[1][k];
                }
                let (kkt, stick, slipping) = kkt_residual(bound, q0, q1, s_out0, s_out1);
                let kkt = kkt / b_scale;
                if kkt < params.kkt_tolerance {
                    return Ok(TangentialInfo {
                        iterations: done + it,
                        residual,
                        kkt,
                        stick_cells: stick,
                        slip_cells: slipping,
                    });
                }
                if it == params.max_iterations {
                    return Err(SamError::NoConvergence {
                        solver: "FISTA tangential contact",
                        iterations: it,
                        residual: kkt,
                    });
                }
            }
        }
        Err(SamError::NoConvergence {
            solver: "FISTA tangential contact",
            iterations: params.max_iterations,
            residual,
        })
    }

    /// `S = b − T q` into `slip` (one block product).
    fn slip_of(
        &mut self,
        b: [&[f64]; 2],
        q: [&[f64]; 2],
        slip: [&mut [f64]; 2],
    ) -> Result<(), SamError> {
        {
            let [t0, t1] = &mut self.tq;
            self.op.apply(&q, &mut [t0, t1])?;
        }
        let [s0, s1] = slip;
        for k in 0..s0.len() {
            s0[k] = b[0][k] - self.tq[0][k];
            s1[k] = b[1][k] - self.tq[1][k];
        }
        Ok(())
    }
}

/// Per cell: `q ← q min(1, g/|q|)`; `q = 0` where `g = 0`.
fn project(bound: &[f64], q0: &mut [f64], q1: &mut [f64]) {
    for k in 0..bound.len() {
        let g = bound[k];
        if g <= 0.0 {
            q0[k] = 0.0;
            q1[k] = 0.0;
            continue;
        }
        let m = (q0[k] * q0[k] + q1[k] * q1[k]).sqrt();
        if m > g {
            let s = g / m;
            q0[k] *= s;
            q1[k] *= s;
        }
    }
}

/// `max_stick |S|` and `max_slip |S − (S·q̂)₊ q̂|` over the contact, with the stick/slip counts.
fn kkt_residual(
    bound: &[f64],
    q0: &[f64],
    q1: &[f64],
    s0: &[f64],
    s1: &[f64],
) -> (f64, usize, usize) {
    let (mut worst, mut stick, mut slip) = (0.0f64, 0usize, 0usize);
    for k in 0..bound.len() {
        let g = bound[k];
        if g <= 0.0 {
            continue;
        }
        let m = (q0[k] * q0[k] + q1[k] * q1[k]).sqrt();
        if m < g * (1.0 - 1e-9) {
            stick += 1;
            worst = worst.max((s0[k] * s0[k] + s1[k] * s1[k]).sqrt());
        } else {
            slip += 1;
            let (e0, e1) = (q0[k] / m, q1[k] / m);
            let along = (s0[k] * e0 + s1[k] * e1).max(0.0);
            let (r0, r1) = (s0[k] - along * e0, s1[k] - along * e1);
            worst = worst.max((r0 * r0 + r1 * r1).sqrt());
        }
    }
    (worst, stick, slip)
}

/// Whether cell `k` sticks (`|q| < g (1 − 1e-9)`, in contact).
pub fn is_stick(bound: f64, q0: f64, q1: f64) -> bool {
    bound > 0.0 && (q0 * q0 + q1 * q1).sqrt() < bound * (1.0 - 1e-9)
}
