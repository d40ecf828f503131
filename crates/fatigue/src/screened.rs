//! The four criteria over a field of points of several materials, each screened by a cheap upper
//! bound (docs/fatigue.md, "Screened field evaluation").
//!
//! Every criterion is evaluated exactly, in decreasing order of an upper bound `b ≥` the
//! criterion, at every point whose bound is at least `fraction ×` the largest exact value found:
//! every point whose value is `≥ fraction ×` the field's maximum is evaluated (so the maximum and
//! its location are those of the full evaluation), the others are `NaN`. Crossland and Dang Van
//! share one minimum ball per point (~40 μs), so a point evaluated for either holds both.
//!
//! The public bound functions check their input (the material constants each bound uses, a
//! non-empty finite path, finite non-negative deviations) and return typed errors; the screen
//! checks once and then runs their unchecked forms.
//!
//! Bounds (`R_X = max_t ‖X(t) − X̄‖`, the radius of the ball about the path's mean — `‖·‖_F` the
//! Frobenius norm, `|y| = √(½ s:s)` the ball's norm of docs/fatigue.md Eq. F1;
//! `σ₁ ≤ λ̂ = min(σ_H + √(2/3)‖s‖_F, Gershgorin)`):
//!
//! * Crossland: `(√J₂,a + α_C σ_H,max)/t₋₁ ≤ (R_y + α_C σ_H,max)/t₋₁` — the minimum ball's
//!   radius is at most that of any enclosing ball, here the one about the mean;
//! * Dang Van: `max_t (τ(ŝ(t)) + α_DV σ_H(t))/t₋₁ ≤ (R_y + max_t α_DV σ_H(t))/t₋₁` — `ŝ(t)`
//!   lies in the minimum ball, `|y(ŝ)| ≤ √J₂,a ≤ R_y`, and for a deviator
//!   `τ_Tresca = (ŝ₁ − ŝ₃)/2 ≤ √(½ ŝ:ŝ)` (`½ŝ:ŝ − τ² = ¾(ŝ₁ + ŝ₃)² ≥ 0`);
//!   both with `R_y (1 + 10⁻⁹) + 10⁻¹² max_t |y(t)|` for the rounding of the exact ball;
//! * SWT: `σ_n,max ε_a ≤ max(0, max_t λ̂(t)) · R_ε` — `σ_n ≤ σ₁`, and the half range of
//!   `n·ε·n` is at most `½ max ‖Δε‖₂ ≤ R_ε`;
//! * Fatemi–Socie: `γ_a (1 + k σ_n,max/σ_y) ≤ R_s/(√2 G) · max(0, 1 + k max_t λ̂(t)/σ_y)` — for
//!   `m ⊥ n`, `|m·Δσ·n| = |m·Δs·n| ≤ (λ_max − λ_min)(Δs)/2 ≤ ‖Δs‖_F/√2 ≤ √2 R_s`, and
//!   `γ_a = half range / G`.
use rayon::prelude::*;

use crate::critical_plane::{
    fatemi_socie, fs_plane_reaches, in_plane_directions, swt, tangent_basis, CriticalPlaneParams,
    PathColumns, PlaneScratch,
};
use crate::error::FatigueError;
use crate::field::{FieldParams, Maximum};
use crate::invariant::{check_path, crossland_dang_van, InvariantScratch};
use crate::material::Material;
use crate::tensor::{
    deviator, deviator_coordinates, hydrostatic, principal_values, strain_from_stress, Voigt,
};

/// The four index fields (`NaN` where a screened criterion was not evaluated), their maxima and
/// the counts of exact critical-plane evaluations.
#[derive(Clone, Debug, PartialEq)]
pub struct ScreenedIndices {
    /// Crossland's index where evaluated.
    pub crossland: Vec<f64>,
    /// Dang Van's index where evaluated.
    pub dang_van: Vec<f64>,
    /// SWT (Pa) where evaluated.
    pub swt: Vec<f64>,
    /// Fatemi–Socie where evaluated.
    pub fatemi_socie: Vec<f64>,
    pub crossland_max: Maximum,
    pub dang_van_max: Maximum,
    pub swt_max: Maximum,
    pub fatemi_socie_max: Maximum,
    /// Points where Crossland and Dang Van (one ball) were evaluated exactly.
    pub invariant_evaluated: usize,
    /// Points where SWT was evaluated exactly.
    pub swt_evaluated: usize,
    /// Points where Fatemi–Socie was evaluated exactly.
    pub fatemi_socie_evaluated: usize,
}

/// `max_t ‖X(t) − X̄‖_F` of the tensors `X(t) = f(path[t])` (two passes, no allocation).
fn frobenius_radius(path: &[Voigt], f: impl Fn(&Voigt) -> Voigt) -> f64 {
    let n = path.len() as f64;
    let mut mean = [0.0; 6];
    for s in path {
        let x = f(s);
        for k in 0..6 {
            mean[k] += x[k] / n;
        }
    }
    path.iter()
        .map(|s| {
            let x = f(s);
            let d: [f64; 6] = std::array::from_fn(|k| x[k] - mean[k]);
            (d[0] * d[0]
                + d[1] * d[1]
                + d[2] * d[2]
                + 2.0 * (d[3] * d[3] + d[4] * d[4] + d[5] * d[5]))
                .sqrt()
        })
        .fold(0.0, f64::max)
}

/// An upper bound of the largest principal stress of `s`.
fn largest_principal_bound(s: &Voigt) -> f64 {
    let h = hydrostatic(s);
    let d = [s[0] - h, s[1] - h, s[2] - h];
    let dev =
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]))
            .sqrt();
    let gershgorin = (s[0] + s[4].abs() + s[5].abs())
        .max(s[1] + s[3].abs() + s[5].abs())
        .max(s[2] + s[3].abs() + s[4].abs());
    (h + (2.0f64 / 3.0).sqrt() * dev).min(gershgorin)
}

/// `[Crossland bound, Dang Van bound]` of one path (module doc).
pub fn invariant_bounds(path: &[Voigt], material: &Material) -> Result<[f64; 2], FatigueError> {
    material.validate_limits()?;
    check_path(path)?;
    Ok(invariant_bounds_unchecked(path, material))
}

