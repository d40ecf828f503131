//! Iterative solvers of `A x = b` on a [`LinearOperator`]:
//!
//! * [`Gmres`]: restarted GMRES(m) (Saad & Schultz 1986) with **right** preconditioning
//!   `A M⁻¹ y = b, x = M⁻¹ y`, modified Gram–Schmidt Arnoldi, Givens rotations for the Hessenberg
//!   least-squares problem (so the residual `‖b − A x‖` is known at every iteration without forming
//!   `x`). Stops when `‖b − A x‖ / ‖b‖ < tol`.
//! * [`richardson`]: the preconditioned Richardson iteration `x ← x + M⁻¹ (b − A x)`. With the block
//!   matrix of the exact self term as `M` this is the block-Jacobi scheme of the equivalent inclusion
//!   method (docs/theory-sam.md#solving-the-eim-equations). Stops when `max|Δx| / max|x| < tol`; stops with an error, not a
//!   hang, when the iteration diverges. [`richardson_mixed`] adds Anderson mixing whose history
//!   is kept across solves with the same operator.
//!
//! Both take a warm start in `x`, never print, and return what they did ([`KrylovInfo`]) or
//! [`NumericsError::NoConvergence`].

use crate::anderson::Anderson;
use crate::linop::LinearOperator;
use crate::NumericsError;
use rayon::prelude::*;

/// Stopping rule and restart length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KrylovParams {
    /// Relative tolerance (GMRES: residual norm over `‖b‖`; Richardson: `max|Δx| / max|x|`).
    pub tolerance: f64,
    /// Limit on operator applications.
    pub max_iterations: usize,
    /// GMRES restart length `m`.
    pub restart: usize,
}

impl Default for KrylovParams {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 2000,
            restart: 50,
        }
    }
}

impl KrylovParams {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), NumericsError> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(NumericsError::InvalidParameter {
                name: "solver tolerance",
                value: self.tolerance,
                allowed: "finite and > 0",
            });
        }
        if self.max_iterations == 0 {
            return Err(NumericsError::InvalidParameter {
                name: "iteration limit",
                value: 0.0,
                allowed: "≥ 1",
            });
        }
        if self.restart == 0 {
            return Err(NumericsError::InvalidParameter {
                name: "GMRES restart length",
                value: 0.0,
                allowed: "≥ 1",
            });
        }
        Ok(())
    }
}

/// What a solve did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KrylovInfo {
    /// Operator applications (iterations).
    pub iterations: usize,
    /// Final relative residual (GMRES) or relative change (Richardson).
    pub residual: f64,
}

/// Restarted, right-preconditioned GMRES with its work arrays allocated once.
pub struct Gmres {
    n: usize,
    m: usize,
    /// Krylov basis, `m + 1` vectors.
    v: Vec<Vec<f64>>,
    /// Hessenberg matrix, column-major `(m + 1) × m`.
    h: Vec<f64>,
    cs: Vec<f64>,
    sn: Vec<f64>,
    g: Vec<f64>,
    y: Vec<f64>,
    w: Vec<f64>,
    z: Vec<f64>,
    /// `M⁻¹ v_j` of the cycle's basis when [`Gmres::keep_preconditioned_basis`] asked for them
    /// (flexible-GMRES storage, Saad 1993): the update `x += Σ y_j M⁻¹ v_j` then needs no
    /// preconditioner application. Empty otherwise.
    zs: Vec<Vec<f64>>,
    /// Whether [`Gmres::solve`] / [`Gmres::solve_in_previous_space`] take their inner products
    /// in eight running sums ([`Gmres::sum_in_lanes`]).
    lanes: bool,
    r: Vec<f64>,
    /// Whether a cycle whose residual estimate fell below the tolerance is confirmed by the true
    /// residual `b − A x` (one more product) before returning (default true).
    confirm: bool,
    /// `(dimension, restart length, k)` of the last completed cycle whose Arnoldi relation
    /// `A M⁻¹ V_k = V_{k+1} H̄_k` is still held in `v` (basis), `h` (the triangle `R`) and
    /// `cs`, `sn` (the Givens rotations `H̄_k = Qᵀ [R; 0]`), for
    /// [`Gmres::solve_in_previous_space`]; `None` when there is none.
    previous: Option<(usize, usize, usize)>,
    /// Whether each cycle keeps its result `x` and `b` ([`Gmres::keep_solution`]) and whether
    /// `kept_x`, `kept_b` belong to the cycle in `previous`.
    keep: bool,
    kept_valid: bool,
    kept_x: Vec<f64>,
    kept_b: Vec<f64>,
}

impl Gmres {
    /// Work arrays for dimension `n` and restart length `m`.
    pub fn new(n: usize, m: usize) -> Self {
        let m = m.max(1);
        Self {
            n,
            m,
            v: vec![vec![0.0; n]; m + 1],
            h: vec![0.0; (m + 1) * m],
            cs: vec![0.0; m],
            sn: vec![0.0; m],
            g: vec![0.0; m + 1],
            y: vec![0.0; m],
            w: vec![0.0; n],
            z: vec![0.0; n],
            zs: Vec::new(),
            lanes: false,
            r: vec![0.0; n],
            confirm: true,
            previous: None,
            keep: false,
            kept_valid: false,
            kept_x: Vec::new(),
            kept_b: Vec::new(),
        }
    }

    /// With `true`, [`Gmres::solve`] and [`Gmres::solve_in_previous_space`] keep `M⁻¹ v_j` of each
    /// cycle's basis (`m` more vectors of `n`) and update `x += Σ y_j M⁻¹ v_j` from them, saving
    /// the preconditioner application of `x += M⁻¹ V y` at each cycle's end (the same iterates in
    /// exact arithmetic; another rounding of the update). Default false.
    pub fn keep_preconditioned_basis(&mut self, on: bool) {
        self.zs = if on {
            vec![vec![0.0; self.n]; self.m]
        } else {
            Vec::new()
        };
    }

    /// With `true`, [`Gmres::solve`] and [`Gmres::solve_in_previous_space`] take their inner
    /// products and norms in eight running sums (`dot_in_lanes`: eight independent chains of
    /// additions; another rounding, the same iterates in exact arithmetic). Default false: the
    /// other callers (the EIM solves, whose checkpoints record no scheme) keep their bits.
    pub fn sum_in_lanes(&mut self, on: bool) {
        self.lanes = on;
    }

    /// With `false`, a solve returns as soon as the Arnoldi residual estimate `|g_k|/‖b‖` of a
    /// cycle is below the tolerance, without the product `b − A x` that confirms it (the two are
    /// equal in exact arithmetic with right preconditioning; they part by rounding and by the
    /// preconditioner's conditioning); [`KrylovInfo::residual`] is then that estimate. Saves one
    /// product a solve, for callers that control the solve's error otherwise (the wear run's
    /// Rosenbrock stages, docs/fretting-wear.md, "Time integration"). Default true.
    pub fn confirm_residual(&mut self, confirm: bool) {
        self.confirm = confirm;
    }

    /// With `true`, each cycle also keeps its result `x` and right-hand side `b` (two vectors of
    /// the work arrays' length, allocated here), so that
    /// [`Gmres::solve_continuing_previous_space`] adds the last result to the recycled space at
    /// no product: `A x = b − r` with `r` the last cycle's residual, known in its basis. Default
    /// false (then nothing is copied).
    pub fn keep_solution(&mut self, keep: bool) {
        self.keep = keep;
        if keep && self.kept_x.len() != self.n {
            self.kept_x = vec![0.0; self.n];
            self.kept_b = vec![0.0; self.n];
        }
    }

    /// Whether [`Gmres::solve_continuing_previous_space`] for an operator of dimension `dim`
    /// with restart length `restart` would use the kept space (otherwise it is [`Gmres::solve`]
    /// from the caller's warm start).
    pub fn has_previous_space(&self, dim: usize, restart: usize) -> bool {
        let m = self.m.min(restart).max(1);
        self.previous
            .is_some_and(|(d, r, k)| d == dim && r == m && k > 0 && k < m)
    }

    /// `(n, m)`: dimension and restart length of the work arrays.
    pub fn shape(&self) -> (usize, usize) {
        (self.n, self.m)
    }

    /// Solves `A x = b` with the preconditioner `M⁻¹` (`precond` applies `M⁻¹`); `x` is the warm
    /// start and the result. The operators may be of any dimension `d ≤ n` (the work arrays'
    /// first `d` entries are used): a caller whose system is the identity beyond its first `d`
    /// unknowns, with `b` and `x` vanishing there, solves on those `d` alone — the same
    /// iterates, since every sum over the zero tail only adds zeros.
    pub fn solve(
        &mut self,
        a: &mut dyn LinearOperator,
        precond: &mut dyn LinearOperator,
        b: &[f64],
        x: &mut [f64],
        params: &KrylovParams,
    ) -> Result<KrylovInfo, NumericsError> {
        self.previous = None;
        self.solve_in_previous_space(a, precond, b, x, params)
    }

