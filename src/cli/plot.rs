//! Figures (plotters: SVG, and PNG through the bitmap backend), with an embedded font
//! (DejaVu Sans in assets/fonts) so that no system font library is needed.

use std::path::Path;

use halfspace::mdr::ContactSolution;
use plotters::prelude::*;

type PlotResult = Result<(), Box<dyn std::error::Error>>;

/// The figure formats, by extension: `.svg` and `.png` (anything else is refused, never written
/// as SVG bytes under another name).
pub fn check_extension(path: &Path, what: &str, allowed: &[&str]) -> Result<(), super::CliError> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if allowed.contains(&ext) {
        Ok(())
    } else {
        Err(super::CliError::Spec(format!(
            "{what} {}: a figure is written as {} (by its extension), not '.{ext}'",
            path.display(),
            allowed
                .iter()
                .map(|e| format!(".{e}"))
                .collect::<Vec<_>>()
                .join(" or ")
        )))
    }
}

/// Draws a figure atomically: into a temporary file of the same extension in the same directory,
/// renamed over `path` when complete (a killed run leaves the old figure or the new one, never a
/// partial one). Refuses extensions other than `.svg` and `.png`.
fn atomic(path: &Path, draw: impl FnOnce(&Path) -> PlotResult) -> PlotResult {
    check_extension(path, "figure", &["svg", "png"]).map_err(|e| e.to_string())?;
    let mut failure = None;
    let written = halfspace::data::write_atomic(path, |tmp| {
        draw(tmp).map_err(|e| {
            let message = e.to_string();
            failure = Some(message.clone());
            halfspace::data::DataError::Format {
                path: path.to_path_buf(),
                message,
            }
        })
    });
    match (written, failure) {
        (Ok(()), _) => Ok(()),
        (Err(_), Some(message)) => Err(message.into()),
        (Err(e), None) => Err(e.to_string().into()),
    }
}

/// Two panels: `p(r)/max p` and `u(r)/δ` against `r/a`.
pub fn pressure_and_displacement(path: &Path, sol: &ContactSolution, title: &str) -> PlotResult {
    atomic(path, |path| {
        let a = sol.contact_radius;
        let pmax = sol.max_pressure();
        let r: Vec<f64> = sol.radii().iter().map(|v| v / a).collect();
        let rmax = r.last().copied().unwrap_or(1.0);
        let p: Vec<(f64, f64)> = r
            .iter()
            .zip(&sol.pressure)
            .filter(|(_, p)| p.is_finite())
            .map(|(x, p)| (*x, p / pmax))
            .collect();
        let u: Vec<(f64, f64)> = r
            .iter()
            .zip(&sol.displacement)
            .map(|(x, u)| (*x, u / sol.depth))
            .collect();
        register_font()?;
        let root = SVGBackend::new(path, (900, 420)).into_drawing_area();
        root.fill(&WHITE)?;
        let (left, right) = root.split_horizontally(450);
        let panels = [
            (
                left,
                p,
                format!("pressure, max {:.4e} Pa", pmax),
                "p / max p",
            ),
            (
                right,
                u,
                format!("displacement, δ = {:.4e} m", sol.depth),
                "u / δ",
            ),
        ];
        for (area, data, caption, ylabel) in panels {
            let ymax = data.iter().map(|(_, y)| *y).fold(0.0, f64::max) * 1.05;
            let mut chart = ChartBuilder::on(&area)
                .caption(caption, ("sans-serif", 16))
                .margin(12)
                .x_label_area_size(36)
                .y_label_area_size(48)
                .build_cartesian_2d(0.0..rmax, 0.0..ymax.max(1e-300))?;
            chart
                .configure_mesh()
                .x_desc("r / a")
                .y_desc(ylabel)
                .draw()?;
            chart.draw_series(LineSeries::new(data, BLUE.stroke_width(2)))?;
        }
        root.titled(title, ("sans-serif", 12))?;
        root.present()?;
        Ok(())
    })
}

/// Log–log errors against N, one line per series, with a reference line of slope `−order`.
pub fn convergence(
    path: &Path,
    title: &str,
    ns: &[usize],
    series: &[(&str, Vec<f64>)],
    order: f64,
) -> PlotResult {
    loglog(path, title, "error", ns, series, &[-order])
}

