//! A cuboid with a uniform eigenstrain `ε*` in an infinite isotropic space (docs/theory-sam.md#cuboid-in-infinite-space;
//! Chiu 1977; Mura 1987 §11; \[LN11\] App. A, Eqs. 9 and 16).
//!
//! With the box centred at 0 with half-sizes `a`, the Newtonian and biharmonic potentials
//! `φ(x) = ∫ dV′/|x − x′|`, `ψ(x) = ∫ |x − x′| dV′` are corner sums `φ = ⟦𝓔⟧₃`, `ψ = ⟦𝓗⟧₃` over the
//! corner vectors `c = x + s∘a` (`s ∈ {±1}³`, sign `s₁s₂s₃`), and
//!
//! `u_i = Dˢ_ikl ε*_kl`, `Dˢ_ikl = [ψ,kli − 2ν δ_kl φ,i − 2(1−ν)(φ,k δ_il + φ,l δ_ik)] / (8π(1−ν))`,
//!
//! `ε_ij = D_ijkl ε*_kl`, `D_ijkl = [ψ,klij − 2ν δ_kl φ,ij − (1−ν)(φ,kj δ_il + φ,ki δ_jl + φ,lj δ_ik
//! + φ,li δ_jk)] / (8π(1−ν))`.
//!
//! Only derivatives of `𝓔, 𝓗` are needed; their primitives (docs/theory-sam.md#cuboid-in-infinite-space table) use `R = |c|`,
//! `L_k = ln(R + c_k)` and `T_k = arctan(c_i c_j / (c_k R))`, with `R + c_k = (c_i² + c_j²)/(R − c_k)`
//! for `c_k < 0` (no cancellation). `ε` is the total strain; the stress is `C:ε` outside and
//! `C:(ε − ε*)` inside the cuboid.

use std::f64::consts::PI;

use super::{Direction, VOIGT};

// The public potentials and kernels take their tensor indices as [`Direction`]s; the private
// helpers below work on positions `0..3` (a `Direction`'s index, or a loop over `0..3`) and on
// multiplicity vectors whose entries sum to the derivative's order — invariants of this module,
// never user input.

/// `R`, `L_k`, `T_k` and `R + c_k` at one corner vector.
struct Corner {
    c: [f64; 3],
    r: f64,
    l: [f64; 3],
    t: [f64; 3],
    r_plus: [f64; 3],
}

/// The two indices other than `k`, in cyclic order (`k < 3`).
#[inline]
fn others(k: usize) -> (usize, usize) {
    ((k + 1) % 3, (k + 2) % 3)
}

impl Corner {
    fn new(c: [f64; 3]) -> Self {
        let r = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        let mut l = [0.0; 3];
        let mut t = [0.0; 3];
        let mut r_plus = [0.0; 3];
        for k in 0..3 {
            let (i, j) = others(k);
            let perp2 = c[i] * c[i] + c[j] * c[j];
            if c[k] >= 0.0 {
                r_plus[k] = r + c[k];
                l[k] = r_plus[k].ln();
            } else {
                r_plus[k] = perp2 / (r - c[k]);
                l[k] = perp2.ln() - (r - c[k]).ln();
            }
            let num = c[i] * c[j];
            // `c_k = 0` (a face plane): the one-sided limit ±π/2 of the side the zero's sign gives.
            t[k] = if num == 0.0 {
                0.0
            } else {
                (num / (c[k] * r)).atan()
            };
        }
        Self { c, r, l, t, r_plus }
    }

    /// `𝓔,i`.
    fn e1(&self, i: usize) -> f64 {
        let (j, k) = others(i);
        self.c[j] * self.l[k] + self.c[k] * self.l[j] - self.c[i] * self.t[i]
    }

    /// `𝓔,ij`.
    fn e2(&self, i: usize, j: usize) -> f64 {
        if i == j {
            -self.t[i]
        } else {
            self.l[3 - i - j]
        }
    }

    /// `𝓗,ijk` from the multiplicities `n` of the indices 0, 1, 2 (`Σ n = 3`).
    fn h3(&self, n: [usize; 3]) -> f64 {
        let c = &self.c;
        match n {
            [1, 1, 1] => self.r,
            _ => {
                let i = (0..3).find(|&i| n[i] >= 2).expect("a repeated index");
                if n[i] == 3 {
                    let (j, k) = others(i);
                    c[j] * self.l[k] + c[k] * self.l[j] - 2.0 * c[i] * self.t[i]
                } else {
                    let j = (0..3).find(|&j| n[j] == 1).expect("one single index");
                    c[i] * self.l[3 - i - j]
                }
            }
        }
    }

