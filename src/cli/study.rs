//! `halfspace study`: convergence studies against closed forms (the docs' figures).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use halfspace::mdr::{studies, Backend, DisplacementMethod};
use serde_json::json;

use halfspace::figures::draw as plot;

use super::CliError;

/// Named error series of one study.
type Series = Vec<(&'static str, Vec<f64>)>;

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum Study {
    /// Eq. 17 on the Eq. 18 pair q = 1 − x⁴: mean relative error (Eq. 19) against N.
    Eq17,
    /// Eqs. 12 and 13 on Hertz (docs/theory-mdr.md#displacement-transform test 2): max error against N.
    Displacement,
    /// Eqs. 25 and 26 on the Eq. 27 pair U = x⁴ at k = ±0.5: mean relative error against N.
    Eq27,
    /// Graded Hertz (E0 = z0 = R = 1, ν = 0.3, δ = 0.01) for k = −0.5, 0, 0.5: p(r) and u(r).
    GradedHertz,
    /// MDR against the scikit-fem references in datasets/fe.h5 (k = 0, ±0.3).
    FeComparison,
    /// Fretting wear: a/a0 against τ for χ = 0.3, 0.5, 0.9 and their limits r*/a0 (docs/theory-mdr.md#fretting-wear).
    FrettingLimit,
    /// Fretting wear of graded media E ∝ z^k: the limiting worn profiles (χ = 0.5) for k = −0.5 … 0.9
    /// and the final wear volume against the amplitude u_A/(μd) (ν = 0.3), the optimal grading.
    GradedWear,
    /// Timing of one application of the EIM volume operator (eigenstrain on every layer → strain on
    /// every layer, half-space) on --grid² cells × --layers layers: build and apply seconds.
    EimOperator,
    /// The paper's Fig. 1: seconds per profile transform (Eq. 7 / Eq. 23, planned beforehand)
    /// against N, MVM against FFT, homogeneous and graded (k = 0.5), one run, log–log.
    TransformTiming,
}

#[derive(Debug, Args)]
pub struct StudyArgs {
    /// Which study.
    #[arg(value_enum)]
    study: Study,
    /// Plot the errors against N (log–log) to FILE.svg.
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Directory of the reference fixtures (fe-comparison).
    #[arg(long, default_value = "datasets")]
    datasets: PathBuf,
    /// Cells per side (eim-operator).
    #[arg(long, default_value_t = 128, allow_hyphen_values = true)]
    grid: usize,
    /// Layers (eim-operator).
    #[arg(long, default_value_t = 8, allow_hyphen_values = true)]
    layers: usize,
}

pub fn run(args: StudyArgs) -> Result<(), CliError> {
    if let Study::GradedHertz = args.study {
        return graded_hertz(&args);
    }
    if let Study::FeComparison = args.study {
        return fe_comparison(&args);
    }
    if let Study::FrettingLimit = args.study {
        return fretting_limit(&args);
    }
    if let Study::GradedWear = args.study {
        return graded_wear(&args);
    }
    if let Study::EimOperator = args.study {
        return eim_operator(&args);
    }
    if let Study::TransformTiming = args.study {
        return transform_timing(&args);
    }
    let (title, ns, series): (&str, Vec<usize>, Series) = match args.study {
        Study::Eq17 => {
            let ns = vec![11, 101, 1001, 2001, 10001, 100001];
            let e: Result<Vec<f64>, _> = ns
                .iter()
                .map(|&n| studies::stress_transform_error(n, Backend::Fft))
                .collect();
            (
                "Eq. 17 on q = 1 − x⁴: mean relative error ε (Eq. 19)",
                ns,
                vec![("Eq. 17 (FFT)", e?)],
            )
        }
        Study::Displacement => {
            let ns = vec![101, 301, 1001, 4001, 10001];
            let mut series = Vec::new();
            for (name, method) in [
                ("Eq. 12 (arccos kernel)", DisplacementMethod::DenseKernel),
                (
                    "Eq. 13 (FFT, parabolic split)",
                    DisplacementMethod::Convolution(Backend::Fft),
                ),
            ] {
                let e: Result<Vec<f64>, _> = ns
                    .iter()
                    .map(|&n| studies::displacement_hertz_error(n, method))
                    .collect();
                series.push((name, e?));
            }
            ("Hertz displacement (a = 0.7, L = 1): max error", ns, series)
        }
        Study::Eq27 => {
            let ns = vec![101, 301, 1001, 2001, 4001];
            let mut series = Vec::new();
            for (name, k, method) in [
                (
                    "Eq. 26 (FFT), k = −0.5",
                    -0.5,
                    DisplacementMethod::Convolution(Backend::Fft),
                ),
                (
                    "Eq. 25 (2F1 kernel), k = −0.5",
                    -0.5,
                    DisplacementMethod::DenseKernel,
                ),
                (
                    "Eq. 26 (FFT), k = 0.5",
                    0.5,
                    DisplacementMethod::Convolution(Backend::Fft),
                ),
                (
                    "Eq. 25 (2F1 kernel), k = 0.5",
                    0.5,
                    DisplacementMethod::DenseKernel,
                ),
            ] {
                let e: Result<Vec<f64>, _> = ns
                    .iter()
                    .map(|&n| studies::graded_quartic_displacement_error(n, k, method))
                    .collect();
                series.push((name, e?));
            }
            ("Eq. 27, U = x⁴ (L = 1): mean relative error", ns, series)
        }
        Study::GradedHertz
        | Study::FeComparison
        | Study::FrettingLimit
        | Study::GradedWear
        | Study::EimOperator
        | Study::TransformTiming => {
            unreachable!("handled above")
        }
    };
    let orders: Vec<f64> = series
        .iter()
        .map(|(_, e)| studies::observed_order(&ns, e))
        .collect();
    if let Some(path) = &args.plot {
        let reference = match args.study {
            Study::Eq27 => 1.0,
            _ => 1.5,
        };
        plot::convergence(path, title, &ns, &series, reference)
            .map_err(|e| CliError::Plot(format!("{}: {e}", path.display())))?;
    }
    if args.json {
        let s: Vec<_> = series
            .iter()
            .zip(&orders)
            .map(|((name, e), order)| json!({"name": name, "errors": e, "observed_order": order}))
            .collect();
        println!("{}", json!({"study": title, "n": ns, "series": s}));
    } else {
        println!("{title}");
        for ((name, e), order) in series.iter().zip(&orders) {
            println!("{name}: observed order {order:.3}");
            for (n, err) in ns.iter().zip(e) {
                println!("  N = {n:>7}  {err:.3e}");
            }
        }
    }
    Ok(())
}

/// Fig. 1 of Willert (2021): seconds per application of the profile transform (Eq. 7, Eq. 23 at
/// k = 0.5) against N for the MVM and the FFT backend, from one run (0.25 s of applications per
/// point, the fastest batch mean); `--plot FILE.svg` draws it log–log with slopes 1 and 2.
fn transform_timing(args: &StudyArgs) -> Result<(), CliError> {
    let ns = vec![100, 300, 1000, 3000, 10000, 30000];
    let cases = [
        ("FFT, homogeneous (Eq. 7)", 0.0, Backend::Fft),
        ("MVM, homogeneous (Eq. 7)", 0.0, Backend::Mvm),
        ("FFT, graded k = 0.5 (Eq. 23)", 0.5, Backend::Fft),
        ("MVM, graded k = 0.5 (Eq. 23)", 0.5, Backend::Mvm),
    ];
    let mut series: Series = Vec::new();
    for (name, k, backend) in cases {
        let t: Result<Vec<f64>, _> = ns
            .iter()
            .map(|&n| studies::profile_transform_seconds(n, k, backend, 0.25))
            .collect();
        series.push((name, t?));
    }
    let title = "Fig. 1: seconds per profile transform against N (MVM vs FFT)";
    if let Some(path) = &args.plot {
        plot::loglog(
            path,
            title,
            "seconds per transform",
            &ns,
            &series,
            &[1.0, 2.0],
        )
        .map_err(|e| CliError::Plot(format!("{}: {e}", path.display())))?;
    }
    let s: Vec<_> = series
        .iter()
        .map(|(name, t)| {
            json!({"name": name, "seconds": t,
                   "slope_last_decade": (t[t.len() - 1] / t[t.len() - 3]).ln()
                       / (ns[ns.len() - 1] as f64 / ns[ns.len() - 3] as f64).ln()})
        })
        .collect();
    println!(
        "{}",
        json!({"study": title, "n": ns, "threads": 1, "series": s})
    );
    Ok(())
}

/// Graded Hertz for k = −0.5, 0, 0.5 through the contact solver (N = 2001, FFT).
fn graded_hertz(args: &StudyArgs) -> Result<(), CliError> {
    use halfspace::mdr::{ContactParams, ContactSolver, Load, Material, Profile};
    let mut pressures = Vec::new();
    let mut displacements = Vec::new();
    let mut rows = Vec::new();
    for k in [-0.5, 0.0, 0.5] {
        let material = Material::power_law(1.0, 1.0, 0.3, k)?;
        let params = ContactParams {
            domain_ratio: 2.5,
            ..ContactParams::default()
        };
        let sol = ContactSolver::new(material, params)?
            .solve(&Profile::sphere(1.0)?, Load::Depth(0.01))?;
        let r = sol.radii();
        let label = format!("k = {k}");
        pressures.push((
            label.clone(),
            r.iter()
                .copied()
                .zip(sol.pressure.iter().copied())
                .collect(),
        ));
        displacements.push((
            label,
            r.iter()
                .copied()
                .zip(sol.displacement.iter().copied())
                .collect(),
        ));
        rows.push(json!({
            "k": k, "c_n": material.contact_modulus(), "contact_radius": sol.contact_radius,
            "force": sol.force, "max_pressure": sol.max_pressure(),
        }));
    }
    if let Some(path) = &args.plot {
        plot::curves(
            path,
            "Graded Hertz: E(z) = E0 (z/z0)^k, E0 = z0 = R = 1, ν = 0.3, δ = 0.01",
            "r",
            ("pressure p", &pressures),
            ("surface displacement u", &displacements),
            false,
        )
        .map_err(|e| CliError::Plot(format!("{}: {e}", path.display())))?;
    }
    if args.json {
        println!("{}", json!({"study": "graded Hertz", "cases": rows}));
    } else {
        for row in rows {
            println!("{row}");
        }
    }
    Ok(())
}

/// MDR (N = 8001) against the FE fixtures: pressure and surface displacement for k = 0, ±0.3.
fn fe_comparison(args: &StudyArgs) -> Result<(), CliError> {
    use halfspace::data::{read_h5_group, AttrValue};
    use halfspace::mdr::{ContactParams, ContactSolver, Load, Material, Profile};
    let path = args.datasets.join("fe.h5");
    let mut pressures = Vec::new();
    let mut displacements = Vec::new();
    let mut rows = Vec::new();
    for k in [0.0, 0.3, -0.3] {
        let rec = read_h5_group(&path, &format!("fe_sphere_k{k:+.1}"))?;
        let depth = match rec.get_attr("depth") {
            Some(AttrValue::Float(d)) => *d,
            _ => {
                return Err(CliError::Spec(format!(
                    "{}: case k = {k} has no depth",
                    path.display()
                )))
            }
        };
        let params = ContactParams {
            nodes: 8001,
            domain_ratio: 3.05,
            ..ContactParams::default()
        };
        let sol = ContactSolver::new(Material::power_law(1.0, 1.0, 0.3, k)?, params)?
            .solve(&Profile::sphere(10.0)?, Load::Depth(depth))?;
        let r = sol.radii();
        let missing = |name: &str| CliError::Spec(format!("{}: no array '{name}'", path.display()));
        let (pr, p) = (
            rec.get("pressure_r").ok_or_else(|| missing("pressure_r"))?,
            rec.get("pressure").ok_or_else(|| missing("pressure"))?,
        );
        let (ru, u) = (
            rec.get("r").ok_or_else(|| missing("r"))?,
            rec.get("displacement")
                .ok_or_else(|| missing("displacement"))?,
        );
        let mdr_p: Vec<(f64, f64)> = r
            .iter()
            .copied()
            .zip(sol.pressure.iter().copied())
            .collect();
        let mdr_u: Vec<(f64, f64)> = r
            .iter()
            .copied()
            .zip(sol.displacement.iter().copied())
            .collect();
        pressures.push((
            format!("MDR k = {k}"),
            mdr_p.into_iter().filter(|(x, _)| *x <= 1.2).collect(),
        ));
        pressures.push((
            format!("FE k = {k}"),
            pr.iter().copied().zip(p.iter().copied()).collect(),
        ));
        displacements.push((format!("MDR k = {k}"), mdr_u));
        displacements.push((
            format!("FE k = {k}"),
            ru.iter().copied().zip(u.iter().copied()).collect(),
        ));
        rows.push(json!({"k": k, "depth": depth, "mdr_force": sol.force, "fe_force": rec.get_attr("force").map(|v| v.to_json())}));
    }
    if let Some(plot_path) = &args.plot {
        plot::curves(
            plot_path,
            "MDR (lines) against scikit-fem (FE): sphere R = 10a, E0 = 1, ν = 0.3",
            "r / a",
            ("contact pressure p", &pressures),
            ("surface displacement u", &displacements),
            true,
        )
        .map_err(|e| CliError::Plot(format!("{}: {e}", plot_path.display())))?;
    }
    let summary = json!({"study": "fe comparison", "cases": rows});
    println!("{summary}");
    Ok(())
}

/// a/a0 against τ for χ = 0.3, 0.5 and 0.9, N = 2001, L = 1.6 a0, adaptive steps at the default
/// tolerance, τ ≤ 5 (every run is at its limit by then), with the limits r*/a0.
fn fretting_limit(args: &StudyArgs) -> Result<(), CliError> {
    use halfspace::fretting::{FrettingParams, FrettingSimulation};
    let mut curves = Vec::new();
    let mut limits = Vec::new();
    let mut rows = Vec::new();
    let tau_end = 5.0;
    for chi in [0.3, 0.5, 0.9] {
        let params = FrettingParams {
            chi,
            tau_end,
            snapshots: vec![0.1, 0.5, 1.0, 2.0, 3.0],
            ..FrettingParams::default()
        };
        let mut sim = FrettingSimulation::new(params).map_err(|e| CliError::Spec(e.to_string()))?;
        // τ at which the worn volume first reaches 50 % and 95 % of V∞ (the observer sees every
        // step; linear between steps).
        let limit = sim.limit_wear_volume();
        let mut reached = [None::<f64>; 2];
        let mut before = (0.0, 0.0);
        sim.run(|s| {
            let v = s.wear_volume() / limit;
            let tau = s.tau();
            for (slot, share) in reached.iter_mut().zip([0.5, 0.95]) {
                if slot.is_none() && v >= share {
                    let w = (share - before.1) / (v - before.1);
                    *slot = Some(before.0 + w * (tau - before.0));
                }
            }
            before = (tau, v);
            false
        })
        .map_err(|e| CliError::Spec(e.to_string()))?;
        let state = sim.state();
        let h = &state.contact_radius_history;
        let pts: Vec<(f64, f64)> = state
            .tau_history
            .iter()
            .copied()
            .zip(h.iter().copied())
            .collect();
        let r_star = sim.limit_contact_radius();
        curves.push((format!("χ = {chi}"), pts));
        limits.push((
            format!("r*/a0 = {r_star:.4}"),
            vec![(0.0, r_star), (tau_end, r_star)],
        ));
        let at = |tau: f64| {
            let i = state
                .tau_history
                .iter()
                .position(|&t| t >= tau)
                .unwrap_or(h.len() - 1);
            h[i]
        };
        let top = h.iter().copied().fold(1.0, f64::max);
        rows.push(json!({"chi": chi, "steps": state.step, "r_star": r_star, "max_a": top,
            "tau_half_volume": reached[0], "tau_95_volume": reached[1],
            "wear_volume": sim.wear_volume(), "limit_wear_volume": sim.limit_wear_volume(),
            "a_at_tau": {"0.1": at(0.1), "0.5": at(0.5), "1": at(1.0), "2": at(2.0), "3": at(3.0), "5": at(5.0)}}));
    }
    if let Some(path) = &args.plot {
        let mut all = Vec::new();
        for (c, l) in curves.into_iter().zip(limits) {
            all.push(c);
            all.push(l);
        }
        plot::curves(
            path,
            "Fretting wear: contact radius a/a0 against τ = N/N0 (limits r*/a0)",
            "τ",
            ("a / a0", &all),
            ("a / a0", &[]),
            true,
        )
        .map_err(|e| CliError::Plot(format!("{}: {e}", path.display())))?;
    }
    println!("{}", json!({"study": "fretting limit", "cases": rows}));
    Ok(())
}

/// The graded limiting profiles and final wear volumes (`halfspace_fretting::studies`):
/// `--plot FILE.svg` draws the profiles there, the volumes against the physical amplitude in
/// `FILE-volume.svg` and against χ in `FILE-volume-chi.svg`.
fn graded_wear(args: &StudyArgs) -> Result<(), CliError> {
    let s = halfspace::fretting::studies::graded_wear_study()
        .map_err(|e| CliError::Spec(e.to_string()))?;
    if let Some(path) = &args.plot {
        let profiles: Vec<(String, Vec<(f64, f64)>)> = s
            .curves
            .iter()
            .map(|c| {
                (
                    format!("k = {:+.2}, r*/a0 = {:.4}", c.k, c.r_star),
                    c.wear_depth.clone(),
                )
            })
            .collect();
        let volumes: Vec<(String, Vec<(f64, f64)>)> = s
            .curves
            .iter()
            .map(|c| {
                let pts = c
                    .volume_against_amplitude
                    .iter()
                    .map(|(u, v)| (u.log10(), v.log10()))
                    .collect();
                (format!("k = {:+.2}", c.k), pts)
            })
            .collect();
        plot::curves(
            path,
            &format!(
                "Graded fretting wear: limiting wear depth (f∞ − f0)/d at χ = {} (E ∝ z^k)",
                s.chi
            ),
            "r / a0",
            ("(f∞ − f0) / d", &profiles),
            ("", &[]),
            false,
        )
        .map_err(|e| CliError::Plot(format!("{}: {e}", path.display())))?;
        let stem = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("graded-wear");
        let ext = path.extension().and_then(|s| s.to_str()).unwrap_or("svg");
        let volume_path = path.with_file_name(format!("{stem}-volume.{ext}"));
        plot::curves(
            &volume_path,
            &format!(
                "Final wear volume log10 V∞/(π a0² d) against log10 u_A/(μ d) (ν = {}; curves end at gross slip)",
                s.nu
            ),
            "log10 u_A / (μ d)",
            ("log10 V∞ / (π a0² d)", &volumes),
            ("", &[]),
            false,
        )
        .map_err(|e| CliError::Plot(format!("{}: {e}", volume_path.display())))?;
        let by_chi: Vec<(String, Vec<(f64, f64)>)> = s
            .curves
            .iter()
            .map(|c| (format!("k = {:+.2}", c.k), c.volume_against_chi.clone()))
            .collect();
        let chi_path = path.with_file_name(format!("{stem}-volume-chi.{ext}"));
        plot::curves(
            &chi_path,
            "Final wear volume V∞/(π a0² d) against χ = u_A/u_max (u_max = μ (c_N/c_T) d depends on k, ν)",
            "χ",
            ("V∞ / (π a0² d)", &by_chi),
            ("", &[]),
            false,
        )
        .map_err(|e| CliError::Plot(format!("{}: {e}", chi_path.display())))?;
    }
    let cases: Vec<_> = s
        .curves
        .iter()
        .map(|c| {
            json!({"k": c.k, "r_star_chi_0.5": c.r_star,
                "tangential_constant_ratio_nu_0.3": c.tangential_ratio,
                "limit_wear_volume_at_chi_0.1_0.3_0.5_0.7_0.9": c.volume_at_chi})
        })
        .collect();
    let optimum: Vec<_> = s
        .optimum
        .iter()
        .map(|o| json!({"amplitude_over_mu_d": o.amplitude_over_mu_d, "best_k": o.k, "limit_wear_volume": o.volume}))
        .collect();
    let gibson: Vec<_> = s
        .towards_gibson
        .iter()
        .map(|(k, nu, r)| json!({"k": k, "nu": nu, "tangential_constant_ratio": r}))
        .collect();
    println!(
        "{}",
        json!({"study": "graded wear", "chi_profiles": s.chi, "nu": s.nu, "cases": cases,
            "optimum": optimum, "towards_gibson": gibson,
            "wear_volume_definition": "V/(π a0² d), a0 and d of the same medium"})
    );
    Ok(())
}

/// Build and apply times of the EIM volume operator on `grid² × layers` cells (unit cells, ν = 0.3,
/// the whole grid as the window, every layer a source and a target): the operator that Tamaas calls
/// `mindlin_gradient` (`verify/eim_vs_tamaas.py` runs both in one run).
fn eim_operator(args: &StudyArgs) -> Result<(), CliError> {
    use halfspace::sam::eim::{Backend, EimFields, Space, Window};
    use halfspace::sam::SurfaceGrid;
    use std::time::Instant;
    let (n, nl) = (args.grid, args.layers);
    if nl == 0 {
        return Err(CliError::Spec("--layers must be ≥ 1".into()));
    }
    let grid = SurfaceGrid::square(n, n as f64)?;
    let layers: Vec<usize> = (0..nl).collect();
    let t = Instant::now();
    let mut f = EimFields::new(
        grid,
        1.0,
        0.3,
        &layers,
        &layers,
        Window::full(&grid),
        Space::HalfSpace,
        Backend::Fft,
    )?;
    let build = t.elapsed().as_secs_f64();
    let eigen: Vec<Vec<f64>> = (0..nl * 6)
        .map(|k| {
            (0..n * n)
                .map(|i| ((i * 7 + k * 3) % 13) as f64 - 6.0)
                .collect()
        })
        .collect();
    let mut strain = vec![vec![0.0; n * n]; nl * 6];
    f.disturbance(&eigen, &mut strain)?;
    let repeats = 5;
    let mut times = Vec::with_capacity(repeats);
    for _ in 0..repeats {
        let t = Instant::now();
        f.disturbance(&eigen, &mut strain)?;
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    let summary = json!({
        "grid": n,
        "layers": nl,
        "build_seconds": build,
        "apply_seconds_median": times[repeats / 2],
        "apply_seconds_min": times[0],
        "spectra_bytes": f.spectra_bytes(),
        "threads": rayon_threads(),
    });
    if args.json {
        println!("{summary}");
    } else {
        println!(
            "EIM operator {n}² × {nl}: build {build:.3} s, apply {:.4} s (median of {repeats}), spectra {:.1} MB",
            times[repeats / 2],
            f.spectra_bytes() as f64 / 1e6
        );
    }
    Ok(())
}

fn rayon_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}