/// [`invariant_bounds`] of a checked path and material (the screen's pass 1).
fn invariant_bounds_unchecked(path: &[Voigt], material: &Material) -> [f64; 2] {
    let n = path.len() as f64;
    let mut mean = [0.0; 5];
    for s in path {
        let y = deviator_coordinates(s);
        for k in 0..5 {
            mean[k] += y[k] / n;
        }
    }
    let (mut radius, mut largest) = (0.0f64, 0.0f64);
    for s in path {
        let y = deviator_coordinates(s);
        let d2: f64 = (0..5).map(|k| (y[k] - mean[k]).powi(2)).sum();
        let y2: f64 = y.iter().map(|v| v * v).sum();
        radius = radius.max(d2.sqrt());
        largest = largest.max(y2.sqrt());
    }
    let r = radius * (1.0 + 1e-9) + 1e-12 * largest;
    let t = material.t_minus1;
    let (ac, adv) = (material.alpha_crossland(), material.alpha_dang_van());
    let h_max = path
        .iter()
        .map(hydrostatic)
        .fold(f64::NEG_INFINITY, f64::max);
    let dv_h = path
        .iter()
        .map(|s| adv * hydrostatic(s))
        .fold(f64::NEG_INFINITY, f64::max);
    [(r + ac * h_max) / t, (r + dv_h) / t]
}

/// `[SWT bound, Fatemi–Socie bound]` of one path (module doc).
pub fn critical_plane_bounds(
    path: &[Voigt],
    material: &Material,
) -> Result<[f64; 2], FatigueError> {
    material.validate_fatemi_socie()?;
    check_path(path)?;
    Ok(critical_plane_bounds_unchecked(path, material))
}

/// [`critical_plane_bounds`] of a checked path and material (the screen's pass 1).
fn critical_plane_bounds_unchecked(path: &[Voigt], material: &Material) -> [f64; 2] {
    let sigma1 = path
        .iter()
        .map(largest_principal_bound)
        .fold(f64::NEG_INFINITY, f64::max);
    let strain = |s: &Voigt| strain_from_stress(s, material.young, material.poisson);
    let deviator = |s: &Voigt| {
        let h = hydrostatic(s);
        [s[0] - h, s[1] - h, s[2] - h, s[3], s[4], s[5]]
    };
    let swt = sigma1.max(0.0) * frobenius_radius(path, strain);
    let factor = (1.0 + material.fs_k * sigma1 / material.yield_stress).max(0.0);
    let fs = frobenius_radius(path, deviator) / (2f64.sqrt() * material.shear_modulus()) * factor;
    [swt, fs]
}

/// Most patch splits of one [`fatemi_socie_patch_bound`] (on the LN11 homogeneous 64² loop
/// 64 → 160 → 400 splits leave 674 → 566 → 532 exact searches, the fatigue part's CPU time
/// 160 ≈ 400 < 64: docs/fatigue.md, "Cost on the loop, stop 23").
pub const FS_PATCH_SPLITS: usize = 160;

/// A patch of plane normals: the square `[u₀, u₁] × [v₀, v₁]` of the cube face `x_face = 1`
/// (every normal, up to sign, meets one of the faces `x = 1`, `y = 1`, `z = 1` at coordinates in
/// `[−1, 1]²`), with its upper bound of Fatemi–Socie.
#[derive(Clone, Copy, Debug)]
struct Patch {
    upper: f64,
    face: usize,
    u: [f64; 2],
    v: [f64; 2],
}

impl PartialEq for Patch {
    fn eq(&self, other: &Self) -> bool {
        self.upper.total_cmp(&other.upper).is_eq()
    }
}
impl Eq for Patch {}
impl PartialOrd for Patch {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Patch {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.upper.total_cmp(&other.upper)
    }
}

/// Reusable buffers of [`fatemi_socie_patch_bound`].
#[derive(Clone, Debug, Default)]
pub struct PatchScratch {
    per_increment: Vec<[f64; 3]>,
    heap: std::collections::BinaryHeap<Patch>,
    shear: Vec<[f64; 2]>,
    hull: Vec<[f64; 2]>,
    columns: PathColumns,
    directions: Vec<[f64; 2]>,
}

/// The unit normal through the point `(u, v)` of the cube face `face`.
fn face_normal(face: usize, u: f64, v: f64) -> [f64; 3] {
    let mut x = [0.0; 3];
    x[face] = 1.0;
    x[(face + 1) % 3] = u;
    x[(face + 2) % 3] = v;
    let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
    [x[0] / r, x[1] / r, x[2] / r]
}

/// The angle between two unit vectors (`atan2(|a × b|, a·b)`, accurate at small angles).
fn angle(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    let c = [
        p[1] * q[2] - p[2] * q[1],
        p[2] * q[0] - p[0] * q[2],
        p[0] * q[1] - p[1] * q[0],
    ];
    let sin = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    sin.atan2(p[0] * q[0] + p[1] * q[1] + p[2] * q[2])
}

