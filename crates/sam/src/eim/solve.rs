//! The discrete equivalency equations (docs/theory-sam.md#equivalency-equation, docs/theory-sam.md#solving-the-eim-equations; \[LN11\] Eqs. 1–2): in every inclusion cell
//! `I`, `r_I = C^m ε*_I − ΔC_I (ε⁰_I + (𝒟ε*)_I) = 0`, `ΔC = C^m − C^I`, solved for the eigenstrains
//! `ε*` (6 per cell) by
//!
//! * **block Jacobi** (\[LN11\]): `ε* ← ε* + P⁻¹ r` with `P_I = C^m − ΔC_I S₀`, `S₀ = D(0)` the
//!   cube's Eshelby tensor at its centre (the exact self term), i.e.
//!   `ε*_new = (C^m − ΔC S₀)⁻¹ ΔC (ε⁰ + 𝒟ε* − S₀ε*)`;
//! * **GMRES** (restart 50) on `A ε* = ΔC ε⁰`, `A = C^m − ΔC 𝒟`, right-preconditioned by the same
//!   blocks — robust for stiffness ratios from voids to 100 (docs/theory-sam.md#solving-the-eim-equations table).
//!
//! The 6 × 6 blocks are inverted once per material with faer's LU. [`EimSystem`] is the flat
//! [`LinearOperator`] `A`; it runs on the FFT operator or on its dense twin alike.

use faer::linalg::solvers::DenseSolveCore;
use faer::Mat;
use halfspace_numerics::krylov::{
    richardson, richardson_mixed, Gmres, KrylovInfo, KrylovParams, RichardsonRecycle,
    RichardsonWork,
};
use halfspace_numerics::linop::{check_lengths, LinearOperator};
use halfspace_numerics::NumericsError;
use rayon::prelude::*;

use super::geometry::InclusionSet;
use super::operator::EimFields;
use crate::kernels::cuboid::StrainPotentials;
use crate::kernels::{matmul6, mul6, stiffness};
use crate::SamError;

/// The iteration used for the equivalency equations.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EimMethod {
    /// Block Jacobi with the exact self term (\[LN11\]); diverges for stiffness ratios ≳ 10 and voids.
    BlockJacobi,
    /// GMRES with the block-Jacobi preconditioner.
    Gmres,
    /// GMRES when any material is outside the block-Jacobi range (`E_I/E_m` ≤ 0.2 or ≥ 5), else
    /// block Jacobi.
    Auto,
}

/// Parameters of the EIM solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EimParams {
    /// The iteration.
    pub method: EimMethod,
    /// Tolerance: relative residual (GMRES) or `max|Δε*|/max|ε*|` (block Jacobi).
    pub tolerance: f64,
    /// Limit on operator applications.
    pub max_iterations: usize,
    /// GMRES restart length (100: with 50, soft inhomogeneities (E_I/E_m = 0.1) of a few hundred
    /// cells stagnate; reduced automatically when the Krylov basis would exceed 2 GiB).
    pub restart: usize,
    /// Block Jacobi only, when > 0: what earlier solves of one [`EimSystem`] learned is
    /// recycled until [`EimSystem::forget_recycled`] ([`richardson_mixed`]): Anderson mixing of
    /// the iterates with this many differences (they do not depend on the right-hand side, so an
    /// outer pass's solve starts by projecting on the earlier passes' iterations), and a solve
    /// warm-started from the last result gets its first residual without an operator
    /// application (docs/theory-sam.md#solving-the-eim-equations). 0: plain block Jacobi
    /// (\[LN11\], the reference; this struct's default). The nested contact ↔ EIM loop's default
    /// is 5 (`crate::contact::DEFAULT_EIM_RECYCLED_DEPTH`, config key `eim_recycled_depth`).
    /// Reduced automatically when its (2·depth + 7) vectors would exceed 2 GiB.
    pub recycled_depth: usize,
}

