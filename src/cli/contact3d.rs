//! `halfspace contact3d` and `halfspace fretting-loop`: 3D semi-analytical contact (spec `sam.md`).

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use halfspace::data::{read_npy_2d, read_record, write_record, AttrValue, Record};
use halfspace::sam::coupled::{ContactParams, ContactProblem, ContactState, IncrementInfo};
use halfspace::sam::eim::{
    composite_fibres, FibreLayout, Inhomogeneity, COMPOSITE_CELLS_PER_RADIUS,
    COMPOSITE_FIBRE_RADIUS,
};
use halfspace::sam::nested::{InhomogeneousContact, NestedInfo, NestedParams};
use halfspace::sam::normal::{NormalLoad, NormalParams};
use halfspace::sam::subsurface::{subsurface_stress, StressField};
use halfspace::sam::tangential::TangentialParams;
use halfspace::sam::{Body, Compliance, SurfaceGrid};
use serde::Deserialize;
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
    #[arg(long, allow_negative_numbers = true)]
    force: Option<f64>,
    /// Rigid approach δ in m.
    #[arg(long, allow_negative_numbers = true)]
    depth: Option<f64>,
    /// Rigid tangential shift along x in m (after the normal load).
    #[arg(
        long,
        allow_negative_numbers = true,
        conflicts_with = "tangential_force"
    )]
    shift_x: Option<f64>,
    /// Tangential force along x in N (after the normal load).
    #[arg(long, allow_negative_numbers = true)]
    tangential_force: Option<f64>,
    /// Coulomb friction coefficient μ (default 0: frictionless, as in other contact codes; a
    /// tangential load needs it).
    #[arg(long, allow_negative_numbers = true)]
    friction: Option<f64>,
    /// Inhomogeneity below the surface (repeatable): sphere:x=..,y=..,z=..,r=..,E=..,nu=.. |
    /// cylinder:axis=y,x=..,z=..,r=..,E=..,nu=.. (or axis=x,y=..) |
    /// cuboid:x=..,y=..,z=..,hx=..,hy=..,hz=..,E=..,nu=..; z = depth of the centre (m).
    #[arg(long = "inhomogeneity")]
    inhomogeneities: Vec<String>,
    /// Compute the stress field below the surface down to DEPTH (m).
    #[arg(long, allow_negative_numbers = true)]
    subsurface: Option<f64>,
    /// Cells per side.
    #[arg(long, default_value_t = 128)]
    grid: usize,
    /// Side of the square domain in m (default: 4 estimated contact radii).
    #[arg(long, allow_negative_numbers = true)]
    extent: Option<f64>,
    /// Relative tolerance of the normal and tangential solvers.
    #[arg(long, default_value_t = 1e-10, allow_negative_numbers = true)]
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

enum Indenter {
    Ellipsoid(f64, f64),
    Cone(f64),
    Flat(f64),
    Table(PathBuf),
}

fn keys(spec: &str, what: &str) -> Result<(String, Vec<(String, f64)>), CliError> {
    let (kind, rest) = spec
        .split_once(':')
        .ok_or_else(|| CliError::Spec(format!("{what} '{spec}': expected KIND:KEY=VALUE,...")))?;
    if kind == "table" {
        return Ok((kind.into(), vec![]));
    }
    let mut out = Vec::new();
    for item in rest.split(',').filter(|s| !s.is_empty()) {
        let (k, v) = item
            .split_once('=')
            .ok_or_else(|| CliError::Spec(format!("{what} '{spec}': '{item}' is not KEY=VALUE")))?;
        let v: f64 = v
            .trim()
            .parse()
            .map_err(|_| CliError::Spec(format!("{what} '{spec}': {k}='{v}' is not a number")))?;
        out.push((k.trim().to_string(), v));
    }
    Ok((kind.to_string(), out))
}

fn take(
    spec: &str,
    what: &str,
    pairs: &mut Vec<(String, f64)>,
    key: &str,
) -> Result<f64, CliError> {
    let i = pairs
        .iter()
        .position(|(k, _)| k == key)
        .ok_or_else(|| CliError::Spec(format!("{what} '{spec}': missing key '{key}'")))?;
    let v = pairs.remove(i).1;
    if !(v.is_finite() && v > 0.0) {
        return Err(CliError::Spec(format!(
            "{what} '{spec}': {key} must be finite and > 0, got {v}"
        )));
    }
    Ok(v)
}

fn done(spec: &str, what: &str, pairs: &[(String, f64)]) -> Result<(), CliError> {
    match pairs.first() {
        None => Ok(()),
        Some((k, _)) => Err(CliError::Spec(format!(
            "{what} '{spec}': unknown key '{k}'"
        ))),
    }
}

fn parse_indenter(spec: &str) -> Result<Indenter, CliError> {
    let what = "--indenter";
    let (kind, mut p) = keys(spec, what)?;
    let ind = match kind.as_str() {
        "sphere" => {
            let r = take(spec, what, &mut p, "R")?;
            Indenter::Ellipsoid(r, r)
        }
        "ellipsoid" => Indenter::Ellipsoid(
            take(spec, what, &mut p, "Rx")?,
            take(spec, what, &mut p, "Ry")?,
        ),
        "cone" => Indenter::Cone(take(spec, what, &mut p, "slope")?),
        "flat" => Indenter::Flat(take(spec, what, &mut p, "a")?),
        "table" => Indenter::Table(PathBuf::from(
            spec.split_once(':').map(|x| x.1).unwrap_or_default(),
        )),
        other => {
            return Err(CliError::Spec(format!(
                "{what} '{spec}': unknown indenter '{other}' (sphere, ellipsoid, cone, flat, table)"
            )))
        }
    };
    done(spec, what, &p)?;
    Ok(ind)
}

fn parse_body(spec: &str, what: &str) -> Result<Body, CliError> {
    if spec == "rigid" {
        return Ok(Body::Rigid);
    }
    let (kind, mut p) = keys(spec, what)?;
    if kind != "homogeneous" {
        return Err(CliError::Spec(format!(
            "{what} '{spec}': use homogeneous:E=..,nu=.. (or rigid)"
        )));
    }
    let e = take(spec, what, &mut p, "E")?;
    let i = p
        .iter()
        .position(|(k, _)| k == "nu")
        .ok_or_else(|| CliError::Spec(format!("{what} '{spec}': missing key 'nu'")))?;
    let nu = p.remove(i).1;
    done(spec, what, &p)?;
    Ok(Body::elastic(e, nu)?)
}

