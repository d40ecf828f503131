//! The studies of `halfspace study` (the docs' convergence and comparison figures): each study's
//! series — the numbers it reports and its figure draws — and its one summary (the JSON keys).
//! The methods live in `halfspace_mdr::studies` (the transforms' errors against closed forms),
//! `halfspace_mdr::ContactSolver`, `halfspace_fretting` and `halfspace_sam::eim`; the figures are
//! `halfspace_figures::studies`.

use std::path::Path;

use serde_json::{json, Value};

use crate::data::{read_h5_group, AttrValue, DataError};
use crate::fretting::studies::GradedWearStudy;
use crate::fretting::{FrettingError, FrettingParams, FrettingSimulation};
use crate::mdr::studies as mdr_studies;
use crate::mdr::{
    Backend, ContactParams, ContactSolver, DisplacementMethod, Load, Material, MdrError, Profile,
};
use crate::sam::SamError;

/// Why a study did not run.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The MDR refused a case.
    #[error(transparent)]
    Mdr(#[from] MdrError),
    /// The fretting wear simulation refused a case.
    #[error(transparent)]
    Fretting(#[from] FrettingError),
    /// The EIM operator refused its grid.
    #[error(transparent)]
    Sam(#[from] SamError),
    /// A reference fixture could not be read.
    #[error(transparent)]
    Data(#[from] DataError),
    /// A reference fixture lacks an array or attribute, or a parameter is out of range (the
    /// message names it).
    #[error("{0}")]
    Input(String),
}

/// Named curves `(x, y)` of one panel of a figure.
pub type Curves = Vec<(String, Vec<(f64, f64)>)>;

/// Errors against N of one or more methods, with the observed orders
/// (`mdr::studies::observed_order`: the least-squares slope of log ε against log N).
#[derive(Debug, Clone)]
pub struct Convergence {
    /// What the errors are (the figure's title and the summary's `study`).
    pub title: &'static str,
    /// The numbers of nodes N.
    pub n: Vec<usize>,
    /// One error series per method, named.
    pub series: Vec<(&'static str, Vec<f64>)>,
    /// The observed order of each series.
    pub orders: Vec<f64>,
    /// The order of the reference slope the figure draws.
    pub reference_order: f64,
}

impl Convergence {
    fn new(
        title: &'static str,
        n: Vec<usize>,
        series: Vec<(&'static str, Vec<f64>)>,
        reference_order: f64,
    ) -> Self {
        let orders = series
            .iter()
            .map(|(_, e)| mdr_studies::observed_order(&n, e))
            .collect();
        Convergence {
            title,
            n,
            series,
            orders,
            reference_order,
        }
    }

    /// The summary: `{"study", "n", "series": [{"name", "errors", "observed_order"}]}`.
    pub fn summary(&self) -> Value {
        let s: Vec<_> = self
            .series
            .iter()
            .zip(&self.orders)
            .map(|((name, e), order)| json!({"name": name, "errors": e, "observed_order": order}))
            .collect();
        json!({"study": self.title, "n": self.n, "series": s})
    }

    /// The summary as text: the title, then per series its observed order and its errors by N.
    pub fn text(&self) -> String {
        let mut out = format!("{}\n", self.title);
        for ((name, e), order) in self.series.iter().zip(&self.orders) {
            out += &format!("{name}: observed order {order:.3}\n");
            for (n, err) in self.n.iter().zip(e) {
                out += &format!("  N = {n:>7}  {err:.3e}\n");
            }
        }
        out
    }
}

/// Eq. 17 on the Eq. 18 pair `q = 1 − x⁴`: the mean relative error (Eq. 19) of the FFT stress
/// transform against N (`mdr::studies::stress_transform_error`).
pub fn eq17() -> Result<Convergence, StudyError> {
    let ns = vec![11, 101, 1001, 2001, 10001, 100001];
    let e: Result<Vec<f64>, _> = ns
        .iter()
        .map(|&n| mdr_studies::stress_transform_error(n, Backend::Fft))
        .collect();
    Ok(Convergence::new(
        "Eq. 17 on q = 1 − x⁴: mean relative error ε (Eq. 19)",
        ns,
        vec![("Eq. 17 (FFT)", e?)],
        1.5,
    ))
}

/// Eqs. 12 and 13 on Hertz (docs/theory-mdr.md#displacement-transform, test 2): the max error of
/// the surface displacement against N (`mdr::studies::displacement_hertz_error`).
pub fn displacement() -> Result<Convergence, StudyError> {
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
            .map(|&n| mdr_studies::displacement_hertz_error(n, method))
            .collect();
        series.push((name, e?));
    }
    Ok(Convergence::new(
        "Hertz displacement (a = 0.7, L = 1): max error",
        ns,
        series,
        1.5,
    ))
}

/// Eqs. 25 and 26 on the Eq. 27 pair `U = x⁴` at k = ±0.5: the mean relative error against N
/// (`mdr::studies::graded_quartic_displacement_error`).
pub fn eq27() -> Result<Convergence, StudyError> {
    let ns = vec![101, 301, 1001, 2001, 4001];
    let mut series = Vec::new();
    let fft = DisplacementMethod::Convolution(Backend::Fft);
    let kernel = DisplacementMethod::DenseKernel;
    for (name, k, method) in [
        ("Eq. 26 (FFT), k = −0.5", -0.5, fft),
        ("Eq. 25 (2F1 kernel), k = −0.5", -0.5, kernel),
        ("Eq. 26 (FFT), k = 0.5", 0.5, fft),
        ("Eq. 25 (2F1 kernel), k = 0.5", 0.5, kernel),
    ] {
        let e: Result<Vec<f64>, _> = ns
            .iter()
            .map(|&n| mdr_studies::graded_quartic_displacement_error(n, k, method))
            .collect();
        series.push((name, e?));
    }
    Ok(Convergence::new(
        "Eq. 27, U = x⁴ (L = 1): mean relative error",
        ns,
        series,
        1.0,
    ))
}

/// Seconds per application of the profile transform (Eq. 7; Eq. 23 at k = 0.5) against N, MVM
/// against FFT (the paper's Fig. 1), from one run: `mdr::studies::profile_transform_seconds`, 0.25 s
/// of applications per point, the fastest batch mean.
#[derive(Debug, Clone)]
pub struct TransformTiming {
    /// The numbers of nodes N.
    pub n: Vec<usize>,
    /// Seconds per transform, one series per backend and material, named.
    pub series: Vec<(&'static str, Vec<f64>)>,
}

/// The title of the transform-timing study (its figure's and its summary's `study`).
pub const TRANSFORM_TIMING_TITLE: &str =
    "Fig. 1: seconds per profile transform against N (MVM vs FFT)";

/// Times the profile transforms (see [`TransformTiming`]).
pub fn transform_timing() -> Result<TransformTiming, StudyError> {
    let ns = vec![100, 300, 1000, 3000, 10000, 30000];
    let cases = [
        ("FFT, homogeneous (Eq. 7)", 0.0, Backend::Fft),
        ("MVM, homogeneous (Eq. 7)", 0.0, Backend::Mvm),
        ("FFT, graded k = 0.5 (Eq. 23)", 0.5, Backend::Fft),
        ("MVM, graded k = 0.5 (Eq. 23)", 0.5, Backend::Mvm),
    ];
    let mut series = Vec::new();
    for (name, k, backend) in cases {
        let t: Result<Vec<f64>, _> = ns
            .iter()
            .map(|&n| mdr_studies::profile_transform_seconds(n, k, backend, 0.25))
            .collect();
        series.push((name, t?));
    }
    Ok(TransformTiming { n: ns, series })
}

impl TransformTiming {
    /// The summary: `{"study", "n", "threads": 1, "series": [{"name", "seconds",
    /// "slope_last_decade"}]}`, the slope `ln(t_last / t_{last−2}) / ln(N_last / N_{last−2})`.
    pub fn summary(&self) -> Value {
        let ns = &self.n;
        let s: Vec<_> = self
            .series
            .iter()
            .map(|(name, t)| {
                json!({"name": name, "seconds": t,
                       "slope_last_decade": (t[t.len() - 1] / t[t.len() - 3]).ln()
                           / (ns[ns.len() - 1] as f64 / ns[ns.len() - 3] as f64).ln()})
            })
            .collect();
        json!({"study": TRANSFORM_TIMING_TITLE, "n": ns, "threads": 1, "series": s})
    }
}

/// Pressure and surface displacement curves of MDR contacts (and references), with one summary
/// row per case.
#[derive(Debug, Clone)]
pub struct ProfileComparison {
    /// The summary's `study`.
    pub study: &'static str,
    /// `p(r)` curves, named.
    pub pressures: Curves,
    /// `u(r)` curves, named.
    pub displacements: Curves,
    /// One summary row per case.
    pub cases: Vec<Value>,
}

impl ProfileComparison {
    /// The summary: `{"study", "cases"}`.
    pub fn summary(&self) -> Value {
        json!({"study": self.study, "cases": self.cases})
    }
}

fn radial_curve(r: &[f64], v: &[f64]) -> Vec<(f64, f64)> {
    r.iter().copied().zip(v.iter().copied()).collect()
}

/// Graded Hertz (E(z) = E0 (z/z0)^k, E0 = z0 = R = 1, ν = 0.3, δ = 0.01) for k = −0.5, 0, 0.5
/// through `mdr::ContactSolver` (N = 2001, FFT, L = 2.5 a): p(r), u(r), and per case c_N, the
/// contact radius, the force and the maximum pressure.
pub fn graded_hertz() -> Result<ProfileComparison, StudyError> {
    let mut out = ProfileComparison {
        study: "graded Hertz",
        pressures: Vec::new(),
        displacements: Vec::new(),
        cases: Vec::new(),
    };
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
        out.pressures
            .push((label.clone(), radial_curve(&r, &sol.pressure)));
        out.displacements
            .push((label, radial_curve(&r, &sol.displacement)));
        out.cases.push(json!({
            "k": k, "c_n": material.contact_modulus(), "contact_radius": sol.contact_radius,
            "force": sol.force, "max_pressure": sol.max_pressure(),
        }));
    }
    Ok(out)
}

/// The MDR (N = 8001, L = 3.05 a, sphere R = 10, E0 = 1, ν = 0.3) against the scikit-fem
/// references of `datasets/fe.h5` (groups `fe_sphere_k+0.0`, `…k+0.3`, `…k-0.3`: the depth, the
/// FE force, `pressure_r`/`pressure` and `r`/`displacement`): the MDR pressure for r ≤ 1.2 and
/// the FE one, the MDR and FE displacements, and per case the depth and both forces.
pub fn fe_comparison(datasets: &Path) -> Result<ProfileComparison, StudyError> {
    let path = datasets.join("fe.h5");
    let mut out = ProfileComparison {
        study: "fe comparison",
        pressures: Vec::new(),
        displacements: Vec::new(),
        cases: Vec::new(),
    };
    for k in [0.0, 0.3, -0.3] {
        let rec = read_h5_group(&path, &format!("fe_sphere_k{k:+.1}"))?;
        let depth = match rec.get_attr("depth") {
            Some(AttrValue::Float(d)) => *d,
            _ => {
                return Err(StudyError::Input(format!(
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
        let array = |name: &str| {
            rec.get(name)
                .ok_or_else(|| StudyError::Input(format!("{}: no array '{name}'", path.display())))
        };
        let (pr, p) = (array("pressure_r")?, array("pressure")?);
        let (ru, u) = (array("r")?, array("displacement")?);
        let mdr_p = radial_curve(&r, &sol.pressure);
        out.pressures.push((
            format!("MDR k = {k}"),
            mdr_p.into_iter().filter(|(x, _)| *x <= 1.2).collect(),
        ));
        out.pressures
            .push((format!("FE k = {k}"), radial_curve(pr, p)));
        out.displacements
            .push((format!("MDR k = {k}"), radial_curve(&r, &sol.displacement)));
        out.displacements
            .push((format!("FE k = {k}"), radial_curve(ru, u)));
        out.cases.push(json!({"k": k, "depth": depth, "mdr_force": sol.force, "fe_force": rec.get_attr("force").map(|v| v.to_json())}));
    }
    Ok(out)
}

/// The approach of MDR fretting wear to its limit (docs/fretting-wear.md): a/a0 against τ for
/// χ = 0.3, 0.5, 0.9 (N = 2001, L = 1.6 a0, adaptive steps at the default tolerance, τ ≤ 5), the
/// limits r*/a0, and per χ the τ at which the worn volume reaches 50 % and 95 % of V∞ (linear
/// between steps) and a/a0 at τ = 0.1 … 5.
#[derive(Debug, Clone)]
pub struct FrettingLimit {
    /// The last τ of every run.
    pub tau_end: f64,
    /// a/a0 against τ, one curve per χ.
    pub radii: Curves,
    /// The limit r*/a0 of each χ as a horizontal line over 0 ≤ τ ≤ `tau_end`.
    pub limits: Curves,
    /// One summary row per χ.
    pub cases: Vec<Value>,
}

impl FrettingLimit {
    /// The summary: `{"study": "fretting limit", "cases"}`.
    pub fn summary(&self) -> Value {
        json!({"study": "fretting limit", "cases": self.cases})
    }
}

/// Runs the fretting-limit study (see [`FrettingLimit`]).
pub fn fretting_limit() -> Result<FrettingLimit, StudyError> {
    let tau_end = 5.0;
    let mut out = FrettingLimit {
        tau_end,
        radii: Vec::new(),
        limits: Vec::new(),
        cases: Vec::new(),
    };
    for chi in [0.3, 0.5, 0.9] {
        let params = FrettingParams {
            chi,
            tau_end,
            snapshots: vec![0.1, 0.5, 1.0, 2.0, 3.0],
            ..FrettingParams::default()
        };
        let mut sim = FrettingSimulation::new(params)?;
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
        })?;
        let state = sim.state();
        let h = &state.contact_radius_history;
        let r_star = sim.limit_contact_radius();
        out.radii
            .push((format!("χ = {chi}"), radial_curve(&state.tau_history, h)));
        out.limits.push((
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
        out.cases.push(json!({"chi": chi, "steps": state.step, "r_star": r_star, "max_a": top,
            "tau_half_volume": reached[0], "tau_95_volume": reached[1],
            "wear_volume": sim.wear_volume(), "limit_wear_volume": sim.limit_wear_volume(),
            "a_at_tau": {"0.1": at(0.1), "0.5": at(0.5), "1": at(1.0), "2": at(2.0), "3": at(3.0), "5": at(5.0)}}));
    }
    Ok(out)
}

/// The graded-wear study (`fretting::studies::graded_wear_study`).
pub fn graded_wear() -> Result<GradedWearStudy, StudyError> {
    Ok(crate::fretting::studies::graded_wear_study()?)
}

/// The summary of the graded-wear study: per k the limit radius at χ = 0.5, c_T/c_N at ν = 0.3
/// and V∞ at χ = 0.1 … 0.9; the optimal k per amplitude; c_T/c_N towards Gibson's medium.
pub fn graded_wear_summary(s: &GradedWearStudy) -> Value {
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
    json!({"study": "graded wear", "chi_profiles": s.chi, "nu": s.nu, "cases": cases,
        "optimum": optimum, "towards_gibson": gibson,
        "wear_volume_definition": "V/(π a0² d), a0 and d of the same medium"})
}

/// Build and apply times of the EIM volume operator (`sam::eim::EimFields::disturbance`:
/// eigenstrain on every layer → strain on every layer, half-space) on `grid² × layers` unit
/// cells, ν = 0.3, the whole grid as the window: the operator that Tamaas calls
/// `mindlin_gradient` (`verify/eim_vs_tamaas.py` runs both in one run).
#[derive(Debug, Clone)]
pub struct EimOperatorTiming {
    /// Cells per side.
    pub grid: usize,
    /// Layers.
    pub layers: usize,
    /// Seconds to build the operator.
    pub build_seconds: f64,
    /// Seconds of each of the timed applications (after one untimed), ascending.
    pub apply_seconds: Vec<f64>,
    /// Bytes of the stored layer spectra.
    pub spectra_bytes: usize,
}

/// Times the EIM operator (see [`EimOperatorTiming`]): one untimed application, then the median
/// and minimum of 5.
pub fn eim_operator(grid: usize, layers: usize) -> Result<EimOperatorTiming, StudyError> {
    use crate::sam::eim::{Backend, EimFields, Space, Window};
    use crate::sam::SurfaceGrid;
    use std::time::Instant;
    let (n, nl) = (grid, layers);
    if nl == 0 {
        return Err(StudyError::Input(format!("layers must be ≥ 1, got {nl}")));
    }
    // Refused before anything of size `layers` is built: the study's eigenstrains and strains
    // (12 fields a layer) and, at least, the operator's stored spectra of `2·layers − 1` depth
    // keys of 36 blocks.
    let (nf, lf) = (n as f64, nl as f64);
    let need = 12.0 * lf * nf * nf * 8.0
        + crate::sam::eim::operator::estimated_bytes(n, n, 1, 36) * (2.0 * lf - 1.0);
    halfspace_numerics::memory::check_fits("the EIM operator study", need)
        .map_err(|e| StudyError::Input(format!("--layers {nl} on a {n}² grid: {e}")))?;
    let surface = SurfaceGrid::square(n, n as f64)?;
    let all: Vec<usize> = (0..nl).collect();
    let t = Instant::now();
    let mut f = EimFields::new(
        surface,
        1.0,
        0.3,
        &all,
        &all,
        Window::full(&surface),
        Space::HalfSpace,
        Backend::Fft,
    )?;
    let build_seconds = t.elapsed().as_secs_f64();
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
    Ok(EimOperatorTiming {
        grid: n,
        layers: nl,
        build_seconds,
        apply_seconds: times,
        spectra_bytes: f.spectra_bytes(),
    })
}

impl EimOperatorTiming {
    fn median(&self) -> f64 {
        self.apply_seconds[self.apply_seconds.len() / 2]
    }

    /// The summary: grid, layers, build seconds, median and minimum apply seconds, spectra bytes,
    /// `threads` (the available parallelism).
    pub fn summary(&self) -> Value {
        json!({
            "grid": self.grid,
            "layers": self.layers,
            "build_seconds": self.build_seconds,
            "apply_seconds_median": self.median(),
            "apply_seconds_min": self.apply_seconds[0],
            "spectra_bytes": self.spectra_bytes,
            "threads": std::thread::available_parallelism().map_or(1, |n| n.get()),
        })
    }

    /// The summary as one line of text.
    pub fn text(&self) -> String {
        format!(
            "EIM operator {}² × {}: build {:.3} s, apply {:.4} s (median of {}), spectra {:.1} MB",
            self.grid,
            self.layers,
            self.build_seconds,
            self.median(),
            self.apply_seconds.len(),
            self.spectra_bytes as f64 / 1e6
        )
    }
}