    /// `𝓗,ijkl` from the multiplicities `n` of the indices 0, 1, 2 (`Σ n = 4`).
    fn h4(&self, n: [usize; 4 - 1]) -> f64 {
        let c = &self.c;
        let r = self.r;
        if let Some(i) = (0..3).find(|&i| n[i] == 4) {
            let (j, k) = others(i);
            return -2.0 * self.t[i]
                - c[i] * c[j] / (r * self.r_plus[k])
                - c[i] * c[k] / (r * self.r_plus[j]);
        }
        if let Some(i) = (0..3).find(|&i| n[i] == 3) {
            let j = (0..3).find(|&j| n[j] == 1).expect("one single index");
            let k = 3 - i - j;
            return self.l[k] + c[i] * c[i] / (r * self.r_plus[k]);
        }
        let single = (0..3).find(|&i| n[i] == 0);
        if let Some(k) = single {
            // n = (2, 2, 0) in some order: 𝓗,iijj = c_i c_j / (R (R + c_k)).
            let (i, j) = others(k);
            return c[i] * c[j] / (r * self.r_plus[k]);
        }
        // n = (2, 1, 1) in some order: 𝓗,iijk = c_i / R.
        let i = (0..3).find(|&i| n[i] == 2).expect("a doubled index");
        c[i] / r
    }
}

/// Multiplicities of the directions `x₁, x₂, x₃` in a multi-index.
#[inline]
fn counts(idx: &[Direction]) -> [usize; 3] {
    let mut n = [0; 3];
    for &i in idx {
        n[i.index()] += 1;
    }
    n
}

/// Position of a sorted multi-index among the distinct ones of its order (`φ,ij`: 6, `ψ,ijk`: 10,
/// `ψ,ijkl`: 15), by multiplicities.
fn slot(n: [usize; 3], order: usize) -> usize {
    // Enumerate (n0, n1) with n0 descending, then n1 descending: a fixed bijection.
    let mut s = 0;
    for a in (0..=order).rev() {
        for b in (0..=order - a).rev() {
            if a == n[0] && b == n[1] {
                return s;
            }
            s += 1;
        }
    }
    unreachable!("multiplicities sum to the order")
}

/// All distinct multiplicity vectors of an order, in [`slot`] order.
const fn multiplicities<const M: usize>(order: usize) -> [[usize; 3]; M] {
    let mut v = [[0; 3]; M];
    let mut s = 0;
    let mut a = order as isize;
    while a >= 0 {
        let mut b = order as isize - a;
        while b >= 0 {
            v[s] = [a as usize, b as usize, order - a as usize - b as usize];
            s += 1;
            b -= 1;
        }
        a -= 1;
    }
    v
}

const M2: [[usize; 3]; 6] = multiplicities::<6>(2);
const M3: [[usize; 3]; 10] = multiplicities::<10>(3);
const M4: [[usize; 3]; 15] = multiplicities::<15>(4);

/// `SLOT2[i][j]`, `SLOT4[i][j][k][l]`: positions of the derivatives in the tables.
const SLOT2: [[usize; 3]; 3] = {
    let mut t = [[0; 3]; 3];
    let mut i = 0;
    while i < 3 {
        let mut j = 0;
        while j < 3 {
            let mut n = [0; 3];
            n[i] += 1;
            n[j] += 1;
            t[i][j] = slot_const(n, 2);
            j += 1;
        }
        i += 1;
    }
    t
};

const SLOT4: [[[[usize; 3]; 3]; 3]; 3] = {
    let mut t = [[[[0; 3]; 3]; 3]; 3];
    let mut q = 0;
    while q < 81 {
        let (i, j, k, l) = (q / 27, (q / 9) % 3, (q / 3) % 3, q % 3);
        let mut n = [0; 3];
        n[i] += 1;
        n[j] += 1;
        n[k] += 1;
        n[l] += 1;
        t[i][j][k][l] = slot_const(n, 4);
        q += 1;
    }
    t
};