    /// [`Gmres::solve`] for a system `A x = b` whose `A` and `M` are the last solve's (the
    /// caller's promise: the same operators, a new `b`; e.g. the two stages of a Rosenbrock step
    /// share `W`): the warm start's residual `r₀ = b − A x₀` is first minimized over the last
    /// cycle's space at no product with `A`. With the Arnoldi relation
    /// `A M⁻¹ V_k = V_{k+1} H̄_k`, `H̄_k = Qᵀ [R; 0]` kept from that cycle,
    ///
    /// `y = R⁻¹ (Q V_{k+1}ᵀ r₀)_{0..k}` minimizes `‖r₀ − A M⁻¹ V_k y‖` over the part of `r₀` in
    /// `span V_{k+1}`, and `x₀ ← x₀ + M⁻¹ V_k y`, `r₀ ← r₀ − V_{k+1} H̄_k y`
    ///
    /// (one preconditioner application, `2k + 2` vector operations; a Galerkin-type projection
    /// onto a recycled Krylov space, Parks et al. 2006, GCRO-DR, here once at the start). GMRES then
    /// goes on from that `r₀` as [`Gmres::solve`] does; the stopping rule is the same (the
    /// residual estimate `|g_k|` starts from the projected `r₀`, equal to `b − A x₀` up to rounding).
    /// Without such a space (none kept, another dimension or restart length) it is [`Gmres::solve`].
    pub fn solve_in_previous_space(
        &mut self,
        a: &mut dyn LinearOperator,
        precond: &mut dyn LinearOperator,
        b: &[f64],
        x: &mut [f64],
        params: &KrylovParams,
    ) -> Result<KrylovInfo, NumericsError> {
        let previous = self.previous.take();
        // The inner products this solve takes ([`Gmres::sum_in_lanes`]).
        let dot: fn(&[f64], &[f64]) -> f64 = if self.lanes { dot_in_lanes } else { dot };
        let norm = |a: &[f64]| dot(a, a).sqrt();
        params.validate()?;
        let n = a.dim();
        if n > self.n || precond.dim() != n {
            return Err(NumericsError::LengthMismatch {
                what: "GMRES operator dimension",
                expected: if n > self.n { self.n } else { n },
                got: if n > self.n { n } else { precond.dim() },
            });
        }
        crate::linop::check_lengths(n, b, x)?;
        let m = self.m.min(params.restart).max(1);
        let b_norm = norm(b);
        if b_norm == 0.0 {
            x.fill(0.0);
            return Ok(KrylovInfo {
                iterations: 0,
                residual: 0.0,
            });
        }
        let mut iterations = 0;
        let mut residual;
        let mut previous = previous.filter(|&(dim, restart, k)| dim == n && restart == m && k > 0);
        loop {
            // r = b − A x.
            let r = &mut self.r[..n];
            a.apply(x, r)?;
            for (ri, bi) in r.iter_mut().zip(b) {
                *ri = bi - *ri;
            }
            if let Some((_, _, k)) = previous.take() {
                self.project_on_previous_space(precond, n, m, k, x)?;
            }
            let beta = norm(&self.r[..n]);
            residual = beta / b_norm;
            if !residual.is_finite() || x.iter().any(|v| !v.is_finite()) {
                return Err(no_convergence("GMRES", iterations, residual));
            }
            if residual < params.tolerance {
                return Ok(KrylovInfo {
                    iterations,
                    residual,
                });
            }
            if iterations >= params.max_iterations {
                return Err(no_convergence("GMRES", iterations, residual));
            }
            // The cycle overwrites the basis: no space is kept until it completes.
            self.previous = None;
            for (v, r) in self.v[0][..n].iter_mut().zip(&self.r[..n]) {
                *v = r / beta;
            }
            self.g.fill(0.0);
            self.g[0] = beta;
            let mut k = 0;
            let mut last_norm = 0.0;
            while k < m && iterations < params.max_iterations {
                iterations += 1;
                // w = A M⁻¹ v_k.
                let z = match self.zs.get_mut(k) {
                    Some(kept) => kept,
                    None => &mut self.z,
                };
                precond.apply(&self.v[k][..n], &mut z[..n])?;
                a.apply(&z[..n], &mut self.w[..n])?;
                // Modified Gram–Schmidt.
                for i in 0..=k {
                    let hik = dot(&self.w[..n], &self.v[i][..n]);
                    self.h[k * (m + 1) + i] = hik;
                    for (w, v) in self.w[..n].iter_mut().zip(&self.v[i][..n]) {
                        *w -= hik * v;
                    }
                }
                let hk1 = norm(&self.w[..n]);
                last_norm = hk1;
                self.h[k * (m + 1) + k + 1] = hk1;
                if hk1 > 0.0 {
                    let (head, tail) = self.v.split_at_mut(k + 1);
                    let _ = head;
                    for (v, w) in tail[0][..n].iter_mut().zip(&self.w[..n]) {
                        *v = w / hk1;
                    }
                }
                // Previous rotations on the new column, then a new one to zero h_{k+1,k}.
                let col = &mut self.h[k * (m + 1)..(k + 1) * (m + 1)];
                rotate(&self.cs[..k], &self.sn[..k], col);
                let (a0, a1) = (col[k], col[k + 1]);
                let den = a0.hypot(a1);
                let (c, s) = if den == 0.0 {
                    (1.0, 0.0)
                } else {
                    (a0 / den, a1 / den)
                };
                self.cs[k] = c;
                self.sn[k] = s;
                col[k] = den;
                col[k + 1] = 0.0;
                self.g[k + 1] = -s * self.g[k];
                self.g[k] *= c;
                k += 1;
                residual = self.g[k].abs() / b_norm;
                if residual < params.tolerance || hk1 == 0.0 {
                    break;
                }
            }
            // y = R⁻¹ g (upper triangular k × k), x += M⁻¹ V y.
            self.back_substitute(k, m);
            if self.zs.len() >= k {
                for j in 0..k {
                    let yj = self.y[j];
                    for (xi, z) in x[..n].iter_mut().zip(&self.zs[j][..n]) {
                        *xi += yj * z;
                    }
                }
            } else {
                self.w[..n].fill(0.0);
                for j in 0..k {
                    let yj = self.y[j];
                    for (w, v) in self.w[..n].iter_mut().zip(&self.v[j][..n]) {
                        *w += yj * v;
                    }
                }
                self.add_preconditioned(precond, n, x)?;
            }
            // The last vector v_k exists unless the Arnoldi process broke down (an invariant
            // space: then no space is kept).
            if k > 0 && last_norm > 0.0 {
                self.previous = Some((n, m, k));
                self.kept_valid = self.keep;
                if self.keep {
                    self.kept_x[..n].copy_from_slice(x);
                    self.kept_b[..n].copy_from_slice(b);
                }
            }
            if !self.confirm && residual < params.tolerance {
                if x.iter().any(|v| !v.is_finite()) {
                    return Err(no_convergence("GMRES", iterations, residual));
                }
                return Ok(KrylovInfo {
                    iterations,
                    residual,
                });
            }
        }
    }

