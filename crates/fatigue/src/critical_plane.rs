//! Critical-plane criteria: Smith–Watson–Topper (1970) and Fatemi–Socie (1988), maximised over
//! material planes by a coarse covering of the hemisphere and local refinement to a stated
//! angular tolerance (docs/fatigue.md, Eqs. F5–F7 and "Critical-plane search").
//!
//! On the plane of unit normal `n` the normal stress is `σ_n(t) = n·σ(t)·n`, the shear traction
//! along a unit in-plane direction `m` is `τ_nm(t) = m·σ(t)·n`; by isotropic Hooke's law
//! `ε_n = ((1 + ν) σ_n − ν tr σ)/E` and the engineering shear strain is `γ_nm = 2 m·ε·n = τ_nm/G`.
use crate::error::FatigueError;
use crate::invariant::check_path;
use crate::material::Material;
use crate::tensor::{bilinear_weights, dot6, Voigt};

/// Coarse normals whose value is more than this fraction of the best coarse value below it are
/// not refined: refinement gains less than the coarse lattice's error (measured < 3 % at the
/// default spacing on random paths).
pub const CANDIDATE_WINDOW: f64 = 0.25;
/// Above this many coarse normals the candidates are chosen greedily at least
/// [`CANDIDATE_SEPARATION`] apart instead of as lattice local maxima (the neighbour lists cost
/// `O(N²)` once per scratch).
pub const NEIGHBOUR_LISTS_UP_TO: usize = 4000;
/// Lattice neighbours are the normals within this many coarse spacings `h` (the Fibonacci
/// lattice's nearest neighbours lie at 0.8–1.1 h).
pub const NEIGHBOUR_RADIUS: f64 = 1.1;
/// Candidates are at least this many coarse spacings apart (as planes).
pub const CANDIDATE_SEPARATION: f64 = 1.0;
/// Pair screening is used for compass steps up to this angle (rad); above, the radius `4h`
/// would keep most pairs.
const SCREEN_ABOVE_STEP: f64 = 0.005;
/// Rounds of escape probes after Fatemi–Socie's exact refinement.
const ESCAPE_ROUNDS: usize = 3;
/// Most candidates refined per search.
pub const MAX_CANDIDATES: usize = 16;
/// Safety margin of the phase-2 pruning of Fatemi–Socie (covers the gain of refining below
/// `FS_EXACT_BELOW`).
const PRUNE_MARGIN: f64 = 0.05;
/// Fatemi–Socie's refinement uses the coarse in-plane directions while its step is above this
/// angle (rad), then the exact maximum over directions.
pub const FS_EXACT_BELOW: f64 = 0.02;

/// Parameters of the critical-plane search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CriticalPlaneParams {
    /// Normals of the coarse covering of the hemisphere (Fibonacci lattice, mean spacing
    /// `√(2π/N)`; default 400 → 7.2°).
    pub coarse_normals: usize,
    /// In-plane directions over `[0, π)` of Fatemi–Socie's coarse stage (default 12 → 15°);
    /// the refinement maximises over directions exactly.
    pub coarse_directions: usize,
    /// Local maxima of the coarse lattice refined (default 4).
    pub candidates: usize,
    /// The compass refinement stops when its step is below this angle, rad (default 1e-4).
    /// This bounds the error on the local maximum found (~1e-8 relative for smooth maxima), not
    /// whether it is the global one (docs/fatigue.md, "Accuracy of the critical-plane search").
    pub angular_tolerance: f64,
}

impl Default for CriticalPlaneParams {
    fn default() -> Self {
        Self {
            coarse_normals: 400,
            coarse_directions: 12,
            candidates: 4,
            angular_tolerance: 1e-4,
        }
    }
}

impl CriticalPlaneParams {
    /// Checks `8 ≤ coarse_normals ≤ 10⁶`, `2 ≤ coarse_directions ≤ 10⁴`,
    /// `1 ≤ candidates ≤ 16`, `0 < angular_tolerance ≤ 0.1`.
    pub fn validate(&self) -> Result<(), FatigueError> {
        let bad = |name, value: usize, reason| {
            Err(FatigueError::InvalidSearch {
                name,
                value: value as f64,
                reason,
            })
        };
        if !(8..=1_000_000).contains(&self.coarse_normals) {
            return bad(
                "coarse_normals",
                self.coarse_normals,
                "must lie in 8 ..= 1e6",
            );
        }
        if !(2..=10_000).contains(&self.coarse_directions) {
            return bad(
                "coarse_directions",
                self.coarse_directions,
                "must lie in 2 ..= 1e4",
            );
        }
        if self.candidates == 0 || self.candidates > MAX_CANDIDATES {
            return bad("candidates", self.candidates, "must lie in 1 ..= 16");
        }
        if !(self.angular_tolerance > 0.0 && self.angular_tolerance <= 0.1) {
            return Err(FatigueError::InvalidSearch {
                name: "angular_tolerance",
                value: self.angular_tolerance,
                reason: "must lie in (0, 0.1] rad",
            });
        }
        Ok(())
    }

    /// Mean spacing of the coarse normals `√(2π/N)`, rad: the first compass step.
    pub fn coarse_spacing(&self) -> f64 {
        (2.0 * std::f64::consts::PI / self.coarse_normals as f64).sqrt()
    }
}

/// Smith–Watson–Topper on the critical plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Swt {
    /// `σ_n,max · ε_a`, Pa.
    pub value: f64,
    /// The critical normal (unit; `n` and `−n` are the same plane).
    pub normal: [f64; 3],
    /// `σ_n,max` on that plane, Pa.
    pub normal_stress_max: f64,
    /// `ε_a = (max_t ε_n − min_t ε_n)/2` on that plane.
    pub strain_amplitude: f64,
    /// Planes evaluated.
    pub evaluations: usize,
}

/// Fatemi–Socie on the critical plane and direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FatemiSocie {
    /// `γ_a (1 + k σ_n,max/σ_y)` (dimensionless).
    pub value: f64,
    /// The critical normal (unit).
    pub normal: [f64; 3],
    /// The critical in-plane shear direction `m ⊥ n` (unit).
    pub direction: [f64; 3],
    /// `γ_a`: half the range of `γ_nm` along `direction`.
    pub shear_strain_amplitude: f64,
    /// `σ_n,max` on the plane, Pa.
    pub normal_stress_max: f64,
    /// Planes evaluated.
    pub evaluations: usize,
}

