//! Macroscopic relations and the contact solve (docs/theory-mdr.md#profile-transform; docs/theory-mdr.md#graded-constant-cn for graded media, of which the
//! homogeneous medium is `k = 0`, `c_N = E*`).
//!
//! * `δ = g(a)`;
//! * `F = 2c_N ∫_0^a x^k (δ − g) dx = 2c_N/(1+k) ∫_0^{a²} ξ^{(1+k)/2} ĝ'(ξ) dξ` (Eq. 2, docs/theory-mdr.md#graded-constant-cn; the last
//!   form on the grid);
//! * `p` from `Q = c_N(δ − g)` by Eq. 17 (Eq. 29), `u` from `U = δ − g` by Eq. 12/25 or 13/26.
//!
//! The contact radius is found on the grid (interpolating `g` or the cumulative force), then the
//! grid is rebuilt so that `a²` is a node (the stress transform needs `a² = (M−1)h`, docs/theory-mdr.md#profile-transform), and
//! the two steps are repeated until the interpolated radius lies on that node to the tolerance: the
//! result is self-consistent, `g(a) = δ` at the edge node, with no snapping error.

use std::f64::consts::PI;

use halfspace_numerics::{diff::derivative_uniform, pow_or_sqrt, quad, Backend, SquaredGrid};

use crate::{
    analytic::{graded_cone_integral, graded_cubic_integral, graded_power_law_factor},
    error::positive,
    DisplacementMethod, DisplacementTransform, Material, MdrError, Profile, ProfileTransform,
    StressTransform,
};

/// What is prescribed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Load {
    /// Indentation depth `δ > 0` in m.
    Depth(f64),
    /// Normal force `F > 0` in N.
    Force(f64),
}

/// Parameters of the contact solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactParams {
    /// Grid nodes `N` (≥ 8).
    pub nodes: usize,
    /// Backend of the profile and stress transforms; the displacement uses Eq. 12 for `Mvm` and
    /// Eq. 13 by FFT for `Fft` ([`DisplacementMethod::for_backend`]).
    pub backend: Backend,
    /// Domain size over contact radius, `L/a ≥ 1` (docs/theory-mdr.md#p8-domain-size; tables may shorten it).
    pub domain_ratio: f64,
    /// Relative tolerance of the contact-radius iteration.
    pub tolerance: f64,
    /// Iteration limit of the contact-radius iteration.
    pub max_iterations: usize,
}

impl Default for ContactParams {
    fn default() -> Self {
        Self {
            nodes: 2001,
            backend: Backend::Fft,
            domain_ratio: 1.5,
            tolerance: 1e-12,
            max_iterations: 60,
        }
    }
}

/// The solved contact. Arrays are on the nodes of `grid` (`r_i = x_i = √(i h)`).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSolution {
    /// The final grid; its node `edge_index` is the contact edge.
    pub grid: SquaredGrid,
    /// Zero-based node index of the contact edge, `a² = edge_index · h`.
    pub edge_index: usize,
    /// Contact radius `a` in m.
    pub contact_radius: f64,
    /// Indentation depth `δ` in m.
    pub depth: f64,
    /// Normal force `F` in N.
    pub force: f64,
    /// Contact modulus used (`E*`, or `c_N` of a graded medium).
    pub contact_modulus: f64,
    /// Grading exponent `k` (0 for a homogeneous medium).
    pub grading_exponent: f64,
    /// Equivalent profile `g(x)` on every node (`+∞` beyond a flat punch).
    pub equivalent: Vec<f64>,
    /// Pressure `p(r)` on every node (0 outside; `+∞` where it is singular: a punch edge, a cone
    /// apex).
    pub pressure: Vec<f64>,
    /// Surface displacement `u(r)` on every node, inside and outside the contact.
    pub displacement: Vec<f64>,
    /// `dg/dx` at the contact edge.
    pub edge_slope: f64,
    /// Contact-radius iterations done.
    pub iterations: usize,
}

impl ContactSolution {
    /// Radii of the nodes.
    pub fn radii(&self) -> Vec<f64> {
        self.grid.coordinates()
    }

    /// Largest finite pressure.
    pub fn max_pressure(&self) -> f64 {
        self.pressure
            .iter()
            .copied()
            .filter(|p| p.is_finite())
            .fold(0.0, f64::max)
    }

    /// `F / (π a²)`.
    pub fn mean_pressure(&self) -> f64 {
        self.force / (PI * self.contact_radius * self.contact_radius)
    }

