//! The tangential MDR constant of power-law graded media, `c_T(k, ν)` (docs/fretting-wear.md,
//! "Graded media", derived there).
//!
//! A surface traction `e^{iξ·x}` on the half-space `G(z) = G₀ (z/z₀)^k`, `ν` constant, gives surface
//! displacements `z₀^k ξ^{k−1}/G₀` times the dimensionless compliances
//!
//! * `m_zz` (normal → normal) and `m_LL` (tangential along `ξ` → along `ξ`), `m_Lz` (coupling): the
//!   P–SV part, two decaying solutions of a fourth-order ODE system in `z`, integrated here;
//! * `m_TT` (tangential across `ξ`): the SH part, `(z^k u')' = z^k u` with `u = z^ν K_ν(z)`,
//!   `ν = (1−k)/2`: `m_TT = 2^{−k} Γ((1−k)/2) / Γ((1+k)/2)`.
//!
//! Both point-force Green's functions decay as `r^{−(1+k)}` (the inverse transform of `ξ^{k−1}`), so
//! the MDR's Winkler constants are in the ratio of the compliances that the axisymmetric problems
//! see: the normal `m_zz`, the tangential the angular mean `(m_LL + m_TT)/2` (a unidirectional
//! traction `∝ (a² − r²)^{(k−1)/2}` displaces a circle uniformly, as at `k = 0`):
//! `c_T / c_N = 2 m_zz / (m_LL + m_TT)`; at `k = 0` this is `G*/E* = 2(1−ν)/(2−ν)`.

use std::f64::consts::PI;

use halfspace_numerics::special::gamma;

use crate::error::MdrError;
use crate::material::check_poisson;

/// The dimensionless surface compliances of the graded half-space (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GradedCompliances {
    /// Normal displacement per normal traction, `m_zz` (`1 − ν` homogeneous).
    pub normal: f64,
    /// Tangential displacement along `ξ` per tangential traction along `ξ`, `m_LL` (`1 − ν`).
    pub longitudinal: f64,
    /// Tangential displacement across `ξ` per traction across `ξ`, `m_TT` (1).
    pub transverse: f64,
    /// Tangential displacement per normal traction, `m_Lz` (`(1 − 2ν)/2`).
    pub coupling: f64,
    /// Normal displacement per tangential traction, `m_zL` (= `m_Lz` by reciprocity; kept as a
    /// check of the integration).
    pub coupling_reciprocal: f64,
}

impl GradedCompliances {
    /// The compliances for `k ∈ (−1, 1)`, `ν ∈ (−1, 1/2]` (P–SV part by a Dormand–Prince 5(4)
    /// integration from depth `40/ξ` to the surface, relative tolerance 1e-15; agrees with the
    /// closed-form `m_zz` to 1e-10).
    pub fn new(k: f64, nu: f64) -> Result<Self, MdrError> {
        check_exponent(k)?;
        check_poisson(nu)?;
        let (u_t, w_t, u_n, w_n) = psv_surface_response(k, nu);
        Ok(Self {
            normal: -w_n,
            longitudinal: -u_t,
            transverse: transverse_compliance(k),
            coupling: -u_n,
            coupling_reciprocal: -w_t,
        })
    }

    /// `c_T / c_N = 2 m_zz / (m_LL + m_TT)`.
    pub fn tangential_ratio(&self) -> f64 {
        2.0 * self.normal / (self.longitudinal + self.transverse)
    }
}

/// `c_T / c_N` of the power-law graded medium (module doc); `2(1−ν)/(2−ν)` at `k = 0` (exactly).
pub fn tangential_constant_ratio(k: f64, nu: f64) -> Result<f64, MdrError> {
    if k == 0.0 {
        check_poisson(nu)?;
        return Ok(2.0 * (1.0 - nu) / (2.0 - nu));
    }
    Ok(GradedCompliances::new(k, nu)?.tangential_ratio())
}

/// `m_TT = 2^{−k} Γ((1−k)/2) / Γ((1+k)/2)` (SH part, module doc).
pub fn transverse_compliance(k: f64) -> f64 {
    2f64.powf(-k) * gamma(0.5 * (1.0 - k)) / gamma(0.5 * (1.0 + k))
}

fn check_exponent(k: f64) -> Result<(), MdrError> {
    if k.is_finite() && k > -1.0 && k < 1.0 {
        Ok(())
    } else {
        Err(MdrError::InvalidParameter {
            name: "grading exponent k",
            value: k,
            allowed: "in (−1, 1)",
        })
    }
}