/// Reusable buffers of the critical-plane search (no allocation once grown).
#[derive(Clone, Debug, Default)]
pub struct PlaneScratch {
    coarse: Vec<[f64; 3]>,
    directions: Vec<[f64; 2]>,
    values: Vec<f64>,
    chosen: Vec<usize>,
    trace: Vec<f64>,
    shear: Vec<[f64; 2]>,
    hull: Vec<[f64; 2]>,
    pair_norms: Vec<f64>,
    active: Vec<(u32, u32)>,
    used: Vec<u32>,
    columns: PathColumns,
    neighbours: Vec<u32>,
    neighbour_start: Vec<usize>,
}

impl PlaneScratch {
    fn prepare(&mut self, params: &CriticalPlaneParams, path: &[Voigt]) {
        if self.coarse.len() != params.coarse_normals {
            self.coarse.clear();
            self.coarse.extend(
                (0..params.coarse_normals).map(|i| fibonacci_normal(i, params.coarse_normals)),
            );
            // Lattice neighbours (as planes, within NEIGHBOUR_RADIUS h) for the local-maximum test.
            self.neighbour_start.clear();
            self.neighbours.clear();
            if self.coarse.len() <= NEIGHBOUR_LISTS_UP_TO {
                let cos_r = (NEIGHBOUR_RADIUS * params.coarse_spacing()).cos();
                for (i, a) in self.coarse.iter().enumerate() {
                    self.neighbour_start.push(self.neighbours.len());
                    for (j, b) in self.coarse.iter().enumerate() {
                        if i != j && (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]).abs() > cos_r {
                            self.neighbours.push(j as u32);
                        }
                    }
                }
                self.neighbour_start.push(self.neighbours.len());
            }
        }
        if self.directions.len() != params.coarse_directions {
            in_plane_directions(params.coarse_directions, &mut self.directions);
        }
        self.trace.clear();
        self.trace.extend(path.iter().map(|s| s[0] + s[1] + s[2]));
        self.columns.fill(path);
    }
}

/// The `i`-th of `n` normals of the Fibonacci lattice on the upper hemisphere: `z = (i + ½)/n`
/// (equal areas), azimuth `i·π(3 − √5)`.
pub fn fibonacci_normal(i: usize, n: usize) -> [f64; 3] {
    let z = (i as f64 + 0.5) / n as f64;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = i as f64 * std::f64::consts::PI * (3.0 - 5f64.sqrt());
    [r * phi.cos(), r * phi.sin(), z]
}

/// An orthonormal basis `(u, v)` of the plane normal to the unit vector `n`, `u × v = n`.
pub fn tangent_basis(n: &[f64; 3]) -> ([f64; 3], [f64; 3]) {
    let k = (0..3)
        .min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
        .unwrap_or(0);
    let mut e = [0.0; 3];
    e[k] = 1.0;
    let u = normalize(cross(&e, n));
    let v = cross(n, &u);
    (u, v)
}

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

/// A user's plane normal scaled to unit length: `n/|n|`, refused when `n` has a non-finite
/// component or is zero (it names no plane). Scaled by its largest component first, so that
/// normals like `[1e200, 0, 0]` or `[1e-200, 0, 0]` neither overflow nor underflow.
fn unit_normal(n: &[f64; 3]) -> Result<[f64; 3], FatigueError> {
    if let Some(&bad) = n.iter().find(|c| !c.is_finite()) {
        return Err(FatigueError::InvalidSearch {
            name: "normal",
            value: bad,
            reason: "a plane normal's components must be finite",
        });
    }
    let scale = n.iter().fold(0.0_f64, |m, c| m.max(c.abs()));
    if scale == 0.0 {
        return Err(FatigueError::InvalidSearch {
            name: "normal",
            value: 0.0,
            reason: "a zero vector is not a plane normal",
        });
    }
    Ok(normalize([n[0] / scale, n[1] / scale, n[2] / scale]))
}

