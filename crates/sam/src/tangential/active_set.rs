//! The primal active-set (inexact semismooth Newton) method of the tangential solve (module docs of
//! [`super`]): `|k|`-preconditioned CG on the free part of the stick and rim cells, set updates
//! between rounds; FISTA (in [`super::TangentialSolver::solve`]) is its fallback.

use std::ops::Range;

use halfspace_numerics::circulant::Circulant2d;
use halfspace_numerics::op::{GridOperator, OperatorSet};

use super::{
    is_stick, kkt_residual, TangentialInfo, TangentialParams, TangentialSolver, ACTIVE_SET_ROUNDS,
    FINAL_REDUCTION, INNER_REDUCTION, STIFF_RIM,
};
use crate::normal::passes::{Chunks, PARALLEL_PASS_CELLS};
use crate::SamError;

/// `v ← M v` on the cells `r` (`v0`, `v1` the chunk's slices): the free part of a field under the
/// current sets — both components on stick cells, only the rotation `v − (v·e) e` on rim (slip)
/// cells of unit shear direction `e` (kept in `q_old`), nothing outside the contact or on stiff
/// rim cells (`λ > stiff`).
#[allow(clippy::too_many_arguments)]
fn mask(
    stick: &[bool],
    bound: &[f64],
    e: &[Vec<f64>; 2],
    lambda: &[f64],
    stiff: f64,
    r: Range<usize>,
    v0: &mut [f64],
    v1: &mut [f64],
) {
    for (i, k) in r.enumerate() {
        if stick[k] {
            continue;
        }
        if bound[k] <= 0.0 || lambda[k] > stiff {
            v0[i] = 0.0;
            v1[i] = 0.0;
            continue;
        }
        let along = v0[i] * e[0][k] + v1[i] * e[1][k];
        v0[i] -= along * e[0][k];
        v1[i] -= along * e[1][k];
    }
}

/// The active set's passes over the grid: below [`PARALLEL_PASS_CELLS`] one pass over the whole
/// grid (the sums in the order of a plain loop), from it fixed chunks on rayon's threads whose
/// partial sums are added in chunk order ([`Chunks`]): either way the bits do not depend on the
/// number of threads.
#[derive(Clone, Copy)]
pub(super) struct Passes {
    chunks: Chunks,
    whole: bool,
    n: usize,
}

impl Passes {
    pub(super) fn new(n: usize) -> Self {
        Self {
            chunks: Chunks::new(n),
            whole: n < PARALLEL_PASS_CELLS,
            n,
        }
    }

    /// `Σ_c body(range_c, fields_c)` (chunk order; `out`: one slot per chunk).
    fn sum<const M: usize>(
        &self,
        out: &mut [f64],
        fields: [&mut [f64]; M],
        body: impl Fn(Range<usize>, [&mut [f64]; M]) -> f64 + Sync,
    ) -> f64 {
        if self.whole {
            body(0..self.n, fields)
        } else {
            self.chunks.run(out, fields, body);
            out.iter().sum()
        }
    }

    /// `max_c body(range_c, fields_c)` (exact in any order).
    fn max<const M: usize>(
        &self,
        out: &mut [f64],
        fields: [&mut [f64]; M],
        body: impl Fn(Range<usize>, [&mut [f64]; M]) -> f64 + Sync,
    ) -> f64 {
        if self.whole {
            body(0..self.n, fields)
        } else {
            self.chunks.run(out, fields, body);
            out.iter().fold(0.0f64, |m, v| m.max(*v))
        }
    }
}

impl<S: OperatorSet> TangentialSolver<S> {
    /// `y ← M y`, `z = M P M y` (the preconditioned residual, `P` the `|k|` circulant); returns
    /// `ρ = y·z` and `max |y|`;
    /// the masks and the sum in the passes of `passes` (the same bits on one or
    /// more threads).
    fn precondition(&mut self, bound: &[f64], passes: Passes) -> Result<(f64, f64), SamError> {
        let stiff = STIFF_RIM * self.self_term;
        let (stick, e, lambda) = (&self.stick, &self.q_old, &self.s[0]);
        let y_max = {
            let [y0, y1] = &mut self.y;
            passes.max(&mut self.sums, [y0, y1], |r, [v0, v1]| {
                mask(stick, bound, e, lambda, stiff, r, v0, v1);
                v0.iter().chain(&*v1).fold(0.0f64, |m, v| m.max(v.abs()))
            })
        };
        let pre = self.preconditioner.as_mut().expect("built by active_set");
        for a in 0..2 {
            pre.apply(&self.y[a], &mut self.z[a])?;
        }
        let y = &self.y;
        let [z0, z1] = &mut self.z;
        let rho = passes.sum(&mut self.sums, [z0, z1], |r, [z0, z1]| {
            let (y0, y1) = (&y[0][r.clone()], &y[1][r.clone()]);
            mask(stick, bound, e, lambda, stiff, r, z0, z1);
            // Component by component, as the plain loop sums.
            let mut rho = 0.0;
            for (y, z) in [(y0, &*z0), (y1, &*z1)] {
                for i in 0..z.len() {
                    rho += y[i] * z[i];
                }
            }
            rho
        });
        Ok((rho, y_max))
    }

