//! The configuration of a 3D fretting-wear run (docs/wear3d.md).

use super::laws::{WearLaw, WornBody};
use crate::drivers::fretting_loop::{LoadPath, LoopCase, LoopEstimate};
use crate::eim::Shape;
use crate::kernels::surface::Compliance;
use crate::normal::NormalLoad;
use crate::{Body, SamError, SurfaceGrid};

/// The default largest depth increment of a wear step over the elastic approach, `η`
/// (docs/wear3d.md#the-wear-step-and-cycle-jumping): the measured change of the worn profile when it is halved is
/// in docs/wear3d.md.
pub const DEFAULT_STEP_FRACTION: f64 = 0.01;

/// The default fraction `β` of the explicit wear step's stability bound `ΔN ≤ 2 C_min / max(k Δu)`
/// (docs/wear3d.md#the-wear-step-and-cycle-jumping): `β = 1` is half the bound, where the stiffest mode of the worn
/// gap decays without overshoot.
pub const DEFAULT_STABILITY_FRACTION: f64 = 1.0;

/// The worn depth of the flat over an inhomogeneity, in cells `2Δ` (the EIM lattice spacing),
/// beyond which the run stops (docs/wear3d.md#inhomogeneities-under-wear): the EIM geometry was
/// built for the unworn surface, and a quarter of a cell is where the first layer's centre has
/// moved by an eighth of its spacing.
pub const INHOMOGENEITY_DEPTH_CELLS: f64 = 0.25;

/// A 3D fretting-wear run (docs/wear3d.md): the fretting loop of `fretting` (sphere, half-space,
/// friction, amplitude, shift step, grid, inhomogeneities) cycled `+A → −A → +A` with the worn
/// depth of `law` added to the gap after every computed cycle, each computed cycle standing for
/// `ΔN` cycles (cycle jumping), until `cycles`.
#[derive(Debug, Clone, PartialEq)]
pub struct WearCase {
    /// The fretting loop: sphere, flat, indenter ([`LoopCase::indenter`]: rigid, or elastic — a
    /// pair of identical bodies with `ν = 0` has no normal–tangential coupling, Mindlin's setting
    /// and the MDR cross-check), normal control by `force` or [`LoopCase::approach`], friction,
    /// amplitude, shift step, grid, inhomogeneities (`subsurface_depth` and `fatigue_depth` are
    /// not used).
    pub fretting: LoopCase,
    /// The wear law and its coefficient.
    pub law: WearLaw,
    /// The body whose depth the wear is booked to (the gap grows the same for all three).
    pub body: WornBody,
    /// Fretting cycles `N` to run.
    pub cycles: u64,
    /// Cycle counts at which a wear step ends exactly and the worn depth and pressure are kept.
    pub record_cycles: Vec<u64>,
    /// `η`: the largest depth increment of a wear step over the elastic approach.
    pub step_fraction: f64,
    /// `β`: the fraction of the stability bound of the explicit wear step.
    pub stability_fraction: f64,
    /// The worn depth of the flat over an inhomogeneity, in cells, at which the run stops
    /// ([`INHOMOGENEITY_DEPTH_CELLS`] by default; smaller is stricter).
    pub inhomogeneity_depth_cells: f64,
}

/// What a wear run will compute, estimated from the configuration before anything is solved
/// (docs/wear3d.md#the-work-estimate). The step count takes the first wear step's `ΔN` for every
/// step: Hertz's `p₀ = 2E*a/(πR)` as the largest pressure and the gross-slip path `4A` as the
/// largest slip path of a cycle, so `max r ≤ rate(p₀, μp₀, 4A)` and
/// `ΔN₁ = ⌊min(η δ / rate(p₀, μp₀, 4A), β C_min / (k_p · 4A))⌋ ≥ 1`
/// (docs/wear3d.md#the-wear-step-and-cycle-jumping); the wear then spreads the pressure and
/// `ΔN` grows, so for a homogeneous pair this errs towards more steps (inhomogeneities can raise
/// the pressure above `p₀`, and then it may err the other way).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WearEstimate {
    /// Wear steps, each one computed cycle `+A → −A → +A`, the final state's cycle included:
    /// `Σ_segments ⌈L / ΔN₁⌉ + 1` over the segments `L` between 0, the record cycles and `cycles`.
    pub wear_steps: f64,
    /// `ΔN₁`: cycles a computed cycle stands for at the first wear step.
    pub first_delta_cycles: f64,
    /// Increments of one computed cycle, `4q`.
    pub increments_per_cycle: f64,
    /// Increments of the run: the loading `n + q` and `wear_steps · 4q`.
    pub increments: f64,
    /// One fretting loop's estimate ([`LoopCase::estimate`]: its memory is the run's, its work
    /// per increment the run's), with `increments` and `work` those of the whole run.
    pub run: LoopEstimate,
}

