//! The figures of `fretting-wear3d` (docs/wear3d.md#figures): the worn-depth map, its profiles,
//! the volume and largest depth against the cycles, and the animation `wear_depth.gif`.

use std::path::Path;

use halfspace_sam::drivers::fretting_wear3d::FrettingWear3d;
use halfspace_sam::SurfaceGrid;

use crate::animation::{frame_records, MAX_FRAMES};
use crate::draw::{curves, render_frame, surface_map, write_gif, FrameMap};
use crate::FigureError;

/// The cell centres of a surface grid along x and y, in μm (the axes of the wear maps).
fn cell_centres_um(g: &SurfaceGrid) -> (Vec<f64>, Vec<f64>) {
    let xs = (0..g.n1).map(|i| g.centre(i, 0).0 * 1e6).collect();
    let ys = (0..g.n2).map(|j| g.centre(0, j).1 * 1e6).collect();
    (xs, ys)
}

/// A field `f[i·N₂ + j]` (m) as rows along y, `values[j][i] = f(x_i, y_j)` in μm (the layout of
/// [`surface_map`] and the animation frames).
fn rows_along_y_um(f: &[f64], n1: usize, n2: usize) -> Vec<Vec<f64>> {
    (0..n2)
        .map(|j| (0..n1).map(|i| f[i * n2 + j] * 1e6).collect())
        .collect()
}

/// The figures of a completed 3D fretting-wear run, written into `dir` (docs/wear3d.md#figures):
/// `wear_depth_map.svg` (the worn depth h(x, y) at the end, μm, with a colour bar),
/// `wear_depth_profiles.svg` (h along x through the row nearest y = 0 and along y through the
/// column nearest x = 0, at every recorded cycle count and the end) and `wear_volume.svg` (the
/// worn volume `A Σ h` and the largest depth against the cycles N, one point per computed cycle).
pub fn wear3d_figures(dir: &Path, run: &FrettingWear3d) -> Result<(), FigureError> {
    let (xs, ys) = cell_centres_um(run.grid());
    let (n1, n2) = (xs.len(), ys.len());
    let um = 1e6;
    // The row/column nearest the axis (an even grid has no cell centred on it).
    let nearest = |c: &[f64]| {
        (0..c.len())
            .min_by(|&a, &b| c[a].abs().total_cmp(&c[b].abs()))
            .unwrap_or(0)
    };
    let (i0, j0) = (nearest(&xs), nearest(&ys));
    let fail = |p: &Path, e: Box<dyn std::error::Error>| {
        FigureError::Draw(format!("{}: {e}", p.display()))
    };
    // (a) The worn depth at the end, rows along y (values[j][i] = h(x_i, y_j)).
    let h = run.wear_depth();
    let values = rows_along_y_um(h, n1, n2);
    let p = dir.join("wear_depth_map.svg");
    surface_map(
        &p,
        &format!(
            "Worn depth h(x, y) after N = {} cycles (max {:.4e} m)",
            run.cycles(),
            h.iter().copied().fold(0.0, f64::max)
        ),
        ("x (μm)", "y (μm)", "worn depth h (μm)"),
        &xs,
        &ys,
        &values,
    )
    .map_err(|e| fail(&p, e))?;
    // (b) Profiles at the recorded cycle counts and the end.
    let mut snapshots: Vec<(u64, &[f64])> = run
        .records()
        .iter()
        .map(|r| (r.cycles, r.wear_depth.as_slice()))
        .collect();
    if snapshots.last().map(|s| s.0) != Some(run.cycles()) {
        snapshots.push((run.cycles(), h));
    }
    let along_x: Vec<(String, Vec<(f64, f64)>)> = snapshots
        .iter()
        .map(|(n, w)| {
            let line = (0..n1).map(|i| (xs[i], w[i * n2 + j0] * um)).collect();
            (format!("N = {n}"), line)
        })
        .collect();
    let along_y: Vec<(String, Vec<(f64, f64)>)> = snapshots
        .iter()
        .map(|(n, w)| {
            let line = (0..n2).map(|j| (ys[j], w[i0 * n2 + j] * um)).collect();
            (format!("N = {n}"), line)
        })
        .collect();
    let p = dir.join("wear_depth_profiles.svg");
    curves(
        &p,
        &format!(
            "Worn depth along x (y = {:.3} μm, left) and along y (x = {:.3} μm, right)",
            ys[j0], xs[i0]
        ),
        "x (μm) left, y (μm) right",
        ("worn depth h (μm)", &along_x),
        ("worn depth h (μm)", &along_y),
        false,
    )
    .map_err(|e| fail(&p, e))?;
    // (c) Volume and largest depth against the cycles.
    let rows = run.history();
    let volume = [(
        "wear volume".to_string(),
        rows.iter()
            .map(|r| (r.cycles as f64, r.wear_volume * 1e18))
            .collect::<Vec<_>>(),
    )];
    let depth = [(
        "largest worn depth".to_string(),
        rows.iter()
            .map(|r| (r.cycles as f64, r.max_wear_depth * um))
            .collect::<Vec<_>>(),
    )];
    let p = dir.join("wear_volume.svg");
    curves(
        &p,
        "Wear volume (left) and largest worn depth (right) against the cycles",
        "cycles N",
        ("wear volume (μm³)", &volume),
        ("largest worn depth (μm)", &depth),
        false,
    )
    .map_err(|e| fail(&p, e))
}

/// `wear_depth.gif` (docs/wear3d.md#figures): the worn depth h(x, y) at the records of the run
/// (the record cycles and the end, [`wear3d_figures`]' snapshots) — every record up to
/// [`MAX_FRAMES`], else that many evenly spaced with the first and the last
/// ([`frame_records`]) — on one colour scale from 0 to the final largest
/// depth (over all records, drawn or not), the cycle count in each frame's title.
pub fn wear3d_animation(dir: &Path, run: &FrettingWear3d) -> Result<(), FigureError> {
    let (xs, ys) = cell_centres_um(run.grid());
    let (n1, n2) = (xs.len(), ys.len());
    let um = 1e6;
    let records = run.records();
    let top = records
        .iter()
        .flat_map(|r| r.wear_depth.iter().copied())
        .fold(0.0, f64::max)
        * um;
    let p = dir.join("wear_depth.gif");
    let fail = |e: Box<dyn std::error::Error>| FigureError::Draw(format!("{}: {e}", p.display()));
    let frames = frame_records(records.len(), MAX_FRAMES)
        .into_iter()
        .map(|k| {
            let r = &records[k];
            let values = rows_along_y_um(&r.wear_depth, n1, n2);
            render_frame(
                &format!("Worn depth h (μm), N = {} of {}", r.cycles, run.cycles()),
                ("x (μm)", "y (μm)"),
                &[FrameMap {
                    caption: &format!("scale 0 to {top:.4} μm"),
                    xs: &xs,
                    ys: &ys,
                    values,
                    range: (0.0, top),
                }],
            )
            .map_err(fail)
        })
        .collect::<Result<Vec<_>, _>>()?;
    write_gif(&p, frames, 400)
}