impl Default for EimParams {
    fn default() -> Self {
        Self {
            method: EimMethod::Auto,
            tolerance: 1e-10,
            max_iterations: 3000,
            restart: 100,
            recycled_depth: 0,
        }
    }
}

/// What an EIM solve did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EimInfo {
    /// Operator applications.
    pub iterations: usize,
    /// Final residual measure.
    pub residual: f64,
    /// The method actually used.
    pub method: EimMethod,
}

/// 6 × 6 matrix inverse by faer's partial-pivoting LU; an error if singular.
fn invert6(m: &[[f64; 6]; 6]) -> Result<[[f64; 6]; 6], SamError> {
    let a = Mat::<f64>::from_fn(6, 6, |i, j| m[i][j]);
    let inv = a.partial_piv_lu().inverse();
    let mut out = [[0.0; 6]; 6];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = inv[(i, j)];
        }
    }
    if out.iter().flatten().any(|v: &f64| !v.is_finite()) {
        return Err(SamError::InvalidParameter {
            name: "determinant of the EIM self-term block",
            value: 0.0,
            allowed: "non-zero",
        });
    }
    Ok(out)
}

/// The operator `A ε* = C^m ε* − ΔC (𝒟 ε*)` on the inclusion cells, with its block
/// preconditioner; the source and target layers of `fields` must be the set's layers. Owns its
/// operators and work arrays: applying does not allocate.
pub struct EimSystem {
    fields: EimFields,
    set: InclusionSet,
    cm: [[f64; 6]; 6],
    /// `ΔC` per material.
    dc: Vec<[[f64; 6]; 6]>,
    /// The eigenstrain fields of the layers: zero outside the cells, written only at the cells.
    eigen: Vec<Vec<f64>>,
    /// Per layer, the range of its cells in `set.cells` (`None` when the cells are not listed
    /// layer by layer: then they are scattered on one thread).
    layer_cells: Option<Vec<std::ops::Range<usize>>>,
    /// Cells per task of the per-cell loops (`CELLS_PER_TASK`; tests lower it).
    cells_per_task: usize,
    strain: Vec<Vec<f64>>,
    /// The right-hand side `ΔC ε⁰` of the last solve (kept: a solve allocates no right-hand side).
    rhs: Vec<f64>,
    /// The block preconditioner `(C^m − ΔC S₀)⁻¹` per material as an operator (built once, the
    /// only copy of the blocks; empty only while a solve holds it).
    pre: BlockPreconditioner,
    /// GMRES work arrays, kept between solves (warm outer loops do not reallocate).
    gmres: Option<Gmres>,
    /// The block-Jacobi iteration's Anderson history ([`EimParams::recycled_depth`]), kept
    /// between solves.
    mixing: Option<RichardsonRecycle>,
    /// The plain block-Jacobi iteration's work vectors (recycled depth 0), kept between solves.
    jacobi: RichardsonWork,
    /// Test hook ([`EimSystem::panic_at_next_application`]): the next operator application
    /// panics.
    panic_at_next_application: bool,
}

