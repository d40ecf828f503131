//! Closed-form kernels of the semi-analytical method (docs/theory-sam.md#cuboid-in-infinite-space to #love-rectangle-stresses):
//!
//! * [`cuboid`]: a cuboid with uniform eigenstrain in an infinite space (Chiu 1977; Mura 1987 §11;
//!   \[LN11\] App. A, Eqs. 9 and 16) — the strain kernel `D`, the displacement kernel `Dˢ`, and the
//!   Eshelby tensor of a sphere for comparison.
//! * [`subsurface`]: Love's (1929) stresses below a uniformly loaded surface rectangle, for a pressure
//!   and for both shears (Liu & Wang 2002).
//!
//! The surface influence coefficients of the same rectangles (docs/theory-sam.md#influence-coefficients) are in [`crate::kernels::surface`].

pub mod cuboid;
pub mod subsurface;
pub mod surface;

/// Voigt order of symmetric tensors (docs/theory-sam.md#conventions): `(11, 22, 33, 23, 13, 12)`, tensor shear components.
pub const VOIGT: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];

/// A tensor index: one of the coordinate directions `x₁, x₂, x₃` (`x₃` the depth;
/// docs/theory-sam.md#conventions). The index arguments of the cuboid potentials and kernels
/// ([`cuboid::StrainPotentials`], [`cuboid::DisplacementPotentials`]) are of this type, so an index
/// out of `{1, 2, 3}` cannot be written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Direction {
    /// `x₁`.
    X1 = 0,
    /// `x₂`.
    X2 = 1,
    /// `x₃` (depth).
    X3 = 2,
}

/// An in-plane direction of the surface: the shear traction `q_α` and the tangential
/// displacement `u_α` (`α = 1, 2`) of the surface kernels ([`surface::Compliance::tangential`],
/// [`surface::Compliance::coupling_shape`], [`subsurface::shear_stress`]). A type rather than an
/// index, so that no third value can be passed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum InPlane {
    /// `x₁`.
    X1 = 0,
    /// `x₂`.
    X2 = 1,
}

impl InPlane {
    /// `x₁, x₂` in order (`ALL[α].index() == α`).
    pub const ALL: [InPlane; 2] = [InPlane::X1, InPlane::X2];

    /// The zero-based position (0, 1) of the direction in a 2-vector `(q₁, q₂)`.
    #[inline]
    pub const fn index(self) -> usize {
        self as usize
    }
}

impl From<InPlane> for Direction {
    fn from(d: InPlane) -> Self {
        match d {
            InPlane::X1 => Direction::X1,
            InPlane::X2 => Direction::X2,
        }
    }
}

impl Direction {
    /// `x₁, x₂, x₃` in order (`ALL[i].index() == i`).
    pub const ALL: [Direction; 3] = [Direction::X1, Direction::X2, Direction::X3];

    /// The zero-based position (0, 1, 2) of the direction in a 3-vector.
    #[inline]
    pub const fn index(self) -> usize {
        self as usize
    }
}

/// Isotropic stiffness `C` as a 6 × 6 matrix on Voigt vectors with **tensor** shear components
/// (`σ_ii = λ tr ε + 2G ε_ii`, `σ_ij = 2G ε_ij`), `λ = 2Gν/(1−2ν)`, `G = E/(2(1+ν))`.
pub fn stiffness(e: f64, nu: f64) -> [[f64; 6]; 6] {
    let g = e / (2.0 * (1.0 + nu));
    let lambda = 2.0 * g * nu / (1.0 - 2.0 * nu);
    let mut c = [[0.0; 6]; 6];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = lambda;
        }
        c[i][i] += 2.0 * g;
        c[i + 3][i + 3] = 2.0 * g;
    }
    c
}

/// Compliance `C⁻¹` on Voigt vectors with tensor shear: `ε_ii = (σ_ii − ν(σ_jj + σ_kk))/E`,
/// `ε_ij = (1+ν) σ_ij / E`.
pub fn compliance(e: f64, nu: f64) -> [[f64; 6]; 6] {
    let mut s = [[0.0; 6]; 6];
    for i in 0..3 {
        for j in 0..3 {
            s[i][j] = if i == j { 1.0 / e } else { -nu / e };
        }
        s[i + 3][i + 3] = (1.0 + nu) / e;
    }
    s
}

/// `y = A x` for a 6 × 6 matrix.
pub fn mul6(a: &[[f64; 6]; 6], x: &[f64]) -> [f64; 6] {
    let mut y = [0.0; 6];
    for (yi, row) in y.iter_mut().zip(a) {
        *yi = row.iter().zip(x).map(|(p, q)| p * q).sum();
    }
    y
}

/// `A B` for 6 × 6 matrices.
pub fn matmul6(a: &[[f64; 6]; 6], b: &[[f64; 6]; 6]) -> [[f64; 6]; 6] {
    let mut c = [[0.0; 6]; 6];
    for i in 0..6 {
        for j in 0..6 {
            c[i][j] = (0..6).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}
