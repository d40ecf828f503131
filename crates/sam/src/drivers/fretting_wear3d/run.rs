//! The wear run, wear step by wear step (docs/wear3d.md).

use std::ops::ControlFlow;
use std::time::Instant;

use super::case::WearCase;
use crate::contact::{
    ContactParams, ContactProblem, ContactSolver, ContactState, NestedParams, NestedWarmStart,
};
use crate::drivers::fretting_loop::LoadPath;
use crate::kernels::surface::{Body, Compliance};
use crate::tangential::is_stick;
use crate::{SamError, SurfaceGrid};

/// The state of the run at one computed cycle (the fields at the same `N`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WearRow {
    /// Cycles `N` done before this computed cycle (its cycle number).
    pub cycles: u64,
    /// Cycles `ΔN` this computed cycle stands for (0 for the last row, at the end of the run).
    pub delta_cycles: u64,
    /// Worn volume at `N`, `A Σ h` (m³).
    pub wear_volume: f64,
    /// Largest worn depth at `N` (m).
    pub max_wear_depth: f64,
    /// Radius of the touching region at `N`, `√(A_t/π)` (m; cells with `p > 0`, or worn with a
    /// deformed gap below `η δ`: docs/wear3d.md#contact-and-stick-radius).
    pub contact_radius: f64,
    /// Radius of the stick zone at `+A`, `√(A_s/π)` (m).
    pub stick_radius: f64,
    /// Energy dissipated in this cycle, `A Σ_cells Σ_k |q_k| |S_k|` (J).
    pub dissipated_energy: f64,
    /// Energy dissipated in the `N` cycles before (J).
    pub dissipated_energy_total: f64,
    /// Largest slip path of the cycle `Σ_k |S_k|` over the cells in contact (m).
    pub max_slip_path: f64,
    /// Largest depth increment per cycle (m).
    pub max_rate: f64,
}

impl WearRow {
    /// The names of [`WearRow::values`] (the results' history datasets).
    pub const FIELDS: [&'static str; 10] = [
        "cycles",
        "delta_cycles",
        "wear_volume",
        "max_wear_depth",
        "contact_radius",
        "stick_radius",
        "dissipated_energy",
        "dissipated_energy_total",
        "max_slip_path",
        "max_rate",
    ];

    /// The row as numbers (the cycle counts exactly, below 2⁵³).
    pub fn values(&self) -> [f64; 10] {
        [
            self.cycles as f64,
            self.delta_cycles as f64,
            self.wear_volume,
            self.max_wear_depth,
            self.contact_radius,
            self.stick_radius,
            self.dissipated_energy,
            self.dissipated_energy_total,
            self.max_slip_path,
            self.max_rate,
        ]
    }

    /// The row of [`WearRow::values`]; `None` when a count is not a whole number ≥ 0 below 2⁵³.
    pub fn from_values(v: [f64; 10]) -> Option<Self> {
        let count = |x: f64| {
            (x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x < 9.007_199_254_740_992e15)
                .then_some(x as u64)
        };
        Some(Self {
            cycles: count(v[0])?,
            delta_cycles: count(v[1])?,
            wear_volume: v[2],
            max_wear_depth: v[3],
            contact_radius: v[4],
            stick_radius: v[5],
            dissipated_energy: v[6],
            dissipated_energy_total: v[7],
            max_slip_path: v[8],
            max_rate: v[9],
        })
    }
}

/// The worn depth and the pressure at `+A` at a record cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct WearRecord {
    /// Cycles `N`.
    pub cycles: u64,
    /// Worn depth per cell (m).
    pub wear_depth: Vec<f64>,
    /// Pressure per cell at the end of the cycle (`+A`) (Pa).
    pub pressure: Vec<f64>,
}

/// The largest ratio `ΔN_n / ΔN_{n−1}` of the cycle predictor's linear extrapolation
/// ([`FrettingWear3d::step`]); above it the last cycle alone is the start.
pub const MAX_CYCLE_RATIO: f64 = 2.0;

