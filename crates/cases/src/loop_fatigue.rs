//! The fatigue criteria of a completed fretting loop (docs/fatigue.md, "On the fretting loop"):
//! the closed cycle's stress history of the box below the contact
//! ([`halfspace_sam::drivers::fretting_loop::CycleStress`]) through the screened field evaluation
//! ([`halfspace_fatigue::evaluate_screened`]), each cell with its own material's constants.

use std::time::Instant;

use rayon::prelude::*;
use serde_json::{json, Value};

use crate::config::FatigueConfig;
use crate::data::{AttrValue, Record};
use crate::fatigue::critical_plane::{fatemi_socie, swt, PlaneScratch};
use crate::fatigue::field::{FieldParams, Maximum};
use crate::fatigue::invariant::{crossland_dang_van, InvariantScratch};
use crate::fatigue::process_volume::volume_centre;
use crate::fatigue::screened::{
    anchored_bounds, critical_plane_bounds, invariant_bounds, largest_first, reference_bounds,
};
use crate::fatigue::{
    evaluate_process_volume, evaluate_screened, BoxNodes, Material, ScreenedIndices, Voigt,
    VolumeParams,
};
use crate::sam::drivers::fretting_loop::{CycleSources, CycleStress, FrettingLoop, LoopCase};
use crate::sam::subsurface::SubsurfacePlan;
use crate::sam::SamError;
use crate::spec::SpecError;

/// The four index fields of a loop and where they peak.
#[derive(Debug, Clone)]
pub struct LoopFatigue {
    /// The fields and maxima, layer slow, the layers in the order of `z`: the surface layer
    /// `z = 0` first, then the layers below (the maxima's `point` in this order).
    pub indices: ScreenedIndices,
    /// Layers of the fields: the surface layer and the layers below the surface.
    pub layers: usize,
    /// Cells per side `(N₁, N₂)`.
    pub shape: (usize, usize),
    /// Cell centres: `x` (N₁), `y` (N₂), `z` (layers: 0, then `(2k + 1)Δ`) (m).
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub z: Vec<f64>,
    /// Positions `[x, y, z]` of the four maxima (Crossland, Dang Van, SWT, Fatemi–Socie).
    pub at: [[f64; 3]; 4],
    /// Increments of the cycle's path.
    pub increments: usize,
    /// Levels of the box whose stress history was computed (the others cannot reach
    /// `screen_fraction ×` any maximum: [`reachable_levels`]).
    pub levels_computed: usize,
    /// Wall time of the evaluation (s).
    pub seconds: f64,
    /// Its parts (wall, s): [`FatigueSeconds`].
    pub parts: FatigueSeconds,
    /// The criteria on the history averaged over the process volume (`[fatigue]
    /// process_volume`; docs/fatigue.md, "Process volume").
    pub process_volume: Option<VolumeFatigue>,
}

/// Where the evaluation's wall time goes (s; JSON `fatigue.level_bounds_seconds`,
/// `history_seconds`, `criteria_seconds`): the bounds that choose the levels
/// ([`reachable_levels`]: the kernel spectra of the box, the reference and anchored bounds, the
/// seed's exact values), the stress history of the levels computed, and the screened criteria on
/// it ([`halfspace_fatigue::evaluate_screened`]); the process volume's time is its own.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FatigueSeconds {
    pub level_bounds: f64,
    pub history: f64,
    pub criteria: f64,
}

/// The four index fields on the stress history averaged over a process volume of side `side`
/// ([`halfspace_fatigue::evaluate_process_volume`] on the whole box), in the layout of
/// [`LoopFatigue::indices`] (layers by depth, the surface first; `NaN` where the volume leaves the
/// box or the screen skipped the cell).
#[derive(Debug, Clone)]
pub struct VolumeFatigue {
    /// The side ℓ of the cube (m).
    pub side: f64,
    pub indices: ScreenedIndices,
    /// Centres `[x, y, max(z, ℓ/2)]` of the process volumes of the four maxima (m).
    pub at: [[f64; 3]; 4],
    /// Cells whose volume lies inside the box.
    pub inside: usize,
    /// Wall time of the averaging and the criteria (s).
    pub seconds: f64,
}

/// The criteria of the completed loop `lp` with the constants of `cfg`; an error when the loop
/// recorded no complete cycle (no `[fatigue]` table when it ran, or not done). The stress history
/// is computed from the cycle's tractions on the levels of the box the screen can reach
/// ([`reachable_levels`]; every level with inhomogeneities or `screen_fraction = 0`).
pub fn evaluate_loop_fatigue(
    lp: &FrettingLoop,
    cfg: &FatigueConfig,
) -> Result<LoopFatigue, SpecError> {
    let start = Instant::now();
    let fail = |e: &dyn std::fmt::Display| SpecError(format!("fatigue: {e}"));
    let increments = lp.path().len() - lp.path().cycle_start();
    let (sources, (layers, all)) = lp
        .cycle_sources()
        .filter(|s| s.recorded == increments)
        .zip(lp.cycle_levels())
        .ok_or_else(|| {
            SpecError("fatigue: the loop holds no complete stress history of its cycle".into())
        })?;
    let case = lp.case();
    let homogeneous = lp.solver().nested().is_none();
    let mut parts = FatigueSeconds::default();
    let h: CycleStress = if homogeneous && cfg.screen_fraction > 0.0 {
        let matrix = cfg.matrix(case.e, case.nu);
        reachable_levels_timed(
            lp,
            sources,
            layers,
            &matrix,
            cfg.screen_fraction,
            &mut parts,
        )
        .map_err(|e| fail(&e))?
    } else {
        let history = Instant::now();
        let h = lp.cycle_history(Some(&all)).map_err(|e| fail(&e))?;
        parts.history = history.elapsed().as_secs_f64();
        h
    };
    let criteria = Instant::now();
    let (materials, material_of) = cell_materials(cfg, case, &h)?;
    let indices = evaluate_screened(
        &h.stress,
        h.increments,
        &materials,
        &material_of,
        &FieldParams::default(),
        cfg.screen_fraction,
    )
    .map_err(|e| fail(&e))?;
    let at = |m: &Maximum| h.position(m.point).map_err(|e| fail(&e));
    let at = [
        at(&indices.crossland_max)?,
        at(&indices.dang_van_max)?,
        at(&indices.swt_max)?,
        at(&indices.fatemi_socie_max)?,
    ];
    // The stored levels into the whole box (level `k` at `k · N₁N₂`, the surface layer
    // `k = layers` last); the levels not computed are NaN like the cells the screen skipped.
    let per = h.grid.len();
    let full = |p: usize| h.level_of[p / per] * per + p % per;
    let mut indices = indices;
    for f in [
        &mut indices.crossland,
        &mut indices.dang_van,
        &mut indices.swt,
        &mut indices.fatemi_socie,
    ] {
        let mut whole = vec![f64::NAN; all.len() * per];
        for (p, v) in f.iter().enumerate() {
            whole[full(p)] = *v;
        }
        *f = whole;
    }
    for m in [
        &mut indices.crossland_max,
        &mut indices.dang_van_max,
        &mut indices.swt_max,
        &mut indices.fatemi_socie_max,
    ] {
        m.point = full(m.point);
    }
    let levels_computed = h.levels();
    let g = h.grid;
    // The box holds the surface layer after the layers below; the fields list the layers by
    // depth, the surface first.
    let order: Vec<usize> = if all.len() > layers {
        std::iter::once(layers).chain(0..layers).collect()
    } else {
        (0..layers).collect()
    };
    let by_depth = |v: &[f64]| -> Vec<f64> {
        order
            .iter()
            .flat_map(|&k| v[k * per..(k + 1) * per].iter().copied())
            .collect()
    };
    let slot = |p: usize| {
        let k = order.iter().position(|&k| k == p / per).unwrap_or(0);
        k * per + p % per
    };
    for f in [
        &mut indices.crossland,
        &mut indices.dang_van,
        &mut indices.swt,
        &mut indices.fatemi_socie,
    ] {
        *f = by_depth(f);
    }
    for m in [
        &mut indices.crossland_max,
        &mut indices.dang_van_max,
        &mut indices.swt_max,
        &mut indices.fatemi_socie_max,
    ] {
        m.point = slot(m.point);
    }
    let x: Vec<f64> = (0..g.n1).map(|i| g.centre(i, 0).0).collect();
    let y: Vec<f64> = (0..g.n2).map(|j| g.centre(0, j).1).collect();
    let z: Vec<f64> = order.iter().map(|&k| h.depth(k)).collect();
    let increments = h.increments;
    drop(h);
    parts.criteria = criteria.elapsed().as_secs_f64();
    let process_volume = match cfg.process_volume {
        Some(side) => Some(volume_fatigue(lp, cfg, side, &all, &order)?),
        None => None,
    };
    Ok(LoopFatigue {
        at,
        indices,
        layers: order.len(),
        shape: (g.n1, g.n2),
        x,
        y,
        z,
        increments,
        levels_computed,
        seconds: start.elapsed().as_secs_f64(),
        parts,
        process_volume,
    })
}

