use std::f64::consts::PI;

use halfspace_numerics::{
    diff::derivative_uniform, pow_or_sqrt, Backend, NumericsError, PowerSum, SquaredGrid,
};
use rayon::prelude::*;

use super::{check_fits, check_len};
use crate::analytic::{cut_linear_displacement, displacement_kernel};
use crate::{Material, MdrError};

/// Which discretization of the displacement transform (docs/theory-mdr.md#displacement-transform, docs/theory-mdr.md#graded-displacements).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DisplacementMethod {
    /// Eq. 12 (Eq. 25 graded): `û(ρ) = U(0) + ∫_0^ρ Û'(ξ) K_k(ξ/ρ) dξ` with
    /// `K_0(y) = (2/π) arccos √y` and the ₂F₁ kernel of docs/theory-mdr.md#graded-displacements for `k ≠ 0`: a dense (not
    /// Toeplitz) O(N²) product. At `k = 0` the kernel is evaluated on the fly; for `k ≠ 0` it is
    /// tabulated once when the transform is built (`N²/2` entries, at most [`Self::MAX_KERNEL_NODES`]
    /// nodes).
    DenseKernel,
    /// Eq. 13 (Eq. 26 graded): `û(ρ) = U(0) + 2cos(kπ/2)/(π(1−k)) [ρ^{(1−k)/2} L₀ +
    /// ∫_0^ρ β(ξ)(ρ−ξ)^{(1−k)/2} dξ]`, `β = d/dξ (ξ^{(k−1)/2} Û)`: a causal convolution evaluated
    /// by the given backend (FFT, or its dense twin).
    Convolution(Backend),
}

impl DisplacementMethod {
    /// Largest grid for which the graded Eq. 25 kernel is tabulated (`N²/2` doubles ≈ 270 MB).
    pub const MAX_KERNEL_NODES: usize = 8193;

    /// The method the CLI's `--method` selects: `mvm` → Eq. 12/25, `fft` → Eq. 13/26 by FFT.
    pub fn for_backend(backend: Backend) -> Self {
        match backend {
            Backend::Mvm => DisplacementMethod::DenseKernel,
            Backend::Fft => DisplacementMethod::Convolution(Backend::Fft),
        }
    }

    /// The paper's equation numbers, e.g. `"eq12"` / `"eq25"`.
    pub fn equation(self, k: f64) -> &'static str {
        match (self, k == 0.0) {
            (DisplacementMethod::DenseKernel, true) => "eq12",
            (DisplacementMethod::DenseKernel, false) => "eq25",
            (DisplacementMethod::Convolution(_), true) => "eq13",
            (DisplacementMethod::Convolution(_), false) => "eq26",
        }
    }
}

/// Displacement transform `U(x) → u(r)` of the MDR (paper Eqs. 8, 24; docs/theory-mdr.md#displacement-transform, docs/theory-mdr.md#graded-displacements):
/// `u(r) = (2/π) cos(kπ/2) ∫_0^r x^k U(x) / (r² − x²)^{(1+k)/2} dx` for a 1D displacement `U` given
/// on the contact nodes `0..M` and zero beyond (`a² = ξ_{M−1}`), evaluated on every node of the
/// grid, inside and outside the contact.
///
/// `U = U(0) + L₁ x + V` on the contact is split: the first two parts, cut at `a`, are transformed
/// in closed form (`U(0)` inside, `U(0)(1 − K_k(a²/r²))` outside; `L₁ r/κ₁(k)` inside and an
/// incomplete beta function outside, [`crate::analytic::cut_linear_displacement`]); `V = O(x²)` goes
/// through Eq. 12/25 or Eq. 13/26, differenced on the array cut at `a` (docs/theory-mdr.md#p3-one-sided-differences-at-the-edge), with its jump
/// `V(a⁻)` at the edge in closed form. For Eq. 13/26 a parabolic term `c₂ x²`, present in every
/// smooth contact and outside the equation's validity (docs/theory-mdr.md#p11-applicability-of-eqs-13-and-26), is subtracted over the whole
/// grid and added back as its transform `c₂ (1+k) r²/2`. These splits are exact identities and
/// this project's additions to the paper's discretization: without them Eq. 13 converges as
/// `O(N^{−1/2})` on Hertz (docs/theory-mdr.md#displacement-transform test 2); with them it matches Eq. 12.
pub struct DisplacementTransform {
    method: DisplacementMethod,
    k: f64,
    capacity: usize,
    sum: Option<PowerSum>,
    /// Packed lower triangle `K_k(i/j)`, row `j` at `j(j+1)/2` (graded Eq. 25 only).
    kernel: Vec<f64>,
    du: Vec<f64>,
    b: Vec<f64>,
    beta: Vec<f64>,
    s: Vec<f64>,
    sqrt_index: Vec<f64>,
    /// `max |U|` of the current input (the rounding scale of the Eq. 26 applicability check).
    input_scale: f64,
    check_applicability: bool,
}

