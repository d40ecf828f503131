//! `halfspace._halfspace`: the Rust side of the Python package. Thin: every function parses its
//! inputs with the library's one spec parser (`halfspace::spec`) or config schema
//! (`halfspace::config`), calls the library's driver with the GIL released, and returns plain
//! dicts of floats and NumPy arrays; the typed classes and result objects live in
//! `halfspace/__init__.py`. Errors are `halfspace.HalfspaceError` (a `ValueError`) carrying the
//! library's message.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::RecvTimeoutError;
use std::time::Duration;

use numpy::{PyArray1, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use halfspace::config::LoopConfig;
use halfspace::fretting::{FrettingParams, FrettingSimulation, TimeStepping};
use halfspace::fretting_map::{run_map_until, MapError};
use halfspace::mdr::{Backend, ContactParams, ContactSolver, Load, Profile};
use halfspace::records::{contact_record, contact_summary, wear_summary};
use halfspace::sam::drivers::fretting_loop::{FrettingLoop, LoopRow, POINT_LABELS};
use halfspace::sam::drivers::fretting_map::{FrettingMap, MapPoint};
use halfspace::sam::drivers::one_contact::{solve_contact, ContactCase, TangentialLoad};
use halfspace::sam::normal::NormalLoad;
use halfspace::spec::{
    parse_body, parse_indenter, parse_inhomogeneity, parse_material, parse_profile,
    parse_wear_medium, WearMedium,
};

create_exception!(
    _halfspace,
    HalfspaceError,
    PyValueError,
    "An input the library refuses or a solve that fails; the message is the library's."
);

fn err(e: impl std::fmt::Display) -> PyErr {
    HalfspaceError::new_err(e.to_string())
}

/// Runs `work` on a worker thread with the GIL released while this (the calling, main) thread
/// checks for signals every 50 ms: on Ctrl-C (or any signal handler raising) `cancel` is set, the
/// work stops at its next check (after the increment or step it is in) and the Python error
/// (`KeyboardInterrupt`) is raised; what the work had done stays intact. Python runs signal
/// handlers only in the main thread, hence the worker.
fn interruptible<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> T + Send,
) -> PyResult<T> {
    let cancel = AtomicBool::new(false);
    let (value, interrupted) = py.detach(|| {
        std::thread::scope(|scope| {
            let (done, finished) = std::sync::mpsc::channel::<()>();
            let cancel = &cancel;
            let handle = scope.spawn(move || {
                let value = work(cancel);
                let _ = done.send(());
                value
            });
            let mut interrupted = None;
            // Until the worker is done (or panicked: the join below re-raises it).
            while let Err(RecvTimeoutError::Timeout) =
                finished.recv_timeout(Duration::from_millis(50))
            {
                if interrupted.is_none() {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        cancel.store(true, Ordering::Relaxed);
                        interrupted = Some(e);
                    }
                }
            }
            let value = match handle.join() {
                Ok(v) => v,
                Err(panic) => std::panic::resume_unwind(panic),
            };
            (value, interrupted)
        })
    });
    match interrupted {
        Some(e) => Err(e),
        None => Ok(value),
    }
}

/// A flat JSON object of numbers and strings as a dict (the CLI's summary keys).
fn json_dict<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (key, v) in value.as_object().into_iter().flatten() {
        match v {
            serde_json::Value::Number(n) if n.is_u64() || n.is_i64() => {
                d.set_item(key, n.as_i64().unwrap_or_default())?
            }
            serde_json::Value::Number(n) => d.set_item(key, n.as_f64().unwrap_or(f64::NAN))?,
            serde_json::Value::String(s) => d.set_item(key, s)?,
            serde_json::Value::Bool(b) => d.set_item(key, b)?,
            other => d.set_item(key, other.to_string())?,
        }
    }
    Ok(d)
}

