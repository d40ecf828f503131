//! Stresses at depth `z > 0` below a uniform traction on the surface rectangle `2Δ₁ × 2Δ₂` centred at
//! 0 (docs/theory-sam.md#love-rectangle-stresses; Love 1929; Liu & Wang 2002): `σ_ij = ⟦Σ_ij⟧` over the corner coordinates
//! `c_α = x_α + s_α Δ_α` (sign `s₁s₂`), `ρ = √(c₁² + c₂² + z²)`.
//!
//! Unit pressure (compressive, acting in `+x₃`): with `Φ_z = −arctan(c₁c₂/(zρ))`,
//! `Φ₁₁ = c₁/(ρ(ρ+c₂))`, `Φ₂₂ = c₂/(ρ(ρ+c₁))`, `A₁ = arctan(c₁c₂(ρ−z)/(c₁²ρ + c₂²z))`,
//! `A₂ = arctan(c₁c₂(ρ−z)/(c₂²ρ + c₁²z))`:
//! `2πΣ₁₁ = 2νΦ_z − (1−2ν)A₁ − zΦ₁₁`, `2πΣ₂₂ = 2νΦ_z − (1−2ν)A₂ − zΦ₂₂`,
//! `2πΣ₃₃ = Φ_z + z(Φ₁₁ + Φ₂₂)`, `2πΣ₁₂ = −(1−2ν) ln(ρ+z) − z/ρ`, `2πΣ₁₃ = −z²/(ρ(ρ+c₂))`,
//! `2πΣ₂₃ = −z²/(ρ(ρ+c₁))`.
//!
//! Unit shear `q₁` (along `+x₁`), `Λ_α = ln(ρ + c_α)`:
//! `2πΣ₁₁ = 2Λ₂ + c₁²c₂/((c₁²+z²)ρ) − (1−2ν)c₂/(ρ+z)`, `2πΣ₂₂ = 2νΛ₂ − c₂/ρ + (1−2ν)c₂/(ρ+z)`,
//! `2πΣ₃₃ = z²c₂/((c₁²+z²)ρ)`, `2πΣ₁₂ = Λ₁ − c₁/ρ + (1−2ν)c₁/(ρ+z)`,
//! `2πΣ₁₃ = −arctan(c₁c₂/(zρ)) + c₁c₂z/((c₁²+z²)ρ)`, `2πΣ₂₃ = −z/ρ`.
//! Unit shear `q₂`: the same with the indices 1 ↔ 2 swapped (in `c` and in the stress).
//!
//! Stresses are in the Voigt order `(11, 22, 33, 23, 13, 12)`, tension positive.

use std::f64::consts::PI;

use super::InPlane;

/// `ρ + c` without cancellation (`c < 0`: `(ρ² − c²)/(ρ − c)`).
#[inline]
fn rho_plus(rho: f64, c: f64, rest2: f64) -> f64 {
    if c >= 0.0 {
        rho + c
    } else {
        rest2 / (rho - c)
    }
}

/// Primitives of the pressure stresses at one corner, Voigt order.
fn pressure_primitive(c1: f64, c2: f64, z: f64, nu: f64) -> [f64; 6] {
    let rho = (c1 * c1 + c2 * c2 + z * z).sqrt();
    let rp1 = rho_plus(rho, c1, c2 * c2 + z * z);
    let rp2 = rho_plus(rho, c2, c1 * c1 + z * z);
    let phi_z = -(c1 * c2 / (z * rho)).atan();
    let phi11 = c1 / (rho * rp2);
    let phi22 = c2 / (rho * rp1);
    let rmz = (c1 * c1 + c2 * c2) / (rho + z);
    let a1 = (c1 * c2 * rmz / (c1 * c1 * rho + c2 * c2 * z)).atan();
    let a2 = (c1 * c2 * rmz / (c2 * c2 * rho + c1 * c1 * z)).atan();
    let k = 1.0 / (2.0 * PI);
    let s11 = 2.0 * nu * phi_z - (1.0 - 2.0 * nu) * a1 - z * phi11;
    let s22 = 2.0 * nu * phi_z - (1.0 - 2.0 * nu) * a2 - z * phi22;
    let s33 = phi_z + z * (phi11 + phi22);
    let s12 = -(1.0 - 2.0 * nu) * (rho + z).ln() - z / rho;
    let s13 = -z * z / (rho * rp2);
    let s23 = -z * z / (rho * rp1);
    [k * s11, k * s22, k * s33, k * s23, k * s13, k * s12]
}

