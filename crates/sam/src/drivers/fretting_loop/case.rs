//! The fretting-loop configuration and its load path.

use crate::contact::{Alternation, BodyResponse, ContactParams, GridWindow, NestedParams};
use crate::eim::{
    composite_fibres, FibreLayout, Inhomogeneity, COMPOSITE_CELLS_PER_RADIUS,
    COMPOSITE_FIBRE_RADIUS,
};
use crate::kernels::surface::Body;
use crate::normal::NormalLoad;
use crate::subsurface::SubsurfacePlan;
use crate::{SamError, SurfaceGrid};

/// The labels of the points of \[LN11\] Figs. 5–7: A end of the normal loading, B `δx = +A`, C
/// `δx = 0` on the way back, D `δx = −A`.
pub const POINT_LABELS: [&str; 4] = ["A", "B", "C", "D"];

/// Declares a struct holding the nine keys a fretting loop's case ([`LoopCase`]) and its
/// configurations (`halfspace_cases::config::LoopConfig`, read from TOML and Python dicts) share,
/// each declared once, here, with its type, documentation and default (\[LN11\]'s homogeneous
/// case): `radius, e, nu, friction`, then the struct's `load` fields, then `normal_steps,
/// amplitude, shift_step, grid, extent_over_a`, then its `rest` fields — in this order, which is
/// the order of `{:?}` (checkpoint fingerprints) and of serde's list of expected keys. Each own
/// field is written `name: Type = default`; the macro also writes `Default` and
/// `loop_keys`/`set_loop_keys`, which copy the shared keys through [`LoopKeys`].
#[macro_export]
macro_rules! fretting_loop_keys {
    (
        $(#[$attr:meta])*
        $vis:vis struct $name:ident {
            load {
                $($(#[$load_attr:meta])* $load:ident : $load_ty:ty = $load_default:expr),* $(,)?
            }
            rest {
                $($(#[$rest_attr:meta])* $rest:ident : $rest_ty:ty = $rest_default:expr),* $(,)?
            }
        }
    ) => {
        $(#[$attr])*
        $vis struct $name {
            /// Sphere radius R (m).
            pub radius: f64,
            /// Young's modulus of the half-space (matrix) (Pa).
            pub e: f64,
            /// Poisson ratio of the half-space.
            pub nu: f64,
            /// Coulomb friction coefficient μ > 0.
            pub friction: f64,
            $($(#[$load_attr])* pub $load: $load_ty,)*
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
            $($(#[$rest_attr])* pub $rest: $rest_ty,)*
        }

        impl ::std::default::Default for $name {
            /// \[LN11\]'s homogeneous case.
            fn default() -> Self {
                Self {
                    radius: 105e-6,
                    e: 210e9,
                    nu: 0.3,
                    friction: 0.3,
                    $($load: $load_default,)*
                    normal_steps: 80,
                    amplitude: 0.04e-6,
                    shift_step: 0.002e-6,
                    grid: 64,
                    extent_over_a: 4.16,
                    $($rest: $rest_default,)*
                }
            }
        }

        impl $name {
            /// The keys shared by every fretting-loop struct (`LoopKeys`).
            pub fn loop_keys(&self) -> $crate::drivers::fretting_loop::LoopKeys {
                $crate::drivers::fretting_loop::LoopKeys {
                    radius: self.radius,
                    e: self.e,
                    nu: self.nu,
                    friction: self.friction,
                    normal_steps: self.normal_steps,
                    amplitude: self.amplitude,
                    shift_step: self.shift_step,
                    grid: self.grid,
                    extent_over_a: self.extent_over_a,
                }
            }

            /// These shared keys set to `keys`'.
            pub fn set_loop_keys(&mut self, keys: $crate::drivers::fretting_loop::LoopKeys) {
                self.radius = keys.radius;
                self.e = keys.e;
                self.nu = keys.nu;
                self.friction = keys.friction;
                self.normal_steps = keys.normal_steps;
                self.amplitude = keys.amplitude;
                self.shift_step = keys.shift_step;
                self.grid = keys.grid;
                self.extent_over_a = keys.extent_over_a;
            }
        }
    };
}

fretting_loop_keys! {
    /// The keys every fretting-loop struct shares, alone ([`fretting_loop_keys!`]): how
    /// [`LoopCase`] and a configuration pass them to each other.
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct LoopKeys {
        load {}
        rest {}
    }
}

fretting_loop_keys! {
    /// A fretting loop: a sphere of radius `radius` (rigid, or elastic with
    /// [`LoopCase::indenter`]) on a flat half-space `(e, nu)` with Coulomb friction `friction`,
    /// normal force ramped to `force` (or the approach to [`LoopCase::approach`]) in
    /// `normal_steps` equal steps, then the shift cycled with amplitude `amplitude` in steps
    /// `shift_step`, on `grid²` cells over `extent_over_a · a` (`a` the Hertz radius of the pair).
    /// Defaults: \[LN11\]'s homogeneous case (rigid sphere, R = 105 μm, E = 210 GPa, ν = 0.3,
    /// μ = 0.3, W = 80 mN in 80 steps, A = 0.04 μm in 0.002 μm steps, 64² over 4.16a); the keys
    /// shared with the configurations are declared by [`fretting_loop_keys!`].
    ///
    /// The two bodies enter the contact through their compliances (docs/theory-sam.md#two-bodies):
    /// `1/E* = Σ(1 − ν²)/E`, the tangential compliance `Σ(2 − ν)/G` of Mindlin's slip shift and the
    /// normal–tangential coupling `κ` (a difference: zero for identical bodies). Inhomogeneities and
    /// subsurface stresses belong to the flat, with its own `(e, nu)`.
    #[derive(Debug, Clone, PartialEq)]
    pub struct LoopCase {
        load {
            /// Final normal force W (N) under force control; must be 0 when
            /// [`LoopCase::approach`] is given (exactly one of them sets the normal load).
            force: f64 = 0.08,
            /// Final rigid approach δ (m) under approach control (`None`: force control by
            /// `force`). The approach is ramped like the force, `δ_i = δ i / n`; the force `W(δ)`
            /// is computed.
            approach: Option<f64> = None,
            /// The indenter (the sphere): [`Body::Rigid`] (\[LN11\]) or [`Body::Elastic`]
            /// `{ e, nu }`.
            indenter: Body = Body::Rigid,
        }
        rest {
            /// Inhomogeneities below the surface (none: the homogeneous loop).
            inhomogeneities: Vec<Inhomogeneity> = Vec::new(),
            /// Depth (m) of the von Mises field stored at the points A–D (`None`: not computed).
            subsurface_depth: Option<f64> = None,
            /// Depth (m) of the box whose stress history over the closed cycle is recorded for the
            /// fatigue criteria ([`super::CycleStress`]; `None`: not recorded).
            fatigue_depth: Option<f64> = None,
            /// How the inhomogeneous body's surface response enters the increments
            /// (docs/theory-sam.md#surface-response-operator): `None` — the nested contact ↔ EIM
            /// loop of \[LN11\] Fig. 2 in every increment (the reference path); `Some(r)` — the
            /// surface-response operator, built once over the cells within `r · a` of the axis
            /// (`a` the Hertz radius), applied instead of the EIM solves. Ignored without
            /// inhomogeneities.
            surface_operator_over_a: Option<f64> = None,
            /// The EIM change factor `η` of the nested loop (each outer pass's EIM solved to `η`
            /// times the last outer change, docs/theory-sam.md#outer-loop-tolerances; in (0, 1]):
            /// `None` — the default of [`NestedParams::eim_change_factor`] (or the one passed to
            /// [`super::FrettingLoop::with_params`]). Used by the nested loop only.
            eim_change_factor: Option<f64> = None,
            /// The nested loop's recycled EIM depth (Anderson differences of the block-Jacobi
            /// iteration kept across an increment's outer passes, [`crate::eim::EimParams::recycled_depth`],
            /// docs/theory-sam.md#solving-the-eim-equations; 0: the plain block Jacobi): `None` —
            /// the default of [`NestedParams`] ([`crate::contact::DEFAULT_EIM_RECYCLED_DEPTH`], or
            /// the one passed to [`super::FrettingLoop::with_params`]). Used by the nested loop only.
            eim_recycled_depth: Option<usize> = None,
            /// The normal–tangential alternation of the contact solves
            /// (docs/theory-sam.md#normal-tangential-alternation): `None` — the library's default
            /// ([`ContactParams::default`]'s [`ContactParams::alternation`]). Read by coupled
            /// pairs only ([`LoopCase::is_coupled`]: an uncoupled increment is one normal and one
            /// tangential solve whatever the scheme); the composite loop and its homogeneous
            /// reference loop ([`LoopCase::homogeneous`]) both take it.
            alternation: Option<Alternation> = None,
        }
    }
}

/// The half-width of the fretting loop's contact window over the Hertz radius `a`
/// ([`ContactProblem::set_window`](crate::contact::ContactProblem::set_window)): the contact of
/// \[LN11\]'s loops reaches ≈ 1.05a (a ±1.04a window is too small, docs/performance.md, "A
/// contact window for the 3D loops"); 1.17a leaves ≈ 3.7 cells at 128² (a 72² window, padded to
/// 144² — 1.3a, an 80² window, until stop 47: the composite command's contact solves 18.8 → 15.5
/// s, the same results to the solvers' tolerance, docs/performance.md "The contraction stopping
/// rule (issue 21, stop 47)"). A solve whose contact goes further runs on the whole grid.
pub const CONTACT_WINDOW_OVER_A: f64 = 1.17;

/// What a loop's checkpoint fingerprint appends for its contact window
/// ([`LoopCase::window_fingerprint`]); absent from checkpoints of builds before the window, which
/// are refused.
pub const CONTACT_WINDOW_FIELD: &str = "; contact window ";

/// What a checkpoint fingerprint of a loop with inhomogeneities ends with, before the outer
/// loop's stopping rule ([`crate::contact::OuterStopping`], [`LoopCase::stopping_fingerprint`]).
pub const OUTER_STOPPING_FIELD: &str = "; outer stopping ";

/// What a checkpoint fingerprint of a loop with inhomogeneities ends with since the predictor's
/// EIM start carries its image ([`crate::contact::EimIterate`], stop 47): the snapshot holds the
/// pairs a bit-for-bit resume needs.
pub const PREDICTOR_IMAGE_FIELD: &str = "; EIM start from the predictor's image";

/// How a fingerprint (`{:?}` of [`LoopCase`]) spells the alternation scheme's field: absent
/// from checkpoints written before it was recorded ([`LoopCase::check_fingerprint`]).
const ALTERNATION_FIELD: &str = ", alternation: ";

/// The EIM change factor meant by `eim_change_factor: None` in a checkpoint fingerprint written
/// before fingerprints recorded the factor used (before commit `ce12b57`, when the library's
/// default was 10⁻²; [`LoopCase::check_fingerprint`]).
pub const UNRECORDED_EIM_CHANGE_FACTOR: f64 = 1e-2;

impl LoopCase {
    /// The flat half-space as a body of the pair.
    pub fn flat(&self) -> Body {
        Body::Elastic {
            e: self.e,
            nu: self.nu,
        }
    }

    /// The final normal force of the normal loading: `force` under force control, Hertz's
    /// `W(δ) = (4/3) E* √R δ^{3/2}` (Johnson 1985 Eq. 4.23) under approach control — the scale of
    /// the loop (Hertz radius, pressure, `μW`, Mindlin's shift); the computed force of a
    /// discretised contact is in the rows.
    pub fn hertz_force(&self) -> f64 {
        match self.approach {
            None => self.force,
            Some(d) => 4.0 / 3.0 * self.e_star() * self.radius.sqrt() * d * d.sqrt(),
        }
    }

    /// The Hertz contact radius `a = (3WR / 4E*)^{1/3}` of the pair (`W` =
    /// [`LoopCase::hertz_force`]; under approach control this is `√(Rδ)` up to rounding).
    pub fn hertz_radius(&self) -> f64 {
        halfspace_mdr::analytic::sphere_radius_for_force(
            self.hertz_force(),
            self.radius,
            self.e_star(),
        )
    }

    /// The Hertz peak pressure `p₀ = 3W / (2πa²)`.
    pub fn hertz_pressure(&self) -> f64 {
        let a = self.hertz_radius();
        3.0 * self.hertz_force() / (2.0 * std::f64::consts::PI * a * a)
    }

    /// The effective modulus of the pair, `1/E* = (1 − ν₁²)/E₁ + (1 − ν²)/E` (Johnson 1985
    /// Eq. 4.22); `E/(1 − ν²)` for a rigid indenter (computed as in earlier versions, bit for bit).
    pub fn e_star(&self) -> f64 {
        match self.indenter {
            Body::Rigid => self.e / (1.0 - self.nu * self.nu),
            indenter => 1.0 / (indenter.normal_term() + self.flat().normal_term()),
        }
    }

    /// Mindlin's full-slip shift `K = (3μW / 16a) Σ(2 − ν)/G` over both bodies, `G = E / 2(1 + ν)`
    /// (docs/theory-sam.md#mindlin-deresiewicz-reference, uncoupled; Johnson 1985 Eq. 7.42): the
    /// loop is in partial slip for `A < K` and reaches gross slip beyond (Mindlin–Deresiewicz,
    /// [`crate::analytic::mindlin`]). Rigid indenter: `3μW(2 − ν)/(16 G a)`, bit for bit as
    /// before.
    pub fn mindlin_slip_shift(&self) -> f64 {
        let w = self.hertz_force();
        match self.indenter {
            Body::Rigid => {
                let g = self.e / (2.0 * (1.0 + self.nu));
                3.0 * self.friction * w * (2.0 - self.nu) / (16.0 * g * self.hertz_radius())
            }
            indenter => {
                let compliance = indenter.mindlin_term() + self.flat().mindlin_term();
                3.0 * self.friction * w * compliance / (16.0 * self.hertz_radius())
            }
        }
    }

    /// Whether the loop's contact problem is coupled ([`crate::Compliance::is_coupled`] of the
    /// pair: friction `μ > 0` and a coupling `κ = (1−2ν₂)/(4πG₂) − (1−2ν₁)/(4πG₁)` that does not
    /// vanish — dissimilar bodies; always for a rigid indenter with `ν < ½`). Its problem then
    /// holds the two coupling operators and four more fields ([`crate::memory::problem_bytes`]).
    pub fn is_coupled(&self) -> bool {
        crate::Compliance::pair(self.indenter, self.flat())
            .map_or(true, |c| c.is_coupled(self.friction))
    }

    /// The grid's side length `extent_over_a · a` (m).
    pub fn extent(&self) -> f64 {
        self.extent_over_a * self.hertz_radius()
    }

    /// \[LN11\]'s composite (§4): this case with the paper's fibres of `layout` (radius 0.13a,
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

    /// The alternation scheme of the loop's contact solves: [`LoopCase::alternation`], or the
    /// library's default when `None` (what [`super::FrettingLoop`] and the wear run pass to
    /// [`ContactParams::alternation`]).
    pub fn alternation_scheme(&self) -> Alternation {
        self.alternation
            .unwrap_or(ContactParams::default().alternation)
    }

    /// The alternation scheme the loop's contact solves use ([`LoopCase::alternation_scheme`]),
    /// `None` for an uncoupled pair, whose increments do not alternate (the scheme is not used;
    /// docs/theory-sam.md#normal-tangential-alternation).
    pub fn alternation_used(&self) -> Option<Alternation> {
        self.is_coupled().then(|| self.alternation_scheme())
    }

    /// The window of the grid the loop's contact solves run on: the central cells within
    /// [`CONTACT_WINDOW_OVER_A`]` · a` of the axis ([`GridWindow::central`]; `None`: the whole
    /// grid).
    pub fn contact_window(&self) -> Result<Option<GridWindow>, SamError> {
        let a = self.hertz_radius();
        let grid = SurfaceGrid::square(self.grid, self.extent_over_a * a)?;
        GridWindow::central(&grid, CONTACT_WINDOW_OVER_A * a)
    }

    /// What the loop's checkpoint fingerprint appends for its contact window
    /// ([`CONTACT_WINDOW_FIELD`] and the window's cells, `None` for the whole grid).
    pub fn window_fingerprint(&self) -> Result<String, SamError> {
        Ok(format!(
            "{CONTACT_WINDOW_FIELD}{:?}",
            self.contact_window()?.map(|w| w.cells)
        ))
    }

    /// What the loop's checkpoint fingerprint appends for the outer loop's stopping rule of
    /// `nested` ([`OUTER_STOPPING_FIELD`] and the rule, then [`PREDICTOR_IMAGE_FIELD`]): nothing
    /// without inhomogeneities (no outer loop).
    pub fn stopping_fingerprint(&self, nested: NestedParams) -> String {
        if self.inhomogeneities.is_empty() {
            String::new()
        } else {
            format!(
                "{OUTER_STOPPING_FIELD}{:?}{PREDICTOR_IMAGE_FIELD}",
                nested.stopping
            )
        }
    }

    /// Refuses, saying why, a checkpoint fingerprint `recorded` of a loop with inhomogeneities
    /// written before the contraction stopping rule and the predictor's image (both stop 47):
    /// its increments would not be repeated bit for bit.
    pub fn check_stopping_recorded(&self, recorded: &str) -> Result<(), SamError> {
        if self.inhomogeneities.is_empty()
            || (recorded.contains(OUTER_STOPPING_FIELD) && recorded.contains(PREDICTOR_IMAGE_FIELD))
        {
            return Ok(());
        }
        Err(SamError::InvalidInput(
            "the checkpoint was written by a build before the outer loop's contraction stopping \
             rule and the predictor's EIM image (docs/theory-sam.md#the-contraction-stopping-rule, \
             #the-predictors-image): its increments would not be repeated bit for bit; start over"
                .into(),
        ))
    }

    /// The case as it runs with the outer-loop parameters `nested`: the alternation scheme the
    /// one used ([`LoopCase::alternation_used`]); with inhomogeneities and the nested loop,
    /// [`LoopCase::eim_change_factor`] is the factor that loop uses (the case's, or `nested`'s
    /// default); otherwise the case unchanged (the factor is not used). A checkpoint's
    /// fingerprint is this case as `{:?}` (and [`LoopCase::window_fingerprint`]), so it records
    /// the values used and a change of the library's defaults is caught
    /// ([`LoopCase::check_fingerprint`]).
    pub fn as_run(&self, nested: NestedParams) -> LoopCase {
        let mut case = self.clone();
        case.alternation = self.alternation_used();
        if !self.inhomogeneities.is_empty() && self.surface_operator_over_a.is_none() {
            let run = self.nested_params(nested);
            case.eim_change_factor = Some(run.eim_change_factor);
            case.eim_recycled_depth = Some(run.eim.recycled_depth);
        }
        case
    }

    /// A checkpoint fingerprint `recorded` checked against this case's run with `nested`, whose
    /// fingerprint is `current` (`{:?}` of a struct holding [`LoopCase::as_run`]): accepted when
    /// equal, or — a checkpoint written before commit `ce12b57`, whose fingerprint held the case
    /// as given (`eim_change_factor: None` when defaulted), `given` — when equal to `given` while
    /// the run uses [`UNRECORDED_EIM_CHANGE_FACTOR`], the default then (given by the run's
    /// configuration or defaulted): the same loop, step for step. A checkpoint without the
    /// recycled EIM depth is accepted only by a run with depth 0, one without the alternation
    /// scheme (written before it was recorded, with the plain alternation) only by a run whose
    /// scheme is [`Alternation::Plain`] (or an uncoupled one, which does not alternate). Any other
    /// checkpoint is refused ([`SamError::InvalidInput`], naming the keys when the depth or the
    /// scheme is not recorded).
    pub fn check_fingerprint(
        &self,
        nested: NestedParams,
        recorded: &str,
        current: &str,
        given: &str,
    ) -> Result<(), SamError> {
        if recorded.contains(ALTERNATION_FIELD) {
            return self.check_recorded_fingerprint(nested, recorded, current, given);
        }
        // Written before fingerprints held the alternation scheme: the plain alternation (the
        // only one the drivers ran then). The field is left out of this run's fingerprints and
        // the rest compared; the run must then use the plain alternation to continue that loop.
        let used = self.alternation_used();
        let unrecorded = |s: &str| {
            s.replacen(&format!("{ALTERNATION_FIELD}{:?}", self.alternation), "", 1)
                .replacen(&format!("{ALTERNATION_FIELD}{used:?}"), "", 1)
        };
        self.check_recorded_fingerprint(
            nested,
            recorded,
            &unrecorded(current),
            &unrecorded(given),
        )?;
        if used == Some(Alternation::Gauged) {
            return Err(SamError::InvalidInput(
                "the checkpoint was written before the alternation scheme was recorded, with the \
                 plain normal-tangential alternation: resume it with alternation = \"plain\""
                    .into(),
            ));
        }
        Ok(())
    }

    /// [`LoopCase::check_fingerprint`] of a fingerprint `recorded` that holds the alternation
    /// scheme (or with it left out of `current` and `given`).
    fn check_recorded_fingerprint(
        &self,
        nested: NestedParams,
        recorded: &str,
        current: &str,
        given: &str,
    ) -> Result<(), SamError> {
        let run = self.as_run(nested);
        // A checkpoint written before fingerprints held the recycled EIM depth (before it became
        // a key) was made with the plain block Jacobi: accepted, with the field left out of the
        // fingerprints, only while this run uses depth 0 (or, without the nested loop, the
        // depth is not used: `None`).
        let plain = matches!(run.eim_recycled_depth, None | Some(0));
        let unrecorded_depth = |s: &str| {
            s.replacen(
                &format!(", eim_recycled_depth: {:?}", self.eim_recycled_depth),
                "",
                1,
            )
            .replacen(
                &format!(", eim_recycled_depth: {:?}", run.eim_recycled_depth),
                "",
                1,
            )
        };
        let unrecorded_default = self.eim_change_factor.is_none()
            && run.eim_change_factor == Some(UNRECORDED_EIM_CHANGE_FACTOR);
        let matches = |current: &str, given: &str| {
            recorded == current || (unrecorded_default && recorded == given)
        };
        // A checkpoint written before `ce12b57` holds `eim_change_factor: None` for the factor
        // then defaulted (10⁻²): the same loop as a run that gives that factor explicitly.
        let given_as_defaulted = given.replacen(
            &format!("eim_change_factor: {:?}", self.eim_change_factor),
            "eim_change_factor: None",
            1,
        );
        let legacy_default = plain
            && run.eim_change_factor == Some(UNRECORDED_EIM_CHANGE_FACTOR)
            && recorded == unrecorded_depth(&given_as_defaulted);
        if matches(current, given)
            || (plain && matches(&unrecorded_depth(current), &unrecorded_depth(given)))
            || legacy_default
        {
            Ok(())
        } else if !recorded.contains("eim_recycled_depth") {
            Err(SamError::InvalidInput(
                "the checkpoint was written before the recycled EIM depth was recorded, with \
                 the plain EIM iteration and (unless its configuration gave another) \
                 eim_change_factor = 1e-2: resume it with eim_recycled_depth = 0 and that \
                 eim_change_factor"
                    .into(),
            ))
        } else {
            Err(SamError::InvalidInput(
                "the checkpoint was made with another configuration".into(),
            ))
        }
    }

    /// `base` with the body response of [`LoopCase::surface_operator_over_a`]
    /// ([`BodyResponse`]): the nested loop, or the surface operator over the cells within `r · a`;
    /// and with [`LoopCase::eim_change_factor`] and [`LoopCase::eim_recycled_depth`] when given.
    pub fn nested_params(&self, base: NestedParams) -> NestedParams {
        NestedParams {
            eim_change_factor: self.eim_change_factor.unwrap_or(base.eim_change_factor),
            eim: crate::eim::EimParams {
                recycled_depth: self.eim_recycled_depth.unwrap_or(base.eim.recycled_depth),
                ..base.eim
            },
            body: match self.surface_operator_over_a {
                Some(r) => BodyResponse::SurfaceOperator {
                    radius: r * self.hertz_radius(),
                },
                None => BodyResponse::Nested,
            },
            ..base
        }
    }

    /// The same loop without inhomogeneities (the reference of \[LN11\] Figs. 5–10).
    pub fn homogeneous(&self) -> Self {
        Self {
            inhomogeneities: Vec::new(),
            ..self.clone()
        }
    }

    /// Checks the configuration (every scalar finite and in range, at least one step of each
    /// kind, a Hertz radius that is a normal number). Errors name the field as the configuration
    /// spells it (`shift_step`, `normal_steps`, …: the keys of `fretting-loop --config` and of
    /// the Python dict).
    pub fn validate(&self) -> Result<(), SamError> {
        for (name, v) in [
            ("radius (sphere radius R, m)", self.radius),
            ("e (Young's modulus, Pa)", self.e),
            (
                "friction (Coulomb μ; a fretting loop needs μ > 0)",
                self.friction,
            ),
            ("amplitude (shift amplitude A, m)", self.amplitude),
            ("shift_step (m)", self.shift_step),
            ("extent_over_a", self.extent_over_a),
        ] {
            crate::error::positive(name, v)?;
        }
        match self.approach {
            None => {
                crate::error::positive("force (normal force W, N)", self.force)?;
            }
            Some(d) => {
                crate::error::positive("approach (rigid approach δ, m)", d)?;
                if self.force != 0.0 {
                    return Err(SamError::InvalidInput(format!(
                        "force = {:e} N and approach = {d:e} m: give exactly one of them (the \
                         normal load is controlled by force or by approach)",
                        self.force
                    )));
                }
            }
        }
        if let Body::Elastic { e, nu } = self.indenter {
            crate::error::positive("indenter_e (Young's modulus of the indenter, Pa)", e)?;
            if !(nu > -1.0 && nu <= 0.5) {
                return Err(SamError::InvalidParameter {
                    name: "indenter_nu (Poisson ratio of the indenter)",
                    value: nu,
                    allowed: "in (−1, 0.5]",
                });
            }
        }
        if !(self.nu > -1.0 && self.nu < 0.5) {
            return Err(SamError::InvalidParameter {
                name: "nu (Poisson ratio)",
                value: self.nu,
                allowed: "in (−1, 0.5)",
            });
        }
        if self.normal_steps == 0 {
            return Err(SamError::InvalidParameter {
                name: "normal_steps",
                value: 0.0,
                allowed: "≥ 1",
            });
        }
        // The surface grid's own minimum (`SurfaceGrid::square`), stated here first.
        if self.grid < 8 {
            return Err(SamError::InvalidParameter {
                name: "grid (cells per side)",
                value: self.grid as f64,
                allowed: "≥ 8",
            });
        }
        // The scales of the loop (a, the cell, the Hertz pressure) must be normal numbers: a
        // subnormal force or radius underflows them.
        let a = self.hertz_radius();
        let cell = self.extent() / self.grid as f64;
        let p0 = self.hertz_pressure();
        if !(a.is_normal() && cell.is_normal() && p0.is_normal() && a > 0.0) {
            return Err(SamError::InvalidInput(format!(
                "force = {:e} N (or approach = {:?} m), radius = {:e} m and e = {:e} Pa give a \
                 Hertz radius a = {a:e} m, cells of {cell:e} m and p0 = {p0:e} Pa: not \
                 representable (give SI values of a real contact)",
                self.force, self.approach, self.radius, self.e
            )));
        }
        if let Some(d) = self.subsurface_depth {
            crate::error::positive("subsurface depth", d)?;
        }
        if let Some(d) = self.fatigue_depth {
            crate::error::positive("fatigue box depth", d)?;
        }
        if let Some(r) = self.surface_operator_over_a {
            crate::error::positive("surface_operator_radius_over_a", r)?;
        }
        if let Some(eta) = self.eim_change_factor {
            NestedParams {
                eim_change_factor: eta,
                ..NestedParams::default()
            }
            .validate()?;
        }
        if let Some(depth) = self.eim_recycled_depth {
            NestedParams {
                eim: crate::eim::EimParams {
                    recycled_depth: depth,
                    ..crate::eim::EimParams::default()
                },
                ..NestedParams::default()
            }
            .validate()?;
        }
        Ok(())
    }

    /// Eigenstrain values of the inclusion cells (6 each), bounded by every cell of the layers
    /// down to the deepest inhomogeneity (the layers of `InclusionSet::new`); 0 without
    /// inhomogeneities.
    pub fn eigenstrain_values_bound(&self) -> f64 {
        let cells = (self.grid as f64).powi(2);
        6.0 * cells * self.inclusion_layers_bound() as f64
    }

    /// The layers of cells down to the deepest inhomogeneity (`⌈deepest / 2Δ⌉ + 1`, a bound on
    /// the inclusion layers of `InclusionSet::new`); 0 without inhomogeneities.
    pub fn inclusion_layers_bound(&self) -> usize {
        if self.inhomogeneities.is_empty() {
            return 0;
        }
        let cell = self.extent() / self.grid as f64;
        let deepest = self
            .inhomogeneities
            .iter()
            .map(|inh| inh.bounds().1)
            .fold(0.0f64, f64::max);
        (deepest / cell).ceil() as usize + 1
    }

    /// [`LoopCase::estimate`] with, for a case with inhomogeneities, the memory of its
    /// homogeneous reference loop ([`LoopCase::homogeneous`]) run beside it
    /// ([`FrettingLoop::run_beside`](super::FrettingLoop::run_beside)): both alive at once.
    pub fn estimate_with_reference(&self) -> LoopEstimate {
        let mut both = self.estimate();
        if !self.inhomogeneities.is_empty() {
            both.bytes += self.homogeneous().estimate().bytes;
        }
        both
    }

    /// Estimated bytes of the loop's frictional contact problem on its grid
    /// ([`memory::problem_bytes_per_cell`](crate::memory::problem_bytes_per_cell), with the
    /// coupling operators when the pair is coupled; with inhomogeneities its three
    /// eigen-displacement fields, 24 bytes a cell) and, with `windowed`, of its contact window
    /// ([`LoopCase::contact_window`], [`memory::window_bytes`](crate::memory::window_bytes); a
    /// case that fails `validate` has none counted here and is refused before it is built).
    pub fn contact_problem_bytes(&self, windowed: bool) -> f64 {
        let cells = (self.grid as f64).powi(2);
        let coupled = self.is_coupled();
        let eigen = if self.inhomogeneities.is_empty() {
            0.0
        } else {
            24.0
        };
        let whole = (crate::memory::problem_bytes_per_cell(true, coupled) + eigen) * cells;
        let window = match self.contact_window() {
            Ok(Some(w)) if windowed => crate::memory::window_bytes(
                cells,
                w.cells[0] as f64 * w.cells[1] as f64,
                true,
                coupled,
                !self.inhomogeneities.is_empty(),
            ),
            _ => 0.0,
        };
        whole + window
    }

    /// The cost of this loop ([`LoopEstimate`]), from the configuration alone; its contact
    /// solves on the contact window ([`LoopCase::contact_window`]).
    pub fn estimate(&self) -> LoopEstimate {
        self.estimate_solved_on(true)
    }

    /// [`LoopCase::estimate`] of a run whose contact solves use the whole grid, not the contact
    /// window (the wear run's, `drivers::fretting_wear3d`).
    pub fn estimate_without_window(&self) -> LoopEstimate {
        self.estimate_solved_on(false)
    }

    fn estimate_solved_on(&self, windowed: bool) -> LoopEstimate {
        let increments =
            self.normal_steps as f64 + 5.0 * quarter_steps(self.amplitude, self.shift_step);
        let cells = (self.grid as f64).powi(2);
        // The EIM loop weighs like a few more contact solves per inclusion layer; without a
        // layer count before the geometry is built, count the inhomogeneities' cells as one
        // layer each (an upper bound's shape, not a timing model).
        let weight = 1.0 + 4.0 * self.inhomogeneities.len().min(64) as f64;
        let cell = self.extent() / self.grid as f64;
        let eigen_len = self.eigenstrain_values_bound();
        // The points A–D: eight surface fields each (and the von Mises fields, when asked); with
        // inhomogeneities and a subsurface depth, the eigenstrains of the three points whose von
        // Mises fields wait for the fourth's (three copies: the loop's, a snapshot's and its
        // record's).
        let pending = if self.subsurface_depth.is_some() {
            3.0 * 3.0 * eigen_len * 8.0
        } else {
            0.0
        };
        // The von Mises fields of the four points, computed at once when the last is reached
        // (`subsurface::von_mises_fields`): their working set (the states' spectra, the strain
        // spectra of a group of layers, the kernels' blocks) and the fields kept.
        let von_mises = match self.subsurface_depth {
            Some(depth) => crate::subsurface::von_mises_fields_bytes(
                (self.grid, self.grid),
                SubsurfacePlan::layers_for(depth, 0.5 * cell),
                self.inclusion_layers_bound(),
                POINT_LABELS.len(),
            ),
            None => 0.0,
        };
        let points = 4.0 * cells * 8.0 * 8.0 + pending + von_mises;
        // The nested loop's recycled EIM history (docs/theory-sam.md#solving-the-eim-equations):
        // `2 · depth + 7` vectors of the EIM system's size (the eigenstrains), capped at 2 GiB
        // like the solver's (`EimParams::recycled_depth`).
        let recycled = if self.inhomogeneities.is_empty() || self.surface_operator_over_a.is_some()
        {
            0.0
        } else {
            let depth = self
                .eim_recycled_depth
                .unwrap_or(crate::contact::DEFAULT_EIM_RECYCLED_DEPTH);
            recycled_history_bytes(depth, eigen_len)
        };
        // The stress history of the closed cycle (docs/fatigue.md, "On the fretting loop"): the
        // path `cells · layers · (4q + 1) · 48 B` once (the checkpoints carry the increments'
        // tractions instead, counted three times: the loop's, the snapshot's and its record's),
        // Love's stored kernel spectra and one stress field per increment.
        let history = match self.fatigue_depth {
            Some(depth) => {
                let layers = super::CycleStress::layers_for(depth, cell);
                let cycle = 4.0 * quarter_steps(self.amplitude, self.shift_step) + 1.0;
                let n = self.grid;
                // The layers and the surface layer z = 0; with inhomogeneities each increment's
                // sources also keep the eigenstrains.
                let levels = layers + 1;
                super::CycleStress::bytes(cells, levels as f64, cycle)
                    + 3.0 * super::CycleSources::bytes(cells, eigen_len, cycle)
                    + crate::subsurface::SubsurfacePlan::spectra_bytes(n, n, levels)
                    + crate::subsurface::SubsurfacePlan::field_bytes(n, n, levels)
            }
            None => 0.0,
        };
        // The surface-response operator: 3 × 3 values per grid cell and candidate cell
        // (docs/theory-sam.md#surface-response-operator), the candidates those within r·a.
        let operator = match self.surface_operator_over_a {
            Some(r) if !self.inhomogeneities.is_empty() => {
                let cells_per_a = self.grid as f64 / self.extent_over_a;
                let candidates = std::f64::consts::PI * (r * cells_per_a).powi(2) + 1.0;
                crate::eim::SurfaceResponse::bytes(cells as usize, candidates as usize, 3)
            }
            _ => 0.0,
        };
        LoopEstimate {
            increments,
            cells,
            loops: 1.0,
            concurrent: 1.0,
            bytes: self.contact_problem_bytes(windowed)
                + points
                + increments * ROW_BYTES
                + history
                + operator
                + recycled,
            work: increments * cells * weight,
        }
    }

    /// The load path of this case.
    pub fn path(&self) -> LoadPath {
        let mut path = LoadPath::fretting(
            self.force,
            self.normal_steps,
            self.amplitude,
            self.shift_step,
        );
        if let Some(d) = self.approach {
            path.force = d;
            path.by_approach = true;
        }
        path
    }
}

/// Bytes of the recycled EIM history of depth `depth` on an EIM system of `len` unknowns:
/// `(2 · depth + 7) · len · 8`, at most 2 GiB (the cap of `EimParams::recycled_depth`).
pub fn recycled_history_bytes(depth: usize, len: f64) -> f64 {
    if depth == 0 {
        return 0.0;
    }
    ((2.0 * depth as f64 + 7.0) * len * 8.0).min((2u64 << 30) as f64)
}

/// The increments of a fretting loop: `W_i = W i / n` (or the approach `δ_i = δ i / n` under
/// approach control) at `δx = 0` (`i = 1..n`), then `δx` from 0
/// to `+A`, to `−A` and back to `+A` in `q = round(A / step)` steps per quarter. Generated on
/// demand ([`LoadPath::increment`]), never stored: a path of 10¹³ increments costs nothing until
/// it is run (and [`LoopCase::estimate`] refuses it before).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoadPath {
    /// Final normal force W (the final approach δ when `by_approach`).
    pub force: f64,
    /// Normal control by approach (`force` holds δ) rather than by force.
    pub by_approach: bool,
    /// Shift amplitude A.
    pub amplitude: f64,
    /// Normal steps `n`.
    pub normal_steps: usize,
    /// Shift steps per quarter cycle `q`.
    pub quarter: usize,
}

impl LoadPath {
    /// The \[LN11\] path (struct doc).
    pub fn fretting(force: f64, normal_steps: usize, amplitude: f64, shift_step: f64) -> Self {
        Self {
            force,
            by_approach: false,
            amplitude,
            normal_steps,
            quarter: quarter_steps(amplitude, shift_step) as usize,
        }
    }

    /// Increment `k` (0-based) as `(W, [δx, δy])`, `None` past the end; the same numbers, bit for
    /// bit, as the stored path of earlier versions.
    pub fn increment(&self, k: usize) -> Option<(f64, [f64; 2])> {
        let (n, q) = (self.normal_steps, self.quarter);
        let (w, a) = (self.force, self.amplitude);
        let dd = a / q as f64;
        if k < n {
            return Some((w * (k + 1) as f64 / n as f64, [0.0, 0.0]));
        }
        let i = k - n + 1;
        if i <= q {
            Some((w, [i as f64 * dd, 0.0]))
        } else if i <= 3 * q {
            Some((w, [a - (i - q) as f64 * dd, 0.0]))
        } else if i <= 5 * q {
            Some((w, [-a + (i - 3 * q) as f64 * dd, 0.0]))
        } else {
            None
        }
    }

    /// Increment `k` as the normal load of the solver ([`NormalLoad::Force`] or
    /// [`NormalLoad::Approach`]) and the shift.
    pub fn load(&self, k: usize) -> Option<(NormalLoad, [f64; 2])> {
        let (v, shift) = self.increment(k)?;
        let load = if self.by_approach {
            NormalLoad::Approach(v)
        } else {
            NormalLoad::Force(v)
        };
        Some((load, shift))
    }

    /// The increments in order.
    pub fn increments(&self) -> impl Iterator<Item = (f64, [f64; 2])> + '_ {
        (0..self.len()).map_while(|k| self.increment(k))
    }

    /// Increments done at the points A–D ([`POINT_LABELS`]).
    pub fn marks(&self) -> [usize; 4] {
        let (n, q) = (self.normal_steps, self.quarter);
        [
            n,
            n.saturating_add(q),
            n.saturating_add(q.saturating_mul(2)),
            n.saturating_add(q.saturating_mul(3)),
        ]
    }

    /// Index of the first row of the closed cycle (`δx = +A`, point B); the cycle runs from there
    /// to the last increment (`δx = +A` again).
    pub fn cycle_start(&self) -> usize {
        self.normal_steps + self.quarter - 1
    }

    /// Number of increments `n + 5q` (saturating; [`LoopCase::estimate`] refuses paths anywhere
    /// near that).
    pub fn len(&self) -> usize {
        self.normal_steps
            .saturating_add(self.quarter.saturating_mul(5))
    }

    /// Whether the path has no increment.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// `q = round(A / step)`, at least 1, as a float (it may exceed any integer type).
fn quarter_steps(amplitude: f64, shift_step: f64) -> f64 {
    (amplitude / shift_step).round().max(1.0)
}

/// What a fretting loop (or a map of them) will cost, estimated before anything is allocated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoopEstimate {
    /// Increments of one loop `n + 5q` (a float: it may exceed any integer type).
    pub increments: f64,
    /// Surface cells.
    pub cells: f64,
    /// Loops (points of a map; 1 for one loop).
    pub loops: f64,
    /// Loops run at once (the map's threads).
    pub concurrent: f64,
    /// Peak bytes: the contact problems running at once and the rows kept (one per increment,
    /// with the checkpoint's and the results' copies).
    pub bytes: f64,
    /// Cell-increments of work (`loops · increments · cells`, times the EIM layers' weight with
    /// inhomogeneities).
    pub work: f64,
}

/// Bytes kept per increment: the row (11 numbers) and its copies in the checkpoint and in the
/// results record.
pub const ROW_BYTES: f64 = 3.0 * 11.0 * 8.0;

/// Cell-increments per second of one core, the work estimate's scale: the 64² homogeneous loop of
/// \[LN11\] (180 increments, 7.4e5 cell-increments, no subsurface fields) took 23.2 s on one thread
/// and 21.3 s on two of the reference machine (`RAYON_NUM_THREADS=1 halfspace fretting-loop`),
/// 3.2e4 per second; rounded up, so that the estimate errs towards accepting.
pub const CELL_INCREMENTS_PER_SECOND: f64 = 4.0e4;

/// The most work accepted, in hours of this machine (all its cores at
/// [`CELL_INCREMENTS_PER_SECOND`] each): `HALFSPACE_WORK_LIMIT` (hours) when set, else 24.
pub fn work_limit_hours() -> f64 {
    std::env::var("HALFSPACE_WORK_LIMIT")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|v| !v.is_nan() && *v > 0.0)
        .unwrap_or(24.0)
}

/// Bytes in a GiB.
const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// Cores of this machine (rayon's pool: `RAYON_NUM_THREADS` or the CPUs).
fn cores() -> f64 {
    rayon::current_num_threads().max(1) as f64
}

impl LoopEstimate {
    /// Refuses an estimate beyond the machine: more memory than is available
    /// ([`halfspace_numerics::memory::available_bytes`]) or more work than [`work_limit_hours`]; the
    /// message gives the estimate and names the inputs that set it.
    pub fn check(&self, what: &str) -> Result<(), SamError> {
        self.check_memory(what)?;
        let limit = work_limit_hours();
        let hours = self.hours();
        if hours.is_nan() || hours > limit {
            return Err(SamError::InvalidInput(format!(
                "{}; more than the limit of {limit} hours (HALFSPACE_WORK_LIMIT): refused before \
                 starting — use fewer increments, fewer points or a coarser grid",
                self.describe(what),
            )));
        }
        Ok(())
    }

    /// The memory half of [`LoopEstimate::check`]: refuses `bytes` above the available memory.
    pub fn check_memory(&self, what: &str) -> Result<(), SamError> {
        if let Some(available) = halfspace_numerics::memory::available_bytes() {
            if self.bytes.is_nan() || self.bytes > available {
                return Err(SamError::InvalidInput(format!(
                    "{}; {:.3} GiB are available (HALFSPACE_MEMORY_LIMIT): refused before \
                     starting — use fewer increments (a larger shift_step, fewer normal_steps), \
                     fewer points or a coarser grid",
                    self.describe(what),
                    available / GIB
                )));
            }
        }
        Ok(())
    }

    /// The estimate in words, for the refusals.
    fn describe(&self, what: &str) -> String {
        let hours = self.hours();
        format!(
            "{what}: {} loop(s) of {:.4e} increments (normal_steps + 5 · amplitude/shift_step) \
             on {} cells: about {:.3} GiB and {hours:.3e} hours of work on {} cores",
            self.loops,
            self.increments,
            self.cells,
            self.bytes / GIB,
            cores()
        )
    }

    /// Estimated wall-clock hours on this machine (the loops spread over its cores).
    pub fn hours(&self) -> f64 {
        self.work / (CELL_INCREMENTS_PER_SECOND * cores()) / 3600.0
    }
}
