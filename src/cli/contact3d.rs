//! `halfspace contact3d`: 3D semi-analytical contact (docs/theory-sam.md), one normal and one tangential
//! increment, with or without inhomogeneities.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use halfspace::config::{InhomogeneityEntry, Names};
use halfspace::contact3d::Contact3dConfig;
use halfspace::data::write_record;
use halfspace::records::{contact_record, contact_summary, VOLUME_FIELDS};
use halfspace::sam::contact::ContactSolver;
use halfspace::sam::drivers::one_contact::{solve_contact, ContactOutcome};
use halfspace::sam::indenter::Indenter;
use halfspace::sam::subsurface::StressField;
use halfspace::sam::SamError;
use serde_json::json;

use super::{plot, CliError};

#[derive(Debug, Args)]
pub struct Contact3dArgs {
    /// TOML (or .json) file with any of the keys indenter, material, indenter_material, force,
    /// depth, shift_x, tangential_force, friction, inhomogeneity (a list), subsurface, grid,
    /// extent, tol; a flag given on the command line overrides its key, --inhomogeneity adds to
    /// the list (docs/architecture.md, "The application layer").
    #[arg(long)]
    config: Option<PathBuf>,
    /// sphere:R=.. | ellipsoid:Rx=..,Ry=.. | cone:slope=.. | flat:a=.. | table:FILE.npy (heights on the grid)
    #[arg(long)]
    indenter: Option<String>,
    /// Half-space: homogeneous:E=..,nu=..
    #[arg(long)]
    material: Option<String>,
    /// Indenter: rigid (default) or homogeneous:E=..,nu=..
    #[arg(long)]
    indenter_material: Option<String>,
    /// Normal force W in N.
    #[arg(long, allow_hyphen_values = true)]
    force: Option<f64>,
    /// Rigid approach δ in m.
    #[arg(long, allow_hyphen_values = true)]
    depth: Option<f64>,
    /// Rigid tangential shift along x in m (after the normal load).
    #[arg(long, allow_hyphen_values = true, conflicts_with = "tangential_force")]
    shift_x: Option<f64>,
    /// Tangential force along x in N (after the normal load).
    #[arg(long, allow_hyphen_values = true)]
    tangential_force: Option<f64>,
    /// Coulomb friction coefficient μ (default 0: frictionless, as in other contact codes; a
    /// tangential load needs it).
    #[arg(long, allow_hyphen_values = true)]
    friction: Option<f64>,
    /// Inhomogeneity below the surface (repeatable): sphere:x=..,y=..,z=..,r=..,E=..,nu=.. |
    /// cylinder:axis=y,x=..,z=..,r=..,E=..,nu=.. (or axis=x,y=..) |
    /// cuboid:x=..,y=..,z=..,hx=..,hy=..,hz=..,E=..,nu=..; z = depth of the centre (m).
    #[arg(long = "inhomogeneity")]
    inhomogeneities: Vec<String>,
    /// Compute the stress field below the surface down to DEPTH (m).
    #[arg(long, allow_hyphen_values = true)]
    subsurface: Option<f64>,
    /// Cells per side (default 128).
    #[arg(long, allow_hyphen_values = true)]
    grid: Option<usize>,
    /// Side of the square domain in m (default: 4 estimated contact radii).
    #[arg(long, allow_hyphen_values = true)]
    extent: Option<f64>,
    /// Relative tolerance of the normal and tangential solvers (default 1e-10).
    #[arg(long, allow_hyphen_values = true)]
    tol: Option<f64>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Write the fields to FILE.h5 or FILE.npz.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Draw the pressure (and eigen-displacement) along x through the centre to FILE.svg|.png;
    /// with --subsurface also the von Mises map in the x–z plane to FILE-von-mises.svg|.png.
    #[arg(long)]
    plot: Option<PathBuf>,
}