/// Log–log `y` against N, one line per series, with reference lines of the given slopes through
/// the first point of the first series (errors against N; the time per transform of Fig. 1).
pub fn loglog(
    path: &Path,
    title: &str,
    ylabel: &str,
    ns: &[usize],
    series: &[(&str, Vec<f64>)],
    slopes: &[f64],
) -> PlotResult {
    atomic(path, |path| {
        let xmin = *ns.first().unwrap_or(&1) as f64 * 0.8;
        let xmax = *ns.last().unwrap_or(&10) as f64 * 1.25;
        let all = series.iter().flat_map(|(_, e)| e.iter().copied());
        let ymin = all.clone().fold(f64::INFINITY, f64::min) * 0.5;
        let ymax = all.fold(0.0, f64::max) * 2.0;
        register_font()?;
        let root = SVGBackend::new(path, (640, 480)).into_drawing_area();
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 15))
            .margin(14)
            .x_label_area_size(40)
            .y_label_area_size(64)
            .build_cartesian_2d((xmin..xmax).log_scale(), (ymin..ymax).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("N (nodes)")
            .y_desc(ylabel)
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()?;
        let colors = [BLUE, RED, GREEN, MAGENTA];
        for (k, (name, errors)) in series.iter().enumerate() {
            let color = colors[k % colors.len()];
            let pts: Vec<(f64, f64)> = ns
                .iter()
                .map(|&n| n as f64)
                .zip(errors.iter().copied())
                .collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))?
                .label(*name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color));
            chart.draw_series(pts.iter().map(|p| Circle::new(*p, 3, color.filled())))?;
        }
        // Reference slopes through the first point of the first series.
        if let Some((_, e)) = series.first() {
            let (n0, e0) = (ns[0] as f64, e[0]);
            for (k, &slope) in slopes.iter().enumerate() {
                let line: Vec<(f64, f64)> = ns
                    .iter()
                    .map(|&n| (n as f64, e0 * (n as f64 / n0).powf(slope)))
                    .collect();
                let style = BLACK.mix(0.25 + 0.2 * k as f64);
                chart
                    .draw_series(LineSeries::new(line, style))?
                    .label(format!("slope {slope}"))
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], style));
            }
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
        root.present()?;
        Ok(())
    })
}

/// Labelled curves `(label, [(x, y)])`.
pub type Curves = [(String, Vec<(f64, f64)>)];

/// Two panels of curves against `r`: pressure and surface displacement, one line per label.
pub fn curves(
    path: &Path,
    title: &str,
    xlabel: &str,
    left: (&str, &Curves),
    right: (&str, &Curves),
    paired: bool,
) -> PlotResult {
    atomic(path, |path| {
        register_font()?;
        if path.extension().and_then(|e| e.to_str()) == Some("png") {
            let root = BitMapBackend::new(path, (960, 440)).into_drawing_area();
            draw_curves(root, title, xlabel, left, right, paired)
        } else {
            let root = SVGBackend::new(path, (960, 440)).into_drawing_area();
            draw_curves(root, title, xlabel, left, right, paired)
        }
    })
}