/// `axisym(profile, material, *, force=None, depth=None, n=2001, method="fft")`: axisymmetric
/// normal contact by the MDR (Willert et al. 2021, Eqs. 7, 12/13, 17; graded media Eqs. 23–29),
/// as `halfspace axisym`. Returns a dict: the CLI's JSON keys and the arrays `r`, `pressure`,
/// `displacement` (m, Pa, m).
#[pyfunction]
#[pyo3(signature = (profile, material, *, force=None, depth=None, n=2001, method="fft", table=None))]
#[allow(clippy::too_many_arguments)]
fn axisym<'py>(
    py: Python<'py>,
    profile: &str,
    material: &str,
    force: Option<f64>,
    depth: Option<f64>,
    n: usize,
    method: &str,
    table: Option<(Vec<f64>, Vec<f64>)>,
) -> PyResult<Bound<'py, PyDict>> {
    // A profile given as arrays `(r, f)` (the Python `Table`) is the `table:FILE.npy` profile
    // without the file.
    let profile = match table {
        Some((r, f)) => Profile::tabulated(r, f).map_err(|e| err(format!("profile table: {e}")))?,
        None => parse_profile(profile, "profile").map_err(err)?,
    };
    let material = parse_material(material, "material").map_err(err)?;
    let load = match (force, depth) {
        (Some(f), None) => Load::Force(f),
        (None, Some(d)) => Load::Depth(d),
        _ => return Err(err("give exactly one of force= and depth=")),
    };
    let backend = match method {
        "fft" => Backend::Fft,
        "mvm" => Backend::Mvm,
        other => return Err(err(format!("method '{other}': fft or mvm"))),
    };
    let params = ContactParams {
        nodes: n,
        backend,
        ..ContactParams::default()
    };
    let sol = interruptible(py, |_| {
        let mut solver = ContactSolver::new(material, params)?;
        solver.solve(&profile, load)
    })?
    .map_err(err)?;
    let d = PyDict::new(py);
    d.set_item("contact_radius", sol.contact_radius)?;
    d.set_item("depth", sol.depth)?;
    d.set_item("force", sol.force)?;
    d.set_item("max_pressure", sol.max_pressure())?;
    d.set_item("mean_pressure", sol.mean_pressure())?;
    d.set_item("normal_stiffness", sol.normal_stiffness())?;
    d.set_item("pressure_singular", sol.pressure_is_singular())?;
    d.set_item("iterations", sol.iterations)?;
    d.set_item("n", n)?;
    d.set_item("method", backend.name())?;
    d.set_item("k", material.grading_exponent())?;
    d.set_item("contact_modulus", material.contact_modulus())?;
    d.set_item("r", PyArray1::from_vec(py, sol.radii()))?;
    d.set_item("pressure", PyArray1::from_vec(py, sol.pressure.clone()))?;
    d.set_item(
        "displacement",
        PyArray1::from_vec(py, sol.displacement.clone()),
    )?;
    Ok(d)
}