    /// [`Gmres::solve_in_previous_space`] with the last cycle's space kept through the whole
    /// first cycle instead of only at its start: a solve whose `A` and `M` are the last solve's
    /// (the caller's promise, e.g. the two stages of a Rosenbrock step, which share
    /// `W = I − γΔτJ`) minimizes `‖b − A x‖` over `x₀ + M⁻¹ span{V_k} + M⁻¹ K_j` at every
    /// iteration, `V_k` the last cycle's multiplied vectors and `K_j` the new Krylov space — an
    /// augmented Krylov method with the last cycle as the recycled space (GCRO, de Sturler 1996,
    /// "Nested Krylov methods based on GCR"; GCRO-DR, Parks et al. 2006, here with the whole last
    /// cycle kept, not a deflation subspace).
    /// With the kept relation `A M⁻¹ V_k = V_{k+1} H̄_k = C R`, `C = V_{k+1} Q₁ᵀ [I_k; 0]` (the
    /// cycle's Givens rotations `Q₁`: `C` orthonormal, a rotation of the kept basis in place) and
    /// `r₀ = b − A x₀` (no product when `x₀ = 0`):
    ///
    /// `c = Cᵀ r₀`, `r₀' = r₀ − C c` (the residual of the start projected as in
    /// [`Gmres::solve_in_previous_space`]), then Arnoldi on `(I − C Cᵀ) A M⁻¹` from `r₀'/‖r₀'‖`
    /// (each new vector orthogonal to `C` and to the new basis), so that
    /// `A M⁻¹ [V_k, A_j] = [C, A_{j+1}] [[R, Cᵀ A M⁻¹ A_j]; [0, H̄_j]]` is upper Hessenberg
    /// and `‖r₀ − A M⁻¹ [V_k, A_j] y‖ = ‖[c; ‖r₀'‖ e₁] − H̃ y‖`
    ///
    /// (one Givens rotation a column as in [`Gmres::solve`]); `x += M⁻¹(V_k y₁ + A_j y₂)`, with
    /// `V_k y₁ = [C, q] Q₁ [y₁; 0]` (`q` the kept basis' last direction). The first iterate is the
    /// projected start's; later ones minimize over `M⁻¹ span{V_k} + M⁻¹ K_j((I − CCᵀ) A M⁻¹, r₀')`,
    /// which does not contain the projected start's `K_j(A M⁻¹, r₀')` beyond `j = 1` (unless `C`
    /// is invariant under `A M⁻¹`), so fewer products than the projected start are observed,
    /// not guaranteed. The new Krylov directions share the `m` columns with the `k` recycled
    /// ones: after `m − k` of them GMRES restarts from the true residual as [`Gmres::solve`]
    /// (one product, the recycled space dropped). With
    /// [`Gmres::keep_solution`] on, the last result `x₁` joins the recycled space too: its image
    /// `A x₁ = b₁ − g_k q` (the last cycle's residual in its basis) is known without a product,
    /// and its part orthogonal to `C` is one more row `ĉ` of the triangle (column `k`: `Cᵀ A x₁`
    /// and `‖(I − CCᵀ) A x₁‖`), the update adding `y_k x₁` (not preconditioned). For the
    /// Rosenbrock stages this carries the first stage's warm start (`x₁ = b₁ + M⁻¹V_k y`), so the
    /// second stage can start from 0. The stopping rule is
    /// [`Gmres::solve`]'s; if the cycle fills the work arrays first, GMRES restarts from the true
    /// residual as [`Gmres::solve`] does. Without a kept space (none, another dimension or restart
    /// length) it is [`Gmres::solve`]. Keeps no space after it.
    pub fn solve_continuing_previous_space(
        &mut self,
        a: &mut dyn LinearOperator,
        precond: &mut dyn LinearOperator,
        b: &[f64],
        x: &mut [f64],
        params: &KrylovParams,
    ) -> Result<KrylovInfo, NumericsError> {
        let previous = self.previous.take();
        params.validate()?;
        let n = a.dim();
        let m = self.m.min(params.restart).max(1);
        self.previous = previous;
        let usable = self.has_previous_space(n, params.restart) && precond.dim() == n;
        let kept = self.previous.take().filter(|_| usable);
        let Some((_, _, k)) = kept else {
            return self.solve_in_previous_space(a, precond, b, x, params);
        };
        crate::linop::check_lengths(n, b, x)?;
        let b_norm = norm(b);
        if b_norm == 0.0 {
            x.fill(0.0);
            return Ok(KrylovInfo {
                iterations: 0,
                residual: 0.0,
            });
        }
        // r₀ = b − A x₀.
        if x.iter().all(|&v| v == 0.0) {
            self.r[..n].copy_from_slice(b);
        } else {
            let r = &mut self.r[..n];
            a.apply(x, r)?;
            for (ri, bi) in r.iter_mut().zip(b) {
                *ri = bi - *ri;
            }
        }
        // The kept basis rotated in place, [C, q] = V_{k+1} Q₁ᵀ.
        for i in 0..k {
            let (c, s) = (self.cs[i], self.sn[i]);
            let (head, tail) = self.v.split_at_mut(i + 1);
            for (p, q) in head[i][..n].iter_mut().zip(&mut tail[0][..n]) {
                let (a0, a1) = (*p, *q);
                *p = c * a0 + s * a1;
                *q = -s * a0 + c * a1;
            }
        }
        // q, needed for the update, in z; its slot takes the next basis vector.
        self.z[..n].copy_from_slice(&self.v[k][..n]);
        // With the last result x₁ kept (`keep_solution`): A x₁ = b₁ − g_k q (its residual
        // in the kept basis), orthogonalized against C, is the image of one more recycled
        // direction, column k of the triangle: p = k + 1 recycled columns.
        let mut p = k;
        if self.kept_valid {
            let gk = self.g[k];
            for ((w, bi), q) in self.w[..n]
                .iter_mut()
                .zip(&self.kept_b[..n])
                .zip(&self.z[..n])
            {
                *w = bi - gk * q;
            }
            let d_norm = norm(&self.w[..n]);
            for i in 0..k {
                let e = dot(&self.w[..n], &self.v[i][..n]);
                self.h[k * (m + 1) + i] = e;
                for (w, v) in self.w[..n].iter_mut().zip(&self.v[i][..n]) {
                    *w -= e * v;
                }
            }
            let delta = norm(&self.w[..n]);
            // (A direction already in the space would make the triangle singular.)
            if delta > 1e-12 * d_norm && k + 1 < m {
                self.h[k * (m + 1) + k] = delta;
                for (v, w) in self.v[k][..n].iter_mut().zip(&self.w[..n]) {
                    *v = w / delta;
                }
                p = k + 1;
            }
        }
        // c = [C, ĉ]ᵀ r₀ (modified Gram–Schmidt), r₀' = r₀ − [C, ĉ] c.
        self.g.fill(0.0);
        for i in 0..p {
            let ci = dot(&self.r[..n], &self.v[i][..n]);
            self.g[i] = ci;
            for (r, v) in self.r[..n].iter_mut().zip(&self.v[i][..n]) {
                *r -= ci * v;
            }
        }
        let beta = norm(&self.r[..n]);
        if beta > 0.0 {
            for (v, r) in self.v[p][..n].iter_mut().zip(&self.r[..n]) {
                *v = r / beta;
            }
        }
        self.r[..n].copy_from_slice(&self.z[..n]);
        self.g[p] = beta;
        let mut col = p;
        let mut residual = beta / b_norm;
        let mut iterations = 0;
        let mut singular = false;
        while residual >= params.tolerance && col < m && iterations < params.max_iterations {
            iterations += 1;
            // w = A M⁻¹ a_j, orthogonal to C and the new basis.
            precond.apply(&self.v[col][..n], &mut self.z[..n])?;
            a.apply(&self.z[..n], &mut self.w[..n])?;
            for i in 0..=col {
                let hi = dot(&self.w[..n], &self.v[i][..n]);
                self.h[col * (m + 1) + i] = hi;
                for (w, v) in self.w[..n].iter_mut().zip(&self.v[i][..n]) {
                    *w -= hi * v;
                }
            }
            let hn = norm(&self.w[..n]);
            self.h[col * (m + 1) + col + 1] = hn;
            if hn > 0.0 {
                let (_, tail) = self.v.split_at_mut(col + 1);
                for (v, w) in tail[0][..n].iter_mut().zip(&self.w[..n]) {
                    *v = w / hn;
                }
            }
            // The new part is Hessenberg below the recycled rows: its rotations only.
            let column = &mut self.h[col * (m + 1)..(col + 1) * (m + 1)];
            for i in p..col {
                let (c, s) = (self.cs[i], self.sn[i]);
                let (a0, a1) = (column[i], column[i + 1]);
                column[i] = c * a0 + s * a1;
                column[i + 1] = -s * a0 + c * a1;
            }
            let (a0, a1) = (column[col], column[col + 1]);
            let den = a0.hypot(a1);
            if den == 0.0 {
                // (I − CCᵀ) A M⁻¹ singular on the new direction (possible when the recycled
                // sources and C⊥ meet): no progress; GMRES from the true residual below.
                singular = true;
                break;
            }
            let (c, s) = (a0 / den, a1 / den);
            self.cs[col] = c;
            self.sn[col] = s;
            column[col] = den;
            column[col + 1] = 0.0;
            self.g[col + 1] = -s * self.g[col];
            self.g[col] *= c;
            col += 1;
            residual = self.g[col].abs() / b_norm;
            if hn == 0.0 {
                break;
            }
        }
        // y = R̃⁻¹ g (col × col); x += M⁻¹([C, q] Q₁ [y₁; 0] + A_j y₂).
        self.back_substitute(col, m);
        let t = &mut self.g[..=k];
        t[..k].copy_from_slice(&self.y[..k]);
        t[k] = 0.0;
        rotate(&self.cs[..k], &self.sn[..k], t);
        self.w[..n].fill(0.0);
        for i in 0..k {
            let ti = self.g[i];
            for (w, v) in self.w[..n].iter_mut().zip(&self.v[i][..n]) {
                *w += ti * v;
            }
        }
        let tq = self.g[k];
        for (w, q) in self.w[..n].iter_mut().zip(&self.r[..n]) {
            *w += tq * q;
        }
        for j in p..col {
            let yj = self.y[j];
            for (w, v) in self.w[..n].iter_mut().zip(&self.v[j][..n]) {
                *w += yj * v;
            }
        }
        self.add_preconditioned(precond, n, x)?;
        if p > k {
            let yk = self.y[k];
            for (xi, x1) in x.iter_mut().zip(&self.kept_x[..n]) {
                *xi += yk * x1;
            }
        }
        if !residual.is_finite() || x.iter().any(|v| !v.is_finite()) {
            return Err(no_convergence("GMRES", iterations, residual));
        }
        if !self.confirm && !singular && residual < params.tolerance {
            return Ok(KrylovInfo {
                iterations,
                residual,
            });
        }
        if iterations >= params.max_iterations {
            return Err(no_convergence("GMRES", iterations, residual));
        }
        // Confirmed, or not converged within the work arrays: GMRES from the true residual.
        let rest = KrylovParams {
            max_iterations: params.max_iterations - iterations,
            ..*params
        };
        let info = self.solve(a, precond, b, x, &rest).map_err(|e| match e {
            NumericsError::NoConvergence {
                iterations: i,
                residual,
                ..
            } => no_convergence("GMRES", iterations + i, residual),
            e => e,
        })?;
        Ok(KrylovInfo {
            iterations: iterations + info.iterations,
            residual: info.residual,
        })
    }
}