fn draw_curves<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    xlabel: &str,
    left: (&str, &Curves),
    right: (&str, &Curves),
    paired: bool,
) -> PlotResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 15))?;
    let panels: Vec<_> = if right.1.is_empty() {
        vec![(root.clone(), left)]
    } else {
        let (a, b) = root.split_horizontally(480);
        vec![(a, left), (b, right)]
    };
    // With `paired`, consecutive lines (MDR, reference) share a hue, the second lighter.
    let colors: Vec<RGBColor> = if paired {
        vec![
            RED,
            RGBColor(255, 150, 150),
            BLACK,
            RGBColor(160, 160, 160),
            BLUE,
            RGBColor(140, 170, 255),
        ]
    } else {
        vec![
            RED,
            BLACK,
            BLUE,
            GREEN,
            MAGENTA,
            CYAN,
            RGBColor(230, 140, 0),
            RGBColor(120, 60, 160),
        ]
    };
    for (area, (ylabel, lines)) in panels {
        let xmax = lines
            .iter()
            .flat_map(|(_, p)| p.iter().map(|v| v.0))
            .fold(0.0, f64::max);
        let xmin = lines
            .iter()
            .flat_map(|(_, p)| p.iter().map(|v| v.0))
            .fold(0.0, f64::min);
        let ys = || {
            lines
                .iter()
                .flat_map(|(_, p)| p.iter().map(|v| v.1))
                .filter(|v| v.is_finite())
        };
        let (ylo, yhi) = (ys().fold(f64::INFINITY, f64::min), ys().fold(0.0, f64::max));
        let ymax = yhi * 1.05;
        // Start at 0 unless the data sit far from it or below it (then pad 5 % of the range).
        let ymin = if ylo < 0.0 || ylo > 0.3 * yhi {
            ylo - 0.05 * (yhi - ylo)
        } else {
            0.0
        };
        let mut chart = ChartBuilder::on(&area)
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(64)
            .build_cartesian_2d(xmin..xmax, ymin..ymax.max(ymin + 1e-300))?;
        chart
            .configure_mesh()
            .x_desc(xlabel)
            .y_desc(ylabel)
            .draw()?;
        for (k, (label, pts)) in lines.iter().enumerate() {
            let color = colors[k % colors.len()];
            let pts: Vec<(f64, f64)> = pts.iter().copied().filter(|p| p.1.is_finite()).collect();
            // A line of one point draws nothing: mark it.
            if pts.len() == 1 {
                chart.draw_series(pts.iter().map(|p| Circle::new(*p, 4, color.filled())))?;
            }
            chart
                .draw_series(LineSeries::new(pts, color.stroke_width(2)))?
                .label(label.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
    }
    root.present()?;
    Ok(())
}

/// The embedded font for bitmap output (DejaVu Sans, assets/fonts; no system font libraries).
fn register_font() -> PlotResult {
    static FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
    plotters::style::register_font("sans-serif", plotters::style::FontStyle::Normal, FONT)
        .map_err(|_| "the embedded font could not be loaded")?;
    Ok(())
}

/// Worn profiles `f/d` against `r/a₀` for every snapshot, the limiting profile dashed (the paper's
/// Fig. 4). SVG or PNG by the extension.
pub fn worn_profiles(path: &Path, sim: &halfspace::fretting::FrettingSimulation) -> PlotResult {
    atomic(path, |path| {
        register_font()?;
        if path.extension().and_then(|e| e.to_str()) == Some("png") {
            let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
            draw_worn(root, sim)
        } else {
            let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
            draw_worn(root, sim)
        }
    })
}

fn draw_worn<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    sim: &halfspace::fretting::FrettingSimulation,
) -> PlotResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let p = sim.params();
    let r = sim.grid().coordinates();
    let xmax = p.length.min(1.6);
    let take = |v: &[f64]| -> Vec<(f64, f64)> {
        r.iter()
            .copied()
            .zip(v.iter().copied())
            .filter(|(x, _)| *x <= xmax)
            .collect()
    };
    let ymax = r
        .iter()
        .filter(|x| **x <= xmax)
        .map(|x| 0.5 * x * x)
        .fold(0.0, f64::max)
        * 1.05;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "Fretting wear (MDR): χ = {}, k = {}, N = {}, {} steps",
                p.chi,
                p.k,
                p.nodes,
                sim.state().step
            ),
            ("sans-serif", 20),
        )
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(56)
        .build_cartesian_2d(0.0..xmax, 0.0..ymax)?;
    chart
        .configure_mesh()
        .x_desc("r / a0")
        .y_desc("f / d")
        .draw()?;
    let initial: Vec<(f64, f64)> = r
        .iter()
        .filter(|x| **x <= xmax)
        .map(|&x| (x, 0.5 * x * x))
        .collect();
    chart
        .draw_series(LineSeries::new(initial, BLACK.stroke_width(1)))?
        .label("τ = 0")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK));
    let colors = [
        BLUE,
        GREEN,
        MAGENTA,
        RED,
        CYAN,
        RGBColor(255, 140, 0),
        RGBColor(120, 60, 0),
    ];
    for (k, s) in sim.state().snapshots.iter().enumerate() {
        let color = colors[k % colors.len()];
        chart
            .draw_series(LineSeries::new(take(&s.profile), color.stroke_width(2)))?
            .label(format!("τ = {}", s.tau))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color));
    }
    // Limiting profile f∞ on c < r ≤ r* (f₀ beyond), dashed.
    let r_star = sim.limit_contact_radius();
    let limit: Vec<(f64, f64)> = r
        .iter()
        .zip(sim.limiting_profile())
        .filter(|(x, _)| **x <= xmax)
        .map(|(&x, &f)| (x, if x <= r_star { f } else { 0.5 * x * x }))
        .collect();
    chart
        .draw_series(DashedLineSeries::new(limit, 8, 6, BLACK.stroke_width(2)))?
        .label("limit (Popov)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK.stroke_width(2)));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

/// A colour map from 0 to 1 (dark blue → teal → yellow, viridis-like).
fn colormap(t: f64) -> RGBColor {
    let stops = [
        (0.0, (68.0, 1.0, 84.0)),
        (0.25, (59.0, 82.0, 139.0)),
        (0.5, (33.0, 145.0, 140.0)),
        (0.75, (94.0, 201.0, 98.0)),
        (1.0, (253.0, 231.0, 37.0)),
    ];
    let t = t.clamp(0.0, 1.0);
    let k = stops.iter().rposition(|s| s.0 <= t).unwrap_or(0).min(3);
    let (t0, c0) = stops[k];
    let (t1, c1) = stops[k + 1];
    let w = (t - t0) / (t1 - t0);
    let mix = |a: f64, b: f64| (a + w * (b - a)).round() as u8;
    RGBColor(mix(c0.0, c1.0), mix(c0.1, c1.1), mix(c0.2, c1.2))
}

/// A map of `values[row][col]` over cells centred at `(xs[col], zs[row])` (z downward: a section
/// below the surface), with a colour bar; non-finite cells are left blank. SVG or PNG by the
/// extension.
pub fn heatmap(
    path: &Path,
    title: &str,
    labels: (&str, &str, &str),
    xs: &[f64],
    zs: &[f64],
    values: &[Vec<f64>],
) -> PlotResult {
    map_figure(path, title, labels, xs, zs, values, true, None)
}

/// Sizes of a map figure: `(width, height)` and the width of the map's panel (the rest holds the
/// colour bar).
struct MapSize {
    width: u32,
    height: u32,
    map: u32,
}

/// A map of `values[row][col]` over cells centred at `(xs[col], ys[row])` with `y` upward (a
/// surface map), with a colour bar; non-finite cells are left blank. SVG or PNG by the extension.
pub fn surface_map(
    path: &Path,
    title: &str,
    labels: (&str, &str, &str),
    xs: &[f64],
    ys: &[f64],
    values: &[Vec<f64>],
) -> PlotResult {
    map_figure(path, title, labels, xs, ys, values, false, None)
}

/// [`heatmap`] (`downward`) or [`surface_map`], with an optional cross at `marker` (a maximum).
#[allow(clippy::too_many_arguments)]
fn map_figure(
    path: &Path,
    title: &str,
    labels: (&str, &str, &str),
    xs: &[f64],
    zs: &[f64],
    values: &[Vec<f64>],
    downward: bool,
    marker: Option<(f64, f64)>,
) -> PlotResult {
    if xs.is_empty() || zs.is_empty() {
        return Err(format!("{title}: no cells to draw").into());
    }
    // A section is wide and shallow; a surface map of a square grid is drawn about square (equal
    // scales on x and y when the extents are equal).
    let size = if downward {
        MapSize {
            width: 960,
            height: 480,
            map: 830,
        }
    } else {
        MapSize {
            width: 720,
            height: 600,
            map: 590,
        }
    };
    atomic(path, |path| {
        register_font()?;
        let dims = (size.width, size.height);
        if path.extension().and_then(|e| e.to_str()) == Some("png") {
            let root = BitMapBackend::new(path, dims).into_drawing_area();
            draw_heatmap(
                root, size.map, title, labels, xs, zs, values, downward, marker,
            )
        } else {
            let root = SVGBackend::new(path, dims).into_drawing_area();
            draw_heatmap(
                root, size.map, title, labels, xs, zs, values, downward, marker,
            )
        }
    })
}

/// A tick label: fixed-point in the readable range, otherwise scientific.
fn tick(v: f64) -> String {
    tick_of_scale(v, v.abs())
}

/// A tick label for an axis whose largest magnitude is `scale`: every tick of the axis in the
/// same notation (fixed-point when `1e-2 ≤ scale < 1e4`, else scientific).
fn tick_of_scale(v: f64, scale: f64) -> String {
    if scale == 0.0 || (1e-2..1e4).contains(&scale) {
        format!("{v:.3}")
    } else {
        format!("{v:.2e}")
    }
}

#[allow(clippy::too_many_arguments)]
fn draw_heatmap<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    map_width: u32,
    title: &str,
    (xlabel, zlabel, unit): (&str, &str, &str),
    xs: &[f64],
    zs: &[f64],
    values: &[Vec<f64>],
    downward: bool,
    marker: Option<(f64, f64)>,
) -> PlotResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 15))?;
    let (main, bar) = root.split_horizontally(map_width);
    let dx = if xs.len() > 1 { xs[1] - xs[0] } else { 1.0 };
    // Row r spans the midpoints to its neighbours (rows may be unequally spaced: the fatigue
    // box's surface layer z = 0 lies Δ above its first layer, those below are 2Δ apart).
    let nz = zs.len();
    let row_edges: Vec<(f64, f64)> = (0..nz)
        .map(|r| {
            let below = if r + 1 < nz {
                zs[r + 1] - zs[r]
            } else if r > 0 {
                zs[r] - zs[r - 1]
            } else {
                1.0
            };
            let above = if r > 0 { zs[r] - zs[r - 1] } else { below };
            (zs[r] - 0.5 * above, zs[r] + 0.5 * below)
        })
        .collect();
    let (x0, x1) = (xs[0] - 0.5 * dx, xs[xs.len() - 1] + 0.5 * dx);
    let (z0, z1) = (row_edges[0].0, row_edges[nz - 1].1);
    let row_edges = &row_edges;
    // The colour range of the finite cells (NaN cells, e.g. screened ones, stay blank).
    let finite = || values.iter().flatten().copied().filter(|v| v.is_finite());
    let (mut vmin, mut vmax) = (
        finite().fold(f64::INFINITY, f64::min),
        finite().fold(f64::NEG_INFINITY, f64::max),
    );
    if vmin > vmax {
        (vmin, vmax) = (0.0, 1.0);
    }
    let span = (vmax - vmin).max(vmax.abs() * 1e-12).max(1e-300);
    vmax = vmin + span;
    let mut chart = ChartBuilder::on(&main)
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(64)
        .build_cartesian_2d(x0..x1, if downward { z1..z0 } else { z0..z1 })?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(xlabel)
        .y_desc(zlabel)
        .draw()?;
    chart.draw_series(values.iter().enumerate().flat_map(|(r, row)| {
        row.iter()
            .enumerate()
            .filter(|(_, v)| v.is_finite())
            .map(move |(c, v)| {
                let (x, (za, zb)) = (xs[c], row_edges[r]);
                Rectangle::new(
                    [(x - 0.5 * dx, za), (x + 0.5 * dx, zb)],
                    colormap((v - vmin) / span).filled(),
                )
            })
    }))?;
    if let Some(at) = marker {
        chart.draw_series([
            Cross::new(at, 7, WHITE.stroke_width(4)),
            Cross::new(at, 6, BLACK.stroke_width(2)),
        ])?;
    }
    let mut cb = ChartBuilder::on(&bar)
        .margin(12)
        .margin_top(20)
        .margin_bottom(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..1.0, vmin..vmax)?;
    cb.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(unit)
        .y_label_formatter(&|v| tick_of_scale(*v, vmin.abs().max(vmax.abs())))
        .y_label_style(("sans-serif", 12))
        .axis_desc_style(("sans-serif", 13))
        .draw()?;
    cb.draw_series((0..100).map(|k| {
        let (a, b) = (
            vmin + span * k as f64 / 100.0,
            vmin + span * (k + 1) as f64 / 100.0,
        );
        Rectangle::new([(0.0, a), (1.0, b)], colormap(k as f64 / 99.0).filled())
    }))?;
    root.present()?;
    Ok(())
}