/// Under approach control, the normal force at the end of a computed cycle over the Hertz force
/// of the approach below which the run stops with [`SamError::WornOutOfLoad`]: the wear has
/// removed the interference and the load decays toward 0 (on the 16² twin at ten times the
/// gross-slip amplitude the dissipation falls by ≈ 8 % a cycle, and the contact solve failed near
/// 1e-10 of the first cycle's).
pub const WORN_OUT_OF_LOAD_FRACTION: f64 = 1e-6;

/// The converged eigenstrains and eigen-displacements of every increment of one computed cycle
/// (with inhomogeneities, on the nested path): increment `j`'s eigenstrains are
/// `eigenstrain[j·m..(j+1)·m]` (`m` = 6 per inclusion cell) and its `u_c^eig` are
/// `eigen_displacement[(3j + c)·n..(3j + c + 1)·n]` (`n` cells); both empty before a cycle is
/// computed.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CycleEigen {
    /// Eigenstrains, increment after increment.
    pub eigenstrain: Vec<f64>,
    /// Eigen-displacements `u₁, u₂, u₃`, increment after increment.
    pub eigen_displacement: Vec<f64>,
}

/// Everything to continue a run bit for bit ([`FrettingWear3d::resume`]).
#[derive(Debug, Clone, PartialEq)]
pub struct WearSnapshot {
    /// The configuration it was made with ([`FrettingWear3d::fingerprint`]).
    pub fingerprint: String,
    /// Cycles done.
    pub cycles: u64,
    /// Whether the initial loading (normal steps and the first quarter) is done.
    pub started: bool,
    /// Whether the run is complete.
    pub done: bool,
    /// Worn depth per cell (m).
    pub wear_depth: Vec<f64>,
    /// Rows so far.
    pub history: Vec<WearRow>,
    /// Records so far.
    pub records: Vec<WearRecord>,
    /// The contact state (friction history, warm start).
    pub state: ContactState,
    /// With inhomogeneities: the nested loop's warm start.
    pub eigen: Option<NestedWarmStart>,
    /// The cycle predictor's store ([`FrettingWear3d::step`]): the last computed cycle's
    /// eigenstrains and eigen-displacements, then the one's before.
    pub cycle_eigen: [CycleEigen; 2],
}

/// Wall time (s) by part; not part of the results' arrays.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WearSeconds {
    /// The initial loading.
    pub loading: f64,
    /// The computed cycles.
    pub cycles: f64,
    /// Computed cycles done.
    pub computed: usize,
    /// Outer contact ↔ EIM passes of the computed cycles (with inhomogeneities).
    pub outer_passes: usize,
    /// EIM operator applications of the computed cycles (with inhomogeneities).
    pub eim_applications: usize,
}

/// A 3D fretting-wear run of a [`WearCase`] (docs/wear3d.md): the fretting loop of
/// [`crate::drivers::fretting_loop`] with the worn depth added to the gap after each computed
/// cycle; one computed cycle stands for `ΔN` cycles ([`FrettingWear3d::step`]).
pub struct FrettingWear3d {
    /// The outer-loop parameters it was planned with (before the case's own).
    nested: NestedParams,
    case: WearCase,
    path: LoadPath,
    solver: ContactSolver,
    unworn: Vec<f64>,
    wear: Vec<f64>,
    cycles: u64,
    started: bool,
    done: bool,
    history: Vec<WearRow>,
    records: Vec<WearRecord>,
    /// `C_min`: the smallest eigenvalue of the surface compliance (the checkerboard mode).
    checkerboard: f64,
    /// Cells over an inhomogeneity (with the flat wearing).
    over_inhomogeneity: Vec<bool>,
    // Scratch of the computed cycle, allocated once.
    rate: Vec<f64>,
    slip_path: Vec<f64>,
    dissipation: Vec<f64>,
    gap: Vec<f64>,
    geometry: Vec<f64>,
    seconds: WearSeconds,
    /// The cycle predictor's store: the last computed cycle, the one before.
    cycle_eigen: [CycleEigen; 2],
    /// The predicted eigenstrains and eigen-displacements of one increment (scratch).
    predicted: (Vec<f64>, [Vec<f64>; 3]),
}

