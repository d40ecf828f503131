//! Special functions: Γ and ln Γ (Lanczos, g = 7, 9 terms; relative error ~1e-15 on the real
//! axis), 1/Γ, and the Gauss hypergeometric function ₂F₁ for real arguments (docs/theory-mdr.md#graded-displacements, docs/theory-mdr.md#p12-special-functions).

use std::f64::consts::PI;

use crate::NumericsError;

const LANCZOS_G: f64 = 7.0;
const LANCZOS: [f64; 9] = [
    0.999_999_999_999_809_9,
    676.520_368_121_885_1,
    -1_259.139_216_722_402_8,
    771.323_428_777_653_1,
    -176.615_029_162_140_6,
    12.507_343_278_686_905,
    -0.138_571_095_265_720_12,
    9.984_369_578_019_572e-6,
    1.505_632_735_149_311_6e-7,
];

/// `Γ(x)` for real `x` (reflection `Γ(x)Γ(1−x) = π / sin(πx)` below 1/2); `±∞` at the poles.
pub fn gamma(x: f64) -> f64 {
    if x < 0.5 {
        let s = (PI * x).sin();
        if s == 0.0 {
            return f64::INFINITY;
        }
        return PI / (s * gamma(1.0 - x));
    }
    let x = x - 1.0;
    let mut a = LANCZOS[0];
    let t = x + LANCZOS_G + 0.5;
    for (i, c) in LANCZOS.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    (2.0 * PI).sqrt() * t.powf(x + 0.5) * (-t).exp() * a
}