/// A fretting map (Vingsbo & Söderberg): two panels over the amplitude (columns, x) × load (rows,
/// y) grid, drawn by cell index so that any spacing of the axes shows as equal cells — the regime
/// (0 partial slip, 1 mixed, 2 gross slip, three colours) and the dissipated energy per cycle
/// (colour, with its value in the cell). SVG or PNG by the extension.
pub fn fretting_map(
    path: &Path,
    title: &str,
    loads: &[f64],
    amplitudes: &[f64],
    regime: &[f64],
    energy: &[f64],
    response: Option<(&[f64], &[f64])>,
) -> PlotResult {
    let size = if response.is_some() {
        (1800, 520)
    } else {
        (1200, 520)
    };
    atomic(path, |path| {
        register_font()?;
        if path.extension().and_then(|e| e.to_str()) == Some("png") {
            let root = BitMapBackend::new(path, size).into_drawing_area();
            draw_fretting_map(root, title, loads, amplitudes, regime, energy, response)
        } else {
            let root = SVGBackend::new(path, size).into_drawing_area();
            draw_fretting_map(root, title, loads, amplitudes, regime, energy, response)
        }
    })
}

fn draw_fretting_map<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    loads: &[f64],
    amplitudes: &[f64],
    regime: &[f64],
    energy: &[f64],
    response: Option<(&[f64], &[f64])>,
) -> PlotResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 16))?;
    let panels = root.split_evenly((1, if response.is_some() { 3 } else { 2 }));
    // The material response (docs/fatigue.md, "Crack–wear fretting maps"): 0 no damage,
    // 1 cracking, 2 wear, 3 both.
    let response_colour = |r: f64| match r as i64 {
        0 => RGBColor(200, 230, 201),
        1 => RGBColor(239, 83, 80),
        2 => RGBColor(255, 202, 40),
        _ => RGBColor(171, 71, 188),
    };
    let (response, crack_risk) = response.unwrap_or((&[], &[]));
    let (nr, nc) = (loads.len(), amplitudes.len());
    let regime_colour = |r: f64| match r as i64 {
        0 => RGBColor(66, 133, 244),
        1 => RGBColor(251, 188, 5),
        _ => RGBColor(219, 68, 55),
    };
    let (emin, emax) = energy
        .iter()
        .fold((f64::MAX, f64::MIN), |(lo, hi), &e| (lo.min(e), hi.max(e)));
    let espan = (emax - emin).max(1e-300);
    for (panel, name) in panels.iter().zip([
        "regime",
        "dissipated energy per cycle (J)",
        "material response: none, crack (risk ≥ 1), wear (E_d/4Q*δ* ≥ 0.2), both",
    ]) {
        let mut chart = ChartBuilder::on(panel)
            .caption(name, ("sans-serif", 14))
            .margin(14)
            .x_label_area_size(40)
            .y_label_area_size(64)
            .build_cartesian_2d(-0.5..nc as f64 - 0.5, -0.5..nr as f64 - 0.5)?;
        let amp_label = |v: &f64| {
            let k = v.round();
            if (v - k).abs() < 1e-9 && k >= 0.0 && (k as usize) < nc {
                format!("{:.3}", amplitudes[k as usize] * 1e6)
            } else {
                String::new()
            }
        };
        let load_label = |v: &f64| {
            let k = v.round();
            if (v - k).abs() < 1e-9 && k >= 0.0 && (k as usize) < nr {
                format!("{:.1}", loads[k as usize] * 1e3)
            } else {
                String::new()
            }
        };
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(nc.max(2) * 2 + 1)
            .y_labels(nr.max(2) * 2 + 1)
            .x_label_formatter(&amp_label)
            .y_label_formatter(&load_label)
            .x_desc("displacement amplitude A (μm)")
            .y_desc("normal load W (mN)")
            .draw()?;
        let cells = (0..nr).flat_map(|i| (0..nc).map(move |j| (i, j)));
        let is_regime = name == "regime";
        let is_response = name.starts_with("material");
        chart.draw_series(cells.clone().map(|(i, j)| {
            let k = i * nc + j;
            let colour = if is_regime {
                regime_colour(regime[k])
            } else if is_response {
                response_colour(response[k])
            } else {
                colormap((energy[k] - emin) / espan)
            };
            let (x, y) = (j as f64, i as f64);
            Rectangle::new([(x - 0.5, y - 0.5), (x + 0.5, y + 0.5)], colour.filled())
        }))?;
        chart.draw_series(cells.map(|(i, j)| {
            let k = i * nc + j;
            let text = if is_regime {
                ["PS", "mixed", "GS"][(regime[k] as usize).min(2)].to_string()
            } else if is_response {
                format!(
                    "{} {:.2}",
                    ["none", "crack", "wear", "both"][(response[k] as usize).min(3)],
                    crack_risk[k]
                )
            } else {
                format!("{:.2e}", energy[k])
            };
            // Black on the categorical colours and on the light end of the colour map.
            let colour = if is_regime || is_response || (energy[k] - emin) / espan > 0.6 {
                BLACK
            } else {
                WHITE
            };
            Text::new(
                text,
                (j as f64 - 0.3, i as f64),
                ("sans-serif", 12).into_font().color(&colour),
            )
        }))?;
    }
    root.present()?;
    Ok(())
}

