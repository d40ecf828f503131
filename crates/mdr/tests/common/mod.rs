//! Shared helpers of the MDR integration tests.
#![allow(dead_code)]

#[allow(unused_imports)]
pub use halfspace_mdr::studies::observed_order;

use halfspace_mdr::{Backend, ContactParams, ContactSolver, Material};

/// A contact solver on `nodes` nodes with the default domain ratio and tolerances.
pub fn solver_for(material: Material, nodes: usize, backend: Backend) -> ContactSolver {
    ContactSolver::new(
        material,
        ContactParams {
            nodes,
            backend,
            ..Default::default()
        },
    )
    .unwrap()
}

/// `|a − b| / |b|`.
pub fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

/// Mean of `|a_i − b_i| / |b_i|` over the given indices.
pub fn mean_relative_error(a: &[f64], b: &[f64], range: std::ops::Range<usize>) -> f64 {
    let n = range.len() as f64;
    range.map(|i| ((a[i] - b[i]) / b[i]).abs()).sum::<f64>() / n
}

/// Max of `|a_i − b_i|` over the given indices.
pub fn max_abs_error(a: &[f64], b: &[f64], range: std::ops::Range<usize>) -> f64 {
    range.map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max)
}

/// `max |a − b| / max |b|`: the relative error in the max norm.
pub fn relative_max_norm(a: &[f64], b: &[f64]) -> f64 {
    let num = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    let den = b.iter().map(|y| y.abs()).fold(0.0, f64::max);
    num / den
}
