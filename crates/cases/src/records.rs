//! The library's results as named arrays ([`Record`]): what the CLI writes to `.h5` / `.npz` and
//! reads back, one conversion for every front end.

use std::path::Path;

use crate::data::{AttrValue, DataError, Record};
use crate::sam::contact::{
    ContactProblem, ContactSolver, ContactState, EimIterate, NestedWarmStart,
};
use crate::sam::drivers::fretting_loop::CycleSources;
use crate::sam::drivers::fretting_loop::{
    FrettingLoop, LoopCase, LoopMetrics, LoopRow, LoopSnapshot, PointFields, POINT_LABELS,
};
use crate::sam::drivers::fretting_wear3d::{
    CycleEigen, FrettingWear3d, WearCase, WearEstimate, WearRecord, WearRow, WearSnapshot,
};
use crate::sam::drivers::one_contact::{ContactCase, ContactOutcome};
use crate::sam::kernels::surface::Body;
use crate::sam::subsurface::StressField;
use serde_json::json;

/// The rows as one array per field of [`LoopRow::FIELDS`], names prefixed by `prefix`.
pub fn rows_record(mut rec: Record, prefix: &str, rows: &[LoopRow]) -> Record {
    for (f, name) in LoopRow::FIELDS.iter().enumerate() {
        rec = rec.array(
            &format!("{prefix}{name}"),
            rows.iter().map(|r| r.values()[f]).collect(),
        );
    }
    rec
}

/// The fields of one point as `(N₁, N₂)` arrays `{prefix}{name}_{label}` (and the von Mises
/// volume `(layers, N₁, N₂)`).
fn point_record(mut rec: Record, prefix: &str, p: &PointFields, shape: (usize, usize)) -> Record {
    let (n1, n2) = shape;
    let l = p.label;
    let put = |rec: Record, name: &str, v: &[f64]| {
        rec.shaped(&format!("{prefix}{name}_{l}"), v.to_vec(), &[n1, n2])
    };
    rec = put(rec, "pressure", &p.pressure);
    rec = put(rec, "shear_x", &p.shear[0]);
    rec = put(rec, "shear_y", &p.shear[1]);
    rec = put(rec, "slip_x", &p.slip[0]);
    rec = put(rec, "slip_y", &p.slip[1]);
    rec = put(rec, "stick", &p.stick);
    if let Some(u) = &p.eigen_displacement {
        for (c, v) in u.iter().enumerate() {
            rec = put(rec, &format!("eigen_displacement_{}", c + 1), v);
        }
    }
    if let Some(eps) = &p.eigenstrain {
        rec = rec.array(&format!("{prefix}eigenstrain_{l}"), eps.clone());
    }
    if let Some(vm) = &p.von_mises {
        let layers = vm.len() / (n1 * n2).max(1);
        rec = rec.shaped(
            &format!("{prefix}von_mises_{l}"),
            vm.clone(),
            &[layers, n1, n2],
        );
    }
    rec.attr(
        &format!("{prefix}increment_{l}"),
        AttrValue::Int(p.increment as i64),
    )
}

/// The parameters of a loop case as a flat JSON object (the keys of `fretting-loop --config`;
/// the inhomogeneities as text): the identity of a run in its directory's manifest
/// (`halfspace::run_dir`), so that a refusal names the keys that differ.
pub fn case_parameters(case: &LoopCase) -> serde_json::Value {
    let mut v = json!({
        "radius": case.radius,
        "e": case.e,
        "nu": case.nu,
        "friction": case.friction,
        "force": case.force,
        "normal_steps": case.normal_steps,
        "amplitude": case.amplitude,
        "shift_step": case.shift_step,
        "grid": case.grid,
        "extent_over_a": case.extent_over_a,
        "subsurface_depth": case.subsurface_depth,
        "inhomogeneities": format!("{:?}", case.inhomogeneities),
    });
    // The elastic indenter and approach control only when used: a rigid, force-controlled
    // case keeps the manifest of earlier versions.
    if let Some(m) = v.as_object_mut() {
        if let Some(d) = case.approach {
            m.insert("approach".into(), json!(d));
        }
        if let Body::Elastic { e, nu } = case.indenter {
            m.insert("indenter_e".into(), json!(e));
            m.insert("indenter_nu".into(), json!(nu));
        }
        if let Some(d) = case.fatigue_depth {
            m.insert("fatigue_depth".into(), json!(d));
        }
    }
    v
}

