//! `halfspace contact3d`: 3D semi-analytical contact (docs/theory-sam.md), one normal and one tangential
//! increment, with or without inhomogeneities.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use halfspace::data::write_record;
use halfspace::records::{contact_record, contact_summary, VOLUME_FIELDS};
use halfspace::sam::contact::ContactSolver;
use halfspace::sam::drivers::one_contact::{
    solve_contact, ContactCase, ContactOutcome, TangentialLoad,
};
use halfspace::sam::indenter::Indenter;
use halfspace::sam::normal::NormalLoad;
use halfspace::sam::subsurface::StressField;
use halfspace::sam::Body;
use halfspace::sam::SamError;
use halfspace::spec::{parse_body, parse_indenter, parse_inhomogeneity};
use serde_json::json;

use super::{plot, CliError};

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("load").required(true).args(["force", "depth"])))]
pub struct Contact3dArgs {
    /// sphere:R=.. | ellipsoid:Rx=..,Ry=.. | cone:slope=.. | flat:a=.. | table:FILE.npy (heights on the grid)
    #[arg(long)]
    indenter: String,
    /// Half-space: homogeneous:E=..,nu=..
    #[arg(long)]
    material: String,
    /// Indenter: rigid (default) or homogeneous:E=..,nu=..
    #[arg(long, default_value = "rigid")]
    indenter_material: String,
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
    /// Cells per side.
    #[arg(long, default_value_t = 128, allow_hyphen_values = true)]
    grid: usize,
    /// Side of the square domain in m (default: 4 estimated contact radii).
    #[arg(long, allow_hyphen_values = true)]
    extent: Option<f64>,
    /// Relative tolerance of the normal and tangential solvers.
    #[arg(long, default_value_t = 1e-10, allow_hyphen_values = true)]
    tol: f64,
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
    if args.indenter.trim_start().starts_with("table:") && args.extent.is_none() {
        return Err(CliError::Spec(
            "--indenter table: give --extent (the side of the grid in m)".into(),
        ));
    }
    if let Some(path) = &args.plot {
        plot::check_extension(path, "--plot", &["svg", "png"])?;
    }
    let indenter = parse_indenter(&args.indenter, "--indenter")?;
    let half = parse_body(&args.material, "--material")?;
    let tool = parse_body(&args.indenter_material, "--indenter-material")?;
    if matches!(half, Body::Rigid) {
        return Err(CliError::Spec(
            "--material: the half-space must be elastic".into(),
        ));
    }
    let load = match (args.force, args.depth) {
        (Some(w), None) => NormalLoad::Force(w),
        (None, Some(d)) => NormalLoad::Approach(d),
        _ => {
            return Err(CliError::Spec(
                "give exactly one of --force and --depth".into(),
            ))
        }
    };
    for (name, v) in [("--force", args.force), ("--depth", args.depth)] {
        if let Some(v) = v {
            if !(v.is_finite() && v > 0.0) {
                return Err(CliError::Spec(format!(
                    "{name} must be finite and > 0, got {v}"
                )));
            }
        }
    }
    let tangential_load = args.shift_x.is_some() || args.tangential_force.is_some();
    let friction =
        match args.friction {
            Some(mu) if !(mu.is_finite() && mu >= 0.0) => {
                return Err(CliError::Spec(format!(
                    "--friction must be finite and ≥ 0, got {mu}"
                )))
            }
            Some(mu) => mu,
            None if tangential_load => return Err(CliError::Spec(
                "--shift-x / --tangential-force need a friction coefficient: give --friction MU"
                    .into(),
            )),
            None => 0.0,
        };
    if tangential_load && friction == 0.0 {
        return Err(CliError::Spec(
            "--shift-x / --tangential-force with --friction 0: a frictionless contact carries no tangential load".into(),
        ));
    }
    if let Some(d) = args.subsurface {
        if !(d.is_finite() && d > 0.0) {
            return Err(CliError::Spec(format!(
                "--subsurface must be a depth > 0 in m, got {d}"
            )));
        }
    }
    let inhomogeneities = args
        .inhomogeneities
        .iter()
        .map(|s| parse_inhomogeneity(s, "--inhomogeneity"))
        .collect::<Result<Vec<_>, _>>()?;
    if !(args.tol.is_finite() && args.tol > 0.0 && args.tol < 1e-2) {
        return Err(CliError::Spec(format!(
            "--tol must be in (0, 1e-2), got {}",
            args.tol
        )));
    }
    if let Some(path) = &args.out {
        halfspace::data::Format::of(path)?;
    }
    let case = ContactCase {
        indenter: indenter.clone(),
        indenter_body: tool,
        half_space: half,
        load,
        tangential: match (args.shift_x, args.tangential_force) {
            (Some(dx), _) => Some(TangentialLoad::Shift(dx)),
            (None, Some(q)) => Some(TangentialLoad::Force(q)),
            (None, None) => None,
        },
        friction,
        grid: args.grid,
        extent: args.extent,
        tolerance: args.tol,
        inhomogeneities,
        subsurface_depth: args.subsurface,
    };
    let outcome = solve_contact(&case).map_err(|e| match e {
        SamError::InvalidInput(m) if m.contains("height table") => CliError::Spec(format!(
            "--indenter '{}': {m} (--grid, --extent)",
            args.indenter
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
        let hertz = match indenter {
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
