//! The fretting loop, increment by increment.

use std::ops::ControlFlow;
use std::time::Instant;

use super::case::{LoadPath, LoopCase, CONTACT_WINDOW_FIELD, POINT_LABELS};
use super::history::{CycleSources, CycleStress};
use super::metrics::LoopMetrics;
use super::row::LoopRow;
use crate::contact::ContactSolver;
use crate::contact::{ContactParams, ContactProblem, ContactState};
use crate::contact::{ContactWork, NestedParams, NestedWarmStart};
use crate::kernels::surface::{Body, Compliance};
use crate::normal::NormalLoad;
use crate::subsurface::{von_mises_fields, FieldSources, SubsurfacePlan};
use crate::tangential::is_stick;
use crate::{SamError, SurfaceGrid};

/// Wall time of the loop by part (s); not deterministic, so not part of the results' arrays.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LoopSeconds {
    /// Whole increments.
    pub increments: f64,
    /// Contact solves (inside the outer loop with inhomogeneities).
    pub contact: f64,
    /// Applied strains of the tractions at the inclusion layers.
    pub traction_strain: f64,
    /// EIM solves.
    pub eim: f64,
    /// Disturbance fields and eigen-displacements.
    pub disturbance: f64,
    /// Von Mises fields at the points A–D.
    pub subsurface: f64,
    /// Recording the closed cycle's tractions ([`LoopCase::fatigue_depth`]; the stress history
    /// is computed from them when asked for, [`FrettingLoop::cycle_history`]).
    pub cycle_stress: f64,
}

/// The surface fields (and the von Mises field below) at one of the points A–D, each `N₁N₂`
/// row-major (x index slow).
#[derive(Debug, Clone, PartialEq)]
pub struct PointFields {
    /// "A" … "D".
    pub label: &'static str,
    /// Increments done at this point.
    pub increment: usize,
    /// Pressure p.
    pub pressure: Vec<f64>,
    /// Shear `(q₁, q₂)`.
    pub shear: [Vec<f64>; 2],
    /// Slip of the last increment `(s₁, s₂)`.
    pub slip: [Vec<f64>; 2],
    /// 1 where the cell sticks, 0 elsewhere.
    pub stick: Vec<f64>,
    /// Surface eigen-displacements `(u₁, u₂, u₃)^eig` (with inhomogeneities).
    pub eigen_displacement: Option<[Vec<f64>; 3]>,
    /// Von Mises stress on the layers below (`layers · N₁N₂`, layer slow), with
    /// [`LoopCase::subsurface_depth`]: computed for the four points at once when the last one
    /// is reached ([`FrettingLoop::step`]; `None` until then).
    pub von_mises: Option<Vec<f64>>,
    /// With inhomogeneities and [`LoopCase::subsurface_depth`], the eigenstrains of the point's
    /// state (6 per inclusion cell) while its von Mises field is pending; `None` once computed.
    pub eigenstrain: Option<Vec<f64>>,
}

/// Everything a loop needs to continue bit for bit.
#[derive(Debug, Clone, PartialEq)]
pub struct LoopSnapshot {
    /// The configuration it was made with ([`FrettingLoop::fingerprint`]).
    pub fingerprint: String,
    /// Rows done.
    pub rows: Vec<LoopRow>,
    /// Points A–D reached.
    pub points: Vec<PointFields>,
    /// Largest `|s₂|` so far.
    pub max_transverse_slip: f64,
    /// The contact state.
    pub state: ContactState,
    /// With inhomogeneities: the nested loop's warm start (eigenstrains, eigen-displacements).
    pub eigen: Option<NestedWarmStart>,
    /// The tractions (and eigenstrains) of the closed cycle's increments so far
    /// ([`LoopCase::fatigue_depth`]): the stress history is rebuilt from them on resume.
    pub cycle_sources: Option<CycleSources>,
}

/// The fretting loop of a [`LoopCase`] (module doc of [`crate::drivers::fretting_loop`]).
pub struct FrettingLoop {
    case: LoopCase,
    path: LoadPath,
    solver: ContactSolver,
    rows: Vec<LoopRow>,
    points: Vec<PointFields>,
    max_transverse_slip: f64,
    seconds: LoopSeconds,
    contact_work: ContactWork,
    /// The complete cycle's full history, computed at the first [`FrettingLoop::cycle_stress`].
    cycle_stress: std::sync::OnceLock<CycleStress>,
    cycle_sources: Option<CycleSources>,
    /// The outer-loop parameters it was planned with (before the case's own).
    nested: NestedParams,
}

