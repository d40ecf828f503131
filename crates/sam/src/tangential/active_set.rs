//! The primal active-set (inexact semismooth Newton) method of the tangential solve (module docs of
//! [`super`]): `|k|`-preconditioned CG on the free part of the stick and rim cells, set updates
//! between rounds; FISTA (in [`super::TangentialSolver::solve`]) is its fallback.

use halfspace_numerics::circulant::Circulant2d;
use halfspace_numerics::op::{GridOperator, OperatorSet};

use super::{
    is_stick, kkt_residual, TangentialInfo, TangentialParams, TangentialSolver, ACTIVE_SET_ROUNDS,
    INNER_REDUCTION, STIFF_RIM,
};
use crate::SamError;

impl<S: OperatorSet> TangentialSolver<S> {
    /// `v ← M v`: the free part of a field under the current sets — both components on stick
    /// cells, only the rotation `v − (v·e) e` on rim (slip) cells of unit shear direction `e`
    /// (kept in `q_old`), nothing outside the contact.
    fn mask(
        stick: &[bool],
        bound: &[f64],
        e: &[Vec<f64>; 2],
        lambda: &[f64],
        stiff: f64,
        v: &mut [Vec<f64>; 2],
    ) {
        for k in 0..stick.len() {
            if stick[k] {
                continue;
            }
            if bound[k] <= 0.0 || lambda[k] > stiff {
                v[0][k] = 0.0;
                v[1][k] = 0.0;
                continue;
            }
            let along = v[0][k] * e[0][k] + v[1][k] * e[1][k];
            v[0][k] -= along * e[0][k];
            v[1][k] -= along * e[1][k];
        }
    }

    fn precondition(&mut self, bound: &[f64]) -> Result<(), SamError> {
        let stiff = STIFF_RIM * self.self_term;
        Self::mask(
            &self.stick,
            bound,
            &self.q_old,
            &self.s[0],
            stiff,
            &mut self.y,
        );
        let pre = self.preconditioner.as_mut().expect("built by active_set");
        for a in 0..2 {
            pre.apply(&self.y[a], &mut self.z[a])?;
        }
        Self::mask(
            &self.stick,
            bound,
            &self.q_old,
            &self.s[0],
            stiff,
            &mut self.z,
        );
        Ok(())
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
        for _round in 0..ACTIVE_SET_ROUNDS {
            // Inner: PCG for S = 0 on the free part (stick cells, and the rotation of the rim cells
            // with λ ≤ STIFF_RIM·T(0)), the other rim cells fixed.
            self.slip_of(b, [&*q0, &*q1], [&mut *s0, &mut *s1])?;
            products += 1;
            let kkt = kkt_residual(bound, q0, q1, s0, s1).0 / b_scale;
            let inner_tol = (INNER_REDUCTION * kkt).max(0.1 * params.kkt_tolerance) * b_scale;
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
            self.precondition(bound)?;
            let mut rho = 0.0;
            for a in 0..2 {
                for k in 0..n {
                    self.dir[a][k] = self.z[a][k];
                    rho += self.y[a][k] * self.z[a][k];
                }
            }
            let residual_max =
                |y: &[Vec<f64>; 2]| y[0].iter().chain(&y[1]).fold(0.0f64, |m, v| m.max(v.abs()));
            while rho > 0.0 && residual_max(&self.y) > inner_tol {
                products += 1;
                if products > params.max_iterations {
                    return Ok(Err(products));
                }
                {
                    let [t0, t1] = &mut self.t_dir;
                    self.op
                        .apply(&[&self.dir[0], &self.dir[1]], &mut [t0, t1])?;
                }
                let mut den = 0.0;
                for a in 0..2 {
                    for k in 0..n {
                        self.t_dir[a][k] += self.s[0][k] * self.dir[a][k];
                        den += self.dir[a][k] * self.t_dir[a][k];
                    }
                }
                if den <= 0.0 {
                    break;
                }
                let alpha = rho / den;
                for k in 0..n {
                    q0[k] += alpha * self.dir[0][k];
                    q1[k] += alpha * self.dir[1][k];
                    self.y[0][k] -= alpha * self.t_dir[0][k];
                    self.y[1][k] -= alpha * self.t_dir[1][k];
                }
                self.precondition(bound)?;
                let mut rho_new = 0.0;
                for a in 0..2 {
                    for k in 0..n {
                        rho_new += self.y[a][k] * self.z[a][k];
                    }
                }
                let beta = rho_new / rho;
                rho = rho_new;
                for a in 0..2 {
                    for k in 0..n {
                        self.dir[a][k] = self.z[a][k] + beta * self.dir[a][k];
                    }
                }
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
                        q0[k] = g * s0[k] / sm;
                        q1[k] = g * s1[k] / sm;
                    }
                }
            }
            if !changed && kkt_now / b_scale < params.kkt_tolerance {
                self.slip_of(b, [&*q0, &*q1], [&mut *s0, &mut *s1])?;
                products += 1;
                let (kkt, stick, slipping) = kkt_residual(bound, q0, q1, s0, s1);
                let kkt = kkt / b_scale;
                if kkt < params.kkt_tolerance {
                    return Ok(Ok(TangentialInfo {
                        iterations: products,
                        residual: 0.0,
                        kkt,
                        stick_cells: stick,
                        slip_cells: slipping,
                    }));
                }
            }
        }
        Ok(Err(products))
    }
}
