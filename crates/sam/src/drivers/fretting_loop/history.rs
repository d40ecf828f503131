//! The stress history of the closed cycle in a box below the contact (docs/fatigue.md, "On the
//! fretting loop"): the six stress components at the centre of every cubic cell of the layers
//! from the surface to a depth (layer `k` centred at depth `(2k + 1)Δ`, as
//! [`crate::subsurface::subsurface_stress`]), at every increment of the last full cycle
//! `+A → −A → +A`, from the loop's tractions (Love's rectangle stresses,
//! docs/theory-sam.md#love-rectangle-stresses) and, with inhomogeneities, the EIM disturbance
//! (`σ = C_I : ε` in an inhomogeneity cell); after the layers, the surface layer `z = 0`
//! (docs/fatigue.md, "The surface layer").

use crate::subsurface::SubsurfacePlan;
use crate::{SamError, SurfaceGrid};

/// The stress path of every cell of the box over the closed cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleStress {
    /// The surface grid.
    pub grid: SurfaceGrid,
    /// Layers below the surface.
    pub layers: usize,
    /// Whether the surface layer `z = 0` is stored (the whole box: after the layers, cells
    /// `layers · N₁N₂ + i N₂ + j`, [`crate::subsurface::SubsurfacePlan::with_surface`]).
    pub surface: bool,
    /// The box level of each stored level (`k < layers` the layer centred at `(2k + 1)Δ`,
    /// `layers` the surface layer): `0, …, layers` for the whole box, fewer for the levels a
    /// screen keeps ([`crate::subsurface::SubsurfacePlan::with_levels`]).
    pub level_of: Vec<usize>,
    /// Increments of the closed cycle (`4q + 1`).
    pub increments: usize,
    /// Increments recorded so far.
    pub recorded: usize,
    /// `stress[(p · increments + t) · 6 + c]`: cell `p = k N₁N₂ + i N₂ + j` of the stored level
    /// `k` (level slow; the box level `level_of[k]`),
    /// increment `t` of the cycle, Voigt component `c` of `(11, 22, 33, 23, 13, 12)` (Pa,
    /// tension positive) — the layout of `halfspace_fatigue::evaluate_field`.
    pub stress: Vec<f64>,
    /// Material of each cell: 0 the matrix, `m + 1` the inclusion material `m` (of
    /// [`CycleStress::materials`]).
    pub material: Vec<u16>,
    /// `(E, ν)` of the inclusion materials.
    pub materials: Vec<(f64, f64)>,
}

impl CycleStress {
    /// Layers of a box of depth `depth` on cells of side `2Δ`: `⌈depth / 2Δ⌉`, at least 1 (as
    /// [`crate::subsurface::subsurface_stress`]).
    pub fn layers_for(depth: f64, cell: f64) -> usize {
        ((depth / cell).ceil() as usize).max(1)
    }

    /// Bytes of the stored path: `cells · layers · increments · 6 · 8`.
    pub fn bytes(cells: f64, layers: f64, increments: f64) -> f64 {
        cells * layers * increments * 48.0
    }

    /// Levels stored (the whole box: the layers below the surface and the surface layer).
    pub fn levels(&self) -> usize {
        self.level_of.len()
    }

    /// Cells of the box (with the surface layer).
    pub fn points(&self) -> usize {
        self.levels() * self.grid.len()
    }

    /// The centre `(x, y, z)` of cell `p` (z the depth, m; 0 on the surface layer). An error
    /// for a cell past the stored levels (`p ≥ levels · N₁N₂`, the public `level_of`).
    pub fn position(&self, p: usize) -> Result<[f64; 3], SamError> {
        let per = self.grid.len();
        let k = p.checked_div(per).unwrap_or(usize::MAX);
        let Some(&level) = self.level_of.get(k) else {
            return Err(SamError::InvalidInput(format!(
                "cycle stress history: cell {p} past its {} levels of {per} cells",
                self.levels()
            )));
        };
        let flat = p % per;
        let (x, y) = self.grid.centre(flat / self.grid.n2, flat % self.grid.n2);
        Ok([x, y, self.depth(level)])
    }

