//! The stress history of the closed cycle in a box below the contact (docs/fatigue.md, "On the
//! fretting loop"): the six stress components at the centre of every cubic cell of the layers
//! from the surface to a depth (layer `k` centred at depth `(2k + 1)Δ`, as
//! [`crate::subsurface::subsurface_stress`]), at every increment of the last full cycle
//! `+A → −A → +A`, from the loop's tractions (Love's rectangle stresses,
//! docs/theory-sam.md#love-rectangle-stresses) and, with inhomogeneities, the EIM disturbance
//! (`σ = C_I : ε` in an inhomogeneity cell).

use crate::subsurface::StressField;
use crate::{SamError, SurfaceGrid};

/// The stress path of every cell of the box over the closed cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleStress {
    /// The surface grid.
    pub grid: SurfaceGrid,
    /// Layers below the surface.
    pub layers: usize,
    /// Increments of the closed cycle (`4q + 1`).
    pub increments: usize,
    /// Increments recorded so far.
    pub recorded: usize,
    /// `stress[(p · increments + t) · 6 + c]`: cell `p = k N₁N₂ + i N₂ + j` (layer slow),
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

    /// Cells of the box.
    pub fn points(&self) -> usize {
        self.layers * self.grid.len()
    }

    /// The centre `(x, y, z)` of cell `p` (z the depth, m).
    pub fn position(&self, p: usize) -> [f64; 3] {
        let per = self.grid.len();
        let (k, flat) = (p / per, p % per);
        let (x, y) = self.grid.centre(flat / self.grid.n2, flat % self.grid.n2);
        [x, y, (2 * k + 1) as f64 * self.grid.half1]
    }

    /// Depth of layer `k`, `(2k + 1)Δ`.
    pub fn depth(&self, k: usize) -> f64 {
        (2 * k + 1) as f64 * self.grid.half1
    }

    /// An empty history of `increments` increments for the layers of `field`.
    pub(super) fn new(
        field: &StressField,
        increments: usize,
        materials: Vec<(f64, f64)>,
    ) -> Result<Self, SamError> {
        let points = field.layers * field.grid.len();
        let len = points
            .checked_mul(increments)
            .and_then(|v| v.checked_mul(6))
            .ok_or_else(|| {
                SamError::InvalidInput("the cycle's stress history does not fit in memory".into())
            })?;
        Ok(Self {
            grid: field.grid,
            layers: field.layers,
            increments,
            recorded: 0,
            stress: vec![0.0; len],
            material: field.material.clone(),
            materials,
        })
    }

    /// Stores `field` as the next increment.
    pub(super) fn record(&mut self, field: &StressField) -> Result<(), SamError> {
        let t = self.recorded;
        if t >= self.increments || field.layers != self.layers || field.grid != self.grid {
            return Err(SamError::InvalidInput(format!(
                "cycle stress history: increment {t} of {} on {} layers, the field has {}",
                self.increments, self.layers, field.layers
            )));
        }
        let n = self.increments;
        for c in 0..6 {
            for (p, v) in field.stress[c].iter().enumerate() {
                self.stress[(p * n + t) * 6 + c] = *v;
            }
        }
        self.recorded += 1;
        Ok(())
    }
}