/// The EIM warm start of a loop or wear snapshot (eigenstrains and eigen-displacements, now and at
/// the previous commit) as arrays of `rec`; read back by the snapshot readers.
fn warm_start_record(rec: Record, w: &NestedWarmStart) -> Record {
    let u = &w.eigen_displacement;
    let (eps_prev, u_prev) = &w.previous;
    let mut rec = rec
        .array("eigenstrain", w.eigenstrain.clone())
        .array("eigen_displacement_1", u[0].clone())
        .array("eigen_displacement_2", u[1].clone())
        .array("eigen_displacement_3", u[2].clone())
        .array("eigenstrain_previous", eps_prev.clone())
        .array("eigen_displacement_previous_1", u_prev[0].clone())
        .array("eigen_displacement_previous_2", u_prev[1].clone())
        .array("eigen_displacement_previous_3", u_prev[2].clone())
        .attr("committed", AttrValue::Int(w.committed as i64));
    // The last EIM iterates and their images (`NestedWarmStart::iterates`), where kept.
    for (it, suffix) in w.iterates.iter().zip(["", "_previous"]) {
        if let Some(it) = it {
            rec = rec
                .array(&format!("eim_iterate{suffix}"), it.iterate.clone())
                .array(&format!("eim_iterate_image{suffix}"), it.image.clone());
        }
    }
    rec
}

/// The contact state of a loop or wear snapshot as arrays of `rec` (`state_*`); read back by
/// [`contact_state_from_record`].
fn contact_state_record(rec: Record, st: &ContactState) -> Record {
    rec.array("state_pressure", st.pressure.clone())
        .array("state_shear_x", st.shear[0].clone())
        .array("state_shear_y", st.shear[1].clone())
        .array("state_history_x", st.tangential_displacement[0].clone())
        .array("state_history_y", st.tangential_displacement[1].clone())
        .array("state_slip_x", st.slip[0].clone())
        .array("state_slip_y", st.slip[1].clone())
        .array(
            "state_scalars",
            vec![st.shift[0], st.shift[1], st.approach, st.force],
        )
}

/// The contact state of [`contact_state_record`]: the `state_*` members read by `array`, with
/// `scalars` (`state_scalars`: shift x, y, approach, force), whose length the caller checked.
fn contact_state_from_record<E>(
    array: impl Fn(&str) -> Result<Vec<f64>, E>,
    scalars: &[f64],
) -> Result<ContactState, E> {
    Ok(ContactState {
        pressure: array("state_pressure")?,
        shear: [array("state_shear_x")?, array("state_shear_y")?],
        tangential_displacement: [array("state_history_x")?, array("state_history_y")?],
        slip: [array("state_slip_x")?, array("state_slip_y")?],
        shift: [scalars[0], scalars[1]],
        approach: scalars[2],
        force: scalars[3],
    })
}

/// The warm start of [`warm_start_record`]: `eigenstrain` and the other members read by `array`,
/// then `committed` (read last, as the readers always did).
fn warm_start_from_record<E>(
    eigenstrain: Vec<f64>,
    array: impl Fn(&str) -> Result<Vec<f64>, E>,
    optional: impl Fn(&str) -> Option<Vec<f64>>,
    committed: impl FnOnce() -> Result<usize, E>,
) -> Result<NestedWarmStart, E> {
    let iterate = |suffix: &str| -> Result<Option<EimIterate>, E> {
        match optional(&format!("eim_iterate{suffix}")) {
            None => Ok(None),
            Some(iterate) => Ok(Some(EimIterate {
                iterate,
                image: array(&format!("eim_iterate_image{suffix}"))?,
            })),
        }
    };
    let iterates = [iterate("")?, iterate("_previous")?];
    Ok(NestedWarmStart {
        iterates,
        eigenstrain,
        eigen_displacement: [
            array("eigen_displacement_1")?,
            array("eigen_displacement_2")?,
            array("eigen_displacement_3")?,
        ],
        previous: (
            array("eigenstrain_previous")?,
            [
                array("eigen_displacement_previous_1")?,
                array("eigen_displacement_previous_2")?,
                array("eigen_displacement_previous_3")?,
            ],
        ),
        committed: committed()?,
    })
}

/// Everything [`snapshot_from_record`] needs.
pub fn snapshot_record(s: &LoopSnapshot, shape: (usize, usize)) -> Record {
    let rec = rows_record(Record::default(), "", &s.rows)
        .attr("config", AttrValue::Text(s.fingerprint.clone()))
        .attr("next", AttrValue::Int(s.rows.len() as i64))
        .attr(
            "max_transverse_slip",
            AttrValue::Float(s.max_transverse_slip),
        )
        .attr("points", AttrValue::Int(s.points.len() as i64));
    let mut rec = contact_state_record(rec, &s.state);
    for p in &s.points {
        rec = point_record(rec, "point_", p, shape);
    }
    if let Some(w) = &s.eigen {
        rec = warm_start_record(rec, w);
    }
    if let Some(h) = &s.cycle_sources {
        rec = rec
            .array("cycle_tractions", h.tractions.clone())
            .array("cycle_eigenstrain", h.eigenstrain.clone())
            .array(
                "cycle_sources_shape",
                vec![h.cells as f64, h.eigen_len as f64, h.recorded as f64],
            );
    }
    rec
}

