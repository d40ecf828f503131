//! Second-order finite differences on a uniform grid (docs/theory-mdr.md#finite-differences):
//!
//! `D[y]_0 = (−3y_0 + 4y_1 − y_2)/(2h)`, `D[y]_i = (y_{i+1} − y_{i−1})/(2h)`,
//! `D[y]_{n−1} = (3y_{n−1} − 4y_{n−2} + y_{n−3})/(2h)` — `numpy.gradient(y, h, edge_order=2)`.
//!
//! Always differentiate arrays cut at a kink (the contact edge), never across it (docs/theory-mdr.md#p3-one-sided-differences-at-the-edge).

use crate::NumericsError;

/// Writes `D[y]` (docs/theory-mdr.md#finite-differences) into `out`. Needs `y.len() == out.len() ≥ 3`; with 2 nodes the
/// first-order difference is used on both, with 1 node the derivative is 0.
pub fn derivative_uniform(y: &[f64], h: f64, out: &mut [f64]) -> Result<(), NumericsError> {
    let n = y.len();
    if out.len() != n {
        return Err(NumericsError::LengthMismatch {
            what: "derivative output",
            expected: n,
            got: out.len(),
        });
    }
    match n {
        0 => {}
        1 => out[0] = 0.0,
        2 => {
            let d = (y[1] - y[0]) / h;
            out[0] = d;
            out[1] = d;
        }
        _ => {
            let inv2h = 0.5 / h;
            out[0] = (-3.0 * y[0] + 4.0 * y[1] - y[2]) * inv2h;
            for (o, w) in out[1..n - 1].iter_mut().zip(y[..n].windows(3)) {
                *o = (w[2] - w[0]) * inv2h;
            }
            out[n - 1] = (3.0 * y[n - 1] - 4.0 * y[n - 2] + y[n - 3]) * inv2h;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_for_quadratics_including_the_ends() {
        let h = 0.1;
        let y: Vec<f64> = (0..7)
            .map(|i| {
                let x = i as f64 * h;
                3.0 * x * x - 2.0 * x + 1.0
            })
            .collect();
        let mut d = vec![0.0; 7];
        derivative_uniform(&y, h, &mut d).unwrap();
        for (i, di) in d.iter().enumerate() {
            let x = i as f64 * h;
            assert!((di - (6.0 * x - 2.0)).abs() < 1e-12, "node {i}: {di}");
        }
    }

    #[test]
    fn second_order_convergence_on_a_smooth_function() {
        let err = |n: usize| {
            let h = 1.0 / (n - 1) as f64;
            let y: Vec<f64> = (0..n).map(|i| (i as f64 * h).exp().sin()).collect();
            let mut d = vec![0.0; n];
            derivative_uniform(&y, h, &mut d).unwrap();
            (0..n)
                .map(|i| {
                    let x = i as f64 * h;
                    (d[i] - x.exp().cos() * x.exp()).abs()
                })
                .fold(0.0, f64::max)
        };
        let order = (err(101) / err(201)).log2();
        assert!((order - 2.0).abs() < 0.1, "observed order {order}");
    }

    #[test]
    fn length_mismatch_is_an_error() {
        let mut d = vec![0.0; 2];
        assert!(derivative_uniform(&[1.0, 2.0, 3.0], 1.0, &mut d).is_err());
    }
}
