use std::f64::consts::FRAC_2_PI;

use halfspace_numerics::{diff::derivative_uniform, Backend, NumericsError, PowerSum, SquaredGrid};
use rayon::prelude::*;

use super::{check_fits, check_len};
use crate::MdrError;

/// Which discretization of the displacement transform (spec §2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DisplacementMethod {
    /// Eq. 12: `û(ρ) = U(0) + (2/π) ∫_0^ρ Û'(ξ) arccos √(ξ/ρ) dξ`, a dense (not Toeplitz)
    /// O(N²) product; the kernel is evaluated on the fly, rows in parallel.
    DenseKernel,
    /// Eq. 13: `û(ρ) = U(0) + (2/π)[√ρ L₀ + ∫_0^ρ β(ξ) √(ρ−ξ) dξ]`, `β = d/dξ (Û/√ξ)`, a causal
    /// convolution evaluated by the given backend (FFT, or its dense twin).
    Convolution(Backend),
}

impl DisplacementMethod {
    /// The method the CLI's `--method` selects: `mvm` → Eq. 12, `fft` → Eq. 13 by FFT.
    pub fn for_backend(backend: Backend) -> Self {
        match backend {
            Backend::Mvm => DisplacementMethod::DenseKernel,
            Backend::Fft => DisplacementMethod::Convolution(Backend::Fft),
        }
    }
}

/// Displacement transform `U(x) → u(r)` of the MDR (paper Eq. 8; spec §2):
/// `u(r) = (2/π) ∫_0^r U(x) / √(r² − x²) dx`, for a 1D displacement `U` given on the contact nodes
/// `0..M` and zero beyond (`a² = ξ_{M−1}`), evaluated on every node of the grid, inside and outside
/// the contact.
///
/// Both discretizations treat the edge of the contact exactly: `Û'` is differenced on the array cut
/// at `a` (spec §7 P3) and the jump `U(a⁻)` contributes its closed form. Two further closed-form
/// splits make them accurate for every profile (spec §7 P11 — these are this project's additions,
/// not the paper's):
/// * Eq. 12 splits off `U(0) + L₀ x` (`L₀ = lim Ũ/x`, the conical part), whose transform is
///   `U(0) + (2/π) L₀ r` inside and `(2/π)[U(0) arcsin(a/r) + L₀ (r − √(r² − a²))]` outside.
/// * Eq. 13 needs `Ũ = L₀ x + O(x³)`; a parabolic term `c₂ x²`, present in every smooth contact, is
///   subtracted over the whole grid and added back as its transform `c₂ r²/2` (`c₂` is estimated
///   from the first nodes; any value is exact, a good one keeps `β` smooth). Without this split
///   Eq. 13 converges as `O(N^{−1/2})` on Hertz (spec §2 test 2).
pub struct DisplacementTransform {
    method: DisplacementMethod,
    capacity: usize,
    sum: Option<PowerSum>,
    du: Vec<f64>,
    b: Vec<f64>,
    beta: Vec<f64>,
    s: Vec<f64>,
    sqrt_index: Vec<f64>,
}

impl DisplacementTransform {
    /// Builds the transform for grids of up to `capacity` nodes.
    pub fn new(capacity: usize, method: DisplacementMethod) -> Result<Self, MdrError> {
        let sum = match method {
            DisplacementMethod::DenseKernel => None,
            DisplacementMethod::Convolution(backend) => {
                Some(PowerSum::new(capacity, 0.5, backend)?)
            }
        };
        Ok(Self {
            method,
            capacity,
            sum,
            du: vec![0.0; capacity],
            b: vec![0.0; capacity],
            beta: vec![0.0; capacity],
            s: vec![0.0; capacity],
            sqrt_index: (0..capacity).map(|i| (i as f64).sqrt()).collect(),
        })
    }

    /// The discretization in use.
    pub fn method(&self) -> DisplacementMethod {
        self.method
    }

    /// `u` on every node from `U` on the contact nodes `0..M` (`M = u_contact.len() ≥ 3`, `U = 0`
    /// beyond) and `L₀ = lim_{x→0} (U(x) − U(0))/x`.
    pub fn apply(
        &mut self,
        grid: &SquaredGrid,
        u_contact: &[f64],
        l0: f64,
        out: &mut [f64],
    ) -> Result<(), MdrError> {
        check_fits("displacement transform grid", grid, self.capacity)?;
        let n = grid.len();
        check_len("surface displacement u", n, out.len())?;
        let m_nodes = u_contact.len();
        if m_nodes < 3 || m_nodes > n {
            return Err(MdrError::Numerics(NumericsError::TooFewNodes {
                what: "the displacement transform (contact nodes, at most the grid)",
                min: 3,
                n: m_nodes,
            }));
        }
        if !l0.is_finite() {
            return Err(MdrError::InvalidParameter {
                name: "slope at the origin L₀",
                value: l0,
                allowed: "finite",
            });
        }
        match self.method {
            DisplacementMethod::DenseKernel => self.arccos_kernel(grid, u_contact, l0, out),
            DisplacementMethod::Convolution(_) => self.convolution(grid, u_contact, l0, out),
        }
    }

