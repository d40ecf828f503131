//! The row of one increment of the fretting loop (what [`super::FrettingLoop`] records and
//! [`super::LoopMetrics`] reads).

use crate::contact::{IncrementInfo, NestedInfo};

/// One increment of the loop (deterministic: equal on a resumed and an uninterrupted run).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoopRow {
    /// Normal force W (N).
    pub w: f64,
    /// Shift δx (m).
    pub d: f64,
    /// Tangential force `(Q₁, Q₂)` (N).
    pub q: [f64; 2],
    /// Largest pressure (Pa).
    pub max_pressure: f64,
    /// Contact area (m²).
    pub contact_area: f64,
    /// Stick area (m²).
    pub stick_area: f64,
    /// Panagiotopoulos alternations (of the last contact solve).
    pub alternations: usize,
    /// Rigid approach δ (m).
    pub approach: f64,
    /// Outer contact ↔ EIM passes (0 without inhomogeneities).
    pub outer_iterations: usize,
    /// EIM operator applications summed over the outer passes (0 without inhomogeneities).
    pub eim_iterations: usize,
}

impl LoopRow {
    /// Names of [`LoopRow::values`], as stored in the results and checkpoints.
    pub const FIELDS: [&'static str; 11] = [
        "normal_force",
        "shift_x",
        "tangential_force",
        "tangential_force_y",
        "max_pressure",
        "contact_area",
        "stick_area",
        "alternations",
        "approach",
        "outer_iterations",
        "eim_iterations",
    ];

    pub(super) fn of(w: f64, d: f64, info: &IncrementInfo, nested: Option<&NestedInfo>) -> Self {
        Self {
            w,
            d,
            q: info.tangential_force,
            max_pressure: info.max_pressure,
            contact_area: info.contact_area,
            stick_area: info.stick_area,
            alternations: info.alternations,
            approach: info.normal.approach,
            outer_iterations: nested.map_or(0, |n| n.outer_iterations),
            eim_iterations: nested.map_or(0, |n| n.eim_iterations),
        }
    }

    /// The row as numbers in the order of [`LoopRow::FIELDS`].
    pub fn values(&self) -> [f64; 11] {
        [
            self.w,
            self.d,
            self.q[0],
            self.q[1],
            self.max_pressure,
            self.contact_area,
            self.stick_area,
            self.alternations as f64,
            self.approach,
            self.outer_iterations as f64,
            self.eim_iterations as f64,
        ]
    }

    /// The inverse of [`LoopRow::values`].
    pub fn from_values(v: [f64; 11]) -> Self {
        Self {
            w: v[0],
            d: v[1],
            q: [v[2], v[3]],
            max_pressure: v[4],
            contact_area: v[5],
            stick_area: v[6],
            alternations: v[7] as usize,
            approach: v[8],
            outer_iterations: v[9] as usize,
            eim_iterations: v[10] as usize,
        }
    }
}