    /// Normal stiffness `dF/dδ = 2c_N a^{1+k}/(1+k)` (`2E* a` homogeneous, docs/theory-mdr.md#profile-transform, docs/theory-mdr.md#graded-constant-cn).
    pub fn normal_stiffness(&self) -> f64 {
        let k = self.grading_exponent;
        2.0 * self.contact_modulus * self.contact_radius.powf(1.0 + k) / (1.0 + k)
    }

    /// `dF/da = 2c_N a^{1+k} g'(a)/(1+k)` (`2E* a g'(a)` homogeneous, docs/theory-mdr.md#profile-transform), `g'(a)` from the grid.
    pub fn force_radius_slope(&self) -> f64 {
        self.normal_stiffness() * self.edge_slope
    }

    /// Whether the pressure has a singular node (punch edge, cone apex).
    pub fn pressure_is_singular(&self) -> bool {
        self.pressure.iter().any(|p| p.is_infinite())
    }
}

/// Contact solver: owns the three transforms (planned once for `params.nodes`) and its buffers, so
/// repeated solves neither plan nor allocate beyond the returned solution.
pub struct ContactSolver {
    params: ContactParams,
    material: Material,
    profile_tf: ProfileTransform,
    stress_tf: StressTransform,
    displacement_tf: DisplacementTransform,
    g: Vec<f64>,
    g_smooth: Vec<f64>,
    dg: Vec<f64>,
    force_curve: Vec<f64>,
    work: Vec<f64>,
}

impl ContactSolver {
    /// Builds the solver: validates the parameters, plans the transforms.
    pub fn new(material: Material, params: ContactParams) -> Result<Self, MdrError> {
        let n = params.nodes;
        if n < SquaredGrid::MIN_NODES {
            return Err(MdrError::Numerics(
                halfspace_numerics::NumericsError::TooFewNodes {
                    what: "the MDR grid",
                    min: SquaredGrid::MIN_NODES,
                    n,
                },
            ));
        }
        if !(params.domain_ratio.is_finite() && params.domain_ratio >= 1.0) {
            return Err(MdrError::InvalidParameter {
                name: "domain ratio L/a",
                value: params.domain_ratio,
                allowed: "finite and ≥ 1",
            });
        }
        if !(params.tolerance.is_finite() && params.tolerance > 0.0) {
            return Err(MdrError::InvalidParameter {
                name: "tolerance",
                value: params.tolerance,
                allowed: "finite and > 0",
            });
        }
        // Footprint per node of the transforms' plans, kernels and work arrays, measured with
        // `/usr/bin/time` on `halfspace axisym --n 200001`: 525 B (FFT), 190 B (MVM); the
        // estimate rounds up.
        let bytes_per_node = match params.backend {
            Backend::Fft => 600.0,
            Backend::Mvm => 250.0,
        };
        halfspace_numerics::memory::check_fits("the MDR solve", bytes_per_node * n as f64)?;
        Ok(Self {
            params,
            material,
            profile_tf: ProfileTransform::new(n, &material, params.backend)?,
            stress_tf: StressTransform::new(n, &material, params.backend)?,
            displacement_tf: DisplacementTransform::new(
                n,
                &material,
                DisplacementMethod::for_backend(params.backend),
            )?,
            g: vec![0.0; n],
            g_smooth: vec![0.0; n],
            dg: vec![0.0; n],
            force_curve: vec![0.0; n],
            work: vec![0.0; n],
        })
    }

    /// The parameters.
    pub fn params(&self) -> &ContactParams {
        &self.params
    }

