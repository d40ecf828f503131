//! `halfspace axisym`: axisymmetric normal contact by the MDR (design.md, CLI contract).

use std::path::PathBuf;
use std::time::Instant;

use clap::{Args, ValueEnum};
use halfspace::axisym::{AxisymCase, AxisymConfig, ProfileEntry};
use halfspace::config::Names;
use halfspace::data::{write_record, AttrValue, Record};
use halfspace::mdr::ContactSolution;
use serde_json::json;

use halfspace::figures::{axisym::pressure_and_displacement, draw::check_extension};

use super::CliError;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Method {
    /// O(N log N) FFT convolutions (Eqs. 7, 17; displacement by Eq. 13).
    Fft,
    /// O(N²) matrix–vector products (Eqs. 7, 17; displacement by Eq. 12).
    Mvm,
}

impl Method {
    /// The `method` key's value.
    pub fn name(self) -> &'static str {
        match self {
            Method::Fft => "fft",
            Method::Mvm => "mvm",
        }
    }
}

#[derive(Debug, Args)]
pub struct AxisymArgs {
    /// TOML (or .json) file with any of the keys profile, material, depth, force, n, method,
    /// domain_ratio; a flag given on the command line overrides its key (docs/architecture.md, "The application layer").
    #[arg(long)]
    config: Option<PathBuf>,
    /// Indenter: sphere:R=.. | cone:slope=.. | flat:a=.. | power:c=..,n=.. | table:FILE.npy
    #[arg(long)]
    profile: Option<String>,
    /// Half-space: homogeneous:E=..,nu=.. | homogeneous:Estar=.. | graded:E0=..,z0=..,nu=..,k=..
    /// (E(z) = E0 (z/z0)^k, −1 < k < 1)
    #[arg(long)]
    material: Option<String>,
    /// Indentation depth δ in m.
    #[arg(long, allow_hyphen_values = true)]
    depth: Option<f64>,
    /// Normal force F in N.
    #[arg(long, allow_hyphen_values = true)]
    force: Option<f64>,
    /// Grid nodes N (≥ 8; default 2001).
    #[arg(long, allow_hyphen_values = true)]
    n: Option<usize>,
    /// Backend of the transforms (default fft).
    #[arg(long, value_enum)]
    method: Option<Method>,
    /// Domain size over contact radius, L/a ≥ 1 (default 1.5).
    #[arg(long, allow_hyphen_values = true)]
    domain_ratio: Option<f64>,
    /// Write r, pressure, displacement, x, g (and the inputs as metadata) to FILE.h5 or FILE.npz.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Plot p(r) and u(r) to FILE.svg.
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
}

pub fn run(args: AxisymArgs) -> Result<(), CliError> {
    let flags = AxisymConfig {
        profile: args.profile.clone().map(ProfileEntry::Spec),
        material: args.material.clone(),
        depth: args.depth,
        force: args.force,
        n: args.n,
        method: args.method.map(|m| m.name().to_string()),
        domain_ratio: args.domain_ratio,
    };
    let file: AxisymConfig = super::read_config(args.config.as_deref())?;
    let case = file.overlay(flags).case(Names::Flags)?;
    if let Some(path) = &args.out {
        halfspace::data::Format::of(path)?;
    }
    if let Some(path) = &args.plot {
        check_extension(path, "--plot", &["svg"])?;
    }
    let start = Instant::now();
    let sol = case.solve()?;
    let seconds = start.elapsed().as_secs_f64();
    let mut summary = case.summary(&sol);
    summary["seconds"] = json!(seconds);
    if let Some(path) = &args.out {
        write_record(path, &record(&sol, &case, &summary))?;
    }
    if let Some(path) = &args.plot {
        pressure_and_displacement(path, &sol, &case.profile_spec)?;
    }
    if args.json {
        println!("{summary}");
    } else {
        println!("contact radius a  = {:.6e} m", sol.contact_radius);
        println!("depth δ           = {:.6e} m", sol.depth);
        println!("force F           = {:.6e} N", sol.force);
        println!("max pressure      = {:.6e} Pa", sol.max_pressure());
        println!("mean pressure     = {:.6e} Pa", sol.mean_pressure());
        println!(
            "N = {}, method = {}, {:.3} ms",
            case.params.nodes,
            case.params.backend.name(),
            1e3 * seconds
        );
    }
    Ok(())
}

fn record(sol: &ContactSolution, case: &AxisymCase, summary: &serde_json::Value) -> Record {
    let r = sol.radii();
    let mut rec = Record::default()
        .array("r", r.clone())
        .array("pressure", sol.pressure.clone())
        .array("displacement", sol.displacement.clone())
        .array("x", r)
        .array("g", sol.equivalent.clone());
    for (key, value) in summary.as_object().expect("summary is an object") {
        let v = match value {
            serde_json::Value::Number(n) if n.is_u64() || n.is_i64() => {
                AttrValue::Int(n.as_i64().unwrap_or_default())
            }
            serde_json::Value::Number(n) => AttrValue::Float(n.as_f64().unwrap_or(f64::NAN)),
            serde_json::Value::String(s) => AttrValue::Text(s.clone()),
            other => AttrValue::Text(other.to_string()),
        };
        rec = rec.attr(key, v);
    }
    rec.attr(
        "units",
        AttrValue::Text("SI: r, x, g, displacement in m; pressure in Pa".into()),
    )
    .attr(
        "generator",
        AttrValue::Text(format!("halfspace {} axisym", env!("CARGO_PKG_VERSION"))),
    )
    .attr("domain_ratio", AttrValue::Float(case.params.domain_ratio))
}
