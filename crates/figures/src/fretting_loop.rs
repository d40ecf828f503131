//! The figures of `fretting-loop` (docs/fretting-loop.md, docs/composite.md#animation,
//! docs/fatigue.md#figures): \[LN11\]'s Figs. 6–9 from a completed loop (and its homogeneous
//! reference), the von Mises sections at A–D, the animation `loop_pq.gif` and the fatigue
//! figures.

use std::path::Path;

use halfspace_cases::loop_fatigue::LoopFatigue;
use halfspace_sam::drivers::fretting_loop::{FrettingLoop, PointFields};

use crate::animation::{frame_records, MAX_FRAMES};
use crate::draw::{
    curves, heatmap, map_figure, render_frame, surface_map, tick, write_gif, Curves, FrameMap,
};
use crate::FigureError;

/// One labelled curve.
type Labelled = (String, Vec<(f64, f64)>);

/// The figures of \[LN11\] from a completed loop (and its homogeneous reference): the loops (Fig. 8),
/// p and q along x and y at A–D (Fig. 6), the slips at B (Fig. 7), the map of q_x at B (Fig. 9),
/// the map of the transverse slip s₂ at B, and the von Mises sections at A–D.
pub fn loop_figures(
    out: &Path,
    lp: &FrettingLoop,
    reference: Option<&FrettingLoop>,
) -> Result<(), FigureError> {
    let case = lp.case();
    let grid = *lp.solver().problem().grid();
    let (n1, n2) = (grid.n1, grid.n2);
    let a = case.hertz_radius();
    let p0 = case.hertz_pressure();
    let mu_w = case.friction * case.hertz_force();
    let mu_p0 = case.friction * p0;
    let fail = |p: &Path, e: Box<dyn std::error::Error>| {
        FigureError::Draw(format!("{}: {e}", p.display()))
    };
    let with = if reference.is_some() {
        " (with the inhomogeneities)"
    } else {
        ""
    };
    let sets: Vec<(&str, &FrettingLoop)> = std::iter::once((with, lp))
        .chain(reference.map(|r| (" (homogeneous)", r)))
        .collect();
    // Fig. 8: the loops.
    let loops: Vec<Labelled> = sets
        .iter()
        .map(|(suffix, l)| {
            let rows = &l.rows()[l.path().cycle_start()..];
            (
                format!("Q/μW{suffix}"),
                rows.iter().map(|r| (r.d * 1e6, r.q[0] / mu_w)).collect(),
            )
        })
        .collect();
    for ext in ["svg", "png"] {
        let p = out.join(format!("fretting_loop.{ext}"));
        curves(
            &p,
            "Fretting loop (SAM, coupled): Q/μW against δx",
            "δx (μm)",
            ("Q / μW", &loops),
            ("", &[]),
            false,
        )
        .map_err(|e| fail(&p, e))?;
    }
    let xs: Vec<f64> = (0..n1).map(|i| grid.centre(i, n2 / 2).0 / a).collect();
    let ys: Vec<f64> = (0..n2).map(|j| grid.centre(n1 / 2, j).1 / a).collect();
    let along_x = |v: &[f64], s: f64| -> Vec<(f64, f64)> {
        (0..n1).map(|i| (xs[i], v[i * n2 + n2 / 2] / s)).collect()
    };
    let along_y = |v: &[f64], s: f64| -> Vec<(f64, f64)> {
        (0..n2).map(|j| (ys[j], v[(n1 / 2) * n2 + j] / s)).collect()
    };
    // Fig. 6: p and q along x (a) and y (b) at A–D.
    type Line<'a> = &'a dyn Fn(&[f64], f64) -> Vec<(f64, f64)>;
    for (axis, line) in [("x", &along_x as Line), ("y", &along_y as Line)] {
        let (mut left, mut right): (Vec<Labelled>, Vec<Labelled>) = (Vec::new(), Vec::new());
        for (suffix, l) in &sets {
            for p in l.points() {
                left.push((format!("p, {}{suffix}", p.label), line(&p.pressure, p0)));
                right.push((
                    format!("q_x, {}{suffix}", p.label),
                    line(&p.shear[0], mu_p0),
                ));
                if axis == "y" {
                    right.push((
                        format!("q_y, {}{suffix}", p.label),
                        line(&p.shear[1], mu_p0),
                    ));
                }
            }
        }
        let p = out.join(format!("profiles_{axis}.svg"));
        curves(
            &p,
            &format!("[LN11] Fig. 6: p/p0 and q/(μ p0) along {axis} at A–D"),
            &format!("{axis} / a"),
            ("p / p0", &left),
            ("q / (μ p0)", &right),
            false,
        )
        .map_err(|e| fail(&p, e))?;
    }
    // Fig. 7: slips at B along x (a) and y (b).
    let at = |l: &FrettingLoop, label: &str| -> Option<PointFields> {
        l.points().iter().find(|p| p.label == label).cloned()
    };
    let mut slip_x: Vec<Labelled> = Vec::new();
    let mut slip_y: Vec<Labelled> = Vec::new();
    for (suffix, l) in &sets {
        if let Some(b) = at(l, "B") {
            for (c, name) in [(0, "s_x"), (1, "s_y")] {
                slip_x.push((format!("{name} along x{suffix}"), along_x(&b.slip[c], 1e-9)));
                slip_y.push((format!("{name} along y{suffix}"), along_y(&b.slip[c], 1e-9)));
            }
        }
    }
    let p = out.join("slip_B.svg");
    curves(
        &p,
        "[LN11] Fig. 7: slip of the last increment at B (nm), along x and along y",
        "x / a (left), y / a (right)",
        ("slip along x (nm)", &slip_x as &Curves),
        ("slip along y (nm)", &slip_y),
        false,
    )
    .map_err(|e| fail(&p, e))?;
    // Fig. 9 and the transverse slip: surface maps at B over |x|, |y| ≤ 1.3a, y upward (as the
    // wear map and the animation frames).
    let window: Vec<usize> = (0..n1).filter(|&i| xs[i].abs() <= 1.3).collect();
    let cols: Vec<usize> = (0..n2).filter(|&j| ys[j].abs() <= 1.3).collect();
    let map = |name: &str, title: &str, unit: &str, v: &[f64], s: f64| -> Result<(), FigureError> {
        let values: Vec<Vec<f64>> = cols
            .iter()
            .map(|&j| window.iter().map(|&i| v[i * n2 + j] / s).collect())
            .collect();
        let p = out.join(name);
        surface_map(
            &p,
            title,
            ("x / a", "y / a", unit),
            &window.iter().map(|&i| xs[i]).collect::<Vec<_>>(),
            &cols.iter().map(|&j| ys[j]).collect::<Vec<_>>(),
            &values,
        )
        .map_err(|e| fail(&p, e))
    };
    for (suffix, l) in &sets {
        let tag = if suffix.contains("homogeneous") {
            "_homogeneous"
        } else {
            ""
        };
        if let Some(b) = at(l, "B") {
            map(
                &format!("shear_x_map_B{tag}.svg"),
                &format!("[LN11] Fig. 9: q_x/(μ p0) on the surface at B{suffix}"),
                "q_x / (μ p0)",
                &b.shear[0],
                mu_p0,
            )?;
            map(
                &format!("transverse_slip_map_B{tag}.svg"),
                &format!("Transverse slip s_y at B (nm){suffix}"),
                "s_y (nm)",
                &b.slip[1],
                1e-9,
            )?;
        }
    }
    // Von Mises sections (x–z through y = 0) at A–D.
    let half = grid.half1;
    for p in lp.points() {
        let Some(vm) = &p.von_mises else { continue };
        let layers = vm.len() / (n1 * n2);
        let zs: Vec<f64> = (0..layers).map(|k| (2 * k + 1) as f64 * half / a).collect();
        let window: Vec<usize> = (0..n1).filter(|&i| xs[i].abs() <= 1.5).collect();
        let values: Vec<Vec<f64>> = (0..layers)
            .map(|k| {
                window
                    .iter()
                    .map(|&i| vm[k * n1 * n2 + i * n2 + n2 / 2] / p0)
                    .collect()
            })
            .collect();
        let path = out.join(format!("von_mises_{}.svg", p.label));
        heatmap(
            &path,
            &format!(
                "Von Mises stress / p0 at {} (x–z section through y = 0){with}",
                p.label
            ),
            ("x / a", "depth / a", "σ_vM / p0"),
            &window.iter().map(|&i| xs[i]).collect::<Vec<_>>(),
            &zs,
            &values,
        )
        .map_err(|e| fail(&path, e))?;
    }
    Ok(())
}

