//! The fatigue criteria of a completed fretting loop (docs/fatigue.md, "On the fretting loop"):
//! the closed cycle's stress history of the box below the contact
//! ([`halfspace_sam::drivers::fretting_loop::CycleStress`]) through the screened field evaluation
//! ([`halfspace_fatigue::evaluate_screened`]), each cell with its own material's constants.

use std::time::Instant;

use serde_json::{json, Value};

use crate::config::FatigueConfig;
use crate::data::{AttrValue, Record};
use crate::fatigue::field::{FieldParams, Maximum};
use crate::fatigue::{evaluate_screened, ScreenedIndices};
use crate::sam::drivers::fretting_loop::{CycleStress, FrettingLoop};
use crate::spec::SpecError;

/// The four index fields of a loop and where they peak.
#[derive(Debug, Clone)]
pub struct LoopFatigue {
    /// The fields and maxima, layer slow, the layers in the order of `z`: the surface layer
    /// `z = 0` first, then the layers below (the maxima's `point` in this order).
    pub indices: ScreenedIndices,
    /// Layers of the fields: the surface layer and the layers below the surface.
    pub layers: usize,
    /// Cells per side `(N₁, N₂)`.
    pub shape: (usize, usize),
    /// Cell centres: `x` (N₁), `y` (N₂), `z` (layers: 0, then `(2k + 1)Δ`) (m).
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub z: Vec<f64>,
    /// Positions `[x, y, z]` of the four maxima (Crossland, Dang Van, SWT, Fatemi–Socie).
    pub at: [[f64; 3]; 4],
    /// Increments of the cycle's path.
    pub increments: usize,
    /// Wall time of the evaluation (s).
    pub seconds: f64,
}

/// The criteria of the completed loop `lp` with the constants of `cfg`; an error when the loop
/// recorded no complete stress history (no `[fatigue]` table when it ran, or not done).
pub fn evaluate_loop_fatigue(
    lp: &FrettingLoop,
    cfg: &FatigueConfig,
) -> Result<LoopFatigue, SpecError> {
    let start = Instant::now();
    let h: &CycleStress = lp
        .cycle_stress()
        .filter(|h| h.recorded == h.increments)
        .ok_or_else(|| {
            SpecError("fatigue: the loop holds no complete stress history of its cycle".into())
        })?;
    let case = lp.case();
    let materials = cfg.materials(case.e, case.nu, &h.materials);
    let indices = evaluate_screened(
        &h.stress,
        h.increments,
        &materials,
        &h.material,
        &FieldParams::default(),
        cfg.screen_fraction,
    )
    .map_err(|e| SpecError(format!("fatigue: {e}")))?;
    let g = h.grid;
    let at = |m: &Maximum| h.position(m.point);
    let at = [
        at(&indices.crossland_max),
        at(&indices.dang_van_max),
        at(&indices.swt_max),
        at(&indices.fatemi_socie_max),
    ];
    // The history holds the surface layer after the layers below; the fields list the layers
    // by depth, the surface first.
    let per = g.len();
    let order: Vec<usize> = if h.surface {
        std::iter::once(h.layers).chain(0..h.layers).collect()
    } else {
        (0..h.layers).collect()
    };
    let by_depth = |v: &[f64]| -> Vec<f64> {
        order
            .iter()
            .flat_map(|&k| v[k * per..(k + 1) * per].iter().copied())
            .collect()
    };
    let slot = |p: usize| {
        let k = order.iter().position(|&k| k == p / per).unwrap_or(0);
        k * per + p % per
    };
    let mut indices = indices;
    for f in [
        &mut indices.crossland,
        &mut indices.dang_van,
        &mut indices.swt,
        &mut indices.fatemi_socie,
    ] {
        *f = by_depth(f);
    }
    for m in [
        &mut indices.crossland_max,
        &mut indices.dang_van_max,
        &mut indices.swt_max,
        &mut indices.fatemi_socie_max,
    ] {
        m.point = slot(m.point);
    }
    Ok(LoopFatigue {
        at,
        indices,
        layers: order.len(),
        shape: (g.n1, g.n2),
        x: (0..g.n1).map(|i| g.centre(i, 0).0).collect(),
        y: (0..g.n2).map(|j| g.centre(0, j).1).collect(),
        z: order.iter().map(|&k| h.depth(k)).collect(),
        increments: h.increments,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The volume fields' names in results.h5 (each `(layers, N₁, N₂)`).
pub const FATIGUE_FIELDS: [&str; 4] = ["crossland", "dang_van", "swt", "fatemi_socie"];

impl LoopFatigue {
    /// The JSON keys `crossland_max`, `crossland_max_at` ([x, y, z] m), `dang_van_max(_at)`,
    /// `swt_max(_at)` (Pa), `fatemi_socie_max(_at)`, and the evaluation's cost.
    pub fn summary(&self) -> Value {
        let i = &self.indices;
        let finite = |v: f64| if v.is_finite() { json!(v) } else { Value::Null };
        json!({
            "crossland_max": finite(i.crossland_max.value),
            "crossland_max_at": self.at[0],
            "dang_van_max": finite(i.dang_van_max.value),
            "dang_van_max_at": self.at[1],
            "swt_max": finite(i.swt_max.value),
            "swt_max_at": self.at[2],
            "fatemi_socie_max": finite(i.fatemi_socie_max.value),
            "fatemi_socie_max_at": self.at[3],
            "fatigue": {
                "cells": i.crossland.len(),
                "layers": self.layers,
                "surface_layer": self.z.first() == Some(&0.0),
                "increments": self.increments,
                "invariant_evaluated": i.invariant_evaluated,
                "swt_evaluated": i.swt_evaluated,
                "fatemi_socie_evaluated": i.fatemi_socie_evaluated,
                "seconds": self.seconds,
            },
        })
    }

    /// `rec` with `z` (layer depths, m: 0 the surface layer, then `(2k + 1)Δ`) and the four
    /// volume fields `(layers, N₁, N₂)` (`NaN`
    /// where the screen skipped them), the maxima as attributes.
    pub fn record(&self, rec: Record) -> Record {
        let shape = [self.layers, self.shape.0, self.shape.1];
        let i = &self.indices;
        let mut rec = rec.array("z", self.z.clone());
        for (name, field) in
            FATIGUE_FIELDS
                .iter()
                .zip([&i.crossland, &i.dang_van, &i.swt, &i.fatemi_socie])
        {
            rec = rec.shaped(name, field.clone(), &shape);
        }
        for (k, (name, m)) in FATIGUE_FIELDS
            .iter()
            .zip([
                i.crossland_max,
                i.dang_van_max,
                i.swt_max,
                i.fatemi_socie_max,
            ])
            .enumerate()
        {
            rec = rec
                .attr(&format!("{name}_max"), AttrValue::Float(m.value))
                .attr(&format!("{name}_max_x"), AttrValue::Float(self.at[k][0]))
                .attr(&format!("{name}_max_y"), AttrValue::Float(self.at[k][1]))
                .attr(&format!("{name}_max_z"), AttrValue::Float(self.at[k][2]));
        }
        rec
    }

    /// The XDMF description of the volume fields (axes Z Y X = depth, x, y): a rectilinear
    /// lattice on the datasets `z`, `x`, `y` of results.h5 (the surface layer at `z = 0` is `Δ`
    /// above the first layer, the layers below `2Δ` apart).
    pub fn volume(&self) -> crate::data::RectilinearVolume {
        crate::data::RectilinearVolume {
            dims: [self.layers, self.shape.0, self.shape.1],
            axes: ["z".into(), "x".into(), "y".into()],
        }
    }
}
