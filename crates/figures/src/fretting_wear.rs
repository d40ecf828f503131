//! The figure of `fretting-wear` (docs/fretting-wear.md): the worn profiles of an MDR wear run.

use std::path::Path;

use halfspace_fretting::FrettingSimulation;
use plotters::prelude::*;

use crate::draw::{atomic, legend_stroke, register_font, DrawResult};
use crate::FigureError;

/// Worn profiles `f/d` against `r/a₀` for every snapshot, the limiting profile dashed (the paper's
/// Fig. 4). SVG or PNG by the extension.
pub fn worn_profiles(path: &Path, sim: &FrettingSimulation) -> Result<(), FigureError> {
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
    .map_err(|e| FigureError::Draw(format!("{}: {e}", path.display())))
}

fn draw_worn<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    sim: &FrettingSimulation,
) -> DrawResult
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
        .legend(legend_stroke(BLACK));
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
            .legend(legend_stroke(color));
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
        .legend(legend_stroke(BLACK.stroke_width(2)));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
