//! SVG figures (plotters, SVG backend: no system fonts needed).

use std::path::Path;

use halfspace::mdr::ContactSolution;
use plotters::prelude::*;

type PlotResult = Result<(), Box<dyn std::error::Error>>;

/// Two panels: `p(r)/max p` and `u(r)/δ` against `r/a`.
pub fn pressure_and_displacement(path: &Path, sol: &ContactSolution, title: &str) -> PlotResult {
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
}