/// A map `[row][col]` of the window.
type WindowMap = Vec<Vec<f64>>;
/// A frame of `loop_pq.gif`: its key (increment or title), `p/p0` and `|q|/(μ p0)`.
type PqFrame<K> = (K, WindowMap, WindowMap);

/// The frames of `loop_pq.gif` (docs/composite.md#animation): the pressure `p/p0` and the shear
/// magnitude `|q|/(μ p0)` over `|x|, |y| ≤ 1.3a` at the increments of the cycle (the loop's rows
/// from `cycle_start`) that are drawn — at most [`MAX_FRAMES`], chosen by [`frame_records`] — kept
/// as the loop runs, with the largest value of each over every increment (the colour scales).
pub struct CycleFrames {
    /// Columns (x) and rows (y) of the window.
    cols: Vec<usize>,
    rows: Vec<usize>,
    /// The increments of the cycle (counted from `cycle_start`) drawn when all are observed.
    drawn: Vec<usize>,
    /// How many increments of the cycle were observed.
    observed: usize,
    /// The largest `p/p0` and `|q|/(μ p0)` over every observed increment.
    top: (f64, f64),
    /// `(increment, p/p0, |q|/(μ p0))` of the drawn increments, each `[row][col]`.
    frames: Vec<PqFrame<usize>>,
}