/// `ln |Γ(x)|` for `x > 0`.
pub fn ln_gamma(x: f64) -> f64 {
    if x < 0.5 {
        return (PI / (PI * x).sin().abs()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = LANCZOS[0];
    let t = x + LANCZOS_G + 0.5;
    for (i, c) in LANCZOS.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// `1/Γ(x)`, exactly 0 at the poles `x = 0, −1, −2, …`.
pub fn reciprocal_gamma(x: f64) -> f64 {
    if x <= 0.0 && x == x.round() {
        0.0
    } else {
        1.0 / gamma(x)
    }
}

/// Incomplete beta function `B_z(p, q) = ∫_0^z s^{p−1} (1−s)^{q−1} ds = (z^p/p) ₂F₁(p, 1−q; p+1; z)`,
/// `p > 0`, `0 ≤ z ≤ 1` (any real `q`; at `z = 1` it needs `q > 0`).
pub fn incomplete_beta(p: f64, q: f64, z: f64) -> Result<f64, NumericsError> {
    if !(p > 0.0 && p.is_finite()) {
        return Err(NumericsError::InvalidParameter {
            name: "incomplete beta p",
            value: p,
            allowed: "finite and > 0",
        });
    }
    if !(0.0..=1.0).contains(&z) {
        return Err(NumericsError::InvalidParameter {
            name: "incomplete beta z",
            value: z,
            allowed: "in [0, 1]",
        });
    }
    if z == 0.0 {
        return Ok(0.0);
    }
    Ok(z.powf(p) / p * hyp2f1(p, 1.0 - q, p + 1.0, z)?)
}

const SERIES_MAX_TERMS: usize = 100_000;

/// Gauss hypergeometric function `₂F₁(a, b; c; z) = Σ (a)_n (b)_n / ((c)_n n!) zⁿ` for real
/// arguments and `z ≤ 1` (docs/theory-mdr.md#graded-displacements: the kernel `H(y; k)` of Eq. 25 needs `0 ≤ y ≤ 1`).
///
/// * `|z| ≤ 1/2`: the series.
/// * `−1 ≤ z < −1/2`, `z < −1`: Pfaff, `₂F₁(a,b;c;z) = (1−z)^{−a} ₂F₁(a, c−b; c; z/(z−1))`.
/// * `1/2 < z < 1`: the linear transformation to `1 − z` (Abramowitz & Stegun 15.3.6), valid when
///   `c − a − b` is not an integer (always the case for the graded MDR, where `c − a − b = (1−k)/2`
///   with `−1 < k < 1`); with an integer `c − a − b` the series is summed directly up to `z ≤ 0.95`.
/// * `z = 1`: Gauss's sum `Γ(c)Γ(c−a−b)/(Γ(c−a)Γ(c−b))`, for `c − a − b > 0`.
pub fn hyp2f1(a: f64, b: f64, c: f64, z: f64) -> Result<f64, NumericsError> {
    for (name, v) in [
        ("2F1 parameter a", a),
        ("2F1 parameter b", b),
        ("2F1 parameter c", c),
        ("2F1 argument z", z),
    ] {
        if !v.is_finite() {
            return Err(NumericsError::InvalidParameter {
                name,
                value: v,
                allowed: "finite",
            });
        }
    }
    if c <= 0.0 && c == c.round() {
        return Err(NumericsError::InvalidParameter {
            name: "2F1 parameter c",
            value: c,
            allowed: "not 0 or a negative integer",
        });
    }
    if z > 1.0 {
        return Err(NumericsError::InvalidParameter {
            name: "2F1 argument z",
            value: z,
            allowed: "≤ 1 (real branch)",
        });
    }
    if z == 0.0 {
        return Ok(1.0);
    }
    let s = c - a - b;
    if z == 1.0 {
        if s <= 0.0 {
            return Err(NumericsError::InvalidParameter {
                name: "2F1 at z = 1: c − a − b",
                value: s,
                allowed: "> 0 (the series diverges otherwise)",
            });
        }
        return Ok(gamma(c) * gamma(s) * reciprocal_gamma(c - a) * reciprocal_gamma(c - b));
    }
    if z < -0.5 {
        let w = z / (z - 1.0);
        return Ok((1.0 - z).powf(-a) * hyp2f1(a, c - b, c, w)?);
    }
    if z <= 0.5 {
        return series(a, b, c, z);
    }
    if s == 0.0 {
        return log_case_zero(a, b, z);
    }
    if (s - s.round()).abs() < 1e-12 {
        if z <= 0.95 {
            return series(a, b, c, z);
        }
        return Err(NumericsError::InvalidParameter {
            name: "2F1 argument z (with integer c − a − b)",
            value: z,
            allowed: "≤ 0.95",
        });
    }
    let w = 1.0 - z;
    let first = gamma(c) * gamma(s) * reciprocal_gamma(c - a) * reciprocal_gamma(c - b);
    let second = gamma(c) * gamma(-s) * reciprocal_gamma(a) * reciprocal_gamma(b);
    let mut value = 0.0;
    if first != 0.0 {
        value += first * series(a, b, 1.0 - s, w)?;
    }
    if second != 0.0 {
        value += second * w.powf(s) * series(c - a, c - b, s + 1.0, w)?;
    }
    Ok(value)
}

/// `c = a + b`, `1/2 < z < 1` (Abramowitz & Stegun 15.3.10):
/// `₂F₁(a,b;a+b;z) = Γ(a+b)/(Γ(a)Γ(b)) Σ (a)_n (b)_n/(n!)² [2ψ(n+1) − ψ(a+n) − ψ(b+n) − ln(1−z)] (1−z)ⁿ`.
fn log_case_zero(a: f64, b: f64, z: f64) -> Result<f64, NumericsError> {
    let w = 1.0 - z;
    let ln_w = w.ln();
    let (mut psi1, mut psia, mut psib) = (digamma(1.0), digamma(a), digamma(b));
    let mut coef = 1.0;
    let mut sum = 0.0;
    for n in 0..SERIES_MAX_TERMS {
        let nf = n as f64;
        let term = coef * (2.0 * psi1 - psia - psib - ln_w);
        sum += term;
        if n > 2 && (term.abs() <= 1e-17 * sum.abs() || coef == 0.0) {
            return Ok(gamma(a + b) * reciprocal_gamma(a) * reciprocal_gamma(b) * sum);
        }
        coef *= (a + nf) * (b + nf) / ((nf + 1.0) * (nf + 1.0)) * w;
        psi1 += 1.0 / (nf + 1.0);
        psia += 1.0 / (a + nf);
        psib += 1.0 / (b + nf);
    }
    Err(NumericsError::InvalidParameter {
        name: "2F1 logarithmic series (did not converge) at z",
        value: z,
        allowed: "a region where the series converges",
    })
}

/// Digamma `ψ(x) = Γ'(x)/Γ(x)`: recurrence up to `x ≥ 10`, then the asymptotic series (error
/// below 1e-15); reflection `ψ(x) = ψ(1−x) − π cot(πx)` for `x < 1/2`.
pub fn digamma(x: f64) -> f64 {
    if x < 0.5 {
        return digamma(1.0 - x) - PI / (PI * x).tan();
    }
    let mut x = x;
    let mut acc = 0.0;
    while x < 10.0 {
        acc -= 1.0 / x;
        x += 1.0;
    }
    let inv2 = 1.0 / (x * x);
    let tail = inv2
        * (1.0 / 12.0
            - inv2
                * (1.0 / 120.0
                    - inv2
                        * (1.0 / 252.0
                            - inv2
                                * (1.0 / 240.0 - inv2 * (1.0 / 132.0 - inv2 * 691.0 / 32760.0)))));
    acc + x.ln() - 0.5 / x - tail
}

fn series(a: f64, b: f64, c: f64, z: f64) -> Result<f64, NumericsError> {
    let mut term = 1.0;
    let mut sum = 1.0;
    for n in 0..SERIES_MAX_TERMS {
        let nf = n as f64;
        term *= (a + nf) * (b + nf) / ((c + nf) * (nf + 1.0)) * z;
        sum += term;
        if term == 0.0 || term.abs() <= 1e-17 * sum.abs() {
            return Ok(sum);
        }
    }
    Err(NumericsError::InvalidParameter {
        name: "2F1 series (did not converge) at z",
        value: z,
        allowed: "a region where the series converges",
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamma_at_known_values() {
        assert!((gamma(1.0) - 1.0).abs() < 1e-14);
        assert!((gamma(5.0) - 24.0).abs() < 1e-12);
        assert!((gamma(0.5) - PI.sqrt()).abs() < 1e-14);
        assert!((gamma(1.5) - 0.5 * PI.sqrt()).abs() < 1e-14);
        assert!((gamma(-0.5) + 2.0 * PI.sqrt()).abs() < 1e-13);
        // Γ(10.3) from the recurrence of Γ(0.3) = 2.991568987687590...
        let g03 = 2.991_568_987_687_590_6;
        let mut v = g03;
        let mut x = 0.3;
        while x < 10.0 {
            v *= x;
            x += 1.0;
        }
        assert!((gamma(10.3) / v - 1.0).abs() < 1e-13);
        assert!((ln_gamma(10.3) - v.ln()).abs() < 1e-13);
        assert!((ln_gamma(0.3) - g03.ln()).abs() < 1e-14);
    }

    #[test]
    fn hyp2f1_identities() {
        // ₂F₁(a, b; b; z) = (1 − z)^{−a}
        for z in [-3.0, -0.7, -0.2, 0.3, 0.6, 0.9, 0.999] {
            for a in [0.25, 0.75, 1.3] {
                let v = hyp2f1(a, 0.6, 0.6, z).unwrap();
                let want = (1.0f64 - z).powf(-a);
                assert!((v / want - 1.0).abs() < 1e-13, "a={a} z={z}: {v} vs {want}");
            }
            // ₂F₁(1, 1; 2; z) = −ln(1 − z)/z (integer c − a − b: direct series up to 0.95)
            if z <= 0.95 {
                let v = hyp2f1(1.0, 1.0, 2.0, z).unwrap();
                let want = -(1.0f64 - z).ln() / z;
                assert!((v / want - 1.0).abs() < 1e-13, "z={z}: {v} vs {want}");
            }
        }
        // Gauss at z = 1: ₂F₁(a, a; a+1; 1) = Γ(a+1)Γ(1−a) (docs/theory-mdr.md#p12-special-functions).
        for a in [0.1, 0.5, 0.9] {
            let v = hyp2f1(a, a, a + 1.0, 1.0).unwrap();
            let want = gamma(a + 1.0) * gamma(1.0 - a);
            assert!((v / want - 1.0).abs() < 1e-13);
            // Approach to z = 1 is like (1 − z)^{c−a−b} = w^{1−a}.
            let w: f64 = 1e-12;
            let near = hyp2f1(a, a, a + 1.0, 1.0 - w).unwrap();
            assert!(
                (near / want - 1.0).abs() < 10.0 * w.powf(1.0 - a),
                "continuity at z = 1"
            );
        }
        // The logarithmic case c = a + b near z = 1: ₂F₁(1/2, 1/2; 1; z) = (2/π) K(z) (complete
        // elliptic integral, m = z); K(0.99) = 3.695637362989875.
        let v = hyp2f1(0.5, 0.5, 1.0, 0.99).unwrap();
        assert!((v - 2.0 / PI * 3.695_637_362_989_875).abs() < 1e-13, "{v}");
        // Nine recurrence steps from x = 1 to 10 leave ~1e-15 of rounding.
        assert!((digamma(1.0) + 0.577_215_664_901_532_9).abs() < 3e-15);
        assert!((digamma(0.5) + 1.963_510_026_021_423_5).abs() < 1e-14);
        // B_z(p, q) against closed forms: B_z(1, 1/2) = 2(1 − √(1−z)), B_1(p, q) = B(p, q).
        for z in [0.1, 0.5, 0.8, 0.99, 1.0] {
            let v = incomplete_beta(1.0, 0.5, z).unwrap();
            assert!(
                (v - 2.0 * (1.0 - (1.0f64 - z).sqrt())).abs() < 1e-14,
                "z={z}"
            );
        }
        let b = incomplete_beta(0.75, 0.25, 1.0).unwrap();
        assert!((b - gamma(0.75) * gamma(0.25) / gamma(1.0)).abs() < 1e-12);
        assert!(hyp2f1(1.0, 1.0, -2.0, 0.1).is_err());
        assert!(hyp2f1(1.0, 1.0, 2.0, 1.5).is_err());
        assert!(hyp2f1(1.0, 1.0, 1.5, 1.0).is_err());
        assert!(hyp2f1(f64::NAN, 1.0, 2.0, 0.1).is_err());
    }
}
