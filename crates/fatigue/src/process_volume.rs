//! The criteria on the stress history averaged over a process volume (docs/fatigue.md,
//! "Process volume"): Fouvry, Kapsa & Vincent's answer to the steep stress gradients of fretting
//! (ASTM STP 1367, 2000; Proudhon, Fouvry & Buffière, arXiv:0710.3715): the stress
//! tensor is averaged over a cube of side `ℓ` before the criterion is applied.
//!
//! The volume of a point `(x, y, z)` (z the depth) is the cube
//! `[x − ℓ/2, x + ℓ/2] × [y − ℓ/2, y + ℓ/2] × [z₀, z₀ + ℓ]`, `z₀ = max(z − ℓ/2, 0)`: centred on the
//! point, its top face on the surface when the point is within `ℓ/2` of it. The stress between
//! the box's nodes is the trilinear interpolant of the nodes' stresses, so the average
//!
//! `σ̄(t) = Σ_{i,j,k} w^x_i w^y_j w^z_k σ_{ijk}(t)`, `w^u_m = (1/ℓ) ∫_{window} φ_m(u) du`
//!
//! (`φ_m` the hat function of node `m` along each axis) is exact for fields linear in each
//! coordinate and continuous in `ℓ` (partial intervals enter with their exact weights). For a
//! smooth field its error is `O(h²)` in the node spacing `h` (the interpolant's): measured on a
//! field quadratic along each axis, orders 2.04, 1.99 over two halvings of `h` (tests/process_volume.rs).
//! It is applied as three banded passes along `x`, `y` and the depth, in place. Points whose
//! volume leaves the box's nodes are not evaluated.
//!
//! Material interfaces (inclusions): the stress is averaged across them like anywhere else (the
//! cube does not stop at an interface), and each point is then evaluated with the constants of
//! its own material (`material_of[p]`, the material at the node, not at the cube's centre or a
//! volume-weighted mix).
use crate::error::FatigueError;
use crate::field::FieldParams;
use crate::material::Material;
use crate::screened::{evaluate_screened, ScreenedIndices};

/// The nodes of the box of a stress history: `x` (N₁) and `y` (N₂) increasing, `depth` (one
/// per stored level, in the order of the levels, distinct, ≥ 0). Point `p = k N₁N₂ + i N₂ + j`
/// sits at `(x[i], y[j], depth[k])`.
#[derive(Clone, Copy, Debug)]
pub struct BoxNodes<'a> {
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub depth: &'a [f64],
}

/// The weights of one output node along one axis: the first input node and the weights of the
/// consecutive nodes from it.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Band {
    pub first: usize,
    pub weights: Vec<f64>,
}

/// `(1/(b − a)) ∫_a^b φ_m(u) du` for every node `m` of `nodes` (increasing) whose hat function
/// meets `[a, b] ⊂ [nodes[0], nodes[n − 1]]`: on each interval `[u_m, u_{m+1}]` met by the
/// window, with `s = (u − u_m)/h`, `∫(1 − s) du = h [s − s²/2]` and `∫ s du = h [s²/2]` between
/// the window's ends.
pub(crate) fn hat_weights(nodes: &[f64], a: f64, b: f64) -> Band {
    let n = nodes.len();
    // The interval holding a: the last node ≤ a (a ≥ nodes[0]).
    let mut m = nodes.partition_point(|&u| u <= a).saturating_sub(1);
    if m + 1 >= n {
        m = n.saturating_sub(2);
    }
    let first = m;
    let mut weights = vec![0.0; 1];
    let width = b - a;
    while m + 1 < n && nodes[m] < b {
        let (lo, hi) = (nodes[m], nodes[m + 1]);
        let h = hi - lo;
        let sa = ((a.max(lo) - lo) / h).clamp(0.0, 1.0);
        let sb = ((b.min(hi) - lo) / h).clamp(0.0, 1.0);
        let left = h * ((sb - 0.5 * sb * sb) - (sa - 0.5 * sa * sa));
        let right = h * 0.5 * (sb * sb - sa * sa);
        let k = m - first;
        if weights.len() < k + 2 {
            weights.resize(k + 2, 0.0);
        }
        weights[k] += left / width;
        weights[k + 1] += right / width;
        m += 1;
    }
    Band { first, weights }
}