/// The criteria on the whole box's history averaged over the process volume of side `side`
/// (docs/fatigue.md, "Process volume"): the history of every level of the box (`all`), each cell
/// of its own material ([`cell_materials`]), through
/// [`halfspace_fatigue::evaluate_process_volume`] with the `[fatigue]` screen; the fields
/// reordered by depth (`order`, as [`evaluate_loop_fatigue`]'s). Errors: `side` below a cell or
/// beyond the box (typed, from the fatigue crate).
fn volume_fatigue(
    lp: &FrettingLoop,
    cfg: &FatigueConfig,
    side: f64,
    all: &[usize],
    order: &[usize],
) -> Result<VolumeFatigue, SpecError> {
    let start = Instant::now();
    let fail = |e: &dyn std::fmt::Display| SpecError(format!("fatigue: process volume: {e}"));
    let h = lp.cycle_history(Some(all)).map_err(|e| fail(&e))?;
    let (materials, material_of) = cell_materials(cfg, lp.case(), &h)?;
    let g = h.grid;
    let x: Vec<f64> = (0..g.n1).map(|i| g.centre(i, 0).0).collect();
    let y: Vec<f64> = (0..g.n2).map(|j| g.centre(0, j).1).collect();
    let depth: Vec<f64> = h.level_of.iter().map(|&k| h.depth(k)).collect();
    let per = g.len();
    let CycleStress {
        stress, increments, ..
    } = h;
    let params = VolumeParams {
        side,
        fraction: cfg.screen_fraction,
        field: FieldParams::default(),
    };
    let nodes = BoxNodes {
        x: &x,
        y: &y,
        depth: &depth,
    };
    let e = evaluate_process_volume(
        stress,
        increments,
        &nodes,
        &materials,
        &material_of,
        &params,
    )
    .map_err(|e| fail(&e))?;
    let mut indices = e.indices;
    // The box's level k (surface last) to the fields' slot (by depth, surface first).
    let slot = |p: usize| {
        let k = order.iter().position(|&k| k == p / per).unwrap_or(0);
        k * per + p % per
    };
    let centre = |p: usize| {
        let (k, flat) = (p / per, p % per);
        volume_centre([x[flat / g.n2], y[flat % g.n2], depth[k]], side)
    };
    let at = [
        centre(indices.crossland_max.point),
        centre(indices.dang_van_max.point),
        centre(indices.swt_max.point),
        centre(indices.fatemi_socie_max.point),
    ];
    for f in [
        &mut indices.crossland,
        &mut indices.dang_van,
        &mut indices.swt,
        &mut indices.fatemi_socie,
    ] {
        *f = order
            .iter()
            .flat_map(|&k| f[k * per..(k + 1) * per].iter().copied())
            .collect();
    }
    for m in [
        &mut indices.crossland_max,
        &mut indices.dang_van_max,
        &mut indices.swt_max,
        &mut indices.fatemi_socie_max,
    ] {
        m.point = slot(m.point);
    }
    Ok(VolumeFatigue {
        side,
        indices,
        at,
        inside: e.inside,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The criteria's materials and each stored cell's index into them (docs/fatigue.md,
/// "Materials"): 0 the matrix (`case.e`, `case.nu`, the `[fatigue]` constants); a cell of an
/// inhomogeneity (`h.material ≠ 0`, the cells of the EIM) is of the inhomogeneity whose shape
/// holds the cell centre — the rule of [`crate::sam::eim::InclusionSet::new`] — with its `E`,
/// `ν` and constants ([`FatigueConfig::inhomogeneity_constants`]). Equal materials share one
/// index. Errors: a cell of two overlapping inhomogeneities of different constants, and (a bug)
/// a cell of the EIM that no inhomogeneity holds or of other elastic constants.
pub fn cell_materials(
    cfg: &FatigueConfig,
    case: &LoopCase,
    h: &CycleStress,
) -> Result<(Vec<Material>, Vec<u16>), SpecError> {
    // `position` indexes the history's levels: its shape first (a typed error, no panic).
    h.check_shape()
        .map_err(|e| SpecError(format!("fatigue: {e}")))?;
    let own = cfg.inhomogeneity_materials(&case.inhomogeneities);
    let mut materials = vec![cfg.matrix(case.e, case.nu)];
    let mut material_of = vec![0u16; h.material.len()];
    for (p, &m) in h.material.iter().enumerate() {
        if m == 0 {
            continue;
        }
        let at = h
            .position(p)
            .map_err(|e| SpecError(format!("fatigue: {e}")))?;
        let mut holders = case
            .inhomogeneities
            .iter()
            .zip(&own)
            .enumerate()
            .filter(|(_, (inh, _))| inh.contains(at));
        let Some((first, (inh, material))) = holders.next() else {
            return Err(SpecError(format!(
                "fatigue: the cell at {at:?} m is of an inhomogeneity's material but no \
                 inhomogeneity holds its centre"
            )));
        };
        if h.materials.get(m as usize - 1) != Some(&(inh.e, inh.nu)) {
            return Err(SpecError(format!(
                "fatigue: the cell at {at:?} m: inhomogeneity {} has other elastic constants \
                 than the cell's",
                first + 1
            )));
        }
        if let Some((other, _)) = holders.find(|(_, (_, o))| *o != material) {
            return Err(SpecError(format!(
                "fatigue: inhomogeneities {} and {} overlap (at {at:?} m) with different fatigue \
                 constants: make them disjoint, or give them the same constants",
                first + 1,
                other + 1
            )));
        }
        let index = match materials.iter().position(|q| q == material) {
            Some(i) => i,
            None => {
                materials.push(*material);
                materials.len() - 1
            }
        };
        material_of[p] = u16::try_from(index).map_err(|_| {
            SpecError(format!(
                "fatigue: more than {} distinct materials",
                u16::MAX as usize + 1
            ))
        })?;
    }
    Ok((materials, material_of))
}

/// Exact values at this many cells per criterion give the screen its lower bounds of the maxima
/// ([`reachable_levels`]).
const SEED_CELLS: usize = 16;

/// The stress history of the homogeneous loop `lp` on the levels of the box the screen can reach
/// (docs/fatigue.md, "Layers the screen cannot reach"): with `τ^ref = (max_t τ + min_t τ)/2` and
/// `amplitude = (max_t τ − min_t τ)/2` per cell and traction component of the cycle, the reference
/// stress `σ^ref` (Love's stresses of `τ^ref`) and the deviation bounds
/// ([`SubsurfacePlan::deviation_bounds`]) give every cell an upper bound `A` of each criterion
/// ([`halfspace_fatigue::screened::reference_bounds`]). The surface layer and the levels holding
/// the `SEED_CELLS` cells of largest `A` of each criterion are computed first; each criterion
/// at their `SEED_CELLS` cells of largest path bound (the bounds of
/// [`halfspace_fatigue::evaluate_screened`]) gives a lower bound `L` of its maximum; a level is a
/// candidate if one of its cells has `A ≥ fraction · L` for some criterion (all levels where
/// some `L ≤ 0`), and computed only if the anchored bound ([`AnchoredBound`]) of one of those
/// cells also reaches `fraction · L`. Every cell whose value reaches `fraction ×` the maximum is
/// therefore in a computed level. The seed's history is kept and the other computed levels'
/// merged into it ([`CycleStress::merged`]). Errors: a loop with inhomogeneities, `sources`
/// other than the loop's own complete cycle, `layers` other than the loop's box
/// ([`FrettingLoop::cycle_levels`]).
///
/// One plan of the whole box ([`SubsurfacePlan::with_levels`]) serves every step: its Love and
/// bound spectra are built once, then kept for the seed, the candidates and the computed levels
/// only ([`SubsurfacePlan::retain_levels`]); each level's history is bit for bit
/// [`FrettingLoop::cycle_history`]'s ([`CycleStress::of_levels`]).
pub fn reachable_levels(
    lp: &FrettingLoop,
    sources: &CycleSources,
    layers: usize,
    matrix: &Material,
    fraction: f64,
) -> Result<CycleStress, SamError> {
    reachable_levels_timed(
        lp,
        sources,
        layers,
        matrix,
        fraction,
        &mut FatigueSeconds::default(),
    )
}

/// [`reachable_levels`], adding its time to `parts` (the stress histories to `history`, the rest
/// to `level_bounds`).
// Index loops over the four criteria read like the bounds they compare.
#[allow(clippy::needless_range_loop)]
fn reachable_levels_timed(
    lp: &FrettingLoop,
    sources: &CycleSources,
    layers: usize,
    matrix: &Material,
    fraction: f64,
    parts: &mut FatigueSeconds,
) -> Result<CycleStress, SamError> {
    let start = Instant::now();
    let mut in_history = 0.0;
    let case = lp.case();
    let LoopBox {
        depth,
        layers: box_layers,
        grid,
        increments,
        friction,
    } = LoopBox::of(lp, sources)?;
    if layers != box_layers {
        return Err(SamError::InvalidInput(format!(
            "fatigue bounds: {layers} layers asked, the loop's box has {box_layers}"
        )));
    }
    let n = grid.len();
    // τ^ref and the amplitude per cell of p, q₁, q₂ over the cycle.
    let mut reference = vec![vec![0.0; n]; 3];
    let mut amplitude = vec![vec![0.0; n]; 3];
    for c in 0..if friction { 3 } else { 1 } {
        for cell in 0..n {
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for t in 0..increments {
                let v = sources.tractions[(t * 3 + c) * n + cell];
                lo = lo.min(v);
                hi = hi.max(v);
            }
            reference[c][cell] = 0.5 * (hi + lo);
            amplitude[c][cell] = 0.5 * (hi - lo);
        }
    }
    let all: Vec<usize> = (0..=layers).collect();
    let mut plan = SubsurfacePlan::with_levels(&grid, case.e, case.nu, depth, &all)?;
    let q = friction.then_some([&reference[1][..], &reference[2][..]]);
    let (sigma_ref, _) = plan.stress(&reference[0], q, None)?;
    let bound = plan.deviation_bounds([&amplitude[0], &amplitude[1], &amplitude[2]])?;
    // Rounding of the transforms of σ(t) and σ^ref: 10⁻⁹ of the largest stress and bound.
    let scale = sigma_ref
        .iter()
        .chain(bound.iter())
        .flat_map(|f| f.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let cells = all.len() * n;
    let a: Vec<[f64; 4]> = (0..cells)
        .into_par_iter()
        .map(|p| {
            let r: Voigt = std::array::from_fn(|k| sigma_ref[k][p]);
            let d: [f64; 6] = std::array::from_fn(|f| bound[f][p] + 1e-9 * scale);
            reference_bounds(&r, &d, matrix)
        })
        .collect::<Result<_, _>>()
        .map_err(|e| SamError::InvalidInput(e.to_string()))?;
    // The seed: the surface layer and the levels of the cells of largest bound of each criterion.
    let mut seed: Vec<usize> = vec![layers];
    for c in 0..4 {
        let mut order: Vec<usize> = (0..cells).collect();
        largest_first(&mut order, 0, SEED_CELLS, |p| a[p][c]);
        seed.extend(order.iter().take(SEED_CELLS).map(|p| p / n));
    }
    seed.sort_unstable();
    seed.dedup();
    let history = Instant::now();
    let seed_history = CycleStress::of_levels(&mut plan, &seed, sources, friction)?;
    in_history += history.elapsed().as_secs_f64();
    // Exact criteria at the seed levels' cells of largest path bound
    // ([`halfspace_fatigue::screened::invariant_bounds`], `critical_plane_bounds`): lower bounds
    // of the maxima.
    let params = FieldParams::default();
    let seed_cells = seed.len() * n;
    let path_of = |q: usize| -> Vec<Voigt> {
        seed_history.stress[q * increments * 6..(q + 1) * increments * 6]
            .chunks_exact(6)
            .map(|v| std::array::from_fn(|i| v[i]))
            .collect()
    };
    let path_bounds: Vec<[f64; 4]> = (0..seed_cells)
        .into_par_iter()
        .map(|q| {
            let path = path_of(q);
            let [c, dv] = invariant_bounds(&path, matrix)?;
            let [s, f] = critical_plane_bounds(&path, matrix)?;
            Ok([c, dv, s, f])
        })
        .collect::<Result<_, halfspace_fatigue::FatigueError>>()
        .map_err(|e| SamError::InvalidInput(e.to_string()))?;
    let mut lower = [f64::NEG_INFINITY; 4];
    let mut inv = InvariantScratch::default();
    let mut plane = PlaneScratch::default();
    let fatigue = |e: halfspace_fatigue::FatigueError| SamError::InvalidInput(e.to_string());
    for c in 0..4 {
        let mut order: Vec<usize> = (0..seed_cells).collect();
        largest_first(&mut order, 0, SEED_CELLS, |p| path_bounds[p][c]);
        for &q in order.iter().take(SEED_CELLS) {
            let path = path_of(q);
            let value = match c {
                0 | 1 => {
                    let (cr, dv) = crossland_dang_van(&path, matrix, &mut inv).map_err(fatigue)?;
                    if c == 0 {
                        cr.index
                    } else {
                        dv.index
                    }
                }
                2 => {
                    swt(&path, matrix, &params.plane, &mut plane)
                        .map_err(fatigue)?
                        .value
                }
                _ => {
                    fatemi_socie(&path, matrix, &params.plane, &mut plane)
                        .map_err(fatigue)?
                        .value
                }
            };
            lower[c] = lower[c].max(value);
        }
    }
    // The levels the reference bound keeps, then those of them the anchored bound keeps.
    let reaches = |b: &[f64; 4]| (0..4).any(|c| lower[c] <= 0.0 || b[c] >= fraction * lower[c]);
    let candidates: Vec<usize> = all
        .iter()
        .copied()
        .filter(|&k| !seed.contains(&k) && (0..n).any(|cell| reaches(&a[k * n + cell])))
        .collect();
    let finish = |h: CycleStress, in_history: f64, parts: &mut FatigueSeconds| {
        parts.history += in_history;
        parts.level_bounds += start.elapsed().as_secs_f64() - in_history;
        Ok(h)
    };
    if candidates.is_empty() {
        return finish(seed_history, in_history, parts);
    }
    plan.retain_levels(&candidates);
    let others = anchored_levels(
        &mut plan,
        sources,
        &candidates,
        &a,
        &reaches,
        matrix,
        friction,
    )?;
    if others.is_empty() {
        return finish(seed_history, in_history, parts);
    }
    // The seed's history is kept; only the other levels are computed.
    plan.retain_levels(&others);
    plan.drop_bound_spectra();
    let history = Instant::now();
    let others = CycleStress::of_levels(&mut plan, &others, sources, friction)?;
    drop(plan);
    let merged = seed_history.merged(others)?;
    in_history += history.elapsed().as_secs_f64();
    finish(merged, in_history, parts)
}

/// What [`reachable_levels`] and [`AnchoredBound::new`] read of a homogeneous loop's box: the
/// box depth and layers, the surface grid, the cycle's increments and whether the contact has
/// friction. An error (docs/fatigue.md, "Layers the screen cannot reach") when the loop has no
/// fatigue depth, has inhomogeneities (their eigenstrains are not in the bounds), `sources` are
/// not the loop's own ([`FrettingLoop::cycle_sources`], by identity or value), record other
/// than the loop's closed cycle (`4q + 1` increments), or (public fields) do not fit the loop's
/// grid — `cells = N₁N₂`, `3 · recorded · N₁N₂` traction values and `recorded · eigen_len`
/// eigenstrain values.
struct LoopBox {
    depth: f64,
    layers: usize,
    grid: crate::sam::SurfaceGrid,
    increments: usize,
    friction: bool,
}

impl LoopBox {
    fn of(lp: &FrettingLoop, sources: &CycleSources) -> Result<Self, SamError> {
        let bad = |what: String| Err(SamError::InvalidInput(format!("fatigue bounds: {what}")));
        let (Some(depth), Some((layers, _))) = (lp.case().fatigue_depth, lp.cycle_levels()) else {
            return bad("the loop has no fatigue depth".into());
        };
        if lp.solver().nested().is_some() {
            return bad(
                "the level bounds are of a homogeneous loop; this one has inhomogeneities".into(),
            );
        }
        if !lp
            .cycle_sources()
            .is_some_and(|own| std::ptr::eq(own, sources) || own == sources)
        {
            return bad("the cycle sources are not the loop's own".into());
        }
        let cycle = lp.path().len() - lp.path().cycle_start();
        if sources.recorded != cycle {
            return bad(format!(
                "the cycle sources record {} increments, the loop's cycle has {cycle}",
                sources.recorded
            ));
        }
        let grid = *lp.solver().problem().grid();
        let n = grid.len();
        let increments = sources.recorded;
        let tractions = increments.checked_mul(3 * n);
        let eigenstrain = increments.checked_mul(sources.eigen_len);
        if sources.cells != n
            || tractions != Some(sources.tractions.len())
            || eigenstrain != Some(sources.eigenstrain.len())
        {
            return bad(format!(
                "cycle sources of {} cells, {} increments, {} traction and {} eigenstrain values \
                 do not fit the loop's {n} surface cells (3 · {increments} · {n} tractions, \
                 {increments} · {} eigenstrains)",
                sources.cells,
                increments,
                sources.tractions.len(),
                sources.eigenstrain.len(),
                sources.eigen_len,
            ));
        }
        Ok(Self {
            depth,
            layers,
            grid,
            increments,
            friction: lp.solver().problem().friction() > 0.0,
        })
    }
}

/// Groups of increments of the anchored level bound ([`AnchoredBound`]).
const ANCHOR_GROUPS: usize = 8;

/// The levels of `candidates` (increasing) that the anchored bound cannot rule out
/// (docs/fatigue.md, "Layers the screen cannot reach", step 6): each cell of a candidate level
/// whose reference bound `a` reaches is bounded again by [`AnchoredBound`] (the smaller of the two
/// counts) and the level is kept if one of its cells still `reaches`.
fn anchored_levels(
    plan: &mut SubsurfacePlan,
    sources: &CycleSources,
    candidates: &[usize],
    a: &[[f64; 4]],
    reaches: &(dyn Fn(&[f64; 4]) -> bool + Sync),
    matrix: &Material,
    friction: bool,
) -> Result<Vec<usize>, SamError> {
    let Some(bound) = AnchoredBound::from_plan(plan, sources, candidates, friction)? else {
        return Ok(candidates.to_vec());
    };
    let n = bound.cells;
    // The levels in parallel, each scanned until one of its cells reaches.
    let kept: Vec<Option<usize>> = candidates
        .par_iter()
        .enumerate()
        .map_init(
            || (Vec::new(), Vec::new()),
            |scratch, (i, &k)| -> Result<Option<usize>, SamError> {
                for cell in 0..n {
                    let reference = &a[k * n + cell];
                    if !reaches(reference) {
                        continue;
                    }
                    let anchored = bound.cell(i * n + cell, matrix, scratch)?;
                    if reaches(&std::array::from_fn(|c| anchored[c].min(reference[c]))) {
                        return Ok(Some(k));
                    }
                }
                Ok(None)
            },
        )
        .collect::<Result<_, _>>()?;
    Ok(kept.into_iter().flatten().collect())
}

/// The anchored level bound of a homogeneous loop on some levels of its box (docs/fatigue.md,
/// "Layers the screen cannot reach", step 6): the exact stresses at `ANCHOR_GROUPS + 1` anchor
/// increments `t_g` (evenly spaced from the first to the last, with the turning points of the
/// cycle among them when its increments are `4q + 1`), and per group `g` the residual
/// `r_g(t) = τ(t) − ((1 − w) τ(t_g) + w τ(t_{g+1}))`, `w = (t − t_g)/(t_{g+1} − t_g)`, of the
/// linear interpolation of the tractions between its anchors, bounded at every cell by
/// [`SubsurfacePlan::deviation_bounds_of`] of `max_{t ∈ g} |r_g(t)|` (Love's stresses are
/// linear in the tractions, so `σ(t)` is the interpolation of the anchors' stresses plus the
/// stress of `r_g(t)`); [`AnchoredBound::cell`] gives the four criteria's
/// [`halfspace_fatigue::screened::anchored_bounds`].
pub struct AnchoredBound {
    /// Cells per level.
    cells: usize,
    /// The anchors' stresses `fields[anchor][component][position-in-levels · N₁N₂ + cell]`.
    fields: Vec<[Vec<f64>; 6]>,
    /// The groups' deviation bounds `bounds[group][functional][…]` (incl. the rounding margin).
    bounds: Vec<[Vec<f64>; 6]>,
    /// `10⁻⁹` of the largest stress and bound: the rounding of the transforms of `σ(t)` and of
    /// the anchors.
    rounding: f64,
}

impl AnchoredBound {
    /// The anchored bound on the box levels `levels` (increasing) of the loop `lp` with the
    /// cycle `sources`; `None` for a cycle of fewer than 3 increments (nothing to interpolate).
    /// Errors: those of the loop and its sources (`LoopBox::of`: a homogeneous loop, its own
    /// complete cycle), levels not increasing or past the loop's box.
    pub fn new(
        lp: &FrettingLoop,
        sources: &CycleSources,
        levels: &[usize],
    ) -> Result<Option<Self>, SamError> {
        let case = lp.case();
        let LoopBox {
            depth,
            layers,
            grid,
            increments,
            friction,
        } = LoopBox::of(lp, sources)?;
        if levels.windows(2).any(|w| w[0] >= w[1]) || levels.iter().any(|&k| k > layers) {
            return Err(SamError::InvalidInput(format!(
                "fatigue bounds: levels {levels:?} are not increasing box levels of the loop's \
                 0..={layers}"
            )));
        }
        if increments < 3 {
            return Ok(None);
        }
        let mut plan = SubsurfacePlan::with_levels(&grid, case.e, case.nu, depth, levels)?;
        Self::from_plan(&mut plan, sources, levels, friction)
    }

    /// [`AnchoredBound::new`] with the kernel spectra of `plan` (holding the box levels
    /// `levels`, increasing) for the cycle `sources` of a loop checked by the caller (`LoopBox`);
    /// `friction`: the shear tractions are used.
    fn from_plan(
        plan: &mut SubsurfacePlan,
        sources: &CycleSources,
        levels: &[usize],
        friction: bool,
    ) -> Result<Option<Self>, SamError> {
        let increments = sources.recorded;
        let n = plan.grid().len();
        if increments < 3 {
            return Ok(None);
        }
        let groups = ANCHOR_GROUPS.min(increments - 1);
        let mut anchors: Vec<usize> = (0..=groups)
            .map(|g| (2 * g * (increments - 1) + groups) / (2 * groups))
            .collect();
        anchors.dedup();
        let components = if friction { 3 } else { 1 };
        let traction = |t: usize, c: usize, cell: usize| sources.tractions[(t * 3 + c) * n + cell];
        let mut residual = vec![vec![vec![0.0f64; n]; 3]; anchors.len() - 1];
        for (g, r) in residual.iter_mut().enumerate() {
            let (t0, t1) = (anchors[g], anchors[g + 1]);
            for (c, rc) in r.iter_mut().enumerate().take(components) {
                for (cell, out) in rc.iter_mut().enumerate() {
                    let (v0, v1) = (traction(t0, c, cell), traction(t1, c, cell));
                    let mut largest = 0.0f64;
                    for t in t0 + 1..t1 {
                        let w = (t - t0) as f64 / (t1 - t0) as f64;
                        largest =
                            largest.max((traction(t, c, cell) - ((1.0 - w) * v0 + w * v1)).abs());
                    }
                    *out = largest;
                }
            }
        }
        let mut fields = Vec::with_capacity(anchors.len());
        for &t in &anchors {
            let (p, q, _) = sources.increment(t);
            fields.push(plan.stress_of_levels(levels, p, friction.then_some(q))?);
        }
        let maps: Vec<[&[f64]; 3]> = residual
            .iter()
            .map(|r| [&r[0][..], &r[1][..], &r[2][..]])
            .collect();
        let bounds = plan.deviation_bounds_of_levels(levels, &maps)?;
        let scale = fields
            .iter()
            .flat_map(|f| f.iter())
            .chain(bounds.iter().flat_map(|b| b.iter()))
            .flat_map(|f| f.iter())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        Ok(Some(Self {
            cells: n,
            fields,
            bounds,
            rounding: 1e-9 * scale,
        }))
    }

    /// Cells of the bound: the levels' count · `N₁N₂`.
    pub fn points(&self) -> usize {
        self.fields.first().map_or(0, |f| f[0].len())
    }

    /// `[Crossland, Dang Van, SWT, Fatemi–Socie]` bounds of cell `q` (position in the levels ·
    /// `N₁N₂` + cell) with the constants `matrix`
    /// ([`halfspace_fatigue::screened::anchored_bounds`]); `scratch` holds the anchors' path and
    /// the groups' deviations. An error for `q ≥` [`AnchoredBound::points`].
    pub fn cell(
        &self,
        q: usize,
        matrix: &Material,
        scratch: &mut (Vec<Voigt>, Vec<[f64; 6]>),
    ) -> Result<[f64; 4], SamError> {
        if q >= self.points() {
            return Err(SamError::InvalidInput(format!(
                "anchored bound: cell {q} of {} (levels · N₁N₂)",
                self.points()
            )));
        }
        let (path, deviation) = scratch;
        path.clear();
        path.extend(self.fields.iter().map(|f| std::array::from_fn(|c| f[c][q])));
        deviation.clear();
        deviation.extend(
            self.bounds
                .iter()
                .map(|b| std::array::from_fn(|f| b[f][q] + self.rounding)),
        );
        anchored_bounds(path, deviation, matrix).map_err(|e| SamError::InvalidInput(e.to_string()))
    }
}

/// The volume fields' names in results.h5 (each `(layers, N₁, N₂)`).
pub const FATIGUE_FIELDS: [&str; 4] = ["crossland", "dang_van", "swt", "fatemi_socie"];

/// The four criteria's fields and maxima, in the order of [`FATIGUE_FIELDS`].
fn criteria(i: &ScreenedIndices) -> [(&[f64], Maximum); 4] {
    [
        (&i.crossland, i.crossland_max),
        (&i.dang_van, i.dang_van_max),
        (&i.swt, i.swt_max),
        (&i.fatemi_socie, i.fatemi_socie_max),
    ]
}

/// `rec` with the four fields `{name}{suffix}` of shape `shape` and their maxima as attributes
/// `{name}{suffix}_max`, `…_max_x`, `…_max_y`, `…_max_z` (`at`: the maxima's positions, m).
fn record_criteria(
    mut rec: Record,
    suffix: &str,
    i: &ScreenedIndices,
    at: &[[f64; 3]; 4],
    shape: &[usize; 3],
) -> Record {
    for (k, (name, (field, m))) in FATIGUE_FIELDS.iter().zip(criteria(i)).enumerate() {
        rec = rec
            .shaped(&format!("{name}{suffix}"), field.to_vec(), shape)
            .attr(&format!("{name}{suffix}_max"), AttrValue::Float(m.value))
            .attr(&format!("{name}{suffix}_max_x"), AttrValue::Float(at[k][0]))
            .attr(&format!("{name}{suffix}_max_y"), AttrValue::Float(at[k][1]))
            .attr(&format!("{name}{suffix}_max_z"), AttrValue::Float(at[k][2]));
    }
    rec
}

impl LoopFatigue {
    /// The JSON keys `crossland_max`, `crossland_max_at` ([x, y, z] m), `dang_van_max(_at)`,
    /// `swt_max(_at)` (Pa), `fatemi_socie_max(_at)`, and the evaluation's cost; with a process
    /// volume also `crossland_pv_max`, `crossland_pv_max_at` (the centre of the maximum's cube,
    /// m), … for the four criteria and the `process_volume` block.
    pub fn summary(&self) -> Value {
        let i = &self.indices;
        let finite = |v: f64| if v.is_finite() { json!(v) } else { Value::Null };
        let mut summary = json!({
            "crossland_max": finite(i.crossland_max.value),
            "crossland_max_at": self.at[0],
            "dang_van_max": finite(i.dang_van_max.value),
            "dang_van_max_at": self.at[1],
            "swt_max": finite(i.swt_max.value),
            "swt_max_at": self.at[2],
            "fatemi_socie_max": finite(i.fatemi_socie_max.value),
            "fatemi_socie_max_at": self.at[3],
            "fatigue": {
                "cells": i.crossland.len(),
                "layers": self.layers,
                "surface_layer": self.z.first() == Some(&0.0),
                "increments": self.increments,
                "levels_computed": self.levels_computed,
                "invariant_evaluated": i.invariant_evaluated,
                "swt_evaluated": i.swt_evaluated,
                "fatemi_socie_evaluated": i.fatemi_socie_evaluated,
                "seconds": self.seconds,
                "level_bounds_seconds": self.parts.level_bounds,
                "history_seconds": self.parts.history,
                "criteria_seconds": self.parts.criteria,
            },
        });
        if let (Some(v), Some(out)) = (&self.process_volume, summary.as_object_mut()) {
            let i = &v.indices;
            for (k, (name, (_, m))) in FATIGUE_FIELDS.iter().zip(criteria(i)).enumerate() {
                out.insert(format!("{name}_pv_max"), finite(m.value));
                out.insert(format!("{name}_pv_max_at"), json!(v.at[k]));
            }
            out.insert(
                "process_volume".into(),
                json!({
                    "side": v.side,
                    "cells_inside": v.inside,
                    "invariant_evaluated": i.invariant_evaluated,
                    "swt_evaluated": i.swt_evaluated,
                    "fatemi_socie_evaluated": i.fatemi_socie_evaluated,
                    "seconds": v.seconds,
                }),
            );
        }
        summary
    }

    /// `rec` with `z` (layer depths, m: 0 the surface layer, then `(2k + 1)Δ`) and the four
    /// volume fields `(layers, N₁, N₂)` (`NaN`
    /// where the screen skipped them), the maxima as attributes; with a process volume also
    /// `crossland_pv`, … (the same shape, `NaN` also where the cube leaves the box), their maxima
    /// and the side `process_volume` (m) as attributes.
    pub fn record(&self, rec: Record) -> Record {
        let shape = [self.layers, self.shape.0, self.shape.1];
        let mut rec = record_criteria(
            rec.array("z", self.z.clone()),
            "",
            &self.indices,
            &self.at,
            &shape,
        );
        if let Some(v) = &self.process_volume {
            rec = record_criteria(
                rec.attr("process_volume", AttrValue::Float(v.side)),
                "_pv",
                &v.indices,
                &v.at,
                &shape,
            );
        }
        rec
    }

    /// The names of the volume fields [`LoopFatigue::record`] writes, each `(layers, N₁, N₂)`:
    /// [`FATIGUE_FIELDS`], then with a process volume `crossland_pv`, `dang_van_pv`, `swt_pv`,
    /// `fatemi_socie_pv` (the fields the XDMF file lists).
    pub fn volume_fields(&self) -> Vec<String> {
        let mut names: Vec<String> = FATIGUE_FIELDS.iter().map(|s| s.to_string()).collect();
        if self.process_volume.is_some() {
            names.extend(FATIGUE_FIELDS.iter().map(|s| format!("{s}_pv")));
        }
        names
    }

    /// The XDMF description of the volume fields (axes Z Y X = depth, x, y): a rectilinear
    /// lattice on the datasets `z`, `x`, `y` of results.h5 (the surface layer at `z = 0` is `Δ`
    /// above the first layer, the layers below `2Δ` apart).
    pub fn volume(&self) -> crate::data::RectilinearVolume {
        crate::data::RectilinearVolume {
            dims: [self.layers, self.shape.0, self.shape.1],
            axes: ["z".into(), "x".into(), "y".into()],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::LoopConfig;

    /// The fields the XDMF file lists are those results.h5 holds, of the lattice's shape: the
    /// four pointwise ones, and with a process volume also the four `*_pv` (written to an XDMF
    /// file and read back).
    #[test]
    fn the_xdmf_lists_every_volume_field_of_the_record() {
        let (layers, n1, n2) = (3, 4, 2);
        let cells = layers * n1 * n2;
        let maximum = halfspace_fatigue::field::Maximum {
            value: 1.0,
            point: 5,
        };
        let indices = ScreenedIndices {
            crossland: vec![0.5; cells],
            dang_van: vec![0.5; cells],
            swt: vec![0.5; cells],
            fatemi_socie: vec![0.5; cells],
            crossland_max: maximum,
            dang_van_max: maximum,
            swt_max: maximum,
            fatemi_socie_max: maximum,
            invariant_evaluated: cells,
            swt_evaluated: cells,
            fatemi_socie_evaluated: cells,
        };
        let mut f = LoopFatigue {
            indices: indices.clone(),
            layers,
            shape: (n1, n2),
            x: vec![0.0, 1.0, 2.0, 3.0],
            y: vec![0.0, 1.0],
            z: vec![0.0, 0.5, 1.5],
            at: [[0.0; 3]; 4],
            increments: 2,
            levels_computed: layers,
            seconds: 0.0,
            parts: FatigueSeconds::default(),
            process_volume: None,
        };
        assert_eq!(f.volume_fields(), FATIGUE_FIELDS.to_vec());
        f.process_volume = Some(VolumeFatigue {
            side: 1.0,
            indices,
            at: [[0.0; 3]; 4],
            inside: cells,
            seconds: 0.0,
        });
        let names = f.volume_fields();
        assert_eq!(names.len(), 8);
        let rec = f.record(crate::data::Record::default());
        for name in &names {
            assert_eq!(rec.shape_of(name), Some(vec![layers, n1, n2]), "{name}");
        }
        let dir = std::env::temp_dir().join(format!("halfspace-xdmf-pv-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let xdmf = dir.join("results.xdmf");
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        crate::data::write_xdmf_rectilinear(
            &xdmf,
            &dir.join("results.h5"),
            &f.volume(),
            &refs,
            "test",
        )
        .unwrap();
        let text = std::fs::read_to_string(&xdmf).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        for name in [
            "crossland",
            "fatemi_socie",
            "crossland_pv",
            "swt_pv",
            "fatemi_socie_pv",
        ] {
            assert!(
                text.contains(&format!("results.h5:/{name}<")),
                "{name}: {text}"
            );
        }
    }

    /// The levels the screen skips ([`reachable_levels`]) hold no cell that reaches
    /// `screen_fraction ×` a maximum: against the same screened evaluation of the whole box's
    /// history, the maxima and their locations are bit for bit the same, every value computed in
    /// both is the same, every cell at or above `screen_fraction ×` its maximum holds its value,
    /// and levels are skipped.
    #[test]
    fn the_levels_the_screen_skips_cannot_reach_the_maxima() {
        let mut case = LoopCase {
            grid: 32,
            normal_steps: 4,
            shift_step: 0.01e-6,
            ..LoopCase::default()
        };
        case.fatigue_depth = Some(1.5 * case.hertz_radius());
        let cfg = FatigueConfig {
            f_minus1: 400e6,
            t_minus1: 280e6,
            fs_k: 0.5,
            yield_stress: 600e6,
            depth_over_a: 1.5,
            screen_fraction: 0.5,
            inhomogeneity: None,
            process_volume: None,
            own: Vec::new(),
        };
        let mut lp = FrettingLoop::new(case.clone()).unwrap();
        lp.run(|_| std::ops::ControlFlow::Continue(())).unwrap();
        let f = evaluate_loop_fatigue(&lp, &cfg).unwrap();
        let whole = lp.cycle_stress().unwrap().unwrap();
        let materials = [cfg.matrix(case.e, case.nu)];
        let full = evaluate_screened(
            &whole.stress,
            whole.increments,
            &materials,
            &whole.material,
            &FieldParams::default(),
            cfg.screen_fraction,
        )
        .unwrap();
        let (layers, per) = (whole.layers, whole.grid.len());
        assert_eq!(f.layers, layers + 1);
        assert!(
            f.levels_computed < layers + 1,
            "no level skipped: {} of {}",
            f.levels_computed,
            layers + 1
        );
        // The box's cell p (surface layer last) in the fields' order (surface layer first).
        let slot = |p: usize| {
            let k = p / per;
            (if k == layers { 0 } else { k + 1 }) * per + p % per
        };
        let pairs = [
            (
                &full.crossland,
                &f.indices.crossland,
                full.crossland_max,
                f.indices.crossland_max,
            ),
            (
                &full.dang_van,
                &f.indices.dang_van,
                full.dang_van_max,
                f.indices.dang_van_max,
            ),
            (&full.swt, &f.indices.swt, full.swt_max, f.indices.swt_max),
            (
                &full.fatemi_socie,
                &f.indices.fatemi_socie,
                full.fatemi_socie_max,
                f.indices.fatemi_socie_max,
            ),
        ];
        for (k, (a, b, ma, mb)) in pairs.into_iter().enumerate() {
            assert_eq!(ma.value, mb.value, "criterion {k}");
            assert_eq!(slot(ma.point), mb.point, "criterion {k}");
            assert_eq!(whole.position(ma.point).unwrap(), f.at[k], "criterion {k}");
            let mut reached = 0;
            for (p, &v) in a.iter().enumerate() {
                let w = b[slot(p)];
                if v.is_finite() && w.is_finite() {
                    assert_eq!(v, w, "criterion {k}, cell {p}");
                }
                if v >= cfg.screen_fraction * ma.value {
                    reached += 1;
                    assert!(w.is_finite(), "criterion {k}, cell {p}: {v} not evaluated");
                }
            }
            assert!(reached > 0);
        }
        // The anchored bound is above every level's exact maxima (the screened evaluation of the
        // level's history alone with fraction 1 gives them), on every level of the box.
        let sources = lp.cycle_sources().unwrap();
        let levels: Vec<usize> = (0..=layers).collect();
        let bound = AnchoredBound::new(&lp, sources, &levels).unwrap().unwrap();
        let mut scratch = (Vec::new(), Vec::new());
        let inc = whole.increments;
        for k in levels {
            let path = &whole.stress[k * per * inc * 6..(k + 1) * per * inc * 6];
            let e = evaluate_screened(
                path,
                inc,
                &materials,
                &vec![0; per],
                &FieldParams::default(),
                1.0,
            )
            .unwrap();
            let exact = [
                e.crossland_max.value,
                e.dang_van_max.value,
                e.swt_max.value,
                e.fatemi_socie_max.value,
            ];
            let mut largest = [f64::NEG_INFINITY; 4];
            for cell in 0..per {
                let b = bound
                    .cell(k * per + cell, &materials[0], &mut scratch)
                    .unwrap();
                for c in 0..4 {
                    largest[c] = largest[c].max(b[c]);
                }
            }
            for c in 0..4 {
                assert!(
                    exact[c] <= largest[c],
                    "level {k}, criterion {c}: maximum {} above the anchored bound {}",
                    exact[c],
                    largest[c]
                );
            }
        }
    }

    /// Cycle sources that do not fit the loop's grid (public fields) are refused with an error
    /// by [`AnchoredBound::new`] and [`reachable_levels`] (no index panic), and
    /// [`AnchoredBound::cell`] refuses a cell past its levels; the fitting sources give a bound.
    #[test]
    fn sources_off_the_grid_and_cells_past_the_levels_are_errors() {
        let mut case = LoopCase {
            grid: 16,
            normal_steps: 4,
            shift_step: 0.01e-6,
            ..LoopCase::default()
        };
        case.fatigue_depth = Some(0.7 * case.hertz_radius());
        let mut lp = FrettingLoop::new(case.clone()).unwrap();
        lp.run(|_| std::ops::ControlFlow::Continue(())).unwrap();
        let sources = lp.cycle_sources().unwrap().clone();
        let (layers, _) = lp.cycle_levels().unwrap();
        let matrix = Material {
            f_minus1: 400e6,
            t_minus1: 280e6,
            young: case.e,
            poisson: case.nu,
            fs_k: 0.5,
            yield_stress: 600e6,
        };
        let levels = [0, layers];
        let bound = AnchoredBound::new(&lp, &sources, &levels).unwrap().unwrap();
        assert_eq!(bound.points(), 2 * 16 * 16);
        let mut scratch = (Vec::new(), Vec::new());
        assert!(bound
            .cell(bound.points() - 1, &matrix, &mut scratch)
            .is_ok());
        assert!(bound.cell(bound.points(), &matrix, &mut scratch).is_err());
        let mut fewer_cells = sources.clone();
        fewer_cells.cells = 8 * 8;
        let mut short = sources.clone();
        short.tractions.truncate(short.tractions.len() - 1);
        let mut more_recorded = sources.clone();
        more_recorded.recorded += 1;
        let mut eigen = sources.clone();
        eigen.eigen_len = 6;
        for bad in [fewer_cells, short, more_recorded, eigen] {
            assert!(
                AnchoredBound::new(&lp, &bad, &levels).is_err(),
                "{:?}",
                bad.cells
            );
            assert!(reachable_levels(&lp, &bad, layers, &matrix, 0.5).is_err());
        }
        // Layers other than the loop's box, levels past it or not increasing.
        let message = |r: Result<CycleStress, SamError>| r.unwrap_err().to_string();
        assert!(
            message(reachable_levels(&lp, &sources, layers + 1, &matrix, 0.5))
                .contains("layers asked")
        );
        assert!(reachable_levels(&lp, &sources, layers, &matrix, 0.5).is_ok());
        for levels in [vec![0, layers + 1], vec![1, 0], vec![2, 2]] {
            assert!(
                AnchoredBound::new(&lp, &sources, &levels).is_err(),
                "{levels:?}"
            );
        }
        // Sources of the same shape but of another loop (twice the load): not the loop's own.
        let mut other = FrettingLoop::new(LoopCase {
            force: 2.0 * case.force,
            ..case.clone()
        })
        .unwrap();
        other.run(|_| std::ops::ControlFlow::Continue(())).unwrap();
        let foreign = other.cycle_sources().unwrap();
        assert_eq!(
            (foreign.cells, foreign.recorded, foreign.tractions.len()),
            (sources.cells, sources.recorded, sources.tractions.len())
        );
        assert!(
            message(reachable_levels(&lp, foreign, layers, &matrix, 0.5))
                .contains("not the loop's own")
        );
        assert!(AnchoredBound::new(&lp, foreign, &levels).is_err());
        // A loop stopped inside its cycle: its own sources record fewer increments.
        let mut stopped = FrettingLoop::new(case.clone()).unwrap();
        let cycle = stopped.path().len() - stopped.path().cycle_start();
        let mut left = stopped.path().cycle_start() + cycle / 2;
        stopped
            .run(|_| {
                left -= 1;
                if left == 0 {
                    std::ops::ControlFlow::Break(())
                } else {
                    std::ops::ControlFlow::Continue(())
                }
            })
            .unwrap();
        let partial = stopped.cycle_sources().unwrap();
        assert!(partial.recorded > 0 && partial.recorded < cycle);
        assert!(
            message(reachable_levels(&stopped, partial, layers, &matrix, 0.5))
                .contains("the loop's cycle has")
        );
        // An inhomogeneous loop.
        let mut composite = case.clone();
        let a = case.hertz_radius();
        composite.inhomogeneities = vec![crate::sam::eim::Inhomogeneity {
            shape: crate::sam::eim::Shape::Sphere {
                x: 0.0,
                y: 0.0,
                z: 0.6 * a,
                r: 0.3 * a,
            },
            e: 2.0 * case.e,
            nu: case.nu,
        }];
        let mut nested = FrettingLoop::new(composite).unwrap();
        nested.run(|_| std::ops::ControlFlow::Continue(())).unwrap();
        let own = nested.cycle_sources().unwrap();
        assert!(
            message(reachable_levels(&nested, own, layers, &matrix, 0.5))
                .contains("inhomogeneities")
        );
        assert!(AnchoredBound::new(&nested, own, &levels).is_err());
    }

    /// Per-inhomogeneity constants (docs/fatigue.md, "Materials"): two inhomogeneities of the
    /// same `E`, `ν` (one material of the EIM) with different `fatigue` tables — a cell inside
    /// each holds the criteria of its own constants (by hand on the same stored path; the second
    /// table gives `f_minus1` alone, the rest is the matrix's), a matrix cell the matrix's; and
    /// without the tables the fields are bit for bit the screened evaluation with the EIM's
    /// materials and the `[fatigue]` constants (the evaluation before per-inhomogeneity
    /// constants).
    #[test]
    fn each_inhomogeneity_cell_takes_its_own_constants() {
        let a = LoopCase::default().hertz_radius();
        let e2 = 2.0 * LoopCase::default().e;
        let head = "grid = 16\nnormal_steps = 4\namplitude = 0.02e-6\nshift_step = 0.005e-6\n\
                    subsurface_over_a = 0.0\n";
        let fatigue = "[fatigue]\nf_minus1 = 400e6\nt_minus1 = 280e6\nfs_k = 0.5\n\
                       yield_stress = 600e6\ndepth_over_a = 0.7\nscreen_fraction = 0.0\n";
        let sphere = format!(
            "[[inhomogeneity]]\nkind = \"sphere\"\nx = 0.0\ny = 0.0\nz = {}\nr = {}\nE = {e2}\n\
             nu = 0.3\n",
            0.52 * a,
            0.3 * a
        );
        let cuboid = format!(
            "[[inhomogeneity]]\nkind = \"cuboid\"\nx = {}\ny = 0.0\nz = {}\nhx = {h}\nhy = {h}\n\
             hz = {h}\nE = {e2}\nnu = 0.3\n",
            1.17 * a,
            0.52 * a,
            h = 0.2 * a
        );
        let own = [
            "fatigue = { f_minus1 = 500e6, t_minus1 = 350e6, fs_k = 0.8, yield_stress = 900e6 }\n",
            "fatigue = { f_minus1 = 300e6 }\n",
        ];
        let plain = format!("{head}{sphere}{cuboid}{fatigue}");
        let with_own = format!("{head}{sphere}{}{cuboid}{}{fatigue}", own[0], own[1]);
        let plain = toml::from_str::<LoopConfig>(&plain)
            .map_err(|e| SpecError(e.message().to_string()))
            .unwrap();
        let with_own = toml::from_str::<LoopConfig>(&with_own)
            .map_err(|e| SpecError(e.message().to_string()))
            .unwrap();
        let case = with_own.case("homogeneous", None).unwrap();
        let mut lp = FrettingLoop::new(case.clone()).unwrap();
        lp.run(|_| std::ops::ControlFlow::Continue(())).unwrap();
        let h = lp.cycle_stress().unwrap().unwrap();
        assert_eq!(h.materials, vec![(e2, 0.3)], "one EIM material");
        let (cfg_plain, cfg_own) = (
            plain.fatigue_config().unwrap(),
            with_own.fatigue_config().unwrap(),
        );
        let f_own = evaluate_loop_fatigue(&lp, &cfg_own).unwrap();
        let f_plain = evaluate_loop_fatigue(&lp, &cfg_plain).unwrap();
        let (layers, per) = (h.layers, h.grid.len());
        let slot = |p: usize| {
            let k = p / per;
            (if k == layers { 0 } else { k + 1 }) * per + p % per
        };
        // By hand: the four criteria of cell p's stored path with the constants `c`.
        let by_hand = |p: usize, c: [f64; 4], young: f64| -> [f64; 4] {
            let m = Material {
                f_minus1: c[0],
                t_minus1: c[1],
                young,
                poisson: 0.3,
                fs_k: c[2],
                yield_stress: c[3],
            };
            let path: Vec<Voigt> = h.stress[p * h.increments * 6..(p + 1) * h.increments * 6]
                .chunks_exact(6)
                .map(|v| std::array::from_fn(|i| v[i]))
                .collect();
            let params = FieldParams::default().plane;
            let (cr, dv) = crossland_dang_van(&path, &m, &mut InvariantScratch::default()).unwrap();
            let mut plane = PlaneScratch::default();
            [
                cr.index,
                dv.index,
                swt(&path, &m, &params, &mut plane).unwrap().value,
                fatemi_socie(&path, &m, &params, &mut plane).unwrap().value,
            ]
        };
        let fields = |f: &LoopFatigue, q: usize| {
            let i = &f.indices;
            [i.crossland[q], i.dang_van[q], i.swt[q], i.fatemi_socie[q]]
        };
        let matrix = [400e6, 280e6, 0.5, 600e6];
        let constants = [[500e6, 350e6, 0.8, 900e6], [300e6, 280e6, 0.5, 600e6]];
        let mut checked = [0usize; 3];
        for p in 0..h.points() {
            let at = h.position(p).unwrap();
            let holder = case.inhomogeneities.iter().position(|i| i.contains(at));
            assert_eq!(holder.is_some(), h.material[p] != 0, "cell {p}");
            // A few cells of each kind (every cell would be slow in a debug build).
            let kind = holder.map_or(0, |i| i + 1);
            if checked[kind] >= 3 || (kind == 0 && p % 97 != 0) {
                continue;
            }
            checked[kind] += 1;
            let (c, young) = match holder {
                Some(i) => (constants[i], e2),
                None => (matrix, LoopCase::default().e),
            };
            let got = fields(&f_own, slot(p));
            assert_eq!(got, by_hand(p, c, young), "cell {p} ({kind})");
            if let Some(i) = holder {
                // Not the matrix's constants: the test sees the difference.
                let other = by_hand(p, matrix, e2);
                assert_ne!(got[0], other[0], "inhomogeneity {i}: Crossland");
                assert_ne!(got[1], other[1], "inhomogeneity {i}: Dang Van");
                if i == 0 {
                    assert_ne!(got[3], other[3], "Fatemi–Socie");
                }
            }
        }
        assert_eq!(checked, [3, 3, 3], "cells of each kind checked");
        // The screen across materials (each cell's bound with its own constants, against the
        // largest exact value of any material): the maxima and every value at or above half of
        // its maximum are those of the full evaluation.
        let half = FatigueConfig {
            screen_fraction: 0.5,
            ..cfg_own.clone()
        };
        let screened = evaluate_loop_fatigue(&lp, &half).unwrap();
        let (a, b) = (&f_own.indices, &screened.indices);
        for (full, part, m, n) in [
            (&a.crossland, &b.crossland, a.crossland_max, b.crossland_max),
            (&a.dang_van, &b.dang_van, a.dang_van_max, b.dang_van_max),
            (&a.swt, &b.swt, a.swt_max, b.swt_max),
            (
                &a.fatemi_socie,
                &b.fatemi_socie,
                a.fatemi_socie_max,
                b.fatemi_socie_max,
            ),
        ] {
            assert_eq!((m.value, m.point), (n.value, n.point));
            for (q, (&v, &w)) in full.iter().zip(part.iter()).enumerate() {
                if v >= 0.5 * m.value {
                    assert_eq!(v, w, "cell {q}");
                }
            }
        }
        // Without the tables: the evaluation before them (materials of the EIM, `[fatigue]`
        // constants everywhere), bit for bit.
        let m = cfg_plain.matrix(case.e, case.nu);
        let before = evaluate_screened(
            &h.stress,
            h.increments,
            &[m, Material { young: e2, ..m }],
            &h.material,
            &FieldParams::default(),
            0.0,
        )
        .unwrap();
        for p in 0..h.points() {
            let b = [
                before.crossland[p],
                before.dang_van[p],
                before.swt[p],
                before.fatemi_socie[p],
            ];
            assert_eq!(
                fields(&f_plain, slot(p)).map(f64::to_bits),
                b.map(f64::to_bits),
                "cell {p}"
            );
        }
        assert_eq!(
            before.crossland_max.value,
            f_plain.indices.crossland_max.value
        );
        assert_eq!(slot(before.swt_max.point), f_plain.indices.swt_max.point);
    }
}