/// SWT on the plane `n`: `σ_n,max · (max_t ε_n − min_t ε_n)/2` with
/// `ε_n = ((1 + ν) σ_n − ν tr σ)/E` (Smith, Watson & Topper 1970; docs/fatigue.md, Eq. F5).
/// Returns `(value, σ_n,max, ε_a)`.
fn swt_plane(path: &[Voigt], trace: &[f64], n: &[f64; 3], young: f64, nu: f64) -> [f64; 3] {
    let w = bilinear_weights(n, n);
    let (mut smax, mut emin, mut emax) = (f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    // Plain comparisons (the path is finite): `f64::max` pays for NaN handling here.
    for (s, tr) in path.iter().zip(trace) {
        let sn = dot6(&w, s);
        let en = (1.0 + nu) * sn - nu * tr;
        smax = if sn > smax { sn } else { smax };
        emin = if en < emin { en } else { emin };
        emax = if en > emax { en } else { emax };
    }
    let ea = 0.5 * (emax - emin) / young;
    [smax * ea, smax, ea]
}

/// SWT on the given plane (unit normal `n`), see [`swt`]; `evaluations = 1`.
pub fn swt_on_plane(
    path: &[Voigt],
    material: &Material,
    n: &[f64; 3],
) -> Result<Swt, FatigueError> {
    material.validate_elastic()?;
    check_path(path)?;
    let n = unit_normal(n)?;
    let trace: Vec<f64> = path.iter().map(|s| s[0] + s[1] + s[2]).collect();
    let [value, smax, ea] = swt_plane(path, &trace, &n, material.young, material.poisson);
    Ok(Swt {
        value,
        normal: n,
        normal_stress_max: smax,
        strain_amplitude: ea,
        evaluations: 1,
    })
}

/// Smith–Watson–Topper (1970) on the critical plane: `max_n σ_n,max(n) · ε_a(n)`, Pa, with
/// `ε_a(n) = (max_t ε_n − min_t ε_n)/2` and `ε_n` from isotropic Hooke's law (docs/fatigue.md,
/// Eq. F5). The value is not clipped: a plane always in compression gives a negative product.
/// Search: the `coarse_normals` Fibonacci normals, then compass refinement of the best
/// `candidates` lattice local maxima to `angular_tolerance` ([`CriticalPlaneParams`];
/// docs/fatigue.md, "Critical-plane search" — a local search: see its accuracy there).
pub fn swt(
    path: &[Voigt],
    material: &Material,
    params: &CriticalPlaneParams,
    scratch: &mut PlaneScratch,
) -> Result<Swt, FatigueError> {
    material.validate_elastic()?;
    params.validate()?;
    check_path(path)?;
    scratch.prepare(params, path);
    let (young, nu) = (material.young, material.poisson);
    let trace = std::mem::take(&mut scratch.trace);
    scratch.values.clear();
    for n in &scratch.coarse {
        scratch
            .values
            .push(swt_plane(path, &trace, n, young, nu)[0]);
    }
    let mut evaluations = scratch.coarse.len();
    choose_candidates(scratch, params);
    let mut best = (f64::NEG_INFINITY, [0.0, 0.0, 1.0]);
    for c in 0..scratch.chosen.len() {
        let i = scratch.chosen[c];
        let (n, v, evals) = refine(
            |n, _| swt_plane(path, &trace, n, young, nu)[0],
            scratch.coarse[i],
            scratch.values[i],
            0.5 * params.coarse_spacing(),
            params.angular_tolerance,
        );
        evaluations += evals;
        if v > best.0 {
            best = (v, n);
        }
    }
    let [value, smax, ea] = swt_plane(path, &trace, &best.1, young, nu);
    scratch.trace = trace;
    Ok(Swt {
        value,
        normal: best.1,
        normal_stress_max: smax,
        strain_amplitude: ea,
        evaluations,
    })
}

/// The path's six Voigt components as columns over the increments, filled once per path: the
/// per-normal sums `w·σ(t)` of [`shear_path`] then run over contiguous increments (vectorised),
/// with the arithmetic of [`dot6`] term for term.
#[derive(Clone, Debug, Default)]
pub(crate) struct PathColumns {
    columns: [Vec<f64>; 6],
}

impl PathColumns {
    pub(crate) fn new(path: &[Voigt]) -> Self {
        let mut c = Self::default();
        c.fill(path);
        c
    }

    pub(crate) fn fill(&mut self, path: &[Voigt]) {
        for (k, column) in self.columns.iter_mut().enumerate() {
            column.clear();
            column.extend(path.iter().map(|s| s[k]));
        }
    }

    fn len(&self) -> usize {
        self.columns[0].len()
    }

    /// `w·σ(t)` at increment `t`, the sum in [`dot6`]'s order.
    #[inline]
    fn dot(&self, w: &[f64; 6], t: usize) -> f64 {
        let c = &self.columns;
        w[0] * c[0][t]
            + w[1] * c[1][t]
            + w[2] * c[2][t]
            + w[3] * c[3][t]
            + w[4] * c[4][t]
            + w[5] * c[5][t]
    }

    /// `σ_n,max = max_t w·σ(t)`: the value of a running `>` comparison over `t` (the first of
    /// equal maxima), taken in four interleaved lanes (vectorised) — the same value, since the
    /// sums are finite; only a zero maximum could differ (in its sign) and is taken again in order.
    fn max_dot(&self, w: &[f64; 6]) -> f64 {
        let [c0, c1, c2, c3, c4, c5] = &self.columns;
        let m = self.len();
        let (c0, c1, c2, c3, c4, c5) = (&c0[..m], &c1[..m], &c2[..m], &c3[..m], &c4[..m], &c5[..m]);
        let sum = |t: usize| {
            w[0] * c0[t] + w[1] * c1[t] + w[2] * c2[t] + w[3] * c3[t] + w[4] * c4[t] + w[5] * c5[t]
        };
        let mut lanes = [f64::NEG_INFINITY; 4];
        let whole = m - m % 4;
        for t0 in (0..whole).step_by(4) {
            for (j, lane) in lanes.iter_mut().enumerate() {
                let sn = sum(t0 + j);
                *lane = if sn > *lane { sn } else { *lane };
            }
        }
        let mut smax = f64::NEG_INFINITY;
        for lane in lanes.into_iter().chain((whole..m).map(sum)) {
            smax = if lane > smax { lane } else { smax };
        }
        if smax == 0.0 {
            smax = f64::NEG_INFINITY;
            for t in 0..m {
                let sn = sum(t);
                smax = if sn > smax { sn } else { smax };
            }
        }
        smax
    }
}

/// The shear traction components `(u·σ·n, v·σ·n)` over the path into `shear`; returns `σ_n,max`.
fn shear_path(
    path: &PathColumns,
    n: &[f64; 3],
    shear: &mut Vec<[f64; 2]>,
) -> (f64, [f64; 3], [f64; 3]) {
    let (u, v) = tangent_basis(n);
    let (wn, wu, wv) = (
        bilinear_weights(n, n),
        bilinear_weights(&u, n),
        bilinear_weights(&v, n),
    );
    let m = path.len();
    let [c0, c1, c2, c3, c4, c5] = &path.columns;
    let (c0, c1, c2, c3, c4, c5) = (&c0[..m], &c1[..m], &c2[..m], &c3[..m], &c4[..m], &c5[..m]);
    shear.clear();
    shear.extend((0..m).map(|t| {
        [
            wu[0] * c0[t]
                + wu[1] * c1[t]
                + wu[2] * c2[t]
                + wu[3] * c3[t]
                + wu[4] * c4[t]
                + wu[5] * c5[t],
            wv[0] * c0[t]
                + wv[1] * c1[t]
                + wv[2] * c2[t]
                + wv[3] * c3[t]
                + wv[4] * c4[t]
                + wv[5] * c5[t],
        ]
    }));
    (path.max_dot(&wn), u, v)
}

/// Fatemi–Socie on the plane `n` maximised exactly over in-plane directions: the half range of
/// `τ_nm(t) = m·τ(t)` maximised over unit `m` is half the diameter of the planar shear path
/// `{τ(t)}` (docs/fatigue.md, Eq. F7). Returns `(value, γ_a, σ_n,max, m)`.
fn fs_plane_exact(
    path: &PathColumns,
    n: &[f64; 3],
    g: f64,
    k_over_sy: f64,
    shear: &mut Vec<[f64; 2]>,
    hull: &mut Vec<[f64; 2]>,
) -> (f64, f64, f64, [f64; 3]) {
    let (smax, u, v) = shear_path(path, n, shear);
    let (d2, d) = diameter(shear, hull);
    let gamma_a = 0.5 * d2.sqrt() / g;
    let m = if d2 > 0.0 {
        normalize([
            d[0] * u[0] + d[1] * v[0],
            d[0] * u[1] + d[1] * v[1],
            d[0] * u[2] + d[1] * v[2],
        ])
    } else {
        u
    };
    (gamma_a * (1.0 + k_over_sy * smax), gamma_a, smax, m)
}

/// Fatemi–Socie on the plane `n` (unit), exact over in-plane directions, with the caller's
/// buffers (`g` the shear modulus, `k_over_sy = k/σ_y`): a lower bound of [`fatemi_socie`]'s
/// maximum over planes.
pub(crate) fn fs_plane_value(
    path: &PathColumns,
    n: &[f64; 3],
    g: f64,
    k_over_sy: f64,
    shear: &mut Vec<[f64; 2]>,
    hull: &mut Vec<[f64; 2]>,
) -> f64 {
    fs_plane_exact(path, n, g, k_over_sy, shear, hull).0
}

/// Whether Fatemi–Socie on the plane `n` (unit) reaches `threshold`, with the caller's buffers:
/// first on the in-plane `directions` (`M` of them over `[0, π)`: a lower bound within the factor
/// `cos(π/2M)` of the exact value), the exact value ([`fs_plane_value`], the convex hull) only
/// when that one can still reach `threshold` (`coarse ≥ threshold · cos(π/2M)`); `cos_half_step`
/// is `cos(π/2M)`. Returns a lower bound of the plane's value that is `≥ threshold` if the exact
/// value is.
#[allow(clippy::too_many_arguments)]
pub(crate) fn fs_plane_reaches(
    path: &PathColumns,
    n: &[f64; 3],
    g: f64,
    k_over_sy: f64,
    threshold: f64,
    directions: &[[f64; 2]],
    cos_half_step: f64,
    shear: &mut Vec<[f64; 2]>,
    hull: &mut Vec<[f64; 2]>,
) -> f64 {
    let coarse = fs_plane_coarse(path, n, g, k_over_sy, directions, shear);
    // 1e-9: the rounding of the two evaluations, only ever to compute the exact value more often.
    if coarse >= threshold || coarse < threshold * cos_half_step * (1.0 - 1e-9) {
        return coarse;
    }
    fs_plane_value(path, n, g, k_over_sy, shear, hull).max(coarse)
}

/// The `m` in-plane directions `(cos ψ, sin ψ)`, `ψ = jπ/m`, of the coarse stage.
pub(crate) fn in_plane_directions(m: usize, out: &mut Vec<[f64; 2]>) {
    out.clear();
    out.extend((0..m).map(|j| {
        let psi = std::f64::consts::PI * j as f64 / m as f64;
        [psi.cos(), psi.sin()]
    }));
}

/// Fatemi–Socie on the coarse in-plane directions `directions` (lower bound of the exact value).
fn fs_plane_coarse(
    path: &PathColumns,
    n: &[f64; 3],
    g: f64,
    k_over_sy: f64,
    directions: &[[f64; 2]],
    shear: &mut Vec<[f64; 2]>,
) -> f64 {
    let (smax, _, _) = shear_path(path, n, shear);
    let mut range: f64 = 0.0;
    // Directions in blocks of 8, the increments inside: plain comparisons, vectorisable.
    for block in directions.chunks(8) {
        let mut lo = [f64::INFINITY; 8];
        let mut hi = [f64::NEG_INFINITY; 8];
        for t in shear.iter() {
            for (j, m) in block.iter().enumerate() {
                let x = t[0] * m[0] + t[1] * m[1];
                lo[j] = if x < lo[j] { x } else { lo[j] };
                hi[j] = if x > hi[j] { x } else { hi[j] };
            }
        }
        for j in 0..block.len() {
            let r = hi[j] - lo[j];
            range = if r > range { r } else { range };
        }
    }
    0.5 * range / g * (1.0 + k_over_sy * smax)
}

/// Fatemi–Socie on the given plane (unit normal `n`), exact over in-plane directions; see
/// [`fatemi_socie`].
pub fn fatemi_socie_on_plane(
    path: &[Voigt],
    material: &Material,
    n: &[f64; 3],
) -> Result<FatemiSocie, FatigueError> {
    material.validate_fatemi_socie()?;
    check_path(path)?;
    let n = unit_normal(n)?;
    let (mut shear, mut hull) = (Vec::new(), Vec::new());
    let (value, gamma_a, smax, m) = fs_plane_exact(
        &PathColumns::new(path),
        &n,
        material.shear_modulus(),
        material.fs_k / material.yield_stress,
        &mut shear,
        &mut hull,
    );
    Ok(FatemiSocie {
        value,
        normal: n,
        direction: m,
        shear_strain_amplitude: gamma_a,
        normal_stress_max: smax,
        evaluations: 1,
    })
}

/// Fatemi–Socie (1988) on the critical plane: `max_{n, m ⊥ n} γ_a(n, m) (1 + k σ_n,max(n)/σ_y)`
/// with `γ_a(n, m) = (max_t γ_nm − min_t γ_nm)/2` the half range of the engineering shear strain
/// `γ_nm = 2 m·ε·n = τ_nm/G` along the fixed direction `m` (docs/fatigue.md, Eqs. F6–F7). For
/// each plane the maximum over `m` is exact (half the diameter of the shear-traction path); over
/// planes: coarse covering (with `coarse_directions` in-plane directions), then compass
/// refinement of the best `candidates` lattice local maxima, on the coarse directions and then
/// exact with pair screening, to `angular_tolerance`, and escape probes (docs/fatigue.md,
/// "Critical-plane search" — a local search: see its accuracy there).
pub fn fatemi_socie(
    path: &[Voigt],
    material: &Material,
    params: &CriticalPlaneParams,
    scratch: &mut PlaneScratch,
) -> Result<FatemiSocie, FatigueError> {
    material.validate_fatemi_socie()?;
    params.validate()?;
    check_path(path)?;
    scratch.prepare(params, path);
    let g = material.shear_modulus();
    let kq = material.fs_k / material.yield_stress;
    let mut shear = std::mem::take(&mut scratch.shear);
    let mut hull = std::mem::take(&mut scratch.hull);
    let columns = std::mem::take(&mut scratch.columns);
    scratch.values.clear();
    for n in &scratch.coarse {
        let v = fs_plane_coarse(&columns, n, g, kq, &scratch.directions, &mut shear);
        scratch.values.push(v);
    }
    let mut evaluations = scratch.coarse.len();
    choose_candidates(scratch, params);
    // Phase 1: every candidate on the coarse in-plane directions down to FS_EXACT_BELOW; its
    // value is a lower bound within the factor cos(π/2M) of the exact one (M directions).
    let h0 = 0.5 * params.coarse_spacing();
    let h1 = FS_EXACT_BELOW.min(h0);
    let mut phase1 = [(f64::NEG_INFINITY, [0.0, 0.0, 1.0]); MAX_CANDIDATES];
    let count = scratch.chosen.len().min(MAX_CANDIDATES);
    for c in 0..count {
        let i = scratch.chosen[c];
        let directions = &scratch.directions;
        let (n1, v1, evals1) = refine(
            |n, _| fs_plane_coarse(&columns, n, g, kq, directions, &mut shear),
            scratch.coarse[i],
            scratch.values[i],
            h0,
            h1,
        );
        evaluations += evals1;
        phase1[c] = (v1, n1);
    }
    // Phase 2, exact over directions, for the candidates that can still win: exact ≤
    // coarse / cos(π/2M), so a candidate below best·cos(π/2M) cannot.
    let best1 = phase1[..count]
        .iter()
        .map(|p| p.0)
        .fold(f64::NEG_INFINITY, f64::max);
    let factor = (std::f64::consts::FRAC_PI_2 / params.coarse_directions as f64).cos();
    let screened = path.len() <= PAIR_SCREEN_UP_TO;
    if screened {
        pair_norms(path, &mut scratch.pair_norms);
    }
    let mut best = (f64::NEG_INFINITY, [0.0, 0.0, 1.0]);
    for &(v1, n1) in &phase1[..count] {
        if count > 1 && v1 >= 0.0 && v1 < best1 * factor * (1.0 - PRUNE_MARGIN) {
            continue;
        }
        let v1 = fs_plane_exact(&columns, &n1, g, kq, &mut shear, &mut hull).0;
        let mut screen = Screen {
            anchor: None,
            radius: 0.0,
            norms: &scratch.pair_norms,
            active: &mut scratch.active,
            used: &mut scratch.used,
        };
        let mut exact = |n: &[f64; 3], h: f64| {
            if screened {
                fs_plane_screened(&columns, n, h, g, kq, &mut shear, &mut hull, &mut screen)
            } else {
                fs_plane_exact(&columns, n, g, kq, &mut shear, &mut hull).0
            }
        };
        let (mut n, mut v, evals) = refine(&mut exact, n1, v1, h1, params.angular_tolerance);
        evaluations += evals + 1;
        // Escape probes: FS is a maximum over increment pairs and has nearby local maxima
        // (0.03–0.07 rad apart); 16 probes at h0 and h0/2 around the converged normal, and a
        // new compass search from the best probe if it is higher, at most ESCAPE_ROUNDS times.
        for _ in 0..ESCAPE_ROUNDS {
            let (probe, pv, pe) = probe_ring(&mut exact, &n, v, &[h0, 0.5 * h0]);
            evaluations += pe;
            if pv <= v {
                break;
            }
            let (n2, v2, e2) = refine(&mut exact, probe, pv, h1, params.angular_tolerance);
            evaluations += e2;
            (n, v) = (n2, v2);
        }
        if v > best.0 {
            best = (v, n);
        }
    }
    let (value, gamma_a, smax, m) = fs_plane_exact(&columns, &best.1, g, kq, &mut shear, &mut hull);
    scratch.shear = shear;
    scratch.hull = hull;
    scratch.columns = columns;
    Ok(FatemiSocie {
        value,
        normal: best.1,
        direction: m,
        shear_strain_amplitude: gamma_a,
        normal_stress_max: smax,
        evaluations,
    })
}

/// The best of the 16 points at each angle of `steps` around `n` in the tangent directions
/// `kπ/8`; returns it, its value (`v` and `n` itself if none is higher) and the evaluations.
fn probe_ring<F: FnMut(&[f64; 3], f64) -> f64>(
    f: &mut F,
    n: &[f64; 3],
    v: f64,
    steps: &[f64],
) -> ([f64; 3], f64, usize) {
    let (u, w) = tangent_basis(n);
    let mut best = (*n, v);
    let mut evals = 0;
    for &h in steps {
        let t = h.tan();
        for k in 0..16 {
            let (sb, cb) = (std::f64::consts::FRAC_PI_8 * k as f64).sin_cos();
            let cand = normalize(std::array::from_fn(|i| n[i] + t * (cb * u[i] + sb * w[i])));
            let val = f(&cand, h);
            evals += 1;
            if val > best.1 {
                best = (cand, val);
            }
        }
    }
    (best.0, best.1, evals)
}

/// `‖σ(i) − σ(j)‖_F` for the pairs `i < j` in the order `(0,1), (0,2), …, (1,2), …`.
fn pair_norms(path: &[Voigt], out: &mut Vec<f64>) {
    out.clear();
    for (i, a) in path.iter().enumerate() {
        for b in &path[i + 1..] {
            let d: [f64; 6] = std::array::from_fn(|k| a[k] - b[k]);
            out.push(
                (d[0] * d[0]
                    + d[1] * d[1]
                    + d[2] * d[2]
                    + 2.0 * (d[3] * d[3] + d[4] * d[4] + d[5] * d[5]))
                    .sqrt(),
            );
        }
    }
}

/// Pair screening of the exact in-plane maximum near an anchor normal `n_a`. The shear of a
/// tensor `Δ` on the plane `n`, `τ_n(Δ) = Δn − (n·Δn) n`, is Lipschitz in `n`:
/// `|τ_n'(Δ) − τ_n(Δ)| ≤ 4‖Δ‖_F |n' − n|`. So within the radius `r` of the anchor only the pairs
/// with `D_ij(n_a) + 4 F_ij r ≥ D*(n_a) − 4 F* r` can attain the diameter (`D = |τ(t_i) − τ(t_j)|`,
/// `F = ‖σ(t_i) − σ(t_j)‖_F`, `*` the anchor's maximising pair): the maximum over them is exact.
struct Screen<'a> {
    anchor: Option<[f64; 3]>,
    radius: f64,
    norms: &'a [f64],
    active: &'a mut Vec<(u32, u32)>,
    /// The increments of the `active` pairs (each once).
    used: &'a mut Vec<u32>,
}