impl DisplacementTransform {
    /// Builds the transform for grids of up to `capacity` nodes in `material`. For the graded
    /// Eq. 25 this tabulates the kernel (O(N²) ₂F₁ evaluations, rows in parallel).
    pub fn new(
        capacity: usize,
        material: &Material,
        method: DisplacementMethod,
    ) -> Result<Self, MdrError> {
        let k = material.grading_exponent();
        let sum = match method {
            DisplacementMethod::DenseKernel => None,
            DisplacementMethod::Convolution(backend) => {
                Some(PowerSum::new(capacity, 0.5 * (1.0 - k), backend)?)
            }
        };
        let kernel = if method == DisplacementMethod::DenseKernel && k != 0.0 {
            if capacity > DisplacementMethod::MAX_KERNEL_NODES {
                return Err(MdrError::InvalidParameter {
                    name: "grid nodes N for the Eq. 25 kernel (N²/2 entries)",
                    value: capacity as f64,
                    allowed: "≤ 8193; use Eq. 26 (the FFT backend) for larger grids",
                });
            }
            tabulate_kernel(capacity, k)?
        } else {
            Vec::new()
        };
        Ok(Self {
            method,
            k,
            capacity,
            sum,
            kernel,
            du: vec![0.0; capacity],
            b: vec![0.0; capacity],
            beta: vec![0.0; capacity],
            s: vec![0.0; capacity],
            sqrt_index: (0..capacity).map(|i| (i as f64).sqrt()).collect(),
            input_scale: 0.0,
            check_applicability: true,
        })
    }

    /// The discretization in use.
    pub fn method(&self) -> DisplacementMethod {
        self.method
    }

    /// `u` on every node from `U` on the contact nodes `0..M` (`M = u_contact.len() ≥ 3`, `U = 0`
    /// beyond) and `L₁ = lim_{x→0} (U(x) − U(0))/x` (the conical part; 0 for smooth `U`).
    /// For Eq. 13/26, a `U` whose remainder starts with a power below `x^{5/2}` (other than the
    /// split-off `x` and `x²`) is refused with an error that names Eq. 12/25 (docs/theory-mdr.md#p11-applicability-of-eqs-13-and-26).
    pub fn apply(
        &mut self,
        grid: &SquaredGrid,
        u_contact: &[f64],
        l1: f64,
        out: &mut [f64],
    ) -> Result<(), MdrError> {
        self.apply_with_check(grid, u_contact, l1, out, true)
    }

    /// [`Self::apply`] without the Eq. 13/26 applicability check, for inputs whose leading powers
    /// are known from elsewhere (the contact solver checks the profile instead: a computed `g`
    /// carries discretization noise at the first nodes that the check would read as a low power).
    pub fn apply_unchecked(
        &mut self,
        grid: &SquaredGrid,
        u_contact: &[f64],
        l1: f64,
        out: &mut [f64],
    ) -> Result<(), MdrError> {
        self.apply_with_check(grid, u_contact, l1, out, false)
    }

    fn apply_with_check(
        &mut self,
        grid: &SquaredGrid,
        u_contact: &[f64],
        l1: f64,
        out: &mut [f64],
        check: bool,
    ) -> Result<(), MdrError> {
        self.check_applicability = check;
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
        if !l1.is_finite() {
            return Err(MdrError::InvalidParameter {
                name: "slope at the origin L₁",
                value: l1,
                allowed: "finite",
            });
        }
        let m = m_nodes - 1;
        let u0 = u_contact[0];
        self.input_scale = u_contact.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        // V = U − U(0) − L₁ x on the contact (smooth, O(x²)), kept in `b`.
        for (i, vi) in self.b[..=m].iter_mut().enumerate() {
            *vi = u_contact[i] - u0 - l1 * grid.coordinate(i);
        }
        self.closed_form_part(grid, m, u0, l1, out)?;
        match self.method {
            DisplacementMethod::DenseKernel => self.dense_kernel(grid, m, out),
            DisplacementMethod::Convolution(_) => self.convolution(grid, m, out),
        }
    }

