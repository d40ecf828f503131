//! What the tests of every crate share: fixed-seed inputs and the check of a fast operator against
//! its dense twin (RustFFT-style: the fast algorithm against a naive control with fixed seeds).

use crate::op::GridOperator;
use crate::NumericsError;

/// A 64-bit linear congruential generator (Knuth's MMIX constants): the same fixed-seed stream on
/// every machine, for test inputs.
#[derive(Debug, Clone)]
pub struct Lcg(u64);

impl Lcg {
    /// The stream seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next value, uniform in `[0, 1)` (the top 53 bits of the state).
    pub fn unit(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `n` values uniform in `[−1, 1)` from [`Lcg`] seeded with `seed`.
pub fn lcg(seed: u64, n: usize) -> Vec<f64> {
    let mut g = Lcg::new(seed);
    (0..n).map(|_| g.unit() * 2.0 - 1.0).collect()
}

/// `max |fast(x) − twin(x)| / max |twin(x)|` over inputs `x` drawn by [`lcg`] from each seed (every
/// input field from its own stream): the one check of every fast operator against its dense twin.
/// The two must have the same shape.
pub fn twin_error(
    fast: &mut dyn GridOperator,
    twin: &mut dyn GridOperator,
    seeds: &[u64],
) -> Result<f64, NumericsError> {
    let shape = fast.shape();
    if twin.shape() != shape {
        return Err(NumericsError::LengthMismatch {
            what: "fields of an operator and its twin",
            expected: shape.inputs * shape.outputs * shape.field_len(),
            got: {
                let t = twin.shape();
                t.inputs * t.outputs * t.field_len()
            },
        });
    }
    let len = shape.field_len();
    let mut worst: f64 = 0.0;
    for &seed in seeds {
        let xs: Vec<Vec<f64>> = (0..shape.inputs)
            .map(|i| lcg(seed.wrapping_mul(1000).wrapping_add(i as u64), len))
            .collect();
        let x: Vec<&[f64]> = xs.iter().map(|v| v.as_slice()).collect();
        let mut f = vec![vec![0.0; len]; shape.outputs];
        let mut d = vec![vec![0.0; len]; shape.outputs];
        {
            let mut y: Vec<&mut [f64]> = f.iter_mut().map(|v| v.as_mut_slice()).collect();
            fast.apply(&x, &mut y)?;
        }
        {
            let mut y: Vec<&mut [f64]> = d.iter_mut().map(|v| v.as_mut_slice()).collect();
            twin.apply(&x, &mut y)?;
        }
        let scale = d.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let err = f
            .iter()
            .flatten()
            .zip(d.iter().flatten())
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        worst = worst.max(if scale > 0.0 { err / scale } else { err });
    }
    Ok(worst)
}