/// `fretting_wear(*, chi=0.5, n=2001, tol=None, dtau=None, tau_end=30.0, method="fft")`: the MDR
/// fretting-wear simulation of a parabolic indenter in partial slip (Willert et al. 2021,
/// Section 4; docs/theory-mdr.md#fretting-wear), dimensionless, as `halfspace fretting-wear`. Returns a dict: the
/// CLI's JSON keys and `r`, `profile` (final worn profile), `limiting_profile`, `tau_history`,
/// `contact_radius_history` (a/a₀, the touching region, per step), `loaded_radius_history`.
/// Adaptive steps at `tol` (default 1e-4) unless `dtau` fixes the step.
#[pyfunction]
#[pyo3(signature = (*, chi=0.5, n=2001, tol=None, dtau=None, tau_end=30.0, method="fft", material=None, length=None))]
#[allow(clippy::too_many_arguments)]
fn fretting_wear<'py>(
    py: Python<'py>,
    chi: f64,
    n: usize,
    tol: Option<f64>,
    dtau: Option<f64>,
    tau_end: f64,
    method: &str,
    material: Option<&str>,
    length: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let backend = match method {
        "fft" => Backend::Fft,
        "mvm" => Backend::Mvm,
        other => return Err(err(format!("method '{other}': fft or mvm"))),
    };
    let medium = match material {
        Some(spec) => parse_wear_medium(spec, "material").map_err(err)?,
        None => WearMedium { k: 0.0, nu: None },
    };
    let length = length.unwrap_or_else(|| FrettingParams::default_length(chi, medium.k));
    let stepping = match (dtau, tol) {
        (Some(_), Some(_)) => {
            return Err(err(
                "give tol (adaptive steps) or dtau (fixed step), not both".to_string(),
            ))
        }
        (Some(dtau), None) => TimeStepping::Fixed { dtau },
        (None, tol) => TimeStepping::Adaptive {
            tolerance: tol.unwrap_or(TimeStepping::DEFAULT_TOLERANCE),
        },
    };
    let mut params = FrettingParams {
        chi,
        k: medium.k,
        nodes: n,
        stepping,
        tau_end,
        backend,
        length,
        ..FrettingParams::default()
    };
    params.snapshots.retain(|t| *t <= tau_end + 1e-12);
    // Ctrl-C: the run stops after the wear step it is in (KeyboardInterrupt).
    let sim = interruptible(py, |cancel| {
        let mut sim = FrettingSimulation::new(params)?;
        sim.run(|_| cancel.load(Ordering::Relaxed))?;
        Ok::<_, halfspace::fretting::FrettingError>(sim)
    })?
    .map_err(err)?;
    let state = sim.state();
    let d = json_dict(py, &wear_summary(&sim, &medium))?;
    d.set_item("r", PyArray1::from_vec(py, sim.grid().coordinates()))?;
    d.set_item("profile", PyArray1::from_vec(py, state.profile.clone()))?;
    d.set_item(
        "limiting_profile",
        PyArray1::from_vec(py, sim.limiting_profile().to_vec()),
    )?;
    d.set_item(
        "tau_history",
        PyArray1::from_vec(py, state.tau_history.clone()),
    )?;
    d.set_item(
        "contact_radius_history",
        PyArray1::from_vec(py, state.contact_radius_history.clone()),
    )?;
    d.set_item(
        "loaded_radius_history",
        PyArray1::from_vec(py, state.loaded_radius_history.clone()),
    )?;
    Ok(d)
}

/// `contact3d(indenter, material, ...)`: one 3D contact (`sam::drivers::one_contact::solve_contact`), as
/// `halfspace contact3d`: returns `(summary_json, arrays)` — the CLI's JSON keys, and the arrays of
/// `halfspace::records::contact_record` (what `contact3d --out` writes): the surface fields `x`,
/// `y`, `pressure`, `shear_x/y`, `slip_x/y`, `stick` shaped (N₁, N₂), with `subsurface` the volume
/// fields (`stress_xx` … `von_mises`, `tresca`, principal stresses, material, eigenstrains) shaped
/// (layers, N₁, N₂), and with inhomogeneities the eigen-displacements `eigen_displacement_1..3`.
#[pyfunction]
#[pyo3(signature = (indenter, material, *, force=None, depth=None, indenter_material="rigid",
    shift_x=None, tangential_force=None, friction=0.0, grid=128, extent=None, tol=1e-10,
    inhomogeneities=Vec::new(), subsurface=None))]