/// The inverse of [`snapshot_record`]; `path` names the file in errors.
pub fn snapshot_from_record(rec: &Record, path: &Path) -> Result<LoopSnapshot, DataError> {
    let bad = |message: String| DataError::InvalidContent {
        path: path.to_path_buf(),
        message,
    };
    let int = |name: &str| match rec.get_attr(name) {
        Some(AttrValue::Int(v)) if *v >= 0 => Ok(*v as usize),
        other => Err(bad(format!("attribute {name} is {other:?}"))),
    };
    let array = |name: &str| {
        rec.get(name)
            .map(|v| v.to_vec())
            .ok_or_else(|| bad(format!("array {name} is missing")))
    };
    let fingerprint = match rec.get_attr("config") {
        Some(AttrValue::Text(t)) => t.clone(),
        other => return Err(bad(format!("attribute config is {other:?}"))),
    };
    let next = int("next")?;
    let columns = LoopRow::FIELDS
        .iter()
        .map(|f| array(f))
        .collect::<Result<Vec<_>, _>>()?;
    if columns.iter().any(|c| c.len() != next) {
        return Err(bad("the rows do not match the next increment".into()));
    }
    // Counts are stored as floats: whole and ≥ 0 (a NaN would otherwise read as 0).
    for (f, c) in columns.iter().enumerate() {
        let count = matches!(
            LoopRow::FIELDS[f],
            "alternations" | "outer_iterations" | "eim_iterations"
        );
        if let Some((k, v)) = c
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_finite() || (count && (**v < 0.0 || v.fract() != 0.0)))
        {
            return Err(bad(format!(
                "member {} row {k} = {v}: {}",
                LoopRow::FIELDS[f],
                if count {
                    "a whole count ≥ 0"
                } else {
                    "finite"
                }
            )));
        }
    }
    let rows = (0..next)
        .map(|k| {
            let mut v = [0.0; 11];
            for (f, c) in columns.iter().enumerate() {
                v[f] = c[k];
            }
            LoopRow::from_values(v)
        })
        .collect();
    let mut points = Vec::new();
    for label in POINT_LABELS.iter().take(int("points")?) {
        let field = |name: &str| array(&format!("point_{name}_{label}"));
        let eigen = match rec.get(&format!("point_eigen_displacement_1_{label}")) {
            Some(_) => Some([
                field("eigen_displacement_1")?,
                field("eigen_displacement_2")?,
                field("eigen_displacement_3")?,
            ]),
            None => None,
        };
        points.push(PointFields {
            label,
            increment: int(&format!("point_increment_{label}"))?,
            pressure: field("pressure")?,
            shear: [field("shear_x")?, field("shear_y")?],
            slip: [field("slip_x")?, field("slip_y")?],
            stick: field("stick")?,
            eigen_displacement: eigen,
            von_mises: rec
                .get(&format!("point_von_mises_{label}"))
                .map(|v| v.to_vec()),
            eigenstrain: rec
                .get(&format!("point_eigenstrain_{label}"))
                .map(|v| v.to_vec()),
        });
    }
    let scalars = array("state_scalars")?;
    if scalars.len() != 4 {
        return Err(bad("state_scalars must hold 4 values".into()));
    }
    let state = contact_state_from_record(array, &scalars)?;
    let eigen = match rec.get("eigenstrain") {
        Some(eps) => Some(warm_start_from_record(
            eps.to_vec(),
            array,
            |name| rec.get(name).map(<[f64]>::to_vec),
            || int("committed"),
        )?),
        None => None,
    };
    let max_transverse_slip = rec.float_attr("max_transverse_slip").ok_or_else(|| {
        bad(format!(
            "max_transverse_slip is {:?}",
            rec.get_attr("max_transverse_slip")
        ))
    })?;
    let cycle_sources = match rec.get("cycle_tractions") {
        None => None,
        Some(tractions) => {
            let shape = array("cycle_sources_shape")?;
            if shape.len() != 3 {
                return Err(bad("cycle_sources_shape must hold 3 values".into()));
            }
            let count = |v: f64| {
                if v.is_finite() && v >= 0.0 && v.fract() == 0.0 && v < 1e15 {
                    Ok(v as usize)
                } else {
                    Err(bad(format!("cycle_sources_shape holds {v}: a count")))
                }
            };
            Some(CycleSources {
                cells: count(shape[0])?,
                eigen_len: count(shape[1])?,
                recorded: count(shape[2])?,
                tractions: tractions.to_vec(),
                eigenstrain: array("cycle_eigenstrain")?,
            })
        }
    };
    Ok(LoopSnapshot {
        fingerprint,
        rows,
        points,
        max_transverse_slip,
        state,
        eigen,
        cycle_sources,
    })
}

