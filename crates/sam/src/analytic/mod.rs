//! Closed-form solutions that serve the tests, the docs and the benchmarks of the 3D method (one
//! library, not re-derived in each test): Hertz's subsurface stresses on the axis, Eshelby's sphere
//! and Mindlin–Cheng's nucleus of strain. (Hertz's surface fields, Cattaneo–Mindlin and
//! Mindlin–Deresiewicz live with the contact solvers in [`mindlin`].)

pub mod mindlin;

use crate::kernels::{mul6, stiffness};

/// Hertz (frictionless, axisymmetric) stresses on the axis at depth `z` below a contact of radius
/// `a` and peak pressure `p₀`, Johnson (1985) Eq. (3.45): `σ_z = −p₀ (1 + z²/a²)⁻¹`,
/// `σ_r = σ_θ = −p₀ [(1+ν)(1 − (z/a) arctan(a/z)) − ½ (1 + z²/a²)⁻¹]`. Returns `(σ_r, σ_z)`.
pub fn hertz_axis_stress(z: f64, a: f64, p0: f64, nu: f64) -> (f64, f64) {
    let s = z / a;
    let sz = -p0 / (1.0 + s * s);
    let sr = if s == 0.0 {
        -p0 * (1.0 + 2.0 * nu) / 2.0
    } else {
        -p0 * ((1.0 + nu) * (1.0 - s * (1.0 / s).atan()) - 0.5 / (1.0 + s * s))
    };
    (sr, sz)
}

/// The maximum shear `τ₁ = ½|σ_z − σ_r|` on the Hertz axis and its depth, by golden-section search
/// on `[0, 2a]` (Johnson: 0.31 p₀ at 0.48 a for ν = 0.3).
pub fn hertz_axis_max_shear(a: f64, p0: f64, nu: f64) -> (f64, f64) {
    let tau = |z: f64| {
        let (sr, sz) = hertz_axis_stress(z, a, p0, nu);
        0.5 * (sz - sr).abs()
    };
    let (mut lo, mut hi) = (0.0, 2.0 * a);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..200 {
        let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if tau(m1) > tau(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let z = 0.5 * (lo + hi);
    (tau(z), z)
}

/// Eshelby's tensor of a sphere as a Voigt 6 × 6 matrix on tensor components:
/// `S_ijkl = (5ν−1)/(15(1−ν)) δ_ij δ_kl + (4−5ν)/(15(1−ν)) (δ_ik δ_jl + δ_il δ_jk)` (docs/theory-sam.md#equivalency-equation).
pub fn eshelby_sphere_tensor(nu: f64) -> [[f64; 6]; 6] {
    let a = (5.0 * nu - 1.0) / (15.0 * (1.0 - nu));
    let b = (4.0 - 5.0 * nu) / (15.0 * (1.0 - nu));
    let mut s = [[0.0; 6]; 6];
    for i in 0..3 {
        for j in 0..3 {
            s[i][j] = a;
        }
        s[i][i] += 2.0 * b;
        // Off-diagonal column = S_ijkl + S_ijlk = 2b for (ij) = (kl).
        s[i + 3][i + 3] = 2.0 * b;
    }
    s
}

/// The uniform stress inside a spherical inhomogeneity `(E_I, ν_I)` in an infinite matrix `(E, ν)`
/// under a remote uniform strain `ε⁰` (Voigt, tensor shear), Eshelby (1957): with
/// `α = (1+ν)/(3(1−ν))`, `β = 2(4−5ν)/(15(1−ν))`, the interior strain has the volumetric part
/// `ε⁰_vol / [1 + α(κ_I/κ − 1)]` and the deviatoric part `e⁰ / [1 + β(μ_I/μ − 1)]`; the stress is
/// `C_I : ε_in`.
pub fn eshelby_sphere_interior_stress(
    e_matrix: f64,
    nu_matrix: f64,
    e_inclusion: f64,
    nu_inclusion: f64,
    remote_strain: &[f64; 6],
) -> [f64; 6] {
    let bulk = |e: f64, nu: f64| e / (3.0 * (1.0 - 2.0 * nu));
    let shear = |e: f64, nu: f64| e / (2.0 * (1.0 + nu));
    let nu = nu_matrix;
    let alpha = (1.0 + nu) / (3.0 * (1.0 - nu));
    let beta = 2.0 * (4.0 - 5.0 * nu) / (15.0 * (1.0 - nu));
    let kr = bulk(e_inclusion, nu_inclusion) / bulk(e_matrix, nu_matrix);
    let mr = shear(e_inclusion, nu_inclusion) / shear(e_matrix, nu_matrix);
    let vol = remote_strain[0] + remote_strain[1] + remote_strain[2];
    let vol_in = vol / (1.0 + alpha * (kr - 1.0));
    let dev_factor = 1.0 / (1.0 + beta * (mr - 1.0));
    let mut eps = [0.0; 6];
    for (i, e) in eps.iter_mut().enumerate() {
        let dev = remote_strain[i] - if i < 3 { vol / 3.0 } else { 0.0 };
        *e = dev * dev_factor + if i < 3 { vol_in / 3.0 } else { 0.0 };
    }
    mul6(&stiffness(e_inclusion, nu_inclusion), &eps)
}

/// Surface displacement `(u_r, u₃)` at radius `r` of a centre of dilatation of strength `e V`
/// (eigenstrain `e δ_ij` in a small volume `V`) at depth `c` in a half-space, Mindlin & Cheng
/// (1950): `u₃ = −(1+ν) e V c / (π R³)`, `u_r = (1+ν) e V r / (π R³)`, `R² = r² + c²`
/// (docs/theory-sam.md#mirror-image-and-correction-pressure; `u₃ > 0` into the body, so the surface bulges out).
pub fn mindlin_cheng_surface(r: f64, depth: f64, ev: f64, nu: f64) -> (f64, f64) {
    let big_r = (r * r + depth * depth).sqrt();
    let k = (1.0 + nu) * ev / (std::f64::consts::PI * big_r.powi(3));
    (k * r, -k * depth)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn johnson_numbers() {
        let (tau, z) = hertz_axis_max_shear(1.0, 1.0, 0.3);
        assert!(
            (tau - 0.31).abs() < 0.005 && (z - 0.48).abs() < 0.01,
            "{tau} at {z}"
        );
        let (sr, sz) = hertz_axis_stress(0.0, 1.0, 1.0, 0.3);
        assert!((sz + 1.0).abs() < 1e-15 && (sr + 0.8).abs() < 1e-15);
    }

    #[test]
    fn eshelby_spec_numbers() {
        // docs/theory-sam.md#kernel-reference-values: E_I = 2 E_m, ν = 0.3, remote σ₃₃ = 1: interior σ₃₃ = 1.3150, σ₁₁ = −0.0398.
        let (e, nu) = (1.0, 0.3);
        let remote = [-nu / e, -nu / e, 1.0 / e, 0.0, 0.0, 0.0];
        let s = eshelby_sphere_interior_stress(e, nu, 2.0 * e, nu, &remote);
        assert!(
            (s[2] - 1.3150).abs() < 5e-5 && (s[0] + 0.0398).abs() < 5e-5,
            "{s:?}"
        );
        let t = eshelby_sphere_tensor(0.3);
        assert!((t[0][0] - 0.523810).abs() < 1e-6 && (t[0][1] - 0.047619).abs() < 1e-6);
        assert!((t[5][5] - 2.0 * 0.238095).abs() < 2e-6);
    }
}