    /// Depth of the box level `k`: `(2k + 1)Δ` below the surface, 0 for the surface layer
    /// `k = layers`.
    pub fn depth(&self, k: usize) -> f64 {
        if k >= self.layers {
            0.0
        } else {
            (2 * k + 1) as f64 * self.grid.half1
        }
    }

    /// An empty history of `increments` increments on the levels `level_of` of a box of
    /// `layers` layers below `grid` (level `layers` the surface layer), the cells of materials
    /// `material` (0 the matrix, `m + 1` inclusion material `m` of `materials`).
    pub(super) fn new(
        grid: SurfaceGrid,
        (layers, level_of): (usize, Vec<usize>),
        material: Vec<u16>,
        increments: usize,
        materials: Vec<(f64, f64)>,
    ) -> Result<Self, SamError> {
        let surface = level_of.contains(&layers);
        let points = level_of.len() * grid.len();
        let len = points
            .checked_mul(increments)
            .and_then(|v| v.checked_mul(6))
            .ok_or_else(|| {
                SamError::InvalidInput("the cycle's stress history does not fit in memory".into())
            })?;
        Ok(Self {
            grid,
            layers,
            surface,
            level_of,
            increments,
            recorded: 0,
            stress: vec![0.0; len],
            material,
            materials,
        })
    }

    /// The history of a loop without inhomogeneities on the box levels `levels` of `plan`
    /// (increasing, their spectra kept: [`SubsurfacePlan::stress_of_levels`]) from the cycle's
    /// recorded tractions `sources` (the shear only when `frictional`): the history
    /// [`crate::drivers::fretting_loop::FrettingLoop::cycle_history`] computes on those levels,
    /// bit for bit, without building their kernel spectra again (docs/fatigue.md, "Layers the
    /// screen cannot reach"). An error for sources with eigenstrains, or levels the plan does not
    /// hold.
    pub fn of_levels(
        plan: &mut SubsurfacePlan,
        levels: &[usize],
        sources: &CycleSources,
        frictional: bool,
    ) -> Result<Self, SamError> {
        if sources.eigen_len != 0 {
            return Err(SamError::InvalidInput(
                "cycle stress history of a plan's levels: the loop has inhomogeneities".into(),
            ));
        }
        let grid = *plan.grid();
        let per = grid.len();
        let mut history = CycleStress::new(
            grid,
            (plan.layers(), levels.to_vec()),
            vec![0; levels.len() * per],
            sources.recorded,
            Vec::new(),
        )?;
        for t in 0..sources.recorded {
            let (p, q, _) = sources.increment(t);
            let stress = plan.stress_of_levels(levels, p, frictional.then_some(q))?;
            history.record(&stress)?;
        }
        Ok(history)
    }