/// The results of a completed loop (and of its homogeneous reference): the rows, the fields at
/// A–D (2D `(N₁, N₂)`, row-major with x slow) and their profiles along x and y through the
/// centre, `x` (m), the metrics as attributes.
pub fn loop_results_record(
    lp: &FrettingLoop,
    metrics: &LoopMetrics,
    reference: Option<(&FrettingLoop, &LoopMetrics)>,
) -> Record {
    let grid = *lp.solver().problem().grid();
    let (n1, n2) = (grid.n1, grid.n2);
    let case = lp.case();
    let mut rec = Record::default()
        .array("x", (0..n1).map(|i| grid.centre(i, n2 / 2).0).collect())
        .array("y", (0..n2).map(|j| grid.centre(n1 / 2, j).1).collect());
    let sets = std::iter::once(("", lp, metrics))
        .chain(reference.into_iter().map(|(r, m)| ("homogeneous_", r, m)));
    for (prefix, l, m) in sets {
        rec = rows_record(rec, prefix, l.rows());
        for p in l.points() {
            rec = point_record(rec, prefix, p, (n1, n2));
            let label = p.label;
            let along_x = |v: &[f64]| (0..n1).map(|i| v[i * n2 + n2 / 2]).collect::<Vec<_>>();
            let along_y = |v: &[f64]| (0..n2).map(|j| v[(n1 / 2) * n2 + j]).collect::<Vec<_>>();
            for (name, v) in [
                ("pressure", &p.pressure),
                ("shear_x", &p.shear[0]),
                ("shear_y", &p.shear[1]),
                ("slip_x", &p.slip[0]),
                ("slip_y", &p.slip[1]),
            ] {
                rec = rec
                    .array(&format!("{prefix}{name}_along_x_{label}"), along_x(v))
                    .array(&format!("{prefix}{name}_along_y_{label}"), along_y(v));
            }
        }
        for (name, v) in [
            ("dissipated_energy", m.dissipated_energy),
            ("ratchet", m.ratchet),
            ("energy_ratio", m.energy_ratio),
            ("sliding_fraction", m.sliding_fraction),
            ("max_transverse_slip", m.max_transverse_slip),
            ("unloading_stiffness", m.unloading_stiffness),
        ] {
            rec = rec.attr(&format!("{prefix}{name}"), AttrValue::Float(v));
        }
        rec = rec.attr(&format!("{prefix}regime"), AttrValue::Int(m.regime as i64));
    }
    if let Some(d) = case.approach {
        rec = rec.attr("approach", AttrValue::Float(d));
    }
    if let Body::Elastic { e, nu } = case.indenter {
        rec = rec
            .attr("indenter_E", AttrValue::Float(e))
            .attr("indenter_nu", AttrValue::Float(nu));
    }
    rec.attr("radius", AttrValue::Float(case.radius))
        .attr("E", AttrValue::Float(case.e))
        .attr("nu", AttrValue::Float(case.nu))
        .attr("friction", AttrValue::Float(case.friction))
        .attr("force", AttrValue::Float(case.force))
        .attr("grid", AttrValue::Int(case.grid as i64))
        .attr("extent", AttrValue::Float(grid.half1 * 2.0 * n1 as f64))
        .attr("hertz_radius", AttrValue::Float(case.hertz_radius()))
        .attr("hertz_pressure", AttrValue::Float(case.hertz_pressure()))
        .attr(
            "points",
            AttrValue::Text(
                "A: end of normal loading; B: D = +A; C: D = 0 unloading; D: D = −A".into(),
            ),
        )
        .attr(
            "layout",
            AttrValue::Text(format!(
                "{n1} × {n2} cells, row-major (x index slow); von Mises (layers, N1, N2), layer k at depth (2k+1)·half cell"
            )),
        )
}