/// `C_min = Σ_{m,n} (−1)^{m+n} K(m, n)` over the grid's offsets: the surface compliance's symbol
/// at the checkerboard frequency `(π, π)`, its smallest value, which bounds the eigenvalues of every
/// contact set's influence matrix from below (docs/wear3d.md#the-wear-step-and-cycle-jumping).
pub fn checkerboard_compliance(compliance: &Compliance, grid: &SurfaceGrid) -> f64 {
    let quadrant = compliance.normal_quadrant(grid, 1 << 14);
    let weight = |m: usize| if m == 0 { 1.0 } else { 2.0 };
    let mut sum = 0.0;
    for m in 0..grid.n1 {
        for n in 0..grid.n2 {
            let sign = if (m + n) % 2 == 0 { 1.0 } else { -1.0 };
            sum += sign * weight(m) * weight(n) * quadrant[m * grid.n2 + n];
        }
    }
    sum
}

impl FrettingWear3d {
    /// Plans the run of `case` (default solver parameters); refuses an invalid case or one that
    /// does not fit in memory.
    pub fn new(case: WearCase) -> Result<Self, SamError> {
        Self::with_params(case, NestedParams::default())
    }

    /// [`FrettingWear3d::new`] with the outer-loop parameters `nested` (with inhomogeneities).
    pub fn with_params(case: WearCase, nested: NestedParams) -> Result<Self, SamError> {
        case.validate()?;
        let lc = &case.fretting;
        let grid = SurfaceGrid::square(lc.grid, case.extent())?;
        crate::memory::check_problem(&grid, true, lc.is_coupled())?;
        case.estimate()?.run.check_memory("the wear run")?;
        let unworn: Vec<f64> = (0..grid.len())
            .map(|k| {
                let (x, y) = grid.centre(k / grid.n2, k % grid.n2);
                (x * x + y * y) / (2.0 * lc.radius)
            })
            .collect();
        let compliance = Compliance::pair(lc.indenter, Body::elastic(lc.e, lc.nu)?)?;
        let checkerboard = checkerboard_compliance(&compliance, &grid);
        if !(checkerboard.is_finite() && checkerboard > 0.0) {
            return Err(SamError::InvalidInput(format!(
                "the surface compliance's checkerboard value is {checkerboard:e}: not a positive \
                 number (grid {} cells, extent {:e} m)",
                lc.grid,
                case.extent()
            )));
        }
        let params = ContactParams {
            friction: lc.friction,
            alternation: lc.alternation_scheme(),
            ..ContactParams::default()
        };
        let problem = ContactProblem::new(grid, compliance, unworn.clone(), params)?;
        let solver = ContactSolver::new(
            problem,
            lc.e,
            lc.nu,
            &lc.inhomogeneities,
            lc.nested_params(nested),
        )?;
        let n = grid.len();
        let over_inhomogeneity = (0..n)
            .map(|k| {
                let (x, y) = grid.centre(k / grid.n2, k % grid.n2);
                case.body.wears_flat() && case.over_inhomogeneity(x, y)
            })
            .collect();
        Ok(Self {
            nested,
            path: case.path(),
            case,
            solver,
            unworn,
            wear: vec![0.0; n],
            cycles: 0,
            started: false,
            done: false,
            history: Vec::new(),
            records: Vec::new(),
            checkerboard,
            over_inhomogeneity,
            rate: vec![0.0; n],
            slip_path: vec![0.0; n],
            dissipation: vec![0.0; n],
            gap: vec![0.0; n],
            geometry: vec![0.0; n],
            seconds: WearSeconds::default(),
            cycle_eigen: Default::default(),
            predicted: Default::default(),
        })
    }

    /// A run continued from `snapshot` (of [`FrettingWear3d::snapshot`] with the same case): the
    /// next wear step repeats the uninterrupted run's bit for bit.
    pub fn resume(case: WearCase, snapshot: WearSnapshot) -> Result<Self, SamError> {
        let mut run = Self::new(case)?;
        run.case
            .fretting
            .check_stopping_recorded(&snapshot.fingerprint)?;
        let given = format!(
            "{:?}{}",
            run.case,
            run.case.fretting.stopping_fingerprint(run.nested)
        );
        run.case.fretting.check_fingerprint(
            run.nested,
            &snapshot.fingerprint,
            &run.fingerprint(),
            &given,
        )?;
        run.check_snapshot(&snapshot)?;
        run.solver
            .restore(&snapshot.state, snapshot.eigen.as_ref())?;
        run.wear = snapshot.wear_depth;
        run.cycles = snapshot.cycles;
        run.started = snapshot.started;
        run.done = snapshot.done;
        run.history = snapshot.history;
        run.records = snapshot.records;
        run.cycle_eigen = snapshot.cycle_eigen;
        run.apply_wear()?;
        Ok(run)
    }