impl Gmres {
    /// The start of [`Gmres::solve_in_previous_space`]: with `r = b − A x` in `self.r`, the
    /// kept cycle's `k` vectors, `R` and rotations, `c = Q V_{k+1}ᵀ r`, `y = R⁻¹ c_{0..k}`,
    /// `x += M⁻¹ V_k y` and `r −= V_{k+1} Qᵀ [c_{0..k}; 0]` (`= V_{k+1} H̄_k y`).
    fn project_on_previous_space(
        &mut self,
        precond: &mut dyn LinearOperator,
        n: usize,
        m: usize,
        k: usize,
        x: &mut [f64],
    ) -> Result<(), NumericsError> {
        for (ci, v) in self.g.iter_mut().zip(&self.v).take(k + 1) {
            *ci = dot(&self.r[..n], &v[..n]);
        }
        rotate(&self.cs[..k], &self.sn[..k], &mut self.g);
        self.back_substitute(k, m);
        // t = Qᵀ [c_{0..k}; 0]: the rotations' transposes in reverse order.
        let c = &mut self.g;
        c[k] = 0.0;
        for i in (0..k).rev() {
            let (cs, sn) = (self.cs[i], self.sn[i]);
            let (a0, a1) = (c[i], c[i + 1]);
            c[i] = cs * a0 - sn * a1;
            c[i + 1] = sn * a0 + cs * a1;
        }
        self.w[..n].fill(0.0);
        for (j, v) in self.v.iter().enumerate().take(k + 1) {
            let (yj, tj) = (if j < k { self.y[j] } else { 0.0 }, c[j]);
            for ((w, r), vi) in self.w[..n].iter_mut().zip(&mut self.r[..n]).zip(&v[..n]) {
                *w += yj * vi;
                *r -= tj * vi;
            }
        }
        self.add_preconditioned(precond, n, x)
    }

    /// `y = R⁻¹ g_{0..k}` (`R` the upper triangle `k × k` of the rotated Hessenberg matrix,
    /// columns of length `m + 1`), by back substitution; a zero pivot (a breakdown) gives `y_i = 0`.
    fn back_substitute(&mut self, k: usize, m: usize) {
        for i in (0..k).rev() {
            let mut s = self.g[i];
            for j in i + 1..k {
                s -= self.h[j * (m + 1) + i] * self.y[j];
            }
            let d = self.h[i * (m + 1) + i];
            self.y[i] = if d != 0.0 { s / d } else { 0.0 };
        }
    }

    /// `x += M⁻¹ w` (`w` the first `n` entries of the work vector `w`).
    fn add_preconditioned(
        &mut self,
        precond: &mut dyn LinearOperator,
        n: usize,
        x: &mut [f64],
    ) -> Result<(), NumericsError> {
        precond.apply(&self.w[..n], &mut self.z[..n])?;
        for (xi, zi) in x.iter_mut().zip(&self.z[..n]) {
            *xi += zi;
        }
        Ok(())
    }
}

/// The Givens rotations `(cs_i, sn_i)`, `i = 0..k`, applied in order to `v`:
/// `(v_i, v_{i+1}) ← (c v_i + s v_{i+1}, −s v_i + c v_{i+1})` (`Q v` of the Hessenberg
/// least-squares problem).
fn rotate(cs: &[f64], sn: &[f64], v: &mut [f64]) {
    for (i, (&c, &s)) in cs.iter().zip(sn).enumerate() {
        let (a0, a1) = (v[i], v[i + 1]);
        v[i] = c * a0 + s * a1;
        v[i + 1] = -s * a0 + c * a1;
    }
}

/// Preconditioned Richardson iteration `x ← x + M⁻¹(b − A x)` (block Jacobi when `M` is the
/// block diagonal), warm-started from `x`. Stops when `max|Δx| / max|x| < tol`; a step `max|Δx|` that
/// grows a thousandfold over its smallest value, or a non-finite iterate, is reported as divergence
/// ([`NumericsError::NoConvergence`]). The work vectors are the caller's `work`, kept between
/// solves (resized, i.e. allocated, only when its length is not `A`'s dimension; its values are
/// overwritten before they are read: the result does not depend on them).
pub fn richardson(
    a: &mut dyn LinearOperator,
    precond: &mut dyn LinearOperator,
    b: &[f64],
    x: &mut [f64],
    params: &KrylovParams,
    work: &mut RichardsonWork,
) -> Result<KrylovInfo, NumericsError> {
    params.validate()?;
    let n = a.dim();
    crate::linop::check_lengths(n, b, x)?;
    work.resize(n);
    richardson_iterate(a, precond, b, x, params, None, work)
}

/// What [`richardson_mixed`] keeps between solves with one operator `A` and preconditioner `M`
/// (and new right-hand sides): the Anderson history of its iterates, and the last solve's last
/// iterate `x_J` with its exact residual `r_J = b − A x_J`, so that a solve warm-started from the
/// last result `x_J + M⁻¹r_J` with a new `b'` knows the residual of `x_J` without applying `A`:
/// `b' − A x_J = r_J + (b' − b)`.
#[derive(Debug, Clone)]
pub struct RichardsonRecycle {
    mixing: Anderson,
    start: Vec<f64>,
    residual: Vec<f64>,
    rhs: Vec<f64>,
    result: Vec<f64>,
    valid: bool,
    /// The iteration's work vectors `r`, `M⁻¹r` and `x_k` (kept: a solve allocates none).
    work: RichardsonWork,
}

/// The work vectors of [`richardson`] and [`richardson_mixed`]: the residual, the preconditioned
/// step and the iterate before the step (three vectors of the system's length).
#[derive(Debug, Clone, Default)]
pub struct RichardsonWork {
    r: Vec<f64>,
    dx: Vec<f64>,
    before: Vec<f64>,
}

impl RichardsonWork {
    /// Work vectors for systems of `len` unknowns.
    pub fn new(len: usize) -> Self {
        Self {
            r: vec![0.0; len],
            dx: vec![0.0; len],
            before: vec![0.0; len],
        }
    }

    /// The length of the vectors.
    pub fn len(&self) -> usize {
        self.r.len()
    }

    /// Whether the vectors are empty.
    pub fn is_empty(&self) -> bool {
        self.r.is_empty()
    }

    /// Vectors of length `len` (allocates only when the length changes).
    fn resize(&mut self, len: usize) {
        if self.len() != len {
            *self = Self::new(len);
        }
    }
}

impl RichardsonRecycle {
    /// For vectors of length `len`, with `depth` Anderson differences.
    pub fn new(len: usize, depth: usize) -> Self {
        Self {
            mixing: Anderson::new(len, depth),
            start: vec![0.0; len],
            residual: vec![0.0; len],
            rhs: vec![0.0; len],
            result: vec![0.0; len],
            valid: false,
            work: RichardsonWork::new(len),
        }
    }

    /// `(len, depth)`.
    pub fn shape(&self) -> (usize, usize) {
        self.mixing.shape()
    }

    /// Forgets everything kept: the next solve is plain [`richardson`] from its warm start.
    pub fn forget(&mut self) {
        self.mixing.reset();
        self.valid = false;
    }

    /// The last solve's last iterate `x_J` (into `iterate`) and its image `A x_J = b_J − r_J`
    /// (into `image`, as kept: `r_J` is the residual the iteration used), when a solve left them
    /// ([`richardson_mixed`] keeps them at convergence; [`RichardsonRecycle::forget`] drops them).
    /// Returns whether they were written.
    /// Errors: a vector not of the recycled length.
    pub fn last_iterate_image(
        &self,
        iterate: &mut [f64],
        image: &mut [f64],
    ) -> Result<bool, NumericsError> {
        let n = self.start.len();
        crate::linop::check_lengths(n, iterate, image)?;
        if !self.valid {
            return Ok(false);
        }
        iterate.copy_from_slice(&self.start);
        for ((v, b), r) in image.iter_mut().zip(&self.rhs).zip(&self.residual) {
            *v = b - r;
        }
        Ok(true)
    }

    /// Declares `image = A x` for a next solve warm-started from `x` bit for bit: that solve's
    /// first residual is `b − image`, without an application of `A` (the recycled differences are
    /// kept). With `image` a linear combination of kept images (`A(2x_n − x_{n−1}) = 2A x_n −
    /// A x_{n−1}`) this is exact up to the rounding of the combination.
    /// Errors: a vector not of the recycled length.
    pub fn set_known_start(&mut self, x: &[f64], image: &[f64]) -> Result<(), NumericsError> {
        let n = self.start.len();
        crate::linop::check_lengths(n, x, image)?;
        // The known-residual path computes `r = residual + (b − rhs)`: with `rhs = 0` and
        // `residual = −image` that is `b − image` exactly.
        self.start.copy_from_slice(x);
        self.result.copy_from_slice(x);
        self.rhs.fill(0.0);
        for (r, v) in self.residual.iter_mut().zip(image) {
            *r = -v;
        }
        self.valid = true;
        Ok(())
    }
}