    /// Solves the contact of `profile` under `load` (docs/theory-mdr.md#profile-transform): contact radius, depth, force,
    /// pressure (Eq. 17) and surface displacement (Eq. 12 or 13).
    pub fn solve(&mut self, profile: &Profile, load: Load) -> Result<ContactSolution, MdrError> {
        match load {
            Load::Depth(d) => positive("indentation depth", d)?,
            Load::Force(f) => positive("normal force", f)?,
        };
        if let Profile::FlatPunch { radius } = *profile {
            return self.solve_flat_punch(radius, load);
        }
        if let (Profile::Power { n, .. }, DisplacementMethod::Convolution(_)) =
            (profile, self.displacement_tf.method())
        {
            // g − κ₂c₀x² − κ₁s₀x starts like xⁿ: Eq. 13/26 needs n ∉ (1, 5/2) \ {2} (docs/theory-mdr.md#p11-applicability-of-eqs-13-and-26).
            if *n > 1.0 && *n < 2.5 && *n != 2.0 {
                return Err(MdrError::InvalidParameter {
                    name:
                        "power-law exponent n for the Eq. 13/26 displacement (use the MVM backend: \
                           Eq. 12/25)",
                    value: *n,
                    allowed:
                        "1, 2 or ≥ 5/2 (docs/theory-mdr.md#p11-applicability-of-eqs-13-and-26)",
                });
            }
        }
        let n = self.params.nodes;
        let tol = self.params.tolerance;
        let mut a = self.initial_radius(profile, load);
        let mut iterations = 0;
        let (grid, edge) = loop {
            iterations += 1;
            let (grid, edge) = self.grid_with_edge_at(profile, a)?;
            self.equivalent_and_force(profile, &grid)?;
            let target = match load {
                Load::Depth(d) => crossing(&self.g[..n], d),
                Load::Force(f) => crossing(&self.force_curve[..n], f),
            };
            self.check_monotone(
                &grid,
                target.map_or(n - 1, |t| (t.ceil() as usize + 1).min(n - 1)),
            )?;
            let a_new = match target {
                Some(t) => (t * grid.step()).sqrt(),
                None => {
                    if let Some(limit) = profile.max_radius() {
                        if grid.length() >= limit * (1.0 - 1e-12) {
                            return Err(MdrError::ContactOutsideDomain {
                                what: "the end of the profile table",
                                limit,
                                hint: "extend the table to larger r or lower the load",
                            });
                        }
                    }
                    2.0 * grid.length()
                }
            };
            let change = (a_new - a).abs() / a;
            if target.is_some() && change <= tol {
                break (grid, edge);
            }
            if iterations >= self.params.max_iterations {
                return Err(MdrError::NoConvergence {
                    what: "the contact-radius iteration",
                    iterations,
                    residual: change,
                });
            }
            if !a_new.is_finite() || a_new <= 0.0 {
                return Err(MdrError::NoConvergence {
                    what: "the contact-radius iteration (radius left the finite range)",
                    iterations,
                    residual: a_new,
                });
            }
            a = a_new;
        };
        let c_n = self.material.contact_modulus();
        let a = grid.coordinate(edge);
        let (depth, force) = match load {
            Load::Depth(d) => (d, self.force_curve[edge]),
            Load::Force(f) => (self.g[edge], f),
        };
        // Pressure: Eq. 17 on q = c_N(δ − g_smooth) cut at the edge, plus the cone part in closed
        // form; the edge terms of the two parts cancel because q(a) = 0.
        // The cubic part (κ₃ c₃ x³) likewise: left in q it makes q̂'' ~ ξ^{−1/2} at the origin,
        // where Eq. 17 then converges at order ≈ 0.7 only (tests/fixtures_quadrature.rs).
        let m = edge + 1;
        let s0 = profile.conical_slope();
        let c3 = profile.cubic_coefficient();
        let k = self.material.grading_exponent();
        let kappa3 = graded_power_law_factor(3.0, k);
        let mut q = vec![0.0; m];
        for (i, qi) in q.iter_mut().enumerate() {
            let x = grid.coordinate(i);
            *qi = c_n * (depth - self.g_smooth[i] + kappa3 * c3 * x * x * x);
        }
        if s0 == 0.0 && c3 == 0.0 {
            q[edge] = 0.0;
        }
        let mut pressure = vec![0.0; n];
        self.stress_tf
            .line_load_to_stress(&grid, &q, 0.0, &mut pressure[..m])?;
        pressure[edge] = 0.0;
        let kappa1 = graded_power_law_factor(1.0, k);
        if c3 != 0.0 {
            // Eq. 28 for g = κ₃ c₃ x³: p = (3 c_N κ₃ c₃/π) ∫_r^a x² (x² − r²)^{(k−1)/2} dx.
            for (j, pj) in pressure.iter_mut().enumerate().take(edge) {
                let integral = graded_cubic_integral(grid.coordinate(j), a, k)?;
                *pj += 3.0 * c_n * kappa3 * c3 / PI * integral;
            }
        }
        if s0 != 0.0 {
            // Eq. 28 for the cone part g = κ₁ s₀ x: p = (c_N κ₁ s₀/π) ∫_r^a (x²−r²)^{(k−1)/2} dx.
            for (j, pj) in pressure.iter_mut().enumerate().take(edge) {
                let integral = graded_cone_integral(grid.coordinate(j), a, k)?;
                *pj += c_n * kappa1 * s0 / PI * integral;
            }
        }
        // Displacement from U = δ − g on the contact.
        let mut u_contact = q;
        for (i, ui) in u_contact.iter_mut().enumerate() {
            *ui = depth - self.g[i];
        }
        u_contact[edge] = 0.0;
        let mut displacement = vec![0.0; n];
        let l1 = -kappa1 * s0;
        self.displacement_tf
            .apply_unchecked(&grid, &u_contact, l1, &mut displacement)?;
        Ok(ContactSolution {
            grid,
            edge_index: edge,
            contact_radius: a,
            depth,
            force,
            contact_modulus: c_n,
            grading_exponent: k,
            equivalent: self.g[..n].to_vec(),
            pressure,
            displacement,
            edge_slope: 2.0 * a * self.dg[edge],
            iterations,
        })
    }