    /// The history on the levels of `self` and `other` together (in increasing box level): two
    /// histories of one box and cycle, on disjoint levels, each complete. Each level's paths are
    /// copied as they are, bit for bit.
    ///
    /// An error unless both are consistent ([`CycleStress::check_shape`]: `stress` and
    /// `material` of their levels' length, levels distinct and in the box), of the same box,
    /// complete, and on disjoint levels.
    pub fn merged(self, other: CycleStress) -> Result<CycleStress, SamError> {
        self.check_shape()?;
        other.check_shape()?;
        let same_box = self.grid == other.grid
            && self.layers == other.layers
            && self.increments == other.increments
            && self.recorded == self.increments
            && other.recorded == other.increments
            && self.materials == other.materials;
        if !same_box || self.level_of.iter().any(|k| other.level_of.contains(k)) {
            return Err(SamError::InvalidInput(
                "cycle stress history: only complete histories of one box on disjoint levels \
                 merge"
                    .into(),
            ));
        }
        let mut level_of: Vec<usize> = self
            .level_of
            .iter()
            .chain(&other.level_of)
            .copied()
            .collect();
        level_of.sort_unstable();
        let per = self.grid.len();
        let block = per * self.increments * 6;
        // In the larger history's buffer (grown in place: no copy of its levels when they stay
        // where they are, as the seed's surface layer after the layers below): its levels moved
        // to their final places from the last one down (a level never moves to a lower place),
        // then the other's copied in.
        let (mut base, extra) = if self.level_of.len() >= other.level_of.len() {
            (self, other)
        } else {
            (other, self)
        };
        if base.level_of.windows(2).any(|w| w[1] < w[0]) {
            // Levels stored out of order: the other history's buffer the base, sorted first
            // (each level copied once).
            base = base.sorted();
        }
        let place = |k: &usize| level_of.iter().position(|l| l == k).unwrap_or(0);
        base.stress.resize(level_of.len() * block, 0.0);
        base.material.resize(level_of.len() * per, 0);
        for (at, k) in base.level_of.iter().enumerate().rev() {
            let to = place(k);
            if to != at {
                base.stress
                    .copy_within(at * block..(at + 1) * block, to * block);
                base.material
                    .copy_within(at * per..(at + 1) * per, to * per);
            }
        }
        for (at, k) in extra.level_of.iter().enumerate() {
            let to = place(k);
            base.stress[to * block..(to + 1) * block]
                .copy_from_slice(&extra.stress[at * block..(at + 1) * block]);
            base.material[to * per..(to + 1) * per]
                .copy_from_slice(&extra.material[at * per..(at + 1) * per]);
        }
        Ok(CycleStress {
            surface: level_of.contains(&base.layers),
            level_of,
            ..base
        })
    }

    /// The same history with its levels in increasing order (a copy of each level).
    fn sorted(self) -> CycleStress {
        let per = self.grid.len();
        let block = per * self.increments * 6;
        let mut order: Vec<usize> = (0..self.level_of.len()).collect();
        order.sort_unstable_by_key(|&at| self.level_of[at]);
        let mut stress = Vec::with_capacity(self.stress.len());
        let mut material = Vec::with_capacity(self.material.len());
        for &at in &order {
            stress.extend_from_slice(&self.stress[at * block..(at + 1) * block]);
            material.extend_from_slice(&self.material[at * per..(at + 1) * per]);
        }
        CycleStress {
            level_of: order.iter().map(|&at| self.level_of[at]).collect(),
            stress,
            material,
            ..self
        }
    }