/// Estimated contact radius for the default domain.
fn estimate_radius(ind: &Indenter, e_star: f64, load: NormalLoad) -> Option<f64> {
    match (ind, load) {
        (Indenter::Ellipsoid(rx, ry), NormalLoad::Force(w)) => {
            Some((3.0 * w * (rx * ry).sqrt() / (4.0 * e_star)).cbrt())
        }
        (Indenter::Ellipsoid(rx, ry), NormalLoad::Approach(d)) => {
            Some((d * (rx * ry).sqrt()).sqrt())
        }
        (Indenter::Cone(s), NormalLoad::Force(w)) => {
            Some((2.0 * w / (std::f64::consts::PI * e_star * s)).sqrt())
        }
        (Indenter::Cone(s), NormalLoad::Approach(d)) => Some(2.0 * d / (std::f64::consts::PI * s)),
        (Indenter::Flat(a), _) => Some(*a * 0.75),
        (Indenter::Table(_), _) => None,
    }
}

fn geometry(ind: &Indenter, grid: &SurfaceGrid) -> Result<Vec<f64>, CliError> {
    let n = grid.n1;
    if let Indenter::Table(path) = ind {
        let (rows, cols, v) = read_npy_2d(path)?;
        if rows != grid.n1 || cols != grid.n2 {
            return Err(CliError::Spec(format!(
                "{}: height table has shape ({rows}, {cols}); the grid is ({n}, {n}) (--grid)",
                path.display()
            )));
        }
        if let Some(bad) = v.iter().find(|x| !x.is_finite()) {
            return Err(CliError::Spec(format!(
                "{}: non-finite height {bad}",
                path.display()
            )));
        }
        return Ok(v);
    }
    let wall = 1e3 * 2.0 * grid.half1 * n as f64;
    Ok((0..grid.len())
        .map(|k| {
            let (x, y) = grid.centre(k / grid.n2, k % grid.n2);
            match ind {
                Indenter::Ellipsoid(rx, ry) => x * x / (2.0 * rx) + y * y / (2.0 * ry),
                Indenter::Cone(s) => s * (x * x + y * y).sqrt(),
                Indenter::Flat(a) => {
                    if x * x + y * y <= a * a {
                        0.0
                    } else {
                        wall
                    }
                }
                Indenter::Table(_) => unreachable!(),
            }
        })
        .collect())
}