impl EimSystem {
    /// Builds the blocks for the matrix `(E, ν)`. Errors: a set whose cells do not fit its own
    /// layers, window and materials ([`InclusionSet::check`]) or whose layers and window are not
    /// the operators'.
    pub fn new(fields: EimFields, set: InclusionSet, e: f64, nu: f64) -> Result<Self, SamError> {
        set.check(fields.grid())?;
        let (ns, nt) = fields.layer_counts();
        if ns != set.layers.len() || nt != set.layers.len() {
            return Err(SamError::InvalidParameter {
                name: "EIM operator layers (must be the inclusion layers)",
                value: ns as f64,
                allowed: "the inclusion set's layer count",
            });
        }
        let cm = stiffness(e, nu);
        let s0 = StrainPotentials::new([0.0; 3], [set.half; 3]).voigt(nu);
        let mut dc = Vec::new();
        let mut precond = Vec::new();
        for &(ei, nui) in &set.materials {
            let ci = stiffness(ei, nui);
            let mut d = [[0.0; 6]; 6];
            for i in 0..6 {
                for j in 0..6 {
                    d[i][j] = cm[i][j] - ci[i][j];
                }
            }
            let ds0 = matmul6(&d, &s0);
            let mut p = cm;
            for i in 0..6 {
                for j in 0..6 {
                    p[i][j] -= ds0[i][j];
                }
            }
            precond.push(invert6(&p)?);
            dc.push(d);
        }
        let n = fields.window().len();
        if *fields.window() != set.window {
            return Err(SamError::InvalidParameter {
                name: "EIM operator window (must be the inclusion set's)",
                value: fields.window().len() as f64,
                allowed: "the set's bounding box",
            });
        }
        let layers = set.layers.len();
        let layer_cells = layer_ranges(&set);
        let pre = BlockPreconditioner {
            blocks: set.cells.iter().map(|c| c.material).collect(),
            inverse: precond,
            cells_per_task: CELLS_PER_TASK,
        };
        Ok(Self {
            layer_cells,
            cells_per_task: CELLS_PER_TASK,
            fields,
            set,
            cm,
            dc,
            eigen: vec![vec![0.0; n]; layers * 6],
            strain: vec![vec![0.0; n]; layers * 6],
            rhs: Vec::new(),
            pre,
            gmres: None,
            mixing: None,
            jacobi: RichardsonWork::default(),
            panic_at_next_application: false,
        })
    }

    /// `b = ΔC ε⁰` from the applied strain fields on the inclusion layers (cell by cell, in
    /// tasks of `CELLS_PER_TASK` (2048) cells). Errors: `b` not of [`LinearOperator::dim`] values,
    /// `applied` not six window fields per layer.
    pub fn rhs(&self, applied: &[Vec<f64>], b: &mut [f64]) -> Result<(), SamError> {
        self.check_layer_fields(applied, "applied strain fields (6 per layer, window-sized)")?;
        check_lengths(self.dim(), b, b)?;
        let (cells, task) = (&self.set.cells, self.cells_per_task);
        b.par_chunks_mut(6 * task)
            .zip(cells.par_chunks(task))
            .for_each(|(b, cells)| {
                for (bc, cell) in b.chunks_exact_mut(6).zip(cells) {
                    let mut e0 = [0.0; 6];
                    for (o, v) in e0.iter_mut().enumerate() {
                        *v = applied[cell.layer * 6 + o][cell.local];
                    }
                    bc.copy_from_slice(&mul6(&self.dc[cell.material], &e0));
                }
            });
        Ok(())
    }

    /// Scatters the cell eigenstrains `x` (6 per cell) into the layer fields (6 per layer,
    /// window-sized), zero elsewhere. Errors: `x` or `fields` of other sizes.
    pub fn scatter(&self, x: &[f64], fields: &mut [Vec<f64>]) -> Result<(), SamError> {
        check_lengths(self.dim(), x, x)?;
        self.check_layer_fields(
            fields,
            "eigenstrain layer fields (6 per layer, window-sized)",
        )?;
        fields.iter_mut().for_each(|f| f.fill(0.0));
        scatter_cells(&self.set, x, fields);
        Ok(())
    }

    /// Six window-sized fields per layer of the set, else the typed error naming `what`.
    fn check_layer_fields(&self, fields: &[Vec<f64>], what: &'static str) -> Result<(), SamError> {
        let wl = self.set.window.len();
        if fields.len() != 6 * self.set.layers.len() || fields.iter().any(|f| f.len() != wl) {
            return Err(SamError::Numerics(NumericsError::LengthMismatch {
                what,
                expected: 6 * self.set.layers.len(),
                got: fields.len(),
            }));
        }
        Ok(())
    }