/// Sets its flag when dropped (on return or unwinding alike): [`FrettingLoop::run_beside`]'s
/// cancellation of the loop beside.
struct CancelOnDrop<'a>(&'a std::sync::atomic::AtomicBool);

impl Drop for CancelOnDrop<'_> {
    fn drop(&mut self) {
        self.0.store(true, std::sync::atomic::Ordering::Relaxed);
    }
}

impl FrettingLoop {
    /// Plans the loop of `case` with the default solver parameters; refuses up front a case that
    /// does not fit in memory.
    pub fn new(case: LoopCase) -> Result<Self, SamError> {
        Self::with_params(case, NestedParams::default())
    }

    /// [`FrettingLoop::new`] with the outer-loop parameters `nested` (used with inhomogeneities).
    pub fn with_params(case: LoopCase, nested: NestedParams) -> Result<Self, SamError> {
        case.validate()?;
        case.estimate().check("the fretting loop")?;
        let a = case.hertz_radius();
        let grid = SurfaceGrid::square(case.grid, case.extent_over_a * a)?;
        crate::memory::check_problem(&grid, true, case.is_coupled())?;
        let geometry = (0..grid.len())
            .map(|k| {
                let (x, y) = grid.centre(k / grid.n2, k % grid.n2);
                (x * x + y * y) / (2.0 * case.radius)
            })
            .collect();
        // The pair (docs/theory-sam.md#two-bodies): the indenter's compliance adds to the flat's;
        // the flat alone carries the inhomogeneities.
        let compliance = Compliance::pair(case.indenter, Body::elastic(case.e, case.nu)?)?;
        let params = ContactParams {
            friction: case.friction,
            alternation: case.alternation_scheme(),
            ..ContactParams::default()
        };
        let mut problem = ContactProblem::new(grid, compliance, geometry, params)?;
        // The contact solved on the cells within `CONTACT_WINDOW_OVER_A · a` of the axis
        // (docs/performance.md, "A contact window for the 3D loops"); the EIM and every field on
        // the whole grid.
        problem.set_window(case.contact_window()?)?;
        let solver = ContactSolver::new(
            problem,
            case.e,
            case.nu,
            &case.inhomogeneities,
            case.nested_params(nested),
        )?;
        Ok(Self {
            nested,
            path: case.path(),
            case,
            solver,
            rows: Vec::new(),
            points: Vec::new(),
            max_transverse_slip: 0.0,
            seconds: LoopSeconds::default(),
            contact_work: ContactWork::default(),
            cycle_stress: std::sync::OnceLock::new(),
            cycle_sources: None,
        })
    }

    /// A loop continued from `snapshot` (made by [`FrettingLoop::snapshot`] of the same case):
    /// the next increment repeats the uninterrupted loop's bit for bit.
    pub fn resume(case: LoopCase, snapshot: LoopSnapshot) -> Result<Self, SamError> {
        let mut lp = Self::new(case)?;
        if !snapshot.fingerprint.contains(CONTACT_WINDOW_FIELD) {
            return Err(SamError::InvalidInput(
                "the checkpoint was written by a build whose contact solves ran on the whole grid \
                 (before the contact window, docs/performance.md \"A contact window for the 3D \
                 loops\"): its increments would not be repeated bit for bit; start the loop over"
                    .into(),
            ));
        }
        lp.case.check_stopping_recorded(&snapshot.fingerprint)?;
        let stopping = lp.case.stopping_fingerprint(lp.nested);
        let given = format!("{:?}{}{stopping}", lp.case, lp.case.window_fingerprint()?);
        lp.case
            .check_fingerprint(lp.nested, &snapshot.fingerprint, &lp.fingerprint(), &given)?;
        lp.check_snapshot(&snapshot)?;
        lp.solver
            .restore(&snapshot.state, snapshot.eigen.as_ref())?;
        lp.rows = snapshot.rows;
        lp.points = snapshot.points;
        lp.max_transverse_slip = snapshot.max_transverse_slip;
        // The tractions of the cycle's increments done: the history is computed from them by
        // the same operator as the uninterrupted loop's (bit for bit).
        lp.cycle_sources = snapshot.cycle_sources;
        Ok(lp)
    }