/// The cell centres of a surface grid along x and y, in μm (the axes of the wear maps).
fn cell_centres_um(g: &halfspace::sam::SurfaceGrid) -> (Vec<f64>, Vec<f64>) {
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
pub fn wear3d_figures(
    dir: &Path,
    run: &halfspace::sam::drivers::fretting_wear3d::FrettingWear3d,
) -> Result<(), super::CliError> {
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
        super::CliError::Plot(format!("{}: {e}", p.display()))
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

/// The fatigue figures of a fretting loop with `[fatigue]`, written into `dir`
/// (docs/fatigue.md#figures): `fatigue_section_{crossland,dang_van,swt,fatemi_socie}.svg`, the
/// x–z section of each index through the row of cells (y) holding its maximum, the maximum
/// marked by a cross (depth downward; cells the screen skipped, NaN, blank), and
/// `fatigue_depth_profile.svg`, the largest value of each index over each layer against the
/// depth, divided by the index's overall maximum.
pub fn fatigue_figures(
    dir: &Path,
    f: &halfspace::loop_fatigue::LoopFatigue,
) -> Result<(), super::CliError> {
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
        super::CliError::Plot(format!("{}: {e}", p.display()))
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

/// One map of an animation frame: `values[row][col]` over cells centred at `(xs[col], ys[row])`,
/// coloured on the fixed range `range` (the same in every frame, so that the frames compare),
/// with its caption and a narrow colour bar.
pub struct FrameMap<'a> {
    /// The caption above the map (the field and its unit).
    pub caption: &'a str,
    /// Cell centres along the horizontal axis.
    pub xs: &'a [f64],
    /// Cell centres along the vertical axis.
    pub ys: &'a [f64],
    /// `values[row][col]`.
    pub values: Vec<Vec<f64>>,
    /// The colour range `(min, max)`, fixed over the animation.
    pub range: (f64, f64),
}

/// The pixel size of the animation frames (at most 480 px): one map per frame (`wear_depth.gif`)
/// or two side by side (`loop_pq.gif`); the map areas about square (equal scales on x and y for
/// a square window).
pub fn frame_size(maps: usize) -> (u32, u32) {
    if maps <= 1 {
        (400, 360)
    } else {
        (480, 232)
    }
}

/// Renders one frame: `title` on top, `maps` side by side below, axes labelled `(xlabel,
/// ylabel)` (the plotters bitmap backend, the embedded font); returns the RGBA pixels.
pub fn render_frame(
    title: &str,
    (xlabel, ylabel): (&str, &str),
    maps: &[FrameMap],
) -> Result<image::RgbaImage, Box<dyn std::error::Error>> {
    register_font()?;
    let (w, h) = frame_size(maps.len());
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE)?;
        let root = root.titled(title, ("sans-serif", 13))?;
        let panels = root.split_evenly((1, maps.len().max(1)));
        for (area, m) in panels.iter().zip(maps) {
            draw_frame_map(area, m, (xlabel, ylabel))?;
        }
        root.present()?;
    }
    let rgba = rgb
        .chunks_exact(3)
        .flat_map(|c| [c[0], c[1], c[2], 255])
        .collect();
    image::RgbaImage::from_raw(w, h, rgba).ok_or_else(|| "frame buffer size".into())
}