/// Fatemi–Socie on the plane `n`, exact over in-plane directions, with pair screening: a step
/// `h ≤ SCREEN_ABOVE_STEP` farther than the screening radius from the anchor re-anchors at `n`
/// with radius `4h`; larger steps scan all pairs.
#[allow(clippy::too_many_arguments)]
fn fs_plane_screened(
    path: &PathColumns,
    n: &[f64; 3],
    h: f64,
    g: f64,
    k_over_sy: f64,
    shear: &mut Vec<[f64; 2]>,
    hull: &mut Vec<[f64; 2]>,
    screen: &mut Screen,
) -> f64 {
    let inside = screen.anchor.is_some_and(|a| {
        let c = (a[0] - n[0]).powi(2) + (a[1] - n[1]).powi(2) + (a[2] - n[2]).powi(2);
        c.sqrt() <= screen.radius
    });
    let smax = if inside {
        // Near the anchor only the increments of the active pairs are read: their shear
        // components alone (the same sums as `shear_path`), `σ_n,max` over the whole path.
        let (u, v) = tangent_basis(n);
        let (wn, wu, wv) = (
            bilinear_weights(n, n),
            bilinear_weights(&u, n),
            bilinear_weights(&v, n),
        );
        shear.resize(path.len(), [0.0; 2]);
        for &t in screen.used.iter() {
            let t = t as usize;
            shear[t] = [path.dot(&wu, t), path.dot(&wv, t)];
        }
        path.max_dot(&wn)
    } else {
        shear_path(path, n, shear).0
    };
    let d2 = |p: &[f64; 2], q: &[f64; 2]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    let mut best: f64 = 0.0;
    if !inside && h > SCREEN_ABOVE_STEP && shear.len() > DIAMETER_PAIRS_UP_TO {
        // Large steps on long paths: the diameter as the full evaluation computes it
        // (`diameter`: the filtered pairs or the hull; the value of `fs_plane_exact`).
        best = diameter(shear, hull).0;
    } else if !inside && h > SCREEN_ABOVE_STEP {
        // Large steps (probes, the first compass steps): the list would keep most pairs; one
        // plain pass over all pairs.
        for i in 0..shear.len() {
            for j in i + 1..shear.len() {
                let d = d2(&shear[i], &shear[j]);
                best = if d > best { d } else { best };
            }
        }
    } else if inside {
        for &(i, j) in screen.active.iter() {
            let d = d2(&shear[i as usize], &shear[j as usize]);
            best = if d > best { d } else { best };
        }
    } else {
        let r = 4.0 * h;
        let (mut best_k, mut k) = (0usize, 0usize);
        for i in 0..shear.len() {
            for j in i + 1..shear.len() {
                let d = d2(&shear[i], &shear[j]);
                if d > best {
                    best = d;
                    best_k = k;
                }
                k += 1;
            }
        }
        let threshold = best.sqrt() - 4.0 * screen.norms.get(best_k).copied().unwrap_or(0.0) * r;
        screen.active.clear();
        let mut k = 0usize;
        for i in 0..shear.len() {
            for j in i + 1..shear.len() {
                let need = threshold - 4.0 * screen.norms[k] * r;
                if need <= 0.0 || d2(&shear[i], &shear[j]) >= need * need {
                    screen.active.push((i as u32, j as u32));
                }
                k += 1;
            }
        }
        screen.used.clear();
        for &(i, j) in screen.active.iter() {
            screen.used.extend([i, j]);
        }
        screen.used.sort_unstable();
        screen.used.dedup();
        screen.anchor = Some(*n);
        screen.radius = r;
    }
    0.5 * best.sqrt() / g * (1.0 + k_over_sy * smax)
}