    /// The content of a snapshot against this loop (beyond its fingerprint): rows no more than
    /// the path's, each at the path's load and shift bit for bit and finite, with a pressure,
    /// areas and counts a contact can have (`0 ≤ stick ≤ contact ≤ domain`, `|Q| ≤ μW` within the
    /// solver's tolerance); the points A–D at their marks with fields of the grid's size, finite
    /// (pressure ≥ 0, stick 0 or 1); the contact state and the eigenstrains finite. Errors name
    /// the checkpoint member (`normal_force`, `state_pressure`, `point_pressure_B`, …).
    fn check_snapshot(&self, snapshot: &LoopSnapshot) -> Result<(), SamError> {
        let bad = |member: String, rule: String| {
            SamError::InvalidInput(format!("checkpoint member {member}: {rule}"))
        };
        let rows = &snapshot.rows;
        if rows.len() > self.path.len() {
            return Err(bad(
                "normal_force".into(),
                format!(
                    "{} increments, the path has {}",
                    rows.len(),
                    self.path.len()
                ),
            ));
        }
        let grid = *self.solver.problem().grid();
        let cells = grid.len();
        let domain = grid.n1 as f64 * grid.n2 as f64 * grid.cell_area();
        let mu = self.case.friction;
        for (k, r) in rows.iter().enumerate() {
            let v = r.values();
            if let Some(f) = (0..v.len()).find(|&f| !v[f].is_finite()) {
                return Err(bad(
                    LoopRow::FIELDS[f].into(),
                    format!("row {k} is {}: every value is finite", v[f]),
                ));
            }
            let (w, shift) = self.path.increment(k).unwrap_or_default();
            // The prescribed normal load: the force, or the approach under approach control.
            let (member, given) = if self.path.by_approach {
                ("approach, shift_x", r.approach)
            } else {
                ("normal_force, shift_x", r.w)
            };
            if given.to_bits() != w.to_bits() || r.d.to_bits() != shift[0].to_bits() {
                return Err(bad(
                    member.into(),
                    format!(
                        "row {k} is (W or δ, δx) = ({given}, {}), this loop's increment {k} is \
                         ({w}, {})",
                        r.d, shift[0]
                    ),
                ));
            }
            let checks: [(&str, bool); 4] = [
                ("max_pressure", r.max_pressure >= 0.0),
                (
                    "contact_area",
                    (0.0..=domain * (1.0 + 1e-12)).contains(&r.contact_area),
                ),
                (
                    "stick_area",
                    r.stick_area >= 0.0 && r.stick_area <= r.contact_area,
                ),
                (
                    "tangential_force",
                    r.q[0].hypot(r.q[1]) <= mu * r.w * (1.0 + 1e-3),
                ),
            ];
            if let Some((member, _)) = checks.iter().find(|(_, ok)| !ok) {
                return Err(bad(
                    (*member).into(),
                    format!(
                        "row {k} = {:?}: outside what a contact can have (0 ≤ stick ≤ contact \
                         area ≤ domain, pressure ≥ 0, |Q| ≤ μW)",
                        v[LoopRow::FIELDS
                            .iter()
                            .position(|f| f == member)
                            .unwrap_or(0)]
                    ),
                ));
            }
        }
        let finite = |member: String, v: &[f64], len: Option<usize>| -> Result<(), SamError> {
            if let Some(len) = len.filter(|&l| l != v.len()) {
                return Err(bad(
                    member,
                    format!("{} values, the grid has {len} cells", v.len()),
                ));
            }
            if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                return Err(bad(member, format!("value [{i}] = {x} is not finite")));
            }
            Ok(())
        };
        let marks = self.path.marks();
        if snapshot.points.len() > POINT_LABELS.len() {
            return Err(bad(
                "points".into(),
                format!("{} points, the loop has 4", snapshot.points.len()),
            ));
        }
        for (m, p) in snapshot.points.iter().enumerate() {
            let l = POINT_LABELS[m];
            if p.increment != marks[m] || p.increment > rows.len() {
                return Err(bad(
                    format!("point_increment_{l}"),
                    format!(
                        "{}: point {l} is reached at increment {} ({} done)",
                        p.increment,
                        marks[m],
                        rows.len()
                    ),
                ));
            }
            finite(format!("point_pressure_{l}"), &p.pressure, Some(cells))?;
            if let Some(x) = p.pressure.iter().find(|x| **x < 0.0) {
                return Err(bad(
                    format!("point_pressure_{l}"),
                    format!("value {x}: a contact pressure is ≥ 0"),
                ));
            }
            for (c, v) in p.shear.iter().enumerate() {
                finite(format!("point_shear_{}_{l}", ["x", "y"][c]), v, Some(cells))?;
            }
            for (c, v) in p.slip.iter().enumerate() {
                finite(format!("point_slip_{}_{l}", ["x", "y"][c]), v, Some(cells))?;
            }
            finite(format!("point_stick_{l}"), &p.stick, Some(cells))?;
            if let Some(x) = p.stick.iter().find(|x| **x != 0.0 && **x != 1.0) {
                return Err(bad(
                    format!("point_stick_{l}"),
                    format!("value {x}: 0 or 1"),
                ));
            }
            for (c, v) in p.eigen_displacement.iter().flatten().enumerate() {
                finite(
                    format!("point_eigen_displacement_{}_{l}", c + 1),
                    v,
                    Some(cells),
                )?;
            }
            // A pending von Mises field (the last point not reached yet) keeps the point's
            // eigenstrains with inhomogeneities, and only then.
            let eigen_len = self.solver.nested().map(|n| n.eigenstrain().len());
            let pending = self.case.subsurface_depth.is_some() && p.von_mises.is_none();
            match (&p.eigenstrain, pending, eigen_len) {
                (Some(eps), true, Some(len)) if eps.len() == len => {
                    finite(format!("point_eigenstrain_{l}"), eps, None)?;
                }
                (None, true, None) | (None, false, _) => {}
                (eps, _, len) => {
                    return Err(bad(
                        format!("point_eigenstrain_{l}"),
                        format!(
                            "{} values: the eigenstrains of a point whose von Mises field is \
                             pending ({} values with this loop's inhomogeneities; none without, \
                             or once the field is computed)",
                            eps.as_ref().map_or(0, Vec::len),
                            len.unwrap_or(0)
                        ),
                    ))
                }
            }
            if let Some(vm) = &p.von_mises {
                finite(format!("point_von_mises_{l}"), vm, None)?;
                if vm.is_empty() || vm.len() % cells != 0 || vm.iter().any(|x| *x < 0.0) {
                    return Err(bad(
                        format!("point_von_mises_{l}"),
                        format!("{} values: layers of {cells} cells, each ≥ 0", vm.len()),
                    ));
                }
            }
        }
        let st = &snapshot.state;
        finite("state_pressure".into(), &st.pressure, Some(cells))?;
        if let Some(x) = st.pressure.iter().find(|x| **x < 0.0) {
            return Err(bad(
                "state_pressure".into(),
                format!("value {x}: a contact pressure is ≥ 0"),
            ));
        }
        let s = snapshot.max_transverse_slip;
        if !(s.is_finite() && s >= 0.0) {
            return Err(bad(
                "max_transverse_slip".into(),
                format!("{s}: finite and ≥ 0"),
            ));
        }
        if let Some(w) = &snapshot.eigen {
            finite("eigenstrain".into(), &w.eigenstrain, None)?;
            finite("eigenstrain_previous".into(), &w.previous.0, None)?;
            for (it, suffix) in w.iterates.iter().zip(["", "_previous"]) {
                if let Some(it) = it {
                    finite(format!("eim_iterate{suffix}"), &it.iterate, None)?;
                    finite(format!("eim_iterate_image{suffix}"), &it.image, None)?;
                }
            }
            for c in 0..3 {
                finite(
                    format!("eigen_displacement_{}", c + 1),
                    &w.eigen_displacement[c],
                    Some(cells),
                )?;
                finite(
                    format!("eigen_displacement_previous_{}", c + 1),
                    &w.previous.1[c],
                    Some(cells),
                )?;
            }
        }
        let expected = rows.len().saturating_sub(self.path.cycle_start());
        match (&snapshot.cycle_sources, self.case.fatigue_depth) {
            (None, Some(_)) if expected > 0 => {
                return Err(bad(
                    "cycle_tractions".into(),
                    format!("missing: {expected} increments of the cycle are done"),
                ))
            }
            (Some(_), None) => {
                return Err(bad(
                    "cycle_tractions".into(),
                    "present, but this loop records no stress history".into(),
                ))
            }
            (Some(h), Some(_)) => {
                let eigen_len = self.solver.nested().map_or(0, |n| n.eigenstrain().len());
                if h.recorded != expected
                    || h.cells != cells
                    || h.eigen_len != eigen_len
                    || h.tractions.len() != expected * 3 * cells
                    || h.eigenstrain.len() != expected * eigen_len
                {
                    return Err(bad(
                        "cycle_tractions".into(),
                        format!(
                            "{} increments of {} cells and {} eigenstrains ({} and {} values): \
                             this loop has {expected} of {cells} cells and {eigen_len}",
                            h.recorded,
                            h.cells,
                            h.eigen_len,
                            h.tractions.len(),
                            h.eigenstrain.len()
                        ),
                    ));
                }
                finite("cycle_tractions".into(), &h.tractions, None)?;
                finite("cycle_eigenstrain".into(), &h.eigenstrain, None)?;
            }
            _ => {}
        }
        Ok(())
    }

    /// The configuration as text, the EIM change factor the one used ([`LoopCase::as_run`]; a
    /// checkpoint is resumed only with the same one, [`LoopCase::check_fingerprint`]).
    pub fn fingerprint(&self) -> String {
        // The case was validated when the loop was planned: its window is known.
        let window = self.case.window_fingerprint().unwrap_or_default();
        let stopping = self.case.stopping_fingerprint(self.nested);
        format!("{:?}{window}{stopping}", self.case.as_run(self.nested))
    }

    /// The case.
    pub fn case(&self) -> &LoopCase {
        &self.case
    }

    /// The load path.
    pub fn path(&self) -> &LoadPath {
        &self.path
    }

    /// The solver (its grid, state, inclusions).
    pub fn solver(&self) -> &ContactSolver {
        &self.solver
    }

    /// The rows of the increments done.
    pub fn rows(&self) -> &[LoopRow] {
        &self.rows
    }

    /// The points A–D reached so far.
    pub fn points(&self) -> &[PointFields] {
        &self.points
    }

    /// Largest `|s₂|` (transverse slip, from the normal–tangential coupling) so far (m).
    pub fn max_transverse_slip(&self) -> f64 {
        self.max_transverse_slip
    }

    /// The closed cycle's stress history on the whole box ([`LoopCase::fatigue_depth`]):
    /// `Ok(None)` until the cycle is complete (or without [`LoopCase::fatigue_depth`]); computed
    /// from the cycle's tractions at the first call ([`FrettingLoop::cycle_history`] of every
    /// level) and kept. An error of that computation (a plan or memory refusal) is returned, not
    /// read as "not complete".
    pub fn cycle_stress(&self) -> Result<Option<&CycleStress>, SamError> {
        if let Some(h) = self.cycle_stress.get() {
            return Ok(Some(h));
        }
        let Some(sources) = self.cycle_sources.as_ref() else {
            return Ok(None);
        };
        if sources.recorded != self.path.len() - self.path.cycle_start() {
            return Ok(None);
        }
        let h = self.cycle_history(None)?;
        Ok(Some(self.cycle_stress.get_or_init(|| h)))
    }

    /// The tractions (and eigenstrains) of the closed cycle's increments recorded so far
    /// ([`LoopCase::fatigue_depth`]).
    pub fn cycle_sources(&self) -> Option<&CycleSources> {
        self.cycle_sources.as_ref()
    }

    /// The levels of the fatigue box: `⌈depth/2Δ⌉` layers below the surface and the surface
    /// layer (level index `layers`) — `(layers, all levels)`; `None` without
    /// [`LoopCase::fatigue_depth`].
    pub fn cycle_levels(&self) -> Option<(usize, Vec<usize>)> {
        let depth = self.case.fatigue_depth?;
        let layers = SubsurfacePlan::layers_for(depth, self.solver.problem().grid().half1);
        Some((layers, (0..=layers).collect()))
    }

    /// The stress path of the closed cycle at arbitrary points `(x₁, x₂, depth > 0)` off the
    /// box's lattice, `out[(m · increments + t) · 6 + k]` (Voigt, Pa): Love's rectangle stresses
    /// of the recorded tractions `p, q` of each increment by direct summation
    /// ([`crate::subsurface::stress_at_points`], the twin of the box's layers at the cell
    /// centres; docs/theory-sam.md#love-rectangle-stresses), with the flat's constants. Used to
    /// evaluate the criteria at fixed points below the surface whatever the grid (their maxima
    /// at a fixed depth converge with the grid; docs/fatigue.md, "Near-surface maxima at a fixed
    /// depth"). O(cells) per point and increment. Errors: no recorded cycle, an incomplete one,
    /// a loop with inhomogeneities (their eigenstrains are not summed here), a point at depth
    /// ≤ 0 (the surface `z = 0` has the logarithmic singularities of the piecewise-constant
    /// tractions' jumps on the cell edges).
    pub fn cycle_stress_at(&self, points: &[[f64; 3]]) -> Result<Vec<f64>, SamError> {
        let Some(sources) = self.cycle_sources.as_ref() else {
            return Err(SamError::InvalidInput(
                "this loop records no stress history (no fatigue depth)".into(),
            ));
        };
        let increments = self.path.len() - self.path.cycle_start();
        if sources.recorded != increments {
            return Err(SamError::InvalidInput(format!(
                "the cycle is not complete: {} of {increments} increments recorded",
                sources.recorded
            )));
        }
        if self.solver.nested().is_some() {
            return Err(SamError::InvalidInput(
                "stress paths at arbitrary points: loops with inhomogeneities are not supported"
                    .into(),
            ));
        }
        let grid = *self.solver.problem().grid();
        let frictional = self.solver.problem().friction() > 0.0;
        let mut out = vec![0.0; points.len() * increments * 6];
        for t in 0..increments {
            let (p, q, _) = sources.increment(t);
            let stress = crate::subsurface::stress_at_points(
                &grid,
                self.case.e,
                self.case.nu,
                p,
                frictional.then_some(q),
                None,
                points,
            )?;
            for (m, s) in stress.iter().enumerate() {
                out[(m * increments + t) * 6..(m * increments + t + 1) * 6].copy_from_slice(s);
            }
        }
        Ok(out)
    }

    /// The stress history of the increments recorded so far on the levels `levels` of the box
    /// (increasing; `None`: every level), computed from the cycle's tractions and, with
    /// inhomogeneities, eigenstrains: Love's stresses and the EIM disturbance with the flat's
    /// constants ([`SubsurfacePlan::with_levels`], [`SubsurfacePlan::stress`]; an elastic
    /// indenter changes the tractions, not the flat's stresses). Each level is bit for bit that
    /// of the whole box's history.
    pub fn cycle_history(&self, levels: Option<&[usize]>) -> Result<CycleStress, SamError> {
        let (Some(depth), Some((layers, all))) = (self.case.fatigue_depth, self.cycle_levels())
        else {
            return Err(SamError::InvalidInput(
                "this loop records no stress history (no fatigue depth)".into(),
            ));
        };
        let levels = levels.unwrap_or(&all);
        let grid = *self.solver.problem().grid();
        // With the surface layer z = 0 (docs/fatigue.md, "The surface layer").
        let mut plan =
            SubsurfacePlan::with_levels(&grid, self.case.e, self.case.nu, depth, levels)?;
        let empty = CycleSources::default();
        let sources = self.cycle_sources.as_ref().unwrap_or(&empty);
        let materials = self
            .solver
            .nested()
            .map(|n| n.inclusions().materials.clone())
            .unwrap_or_default();
        let increments = self.path.len() - self.path.cycle_start();
        let mut history: Option<CycleStress> = None;
        for t in 0..sources.recorded {
            let (p, q, eigen) = sources.increment(t);
            let q = (self.solver.problem().friction() > 0.0).then_some(q);
            let inclusions = self.solver.nested().map(|n| (n.inclusions(), eigen));
            let (stress, material) = plan.stress(p, q, inclusions)?;
            if history.is_none() {
                history = Some(CycleStress::new(
                    grid,
                    (layers, levels.to_vec()),
                    material,
                    increments,
                    materials.clone(),
                )?);
            }
            if let Some(h) = history.as_mut() {
                h.record(&stress)?;
            }
        }
        match history {
            Some(h) => Ok(h),
            None => CycleStress::new(
                grid,
                (layers, levels.to_vec()),
                vec![0; levels.len() * grid.len()],
                increments,
                materials,
            ),
        }
    }

    /// Wall time by part since this object was made.
    pub fn seconds(&self) -> LoopSeconds {
        self.seconds
    }

    /// The contact solves' work summed over the increments since this object was made (with
    /// inhomogeneities; zero without: [`ContactWork`]).
    pub fn contact_work(&self) -> ContactWork {
        self.contact_work
    }

    /// Whether every increment is done.
    pub fn is_done(&self) -> bool {
        self.rows.len() >= self.path.len()
    }

    /// The next increment: its row, or `None` when the loop is done.
    pub fn step(&mut self) -> Result<Option<&LoopRow>, SamError> {
        // Fields still pending with every point reached (a failure at the fourth point, saved
        // by the checkpoint written after it): computed before anything else.
        if self.points.len() == POINT_LABELS.len() {
            self.von_mises_fields()?;
        }
        let k = self.rows.len();
        let Some((load, shift)) = self.path.load(k) else {
            return Ok(None);
        };
        let start = Instant::now();
        let (info, nested) = self.solver.increment(load, shift)?;
        // The row's W: the prescribed force, or the force computed at the prescribed approach.
        let w = match load {
            NormalLoad::Force(w) => w,
            NormalLoad::Approach(_) => info.normal.force,
        };
        self.seconds.increments += start.elapsed().as_secs_f64();
        match &nested {
            Some(n) => {
                self.seconds.contact += n.seconds.contact;
                self.seconds.traction_strain += n.seconds.traction_strain;
                self.seconds.eim += n.seconds.eim;
                self.seconds.disturbance += n.seconds.disturbance;
                let w = &mut self.contact_work;
                w.solves += n.contact_work.solves;
                w.alternations += n.contact_work.alternations;
                w.normal_iterations += n.contact_work.normal_iterations;
                w.tangential_iterations += n.contact_work.tangential_iterations;
                w.normal_iterations_total += n.contact_work.normal_iterations_total;
                w.tangential_iterations_total += n.contact_work.tangential_iterations_total;
            }
            None => self.seconds.contact += start.elapsed().as_secs_f64(),
        }
        self.rows
            .push(LoopRow::of(w, shift[0], &info, nested.as_ref()));
        let state = self.solver.problem().state();
        self.max_transverse_slip = state.slip[1]
            .iter()
            .fold(self.max_transverse_slip, |m, v| m.max(v.abs()));
        if let Some(m) = self.path.marks().iter().position(|&s| s == k + 1) {
            let fields = self.point_fields(POINT_LABELS[m], k + 1)?;
            self.points.push(fields);
            if self.points.len() == POINT_LABELS.len() {
                self.von_mises_fields()?;
            }
        }
        if self.case.fatigue_depth.is_some() && k >= self.path.cycle_start() {
            let t = Instant::now();
            self.record_cycle_sources()?;
            self.seconds.cycle_stress += t.elapsed().as_secs_f64();
        }
        Ok(self.rows.last())
    }

    /// The loop of `case` run to its end on a thread of its own while `main` runs on the calling
    /// thread; returns `main`'s result and, when `keep` accepts it, the finished loop (`None`
    /// when `keep` refuses: the loop is stopped at its next increment and dropped).
    ///
    /// For the homogeneous reference of a loop with inhomogeneities ([`LoopCase::homogeneous`]):
    /// the nested loop's contact solves run on one thread and leave the second core to poll, so
    /// the reference's increments fit beside them (docs/performance.md, "The reference loop
    /// beside the composite loop"). The loop runs in a rayon pool of one thread of its own, so
    /// its solves never queue behind the global pool's jobs; its results are bit for bit those
    /// of [`FrettingLoop::run`] on any pool (every sum of the solvers keeps its order). Without
    /// a second thread (the global pool has one) it runs after `main`.
    pub fn run_beside<T>(
        case: LoopCase,
        main: impl FnOnce() -> T,
        keep: impl FnOnce(&T) -> bool,
    ) -> (T, Option<Result<FrettingLoop, SamError>>) {
        let run_to_end = |cancel: &std::sync::atomic::AtomicBool| {
            let mut lp = FrettingLoop::new(case.clone())?;
            let done = lp.run(|_| {
                if cancel.load(std::sync::atomic::Ordering::Relaxed) {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            })?;
            Ok(done.then_some(lp))
        };
        let cancel = std::sync::atomic::AtomicBool::new(false);
        let pool = (rayon::current_num_threads() > 1)
            .then(|| rayon::ThreadPoolBuilder::new().num_threads(1).build().ok())
            .flatten();
        let Some(pool) = pool else {
            let out = main();
            let reference = keep(&out)
                .then(|| run_to_end(&cancel))
                .map(Result::transpose);
            return (out, reference.flatten());
        };
        std::thread::scope(|scope| {
            let handle = scope.spawn(|| pool.install(|| run_to_end(&cancel)));
            // Cancelled unless kept, also when `main` or `keep` panics (the scope joins the
            // loop before the panic goes on: it stops at its next increment).
            let cancel_unless_kept = CancelOnDrop(&cancel);
            let out = main();
            let wanted = keep(&out);
            if wanted {
                std::mem::forget(cancel_unless_kept);
            } else {
                drop(cancel_unless_kept);
            }
            let reference = match handle.join() {
                Ok(r) => r.transpose(),
                Err(panic) => std::panic::resume_unwind(panic),
            };
            (out, if wanted { reference } else { None })
        })
    }

    /// Runs to the end, calling `observer` after every increment; the observer stops the loop
    /// early with `ControlFlow::Break` (the loop can continue later). Returns whether it is done.
    pub fn run(
        &mut self,
        mut observer: impl FnMut(&Self) -> ControlFlow<()>,
    ) -> Result<bool, SamError> {
        while self.step()?.is_some() {
            if observer(self).is_break() {
                return Ok(self.is_done());
            }
        }
        Ok(true)
    }

    /// This increment's tractions (and eigenstrains) into the cycle's sources (the history is
    /// computed from them, [`FrettingLoop::cycle_history`]).
    fn record_cycle_sources(&mut self) -> Result<(), SamError> {
        // On the surface-operator path the eigenstrains follow the tractions only when synced.
        self.solver.sync_eigenstrain()?;
        let st = self.solver.problem().state();
        let eigen = self.solver.nested().map_or(&[][..], |n| n.eigenstrain());
        let sources = self.cycle_sources.get_or_insert_with(|| CycleSources {
            cells: st.pressure.len(),
            eigen_len: eigen.len(),
            ..CycleSources::default()
        });
        sources.push(&st.pressure, [&st.shear[0], &st.shear[1]], eigen);
        Ok(())
    }

    /// The state to continue from ([`FrettingLoop::resume`]).
    pub fn snapshot(&self) -> LoopSnapshot {
        LoopSnapshot {
            fingerprint: self.fingerprint(),
            rows: self.rows.clone(),
            points: self.points.clone(),
            max_transverse_slip: self.max_transverse_slip,
            state: self.solver.problem().state().clone(),
            eigen: self.solver.nested().map(|n| n.warm_start()),
            cycle_sources: self.cycle_sources.clone(),
        }
    }

    /// The loop's metrics ([`LoopMetrics`]); an error before the loop is done.
    pub fn metrics(&self) -> Result<LoopMetrics, SamError> {
        if !self.is_done() {
            return Err(SamError::InvalidInput(format!(
                "the loop's metrics need all {} increments, {} done",
                self.path.len(),
                self.rows.len()
            )));
        }
        Ok(LoopMetrics::of(
            &self.case,
            &self.path,
            &self.rows,
            self.max_transverse_slip,
        ))
    }

    /// The surface fields at a point; with [`LoopCase::subsurface_depth`] its von Mises field is
    /// left pending (and, with inhomogeneities, the state's eigenstrains kept for it:
    /// [`FrettingLoop::von_mises_fields`]).
    fn point_fields(
        &mut self,
        label: &'static str,
        increment: usize,
    ) -> Result<PointFields, SamError> {
        let eigenstrain = match (self.case.subsurface_depth, self.solver.nested().is_some()) {
            (Some(_), true) => {
                let t = Instant::now();
                // On the surface-operator path the eigenstrains follow the tractions only when
                // synced.
                self.solver.sync_eigenstrain()?;
                self.seconds.subsurface += t.elapsed().as_secs_f64();
                self.solver.nested().map(|n| n.eigenstrain().to_vec())
            }
            _ => None,
        };
        let problem = self.solver.problem();
        let st = problem.state();
        let n = problem.grid().len();
        let mu = problem.friction();
        let stick = (0..n)
            .map(|k| {
                f64::from(u8::from(is_stick(
                    mu * st.pressure[k],
                    st.shear[0][k],
                    st.shear[1][k],
                )))
            })
            .collect();
        Ok(PointFields {
            label,
            increment,
            pressure: st.pressure.clone(),
            shear: st.shear.clone(),
            slip: st.slip.clone(),
            stick,
            eigen_displacement: self
                .solver
                .nested()
                .map(|n| n.eigen_displacements().clone()),
            von_mises: None,
            eigenstrain,
        })
    }

    /// The von Mises fields of the points whose field is pending (with
    /// [`LoopCase::subsurface_depth`]), all at once: [`crate::subsurface::von_mises_fields`] of
    /// their tractions and eigenstrains in the flat `(e, nu)` down to the depth (each the field
    /// of [`ContactSolver::subsurface`] at that point, bit for bit), the kernels' spectra built
    /// once for the four points (docs/performance.md, "The 128² composite command outside the
    /// EIM (issue 21)").
    fn von_mises_fields(&mut self) -> Result<(), SamError> {
        let Some(depth) = self.case.subsurface_depth else {
            return Ok(());
        };
        let t = Instant::now();
        let pending: Vec<usize> = (0..self.points.len())
            .filter(|&i| self.points[i].von_mises.is_none())
            .collect();
        if pending.is_empty() {
            return Ok(());
        }
        let problem = self.solver.problem();
        let frictional = problem.friction() > 0.0;
        let inclusions = self.solver.nested().map(|n| n.inclusions());
        let sources: Vec<FieldSources> = pending
            .iter()
            .map(|&i| {
                let p = &self.points[i];
                FieldSources {
                    pressure: &p.pressure,
                    shear: frictional.then(|| [p.shear[0].as_slice(), p.shear[1].as_slice()]),
                    eigenstrain: p.eigenstrain.as_deref(),
                }
            })
            .collect();
        let fields = von_mises_fields(
            problem.grid(),
            self.case.e,
            self.case.nu,
            depth,
            inclusions,
            &sources,
        )?;
        for (&i, field) in pending.iter().zip(fields) {
            self.points[i].von_mises = Some(field);
            self.points[i].eigenstrain = None;
        }
        self.seconds.subsurface += t.elapsed().as_secs_f64();
        Ok(())
    }
}