    /// [`EimSystem::scatter`] into the system's own layer fields, which are zero outside the
    /// cells from their allocation on and only ever written at the cells: only the cells are
    /// written (no pass clears the fields).
    /// Layer by layer on the pool when the cells are listed so (each layer's six fields are
    /// written by one task: the same values).
    fn scatter_own(&mut self, x: &[f64]) {
        match &self.layer_cells {
            Some(ranges) => {
                let cells = &self.set.cells;
                self.eigen
                    .par_chunks_mut(6)
                    .zip(ranges.par_iter())
                    .for_each(|(fields, range)| {
                        for c in range.clone() {
                            write_cell(fields, cells[c].local, &x[c * 6..c * 6 + 6]);
                        }
                    });
            }
            None => scatter_cells(&self.set, x, &mut self.eigen),
        }
    }

    /// The block preconditioner `P⁻¹`, `P_I = C^m − ΔC_I S₀` (module documentation; \[LN11\]),
    /// the one the solves apply (no copy: clone it for an operator to use next to the system).
    pub fn preconditioner(&self) -> &BlockPreconditioner {
        &self.pre
    }

    /// Test hook: the next [`LinearOperator::apply`] panics (once), to check that a solve
    /// interrupted by a panic leaves the system whole.
    #[doc(hidden)]
    pub fn panic_at_next_application(&mut self) {
        self.panic_at_next_application = true;
    }

    /// Sets the cells per task of the per-cell loops (the right-hand side, the restriction of
    /// [`LinearOperator::apply`], the block preconditioner; `CELLS_PER_TASK` (2048) by default,
    /// clamped to `[1, cells]`): every cell's arithmetic is the same on any split, so the results
    /// are the same bits (tests lower it to cross task boundaries on small sets).
    #[doc(hidden)]
    pub fn set_cells_per_task(&mut self, cells: usize) {
        self.cells_per_task = cells.clamp(1, self.set.len().max(1));
        self.pre.cells_per_task = self.cells_per_task;
    }

    /// Whether the eigenstrains are scattered into the layer fields layer by layer on the pool
    /// (the cells listed layer by layer), not on one thread (tests: both paths run).
    #[doc(hidden)]
    pub fn scatters_by_layer(&self) -> bool {
        self.layer_cells.is_some()
    }

