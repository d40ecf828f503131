//! The four criteria over a field of points of several materials, the critical-plane criteria
//! screened by cheap upper bounds (docs/fatigue.md, "Screened field evaluation").
//!
//! Crossland and Dang Van (one minimum ball per point, ~40 μs) are evaluated at every point.
//! SWT (~0.1 ms) and Fatemi–Socie (~2 ms) are evaluated exactly, in decreasing order of an upper
//! bound `b ≥` the criterion, at every point whose bound is at least `fraction ×` the largest
//! exact value found: every point whose value is `≥ fraction ×` the field's maximum is evaluated
//! (so the maximum and its location are those of the full evaluation), the others are `NaN`.
//!
//! Bounds (`R_X = max_t ‖X(t) − X̄‖_F`, the radius of the ball about the path's mean, `‖·‖_F` the
//! Frobenius norm of the tensor; `σ₁ ≤ λ̂ = min(σ_H + √(2/3)‖s‖_F, Gershgorin)`):
//!
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
use crate::tensor::{hydrostatic, strain_from_stress, Voigt};

/// The four index fields (`NaN` where a screened criterion was not evaluated), their maxima and
/// the counts of exact critical-plane evaluations.
#[derive(Clone, Debug, PartialEq)]
pub struct ScreenedIndices {
    /// Crossland's index (every point).
    pub crossland: Vec<f64>,
    /// Dang Van's index (every point).
    pub dang_van: Vec<f64>,
    /// SWT (Pa) where evaluated.
    pub swt: Vec<f64>,
    /// Fatemi–Socie where evaluated.
    pub fatemi_socie: Vec<f64>,
    pub crossland_max: Maximum,
    pub dang_van_max: Maximum,
    pub swt_max: Maximum,
    pub fatemi_socie_max: Maximum,
    /// Points where SWT was evaluated exactly.
    pub swt_evaluated: usize,
    /// Points where Fatemi–Socie was evaluated exactly.
    pub fatemi_socie_evaluated: usize,
}

fn frobenius_radius(path: &[Voigt]) -> f64 {
    let n = path.len() as f64;
    let mut mean = [0.0; 6];
    for s in path {
        for k in 0..6 {
            mean[k] += s[k] / n;
        }
    }
    path.iter()
        .map(|s| {
            let d: Vec<f64> = (0..6).map(|k| s[k] - mean[k]).collect();
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

/// `[SWT bound, Fatemi–Socie bound]` of one path (module doc).
pub fn critical_plane_bounds(path: &[Voigt], material: &Material) -> [f64; 2] {
    let sigma1 = path
        .iter()
        .map(largest_principal_bound)
        .fold(f64::NEG_INFINITY, f64::max);
    let strain: Vec<Voigt> = path
        .iter()
        .map(|s| strain_from_stress(s, material.young, material.poisson))
        .collect();
    let deviator: Vec<Voigt> = path
        .iter()
        .map(|s| {
            let h = hydrostatic(s);
            [s[0] - h, s[1] - h, s[2] - h, s[3], s[4], s[5]]
        })
        .collect();
    let swt = sigma1.max(0.0) * frobenius_radius(&strain);
    let factor = (1.0 + material.fs_k * sigma1 / material.yield_stress).max(0.0);
    let fs = frobenius_radius(&deviator) / (2f64.sqrt() * material.shear_modulus()) * factor;
    [swt, fs]
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
    // Pass 1: Crossland, Dang Van and the bounds, every point.
    let first: Vec<([f64; 2], [f64; 2])> = (0..points)
        .into_par_iter()
        .map_init(
            || (Vec::new(), InvariantScratch::default()),
            |(path, scratch), p| {
                path_of(stress, p, increments, path);
                let material = &materials[material_of[p] as usize];
                let (c, dv) = crossland_dang_van(path, material, scratch)?;
                Ok(([c.index, dv.index], critical_plane_bounds(path, material)))
            },
        )
        .collect::<Result<_, FatigueError>>()?;
    let crossland: Vec<f64> = first.iter().map(|r| r.0[0]).collect();
    let dang_van: Vec<f64> = first.iter().map(|r| r.0[1]).collect();
    // Pass 2: each critical-plane criterion in decreasing order of its bound, in batches.
    let screened = |which: usize| -> Result<(Vec<f64>, usize), FatigueError> {
        let mut order: Vec<usize> = (0..points).collect();
        order.sort_by(|&a, &b| first[b].1[which].total_cmp(&first[a].1[which]));
        let mut field = vec![f64::NAN; points];
        let mut best = f64::NEG_INFINITY;
        let mut done = 0;
        let batch = 16;
        while done < points {
            let bound = first[order[done]].1[which];
            if best > 0.0 && bound < fraction * best {
                break;
            }
            let end = (done + batch).min(points);
            let values: Vec<f64> = order[done..end]
                .par_iter()
                .map_init(
                    || (Vec::new(), PlaneScratch::default()),
                    |(path, scratch), &p| {
                        path_of(stress, p, increments, path);
                        let material = &materials[material_of[p] as usize];
                        Ok(if which == 0 {
                            swt(path, material, &params.plane, scratch)?.value
                        } else {
                            fatemi_socie(path, material, &params.plane, scratch)?.value
                        })
                    },
                )
                .collect::<Result<_, FatigueError>>()?;
            for (&p, v) in order[done..end].iter().zip(values) {
                field[p] = v;
                best = best.max(v);
            }
            done = end;
        }
        Ok((field, done))
    };
    let (swt_field, swt_evaluated) = screened(0)?;
    let (fs_field, fatemi_socie_evaluated) = screened(1)?;
    let nan_max = |f: &[f64]| {
        let cleaned: Vec<f64> = f
            .iter()
            .map(|v| if v.is_nan() { f64::NEG_INFINITY } else { *v })
            .collect();
        maximum(&cleaned)
    };
    Ok(ScreenedIndices {
        crossland_max: maximum(&crossland),
        dang_van_max: maximum(&dang_van),
        swt_max: nan_max(&swt_field),
        fatemi_socie_max: nan_max(&fs_field),
        crossland,
        dang_van,
        swt: swt_field,
        fatemi_socie: fs_field,
        swt_evaluated,
        fatemi_socie_evaluated,
    })
}