/// The window `[a, b]` of side `side` about `u` along an in-plane axis (`top = false`) or the
/// depth (`top = true`: the top face on the surface within `side/2` of it), and whether it lies
/// in `[nodes[0], nodes[n − 1]]` (to a relative `1e-12` of the side).
fn window(nodes: &[f64], u: f64, side: f64, top: bool) -> Option<(f64, f64)> {
    let a = if top {
        (u - 0.5 * side).max(0.0)
    } else {
        u - 0.5 * side
    };
    let b = a + side;
    let slack = 1e-12 * side;
    let (lo, hi) = (nodes[0], nodes[nodes.len() - 1]);
    (a >= lo - slack && b <= hi + slack).then(|| (a.max(lo), b.min(hi)))
}

/// One axis: the band of every output node (`None` where its window leaves the nodes).
fn axis_bands(nodes: &[f64], side: f64, top: bool) -> Vec<Option<Band>> {
    nodes
        .iter()
        .map(|&u| window(nodes, u, side, top).map(|(a, b)| hat_weights(nodes, a, b)))
        .collect()
}

/// The checks of [`average_over_volume`]: the nodes finite and increasing; `side` finite, at
/// most the smallest extent of the box, and on each axis at least the largest node spacing the
/// cubes meet (a cell): along `x` and `y` every spacing (every window slides over the whole
/// axis); along the depth the intervals within `side` of the first depth, where the surface
/// cubes sit and the gradients the volume averages are steep. Deeper, a window narrower than a
/// coarse interval is still the exact mean of the interpolant, so one coarse deep layer does
/// not refuse every side.
fn check_side(nodes: &BoxNodes<'_>, side: f64) -> Result<(), FatigueError> {
    let spacing = |u: &[f64]| u.windows(2).map(|w| w[1] - w[0]).fold(0.0f64, f64::max);
    let extent = |u: &[f64]| u[u.len() - 1] - u[0];
    for (name, u) in [("x", nodes.x), ("y", nodes.y)] {
        if u.len() < 2
            || !u.iter().all(|v| v.is_finite())
            || u.windows(2)
                .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
        {
            return Err(FatigueError::ProcessVolumeNodes {
                axis: name,
                reason: "needs two or more increasing, finite nodes",
            });
        }
    }
    let mut depth: Vec<f64> = nodes.depth.to_vec();
    depth.sort_by(f64::total_cmp);
    if depth.len() < 2
        || depth[0] < 0.0
        || !depth.iter().all(|d| d.is_finite())
        || depth.windows(2).any(|w| w[1] <= w[0])
    {
        return Err(FatigueError::ProcessVolumeNodes {
            axis: "depth",
            reason: "needs two or more distinct, finite depths >= 0",
        });
    }
    // The depth intervals met by a window starting at the first depth (or the first interval).
    let near = depth.partition_point(|&d| d < depth[0] + side).max(2);
    let shallow = spacing(&depth[..near.min(depth.len())]);
    // A side of exactly one cell passes (the spacing's rounding: 1e-9 relative).
    for cell in [spacing(nodes.x), spacing(nodes.y), shallow] {
        if !side.is_finite() || side < cell * (1.0 - 1e-9) {
            return Err(FatigueError::ProcessVolumeBelowCell { side, cell });
        }
    }
    let reach = extent(nodes.x)
        .min(extent(nodes.y))
        .min(depth[depth.len() - 1]);
    if side > reach {
        return Err(FatigueError::ProcessVolumeBeyondBox { side, reach });
    }
    Ok(())
}

/// `n₁ n₂ levels` points and `increments · 6` values per point, refused when either overflows.
fn box_sizes(nodes: &BoxNodes<'_>, increments: usize) -> Result<(usize, usize), FatigueError> {
    let points = nodes
        .x
        .len()
        .checked_mul(nodes.y.len())
        .and_then(|v| v.checked_mul(nodes.depth.len()))
        .ok_or(FatigueError::SizeOverflow {
            what: "process volume: points of the box (N1 N2 levels)",
        })?;
    let block = increments
        .checked_mul(6)
        .ok_or(FatigueError::SizeOverflow {
            what: "process volume: values per point (increments × 6)",
        })?;
    Ok((points, block))
}