    /// The primal active-set method (module docs). `Ok(Ok(info))` when converged;
    /// `Ok(Err(iterations))` when the rounds ran out (`q` is then a warm start for FISTA).
    #[allow(clippy::type_complexity)]
    pub(super) fn active_set(
        &mut self,
        bound: &[f64],
        b: [&[f64]; 2],
        q: [&mut [f64]; 2],
        slip: [&mut [f64]; 2],
        params: &TangentialParams,
        b_scale: f64,
    ) -> Result<Result<TangentialInfo, usize>, SamError> {
        let n = self.grid.len();
        let passes = Passes::new(n);
        let [q0, q1] = q;
        let [s0, s1] = slip;
        if self.preconditioner.is_none() {
            let (d1, d2) = (2.0 * self.grid.half1, 2.0 * self.grid.half2);
            self.preconditioner = Some(Circulant2d::inverse_half_space_on(
                self.periodic.clone(),
                d1,
                d2,
            )?);
        }
        // Initial sets from the (projected) warm start.
        for k in 0..n {
            self.stick[k] = is_stick(bound[k], q0[k], q1[k]);
        }
        // Block products T·x made (one per CG iteration, one per slip evaluation).
        let mut products = 0;
        // Whether `s` holds the slip `b − Tq` of the current `q` (bit for bit: a product of the
        // same `q` would give the same bits), so that no product is spent to recompute it.
        let mut slip_current = false;
        // Whether the last round's set update changed no cell.
        let mut settled = false;
        for round in 0..ACTIVE_SET_ROUNDS {
            // Inner: PCG for S = 0 on the free part (stick cells, and the rotation of the rim cells
            // with λ ≤ STIFF_RIM·T(0)), the other rim cells fixed.
            if !slip_current {
                self.slip_of(b, [&*q0, &*q1], [&mut *s0, &mut *s1])?;
                products += 1;
            }
            let (kkt, stick, slipping) = kkt_residual(bound, q0, q1, s0, s1);
            let kkt = kkt / b_scale;
            // A warm start that already meets the stopping rule, with no rim cell whose slip
            // opposes its shear (the set update would release it): done, on one product.
            if round == 0
                && params.warm_start
                && kkt < params.kkt_tolerance
                && !(0..n).any(|k| {
                    !self.stick[k] && bound[k] > 0.0 && s0[k] * q0[k] + s1[k] * q1[k] < 0.0
                })
            {
                return Ok(Ok(kkt_met(products, kkt, stick, slipping)));
            }
            // Inexact Newton: while the sets move, a round reduces the free part's slip to
            // INNER_REDUCTION of the KKT residual; once a round left them unchanged, the inner
            // solve aims at the stopping rule itself (FINAL_REDUCTION of the KKT tolerance: the
            // Newton system is then the final one but for the rim's rotation).
            let reduction = if settled && params.warm_start {
                FINAL_REDUCTION * params.kkt_tolerance
            } else {
                INNER_REDUCTION * kkt
            };
            let inner_tol = reduction.max(0.1 * params.kkt_tolerance) * b_scale;
            for a in 0..2 {
                let sa = if a == 0 { &*s0 } else { &*s1 };
                self.y[a].copy_from_slice(sa);
            }
            // Rim directions e and the multipliers λ = (S·e)₊/g of |q| = g: the Newton system of
            // the rim rotation is (T_tt + λ) δ_t (linearised S − λ q = 0 along the tangent).
            for k in 0..n {
                let m = q0[k].hypot(q1[k]);
                let (e0, e1) = if m > 0.0 {
                    (q0[k] / m, q1[k] / m)
                } else {
                    (0.0, 0.0)
                };
                self.q_old[0][k] = e0;
                self.q_old[1][k] = e1;
                self.s[0][k] = if !self.stick[k] && bound[k] > 0.0 {
                    (s0[k] * e0 + s1[k] * e1).max(0.0) / bound[k]
                } else {
                    0.0
                };
            }
            // `max |M y|`: the residual on the free part.
            let (mut rho, mut residual_max) = self.precondition(bound, passes)?;
            self.dir[0].copy_from_slice(&self.z[0]);
            self.dir[1].copy_from_slice(&self.z[1]);
            // The CG passes in fixed chunks on rayon's threads (crate::normal::passes: the same
            // bits on one or more threads; docs/performance.md, "The contact solves on two
            // threads").
            while rho > 0.0 && residual_max > inner_tol {
                products += 1;
                if products > params.max_iterations {
                    return Ok(Err(products));
                }
                {
                    let [t0, t1] = &mut self.t_dir;
                    self.op
                        .apply(&[&self.dir[0], &self.dir[1]], &mut [t0, t1])?;
                }
                // (T + Λ) d and d·(T + Λ) d.
                let den = {
                    let (lambda, dir) = (&self.s[0], &self.dir);
                    let [t0, t1] = &mut self.t_dir;
                    passes.sum(&mut self.sums, [t0, t1], |r, [t0, t1]| {
                        let l = &lambda[r.clone()];
                        let (d0, d1) = (&dir[0][r.clone()], &dir[1][r]);
                        let mut den = 0.0;
                        for (t, d) in [(t0, d0), (t1, d1)] {
                            for i in 0..t.len() {
                                t[i] += l[i] * d[i];
                                den += d[i] * t[i];
                            }
                        }
                        den
                    })
                };
                if den <= 0.0 {
                    break;
                }
                let alpha = rho / den;
                {
                    let (dir, t_dir) = (&self.dir, &self.t_dir);
                    let [y0, y1] = &mut self.y;
                    passes.max(
                        &mut self.sums,
                        [&mut *q0, &mut *q1, y0, y1],
                        |r, [q0, q1, y0, y1]| {
                            let (d0, d1) = (&dir[0][r.clone()], &dir[1][r.clone()]);
                            let (t0, t1) = (&t_dir[0][r.clone()], &t_dir[1][r]);
                            for i in 0..q0.len() {
                                q0[i] += alpha * d0[i];
                                q1[i] += alpha * d1[i];
                                y0[i] -= alpha * t0[i];
                                y1[i] -= alpha * t1[i];
                            }
                            0.0
                        },
                    );
                }
                let (rho_new, y_max) = self.precondition(bound, passes)?;
                residual_max = y_max;
                let beta = rho_new / rho;
                rho = rho_new;
                let z = &self.z;
                let [d0, d1] = &mut self.dir;
                passes.max(&mut self.sums, [d0, d1], |r, [d0, d1]| {
                    let (z0, z1) = (&z[0][r.clone()], &z[1][r]);
                    for i in 0..d0.len() {
                        d0[i] = z0[i] + beta * d0[i];
                        d1[i] = z1[i] + beta * d1[i];
                    }
                    0.0
                });
            }
            // Rim cells moved along their tangent: back onto the circle.
            for k in 0..n {
                if !self.stick[k] && bound[k] > 0.0 {
                    let m = q0[k].hypot(q1[k]);
                    if m > 0.0 {
                        q0[k] *= bound[k] / m;
                        q1[k] *= bound[k] / m;
                    }
                }
            }
            // Outer: the slip of the new shear, then the sets.
            self.slip_of(b, [&*q0, &*q1], [&mut *s0, &mut *s1])?;
            products += 1;
            slip_current = true;
            let (kkt_now, _, _) = kkt_residual(bound, q0, q1, s0, s1);
            let mut changed = false;
            // Stick cells beyond their disc join the slip set first; slip cells are released
            // only in a round where none did (releasing and capturing in the same round cycles).
            let any_beyond =
                (0..n).any(|k| self.stick[k] && bound[k] > 0.0 && q0[k].hypot(q1[k]) > bound[k]);
            for k in 0..n {
                let g = bound[k];
                if g <= 0.0 {
                    continue;
                }
                let m = (q0[k] * q0[k] + q1[k] * q1[k]).sqrt();
                if self.stick[k] {
                    if m > g {
                        // Beyond the disc: slips, in the direction of its shear.
                        q0[k] *= g / m;
                        q1[k] *= g / m;
                        self.stick[k] = false;
                        changed = true;
                        slip_current = false;
                    }
                } else {
                    let along = s0[k] * q0[k] + s1[k] * q1[k];
                    let sm = (s0[k] * s0[k] + s1[k] * s1[k]).sqrt();
                    if along < 0.0 && !any_beyond {
                        // The slip opposes the shear: the cell sticks again.
                        self.stick[k] = true;
                        changed = true;
                    } else if sm > 0.0 && self.s[0][k] > STIFF_RIM * self.self_term {
                        // Rim cells held fixed in the inner solve turn to their slip.
                        let (t0, t1) = (g * s0[k] / sm, g * s1[k] / sm);
                        if t0.to_bits() != q0[k].to_bits() || t1.to_bits() != q1[k].to_bits() {
                            slip_current = false;
                        }
                        q0[k] = t0;
                        q1[k] = t1;
                    }
                }
            }
            settled = !changed;
            if !changed && kkt_now / b_scale < params.kkt_tolerance {
                if !slip_current {
                    self.slip_of(b, [&*q0, &*q1], [&mut *s0, &mut *s1])?;
                    products += 1;
                    slip_current = true;
                }
                let (kkt, stick, slipping) = kkt_residual(bound, q0, q1, s0, s1);
                let kkt = kkt / b_scale;
                if kkt < params.kkt_tolerance {
                    return Ok(Ok(kkt_met(products, kkt, stick, slipping)));
                }
            }
        }
        Ok(Err(products))
    }
}

/// The active set's result when the KKT residual `kkt` (relative) meets its tolerance after
/// `products` block products: `stick` and `slipping` cells as [`kkt_residual`] counted them.
fn kkt_met(products: usize, kkt: f64, stick: usize, slipping: usize) -> TangentialInfo {
    TangentialInfo {
        iterations: products,
        residual: 0.0,
        kkt,
        stick_cells: stick,
        slip_cells: slipping,
    }
}