fn draw_frame_map<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    m: &FrameMap,
    (xlabel, ylabel): (&str, &str),
) -> PlotResult
where
    DB::ErrorType: 'static,
{
    let (xs, ys) = (m.xs, m.ys);
    if xs.is_empty() || ys.is_empty() {
        return Err(format!("{}: no cells to draw", m.caption).into());
    }
    let (width, _) = area.dim_in_pixel();
    let (main, bar) = area.split_horizontally(width.saturating_sub(66));
    let dx = if xs.len() > 1 { xs[1] - xs[0] } else { 1.0 };
    let dy = if ys.len() > 1 { ys[1] - ys[0] } else { 1.0 };
    let (vmin, vmax) = m.range;
    let span = (vmax - vmin).max(vmax.abs() * 1e-12).max(1e-300);
    let vmax = vmin + span;
    let small = ("sans-serif", 10);
    let mut chart = ChartBuilder::on(&main)
        .caption(m.caption, ("sans-serif", 12))
        .margin(4)
        .x_label_area_size(26)
        .y_label_area_size(34)
        .build_cartesian_2d(
            xs[0] - 0.5 * dx..xs[xs.len() - 1] + 0.5 * dx,
            ys[0] - 0.5 * dy..ys[ys.len() - 1] + 0.5 * dy,
        )?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(5)
        .y_labels(5)
        .x_desc(xlabel)
        .y_desc(ylabel)
        .label_style(small)
        .axis_desc_style(small)
        .draw()?;
    chart.draw_series(m.values.iter().enumerate().flat_map(|(r, row)| {
        row.iter()
            .enumerate()
            .filter(|(_, v)| v.is_finite())
            .map(move |(c, v)| {
                let (x, y) = (xs[c], ys[r]);
                Rectangle::new(
                    [(x - 0.5 * dx, y - 0.5 * dy), (x + 0.5 * dx, y + 0.5 * dy)],
                    colormap((v - vmin) / span).filled(),
                )
            })
    }))?;
    // The colour bar: a strip, its labels drawn beside it in pixels (three significant digits
    // of the scale, fixed-point: short enough for the narrow bar).
    let (strip, labels) = bar.split_horizontally(18);
    let (top, bottom) = (22, 30);
    let mut cb = ChartBuilder::on(&strip)
        .margin(4)
        .margin_top(top)
        .margin_bottom(bottom)
        .build_cartesian_2d(0.0..1.0, vmin..vmax)?;
    cb.draw_series((0..64).map(|k| {
        let (a, b) = (
            vmin + span * k as f64 / 64.0,
            vmin + span * (k + 1) as f64 / 64.0,
        );
        Rectangle::new([(0.0, a), (1.0, b)], colormap(k as f64 / 63.0).filled())
    }))?;
    let digits = (2 - vmin.abs().max(vmax.abs()).log10().floor() as i32).clamp(0, 6) as usize;
    let (_, height) = labels.dim_in_pixel();
    let length = height.saturating_sub(top + bottom) as f64;
    for k in 0..=4 {
        let t = k as f64 / 4.0;
        let y = top as f64 + (1.0 - t) * length;
        labels.draw(&Text::new(
            format!("{:.digits$}", vmin + t * span),
            (2, y as i32 - 5),
            small.into_font(),
        ))?;
    }
    Ok(())
}