/// [`richardson`] recycling what earlier solves with the same `A` and `M` learned, when `recycle`
/// is given (docs/theory-sam.md#solving-the-eim-equations):
///
/// * **Anderson mixing** of the iterates: with `G(x) = x + M⁻¹(b − A x)`, `x_{k+1}` is the
///   Anderson step of `(x_k, G(x_k))` ([`crate::anderson`], mixing `ω = 1`). `G` is affine and its
///   differences `Δf = −M⁻¹A Δx` do not depend on `b`, so the history of earlier solves stays
///   valid and is kept ([`Anderson::forget_previous`]): a new solve's first step already projects
///   on it.
/// * **The first residual without an application**: when the warm start `x` is, bit for bit, the
///   last solve's result, the iteration restarts from that solve's last iterate `x_J`, whose
///   residual for the new `b` is `r_J + (b − b_J)` (exact in exact arithmetic), so the first step
///   costs no application of `A` and adds `M⁻¹(b − b_J)` to the old result.
///
/// The stop is [`richardson`]'s, on the step `max|G(x_k) − x_k| / max|G(x_k)|`, and the result
/// is the plain step `G(x_k)`; [`KrylovInfo::iterations`] counts applications of `A`. `None` is
/// [`richardson`], bit for bit, on work vectors allocated for the call (a caller solving
/// repeatedly keeps a [`RichardsonWork`] and calls [`richardson`]).
pub fn richardson_mixed(
    a: &mut dyn LinearOperator,
    precond: &mut dyn LinearOperator,
    b: &[f64],
    x: &mut [f64],
    params: &KrylovParams,
    mut recycle: Option<&mut RichardsonRecycle>,
) -> Result<KrylovInfo, NumericsError> {
    params.validate()?;
    let n = a.dim();
    crate::linop::check_lengths(n, b, x)?;
    if let Some(rc) = recycle.as_deref() {
        if rc.shape().0 != n {
            return Err(NumericsError::LengthMismatch {
                what: "recycled Richardson state",
                expected: n,
                got: rc.shape().0,
            });
        }
    }
    // The work vectors: the recycled state's (no allocation per solve), or new ones.
    let mut work = match recycle.as_deref_mut() {
        Some(rc) => std::mem::take(&mut rc.work),
        None => RichardsonWork::new(n),
    };
    let result = richardson_iterate(a, precond, b, x, params, recycle.as_deref_mut(), &mut work);
    if let Some(rc) = recycle {
        rc.work = work;
    }
    result
}

/// Elements per task of [`richardson_mixed`]'s element passes (each element's arithmetic is the
/// same on any chunking).
const RICHARDSON_CHUNK: usize = 1 << 14;

/// [`richardson_mixed`]'s iteration on given work vectors (of length `n`).
fn richardson_iterate(
    a: &mut dyn LinearOperator,
    precond: &mut dyn LinearOperator,
    b: &[f64],
    x: &mut [f64],
    params: &KrylovParams,
    mut recycle: Option<&mut RichardsonRecycle>,
    work: &mut RichardsonWork,
) -> Result<KrylovInfo, NumericsError> {
    let RichardsonWork { r, dx, before } = work;
    // Whether the first residual is known (the warm start is the last result).
    let mut known = false;
    if let Some(rc) = recycle.as_deref_mut() {
        rc.mixing.forget_previous();
        known = rc.valid
            && x.iter()
                .zip(&rc.result)
                .all(|(p, q)| p.to_bits() == q.to_bits());
        if known {
            x.copy_from_slice(&rc.start);
            for (ri, ((rj, bi), bj)) in r.iter_mut().zip(rc.residual.iter().zip(b).zip(&rc.rhs)) {
                *ri = rj + (bi - bj);
            }
        }
        rc.valid = false;
    }
    let mixed = recycle.is_some();
    let mut applications = 0;
    let mut best = f64::INFINITY;
    for it in 1..=params.max_iterations {
        if it > 1 || !known {
            a.apply(x, r)?;
            applications += 1;
            r.par_chunks_mut(RICHARDSON_CHUNK)
                .zip(b.par_chunks(RICHARDSON_CHUNK))
                .for_each(|(r, b)| {
                    for (ri, bi) in r.iter_mut().zip(b) {
                        *ri = bi - *ri;
                    }
                });
        }
        precond.apply(r, dx)?;
        // One element pass on the pool: `x_k` kept (mixing only), `x ← x + M⁻¹r`, and the
        // maxima of the step and the iterate (a maximum has the same bits in any order).
        let (change, size, finite) = x
            .par_chunks_mut(RICHARDSON_CHUNK)
            .zip(dx.par_chunks(RICHARDSON_CHUNK))
            .zip(before.par_chunks_mut(RICHARDSON_CHUNK))
            .map(|((x, dx), before)| {
                if mixed {
                    before.copy_from_slice(x);
                }
                let mut change: f64 = 0.0;
                let mut size: f64 = 0.0;
                let mut finite = true;
                for (xi, d) in x.iter_mut().zip(dx) {
                    *xi += d;
                    finite &= xi.is_finite();
                    change = change.max(d.abs());
                    size = size.max(xi.abs());
                }
                (change, size, finite)
            })
            .reduce(
                || (0.0, 0.0, true),
                |(c0, s0, f0), (c1, s1, f1)| (c0.max(c1), s0.max(s1), f0 && f1),
            );
        // f64::max skips NaN: check finiteness of the iterate itself.
        let rel = if !finite {
            f64::NAN
        } else if size > 0.0 {
            change / size
        } else {
            0.0
        };
        if !rel.is_finite() {
            return Err(no_convergence("block Jacobi", it, rel));
        }
        if rel < params.tolerance {
            if let Some(rc) = recycle.as_deref_mut() {
                rc.start.copy_from_slice(before);
                rc.residual.copy_from_slice(r);
                rc.rhs.copy_from_slice(b);
                rc.result.copy_from_slice(x);
                rc.valid = true;
            }
            return Ok(KrylovInfo {
                iterations: applications,
                residual: rel,
            });
        }
        // Divergence: the step itself grows (a spectral radius > 1 keeps max|Δx|/max|x| level).
        best = best.min(change);
        if change > 1e3 * best && it > 3 {
            return Err(no_convergence("block Jacobi (diverging)", it, rel));
        }
        if it == params.max_iterations {
            return Err(no_convergence("block Jacobi", it, rel));
        }
        if let Some(rc) = recycle.as_deref_mut() {
            // `x` holds G(x_k), `before` x_k: the mixed iterate written over `x`.
            rc.mixing.step_onto(before, x, 1.0)?;
        }
    }
    Err(no_convergence(
        "block Jacobi",
        params.max_iterations,
        f64::NAN,
    ))
}

fn no_convergence(solver: &'static str, iterations: usize, residual: f64) -> NumericsError {
    NumericsError::NoConvergence {
        solver,
        iterations,
        residual,
    }
}