/// The second-order bound `max |τ(n, S)|` over the normals `n` within the angle `θ` of the unit
/// normal `n₀` (docs/fatigue.md, "A per-plane Fatemi–Socie bound"), `basis = (e₁, e₂)` an
/// orthonormal basis of the plane `⊥ n₀`, `rho ≥ (λ₁ − λ₃)(S)/2`:
/// `√(|τ₀|² + 2θ |Mᵀτ₀| + θ² ‖M‖₂²) + ½ θ² √41 ρ`, `τ₀ = S n₀ − σ_n n₀`, `σ_n = n₀·S n₀`,
/// `M = [L e₁, L e₂]`, `L e = S e − 2(e·τ₀) n₀ − σ_n e`.
///
/// Along `n(φ) = n₀ cos φ + e sin φ`, `τ = S n − (n·S n) n` has `τ'(0) = L e` and
/// `τ'' = −τ − 4(n'·τ) n' + 2(σ_n − n'·S n') n` (`n'' = −n`), whose tangential part is at most
/// `5|τ| ≤ 5ρ` and normal part at most `2(λ₁ − λ₃) = 4ρ`: `|τ''| ≤ √41 ρ`, so by Taylor's
/// theorem `|τ(n(φ))| ≤ |τ₀ + φ L e| + ½ φ² √41 ρ`, and over `φ e = δ`, `|δ| ≤ θ`,
/// `|τ₀ + M δ|² ≤ |τ₀|² + 2θ |Mᵀτ₀| + θ² ‖M‖₂²`. A cap of radius `θ` about `n₀` holds the patch.
fn shear_on_patch_bound(
    s: &Voigt,
    n: &[f64; 3],
    basis: &([f64; 3], [f64; 3]),
    theta: f64,
    rho: f64,
) -> f64 {
    let apply = |x: &[f64; 3]| {
        [
            s[0] * x[0] + s[5] * x[1] + s[4] * x[2],
            s[5] * x[0] + s[1] * x[1] + s[3] * x[2],
            s[4] * x[0] + s[3] * x[1] + s[2] * x[2],
        ]
    };
    let dot = |x: &[f64; 3], y: &[f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    let w = apply(n);
    let sn = dot(&w, n);
    let tau: [f64; 3] = std::array::from_fn(|i| w[i] - sn * n[i]);
    let derivative = |e: &[f64; 3]| -> [f64; 3] {
        let se = apply(e);
        let te = dot(&tau, e);
        std::array::from_fn(|i| se[i] - 2.0 * te * n[i] - sn * e[i])
    };
    let (l1, l2) = (derivative(&basis.0), derivative(&basis.1));
    let g = [dot(&tau, &l1), dot(&tau, &l2)];
    let (p, q, r) = (dot(&l1, &l1), dot(&l1, &l2), dot(&l2, &l2));
    let largest = 0.5 * (p + r) + (0.25 * (p - r) * (p - r) + q * q).sqrt();
    let linear = (dot(&tau, &tau)
        + 2.0 * theta * (g[0] * g[0] + g[1] * g[1]).sqrt()
        + theta * theta * largest)
        .sqrt();
    linear + 0.5 * theta * theta * 41f64.sqrt() * rho
}

/// An upper bound `U` of Fatemi–Socie (Eq. F7) of one path by branch and bound over patches of
/// plane normals (docs/fatigue.md, "A per-plane Fatemi–Socie bound"), tighter than
/// [`critical_plane_bounds`]'s because the shear amplitude and the normal stress are bounded
/// jointly per patch. With `c` the componentwise mid-range of the path, `Δσ(t) = σ(t) − c`,
/// `τ(n, S) = |S n − (n·S n) n|` the shear traction of `S` on the plane `n`, a patch of centre
/// `n₀` and radius `θ` (the largest angle from `n₀` to its corners: a cube-face square is
/// geodesically convex, so the farthest point is a corner; `+10⁻¹²`), every plane `n` of it has
///
/// * `γ_a(n, m) G ≤ A = max_t min(A₁(t), A₂(t))` — half the diameter of the shear path is at
///   most its distance to any centre, `max_t |τ(n, Δσ(t))|`, and along a great circle
///   `n = n₀ cos φ + e sin φ` (`e ⊥ n₀`, `φ ≤ θ`) with `S = Δσ(t)`, `ρ = (λ₁ − λ₃)(S)/2`:
///   - first order, `A₁ = |τ(n₀, S)| + θ (λ₁ − λ₃)`: `|dτ/dφ| ≤ ‖S − (n·S n) I‖₂ ≤ λ₁ − λ₃`;
///   - second order (`shear_on_patch_bound`), `A₂ = √(|τ₀|² + 2θ|Mᵀτ₀| + θ² ‖M‖₂²) +
///     ½ θ² √41 ρ` with `τ₀ = τ(n₀, S)` and `M = [L e₁, L e₂]`, `L e = dτ/dφ(0) = S e −
///     2(e·τ₀) n₀ − σ_n(n₀) e`, on a tangent basis `e₁, e₂` at `n₀` (Taylor's theorem:
///     `|d²τ/dφ²| ≤ √41 ρ` everywhere);
///
///   both with `λ₁ − λ₃ ≤ √2 ‖dev S‖_F`;
/// * `σ_n(n, t) ≤ B = max_t [σ_n(n₀, t) + sin 2θ τ(n₀, σ(t)) + sin²θ max(0, λ̂(t) − σ_n(n₀, t))]`
///   — `n = n₀ cos φ + u sin φ`, `u ⊥ n₀`, gives `σ_n = σ_n(n₀) + sin 2φ u·τ₀ +
///   sin²φ (u·σ u − σ_n(n₀))`, and `u·σ u ≤ σ₁ ≤ λ̂` (the module doc's; `θ ≤ π/4`);
///
/// so `FS ≤ A/G · max(0, 1 + k B/σ_y)` on the patch (`× (1 + 10⁻⁹)` for rounding). Starting
/// from the 12 squares of side 1 of the three faces, the patch of the largest bound is split in
/// four until that bound is below `threshold` (the point cannot reach it), or a plane's value
/// (a lower bound from the patch centres: half the largest `|τ(t) − τ(0)|`, and with a
/// threshold the value on the centre plane of each patch split, on the 12 default in-plane
/// directions and exact only where those cannot decide, `fs_plane_reaches`) reaches `threshold`,
/// or after [`FS_PATCH_SPLITS`] splits (always, with no threshold). Returns the largest patch bound then, never above
/// [`critical_plane_bounds`]'s.
pub fn fatemi_socie_patch_bound(
    path: &[Voigt],
    material: &Material,
    threshold: Option<f64>,
    scratch: &mut PatchScratch,
) -> Result<f64, FatigueError> {
    material.validate_fatemi_socie()?;
    check_path(path)?;
    Ok(fatemi_socie_patch_bound_unchecked(
        path, material, threshold, scratch,
    ))
}

/// [`fatemi_socie_patch_bound`] of a checked path and material (the screen's pass 2).
fn fatemi_socie_patch_bound_unchecked(
    path: &[Voigt],
    material: &Material,
    threshold: Option<f64>,
    scratch: &mut PatchScratch,
) -> f64 {
    let path_bound = critical_plane_bounds_unchecked(path, material)[1];
    let mut lo = [f64::INFINITY; 6];
    let mut hi = [f64::NEG_INFINITY; 6];
    for s in path {
        for k in 0..6 {
            lo[k] = lo[k].min(s[k]);
            hi[k] = hi[k].max(s[k]);
        }
    }
    let c: [f64; 6] = std::array::from_fn(|k| 0.5 * (lo[k] + hi[k]));
    // Per increment: the Lipschitz constant √2 ‖dev Δσ‖_F ≥ λ₁ − λ₃, λ̂(t) ≥ σ₁(t), and
    // 10⁻¹² ‖Δσ‖_F for the rounding of the shear tractions.
    scratch.per_increment.clear();
    scratch.per_increment.extend(path.iter().map(|s| {
        let d: Voigt = std::array::from_fn(|k| s[k] - c[k]);
        let h = hydrostatic(&d);
        let (a, b, e) = (d[0] - h, d[1] - h, d[2] - h);
        let off = 2.0 * (d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
        let frob = (a * a + b * b + e * e + off).sqrt();
        let full = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + off).sqrt();
        [2f64.sqrt() * frob, largest_principal_bound(s), 1e-12 * full]
    }));
    // The centre planes' values (with a threshold) first on the default coarse in-plane
    // directions, exact only where those can still reach the threshold.
    let m = CriticalPlaneParams::default().coarse_directions;
    if threshold.is_some() {
        scratch.columns.fill(path);
        if scratch.directions.len() != m {
            in_plane_directions(m, &mut scratch.directions);
        }
    }
    let cos_half_step = (std::f64::consts::FRAC_PI_2 / m as f64).cos();
    let g = material.shear_modulus();
    let kq = material.fs_k / material.yield_stress;
    let per_increment = &scratch.per_increment;
    // (upper bound on the patch, value bound below at its centre).
    let bounds = |face: usize, u: [f64; 2], v: [f64; 2]| -> (f64, f64) {
        let n = face_normal(face, 0.5 * (u[0] + u[1]), 0.5 * (v[0] + v[1]));
        let theta = [(0, 0), (1, 0), (0, 1), (1, 1)]
            .iter()
            .map(|&(i, j)| angle(&n, &face_normal(face, u[i], v[j])))
            .fold(0.0, f64::max)
            + 1e-12;
        let (sin2, sinsq) = ((2.0 * theta).sin(), theta.sin().powi(2));
        let basis = tangent_basis(&n);
        let (mut a, mut b, mut smax, mut chord) =
            (0.0f64, f64::NEG_INFINITY, f64::NEG_INFINITY, 0.0f64);
        let mut first = None;
        // The shear vector of c (the same for every t).
        let wc = [
            c[0] * n[0] + c[5] * n[1] + c[4] * n[2],
            c[5] * n[0] + c[1] * n[1] + c[3] * n[2],
            c[4] * n[0] + c[3] * n[1] + c[2] * n[2],
        ];
        let fc = wc[0] * n[0] + wc[1] * n[1] + wc[2] * n[2];
        let tc = [wc[0] - fc * n[0], wc[1] - fc * n[1], wc[2] - fc * n[2]];
        for (s, &[lip, lambda, rounding]) in path.iter().zip(per_increment.iter()) {
            // σ n, its normal part and shear vector (Voigt [xx, yy, zz, yz, xz, xy]).
            let w = [
                s[0] * n[0] + s[5] * n[1] + s[4] * n[2],
                s[5] * n[0] + s[1] * n[1] + s[3] * n[2],
                s[4] * n[0] + s[3] * n[1] + s[2] * n[2],
            ];
            let f = w[0] * n[0] + w[1] * n[1] + w[2] * n[2];
            let tau = [w[0] - f * n[0], w[1] - f * n[1], w[2] - f * n[2]];
            // The shear vector of Δσ(t) is τ(t) minus that of c.
            let td = [tau[0] - tc[0], tau[1] - tc[1], tau[2] - tc[2]];
            let norm = |x: &[f64; 3]| (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
            let first_order = norm(&td) + theta * lip;
            let delta: Voigt = std::array::from_fn(|k| s[k] - c[k]);
            // The second-order bound only where it can raise the maximum over t.
            if first_order + rounding > a {
                let second = shear_on_patch_bound(&delta, &n, &basis, theta, 0.5 * lip);
                a = a.max(first_order.min(second) + rounding);
            }
            b = b.max(f + sin2 * norm(&tau) + sinsq * (lambda - f).max(0.0));
            smax = smax.max(f);
            let t0 = *first.get_or_insert(tau);
            chord = chord.max(norm(&[tau[0] - t0[0], tau[1] - t0[1], tau[2] - t0[2]]));
        }
        (
            a / g * (1.0 + kq * b).max(0.0) * (1.0 + 1e-9),
            0.5 * chord / g * (1.0 + kq * smax).max(0.0),
        )
    };
    let heap = &mut scratch.heap;
    heap.clear();
    let mut lower = 0.0f64;
    for face in 0..3 {
        for (u, v) in [
            ([-1.0, 0.0], [-1.0, 0.0]),
            ([0.0, 1.0], [-1.0, 0.0]),
            ([-1.0, 0.0], [0.0, 1.0]),
            ([0.0, 1.0], [0.0, 1.0]),
        ] {
            let (upper, below) = bounds(face, u, v);
            lower = lower.max(below);
            heap.push(Patch { upper, face, u, v });
        }
    }
    for _ in 0..FS_PATCH_SPLITS {
        let top = heap.peek().map_or(0.0, |p| p.upper);
        if threshold.is_some_and(|t| top < t || lower >= t) {
            break;
        }
        let Some(p) = heap.pop() else { break };
        let (um, vm) = (0.5 * (p.u[0] + p.u[1]), 0.5 * (p.v[0] + p.v[1]));
        if let Some(t) = threshold {
            // The value on the most promising plane: a lower bound that reaches the threshold
            // early where the point can (exact where the coarse directions do not decide).
            let n = face_normal(p.face, um, vm);
            lower = lower.max(fs_plane_reaches(
                &scratch.columns,
                &n,
                g,
                kq,
                t,
                &scratch.directions,
                cos_half_step,
                &mut scratch.shear,
                &mut scratch.hull,
            ));
        }
        for (u, v) in [
            ([p.u[0], um], [p.v[0], vm]),
            ([um, p.u[1]], [p.v[0], vm]),
            ([p.u[0], um], [vm, p.v[1]]),
            ([um, p.u[1]], [vm, p.v[1]]),
        ] {
            let (upper, below) = bounds(p.face, u, v);
            lower = lower.max(below);
            heap.push(Patch {
                // A child's bound never needs to exceed its parent's.
                upper: upper.min(p.upper),
                face: p.face,
                u,
                v,
            });
        }
    }
    heap.peek().map_or(0.0, |p| p.upper).min(path_bound)
}

/// Upper bounds `[Crossland, Dang Van, SWT, Fatemi–Socie]` of every path whose states lie near
/// a reference state (docs/fatigue.md, "Layers the screen cannot reach"): for all `t`,
/// `|y_i(σ(t)) − y_i(σ^ref)| ≤ deviation[i]` (`i < 5`, the deviator coordinates of Eq. F1) and
/// `|σ_H(t) − σ_H^ref| ≤ deviation[5]`. With `D = |(deviation[0..5])|`,
/// `σ_H,max ≤ h = σ_H^ref + deviation[5]` and, by Weyl's inequality and
/// `λ₁(Δs) ≤ √(2/3)‖Δs‖_F = (2/√3)|y(Δs)|`, `σ₁(t) ≤ S₁ = h + λ₁(s^ref) + (2/√3) D`:
///
/// * Crossland `≤ (D + α_C h)/t₋₁` (the ball of radius `D` about `y(σ^ref)` encloses the path);
/// * Dang Van `≤ (D + α_DV h)/t₋₁` (`τ_Tresca(ŝ) ≤ |y(ŝ)| ≤ √J₂,a ≤ D`);
/// * SWT `≤ max(0, S₁) · ((1 + ν)(2/√3) D + (1 − 2ν) deviation[5])/E` (the half range of
///   `ε_n` is at most `max_t |n·(ε(t) − ε^ref)·n|`, `Δε = ((1 + ν)Δs + (1 − 2ν)Δσ_H I)/E`);
/// * Fatemi–Socie `≤ D/G · max(0, 1 + k S₁/σ_y)` (`|m·Δs·n| ≤ (λ₁ − λ₃)(Δs)/2 ≤ |y(Δs)|`).
///
/// `D` is taken `× (1 + 10⁻⁹)` plus `10⁻¹²` of `|y(σ^ref)| + D` for the rounding of the exact
/// ball and of the principal values. [`anchored_bounds`] with the one anchor `σ^ref`.
pub fn reference_bounds(
    reference: &Voigt,
    deviation: &[f64; 6],
    material: &Material,
) -> Result<[f64; 4], FatigueError> {
    material.validate()?;
    check_path(std::slice::from_ref(reference))?;
    check_deviations(std::slice::from_ref(deviation))?;
    let y_ref = deviator_coordinates(reference);
    let y_norm = y_ref.iter().map(|v| v * v).sum::<f64>().sqrt();
    let d = deviation[..5].iter().map(|v| v * v).sum::<f64>().sqrt();
    let d = d * (1.0 + 1e-9) + 1e-12 * (y_norm + d);
    let h = hydrostatic(reference) + deviation[5];
    let lambda1 = principal_values(&deviator(reference))[0] + 1e-12 * y_norm;
    let s1 = h + lambda1 + 2.0 / 3f64.sqrt() * d;
    Ok(enclosure_bounds(d, h, s1, deviation[5], material))
}

/// Upper bounds `[Crossland, Dang Van, SWT, Fatemi–Socie]` of every path whose states lie near
/// the polygon of exact `anchors` (docs/fatigue.md, "Layers the screen cannot reach", the
/// anchored bound): each state is an anchor or `σ(t) = σ̃(t) + Δ(t)` with `σ̃(t)` on the segment
/// between anchors `g` and `g + 1` and `|y_i(Δ(t))| ≤ deviation[g][i]` (`i < 5`, Eq. F1),
/// `|σ_H(Δ(t))| ≤ deviation[g][5]` (`g < deviation.len()`; one anchor and one deviation: the
/// states near that anchor). With `c` the componentwise mid-range of the anchors' `y`,
/// `c_H` that of their `σ_H` and `D_g = |(deviation[g][0..5])|`:
///
/// * every `y(σ(t))` lies in the ball of radius `ρ = max_g (max(|y(a_g) − c|, |y(a_{g+1}) − c|)
///   + D_g)` about `c` (`|y − c|` is convex, so on a segment it is largest at an end), so
///   `√J₂,a ≤ ρ` and `τ_Tresca(ŝ) ≤ ρ`;
/// * `σ_H,max ≤ h = max_g (max(σ_H(a_g), σ_H(a_{g+1})) + deviation[g][5])`, and
///   `|σ_H(t) − c_H| ≤ H = max_g (max |σ_H − c_H| at its ends + deviation[g][5])`;
/// * `σ₁(t) ≤ S₁ = max_g (max σ₁ at its ends + deviation[g][5] + (2/√3) D_g)` (`σ₁` is convex
///   in `σ`; Weyl's inequality and `λ₁(Δs) ≤ (2/√3)|y(Δs)|`);
///
/// and the criteria are bounded as in [`reference_bounds`] with `ρ` for `D` (SWT with `H` for the
/// hydrostatic half range). `ρ` is taken `× (1 + 10⁻⁹)` plus `10⁻¹²` of `max_a |y(a)| + ρ`, the
/// principal values `+ 10⁻¹² max_a |y(a)|`, for the rounding. With no anchor nothing is known:
/// every bound is `+∞` (no level can be ruled out).
pub fn anchored_bounds(
    anchors: &[Voigt],
    deviation: &[[f64; 6]],
    material: &Material,
) -> Result<[f64; 4], FatigueError> {
    material.validate()?;
    check_deviations(deviation)?;
    if anchors.is_empty() {
        return Ok([f64::INFINITY; 4]);
    }
    check_path(anchors)?;
    let mut lo = [f64::INFINITY; 6];
    let mut hi = [f64::NEG_INFINITY; 6];
    let mut y_norm = 0.0f64;
    // Per anchor: y, σ_H, σ₁.
    let states: Vec<([f64; 5], f64, f64)> = anchors
        .iter()
        .map(|a| {
            let y = deviator_coordinates(a);
            let sh = hydrostatic(a);
            for i in 0..5 {
                lo[i] = lo[i].min(y[i]);
                hi[i] = hi[i].max(y[i]);
            }
            lo[5] = lo[5].min(sh);
            hi[5] = hi[5].max(sh);
            y_norm = y_norm.max(y.iter().map(|v| v * v).sum::<f64>().sqrt());
            (y, sh, sh + principal_values(&deviator(a))[0])
        })
        .collect();
    let centre: [f64; 6] = std::array::from_fn(|i| 0.5 * (lo[i] + hi[i]));
    let radius = |y: &[f64; 5]| {
        (0..5)
            .map(|i| (y[i] - centre[i]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let (mut rho, mut h, mut s1, mut range) =
        (0.0f64, f64::NEG_INFINITY, f64::NEG_INFINITY, 0.0f64);
    let last = states.len().saturating_sub(1);
    // The anchors themselves (deviation 0), then each segment's ends widened by its deviation.
    let zero = [[0.0; 6]];
    let spans = states
        .iter()
        .map(|s| (std::slice::from_ref(s), &zero[0]))
        .chain(deviation.iter().enumerate().filter_map(|(g, dev)| {
            states
                .get(g.min(last)..=(g + 1).min(last))
                .map(|ends| (ends, dev))
        }));
    for (ends, dev) in spans {
        let d = dev[..5].iter().map(|v| v * v).sum::<f64>().sqrt();
        for (y, sh, sigma1) in ends {
            rho = rho.max(radius(y) + d);
            h = h.max(sh + dev[5]);
            s1 = s1.max(sigma1 + dev[5] + 2.0 / 3f64.sqrt() * d * (1.0 + 1e-9));
            range = range.max((sh - centre[5]).abs() * (1.0 + 1e-9) + dev[5]);
        }
    }
    let rho = rho * (1.0 + 1e-9) + 1e-12 * (y_norm + rho);
    Ok(enclosure_bounds(
        rho,
        h,
        s1 + 1e-12 * y_norm,
        range,
        material,
    ))
}

/// Deviations of [`reference_bounds`] and [`anchored_bounds`]: finite and non-negative (they are
/// bounds on magnitudes).
fn check_deviations(deviation: &[[f64; 6]]) -> Result<(), FatigueError> {
    for (g, dev) in deviation.iter().enumerate() {
        if let Some((k, &v)) = dev
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
        {
            return Err(FatigueError::InvalidDeviation {
                segment: g,
                component: k,
                value: v,
            });
        }
    }
    Ok(())
}

/// The four bounds of a path whose deviator coordinates lie in a ball of radius `rho` (the
/// ball's norm of Eq. F1), with `σ_H ≤ h`, `σ₁ ≤ s1` and `σ_H` within `hydrostatic_range` of
/// one value ([`reference_bounds`], [`anchored_bounds`]).
fn enclosure_bounds(
    rho: f64,
    h: f64,
    s1: f64,
    hydrostatic_range: f64,
    material: &Material,
) -> [f64; 4] {
    let t = material.t_minus1;
    let crossland = (rho + material.alpha_crossland() * h) / t;
    let dang_van = (rho + material.alpha_dang_van() * h) / t;
    let two_over_root3 = 2.0 / 3f64.sqrt();
    let nu = material.poisson;
    let strain =
        ((1.0 + nu) * two_over_root3 * rho + (1.0 - 2.0 * nu) * hydrostatic_range) / material.young;
    let swt = s1.max(0.0) * strain;
    let fs = rho / material.shear_modulus()
        * (1.0 + material.fs_k * s1 / material.yield_stress).max(0.0);
    [crossland, dang_van, swt, fs]
}

fn path_of(stress: &[f64], p: usize, increments: usize, out: &mut Vec<Voigt>) {
    out.clear();
    out.extend(
        stress[p * increments * 6..(p + 1) * increments * 6]
            .chunks_exact(6)
            .map(|c| [c[0], c[1], c[2], c[3], c[4], c[5]]),
    );
}

/// Crossland and Dang Van at every point, SWT and Fatemi–Socie screened (module doc), of the
/// stress histories `stress[(p · increments + t) · 6 + k]` (the layout of
/// [`crate::evaluate_field`]); point `p` is of material `materials[material_of[p]]`.
/// `fraction ∈ [0, 1]`: 0 evaluates every point exactly (the fields of
/// [`crate::evaluate_field`]), 1 only what the maxima need.
pub fn evaluate_screened(
    stress: &[f64],
    increments: usize,
    materials: &[Material],
    material_of: &[u16],
    params: &FieldParams,
    fraction: f64,
) -> Result<ScreenedIndices, FatigueError> {
    let points = material_of.len();
    if increments == 0 || points == 0 {
        return Err(FatigueError::EmptyPath);
    }
    if increments
        .checked_mul(6)
        .and_then(|n| n.checked_mul(points))
        != Some(stress.len())
    {
        return Err(FatigueError::FieldShape {
            len: stress.len(),
            points,
            increments,
        });
    }
    if !(0.0..=1.0).contains(&fraction) {
        return Err(FatigueError::InvalidMaterial {
            name: "fatemi_socie screening fraction",
            value: fraction,
            reason: "must lie in [0, 1]",
        });
    }
    for m in materials {
        m.validate()?;
    }
    params.plane.validate()?;
    if let Some(&m) = material_of.iter().find(|&&m| m as usize >= materials.len()) {
        return Err(FatigueError::InvalidMaterial {
            name: "material index of a point",
            value: m as f64,
            reason: "must name one of the materials",
        });
    }
    if let Some((i, &value)) = stress.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(FatigueError::NonFiniteField {
            point: i / (increments * 6),
            increment: (i % (increments * 6)) / 6,
            component: i % 6,
            value,
        });
    }
    // Pass 1: the four bounds at every point (O(increments) each).
    let bounds: Vec<[f64; 4]> = (0..points)
        .into_par_iter()
        .map_init(Vec::new, |path, p| {
            path_of(stress, p, increments, path);
            let material = &materials[material_of[p] as usize];
            let [c, dv] = invariant_bounds_unchecked(path, material);
            let [s, f] = critical_plane_bounds_unchecked(path, material);
            [c, dv, s, f]
        })
        .collect();
    let bound = |which: usize| -> Vec<f64> { bounds.iter().map(|b| b[which]).collect() };
    // Pass 2: each criterion in decreasing order of its bound; Crossland and Dang Van from one
    // ball, so a point evaluated for one holds both.
    let invariant = |p: usize,
                     scratch: &mut (Vec<Voigt>, InvariantScratch)|
     -> Result<[f64; 2], FatigueError> {
        path_of(stress, p, increments, &mut scratch.0);
        let material = &materials[material_of[p] as usize];
        let (c, dv) = crossland_dang_van(&scratch.0, material, &mut scratch.1)?;
        Ok([c.index, dv.index])
    };
    let mut fields = [vec![f64::NAN; points], vec![f64::NAN; points]];
    let mut done = vec![false; points];
    let mut best = [f64::NEG_INFINITY; 2];
    let mut invariant_evaluated = 0;
    for which in 0..2 {
        invariant_evaluated += screen(
            &bound(which),
            fraction,
            which,
            &mut best,
            &mut fields,
            &mut done,
            &invariant,
            None,
        )?;
    }
    let [crossland, dang_van] = fields;
    let plane = |which: usize| {
        move |p: usize,
              scratch: &mut (Vec<Voigt>, PlaneScratch)|
              -> Result<[f64; 1], FatigueError> {
            path_of(stress, p, increments, &mut scratch.0);
            let material = &materials[material_of[p] as usize];
            Ok([if which == 0 {
                swt(&scratch.0, material, &params.plane, &mut scratch.1)?.value
            } else {
                fatemi_socie(&scratch.0, material, &params.plane, &mut scratch.1)?.value
            }])
        }
    };
    let critical = |which: usize| -> Result<(Vec<f64>, usize), FatigueError> {
        let mut field = [vec![f64::NAN; points]];
        let mut done = vec![false; points];
        let mut best = [f64::NEG_INFINITY];
        // Fatemi–Socie: the cells the path bound keeps are bounded again per plane patch
        // (fatemi_socie_patch_bound) before the exact search.
        let patch_bound = |p: usize, threshold: f64, scratch: &mut (Vec<Voigt>, PatchScratch)| {
            path_of(stress, p, increments, &mut scratch.0);
            let material = &materials[material_of[p] as usize];
            fatemi_socie_patch_bound_unchecked(
                &scratch.0,
                material,
                Some(threshold),
                &mut scratch.1,
            )
        };
        let refine: Option<&Refine<'_>> = if which == 1 { Some(&patch_bound) } else { None };
        let count = screen(
            &bound(2 + which),
            fraction,
            0,
            &mut best,
            &mut field,
            &mut done,
            &plane(which),
            refine,
        )?;
        let [field] = field;
        Ok((field, count))
    };
    let (swt_field, swt_evaluated) = critical(0)?;
    let (fs_field, fatemi_socie_evaluated) = critical(1)?;
    let nan_max = |f: &[f64]| {
        let cleaned: Vec<f64> = f
            .iter()
            .map(|v| if v.is_nan() { f64::NEG_INFINITY } else { *v })
            .collect();
        Maximum::of(&cleaned)
    };
    Ok(ScreenedIndices {
        crossland_max: nan_max(&crossland),
        dang_van_max: nan_max(&dang_van),
        swt_max: nan_max(&swt_field),
        fatemi_socie_max: nan_max(&fs_field),
        crossland,
        dang_van,
        swt: swt_field,
        fatemi_socie: fs_field,
        invariant_evaluated,
        swt_evaluated,
        fatemi_socie_evaluated,
    })
}

/// The `K` criteria of point `p` with a worker's path buffer and scratch.
type PointCriteria<'a, const K: usize, S> =
    dyn Fn(usize, &mut (Vec<Voigt>, S)) -> Result<[f64; K], FatigueError> + Sync + 'a;

/// A second, tighter (and dearer) upper bound of a point's criterion.
/// `refine(p, threshold, scratch)` may stop refining once it knows on which side of
/// `threshold` the point lies.
type Refine<'a> = dyn Fn(usize, f64, &mut (Vec<Voigt>, PatchScratch)) -> f64 + Sync + 'a;

/// Buffers shared by the workers of successive parallel batches.
struct Pool<T>(std::sync::Mutex<Vec<T>>);

impl<T> Default for Pool<T> {
    fn default() -> Self {
        Self(std::sync::Mutex::new(Vec::new()))
    }
}

impl<T: Default> Pool<T> {
    /// A buffer of the pool (a new one if none is free), returned to it when dropped.
    fn take(&self) -> Pooled<'_, T> {
        let item = self
            .0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .pop()
            .unwrap_or_default();
        Pooled {
            item: Some(item),
            pool: self,
        }
    }
}

/// A buffer taken from a [`Pool`].
struct Pooled<'a, T> {
    item: Option<T>,
    pool: &'a Pool<T>,
}

impl<T: Default> Pooled<'_, T> {
    fn get(&mut self) -> &mut T {
        self.item.get_or_insert_with(T::default)
    }
}

impl<T> Drop for Pooled<'_, T> {
    fn drop(&mut self) {
        if let Some(item) = self.item.take() {
            self.pool
                .0
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(item);
        }
    }
}