    /// Solves for `ε*` (warm start and result, 6 per cell) given the applied strain on the
    /// inclusion layers.
    pub fn solve(
        &mut self,
        applied: &[Vec<f64>],
        eps_star: &mut [f64],
        params: &EimParams,
    ) -> Result<EimInfo, SamError> {
        let n = self.dim();
        check_lengths(n, eps_star, eps_star)?;
        let mut b = std::mem::take(&mut self.rhs);
        b.resize(n, 0.0);
        if let Err(e) = self.rhs(applied, &mut b) {
            self.rhs = b;
            return Err(e);
        }
        let method = self.resolved_method(params.method);
        // The Krylov basis holds restart + 1 vectors of the system's size: cap it at 2 GiB.
        let cap = ((2usize << 30) / (8 * n.max(1))).saturating_sub(1).max(1);
        let restart = params.restart.min(cap);
        let kp = KrylovParams {
            tolerance: params.tolerance,
            max_iterations: params.max_iterations,
            restart,
        };
        // The kept preconditioner, out of the system while the system is the operator (moved,
        // not copied: the empty stand-in allocates nothing). A panic inside the iteration is
        // caught to put it and the right-hand side's buffer back before it resumes unwinding: a
        // caller that catches the panic keeps a system that solves again (test
        // `a_solve_interrupted_by_a_panic_leaves_a_system_that_solves`).
        let mut pre = std::mem::take(&mut self.pre);
        let caught = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match method {
            EimMethod::Gmres => {
                let mut gmres = match self.gmres.take() {
                    Some(g) if g.shape() == (n, restart.max(1)) => g,
                    _ => Gmres::new(n, restart),
                };
                let r = gmres.solve(self, &mut pre, &b, eps_star, &kp);
                self.gmres = Some(gmres);
                r
            }
            EimMethod::BlockJacobi | EimMethod::Auto => {
                let depth = capped_recycled_depth(n, params.recycled_depth);
                if depth == 0 {
                    // Plain block Jacobi on the kept work vectors (a kept history is dropped:
                    // a later recycled solve starts a fresh one).
                    self.mixing = None;
                    let mut work = std::mem::take(&mut self.jacobi);
                    let r = richardson(self, &mut pre, &b, eps_star, &kp, &mut work);
                    self.jacobi = work;
                    r
                } else {
                    let mut mixing = match self.mixing.take() {
                        Some(m) if m.shape() == (n, depth) => m,
                        _ => RichardsonRecycle::new(n, depth),
                    };
                    let r = richardson_mixed(self, &mut pre, &b, eps_star, &kp, Some(&mut mixing));
                    self.mixing = Some(mixing);
                    r
                }
            }
        }));
        self.rhs = b;
        self.pre = pre;
        let result = match caught {
            Ok(result) => result,
            Err(payload) => std::panic::resume_unwind(payload),
        };
        let info: KrylovInfo = result.map_err(|e| match e {
            NumericsError::NoConvergence {
                solver,
                iterations,
                residual,
            } => SamError::NoConvergence {
                solver: if solver.starts_with("GMRES") {
                    "EIM (GMRES)"
                } else {
                    "EIM (block Jacobi)"
                },
                iterations,
                residual,
            },
            other => SamError::Numerics(other),
        })?;
        Ok(EimInfo {
            iterations: info.iterations,
            residual: info.residual,
            method,
        })
    }

    /// Forgets the block-Jacobi history recycled across solves ([`EimParams::recycled_depth`]):
    /// the next solve starts as plain block Jacobi from its warm start (a checkpointed loop calls
    /// it at every increment, so a resumed increment repeats the uninterrupted one bit for bit when
    /// it runs with the same [`EimParams`]; the checkpoint fingerprint records the depth used,
    /// `LoopCase::eim_recycled_depth`).
    pub fn forget_recycled(&mut self) {
        if let Some(m) = self.mixing.as_mut() {
            m.forget();
        }
    }

    /// The last recycled solve's last iterate `x_J` and its image `A x_J` (into `iterate`,
    /// `image`; [`RichardsonRecycle::last_iterate_image`]): `false` when none is kept (no
    /// recycled solve since the last [`EimSystem::forget_recycled`], or the GMRES or plain
    /// iteration).
    /// Errors: a vector not of [`LinearOperator::dim`] values.
    pub fn last_iterate_image(
        &self,
        iterate: &mut [f64],
        image: &mut [f64],
    ) -> Result<bool, SamError> {
        check_lengths(self.dim(), iterate, image)?;
        match &self.mixing {
            Some(m) if m.shape().0 == self.dim() => Ok(m.last_iterate_image(iterate, image)?),
            _ => Ok(false),
        }
    }

    /// The method a solve with `method` runs: [`EimMethod::Auto`] is GMRES when an inclusion's
    /// shear modulus is outside `[0.2, 5]` times the matrix's, block Jacobi otherwise.
    fn resolved_method(&self, method: EimMethod) -> EimMethod {
        match method {
            EimMethod::Auto => {
                // Shear-modulus ratio G_I/G_m (the matrix's 2G sits on the shear diagonal).
                let gm = 0.5 * self.cm[5][5];
                let wide = self.set.materials.iter().any(|&(ei, nui)| {
                    let ratio = ei / (2.0 * (1.0 + nui)) / gm;
                    !(0.2..=5.0).contains(&ratio)
                });
                if wide {
                    EimMethod::Gmres
                } else {
                    EimMethod::BlockJacobi
                }
            }
            m => m,
        }
    }

    /// Declares `image = A x` for the next solve with `params` warm-started from `x` bit for bit
    /// ([`RichardsonRecycle::set_known_start`]: its first residual `b − image` without an
    /// application); a history of another depth, or none
    /// yet (a system just built, e.g. after a resume), is replaced by a fresh one, as that solve
    /// would make it. Returns `false` (nothing declared) unless that solve is the recycled block
    /// Jacobi (not GMRES, not the plain iteration: [`EimParams::recycled_depth`] 0).
    /// Errors: a vector not of [`LinearOperator::dim`] values.
    pub fn set_known_start(
        &mut self,
        x: &[f64],
        image: &[f64],
        params: &EimParams,
    ) -> Result<bool, SamError> {
        let n = self.dim();
        check_lengths(n, x, image)?;
        let depth = capped_recycled_depth(n, params.recycled_depth);
        if depth == 0 || self.resolved_method(params.method) == EimMethod::Gmres {
            return Ok(false);
        }
        let mixing = match self.mixing.take() {
            Some(m) if m.shape() == (n, depth) => m,
            _ => RichardsonRecycle::new(n, depth),
        };
        let mixing = self.mixing.insert(mixing);
        mixing.set_known_start(x, image)?;
        Ok(true)
    }

    /// The disturbance strain of `eps_star` at the inclusion layers (the fields are kept for
    /// eigen-displacements).
    /// Errors: `eps_star` not of [`LinearOperator::dim`] values.
    pub fn disturbance(&mut self, eps_star: &[f64]) -> Result<&[Vec<f64>], SamError> {
        check_lengths(self.dim(), eps_star, eps_star)?;
        self.scatter_own(eps_star);
        self.fields.disturbance(&self.eigen, &mut self.strain)?;
        Ok(&self.strain)
    }

    /// Only the surface fields of the disturbance of `eps_star` ([`EimFields::surface_disturbance`]:
    /// bit for bit those of [`EimSystem::disturbance`], without the strain at the inclusion
    /// layers), for [`EimFields::eigen_displacements`].
    /// Errors: `eps_star` not of [`LinearOperator::dim`] values.
    pub fn surface_disturbance(&mut self, eps_star: &[f64]) -> Result<(), SamError> {
        check_lengths(self.dim(), eps_star, eps_star)?;
        self.scatter_own(eps_star);
        self.fields.surface_disturbance(&self.eigen)
    }

    /// The field operators (for eigen-displacements after a solve).
    pub fn fields(&mut self) -> &mut EimFields {
        &mut self.fields
    }

    /// Bytes of the stored kernel spectra.
    pub fn spectra_bytes(&self) -> usize {
        self.fields.spectra_bytes()
    }

    /// The correction pressure `p_c` of the last disturbance (docs/theory-sam.md#mirror-image-and-correction-pressure).
    pub fn correction_pressure(&self) -> &[f64] {
        self.fields.correction_pressure()
    }

    /// The inclusion cells.
    pub fn set(&self) -> &InclusionSet {
        &self.set
    }
}

