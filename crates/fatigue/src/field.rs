//! The four criteria over the stress histories of many points (docs/fatigue.md, "Field
//! evaluation").
use rayon::prelude::*;

use crate::critical_plane::{fatemi_socie, swt, CriticalPlaneParams, PlaneScratch};
use crate::error::FatigueError;
use crate::invariant::{crossland_dang_van, InvariantScratch};
use crate::material::Material;
use crate::tensor::Voigt;

/// Parameters of [`evaluate_field`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldParams {
    /// The critical-plane search of SWT and Fatemi–Socie.
    pub plane: CriticalPlaneParams,
    /// Evaluate the points in parallel (rayon): 1.98× on 2 free cores (benches/criteria.rs,
    /// docs/fatigue.md "Cost").
    pub parallel: bool,
}

impl Default for FieldParams {
    fn default() -> Self {
        Self {
            plane: CriticalPlaneParams::default(),
            parallel: true,
        }
    }
}

/// The largest value of an index field and the point where it is reached (the first such
/// point on ties).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Maximum {
    pub value: f64,
    pub point: usize,
}

/// The four indices at every point, the critical planes, and their maxima.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldIndices {
    /// Crossland's index per point (docs/fatigue.md, Eq. F3).
    pub crossland: Vec<f64>,
    /// Dang Van's index per point (Eq. F4).
    pub dang_van: Vec<f64>,
    /// SWT `σ_n,max ε_a` per point, Pa (Eq. F5).
    pub swt: Vec<f64>,
    /// Fatemi–Socie `γ_a (1 + k σ_n,max/σ_y)` per point (Eq. F6).
    pub fatemi_socie: Vec<f64>,
    /// SWT's critical normal per point.
    pub swt_normal: Vec<[f64; 3]>,
    /// Fatemi–Socie's critical normal per point.
    pub fatemi_socie_normal: Vec<[f64; 3]>,
    /// Fatemi–Socie's critical shear direction per point.
    pub fatemi_socie_direction: Vec<[f64; 3]>,
    pub crossland_max: Maximum,
    pub dang_van_max: Maximum,
    pub swt_max: Maximum,
    pub fatemi_socie_max: Maximum,
}

/// Per-worker buffers: the path of one point and the scratch of the criteria.
#[derive(Default)]
struct PointScratch {
    path: Vec<Voigt>,
    invariant: InvariantScratch,
    plane: PlaneScratch,
}

/// All four criteria of one point: `[crossland, dang_van, swt, fs]` and the three vectors.
type PointIndices = ([f64; 4], [[f64; 3]; 3]);

fn evaluate_point(
    history: &[f64],
    material: &Material,
    params: &FieldParams,
    scratch: &mut PointScratch,
) -> Result<PointIndices, FatigueError> {
    scratch.path.clear();
    scratch.path.extend(
        history
            .chunks_exact(6)
            .map(|c| [c[0], c[1], c[2], c[3], c[4], c[5]]),
    );
    let (c, dv) = crossland_dang_van(&scratch.path, material, &mut scratch.invariant)?;
    let s = swt(&scratch.path, material, &params.plane, &mut scratch.plane)?;
    let f = fatemi_socie(&scratch.path, material, &params.plane, &mut scratch.plane)?;
    Ok((
        [c.index, dv.index, s.value, f.value],
        [s.normal, f.normal, f.direction],
    ))
}

/// Crossland, Dang Van, SWT and Fatemi–Socie at each of `points` points from their stress
/// histories over one steady cycle, `stress[(p · increments + t) · 6 + k]` (point-major, then
/// increment, then the Voigt component `k` of `[σxx, σyy, σzz, σyz, σxz, σxy]`, Pa), and the
/// argmax of each field. Every point is evaluated as by [`crossland_dang_van`], [`swt`] and
/// [`fatemi_socie`]; the only allocations are the outputs and one scratch per worker.
pub fn evaluate_field(
    stress: &[f64],
    points: usize,
    increments: usize,
    material: &Material,
    params: &FieldParams,
) -> Result<FieldIndices, FatigueError> {
    let shape_error = FatigueError::FieldShape {
        len: stress.len(),
        points,
        increments,
    };
    let per_point = increments.checked_mul(6).ok_or(shape_error.clone())?;
    if points.checked_mul(per_point) != Some(stress.len()) {
        return Err(shape_error);
    }
    if points == 0 || increments == 0 {
        return Err(FatigueError::EmptyPath);
    }
    material.validate()?;
    params.plane.validate()?;
    if let Some((i, &value)) = stress.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(FatigueError::NonFiniteField {
            point: i / per_point,
            increment: (i % per_point) / 6,
            component: i % 6,
            value,
        });
    }
    let results: Vec<PointIndices> = if params.parallel {
        stress
            .par_chunks_exact(per_point)
            .map_init(PointScratch::default, |scratch, history| {
                evaluate_point(history, material, params, scratch)
            })
            .collect::<Result<_, _>>()?
    } else {
        let mut scratch = PointScratch::default();
        stress
            .chunks_exact(per_point)
            .map(|history| evaluate_point(history, material, params, &mut scratch))
            .collect::<Result<_, _>>()?
    };
    let column = |k: usize| results.iter().map(|r| r.0[k]).collect::<Vec<f64>>();
    let (crossland, dang_van, swt, fatemi_socie) = (column(0), column(1), column(2), column(3));
    Ok(FieldIndices {
        crossland_max: Maximum::of(&crossland),
        dang_van_max: Maximum::of(&dang_van),
        swt_max: Maximum::of(&swt),
        fatemi_socie_max: Maximum::of(&fatemi_socie),
        crossland,
        dang_van,
        swt,
        fatemi_socie,
        swt_normal: results.iter().map(|r| r.1[0]).collect(),
        fatemi_socie_normal: results.iter().map(|r| r.1[1]).collect(),
        fatemi_socie_direction: results.iter().map(|r| r.1[2]).collect(),
    })
}

impl Maximum {
    /// The largest value of `field` and its first point (`−∞` at point 0 for an empty field or
    /// one of NaN only).
    pub(crate) fn of(field: &[f64]) -> Self {
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
}