/// Primitives of the `q₁` stresses at one corner, Voigt order.
fn shear1_primitive(c1: f64, c2: f64, z: f64, nu: f64) -> [f64; 6] {
    let rho = (c1 * c1 + c2 * c2 + z * z).sqrt();
    let lam1 = rho_plus(rho, c1, c2 * c2 + z * z).ln();
    let lam2 = rho_plus(rho, c2, c1 * c1 + z * z).ln();
    let c1z = c1 * c1 + z * z;
    let k = 1.0 / (2.0 * PI);
    let s11 = 2.0 * lam2 + c1 * c1 * c2 / (c1z * rho) - (1.0 - 2.0 * nu) * c2 / (rho + z);
    let s22 = 2.0 * nu * lam2 - c2 / rho + (1.0 - 2.0 * nu) * c2 / (rho + z);
    let s33 = z * z * c2 / (c1z * rho);
    let s12 = lam1 - c1 / rho + (1.0 - 2.0 * nu) * c1 / (rho + z);
    let s13 = -(c1 * c2 / (z * rho)).atan() + c1 * c2 * z / (c1z * rho);
    let s23 = -z / rho;
    [k * s11, k * s22, k * s33, k * s23, k * s13, k * s12]
}

/// Corner sum of a Voigt-valued primitive over the rectangle of half-widths `(d1, d2)`.
fn corner_sum6(f: impl Fn(f64, f64) -> [f64; 6], x1: f64, x2: f64, d1: f64, d2: f64) -> [f64; 6] {
    let mut out = [0.0; 6];
    for (s1, s2) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
        let v = f(x1 + s1 * d1, x2 + s2 * d2);
        for (o, vi) in out.iter_mut().zip(v) {
            *o += s1 * s2 * vi;
        }
    }
    out
}

/// Stress at `(x1, x2, z)`, `z > 0`, per unit **pressure** on the rectangle of half-widths
/// `(d1, d2)` centred at 0. Voigt order.
pub fn pressure_stress(x1: f64, x2: f64, z: f64, d1: f64, d2: f64, nu: f64) -> [f64; 6] {
    corner_sum6(|c1, c2| pressure_primitive(c1, c2, z, nu), x1, x2, d1, d2)
}

/// The stresses of the three unit tractions (pressure, `q₁`, `q₂`) on the square cell of half-width
/// `half` centred at 0, at the lattice point `(2·half·m, 2·half·n, half·key)` of the layered kernels
/// (cell centres in-plane, depth in half-cells). Voigt order, one row per traction.
pub fn unit_traction_stresses(key: i64, m: i64, n: i64, half: f64, nu: f64) -> [[f64; 6]; 3] {
    let d = half;
    let (x1, x2, z) = (2.0 * d * m as f64, 2.0 * d * n as f64, d * key as f64);
    [
        pressure_stress(x1, x2, z, d, d, nu),
        shear_stress(InPlane::X1, x1, x2, z, d, d, nu),
        shear_stress(InPlane::X2, x1, x2, z, d, d, nu),
    ]
}

/// Stress per unit shear along `+x_α` (`InPlane::X1` for `q₁`, `InPlane::X2` for `q₂`). Voigt order.
pub fn shear_stress(
    alpha: InPlane,
    x1: f64,
    x2: f64,
    z: f64,
    d1: f64,
    d2: f64,
    nu: f64,
) -> [f64; 6] {
    if alpha == InPlane::X1 {
        corner_sum6(|c1, c2| shear1_primitive(c1, c2, z, nu), x1, x2, d1, d2)
    } else {
        // Swap 1 ↔ 2: Σ^{q₂}_{ij}(c₁, c₂) = Σ^{q₁}_{σ(i)σ(j)}(c₂, c₁); Voigt (11,22,33,23,13,12) maps
        // to (22,11,33,13,23,12).
        let s = corner_sum6(|c1, c2| shear1_primitive(c2, c1, z, nu), x1, x2, d1, d2);
        [s[1], s[0], s[2], s[4], s[3], s[5]]
    }
}