    /// `(U(0) + L₁ x)` cut at `a`, in closed form, written into `out`.
    fn closed_form_part(
        &self,
        grid: &SquaredGrid,
        m: usize,
        u0: f64,
        l1: f64,
        out: &mut [f64],
    ) -> Result<(), MdrError> {
        let (k, a) = (self.k, grid.coordinate(m));
        let inside_slope = 1.0 / crate::analytic::graded_power_law_factor(1.0, k);
        for (j, uj) in out.iter_mut().enumerate() {
            let r = grid.coordinate(j);
            *uj = if j <= m {
                u0 + l1 * inside_slope * r
            } else {
                let y = grid.squared(m) / grid.squared(j);
                let mut v = u0 * (1.0 - displacement_kernel(y, k)?);
                if l1 != 0.0 {
                    v += l1 * cut_linear_displacement(r, a, k)?;
                }
                v
            };
        }
        Ok(())
    }

    /// `V = c₂ x² + R` over the whole grid, `R = V − c₂ξ` on the contact and `−c₂ξ` beyond (`V` in
    /// `self.b[..=m]` on entry). Writes `R̂'` into `self.beta` (differenced on each side of the edge,
    /// averaged on the edge node) after transforming `R` by `weight(ξ)` (1 for Eq. 12/25,
    /// `ξ^{(k−1)/2}` for Eq. 13/26), and returns `c₂`. `c₂ = lim V/x²` is extrapolated quadratically in
    /// `x` from nodes 1–3, exact when `V` is a polynomial of degree ≤ 4 in `x`.
    fn split_parabola(
        &mut self,
        grid: &SquaredGrid,
        m: usize,
        weight: impl Fn(f64) -> f64,
    ) -> Result<f64, MdrError> {
        let n = grid.len();
        let h = grid.step();
        let c2 = parabolic_coefficient(&self.b[..=m], grid);
        let b = &mut self.b[..n];
        for (i, bi) in b.iter_mut().enumerate().take(m + 1) {
            let xi = grid.squared(i);
            *bi = if i == 0 {
                0.0
            } else {
                weight(xi) * (*bi - c2 * xi)
            };
        }
        derivative_uniform(&b[..=m], h, &mut self.beta[..=m])?;
        if m + 1 < n {
            for (i, bi) in b.iter_mut().enumerate().skip(m) {
                let xi = grid.squared(i);
                *bi = -c2 * xi * weight(xi);
            }
            derivative_uniform(&b[m..], h, &mut self.du[m..n])?;
            self.beta[m] = 0.5 * (self.beta[m] + self.du[m]);
            self.beta[m + 1..n].copy_from_slice(&self.du[m + 1..n]);
        }
        Ok(c2)
    }

    /// Eq. 12/25 on `V = c₂x² + R`: the trapezoid rule over `0 ≤ ξ ≤ ρ_j` of `R̂' K_k(ξ/ρ_j)`, the
    /// edge jump `−V(a⁻) K_k(a²/ρ_j)` for `ρ_j > a²`, and `c₂ (1+k) ρ_j/2`; added to `out`.
    fn dense_kernel(
        &mut self,
        grid: &SquaredGrid,
        m: usize,
        out: &mut [f64],
    ) -> Result<(), MdrError> {
        let h = grid.step();
        let k = self.k;
        let v_edge = self.b[m];
        let c2 = self.split_parabola(grid, m, |_| 1.0)?;
        let dr = &self.beta[..grid.len()];
        let sq = &self.sqrt_index;
        let table = &self.kernel;
        let graded = k != 0.0;
        out.par_iter_mut().enumerate().for_each(|(j, uj)| {
            if j == 0 {
                return;
            }
            let kernel = |i: usize| {
                if graded {
                    table[j * (j + 1) / 2 + i]
                } else {
                    2.0 / PI * (sq[i] / sq[j]).min(1.0).acos()
                }
            };
            // The upper end carries K(1) = 0.
            let mut acc = 0.5 * dr[0] * kernel(0);
            for (i, d) in dr.iter().enumerate().take(j).skip(1) {
                acc += d * kernel(i);
            }
            let mut value = h * acc + 0.5 * (1.0 + k) * c2 * grid.squared(j);
            if j > m {
                value -= v_edge * kernel(m);
            }
            *uj += value;
        });
        Ok(())
    }

