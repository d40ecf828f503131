//! The four criteria over a field of points of several materials, each screened by a cheap upper
//! bound (docs/fatigue.md, "Screened field evaluation").
//!
//! Every criterion is evaluated exactly, in decreasing order of an upper bound `b ≥` the
//! criterion, at every point whose bound is at least `fraction ×` the largest exact value found:
//! every point whose value is `≥ fraction ×` the field's maximum is evaluated (so the maximum and
//! its location are those of the full evaluation), the others are `NaN`. Crossland and Dang Van
//! share one minimum ball per point (~40 μs), so a point evaluated for either holds both.
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

use crate::critical_plane::{fatemi_socie, swt, PlaneScratch};
use crate::error::FatigueError;
use crate::field::{FieldParams, Maximum};
use crate::invariant::{crossland_dang_van, InvariantScratch};
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
pub fn invariant_bounds(path: &[Voigt], material: &Material) -> [f64; 2] {
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
pub fn critical_plane_bounds(path: &[Voigt], material: &Material) -> [f64; 2] {
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
/// ball and of the principal values.
pub fn reference_bounds(reference: &Voigt, deviation: &[f64; 6], material: &Material) -> [f64; 4] {
    let y_ref = deviator_coordinates(reference);
    let y_norm = y_ref.iter().map(|v| v * v).sum::<f64>().sqrt();
    let d = deviation[..5].iter().map(|v| v * v).sum::<f64>().sqrt();
    let d = d * (1.0 + 1e-9) + 1e-12 * (y_norm + d);
    let h = hydrostatic(reference) + deviation[5];
    let t = material.t_minus1;
    let crossland = (d + material.alpha_crossland() * h) / t;
    let dang_van = (d + material.alpha_dang_van() * h) / t;
    let two_over_root3 = 2.0 / 3f64.sqrt();
    let lambda1 = principal_values(&deviator(reference))[0] + 1e-12 * y_norm;
    let s1 = h + lambda1 + two_over_root3 * d;
    let nu = material.poisson;
    let strain =
        ((1.0 + nu) * two_over_root3 * d + (1.0 - 2.0 * nu) * deviation[5]) / material.young;
    let swt = s1.max(0.0) * strain;
    let fs =
        d / material.shear_modulus() * (1.0 + material.fs_k * s1 / material.yield_stress).max(0.0);
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

fn maximum(field: &[f64]) -> Maximum {
    let mut best = Maximum {
        value: f64::NEG_INFINITY,
        point: 0,
    };
    for (point, &value) in field.iter().enumerate() {
        if value > best.value {
            best = Maximum { value, point };
        }
    }
    best
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
    if points.checked_mul(increments * 6) != Some(stress.len()) {
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
            let [c, dv] = invariant_bounds(path, material);
            let [s, f] = critical_plane_bounds(path, material);
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
        let count = screen(
            &bound(2 + which),
            fraction,
            0,
            &mut best,
            &mut field,
            &mut done,
            &plane(which),
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
        maximum(&cleaned)
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

/// One screen (module doc): the points not yet `done`, in decreasing order of `bound`, evaluated
/// by `eval` (`K` values per point into `fields`, `best` their running maxima) in parallel batches
/// of 16, until the next bound is below `fraction × best[which]` (with `fraction > 0` and
/// `best[which] > 0`). Returns the number of points evaluated.
fn screen<const K: usize, S: Default + Send>(
    bound: &[f64],
    fraction: f64,
    which: usize,
    best: &mut [f64; K],
    fields: &mut [Vec<f64>; K],
    done: &mut [bool],
    eval: &PointCriteria<'_, K, S>,
) -> Result<usize, FatigueError> {
    let mut order: Vec<usize> = (0..bound.len()).filter(|&p| !done[p]).collect();
    order.sort_by(|&a, &b| bound[b].total_cmp(&bound[a]));
    let batch = 16;
    let mut next = 0;
    while next < order.len() {
        let b = best[which];
        if fraction > 0.0 && b > 0.0 && bound[order[next]] < fraction * b {
            break;
        }
        let end = (next + batch).min(order.len());
        let values: Vec<[f64; K]> = order[next..end]
            .par_iter()
            .map_init(<(Vec<Voigt>, S)>::default, |scratch, &p| eval(p, scratch))
            .collect::<Result<_, FatigueError>>()?;
        for (&p, v) in order[next..end].iter().zip(values) {
            done[p] = true;
            for k in 0..K {
                fields[k][p] = v[k];
                best[k] = best[k].max(v[k]);
            }
        }
        next = end;
    }
    Ok(next)
}