#[allow(clippy::too_many_arguments)]
fn contact3d<'py>(
    py: Python<'py>,
    indenter: &str,
    material: &str,
    force: Option<f64>,
    depth: Option<f64>,
    indenter_material: &str,
    shift_x: Option<f64>,
    tangential_force: Option<f64>,
    friction: f64,
    grid: usize,
    extent: Option<f64>,
    tol: f64,
    inhomogeneities: Vec<String>,
    subsurface: Option<f64>,
) -> PyResult<(String, Bound<'py, PyDict>)> {
    let load = match (force, depth) {
        (Some(w), None) if w.is_finite() && w > 0.0 => NormalLoad::Force(w),
        (None, Some(d)) if d.is_finite() && d > 0.0 => NormalLoad::Approach(d),
        (Some(_), None) | (None, Some(_)) => {
            return Err(err("force / depth must be finite and > 0"))
        }
        _ => return Err(err("give exactly one of force= and depth=")),
    };
    let tangential = match (shift_x, tangential_force) {
        (Some(dx), None) => Some(TangentialLoad::Shift(dx)),
        (None, Some(q)) => Some(TangentialLoad::Force(q)),
        (None, None) => None,
        _ => return Err(err("give at most one of shift_x= and tangential_force=")),
    };
    let case = ContactCase {
        indenter: parse_indenter(indenter, "indenter").map_err(err)?,
        indenter_body: parse_body(indenter_material, "indenter_material").map_err(err)?,
        half_space: parse_body(material, "material").map_err(err)?,
        load,
        tangential,
        friction,
        grid,
        extent,
        tolerance: tol,
        inhomogeneities: inhomogeneities
            .iter()
            .map(|s| parse_inhomogeneity(s, "inhomogeneity"))
            .collect::<Result<Vec<_>, _>>()
            .map_err(err)?,
        subsurface_depth: subsurface,
    };
    let outcome = interruptible(py, |_| solve_contact(&case))?.map_err(err)?;
    let summary = contact_summary(&outcome, &case);
    let grid = *outcome.solver.problem().grid();
    let rec = contact_record(&outcome, &summary);
    let d = PyDict::new(py);
    for (name, values) in &rec.arrays {
        // The record's surface arrays are per cell (row-major): shaped (N₁, N₂) here.
        let shape = match rec.shape_of(name) {
            Some(s) if s.len() > 1 => s,
            _ => vec![grid.n1, grid.n2],
        };
        d.set_item(name, PyArray1::from_vec(py, values.clone()).reshape(shape)?)?;
    }
    if let Some(n) = outcome.solver.nested() {
        for (c, u) in n.eigen_displacements().iter().enumerate() {
            d.set_item(
                format!("eigen_displacement_{}", c + 1),
                PyArray1::from_vec(py, u.clone()).reshape([grid.n1, grid.n2])?,
            )?;
        }
    }
    Ok((summary.to_string(), d))
}

/// The fretting loop of [LN11] (`sam::drivers::fretting_loop::FrettingLoop`), increment by increment.
#[pyclass(name = "_FrettingLoop", module = "halfspace._halfspace")]
struct PyFrettingLoop {
    inner: FrettingLoop,
}

#[pymethods]
impl PyFrettingLoop {
    /// `config_json`: the fretting-loop TOML keys as a JSON object (`halfspace::config`).
    #[new]
    #[pyo3(signature = (config_json=None, case="homogeneous", grid=None))]
    fn new(config_json: Option<&str>, case: &str, grid: Option<usize>) -> PyResult<Self> {
        let config = loop_config(config_json)?;
        if config.fatigue.is_some() {
            // The indices are computed by the CLI (halfspace::loop_fatigue); refused here rather
            // than recorded and dropped.
            return Err(err(
                "config: [fatigue] is read by `halfspace fretting-loop` only (not yet by \
                 FrettingLoop); remove it",
            ));
        }
        let case = config.case(case, grid).map_err(err)?;
        Ok(Self {
            inner: FrettingLoop::new(case).map_err(err)?,
        })
    }

    /// Increments in the load path.
    fn __len__(&self) -> usize {
        self.inner.path().len()
    }

    /// Increments done.
    #[getter]
    fn done(&self) -> usize {
        self.inner.rows().len()
    }