/// Surface `(U, W)` of the decaying P–SV solutions with unit tangential traction `(S, N) = (1, 0)`
/// and unit normal traction `(0, 1)` at `ξ = G₀ = z₀ = 1`: `(U_t, W_t, U_n, W_n)`.
///
/// State `X = (U, W, S, N)` with `u_x = i U e^{ix}`, `u_z = W e^{ix}`, `σ_xz = i S e^{ix}`,
/// `σ_zz = N e^{ix}`, `G = z^k`, `λ = 2νG/(1−2ν)`:
/// `U' = S/G − W`, `W' = (1−2ν)/(2(1−ν)) N/G + ν/(1−ν) U`, `S' = 2/(1−ν) G U − ν/(1−ν) N`, `N' = S`,
/// in the variable `t = z^{1−|k|}/(1−|k|)` (`dz/dt = z^{|k|}`), which makes the right-hand side
/// bounded at the surface. Integrated from `z = 40` towards 0, any start converges onto the decaying
/// pair (the growing pair shrinks by `e^{−80}`); two independent starts span it.
fn psv_surface_response(k: f64, nu: f64) -> (f64, f64, f64, f64) {
    let a = k.abs();
    let big_a = nu / (1.0 - nu);
    let big_b = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu));
    let big_c = 2.0 / (1.0 - nu);
    let z_of_t = |t: f64| ((1.0 - a) * t.max(0.0)).powf(1.0 / (1.0 - a));
    let rhs = |t: f64, x: &[f64; 4]| -> [f64; 4] {
        let z = z_of_t(t);
        let za = z.powf(a);
        let [u, w, s, n] = *x;
        if k >= 0.0 {
            // G = z^a: S/G · z^a = S; G U z^a = z^{2a} U.
            [
                s - w * za,
                big_b * n + big_a * u * za,
                big_c * za * za * u - big_a * n * za,
                s * za,
            ]
        } else {
            // G = z^{−a}: S/G · z^a = S z^{2a}; G U z^a = U.
            [
                (s * za - w) * za,
                (big_b * n * za + big_a * u) * za,
                big_c * u - big_a * n * za,
                s * za,
            ]
        }
    };
    let t_far = 40f64.powf(1.0 - a) / (1.0 - a);
    let starts = [[1.0, 0.3, -0.2, 0.5], [0.2, -1.0, 0.7, 0.1]];
    let ends: Vec<[f64; 4]> = starts
        .iter()
        .map(|x0| integrate_dp45(&rhs, t_far, 0.0, *x0, 1e-15))
        .collect();
    // Combinations with surface tractions (S, N) = (1, 0) and (0, 1).
    let (x1, x2) = (ends[0], ends[1]);
    let det = x1[2] * x2[3] - x2[2] * x1[3];
    let tang = [x2[3] / det, -x1[3] / det];
    let norm = [-x2[2] / det, x1[2] / det];
    let comb = |c: [f64; 2], i: usize| c[0] * x1[i] + c[1] * x2[i];
    (comb(tang, 0), comb(tang, 1), comb(norm, 0), comb(norm, 1))
}