    /// The snapshot's content against this run: the worn depth of the grid's size, finite and
    /// ≥ 0; cycles within the run; rows at increasing cycles, each `N + ΔN` the next row's `N`,
    /// finite, volumes and energies ≥ 0, ending at the snapshot's cycles; records at record cycles
    /// with fields of the grid's size; the pressure ≥ 0. Errors name the checkpoint member.
    fn check_snapshot(&self, s: &WearSnapshot) -> Result<(), SamError> {
        let bad = |member: &str, rule: String| {
            SamError::InvalidInput(format!("checkpoint member {member}: {rule}"))
        };
        let cells = self.wear.len();
        let field = |member: &str, v: &[f64]| -> Result<(), SamError> {
            if v.len() != cells {
                return Err(bad(
                    member,
                    format!("{} values, the grid has {cells} cells", v.len()),
                ));
            }
            match v
                .iter()
                .enumerate()
                .find(|(_, x)| !(x.is_finite() && **x >= 0.0))
            {
                Some((i, x)) => Err(bad(member, format!("value [{i}] = {x}: finite and ≥ 0"))),
                None => Ok(()),
            }
        };
        field("wear_depth", &s.wear_depth)?;
        field("state_pressure", &s.state.pressure)?;
        if s.cycles > self.case.cycles {
            return Err(bad(
                "cycles",
                format!("{} cycles, the run has {}", s.cycles, self.case.cycles),
            ));
        }
        if !s.started && (s.cycles > 0 || !s.history.is_empty()) {
            return Err(bad(
                "started",
                "false with cycles done: the loading precedes every cycle".into(),
            ));
        }
        let mut next = 0u64;
        for (i, r) in s.history.iter().enumerate() {
            let v = r.values();
            if let Some(f) = (0..v.len()).find(|&f| !(v[f].is_finite() && v[f] >= 0.0)) {
                return Err(bad(
                    WearRow::FIELDS[f],
                    format!("row {i} is {}: finite and ≥ 0", v[f]),
                ));
            }
            if r.cycles != next {
                return Err(bad(
                    "cycles",
                    format!(
                        "row {i} at {} cycles, the row before ends at {next}",
                        r.cycles
                    ),
                ));
            }
            next = r.cycles.saturating_add(r.delta_cycles);
        }
        if next != s.cycles || (s.done && s.history.last().is_some_and(|r| r.delta_cycles != 0)) {
            return Err(bad(
                "cycles",
                format!(
                    "{} cycles, the rows end at {next} (done: {})",
                    s.cycles, s.done
                ),
            ));
        }
        // The cycle store: empty, or one value per increment of a cycle on the nested path.
        let per_cycle = self.path.len() - (self.path.cycle_start() + 1);
        let sizes = self.cycle_store_sizes();
        for (k, c) in s.cycle_eigen.iter().enumerate() {
            let (m, n) = match sizes {
                Some(_) if c.eigenstrain.is_empty() && c.eigen_displacement.is_empty() => continue,
                Some(mn) => mn,
                None if c.eigenstrain.is_empty() && c.eigen_displacement.is_empty() => continue,
                None => {
                    return Err(bad(
                        &format!("cycle_eigenstrain_{k}"),
                        "present, but the run keeps no eigenstrains per increment".into(),
                    ))
                }
            };
            for (member, v, len) in [
                ("eigenstrain", &c.eigenstrain, per_cycle * m),
                (
                    "eigen_displacement",
                    &c.eigen_displacement,
                    3 * per_cycle * n,
                ),
            ] {
                let member = format!("cycle_{member}_{k}");
                if v.len() != len {
                    return Err(bad(
                        &member,
                        format!("{} values, the run's cycle needs {len}", v.len()),
                    ));
                }
                if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                    return Err(bad(&member, format!("value [{i}] is not finite")));
                }
            }
        }
        if s.cycle_eigen[0].eigenstrain.is_empty() && !s.cycle_eigen[1].eigenstrain.is_empty() {
            return Err(bad(
                "cycle_eigenstrain_1",
                "present without cycle_eigenstrain_0".into(),
            ));
        }
        for r in &s.records {
            if !(self.case.record_cycles.contains(&r.cycles) || r.cycles == self.case.cycles)
                || r.cycles > s.cycles
            {
                return Err(bad(
                    "record_cycles",
                    format!("a record at {} cycles, not a record cycle done", r.cycles),
                ));
            }
            field("record_wear_depth", &r.wear_depth)?;
            field("record_pressure", &r.pressure)?;
        }
        Ok(())
    }

    /// The configuration as text, the EIM change factor the one used
    /// ([`crate::drivers::fretting_loop::LoopCase::as_run`]; a checkpoint is resumed only with the
    /// same one, [`crate::drivers::fretting_loop::LoopCase::check_fingerprint`]).
    pub fn fingerprint(&self) -> String {
        let case = WearCase {
            fretting: self.case.fretting.as_run(self.nested),
            ..self.case.clone()
        };
        let stopping = self.case.fretting.stopping_fingerprint(self.nested);
        format!("{case:?}{stopping}")
    }

    /// The case.
    pub fn case(&self) -> &WearCase {
        &self.case
    }

    /// The grid.
    pub fn grid(&self) -> &SurfaceGrid {
        self.solver.problem().grid()
    }

    /// The solver (state, inclusions).
    pub fn solver(&self) -> &ContactSolver {
        &self.solver
    }

    /// Worn depth per cell (m), the total over both bodies.
    pub fn wear_depth(&self) -> &[f64] {
        &self.wear
    }

    /// Cycles done.
    pub fn cycles(&self) -> u64 {
        self.cycles
    }

    /// The rows, one per computed cycle.
    pub fn history(&self) -> &[WearRow] {
        &self.history
    }

    /// The records at the record cycles (and at the end).
    pub fn records(&self) -> &[WearRecord] {
        &self.records
    }

    /// `C_min` (m/Pa): [`checkerboard_compliance`] of this grid.
    pub fn checkerboard_compliance(&self) -> f64 {
        self.checkerboard
    }

    /// Wall time by part since this object was made.
    pub fn seconds(&self) -> WearSeconds {
        self.seconds
    }

    /// Whether the run is complete (the last row, at `cycles`, is computed).
    pub fn is_done(&self) -> bool {
        self.done
    }

    /// The worn volume `A Σ h` (m³).
    pub fn wear_volume(&self) -> f64 {
        self.grid().cell_area() * self.wear.iter().sum::<f64>()
    }

    /// The state to continue from ([`FrettingWear3d::resume`]).
    pub fn snapshot(&self) -> WearSnapshot {
        WearSnapshot {
            fingerprint: self.fingerprint(),
            cycles: self.cycles,
            started: self.started,
            done: self.done,
            wear_depth: self.wear.clone(),
            history: self.history.clone(),
            records: self.records.clone(),
            state: self.solver.problem().state().clone(),
            eigen: self.solver.nested().map(|n| n.warm_start()),
            cycle_eigen: self.cycle_eigen.clone(),
        }
    }

    /// The sizes `(m, n)` of one increment's eigenstrains and of one eigen-displacement component
    /// when the cycle predictor is on: with inhomogeneities on the nested path (the surface
    /// operator solves no eigenstrains per increment) and [`NestedParams::predictor`].
    fn cycle_store_sizes(&self) -> Option<(usize, usize)> {
        let n = self.solver.nested()?;
        (self.nested.predictor && self.nested.cycle_predictor && n.surface_response().is_none())
            .then(|| (n.eigenstrain().len(), n.eigen_displacements()[0].len()))
    }

    /// Sets the nested loop's start of increment `j` of the cycle from the cycle store (both
    /// slots checked complete by [`FrettingWear3d::step`]): `S_j + ratio (S_j − B_j)` when
    /// `linear`, else `S_j`.
    fn predict_cycle(
        &mut self,
        j: usize,
        (m, n): (usize, usize),
        linear: bool,
        ratio: f64,
    ) -> Result<(), SamError> {
        let [now, before] = &self.cycle_eigen;
        let extrapolate = |out: &mut [f64], s: &[f64], b: &[f64]| {
            if linear {
                for ((o, s), b) in out.iter_mut().zip(s).zip(b) {
                    *o = s + ratio * (s - b);
                }
            } else {
                out.copy_from_slice(s);
            }
        };
        let (eps, u) = &mut self.predicted;
        let range = j * m..(j + 1) * m;
        extrapolate(
            eps,
            &now.eigenstrain[range.clone()],
            &before.eigenstrain[range],
        );
        for (c, u) in u.iter_mut().enumerate() {
            let range = (3 * j + c) * n..(3 * j + c + 1) * n;
            extrapolate(
                u,
                &now.eigen_displacement[range.clone()],
                &before.eigen_displacement[range],
            );
        }
        if let Some(nested) = self.solver.nested_mut() {
            nested.set_prediction(eps, [&u[0], &u[1], &u[2]])?;
        }
        Ok(())
    }

    /// Keeps increment `j`'s converged eigenstrains and eigen-displacements in the cycle store's
    /// second slot (allocated by [`FrettingWear3d::step`] before the cycle), whose value for `j`
    /// the prediction has read; the slots are swapped once the cycle is complete.
    fn store_cycle(&mut self, j: usize, (m, n): (usize, usize)) {
        let Some(nested) = self.solver.nested() else {
            return;
        };
        let next = &mut self.cycle_eigen[1];
        next.eigenstrain[j * m..(j + 1) * m].copy_from_slice(nested.eigenstrain());
        for (c, u) in nested.eigen_displacements().iter().enumerate() {
            next.eigen_displacement[(3 * j + c) * n..(3 * j + c + 1) * n].copy_from_slice(u);
        }
    }

    fn apply_wear(&mut self) -> Result<(), SamError> {
        for ((g, h0), w) in self.geometry.iter_mut().zip(&self.unworn).zip(&self.wear) {
            *g = h0 + w;
        }
        self.solver.problem_mut().set_geometry(&self.geometry)
    }

    /// One wear step (docs/wear3d.md#the-wear-step-and-cycle-jumping): the first call loads the contact (the normal
    /// steps and the quarter `0 → +A`); each call computes the cycle `+A → −A → +A` on the
    /// current worn gap and integrates the law over its increments, `r_i = Σ_k rate(p_k, |q_k|,
    /// |S_k|)` per cell; then `ΔN = ⌊min(η δ / max r, β C_min / (k_p max Δu), cycles to the
    /// next record or the end)⌋ ≥ 1` and `h ← h + ΔN r`. The last call (at `cycles`) computes the
    /// final state without wear. Returns the row, or `None` when the run is complete. Refuses
    /// ([`SamError::WornIntoInhomogeneity`], nothing applied) a step that would wear the flat over
    /// an inhomogeneity deeper than [`WearCase::inhomogeneity_depth_cells`] cells (the contact state and
    /// the cycle predictor's store have moved on: resume from the last snapshot), and, under
    /// approach control, a step whose normal force has fallen below [`WORN_OUT_OF_LOAD_FRACTION`]
    /// of the Hertz force of the approach ([`SamError::WornOutOfLoad`]: the wear has removed the
    /// load; nothing applied).
    pub fn step(&mut self) -> Result<Option<&WearRow>, SamError> {
        if self.done {
            return Ok(None);
        }
        if !self.started {
            let t = Instant::now();
            for k in 0..=self.path.cycle_start() {
                let (_, shift) = self.path.increment(k).unwrap_or_default();
                self.solver.increment(self.case.normal_load(k), shift)?;
            }
            self.started = true;
            self.seconds.loading += t.elapsed().as_secs_f64();
        }
        let t = Instant::now();
        self.rate.fill(0.0);
        self.slip_path.fill(0.0);
        self.dissipation.fill(0.0);
        let law = self.case.law;
        let first = self.path.cycle_start() + 1;
        let per_cycle = self.path.len() - first;
        // The cycle predictor: linear in the cycles through the last two computed cycles,
        // `x = S + (ΔN_n / ΔN_{n−1}) (S − B)` (the worn gap changes by `ΔN r` between computed
        // cycles), `S` alone after one cycle.
        let ratio = match self.history.as_slice() {
            [.., a, b] if a.delta_cycles > 0 => b.delta_cycles as f64 / a.delta_cycles as f64,
            _ => 0.0,
        };
        let store = self.cycle_store_sizes();
        // Decided once per cycle, before the store's second slot is written: predict from the
        // last cycle when it is complete, linearly when the one before is complete too and the
        // ratio is at most MAX_CYCLE_RATIO (a short step landing on a record cycle followed by a
        // long one would magnify the two cycles' convergence noise).
        let mut predict = None;
        if let Some((m, n)) = store {
            let full = |c: &CycleEigen| {
                c.eigenstrain.len() == per_cycle * m
                    && c.eigen_displacement.len() == 3 * per_cycle * n
            };
            let [now, before] = &self.cycle_eigen;
            if full(now) {
                predict = Some(full(before) && ratio > 0.0 && ratio <= MAX_CYCLE_RATIO);
            }
            if self.predicted.0.len() != m {
                self.predicted = (vec![0.0; m], [vec![0.0; n], vec![0.0; n], vec![0.0; n]]);
            }
            if !full(&self.cycle_eigen[1]) {
                self.cycle_eigen[1] = CycleEigen {
                    eigenstrain: vec![0.0; per_cycle * m],
                    eigen_displacement: vec![0.0; 3 * per_cycle * n],
                };
            }
        }
        for k in first..self.path.len() {
            let (_, shift) = self.path.increment(k).unwrap_or_default();
            let j = k - first;
            if let (Some((m, n)), Some(linear)) = (store, predict) {
                self.predict_cycle(j, (m, n), linear, ratio)?;
            }
            let (_, info) = self.solver.increment(self.case.normal_load(k), shift)?;
            if let Some(info) = &info {
                self.seconds.outer_passes += info.outer_iterations;
                self.seconds.eim_applications += info.eim_iterations;
            }
            if let Some((m, n)) = store {
                self.store_cycle(j, (m, n));
            }
            let st = self.solver.problem().state();
            for i in 0..self.rate.len() {
                let p = st.pressure[i];
                if p <= 0.0 {
                    continue;
                }
                let s = st.slip[0][i].hypot(st.slip[1][i]);
                let q = st.shear[0][i].hypot(st.shear[1][i]);
                self.rate[i] += law.rate(p, q, s);
                self.slip_path[i] += s;
                self.dissipation[i] += q * s;
            }
        }
        if store.is_some() {
            // This cycle's values (written over the cycle before's) become the last cycle.
            self.cycle_eigen.swap(0, 1);
        }
        self.seconds.cycles += t.elapsed().as_secs_f64();
        self.seconds.computed += 1;
        let area = self.grid().cell_area();
        let scale = self.case.approach_scale();
        let eta = self.case.step_fraction;
        // The measures at N (the geometry of this cycle).
        self.solver.problem_mut().deformed_gap(&mut self.gap)?;
        let st = self.solver.problem().state();
        let mu = self.case.fretting.friction;
        let (mut touching, mut stick) = (0usize, 0usize);
        for i in 0..self.wear.len() {
            let p = st.pressure[i];
            if p > 0.0 || (self.wear[i] > 0.0 && self.gap[i] <= eta * scale) {
                touching += 1;
            }
            if is_stick(mu * p, st.shear[0][i], st.shear[1][i]) {
                stick += 1;
            }
        }
        let radius = |cells: usize| (cells as f64 * area / std::f64::consts::PI).sqrt();
        let max_rate = self.rate.iter().cloned().fold(0.0, f64::max);
        let max_path = self.slip_path.iter().cloned().fold(0.0, f64::max);
        let mut row = WearRow {
            cycles: self.cycles,
            delta_cycles: 0,
            wear_volume: self.wear_volume(),
            max_wear_depth: self.wear.iter().cloned().fold(0.0, f64::max),
            contact_radius: radius(touching),
            stick_radius: radius(stick),
            dissipated_energy: area * self.dissipation.iter().sum::<f64>(),
            dissipated_energy_total: self.history.last().map_or(0.0, |r| {
                r.dissipated_energy_total + r.delta_cycles as f64 * r.dissipated_energy
            }),
            max_slip_path: max_path,
            max_rate,
        };
        if self.case.record_cycles.contains(&self.cycles) || self.cycles >= self.case.cycles {
            self.records.push(WearRecord {
                cycles: self.cycles,
                wear_depth: self.wear.clone(),
                pressure: st.pressure.clone(),
            });
        }
        if self.cycles >= self.case.cycles {
            self.done = true;
            self.history.push(row);
            return Ok(self.history.last());
        }
        // ΔN: accuracy (η δ per step), stability (β C_min / (k_p max Δu)), landing on the next
        // record cycle or the end.
        let next = self
            .case
            .record_cycles
            .iter()
            .copied()
            .filter(|&c| c > self.cycles)
            .chain(std::iter::once(self.case.cycles))
            .min()
            .unwrap_or(self.case.cycles);
        let cap = (next - self.cycles) as f64;
        let accuracy = if max_rate > 0.0 {
            eta * scale / max_rate
        } else {
            f64::INFINITY
        };
        let kp = law.pressure_coefficient(mu);
        let stability = if max_path > 0.0 {
            self.case.stability_fraction * self.checkerboard / (kp * max_path)
        } else {
            f64::INFINITY
        };
        let dn = accuracy.min(stability).min(cap).floor().max(1.0) as u64;
        // Under approach control the wear can remove the interference: the load decays toward
        // 0 while the stability bound keeps ΔN small — a run of steps that wear ever less until
        // the contact solve can no longer resolve the load. Stopped here, with a message, once
        // the force falls below WORN_OUT_OF_LOAD_FRACTION of the Hertz force of the approach.
        // (Not a rule on the wear rate: in Popov's limit of partial slip the rate vanishes while
        // the stick zone keeps the load.)
        if let Some(approach) = self.case.fretting.approach {
            let hertz = self.case.fretting.hertz_force();
            let force = self.solver.problem().state().force;
            if force < WORN_OUT_OF_LOAD_FRACTION * hertz {
                return Err(SamError::WornOutOfLoad {
                    cycles: self.cycles,
                    force,
                    hertz,
                    ratio: force / hertz,
                    depth: row.max_wear_depth,
                    approach,
                });
            }
        }
        if self.over_inhomogeneity.iter().any(|&b| b) {
            let limit = self.case.inhomogeneity_depth_cells
                * 2.0
                * self.grid().half1.min(self.grid().half2);
            let depth = (0..self.wear.len())
                .filter(|&i| self.over_inhomogeneity[i])
                .map(|i| self.wear[i] + dn as f64 * self.rate[i])
                .fold(0.0, f64::max);
            if depth > limit {
                // Nothing of this step is kept: the state is that of the last completed step
                // except the contact state and the cycle predictor's store, which a resume
                // restores from the checkpoint.
                return Err(SamError::WornIntoInhomogeneity {
                    cycles: self.cycles + dn,
                    depth,
                    limit,
                });
            }
        }
        for (w, r) in self.wear.iter_mut().zip(&self.rate) {
            *w += dn as f64 * r;
        }
        self.apply_wear()?;
        row.delta_cycles = dn;
        self.cycles += dn;
        self.history.push(row);
        Ok(self.history.last())
    }

    /// Runs to the end, calling `observer` after every wear step; `ControlFlow::Break` stops
    /// early (the run can continue). Returns whether it is complete.
    pub fn run(
        &mut self,
        mut observer: impl FnMut(&Self) -> ControlFlow<()>,
    ) -> Result<bool, SamError> {
        while self.step()?.is_some() {
            if observer(self).is_break() {
                return Ok(self.done);
            }
        }
        Ok(true)
    }
}
