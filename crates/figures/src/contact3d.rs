//! The figures of `contact3d --plot` (docs/contact3d.md): the pressure (and `u₃^eig`) along x
//! through the centre, with Hertz's pressure for a sphere, and the von Mises map of the x–z plane.

use std::path::Path;

use halfspace_sam::contact::ContactSolver;
use halfspace_sam::drivers::one_contact::{ContactCase, ContactOutcome};
use halfspace_sam::indenter::Indenter;
use halfspace_sam::subsurface::StressField;

use crate::draw::{curves, heatmap};
use crate::FigureError;

/// The figures of a solved contact: `path` (SVG or PNG by its extension) and, with a stress field,
/// `STEM-von-mises.EXT` beside it ([`figures`] of the outcome; Hertz's pressure is drawn for a
/// spherical indenter, `Ellipsoid { rx = ry }`).
pub fn contact_figures(
    path: &Path,
    case: &ContactCase,
    outcome: &ContactOutcome,
) -> Result<(), FigureError> {
    let hertz = match case.indenter {
        Indenter::Ellipsoid { rx, ry } if rx == ry => {
            Some((rx, outcome.solver.problem().state().force, outcome.e_star))
        }
        _ => None,
    };
    figures(path, &outcome.solver, outcome.field.as_ref(), hertz)
}

/// The pressure (and `u₃^eig`) along x through the centre, with Hertz's pressure for a sphere
/// (`hertz = (R, W, E*)`), and the von Mises map in the x–z plane through the centre.
pub fn figures(
    path: &Path,
    solver: &ContactSolver,
    field: Option<&StressField>,
    hertz: Option<(f64, f64, f64)>,
) -> Result<(), FigureError> {
    let problem = solver.problem();
    let g = problem.grid();
    // The row of cells nearest y = 0 along x: index i (x) varies, j fixed.
    let col = g.n2 / 2;
    let xs: Vec<f64> = (0..g.n1).map(|i| g.centre(i, col).0).collect();
    let st = problem.state();
    let mut left = vec![(
        "pressure (MPa)".to_string(),
        xs.iter()
            .enumerate()
            .map(|(i, x)| (x * 1e6, st.pressure[i * g.n2 + col] * 1e-6))
            .collect::<Vec<_>>(),
    )];
    if let Some((r, w, e_star)) = hertz {
        let a = halfspace_mdr::analytic::sphere_radius_for_force(w, r, e_star);
        let p0 = 3.0 * w / (2.0 * std::f64::consts::PI * a * a);
        let y = g.centre(0, col).1;
        left.push((
            "Hertz (homogeneous)".to_string(),
            xs.iter()
                .map(|x| {
                    let r2 = (x * x + y * y) / (a * a);
                    (
                        x * 1e6,
                        if r2 < 1.0 {
                            p0 * (1.0 - r2).sqrt() * 1e-6
                        } else {
                            0.0
                        },
                    )
                })
                .collect(),
        ));
    }
    let right: Vec<(String, Vec<(f64, f64)>)> = match solver.nested() {
        Some(n) => vec![(
            "eigen-displacement u3 (nm)".to_string(),
            xs.iter()
                .enumerate()
                .map(|(i, x)| (x * 1e6, n.eigen_displacements()[2][i * g.n2 + col] * 1e9))
                .collect(),
        )],
        None => vec![],
    };
    let err = |e: Box<dyn std::error::Error>| FigureError::Draw(e.to_string());
    curves(
        path,
        "contact3d: along x through the centre (y ≈ 0)",
        "x (μm)",
        ("pressure (MPa)", &left),
        ("u3 eig (nm)", &right),
        false,
    )
    .map_err(err)?;
    if let Some(f) = field {
        let n = g.len();
        let zs: Vec<f64> = (0..f.layers).map(|k| f.depth(k) * 1e6).collect();
        let values: Vec<Vec<f64>> = (0..f.layers)
            .map(|k| {
                (0..g.n1)
                    .map(|i| f.von_mises[k * n + i * g.n2 + col] * 1e-6)
                    .collect()
            })
            .collect();
        let xs_um: Vec<f64> = xs.iter().map(|x| x * 1e6).collect();
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let ext = path
            .extension()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "svg".into());
        let map = path.with_file_name(format!("{stem}-von-mises.{ext}"));
        heatmap(
            &map,
            "von Mises stress in the x–z plane through the centre",
            ("x (μm)", "depth z (μm)", "MPa"),
            &xs_um,
            &zs,
            &values,
        )
        .map_err(err)?;
    }
    Ok(())
}
