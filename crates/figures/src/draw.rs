//! The drawing primitives of every figure (plotters: SVG, and PNG through the bitmap backend;
//! GIF animations through the image crate's encoder), with an embedded font (DejaVu Sans in
//! assets/fonts) so that no system font library is needed: curves in one or two panels, log–log
//! errors, maps with a colour bar (sections downward, surface maps upward), animation frames.
//! What a figure shows is chosen by the figure modules of this crate, not here.

use std::path::Path;

use plotters::prelude::*;

use crate::FigureError;

/// What a drawing primitive returns: plotters' and the writer's errors, boxed.
pub type DrawResult = Result<(), Box<dyn std::error::Error>>;

/// The figure formats, by extension: `.svg` and `.png` (anything else is refused, never written
/// as SVG bytes under another name).
pub fn check_extension(path: &Path, what: &str, allowed: &[&str]) -> Result<(), FigureError> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if allowed.contains(&ext) {
        Ok(())
    } else {
        Err(FigureError::Extension(format!(
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
pub(crate) fn atomic(path: &Path, draw: impl FnOnce(&Path) -> DrawResult) -> DrawResult {
    check_extension(path, "figure", &["svg", "png"]).map_err(|e| e.to_string())?;
    let mut failure = None;
    let written = halfspace_data::write_atomic(path, |tmp| {
        draw(tmp).map_err(|e| {
            let message = e.to_string();
            failure = Some(message.clone());
            halfspace_data::DataError::Format {
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

/// Log–log errors against N, one line per series, with a reference line of slope `−order`.
pub fn convergence(
    path: &Path,
    title: &str,
    ns: &[usize],
    series: &[(&str, Vec<f64>)],
    order: f64,
) -> DrawResult {
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
) -> DrawResult {
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
                .legend(legend_stroke(color));
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
                    .legend(legend_stroke(style));
            }
        }
        legend_box(&mut chart)?;
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
) -> DrawResult {
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
) -> DrawResult
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
                .legend(legend_stroke(color));
        }
        legend_box(&mut chart)?;
    }
    root.present()?;
    Ok(())
}

/// A legend entry: an 18 px stroke in the line's style.
pub(crate) fn legend_stroke(
    style: impl Into<ShapeStyle>,
) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    let style = style.into();
    move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], style)
}

/// The legend box of the curves and log–log figures: white at 80 %, a black border.
fn legend_box<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}

/// The embedded font for bitmap output (DejaVu Sans, assets/fonts; no system font libraries).
pub(crate) fn register_font() -> DrawResult {
    static FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");
    plotters::style::register_font("sans-serif", plotters::style::FontStyle::Normal, FONT)
        .map_err(|_| "the embedded font could not be loaded")?;
    Ok(())
}

/// A colour map from 0 to 1 (dark blue → teal → yellow, viridis-like).
pub(crate) fn colormap(t: f64) -> RGBColor {
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
) -> DrawResult {
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
) -> DrawResult {
    map_figure(path, title, labels, xs, ys, values, false, None)
}

/// [`heatmap`] (`downward`) or [`surface_map`], with an optional cross at `marker` (a maximum).
#[allow(clippy::too_many_arguments)]
pub(crate) fn map_figure(
    path: &Path,
    title: &str,
    labels: (&str, &str, &str),
    xs: &[f64],
    zs: &[f64],
    values: &[Vec<f64>],
    downward: bool,
    marker: Option<(f64, f64)>,
) -> DrawResult {
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
pub(crate) fn tick(v: f64) -> String {
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
) -> DrawResult
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
) -> DrawResult
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
) -> Result<(), FigureError> {
    use image::codecs::gif::{GifEncoder, Repeat};
    let fail = |m: String| FigureError::Draw(format!("{}: {m}", path.display()));
    if frames.is_empty() {
        return Err(fail("no frames".into()));
    }
    halfspace_data::write_atomic(path, |tmp| {
        let format = |e: image::ImageError| halfspace_data::DataError::Format {
            path: path.to_path_buf(),
            message: e.to_string(),
        };
        let file = std::fs::File::create(tmp).map_err(|source| halfspace_data::DataError::Io {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The rows (pixels from the top) of the column `x` of `rgb` (`width` wide) holding `colour`.
    fn rows_of(rgb: &[u8], width: u32, x: u32, colour: RGBColor) -> Vec<u32> {
        (0..rgb.len() as u32 / (3 * width))
            .filter(|&y| {
                let i = 3 * (y * width + x) as usize;
                rgb[i..i + 3] == [colour.0, colour.1, colour.2]
            })
            .collect()
    }

    /// The mean pixel row of the cells valued 1 and of those valued 0, in the middle column of
    /// the map panel, for a field that is 1 where the row coordinate is > 0 and 0 elsewhere.
    fn mean_rows(downward: bool) -> (f64, f64) {
        let (w, h, map) = (720u32, 600u32, 590u32);
        let xs: Vec<f64> = (0..8).map(|i| i as f64 - 3.5).collect();
        let ys = xs.clone();
        let values: Vec<Vec<f64>> = ys
            .iter()
            .map(|&y| vec![if y > 0.0 { 1.0 } else { 0.0 }; xs.len()])
            .collect();
        let mut rgb = vec![0u8; (w * h * 3) as usize];
        {
            let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
            register_font().unwrap();
            draw_heatmap(
                root,
                map,
                "orientation",
                ("x", "y", "v"),
                &xs,
                &ys,
                &values,
                downward,
                None,
            )
            .unwrap();
        }
        let mean = |rows: Vec<u32>| {
            assert!(rows.len() > 100, "{} pixels of the colour", rows.len());
            rows.iter().map(|&r| r as f64).sum::<f64>() / rows.len() as f64
        };
        // The middle of the map panel (the y labels take its left 64 px).
        let x = (64 + map) / 2;
        (
            mean(rows_of(&rgb, w, x, colormap(1.0))),
            mean(rows_of(&rgb, w, x, colormap(0.0))),
        )
    }

    /// `surface_map` draws y upward: a field positive only for y > 0 fills the top half of the
    /// map (the fretting loop's Fig. 9 and slip maps, the wear map); `heatmap` draws depth
    /// downward: a field positive only for z > 0 fills the bottom half.
    #[test]
    fn surface_maps_put_y_up_and_sections_put_depth_down() {
        let (high, low) = mean_rows(false);
        assert!(
            high < low,
            "y up: y > 0 at rows {high}, y < 0 at rows {low}"
        );
        let (high, low) = mean_rows(true);
        assert!(
            high > low,
            "depth down: z > 0 at rows {high}, z < 0 at rows {low}"
        );
    }
}