/// Applies `bands` along one axis of `data` in place: the axis has `n` nodes at stride `stride`
/// (in blocks of `block` values), `outer` groups of `n · stride` blocks; a node without a band
/// is left as it is. `line` is scratch (`n · block` values).
fn pass(
    data: &mut [f64],
    block: usize,
    n: usize,
    stride: usize,
    bands: &[Option<Band>],
    line: &mut Vec<f64>,
) {
    let group = n * stride * block;
    line.resize(n * block, 0.0);
    for chunk in data.chunks_exact_mut(group) {
        for s in 0..stride {
            for m in 0..n {
                let at = (m * stride + s) * block;
                line[m * block..(m + 1) * block].copy_from_slice(&chunk[at..at + block]);
            }
            for (m, band) in bands.iter().enumerate() {
                let Some(band) = band else { continue };
                let out = &mut chunk[(m * stride + s) * block..(m * stride + s + 1) * block];
                out.fill(0.0);
                for (q, &w) in band.weights.iter().enumerate() {
                    if w == 0.0 {
                        continue;
                    }
                    let src = &line[(band.first + q) * block..(band.first + q + 1) * block];
                    for (o, v) in out.iter_mut().zip(src) {
                        *o += w * v;
                    }
                }
            }
        }
    }
}

/// The stress history averaged over the process volume of side `side` (m) at every node of the
/// box (module doc): `stress[(p · increments + t) · 6 + c]` (the layout of
/// [`crate::evaluate_field`]) is overwritten by `σ̄` where the volume lies inside the nodes;
/// returns whether each point holds its average (`false`: its volume leaves the box, the value
/// is not an average). Errors (before the history is touched): `side` below a cell
/// (`check_side`) or beyond the box's smallest extent, no point whose volume is inside, nodes
/// not finite and increasing, sizes overflowing `usize`, a shape that does not fit the nodes.
pub fn average_over_volume(
    stress: &mut [f64],
    increments: usize,
    nodes: &BoxNodes<'_>,
    side: f64,
) -> Result<Vec<bool>, FatigueError> {
    check_side(nodes, side)?;
    let (n1, n2, levels) = (nodes.x.len(), nodes.y.len(), nodes.depth.len());
    let (points, block) = box_sizes(nodes, increments)?;
    if increments == 0 || points.checked_mul(block) != Some(stress.len()) {
        return Err(FatigueError::FieldShape {
            len: stress.len(),
            points,
            increments,
        });
    }
    let bx = axis_bands(nodes.x, side, false);
    let by = axis_bands(nodes.y, side, false);
    // The depth axis in increasing depth: the bands on the sorted depths, mapped back to the
    // stored levels (a level's band lists sorted positions; `order[r]` the level of rank r).
    let mut order: Vec<usize> = (0..levels).collect();
    order.sort_by(|&a, &b| nodes.depth[a].total_cmp(&nodes.depth[b]));
    let sorted: Vec<f64> = order.iter().map(|&k| nodes.depth[k]).collect();
    let bz_sorted = axis_bands(&sorted, side, true);
    // A point is inside when its window is inside on every axis: refuse before overwriting.
    if [&bx, &by, &bz_sorted]
        .iter()
        .any(|b| b.iter().all(Option::is_none))
    {
        return Err(FatigueError::ProcessVolumeNoPointInside {
            side,
            depth_min: sorted[0],
            depth_max: sorted[levels - 1],
        });
    }
    let mut line = Vec::new();
    // x: the levels × (N₂ columns) with N₁ nodes at stride N₂.
    pass(stress, block, n1, n2, &bx, &mut line);
    // y: contiguous N₂ nodes.
    pass(stress, block, n2, 1, &by, &mut line);
    // depth: the levels in stored order at stride N₁N₂; gather the stored levels of each band.
    let per = n1 * n2;
    let mut rank = vec![0; levels];
    for (r, &k) in order.iter().enumerate() {
        rank[k] = r;
    }
    line.resize(levels * block, 0.0);
    for cell in 0..per {
        for k in 0..levels {
            let at = (k * per + cell) * block;
            line[rank[k] * block..(rank[k] + 1) * block].copy_from_slice(&stress[at..at + block]);
        }
        for (r, band) in bz_sorted.iter().enumerate() {
            let Some(band) = band else { continue };
            let k = order[r];
            let out = &mut stress[(k * per + cell) * block..(k * per + cell + 1) * block];
            out.fill(0.0);
            for (q, &w) in band.weights.iter().enumerate() {
                if w == 0.0 {
                    continue;
                }
                let src = &line[(band.first + q) * block..(band.first + q + 1) * block];
                for (o, v) in out.iter_mut().zip(src) {
                    *o += w * v;
                }
            }
        }
    }
    let mut inside = vec![false; points];
    for k in 0..levels {
        for i in 0..n1 {
            for j in 0..n2 {
                inside[k * per + i * n2 + j] =
                    bx[i].is_some() && by[j].is_some() && bz_sorted[rank[k]].is_some();
            }
        }
    }
    Ok(inside)
}

