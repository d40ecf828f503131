//! The figure of `axisym --plot` (docs/axisym.md): the MDR contact's pressure and surface
//! displacement.

use std::path::Path;

use halfspace_mdr::ContactSolution;
use plotters::prelude::*;

use crate::draw::{atomic, register_font};
use crate::FigureError;

/// `path` (SVG): two panels, `p(r)/max p` and `u(r)/δ` against `r/a`, titled `title` (the
/// profile's spec).
pub fn pressure_and_displacement(
    path: &Path,
    sol: &ContactSolution,
    title: &str,
) -> Result<(), FigureError> {
    draw_pressure_and_displacement(path, sol, title)
        .map_err(|e| FigureError::Draw(format!("{}: {e}", path.display())))
}

fn draw_pressure_and_displacement(
    path: &Path,
    sol: &ContactSolution,
    title: &str,
) -> crate::draw::DrawResult {
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