/// Orders `order[sorted..]` far enough that `order[..end]` (at least) holds the indices of the
/// largest `key` in decreasing order, ties by increasing index — for indices given in increasing
/// order the prefix a stable sort by decreasing `key` gives, without sorting the rest: the next
/// block (at least `end − sorted`, at least 256 and at least `sorted`, so the blocks double) is
/// selected (`select_nth_unstable_by`, linear) and sorted. `order[..sorted]` must already be
/// so ordered and precede the rest; returns the new `sorted`.
pub fn largest_first(
    order: &mut [usize],
    sorted: usize,
    end: usize,
    key: impl Fn(usize) -> f64,
) -> usize {
    let end = end.min(order.len());
    if end <= sorted {
        return sorted;
    }
    let block = (end - sorted)
        .max(sorted)
        .max(256)
        .min(order.len() - sorted);
    let descending = |x: &usize, y: &usize| key(*y).total_cmp(&key(*x)).then(x.cmp(y));
    let rest = &mut order[sorted..];
    if block < rest.len() {
        rest.select_nth_unstable_by(block - 1, descending);
    }
    rest[..block].sort_unstable_by(descending);
    sorted + block
}

/// One screen (module doc): the points not yet `done`, in decreasing order of `bound`, evaluated
/// by `eval` (`K` values per point into `fields`, `best` their running maxima) in parallel batches
/// of 16, until the next bound is below `fraction × best[which]` (with `fraction > 0` and
/// `best[which] > 0`). With `refine`, a point of a batch whose refined bound is below
/// `fraction × best[which]` (as at the batch's start) is skipped: since `best` never exceeds the
/// maximum, every point reaching `fraction ×` the maximum is still evaluated. Returns the number
/// of points evaluated.
#[allow(clippy::too_many_arguments)]
fn screen<const K: usize, S: Default + Send>(
    bound: &[f64],
    fraction: f64,
    which: usize,
    best: &mut [f64; K],
    fields: &mut [Vec<f64>; K],
    done: &mut [bool],
    eval: &PointCriteria<'_, K, S>,
    refine: Option<&Refine<'_>>,
) -> Result<usize, FatigueError> {
    // Ordered lazily: only the prefix the batches reach is selected and sorted.
    let mut order: Vec<usize> = (0..bound.len()).filter(|&p| !done[p]).collect();
    let mut sorted = 0;
    let batch = 16;
    // Workers' buffers kept across batches (the critical-plane scratch builds its lattice
    // neighbour lists once).
    let eval_pool: Pool<(Vec<Voigt>, S)> = Pool::default();
    let refine_pool: Pool<(Vec<Voigt>, PatchScratch)> = Pool::default();
    let mut next = 0;
    let mut evaluated = 0;
    let mut kept = Vec::with_capacity(batch);
    while next < order.len() {
        sorted = largest_first(&mut order, sorted, next + batch, |p| bound[p]);
        let b = best[which];
        let below = |value: f64| fraction > 0.0 && b > 0.0 && value < fraction * b;
        if below(bound[order[next]]) {
            break;
        }
        let end = (next + batch).min(order.len());
        kept.clear();
        match refine {
            Some(refine) if fraction > 0.0 && b > 0.0 => {
                let threshold = fraction * b;
                let tight: Vec<f64> = order[next..end]
                    .par_iter()
                    .map_init(
                        || refine_pool.take(),
                        |scratch, &p| refine(p, threshold, scratch.get()),
                    )
                    .collect();
                kept.extend(
                    order[next..end]
                        .iter()
                        .zip(tight)
                        .filter(|(_, t)| !below(*t))
                        .map(|(&p, _)| p),
                );
            }
            _ => kept.extend_from_slice(&order[next..end]),
        }
        let values: Vec<[f64; K]> = kept
            .par_iter()
            .map_init(|| eval_pool.take(), |scratch, &p| eval(p, scratch.get()))
            .collect::<Result<_, FatigueError>>()?;
        for (&p, v) in kept.iter().zip(values) {
            done[p] = true;
            for k in 0..K {
                fields[k][p] = v[k];
                best[k] = best[k].max(v[k]);
            }
        }
        evaluated += kept.len();
        next = end;
    }
    Ok(evaluated)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tensor::principal_values;

    fn shear(s: &Voigt, n: &[f64; 3]) -> [f64; 3] {
        let w = [
            s[0] * n[0] + s[5] * n[1] + s[4] * n[2],
            s[5] * n[0] + s[1] * n[1] + s[3] * n[2],
            s[4] * n[0] + s[3] * n[1] + s[2] * n[2],
        ];
        let f = w[0] * n[0] + w[1] * n[1] + w[2] * n[2];
        std::array::from_fn(|i| w[i] - f * n[i])
    }

    fn on_circle(n: &[f64; 3], e: &[f64; 3], phi: f64) -> [f64; 3] {
        std::array::from_fn(|i| n[i] * phi.cos() + e[i] * phi.sin())
    }

    struct Lcg(u64);
    impl Lcg {
        fn uniform(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    /// `L e` of [`shear_on_patch_bound`] is `dτ/dφ` at `φ = 0` (central differences, step
    /// 1e-5: error O(h²) ≈ 1e-10 relative), and the bound holds at 200 normals inside the cap of
    /// every radius on random tensors (fixed seed).
    #[test]
    fn second_order_shear_bound_holds_and_its_derivative_matches_differences() {
        let mut rng = Lcg(11);
        for _ in 0..200 {
            let s: Voigt = std::array::from_fn(|_| 1e8 * rng.uniform());
            let n = {
                let x = [rng.uniform(), rng.uniform(), rng.uniform()];
                let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
                [x[0] / r, x[1] / r, x[2] / r]
            };
            let basis = tangent_basis(&n);
            let p = principal_values(&s);
            let rho = 0.5 * (p[0] - p[2]);
            let t0 = shear(&s, &n);
            let sn = (0..3).map(|i| n[i] * (s_apply(&s, &n)[i])).sum::<f64>();
            for e in [basis.0, basis.1] {
                let h = 1e-5;
                let (a, b) = (
                    shear(&s, &on_circle(&n, &e, h)),
                    shear(&s, &on_circle(&n, &e, -h)),
                );
                let se = s_apply(&s, &e);
                let te: f64 = (0..3).map(|i| t0[i] * e[i]).sum();
                for i in 0..3 {
                    let fd = (a[i] - b[i]) / (2.0 * h);
                    let l = se[i] - 2.0 * te * n[i] - sn * e[i];
                    assert!((fd - l).abs() <= 1e-8 * 1e8, "{fd} vs {l}");
                }
            }
            for theta in [0.3, 0.1, 0.01] {
                let bound = shear_on_patch_bound(&s, &n, &basis, theta, rho);
                for _ in 0..200 {
                    let psi = std::f64::consts::PI * rng.uniform();
                    let phi = theta * rng.uniform().abs();
                    let e: [f64; 3] =
                        std::array::from_fn(|i| psi.cos() * basis.0[i] + psi.sin() * basis.1[i]);
                    let t = shear(&s, &on_circle(&n, &e, phi));
                    let norm = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
                    assert!(norm <= bound * (1.0 + 1e-12), "{norm} > {bound}");
                }
            }
        }
    }

    fn s_apply(s: &Voigt, x: &[f64; 3]) -> [f64; 3] {
        [
            s[0] * x[0] + s[5] * x[1] + s[4] * x[2],
            s[5] * x[0] + s[1] * x[1] + s[3] * x[2],
            s[4] * x[0] + s[3] * x[1] + s[2] * x[2],
        ]
    }

    /// At the plane of maximum shear (where `|τ|` is stationary) the bound's margin over the
    /// maximum shear `ρ` is second order: it falls 4× when `θ` halves (observed ratio within
    /// 3.9–4.1 from θ = 0.1 down to 0.0125), where the first-order margin `θ (λ₁ − λ₃)` halves.
    #[test]
    fn second_order_margin_at_the_maximum_shear_plane() {
        let s: Voigt = [2e8, 5e7, -1e8, 0.0, 0.0, 0.0];
        let rho = 0.5 * (2e8 + 1e8);
        let r = 0.5f64.sqrt();
        let n = [r, 0.0, r];
        let basis = tangent_basis(&n);
        let margin = |theta: f64| shear_on_patch_bound(&s, &n, &basis, theta, rho) - rho;
        let mut theta = 0.1;
        while theta > 0.01 {
            let ratio = margin(theta) / margin(0.5 * theta);
            assert!((3.9..=4.1).contains(&ratio), "θ = {theta}: ratio {ratio}");
            assert!(margin(theta) < 0.5 * theta * 2.0 * rho, "{}", margin(theta));
            theta *= 0.5;
        }
    }
}