impl WearEstimate {
    /// Hours of work on this machine's cores ([`LoopEstimate::hours`]).
    pub fn hours(&self) -> f64 {
        self.run.hours()
    }
}

impl WearCase {
    /// The computed cycles and the work of the run ([`WearEstimate`]), before anything is
    /// solved: the surface grid and its checkerboard compliance `C_min` are evaluated (no
    /// contact solve). Refuses nothing but an invalid case and a grid whose solver would not fit
    /// in memory (checked before the compliance's `N₁ × N₂` table is built).
    pub fn estimate(&self) -> Result<WearEstimate, SamError> {
        self.validate()?;
        let lc = &self.fretting;
        let grid = SurfaceGrid::square(lc.grid, self.extent())?;
        crate::memory::check_problem(&grid, true, lc.is_coupled())?;
        let compliance = Compliance::pair(lc.indenter, Body::elastic(lc.e, lc.nu)?)?;
        let checkerboard = super::run::checkerboard_compliance(&compliance, &grid);
        let a = self.reference_radius();
        let p0 = 2.0 * self.e_star() * a / (std::f64::consts::PI * lc.radius);
        let path_length = 4.0 * lc.amplitude;
        let max_rate = self.law.rate(p0, lc.friction * p0, path_length);
        let accuracy = self.step_fraction * self.approach_scale() / max_rate;
        let stability = self.stability_fraction * checkerboard
            / (self.law.pressure_coefficient(lc.friction) * path_length);
        let dn = accuracy.min(stability).floor().max(1.0);
        let mut ends: Vec<u64> = self.record_cycles.clone();
        ends.push(self.cycles);
        ends.sort_unstable();
        ends.dedup();
        let mut start = 0u64;
        let mut wear_steps = 1.0; // the final state's cycle
        for end in ends {
            wear_steps += ((end - start) as f64 / dn).ceil();
            start = end;
        }
        let path = self.path();
        let quarter = path.quarter as f64;
        let increments_per_cycle = 4.0 * quarter;
        let increments = (path.cycle_start() + 1) as f64 + wear_steps * increments_per_cycle;
        // The wear run solves its contacts on the whole grid (no contact window).
        let one = lc.estimate_without_window();
        // With inhomogeneities, the cycle predictor's store (docs/wear3d.md#the-cycle-predictor):
        // eigenstrains and eigen-displacements of every increment of the last two computed
        // cycles, in the run and in its checkpoint's snapshot and record.
        let cycle_store = if lc.inhomogeneities.is_empty() || lc.surface_operator_over_a.is_some() {
            0.0
        } else {
            let cells = (lc.grid as f64).powi(2);
            3.0 * 2.0 * increments_per_cycle * (lc.eigenstrain_values_bound() + 3.0 * cells) * 8.0
        };
        Ok(WearEstimate {
            wear_steps,
            first_delta_cycles: dn,
            increments_per_cycle,
            increments,
            run: LoopEstimate {
                increments,
                work: one.work / one.increments * increments,
                bytes: one.bytes + cycle_store,
                ..one
            },
        })
    }
}

impl WearCase {
    /// A run of `fretting` under `law` for `cycles`, on the gap, force control, default steps.
    pub fn new(fretting: LoopCase, law: WearLaw, cycles: u64) -> Self {
        Self {
            fretting,
            law,
            body: WornBody::Gap,
            cycles,
            record_cycles: Vec::new(),
            step_fraction: DEFAULT_STEP_FRACTION,
            stability_fraction: DEFAULT_STABILITY_FRACTION,
            inhomogeneity_depth_cells: INHOMOGENEITY_DEPTH_CELLS,
        }
    }

