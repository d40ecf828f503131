//! The fretting-loop configuration and its load path.

use crate::eim::{
    composite_fibres, FibreLayout, Inhomogeneity, COMPOSITE_CELLS_PER_RADIUS,
    COMPOSITE_FIBRE_RADIUS,
};
use crate::SamError;

/// The labels of the points of [LN11] Figs. 5–7: A end of the normal loading, B `δx = +A`, C
/// `δx = 0` on the way back, D `δx = −A`.
pub const POINT_LABELS: [&str; 4] = ["A", "B", "C", "D"];

/// A fretting loop: rigid sphere of radius `radius` on a half-space `(e, nu)` with Coulomb
/// friction `friction`, normal force ramped to `force` in `normal_steps` equal steps, then the
/// shift cycled with amplitude `amplitude` in steps `shift_step`, on `grid²` cells over
/// `extent_over_a · a` (`a` the Hertz radius). Defaults: [LN11]'s homogeneous case (R = 105 μm,
/// E = 210 GPa, ν = 0.3, μ = 0.3, W = 80 mN in 80 steps, A = 0.04 μm in 0.002 μm steps, 64² over
/// 4.16a).
#[derive(Debug, Clone, PartialEq)]
pub struct LoopCase {
    /// Sphere radius R (m).
    pub radius: f64,
    /// Young's modulus of the half-space (matrix) (Pa).
    pub e: f64,
    /// Poisson ratio of the half-space.
    pub nu: f64,
    /// Coulomb friction coefficient μ > 0.
    pub friction: f64,
    /// Final normal force W (N).
    pub force: f64,
    /// Normal load steps.
    pub normal_steps: usize,
    /// Shift amplitude A (m).
    pub amplitude: f64,
    /// Shift step (m).
    pub shift_step: f64,
    /// Cells per side.
    pub grid: usize,
    /// Domain side over the Hertz radius.
    pub extent_over_a: f64,
    /// Inhomogeneities below the surface (none: the homogeneous loop).
    pub inhomogeneities: Vec<Inhomogeneity>,
    /// Depth (m) of the von Mises field stored at the points A–D (`None`: not computed).
    pub subsurface_depth: Option<f64>,
}

impl Default for LoopCase {
    fn default() -> Self {
        Self {
            radius: 105e-6,
            e: 210e9,
            nu: 0.3,
            friction: 0.3,
            force: 0.08,
            normal_steps: 80,
            amplitude: 0.04e-6,
            shift_step: 0.002e-6,
            grid: 64,
            extent_over_a: 4.16,
            inhomogeneities: Vec::new(),
            subsurface_depth: None,
        }
    }
}

impl LoopCase {
    /// The Hertz contact radius `a = (3WR / 4E*)^{1/3}`, `E* = E/(1 − ν²)` (rigid sphere).
    pub fn hertz_radius(&self) -> f64 {
        halfspace_mdr::analytic::sphere_radius_for_force(self.force, self.radius, self.e_star())
    }

    /// The Hertz peak pressure `p₀ = 3W / (2πa²)`.
    pub fn hertz_pressure(&self) -> f64 {
        let a = self.hertz_radius();
        3.0 * self.force / (2.0 * std::f64::consts::PI * a * a)
    }

    /// `E* = E / (1 − ν²)` (rigid indenter).
    pub fn e_star(&self) -> f64 {
        self.e / (1.0 - self.nu * self.nu)
    }

    /// Mindlin's full-slip shift `K = 3μW(2 − ν) / (16 G a)`, `G = E / 2(1 + ν)` (rigid sphere;
    /// spec §7.3, uncoupled): the loop is in partial slip for `A < K` and reaches gross slip beyond
    /// (Mindlin–Deresiewicz, [`crate::analytic::mindlin`]).
    pub fn mindlin_slip_shift(&self) -> f64 {
        let g = self.e / (2.0 * (1.0 + self.nu));
        3.0 * self.friction * self.force * (2.0 - self.nu) / (16.0 * g * self.hertz_radius())
    }

    /// The grid's side length `extent_over_a · a` (m).
    pub fn extent(&self) -> f64 {
        self.extent_over_a * self.hertz_radius()
    }

