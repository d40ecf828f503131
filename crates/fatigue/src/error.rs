//! Typed errors of the fatigue criteria: every message names the offending parameter or entry.
use thiserror::Error;

/// What can go wrong when evaluating a fatigue criterion.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FatigueError {
    /// A stress path with no increment has no cycle.
    #[error("empty stress path: a cycle needs at least one increment")]
    EmptyPath,
    /// A stress component of a path is NaN or infinite.
    #[error("non-finite stress at increment {increment}, component {component}: {value}")]
    NonFiniteStress {
        increment: usize,
        component: usize,
        value: f64,
    },
    /// A stress component of a field is NaN or infinite.
    #[error(
        "non-finite stress at point {point}, increment {increment}, component {component}: {value}"
    )]
    NonFiniteField {
        point: usize,
        increment: usize,
        component: usize,
        value: f64,
    },
    /// A material constant is out of its admissible range.
    #[error("invalid material parameter `{name}` = {value}: {reason}")]
    InvalidMaterial {
        name: &'static str,
        value: f64,
        reason: &'static str,
    },
    /// Crossland and Dang Van need `f₋₁/√3 < t₋₁ ≤ f₋₁` (docs/fatigue.md, "Material constants").
    #[error(
        "invalid material parameter `t_minus1` = {t_minus1} Pa: Crossland and Dang Van need \
         f_minus1/√3 < t_minus1 <= f_minus1, here ({lower} Pa, {f_minus1} Pa]"
    )]
    TorsionBendingRatio {
        f_minus1: f64,
        t_minus1: f64,
        lower: f64,
    },
    /// A parameter of the critical-plane search is out of range.
    #[error("invalid search parameter `{name}` = {value}: {reason}")]
    InvalidSearch {
        name: &'static str,
        value: f64,
        reason: &'static str,
    },
    /// A deviation bound of a screening bound is negative or not finite.
    #[error(
        "invalid deviation bound at segment {segment}, component {component}: {value} \
         (must be finite and non-negative)"
    )]
    InvalidDeviation {
        segment: usize,
        component: usize,
        value: f64,
    },
    /// The minimum-ball pivoting did not terminate (cannot happen in exact arithmetic).
    #[error("minimum enclosing ball: no convergence after {iterations} pivot iterations")]
    NoConvergence { iterations: usize },
    /// The flat stress slice of a field does not have `points × increments × 6` entries.
    #[error(
        "field shape: {len} values is not points × increments × 6 = {points} × {increments} × 6"
    )]
    FieldShape {
        len: usize,
        points: usize,
        increments: usize,
    },
    /// The process volume is smaller than a cell of the box (docs/fatigue.md, "Process volume").
    #[error(
        "process volume side {side} m is below a cell of the box ({cell} m): the average would \
         interpolate within one cell"
    )]
    ProcessVolumeBelowCell { side: f64, cell: f64 },
    /// The process volume does not fit in the box.
    #[error(
        "process volume side {side} m is beyond the box (its smallest extent, or no point's \
         volume inside it: {reach} m)"
    )]
    ProcessVolumeBeyondBox { side: f64, reach: f64 },
    /// No point of the box has its process volume inside the nodes: e.g. the depths start below
    /// the surface, so the cubes of the shallow points (top face on `z = 0`) leave the box and the
    /// deeper ones reach past its bottom.
    #[error(
        "process volume side {side} m: no point of the box has its cube inside the nodes \
         (depths {depth_min} m to {depth_max} m; a cube within side/2 of the surface has its top \
         face on z = 0: store the surface z = 0, or nodes deeper than one side below the first)"
    )]
    ProcessVolumeNoPointInside {
        side: f64,
        depth_min: f64,
        depth_max: f64,
    },
    /// The material map does not have one entry per point of the box.
    #[error("material map: {len} entries for {points} points of the box")]
    MaterialMapLength { len: usize, points: usize },
    /// The sizes of a box overflow the address space (`usize`).
    #[error("{what}: the size overflows usize")]
    SizeOverflow { what: &'static str },
    /// The nodes of the box along one axis are not increasing.
    #[error("process volume: the {axis} nodes of the box: {reason}")]
    ProcessVolumeNodes {
        axis: &'static str,
        reason: &'static str,
    },
}