    /// Eq. 13/26 on `V = c₂x² + R` (`B = ξ^{(k−1)/2} R`, `B₀ = 0`), the edge jump and
    /// `c₂ (1+k) ρ/2`; added to `out`.
    fn convolution(
        &mut self,
        grid: &SquaredGrid,
        m: usize,
        out: &mut [f64],
    ) -> Result<(), MdrError> {
        let n = grid.len();
        let (h, k) = (grid.step(), self.k);
        let power = 0.5 * (k - 1.0);
        let v_edge = self.b[m];
        if self.check_applicability {
            check_eq26_applicability(&self.b[..=m], grid, k, self.input_scale)?;
        }
        let c2 = self.split_parabola(grid, m, |xi| xi.powf(power))?;
        let sum = self
            .sum
            .as_mut()
            .expect("the convolution method owns a power sum");
        sum.causal(&self.beta[..n], &mut self.s[..n])?;
        let gamma = 0.5 * (1.0 - k);
        let scale = h.powf(0.5 * (3.0 - k));
        let pref = 2.0 * (0.5 * k * PI).cos() / (PI * (1.0 - k));
        let jump = -v_edge * grid.squared(m).powf(power);
        for (j, uj) in out.iter_mut().enumerate() {
            let rho = grid.squared(j);
            let mut bracket = scale * self.s[j];
            if j > m {
                bracket += jump * pow_or_sqrt(rho - grid.squared(m), gamma);
            }
            *uj += 0.5 * (1.0 + k) * c2 * rho + pref * bracket;
        }
        Ok(())
    }
}

/// `c₂ = lim V/x²` for `V = O(x²)` on the contact nodes, extrapolated quadratically in `x` from
/// nodes 1–3 (linearly from 1–2 when the contact has only 3 nodes).
fn parabolic_coefficient(v: &[f64], grid: &SquaredGrid) -> f64 {
    let x = |i: usize| grid.coordinate(i);
    let ratio = |i: usize| v[i] / grid.squared(i);
    if v.len() >= 4 {
        let (x1, x2, x3) = (x(1), x(2), x(3));
        ratio(1) * x2 * x3 / ((x1 - x2) * (x1 - x3))
            + ratio(2) * x1 * x3 / ((x2 - x1) * (x2 - x3))
            + ratio(3) * x1 * x2 / ((x3 - x1) * (x3 - x2))
    } else {
        (ratio(1) * x(2) - ratio(2) * x(1)) / (x(2) - x(1))
    }
}

/// Eq. 13/26 needs `β = d/dξ(ξ^{(k−1)/2} R)` bounded enough for the trapezoid rule, where
/// `R = V − c₂x²` is what remains after the closed-form parts (docs/theory-mdr.md#displacement-transform Variant B, docs/theory-mdr.md#p11-applicability-of-eqs-13-and-26). A
/// remainder that starts like `x^m` with `m < 5/2` (e.g. `x^{3/2}` from a profile `r^{3/2}`) makes
/// `β ~ ξ^{(m+k−3)/2}` too singular: refuse it and name Eq. 12/25. The exponent is estimated from
/// nodes 1–4 and only when the remainder there is above rounding (`1e-9` of `max |U|`).
fn check_eq26_applicability(
    v: &[f64],
    grid: &SquaredGrid,
    k: f64,
    scale: f64,
) -> Result<(), MdrError> {
    if v.len() < 6 {
        return Ok(());
    }
    let c2 = parabolic_coefficient(v, grid);
    let r: Vec<f64> = (1..=4).map(|i| v[i] - c2 * grid.squared(i)).collect();
    if scale == 0.0 || r.iter().any(|ri| ri.abs() <= 1e-9 * scale) {
        return Ok(());
    }
    if !(r.iter().all(|ri| *ri > 0.0) || r.iter().all(|ri| *ri < 0.0)) {
        return Ok(());
    }
    // Local exponent between nodes 2 and 4 (node 1 is disturbed by the extrapolated c₂).
    let m = (r[3] / r[1]).abs().ln() / (grid.coordinate(4) / grid.coordinate(2)).ln();
    if m < 2.5 {
        return Err(MdrError::InvalidParameter {
            name: if k == 0.0 {
                "leading exponent of U − U(0) − L₁x − c₂x² for Eq. 13 (use Eq. 12: the MVM backend)"
            } else {
                "leading exponent of U − U(0) − L₁x − c₂x² for Eq. 26 (use Eq. 25: the MVM backend)"
            },
            value: m,
            allowed: "≥ 5/2 (no terms between x² and x^{5/2} at the origin, docs/theory-mdr.md#p11-applicability-of-eqs-13-and-26)",
        });
    }
    Ok(())
}

/// `K_k(i/j)` for `0 ≤ i ≤ j < n`, packed by rows.
fn tabulate_kernel(n: usize, k: f64) -> Result<Vec<f64>, MdrError> {
    let rows: Result<Vec<Vec<f64>>, _> = (0..n)
        .into_par_iter()
        .map(|j| {
            (0..=j)
                .map(|i| {
                    if j == 0 {
                        Ok(1.0)
                    } else {
                        displacement_kernel(i as f64 / j as f64, k)
                    }
                })
                .collect::<Result<Vec<f64>, _>>()
        })
        .collect();
    Ok(rows?.concat())
}
