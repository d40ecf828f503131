//! Symmetric stress/strain tensors in Voigt order and the operations the criteria need
//! (docs/fatigue.md, "Notation").
//!
//! Voigt order `[σxx, σyy, σzz, σyz, σxz, σxy]`, tension positive — the order of
//! `halfspace_sam::subsurface` (`(11, 22, 33, 23, 13, 12)`). Shear entries are tensor components
//! (not engineering strains) for strains too.

/// A symmetric 3 × 3 tensor `[xx, yy, zz, yz, xz, xy]`.
pub type Voigt = [f64; 6];

/// Dimension of the deviatoric space.
pub const DEVIATOR_DIM: usize = 5;

/// Hydrostatic stress `σ_H = tr σ / 3`.
pub fn hydrostatic(s: &Voigt) -> f64 {
    (s[0] + s[1] + s[2]) / 3.0
}

/// Deviator `s = σ − σ_H I` in Voigt order.
pub fn deviator(s: &Voigt) -> Voigt {
    let h = hydrostatic(s);
    [s[0] - h, s[1] - h, s[2] - h, s[3], s[4], s[5]]
}

/// Coordinates of the deviator of `σ` in a 5D orthonormal basis of the traceless tensors,
/// `y = (√3/2 s_zz, (s_xx − s_yy)/2, s_yz, s_xz, s_xy)`, so that `|y|² = J₂ = ½ s:s`
/// (docs/fatigue.md, Eq. F1). The hydrostatic part drops out: `y(σ + p I) = y(σ)`.
pub fn deviator_coordinates(s: &Voigt) -> [f64; DEVIATOR_DIM] {
    let szz = s[2] - hydrostatic(s);
    [
        0.5 * 3f64.sqrt() * szz,
        0.5 * (s[0] - s[1]),
        s[3],
        s[4],
        s[5],
    ]
}

/// Inverse of [`deviator_coordinates`]: the traceless tensor with coordinates `y`,
/// `s_zz = 2y₀/√3`, `s_xx = −s_zz/2 + y₁`, `s_yy = −s_zz/2 − y₁`.
pub fn deviator_from_coordinates(y: &[f64; DEVIATOR_DIM]) -> Voigt {
    let szz = 2.0 * y[0] / 3f64.sqrt();
    [-0.5 * szz + y[1], -0.5 * szz - y[1], szz, y[2], y[3], y[4]]
}

/// Second invariant of the deviator `J₂ = ½ s:s`.
pub fn j2(s: &Voigt) -> f64 {
    let d = deviator(s);
    0.5 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) + d[3] * d[3] + d[4] * d[4] + d[5] * d[5]
}

/// Principal values of a symmetric tensor, descending, by cyclic Jacobi rotations until the
/// off-diagonal part is below `1e-15` of the Frobenius norm (Golub & Van Loan, Matrix
/// Computations, Algorithm 8.5.3). Accurate to ~1e-16 of `max |λ|` also for repeated values,
/// where the trigonometric solution of the characteristic cubic loses half the digits (1e-8 at
/// uniaxial and equibiaxial states: tests/tensor.rs measures both against `R diag(λ) Rᵀ`), which
/// would show in Dang Van's index at the endurance limits.
pub fn principal_values(s: &Voigt) -> [f64; 3] {
    let mut m = to_matrix(s);
    let norm: f64 = m.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    for _sweep in 0..64 {
        let off = (m[0][1].powi(2) + m[0][2].powi(2) + m[1][2].powi(2)).sqrt();
        if off <= 1e-15 * norm {
            break;
        }
        for (p, q) in [(0usize, 1usize), (0, 2), (1, 2)] {
            if m[p][q] == 0.0 {
                continue;
            }
            let theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let sn = t * c;
            // m ← Jᵀ m J with J the rotation in the (p, q) plane.
            for row in m.iter_mut() {
                let (xp, xq) = (row[p], row[q]);
                row[p] = c * xp - sn * xq;
                row[q] = sn * xp + c * xq;
            }
            for k in 0..3 {
                let (xp, xq) = (m[p][k], m[q][k]);
                m[p][k] = c * xp - sn * xq;
                m[q][k] = sn * xp + c * xq;
            }
        }
    }
    // Descending by `total_cmp` (a three-element sorting network: values equal under
    // `total_cmp` are the same bits, so the result is the sort's).
    let mut v = [m[0][0], m[1][1], m[2][2]];
    for (i, j) in [(0, 1), (1, 2), (0, 1)] {
        if v[i].total_cmp(&v[j]).is_lt() {
            v.swap(i, j);
        }
    }
    v
}

/// Maximum shear (Tresca) `τ = (λ₁ − λ₃)/2` of the principal values.
pub fn tresca_shear(s: &Voigt) -> f64 {
    let l = principal_values(s);
    0.5 * (l[0] - l[2])
}

/// The 3 × 3 matrix of a Voigt tensor.
pub fn to_matrix(s: &Voigt) -> [[f64; 3]; 3] {
    [[s[0], s[5], s[4]], [s[5], s[1], s[3]], [s[4], s[3], s[2]]]
}

/// The rotated tensor `R σ Rᵀ` (components of `σ` in the frame whose axes are the rows of `R`
/// transposed, i.e. `σ'_ij = R_ik σ_kl R_jl`).
pub fn rotate(s: &Voigt, r: &[[f64; 3]; 3]) -> Voigt {
    let m = to_matrix(s);
    let mut out = [[0.0; 3]; 3];
    for (i, out_row) in out.iter_mut().enumerate() {
        for (j, o) in out_row.iter_mut().enumerate() {
            let mut acc = 0.0;
            for (k, m_row) in m.iter().enumerate() {
                for (l, m_kl) in m_row.iter().enumerate() {
                    acc += r[i][k] * m_kl * r[j][l];
                }
            }
            *o = acc;
        }
    }
    [
        out[0][0], out[1][1], out[2][2], out[1][2], out[0][2], out[0][1],
    ]
}

/// Weights `w` with `a·σ·b = w·σ` (Voigt dot product) for unit vectors `a`, `b`:
/// `w = (a_x b_x, a_y b_y, a_z b_z, a_y b_z + a_z b_y, a_x b_z + a_z b_x, a_x b_y + a_y b_x)`.
/// With `a = b = n` this is the normal stress `σ_n = n·σ·n`.
pub fn bilinear_weights(a: &[f64; 3], b: &[f64; 3]) -> [f64; 6] {
    [
        a[0] * b[0],
        a[1] * b[1],
        a[2] * b[2],
        a[1] * b[2] + a[2] * b[1],
        a[0] * b[2] + a[2] * b[0],
        a[0] * b[1] + a[1] * b[0],
    ]
}

/// Voigt dot product `w·σ`.
#[inline]
pub fn dot6(w: &[f64; 6], s: &Voigt) -> f64 {
    w[0] * s[0] + w[1] * s[1] + w[2] * s[2] + w[3] * s[3] + w[4] * s[4] + w[5] * s[5]
}

/// Isotropic Hooke's law `ε = ((1 + ν) σ − ν tr σ I)/E` (tensor shear components).
pub fn strain_from_stress(s: &Voigt, young: f64, poisson: f64) -> Voigt {
    let tr = s[0] + s[1] + s[2];
    let k = (1.0 + poisson) / young;
    let l = poisson / young * tr;
    [
        k * s[0] - l,
        k * s[1] - l,
        k * s[2] - l,
        k * s[3],
        k * s[4],
        k * s[5],
    ]
}
