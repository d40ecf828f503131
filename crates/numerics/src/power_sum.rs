//! The two convolution primitives of docs/theory-mdr.md#power-sums with the kernel `b_m = m^γ`, `γ > 0`
//! (so `b_0 = 0`), evaluated by one [`ToeplitzConvolution`] (FFT or MVM).
//!
//! * Causal sum (Eqs. 7, 13, 23, 26): `S_i[a] = ½ a_0 i^γ + Σ_{j=1}^{i−1} a_j (i−j)^γ`
//!   (zero-based), the trapezoid rule with the half weight at the lower end; the half weight at
//!   the upper end meets `b_0 = 0`.
//! * Anti-causal sum (Eqs. 17, 29): `A_j[c] = ½ c_{M−1} (M−1−j)^γ + Σ_{i=j+1}^{M−2} c_i (i−j)^γ`
//!   for `c_0 … c_{M−1}`: reverse, convolve causally, reverse.

use crate::{Backend, NumericsError, Precision, ToeplitzConvolution};

/// Causal and anti-causal trapezoid sums with the kernel `m^γ` (docs/theory-mdr.md#power-sums), for inputs of any
/// length up to the capacity. Owns its scratch; applying does not allocate.
pub struct PowerSum {
    gamma: f64,
    conv: ToeplitzConvolution,
    /// The convolution with the increments `e_m = m^γ − (m−1)^γ` (`e_0 = 0`) in `f32`
    /// ([`PowerSum::causal_increments`]), once [`Precision::Single`] was asked for.
    increments: Option<ToeplitzConvolution>,
    /// The precision of [`PowerSum::causal_increments`].
    precision: Precision,
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
            increments: None,
            precision: Precision::Double,
            weighted: vec![0.0; capacity],
            reversed_out: vec![0.0; capacity],
        })
    }

    /// Plans shorter FFT lengths for inputs much shorter than the capacity
    /// ([`ToeplitzConvolution::plan_shorter_lengths`]; the same sums to rounding).
    pub fn plan_shorter_lengths(&mut self) {
        self.conv.plan_shorter_lengths();
        if let Some(increments) = &mut self.increments {
            increments.plan_shorter_lengths();
        }
    }

    /// The precision of [`PowerSum::causal_increments`] (no effect with the MVM backend).
    /// [`Precision::Single`] convolves with the increments `e_m = m^γ − (m−1)^γ` directly, by
    /// `f32` transforms ([`ToeplitzConvolution::set_precision`], planned on the first request,
    /// with the ladder of shorter plans if the sums have one; later switches allocate nothing):
    /// the error is `O(ε₃₂ log P)` of the increments' own scale (the kernel decays like
    /// `m^{γ−1}`), where differencing sums `S` computed in `f32` would lose a factor of order `M`
    /// to cancellation (`S_i` grows like `i^{γ+1}`; docs/performance.md, "The N = 8001 wear run:
    /// single-precision stage products (issue 20)"). [`PowerSum::causal`] and
    /// [`PowerSum::anticausal`] stay in `f64`.
    pub fn set_precision(&mut self, precision: Precision) -> Result<(), NumericsError> {
        if self.conv.backend() == Backend::Mvm {
            return Ok(());
        }
        if precision == Precision::Single && self.increments.is_none() {
            let b = self.conv.kernel();
            let kernel = (0..b.len())
                .map(|m| if m == 0 { 0.0 } else { b[m] - b[m - 1] })
                .collect();
            let mut conv = ToeplitzConvolution::new(kernel, Backend::Fft)?;
            if self.conv.padded_length_for(1) != self.conv.padded_length() {
                conv.plan_shorter_lengths();
            }
            conv.set_precision(Precision::Single);
            self.increments = Some(conv);
        }
        self.precision = precision;
        Ok(())
    }

    /// The precision of [`PowerSum::causal_increments`].
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// The increments of the causal sum, `E_i = S_i[a] − S_{i−1}[a]` (`E_0 = S_0 = 0`), as one
    /// convolution `E_i = Σ_{j=0}^{i} ã_j e_{i−j}` with `e_m = m^γ − (m−1)^γ`, `e_0 = b_0 = 0`
    /// (docs/theory-mdr.md#power-sums: `S_i − S_{i−1} = Σ_j ã_j (b_{i−j} − b_{i−1−j})`, the term
    /// `j = i` of `S_{i−1}` absent). With [`Precision::Single`] from `f32` transforms; with
    /// [`Precision::Double`] the differences of [`PowerSum::causal`] (the reference).
    pub fn causal_increments(&mut self, a: &[f64], out: &mut [f64]) -> Result<(), NumericsError> {
        let m = self.check(a.len(), out.len())?;
        if m == 0 {
            return Ok(());
        }
        match (&mut self.increments, self.precision) {
            (Some(conv), Precision::Single) => {
                let w = &mut self.weighted[..m];
                w.copy_from_slice(a);
                w[0] *= 0.5;
                conv.apply(w, out)?;
            }
            _ => {
                self.causal(a, out)?;
                for i in (1..m).rev() {
                    out[i] -= out[i - 1];
                }
            }
        }
        out[0] = 0.0;
        Ok(())
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

    /// The causal sum's increments `E_i = S_i − S_{i−1}`: in `f64` (the differences of
    /// `causal`) against the literal sums' differences to rounding, and in `f32` (one convolution
    /// with `m^γ − (m−1)^γ`) against the `f64` ones within `5e-6` of their largest — the `f32`
    /// transforms' `O(ε₃₂ log₂ P)` (measured at most 2.5e-7 up to `N = 8001`; differencing the sums
    /// themselves in `f32` loses a factor of order `N`: 1e-3 at `N = 8001`) — with the ladder of
    /// shorter plans. The MVM backend stays in `f64`.
    #[test]
    fn causal_increments_in_both_precisions() {
        let a: Vec<f64> = (0..60).map(|i| (0.3 * i as f64).cos() + 1.5).collect();
        for gamma in [0.5, 0.25, 0.75] {
            let mut ps = PowerSum::new(80, gamma, Backend::Fft).unwrap();
            let mut e = vec![0.0; a.len()];
            ps.causal_increments(&a, &mut e).unwrap();
            let s = causal_literal(&a, gamma);
            let scale = s.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            assert_eq!(e[0], 0.0);
            for i in 1..a.len() {
                assert!((e[i] - (s[i] - s[i - 1])).abs() < 1e-14 * scale);
            }
        }
        let mut worst = 0.0f64;
        for (n, gamma) in [
            (121usize, 0.5),
            (2001, 0.5),
            (2001, 0.25),
            (8001, 0.5),
            (8001, 0.75),
        ] {
            let a = crate::testkit::lcg(7 + n as u64, n);
            let mut ps = PowerSum::new(n, gamma, Backend::Fft).unwrap();
            ps.plan_shorter_lengths();
            for m in [n, n / 3] {
                let (mut e64, mut e32) = (vec![0.0; m], vec![0.0; m]);
                ps.set_precision(Precision::Double).unwrap();
                ps.causal_increments(&a[..m], &mut e64).unwrap();
                ps.set_precision(Precision::Single).unwrap();
                assert_eq!(ps.precision(), Precision::Single);
                ps.causal_increments(&a[..m], &mut e32).unwrap();
                let scale = e64.iter().fold(0.0f64, |w, v| w.max(v.abs()));
                let error = e64
                    .iter()
                    .zip(&e32)
                    .fold(0.0f64, |w, (u, v)| w.max((u - v).abs()));
                assert!(
                    error <= 5e-6 * scale,
                    "n = {n}, γ = {gamma}: {error:e} of {scale:e}"
                );
                assert!(error > 1e-13 * scale, "the f32 plans were not used");
                worst = worst.max(error / scale);
            }
        }
        eprintln!("f32 increments: at most {worst:.2e} of the largest");
        let mut mvm = PowerSum::new(10, 0.5, Backend::Mvm).unwrap();
        mvm.set_precision(Precision::Single).unwrap();
        assert_eq!(mvm.precision(), Precision::Double);
    }

    #[test]
    fn invalid_exponent_is_an_error() {
        assert!(PowerSum::new(10, 0.0, Backend::Fft).is_err());
        assert!(PowerSum::new(10, f64::NAN, Backend::Fft).is_err());
    }
}