/// The summary of one 3D contact (`halfspace contact3d --json`, the Python `contact3d`): the
/// contact, the work, and with inhomogeneities or a subsurface field their numbers.
pub fn contact_summary(outcome: &ContactOutcome, case: &ContactCase) -> serde_json::Value {
    let ContactOutcome {
        solver,
        info,
        nested,
        shift,
        iterations,
        field,
        extent,
        seconds: [setup_seconds, solve_seconds, subsurface_seconds],
        ..
    } = outcome;
    let problem = solver.problem();
    let state = problem.state();
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
        "grid": case.grid,
        "extent": extent,
        "coupled": problem.is_coupled(),
        "seconds": setup_seconds + solve_seconds + subsurface_seconds,
        "setup_seconds": setup_seconds,
        "solve_seconds": solve_seconds,
        "friction": case.friction,
    });
    let extra = summary.as_object_mut().expect("object");
    if let (Some(n), Some(ni)) = (solver.nested(), nested) {
        extra.insert("inclusion_cells".into(), json!(n.inclusions().len()));
        extra.insert("layers".into(), json!(n.inclusions().layers.len()));
        extra.insert("eim_iterations".into(), json!(ni.eim_iterations));
        extra.insert("outer_iterations".into(), json!(ni.outer_iterations));
        extra.insert("outer_change".into(), json!(ni.change));
        extra.insert(
            "min_eigen_displacement".into(),
            json!(ni.min_eigen_displacement),
        );
        // docs/theory-sam.md#domain-size-and-truncation: A Σ p_c should vanish; its size relative to W measures the truncation of p_c
        // by the domain (enlarge the extent when it is not small).
        let pc: f64 = n.correction_pressure().iter().sum::<f64>() * problem.grid().cell_area();
        extra.insert(
            "correction_pressure_integral_over_force".into(),
            json!(pc / state.force),
        );
        extra.insert(
            "eim_method".into(),
            json!(format!("{:?}", ni.last_eim.method)),
        );
        extra.insert("eim_spectra_bytes".into(), json!(n.spectra_bytes()));
    }
    if let Some(f) = field {
        let (vm, vm_at) = f.maximum(&f.von_mises);
        let (tr, tr_at) = f.maximum(&f.tresca);
        extra.insert("max_von_mises".into(), json!(vm));
        extra.insert("max_von_mises_at".into(), json!(vm_at));
        extra.insert("max_tresca".into(), json!(tr));
        extra.insert("max_tresca_at".into(), json!(tr_at));
        extra.insert("subsurface_layers".into(), json!(f.layers));
        extra.insert("subsurface_seconds".into(), json!(subsurface_seconds));
    }
    summary
}

/// Names of the volume datasets of [`contact_record`], each of shape `(layers, N₁, N₂)`: the six
/// stresses (Voigt order), von Mises, Tresca, the principal stresses, the material index (0 matrix,
/// `i + 1` inhomogeneity `i`) and the six eigenstrains.
pub const VOLUME_FIELDS: [&str; 18] = [
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
    "eigenstrain_yy",
    "eigenstrain_zz",
    "eigenstrain_yz",
    "eigenstrain_xz",
    "eigenstrain_xy",
];

/// One 3D contact as named arrays (what `halfspace contact3d --out` writes and the Python
/// `contact3d` returns): per surface cell (row-major, x index slow) `x`, `y`, `pressure`,
/// `shear_x/y`, `slip_x/y`, `stick`; with a subsurface field the [`VOLUME_FIELDS`]; `summary`'s
/// keys as attributes.
pub fn contact_record(outcome: &ContactOutcome, summary: &serde_json::Value) -> Record {
    let mut rec = surface_record(outcome.solver.problem(), summary);
    if let Some(f) = &outcome.field {
        rec = volume_record(rec, f, &outcome.solver);
    }
    rec
}