/// [`slot`] as a `const fn`.
const fn slot_const(n: [usize; 3], order: usize) -> usize {
    let mut s = 0;
    let mut a = order as isize;
    while a >= 0 {
        let mut b = order as isize - a;
        while b >= 0 {
            if a as usize == n[0] && b as usize == n[1] {
                return s;
            }
            s += 1;
            b -= 1;
        }
        a -= 1;
    }
    usize::MAX
}

/// [`VOIGT`] as pairs of [`Direction`]s.
const VOIGT_DIRECTIONS: [(Direction, Direction); 6] = {
    let mut t = [(Direction::X1, Direction::X1); 6];
    let mut v = 0;
    while v < 6 {
        t[v] = (Direction::ALL[VOIGT[v].0], Direction::ALL[VOIGT[v].1]);
        v += 1;
    }
    t
};

/// Second derivatives of `φ` and fourth of `ψ` at `x` for the box of half-sizes `a` (corner sums of
/// the primitives), indexed by `slot`.
pub struct StrainPotentials {
    phi2: [f64; 6],
    psi4: [f64; 15],
}

/// First derivatives of `φ` and third of `ψ` at `x`.
pub struct DisplacementPotentials {
    phi1: [f64; 3],
    psi3: [f64; 10],
}

/// Calls `f(sign, corner)` for the eight corners `c = x + s∘a`, sign `s₁s₂s₃`.
fn for_corners(x: [f64; 3], a: [f64; 3], mut f: impl FnMut(f64, &Corner)) {
    for s in 0..8 {
        let sg = [
            if s & 1 == 0 { 1.0 } else { -1.0 },
            if s & 2 == 0 { 1.0 } else { -1.0 },
            if s & 4 == 0 { 1.0 } else { -1.0 },
        ];
        let c = [
            x[0] + sg[0] * a[0],
            x[1] + sg[1] * a[1],
            x[2] + sg[2] * a[2],
        ];
        f(sg[0] * sg[1] * sg[2], &Corner::new(c));
    }
}

impl StrainPotentials {
    /// `φ,ij` and `ψ,ijkl` at `x` for the box of half-sizes `a`.
    pub fn new(x: [f64; 3], a: [f64; 3]) -> Self {
        let mut phi2 = [0.0; 6];
        let mut psi4 = [0.0; 15];
        for_corners(x, a, |s, corner| {
            for (v, n) in phi2.iter_mut().zip(&M2) {
                let (i, j) = pair_of(*n);
                *v += s * corner.e2(i, j);
            }
            for (v, n) in psi4.iter_mut().zip(&M4) {
                *v += s * corner.h4(*n);
            }
        });
        Self { phi2, psi4 }
    }

    /// `φ,ij`.
    #[inline]
    pub fn phi2(&self, i: Direction, j: Direction) -> f64 {
        self.phi2[SLOT2[i.index()][j.index()]]
    }

    /// `ψ,ijkl`.
    #[inline]
    pub fn psi4(&self, i: Direction, j: Direction, k: Direction, l: Direction) -> f64 {
        self.psi4[SLOT4[i.index()][j.index()][k.index()][l.index()]]
    }

    /// `D_ijkl` (the strain at `x` per unit `ε*_kl`, `ε*_lk` not included; the formula of the
    /// module documentation, \[LN11\] Eq. 9).
    pub fn d(&self, nu: f64, i: Direction, j: Direction, k: Direction, l: Direction) -> f64 {
        let delta = |p: Direction, q: Direction| if p == q { 1.0 } else { 0.0 };
        (self.psi4(k, l, i, j)
            - 2.0 * nu * delta(k, l) * self.phi2(i, j)
            - (1.0 - nu)
                * (self.phi2(k, j) * delta(i, l)
                    + self.phi2(k, i) * delta(j, l)
                    + self.phi2(l, j) * delta(i, k)
                    + self.phi2(l, i) * delta(j, k)))
            / (8.0 * PI * (1.0 - nu))
    }

    /// The 6 × 6 Voigt matrix: `ε_V = D_V ε*_V` with tensor shear components on both sides (an
    /// off-diagonal column is `D_ijkl + D_ijlk`).
    pub fn voigt(&self, nu: f64) -> [[f64; 6]; 6] {
        let mut m = [[0.0; 6]; 6];
        for (row, &(i, j)) in m.iter_mut().zip(&VOIGT_DIRECTIONS) {
            for (v, &(k, l)) in row.iter_mut().zip(&VOIGT_DIRECTIONS) {
                *v = self.d(nu, i, j, k, l);
                if k != l {
                    *v += self.d(nu, i, j, l, k);
                }
            }
        }
        m
    }
}