/// The best `candidates` local maxima of the coarse lattice (value ≥ every lattice neighbour
/// within [`NEIGHBOUR_RADIUS`] h, as planes) within [`CANDIDATE_WINDOW`] of the best coarse value; above
/// [`NEIGHBOUR_LISTS_UP_TO`] normals, greedily the best normals more than
/// [`CANDIDATE_SEPARATION`] `h` apart.
fn choose_candidates(scratch: &mut PlaneScratch, params: &CriticalPlaneParams) {
    let cos_sep = (CANDIDATE_SEPARATION * params.coarse_spacing())
        .min(std::f64::consts::FRAC_PI_2)
        .cos();
    scratch.chosen.clear();
    let top = scratch
        .values
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let floor = top - CANDIDATE_WINDOW * top.abs();
    if !scratch.neighbour_start.is_empty() {
        // The best local maxima of the lattice (each basin the lattice resolves, once).
        for _ in 0..params.candidates {
            let mut best: Option<usize> = None;
            for (i, &v) in scratch.values.iter().enumerate() {
                if best.is_some_and(|b| scratch.values[b] >= v)
                    || v.is_nan()
                    || v < floor
                    || scratch.chosen.contains(&i)
                {
                    continue;
                }
                let nb =
                    &scratch.neighbours[scratch.neighbour_start[i]..scratch.neighbour_start[i + 1]];
                if nb.iter().all(|&j| scratch.values[j as usize] <= v) {
                    best = Some(i);
                }
            }
            match best {
                Some(b) => scratch.chosen.push(b),
                None => break,
            }
        }
        return;
    }
    for _ in 0..params.candidates {
        let mut best: Option<usize> = None;
        for (i, (&v, n)) in scratch.values.iter().zip(&scratch.coarse).enumerate() {
            if best.is_some_and(|b| scratch.values[b] >= v) || v.is_nan() || v < floor {
                continue;
            }
            let near = scratch.chosen.iter().any(|&c| {
                let m = &scratch.coarse[c];
                (n[0] * m[0] + n[1] * m[1] + n[2] * m[2]).abs() > cos_sep
            });
            if !near {
                best = Some(i);
            }
        }
        match best {
            Some(b) => scratch.chosen.push(b),
            None => break,
        }
    }
}