    fn solve_flat_punch(&mut self, radius: f64, load: Load) -> Result<ContactSolution, MdrError> {
        let n = self.params.nodes;
        let c_n = self.material.contact_modulus();
        let k = self.material.grading_exponent();
        // F = 2c_N δ a^{1+k}/(1+k) (docs/theory-mdr.md#graded-closed-forms; 2E* a δ at k = 0).
        let stiffness = 2.0 * c_n * radius.powf(1.0 + k) / (1.0 + k);
        let (depth, force) = match load {
            Load::Depth(d) => (d, stiffness * d),
            Load::Force(f) => (f / stiffness, f),
        };
        let edge = self.edge_index(self.params.domain_ratio)?;
        let grid = SquaredGrid::with_node_at(n, radius, edge)?;
        let m = edge + 1;
        let mut equivalent = vec![f64::INFINITY; n];
        equivalent[..m].fill(0.0);
        let q = vec![c_n * depth; m];
        let mut pressure = vec![0.0; n];
        self.stress_tf
            .line_load_to_stress(&grid, &q, c_n * depth, &mut pressure[..m])?;
        let u_contact = vec![depth; m];
        let mut displacement = vec![0.0; n];
        self.displacement_tf
            .apply(&grid, &u_contact, 0.0, &mut displacement)?;
        Ok(ContactSolution {
            grid,
            edge_index: edge,
            contact_radius: radius,
            depth,
            force,
            contact_modulus: c_n,
            grading_exponent: k,
            equivalent,
            pressure,
            displacement,
            edge_slope: 0.0,
            iterations: 0,
        })
    }

    /// Node index of the edge for a domain ratio `λ`: `round((N−1)/λ²)`, at least 8 contact nodes.
    fn edge_index(&self, ratio: f64) -> Result<usize, MdrError> {
        let n = self.params.nodes;
        let edge = (((n - 1) as f64) / (ratio * ratio)).round() as usize;
        let edge = edge.clamp(1, n - 1);
        if edge + 1 < SquaredGrid::MIN_NODES {
            return Err(MdrError::InvalidParameter {
                name: "domain ratio L/a",
                value: ratio,
                allowed: "small enough that the contact keeps ≥ 8 of the N nodes (raise N)",
            });
        }
        Ok(edge)
    }

    /// Grid of `N` nodes with node `edge` at `a` and `L = λ a`, shortened to the profile's end.
    fn grid_with_edge_at(
        &self,
        profile: &Profile,
        a: f64,
    ) -> Result<(SquaredGrid, usize), MdrError> {
        let mut ratio = self.params.domain_ratio;
        if let Some(limit) = profile.max_radius() {
            if a > limit {
                return Err(MdrError::ContactOutsideDomain {
                    what: "the end of the profile table",
                    limit,
                    hint: "extend the table to larger r or lower the load",
                });
            }
            ratio = ratio.min(limit / a);
        }
        let edge = self.edge_index(ratio)?;
        Ok((SquaredGrid::with_node_at(self.params.nodes, a, edge)?, edge))
    }