    /// The 3D twin of the MDR wear problem of docs/theory-mdr.md#fretting-wear (the issue's
    /// cross-check, docs/wear3d.md#the-mdr-cross-check): two identical elastic bodies
    /// `E = 210 GPa`, `ν = 0` (`E* = E/2`, `G* = E/2`, no normal–tangential coupling: `κ = 0`
    /// for identical bodies, whereas a rigid sphere on a `ν = 0` half-space has the largest
    /// coupling `κ = 1/(4πG)`), `R = 105 μm`, fixed approach `d = 0.1 μm`
    /// (`a₀ = √(Rd)`), `μ = 0.3`, amplitude `u_A = χ μ d` (`u_max = μ E* d / G* = μd` for this
    /// pair), Archard on the gap with `k = a₀² d / (N₀ F₀ u_A)` (`F₀ = 4E* a₀³ / 3R`) so that
    /// `τ = N / N₀` (Willert 2021 Eq. 31); `grid²` cells over `±1.6 a₀`, `quarter` shift steps
    /// per quarter cycle, run to `τ_end`, records at `taus`.
    pub fn mdr_twin(
        grid: usize,
        chi: f64,
        n0: f64,
        tau_end: f64,
        taus: &[f64],
        quarter: usize,
    ) -> Result<Self, SamError> {
        if !(chi > 0.0 && chi < 1.0) {
            return Err(SamError::InvalidParameter {
                name: "chi (amplitude over the gross-slip amplitude)",
                value: chi,
                allowed: "in (0, 1)",
            });
        }
        crate::error::positive("N0 (cycles)", n0)?;
        crate::error::positive("tau_end", tau_end)?;
        let (e_pair, radius, d, mu): (f64, f64, f64, f64) = (210e9, 105e-6, 0.1e-6, 0.3);
        let e_half = 0.5 * e_pair; // E* of the pair
        let a0 = (radius * d).sqrt();
        let f0 = 4.0 * e_half * a0.powi(3) / (3.0 * radius);
        let amplitude = chi * mu * d;
        let k = a0 * a0 * d / (n0 * f0 * amplitude);
        let fretting = LoopCase {
            radius,
            e: e_pair,
            nu: 0.0,
            friction: mu,
            force: 0.0,
            approach: Some(d),
            indenter: Body::elastic(e_pair, 0.0)?,
            normal_steps: 1,
            amplitude,
            shift_step: amplitude / quarter.max(1) as f64,
            grid,
            extent_over_a: 3.2,
            inhomogeneities: Vec::new(),
            subsurface_depth: None,
            fatigue_depth: None,
            surface_operator_over_a: None,
            eim_change_factor: None,
            eim_recycled_depth: None,
            alternation: None,
        };
        debug_assert!((fretting.hertz_force() / f0 - 1.0).abs() < 1e-12);
        let cycles = (tau_end * n0).round() as u64;
        let mut case = Self::new(fretting, WearLaw::Archard { coefficient: k }, cycles);
        case.record_cycles = taus.iter().map(|t| (t * n0).round() as u64).collect();
        case.validate()?;
        Ok(case)
    }

    /// The reference radius the domain is scaled by: `a₀ = √(Rδ)` under approach control (the
    /// Hertz radius at that approach, rigid sphere), the Hertz radius of the force otherwise.
    pub fn reference_radius(&self) -> f64 {
        match self.fretting.approach {
            Some(d) => (self.fretting.radius * d).sqrt(),
            None => halfspace_mdr::analytic::sphere_radius_for_force(
                self.fretting.force,
                self.fretting.radius,
                self.e_star(),
            ),
        }
    }

    /// The pair's `E* = 1 / Σ (1 − νᵢ²)/Eᵢ` ([`LoopCase::e_star`]).
    pub fn e_star(&self) -> f64 {
        self.fretting.e_star()
    }

    /// The unworn elastic approach: `δ` under approach control, `a²/R` (Hertz) under force
    /// control: the scale of the depth increment per wear step.
    pub fn approach_scale(&self) -> f64 {
        match self.fretting.approach {
            Some(d) => d,
            None => {
                let a = self.reference_radius();
                a * a / self.fretting.radius
            }
        }
    }