/// Compass search on the unit sphere: from `n0` (value `v0`) try the 8 points at angle `h` in
/// the directions `kπ/4` (`π/8 + kπ/4` on every other iteration) of the tangent plane, move to
/// the best if it improves, else halve `h`; stop when `h < tol`. `f(n, h)` is told the step. Returns the best normal, its value and the evaluations.
fn refine<F: FnMut(&[f64; 3], f64) -> f64>(
    mut f: F,
    n0: [f64; 3],
    v0: f64,
    h0: f64,
    tol: f64,
) -> ([f64; 3], f64, usize) {
    let (mut n, mut best, mut h) = (n0, v0, h0);
    let mut evals = 0;
    let mut iteration = 0usize;
    while h >= tol {
        let (u, v) = tangent_basis(&n);
        let t = h.tan();
        // The 8-point stencil, turned by π/8 on every other iteration (16 directions over two
        // iterations: ridges of the max-over-time functions are followed, not stalled on).
        let offset = if iteration % 2 == 1 {
            std::f64::consts::FRAC_PI_8
        } else {
            0.0
        };
        iteration += 1;
        let mut improved: Option<([f64; 3], f64)> = None;
        for k in 0..8 {
            let (sb, cb) = (offset + std::f64::consts::FRAC_PI_4 * k as f64).sin_cos();
            let cand = normalize(std::array::from_fn(|i| n[i] + t * (cb * u[i] + sb * v[i])));
            let val = f(&cand, h);
            evals += 1;
            if val > improved.map_or(best, |x| x.1) {
                improved = Some((cand, val));
            }
        }
        match improved {
            Some((c, v)) => {
                n = c;
                best = v;
            }
            None => h *= 0.5,
        }
    }
    (n, best, evals)
}

