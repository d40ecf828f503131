//! Iterative solvers of `A x = b` on a [`LinearOperator`]:
//!
//! * [`Gmres`]: restarted GMRES(m) (Saad & Schultz 1986) with **right** preconditioning
//!   `A M⁻¹ y = b, x = M⁻¹ y`, modified Gram–Schmidt Arnoldi, Givens rotations for the Hessenberg
//!   least-squares problem (so the residual `‖b − A x‖` is known at every iteration without forming
//!   `x`). Stops when `‖b − A x‖ / ‖b‖ < tol`.
//! * [`richardson`]: the preconditioned Richardson iteration `x ← x + M⁻¹ (b − A x)`. With the block
//!   matrix of the exact self term as `M` this is the block-Jacobi scheme of the equivalent inclusion
//!   method (docs/theory-sam.md#solving-the-eim-equations). Stops when `max|Δx| / max|x| < tol`; stops with an error, not a
//!   hang, when the iteration diverges.
//!
//! Both take a warm start in `x`, never print, and return what they did ([`KrylovInfo`]) or
//! [`NumericsError::NoConvergence`].

use crate::linop::LinearOperator;
use crate::NumericsError;

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
    r: Vec<f64>,
    /// Whether a cycle whose residual estimate fell below the tolerance is confirmed by the true
    /// residual `b − A x` (one more product) before returning (default true).
    confirm: bool,
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
            r: vec![0.0; n],
            confirm: true,
        }
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
        loop {
            // r = b − A x.
            let r = &mut self.r[..n];
            a.apply(x, r)?;
            for (ri, bi) in r.iter_mut().zip(b) {
                *ri = bi - *ri;
            }
            let beta = norm(r);
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
            for (v, r) in self.v[0][..n].iter_mut().zip(&self.r[..n]) {
                *v = r / beta;
            }
            self.g.fill(0.0);
            self.g[0] = beta;
            let mut k = 0;
            while k < m && iterations < params.max_iterations {
                iterations += 1;
                // w = A M⁻¹ v_k.
                precond.apply(&self.v[k][..n], &mut self.z[..n])?;
                a.apply(&self.z[..n], &mut self.w[..n])?;
                // Modified Gram–Schmidt.
                for i in 0..=k {
                    let hik = dot(&self.w[..n], &self.v[i][..n]);
                    self.h[k * (m + 1) + i] = hik;
                    for (w, v) in self.w[..n].iter_mut().zip(&self.v[i][..n]) {
                        *w -= hik * v;
                    }
                }
                let hk1 = norm(&self.w[..n]);
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
                for i in 0..k {
                    let (c, s) = (self.cs[i], self.sn[i]);
                    let (a0, a1) = (col[i], col[i + 1]);
                    col[i] = c * a0 + s * a1;
                    col[i + 1] = -s * a0 + c * a1;
                }
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
            // y = H⁻¹ g (upper triangular k × k), x += M⁻¹ V y.
            for i in (0..k).rev() {
                let mut s = self.g[i];
                for j in i + 1..k {
                    s -= self.h[j * (m + 1) + i] * self.y[j];
                }
                let d = self.h[i * (m + 1) + i];
                self.y[i] = if d != 0.0 { s / d } else { 0.0 };
            }
            self.w[..n].fill(0.0);
            for j in 0..k {
                let yj = self.y[j];
                for (w, v) in self.w[..n].iter_mut().zip(&self.v[j][..n]) {
                    *w += yj * v;
                }
            }
            precond.apply(&self.w[..n], &mut self.z[..n])?;
            for (xi, zi) in x.iter_mut().zip(&self.z[..n]) {
                *xi += zi;
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
}

/// Preconditioned Richardson iteration `x ← x + M⁻¹(b − A x)` (block Jacobi when `M` is the
/// block diagonal), warm-started from `x`. Stops when `max|Δx| / max|x| < tol`; a step `max|Δx|` that
/// grows a thousandfold over its smallest value, or a non-finite iterate, is reported as divergence
/// ([`NumericsError::NoConvergence`]).
pub fn richardson(
    a: &mut dyn LinearOperator,
    precond: &mut dyn LinearOperator,
    b: &[f64],
    x: &mut [f64],
    params: &KrylovParams,
) -> Result<KrylovInfo, NumericsError> {
    params.validate()?;
    let n = a.dim();
    crate::linop::check_lengths(n, b, x)?;
    let mut r = vec![0.0; n];
    let mut dx = vec![0.0; n];
    let mut best = f64::INFINITY;
    for it in 1..=params.max_iterations {
        a.apply(x, &mut r)?;
        for (ri, bi) in r.iter_mut().zip(b) {
            *ri = bi - *ri;
        }
        precond.apply(&r, &mut dx)?;
        let mut change: f64 = 0.0;
        let mut size: f64 = 0.0;
        let mut finite = true;
        for (xi, d) in x.iter_mut().zip(&dx) {
            *xi += d;
            finite &= xi.is_finite();
            change = change.max(d.abs());
            size = size.max(xi.abs());
        }
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
            return Ok(KrylovInfo {
                iterations: it,
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

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
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
        )
        .unwrap_err();
        assert!(matches!(err, NumericsError::NoConvergence { .. }), "{err}");
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