    /// Eq. 12 with the trapezoid rule over `0 ≤ ξ ≤ min(ρ_j, a²)` (spec §2 Variant A).
    fn arccos_kernel(
        &mut self,
        grid: &SquaredGrid,
        u: &[f64],
        l0: f64,
        out: &mut [f64],
    ) -> Result<(), MdrError> {
        let m = u.len() - 1;
        let h = grid.step();
        let u0 = u[0];
        // V = U − U(0) − L₀ x on the contact (smooth, O(x²)); its ξ-derivative cut at a.
        let v = &mut self.b[..=m];
        for (i, vi) in v.iter_mut().enumerate() {
            *vi = u[i] - u0 - l0 * grid.coordinate(i);
        }
        let v_edge = v[m];
        derivative_uniform(v, h, &mut self.du[..=m])?;
        let dv = &self.du[..=m];
        let sq = &self.sqrt_index;
        out.par_iter_mut().enumerate().for_each(|(j, uj)| {
            if j == 0 {
                *uj = u0;
                return;
            }
            let top = j.min(m);
            let inv = 1.0 / sq[j];
            let mut acc = 0.5 * dv[0] * std::f64::consts::FRAC_PI_2;
            for i in 1..top {
                acc += dv[i] * (sq[i] * inv).min(1.0).acos();
            }
            acc += 0.5 * dv[top] * (sq[top] * inv).min(1.0).acos();
            let r = grid.coordinate(j);
            let mut value = FRAC_2_PI * h * acc;
            if j <= m {
                value += u0 + FRAC_2_PI * l0 * r;
            } else {
                let ratio = sq[m] * inv;
                let a = grid.coordinate(m);
                value += -FRAC_2_PI * v_edge * ratio.acos()
                    + FRAC_2_PI * u0 * ratio.asin()
                    + FRAC_2_PI * l0 * (r - (r * r - a * a).max(0.0).sqrt());
            }
            *uj = value;
        });
        Ok(())
    }

    /// Eq. 13 with the parabolic split and the exact edge jump (spec §2 Variant B).
    fn convolution(
        &mut self,
        grid: &SquaredGrid,
        u: &[f64],
        l0: f64,
        out: &mut [f64],
    ) -> Result<(), MdrError> {
        let n = grid.len();
        let m = u.len() - 1;
        let h = grid.step();
        let u0 = u[0];
        let x = |i: usize| grid.coordinate(i);
        // c₂ ≈ lim (Ũ − L₀x)/x², by linear extrapolation in x from nodes 1 and 2.
        let v1 = (u[1] - u0 - l0 * x(1)) / grid.squared(1);
        let v2 = (u[2] - u0 - l0 * x(2)) / grid.squared(2);
        let c2 = (v1 * x(2) - v2 * x(1)) / (x(2) - x(1));
        // B = (Ũ − c₂ξ)/√ξ inside (B₀ = L₀), and its outside branch from node m on.
        let b = &mut self.b[..n];
        b[0] = l0;
        for i in 1..=m {
            b[i] = (u[i] - u0 - c2 * grid.squared(i)) / x(i);
        }
        let jump = -u[m] / x(m);
        derivative_uniform(&b[..=m], h, &mut self.beta[..=m])?;
        if m + 1 < n {
            for (i, bi) in b.iter_mut().enumerate().skip(m) {
                *bi = (-u0 - c2 * grid.squared(i)) / x(i);
            }
            derivative_uniform(&b[m..], h, &mut self.du[m..n])?;
            self.beta[m] = 0.5 * (self.beta[m] + self.du[m]);
            self.beta[m + 1..n].copy_from_slice(&self.du[m + 1..n]);
        }
        let sum = self
            .sum
            .as_mut()
            .expect("convolution method owns a power sum");
        sum.causal(&self.beta[..n], &mut self.s[..n])?;
        let scale = h.powf(1.5);
        for (j, uj) in out.iter_mut().enumerate() {
            let rho = grid.squared(j);
            let mut bracket = rho.sqrt() * l0 + scale * self.s[j];
            if j > m {
                bracket += jump * (rho - grid.squared(m)).sqrt();
            }
            *uj = u0 + 0.5 * c2 * rho + FRAC_2_PI * bracket;
        }
        Ok(())
    }
}