/// The two indices of a multiplicity vector of order 2.
fn pair_of(n: [usize; 3]) -> (usize, usize) {
    match (0..3).find(|&i| n[i] == 2) {
        Some(i) => (i, i),
        None => {
            let k = (0..3).find(|&i| n[i] == 0).expect("order 2");
            others(k)
        }
    }
}

impl DisplacementPotentials {
    /// `φ,i` and `ψ,ijk` at `x` for the box of half-sizes `a`.
    pub fn new(x: [f64; 3], a: [f64; 3]) -> Self {
        let mut phi1 = [0.0; 3];
        let mut psi3 = [0.0; 10];
        for_corners(x, a, |s, corner| {
            for (i, v) in phi1.iter_mut().enumerate() {
                *v += s * corner.e1(i);
            }
            for (v, n) in psi3.iter_mut().zip(&M3) {
                *v += s * corner.h3(*n);
            }
        });
        Self { phi1, psi3 }
    }

    /// `φ,i`.
    pub fn phi1(&self, i: Direction) -> f64 {
        self.phi1[i.index()]
    }

    /// `ψ,ijk`.
    pub fn psi3(&self, i: Direction, j: Direction, k: Direction) -> f64 {
        self.psi3[slot(counts(&[i, j, k]), 3)]
    }

    /// `Dˢ_ikl` (displacement `u_i` per unit `ε*_kl`; the formula of the module documentation,
    /// \[LN11\] Eq. 16).
    pub fn ds(&self, nu: f64, i: Direction, k: Direction, l: Direction) -> f64 {
        let delta = |p: Direction, q: Direction| if p == q { 1.0 } else { 0.0 };
        (self.psi3(k, l, i)
            - 2.0 * nu * delta(k, l) * self.phi1(i)
            - 2.0 * (1.0 - nu) * (self.phi1(k) * delta(i, l) + self.phi1(l) * delta(i, k)))
            / (8.0 * PI * (1.0 - nu))
    }

    /// The 3 × 6 matrix `u = Dˢ ε*_V` (off-diagonal columns `Dˢ_ikl + Dˢ_ilk`).
    pub fn voigt(&self, nu: f64) -> [[f64; 6]; 3] {
        let mut m = [[0.0; 6]; 3];
        for (&i, row) in Direction::ALL.iter().zip(m.iter_mut()) {
            for (v, &(k, l)) in row.iter_mut().zip(&VOIGT_DIRECTIONS) {
                *v = self.ds(nu, i, k, l);
                if k != l {
                    *v += self.ds(nu, i, l, k);
                }
            }
        }
        m
    }
}

/// `D` as a Voigt 6 × 6 matrix at `x` for the box of half-sizes `a` (docs/theory-sam.md#cuboid-in-infinite-space, \[LN11\] Eq. 9).
pub fn strain_kernel(x: [f64; 3], a: [f64; 3], nu: f64) -> [[f64; 6]; 6] {
    StrainPotentials::new(x, a).voigt(nu)
}

/// `Dˢ` as a 3 × 6 matrix at `x` for the box of half-sizes `a` (docs/theory-sam.md#cuboid-in-infinite-space, \[LN11\] Eq. 16).
pub fn displacement_kernel(x: [f64; 3], a: [f64; 3], nu: f64) -> [[f64; 6]; 3] {
    DisplacementPotentials::new(x, a).voigt(nu)
}

/// `φ` itself (a corner sum of `𝓔`), for checks of the potentials.
pub fn newtonian_potential(x: [f64; 3], a: [f64; 3]) -> f64 {
    let mut v = 0.0;
    for_corners(x, a, |s, k| {
        let c = k.c;
        let e = c[0] * c[1] * k.l[2] + c[1] * c[2] * k.l[0] + c[2] * c[0] * k.l[1]
            - 0.5 * (c[0] * c[0] * k.t[0] + c[1] * c[1] * k.t[1] + c[2] * c[2] * k.t[2]);
        v += s * e;
    });
    v
}
