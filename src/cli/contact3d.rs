//! `halfspace contact3d`: 3D semi-analytical contact (docs/theory-sam.md), one normal and one tangential
//! increment, with or without inhomogeneities.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use halfspace::config::{InhomogeneityEntry, Names};
use halfspace::contact3d::Contact3dConfig;
use halfspace::data::write_record;
use halfspace::records::{contact_record, contact_summary, VOLUME_FIELDS};
use halfspace::sam::drivers::one_contact::{solve_contact, ContactOutcome};
use halfspace::sam::subsurface::StressField;
use halfspace::sam::SamError;
use serde_json::json;

use halfspace::figures::contact3d::contact_figures;
use halfspace::figures::draw::check_extension;

use super::CliError;

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
        check_extension(path, "--plot", &["svg", "png"])?;
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
        ..
    } = &outcome;
    let state = solver.problem().state();
    let seconds = start.elapsed().as_secs_f64();
    if let Some(path) = &args.plot {
        contact_figures(path, &case, &outcome)?;
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
