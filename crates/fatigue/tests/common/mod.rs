//! Shared helpers of the fatigue tests: a fixed-seed generator and random paths.
#![allow(dead_code)]
use halfspace_fatigue::Voigt;

/// SplitMix64: a fixed-seed generator for reproducible test inputs.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.uniform()
    }
    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = self.uniform().max(1e-300);
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }
    pub fn point5(&mut self) -> [f64; 5] {
        std::array::from_fn(|_| self.range(-1.0, 1.0))
    }
    /// A random rotation matrix (Gram–Schmidt of Gaussian columns, det +1).
    pub fn rotation(&mut self) -> [[f64; 3]; 3] {
        rotation_from(std::array::from_fn(|_| self.normal()))
    }
}

/// A rotation from 9 numbers (rows Gram–Schmidt orthonormalised, last row the cross product;
/// degenerate rows are replaced by a coordinate axis).
pub fn rotation_from(g: [f64; 9]) -> [[f64; 3]; 3] {
    let len = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let norm = |v: [f64; 3]| {
        let l = len(v);
        [v[0] / l, v[1] / l, v[2] / l]
    };
    let a0 = [g[0], g[1], g[2]];
    let a = if len(a0) > 1e-3 {
        norm(a0)
    } else {
        [1.0, 0.0, 0.0]
    };
    let orth = |b0: [f64; 3]| {
        let d = a[0] * b0[0] + a[1] * b0[1] + a[2] * b0[2];
        [b0[0] - d * a[0], b0[1] - d * a[1], b0[2] - d * a[2]]
    };
    let mut b1 = orth([g[3], g[4], g[5]]);
    for axis in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
        if len(b1) > 1e-3 {
            break;
        }
        b1 = orth(axis);
    }
    // Gram–Schmidt twice ("twice is enough"): one pass leaves b off-orthogonal to a by
    // ~ε/|b1|, and |b1| may be 1e-3, which would make R S Rᵀ change the principal values by
    // ~1e3 ε|S| — the tests would measure the helper, not the code.
    let b = norm(orth(norm(b1)));
    let c = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    [a, b, c]
}

/// A random non-proportional cycle: `σ(t) = mean + Σ_h A_h cos(h ωt) + B_h sin(h ωt)` with two
/// harmonics, amplitudes ~`amp`, `n` increments over one period.
pub fn random_cycle(rng: &mut Rng, n: usize, amp: f64, mean: f64) -> Vec<Voigt> {
    let m: Voigt = std::array::from_fn(|_| mean * rng.range(-1.0, 1.0));
    let coef: Vec<Voigt> = (0..4)
        .map(|_| std::array::from_fn(|_| amp * rng.range(-1.0, 1.0)))
        .collect();
    (0..n)
        .map(|i| {
            let w = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
            let (c1, s1, c2, s2) = (w.cos(), w.sin(), (2.0 * w).cos(), (2.0 * w).sin());
            std::array::from_fn(|k| {
                m[k] + coef[0][k] * c1 + coef[1][k] * s1 + 0.3 * (coef[2][k] * c2 + coef[3][k] * s2)
            })
        })
        .collect()
}

/// A proportional cycle `σ(t) = mean + λ(t) direction`, λ = sin over `n` increments.
pub fn proportional_cycle(mean: Voigt, direction: Voigt, n: usize) -> Vec<Voigt> {
    (0..n)
        .map(|i| {
            let l = (2.0 * std::f64::consts::PI * i as f64 / n as f64).sin();
            std::array::from_fn(|k| mean[k] + l * direction[k])
        })
        .collect()
}

/// A steel-like material: f₋₁ = 400 MPa, t₋₁ = 280 MPa, E = 210 GPa, ν = 0.3, k = 0.5,
/// σ_y = 600 MPa.
pub fn steel() -> halfspace_fatigue::Material {
    halfspace_fatigue::Material {
        f_minus1: 400e6,
        t_minus1: 280e6,
        young: 210e9,
        poisson: 0.3,
        fs_k: 0.5,
        yield_stress: 600e6,
    }
}

/// `R σ Rᵀ` over a path.
pub fn rotate_path(path: &[Voigt], r: &[[f64; 3]; 3]) -> Vec<Voigt> {
    path.iter()
        .map(|s| halfspace_fatigue::tensor::rotate(s, r))
        .collect()
}