pub fn run(args: Contact3dArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let indenter = parse_indenter(&args.indenter)?;
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
        .map(|s| super::spec::parse_inhomogeneity(s))
        .collect::<Result<Vec<_>, _>>()?;
    if !inhomogeneities.is_empty() && args.tangential_force.is_some() {
        return Err(CliError::Spec(
            "--tangential-force with --inhomogeneity is not available yet (use --shift-x)".into(),
        ));
    }
    if !(args.tol.is_finite() && args.tol > 0.0 && args.tol < 1e-2) {
        return Err(CliError::Spec(format!(
            "--tol must be in (0, 1e-2), got {}",
            args.tol
        )));
    }
    if let Some(path) = &args.out {
        halfspace::data::Format::of(path)?;
    }
    let e_star = 1.0 / (tool.normal_term() + half.normal_term());
    let extent = match (args.extent, estimate_radius(&indenter, e_star, load)) {
        (Some(x), _) => x,
        (None, Some(a)) => 4.0 * a,
        (None, None) => {
            return Err(CliError::Spec(
                "--indenter table: give --extent (the side of the grid in m)".into(),
            ))
        }
    };
    // A grid of any size is accepted; FFT sizes need no padding to powers of two (5-smooth is fastest).
    let grid = SurfaceGrid::square(args.grid, extent)?;
    let compliance = Compliance::pair(tool, half)?;
    // Before the first field is allocated: a grid that cannot fit is refused with the estimate.
    halfspace::sam::memory::check_problem(
        &grid,
        friction > 0.0,
        friction > 0.0 && compliance.coupling != 0.0,
    )?;
    let geometry = geometry(&indenter, &grid)?;
    let params = ContactParams {
        friction,
        normal: NormalParams {
            tolerance: args.tol,
            ..NormalParams::default()
        },
        tangential: TangentialParams {
            tolerance: args.tol,
            ..TangentialParams::default()
        },
        ..ContactParams::default()
    };
    let problem = ContactProblem::new(grid, compliance, geometry, params)?;
    let (e_half, nu_half) = match half {
        Body::Elastic { e, nu } => (e, nu),
        Body::Rigid => unreachable!("checked above"),
    };
    let mut solver = if inhomogeneities.is_empty() {
        Solver::Plain(Box::new(problem))
    } else {
        Solver::Nested(Box::new(InhomogeneousContact::new(
            problem,
            e_half,
            nu_half,
            &inhomogeneities,
            NestedParams::default(),
        )?))
    };
    let setup_seconds = start.elapsed().as_secs_f64();
    let solve_start = Instant::now();
    let mut nested_info = None;
    let mut info = solver.increment(load, [0.0, 0.0], &mut nested_info)?;
    let mut iterations = info.normal.iterations + info.tangential.iterations;
    let mut shift = 0.0;
    if let Some(dx) = args.shift_x {
        info = solver.increment(load, [dx, 0.0], &mut nested_info)?;
        iterations += info.normal.iterations + info.tangential.iterations;
        shift = dx;
    } else if let Some(qx) = args.tangential_force {
        let Solver::Plain(problem) = &mut solver else {
            unreachable!("refused above")
        };
        let bracket = 0.05 * extent * 1e-3;
        let (i, d) = problem.increment_with_force(load, qx, bracket)?;
        info = i;
        iterations += info.normal.iterations + info.tangential.iterations;
        shift = d;
    }
    let solve_seconds = solve_start.elapsed().as_secs_f64();
    let problem = solver.problem();
    let subsurface_start = Instant::now();
    let field = match args.subsurface {
        None => None,
        Some(depth) => {
            let st = problem.state();
            let q = (friction > 0.0).then(|| [st.shear[0].as_slice(), st.shear[1].as_slice()]);
            let inclusions = match &solver {
                Solver::Nested(n) => Some((n.inclusions(), n.eigenstrain())),
                Solver::Plain(_) => None,
            };
            Some(subsurface_stress(
                problem.grid(),
                e_half,
                nu_half,
                &st.pressure,
                q,
                depth,
                inclusions,
            )?)
        }
    };
    let subsurface_seconds = subsurface_start.elapsed().as_secs_f64();
    let state = problem.state();
    let seconds = start.elapsed().as_secs_f64();
    let mut summary = json!({
        "contact_radius": (info.contact_area / std::f64::consts::PI).sqrt(),
        "contact_area": info.contact_area,
        "max_pressure": info.max_pressure,
        "force": state.force,
        "depth": state.approach,
        "tangential_force": info.tangential_force[0],
        "tangential_force_y": info.tangential_force[1],
        "shift_x": shift,
        "stick_radius": (info.stick_area / std::f64::consts::PI).sqrt(),
        "iterations": iterations,
        "alternations": info.alternations,
        "residual": info.normal.residual.max(info.tangential.residual),
        "kkt": info.tangential.kkt,
        "grid": args.grid,
        "extent": extent,
        "coupled": problem.is_coupled(),
        "seconds": seconds,
        "setup_seconds": setup_seconds,
        "solve_seconds": solve_seconds,
        "friction": friction,
    });
    let extra = summary.as_object_mut().expect("object");
    if let (Solver::Nested(n), Some(ni)) = (&solver, &nested_info) {
        extra.insert("inclusion_cells".into(), json!(n.inclusions().len()));
        extra.insert("layers".into(), json!(n.inclusions().layers.len()));
        extra.insert("eim_iterations".into(), json!(ni.eim_iterations));
        extra.insert("outer_iterations".into(), json!(ni.outer_iterations));
        extra.insert("outer_change".into(), json!(ni.change));
        extra.insert(
            "min_eigen_displacement".into(),
            json!(ni.min_eigen_displacement),
        );
        // Spec §8.5b: A Σ p_c should vanish; its size relative to W measures the truncation of p_c
        // by the domain (enlarge --extent when it is not small).
        let pc: f64 = n.correction_pressure().iter().sum::<f64>() * problem.grid().cell_area();
        extra.insert(
            "correction_pressure_integral_over_force".into(),
            json!(pc / state.force),
        );
        extra.insert(
            "eim_method".into(),
            json!(format!("{:?}", ni.last_eim.method)),
        );
    }
    if let Solver::Nested(n) = &solver {
        extra.insert("eim_spectra_bytes".into(), json!(n.spectra_bytes()));
    }
    if let Some(f) = &field {
        let (vm, vm_at) = f.maximum(&f.von_mises);
        let (tr, tr_at) = f.maximum(&f.tresca);
        extra.insert("max_von_mises".into(), json!(vm));
        extra.insert("max_von_mises_at".into(), json!(vm_at));
        extra.insert("max_tresca".into(), json!(tr));
        extra.insert("max_tresca_at".into(), json!(tr_at));
        extra.insert("subsurface_layers".into(), json!(f.layers));
        extra.insert("subsurface_seconds".into(), json!(subsurface_seconds));
    }
    let problem = solver.problem();
    if let Some(path) = &args.plot {
        let hertz = match indenter {
            Indenter::Ellipsoid(rx, ry) if rx == ry => Some((rx, state.force, e_star)),
            _ => None,
        };
        draw_figures(path, &solver, field.as_ref(), hertz)?;
    }
    if let Some(path) = &args.out {
        let mut rec = fields_record(problem, &summary);
        if let Some(f) = &field {
            rec = volume_record(rec, f, &solver);
        }
        write_record(path, &rec)?;
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

/// The contact solver: plain, or nested with the EIM when there are inhomogeneities.
enum Solver {
    Plain(Box<ContactProblem>),
    Nested(Box<InhomogeneousContact>),
}

impl Solver {
    fn increment(
        &mut self,
        load: NormalLoad,
        shift: [f64; 2],
        nested_info: &mut Option<NestedInfo>,
    ) -> Result<IncrementInfo, CliError> {
        Ok(match self {
            Solver::Plain(p) => p.increment(load, shift)?,
            Solver::Nested(n) => {
                let info = n.increment(load, shift)?;
                *nested_info = Some(info);
                info.contact
            }
        })
    }

    fn problem(&self) -> &ContactProblem {
        match self {
            Solver::Plain(p) => p,
            Solver::Nested(n) => n.problem(),
        }
    }
}

/// The pressure (and `u₃^eig`) along x through the centre, with Hertz's pressure for a sphere
/// (`hertz = (R, W, E*)`), and the von Mises map in the x–z plane through the centre.
fn draw_figures(
    path: &std::path::Path,
    solver: &Solver,
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
        let a = (3.0 * w * r / (4.0 * e_star)).cbrt();
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
    let right: Vec<(String, Vec<(f64, f64)>)> = match solver {
        Solver::Nested(n) => vec![(
            "eigen-displacement u3 (nm)".to_string(),
            xs.iter()
                .enumerate()
                .map(|(i, x)| (x * 1e6, n.eigen_displacements()[2][i * g.n2 + col] * 1e9))
                .collect(),
        )],
        Solver::Plain(_) => vec![],
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

/// Names of the volume datasets (shape `(layers, N₁, N₂)`).
const VOLUME_FIELDS: [&str; 14] = [
    "stress_xx",
    "stress_yy",
    "stress_zz",
    "stress_yz",
    "stress_xz",
    "stress_xy",
    "von_mises",
    "tresca",
    "principal_1",
    "principal_2",
    "principal_3",
    "material",
    "eigenstrain_xx",
    "eigenstrain_zz",
];

/// Adds the subsurface fields (and the eigenstrains on the same lattice) with their shape.
fn volume_record(mut rec: Record, f: &StressField, solver: &Solver) -> Record {
    let shape = [f.layers, f.grid.n1, f.grid.n2];
    for (o, name) in VOLUME_FIELDS[..6].iter().enumerate() {
        rec = rec.shaped(name, f.stress[o].clone(), &shape);
    }
    rec = rec.shaped("von_mises", f.von_mises.clone(), &shape).shaped(
        "tresca",
        f.tresca.clone(),
        &shape,
    );
    for (o, name) in VOLUME_FIELDS[8..11].iter().enumerate() {
        rec = rec.shaped(name, f.principal[o].clone(), &shape);
    }
    rec = rec.shaped(
        "material",
        f.material.iter().map(|&m| f64::from(m)).collect(),
        &shape,
    );
    let n = f.grid.len();
    let mut eig: [Vec<f64>; 6] = std::array::from_fn(|_| vec![0.0; f.layers * n]);
    if let Solver::Nested(nested) = solver {
        let set = nested.inclusions();
        for (c, cell) in set.cells.iter().enumerate() {
            let k = set.layers[cell.layer];
            if k < f.layers {
                for (o, field) in eig.iter_mut().enumerate() {
                    field[k * n + cell.flat] = nested.eigenstrain()[c * 6 + o];
                }
            }
        }
    }
    for (o, name) in [
        "eigenstrain_xx",
        "eigenstrain_yy",
        "eigenstrain_zz",
        "eigenstrain_yz",
        "eigenstrain_xz",
        "eigenstrain_xy",
    ]
    .iter()
    .enumerate()
    {
        rec = rec.shaped(name, std::mem::take(&mut eig[o]), &shape);
    }
    rec.attr(
        "volume_layout",
        AttrValue::Text(format!(
            "volume fields of shape (layers, N1, N2) = ({}, {}, {}): layer k at depth (2k+1)Δ = {:e}·(2k+1) m, cell (i, j) at the surface cell centres (x index i slow)",
            f.layers, f.grid.n1, f.grid.n2, f.grid.half1
        )),
    )
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
    let mut names: Vec<&str> = VOLUME_FIELDS[..12].to_vec();
    names.extend([
        "eigenstrain_xx",
        "eigenstrain_yy",
        "eigenstrain_zz",
        "eigenstrain_yz",
        "eigenstrain_xz",
        "eigenstrain_xy",
    ]);
    halfspace::data::write_xdmf(
        &h5.with_extension("xdmf"),
        h5,
        &volume,
        &names,
        "halfspace contact3d volume fields; XDMF axes Z Y X = depth (into the body), x, y (m)",
    )?;
    Ok(())
}

fn fields_record(problem: &ContactProblem, summary: &serde_json::Value) -> Record {
    let g = problem.grid();
    let s = problem.state();
    let (x, y): (Vec<f64>, Vec<f64>) = (0..g.len()).map(|k| g.centre(k / g.n2, k % g.n2)).unzip();
    // Without friction the problem holds no tangential fields: q = 0, no stick; the slip of a
    // frictionless increment is not tracked (written as zeros).
    let frictional = !s.shear[0].is_empty();
    let or_zeros = |v: &Vec<f64>| {
        if frictional {
            v.clone()
        } else {
            vec![0.0; g.len()]
        }
    };
    let stick = (0..g.len())
        .map(|k| {
            f64::from(u8::from(
                frictional
                    && halfspace::sam::tangential::is_stick(
                        problem.friction() * s.pressure[k],
                        s.shear[0][k],
                        s.shear[1][k],
                    ),
            ))
        })
        .collect();
    let mut rec = Record::default()
        .array("x", x)
        .array("y", y)
        .array("pressure", s.pressure.clone())
        .array("shear_x", or_zeros(&s.shear[0]))
        .array("shear_y", or_zeros(&s.shear[1]))
        .array("slip_x", or_zeros(&s.slip[0]))
        .array("slip_y", or_zeros(&s.slip[1]))
        .array("stick", stick);
    for (k, v) in summary.as_object().expect("object") {
        let value = match v {
            serde_json::Value::Number(n) if n.is_i64() || n.is_u64() => {
                AttrValue::Int(n.as_i64().unwrap_or_default())
            }
            serde_json::Value::Number(n) => AttrValue::Float(n.as_f64().unwrap_or(f64::NAN)),
            other => AttrValue::Text(other.to_string()),
        };
        rec = rec.attr(k, value);
    }
    rec.attr(
        "layout",
        AttrValue::Text(format!(
            "{} × {} cells, row-major (x index slow)",
            g.n1, g.n2
        )),
    )
}

#[derive(Debug, Args)]
pub struct FrettingLoopArgs {
    /// TOML file with any of: radius, e, nu, friction, force, normal_steps, amplitude, shift_step, grid, extent_over_a.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Output directory (results.h5, fretting_loop.png/.svg, fretting_profiles.svg).
    #[arg(long, default_value = "fretting-loop-out")]
    out: PathBuf,
    /// Cells per side (overrides the config).
    #[arg(long)]
    grid: Option<usize>,
    /// Preset: `homogeneous` ([LN11]'s homogeneous half-space, the default) or `composite` (its
    /// unidirectional composite: fibres along y, r = 0.13a, spacing 3r, axes at depth 1.5r,
    /// E_I = 2E_m (config `fibre_e_ratio`), ν_I = ν_m, 4 cells per fibre radius; config `layout`).
    #[arg(long, default_value = "homogeneous")]
    case: String,
    /// Continue a killed run from OUT/checkpoint.npz (the same configuration), bit for bit.
    #[arg(long)]
    resume: bool,
    /// Seconds of work between checkpoints (written atomically to OUT/checkpoint.npz; removed when
    /// the loop completes).
    #[arg(long, default_value_t = 5.0)]
    checkpoint_seconds: f64,
    /// Testing hook: stop (as if killed) after this many increments, leaving the checkpoint.
    #[arg(long, hide = true)]
    stop_after: Option<usize>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
}

/// One increment of the loop as stored in the results and the checkpoint.
#[derive(Debug, Clone, Copy, PartialEq)]
struct LoopRow {
    w: f64,
    d: f64,
    q: [f64; 2],
    max_pressure: f64,
    contact_area: f64,
    stick_area: f64,
    alternations: f64,
    approach: f64,
}

impl LoopRow {
    fn of(w: f64, d: f64, info: &IncrementInfo) -> Self {
        Self {
            w,
            d,
            q: info.tangential_force,
            max_pressure: info.max_pressure,
            contact_area: info.contact_area,
            stick_area: info.stick_area,
            alternations: info.alternations as f64,
            approach: info.normal.approach,
        }
    }

    /// (array name, field) pairs of the results file.
    const FIELDS: [&'static str; 9] = [
        "normal_force",
        "shift_x",
        "tangential_force",
        "tangential_force_y",
        "max_pressure",
        "contact_area",
        "stick_area",
        "alternations",
        "approach",
    ];

    fn values(&self) -> [f64; 9] {
        [
            self.w,
            self.d,
            self.q[0],
            self.q[1],
            self.max_pressure,
            self.contact_area,
            self.stick_area,
            self.alternations,
            self.approach,
        ]
    }

    fn from_values(v: [f64; 9]) -> Self {
        Self {
            w: v[0],
            d: v[1],
            q: [v[2], v[3]],
            max_pressure: v[4],
            contact_area: v[5],
            stick_area: v[6],
            alternations: v[7],
            approach: v[8],
        }
    }
}

/// The rows as named arrays.
fn rows_record(mut rec: Record, rows: &[LoopRow]) -> Record {
    for (f, name) in LoopRow::FIELDS.iter().enumerate() {
        rec = rec.array(name, rows.iter().map(|r| r.values()[f]).collect());
    }
    rec
}

/// Everything an interrupted loop needs to continue bit for bit: the next increment, the rows so
/// far, the profiles at A–D so far, the contact state and (with inhomogeneities) the eigenstrains
/// and eigen-displacements; the configuration as text, to refuse a resume with another one.
fn loop_checkpoint(
    fingerprint: &str,
    next: usize,
    rows: &[LoopRow],
    profiles: &[Profiles],
    max_transverse_slip: f64,
    solver: &Solver,
) -> Record {
    let st = solver.problem().state();
    let mut rec = rows_record(Record::default(), rows)
        .attr("config", AttrValue::Text(fingerprint.into()))
        .attr("next", AttrValue::Int(next as i64))
        .attr("max_transverse_slip", AttrValue::Float(max_transverse_slip))
        .attr("profiles", AttrValue::Int(profiles.len() as i64))
        .array("state_pressure", st.pressure.clone())
        .array("state_shear_x", st.shear[0].clone())
        .array("state_shear_y", st.shear[1].clone())
        .array("state_history_x", st.tangential_displacement[0].clone())
        .array("state_history_y", st.tangential_displacement[1].clone())
        .array("state_slip_x", st.slip[0].clone())
        .array("state_slip_y", st.slip[1].clone())
        .array(
            "state_scalars",
            vec![st.shift[0], st.shift[1], st.approach, st.force],
        );
    for (label, px, qx, py) in profiles {
        rec = rec
            .array(&format!("profile_{label}_px"), px.clone())
            .array(&format!("profile_{label}_qx"), qx.clone())
            .array(&format!("profile_{label}_py"), py.clone());
    }
    if let Solver::Nested(n) = solver {
        let u = n.eigen_displacements();
        rec = rec
            .array("eigenstrain", n.eigenstrain().to_vec())
            .array("eigen_displacement_1", u[0].clone())
            .array("eigen_displacement_2", u[1].clone())
            .array("eigen_displacement_3", u[2].clone());
    }
    rec
}

/// The state of [`loop_checkpoint`], restored into `solver`: (next, rows, profiles, max s₂).
fn restore_loop(
    path: &std::path::Path,
    fingerprint: &str,
    solver: &mut Solver,
) -> Result<(usize, Vec<LoopRow>, Vec<Profiles>, f64), CliError> {
    let rec = read_record(path)?;
    let bad = |what: String| CliError::Spec(format!("--resume {}: {what}", path.display()));
    match rec.get_attr("config") {
        Some(AttrValue::Text(t)) if t == fingerprint => {}
        _ => {
            return Err(bad(
                "the checkpoint was made with another configuration; resume with the same                  --config, --case and --grid (or remove it to start over)"
                    .into(),
            ))
        }
    }
    let int = |name: &str| match rec.get_attr(name) {
        Some(AttrValue::Int(v)) if *v >= 0 => Ok(*v as usize),
        other => Err(bad(format!("attribute {name} is {other:?}"))),
    };
    let array = |name: &str| {
        rec.get(name)
            .map(|v| v.to_vec())
            .ok_or_else(|| bad(format!("array {name} is missing")))
    };
    let next = int("next")?;
    let columns = LoopRow::FIELDS
        .iter()
        .map(|f| array(f))
        .collect::<Result<Vec<_>, _>>()?;
    if columns.iter().any(|c| c.len() != next) {
        return Err(bad("the rows do not match the next increment".into()));
    }
    let rows = (0..next)
        .map(|k| {
            let mut v = [0.0; 9];
            for (f, c) in columns.iter().enumerate() {
                v[f] = c[k];
            }
            LoopRow::from_values(v)
        })
        .collect();
    let mut profiles = Vec::new();
    for label in ["A", "B", "C", "D"].iter().take(int("profiles")?) {
        profiles.push((
            label.to_string(),
            array(&format!("profile_{label}_px"))?,
            array(&format!("profile_{label}_qx"))?,
            array(&format!("profile_{label}_py"))?,
        ));
    }
    let scalars = array("state_scalars")?;
    if scalars.len() != 4 {
        return Err(bad("state_scalars must hold 4 values".into()));
    }
    let state = ContactState {
        pressure: array("state_pressure")?,
        shear: [array("state_shear_x")?, array("state_shear_y")?],
        tangential_displacement: [array("state_history_x")?, array("state_history_y")?],
        slip: [array("state_slip_x")?, array("state_slip_y")?],
        shift: [scalars[0], scalars[1]],
        approach: scalars[2],
        force: scalars[3],
    };
    match solver {
        Solver::Plain(p) => p.restore_state(&state)?,
        Solver::Nested(n) => {
            n.problem_mut().restore_state(&state)?;
            let (u1, u2, u3) = (
                array("eigen_displacement_1")?,
                array("eigen_displacement_2")?,
                array("eigen_displacement_3")?,
            );
            n.restore(&array("eigenstrain")?, [&u1, &u2, &u3])?;
        }
    }
    let max_s2 = match rec.get_attr("max_transverse_slip") {
        Some(AttrValue::Float(v)) => *v,
        other => return Err(bad(format!("max_transverse_slip is {other:?}"))),
    };
    Ok((next, rows, profiles, max_s2))
}

/// The fretting-loop case (defaults: [LN11]'s homogeneous case).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
struct LoopConfig {
    radius: f64,
    e: f64,
    nu: f64,
    friction: f64,
    force: f64,
    normal_steps: usize,
    amplitude: f64,
    shift_step: f64,
    grid: usize,
    extent_over_a: f64,
    /// `[[inhomogeneity]]` tables: `kind = "sphere" | "cylinder" | "cuboid"` and the keys of the
    /// CLI's `--inhomogeneity` specs (`x, y, z, r, axis, hx, hy, hz, e, nu`).
    inhomogeneity: Vec<toml::Table>,
    /// Composite preset: `"fibre-centred"` (a fibre axis at x = 0) or `"gap-centred"`.
    layout: String,
    /// Composite preset: E_I / E_m of the fibres (2 in [LN11]; 0.5 for soft fibres).
    fibre_e_ratio: f64,
}

impl Default for LoopConfig {
    fn default() -> Self {
        Self {
            radius: 105e-6,
            e: 210e9,
            nu: 0.3,
            friction: 0.3,
            force: 0.08,
            normal_steps: 80,
            amplitude: 0.04e-6,
            shift_step: 0.002e-6,
            grid: 64,
            extent_over_a: 4.16,
            inhomogeneity: Vec::new(),
            layout: "fibre-centred".into(),
            fibre_e_ratio: 2.0,
        }
    }
}

/// One `[[inhomogeneity]]` table as the CLI's `kind:key=value,...` spec (one parser for both; the
/// TOML key `e` is the spec's `E`).
fn inhomogeneity_from_table(table: &toml::Table) -> Result<Inhomogeneity, CliError> {
    let kind = table
        .get("kind")
        .and_then(|v| v.as_str())
        .ok_or_else(|| {
            CliError::Spec(
                "fretting-loop: every [[inhomogeneity]] needs kind = \"sphere\" | \"cylinder\" | \"cuboid\""
                    .into(),
            )
        })?;
    let mut pairs = Vec::new();
    for (key, value) in table.iter().filter(|(k, _)| k.as_str() != "kind") {
        let text = match value {
            toml::Value::Float(v) => format!("{v:e}"),
            toml::Value::Integer(v) => v.to_string(),
            toml::Value::String(v) => v.clone(),
            other => {
                return Err(CliError::Spec(format!(
                    "fretting-loop: [[inhomogeneity]] {key} = {other}: a number (or x/y for axis)"
                )))
            }
        };
        let key = if key == "e" { "E" } else { key.as_str() };
        pairs.push(format!("{key}={text}"));
    }
    super::spec::parse_inhomogeneity(&format!("{kind}:{}", pairs.join(",")))
}

/// (label, pressure along x, shear q_x along x, pressure along y) at one of the points A–D.
type Profiles = (String, Vec<f64>, Vec<f64>, Vec<f64>);

pub fn run_loop(args: FrettingLoopArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let mut cfg: LoopConfig = super::read_config(args.config.as_deref())?;
    let composite = match args.case.as_str() {
        "homogeneous" => false,
        "composite" => true,
        other => {
            return Err(CliError::Spec(format!(
                "--case '{other}': homogeneous or composite"
            )))
        }
    };
    if composite {
        // [LN11]: 4 cells per fibre radius r = 0.13a over the domain (128² at 4.16a).
        let cell = COMPOSITE_FIBRE_RADIUS / COMPOSITE_CELLS_PER_RADIUS;
        cfg.grid = (cfg.extent_over_a / cell).round() as usize;
    }
    if let Some(g) = args.grid {
        cfg.grid = g;
    }
    for (name, v) in [
        ("radius", cfg.radius),
        ("force", cfg.force),
        ("amplitude", cfg.amplitude),
        ("shift_step", cfg.shift_step),
        ("extent_over_a", cfg.extent_over_a),
        ("friction", cfg.friction),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(CliError::Spec(format!(
                "fretting-loop: {name} must be finite and > 0, got {v}"
            )));
        }
    }
    if cfg.normal_steps == 0 {
        return Err(CliError::Spec(
            "fretting-loop: normal_steps must be ≥ 1".into(),
        ));
    }
    let half = Body::elastic(cfg.e, cfg.nu)?;
    let e_star = cfg.e / (1.0 - cfg.nu * cfg.nu);
    let a = (3.0 * cfg.force * cfg.radius / (4.0 * e_star)).cbrt();
    let grid = SurfaceGrid::square(cfg.grid, cfg.extent_over_a * a)?;
    halfspace::sam::memory::check_problem(&grid, true, false)?;
    let geometry: Vec<f64> = (0..grid.len())
        .map(|k| {
            let (x, y) = grid.centre(k / grid.n2, k % grid.n2);
            (x * x + y * y) / (2.0 * cfg.radius)
        })
        .collect();
    let reference_geometry = geometry.clone();
    let compliance = Compliance::pair(Body::Rigid, half)?;
    let params = ContactParams {
        friction: cfg.friction,
        ..ContactParams::default()
    };
    let problem = ContactProblem::new(grid, compliance, geometry, params)?;
    let mut inhomogeneities = cfg
        .inhomogeneity
        .iter()
        .map(inhomogeneity_from_table)
        .collect::<Result<Vec<_>, _>>()?;
    if composite {
        let layout = match cfg.layout.as_str() {
            "fibre-centred" => FibreLayout::FibreCentred,
            "gap-centred" => FibreLayout::GapCentred,
            other => {
                return Err(CliError::Spec(format!(
                    "fretting-loop: layout = '{other}': fibre-centred or gap-centred"
                )))
            }
        };
        inhomogeneities.extend(composite_fibres(
            a,
            0.5 * cfg.extent_over_a * a,
            layout,
            cfg.e,
            cfg.nu,
            cfg.fibre_e_ratio,
        )?);
    }
    let mut solver = if inhomogeneities.is_empty() {
        Solver::Plain(Box::new(problem))
    } else {
        Solver::Nested(Box::new(InhomogeneousContact::new(
            problem,
            cfg.e,
            cfg.nu,
            &inhomogeneities,
            NestedParams::default(),
        )?))
    };
    let mut nested_info = None;
    if !(args.checkpoint_seconds.is_finite() && args.checkpoint_seconds > 0.0) {
        return Err(CliError::Spec(format!(
            "--checkpoint-seconds must be finite and > 0, got {}",
            args.checkpoint_seconds
        )));
    }
    std::fs::create_dir_all(&args.out)
        .map_err(|e| CliError::Spec(format!("--out {}: {e}", args.out.display())))?;
    let checkpoint = args.out.join("checkpoint.npz");
    if checkpoint.exists() && !args.resume {
        return Err(CliError::Spec(format!(
            "{} holds an interrupted run: --resume continues it (or remove it to start over)",
            checkpoint.display()
        )));
    }
    if args.resume && !checkpoint.exists() {
        return Err(CliError::Spec(format!(
            "--resume: {} has no checkpoint.npz",
            args.out.display()
        )));
    }
    let fingerprint = format!("{cfg:?} case={} grid={}", args.case, cfg.grid);
    // Path: W ramp at D = 0, then D: 0 → +A → −A → +A.
    let quarter = (cfg.amplitude / cfg.shift_step).round().max(1.0) as usize;
    let mut path: Vec<(f64, f64)> = (1..=cfg.normal_steps)
        .map(|i| (cfg.force * i as f64 / cfg.normal_steps as f64, 0.0))
        .collect();
    let dd = cfg.amplitude / quarter as f64;
    for i in 1..=quarter {
        path.push((cfg.force, i as f64 * dd));
    }
    for i in 1..=2 * quarter {
        path.push((cfg.force, cfg.amplitude - i as f64 * dd));
    }
    for i in 1..=2 * quarter {
        path.push((cfg.force, -cfg.amplitude + i as f64 * dd));
    }
    let bar = if std::io::stderr().is_terminal() && !args.json {
        let bar = indicatif::ProgressBar::new(path.len() as u64);
        Some(bar)
    } else {
        None
    };
    let (first, mut history, mut profiles, mut max_transverse_slip) = if args.resume {
        restore_loop(&checkpoint, &fingerprint, &mut solver)?
    } else {
        (0, Vec::new(), Vec::new(), 0.0f64)
    };
    let n = cfg.grid;
    let mid = n / 2;
    // Points A–D ([LN11] Fig. 6 style): end of normal loading; D = +A; D = 0 on unloading; D = −A.
    let marks = [
        cfg.normal_steps,
        cfg.normal_steps + quarter,
        cfg.normal_steps + 2 * quarter,
        cfg.normal_steps + 3 * quarter,
    ];
    if let Some(bar) = &bar {
        bar.set_position(first as u64);
    }
    let every = std::time::Duration::from_secs_f64(args.checkpoint_seconds);
    let mut last_checkpoint = Instant::now();
    for (k, (w, d)) in path.iter().enumerate().skip(first) {
        let info = match solver.increment(NormalLoad::Force(*w), [*d, 0.0], &mut nested_info) {
            Ok(info) => info,
            Err(e) => {
                // Keep what was done: the checkpoint holds the last converged increment.
                let rec = loop_checkpoint(
                    &fingerprint,
                    k,
                    &history,
                    &profiles,
                    max_transverse_slip,
                    &solver,
                );
                let _ = write_record(&checkpoint, &rec);
                return Err(e);
            }
        };
        history.push(LoopRow::of(*w, *d, &info));
        if let Some(bar) = &bar {
            bar.inc(1);
        }
        let s = solver.problem().state();
        max_transverse_slip = s.slip[1]
            .iter()
            .fold(max_transverse_slip, |m, v| m.max(v.abs()));
        if let Some(m) = marks.iter().position(|&s| s == k + 1) {
            let label = ["A", "B", "C", "D"][m].to_string();
            let along_x: Vec<f64> = (0..n).map(|i| s.pressure[i * n + mid]).collect();
            let shear_x: Vec<f64> = (0..n).map(|i| s.shear[0][i * n + mid]).collect();
            let along_y: Vec<f64> = (0..n).map(|j| s.pressure[mid * n + j]).collect();
            profiles.push((label, along_x, shear_x, along_y));
        }
        let stop = args.stop_after.is_some_and(|m| k + 1 >= m) && k + 1 < path.len();
        if stop || last_checkpoint.elapsed() >= every {
            let rec = loop_checkpoint(
                &fingerprint,
                k + 1,
                &history,
                &profiles,
                max_transverse_slip,
                &solver,
            );
            write_record(&checkpoint, &rec)?;
            last_checkpoint = Instant::now();
        }
        if stop {
            if let Some(bar) = &bar {
                bar.finish_and_clear();
            }
            return Ok(());
        }
    }
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    // With inhomogeneities: the homogeneous loop of the same configuration, for the comparison
    // ([LN11] Figs. 5–10 show both); cheap beside the nested loop.
    let reference = if matches!(solver, Solver::Nested(_)) {
        let mut plain = ContactProblem::new(grid, compliance, reference_geometry, params)?;
        let (mut rows, mut prof) = (Vec::new(), Vec::new());
        for (k, (w, d)) in path.iter().enumerate() {
            let info = plain.increment(NormalLoad::Force(*w), [*d, 0.0])?;
            rows.push(LoopRow::of(*w, *d, &info));
            if let Some(m) = marks.iter().position(|&s| s == k + 1) {
                let s = plain.state();
                prof.push((
                    ["A", "B", "C", "D"][m].to_string(),
                    (0..n).map(|i| s.pressure[i * n + mid]).collect(),
                    (0..n).map(|i| s.shear[0][i * n + mid]).collect(),
                    (0..n).map(|j| s.pressure[mid * n + j]).collect(),
                ));
            }
        }
        Some((rows, prof))
    } else {
        None
    };
    let mu_w = cfg.friction * cfg.force;
    let cycle_of = |rows: &[LoopRow]| -> Vec<(f64, f64)> {
        rows[cfg.normal_steps + quarter - 1..]
            .iter()
            .map(|r| (r.d, r.q[0]))
            .collect()
    };
    let energy_of = |cycle: &[(f64, f64)]| -> f64 {
        cycle
            .windows(2)
            .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
            .sum::<f64>()
            .abs()
    };
    let cycle = cycle_of(&history);
    let energy = energy_of(&cycle);
    let end_normal = &history[cfg.normal_steps - 1];
    let p0 = 3.0 * cfg.force / (2.0 * std::f64::consts::PI * a * a);
    let seconds = start.elapsed().as_secs_f64();
    let rec = {
        let mut r = rows_record(Record::default(), &history)
            .array("x", (0..n).map(|i| grid.centre(i, mid).0).collect());
        for (label, px, qx, py) in &profiles {
            r = r
                .array(&format!("pressure_x_{label}"), px.clone())
                .array(&format!("shear_x_{label}"), qx.clone())
                .array(&format!("pressure_y_{label}"), py.clone());
        }
        r.attr("radius", AttrValue::Float(cfg.radius))
            .attr("E", AttrValue::Float(cfg.e))
            .attr("nu", AttrValue::Float(cfg.nu))
            .attr("friction", AttrValue::Float(cfg.friction))
            .attr("force", AttrValue::Float(cfg.force))
            .attr("grid", AttrValue::Int(cfg.grid as i64))
            .attr("extent", AttrValue::Float(grid.half1 * 2.0 * n as f64))
            .attr("dissipated_energy", AttrValue::Float(energy))
            .attr(
                "points",
                AttrValue::Text(
                    "A: end of normal loading; B: D = +A; C: D = 0 unloading; D: D = −A".into(),
                ),
            )
    };
    write_record(&args.out.join("results.h5"), &rec)?;
    // Complete: the checkpoint is no longer needed (a re-run into the same directory starts over).
    if checkpoint.exists() {
        std::fs::remove_file(&checkpoint)
            .map_err(|e| CliError::Spec(format!("removing {}: {e}", checkpoint.display())))?;
    }
    let mut loop_curve: Vec<(String, Vec<(f64, f64)>)> = vec![(
        if reference.is_some() {
            "with the inhomogeneities".into()
        } else {
            "Q / μW against δx (μm)".into()
        },
        cycle.iter().map(|(d, q)| (d * 1e6, q / mu_w)).collect(),
    )];
    if let Some((rows, _)) = &reference {
        loop_curve.push((
            "homogeneous".into(),
            cycle_of(rows)
                .iter()
                .map(|(d, q)| (d * 1e6, q / mu_w))
                .collect(),
        ));
    }
    for ext in ["svg", "png"] {
        let p = args.out.join(format!("fretting_loop.{ext}"));
        plot::curves(
            &p,
            "Fretting loop (SAM, coupled): Q/μW against δx",
            "δx (μm)",
            ("Q / μW", &loop_curve),
            ("", &[]),
            false,
        )
        .map_err(|e| CliError::Plot(format!("{}: {e}", p.display())))?;
    }
    let x: Vec<f64> = (0..n).map(|i| grid.centre(i, mid).0 / a).collect();
    let mut pressure: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let mut shear: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let sets = std::iter::once(("", &profiles))
        .chain(reference.as_ref().map(|(_, prof)| (" (homogeneous)", prof)));
    for (suffix, prof) in sets {
        for (l, px, qx, _) in prof.iter() {
            pressure.push((
                format!("p along x, {l}{suffix}"),
                x.iter().copied().zip(px.iter().map(|v| v / p0)).collect(),
            ));
            shear.push((
                format!("q_x along x, {l}{suffix}"),
                x.iter()
                    .copied()
                    .zip(qx.iter().map(|v| v / (cfg.friction * p0)))
                    .collect(),
            ));
        }
    }
    let p = args.out.join("fretting_profiles.svg");
    plot::curves(
        &p,
        "Pressure p/p0 and shear q_x/(μ p0) along x at A–D",
        "x / a",
        ("p / p0", &pressure),
        ("q_x / (μ p0)", &shear),
        false,
    )
    .map_err(|e| CliError::Plot(format!("{}: {e}", p.display())))?;
    // Ratchet: Q/μW at the loop's end minus at its start, both at δx = +A.
    let ratchet =
        (history[history.len() - 1].q[0] - history[cfg.normal_steps + quarter - 1].q[0]) / mu_w;
    let mut summary = json!({
        "contact_area_over_hertz_end_of_normal_loading":
            end_normal.contact_area / (std::f64::consts::PI * a * a),
        "max_transverse_slip": max_transverse_slip,
        "ratchet": ratchet,
        "max_pressure_over_p0_end_of_normal_loading": end_normal.max_pressure / p0,
        "approach_over_hertz_end_of_normal_loading": end_normal.approach / (a * a / cfg.radius),
        "tangential_force_over_mu_w_at_amplitude": history[cfg.normal_steps + quarter - 1].q[0] / mu_w,
        "dissipated_energy": energy,
        "increments": history.len(),
        "grid": cfg.grid,
        "seconds": seconds,
        "out": args.out.display().to_string(),
    });
    if let Solver::Nested(n) = &solver {
        let extra = summary.as_object_mut().expect("object");
        extra.insert("inclusion_cells".into(), json!(n.inclusions().len()));
        extra.insert("layers".into(), json!(n.inclusions().layers.len()));
        extra.insert("case".into(), json!(args.case));
        if let Some((rows, _)) = &reference {
            let end = &rows[cfg.normal_steps - 1];
            let ref_energy = energy_of(&cycle_of(rows));
            extra.insert(
                "homogeneous".into(),
                json!({
                    "max_pressure_over_p0_end_of_normal_loading": end.max_pressure / p0,
                    "contact_area_over_hertz_end_of_normal_loading":
                        end.contact_area / (std::f64::consts::PI * a * a),
                    "dissipated_energy": ref_energy,
                    "ratchet": (rows[rows.len() - 1].q[0] - rows[cfg.normal_steps + quarter - 1].q[0]) / mu_w,
                }),
            );
            extra.insert(
                "max_pressure_ratio_to_homogeneous".into(),
                json!(end_normal.max_pressure / end.max_pressure),
            );
            extra.insert(
                "contact_area_ratio_to_homogeneous".into(),
                json!(end_normal.contact_area / end.contact_area),
            );
            extra.insert(
                "dissipated_energy_ratio_to_homogeneous".into(),
                json!(energy / ref_energy),
            );
        }
    }
    if args.json {
        println!("{summary}");
    } else {
        println!("{summary:#}");
    }
    Ok(())
}
