//! The figure of `fretting-map` (docs/fretting-map.md): the regime, the dissipated energy and,
//! with the fatigue criteria, the material response of every point of the map.

use std::path::Path;

use halfspace_sam::drivers::fretting_loop::LoopCase;
use halfspace_sam::drivers::fretting_map::FrettingMap;
use plotters::prelude::*;

use crate::draw::{atomic, colormap, register_font, DrawResult};
use crate::FigureError;

/// `fretting_map.svg` and `fretting_map.png` in `dir`: [`fretting_map`] of the map's points —
/// `regime` and `energy` by point (row-major over loads × amplitudes) and, with the fatigue
/// criteria, `(material response, crack risk)` — titled by [`map_title`] of the map's base case.
pub fn map_figures(
    dir: &Path,
    map: &FrettingMap,
    regime: &[f64],
    energy: &[f64],
    response: Option<(&[f64], &[f64])>,
) -> Result<(), FigureError> {
    let figure = MapFigure {
        title: map_title(map.base()),
        loads: map.loads(),
        amplitudes: map.amplitudes(),
        regime,
        energy,
        response,
    };
    for name in ["fretting_map.svg", "fretting_map.png"] {
        fretting_map(&dir.join(name), &figure)?;
    }
    Ok(())
}

/// What a fretting map shows: its title, the loads (rows) and amplitudes (columns), and by point
/// (row-major) the regime, the dissipated energy per cycle and, with the fatigue criteria,
/// `(material response, crack risk)`.
pub struct MapFigure<'a> {
    pub title: String,
    pub loads: &'a [f64],
    pub amplitudes: &'a [f64],
    pub regime: &'a [f64],
    pub energy: &'a [f64],
    pub response: Option<(&'a [f64], &'a [f64])>,
}

/// The title of a map of `base` (the point case of the largest load): the sphere, the material,
/// the friction, the grid and the inhomogeneities.
pub fn map_title(base: &LoopCase) -> String {
    format!(
        "Fretting map: sphere R = {:.0} μm, E = {:.0} GPa, μ = {}, {}² cells{}",
        base.radius * 1e6,
        base.e * 1e-9,
        base.friction,
        base.grid,
        if base.inhomogeneities.is_empty() {
            String::new()
        } else {
            format!(", {} inhomogeneities", base.inhomogeneities.len())
        }
    )
}

/// A fretting map (Vingsbo & Söderberg): two panels over the amplitude (columns, x) × load (rows,
/// y) grid, drawn by cell index so that any spacing of the axes shows as equal cells — the regime
/// (0 partial slip, 1 mixed, 2 gross slip, three colours) and the dissipated energy per cycle
/// (colour, with its value in the cell). SVG or PNG by the extension.
pub fn fretting_map(path: &Path, figure: &MapFigure) -> Result<(), FigureError> {
    let size = if figure.response.is_some() {
        (1800, 520)
    } else {
        (1200, 520)
    };
    atomic(path, |path| {
        register_font()?;
        if path.extension().and_then(|e| e.to_str()) == Some("png") {
            let root = BitMapBackend::new(path, size).into_drawing_area();
            draw_fretting_map(root, figure)
        } else {
            let root = SVGBackend::new(path, size).into_drawing_area();
            draw_fretting_map(root, figure)
        }
    })
    .map_err(|e| FigureError::Draw(e.to_string()))
}

fn draw_fretting_map<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    figure: &MapFigure,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let (title, loads, amplitudes) = (figure.title.as_str(), figure.loads, figure.amplitudes);
    let (regime, energy, response) = (figure.regime, figure.energy, figure.response);
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
