//! The two convolution primitives of docs/theory-mdr.md#power-sums with the kernel `b_m = m^γ`, `γ > 0`
//! (so `b_0 = 0`), evaluated by one [`ToeplitzConvolution`] (FFT or MVM).
//!
//! * Causal sum (Eqs. 7, 13, 23, 26): `S_i[a] = ½ a_0 i^γ + Σ_{j=1}^{i−1} a_j (i−j)^γ`
//!   (zero-based), the trapezoid rule with the half weight at the lower end; the half weight at
//!   the upper end meets `b_0 = 0`.
//! * Anti-causal sum (Eqs. 17, 29): `A_j[c] = ½ c_{M−1} (M−1−j)^γ + Σ_{i=j+1}^{M−2} c_i (i−j)^γ`
//!   for `c_0 … c_{M−1}`: reverse, convolve causally, reverse.

use crate::{Backend, NumericsError, ToeplitzConvolution};

/// Causal and anti-causal trapezoid sums with the kernel `m^γ` (docs/theory-mdr.md#power-sums), for inputs of any
/// length up to the capacity. Owns its scratch; applying does not allocate.
pub struct PowerSum {
    gamma: f64,
    conv: ToeplitzConvolution,
    weighted: Vec<f64>,
    reversed_out: Vec<f64>,
}

impl PowerSum {
    /// Builds the sums for inputs of length up to `capacity` with exponent `gamma > 0`.
    pub fn new(capacity: usize, gamma: f64, backend: Backend) -> Result<Self, NumericsError> {
        if !(gamma.is_finite() && gamma > 0.0) {
            return Err(NumericsError::InvalidParameter {
                name: "kernel exponent γ",
                value: gamma,
                allowed: "finite and > 0",
            });
        }
        let kernel: Vec<f64> = (0..capacity).map(|m| (m as f64).powf(gamma)).collect();
        Ok(Self {
            gamma,
            conv: ToeplitzConvolution::new(kernel, backend)?,
            weighted: vec![0.0; capacity],
            reversed_out: vec![0.0; capacity],
        })
    }

    /// Plans shorter FFT lengths for inputs much shorter than the capacity
    /// ([`ToeplitzConvolution::plan_shorter_lengths`]; the same sums to rounding).
    pub fn plan_shorter_lengths(&mut self) {
        self.conv.plan_shorter_lengths();
    }

    /// The exponent `γ`.
    pub fn gamma(&self) -> f64 {
        self.gamma
    }

    /// The kernel `b_m = m^γ`, `m = 0..capacity` (reused by callers that need `(i h)^γ = h^γ b_i`).
    pub fn kernel(&self) -> &[f64] {
        self.conv.kernel()
    }

    /// Largest input length.
    pub fn capacity(&self) -> usize {
        self.conv.capacity()
    }

    /// The backend that evaluates the sums.
    pub fn backend(&self) -> Backend {
        self.conv.backend()
    }

    /// Causal sum `S_i[a] = Σ_{j=0}^{i} ã_j (i−j)^γ`, `ã_0 = a_0/2`, `ã_j = a_j` (docs/theory-mdr.md#power-sums).
    pub fn causal(&mut self, a: &[f64], out: &mut [f64]) -> Result<(), NumericsError> {
        let m = self.check(a.len(), out.len())?;
        if m == 0 {
            return Ok(());
        }
        let w = &mut self.weighted[..m];
        w.copy_from_slice(a);
        w[0] *= 0.5;
        self.conv.apply(w, out)?;
        // S_0 = ã_0 b_0 = 0 exactly; do not leave FFT rounding there.
        out[0] = 0.0;
        Ok(())
    }

    /// Anti-causal sum `A_j[c] = Σ_{i=j}^{M−1} c̃_i (i−j)^γ`, `c̃_{M−1} = c_{M−1}/2`, `M = c.len()`
    /// (docs/theory-mdr.md#power-sums); `A_{M−1} = 0` and `A_{M−2} = c_{M−1}/2`.
    pub fn anticausal(&mut self, c: &[f64], out: &mut [f64]) -> Result<(), NumericsError> {
        let m = self.check(c.len(), out.len())?;
        if m == 0 {
            return Ok(());
        }
        let w = &mut self.weighted[..m];
        for (wi, ci) in w.iter_mut().zip(c.iter().rev()) {
            *wi = *ci;
        }
        w[0] *= 0.5;
        let r = &mut self.reversed_out[..m];
        self.conv.apply(w, r)?;
        for (o, ri) in out.iter_mut().zip(r.iter().rev()) {
            *o = *ri;
        }
        // A_{M−1} = c̃_{M−1} b_0 = 0 exactly.
        out[m - 1] = 0.0;
        Ok(())
    }

    fn check(&self, m: usize, out: usize) -> Result<usize, NumericsError> {
        if out != m {
            return Err(NumericsError::LengthMismatch {
                what: "power-sum output",
                expected: m,
                got: out,
            });
        }
        if m > self.capacity() {
            return Err(NumericsError::LengthMismatch {
                what: "power-sum input (at most the capacity)",
                expected: self.capacity(),
                got: m,
            });
        }
        Ok(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// docs/theory-mdr.md#power-sums written out literally (one-based in the spec, zero-based here).
    fn causal_literal(a: &[f64], gamma: f64) -> Vec<f64> {
        (0..a.len())
            .map(|i| {
                if i == 0 {
                    return 0.0;
                }
                let mut s = 0.5 * a[0] * (i as f64).powf(gamma);
                for (j, aj) in a.iter().enumerate().take(i).skip(1) {
                    s += aj * ((i - j) as f64).powf(gamma);
                }
                s
            })
            .collect()
    }

    fn anticausal_literal(c: &[f64], gamma: f64) -> Vec<f64> {
        let m = c.len();
        (0..m)
            .map(|j| {
                if j == m - 1 {
                    return 0.0;
                }
                let mut s = 0.5 * c[m - 1] * ((m - 1 - j) as f64).powf(gamma);
                for (i, ci) in c.iter().enumerate().take(m - 1).skip(j + 1) {
                    s += ci * ((i - j) as f64).powf(gamma);
                }
                s
            })
            .collect()
    }

    #[test]
    fn sums_match_the_literal_formulas_and_the_special_values() {
        let a: Vec<f64> = (0..50).map(|i| (0.3 * i as f64).cos() + 1.5).collect();
        for backend in [Backend::Fft, Backend::Mvm] {
            for gamma in [0.5, 0.25, 0.75, 1.5] {
                let mut ps = PowerSum::new(80, gamma, backend).unwrap();
                let mut s = vec![0.0; a.len()];
                ps.causal(&a, &mut s).unwrap();
                let want = causal_literal(&a, gamma);
                let scale = want.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                for i in 0..a.len() {
                    assert!((s[i] - want[i]).abs() < 1e-14 * scale);
                }
                assert_eq!(s[0], 0.0);
                assert!((s[1] - 0.5 * a[0]).abs() < 1e-14 * scale);
                ps.anticausal(&a, &mut s).unwrap();
                let want = anticausal_literal(&a, gamma);
                let scale = want.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                for i in 0..a.len() {
                    assert!((s[i] - want[i]).abs() < 1e-14 * scale);
                }
                assert_eq!(s[49], 0.0);
                assert!((s[48] - 0.5 * a[49]).abs() < 1e-14 * scale);
            }
        }
    }

    #[test]
    fn invalid_exponent_is_an_error() {
        assert!(PowerSum::new(10, 0.0, Backend::Fft).is_err());
        assert!(PowerSum::new(10, f64::NAN, Backend::Fft).is_err());
    }
}