pub fn run(args: Contact3dArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let flags = Contact3dConfig {
        indenter: args.indenter.clone(),
        material: args.material.clone(),
        indenter_material: args.indenter_material.clone(),
        force: args.force,
        depth: args.depth,
        shift_x: args.shift_x,
        tangential_force: args.tangential_force,
        friction: args.friction,
        inhomogeneity: args
            .inhomogeneities
            .iter()
            .map(|s| InhomogeneityEntry::Spec(s.clone()))
            .collect(),
        subsurface: args.subsurface,
        grid: args.grid,
        extent: args.extent,
        tol: args.tol,
    };
    let file: Contact3dConfig = super::read_config(args.config.as_deref())?;
    let config = file.overlay(flags);
    if let Some(path) = &args.plot {
        plot::check_extension(path, "--plot", &["svg", "png"])?;
    }
    let case = config.case(Names::Flags)?;
    if let Some(path) = &args.out {
        halfspace::data::Format::of(path)?;
    }
    let outcome = solve_contact(&case).map_err(|e| match e {
        SamError::InvalidInput(m) if m.contains("height table") => CliError::Spec(format!(
            "--indenter '{}': {m} (--grid, --extent)",
            config.indenter.as_deref().unwrap_or_default()
        )),
        other => other.into(),
    })?;
    let mut summary = contact_summary(&outcome, &case);
    summary["seconds"] = json!(start.elapsed().as_secs_f64());
    let ContactOutcome {
        solver,
        info,
        field,
        e_star,
        ..
    } = &outcome;
    let state = solver.problem().state();
    let seconds = start.elapsed().as_secs_f64();
    if let Some(path) = &args.plot {
        let hertz = match case.indenter {
            Indenter::Ellipsoid { rx, ry } if rx == ry => Some((rx, state.force, *e_star)),
            _ => None,
        };
        draw_figures(path, solver, field.as_ref(), hertz)?;
    }
    if let Some(path) = &args.out {
        write_record(path, &contact_record(&outcome, &summary))?;
        if let (Some(f), Ok(halfspace::data::Format::Hdf5)) =
            (&field, halfspace::data::Format::of(path))
        {
            write_volume_xdmf(path, f)?;
        }
    }
    if args.json {
        println!("{summary}");
    } else {
        println!(
            "contact radius {:.4e} m, max pressure {:.4e} Pa, force {:.4e} N, approach {:.4e} m, Q {:.4e} N, stick radius {:.4e} m ({seconds:.2} s)",
            summary["contact_radius"].as_f64().unwrap_or(0.0),
            info.max_pressure,
            state.force,
            state.approach,
            info.tangential_force[0],
            summary["stick_radius"].as_f64().unwrap_or(0.0)
        );
    }
    Ok(())
}

/// The pressure (and `u₃^eig`) along x through the centre, with Hertz's pressure for a sphere
/// (`hertz = (R, W, E*)`), and the von Mises map in the x–z plane through the centre.
fn draw_figures(
    path: &std::path::Path,
    solver: &ContactSolver,
    field: Option<&StressField>,
    hertz: Option<(f64, f64, f64)>,
) -> Result<(), CliError> {
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
        let a = halfspace::mdr::analytic::sphere_radius_for_force(w, r, e_star);
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
    let err = |e: Box<dyn std::error::Error>| CliError::Plot(e.to_string());
    plot::curves(
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
        plot::heatmap(
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

/// `FILE.xdmf` beside `FILE.h5`: the volume fields on their lattice, for ParaView.
fn write_volume_xdmf(h5: &std::path::Path, f: &StressField) -> Result<(), CliError> {
    let (x0, y0) = f.grid.centre(0, 0);
    let d = 2.0 * f.grid.half1;
    let volume = halfspace::data::UniformVolume {
        dims: [f.layers, f.grid.n1, f.grid.n2],
        origin: [f.grid.half1, x0, y0],
        spacing: [d, d, d],
    };
    halfspace::data::write_xdmf(
        &h5.with_extension("xdmf"),
        h5,
        &volume,
        &VOLUME_FIELDS,
        "halfspace contact3d volume fields; XDMF axes Z Y X = depth (into the body), x, y (m)",
    )?;
    Ok(())
}