/// The centre of the process volume of the node at `(x, y, depth)`:
/// `(x, y, max(depth, ℓ/2))`.
pub fn volume_centre(at: [f64; 3], side: f64) -> [f64; 3] {
    [at[0], at[1], at[2].max(0.5 * side)]
}

/// Parameters of [`evaluate_process_volume`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeParams {
    /// The side `ℓ` of the process volume (m).
    pub side: f64,
    /// The screen of [`evaluate_screened`] (0: every point exactly).
    pub fraction: f64,
    /// The critical-plane search and parallelism.
    pub field: FieldParams,
}

/// The four criteria on the averaged histories and the points they were evaluated at.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeIndices {
    /// The fields over the whole box (`NaN` where the volume leaves the box or the screen skipped
    /// the point), the maxima's `point` in the box's numbering.
    pub indices: ScreenedIndices,
    /// Points whose volume lies inside the box.
    pub inside: usize,
}

/// Crossland, Dang Van, SWT and Fatemi–Socie (as [`evaluate_screened`], one algorithm) on the
/// histories averaged over the process volume of side `params.side` (m) ([`average_over_volume`];
/// the history is consumed and overwritten), at every point of the box whose volume lies inside it;
/// point `p` of material `materials[material_of[p]]`.
pub fn evaluate_process_volume(
    mut stress: Vec<f64>,
    increments: usize,
    nodes: &BoxNodes<'_>,
    materials: &[Material],
    material_of: &[u16],
    params: &VolumeParams,
) -> Result<VolumeIndices, FatigueError> {
    let VolumeParams {
        side,
        fraction,
        field: ref params,
    } = *params;
    // The material map is checked before the averaging overwrites the history.
    let (points, block) = box_sizes(nodes, increments)?;
    if material_of.len() != points {
        return Err(FatigueError::MaterialMapLength {
            len: material_of.len(),
            points,
        });
    }
    let inside = average_over_volume(&mut stress, increments, nodes, side)?;
    // Compact the points inside to the front (order kept), then evaluate them.
    let mut kept = Vec::new();
    for (p, _) in inside.iter().enumerate().filter(|(_, &b)| b) {
        let to = kept.len();
        if to != p {
            stress.copy_within(p * block..(p + 1) * block, to * block);
        }
        kept.push(p);
    }
    stress.truncate(kept.len() * block);
    let own: Vec<u16> = kept.iter().map(|&p| material_of[p]).collect();
    let e = evaluate_screened(&stress, increments, materials, &own, params, fraction)?;
    drop(stress);
    let whole = |f: &[f64]| {
        let mut out = vec![f64::NAN; inside.len()];
        for (q, &p) in kept.iter().enumerate() {
            out[p] = f[q];
        }
        out
    };
    let back = |m: crate::field::Maximum| crate::field::Maximum {
        value: m.value,
        point: kept[m.point],
    };
    Ok(VolumeIndices {
        indices: ScreenedIndices {
            crossland: whole(&e.crossland),
            dang_van: whole(&e.dang_van),
            swt: whole(&e.swt),
            fatemi_socie: whole(&e.fatemi_socie),
            crossland_max: back(e.crossland_max),
            dang_van_max: back(e.dang_van_max),
            swt_max: back(e.swt_max),
            fatemi_socie_max: back(e.fatemi_socie_max),
            invariant_evaluated: e.invariant_evaluated,
            swt_evaluated: e.swt_evaluated,
            fatemi_socie_evaluated: e.fatemi_socie_evaluated,
        },
        inside: kept.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hat weights sum to one and integrate `u` exactly (the window's midpoint), on uneven
    /// nodes and windows cutting intervals anywhere.
    #[test]
    fn hat_weights_integrate_linear_functions_exactly() {
        let nodes = [0.0, 0.5, 1.5, 2.5, 3.5, 4.5, 5.0];
        for (a, b) in [(0.0, 1.2), (0.3, 2.9), (1.5, 2.5), (0.7, 0.9), (2.0, 5.0)] {
            let band = hat_weights(&nodes, a, b);
            let sum: f64 = band.weights.iter().sum();
            let mean: f64 = band
                .weights
                .iter()
                .enumerate()
                .map(|(q, w)| w * nodes[band.first + q])
                .sum();
            assert!((sum - 1.0).abs() < 1e-14, "{a} {b}: {sum}");
            assert!((mean - 0.5 * (a + b)).abs() < 1e-14, "{a} {b}: {mean}");
        }
    }
}