    /// One increment (GIL released); its row as a dict, or `None` when the loop is done.
    fn step<'py>(&mut self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let inner = &mut self.inner;
        let row = interruptible(py, |_| inner.step().map(|r| r.copied()))?.map_err(err)?;
        row.map(|r| row_dict(py, &r)).transpose()
    }

    /// Every remaining increment (GIL released). Ctrl-C stops after the increment in progress
    /// (KeyboardInterrupt); the loop keeps every increment done and can continue.
    fn run(&mut self, py: Python<'_>) -> PyResult<()> {
        let inner = &mut self.inner;
        interruptible(py, |cancel| {
            inner.run(|_| {
                if cancel.load(Ordering::Relaxed) {
                    std::ops::ControlFlow::Break(())
                } else {
                    std::ops::ControlFlow::Continue(())
                }
            })
        })?
        .map_err(err)?;
        Ok(())
    }

    /// The rows so far: one array per field (`LoopRow::FIELDS`).
    fn rows<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (f, name) in LoopRow::FIELDS.iter().enumerate() {
            let v: Vec<f64> = self.inner.rows().iter().map(|r| r.values()[f]).collect();
            d.set_item(*name, PyArray1::from_vec(py, v))?;
        }
        Ok(d)
    }

    /// The fields at the points A–D reached so far: label → {name: (N₁, N₂) array}.
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let grid = *self.inner.solver().problem().grid();
        let (n1, n2) = (grid.n1, grid.n2);
        let out = PyDict::new(py);
        for p in self.inner.points() {
            let d = PyDict::new(py);
            let put = |name: &str, v: &[f64]| -> PyResult<()> {
                d.set_item(name, PyArray1::from_vec(py, v.to_vec()).reshape([n1, n2])?)
            };
            put("pressure", &p.pressure)?;
            put("shear_x", &p.shear[0])?;
            put("shear_y", &p.shear[1])?;
            put("slip_x", &p.slip[0])?;
            put("slip_y", &p.slip[1])?;
            put("stick", &p.stick)?;
            if let Some(u) = &p.eigen_displacement {
                for (c, v) in u.iter().enumerate() {
                    put(&format!("eigen_displacement_{}", c + 1), v)?;
                }
            }
            if let Some(vm) = &p.von_mises {
                let layers = vm.len() / (n1 * n2).max(1);
                d.set_item(
                    "von_mises",
                    PyArray1::from_vec(py, vm.clone()).reshape([layers, n1, n2])?,
                )?;
            }
            d.set_item("increment", p.increment)?;
            out.set_item(p.label, d)?;
        }
        Ok(out)
    }

    /// The metrics of the completed loop (an error before it is done).
    fn metrics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let m = self.inner.metrics().map_err(err)?;
        let d = PyDict::new(py);
        d.set_item("dissipated_energy", m.dissipated_energy)?;
        d.set_item("ratchet", m.ratchet)?;
        d.set_item(
            "tangential_force_over_mu_w_at_amplitude",
            m.tangential_force_over_mu_w_at_amplitude,
        )?;
        d.set_item(
            "max_pressure_over_p0_end_of_normal_loading",
            m.max_pressure_over_p0_end_of_normal_loading,
        )?;
        d.set_item(
            "contact_area_over_hertz_end_of_normal_loading",
            m.contact_area_over_hertz_end_of_normal_loading,
        )?;
        d.set_item(
            "approach_over_hertz_end_of_normal_loading",
            m.approach_over_hertz_end_of_normal_loading,
        )?;
        d.set_item("max_transverse_slip", m.max_transverse_slip)?;
        d.set_item("sliding_fraction", m.sliding_fraction)?;
        d.set_item("regime", m.regime as i64)?;
        d.set_item("energy_ratio", m.energy_ratio)?;
        d.set_item("unloading_stiffness", m.unloading_stiffness)?;
        d.set_item("increments", self.inner.rows().len())?;
        d.set_item("grid", self.inner.case().grid)?;
        if let Some(n) = self.inner.solver().nested() {
            d.set_item("inclusion_cells", n.inclusions().len())?;
            d.set_item("layers", n.inclusions().layers.len())?;
        }
        Ok(d)
    }

    /// Labels of the points A–D.
    #[staticmethod]
    fn point_labels() -> Vec<&'static str> {
        POINT_LABELS.to_vec()
    }
}

/// The fretting-loop configuration from its JSON text (the Python dict), or the default.
fn loop_config(config_json: Option<&str>) -> PyResult<LoopConfig> {
    match config_json {
        Some(text) => serde_json::from_str(text).map_err(|e| err(format!("config: {e}"))),
        None => Ok(LoopConfig::default()),
    }
}

/// The fretting map of the config over `loads × amplitudes` (`LoopConfig::map`).
fn build_map(
    config_json: Option<&str>,
    case: &str,
    grid: Option<usize>,
    loads: Vec<f64>,
    amplitudes: Vec<f64>,
) -> PyResult<FrettingMap> {
    loop_config(config_json)?
        .map(case, grid, loads, amplitudes)
        .map_err(err)
}

