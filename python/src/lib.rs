//! `halfspace._halfspace`: the Rust side of the Python package, over the application layer
//! (`halfspace-cases`, docs/architecture.md) and the libraries only — no CLI dependency. Thin:
//! every function reads its inputs as a case of the application layer (`axisym`, `contact3d`,
//! `fretting_wear`, `config`: a Python dict goes to serde as TOML data, [`toml_value`], never as
//! text; `kind:key=value` values through the one parser, `spec`), validated there, calls the
//! library's driver with the GIL released, and returns the application layer's summary (a dict)
//! and NumPy arrays; the typed classes and result objects live in `halfspace/__init__.py`. Errors
//! are `halfspace.HalfspaceError` (a `ValueError`) carrying the library's message, or `TypeError`
//! for a configuration value of the wrong type.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::RecvTimeoutError;
use std::time::Duration;

use numpy::{PyArray1, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use halfspace_cases as halfspace;

use halfspace::axisym::AxisymConfig;
use halfspace::config::{
    from_table, is_type_error, FatigueConfig, LoopConfig, Names, Wear3dConfig,
};
use halfspace::contact3d::Contact3dConfig;
use halfspace::fretting::FrettingSimulation;
use halfspace::fretting_map::{crack_risk, run_map_with, MapError};
use halfspace::fretting_wear::{resume_state, WearConfig, WearRunCase};
use halfspace::loop_fatigue::{evaluate_loop_fatigue, LoopFatigue, FATIGUE_FIELDS};
use halfspace::records::{
    contact_record, contact_summary, loop_summary, wear3d_estimate_summary, wear3d_summary,
    wear_summary,
};
use halfspace::sam::drivers::fretting_loop::{FrettingLoop, LoopRow, POINT_LABELS};
use halfspace::sam::drivers::fretting_map::{FrettingMap, MapPoint};
use halfspace::sam::drivers::fretting_wear3d::{FrettingWear3d, WearCase, WearRow};
use halfspace::sam::drivers::one_contact::solve_contact;

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

/// A summary (a JSON object: the CLI's keys) as a dict: integers as `int`, other numbers as
/// `float`, objects as dicts, arrays as lists.
fn json_dict<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (key, v) in value.as_object().into_iter().flatten() {
        d.set_item(key, json_py(py, v)?)?;
    }
    Ok(d)
}

fn json_py<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    Ok(match value {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) if n.is_i64() => {
            n.as_i64().unwrap_or_default().into_pyobject(py)?.into_any()
        }
        Value::Number(n) if n.is_u64() => {
            n.as_u64().unwrap_or_default().into_pyobject(py)?.into_any()
        }
        Value::Number(n) => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(json_py(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(_) => json_dict(py, value)?.into_any(),
    })
}

/// `axisym(config)`: axisymmetric normal contact by the MDR (Willert et al. 2021, Eqs. 7, 12/13,
/// 17; graded media Eqs. 23–29), as `halfspace axisym`: `config` a dict of its keys
/// (`halfspace_cases::axisym::AxisymConfig`: `profile` a spec or `{r, f}` arrays, `material`,
/// `force` or `depth`, `n`, `method`, `domain_ratio`). Returns a dict: the CLI's JSON keys and the
/// arrays `r`, `pressure`, `displacement` (m, Pa, m).
#[pyfunction]
fn axisym<'py>(py: Python<'py>, config: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
    let case = from_table::<AxisymConfig>(config_table(config, "axisym")?, "config")
        .map_err(config_error)?
        .case(Names::Keys)
        .map_err(err)?;
    let sol = interruptible(py, |_| case.solve())?.map_err(err)?;
    let d = json_dict(py, &case.summary(&sol))?;
    d.set_item("r", PyArray1::from_vec(py, sol.radii()))?;
    d.set_item("pressure", PyArray1::from_vec(py, sol.pressure.clone()))?;
    d.set_item(
        "displacement",
        PyArray1::from_vec(py, sol.displacement.clone()),
    )?;
    Ok(d)
}