impl LinearOperator for EimSystem {
    fn dim(&self) -> usize {
        6 * self.set.len()
    }

    fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        check_lengths(self.dim(), x, y)?;
        if std::mem::take(&mut self.panic_at_next_application) {
            panic!("EimSystem::panic_at_next_application");
        }
        self.scatter_own(x);
        // The strain alone (bit for bit the full disturbance's): the iteration reads no
        // surface displacement.
        let r = self
            .fields
            .disturbance_strain(&self.eigen, &mut self.strain);
        r.map_err(|e| match e {
            SamError::Numerics(n) => n,
            _ => NumericsError::InvalidParameter {
                name: "EIM operator application",
                value: f64::NAN,
                allowed: "consistent field shapes",
            },
        })?;
        // The restriction `C^m x − ΔC ε` cell by cell, in tasks of `cells_per_task` cells.
        let (cm, dc, strain) = (&self.cm, &self.dc, &self.strain);
        let task = self.cells_per_task;
        y.par_chunks_mut(6 * task)
            .zip(x.par_chunks(6 * task))
            .zip(self.set.cells.par_chunks(task))
            .for_each(|((y, x), cells)| {
                for ((yc, xs), cell) in y.chunks_exact_mut(6).zip(x.chunks_exact(6)).zip(cells) {
                    let mut eps = [0.0; 6];
                    for (o, v) in eps.iter_mut().enumerate() {
                        *v = strain[cell.layer * 6 + o][cell.local];
                    }
                    let a = mul6(cm, xs);
                    let d = mul6(&dc[cell.material], &eps);
                    for o in 0..6 {
                        yc[o] = a[o] - d[o];
                    }
                }
            });
        Ok(())
    }
}