/// The largest value of a window map, from `start` (the order of `f64::max`'s comparisons does
/// not change the result).
fn largest(start: f64, map: &WindowMap) -> f64 {
    map.iter().flatten().copied().fold(start, f64::max)
}

impl CycleFrames {
    pub fn new(lp: &FrettingLoop) -> Self {
        let grid = *lp.solver().problem().grid();
        let a = lp.case().hertz_radius();
        let cols = (0..grid.n1)
            .filter(|&i| (grid.centre(i, 0).0 / a).abs() <= 1.3)
            .collect();
        let rows = (0..grid.n2)
            .filter(|&j| (grid.centre(0, j).1 / a).abs() <= 1.3)
            .collect();
        let cycle = lp.path().len() - lp.path().cycle_start();
        Self {
            cols,
            rows,
            drawn: frame_records(cycle, MAX_FRAMES),
            observed: 0,
            top: (0.0, 0.0),
            frames: Vec::new(),
        }
    }

    /// After an increment: if it belongs to the cycle, its largest values, and its fields if it
    /// is drawn.
    pub fn observe(&mut self, lp: &FrettingLoop) {
        let k = lp.rows().len() - 1;
        let start = lp.path().cycle_start();
        if k < start {
            return;
        }
        let n2 = lp.solver().problem().grid().n2;
        let p0 = lp.case().hertz_pressure();
        let mu_p0 = lp.case().friction * p0;
        let st = lp.solver().problem().state();
        let field = |f: &dyn Fn(usize) -> f64| -> Vec<Vec<f64>> {
            self.rows
                .iter()
                .map(|&j| self.cols.iter().map(|&i| f(i * n2 + j)).collect())
                .collect()
        };
        let p = field(&|c| st.pressure[c] / p0);
        let q = field(&|c| st.shear[0][c].hypot(st.shear[1][c]) / mu_p0);
        self.observed += 1;
        self.top = (largest(self.top.0, &p), largest(self.top.1, &q));
        if self.drawn.binary_search(&(k - start)).is_ok() {
            self.frames.push((k, p, q));
        }
    }

    /// Writes the animation: the drawn increments of the cycle when all were observed (one
    /// frame per increment up to [`MAX_FRAMES`], else that many evenly spaced with the first and
    /// the last increment: [`frame_records`], the rule of `wear_depth.gif`); after a resume that
    /// missed some, one frame per loop point A–D (the fields the loop keeps). Each map's colour
    /// scale runs from 0 to its largest value over the whole cycle (every increment observed,
    /// drawn or not).
    pub fn write(&self, path: &Path, lp: &FrettingLoop) -> Result<(), FigureError> {
        let grid = *lp.solver().problem().grid();
        let n2 = grid.n2;
        let a = lp.case().hertz_radius();
        let p0 = lp.case().hertz_pressure();
        let mu_p0 = lp.case().friction * p0;
        let mu_w = lp.case().friction * lp.case().hertz_force();
        let complete = self.observed == lp.path().len() - lp.path().cycle_start();
        let field = |v: &[f64], s: f64| -> Vec<Vec<f64>> {
            self.rows
                .iter()
                .map(|&j| self.cols.iter().map(|&i| v[i * n2 + j] / s).collect())
                .collect()
        };
        let (frames, (pmax, qmax)): (Vec<PqFrame<String>>, _) = if complete {
            let start = lp.path().cycle_start();
            let frames = self
                .frames
                .iter()
                .map(|(k, p, q)| {
                    let row = &lp.rows()[*k];
                    (
                        format!(
                            "Increment {} of {}: δx = {:.4} μm, Q/μW = {:.3}",
                            k - start,
                            self.observed - 1,
                            row.d * 1e6,
                            row.q[0] / mu_w
                        ),
                        p.clone(),
                        q.clone(),
                    )
                })
                .collect();
            (frames, self.top)
        } else {
            let frames: Vec<PqFrame<String>> = lp
                .points()
                .iter()
                .map(|f| {
                    let q: Vec<f64> = f.shear[0]
                        .iter()
                        .zip(&f.shear[1])
                        .map(|(a, b)| a.hypot(*b))
                        .collect();
                    (
                        format!("Point {} (increment {})", f.label, f.increment),
                        field(&f.pressure, p0),
                        field(&q, mu_p0),
                    )
                })
                .collect();
            let top = frames
                .iter()
                .fold((0.0, 0.0), |(p, q), f| (largest(p, &f.1), largest(q, &f.2)));
            (frames, top)
        };
        let xs: Vec<f64> = self.cols.iter().map(|&i| grid.centre(i, 0).0 / a).collect();
        let ys: Vec<f64> = self.rows.iter().map(|&j| grid.centre(0, j).1 / a).collect();
        let fail =
            |e: Box<dyn std::error::Error>| FigureError::Draw(format!("{}: {e}", path.display()));
        let images = frames
            .into_iter()
            .map(|(title, p, q)| {
                render_frame(
                    &title,
                    ("x / a", "y / a"),
                    &[
                        FrameMap {
                            caption: &format!("p / p0 (0 to {pmax:.3})"),
                            xs: &xs,
                            ys: &ys,
                            values: p,
                            range: (0.0, pmax),
                        },
                        FrameMap {
                            caption: &format!("|q| / (μ p0) (0 to {qmax:.3})"),
                            xs: &xs,
                            ys: &ys,
                            values: q,
                            range: (0.0, qmax),
                        },
                    ],
                )
                .map_err(fail)
            })
            .collect::<Result<Vec<_>, _>>()?;
        write_gif(path, images, 150)
    }
}