/// `_fretting_map(config_json, case, grid, loads, amplitudes)`: every point of the fretting map
/// (`halfspace::fretting_map::run_map` on the local cores, GIL released), as
/// `halfspace fretting-map`: a dict of `loads`, `amplitudes` and the fields of
/// `MapPoint::FIELDS` shaped (len(loads), len(amplitudes)).
#[pyfunction]
#[pyo3(signature = (config_json, case, grid, loads, amplitudes))]
fn fretting_map<'py>(
    py: Python<'py>,
    config_json: Option<&str>,
    case: &str,
    grid: Option<usize>,
    loads: Vec<f64>,
    amplitudes: Vec<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let map = build_map(config_json, case, grid, loads, amplitudes)?;
    let run = interruptible(py, |cancel| {
        run_map_until(&map, None, None, |_, _| {}, &|| {
            cancel.load(Ordering::Relaxed)
        })
    })?
    .map_err(|e| match e {
        MapError::Cancelled => err("the map was cancelled"),
        e => err(e),
    })?;
    let points = run.complete().ok_or_else(|| err("the map is incomplete"))?;
    let (rows, cols) = map.shape();
    let d = PyDict::new(py);
    d.set_item("loads", PyArray1::from_vec(py, map.loads().to_vec()))?;
    d.set_item(
        "amplitudes",
        PyArray1::from_vec(py, map.amplitudes().to_vec()),
    )?;
    for (f, name) in MapPoint::FIELDS.iter().enumerate().skip(2) {
        let v: Vec<f64> = points.iter().map(|p| p.values()[f]).collect();
        d.set_item(*name, PyArray1::from_vec(py, v).reshape([rows, cols])?)?;
    }
    Ok(d)
}

/// `_fretting_map_shape(config_json, case, grid, loads, amplitudes)`: builds the map (every check
/// of the configuration and the axes, no loop run) and returns its shape.
#[pyfunction]
#[pyo3(signature = (config_json, case, grid, loads, amplitudes))]
fn fretting_map_shape(
    config_json: Option<&str>,
    case: &str,
    grid: Option<usize>,
    loads: Vec<f64>,
    amplitudes: Vec<f64>,
) -> PyResult<(usize, usize)> {
    let map = build_map(config_json, case, grid, loads, amplitudes)?;
    Ok(map.shape())
}

/// `_fretting_map_point(config_json, case, grid, loads, amplitudes, i, j)`: point `(i, j)` of the
/// same map (one task of a distributed map; GIL released): the values of `MapPoint::FIELDS`.
#[pyfunction]
#[pyo3(signature = (config_json, case, grid, loads, amplitudes, i, j))]
#[allow(clippy::too_many_arguments)]
fn fretting_map_point(
    py: Python<'_>,
    config_json: Option<&str>,
    case: &str,
    grid: Option<usize>,
    loads: Vec<f64>,
    amplitudes: Vec<f64>,
    i: usize,
    j: usize,
) -> PyResult<Vec<f64>> {
    let map = build_map(config_json, case, grid, loads, amplitudes)?;
    let point = interruptible(py, |cancel| {
        map.run_point_until(i, j, &|| cancel.load(Ordering::Relaxed))
    })?
    .map_err(err)?;
    Ok(point.values().to_vec())
}

fn row_dict<'py>(py: Python<'py>, r: &LoopRow) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, v) in LoopRow::FIELDS.iter().zip(r.values()) {
        d.set_item(*name, v)?;
    }
    Ok(d)
}

#[pymodule]
fn _halfspace(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // Import NumPy's C API now, while the GIL is held and no signal is pending: imported lazily at
    // the first array, after a Ctrl-C in a first long call, the import fails and rust-numpy panics
    // ("Failed to access NumPy array API capsule").
    let _ = PyArray1::<f64>::zeros(m.py(), 0, false);
    m.add("HalfspaceError", m.py().get_type::<HalfspaceError>())?;
    m.add_function(wrap_pyfunction!(axisym, m)?)?;
    m.add_function(wrap_pyfunction!(fretting_wear, m)?)?;
    m.add_function(wrap_pyfunction!(contact3d, m)?)?;
    m.add_function(wrap_pyfunction!(fretting_map, m)?)?;
    m.add_function(wrap_pyfunction!(fretting_map_point, m)?)?;
    m.add_function(wrap_pyfunction!(fretting_map_shape, m)?)?;
    m.add("MAP_FIELDS", MapPoint::FIELDS.to_vec())?;
    m.add_class::<PyFrettingLoop>()?;
    Ok(())
}
