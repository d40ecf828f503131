//! Shared helpers of the MDR integration tests.
#![allow(dead_code)]

/// Least-squares slope of `ln e` against `ln N`: the observed order is `−slope`.
pub fn observed_order(ns: &[usize], errors: &[f64]) -> f64 {
    let xs: Vec<f64> = ns.iter().map(|&n| (n as f64).ln()).collect();
    let ys: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let k = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / k, ys.iter().sum::<f64>() / k);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    -sxy / sxx
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