/// The fatigue figures of a fretting loop with `[fatigue]`, written into `dir`
/// (docs/fatigue.md#figures): `fatigue_section_{crossland,dang_van,swt,fatemi_socie}.svg`, the
/// x–z section of each index through the row of cells (y) holding its maximum, the maximum
/// marked by a cross (depth downward; cells the screen skipped, NaN, blank), and
/// `fatigue_depth_profile.svg`, the largest value of each index over each layer against the
/// depth, divided by the index's overall maximum.
pub fn fatigue_figures(dir: &Path, f: &LoopFatigue) -> Result<(), FigureError> {
    let (n1, n2) = f.shape;
    let um = 1e6;
    let xs: Vec<f64> = f.x.iter().map(|x| x * um).collect();
    let zs: Vec<f64> = f.z.iter().map(|z| z * um).collect();
    let i = &f.indices;
    // Name, display name, field, colour-bar label and its scale.
    let fields: [(&str, &str, &[f64], &str, f64); 4] = [
        (
            "crossland",
            "Crossland",
            &i.crossland,
            "Crossland index",
            1.0,
        ),
        ("dang_van", "Dang Van", &i.dang_van, "Dang Van index", 1.0),
        (
            "swt",
            "Smith–Watson–Topper",
            &i.swt,
            "SWT σn,max·εa (MPa)",
            1e-6,
        ),
        (
            "fatemi_socie",
            "Fatemi–Socie",
            &i.fatemi_socie,
            "Fatemi–Socie parameter",
            1.0,
        ),
    ];
    let fail = |p: &Path, e: Box<dyn std::error::Error>| {
        FigureError::Draw(format!("{}: {e}", p.display()))
    };
    let mut profiles: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for (k, (name, display, field, unit, scale)) in fields.into_iter().enumerate() {
        let [mx, my, mz] = f.at[k];
        let j = (0..n2)
            .min_by(|&a, &b| (f.y[a] - my).abs().total_cmp(&(f.y[b] - my).abs()))
            .unwrap_or(0);
        let values: Vec<Vec<f64>> = (0..f.layers)
            .map(|l| {
                (0..n1)
                    .map(|c| field[l * n1 * n2 + c * n2 + j] * scale)
                    .collect()
            })
            .collect();
        let max = field
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .fold(f64::NEG_INFINITY, f64::max);
        let p = dir.join(format!("fatigue_section_{name}.svg"));
        map_figure(
            &p,
            &format!(
                "{display}: x–z section through its maximum {} at x = {:.3}, y = {:.3}, z = {:.3} μm",
                tick(max * scale),
                mx * um,
                my * um,
                mz * um
            ),
            ("x (μm)", "depth z (μm)", unit),
            &xs,
            &zs,
            &values,
            true,
            Some((mx * um, mz * um)),
        )
        .map_err(|e| fail(&p, e))?;
        let layer_max = (0..f.layers).map(|l| {
            let layer = &field[l * n1 * n2..(l + 1) * n1 * n2];
            let m = layer
                .iter()
                .copied()
                .filter(|v| v.is_finite())
                .fold(f64::NEG_INFINITY, f64::max);
            (zs[l], if m.is_finite() { m / max } else { f64::NAN })
        });
        profiles.push((
            format!("{display} (max {})", tick(max * scale)),
            layer_max.collect(),
        ));
    }
    let p = dir.join("fatigue_depth_profile.svg");
    curves(
        &p,
        "Largest index over each layer against the depth (each over its overall maximum)",
        "depth z (μm)",
        ("layer maximum / overall maximum", &profiles),
        ("", &[]),
        false,
    )
    .map_err(|e| fail(&p, e))
}