/// Adds the subsurface fields (and the eigenstrains on the same lattice) with their shape.
fn volume_record(mut rec: Record, f: &StressField, solver: &ContactSolver) -> Record {
    let shape = [f.layers, f.grid.n1, f.grid.n2];
    for (o, name) in VOLUME_FIELDS[..6].iter().enumerate() {
        rec = rec.shaped(name, f.stress[o].clone(), &shape);
    }
    rec = rec
        .shaped(VOLUME_FIELDS[6], f.von_mises.clone(), &shape)
        .shaped(VOLUME_FIELDS[7], f.tresca.clone(), &shape);
    for (o, name) in VOLUME_FIELDS[8..11].iter().enumerate() {
        rec = rec.shaped(name, f.principal[o].clone(), &shape);
    }
    rec = rec.shaped(
        VOLUME_FIELDS[11],
        f.material.iter().map(|&m| f64::from(m)).collect(),
        &shape,
    );
    let n = f.grid.len();
    let mut eig: [Vec<f64>; 6] = std::array::from_fn(|_| vec![0.0; f.layers * n]);
    if let Some(nested) = solver.nested() {
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
    for (o, name) in VOLUME_FIELDS[12..].iter().enumerate() {
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

/// The surface fields of one contact and the summary's keys as attributes.
fn surface_record(problem: &ContactProblem, summary: &serde_json::Value) -> Record {
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
                    && crate::sam::tangential::is_stick(
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

/// The summary of a fretting-wear run (`halfspace fretting-wear --json`, the Python
/// `fretting_wear`): the contact radius and its limit, `f̃(a₀)`, the wear volume and its limit
/// over `π a₀² d`, the parameters (for adaptive steps `tol` and `adaptive_scheme`,
/// [`crate::fretting::ADAPTIVE_SCHEME`]; with the edge cells `edge_cell_rule`,
/// [`crate::fretting::EDGE_CELL_RULE`]), and with `ν` the graded tangential constant `c_T/c_N` and
/// `u_max/(μ d) = c_N/c_T`.
pub fn wear_summary(
    sim: &crate::fretting::FrettingSimulation,
    medium: &crate::spec::WearMedium,
) -> serde_json::Value {
    let p = sim.params();
    let state = sim.state();
    let mut summary = json!({
        "tau_final": state.tau,
        "steps": state.step,
        "rejected_steps": state.rejected_steps,
        "stepping": p.stepping.name(),
        "contact_radius_over_a0": state.contact_radius_history.last().copied().unwrap_or(1.0),
        "loaded_radius_over_a0": state.loaded_radius_history.last().copied().unwrap_or(1.0),
        "max_contact_radius_over_a0": state.contact_radius_history.iter().copied().fold(1.0, f64::max),
        "contact_radius_definition": format!(
            "a/a0: extent of the touching region, where the MDR gap g closes to {} h d \
             (h the grid step in r²/a0²); loaded radius: outermost node with p > {} max p",
            crate::fretting::GAP_TOLERANCE,
            crate::fretting::LOAD_THRESHOLD
        ),
        "profile_at_a0_over_d": sim.profile_at_a0(),
        "limit_contact_radius_over_a0": sim.limit_contact_radius(),
        "method": p.backend.name(),
        "gap_transform": p.gap_transform.name(),
        "edge_cells": p.edge_cells,
        "n": p.nodes,
        "chi": p.chi,
        "length": p.length,
        "k": p.k,
        "wear_volume": sim.wear_volume(),
        "limit_wear_volume": sim.limit_wear_volume(),
        "limit_deviation": sim.limit_deviation(0.02),
        "limit_deviation_definition": "max |f − f∞|/d over c + 0.02 a0 < r ≤ r*",
        "wear_volume_definition": "V / (π a0² d): worn volume 2π∫(f − f0) r dr over the contact's a0² d",
    });
    match p.stepping {
        crate::fretting::TimeStepping::Adaptive { tolerance } => {
            summary["tol"] = json!(tolerance);
            // Which adaptive scheme took the steps (as the results and checkpoints record it):
            // two step counts of the same parameters differ by it.
            summary["adaptive_scheme"] = json!(crate::fretting::ADAPTIVE_SCHEME);
        }
        crate::fretting::TimeStepping::Fixed { dtau }
        | crate::fretting::TimeStepping::ExplicitEuler { dtau } => summary["dtau"] = json!(dtau),
    }
    if p.edge_cells {
        // Which rule of the edge cells gave their rates (as checkpoints record it).
        summary["edge_cell_rule"] = json!(crate::fretting::EDGE_CELL_RULE);
    }
    if let (Some(nu), Some(ratio)) = (medium.nu, medium.tangential_ratio()) {
        summary["nu"] = json!(nu);
        summary["tangential_constant_ratio"] = json!(ratio);
        summary["u_max_over_mu_d"] = json!(1.0 / ratio);
    }
    summary
}

/// The metrics of a completed fretting loop as JSON ([`LoopMetrics`]: docs/fretting-loop.md): the
/// one conversion of the CLI's summary, its homogeneous reference and the Python `metrics()`.
pub fn metrics_summary(m: &LoopMetrics) -> serde_json::Value {
    json!({
        "dissipated_energy": m.dissipated_energy,
        "ratchet": m.ratchet,
        "tangential_force_over_mu_w_at_amplitude": m.tangential_force_over_mu_w_at_amplitude,
        "max_pressure_over_p0_end_of_normal_loading": m.max_pressure_over_p0_end_of_normal_loading,
        "contact_area_over_hertz_end_of_normal_loading": m.contact_area_over_hertz_end_of_normal_loading,
        "approach_over_hertz_end_of_normal_loading": m.approach_over_hertz_end_of_normal_loading,
        "max_transverse_slip": m.max_transverse_slip,
        "sliding_fraction": m.sliding_fraction,
        "regime": m.regime as i64,
        "energy_ratio": m.energy_ratio,
        "unloading_stiffness": m.unloading_stiffness,
    })
}

/// The summary of a completed fretting loop: [`metrics_summary`], the increments and the grid,
/// and with inhomogeneities the inclusion cells and layers (the CLI adds times and its output).
pub fn loop_summary(lp: &FrettingLoop, m: &LoopMetrics) -> serde_json::Value {
    let mut summary = metrics_summary(m);
    summary["increments"] = json!(lp.rows().len());
    summary["grid"] = json!(lp.case().grid);
    if let Some(n) = lp.solver().nested() {
        summary["inclusion_cells"] = json!(n.inclusions().len());
        summary["layers"] = json!(n.inclusions().layers.len());
    }
    summary
}

/// The summary of an axisymmetric MDR contact (`halfspace axisym --json`, the Python `axisym`):
/// contact radius, depth, force, pressures, stiffness, the grid and method, the medium's `k` and
/// contact modulus `c_N` (docs/theory-mdr.md), and the `profile` and `material` as given.
pub fn axisym_summary(
    sol: &crate::mdr::ContactSolution,
    material: &crate::mdr::Material,
    backend: crate::mdr::Backend,
    nodes: usize,
    profile: &str,
    material_spec: &str,
) -> serde_json::Value {
    let displacement_method =
        crate::mdr::DisplacementMethod::for_backend(backend).equation(material.grading_exponent());
    json!({
        "contact_radius": sol.contact_radius,
        "depth": sol.depth,
        "force": sol.force,
        "max_pressure": sol.max_pressure(),
        "mean_pressure": sol.mean_pressure(),
        "pressure_singular": sol.pressure_is_singular(),
        "n": nodes,
        "method": backend.name(),
        "displacement_method": displacement_method,
        "k": material.grading_exponent(),
        "contact_modulus": material.contact_modulus(),
        "c_n": material.contact_modulus(),
        "normal_stiffness": sol.normal_stiffness(),
        "grid_length": sol.grid.length(),
        "edge_index": sol.edge_index,
        "iterations": sol.iterations,
        "profile": profile,
        "material": material_spec,
    })
}

/// The up-front estimate of a 3D fretting-wear run (`halfspace fretting-wear3d --estimate`;
/// docs/wear3d.md#the-work-estimate): the cycles asked, the wear steps (computed cycles, the
/// final one included) and the first step's cycles per computed cycle, the increments per
/// computed cycle and of the whole run, the surface cells, the peak memory (bytes) and the hours
/// of work on this machine's cores.
pub fn wear3d_estimate_summary(case: &WearCase, estimate: &WearEstimate) -> serde_json::Value {
    json!({
        "cycles": case.cycles,
        "wear_steps": estimate.wear_steps,
        "computed_cycles": estimate.wear_steps,
        "first_delta_cycles": estimate.first_delta_cycles,
        "increments_per_cycle": estimate.increments_per_cycle,
        "increments": estimate.increments,
        "cells": estimate.run.cells,
        "bytes": estimate.run.bytes,
        "hours": estimate.hours(),
    })
}

/// The summary of a 3D fretting-wear run (`halfspace fretting-wear3d --json`, the Python
/// `fretting_wear3d`; docs/wear3d.md): the cycles run, the wear steps computed, the worn volume
/// (m³), and of the last step the largest wear depth (m), the contact and stick radii (m) and the
/// energy dissipated so far (J); `seconds` the caller's wall time of the run, and the wall time
/// per computed cycle. Before any step the last step's keys are null.
pub fn wear3d_summary(run: &FrettingWear3d, seconds: f64) -> serde_json::Value {
    let last = run.history().last().copied();
    json!({
        "cycles": run.cycles(),
        "wear_steps": run.history().len(),
        "wear_volume": run.wear_volume(),
        "max_wear_depth": last.map(|r| r.max_wear_depth),
        "contact_radius": last.map(|r| r.contact_radius),
        "stick_radius": last.map(|r| r.stick_radius),
        "dissipated_energy_total": last.map(|r| r.dissipated_energy_total),
        "seconds": seconds,
        "seconds_per_computed_cycle": run.seconds().cycles / run.seconds().computed.max(1) as f64,
        "outer_passes": run.seconds().outer_passes,
        "eim_applications": run.seconds().eim_applications,
    })
}

/// The results of a 3D fretting-wear run (`fretting-wear3d`'s results.h5): `x`, `y` (cell centres, m), `wear_depth` (N₁ × N₂, m), the history per computed
/// cycle ([`WearRow::FIELDS`]) and the records (`record_cycles`, `record_wear_depth_{N}`,
/// `record_pressure_{N}`).
pub fn wear3d_results_record(run: &FrettingWear3d) -> Record {
    let g = *run.grid();
    let (n1, n2) = (g.n1, g.n2);
    let mut rec = Record::default()
        .array("x", (0..n1).map(|i| g.centre(i, 0).0).collect())
        .array("y", (0..n2).map(|j| g.centre(0, j).1).collect())
        .shaped("wear_depth", run.wear_depth().to_vec(), &[n1, n2])
        .attr("config", AttrValue::Text(run.fingerprint()));
    rec = wear3d_rows_record(rec, run.history());
    rec = rec.array(
        "record_cycles",
        run.records().iter().map(|r| r.cycles as f64).collect(),
    );
    for r in run.records() {
        rec = rec
            .shaped(
                &format!("record_wear_depth_{}", r.cycles),
                r.wear_depth.clone(),
                &[n1, n2],
            )
            .shaped(
                &format!("record_pressure_{}", r.cycles),
                r.pressure.clone(),
                &[n1, n2],
            );
    }
    rec
}

/// The history rows as one array per field of [`WearRow::FIELDS`].
pub fn wear3d_rows_record(mut rec: Record, rows: &[WearRow]) -> Record {
    for (f, name) in WearRow::FIELDS.iter().enumerate() {
        rec = rec.array(name, rows.iter().map(|r| r.values()[f]).collect());
    }
    rec
}

/// The checkpoint of a 3D fretting-wear run (`fretting-wear3d`'s checkpoint.npz): the snapshot's
/// members by name.
pub fn wear3d_snapshot_record(s: &WearSnapshot) -> Record {
    let rec = wear3d_rows_record(Record::default(), &s.history)
        .attr("config", AttrValue::Text(s.fingerprint.clone()))
        .array(
            "progress",
            vec![
                s.cycles as f64,
                f64::from(u8::from(s.started)),
                f64::from(u8::from(s.done)),
            ],
        )
        .array("wear_depth", s.wear_depth.clone());
    let mut rec = contact_state_record(rec, &s.state).array(
        "record_cycles",
        s.records.iter().map(|r| r.cycles as f64).collect(),
    );
    for (k, r) in s.records.iter().enumerate() {
        rec = rec
            .array(&format!("record_wear_depth_{k}"), r.wear_depth.clone())
            .array(&format!("record_pressure_{k}"), r.pressure.clone());
    }
    if let Some(w) = &s.eigen {
        rec = warm_start_record(rec, w);
    }
    for (k, c) in s.cycle_eigen.iter().enumerate() {
        if !c.eigenstrain.is_empty() {
            rec = rec
                .array(&format!("cycle_eigenstrain_{k}"), c.eigenstrain.clone())
                .array(
                    &format!("cycle_eigen_displacement_{k}"),
                    c.eigen_displacement.clone(),
                );
        }
    }
    rec
}

/// The snapshot of a checkpoint (its content is checked by [`FrettingWear3d::resume`]; the inverse of [`wear3d_snapshot_record`]).
pub fn wear3d_snapshot_from_record(rec: &Record) -> Result<WearSnapshot, String> {
    let array = |name: &str| {
        rec.get(name)
            .map(|v| v.to_vec())
            .ok_or_else(|| format!("member {name} is missing"))
    };
    let count = |name: &str, x: f64| -> Result<u64, String> {
        if x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x < 9.0e15 {
            Ok(x as u64)
        } else {
            Err(format!("member {name}: {x} is not a whole count ≥ 0"))
        }
    };
    let fingerprint = match rec.get_attr("config") {
        Some(AttrValue::Text(t)) => t.clone(),
        other => return Err(format!("attribute config is {other:?}")),
    };
    let columns = WearRow::FIELDS
        .iter()
        .map(|f| array(f))
        .collect::<Result<Vec<_>, _>>()?;
    let rows = columns[0].len();
    if columns.iter().any(|c| c.len() != rows) {
        return Err("member cycles: the history columns differ in length".into());
    }
    let history = (0..rows)
        .map(|k| {
            let mut v = [0.0; 10];
            for (f, c) in columns.iter().enumerate() {
                v[f] = c[k];
            }
            WearRow::from_values(v).ok_or_else(|| format!("member cycles: row {k} = {v:?}"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let progress = array("progress")?;
    if progress.len() != 3 || progress[1..].iter().any(|v| *v != 0.0 && *v != 1.0) {
        return Err(format!("member progress: {progress:?}"));
    }
    let scalars = array("state_scalars")?;
    if scalars.len() != 4 {
        return Err(format!(
            "member state_scalars: {} values, 4 expected",
            scalars.len()
        ));
    }
    let state = contact_state_from_record(array, &scalars)?;
    let records = array("record_cycles")?
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            Ok(WearRecord {
                cycles: count("record_cycles", c)?,
                wear_depth: array(&format!("record_wear_depth_{k}"))?,
                pressure: array(&format!("record_pressure_{k}"))?,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let eigen = match rec.get("eigenstrain") {
        None => None,
        Some(_) => Some(warm_start_from_record(
            array("eigenstrain")?,
            array,
            |name| rec.get(name).map(<[f64]>::to_vec),
            || match rec.get_attr("committed") {
                Some(AttrValue::Int(v)) if *v >= 0 => Ok(*v as usize),
                other => Err(format!("attribute committed is {other:?}")),
            },
        )?),
    };
    // The cycle predictor's store (absent: empty, as in a checkpoint written before it).
    let cycle = |k: usize| -> Result<CycleEigen, String> {
        match rec.get(&format!("cycle_eigenstrain_{k}")) {
            None if rec.get(&format!("cycle_eigen_displacement_{k}")).is_some() => Err(format!(
                "member cycle_eigen_displacement_{k} is present without cycle_eigenstrain_{k}"
            )),
            None => Ok(CycleEigen::default()),
            Some(e) => Ok(CycleEigen {
                eigenstrain: e.to_vec(),
                eigen_displacement: array(&format!("cycle_eigen_displacement_{k}"))?,
            }),
        }
    };
    let cycle_eigen = [cycle(0)?, cycle(1)?];
    Ok(WearSnapshot {
        fingerprint,
        cycles: count("progress", progress[0])?,
        started: progress[1] == 1.0,
        done: progress[2] == 1.0,
        wear_depth: array("wear_depth")?,
        history,
        records,
        state,
        eigen,
        cycle_eigen,
    })
}