/// Dormand–Prince 5(4) with step control on the mixed error `|e| / (atol + rtol |x|)`, `atol` 1e-300
/// relative to the state's scale; integrates `x' = f(t, x)` from `t0` to `t1` (either direction).
fn integrate_dp45(
    f: &impl Fn(f64, &[f64; 4]) -> [f64; 4],
    t0: f64,
    t1: f64,
    x0: [f64; 4],
    rtol: f64,
) -> [f64; 4] {
    const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
    const A: [[f64; 6]; 7] = [
        [0.0; 6],
        [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
        [
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
            0.0,
            0.0,
        ],
        [
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
            0.0,
        ],
        [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ];
    const B4: [f64; 7] = [
        5179.0 / 57600.0,
        0.0,
        7571.0 / 16695.0,
        393.0 / 640.0,
        -92097.0 / 339200.0,
        187.0 / 2100.0,
        1.0 / 40.0,
    ];
    let direction = (t1 - t0).signum();
    let mut t = t0;
    let mut x = x0;
    let mut h = direction * (t1 - t0).abs() * 1e-3;
    let mut steps = 0usize;
    while (t1 - t) * direction > 0.0 && steps < 10_000_000 {
        steps += 1;
        if (t + h - t1) * direction > 0.0 {
            h = t1 - t;
        }
        let mut k = [[0.0; 4]; 7];
        for s in 0..7 {
            let mut xs = x;
            for (j, kj) in k.iter().enumerate().take(s) {
                for i in 0..4 {
                    xs[i] += h * A[s][j] * kj[i];
                }
            }
            k[s] = f(t + C[s] * h, &xs);
        }
        let mut x5 = x;
        let mut err = 0.0f64;
        let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
        for i in 0..4 {
            let (mut d5, mut d4) = (0.0, 0.0);
            // The 5th-order weights are the last stage's row (FSAL): A[6], and 0 for stage 7.
            for s in 0..7 {
                d5 += A[6].get(s).copied().unwrap_or(0.0) * k[s][i];
                d4 += B4[s] * k[s][i];
            }
            x5[i] += h * d5;
            err = err.max((h * (d5 - d4)).abs() / (rtol * scale));
        }
        if err <= 1.0 {
            t += h;
            x = x5;
        }
        let factor = if err == 0.0 {
            5.0
        } else {
            (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
        };
        h *= factor;
    }
    x
}

/// `Λ(k, ν) = m_zz`, the normal compliance in closed form (docs/theory-mdr.md#graded-constant-cn, the Green's
/// function's factor): `(1−ν) 2^k β sin(πβ/2) Γ((3+k+β)/2) Γ((3+k−β)/2) / (cos(πk/2) Γ(k+2)²)`.
pub fn normal_compliance(k: f64, nu: f64) -> f64 {
    let beta = ((1.0 + k) * (1.0 - k * nu / (1.0 - nu))).sqrt();
    (1.0 - nu)
        * 2f64.powf(k)
        * beta
        * (0.5 * PI * beta).sin()
        * gamma(0.5 * (3.0 + k + beta))
        * gamma(0.5 * (3.0 + k - beta))
        / ((0.5 * PI * k).cos() * gamma(k + 2.0).powi(2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn homogeneous_compliances_are_boussinesq_and_cerruti() {
        for nu in [0.0, 0.3, 0.5] {
            let m = GradedCompliances::new(1e-300, nu).unwrap();
            assert_relative_eq!(m.normal, 1.0 - nu, max_relative = 1e-10);
            assert_relative_eq!(m.longitudinal, 1.0 - nu, max_relative = 1e-10);
            assert_relative_eq!(m.transverse, 1.0, max_relative = 1e-12);
            assert_relative_eq!(m.coupling, 0.5 * (1.0 - 2.0 * nu), epsilon = 1e-10);
            assert_relative_eq!(
                m.tangential_ratio(),
                2.0 * (1.0 - nu) / (2.0 - nu),
                max_relative = 1e-10
            );
        }
    }

    #[test]
    fn the_integrated_normal_compliance_is_the_closed_form_of_spec_4_2() {
        for (k, nu) in [
            (0.5, 0.3),
            (-0.5, 0.3),
            (0.8, 0.45),
            (-0.8, 0.1),
            (0.25, 0.0),
            (0.6, 0.5),
        ] {
            let m = GradedCompliances::new(k, nu).unwrap();
            assert_relative_eq!(m.normal, normal_compliance(k, nu), max_relative = 1e-10);
            // Reciprocity (Maxwell–Betti) of the two integrated couplings.
            assert_relative_eq!(m.coupling, m.coupling_reciprocal, epsilon = 1e-10);
        }
    }

    #[test]
    fn kleins_radial_stress_case_decouples() {
        // ν = 1/(2+k) (β = 1): the coupling vanishes and m_LL = (1+k)/2 · m_TT (observed to 1e-10
        // for every k tried; at k = 0 it is ν = 1/2, m_LL = 1/2).
        for k in [0.1, 0.3, 0.5, 0.75] {
            let m = GradedCompliances::new(k, 1.0 / (2.0 + k)).unwrap();
            assert!(m.coupling.abs() < 1e-10, "k {k}: {}", m.coupling);
            assert_relative_eq!(
                m.longitudinal,
                0.5 * (1.0 + k) * m.transverse,
                max_relative = 1e-10
            );
        }
    }

    #[test]
    fn ratios_match_an_independent_integration() {
        // scipy's DOP853 on the same system in Python (rtol 1e-13; docs/fretting-wear.md table).
        for (k, nu, want) in [
            (-0.75, 0.3, 3.346902),
            (-0.5, 0.3, 1.738627),
            (0.25, 0.0, 0.817954),
            (0.5, 0.3, 0.474486),
            (0.9, 0.45, 0.133543),
        ] {
            let got = tangential_constant_ratio(k, nu).unwrap();
            assert!((got - want).abs() < 1e-6, "k {k} ν {nu}: {got} vs {want}");
        }
    }

    #[test]
    fn bad_parameters_are_refused() {
        assert!(GradedCompliances::new(1.0, 0.3).is_err());
        assert!(GradedCompliances::new(0.5, 0.6).is_err());
        assert!(tangential_constant_ratio(0.0, -1.0).is_err());
    }
}