    /// Checks that the public fields agree: `level_of` distinct box levels `≤ layers` (`layers`
    /// the surface layer, present iff `surface`), `stress` of `levels · N₁N₂ · increments · 6`
    /// values, `material` of `levels · N₁N₂`, each `material` index `≤ materials.len()` (0 the
    /// matrix, `m + 1` the entry `m` of `materials`), `recorded ≤ increments`.
    pub fn check_shape(&self) -> Result<(), SamError> {
        let per = self.grid.len();
        let fail = |what: String| {
            Err(SamError::InvalidInput(format!(
                "cycle stress history: {what}"
            )))
        };
        if let Some(&k) = self.level_of.iter().find(|&&k| k > self.layers) {
            return fail(format!(
                "level {k} outside the box of {} layers",
                self.layers
            ));
        }
        // Sorted copy: no allocation sized by the (public, unchecked) `layers`.
        let mut sorted = self.level_of.clone();
        sorted.sort_unstable();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            return fail(format!("level {} stored twice", w[0]));
        }
        if self.surface != self.level_of.contains(&self.layers) {
            return fail("the surface flag does not match its levels".into());
        }
        let points = self.levels().checked_mul(per);
        let values = points
            .and_then(|p| p.checked_mul(self.increments))
            .and_then(|v| v.checked_mul(6));
        if values != Some(self.stress.len()) || points != Some(self.material.len()) {
            return fail(format!(
                "{} stress and {} material values for {} levels of {per} cells, {} increments",
                self.stress.len(),
                self.material.len(),
                self.levels(),
                self.increments
            ));
        }
        if let Some((p, &m)) = self
            .material
            .iter()
            .enumerate()
            .find(|(_, &m)| m as usize > self.materials.len())
        {
            return fail(format!(
                "cell {p} of material {m}, past the matrix (0) and the {} inclusion materials",
                self.materials.len()
            ));
        }
        if self.recorded > self.increments {
            return fail(format!(
                "{} of {} increments recorded",
                self.recorded, self.increments
            ));
        }
        Ok(())
    }

    /// Stores the six stress components `stress[c][p]` of the box as the next increment.
    pub(super) fn record(&mut self, stress: &[Vec<f64>; 6]) -> Result<(), SamError> {
        let t = self.recorded;
        let points = self.points();
        if t >= self.increments || stress.iter().any(|s| s.len() != points) {
            return Err(SamError::InvalidInput(format!(
                "cycle stress history: increment {t} of {} on {points} cells, the field has {}",
                self.increments,
                stress[0].len()
            )));
        }
        let n = self.increments;
        // Cell by cell, its six components together (one cache line of the path, not six
        // sweeps over the whole history).
        for (p, out) in self.stress.chunks_exact_mut(6 * n).enumerate() {
            let out = &mut out[6 * t..6 * t + 6];
            for (o, field) in out.iter_mut().zip(stress.iter()) {
                *o = field[p];
            }
        }
        self.recorded += 1;
        Ok(())
    }
}

/// What the stress history is made of, per recorded increment of the cycle: the surface tractions
/// `p, q₁, q₂` and, with inhomogeneities, the eigenstrains. The checkpoint carries these instead
/// of the history (`2 · layers` times smaller without inhomogeneities); a resumed loop rebuilds the
/// history from them with the same operator, bit for bit.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CycleSources {
    /// Surface cells `N₁N₂`.
    pub cells: usize,
    /// Eigenstrain values per increment (`6 ×` inclusion cells; 0 without inhomogeneities).
    pub eigen_len: usize,
    /// Increments recorded.
    pub recorded: usize,
    /// `tractions[(t · 3 + c) · cells + k]`: `c` = 0 the pressure, 1 and 2 the shear `q₁, q₂`.
    pub tractions: Vec<f64>,
    /// `eigenstrain[t · eigen_len + i]`.
    pub eigenstrain: Vec<f64>,
}

impl CycleSources {
    /// Appends one increment.
    pub(super) fn push(&mut self, p: &[f64], q: [&[f64]; 2], eigenstrain: &[f64]) {
        self.tractions.extend_from_slice(p);
        self.tractions.extend_from_slice(q[0]);
        self.tractions.extend_from_slice(q[1]);
        self.eigenstrain.extend_from_slice(eigenstrain);
        self.recorded += 1;
    }

    /// `(p, [q₁, q₂], ε*)` of increment `t`.
    pub fn increment(&self, t: usize) -> (&[f64], [&[f64]; 2], &[f64]) {
        let n = self.cells;
        let tr = &self.tractions[t * 3 * n..(t + 1) * 3 * n];
        let (p, q) = tr.split_at(n);
        let (q1, q2) = q.split_at(n);
        let e = &self.eigenstrain[t * self.eigen_len..(t + 1) * self.eigen_len];
        (p, [q1, q2], e)
    }

    /// Bytes of `increments` increments on `cells` surface cells with `eigen_len` eigenstrain
    /// values each.
    pub fn bytes(cells: f64, eigen_len: f64, increments: f64) -> f64 {
        (3.0 * cells + eigen_len) * increments * 8.0
    }
}