/// `Σ a_i b_i`, one running sum (the default rounding of every solver here).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `Σ a_i b_i` in eight running sums (lanes `i mod 8`), added pairwise at the end, and the tail:
/// eight independent chains of additions instead of one ([`Gmres::sum_in_lanes`]; the wear run's
/// GMRES spends its own time in these dependent additions; docs/performance.md, "The GMRES inner
/// products in eight sums").
fn dot_in_lanes(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let mut acc = [0.0f64; 8];
    let (lanes_a, lanes_b) = (a[..n].chunks_exact(8), b[..n].chunks_exact(8));
    let (tail_a, tail_b) = (lanes_a.remainder(), lanes_b.remainder());
    for (x, y) in lanes_a.zip(lanes_b) {
        for l in 0..8 {
            acc[l] += x[l] * y[l];
        }
    }
    let tail: f64 = tail_a.iter().zip(tail_b).map(|(x, y)| x * y).sum();
    ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7])) + tail
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linop::{DenseMatrix, Identity};

    /// A nonsymmetric, diagonally dominant test matrix with a fixed seed.
    fn matrix(n: usize, seed: u64) -> DenseMatrix {
        let mut rng = crate::testkit::Lcg::new(seed);
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let r = rng.unit() - 0.5;
                a[i * n + j] = r / n as f64 + if i == j { 1.0 + 0.01 * i as f64 } else { 0.0 };
            }
        }
        DenseMatrix::from_row_major(n, a).unwrap()
    }

    #[test]
    fn gmres_solves_a_nonsymmetric_system_with_and_without_restart() {
        let n = 60;
        let mut a = matrix(n, 7);
        let x_true: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut b = vec![0.0; n];
        a.apply(&x_true, &mut b).unwrap();
        for restart in [5, 60] {
            let mut x = vec![0.0; n];
            let params = KrylovParams {
                tolerance: 1e-12,
                restart,
                ..Default::default()
            };
            let info = Gmres::new(n, restart)
                .solve(&mut a, &mut Identity(n), &b, &mut x, &params)
                .unwrap();
            let err = x
                .iter()
                .zip(&x_true)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e-10, "restart {restart}: {err:e} after {info:?}");
        }
    }

    /// With the preconditioned basis kept (flexible-GMRES storage), a preconditioned solve
    /// takes the same number of iterations and products and returns the same solution to
    /// rounding, with and without restarts; one preconditioner application fewer a cycle.
    #[test]
    fn kept_preconditioned_basis_gives_the_same_solve() {
        let n = 80;
        let (mut a, mut m, b1, _, _) = second_right_hand_side_problem(n);
        for restart in [8, 80] {
            let params = KrylovParams {
                tolerance: 1e-10,
                restart,
                ..Default::default()
            };
            let mut runs = Vec::new();
            for keep in [false, true] {
                let mut gmres = Gmres::new(n, restart);
                gmres.keep_preconditioned_basis(keep);
                let mut x = vec![0.0; n];
                let mut counted = Counted(&mut m, 0);
                let info = gmres
                    .solve(&mut a, &mut counted, &b1, &mut x, &params)
                    .unwrap();
                runs.push((x, info.iterations, counted.1));
            }
            let (plain, kept) = (&runs[0], &runs[1]);
            assert_eq!(plain.1, kept.1, "restart {restart}: iterations");
            let cycles = plain.1.div_ceil(restart);
            assert_eq!(
                plain.2,
                kept.2 + cycles,
                "restart {restart}: M⁻¹ applications"
            );
            let size = plain.0.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            for (p, k) in plain.0.iter().zip(&kept.0) {
                assert!(
                    (p - k).abs() <= 1e-12 * size,
                    "restart {restart}: {p} vs {k}"
                );
            }
        }
    }

    /// Counts the products of the operator it wraps.
    struct Counted<'a>(&'a mut DenseMatrix, usize);

    impl LinearOperator for Counted<'_> {
        fn dim(&self) -> usize {
            self.0.dim()
        }
        fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
            self.1 += 1;
            self.0.apply(x, y)
        }
    }

    /// Without the confirming product: one product fewer, the returned residual is the estimate,
    /// and the true residual of the answer is within the tolerance too (to rounding), with and
    /// without restarts.
    /// The two previous-space tests' problem: `A` (the test matrix of size `n`), a diagonal
    /// `M`, a first right-hand side `b₁`, a nearby one (as the second stage's) and an unrelated
    /// one.
    fn second_right_hand_side_problem(
        n: usize,
    ) -> (DenseMatrix, DenseMatrix, Vec<f64>, Vec<f64>, Vec<f64>) {
        let a = matrix(n, 5);
        let diagonal: Vec<f64> = (0..n * n)
            .map(|l| {
                if l % (n + 1) == 0 {
                    1.0 / (1.0 + 0.01 * (l / n) as f64)
                } else {
                    0.0
                }
            })
            .collect();
        let m = DenseMatrix::from_row_major(n, diagonal).unwrap();
        let b1: Vec<f64> = (0..n).map(|i| (i as f64 * 0.13).sin() + 0.2).collect();
        let near: Vec<f64> = b1
            .iter()
            .enumerate()
            .map(|(i, v)| -1.3 * v + 1e-3 * (i as f64 * 0.7).cos())
            .collect();
        let far: Vec<f64> = (0..n).map(|i| ((i * i) as f64 * 0.37).cos()).collect();
        (a, m, b1, near, far)
    }

    /// A second right-hand side with the same `A` and `M`: the start in the first solve's last
    /// cycle's space meets the tolerance by the true residual, on fewer products when the new `b`
    /// is close to that space; with no space kept (a fresh solver, another dimension) it is the
    /// plain solve bit for bit.
    #[test]
    fn gmres_in_the_previous_space_meets_the_tolerance_on_fewer_products() {
        let n = 80;
        let (mut a, mut m, b1, near, far) = second_right_hand_side_problem(n);
        for confirm in [true, false] {
            for restart in [8, 80] {
                let params = KrylovParams {
                    tolerance: 1e-9,
                    restart,
                    ..Default::default()
                };
                for (b2, fewer) in [(&near, true), (&far, false)] {
                    let mut counts = [0usize; 2];
                    for (recycled, count) in [false, true].into_iter().zip(counts.iter_mut()) {
                        let mut gmres = Gmres::new(n, restart);
                        gmres.confirm_residual(confirm);
                        let mut x1 = vec![0.0; n];
                        gmres.solve(&mut a, &mut m, &b1, &mut x1, &params).unwrap();
                        let mut x = vec![0.0; n];
                        let mut counted = Counted(&mut a, 0);
                        let info = if recycled {
                            gmres.solve_in_previous_space(&mut counted, &mut m, b2, &mut x, &params)
                        } else {
                            gmres.solve(&mut counted, &mut m, b2, &mut x, &params)
                        }
                        .unwrap();
                        *count = counted.1;
                        assert!(info.residual < params.tolerance);
                        let mut r = vec![0.0; n];
                        a.apply(&x, &mut r).unwrap();
                        let true_residual = norm(
                            &r.iter()
                                .zip(b2.iter())
                                .map(|(p, q)| p - q)
                                .collect::<Vec<_>>(),
                        ) / norm(b2);
                        assert!(true_residual < 1.5 * params.tolerance, "{true_residual:e}");
                    }
                    // (The first solve in one cycle: its whole space is kept.)
                    if fewer && restart == n {
                        assert!(counts[1] < counts[0], "{counts:?}, restart {restart}");
                    }
                }
            }
        }
        // No space kept: the plain solve's bits (a fresh solver; a space of another dimension).
        let params = KrylovParams {
            tolerance: 1e-9,
            restart: 10,
            ..Default::default()
        };
        let mut plain = vec![0.0; n];
        Gmres::new(n, 10)
            .solve(&mut a, &mut m, &far, &mut plain, &params)
            .unwrap();
        let mut fresh = vec![0.0; n];
        Gmres::new(n, 10)
            .solve_in_previous_space(&mut a, &mut m, &far, &mut fresh, &params)
            .unwrap();
        let mut gmres = Gmres::new(n + 5, 10);
        let mut small = matrix(n + 5, 9);
        let mut x = vec![0.0; n + 5];
        gmres
            .solve(
                &mut small,
                &mut Identity(n + 5),
                &vec![1.0; n + 5],
                &mut x,
                &params,
            )
            .unwrap();
        let mut other = vec![0.0; n];
        gmres
            .solve_in_previous_space(&mut a, &mut m, &far, &mut other, &params)
            .unwrap();
        for v in [&fresh, &other] {
            assert!(v
                .iter()
                .zip(&plain)
                .all(|(p, q)| p.to_bits() == q.to_bits()));
        }
    }

    /// The continued cycle ([`Gmres::solve_continuing_previous_space`]): on a second right-hand
    /// side with the same `A` and `M`, from a warm start and from zero, with and without the
    /// confirming product and with a restart length that the continued cycle fills, the true
    /// residual meets the tolerance; on this matrix it takes no more products than the projected
    /// start (an observation: not a theorem beyond the first iterate), and
    /// on a right-hand side near the first one started from zero fewer than the plain solve
    /// (observed 4 against 7 and the projected 5), also with the first result kept
    /// ([`Gmres::keep_solution`]); stopped after `j`
    /// products, the reported least-squares residual is the true one of the iterate (the identity
    /// `‖r₀ − V H̄ y‖ = ‖c − H̄ y‖`, with and without the kept result) and falls with `j`
    /// (nested spaces);
    /// with no space kept it is the plain solve bit for bit.
    #[test]
    fn gmres_continuing_the_previous_space_meets_the_tolerance_on_fewer_products() {
        let n = 80;
        let (mut a, mut m, b1, near, far) = second_right_hand_side_problem(n);
        let true_residual = |a: &mut DenseMatrix, x: &[f64], b: &[f64]| {
            let mut r = vec![0.0; n];
            a.apply(x, &mut r).unwrap();
            norm(&r.iter().zip(b).map(|(p, q)| p - q).collect::<Vec<_>>()) / norm(b)
        };
        for confirm in [true, false] {
            for restart in [12, 80] {
                let params = KrylovParams {
                    tolerance: 1e-9,
                    restart,
                    ..Default::default()
                };
                for (b2, near_first) in [(&near, true), (&far, false)] {
                    for zero in [false, true] {
                        // plain, projected, continued, continued with the first result kept
                        let mut counts = [0usize; 4];
                        for (mode, count) in counts.iter_mut().enumerate() {
                            let mut gmres = Gmres::new(n, restart);
                            gmres.confirm_residual(confirm);
                            gmres.keep_solution(mode == 3);
                            // A first solve that stops early keeps a short cycle.
                            let first = KrylovParams {
                                tolerance: 1e-4,
                                ..params
                            };
                            let mut x1 = vec![0.0; n];
                            gmres.solve(&mut a, &mut m, &b1, &mut x1, &first).unwrap();
                            let mut x: Vec<f64> = if zero { vec![0.0; n] } else { b2.clone() };
                            let mut counted = Counted(&mut a, 0);
                            let info = match mode {
                                0 => gmres.solve(&mut counted, &mut m, b2, &mut x, &params),
                                1 => gmres.solve_in_previous_space(
                                    &mut counted,
                                    &mut m,
                                    b2,
                                    &mut x,
                                    &params,
                                ),
                                _ => gmres.solve_continuing_previous_space(
                                    &mut counted,
                                    &mut m,
                                    b2,
                                    &mut x,
                                    &params,
                                ),
                            }
                            .unwrap();
                            *count = counted.1;
                            assert!(info.residual < params.tolerance);
                            let t = true_residual(&mut a, &x, b2);
                            assert!(t < 1.5 * params.tolerance, "mode {mode}: {t:e}");
                        }
                        // Observed on this matrix (deterministic), not a theorem beyond the
                        // first iterate: no more products than the projected start; on the
                        // nearby right-hand side from zero, fewer than the plain solve.
                        assert!(counts[2] <= counts[1], "{counts:?}");
                        if near_first && zero {
                            assert!(counts[2] < counts[0], "{counts:?}");
                            assert!(counts[3] < counts[0], "{counts:?}");
                        }
                    }
                }
            }
        }
        // Stopped after j products: the estimate is the true residual, and it falls with j.
        for keep in [false, true] {
            let mut last = f64::INFINITY;
            for j in 1..8 {
                let mut gmres = Gmres::new(n, n);
                gmres.confirm_residual(false);
                gmres.keep_solution(keep);
                let mut x1 = vec![0.0; n];
                let first = KrylovParams {
                    tolerance: 1e-4,
                    restart: n,
                    ..Default::default()
                };
                gmres.solve(&mut a, &mut m, &b1, &mut x1, &first).unwrap();
                let mut x = far.clone();
                let limited = KrylovParams {
                    tolerance: 1e-14,
                    max_iterations: j,
                    restart: n,
                };
                let err = gmres
                    .solve_continuing_previous_space(&mut a, &mut m, &far, &mut x, &limited)
                    .unwrap_err();
                let NumericsError::NoConvergence {
                    iterations,
                    residual,
                    ..
                } = err
                else {
                    panic!("{err}");
                };
                assert_eq!(iterations, j);
                let t = true_residual(&mut a, &x, &far);
                // (The true residual's own rounding, ε ‖A‖ ‖x‖ / ‖b‖, is ~1e-15.)
                assert!(
                    (t - residual).abs() < 1e-12 + 1e-8 * t,
                    "j {j}: {t:e} against {residual:e}"
                );
                assert!(t <= last * (1.0 + 1e-12), "j {j}: {t:e} after {last:e}");
                last = t;
            }
        }
        // No space kept: the plain solve's bits.
        let params = KrylovParams {
            tolerance: 1e-9,
            restart: 10,
            ..Default::default()
        };
        let mut plain = vec![0.0; n];
        Gmres::new(n, 10)
            .solve(&mut a, &mut m, &far, &mut plain, &params)
            .unwrap();
        let mut fresh = vec![0.0; n];
        Gmres::new(n, 10)
            .solve_continuing_previous_space(&mut a, &mut m, &far, &mut fresh, &params)
            .unwrap();
        assert!(fresh
            .iter()
            .zip(&plain)
            .all(|(p, q)| p.to_bits() == q.to_bits()));
    }

    #[test]
    fn gmres_without_the_confirming_product_saves_one() {
        let n = 60;
        let mut a = matrix(n, 11);
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.21).cos()).collect();
        for restart in [5, 60] {
            let params = KrylovParams {
                tolerance: 1e-9,
                restart,
                ..Default::default()
            };
            let mut products = [0usize; 2];
            let mut answers = [vec![0.0; n], vec![0.0; n]];
            for (confirm, (x, count)) in [true, false]
                .into_iter()
                .zip(answers.iter_mut().zip(products.iter_mut()))
            {
                let mut gmres = Gmres::new(n, restart);
                gmres.confirm_residual(confirm);
                let mut counted = Counted(&mut a, 0);
                let info = gmres
                    .solve(&mut counted, &mut Identity(n), &b, x, &params)
                    .unwrap();
                *count = counted.1;
                assert!(info.residual < params.tolerance);
                let mut r = vec![0.0; n];
                a.apply(x, &mut r).unwrap();
                let true_residual =
                    norm(&r.iter().zip(&b).map(|(p, q)| p - q).collect::<Vec<_>>()) / norm(&b);
                assert!(true_residual < 1.01 * params.tolerance, "{true_residual:e}");
            }
            assert_eq!(products[1] + 1, products[0], "restart {restart}");
            // The same iterates up to the last update.
            assert!(answers[0]
                .iter()
                .zip(&answers[1])
                .all(|(p, q)| p.to_bits() == q.to_bits()));
        }
    }

    #[test]
    fn richardson_converges_when_contractive_and_reports_divergence() {
        let n = 20;
        let mut a = matrix(n, 3);
        let b: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let mut x = vec![0.0; n];
        let info = richardson(
            &mut a,
            &mut Identity(n),
            &b,
            &mut x,
            &KrylovParams::default(),
            &mut RichardsonWork::new(n),
        )
        .unwrap();
        assert!(info.iterations < 100);
        let mut r = vec![0.0; n];
        a.apply(&x, &mut r).unwrap();
        assert!(r
            .iter()
            .zip(&b)
            .all(|(p, q)| (p - q).abs() < 1e-8 * q.abs()));
        // 3 A: the iteration matrix I − 3A has spectral radius ≈ 2 → divergence, reported.
        let mut a3 = DenseMatrix::from_row_major(n, a.a.iter().map(|v| 3.0 * v).collect()).unwrap();
        let mut x = vec![0.0; n];
        let err = richardson(
            &mut a3,
            &mut Identity(n),
            &b,
            &mut x,
            &KrylovParams::default(),
            &mut RichardsonWork::new(n),
        )
        .unwrap_err();
        assert!(matches!(err, NumericsError::NoConvergence { .. }), "{err}");
    }

    /// A seeded tridiagonal, diagonally dominant, nonsymmetric operator (any length, no n² storage).
    struct Tridiagonal {
        lower: Vec<f64>,
        diagonal: Vec<f64>,
        upper: Vec<f64>,
    }

    impl Tridiagonal {
        fn new(n: usize, seed: u64) -> Self {
            let mut rng = crate::testkit::Lcg::new(seed);
            let mut v = |base: f64| (0..n).map(|_| base + 0.4 * (rng.unit() - 0.5)).collect();
            Self {
                lower: v(-0.3),
                diagonal: v(1.5),
                upper: v(0.2),
            }
        }
    }

    impl LinearOperator for Tridiagonal {
        fn dim(&self) -> usize {
            self.diagonal.len()
        }
        fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
            let n = x.len();
            for i in 0..n {
                let mut v = self.diagonal[i] * x[i];
                if i > 0 {
                    v += self.lower[i] * x[i - 1];
                }
                if i + 1 < n {
                    v += self.upper[i] * x[i + 1];
                }
                y[i] = v;
            }
            Ok(())
        }
    }

    /// `y = x / d`: the Jacobi preconditioner of a [`Tridiagonal`].
    struct Jacobi(Vec<f64>);

    impl LinearOperator for Jacobi {
        fn dim(&self) -> usize {
            self.0.len()
        }
        fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
            for ((y, x), d) in y.iter_mut().zip(x).zip(&self.0) {
                *y = x / d;
            }
            Ok(())
        }
    }

    /// [`richardson`] on caller-owned work vectors is the iteration as first written — a loop of
    /// `r = b − A x`, `Δx = M⁻¹ r`, `x += Δx`, stopped at `max|Δx| / max|x| < tol`, fresh vectors
    /// per step — bit for bit (the iterate and the count), on seeded systems (tridiagonal,
    /// nonsymmetric, Jacobi-preconditioned; 37 unknowns, and 2 chunks + 5 of the element passes):
    /// with new work vectors, with those of an earlier solve of another system (dirty), and with
    /// vectors of another length (resized).
    #[test]
    fn richardson_on_kept_work_vectors_is_the_plain_loop_bit_for_bit() {
        let plain_loop = |a: &mut Tridiagonal, b: &[f64], x: &mut [f64], tol: f64| -> usize {
            let n = b.len();
            let mut m = Jacobi(a.diagonal.clone());
            for it in 1..=500 {
                let mut r = vec![0.0; n];
                a.apply(x, &mut r).unwrap();
                for (ri, bi) in r.iter_mut().zip(b) {
                    *ri = bi - *ri;
                }
                let mut dx = vec![0.0; n];
                m.apply(&r, &mut dx).unwrap();
                let (mut change, mut size) = (0.0f64, 0.0f64);
                for (xi, d) in x.iter_mut().zip(&dx) {
                    *xi += d;
                    change = change.max(d.abs());
                    size = size.max(xi.abs());
                }
                if change / size < tol {
                    return it;
                }
            }
            panic!("the plain loop did not converge");
        };
        let params = KrylovParams {
            tolerance: 1e-12,
            max_iterations: 500,
            restart: 1,
        };
        let mut work = RichardsonWork::new(3);
        for (n, seed) in [(37usize, 11u64), (37, 12), (2 * RICHARDSON_CHUNK + 5, 13)] {
            let mut a = Tridiagonal::new(n, seed);
            let b = crate::testkit::lcg(seed + 100, n);
            let start = crate::testkit::lcg(seed + 200, n);
            let mut control = start.clone();
            let k = plain_loop(&mut a, &b, &mut control, params.tolerance);
            assert!(k > 5, "{k} steps");
            for fresh in [false, true] {
                let mut x = start.clone();
                let mut own = RichardsonWork::new(n);
                let w = if fresh { &mut own } else { &mut work };
                let mut m = Jacobi(a.diagonal.clone());
                let info = richardson(&mut a, &mut m, &b, &mut x, &params, w).unwrap();
                assert_eq!(info.iterations, k);
                assert!(x
                    .iter()
                    .zip(&control)
                    .all(|(p, q)| p.to_bits() == q.to_bits()));
            }
            assert_eq!(work.len(), n);
        }
    }

    /// Block Jacobi with Anderson mixing ([`richardson_mixed`]) against the plain iteration (the
    /// naive control) on `A = I − 0.45 (S + Sᵀ)` (`S` the shift; Jacobi rate ≈ 0.9): the same
    /// solution to the stopping error, in fewer applications; a second right-hand side solved
    /// with the first solve's history kept needs fewer applications than with a fresh history
    /// (the differences do not depend on `b`); without mixing it is `richardson` bit for bit.
    #[test]
    fn anderson_mixed_richardson_recycles_its_history_across_right_hand_sides() {
        let n = 40;
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            a[i * n + i] = 1.0;
            if i + 1 < n {
                a[i * n + i + 1] = -0.45;
                a[(i + 1) * n + i] = -0.45;
            }
        }
        let mut a = DenseMatrix::from_row_major(n, a).unwrap();
        let params = KrylovParams {
            tolerance: 1e-11,
            max_iterations: 5000,
            restart: 1,
        };
        let solve = |a: &mut DenseMatrix, b: &[f64], recycle: Option<&mut RichardsonRecycle>| {
            let mut x = vec![0.0; n];
            let info = richardson_mixed(a, &mut Identity(n), b, &mut x, &params, recycle).unwrap();
            (x, info.iterations)
        };
        let b1: Vec<f64> = (0..n).map(|i| 1.0 + (0.3 * i as f64).sin()).collect();
        let b2: Vec<f64> = (0..n).map(|i| (0.2 * i as f64).cos() - 0.5).collect();
        let (plain1, k_plain1) = solve(&mut a, &b1, None);
        let mut control = vec![0.0; n];
        richardson(
            &mut a,
            &mut Identity(n),
            &b1,
            &mut control,
            &params,
            &mut RichardsonWork::default(),
        )
        .unwrap();
        assert!(plain1
            .iter()
            .zip(&control)
            .all(|(p, q)| p.to_bits() == q.to_bits()));
        let (plain2, _) = solve(&mut a, &b2, None);
        let mut acc = RichardsonRecycle::new(n, 6);
        let (mixed1, k_mixed1) = solve(&mut a, &b1, Some(&mut acc));
        let (mixed2, k_recycled) = solve(&mut a, &b2, Some(&mut acc));
        let (fresh2, k_fresh) = solve(&mut a, &b2, Some(&mut RichardsonRecycle::new(n, 6)));
        // Warm-started from the last result, a new right-hand side's first step is free: a
        // b close to the last one converges in fewer applications than from the same start
        // with the history forgotten (observed 40 against 43).
        let b3: Vec<f64> = b2.iter().map(|v| v * (1.0 + 1e-4)).collect();
        let mut x3 = mixed2.clone();
        let warm = richardson_mixed(
            &mut a,
            &mut Identity(n),
            &b3,
            &mut x3,
            &params,
            Some(&mut acc),
        )
        .unwrap()
        .iterations;
        acc.forget();
        let mut x3_cold = mixed2.clone();
        let cold = richardson_mixed(
            &mut a,
            &mut Identity(n),
            &b3,
            &mut x3_cold,
            &params,
            Some(&mut acc),
        )
        .unwrap()
        .iterations;
        assert!(warm < cold, "{warm} against {cold}");
        let (plain3, _) = solve(&mut a, &b3, None);
        let err = x3
            .iter()
            .zip(&plain3)
            .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
        assert!(
            err < 1e-8 * plain3.iter().fold(0.0f64, |m, v| m.max(v.abs())),
            "{err:e}"
        );
        let scale = plain1.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (x, y) in [(&mixed1, &plain1), (&mixed2, &plain2), (&fresh2, &plain2)] {
            let err = x
                .iter()
                .zip(y)
                .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
            // The stop leaves an error of about rate/(1 − rate) × tolerance ≈ 1e-10 relative.
            assert!(err < 1e-8 * scale, "{err:e}");
        }
        // Observed: 212 applications plain, 76 mixed; on the second right-hand side 80 with a
        // fresh history, 64 with the first solve's.
        assert!(2 * k_mixed1 < k_plain1, "{k_mixed1} against {k_plain1}");
        assert!(k_recycled < k_fresh, "{k_recycled} against {k_fresh}");
    }

    /// A start declared with its image ([`RichardsonRecycle::set_known_start`]) is the solve
    /// that applies `A` to it, bit for bit, with one application fewer; the kept last iterate's
    /// image ([`RichardsonRecycle::last_iterate_image`]) is `A x_J` to the rounding of the kept
    /// residual; with the history forgotten none is kept.
    #[test]
    fn a_start_with_its_image_saves_the_first_application_bit_for_bit() {
        let n = 37;
        let mut a = Tridiagonal::new(n, 11);
        let mut pre = Jacobi(a.diagonal.clone());
        let params = KrylovParams {
            tolerance: 1e-10,
            max_iterations: 500,
            restart: 1,
        };
        let b: Vec<f64> = (0..n).map(|i| 1.0 + (0.7 * i as f64).sin()).collect();
        let x0: Vec<f64> = (0..n).map(|i| 0.1 * (0.3 * i as f64).cos()).collect();
        // A first solve makes a history; both runs below start from it.
        let mut made = RichardsonRecycle::new(n, 4);
        let mut x = vec![0.0; n];
        richardson_mixed(&mut a, &mut pre, &b, &mut x, &params, Some(&mut made)).unwrap();
        let (mut iterate, mut image) = (vec![0.0; n], vec![0.0; n]);
        assert!(made.last_iterate_image(&mut iterate, &mut image).unwrap());
        let mut direct = vec![0.0; n];
        a.apply(&iterate, &mut direct).unwrap();
        let scale = direct.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (p, q) in image.iter().zip(&direct) {
            assert!((p - q).abs() <= 1e-13 * scale, "{p} {q}");
        }
        let b2: Vec<f64> = b.iter().map(|v| 0.9 * v + 0.01).collect();
        let mut applied = made.clone();
        applied.forget();
        let mut declared = applied.clone();
        assert!(!declared
            .last_iterate_image(&mut iterate, &mut image)
            .unwrap());
        let mut x_applied = x0.clone();
        let k_applied = richardson_mixed(
            &mut a,
            &mut pre,
            &b2,
            &mut x_applied,
            &params,
            Some(&mut applied),
        )
        .unwrap()
        .iterations;
        let mut ax0 = vec![0.0; n];
        a.apply(&x0, &mut ax0).unwrap();
        declared.set_known_start(&x0, &ax0).unwrap();
        let mut x_declared = x0.clone();
        let k_declared = richardson_mixed(
            &mut a,
            &mut pre,
            &b2,
            &mut x_declared,
            &params,
            Some(&mut declared),
        )
        .unwrap()
        .iterations;
        assert_eq!(k_declared + 1, k_applied);
        assert!(x_declared
            .iter()
            .zip(&x_applied)
            .all(|(p, q)| p.to_bits() == q.to_bits()));
        // Wrong lengths are refused.
        assert!(declared.set_known_start(&x0[1..], &ax0).is_err());
    }

    /// A system that is the identity beyond its first `d` unknowns, with `b` and the warm start
    /// vanishing there, solved on those `d` by a `Gmres` sized for more (after a full-size solve
    /// left its work arrays dirty) gives the full solve's iterates bit for bit; an operator
    /// larger than the work arrays is refused.
    #[test]
    fn gmres_on_a_leading_block_matches_the_full_solve_bit_for_bit() {
        let (n, d) = (40, 23);
        let block = matrix(d, 5);
        let mut full = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                full[i * n + j] = if i < d && j < d {
                    block.a[i * d + j]
                } else if i == j {
                    1.0
                } else {
                    0.0
                };
            }
        }
        let mut full = DenseMatrix::from_row_major(n, full).unwrap();
        let mut block = block;
        let mut b = vec![0.0; n];
        for (i, v) in b.iter_mut().enumerate().take(d) {
            *v = (i as f64 * 0.3).sin() + 0.5;
        }
        let params = KrylovParams {
            tolerance: 1e-11,
            restart: 7,
            ..Default::default()
        };
        let mut gmres = Gmres::new(n, 7);
        let mut x_full = vec![0.0; n];
        let info_full = gmres
            .solve(&mut full, &mut Identity(n), &b, &mut x_full, &params)
            .unwrap();
        let mut x_block = vec![0.0; d];
        let info_block = gmres
            .solve(&mut block, &mut Identity(d), &b[..d], &mut x_block, &params)
            .unwrap();
        assert_eq!(info_full, info_block);
        assert!(x_full[d..].iter().all(|&v| v == 0.0));
        for (p, q) in x_full.iter().zip(&x_block) {
            assert_eq!(p.to_bits(), q.to_bits());
        }
        let mut big = matrix(n + 1, 3);
        let mut x = vec![0.0; n + 1];
        assert!(gmres
            .solve(&mut big, &mut Identity(n + 1), &[1.0; 41], &mut x, &params)
            .is_err());
    }

    #[test]
    fn bad_parameters_are_errors() {
        let mut a = matrix(4, 1);
        let mut x = vec![0.0; 4];
        let p = KrylovParams {
            max_iterations: 0,
            ..Default::default()
        };
        assert!(Gmres::new(4, 2)
            .solve(&mut a, &mut Identity(4), &[1.0; 4], &mut x, &p)
            .is_err());
        assert!(Gmres::new(4, 2)
            .solve(
                &mut a,
                &mut Identity(4),
                &[1.0; 3],
                &mut x,
                &KrylovParams::default()
            )
            .is_err());
    }
}