    /// `g` (and its smooth part without the cone), `ĝ'`, and the cumulative force
    /// `F_i = 2c_N/(1+k) ∫_0^{ξ_i} ξ^{(1+k)/2} ĝ' dξ` (Eq. 2, docs/theory-mdr.md#graded-constant-cn), its cone part
    /// `κ₁ s₀ ξ^{(2+k)/2}/(2+k)`, parabolic part `2κ₂ c₀ ξ^{(3+k)/2}/(3+k)` and cubic part
    /// `3κ₃ c₃ ξ^{(4+k)/2}/(4+k)` (inside the bracket)
    /// in closed form, the rest by the trapezoid rule. At `k = 0`: `(π/2)E* s₀ ξ + (8/3)E* c₀ ξ^{3/2}`.
    fn equivalent_and_force(
        &mut self,
        profile: &Profile,
        grid: &SquaredGrid,
    ) -> Result<(), MdrError> {
        let n = grid.len();
        let split = self
            .profile_tf
            .profile_to_equivalent(profile, grid, &mut self.g[..n])?;
        let (s0, c0, c3) = (split.conical, split.parabolic, split.cubic);
        let k = self.material.grading_exponent();
        let kappa1 = graded_power_law_factor(1.0, k);
        let kappa2 = 2.0 / (1.0 + k);
        let kappa3 = graded_power_law_factor(3.0, k);
        for i in 0..n {
            let x = grid.coordinate(i);
            self.g_smooth[i] = self.g[i] - kappa1 * s0 * x;
            self.work[i] =
                self.g_smooth[i] - kappa2 * c0 * grid.squared(i) - kappa3 * c3 * x * x * x;
        }
        let h = grid.step();
        derivative_uniform(&self.work[..n], h, &mut self.dg[..n])?;
        let weight_power = 0.5 * (1.0 + k);
        for i in 0..n {
            self.work[i] = self.dg[i] * pow_or_sqrt(grid.squared(i), weight_power);
        }
        quad::cumulative_trapezoid_uniform(&self.work[..n], h, &mut self.force_curve[..n]);
        let c_n = self.material.contact_modulus();
        for i in 0..n {
            let xi = grid.squared(i);
            let closed = 2.0 * kappa2 * c0 * xi.powf(0.5 * (3.0 + k)) / (3.0 + k)
                + kappa1 * s0 * xi.powf(0.5 * (2.0 + k)) / (2.0 + k)
                + 3.0 * kappa3 * c3 * xi.powf(0.5 * (4.0 + k)) / (4.0 + k);
            self.force_curve[i] = 2.0 * c_n / (1.0 + k) * (self.force_curve[i] + closed);
        }
        derivative_uniform(&self.g[..n], h, &mut self.dg[..n])?;
        Ok(())
    }

    fn check_monotone(&self, grid: &SquaredGrid, upto: usize) -> Result<(), MdrError> {
        let g = &self.g;
        for i in 1..=upto {
            if g[i] < g[i - 1] - 1e-12 * g[i - 1].abs() {
                return Err(MdrError::NonConvexProfile {
                    x: grid.coordinate(i),
                });
            }
        }
        Ok(())
    }

    /// A first contact radius: for a depth the radius where `f(r) = δ` (an upper bound, since
    /// `g ≥ f` for convex `f`); for a force a Hertz-like estimate `(F/(E* f''))^{1/3}` scaled to
    /// the profile. The iteration corrects either.
    fn initial_radius(&self, profile: &Profile, load: Load) -> f64 {
        let e = self.material.contact_modulus();
        let guess = match (profile, load) {
            (Profile::Sphere { radius }, Load::Depth(d)) => (radius * d).sqrt(),
            (Profile::Sphere { radius }, Load::Force(f)) => {
                crate::analytic::sphere_radius_for_force(f, *radius, e)
            }
            (Profile::Cone { slope }, Load::Depth(d)) => d / slope,
            (Profile::Cone { slope }, Load::Force(f)) => (f / (e * slope)).sqrt(),
            (Profile::Power { c, n }, Load::Depth(d)) => (d / c).powf(1.0 / n),
            (Profile::Power { c, n }, Load::Force(f)) => (f / (e * c)).powf(1.0 / (n + 1.0)),
            (p, Load::Depth(d)) => radius_where_height_reaches(p, d),
            (p, Load::Force(_)) => p.max_radius().unwrap_or(1.0) / self.params.domain_ratio,
        };
        let guess = if guess.is_finite() && guess > 0.0 {
            guess
        } else {
            1.0
        };
        match profile.max_radius() {
            Some(limit) => guess.min(limit),
            None => guess,
        }
    }
}

/// Bisection for `f(r) = δ` on `[0, r_max]` (or a doubling bracket); capped at the table end.
fn radius_where_height_reaches(profile: &Profile, depth: f64) -> f64 {
    let mut hi = profile.max_radius().unwrap_or(1.0);
    let mut steps = 0;
    while profile.height(hi) < depth && steps < 200 {
        hi *= 2.0;
        steps += 1;
    }
    let mut lo = 0.0;
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if profile.height(mid) < depth {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// Fractional node index `t` where the non-decreasing `values` first reach `target`, linear
/// between nodes; `None` if they never do.
fn crossing(values: &[f64], target: f64) -> Option<f64> {
    if values.first().is_some_and(|&v| v >= target) {
        return Some(0.0);
    }
    let i = values.windows(2).position(|w| w[1] >= target)?;
    let (lo, hi) = (values[i], values[i + 1]);
    Some(i as f64 + (target - lo) / (hi - lo))
}