/// The recycled block-Jacobi depth a solve of `n` unknowns uses for the requested `depth`: its
/// history holds (2·depth + 7) vectors of the system's size, capped at 2 GiB like the Krylov
/// basis (the nested loop refuses depths above `MAX_EIM_RECYCLED_DEPTH` up front).
fn capped_recycled_depth(n: usize, depth: usize) -> usize {
    let vectors = (2usize << 30) / (8 * n.max(1));
    depth.min(vectors.saturating_sub(7) / 2)
}

/// Cells per task of the per-cell loops (the right-hand side, the restriction, the block
/// preconditioner): 36 tasks for the composite's 73 216 cells at 128².
const CELLS_PER_TASK: usize = 2048;

/// Per layer, the range of its cells, when `set.cells` lists them layer by layer.
fn layer_ranges(set: &InclusionSet) -> Option<Vec<std::ops::Range<usize>>> {
    let mut ranges = vec![0..0; set.layers.len()];
    let mut start = 0;
    for layer in 0..set.layers.len() {
        let end = start
            + set.cells[start..]
                .iter()
                .take_while(|c| c.layer == layer)
                .count();
        ranges[layer] = start..end;
        start = end;
    }
    (start == set.cells.len()).then_some(ranges)
}

/// `fields[layer · 6 + o][local] = x[c · 6 + o]` at every cell `c` of `set` (the other values are
/// not written).
fn scatter_cells(set: &InclusionSet, x: &[f64], fields: &mut [Vec<f64>]) {
    for (c, cell) in set.cells.iter().enumerate() {
        let layer = &mut fields[cell.layer * 6..cell.layer * 6 + 6];
        write_cell(layer, cell.local, &x[c * 6..c * 6 + 6]);
    }
}

/// `fields[o][local] = xc[o]` for the six fields of one layer.
#[inline(always)]
fn write_cell(fields: &mut [Vec<f64>], local: usize, xc: &[f64]) {
    for (f, v) in fields.iter_mut().zip(xc) {
        f[local] = *v;
    }
}

/// `P⁻¹` applied cell by cell.
#[derive(Debug, Clone, Default)]
pub struct BlockPreconditioner {
    blocks: Vec<usize>,
    inverse: Vec<[[f64; 6]; 6]>,
    /// Cells per task ([`EimSystem::set_cells_per_task`]).
    cells_per_task: usize,
}

impl LinearOperator for BlockPreconditioner {
    fn dim(&self) -> usize {
        6 * self.blocks.len()
    }
    fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        check_lengths(self.dim(), x, y)?;
        let (inverse, task) = (&self.inverse, self.cells_per_task);
        y.par_chunks_mut(6 * task)
            .zip(x.par_chunks(6 * task))
            .zip(self.blocks.par_chunks(task))
            .for_each(|((y, x), blocks)| {
                for ((yc, xc), &m) in y.chunks_exact_mut(6).zip(x.chunks_exact(6)).zip(blocks) {
                    yc.copy_from_slice(&mul6(&inverse[m], xc));
                }
            });
        Ok(())
    }
}
