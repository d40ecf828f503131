//! Trapezoid rules on uniform grids.

/// `h [y_0/2 + y_1 + … + y_{n−2} + y_{n−1}/2]`; 0 for fewer than two nodes.
pub fn trapezoid_uniform(y: &[f64], h: f64) -> f64 {
    match y.len() {
        0 | 1 => 0.0,
        n => h * (0.5 * (y[0] + y[n - 1]) + y[1..n - 1].iter().sum::<f64>()),
    }
}

/// Cumulative trapezoid: `out_0 = 0`, `out_i = out_{i−1} + h (y_{i−1} + y_i)/2`.
pub fn cumulative_trapezoid_uniform(y: &[f64], h: f64, out: &mut [f64]) {
    let mut acc = 0.0;
    for i in 0..y.len().min(out.len()) {
        if i > 0 {
            acc += 0.5 * h * (y[i - 1] + y[i]);
        }
        out[i] = acc;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_for_linear_functions() {
        let y: Vec<f64> = (0..11).map(|i| 2.0 + 0.5 * i as f64).collect();
        // ∫_0^10 (2 + x/2) dx = 20 + 25
        assert!((trapezoid_uniform(&y, 1.0) - 45.0).abs() < 1e-12);
        let mut c = vec![0.0; 11];
        cumulative_trapezoid_uniform(&y, 1.0, &mut c);
        assert!((c[10] - 45.0).abs() < 1e-12);
        assert_eq!(c[0], 0.0);
    }
}