/// `fretting_wear(config)`: the MDR fretting-wear simulation of a parabolic indenter in partial
/// slip (Willert et al. 2021, Section 4; docs/theory-mdr.md#fretting-wear), dimensionless, as
/// `halfspace fretting-wear`: `config` a dict of its keys
/// (`halfspace_cases::fretting_wear::WearConfig`). Returns a dict: the CLI's JSON keys and `r`,
/// `profile` (final worn profile), `limiting_profile`, `tau_history`, `contact_radius_history`
/// (a/a₀, the touching region, per step), `loaded_radius_history`. `resume`: a run directory of
/// `halfspace fretting-wear` made with the same parameters — the run continues from its checkpoint
/// (`halfspace_cases::fretting_wear::resume_state`, the command line's `--resume` checks, the
/// adaptive scheme's refusal among them) to the uninterrupted run's result bit for bit; the
/// directory is only read.
#[pyfunction]
#[pyo3(signature = (config, resume=None))]
fn fretting_wear<'py>(
    py: Python<'py>,
    config: &Bound<'py, PyAny>,
    resume: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let WearRunCase { params, medium } =
        from_table::<WearConfig>(config_table(config, "fretting-wear")?, "config")
            .map_err(config_error)?
            .case(Names::Keys)
            .map_err(err)?;
    let start = match &resume {
        Some(dir) => Some(resume_state(dir, &params).map_err(err)?),
        None => None,
    };
    // Ctrl-C: the run stops after the wear step it is in (KeyboardInterrupt).
    let sim = interruptible(py, |cancel| {
        let mut sim = match start {
            Some(state) => FrettingSimulation::resume(params, state)?,
            None => FrettingSimulation::new(params)?,
        };
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

/// `contact3d(config)`: one 3D contact (`sam::drivers::one_contact::solve_contact`), as
/// `halfspace contact3d`: `config` a dict of its keys
/// (`halfspace_cases::contact3d::Contact3dConfig`). Returns `(summary, arrays)` — the CLI's JSON
/// keys, and the arrays of `halfspace::records::contact_record` (what `contact3d --out` writes):
/// the surface fields `x`, `y`, `pressure`, `shear_x/y`, `slip_x/y`, `stick` shaped (N₁, N₂), with
/// `subsurface` the volume fields (`stress_xx` … `von_mises`, `tresca`, principal stresses,
/// material, eigenstrains) shaped (layers, N₁, N₂), and with inhomogeneities the
/// eigen-displacements `eigen_displacement_1..3`.
#[pyfunction]
fn contact3d<'py>(
    py: Python<'py>,
    config: &Bound<'py, PyAny>,
) -> PyResult<(Bound<'py, PyDict>, Bound<'py, PyDict>)> {
    let case = from_table::<Contact3dConfig>(config_table(config, "contact3d")?, "config")
        .map_err(config_error)?
        .case(Names::Keys)
        .map_err(err)?;
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
    Ok((json_dict(py, &summary)?, d))
}

/// The fretting loop of [LN11] (`sam::drivers::fretting_loop::FrettingLoop`), increment by increment.
#[pyclass(name = "_FrettingLoop", module = "halfspace._halfspace")]
struct PyFrettingLoop {
    inner: FrettingLoop,
    /// The `[fatigue]` table of the config (the loop then records its cycle's stress history).
    fatigue_config: Option<FatigueConfig>,
    /// The indices once evaluated (`fatigue()`; the completed loop does not change).
    fatigue: Option<LoopFatigue>,
}

#[pymethods]
impl PyFrettingLoop {
    /// `config`: a dict of the fretting-loop keys (`halfspace_cases::config::LoopConfig`).
    #[new]
    #[pyo3(signature = (config=None, case="homogeneous", grid=None))]
    fn new(config: Option<&Bound<'_, PyAny>>, case: &str, grid: Option<usize>) -> PyResult<Self> {
        let config = loop_config(config)?;
        let case = config.case(case, grid).map_err(err)?;
        Ok(Self {
            inner: FrettingLoop::new(case).map_err(err)?,
            fatigue_config: config.fatigue_config(),
            fatigue: None,
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
        json_dict(py, &loop_summary(&self.inner, &m))
    }

    /// The fatigue indices of the completed loop (`[fatigue]`; docs/fatigue.md, "On the fretting
    /// loop"): `halfspace_cases::loop_fatigue::evaluate_loop_fatigue` (GIL released) once, as
    /// `halfspace fretting-loop`. Returns `(summary, arrays)`: the CLI's JSON keys
    /// (`LoopFatigue::summary`: `crossland_max`, `crossland_max_at` [x, y, z] m, … and the
    /// `fatigue` block) and the datasets of its results.h5 (`LoopFatigue::record`): `z` (layer
    /// depths, m), the four fields (`FATIGUE_FIELDS`) shaped (layers, N₁, N₂), with `x`, `y`
    /// (cell centres, m). An error without `[fatigue]` or before the loop is done.
    fn fatigue<'py>(
        &mut self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyDict>, Bound<'py, PyDict>)> {
        if self.fatigue.is_none() {
            let cfg = self.fatigue_config.as_ref().ok_or_else(|| {
                err("fatigue: the config has no [fatigue] table (the criteria's constants)")
            })?;
            if self.inner.rows().len() < self.inner.path().len() {
                return Err(err(format!(
                    "fatigue: the loop is not done ({} of {} increments); run it first",
                    self.inner.rows().len(),
                    self.inner.path().len()
                )));
            }
            let inner = &mut self.inner;
            let f = interruptible(py, |_| evaluate_loop_fatigue(inner, cfg))?.map_err(err)?;
            self.fatigue = Some(f);
        }
        let Some(f) = &self.fatigue else {
            return Err(err("fatigue: not evaluated"));
        };
        let d = PyDict::new(py);
        d.set_item("x", PyArray1::from_vec(py, f.x.clone()))?;
        d.set_item("y", PyArray1::from_vec(py, f.y.clone()))?;
        // The record the CLI writes (one writer): `z` and the four fields.
        let rec = f.record(halfspace::data::Record::default());
        for (name, values) in &rec.arrays {
            let array = PyArray1::from_vec(py, values.clone());
            match rec.shape_of(name) {
                Some(shape) if shape.len() > 1 => d.set_item(name, array.reshape(shape)?)?,
                _ => d.set_item(name, array)?,
            }
        }
        Ok((json_dict(py, &f.summary())?, d))
    }

    /// Labels of the points A–D.
    #[staticmethod]
    fn point_labels() -> Vec<&'static str> {
        POINT_LABELS.to_vec()
    }
}

/// A Python value as TOML data for serde (`config::from_table`): dicts with string keys (a `None`
/// value is an absent key: the default), lists and tuples, strings, booleans, integers (64-bit),
/// floats, NumPy arrays and scalars (as their `tolist()`); an object with a `spec()` method (an
/// `Inhomogeneity`) is its `kind:key=value` spec.
/// `path` names the value in errors (`config['grid']`).
fn toml_value(value: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
    use toml::Value;
    if value.is_instance_of::<PyBool>() {
        return Ok(Value::Boolean(value.extract()?));
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(Value::Float(value.extract()?));
    }
    // NumPy arrays and scalars (an `ndarray` has `__index__`, which fails for floats and
    // arrays): their Python values (`tolist()`: a number, or nested lists).
    if !value.is_instance_of::<PyInt>() && value.hasattr("tolist")? && value.hasattr("dtype")? {
        return toml_value(&value.call_method0("tolist")?, path);
    }
    if value.is_instance_of::<PyInt>() || value.hasattr("__index__")? {
        return value.extract::<i64>().map(Value::Integer).map_err(|_| {
            err(format!(
                "{path} = {value}: an integer beyond 64 bits (must be < 2**63)"
            ))
        });
    }
    if let Ok(s) = value.cast::<PyString>() {
        return Ok(Value::String(s.to_str()?.to_string()));
    }
    if let Ok(d) = value.cast::<PyDict>() {
        return Ok(Value::Table(toml_table(d, path)?));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (k, v) in value.try_iter()?.enumerate() {
            items.push(toml_value(&v?, &format!("{path}[{k}]"))?);
        }
        return Ok(Value::Array(items));
    }
    if value.hasattr("spec")? {
        return toml_value(&value.call_method0("spec")?, path);
    }
    Err(PyTypeError::new_err(format!(
        "{path} must be a number, a string, a list or a dict, got {value}"
    )))
}

fn toml_table(d: &Bound<'_, PyDict>, path: &str) -> PyResult<toml::Table> {
    let mut table = toml::Table::new();
    for (k, v) in d.iter() {
        let key = k
            .cast::<PyString>()
            .map_err(|_| PyTypeError::new_err(format!("{path}: keys must be strings, got {k}")))?
            .to_str()?
            .to_string();
        if v.is_none() {
            continue;
        }
        let item = toml_value(&v, &format!("{path}['{key}']"))?;
        table.insert(key, item);
    }
    Ok(table)
}

/// The fretting-loop configuration of a Python dict (serde on its data), or the default.
fn loop_config(config: Option<&Bound<'_, PyAny>>) -> PyResult<LoopConfig> {
    let Some(config) = config.filter(|c| !c.is_none()) else {
        return Ok(LoopConfig::default());
    };
    from_table(config_table(config, "fretting-loop")?, "config").map_err(config_error)
}

/// A config dict as TOML data (`what` names the keys it should hold in the error).
fn config_table(config: &Bound<'_, PyAny>, what: &str) -> PyResult<toml::Table> {
    if !config.is_instance_of::<PyDict>() {
        return Err(PyTypeError::new_err(format!(
            "config must be a dict of the {what} keys, got {config}"
        )));
    }
    toml_table(config.cast::<PyDict>()?, "config")
}

/// A refused configuration: `TypeError` for a value of the wrong type, else `HalfspaceError`.
fn config_error(e: halfspace::spec::SpecError) -> PyErr {
    if is_type_error(&e) {
        PyTypeError::new_err(e.0)
    } else {
        err(e)
    }
}

/// The fretting map of the config over `loads × amplitudes` (`LoopConfig::map`) and its
/// `[fatigue]` constants, if any (each point's `crack_risk`, as `halfspace fretting-map`).
fn build_map(
    config: Option<&Bound<'_, PyAny>>,
    case: &str,
    grid: Option<usize>,
    loads: Vec<f64>,
    amplitudes: Vec<f64>,
) -> PyResult<(FrettingMap, Option<FatigueConfig>)> {
    let cfg = loop_config(config)?;
    let map = cfg.map(case, grid, loads, amplitudes).map_err(err)?;
    Ok((map, cfg.fatigue_config()))
}

/// `_fretting_map(config, case, grid, loads, amplitudes)`: every point of the fretting map
/// (`halfspace::fretting_map::run_map` on the local cores, GIL released), as
/// `halfspace fretting-map`: a dict of `loads`, `amplitudes` and the fields of
/// `MapPoint::FIELDS` shaped (len(loads), len(amplitudes)).
#[pyfunction]
#[pyo3(signature = (config, case, grid, loads, amplitudes))]
fn fretting_map<'py>(
    py: Python<'py>,
    config: Option<&Bound<'py, PyAny>>,
    case: &str,
    grid: Option<usize>,
    loads: Vec<f64>,
    amplitudes: Vec<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let (map, fatigue) = build_map(config, case, grid, loads, amplitudes)?;
    let run = interruptible(py, |cancel| {
        run_map_with(&map, fatigue.as_ref(), None, None, |_, _| {}, &|| {
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

/// `_fretting_map_shape(config, case, grid, loads, amplitudes)`: builds the map (every check
/// of the configuration and the axes, no loop run) and returns its shape.
#[pyfunction]
#[pyo3(signature = (config, case, grid, loads, amplitudes))]
fn fretting_map_shape(
    config: Option<&Bound<'_, PyAny>>,
    case: &str,
    grid: Option<usize>,
    loads: Vec<f64>,
    amplitudes: Vec<f64>,
) -> PyResult<(usize, usize)> {
    let (map, _) = build_map(config, case, grid, loads, amplitudes)?;
    Ok(map.shape())
}

/// `_fretting_map_point(config, case, grid, loads, amplitudes, i, j)`: point `(i, j)` of the
/// same map (one task of a distributed map; GIL released): the values of `MapPoint::FIELDS`.
#[pyfunction]
#[pyo3(signature = (config, case, grid, loads, amplitudes, i, j))]
#[allow(clippy::too_many_arguments)]
fn fretting_map_point(
    py: Python<'_>,
    config: Option<&Bound<'_, PyAny>>,
    case: &str,
    grid: Option<usize>,
    loads: Vec<f64>,
    amplitudes: Vec<f64>,
    i: usize,
    j: usize,
) -> PyResult<Vec<f64>> {
    let (map, fatigue) = build_map(config, case, grid, loads, amplitudes)?;
    let risk = |lp: &FrettingLoop| match &fatigue {
        Some(cfg) => crack_risk(lp, cfg),
        None => Ok(f64::NAN),
    };
    let point = interruptible(py, |cancel| {
        map.run_point_with(i, j, &|| cancel.load(Ordering::Relaxed), &risk)
    })?
    .map_err(err)?;
    Ok(point.values().to_vec())
}

/// The 3D wear case of a config dict (`Wear3dConfig::from_table`, validated once) with `grid`
/// overriding its grid: what `fretting_wear3d` runs and `fretting_wear3d_estimate` estimates.
fn wear3d_case(config: &Bound<'_, PyAny>, grid: Option<usize>) -> PyResult<WearCase> {
    let table = config_table(config, "fretting-wear3d")?;
    Wear3dConfig::from_table(table, "config")
        .map_err(config_error)?
        .case(grid)
        .map_err(err)
}

/// `fretting_wear3d(config, grid=None)`: 3D fretting wear on the SAM solver
/// (`sam::drivers::fretting_wear3d`, docs/wear3d.md), as `halfspace fretting-wear3d`: `config` a
/// dict of the fretting-loop keys and a `wear` dict (`halfspace_cases::config::Wear3dConfig`),
/// `grid` overriding its grid. Runs every wear step with the GIL released (Ctrl-C stops after the
/// step in progress: KeyboardInterrupt). Returns a dict: the CLI's JSON keys
/// (`records::wear3d_summary`), `x`, `y` (cell centres, m), `wear_depth` (N₁, N₂; m) and the
/// history per wear step, `{field}_history` for each field of `WearRow::FIELDS`.
#[pyfunction]
#[pyo3(signature = (config, grid=None))]
fn fretting_wear3d<'py>(
    py: Python<'py>,
    config: &Bound<'py, PyAny>,
    grid: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let case = wear3d_case(config, grid)?;
    let start = std::time::Instant::now();
    let run = interruptible(py, |cancel| {
        let mut run = FrettingWear3d::new(case)?;
        run.run(|_| {
            if cancel.load(Ordering::Relaxed) {
                std::ops::ControlFlow::Break(())
            } else {
                std::ops::ControlFlow::Continue(())
            }
        })?;
        Ok::<_, halfspace::sam::SamError>(run)
    })?
    .map_err(err)?;
    let d = json_dict(py, &wear3d_summary(&run, start.elapsed().as_secs_f64()))?;
    let g = *run.grid();
    d.set_item(
        "x",
        PyArray1::from_vec(py, (0..g.n1).map(|i| g.centre(i, 0).0).collect()),
    )?;
    d.set_item(
        "y",
        PyArray1::from_vec(py, (0..g.n2).map(|j| g.centre(0, j).1).collect()),
    )?;
    d.set_item(
        "wear_depth",
        PyArray1::from_vec(py, run.wear_depth().to_vec()).reshape([g.n1, g.n2])?,
    )?;
    for (f, name) in WearRow::FIELDS.iter().enumerate() {
        let v: Vec<f64> = run.history().iter().map(|r| r.values()[f]).collect();
        d.set_item(format!("{name}_history"), PyArray1::from_vec(py, v))?;
    }
    Ok(d)
}

/// `fretting_wear3d_estimate(config, grid=None)`: the up-front estimate of the same run
/// (`WearCase::estimate`, docs/wear3d.md#the-work-estimate), as `halfspace fretting-wear3d
/// --estimate`: runs nothing, writes nothing. Every wear step is given the first step's
/// `ΔN₁ = ⌊min(η δ / r₀, β C_min / (k_p 4A))⌋ ≥ 1` (docs/wear3d.md#the-wear-step-and-cycle-jumping;
/// `r₀` the law's rate at Hertz's `p₀`, `q = μp₀`, over the slip path `4A`), so the wear steps are
/// `Σ_segments ⌈L / ΔN₁⌉ + 1` over the segments `L` between 0, the record cycles and `cycles`.
/// Returns a dict: the CLI's JSON keys (`records::wear3d_estimate_summary`).
#[pyfunction]
#[pyo3(signature = (config, grid=None))]
fn fretting_wear3d_estimate<'py>(
    py: Python<'py>,
    config: &Bound<'py, PyAny>,
    grid: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let case = wear3d_case(config, grid)?;
    let estimate = case.estimate().map_err(err)?;
    json_dict(py, &wear3d_estimate_summary(&case, &estimate))
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
    m.add_function(wrap_pyfunction!(fretting_wear3d, m)?)?;
    m.add_function(wrap_pyfunction!(fretting_wear3d_estimate, m)?)?;
    m.add_function(wrap_pyfunction!(contact3d, m)?)?;
    m.add_function(wrap_pyfunction!(fretting_map, m)?)?;
    m.add_function(wrap_pyfunction!(fretting_map_point, m)?)?;
    m.add_function(wrap_pyfunction!(fretting_map_shape, m)?)?;
    m.add("MAP_FIELDS", MapPoint::FIELDS.to_vec())?;
    m.add("FATIGUE_FIELDS", FATIGUE_FIELDS.to_vec())?;
    m.add_class::<PyFrettingLoop>()?;
    Ok(())
}