/// Up to this many points [`diameter`] compares all pairs (measured faster than the hull).
pub const DIAMETER_PAIRS_UP_TO: usize = 64;

/// Up to this many increments the phase-2 refinement of Fatemi–Socie screens increment pairs
/// (docs/fatigue.md, "Critical-plane search", step 4; `N(N − 1)/2` pair norms of scratch, 33 k
/// at 256): near an anchor only the few pairs that can attain the diameter are compared, which
/// beats the hull (its sort) also above [`DIAMETER_PAIRS_UP_TO`] (the fretting loop's cycles
/// have 4q + 1 = 81 increments).
pub const PAIR_SCREEN_UP_TO: usize = 256;

/// The largest squared distance between two of `points` and the difference vector of that
/// pair, by the convex hull (Andrew's monotone chain) and rotating calipers (Shamos 1978):
/// `O(N log N)`; up to [`DIAMETER_PAIRS_UP_TO`] points all pairs are cheaper (no sort) and
/// are used instead. Sorts `points` in place. Its twin is [`diameter_brute_force`].
///
/// Hull vertices whose turn `|(b − a) × (c − a)|` is below `1e-12 L²` (`L` the extent of the
/// points) are dropped as collinear, so the calipers see a strictly convex polygon (rounding
/// on nearly collinear shear paths — proportional loading — would otherwise break the
/// unimodality they rely on); this changes the diameter by at most a relative `1e-12`.
pub fn diameter(points: &mut [[f64; 2]], hull: &mut Vec<[f64; 2]>) -> (f64, [f64; 2]) {
    if points.len() <= DIAMETER_PAIRS_UP_TO {
        return diameter_brute_force(points);
    }
    diameter_filtered(points, hull)
}