/// Writes `frames` as a looping GIF animation, `delay_ms` per frame, atomically (a temporary file
/// renamed over `path`). The image crate's encoder quantises each frame to 256 colours (NeuQuant,
/// speed 10: the frames are flat colour maps, which it renders without visible banding).
pub fn write_gif(
    path: &Path,
    frames: Vec<image::RgbaImage>,
    delay_ms: u32,
) -> Result<(), super::CliError> {
    use image::codecs::gif::{GifEncoder, Repeat};
    let fail = |m: String| super::CliError::Plot(format!("{}: {m}", path.display()));
    if frames.is_empty() {
        return Err(fail("no frames".into()));
    }
    halfspace::data::write_atomic(path, |tmp| {
        let format = |e: image::ImageError| halfspace::data::DataError::Format {
            path: path.to_path_buf(),
            message: e.to_string(),
        };
        let file = std::fs::File::create(tmp).map_err(|source| halfspace::data::DataError::Io {
            path: tmp.to_path_buf(),
            source,
        })?;
        let mut encoder = GifEncoder::new_with_speed(std::io::BufWriter::new(file), 10);
        encoder.set_repeat(Repeat::Infinite).map_err(format)?;
        let delay = image::Delay::from_numer_denom_ms(delay_ms, 1);
        encoder
            .encode_frames(
                frames
                    .into_iter()
                    .map(|f| image::Frame::from_parts(f, 0, 0, delay)),
            )
            .map_err(format)
    })
    .map_err(|e| fail(e.to_string()))
}

/// `wear_depth.gif` (docs/wear3d.md#figures): the worn depth h(x, y) at the records of the run
/// (the record cycles and the end, [`wear3d_figures`]' snapshots) — every record up to
/// [`halfspace::animation::MAX_FRAMES`], else that many evenly spaced with the first and the last
/// ([`halfspace::animation::frame_records`]) — on one colour scale from 0 to the final largest
/// depth (over all records, drawn or not), the cycle count in each frame's title.
pub fn wear3d_animation(
    dir: &Path,
    run: &halfspace::sam::drivers::fretting_wear3d::FrettingWear3d,
) -> Result<(), super::CliError> {
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
    let fail =
        |e: Box<dyn std::error::Error>| super::CliError::Plot(format!("{}: {e}", p.display()));
    let frames =
        halfspace::animation::frame_records(records.len(), halfspace::animation::MAX_FRAMES)
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