    /// [LN11]'s composite (§4): this case with the paper's fibres of `layout` (radius 0.13a,
    /// spacing 3r, axes at depth 1.5r, `E_I = e_ratio · E`, `ν_I = ν`) across the whole domain, and
    /// the grid of the paper's resolution (4 cells per fibre radius: 128² over 4.16a).
    pub fn composite(mut self, layout: FibreLayout, e_ratio: f64) -> Result<Self, SamError> {
        self.validate()?;
        let cell = COMPOSITE_FIBRE_RADIUS / COMPOSITE_CELLS_PER_RADIUS;
        self.grid = (self.extent_over_a / cell).round() as usize;
        let a = self.hertz_radius();
        self.inhomogeneities.extend(composite_fibres(
            a,
            0.5 * self.extent(),
            layout,
            self.e,
            self.nu,
            e_ratio,
        )?);
        Ok(self)
    }

    /// The same loop without inhomogeneities (the reference of [LN11] Figs. 5–10).
    pub fn homogeneous(&self) -> Self {
        Self {
            inhomogeneities: Vec::new(),
            ..self.clone()
        }
    }

    /// Checks the configuration (every scalar finite and in range, at least one step of each kind).
    pub fn validate(&self) -> Result<(), SamError> {
        for (name, v) in [
            ("sphere radius", self.radius),
            ("Young's modulus", self.e),
            (
                "friction coefficient (a fretting loop needs μ > 0)",
                self.friction,
            ),
            ("normal force", self.force),
            ("shift amplitude", self.amplitude),
            ("shift step", self.shift_step),
            ("extent over a", self.extent_over_a),
        ] {
            crate::error::positive(name, v)?;
        }
        if !(self.nu > -1.0 && self.nu < 0.5) {
            return Err(SamError::InvalidParameter {
                name: "Poisson ratio",
                value: self.nu,
                allowed: "in (−1, 0.5)",
            });
        }
        if self.normal_steps == 0 {
            return Err(SamError::InvalidParameter {
                name: "normal steps",
                value: 0.0,
                allowed: "≥ 1",
            });
        }
        if self.grid < 2 {
            return Err(SamError::InvalidParameter {
                name: "cells per side",
                value: self.grid as f64,
                allowed: "≥ 2",
            });
        }
        if let Some(d) = self.subsurface_depth {
            crate::error::positive("subsurface depth", d)?;
        }
        Ok(())
    }

    /// The load path of this case.
    pub fn path(&self) -> LoadPath {
        LoadPath::fretting(
            self.force,
            self.normal_steps,
            self.amplitude,
            self.shift_step,
        )
    }
}

/// The increments of a fretting loop: `W_i = W i / n` at `δx = 0` (`i = 1..n`), then `δx` from 0
/// to `+A`, to `−A` and back to `+A` in `q = round(A / step)` steps per quarter.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadPath {
    /// `(W, [δx, δy])` per increment.
    pub increments: Vec<(f64, [f64; 2])>,
    /// Normal steps `n`.
    pub normal_steps: usize,
    /// Shift steps per quarter cycle `q`.
    pub quarter: usize,
}

impl LoadPath {
    /// The [LN11] path (module doc).
    pub fn fretting(force: f64, normal_steps: usize, amplitude: f64, shift_step: f64) -> Self {
        let quarter = (amplitude / shift_step).round().max(1.0) as usize;
        let mut increments: Vec<(f64, [f64; 2])> = (1..=normal_steps)
            .map(|i| (force * i as f64 / normal_steps as f64, [0.0, 0.0]))
            .collect();
        let dd = amplitude / quarter as f64;
        for i in 1..=quarter {
            increments.push((force, [i as f64 * dd, 0.0]));
        }
        for i in 1..=2 * quarter {
            increments.push((force, [amplitude - i as f64 * dd, 0.0]));
        }
        for i in 1..=2 * quarter {
            increments.push((force, [-amplitude + i as f64 * dd, 0.0]));
        }
        Self {
            increments,
            normal_steps,
            quarter,
        }
    }

    /// Increments done at the points A–D ([`POINT_LABELS`]).
    pub fn marks(&self) -> [usize; 4] {
        let (n, q) = (self.normal_steps, self.quarter);
        [n, n + q, n + 2 * q, n + 3 * q]
    }

    /// Index of the first row of the closed cycle (`δx = +A`, point B); the cycle runs from there
    /// to the last increment (`δx = +A` again).
    pub fn cycle_start(&self) -> usize {
        self.normal_steps + self.quarter - 1
    }

    /// Number of increments.
    pub fn len(&self) -> usize {
        self.increments.len()
    }

    /// Whether the path has no increment.
    pub fn is_empty(&self) -> bool {
        self.increments.is_empty()
    }
}