/// The diameter of [`diameter`] above [`DIAMETER_PAIRS_UP_TO`] points, without sorting them all
/// (docs/fatigue.md, "Critical-plane criteria"): a lower bound `D₀` from the extreme points along
/// `x`, `y`, `x + y`, `x − y` (all pairs of those eight), the centre `c` of the bounding box and
/// `R = max |q − c|`; a point `p` with `|p − c| + R < D₀` is in no pair longer than `D₀`
/// (`|p − q| ≤ |p − c| + |q − c|`), so the diameter pair is among the others (kept with a
/// relative margin of `1e-9` against rounding, which only keeps more). Those points, in their
/// order, go through all pairs when at most [`DIAMETER_PAIRS_UP_TO`] are left — then the result is
/// [`diameter_brute_force`]'s bit for bit, pair and sign included — else through
/// [`diameter_hull`] on all of `points` (sorting them in place: the former result bit for bit,
/// the same value to the hull's `1e-12`). Fretting cycles' shear paths are thin loops: only the
/// points near their two ends are left. `kept` is scratch.
pub fn diameter_filtered(points: &mut [[f64; 2]], kept: &mut Vec<[f64; 2]>) -> (f64, [f64; 2]) {
    if points.len() < 2 {
        return (0.0, [0.0, 0.0]);
    }
    // The extremes along x, y, x + y, x − y (indices of the min and max of each).
    let mut ext = [0usize; 8];
    let mut lo = [f64::INFINITY; 4];
    let mut hi = [f64::NEG_INFINITY; 4];
    for (i, p) in points.iter().enumerate() {
        let v = [p[0], p[1], p[0] + p[1], p[0] - p[1]];
        for k in 0..4 {
            if v[k] < lo[k] {
                lo[k] = v[k];
                ext[2 * k] = i;
            }
            if v[k] > hi[k] {
                hi[k] = v[k];
                ext[2 * k + 1] = i;
            }
        }
    }
    let d2 = |a: &[f64; 2], b: &[f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
    let mut lower: f64 = 0.0;
    for (k, &i) in ext.iter().enumerate() {
        for &j in &ext[k + 1..] {
            let d = d2(&points[i], &points[j]);
            lower = if d > lower { d } else { lower };
        }
    }
    let c = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let mut r2: f64 = 0.0;
    for p in points.iter() {
        let d = d2(p, &c);
        r2 = if d > r2 { d } else { r2 };
    }
    let r = r2.sqrt();
    // |p − c| ≥ D₀ − R, with the margin; a negative or non-finite bound (coordinates whose
    // squares overflow) keeps every point.
    let reach = lower.sqrt() * (1.0 - 1e-9) - r * (1.0 + 1e-9);
    kept.clear();
    if !(reach > 0.0 && reach.is_finite()) {
        kept.extend_from_slice(points);
    } else {
        let reach2 = reach * reach;
        kept.extend(points.iter().filter(|p| d2(p, &c) >= reach2));
    }
    if kept.len() <= DIAMETER_PAIRS_UP_TO {
        return diameter_brute_force(kept);
    }
    diameter_hull(points, kept)
}

/// The diameter of [`diameter`] by the hull and rotating calipers at any size.
pub fn diameter_hull(points: &mut [[f64; 2]], hull: &mut Vec<[f64; 2]>) -> (f64, [f64; 2]) {
    points.sort_unstable_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let turn = |a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]| {
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    let (mut ylo, mut yhi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in points.iter() {
        ylo = ylo.min(p[1]);
        yhi = yhi.max(p[1]);
    }
    let extent = match (points.first(), points.last()) {
        (Some(a), Some(b)) => (b[0] - a[0]).max(yhi - ylo),
        _ => 0.0,
    };
    let flat = 1e-12 * extent * extent;
    hull.clear();
    for p in points.iter() {
        while hull.len() >= 2 && turn(&hull[hull.len() - 2], &hull[hull.len() - 1], p) <= flat {
            hull.pop();
        }
        hull.push(*p);
    }
    let lower = hull.len() + 1;
    for p in points.iter().rev().skip(1) {
        while hull.len() >= lower && turn(&hull[hull.len() - 2], &hull[hull.len() - 1], p) <= flat {
            hull.pop();
        }
        hull.push(*p);
    }
    hull.pop(); // the first point again
    let h = hull.len();
    if h <= 3 {
        return diameter_brute_force(hull);
    }
    let d2 = |a: &[f64; 2], b: &[f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
    let mut best = (0.0, [0.0, 0.0]);
    let mut consider = |a: &[f64; 2], b: &[f64; 2]| {
        let d = d2(a, b);
        if d > best.0 {
            best = (d, [a[0] - b[0], a[1] - b[1]]);
        }
    };
    let mut j = 1;
    for i in 0..h {
        let i1 = (i + 1) % h;
        // Advance j to the vertex farthest from the edge (i, i1) (the area is unimodal).
        for _ in 0..h {
            let j1 = (j + 1) % h;
            if turn(&hull[i], &hull[i1], &hull[j1]) > turn(&hull[i], &hull[i1], &hull[j]) {
                j = j1;
            } else {
                break;
            }
        }
        consider(&hull[i], &hull[j]);
        consider(&hull[i1], &hull[j]);
    }
    best
}

/// The largest squared distance over all pairs, `O(N²)`: the twin of [`diameter`].
pub fn diameter_brute_force(points: &[[f64; 2]]) -> (f64, [f64; 2]) {
    let mut best = (0.0, [0.0, 0.0]);
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            let d = (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
            if d > best.0 {
                best = (d, [a[0] - b[0], a[1] - b[1]]);
            }
        }
    }
    best
}

/// SWT by brute force on the grid `θ = i δ ∈ [0, π/2]`, `φ = j δ ∈ [0, 2π)` (the twin of
/// [`swt`] for verification; `δ = step` rad).
pub fn swt_brute_force(
    path: &[Voigt],
    material: &Material,
    step: f64,
) -> Result<Swt, FatigueError> {
    material.validate_elastic()?;
    check_path(path)?;
    let trace: Vec<f64> = path.iter().map(|s| s[0] + s[1] + s[2]).collect();
    let mut best = (f64::NEG_INFINITY, [0.0, 0.0, 1.0]);
    let mut evaluations = 0;
    for_each_grid_normal(step, |n| {
        let v = swt_plane(path, &trace, n, material.young, material.poisson)[0];
        evaluations += 1;
        if v > best.0 {
            best = (v, *n);
        }
    });
    let [value, smax, ea] = swt_plane(path, &trace, &best.1, material.young, material.poisson);
    Ok(Swt {
        value,
        normal: best.1,
        normal_stress_max: smax,
        strain_amplitude: ea,
        evaluations,
    })
}

/// Fatemi–Socie by brute force on the `(θ, φ)` grid of step `step` rad, exact over in-plane
/// directions at each normal (the twin of [`fatemi_socie`] for verification).
pub fn fatemi_socie_brute_force(
    path: &[Voigt],
    material: &Material,
    step: f64,
) -> Result<FatemiSocie, FatigueError> {
    material.validate_fatemi_socie()?;
    check_path(path)?;
    let g = material.shear_modulus();
    let kq = material.fs_k / material.yield_stress;
    let (mut shear, mut hull) = (Vec::new(), Vec::new());
    let columns = PathColumns::new(path);
    let mut best = (f64::NEG_INFINITY, [0.0, 0.0, 1.0]);
    let mut evaluations = 0;
    for_each_grid_normal(step, |n| {
        let v = fs_plane_exact(&columns, n, g, kq, &mut shear, &mut hull).0;
        evaluations += 1;
        if v > best.0 {
            best = (v, *n);
        }
    });
    let (value, gamma_a, smax, m) = fs_plane_exact(&columns, &best.1, g, kq, &mut shear, &mut hull);
    Ok(FatemiSocie {
        value,
        normal: best.1,
        direction: m,
        shear_strain_amplitude: gamma_a,
        normal_stress_max: smax,
        evaluations,
    })
}

fn for_each_grid_normal<F: FnMut(&[f64; 3])>(step: f64, mut f: F) {
    let step = step.clamp(1e-5, 1.0);
    let nt = (std::f64::consts::FRAC_PI_2 / step).ceil() as usize;
    let np = (2.0 * std::f64::consts::PI / step).ceil() as usize;
    for i in 0..=nt {
        let theta = std::f64::consts::FRAC_PI_2 * i as f64 / nt as f64;
        let (st, ct) = theta.sin_cos();
        let count = if i == 0 { 1 } else { np };
        for j in 0..count {
            let phi = 2.0 * std::f64::consts::PI * j as f64 / np as f64;
            let (sp, cp) = phi.sin_cos();
            f(&[st * cp, st * sp, ct]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The screened maximum equals the full one at normals around the anchor, within and
    /// beyond the screening radius (fixed seeds).
    #[test]
    fn screening_is_exact() {
        let mut state = 7u64;
        let mut uniform = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let (g, kq) = (80e9, 1e-9);
        let (mut shear, mut hull, mut norms, mut active) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut used = Vec::new();
        let mut checked = 0;
        // 40 increments (all pairs in the full evaluation) and 81, the fretting loop's cycle
        // (the hull: equal to 1e-12, the collinearity tolerance of `diameter_hull`).
        for (len, tol) in [(40usize, 1e-15), (81, 1e-12)] {
            for _ in 0..50 {
                let c: [[f64; 6]; 3] =
                    std::array::from_fn(|_| std::array::from_fn(|_| 1e8 * uniform()));
                let path: Vec<Voigt> = (0..len)
                    .map(|i| {
                        let w = 2.0 * std::f64::consts::PI * i as f64 / len as f64;
                        std::array::from_fn(|k| {
                            c[0][k] + c[1][k] * w.cos() + c[2][k] * (2.0 * w).sin()
                        })
                    })
                    .collect();
                pair_norms(&path, &mut norms);
                let columns = PathColumns::new(&path);
                let n0 = normalize([uniform(), uniform(), uniform()]);
                for h in [0.05, 0.01, 1e-3, 1e-4] {
                    let mut screen = Screen {
                        anchor: None,
                        radius: 0.0,
                        norms: &norms,
                        active: &mut active,
                        used: &mut used,
                    };
                    let full = fs_plane_exact(&columns, &n0, g, kq, &mut shear, &mut hull).0;
                    let anchored = fs_plane_screened(
                        &columns,
                        &n0,
                        h,
                        g,
                        kq,
                        &mut shear,
                        &mut hull,
                        &mut screen,
                    );
                    assert!(
                        (full - anchored).abs() <= tol * full,
                        "{anchored} vs {full}"
                    );
                    for _ in 0..40 {
                        let scale = 6.0 * h * uniform().abs();
                        let n = normalize(std::array::from_fn(|k| n0[k] + scale * uniform()));
                        let full = fs_plane_exact(&columns, &n, g, kq, &mut shear, &mut hull).0;
                        let s = fs_plane_screened(
                            &columns,
                            &n,
                            h,
                            g,
                            kq,
                            &mut shear,
                            &mut hull,
                            &mut screen,
                        );
                        assert!((s - full).abs() <= tol * full, "{len}: {s} vs {full}");
                        checked += 1;
                    }
                }
            }
        }
        assert_eq!(checked, 2 * 50 * 4 * 40);
    }
}