    /// The domain side `extent_over_a · a₀` (m).
    pub fn extent(&self) -> f64 {
        self.fretting.extent_over_a * self.reference_radius()
    }

    /// The normal load of increment `k` of the path: `(k+1)/n` of the final force or approach
    /// during the `n` normal steps, the final one after.
    pub fn normal_load(&self, k: usize) -> NormalLoad {
        let n = self.fretting.normal_steps;
        let ramp = if k < n {
            (k + 1) as f64 / n as f64
        } else {
            1.0
        };
        match self.fretting.approach {
            Some(d) => NormalLoad::Approach(if k + 1 >= n { d } else { d * ramp }),
            None => NormalLoad::Force(if k + 1 >= n {
                self.fretting.force
            } else {
                self.fretting.force * ramp
            }),
        }
    }

    /// The shifts: the fretting loop's path ([`LoadPath`]); its cycle (after
    /// [`LoadPath::cycle_start`]) is the computed cycle of every wear step.
    pub fn path(&self) -> LoadPath {
        self.fretting.path()
    }

    /// Checks the configuration: the fretting loop's ([`LoopCase::validate`]), the approach,
    /// the coefficient, `cycles ≥ 1`, the record cycles in `[1, cycles]`, `η` in `(0, 0.5]`, `β`
    /// in `(0, 1.9]` (below the stability bound 2).
    pub fn validate(&self) -> Result<(), SamError> {
        self.fretting.validate()?;
        self.law.validate()?;
        if self.cycles == 0 {
            return Err(SamError::InvalidParameter {
                name: "cycles",
                value: 0.0,
                allowed: "≥ 1",
            });
        }
        if let Some(&c) = self
            .record_cycles
            .iter()
            .find(|&&c| c == 0 || c > self.cycles)
        {
            return Err(SamError::InvalidParameter {
                name: "record_cycles",
                value: c as f64,
                allowed: "in [1, cycles]",
            });
        }
        if !(self.step_fraction > 0.0 && self.step_fraction <= 0.5) {
            return Err(SamError::InvalidParameter {
                name: "step_fraction (largest depth increment per wear step / approach)",
                value: self.step_fraction,
                allowed: "in (0, 0.5]",
            });
        }
        if !(self.stability_fraction > 0.0 && self.stability_fraction <= 1.9) {
            return Err(SamError::InvalidParameter {
                name: "stability_fraction (of the explicit wear step's bound)",
                value: self.stability_fraction,
                allowed: "in (0, 1.9]",
            });
        }
        if !(self.inhomogeneity_depth_cells > 0.0 && self.inhomogeneity_depth_cells <= 1.0) {
            return Err(SamError::InvalidParameter {
                name: "inhomogeneity_depth_cells (worn depth over an inhomogeneity, cells)",
                value: self.inhomogeneity_depth_cells,
                allowed: "in (0, 1]",
            });
        }
        let a = self.reference_radius();
        let cell = self.extent() / self.fretting.grid as f64;
        if !(a.is_normal() && cell.is_normal()) {
            return Err(SamError::InvalidInput(format!(
                "approach = {:?} m and radius = {:e} m give a reference radius a0 = {a:e} m and \
                 cells of {cell:e} m: not representable (give SI values of a real contact)",
                self.fretting.approach, self.fretting.radius
            )));
        }
        Ok(())
    }

    /// Whether cell centre `(x, y)` lies above (inside the footprint of) an inhomogeneity.
    pub fn over_inhomogeneity(&self, x: f64, y: f64) -> bool {
        self.fretting.inhomogeneities.iter().any(|h| match h.shape {
            Shape::Sphere {
                x: cx, y: cy, r, ..
            } => (x - cx).hypot(y - cy) <= r,
            Shape::Cylinder {
                axis, position, r, ..
            } => match axis {
                crate::eim::Axis::X => (y - position).abs() <= r,
                crate::eim::Axis::Y => (x - position).abs() <= r,
            },
            Shape::Cuboid {
                x: cx, y: cy, half, ..
            } => (x - cx).abs() <= half[0] && (y - cy).abs() <= half[1],
        })
    }
}
