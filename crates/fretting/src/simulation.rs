use halfspace_mdr::{CellStressTransform, Material, MdrError, ProfileTransform};
use halfspace_numerics::krylov::{Gmres, KrylovParams};
use halfspace_numerics::linop::Identity;
use halfspace_numerics::{NumericsError, Precision, SquaredGrid};

use crate::limit::{
    annulus_response, initial_profile, limit_contact_radius, limit_wear_volume, limiting_profile,
    stick_radius,
};
use crate::linearization::{
    samples_to_gap, BandPreconditioner, MaskedBand, RosenbrockMatrix, CLOSED_REACH,
};
use crate::{FrettingError, FrettingParams, TimeStepping};

/// `c_N` of the normalized problem: with `q̃ = c̃_N (1 − g̃)`, Eq. 29 (Eq. 17 at `k = 0`) gives
/// `p̃ = p a₀²/F₀`, `p̃ = (c̃_N/π) ∫ g̃'/(x̃² − r̃²)^{(1−k)/2}` with `c̃_N = (1+k)(3+k)/4` (graded Hertz,
/// docs/theory-mdr.md#graded-closed-forms: `F₀ = 4 c_N a₀^{3+k} / ((1+k)²(3+k)R)`, `a₀² = (1+k)Rd`); `3/4` homogeneous (docs/theory-mdr.md#fretting-wear).
pub fn normalized_modulus(k: f64) -> f64 {
    0.25 * (1.0 + k) * (3.0 + k)
}

/// The state at one recorded `τ`.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Steps taken before it.
    pub step: u64,
    /// `τ` of the snapshot.
    pub tau: f64,
    /// Profile `f̃` on the grid nodes.
    pub profile: Vec<f64>,
    /// Pressure `p̃` on the grid nodes (of this profile).
    pub pressure: Vec<f64>,
    /// Slip per cycle `Δũ` on the grid nodes.
    pub slip: Vec<f64>,
    /// Contact radius `a/a₀`: the extent of the touching region ([`ContactRadii::touching`]).
    pub contact_radius: f64,
    /// Loaded radius `a_p/a₀` ([`ContactRadii::loaded`]).
    pub loaded_radius: f64,
}

/// The two radii of a worn contact (docs/fretting-wear.md, "Contact radius and loaded radius").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactRadii {
    /// The extent of the touching region, the nodes with `g̃ < 1 + ε`, `ε = GAP_TOLERANCE · h`
    /// (the gap `g̃₀ = ξ` of the initial equivalent profile opens by `h` over one cell): the edge
    /// where the linear interpolant of `g̃` reaches 1 (as in the wear step) while the touching
    /// nodes end at the first node outside it; in the grazing end phase, where nodes further out
    /// are within `ε` of closing, where the interpolant beyond the outermost of them reaches
    /// `1 + ε`. At the limit this is `r*`.
    pub touching: f64,
    /// The outermost node with `p̃ > LOAD_THRESHOLD · max p̃`. In the grazing limit the annulus
    /// carries no pressure and this falls to the stick radius `c`.
    pub loaded: f64,
}

/// `ε/h` of [`ContactRadii::touching`].
pub const GAP_TOLERANCE: f64 = 1.0;
/// The pressure threshold of [`ContactRadii::loaded`], relative to the largest pressure.
pub const LOAD_THRESHOLD: f64 = 1e-3;

/// Everything a run needs to continue: the step, `τ`, the profile, the step-size controller, the
/// histories and the snapshots. A run resumed from a state ends bit for bit where the
/// uninterrupted run ends.
#[derive(Debug, Clone, PartialEq)]
pub struct FrettingState {
    /// Steps taken (accepted).
    pub step: u64,
    /// `τ` reached.
    pub tau: f64,
    /// Profile `f̃` on the grid nodes.
    pub profile: Vec<f64>,
    /// `τ` after each step.
    pub tau_history: Vec<f64>,
    /// `a/a₀` (touching) after each step.
    pub contact_radius_history: Vec<f64>,
    /// Loaded radius after each step.
    pub loaded_radius_history: Vec<f64>,
    /// Adaptive stepping: the next step to try (0 before the first).
    pub next_step: f64,
    /// Adaptive stepping: the error ratio of the last accepted step (the PI controller's memory).
    pub previous_error: f64,
    /// Adaptive stepping: steps rejected so far.
    pub rejected_steps: u64,
    /// Snapshots taken so far.
    pub snapshots: Vec<Snapshot>,
}

/// One attempt of an error-controlled step, reported to the observer of
/// [`FrettingSimulation::set_attempt_observer`] (diagnostics: where the steps go; not state).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepAttempt {
    /// `τ` at the step's start.
    pub tau: f64,
    /// The step tried.
    pub dtau: f64,
    /// The error estimate over the tolerance (`∞` when a stage solve did not converge).
    pub error_ratio: f64,
    /// Whether the attempt was accepted (`error_ratio ≤ 1`).
    pub accepted: bool,
    /// The node of the largest error estimate.
    pub worst_node: usize,
    /// The first node outside the contact at the step's start, of the second stage's trial
    /// profile `f + Δτ k₁`, and of the attempt's result.
    pub edge_start: usize,
    /// See `edge_start`.
    pub edge_trial: usize,
    /// See `edge_start` (the contact of the result is computed for the observer only when the
    /// attempt is rejected; an accepted one needs it anyway); `usize::MAX` when a rejected
    /// attempt's contact could not be evaluated (e.g. it reached beyond the grid).
    pub edge_end: usize,
    /// The sub-cell edge (where the linear interpolant of `g` reaches `d`, `a/a₀`) at the step's
    /// start and of the attempt's result (NaN when the result's contact could not be evaluated or
    /// the attempt's error is not finite).
    pub edge_radius_start: f64,
    /// See `edge_radius_start`.
    pub edge_radius_end: f64,
    /// GMRES iterations of the two stages.
    pub krylov_iterations: (usize, usize),
    /// The nodes the second stage's trial brought into contact beyond the start's contact
    /// (their wear is the end-of-step correction; docs/fretting-wear.md, "The contact set within
    /// a step").
    pub entered_nodes: usize,
    /// The trial's outermost node with `g < d`.
    pub trial_outermost: usize,
    /// `min |g − d|/d` at the trial over the nodes beyond the start's contact: how far the
    /// trial's discrete contact decisions are from flipping (rounding of the transforms is
    /// ~1e-13).
    pub trial_gap_margin: f64,
    /// Holes the result opens that the embedded first-order solution `f + Δτ k₁` does not have:
    /// annulus nodes inside the result's last contact node with `g ≥ d` where the trial has
    /// `g < d` (`FrettingSimulation::opened_hole_error`; 0 when not estimated).
    pub opened_holes: usize,
    /// The three parts of the error estimate (in `f̃`'s units, before the division by the
    /// tolerance): the ROS2 pair's
    /// `max_i Δτ |k₁ + k₂|_i / 2`, the outside wear's (`FrettingSimulation::outside_wear_error`;
    /// of the unprojected result `f₂` when the attempt is projected)
    /// and the opened holes' (`FrettingSimulation::opened_hole_error`, also when it is not part
    /// of the estimate; when the attempt fell back to its first-order solution, the holes that
    /// solution opens and the second-order result keeps closed: the term that entered the
    /// estimate, [`FrettingSimulation::set_first_order_fallback`]); the error is the largest of those the estimate includes.
    pub error_terms: [f64; 3],
    /// Whether the attempt's result is its first-order solution (only with the first-order
    /// fallback and the frozen contact stages: without the frozen contact no attempt falls back).
    pub first_order: bool,
    /// `λ` of the projection onto the closed set ([`FrettingSimulation::set_hole_projection`]):
    /// the result is `f₁ + λ(f₂ − f₁)`; 1 when not projected.
    pub projection: f64,
    /// The node held on the contact surface in the attempt's stages
    /// ([`FrettingSimulation::set_sliding_edge`]), if any.
    pub sliding_node: Option<usize>,
}

/// The observer of [`FrettingSimulation::set_attempt_observer`].
pub type AttemptObserver = Box<dyn FnMut(&StepAttempt) + Send>;

/// What the current profile's contact is: the first node outside, the edge `θ` in the last cell
/// and the radii.
#[derive(Debug, Clone, Copy)]
struct Contact {
    edge: usize,
    theta: f64,
    /// `a/a₀` of the computational edge (where `g` reaches `d` between nodes).
    edge_radius: f64,
    radii: ContactRadii,
}

/// What [`FrettingSimulation::contact_state_with`] leaves for the step's start: `g`, `σ`, `p`,
/// the slip, the rate and the contact.
struct StartRate {
    g: Vec<f64>,
    sigma: Vec<f64>,
    p: Vec<f64>,
    slip: Vec<f64>,
    rate: Vec<f64>,
    contact: Option<Contact>,
    /// The nodes on which `g` is the transform's (`FrettingSimulation::gap_valid`).
    gap_valid: usize,
}

/// The name of the default adaptive scheme, which a checkpoint records (`fretting-wear`'s
/// `adaptive_scheme`): a resume refuses a checkpoint of another scheme, whose steps it would not
/// repeat bit for bit. `ros2-hole-projection-eta1e-3-band5x12-rate-plans-masked-prefix-fma`: ROS2 with the frozen contact stages, the
/// outside-wear and opened-hole estimates, and the projection onto the closed set
/// ([`FrettingSimulation::set_hole_projection`]) with the margin `η = 1e-3` (`HOLE_MARGIN`);
/// checkpoints without the attribute were made by the scheme before the projection (the same
/// path was first recorded as `ros2-hole-projection`, never on main), and the stages' band
/// preconditioner of half width 5 probed with 12 colours (`PRECONDITIONER_WIDTH`,
/// `PROBE_COLOURS`: they change the stage solves' rounding, so the steps; `-eta1e-3` alone was the
/// same scheme with width 3 and 7 colours), and the rate's stress transform on the contact nodes
/// with the shorter plans (`-band5x12` alone was the same scheme with the whole grid's plan
/// there: other rounding, so other steps), and the closed nodes' part taken out of the probed band
/// ([`FrettingSimulation::set_masked_band`]; `-rate-plans` alone was the same scheme without it),
/// and the rate's profile transform on the prefix `0..L` ([`FrettingSimulation::set_prefix_rate`];
/// `-masked` alone was the same scheme on the whole grid), and the preconditioner's factors and
/// substitutions on fused multiply-adds (`BandPreconditioner::factor` in linearization.rs;
/// `-prefix` alone was the same scheme with separate multiplies and subtractions), and the
/// convolutions as packed complex FFTs with the preconditioned Krylov basis kept and the edge's
/// θ-difference without a convolution (`-fma` alone was the same scheme with real FFTs, the
/// preconditioner applied to the update, and the difference of two stress transforms), and
/// GMRES's inner products in eight running sums (`-packed-fgmres` alone was the same scheme with
/// one sum; docs/performance.md, "The GMRES inner products in eight sums"), and the shorter plans
/// at the lengths [`halfspace_numerics::conv1d::rung_lengths`] (`-dot8` alone was the same scheme
/// with capacities falling by 4/5; docs/performance.md, "The rungs of the shorter plans").
/// The name must change
/// whenever the path does: `HOLE_MARGIN`, the default
/// switches (`hole_estimate`, `freeze_contact`, `first_order_fallback`, `hole_projection`,
/// `recycled_second_stage`, `masked_band_on`, `prefix_nodes` in `FrettingSimulation::with_state`) or how an attempt's error is
/// formed. A library run with a non-default switch records nothing of it: it must be set again
/// to resume on the same path.
pub const ADAPTIVE_SCHEME: &str = if SLIDING_EDGE_DEFAULT {
    SLIDING_EDGE_SCHEME
} else {
    MAIN_SCHEME
};

/// The default scheme's name without the sliding mode ([`ADAPTIVE_SCHEME`]).
const MAIN_SCHEME: &str =
    "ros2-hole-projection-eta1e-3-band5x12-rate-plans-masked-prefix-fma-packed-fgmres-dot8-pow2-rungs";

/// The name of the adaptive scheme with the sliding mode of the contact edge's last node
/// ([`FrettingSimulation::set_sliding_edge`]; not the default): what [`ADAPTIVE_SCHEME`] records
/// when a build makes it the default, so that a checkpoint of either scheme is refused by the
/// other.
pub const SLIDING_EDGE_SCHEME: &str =
    "ros2-hole-projection-eta1e-3-band5x12-rate-plans-masked-prefix-fma-packed-fgmres-dot8-pow2-rungs-sliding-edge";

/// The stages whose GMRES tolerance (relative) is at least this take the products `W x` by
/// `f32` transforms ([`FrettingSimulation::set_single_precision_products`]): their relative
/// error, measured ≤ 1.2e-6 at N = 8001 (docs/performance.md, "The N = 8001 wear run:
/// single-precision stage products (issue 20)"), stays two orders below the tolerance (an inexact
/// Krylov method; Simoncini & Szyld 2003, SIAM J. Sci. Comput. 25; Bouras & Frayssé 2005, SIAM
/// J. Matrix Anal. Appl. 26). Fixed steps solve to `1e-8`: they stay in `f64`.
pub const SINGLE_PRECISION_FROM: f64 = 1e-4;

/// The name of the explicit Euler path's rounding, which its checkpoints record as
/// `euler_scheme`: `euler-packed` is the rate by the packed complex FFTs (docs/performance.md,
/// "The convolutions as packed complex transforms"); an Euler checkpoint without it (real FFTs)
/// is refused on resume, whose steps would not be repeated bit for bit.
pub const EULER_SCHEME: &str = "euler-packed";

/// The name of the fixed-step ROS2 path ([`crate::TimeStepping::Fixed`]), which checkpoints
/// record as `fixed_scheme` so that a fixed-step run is resumed only by a build whose stages round
/// the same way: `ros2-fixed-rate-plans-masked-prefix-fma` is ROS2 at the step `dtau` with the rate's stress
/// transform on the contact nodes with the shorter plans (docs/performance.md, "The N = 8001 wear
/// run: the masked band and the second core") and the closed nodes' part taken out of the
/// preconditioner's band ([`FrettingSimulation::set_masked_band`]; `ros2-fixed-rate-plans` was
/// the path without it) and the rate's profile transform on the prefix
/// ([`FrettingSimulation::set_prefix_rate`]; `ros2-fixed-rate-plans-masked` was the path without
/// it) and the preconditioner on fused multiply-adds (`ros2-fixed-rate-plans-masked-prefix` was
/// the path without them) and the packed FFTs, the kept preconditioned basis and the edge's
/// θ-difference, the eight-sum inner products and the shorter plans' lengths of
/// [`ADAPTIVE_SCHEME`] (`ros2-fixed-rate-plans-masked-prefix-fma` was the path without the first
/// three, `-packed-fgmres` without the last two, `-dot8` without the last); its stages solve to `1e-8`, below [`SINGLE_PRECISION_FROM`]: no `f32` products. A
/// checkpoint made before the name was recorded
/// (the whole grid's plan there: other rounding) is refused. The name must change whenever the
/// fixed-step path's rounding does. Explicit Euler, the reference path, records
/// [`EULER_SCHEME`].
pub const FIXED_STEP_SCHEME: &str =
    "ros2-fixed-rate-plans-masked-prefix-fma-packed-fgmres-dot8-pow2-rungs";

/// `γ = 1 + 1/√2` of ROS2.
const ROS2_GAMMA: f64 = 1.0 + std::f64::consts::FRAC_1_SQRT_2;
/// The first adaptive step.
const FIRST_STEP: f64 = 1e-4;

/// The per-cycle loop of docs/theory-mdr.md#fretting-wear with the edge between nodes, planned once: no allocation per
/// step. Integrates `∂f̃/∂τ = p̃ Δũ` by [`TimeStepping`].
pub struct FrettingSimulation {
    params: FrettingParams,
    grid: SquaredGrid,
    profile_tf: ProfileTransform,
    stress_tf: CellStressTransform,
    limit: Vec<f64>,
    /// `J(r̃_i)` ([`annulus_response`]) on the slip-annulus nodes, 0 elsewhere.
    annulus: Vec<f64>,
    stick: f64,
    r_star: f64,
    slope: Vec<f64>,
    g: Vec<f64>,
    q: Vec<f64>,
    sigma: Vec<f64>,
    p: Vec<f64>,
    slip: Vec<f64>,
    /// The initial profile `f̃₀` on the nodes (the worn extent of [`FrettingSimulation::rate_prefix`]).
    initial: Vec<f64>,
    /// The nodes `0..L` of the prefix rate evaluations ([`rate_prefix_nodes`],
    /// [`FrettingSimulation::set_prefix_rate`]; `N`: every evaluation on the whole grid, the
    /// default).
    prefix_nodes: usize,
    /// The nodes `0..V` on which the last rate evaluation's `g` is the transform's (`V = N` for a
    /// whole-grid evaluation, `L − 2` for a prefix one, beyond which `g` holds the lower bound
    /// `g_{V−1}`), and the whole grid's `g` for [`FrettingSimulation::equivalent_profile`].
    gap_valid: usize,
    full_gap: Vec<f64>,
    /// Rate evaluations so far and those on a prefix (diagnostics, not state).
    rate_evaluations: (u64, u64),
    state: FrettingState,
    snapshot_times: Vec<f64>,
    /// The contact of the current profile when g, p and the slip are up to date with it.
    current: Option<Contact>,
    /// ROS2 work: `W = I − γΔτ J`, GMRES, the stages, the rate at the step's start.
    matrix: RosenbrockMatrix,
    gmres: Gmres,
    /// The band preconditioner of `W` (rescaled at each linearization, probed again when the contact
    /// nodes change) and whether GMRES uses it (the tests compare with it off).
    precond: BandPreconditioner,
    precondition: bool,
    rate: Vec<f64>,
    k1: Vec<f64>,
    k2: Vec<f64>,
    rhs: Vec<f64>,
    trial: Vec<f64>,
    /// `g` of the second stage's trial `f + Δτ k₁` (the embedded first-order solution), for
    /// `FrettingSimulation::opened_hole_error`.
    trial_gap: Vec<f64>,
    /// The first node of the slip annulus (`r̃ > c̃`).
    first_annulus_node: usize,
    /// Whether the adaptive error estimate includes `FrettingSimulation::opened_hole_error`
    /// (default on; off: the estimate of before, for comparisons).
    hole_estimate: bool,
    /// Whether an attempt whose result opens holes that its first-order solution keeps closed
    /// takes the first-order solution ([`FrettingSimulation::set_first_order_fallback`]).
    first_order_fallback: bool,
    /// Whether an attempt whose result opens holes that its first-order solution keeps closed
    /// is projected back onto the closed set along the pair's segment
    /// ([`FrettingSimulation::set_hole_projection`]).
    hole_projection: bool,
    start: Vec<f64>,
    /// `g`, `σ`, `p`, the slip and the rate of the step's start and its contact, put back after a
    /// rejected attempt instead of evaluated again (the same bits).
    start_rate: StartRate,
    /// `a²` of the step's start (the edge where g reaches d).
    start_edge_squared: f64,
    /// The rate of the nodes that entered the contact in the second stage's trial profile, and
    /// the range of them.
    entered: Vec<f64>,
    entered_nodes: std::ops::Range<usize>,
    /// Whether the last attempt was rejected because its result's contact reached the end of
    /// the grid (reported as [`FrettingError::ContactOutsideGrid`] if the step then fails).
    outside_grid: bool,
    /// `a_t²` of the second stage's trial contact (the edge the entered nodes' wear assumes).
    trial_edge_squared: f64,
    /// GMRES iterations so far (not part of the state: a diagnostic).
    krylov_iterations: u64,
    /// Band probes of the preconditioner so far (a diagnostic, not state).
    probes: u64,
    /// The closed nodes' part of the preconditioner's band (built at the first linearization
    /// with closed nodes).
    masked_band: Option<MaskedBand>,
    /// Whether the preconditioner's band takes out the closed nodes' part
    /// ([`FrettingSimulation::set_masked_band`]).
    masked_band_on: bool,
    /// `f32` products in the stages solved to at least [`SINGLE_PRECISION_FROM`]
    /// ([`FrettingSimulation::set_single_precision_products`]).
    single_precision_products: bool,
    /// `π_j = σ_j/(a² − ξ_j)^γ` on the edge cells ([`FrettingSimulation::edge_cell_rates`]).
    edge_shape: Vec<f64>,
    /// `p̄_j` of the edge cells.
    edge_mean: Vec<f64>,
    /// Nodes before the last contact node whose rate is the cell mean ([`EDGE_CELLS`]; 0: the
    /// nodal rate, the default).
    edge_cells: usize,
    /// Whether the second ROS2 stage keeps the contact nodes of the step's start (default; off:
    /// those of the trial profile, as before, for the tests' comparison).
    freeze_contact: bool,
    /// Whether the second ROS2 stage's GMRES continues the first stage's Krylov space
    /// ([`FrettingSimulation::set_recycled_second_stage`]; default off) and the dimension the
    /// first stage's solve ran on (the space is reused only on the same one).
    recycled_second_stage: bool,
    stage_one_dim: Option<usize>,
    /// Whether the adaptive steps hold the last contact node on the contact surface while it
    /// slides ([`FrettingSimulation::set_sliding_edge`]), and this step's sliding node.
    sliding_edge: bool,
    sliding: Option<SlidingNode>,
    /// The step's sliding candidate (a function of the step's start), held by an attempt when
    /// its gap reaches the surface early in the attempt.
    slide_candidate: Option<SlidingNode>,
    /// The band `|i − j| ≤ w` of `G = P D` (`f ↦ g`), row-major as the preconditioner's band,
    /// filled column by column when a sliding node needs it (`gap_column_done`): `G` is a
    /// function of the grid alone, so a column once computed is kept.
    gap_band: Vec<f64>,
    gap_column_done: Vec<bool>,
    /// Work of the sliding node's test: the slope and `g` of a rate or a unit vector.
    slide_slope: Vec<f64>,
    /// `e_j` for a column of `G` ([`FrettingSimulation::gap_column`]).
    slide_unit: Vec<f64>,
    slide_gap: Vec<f64>,
    /// The observer of the adaptive attempts and the attempt being made.
    observer: Option<AttemptObserver>,
    attempt: StepAttempt,
}

/// The node held on the contact surface in a step's stages
/// ([`FrettingSimulation::set_sliding_edge`]; docs/fretting-wear.md, "The sliding mode in the
/// stages"): the stages' row `node` is the constraint `c(f) = g_node(f) − target = 0`, scaled by
/// `1/G_ss` (`self_gap`).
#[derive(Debug, Clone, Copy)]
struct SlidingNode {
    node: usize,
    target: f64,
    self_gap: f64,
    /// The time the node's gap takes to reach `target` at the start's `ġ` (0 when it is there).
    approach: f64,
}

impl FrettingSimulation {
    /// A new run from the initial paraboloid `f̃₀ = r̃²/2`.
    pub fn new(params: FrettingParams) -> Result<Self, FrettingError> {
        params.validate()?;
        let grid = SquaredGrid::new(params.nodes, params.length).map_err(MdrError::from)?;
        let profile = grid
            .coordinates()
            .iter()
            .map(|&r| initial_profile(r, params.k))
            .collect();
        let state = FrettingState {
            step: 0,
            tau: 0.0,
            profile,
            tau_history: Vec::new(),
            contact_radius_history: Vec::new(),
            loaded_radius_history: Vec::new(),
            next_step: 0.0,
            previous_error: 0.0,
            rejected_steps: 0,
            snapshots: Vec::new(),
        };
        Self::with_state(params, grid, state)
    }

    /// Continues a run from a saved state (`--resume`), checked for content first
    /// (`checkpoint::check_state`: shapes, finite values, ranges, monotone histories, the step
    /// controller's memory).
    pub fn resume(params: FrettingParams, state: FrettingState) -> Result<Self, FrettingError> {
        params.validate()?;
        let grid = SquaredGrid::new(params.nodes, params.length).map_err(MdrError::from)?;
        crate::checkpoint::check_state(
            &state,
            &params,
            &grid,
            limit_contact_radius(params.chi, params.k),
        )?;
        Self::with_state(params, grid, state)
    }

    fn with_state(
        params: FrettingParams,
        grid: SquaredGrid,
        state: FrettingState,
    ) -> Result<Self, FrettingError> {
        let n = params.nodes;
        // The transforms need only k (the stress transform takes q̃ with c̃_N in it).
        let material = if params.k == 0.0 {
            Material::from_e_star(normalized_modulus(0.0))?
        } else {
            Material::power_law(1.0, 1.0, 0.0, params.k)?
        };
        let limit = grid
            .coordinates()
            .iter()
            .map(|&r| limiting_profile(r, params.chi, params.k))
            .collect();
        let stick = stick_radius(params.chi);
        let annulus = grid
            .coordinates()
            .iter()
            .map(|&r| {
                if r > stick {
                    annulus_response(r, stick, params.k)
                } else {
                    0.0
                }
            })
            .collect();
        let matrix = RosenbrockMatrix::new(
            grid,
            &material,
            params.backend,
            normalized_modulus(params.k),
            params.chi,
            params.gap_transform,
        )?;
        // Explicit Euler's rate keeps the full-length plans: the explicit reference runs of the
        // tests keep their bits (their grazing-phase a/a₀ at τ = 3 moves by 3e-4 with the
        // rounding of shorter plans, docs/fretting-wear.md, "Cost per step"). The implicit runs'
        // stress transform of the rate, on the `m` contact nodes, takes the shorter plans
        // (`2m − 1` padded instead of `2N − 1`), and their profile transform the prefix.
        let explicit = matches!(params.stepping, TimeStepping::ExplicitEuler { .. });
        let mut profile_tf = ProfileTransform::new(n, &material, params.backend)?;
        let mut stress_tf = CellStressTransform::new(n, &material, params.backend)?;
        let r_star = limit_contact_radius(params.chi, params.k);
        // The implicit runs' profile transform of the rate on the prefix `0..L`
        // (`rate_prefix_nodes`) by default ([`FrettingSimulation::set_prefix_rate`]).
        let prefix_nodes = if explicit {
            n
        } else {
            stress_tf.plan_shorter_lengths();
            profile_tf.plan_shorter_lengths();
            rate_prefix_nodes(&grid, r_star)
        };
        let initial = grid
            .coordinates()
            .iter()
            .map(|&r| initial_profile(r, params.k))
            .collect();
        Ok(Self {
            profile_tf,
            stress_tf,
            initial,
            prefix_nodes,
            gap_valid: n,
            full_gap: vec![0.0; n],
            rate_evaluations: (0, 0),
            limit,
            annulus,
            stick,
            r_star,
            slope: vec![0.0; n],
            g: vec![0.0; n],
            q: vec![0.0; n],
            sigma: vec![0.0; n],
            p: vec![0.0; n],
            slip: vec![0.0; n],
            snapshot_times: params.snapshot_times(),
            matrix,
            gmres: {
                // The stage error is controlled by the step's error estimate: no confirming
                // product after the Arnoldi estimate falls below the stage tolerance.
                let mut gmres = Gmres::new(n, KRYLOV.restart);
                gmres.confirm_residual(false);
                gmres.keep_preconditioned_basis(true);
                gmres.sum_in_lanes(true);
                gmres
            },
            precond: BandPreconditioner::new(n, PRECONDITIONER_WIDTH),
            precondition: true,
            rate: vec![0.0; n],
            k1: vec![0.0; n],
            k2: vec![0.0; n],
            rhs: vec![0.0; n],
            trial: vec![0.0; n],
            trial_gap: vec![0.0; n],
            first_annulus_node: grid
                .coordinates()
                .iter()
                .position(|&r| r > stick)
                .unwrap_or(n),
            // The default adaptive scheme's switches (with `freeze_contact`, `first_order_fallback`
            // and `hole_projection` below): changing a default changes the steps, so rename
            // ADAPTIVE_SCHEME with it (old checkpoints are then refused instead of resumed on
            // another path).
            hole_estimate: true,
            start: vec![0.0; n],
            start_rate: StartRate {
                g: vec![0.0; n],
                sigma: vec![0.0; n],
                p: vec![0.0; n],
                slip: vec![0.0; n],
                rate: vec![0.0; n],
                contact: None,
                gap_valid: n,
            },
            start_edge_squared: 0.0,
            entered: vec![0.0; n],
            entered_nodes: 0..0,
            outside_grid: false,
            trial_edge_squared: 0.0,
            krylov_iterations: 0,
            probes: 0,
            masked_band: None,
            // Part of ADAPTIVE_SCHEME (see `hole_estimate`): rename it when a default changes.
            masked_band_on: true,
            // Off: measured, not the default (`set_single_precision_products`); part of
            // ADAPTIVE_SCHEME if turned on.
            single_precision_products: false,
            edge_shape: vec![0.0; n],
            edge_mean: vec![0.0; n],
            edge_cells: if params.edge_cells { EDGE_CELLS } else { 0 },
            // Part of ADAPTIVE_SCHEME (see `hole_estimate`): rename it when a default changes.
            freeze_contact: true,
            first_order_fallback: false,
            hole_projection: true,
            // Off: measured, not a net gain (docs/performance.md, "The second stage started
            // from the first stage's Krylov space"); part of ADAPTIVE_SCHEME if turned on.
            recycled_second_stage: false,
            stage_one_dim: None,
            sliding_edge: SLIDING_EDGE_DEFAULT,
            sliding: None,
            slide_candidate: None,
            gap_band: vec![0.0; n * (2 * PRECONDITIONER_WIDTH + 1)],
            gap_column_done: vec![false; n],
            slide_slope: vec![0.0; n],
            slide_unit: vec![0.0; n],
            slide_gap: vec![0.0; n],
            observer: None,
            attempt: StepAttempt {
                tau: 0.0,
                dtau: 0.0,
                error_ratio: 0.0,
                accepted: false,
                worst_node: 0,
                edge_start: 0,
                edge_trial: 0,
                edge_end: 0,
                edge_radius_start: 0.0,
                edge_radius_end: 0.0,
                krylov_iterations: (0, 0),
                entered_nodes: 0,
                trial_outermost: 0,
                trial_gap_margin: 0.0,
                opened_holes: 0,
                error_terms: [0.0; 3],
                first_order: false,
                projection: 1.0,
                sliding_node: None,
            },
            grid,
            params,
            state,
            current: None,
        })
    }

    /// Off by default ([`FrettingParams::edge_cells`], which sets it at construction and is
    /// recorded in checkpoints): the wear rate of the cells at the contact edge as the cell mean
    /// of `p Δu` with the edge pressure `π (a² − ξ)^{(1+k)/2}` integrated over the cell
    /// (docs/fretting-wear.md, "Edge cells"), instead of the nodal `p Δu`. Takes fewer adaptive
    /// steps; not the default because of the open points listed there. Set before the first
    /// step; this setter changes the parameters' value too.
    pub fn set_edge_cell_rates(&mut self, on: bool) {
        self.params.edge_cells = on;
        self.edge_cells = if on { EDGE_CELLS } else { 0 };
        self.current = None;
    }

    /// On by default (since stop 40): implicit runs evaluate `g` of the rate on the prefix `0..L`
    /// of the grid (`rate_prefix_nodes`: the node of `r*` and `N/16` more) with a shorter plan
    /// when the worn part of the profile ends inside it and `g` at its end is above
    /// `d + ε + 0.02` (else on the whole grid; `FrettingSimulation::equivalent_on_prefix`). At
    /// N = 8001 `g`'s FFT is 10 240 points long instead of 16 200. Off: every evaluation on the
    /// whole grid (the path of the schemes before `-prefix`). It changes the rounding of the
    /// rate, so the step sequence: the grazing-phase stepping tests assert over perturbed starts
    /// (docs/performance.md, "The N = 8001 wear run: the prefix rate by default (issue 20)").
    /// Not part of the checkpointed state: a run with it off must set it again to resume on the
    /// same path. No effect on explicit Euler. Set before the first step.
    pub fn set_prefix_rate(&mut self, on: bool) {
        let explicit = matches!(self.params.stepping, TimeStepping::ExplicitEuler { .. });
        self.prefix_nodes = if on && !explicit {
            // At the whole grid's length the ladder's last plan is the full one (the same bits).
            self.profile_tf.plan_shorter_lengths();
            rate_prefix_nodes(&self.grid, self.r_star)
        } else {
            self.grid.len()
        };
        self.current = None;
    }

    /// Whether the second ROS2 stage keeps the contact nodes of the step's start (on by default,
    /// docs/fretting-wear.md, "Time integration"); off: the contact of its trial profile, the
    /// scheme of before (for comparisons). Set before the first step.
    pub fn set_frozen_contact_stages(&mut self, on: bool) {
        self.freeze_contact = on;
        self.current = None;
    }

    /// Whether the error estimate of the adaptive steps includes the holes a step opens that its
    /// embedded first-order solution does not have (on by default, docs/fretting-wear.md, "What
    /// sets the step"; off: the estimate of before, for comparisons). Set before the first step;
    /// not part of the checkpointed state: a
    /// resumed run repeats the uninterrupted one bit for bit when it is set the same way again.
    pub fn set_hole_estimate(&mut self, on: bool) {
        self.hole_estimate = on;
    }

    /// Experimental, off by default: whether an adaptive attempt whose result opens holes that
    /// its embedded first-order solution `f + Δτ k₁` keeps closed, by more than the tolerance
    /// (holes that would reject it), takes that first-order solution as its result (the pair's
    /// estimate is its error), with the holes that solution opens and the result keeps closed,
    /// `g_i − d`, in the estimate instead (only with the hole estimate on; the projection onto
    /// the closed set, [`FrettingSimulation::set_hole_projection`], with `λ = 0`). Off: such
    /// attempts are projected (the default) or, with the projection off, rejected. Fewer steps
    /// than rejecting (default run 890 → 641; graded k = −0.5,
    /// χ = 0.9, N = 2001 to τ = 30: 57 204 → 22 156, no holes), but the default run's touching radius at
    /// τ = 3, in the near-grazing phase, is 1.3e-3 off the converged reference (2e-4 with it off)
    /// (docs/fretting-wear.md, "What sets the step"). Set before the first step; not part of the
    /// checkpointed state (as [`FrettingSimulation::set_hole_estimate`]): a resumed run repeats
    /// the uninterrupted one bit for bit only when it is set the same way again. Acts only with
    /// the frozen contact stages ([`FrettingSimulation::set_frozen_contact_stages`], the default).
    pub fn set_first_order_fallback(&mut self, on: bool) {
        self.first_order_fallback = on;
    }

    /// Whether an adaptive attempt whose result `f₂ = f + Δτ(3k₁ + k₂)/2` opens holes that its
    /// first-order solution `f₁ = f + Δτ k₁` keeps closed, by more than the tolerance (holes
    /// that would reject it), is projected onto the closed set along the pair's segment (on by
    /// default; off: such holes reject the attempt, the scheme before). The result is
    /// `f₁ + λ(f₂ − f₁)` with the largest `λ ∈ [0, 1]` that keeps every such node closed (`g` is
    /// linear in `f`, so `g_λ = g₁ + λ(g₂ − g₁)`: `λ = (1 − η) min_i (d − g₁ᵢ)/(g₂ᵢ − g₁ᵢ)`,
    /// `η` = `HOLE_MARGIN`). The exact flow keeps `g ≤ d` on the slip annulus (the rate `p Δu`
    /// vanishes as the gap closes), so the projection restores a property of the solution; its
    /// size `(1 − λ) Δτ |k₁ + k₂|/2` is bounded by the pair's estimate, which stays in the error,
    /// and the holes `g_λ` opens where `f₂` keeps the node closed join it as `g_i − d`. The
    /// outside-wear term (`FrettingSimulation::outside_wear_error`) stays the one of `f₂`, the
    /// unprojected result (its edge `a_e` and rates): it describes a result that is not kept (the
    /// kept one's edge lies near `f₁`'s when λ is small). Evaluating it again on the projected
    /// result was measured and not landed (docs/fretting-wear.md, "What sets the step"). Only with
    /// the hole estimate and the frozen contact stages on; the first-order fallback
    /// ([`FrettingSimulation::set_first_order_fallback`]) takes precedence when it is on.
    /// Measured (docs/fretting-wear.md, "What sets the step"): graded k = −0.5, χ = 0.9,
    /// N = 2001 to τ = 30 57 204 → 23 276 steps, 0 holes; the default run 890 → 670 with a/a₀
    /// within 3.5e-5 of the converged reference at τ = 0.1, 1, 3. Set before the first step; not
    /// part of the checkpointed state (the CLI records the scheme, [`ADAPTIVE_SCHEME`]).
    pub fn set_hole_projection(&mut self, on: bool) {
        self.hole_projection = on;
    }

    /// Experimental, off by default: the second ROS2 stage `W k₂ = b₂` solved in the first
    /// stage's Krylov space. Both stages share `W` and the band preconditioner `M`, so with the
    /// first stage's Arnoldi relation `W M⁻¹ V_k = V_{k+1} H̄_k` and its result `k₁` kept (whose
    /// image `W k₁ = b₁ − r₁` is known in the kept basis without a product), GMRES for the second
    /// stage starts from 0 and minimizes `‖b₂ − W k‖` over `k ∈ M⁻¹ span{V_k} + span{k₁} +
    /// M⁻¹ K_j`, the new Krylov space (`Gmres::solve_continuing_previous_space`; an augmented
    /// Krylov method, GCRO, de Sturler 1996), with the same stopping rule on `‖b₂ − W k₂‖`.
    /// Measured on the same systems (a run solving every second stage both ways): 5.38 → 3.12
    /// products a solve (graded k = −0.5, χ = 0.9, N = 2001 to τ = 1), 7.46 → 5.49 (N = 8001,
    /// χ = 0.5, to τ = 3); but whole runs take other step sequences with more rejections at
    /// χ = 0.5 and are not faster but for the graded run (docs/performance.md, "The second
    /// stage started from the first stage's Krylov space"). Set before the first step; not part
    /// of the checkpointed state (with it on, the checkpoint's `adaptive_scheme` does not say so).
    pub fn set_recycled_second_stage(&mut self, on: bool) {
        self.recycled_second_stage = on;
        // The first stage's result joins the recycled space of the second.
        self.gmres.keep_solution(on);
    }

    /// The closed nodes (`g ≥ d` inside the contact) in the stages' band preconditioner (default
    /// on): at a linearization with closed nodes its band is the probed band of `K` (every
    /// contact node open, `RosenbrockMatrix::probe_band`) less the band of the closed nodes'
    /// part `S_θ[−c̃_N 1[g ≥ d] ⊙ P[D ·]]` (`MaskedBand`, closed forms of the two transforms'
    /// matrices, each closed node's column summed on the 64 rows above it), so that it is the band
    /// of the stages' masked operator up to the probe's folding, the edge and that kernel's tail.
    /// When the edge node `m − 1` itself is closed, its column is subtracted with the edge's
    /// partial cell (`θ`) while the probe has it as an interior node (`θ = 1` at the bucket's
    /// end): an approximation in that column. Off: the probed band of `K` alone (the path before). Measured at N = 8001 over three
    /// starts: 25 373 → 21 542 GMRES iterations to τ = 30, −7.7 % CPU
    /// (docs/performance.md, "The N = 8001 wear run: the exact masked band"). Part of the scheme
    /// ([`ADAPTIVE_SCHEME`]): set before the first step; a library run with it off records nothing
    /// of it.
    pub fn set_masked_band(&mut self, on: bool) {
        self.masked_band_on = on;
    }

    /// Experimental, off by default: the products `W x` of the adaptive stages whose GMRES
    /// tolerance is at least [`SINGLE_PRECISION_FROM`] by `f32` FFT transforms (the FFT backend
    /// only): the stress transform's convolution in `f32`, the profile transform's derivative
    /// from its increments convolved in `f32` (`ProfileTransform::set_precision`), inputs and
    /// outputs in `f64`; the rate evaluations, the probes of the band and the other stages stay
    /// in `f64`. On, plans the `f32` twins of the Jacobian's transforms here (the stages then
    /// switch precision without allocating). Measured (docs/performance.md, "The N = 8001 wear
    /// run: single-precision stage products (issue 20)"): one product 1.24–1.32× faster, the
    /// graded run −6 … −9 % CPU at about the same steps (N = 8001 not at the 5 s target); other step
    /// sequences, within the scatter of `f64` runs from perturbed starts, but on by default the
    /// tol-1e-6 reference of `recycled_second_stage_stays_within_the_error_bound_over_perturbed_starts`
    /// moved its touching radius at τ = 1 (k = −0.5) by about half a cell and the test failed:
    /// not the default. Set before the first step; not part of the
    /// checkpointed state (with it on, the checkpoint's `adaptive_scheme` does not say so).
    pub fn set_single_precision_products(&mut self, on: bool) -> Result<(), FrettingError> {
        if on {
            self.matrix.set_precision(Precision::Single)?;
            self.matrix.set_precision(Precision::Double)?;
        }
        self.single_precision_products = on;
        Ok(())
    }

    /// The sliding mode of the contact edge's last node in the adaptive steps
    /// (docs/fretting-wear.md, "The sliding mode in the stages"). Near grazing the last contact
    /// node `s` wears itself open within a step (its rate switches on like `(a² − ξ_s)^γ`,
    /// `γ = (1+k)/2`, infinite slope at `g_s = d`) and its neighbours' wear closes it again: the
    /// flow slides along `g_s ≈ d`. At a step's start, with `ġ = G F` (`G = P D`, `g` is linear
    /// in `f`), `F*_s = F_s − ġ_s/G_ss` (the rate that keeps `g_s` still against the others'
    /// wear) and `F¹_s = F_s θ^{−γ}` (the node's rate with the edge a cell beyond it), the node
    /// slides when `0 < F*_s < θ_max^γ F¹_s` (Filippov's condition: the flow points into the
    /// surface from both sides, the node out of contact (rate 0) and in it; `θ_max` =
    /// `SLIDING_THETA`: the equilibrium edge `θ* = (F*/F¹)^{1/γ}` lies within `θ_max` of the node)
    /// — decided at each step's start, so a node is released when its sliding rate leaves that
    /// interval. The surface is the gap at that equilibrium edge, `g* = d − θ*(g_E − g_s)` (at
    /// least `SLIDING_MARGIN` inside the contact); an attempt at `Δτ` holds the node when the
    /// start's `ġ_s` brings its gap to `g*` within `SLIDING_REACH · Δτ`: both ROS2 stages carry in
    /// its row the index-1 constraint `c(f) = g_s − g* = 0` in ROS2's form,
    /// `(G k₁)_s = −c(f)/(γΔτ)`, `(G k₂)_s = −c(f + Δτ k₁)/(γΔτ)` (scaled by `1/G_ss`; the band
    /// preconditioner's row `s` is `G`'s band over `G_ss`), so the result has `c = 0` (c is
    /// linear, `γ² − 2γ + 1/2 = 0`) and the node's wear is whatever keeps it there; the error
    /// estimate keeps its row (the embedded `f + Δτ k₁` is off the surface by `0.41 c(f)` when
    /// the start is). Only a node whose inner neighbour is closed (`g < d`): an isolated closed
    /// node beyond an open one is the adaptive steps' comb, not an edge (held, it moved the
    /// grazing phase by tens of tolerances). A function of the step's start and `Δτ` alone:
    /// resumes bit for bit. Only for adaptive steps. Set before the first step; the CLI records the default scheme
    /// ([`ADAPTIVE_SCHEME`]).
    pub fn set_sliding_edge(&mut self, on: bool) {
        self.sliding_edge = on;
    }

    /// The name of the adaptive scheme this run takes, for checkpoints: [`SLIDING_EDGE_SCHEME`]
    /// with the sliding mode on ([`FrettingSimulation::set_sliding_edge`]), else main's
    /// `ros2-hole-projection-eta1e-3-band5x12-rate-plans-masked-prefix-fma` ([`ADAPTIVE_SCHEME`] when the default is off).
    pub fn adaptive_scheme(&self) -> &'static str {
        if self.sliding_edge {
            SLIDING_EDGE_SCHEME
        } else {
            MAIN_SCHEME
        }
    }

    /// Calls `observer` after every attempt of an error-controlled step ([`StepAttempt`]: the step,
    /// its error ratio, where the error was largest, the contact edge at the start, the trial and
    /// the end). A diagnostic: it changes nothing in the run.
    pub fn set_attempt_observer(&mut self, observer: AttemptObserver) {
        self.observer = Some(observer);
    }

    /// The parameters.
    pub fn params(&self) -> &FrettingParams {
        &self.params
    }

    /// The grid (`r̃_i = √(i h)`).
    pub fn grid(&self) -> &SquaredGrid {
        &self.grid
    }

    /// The current state (for checkpoints and results).
    pub fn state(&self) -> &FrettingState {
        &self.state
    }

    /// `τ` reached.
    pub fn tau(&self) -> f64 {
        self.state.tau
    }

    /// GMRES iterations of the implicit steps so far in this process (a diagnostic, not state).
    pub fn krylov_iterations(&self) -> u64 {
        self.krylov_iterations
    }

    /// Band probes of the preconditioner so far in this process (a diagnostic, not state): each
    /// is `PROBE_COLOURS` (12) products of the profile and stress transforms.
    pub fn band_probes(&self) -> u64 {
        self.probes
    }

    /// `r*/a₀`, the limit of the contact radius.
    pub fn limit_contact_radius(&self) -> f64 {
        self.r_star
    }

    /// Popov's limiting profile `f̃∞` on the grid nodes.
    pub fn limiting_profile(&self) -> &[f64] {
        &self.limit
    }

    /// The final wear volume over `π a₀² d` ([`limit_wear_volume`]).
    pub fn limit_wear_volume(&self) -> f64 {
        limit_wear_volume(self.params.chi, self.params.k)
    }

    /// The wear volume so far over `π a₀² d`: `Ṽ = 2 ∫ (f̃ − f̃₀) r̃ dr̃ = ∫ (f̃ − f̃₀) dξ`, by the
    /// trapezoid rule on the grid (uniform in `ξ = r̃²`).
    pub fn wear_volume(&self) -> f64 {
        let k = self.params.k;
        let worn: Vec<f64> = self
            .grid
            .coordinates()
            .iter()
            .zip(&self.state.profile)
            .map(|(&r, &f)| f - initial_profile(r, k))
            .collect();
        halfspace_numerics::quad::trapezoid_uniform(&worn, self.grid.step())
    }

    /// `max |f̃ − f̃∞|` over `c̃ + margin < r̃ ≤ r*`: how far the worn profile is from Popov's limit
    /// away from the stick edge (where `f̃∞ − f̃₀ ~ (r − c)^{(1−k)/2}` is resolved by one node).
    pub fn limit_deviation(&self, margin: f64) -> f64 {
        let from = self.stick + margin;
        self.grid
            .coordinates()
            .iter()
            .zip(&self.state.profile)
            .zip(&self.limit)
            .filter(|((&r, _), _)| r > from && r <= self.r_star)
            .map(|((_, f), fl)| (f - fl).abs())
            .fold(0.0, f64::max)
    }

    /// Whether `τ_end` is reached.
    pub fn is_finished(&self) -> bool {
        self.state.tau >= self.params.fixed_end()
    }

    /// `f̃(a₀)`, linear in `ξ` between the nodes around `r̃ = 1`.
    pub fn profile_at_a0(&self) -> f64 {
        let t = self.grid.fractional_index(1.0);
        let i = (t.floor() as usize).min(self.grid.len() - 2);
        let w = t - i as f64;
        (1.0 - w) * self.state.profile[i] + w * self.state.profile[i + 1]
    }

    /// The equivalent profile `g̃` of the current profile (Eq. 7 / 23), over `d`.
    pub fn equivalent_profile(&mut self) -> Result<&[f64], FrettingError> {
        self.contact()?;
        let valid = self.gap_valid;
        if valid == self.grid.len() {
            return Ok(&self.g);
        }
        // A prefix evaluation: the nodes it computed as the step used them, the rest from the
        // whole grid's transform (not kept for the steps: their bits do not depend on who asks).
        std::mem::swap(&mut self.g, &mut self.full_gap);
        let whole = self.equivalent_into(self.grid.len());
        std::mem::swap(&mut self.g, &mut self.full_gap);
        whole?;
        self.full_gap[..valid].copy_from_slice(&self.g[..valid]);
        Ok(&self.full_gap)
    }

    /// Rate evaluations so far and how many of them ran on a prefix of the grid
    /// (`rate_prefix_nodes`; a diagnostic, not state).
    pub fn rate_evaluations(&self) -> (u64, u64) {
        self.rate_evaluations
    }

    /// The radii of the current profile.
    pub fn radii(&mut self) -> Result<ContactRadii, FrettingError> {
        Ok(self.contact()?.radii)
    }

    /// One accepted wear step of `∂f̃/∂τ = p̃ Δũ` (Eq. 30–31; the one of docs/theory-mdr.md#fretting-wear per-cycle loop with the edge
    /// between nodes): the rate `F(f̃) = p̃ Δũ` is `f → g` (Eq. 7 / 23), the contact edge `a`
    /// where the linear interpolant of `g` beyond the outermost node with `g < d` reaches `d`,
    /// `q = c̃_N max(d − g, 0)`, `q → p` by product integration with that edge
    /// ([`CellStressTransform`], clipped ≥ 0) and the slip `Δũ`. The step is
    ///
    /// * explicit Euler `f̃ ← f̃ + Δτ F(f̃)` ([`TimeStepping::ExplicitEuler`]), or
    /// * ROS2 (Verwer, Spee, Blom & Hundsdorfer 1999), `γ = 1 + 1/√2`, `W = I − γΔτ J`:
    ///   `W k₁ = F(f̃)`, `W k₂ = F(f̃ + Δτ k₁) − 2k₁`, `f̃ ← f̃ + Δτ (3k₁ + k₂)/2`, with `J` the
    ///   Jacobian at a frozen contact (`linearization`), each solve by GMRES on the transforms;
    ///   adaptive steps keep the embedded error `Δτ |k₁ + k₂|/2` (vs. the linearly implicit Euler
    ///   `f̃ + Δτ k₁`) and, on the nodes outside the start's contact, the error of their
    ///   end-of-step wear (`FrettingSimulation::outside_wear_error`) and the holes the result
    ///   opens (`FrettingSimulation::opened_hole_error`; a result whose holes exceed the
    ///   tolerance is projected onto the closed set, [`FrettingSimulation::set_hole_projection`])
    ///   below the tolerance with a
    ///   PI controller whose steps are rounded to `2^(j/64)` (`quantized_step`), and land on the
    ///   snapshot times.
    ///
    /// Takes a snapshot after the step when it lands on a snapshot time (and of the initial state
    /// when 0 is one).
    ///
    /// docs/theory-mdr.md#fretting-wear (and the paper) cut `q` at the first node outside and use Eq. 17/29; that pressure
    /// jumps by `O(1)` each time the edge crosses a node and the run does not converge under grid
    /// refinement (docs/fretting-wear.md, "The contact edge between nodes").
    ///
    /// Runs on the calling thread: called from outside a pool, one thread (the split FFTs'
    /// halves one after the other); [`Self::run`] moves the steps onto the pool when the plans
    /// split. The same bits either way.
    pub fn step(&mut self) -> Result<(), FrettingError> {
        self.contact()?;
        if self.is_finished() {
            return Ok(());
        }
        let tau = self.state.tau;
        let target = self
            .snapshot_times
            .iter()
            .copied()
            .find(|&t| t > tau)
            .unwrap_or(self.params.fixed_end());
        let (new_tau, dtau) = match self.params.stepping {
            TimeStepping::ExplicitEuler { dtau } => {
                self.euler_step(dtau);
                self.current = None;
                (self.fixed_tau(self.state.step + 1, dtau), dtau)
            }
            TimeStepping::Fixed { dtau } => {
                self.ros2_step(dtau)?;
                (self.fixed_tau(self.state.step + 1, dtau), dtau)
            }
            TimeStepping::Adaptive { tolerance } => {
                let dtau = self.adaptive_step(tolerance, target - tau)?;
                let new_tau = if tau + dtau >= target * (1.0 - 1e-14) {
                    target
                } else {
                    tau + dtau
                };
                (new_tau, dtau)
            }
        };
        self.state.step += 1;
        self.state.tau = new_tau;
        // The ROS2 steps leave the contact of their result in `current` when it is up to date
        // (evaluated for the error estimate; a function of the profile alone, so reusing it is
        // bit for bit the evaluation it saves) and clear it whenever the profile changes after.
        let contact = self.contact()?;
        let radii = contact.radii;
        self.state.tau_history.push(new_tau);
        self.state.contact_radius_history.push(radii.touching);
        self.state.loaded_radius_history.push(radii.loaded);
        // Wear only raises f, so the edge where g reaches d approaches r* from below; three cells
        // of slack for the grazing end phase, where g ≈ d on the whole annulus and the edge
        // jitters; an unstable step overshoots further (docs/theory-mdr.md#p10-explicit-wear-step).
        // The implicit steps are stable at any step; their end phase may leave the edge a few
        // cells beyond r* (measured 3.7 cells, k = −0.5, χ = 0.9, N = 2001), so only explicit
        // Euler is watched.
        let cell = self.grid.step() / (2.0 * self.r_star);
        let explicit = matches!(self.params.stepping, TimeStepping::ExplicitEuler { .. });
        if explicit && contact.edge_radius > self.r_star + 3.0 * cell {
            return Err(FrettingError::Unstable {
                tau: new_tau,
                contact_radius: contact.edge_radius,
                limit: self.r_star,
                suggested: 0.5 * dtau,
            });
        }
        if self.snapshot_times.contains(&new_tau) {
            self.take_snapshot(radii);
        }
        Ok(())
    }

    /// `τ` after `steps` fixed steps ([`FrettingParams::fixed_tau`]).
    fn fixed_tau(&self, steps: u64, dtau: f64) -> f64 {
        self.params.fixed_tau(steps).unwrap_or(steps as f64 * dtau)
    }

    /// `f̃ ← f̃ + Δτ p̃ Δũ` with the current pressure and slip (in this order of operations, which
    /// the pinned bits of the explicit runs depend on).
    fn euler_step(&mut self, dtau: f64) {
        if self.edge_cells > 0 {
            for (f, r) in self.state.profile.iter_mut().zip(&self.rate) {
                *f += dtau * r;
            }
            return;
        }
        for ((f, p), s) in self.state.profile.iter_mut().zip(&self.p).zip(&self.slip) {
            *f += dtau * p * s;
        }
    }

    /// One ROS2 attempt from the current profile (kept in `start`) at `dtau`; leaves the new profile
    /// in `state.profile` and returns the error estimate `max_i Δτ |k₁ + k₂|_i / 2`.
    fn ros2_attempt(&mut self, dtau: f64) -> Result<f64, FrettingError> {
        self.outside_grid = false;
        // The diagnostics of this attempt only: a stage whose GMRES fails returns before they
        // are set, and the observer must not see the previous attempt's.
        self.attempt.error_terms = [0.0; 3];
        self.attempt.first_order = false;
        self.attempt.projection = 1.0;
        self.attempt.opened_holes = 0;
        self.matrix.beta = ROS2_GAMMA * dtau;
        self.set_sliding_for(dtau);
        if self.precondition {
            self.precond.factor(self.matrix.beta);
            if !self.precond.is_factored() && self.sliding.is_some() {
                // The constraint row cost a pivot (not seen in the graded run: 0 of 4423 held
                // attempts to τ = 3): the band without it, GMRES keeps the row.
                self.precond.clear_constraint_row();
                self.precond.factor(self.matrix.beta);
            }
        }
        // W k₁ = F(f), warm-started from F (a function of the profile alone: resumable). A start
        // from M⁻¹F (the band preconditioner's solve) saves 15 % of the GMRES iterations on the
        // graded run but costs 19 % at N = 8001, χ = 0.5 (docs/performance.md, "Arithmetic
        // levers of the MDR wear run, each alone"): not used.
        if let Some(slide) = self.sliding {
            // The constraint row of the sliding node: (G k₁)_s/G_ss = −c(f)/(γΔτ G_ss), the
            // rate at the start put back by `restore_start` after a rejection.
            let c = self.g[slide.node] - slide.target;
            self.rate[slide.node] = -c / (self.matrix.beta * slide.self_gap);
        }
        self.k1.copy_from_slice(&self.rate);
        self.attempt.krylov_iterations.0 = self.solve(Stage::First)?;
        // W k₂ = F(f + Δτ k₁) − 2 k₁.
        for ((t, f), k) in self.trial.iter_mut().zip(&self.start).zip(&self.k1) {
            *t = f + dtau * k;
        }
        self.state.profile.copy_from_slice(&self.trial);
        // The contact nodes of the step's start (unless `freeze_contact` is off): within a step the
        // rate is a smooth function of f, and the contact set moves at the step's end.
        let frozen = self.freeze_contact.then(|| self.matrix.contact_nodes() - 1);
        let trial_contact = self.contact_state_with(frozen)?;
        self.trial_gap.copy_from_slice(&self.g);
        self.current = frozen.is_none().then_some(trial_contact);
        self.attempt.edge_trial = trial_contact.edge;
        // Nodes the trial profile brings into contact (g < d beyond the frozen edge): the
        // second stage takes the trial's own contact with their rate held at 0 (the stress of
        // the nodes inside follows the edge continuously), and their rate at the trial is kept
        // for the correction at the step's end.
        self.entered_nodes = 0..0;
        if let Some(last) = frozen {
            if self.observer.is_some() {
                self.attempt.trial_outermost = self.g.iter().rposition(|&g| g < 1.0).unwrap_or(0);
                self.attempt.trial_gap_margin = self.g[last + 1..]
                    .iter()
                    .map(|g| (g - 1.0).abs())
                    .fold(f64::INFINITY, f64::min);
            }
            // Only an edge that moved out continuously: every node from the frozen edge to the
            // trial's outermost node with g < d has g < d. Isolated nodes closing further out
            // (the near-grazing annulus, where g ≈ d) wait for the next step's contact.
            let outermost = self.g.iter().rposition(|&g| g < 1.0).unwrap_or(0);
            if outermost > last && self.g[last + 1..=outermost].iter().all(|&g| g < 1.0) {
                // The same profile: its g is the frozen evaluation's.
                let trial = self.contact_from_gap(None)?;
                self.current = Some(trial);
                self.attempt.edge_trial = trial.edge;
                self.trial_edge_squared =
                    self.grid.squared(trial.edge - 1) + trial.theta * self.grid.step();
                let from = last + 1;
                self.entered[from..trial.edge].copy_from_slice(&self.rate[from..trial.edge]);
                self.rate[from..trial.edge].fill(0.0);
                self.entered_nodes = from..trial.edge;
            }
        }
        self.attempt.entered_nodes = self.entered_nodes.len();
        for ((b, r), k) in self.rhs.iter_mut().zip(&self.rate).zip(&self.k1) {
            *b = r - 2.0 * k;
        }
        if let Some(slide) = self.sliding {
            // (G k₂)_s/G_ss = −c(f + Δτ k₁)/(γΔτ G_ss): the constraint's row has no mass, so no
            // −2k₁ (ROS2 for index-1 problems in the form M y' = F, Hairer & Wanner II, VI.4).
            let c = self.trial_gap[slide.node] - slide.target;
            self.rhs[slide.node] = -c / (self.matrix.beta * slide.self_gap);
        }
        self.k2.copy_from_slice(&self.rhs);
        self.attempt.krylov_iterations.1 = self.solve(Stage::Second)?;
        let mut error = 0.0f64;
        for (i, (((f, s), a), b)) in self
            .state
            .profile
            .iter_mut()
            .zip(&self.start)
            .zip(&self.k1)
            .zip(&self.k2)
            .enumerate()
        {
            *f = s + dtau * (1.5 * a + 0.5 * b);
            let e = (0.5 * dtau * (a + b)).abs();
            if e > error {
                error = e;
                self.attempt.worst_node = i;
            }
        }
        self.current = None;
        self.attempt.error_terms[0] = error;
        if let Some(last) = frozen {
            // The wear of the nodes beyond the start's contact, estimated again from the result.
            let outside_error = match self.outside_wear_error(last + 1, dtau) {
                Ok(e) => e,
                // The result's contact reaches beyond the grid: no estimate (rejected; a fixed
                // step stops at its contact, as before).
                Err(FrettingError::ContactOutsideGrid { .. }) => {
                    self.outside_grid = true;
                    return Ok(f64::INFINITY);
                }
                Err(e) => return Err(e),
            };
            self.attempt.error_terms[1] = outside_error.0;
            if outside_error.0 > error {
                error = outside_error.0;
                self.attempt.worst_node = outside_error.1;
            }
            // `g` is the result's (before the entered nodes' correction, which acts beyond the
            // start's contact).
            let tolerance = match self.params.stepping {
                TimeStepping::Adaptive { tolerance } => tolerance,
                _ => f64::INFINITY,
            };
            let holes = self.opened_hole_error();
            self.attempt.opened_holes = holes.2;
            self.attempt.error_terms[2] = holes.0;
            let fallback = self.first_order_fallback;
            if self.hole_estimate && (fallback || self.hole_projection) && holes.0 > tolerance {
                // The result opens holes its first-order solution keeps closed, by more than the
                // tolerance (they would reject it): projected onto the closed set along the
                // segment from the first-order solution f₁ = f + Δτ k₁ (the trial) to the result
                // f₂, f₁ + λ(f₂ − f₁); g is linear in f, so g_λ = g₁ + λ(g₂ − g₁). The pair's
                // estimate |f₂ − f₁| stays in the error: it bounds the projection's size
                // (1 − λ)|f₂ − f₁| (and is the error of f₁ itself). The first-order fallback is
                // λ = 0: f₁ (the same bits as the trial).
                let lambda = if fallback {
                    0.0
                } else {
                    hole_projection(self.first_annulus_node, &self.g, &self.trial_gap)
                };
                for (((f, s), a), b) in self
                    .state
                    .profile
                    .iter_mut()
                    .zip(&self.start)
                    .zip(&self.k1)
                    .zip(&self.k2)
                {
                    *f = s + dtau * (a + lambda * 0.5 * (a + b));
                }
                // The result's g kept in `rhs` (free after the second stage).
                self.rhs.copy_from_slice(&self.g);
                for (g, t) in self.g.iter_mut().zip(&self.trial_gap) {
                    *g = t + lambda * (*g - t);
                }
                self.current = None;
                self.attempt.first_order = fallback;
                self.attempt.projection = lambda;
                // The holes the projected solution opens where the result keeps the node closed.
                let h = opened_holes(self.first_annulus_node, &self.g, &self.rhs);
                self.attempt.error_terms[2] = h.0;
                if h.0 > error {
                    error = h.0;
                    self.attempt.worst_node = h.1;
                }
            } else if self.hole_estimate && holes.0 > error {
                error = holes.0;
                self.attempt.worst_node = holes.1;
            }
        }
        self.wear_entered_nodes(dtau);
        Ok(error)
    }

    /// The error of the wear of the nodes `j ≥ m` outside the step's start contact (`0..m`),
    /// which the ROS2 stages do not integrate (their rate is 0 at the start and held at 0 in the
    /// second stage): the end-of-step correction [`FrettingSimulation::wear_entered_nodes`]
    /// `W_j = Δτ (1 − s_j) F_j/(1 + γ)` from the trial `f + Δτ k₁` (its edge `a_t²` and rate;
    /// 0 for nodes it did not bring into contact) against the same formula from the step's result
    /// before the correction (its edge `a_e²`, `s_j = (ξ_j − a₀²)/(a_e² − a₀²)` and rate `F_j`,
    /// which also counts isolated nodes closing beyond the edge and nodes the trial missed):
    /// `max_j |W_j(trial) − W_j(result)|` and its node (docs/fretting-wear.md, "The contact set
    /// within a step"). Leaves `g`, `p`, the slip and the rate of the result (its contact in
    /// `current` when no correction follows, so an accepted step does not compute it again).
    fn outside_wear_error(&mut self, m: usize, dtau: f64) -> Result<(f64, usize), FrettingError> {
        let end = self.contact_state_with(None)?;
        let gamma = 0.5 * (1.0 + self.params.k);
        let a0 = self.start_edge_squared;
        let fraction = |xi: f64, a: f64| {
            if a > a0 {
                ((xi - a0) / (a - a0)).clamp(0.0, 1.0)
            } else {
                1.0
            }
        };
        let ae = self.grid.squared(end.edge - 1) + end.theta * self.grid.step();
        let at = self.trial_edge_squared;
        let mut worst = (0.0f64, 0);
        for j in m..end.edge.max(self.entered_nodes.end) {
            let xi = self.grid.squared(j);
            let trial = if self.entered_nodes.contains(&j) {
                dtau * (1.0 - fraction(xi, at)) * self.entered[j]
            } else {
                0.0
            };
            let result = dtau * (1.0 - fraction(xi, ae)) * self.rate[j];
            let e = (trial - result).abs() / (1.0 + gamma);
            if e > worst.0 {
                worst = (e, j);
            }
        }
        if self.entered_nodes.is_empty() {
            self.current = Some(end);
        }
        Ok(worst)
    }

    /// The holes the step's result opens against its embedded first-order solution: on the slip
    /// annulus inside the result's last contact node (`c̃ < r̃_i`, `i < L`, `L` the outermost node
    /// with `g < d`), the nodes with `g_i ≥ d` (no line load, `p = 0`: open although the contact
    /// reaches beyond them) where the trial `f + Δτ k₁` has `g_i < d`. Such a node is a
    /// difference of the contact set between the two solutions of the pair, which the error in
    /// `f` does not see (`g` is the Abel transform of `f'`, Eq. 7 / 23); once open it stops
    /// wearing and stays open. Its error is how far the result crossed, `g_i − d` (over `d`, as
    /// `f̃`): an indicator put in the estimate's units, not a bound of a defined error (its order
    /// in the step is not measured; it vanishes when the two solutions agree on the contact set).
    /// Holes the first-order solution opens too are not seen. The largest joins the error
    /// estimate; above the tolerance the attempt is projected onto the closed set instead
    /// ([`FrettingSimulation::set_hole_projection`], the default; or, with
    /// [`FrettingSimulation::set_first_order_fallback`], takes its first-order solution). Returns the largest, its node and the count
    /// (docs/fretting-wear.md, "What sets the step"). Reads `g` of the result.
    fn opened_hole_error(&self) -> (f64, usize, usize) {
        opened_holes(self.first_annulus_node, &self.g, &self.trial_gap)
    }

    /// The correction at the end of a step whose second stage kept the contact nodes of its start
    /// (docs/fretting-wear.md, "Time integration"): a node `j` that the trial profile `f + Δτ k₁`
    /// brings into contact was passed by the edge at the fraction `s_j = (ξ_j − a₀²)/(a_t² − a₀²)`
    /// of the step (the edge moving linearly in `ξ` from the start's `a₀²` to the trial's
    /// `a_t²`); its pressure grows like `(a²(τ) − ξ_j)^γ`, `γ = (1+k)/2`, so the wear it missed is
    /// `∫ F_j dτ = Δτ (1 − s_j) F_j(f + Δτ k₁)/(1 + γ)`. Outside the ROS2 stages (these rates
    /// switch on like `(τ − τ_j)^γ`, the non-smoothness that set the steps before); its error is
    /// estimated by `FrettingSimulation::outside_wear_error`.
    fn wear_entered_nodes(&mut self, dtau: f64) {
        if self.entered_nodes.is_empty() {
            return;
        }
        // The trial's edge a_t² = ξ_L + θh (θ of the trial contact).
        let (a0, at) = (self.start_edge_squared, self.trial_edge_squared);
        let gamma = 0.5 * (1.0 + self.params.k);
        for j in self.entered_nodes.clone() {
            let s = if at > a0 {
                ((self.grid.squared(j) - a0) / (at - a0)).clamp(0.0, 1.0)
            } else {
                1.0
            };
            self.state.profile[j] += dtau * (1.0 - s) * self.entered[j] / (1.0 + gamma);
        }
    }

    /// Freezes the Jacobian at the current (start) profile and keeps that profile.
    fn linearize(&mut self, contact: Contact) -> Result<(), FrettingError> {
        self.start.copy_from_slice(&self.state.profile);
        let kept = &mut self.start_rate;
        kept.g.copy_from_slice(&self.g);
        kept.sigma.copy_from_slice(&self.sigma);
        kept.p.copy_from_slice(&self.p);
        kept.slip.copy_from_slice(&self.slip);
        kept.rate.copy_from_slice(&self.rate);
        kept.contact = Some(contact);
        kept.gap_valid = self.gap_valid;
        self.start_edge_squared = contact.edge_radius * contact.edge_radius;
        self.matrix.freeze(
            &self.slip,
            &self.p,
            &self.sigma,
            &self.g,
            contact.edge,
            contact.theta,
        )?;
        if self.precondition {
            let p = &mut self.precond;
            // The band of K for the contact nodes rounded up to the next multiple of
            // PROBE_BUCKET (a function of the contact nodes alone: a resumed run rebuilds the
            // same one), probed again only when they enter another bucket.
            let target = probe_nodes(contact.edge, self.grid.len());
            if p.probed_for != target {
                self.matrix.probe_band(
                    target,
                    p.width(),
                    PROBE_COLOURS,
                    &mut p.probe,
                    &mut p.response,
                    &mut p.stress_band,
                )?;
                p.probed_for = target;
                self.probes += 1;
            }
            if self.masked_band_on && self.matrix.has_closed_nodes() {
                // The probed band of `K` (every node open) less the band of the closed nodes'
                // part: the band of the stages' masked operator up to the probe's folding, the
                // edge and the closed part's tail (docs/performance.md, "The N = 8001 wear run:
                // the exact masked band").
                let (grid, k, width) = (&self.grid, self.params.k, p.width());
                let transform = self.params.gap_transform;
                let bands = self.masked_band.get_or_insert_with(|| {
                    MaskedBand::new(grid, k, width, CLOSED_REACH, transform)
                });
                self.matrix.closed_band(bands).map_err(MdrError::from)?;
                bands.subtract_from(&p.stress_band, contact.edge);
                self.matrix.scale_band(p.width(), &bands.band, &mut p.band);
            } else {
                self.matrix
                    .scale_band(p.width(), &p.stress_band, &mut p.band);
            }
            p.active = contact.edge;
        }
        self.slide_candidate = self.sliding_node(contact)?;
        Ok(())
    }

    /// Whether the attempt at `dtau` holds the step's sliding candidate on the contact surface
    /// (when its gap reaches the surface within `SLIDING_REACH · Δτ`), and the constraint row in
    /// the stages' operator and the preconditioner (set before the preconditioner is factored).
    fn set_sliding_for(&mut self, dtau: f64) {
        self.sliding = self
            .slide_candidate
            .filter(|s| s.approach <= SLIDING_REACH * dtau);
        self.matrix.constraint = self.sliding.map(|s| (s.node, 1.0 / s.self_gap));
        self.attempt.sliding_node = self.sliding.map(|s| s.node);
        if let Some(s) = self.sliding.filter(|_| self.precondition) {
            let w = PRECONDITIONER_WIDTH;
            let row = &self.gap_band[s.node * (2 * w + 1)..(s.node + 1) * (2 * w + 1)];
            self.precond
                .set_constraint_row(s.node, row, 1.0 / s.self_gap);
        } else {
            self.precond.clear_constraint_row();
        }
    }

    /// The step's sliding candidate ([`FrettingSimulation::set_sliding_edge`]): the last contact
    /// node `s` (slip annulus, wearing, its inner neighbour closed) when
    /// `0 < F*_s < θ_max^γ F¹_s`, with its surface `g*` and the time its gap takes to reach it.
    /// One profile transform (`G F`) a step, and one per column of `G` not computed before.
    fn sliding_node(&mut self, contact: Contact) -> Result<Option<SlidingNode>, FrettingError> {
        if !matches!(self.params.stepping, TimeStepping::Adaptive { .. }) {
            return Ok(None);
        }
        let s = contact.edge - 1;
        let w = PRECONDITIONER_WIDTH;
        if !self.sliding_edge
            || s <= self.first_annulus_node.max(w)
            || s + w + 3 >= self.grid.len()
            || self.rate[s] <= 0.0
            || self.g[s - 1] >= 1.0
            || self.edge_cells > 0
        {
            return Ok(None);
        }
        let gamma = 0.5 * (1.0 + self.params.k);
        let full_rate = self.rate[s] * contact.theta.powf(-gamma);
        // ġ = G F at the start (the rate with the node in contact).
        for j in s - w..=s + w {
            self.gap_column(j)?;
        }
        samples_to_gap(
            &mut self.profile_tf,
            self.params.gap_transform,
            &self.grid,
            &self.rate,
            &mut self.slide_slope,
            &mut self.slide_gap,
        )?;
        let self_gap = self.gap_band[s * (2 * w + 1) + w];
        if self_gap.is_nan() || self_gap <= 0.0 {
            return Ok(None);
        }
        let sliding_rate = self.rate[s] - self.slide_gap[s] / self_gap;
        // The surface: the gap at the equilibrium edge θ* = (F*/F¹)^{1/γ} in the start's last
        // cell, g* = d − θ* (g_E − g_s), at least SLIDING_MARGIN inside.
        let equilibrium = (sliding_rate / full_rate).max(0.0).powf(1.0 / gamma);
        let target = 1.0 - (equilibrium * (self.g[s + 1] - self.g[s])).max(SLIDING_MARGIN);
        // The time the node's gap takes to reach g* at the start's ġ (0 when it is there).
        let moving = target - self.g[s];
        let approach = if moving == 0.0 {
            0.0
        } else if moving * self.slide_gap[s] > 0.0 {
            moving / self.slide_gap[s]
        } else {
            f64::INFINITY
        };
        let slides = sliding_rate > 0.0 && sliding_rate < SLIDING_THETA.powf(gamma) * full_rate;
        Ok(slides.then_some(SlidingNode {
            node: s,
            target,
            self_gap,
            approach,
        }))
    }

    /// Column `j` of `G = P D` on the rows `j − w ..= j + w` into `gap_band` (once: `G` depends
    /// on the grid alone), by one profile transform of `e_j`.
    fn gap_column(&mut self, j: usize) -> Result<(), FrettingError> {
        if self.gap_column_done[j] {
            return Ok(());
        }
        let (w, n) = (PRECONDITIONER_WIDTH, self.grid.len());
        self.slide_unit.fill(0.0);
        self.slide_unit[j] = 1.0;
        samples_to_gap(
            &mut self.profile_tf,
            self.params.gap_transform,
            &self.grid,
            &self.slide_unit,
            &mut self.slide_slope,
            &mut self.slide_gap,
        )?;
        for i in j.saturating_sub(w)..(j + w + 1).min(n) {
            self.gap_band[i * (2 * w + 1) + (j + w - i)] = self.slide_gap[i];
        }
        self.gap_column_done[j] = true;
        Ok(())
    }

    /// Puts the start profile and its rate back after a rejected attempt (kept by
    /// [`FrettingSimulation::linearize`]: the bits an evaluation of the start would give).
    fn restore_start(&mut self) -> Result<(), FrettingError> {
        self.state.profile.copy_from_slice(&self.start);
        let kept = &self.start_rate;
        self.g.copy_from_slice(&kept.g);
        self.sigma.copy_from_slice(&kept.sigma);
        self.p.copy_from_slice(&kept.p);
        self.slip.copy_from_slice(&kept.slip);
        self.rate.copy_from_slice(&kept.rate);
        self.current = kept.contact;
        self.gap_valid = kept.gap_valid;
        self.contact()?;
        Ok(())
    }

    /// A fixed ROS2 step.
    fn ros2_step(&mut self, dtau: f64) -> Result<(), FrettingError> {
        let contact = self.contact()?;
        self.linearize(contact)?;
        self.ros2_attempt(dtau)?;
        Ok(())
    }

    /// An error-controlled ROS2 step no longer than `room` (to the next snapshot or the end):
    /// attempts until the error ratio `E = err/tol ≤ 1`, then the PI controller
    /// `Δτ_next = Δτ · clamp(0.9 E^{−0.35} E_prev^{0.2}, 0.2, 5)` (Gustafsson; exponents `0.7/2`,
    /// `0.4/2` for the second-order pair); a rejection shrinks by `clamp(0.9 E^{−1/2}, 0.1, 0.9)`.
    /// Returns the step taken.
    fn adaptive_step(&mut self, tolerance: f64, room: f64) -> Result<f64, FrettingError> {
        let contact = self.contact()?;
        self.linearize(contact)?;
        let mut dtau = if self.state.next_step > 0.0 {
            self.state.next_step
        } else {
            FIRST_STEP
        };
        self.attempt.edge_start = contact.edge;
        self.attempt.edge_radius_start = contact.edge_radius;
        loop {
            let attempt = dtau.min(room);
            self.attempt.tau = self.state.tau;
            self.attempt.dtau = attempt;
            let ratio = match self.ros2_attempt(attempt) {
                Ok(error) => error / tolerance,
                // GMRES did not converge at this step: a rejection.
                Err(FrettingError::Mdr(MdrError::Numerics(NumericsError::NoConvergence {
                    ..
                }))) => f64::INFINITY,
                Err(e) => return Err(e),
            };
            if self.observer.is_some() {
                self.attempt.error_ratio = ratio;
                self.attempt.accepted = ratio <= 1.0;
                // The observer only reads: a rejected profile whose contact cannot be evaluated
                // (e.g. outside the grid) is reported as edge `usize::MAX` and retried as without
                // an observer, never turned into an error.
                (self.attempt.edge_end, self.attempt.edge_radius_end) = if ratio.is_finite() {
                    self.contact()
                        .map_or((usize::MAX, f64::NAN), |c| (c.edge, c.edge_radius))
                } else {
                    (0, f64::NAN)
                };
                let attempt = self.attempt;
                if let Some(observer) = self.observer.as_mut() {
                    observer(&attempt);
                }
            }
            if ratio <= 1.0 {
                let ratio = ratio.max(1e-10);
                let previous = if self.state.previous_error > 0.0 {
                    self.state.previous_error
                } else {
                    ratio
                };
                let factor = (0.9 * ratio.powf(-0.35) * previous.powf(0.2)).clamp(0.2, 5.0);
                // A step cut short by a snapshot keeps the controller's step for the next one.
                self.state.next_step = quantized_step(dtau.max(attempt) * factor);
                self.state.previous_error = ratio;
                return Ok(attempt);
            }
            self.state.rejected_steps += 1;
            let shrink = if ratio.is_finite() {
                (0.9 / ratio.sqrt()).clamp(0.1, 0.9)
            } else {
                0.25
            };
            dtau = quantized_step(attempt * shrink);
            if dtau < 1e-14 * self.params.tau_end.max(1.0) {
                // Steps shrunk because every result reached beyond the grid: the domain is too
                // short, not the tolerance too tight.
                if self.outside_grid {
                    return Err(FrettingError::ContactOutsideGrid {
                        length: self.params.length,
                    });
                }
                return Err(FrettingError::StepTooSmall {
                    tau: self.state.tau,
                    dtau,
                });
            }
            self.restore_start()?;
        }
    }

    /// `W k = b` by GMRES for the stage's `k` (warm start in it); returns the iterations.
    fn solve(&mut self, stage: Stage) -> Result<usize, FrettingError> {
        let n = self.grid.len();
        let (b, x) = match stage {
            Stage::First => (&self.rate, &mut self.k1),
            Stage::Second => (&self.rhs, &mut self.k2),
        };
        // Adaptive steps: the stage error Δτ |δk| ≤ Δτ ρ ‖b‖₂ (‖W⁻¹‖ ≤ 1 for the damped modes)
        // is held to a hundredth of the step's tolerance.
        let mut params = KRYLOV;
        if let TimeStepping::Adaptive { tolerance } = self.params.stepping {
            let norm = b.iter().map(|v| v * v).sum::<f64>().sqrt();
            let dtau = self.matrix.beta / ROS2_GAMMA;
            if norm > 0.0 {
                params.tolerance = (0.01 * tolerance / (dtau * norm)).clamp(KRYLOV.tolerance, 1e-3);
            }
        }
        // W is the identity beyond the contact nodes' support (and M beyond the band's rows):
        // when b and the warm start vanish there (the frozen-contact stages), so do GMRES's
        // vectors, and GMRES runs on the leading block alone — the same iterates bit for bit
        // (docs/fretting-wear.md, "Cost per step").
        let block = self
            .matrix
            .support()
            .max(if self.precondition {
                self.precond.active.min(n) + self.precond.width()
            } else {
                0
            })
            .min(n);
        let d = if b[block..].iter().all(|&v| v == 0.0) && x[block..].iter().all(|&v| v == 0.0) {
            block
        } else {
            n
        };
        self.matrix.set_dim(d);
        self.precond.dim = d;
        let single = self.single_precision_products && params.tolerance >= SINGLE_PRECISION_FROM;
        if single {
            self.matrix.set_precision(Precision::Single)?;
        }
        let info = if self.precondition {
            // Only when the first stage left a usable space (else its warm start b₂ stays).
            let recycled = matches!(stage, Stage::Second)
                && self.recycled_second_stage
                && self.stage_one_dim == Some(d)
                && self.gmres.has_previous_space(d, params.restart);
            if recycled {
                // The second stage minimizes over the first stage's space, its result and the
                // new Krylov directions from a zero start (no product for the start's residual;
                // docs/fretting-wear.md, "Time integration").
                x[..d].fill(0.0);
                self.gmres.solve_continuing_previous_space(
                    &mut self.matrix,
                    &mut self.precond,
                    &b[..d],
                    &mut x[..d],
                    &params,
                )
            } else {
                self.gmres.solve(
                    &mut self.matrix,
                    &mut self.precond,
                    &b[..d],
                    &mut x[..d],
                    &params,
                )
            }
        } else {
            self.gmres.solve(
                &mut self.matrix,
                &mut Identity(d),
                &b[..d],
                &mut x[..d],
                &params,
            )
        };
        self.stage_one_dim = matches!(stage, Stage::First).then_some(d);
        if single {
            self.matrix.set_precision(Precision::Double)?;
        }
        self.matrix.set_dim(n);
        self.precond.dim = n;
        let info = info.map_err(MdrError::from)?;
        self.krylov_iterations += info.iterations as u64;
        Ok(info.iterations)
    }

    /// The contact of the current profile, computing g, p, the slip and the rate only when the
    /// profile changed (one profile and one stress transform).
    fn contact(&mut self) -> Result<Contact, FrettingError> {
        match self.current {
            Some(contact) => Ok(contact),
            None => {
                let contact = self.contact_state()?;
                self.current = Some(contact);
                Ok(contact)
            }
        }
    }

    /// Computes g, p, the slip, the rate `p Δu` and the radii of the current profile.
    fn contact_state(&mut self) -> Result<Contact, FrettingError> {
        self.contact_state_with(None)
    }

    /// [`FrettingSimulation::contact_state`], with the last contact node either that of the
    /// profile (`None`: the outermost node with `g < d`) or held at `frozen` (the second stage
    /// of a step whose contact nodes are those of its start, docs/fretting-wear.md, "Time
    /// integration"): then `θ = (1 − g_L)/(g_E − g_L)` is clamped to `(0, 1]` in that cell
    /// (`θ → 0` when `g_L ≥ d`, `θ = 1` when `g_E < d`, the nodes beyond stay open).
    fn contact_state_with(&mut self, frozen: Option<usize>) -> Result<Contact, FrettingError> {
        // `g` on the nodes `0..valid`; beyond them (a prefix evaluation) the lower bound
        // `g_{valid−1} ≥ d + ε` of the nodes outside.
        self.equivalent_on_prefix()?;
        self.contact_from_gap(frozen)
    }

    /// The rest of [`FrettingSimulation::contact_state_with`] from `g` of the current profile
    /// as it stands (the last evaluation's, on its nodes `0..gap_valid`): the contact, `p`, the
    /// slip, the rate and the radii. The second stage's trial takes its own contact with the
    /// `g` of its frozen-contact evaluation (the same profile: the same `g` bit for bit, one
    /// profile transform saved).
    fn contact_from_gap(&mut self, frozen: Option<usize>) -> Result<Contact, FrettingError> {
        let n = self.grid.len();
        let h = self.grid.step();
        let valid = self.gap_valid;
        let outermost =
            frozen.unwrap_or_else(|| self.g[..valid].iter().rposition(|&g| g < 1.0).unwrap_or(0));
        let edge = outermost + 1;
        if edge >= n - 1 {
            return Err(FrettingError::ContactOutsideGrid {
                length: self.params.length,
            });
        }
        // The edge between the last node with g < d and the next one, where the linear
        // interpolant of g reaches d: a² = ξ_last + θh (θ ∈ (0, 1]).
        let last = outermost;
        let theta = if self.g[edge] > self.g[last] {
            ((1.0 - self.g[last]) / (self.g[edge] - self.g[last])).clamp(f64::MIN_POSITIVE, 1.0)
        } else if self.g[last] < 1.0 {
            // Only with a frozen contact: g falls towards the next node.
            1.0
        } else {
            f64::MIN_POSITIVE
        };
        let modulus = normalized_modulus(self.params.k);
        for (q, &g) in self.q[..=last].iter_mut().zip(&self.g[..=last]) {
            *q = modulus * (1.0 - g).max(0.0);
        }
        let m = last + 1;
        self.stress_tf.line_load_to_stress(
            &self.grid,
            &self.q[..m],
            theta,
            &mut self.sigma[..m],
        )?;
        self.sigma[m..].fill(0.0);
        for (p, s) in self.p[..m].iter_mut().zip(&self.sigma) {
            *p = s.max(0.0);
        }
        self.p[m..].fill(0.0);
        // The slip vanishes from the edge on (`edge = m`), and with it the rate.
        // slip_at(i) on 0..edge, as zipped slices (the same operations per node).
        let first = self.first_annulus_node.min(edge);
        for ((slip, rate), &p) in self.slip[..first]
            .iter_mut()
            .zip(&mut self.rate[..first])
            .zip(&self.p[..first])
        {
            *slip = 0.0;
            *rate = p * 0.0;
        }
        let chi = self.params.chi;
        for (((((slip, rate), &p), &f), &limit), &annulus) in self.slip[first..edge]
            .iter_mut()
            .zip(&mut self.rate[first..edge])
            .zip(&self.p[first..edge])
            .zip(&self.state.profile[first..edge])
            .zip(&self.limit[first..edge])
            .zip(&self.annulus[first..edge])
        {
            *slip = (4.0 * ((f - limit) / chi + annulus)).max(0.0);
            *rate = p * *slip;
        }
        self.slip[edge..].fill(0.0);
        self.rate[edge..].fill(0.0);
        self.edge_cell_rates(last, theta);
        // The touching region: nodes with g < 1 + ε, ε = GAP_TOLERANCE · h. Its radius is the
        // edge where g reaches d unless nodes beyond the first one outside are within ε (the
        // grazing end phase); then where the interpolant of g beyond the outermost such node
        // reaches 1 + ε.
        let edge_radius = (self.grid.squared(last) + theta * h).sqrt();
        let closed = 1.0 + GAP_TOLERANCE * h;
        let touching_last = self.g[..valid]
            .iter()
            .rposition(|&g| g < closed)
            .unwrap_or(0)
            .min(n - 2);
        let touching = if touching_last <= edge {
            edge_radius
        } else {
            let (g0, g1) = (self.g[touching_last], self.g[touching_last + 1]);
            let t = ((closed - g0) / (g1 - g0)).clamp(0.0, 1.0);
            (self.grid.squared(touching_last) + t * h).sqrt()
        };
        let p_max = self.p[..m].iter().copied().fold(0.0, f64::max);
        let loaded = self.p[..m]
            .iter()
            .rposition(|&p| p > LOAD_THRESHOLD * p_max)
            .map_or(0.0, |i| self.grid.coordinate(i));
        Ok(Contact {
            edge,
            theta,
            edge_radius,
            radii: ContactRadii { touching, loaded },
        })
    }

    /// `g = P[D f]` (Eq. 7 / 23) of the current profile into `g`; returns the nodes `0..V` on
    /// which it is the transform's. With [`FrettingSimulation::set_prefix_rate`] on, implicit
    /// runs first try the prefix `0..L` of [`rate_prefix_nodes`] with a shorter plan: `P` is a
    /// causal sum followed by a central difference, and `D` is a central difference, so `g_k`
    /// reads `f` up to node `k + 2` (and the columns 0–2 through the split `c₀ = f̂'_0`); `g` on
    /// `0..L − 2` is the whole grid's to rounding (as the Jacobian's `m + 3` nodes,
    /// `RosenbrockMatrix::equivalent_near_contact`). Kept only when the worn part of the profile
    /// (`f̃ ≠ f̃₀`) ends before the node `V − 1 = L − 3`, `w = f̃ − f̃₀ ≥ 0` on it, and
    /// `g_{V−1} ≥ max(d + ε + PREFIX_GAP_MARGIN, g_{V−2})`: beyond the worn part `g` increases
    /// (with `w ≥ 0` vanishing there and at the centre, `g_w = −C ξ^{1−γ} ∫ w(ρ)(ξ − ρ)^{γ−2} dρ`,
    /// `γ = (1+k)/2`, increases with `ξ`, and so does `g₀`; docs/fretting-wear.md, "The rate
    /// evaluations of the implicit runs"), so no node beyond is touching and `g_{V−1}` is a lower
    /// bound for them, which the nodes `V..N` of `g` then hold. Otherwise (and by default) the
    /// whole grid.
    fn equivalent_on_prefix(&mut self) -> Result<usize, FrettingError> {
        let n = self.grid.len();
        let h = self.grid.step();
        let len = self.prefix_nodes;
        self.rate_evaluations.0 += 1;
        if len < n {
            let valid = len - 2;
            let worn = self
                .state
                .profile
                .iter()
                .zip(&self.initial)
                .rposition(|(f, f0)| (f - f0).abs() > PREFIX_WORN_TOLERANCE * f0.abs())
                .map_or(0, |i| i + 1);
            // The argument needs w = f − f₀ ≥ 0 (the ROS2 stages do not constrain its sign).
            let nonnegative = self.state.profile[..worn]
                .iter()
                .zip(&self.initial)
                .all(|(f, f0)| f - f0 >= -PREFIX_WORN_TOLERANCE * f0.abs());
            if worn + 1 < valid && nonnegative {
                self.equivalent_into(len)?;
                let bound = self.g[valid - 1];
                // And the discrete g rising at the prefix's end.
                if bound >= 1.0 + GAP_TOLERANCE * h + PREFIX_GAP_MARGIN
                    && bound >= self.g[valid - 2]
                {
                    self.g[valid..].fill(bound);
                    self.gap_valid = valid;
                    self.rate_evaluations.1 += 1;
                    return Ok(valid);
                }
            }
        }
        self.equivalent_into(n)?;
        self.gap_valid = n;
        Ok(n)
    }

    /// `g = P[D f]` of the current profile on the first `len` nodes (the whole grid's for
    /// `len = N`) into `g[..len]`, with the plan for `len` (Eq. 7 / 23; `slope` is scratch).
    fn equivalent_into(&mut self, len: usize) -> Result<(), FrettingError> {
        let h = self.grid.step();
        let prefix = SquaredGrid::with_step(len, h).map_err(MdrError::from)?;
        samples_to_gap(
            &mut self.profile_tf,
            self.params.gap_transform,
            &prefix,
            &self.state.profile[..len],
            &mut self.slope[..len],
            &mut self.g[..len],
        )?;
        Ok(())
    }

    /// `Δũ_i` on a node inside the contact: `4[(f̃_i − f̃∞_i)/χ + J(r̃_i)]` clipped ≥ 0 on the slip
    /// annulus (`r̃_i > c̃`: from the first annulus node on, the coordinates increase), 0 inside
    /// the stick radius (slip_per_cycle with the stored f̃∞ and J, the same operations).
    fn slip_at(&self, i: usize) -> f64 {
        if i >= self.first_annulus_node {
            let s =
                4.0 * ((self.state.profile[i] - self.limit[i]) / self.params.chi + self.annulus[i]);
            s.max(0.0)
        } else {
            0.0
        }
    }

    /// The wear rate of the cells at the contact edge as the cell mean of `p Δu`
    /// ([`edge_cell_means`]): the cells `last − EDGE_CELLS ..= last + 1` get `F_j = p̄_j Δu_j`,
    /// the first node outside included once the edge is in its cell (its slip by the same formula
    /// as the contact nodes'). The rate of a node then switches on like `(τ − τ₀)^{1+γ}` as the
    /// edge enters its cell, instead of jumping on like `(τ − τ₀)^γ` (`γ = (1+k)/2`) as the edge
    /// passes the node (docs/fretting-wear.md, "Edge cells").
    fn edge_cell_rates(&mut self, last: usize, theta: f64) {
        if self.edge_cells == 0 || last < 3 {
            return;
        }
        let range = edge_cell_means(
            &self.grid,
            0.5 * (1.0 + self.params.k),
            &self.sigma,
            (last, theta),
            self.edge_cells,
            &mut self.edge_shape,
            &mut self.edge_mean,
        );
        for j in range {
            self.rate[j] = self.edge_mean[j] * self.slip_at(j);
        }
    }

    fn take_snapshot(&mut self, radii: ContactRadii) {
        self.state.snapshots.push(Snapshot {
            step: self.state.step,
            tau: self.state.tau,
            profile: self.state.profile.clone(),
            pressure: self.p.clone(),
            slip: self.slip.clone(),
            contact_radius: radii.touching,
            loaded_radius: radii.loaded,
        });
    }

    /// Runs until `τ_end` (or until `after_step` returns true after a step, for checkpoints and
    /// progress).
    /// On grids whose transforms split their FFTs (`2N − 1` padded to
    /// `halfspace_numerics::conv1d::SPLIT_FROM` or more) each step runs on a worker of the rayon
    /// pool with a partner polling for its sections (the split FFTs' halves on two threads,
    /// docs/performance.md, "Two threads in the MDR wear run"); smaller grids run on the calling
    /// thread (nothing to share, no core spent polling). The same results bit for bit on any
    /// number of threads (tests/threads.rs). On such grids the attempt observer
    /// ([`Self::set_attempt_observer`]) is called on that pool worker thread, not on the caller's;
    /// `after_step` stays on the calling thread. [`Self::step`] called alone runs on the calling
    /// thread, its FFT halves one after the other (one thread) unless that thread is itself a
    /// worker of a pool of two or more.
    pub fn run(&mut self, mut after_step: impl FnMut(&Self) -> bool) -> Result<(), FrettingError> {
        let split = self.plans_split();
        while !self.is_finished() {
            self.step_where_it_runs(split)?;
            if after_step(self) {
                return Ok(());
            }
        }
        // Make sure the final snapshot exists (a run resumed at its last step).
        let tau = self.state.tau;
        if !self.state.snapshots.iter().any(|s| s.tau == tau) {
            let radii = self.contact()?.radii;
            self.take_snapshot(radii);
        }
        Ok(())
    }

    /// Whether this grid's transforms split their FFTs (`2N − 1` padded to
    /// `halfspace_numerics::conv1d::SPLIT_FROM` or more): then [`Self::run`] takes each step on
    /// the pool ([`Self::step_where_it_runs`]).
    fn plans_split(&self) -> bool {
        use halfspace_numerics::conv1d::{plan_length, SPLIT_FROM};
        plan_length(2 * self.grid.len() - 1) >= SPLIT_FROM
    }

    /// One [`Self::step`] where [`Self::run`] takes it: with `split` ([`Self::plans_split`]) on a
    /// worker of the rayon pool with a polling partner, else on the calling thread (the same bits
    /// either way).
    fn step_where_it_runs(&mut self, split: bool) -> Result<(), FrettingError> {
        if split {
            halfspace_numerics::parallel::on_pool_with_partner(|| self.step())
        } else {
            self.step()
        }
    }
}

impl FrettingSimulation {
    /// Runs to the end (as [`Self::run`], each step on the pool when the plans split, without
    /// its observer) and returns, for each window `[τ₀, τ₁]`, the mean touching radius over it,
    /// `ā = (1/(τ₁ − τ₀)) ∫_{τ₀}^{τ₁} a(τ) dτ`, with `a(τ)` the linear interpolant of the
    /// touching radii ([`ContactRadii::touching`]) at the step ends `τ_n` (the trapezoidal rule
    /// on the steps), over the part of the window the run covers. Windows must start at or after
    /// the current `τ` and before the run's last `τ` ([`FrettingParams::fixed_end`]: `τ_end`, or
    /// for fixed steps the last step's `τ`, up to half a step before `τ_end`), and end by
    /// `τ_end`.
    ///
    /// Where the contact edge goes back and forth among the nodes of an annulus (the chattering
    /// edge of the graded runs, docs/fretting-wear.md, "The contact edge going back and
    /// forth"), the radius at one instant depends on the step sequence by up to a few cells; its
    /// mean over a window does not (docs/performance.md, "The band substitutions on fused
    /// multiply-adds (issue 20)"): this is the observable the stepping tests compare there.
    pub fn run_with_mean_radii(
        &mut self,
        windows: &[(f64, f64)],
    ) -> Result<Vec<f64>, FrettingError> {
        let (start, last, end) = (self.state.tau, self.params.fixed_end(), self.params.tau_end);
        for &(from, to) in windows {
            if !(from >= start && from < last && to > from && to <= end) {
                return Err(FrettingError::InvalidParameter {
                    name: "mean-radius window [τ₀, τ₁]",
                    value: if from >= start && from < last {
                        to
                    } else {
                        from
                    },
                    allowed: format!(
                        "τ₀ from the current τ ({start}) and before the last step's ({last}), \
                         τ₀ < τ₁ ≤ τ_end ({end})"
                    ),
                });
            }
        }
        let split = self.plans_split();
        // ∫ a dτ and the length covered, per window.
        let mut integrals = vec![(0.0, 0.0); windows.len()];
        let mut radius = self.radii()?.touching;
        while !self.is_finished() {
            let (before, start_radius) = (self.state.tau, radius);
            self.step_where_it_runs(split)?;
            let after = self.state.tau;
            radius = self.radii()?.touching;
            let slope = (radius - start_radius) / (after - before);
            for ((integral, covered), &(from, to)) in integrals.iter_mut().zip(windows) {
                let (lo, hi) = (before.max(from), after.min(to));
                if hi > lo {
                    *integral += (hi - lo) * (start_radius + slope * (0.5 * (lo + hi) - before));
                    *covered += hi - lo;
                }
            }
        }
        Ok(integrals
            .iter()
            .map(|(integral, covered)| integral / covered)
            .collect())
    }
}

/// The mean pressure `p̄_j` of the cells `[ξ_j − h/2, ξ_j + h/2] ∩ [0, a²]` at the contact edge,
/// `j = last − cells ..= last + 1` (returned as a range), `a² = ξ_last + θh`. Near the edge
/// `p = π(ξ)(a² − ξ)^γ`, `γ = (1+k)/2`, with `π` smooth (Eq. 14 / 28 of a load linear in `a² − ξ`
/// at the edge gives `(a² − ξ)^γ` times a power series in `a² − ξ`; Hertz: `π` constant), so with
/// `π` linear on the cell
///
/// `p̄_j = max(π_j A₀ + π'_j A₁, 0)/h`, `A_m = ∫ (ξ − ξ_j)^m (a² − ξ)^γ dξ` over the cell,
/// `A₀ = (u₋^{1+γ} − u₊^{1+γ})/(1+γ)`, `A₁ = (a² − ξ_j) A₀ − (u₋^{2+γ} − u₊^{2+γ})/(2+γ)`,
/// `u∓ = max(a² − ξ_j ± h/2, 0)`,
///
/// with `π_j = p_j/(a² − ξ_j)^γ` (`p = max(σ, 0)`) on the nodes before the last; at the last node
/// its own value `π_own = p_L/(θh)^γ`, blended (linear in θ over [`BLEND`] = `[θ₀, θ₁]`) into
/// the linear extrapolation `π_x = 2π_{L−1} − π_{L−2}` from the two nodes before as `θ → 0`
/// (where `π_own` is `0/0`), and never below `c min(θ/θ₀, 1) π_own` (`c` = [`OWN_FLOOR`]):
///
/// `π_L = max(b π_own + (1 − b) π_x, c min(θ/θ₀, 1) π_own)`, `b = clamp((θ − θ₀)/(θ₁ − θ₀), 0, 1)`
///
/// (a loaded last node beyond an unloaded inside — a grazing annulus — wears);
/// extrapolated linearly to the first node outside; `π'` by backward differences
/// (docs/fretting-wear.md, "Edge cells", "The edge cells' stall").
fn edge_cell_means(
    grid: &SquaredGrid,
    gamma: f64,
    sigma: &[f64],
    (last, theta): (usize, f64),
    cells: usize,
    shape: &mut [f64],
    mean: &mut [f64],
) -> std::ops::Range<usize> {
    let n = grid.len();
    let h = grid.step();
    let a2 = grid.squared(last) + theta * h;
    let first = last.saturating_sub(cells).max(2);
    let end = (last + 1).min(n - 1);
    for j in first - 2..last {
        shape[j] = sigma[j].max(0.0) / (a2 - grid.squared(j)).powf(gamma);
    }
    let own = sigma[last].max(0.0) / (theta * h).powf(gamma);
    let extrapolated = 2.0 * shape[last - 1] - shape[last - 2];
    let blend = ((theta - BLEND.0) / (BLEND.1 - BLEND.0)).clamp(0.0, 1.0);
    // Never below a share of its own value faded in as θ/θ₀ (θ₀ = BLEND.0): a last node loaded
    // beyond what the nodes inside extrapolate to (a grazing annulus — no load inside, the load
    // of the edge cell on the last node) wears, and the floor is continuous in θ and in the
    // stresses. (The rule before took `own` only where the extrapolation was ≤ 0: rounding-level
    // stresses inside the grazing annulus, ~1e-11, made it positive, the last node's rate ≈ 0
    // although `p = 2.1`, and the adaptive runs came to rest in that state — not an equilibrium
    // of the rate — at tight tolerances: docs/fretting-wear.md, "The edge cells' stall".)
    shape[last] = (blend * own + (1.0 - blend) * extrapolated)
        .max(OWN_FLOOR * (theta / BLEND.0).min(1.0) * own);
    if end > last {
        // The first node outside (none when the edge sits in the grid's last cell).
        shape[end] = 2.0 * shape[last] - shape[last - 1];
    }
    let (g1, g2) = (1.0 + gamma, 2.0 + gamma);
    for j in first..=end {
        let xi = grid.squared(j);
        let u_lo = a2 - (xi - 0.5 * h);
        let u_hi = (a2 - (xi + 0.5 * h)).max(0.0);
        mean[j] = if u_lo > 0.0 {
            let m0 = (u_lo.powf(g1) - u_hi.powf(g1)) / g1;
            let m1 = (a2 - xi) * m0 - (u_lo.powf(g2) - u_hi.powf(g2)) / g2;
            let slope = (shape[j] - shape[j - 1]) / h;
            ((shape[j] * m0 + slope * m1) / h).max(0.0)
        } else {
            0.0
        };
    }
    first..end + 1
}

/// Levels per octave of the adaptive step (`quantized_step`).
const STEP_LEVELS: f64 = 64.0;

/// `Δτ` rounded to the nearest `2^(j/STEP_LEVELS)` (`j` an integer): the step the controller
/// proposes becomes a discrete choice, which a difference of rounding between two runs (FFT and
/// MVM) flips only when the proposal lies within rounding of the midpoint between two levels, so
/// such runs take the same steps (docs/fretting-wear.md, "Adaptive runs that differ by rounding
/// or by the stage solves"). Costs at most `2^(1/128) − 1 = 0.5 %` of a step.
fn quantized_step(dtau: f64) -> f64 {
    if !(dtau > 0.0 && dtau.is_finite()) {
        return dtau;
    }
    ((dtau.log2() * STEP_LEVELS).round() / STEP_LEVELS).exp2()
}

/// Which ROS2 stage a solve is for.
#[derive(Debug, Clone, Copy)]
enum Stage {
    First,
    Second,
}

/// The holes `g` opens against `other`: the annulus nodes from `first` inside the last node with
/// `g < d` that have `g ≥ d` where `other < d` (docs/fretting-wear.md, "What sets the step"):
/// the largest `g − d`, its node and the count.
fn opened_holes(first: usize, g: &[f64], other: &[f64]) -> (f64, usize, usize) {
    let last = g.iter().rposition(|&x| x < 1.0).unwrap_or(0);
    let mut worst = (0.0f64, 0, 0);
    for i in first..last {
        if g[i] >= 1.0 && other[i] < 1.0 {
            worst.2 += 1;
            if g[i] - 1.0 > worst.0 {
                (worst.0, worst.1) = (g[i] - 1.0, i);
            }
        }
    }
    worst
}

/// The relative margin `η` of [`hole_projection`]: a projected hole node ends at
/// `g_λ = d − η (d − g₁)` in the interpolated gap `g₁ + λ(g₂ − g₁)` the hole estimate reads,
/// closed by a fraction of its first-order gap (< d there by construction). The gap recomputed
/// from the projected profile (the next step's start) differs from it by rounding of the
/// transforms (~1e-15); where `d − g₁` is itself at rounding level the margin is too, and that
/// node may open in the recomputed gap: a hole no estimate charges (the next step's holes are
/// counted against its own first-order solution). The default run's
/// a/a₀ at τ = 3 (near grazing) moves with it by up to 3.3 cells (η = 1e-4 … 1e-1 scanned,
/// docs/fretting-wear.md, "How robust the τ = 3 radius is"); 1e-3 passes the accuracy test.
/// Part of the scheme: changing it changes the steps, so rename [`ADAPTIVE_SCHEME`] with it
/// (its `eta1e-3`).
const HOLE_MARGIN: f64 = 1e-3;

/// `λ ∈ [0, 1]` of the projection onto the closed set
/// ([`FrettingSimulation::set_hole_projection`]): the largest step along `g₁ + λ(g₂ − g₁)` that
/// keeps closed the annulus nodes from `first` inside `g₂`'s last node with `g < d` that `g₂`
/// opens (`g₂ ≥ d`) and `g₁` keeps closed, `λ = (1 − η) min (d − g₁ᵢ)/(g₂ᵢ − g₁ᵢ)`.
fn hole_projection(first: usize, g2: &[f64], g1: &[f64]) -> f64 {
    let last = g2.iter().rposition(|&x| x < 1.0).unwrap_or(0);
    let mut lambda = 1.0f64;
    for i in first..last {
        if g2[i] >= 1.0 && g1[i] < 1.0 {
            lambda = lambda.min((1.0 - g1[i]) / (g2[i] - g1[i]));
        }
    }
    if lambda < 1.0 {
        (1.0 - HOLE_MARGIN) * lambda
    } else {
        lambda
    }
}

/// The half bandwidth `w` of the band preconditioner ([`BandPreconditioner`]), probed with
/// [`PROBE_COLOURS`] colours each time the contact nodes enter another bucket. Measured GMRES
/// iterations (default run / N = 8001 / graded k = −0.5, χ = 0.9): none 25 176 / 58 713 /
/// 1 025 082; w = 3 (7 colours): 13 864 / 29 158 / 429 077. At N = 8001 to τ = 30 (one step
/// sequence each, `step_trace 8001 0 0.5 1e-4 30` with these constants edited and rebuilt): w = 3
/// with 7 colours 34 895, with 14
/// colours 33 040; w = 4 with 10 colours 52 007; w = 5 with 11 colours 28 173, with 12
/// colours 25 164, with 14 colours 27 115; w = 7 with 16 colours 23 359 (docs/performance.md,
/// "The N = 8001 wear run on two cores (issue 20)"). w = 1 is worse than none and even widths
/// are worse than the odd width below them (the central-difference slope spreads the stencil
/// over ±1 before `P`).
pub(crate) const PRECONDITIONER_WIDTH: usize = 5;

/// The colours of the band probe ([`RosenbrockMatrix::probe_band`], more than `2w`): the probed
/// entry `(i, j)` also carries `K`'s entries of the same colour, `|i − j'| ≥ PROBE_COLOURS − w`
/// columns away. `2w + 1` colours put those aliases 4 (w = 3) or 6 (w = 5) columns away, and the
/// band they spoil preconditions worse: a dense study of one stage at N = 8001, τ = 5 (near
/// grazing; `K` assembled column by column, GMRES to 1e-5 at Δτ = 0.1): w = 3 with 7 / 13 / 14
/// colours 113 / 59 / 59 iterations, w = 5 with 11 / 12 / 13 colours 73 / 46 / 46 (the exact
/// band of the masked `J` itself 44 at w = 3). The parity of the count does not matter (13 and
/// 14 alike); the alias distance does.
pub(crate) const PROBE_COLOURS: usize = 12;

// Two columns of a row's band in one colour would be stored as their sum: refused at compile time.
const _: () = assert!(PROBE_COLOURS > 2 * PRECONDITIONER_WIDTH);

/// The contact nodes whose band of `K` the preconditioner uses for `m` contact nodes: `m`
/// rounded up to the next multiple of [`PROBE_BUCKET`] (at most `n − 4`, so that the probe's
/// transforms fit the grid). The rows `0..m` of that band differ from `K`'s for `m` only by
/// where the edge sits, a preconditioner's approximation (GMRES solves `W k = b` itself).
fn probe_nodes(m: usize, n: usize) -> usize {
    (m.div_ceil(PROBE_BUCKET) * PROBE_BUCKET).clamp(m, n.saturating_sub(4).max(m))
}

/// The prefix `0..L` of the grid on which the implicit runs evaluate the rate with
/// [`FrettingSimulation::set_prefix_rate`] (`FrettingSimulation::equivalent_on_prefix`): the node of `r*` (the touching radius's limit,
/// approached from below) and `N/16` more, at most `N`. The outside nodes' `g` then needs
/// `g ≥ d + ε + PREFIX_GAP_MARGIN` at the prefix's last computed node, else the evaluation takes
/// the whole grid.
fn rate_prefix_nodes(grid: &SquaredGrid, r_star: f64) -> usize {
    let n = grid.len();
    let star = grid.fractional_index(r_star).ceil() as usize;
    (star + (n / 16).max(32)).min(n)
}

/// How far above `d + ε` the last computed node of a prefix rate evaluation must be
/// (`FrettingSimulation::equivalent_on_prefix`): a margin over the transform's rounding and the
/// discretization of the monotonicity argument there.
const PREFIX_GAP_MARGIN: f64 = 0.02;

/// `|f̃ − f̃₀| ≤ PREFIX_WORN_TOLERANCE |f̃₀|` counts as unworn in
/// `FrettingSimulation::equivalent_on_prefix` (rounding-level perturbations of the start do not
/// count as wear).
const PREFIX_WORN_TOLERANCE: f64 = 1e-12;

/// The bucket of [`probe_nodes`] (nodes).
const PROBE_BUCKET: usize = 16;

/// Whether the adaptive steps use the sliding mode of the contact edge's last node by default
/// ([`FrettingSimulation::set_sliding_edge`]): off, unless the crate is built with the feature
/// `sliding-edge-default` (for measuring the tests with it).
const SLIDING_EDGE_DEFAULT: bool = cfg!(feature = "sliding-edge-default");

/// `θ_max` of [`FrettingSimulation::set_sliding_edge`]: a node slides when the edge position at
/// which its own wear would balance its neighbours', `θ* = (F*/F¹)^{1/γ}`, lies within `θ_max`
/// cells of it.
const SLIDING_THETA: f64 = 0.5;

/// An attempt holds the sliding candidate on the surface when the start's `ġ_s` brings its gap
/// there within `SLIDING_REACH · Δτ` ([`FrettingSimulation::set_sliding_edge`]): the exact flow
/// reaches the surface early in the step and slides after, and the node's wear over the step is
/// the jump onto the surface plus `F* Δτ` either way (to first order).
const SLIDING_REACH: f64 = 0.1;

/// The least depth of the sliding node's surface below `d`
/// ([`FrettingSimulation::set_sliding_edge`]): it is held at `g* = d − max(θ*(g_E − g_s), SLIDING_MARGIN)`, inside the contact, so the next
/// step sees it as a contact node again (the stage solves leave `c` at ≈ `0.01 tol G_ss`; 1e-4 in
/// `g` is 1e-6–2e-6 in `f` at N = 401–2001, `G_ss` = 50–200). The surface `max(g_s, d − 1e-4)`
/// instead of the equilibrium edge, and a margin `0.1 tol G_ss`, were measured too
/// (docs/fretting-wear.md, "The sliding mode in the stages").
const SLIDING_MARGIN: f64 = 1e-4;

/// The name of the edge cells' rule (`edge_cell_means` in simulation.rs; docs/fretting-wear.md,
/// "The edge cells' stall") that a run with them records (`fretting-wear`'s `edge_cell_rule`,
/// also in its JSON summary): a checkpoint of another rule (or of none recorded, the
/// rule before the last node's floor `c min(θ/θ₀, 1) π_own`) is refused, since its steps would not
/// be repeated bit for bit. The name must change whenever the edge cells' rate does.
pub const EDGE_CELL_RULE: &str = "own-floor-0.5";

/// The edge positions `θ` over which the last node's `π` goes from the extrapolation of the two
/// nodes before to its own `p/(θh)^γ` ([`edge_cell_means`]).
const BLEND: (f64, f64) = (0.25, 0.75);

/// The share `c` of the last contact node's own `π` below which its edge cell's `π` does not
/// fall ([`edge_cell_means`], `c min(θ/θ₀, 1) π_own`). Below 1 so that the floor acts only where
/// the extrapolation from the nodes inside fails (a grazing annulus): with `c = 1` it also took
/// over wherever `π_own` exceeded the blend by rounding, and the default run's a/a₀ at τ = 1 with
/// both options ended 2.9e-4 from explicit Euler of the same rate (1.2e-4 with `c = 0.5`; the
/// test's bound 2e-4; docs/fretting-wear.md, "The edge cells' stall"). Part of
/// [`EDGE_CELL_RULE`].
const OWN_FLOOR: f64 = 0.5;

/// The cells before the last contact node whose wear rate is the cell mean
/// ([`FrettingSimulation::edge_cell_rates`]).
const EDGE_CELLS: usize = 16;

/// GMRES for `W k = b`: relative residual 1e-8, restart 40. (1e-6 saves 30 % of the iterations
/// but moved a/a₀ at τ = 3 of the default run, in the grazing phase, by 1.2e-3; measured.)
const KRYLOV: KrylovParams = KrylovParams {
    tolerance: 1e-8,
    max_iterations: 400,
    restart: 40,
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::GapTransform;
    use halfspace_numerics::linop::LinearOperator;

    /// The band preconditioner: the probed band of `K` against the dense `K` (assembled column by
    /// column, the dense twin), and `W k = b` solved with and without it (GMRES to 1e-12) agree,
    /// with fewer iterations preconditioned, at steps from the explicit bound to 30 times it.
    #[test]
    fn preconditioned_solve_matches_unpreconditioned() {
        for k in [0.0, -0.5] {
            let nodes = 401;
            let length = FrettingParams::default_length(0.5, k);
            // The default discretization's explicit bound.
            let dtau_explicit = FrettingParams::default_step(nodes, length, k)
                * GapTransform::default().explicit_step_factor();
            let params = FrettingParams {
                nodes,
                k,
                length,
                stepping: TimeStepping::ExplicitEuler {
                    dtau: dtau_explicit,
                },
                tau_end: 0.5,
                snapshots: vec![],
                ..FrettingParams::default()
            };
            let mut sim = FrettingSimulation::new(params).unwrap();
            sim.run(|_| false).unwrap();
            let contact = sim.contact().unwrap();
            sim.precondition = true;
            sim.linearize(contact).unwrap();
            let n = sim.grid.len();
            let w = sim.precond.width();
            let (row_len, colours) = (2 * w + 1, PROBE_COLOURS);
            // The band is K's for the contact nodes rounded up to the probe bucket.
            let m = sim.precond.probed_for;
            assert_eq!(m, probe_nodes(contact.edge, n));
            // The dense twin of K, column by column.
            let mut dense = vec![0.0f64; n * n];
            let (mut e, mut col) = (vec![0.0; n], vec![0.0; n]);
            for j in 0..n {
                e.fill(0.0);
                e[j] = 1.0;
                sim.matrix.edge_node_response(m, &e, &mut col).unwrap();
                for i in 0..n {
                    dense[i * n + j] = col[i];
                }
            }
            // Probing adds to K_ij the entries of the same colour outside the band, exactly.
            let (mut worst, mut largest) = (0.0f64, 0.0f64);
            for i in 0..m {
                for l in 0..row_len {
                    let Some(j) = (i + l).checked_sub(w).filter(|&j| j < n) else {
                        continue;
                    };
                    let probed = sim.precond.stress_band[i * row_len + l];
                    let same_colour =
                        (0..n).filter(|&c| c.abs_diff(i) > w && c % colours == j % colours);
                    let folded: f64 = same_colour.clone().map(|c| dense[i * n + c]).sum();
                    let size: f64 = same_colour.map(|c| dense[i * n + c].abs()).sum();
                    let error = probed - dense[i * n + j];
                    assert!(
                        (error - folded).abs() <= 1e-10 * (size + dense[i * n + i].abs()),
                        "k = {k}, K_{i},{j}: probed {probed:e}, dense {:e}, folded {folded:e}",
                        dense[i * n + j]
                    );
                    worst = worst.max(error.abs());
                    largest = largest.max(dense[i * n + j].abs());
                }
            }
            // What the band misses (the preconditioner's approximation, not a test tolerance):
            // measured 0.14 (k = 0) and 0.020 (k = −0.5) of the largest entry at w = 5 with 12
            // colours (0.22 and 0.057 at w = 3 with 7), at the edge rows,
            // mostly from column 0 (the slope at the centre enters every slope through the
            // parabolic split of the profile transform).
            eprintln!("k = {k}: probed band vs dense K: {worst:e} of {largest:e}");
            let b = sim.rate.clone();
            let tight = KrylovParams {
                tolerance: 1e-12,
                ..KRYLOV
            };
            for factor in [1.0, 3.0, 10.0, 30.0] {
                let beta = ROS2_GAMMA * factor * dtau_explicit;
                sim.matrix.beta = beta;
                sim.precond.factor(beta);
                let mut plain = vec![0.0; n];
                let mut gmres = Gmres::new(n, 200);
                let wide = KrylovParams {
                    max_iterations: 5000,
                    restart: 200,
                    ..tight
                };
                let plain_info = gmres
                    .solve(&mut sim.matrix, &mut Identity(n), &b, &mut plain, &wide)
                    .unwrap();
                let mut preconditioned = vec![0.0; n];
                let info = gmres
                    .solve(
                        &mut sim.matrix,
                        &mut sim.precond,
                        &b,
                        &mut preconditioned,
                        &wide,
                    )
                    .unwrap();
                // Both residuals against W itself.
                for x in [&plain, &preconditioned] {
                    let mut wx = vec![0.0; n];
                    sim.matrix.apply(x, &mut wx).unwrap();
                    let r = wx.iter().zip(&b).map(|(a, c)| (a - c).powi(2)).sum::<f64>();
                    let bn = b.iter().map(|c| c * c).sum::<f64>();
                    assert!((r / bn).sqrt() < 1e-11);
                }
                let diff = max_abs(&plain, &preconditioned);
                let scale = plain.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                eprintln!(
                    "k = {k}, Δτ = {factor} × explicit: {} → {} iterations, |Δk| {diff:e} of {scale:e}",
                    plain_info.iterations, info.iterations
                );
                assert!(diff < 1e-9 * scale, "k = {k}: {diff:e} of {scale:e}");
                assert!(info.iterations < plain_info.iterations);
            }
        }
    }

    /// The prefix rate evaluation ([`FrettingSimulation::set_prefix_rate`]) against the whole
    /// grid's on a worn profile (k = 0 and −0.5, χ = 0.5, N = 401, to τ = 1): `g` on the prefix's
    /// computed nodes, the contact, the pressure and the rate equal to rounding, `g` beyond them
    /// a lower bound of the whole grid's and above `d + ε` (no node beyond touches), the whole
    /// grid's `g` from [`FrettingSimulation::equivalent_profile`]; a prefix too short for the
    /// gap's margin falls back to the whole grid.
    #[test]
    fn prefix_rate_matches_the_whole_grid() {
        for k in [0.0, -0.5] {
            let mut sim = FrettingSimulation::new(FrettingParams {
                nodes: 401,
                k,
                length: FrettingParams::default_length(0.5, k),
                tau_end: 1.0,
                snapshots: vec![1.0],
                ..FrettingParams::default()
            })
            .unwrap();
            sim.set_prefix_rate(false);
            sim.run(|_| false).unwrap();
            let n = sim.grid.len();
            let full = sim.contact_state_with(None).unwrap();
            let (g, p, rate) = (sim.g.clone(), sim.p.clone(), sim.rate.clone());
            sim.set_prefix_rate(true);
            let prefix = sim.contact_state_with(None).unwrap();
            let valid = sim.gap_valid;
            assert!(valid < n - 10, "k = {k}: prefix {valid} of {n}");
            assert_eq!(sim.rate_evaluations().1, 1);
            assert!(max_abs(&sim.g[..valid], &g[..valid]) < 1e-12);
            let closed = 1.0 + GAP_TOLERANCE * sim.grid.step();
            for (i, (bound, whole)) in sim.g.iter().zip(&g).enumerate().skip(valid) {
                assert!(
                    *bound <= whole + 1e-12 && *bound > closed,
                    "k = {k}, node {i}"
                );
            }
            assert_eq!(prefix.edge, full.edge);
            assert!((prefix.theta - full.theta).abs() < 1e-9);
            assert!((prefix.radii.touching - full.radii.touching).abs() < 1e-12);
            let p_max = p.iter().copied().fold(0.0, f64::max);
            assert!(max_abs(&sim.p, &p) < 1e-11 * p_max);
            assert!(max_abs(&sim.rate, &rate) < 1e-11 * p_max);
            sim.current = Some(prefix);
            let whole = sim.equivalent_profile().unwrap().to_vec();
            assert!(max_abs(&whole, &g) < 1e-12);
            // The prefix's computed nodes ending at the contact edge: refused (the worn part and
            // g < d + ε + 0.02 reach its end).
            sim.prefix_nodes = full.edge + 2;
            sim.contact_state_with(None).unwrap();
            assert_eq!(sim.gap_valid, n);
            assert_eq!(sim.rate_evaluations().1, 1);
        }
    }

    /// [`FrettingSimulation::run_with_mean_radii`] against the defining sum computed by hand on a
    /// twin run (explicit Euler, N = 201 to τ = 0.2: each step's touching radius, the trapezoid
    /// over the part of each window the steps cover, windows that cut steps), and its refusals.
    #[test]
    fn mean_radii_are_the_trapezoid_of_the_step_radii() {
        let params = FrettingParams {
            nodes: 201,
            tau_end: 0.2,
            stepping: TimeStepping::ExplicitEuler { dtau: 3e-3 },
            ..FrettingParams::default()
        };
        let windows = [(0.0, 0.2), (0.0101, 0.05), (0.1234, 0.1999)];
        let mut sim = FrettingSimulation::new(params.clone()).unwrap();
        let means = sim.run_with_mean_radii(&windows).unwrap();
        let mut twin = FrettingSimulation::new(params.clone()).unwrap();
        let mut samples = vec![(twin.tau(), twin.radii().unwrap().touching)];
        while !twin.is_finished() {
            twin.step().unwrap();
            samples.push((twin.tau(), twin.radii().unwrap().touching));
        }
        for (&(from, to), mean) in windows.iter().zip(&means) {
            // The polyline of the step radii clipped to the window (its ends interpolated),
            // integrated by the trapezoidal rule.
            let end = to.min(samples.last().unwrap().0);
            let at = |t: f64| {
                let n = samples.partition_point(|s| s.0 < t).max(1);
                let ((t0, a0), (t1, a1)) = (samples[n - 1], samples[n]);
                a0 + (a1 - a0) * (t - t0) / (t1 - t0)
            };
            let mut points = vec![(from, at(from))];
            points.extend(samples.iter().filter(|s| s.0 > from && s.0 < end));
            points.push((end, at(end)));
            let by_hand = points
                .windows(2)
                .map(|p| 0.5 * (p[0].1 + p[1].1) * (p[1].0 - p[0].0))
                .sum::<f64>()
                / (end - from);
            assert!(
                (mean - by_hand).abs() < 1e-12,
                "[{from}, {to}]: {mean} vs {by_hand}"
            );
        }
        // The run ends at 67 steps of 3e-3 = 0.201 ≥ τ_end; a window must start before that.
        let refused = |w: (f64, f64)| {
            let mut sim = FrettingSimulation::new(params.clone()).unwrap();
            matches!(
                sim.run_with_mean_radii(&[w]),
                Err(FrettingError::InvalidParameter { .. })
            )
        };
        assert!(refused((-0.1, 0.1)));
        assert!(refused((0.1, 0.1)));
        assert!(refused((0.1, 0.25)));
        assert!(refused((0.15, f64::NAN)));
    }

    /// [`prefix_rate_matches_the_whole_grid`] in the grazing end phase (τ = 30, k = 0 and −0.5,
    /// N = 401): the contact and the touching radius equal to rounding. (At N = 401 and 2001 the
    /// touching region ends at the edge's last node there, and the node two beyond the worn part
    /// has `g` 0.09 / 0.037 above `d` at k = 0: the worn-part condition, not the margin, bounds
    /// the prefix.)
    /// The margin on the unworn start (`w = 0`, `g = ξ`): a prefix whose last computed `g` lies
    /// within `PREFIX_GAP_MARGIN` of `d + ε` falls back to the whole grid, one beyond it does not.
    #[test]
    fn prefix_rate_matches_the_whole_grid_when_grazing() {
        for k in [0.0, -0.5] {
            let params = FrettingParams {
                nodes: 401,
                k,
                length: FrettingParams::default_length(0.5, k),
                tau_end: 30.0,
                snapshots: vec![30.0],
                ..FrettingParams::default()
            };
            let mut sim = FrettingSimulation::new(params.clone()).unwrap();
            sim.set_prefix_rate(false);
            sim.run(|_| false).unwrap();
            let n = sim.grid.len();
            let full = sim.contact_state_with(None).unwrap();
            let g = sim.g.clone();
            sim.set_prefix_rate(true);
            let prefix = sim.contact_state_with(None).unwrap();
            assert!(sim.gap_valid < n, "k = {k}: no prefix");
            assert!(max_abs(&sim.g[..sim.gap_valid], &g[..sim.gap_valid]) < 1e-12);
            if prefix.edge == full.edge {
                assert!((prefix.theta - full.theta).abs() < 1e-9);
            } else {
                // The edge follows the last node with g < d. Where a node sits within g's
                // rounding of d (an isolated grazing node at τ = 30), the two evaluations, whose g
                // agree to 1e-12 (asserted above, which is all that can be asked of the edge
                // there), may put the edge at different nodes. The touching radius, which takes
                // a tolerance, must not move (below).
                let decides = prefix.edge.max(full.edge) - 1;
                eprintln!(
                    "k = {k}: edges {} (prefix) and {} (whole grid); g − d at node {decides}: \
                     {:.1e} / {:.1e}",
                    prefix.edge,
                    full.edge,
                    sim.g[decides] - 1.0,
                    g[decides] - 1.0
                );
            }
            assert!(
                (prefix.radii.touching - full.radii.touching).abs() < 1e-12,
                "k = {k}: touching {} vs {}",
                prefix.radii.touching,
                full.radii.touching
            );
            // The unworn start: g = ξ (over d), so g_{V−1} = (L − 3) h.
            let mut start = FrettingSimulation::new(params).unwrap();
            start.set_prefix_rate(true);
            let h = start.grid.step();
            let closed = 1.0 + GAP_TOLERANCE * h;
            let inside = (0..n)
                .find(|&i| start.grid.squared(i) > closed + 0.25 * PREFIX_GAP_MARGIN)
                .unwrap();
            let beyond = (0..n)
                .find(|&i| start.grid.squared(i) > closed + 1.5 * PREFIX_GAP_MARGIN)
                .unwrap();
            for (last, kept) in [(inside, false), (beyond, true)] {
                start.prefix_nodes = last + 3;
                start.contact_state_with(None).unwrap();
                assert_eq!(
                    start.gap_valid < n,
                    kept,
                    "k = {k}, last computed node {last}"
                );
            }
        }
    }

    /// Whole adaptive runs with and without the preconditioner (docs/fretting-wear.md, "Adaptive
    /// runs that differ by rounding or by the stage solves"). GMRES stops at the adaptive stage
    /// tolerance (`solve`), so the two stage solutions differ by up to that tolerance from the
    /// first step and the runs are two step sequences at the step tolerance 1e-4. Asserted, at
    /// τ = 1 and 3:
    /// * both within 10 tol of a tight-tolerance reference (preconditioned, tol 1e-6) in f: the
    ///   global error of the adaptive runs, measured against tol 1e-7 at tol 1e-3 … 1e-6, is
    ///   0.3–6.6 tol (`stepping.rs::global_error_is_a_multiple_of_the_tolerance`, ignored);
    ///   here 3.2 tol (plain, k = −0.5, τ = 3), 1.4 tol preconditioned. Before the error
    ///   estimate included the wear of the nodes outside the start's contact, steps rounded to
    ///   `2^(j/16)` put the plain run 29 tol off there (1.9 tol with it);
    /// * the two within 5 tol of each other (measured 2.3e-4 at k = −0.5, 2.3e-5 at k = 0);
    /// * a/a₀ within 0.5 cell at τ = 1 (measured 0.11 cell) and 1.5 cells at τ = 3, in the
    ///   near-grazing phase: there g ≈ d over the annulus (the edge where g reaches d lies 4.6
    ///   cells apart between accurate runs), and the touching radius switches between the edge
    ///   (the first node outside within ε of closing) and the crossing of d + ε beyond it (a node
    ///   beyond the first one outside within ε), about one cell apart: runs at tol 1e-4 … 1e-7,
    ///   all accurate in f as above, spread over −0.50 … +0.51 cell around the 1e-7 run; the
    ///   plain and preconditioned runs here were on the two sides (1.00 cell apart) before the
    ///   quantized step; now 0.06 cell.
    #[test]
    fn preconditioned_runs_match_unpreconditioned() {
        let tolerance = 1e-4;
        for k in [0.0, -0.5] {
            let params = FrettingParams {
                nodes: 401,
                k,
                length: FrettingParams::default_length(0.5, k),
                tau_end: 3.0,
                snapshots: vec![1.0, 3.0],
                ..FrettingParams::default()
            };
            let run = |precondition: bool, tolerance: f64| {
                let mut sim = FrettingSimulation::new(FrettingParams {
                    stepping: TimeStepping::Adaptive { tolerance },
                    ..params.clone()
                })
                .unwrap();
                sim.precondition = precondition;
                sim.run(|_| false).unwrap();
                sim
            };
            let (plain, preconditioned) = (run(false, tolerance), run(true, tolerance));
            let reference = run(true, 1e-6);
            let cell = plain.grid.step() / (2.0 * plain.r_star);
            for ((a, b), r) in plain
                .state
                .snapshots
                .iter()
                .zip(&preconditioned.state.snapshots)
                .zip(&reference.state.snapshots)
            {
                let (fa, fb) = (
                    max_abs(&a.profile, &r.profile),
                    max_abs(&b.profile, &r.profile),
                );
                let df = max_abs(&a.profile, &b.profile);
                let da = (a.contact_radius - b.contact_radius).abs() / cell;
                eprintln!(
                    "k = {k}, τ = {}: steps {} / {}; |f − f_ref| {fa:.2e} / {fb:.2e}; apart {df:.2e}, {da:.2} cells; iterations {} → {}",
                    a.tau,
                    a.step,
                    b.step,
                    plain.krylov_iterations,
                    preconditioned.krylov_iterations
                );
                assert!(
                    fa < 10.0 * tolerance,
                    "k = {k}, τ = {}: plain {fa:e}",
                    a.tau
                );
                assert!(
                    fb < 10.0 * tolerance,
                    "k = {k}, τ = {}: preconditioned {fb:e}",
                    a.tau
                );
                assert!(df < 5.0 * tolerance, "k = {k}, τ = {}: {df:e}", a.tau);
                let bound = if a.tau < 2.0 { 0.5 } else { 1.5 };
                assert!(da < bound, "k = {k}, τ = {}: {da} cells", a.tau);
            }
            assert!(preconditioned.krylov_iterations < plain.krylov_iterations);
        }
    }

    /// The second stage in the first stage's Krylov space
    /// ([`FrettingSimulation::set_recycled_second_stage`]) against the stages solved on their own,
    /// N = 401, χ = 0.5, k = 0 and −0.5, τ = 1 and 3, tol 1e-4, each from the unperturbed start
    /// and three starts perturbed at 1e-13 (other step sequences, as other roundings give:
    /// docs/fretting-wear.md, "The grazing-phase stepping tests over perturbed step sequences";
    /// a single sequence's touching radius at one instant is not bounded by the tolerance — at
    /// k = −0.5, τ = 3 one recycled start's snapshot radius lands 3.7 cells from the references'):
    /// the medians over the starts of the profile error against a tol-1e-6 run within 10 tol
    /// (`GLOBAL_ERROR` of tests/stepping.rs) and of the radius, as its mean over the windows
    /// [0.9, 1] and [2.9, 3] ([`FrettingSimulation::run_with_mean_radii`]), within half a cell of
    /// the tol-1e-6 runs' median mean radius over the same four starts (the bound
    /// of `preconditioned_runs_match_unpreconditioned` at τ = 1), for both, and fewer GMRES
    /// iterations summed over the starts with the recycled space. Not "as accurate": measured
    /// at k = −0.5, τ = 3 the recycled median is 2.97 tol against 1.23 (all four starts larger),
    /// which this bound lets pass (docs/performance.md, "The second stage started from the first
    /// stage's Krylov space"); the switch is off by default.
    #[test]
    fn recycled_second_stage_stays_within_the_error_bound_over_perturbed_starts() {
        let tolerance = 1e-4;
        let median = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            0.5 * (v[(v.len() - 1) / 2] + v[v.len() / 2])
        };
        for k in [0.0, -0.5] {
            let params = |tolerance: f64| FrettingParams {
                nodes: 401,
                k,
                length: FrettingParams::default_length(0.5, k),
                tau_end: 3.0,
                snapshots: vec![1.0, 3.0],
                stepping: TimeStepping::Adaptive { tolerance },
                // The switch was measured on the central differences' nodal rate.
                gap_transform: GapTransform::CentralDifferences,
                edge_cells: false,
                ..FrettingParams::default()
            };
            let start = |tolerance: f64, seed: u64| {
                let mut sim = FrettingSimulation::new(params(tolerance)).unwrap();
                if seed > 0 {
                    let mut state = sim.state().clone();
                    let mut x = seed.wrapping_mul(6_364_136_223_846_793_005);
                    for f in &mut state.profile {
                        x = x
                            .wrapping_mul(6_364_136_223_846_793_005)
                            .wrapping_add(1_442_695_040_888_963_407);
                        let u = (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
                        *f *= 1.0 + 1e-13 * u;
                    }
                    sim = FrettingSimulation::resume(params(tolerance), state).unwrap();
                }
                sim
            };
            // The reference radius: the median of the tol-1e-6 runs from the same four starts.
            // One tol-1e-6 sequence's snapshot radius is not the converged one to half a cell:
            // at k = −0.5, τ = 1 the four reference starts ended up to 0.55 cell apart (two
            // sub-cell positions of the edge; docs/performance.md, "The N = 8001 wear run: the
            // prefix rate by default (issue 20)"); their window means spread by ≤ 0.04 cell.
            // The radius as its mean over a window ending at each snapshot
            // (`run_with_mean_radii`): at k = −0.5 the edge goes back and forth among the nodes
            // of an annulus, and the radius at one instant lands up to 3.7 cells from the
            // references' on one start.
            let windows = [(0.9, 1.0), (2.9, 3.0)];
            let (references, reference_means): (Vec<FrettingSimulation>, Vec<Vec<f64>>) = (0..4u64)
                .map(|seed| {
                    let mut sim = start(1e-6, seed);
                    let means = sim.run_with_mean_radii(&windows).unwrap();
                    (sim, means)
                })
                .unzip();
            let reference = &references[0];
            let reference_radii: Vec<f64> = (0..2)
                .map(|i| median(reference_means.iter().map(|m| m[i]).collect()))
                .collect();
            let cell = reference.grid.step() / (2.0 * reference.r_star);
            for (i, middle) in reference_radii.iter().enumerate() {
                let spread: Vec<f64> = reference_means
                    .iter()
                    .map(|m| (m[i] - middle) / cell)
                    .collect();
                eprintln!(
                    "k = {k}, τ = {}: tol-1e-6 mean radii about their median {spread:.2?} cells",
                    reference.state.snapshots[i].tau
                );
            }
            for recycled in [true, false] {
                let (mut errors, mut radii, mut iterations) =
                    ([vec![], vec![]], [vec![], vec![]], 0);
                for seed in 0..4u64 {
                    let mut sim = start(tolerance, seed);
                    sim.set_recycled_second_stage(recycled);
                    let means = sim.run_with_mean_radii(&windows).unwrap();
                    iterations += sim.krylov_iterations;
                    for (i, (s, r)) in sim
                        .state
                        .snapshots
                        .iter()
                        .zip(&reference.state.snapshots)
                        .enumerate()
                    {
                        errors[i].push(max_abs(&s.profile, &r.profile) / tolerance);
                        radii[i].push((means[i] - reference_radii[i]).abs() / cell);
                    }
                }
                for i in 0..2 {
                    let (e, a) = (median(errors[i].clone()), median(radii[i].clone()));
                    eprintln!(
                        "k = {k}, recycled {recycled}, τ = {}: profile errors {:.2?} tol (median {e:.2}), radii {:.2?} cells (median {a:.2}); {iterations} GMRES iterations",
                        reference.state.snapshots[i].tau, errors[i], radii[i]
                    );
                    assert!(e < 10.0, "k = {k}, recycled {recycled}: {e} tol");
                    assert!(a < 0.5, "k = {k}, recycled {recycled}: {a} cells");
                }
                if recycled {
                    ITERATIONS.with(|c| c.set(iterations));
                } else {
                    let with = ITERATIONS.with(std::cell::Cell::get);
                    assert!(with < iterations, "k = {k}: {with} against {iterations}");
                }
            }
        }
    }

    thread_local! {
        static ITERATIONS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
    }

    /// The edge cells ([`edge_cell_means`]) against a direct quadrature of the cell mean of
    /// `p = P(a² − ξ)^γ` (π constant, the form at the edge; exact for Hertz), for edges across
    /// a whole cell, and continuous as the edge crosses a node (where the node-sampled pressure
    /// jumps on like `(a² − ξ)^γ`).
    #[test]
    fn edge_cell_means_integrate_the_edge_pressure() {
        let grid = SquaredGrid::new(201, 1.6).unwrap();
        let n = grid.len();
        let h = grid.step();
        for k in [-0.5, 0.0, 0.5] {
            let gamma = 0.5 * (1.0 + k);
            let (mut shape, mut mean) = (vec![0.0; n], vec![0.0; n]);
            let mut sigma = vec![0.0; n];
            // Edge from just past node 120 to node 121, then just past 121.
            let mut previous: Option<Vec<f64>> = None;
            for (last, theta) in [
                (120, 1e-9),
                (120, 0.1),
                (120, 0.5),
                (120, 0.9),
                (120, 1.0),
                (121, 1e-9),
            ] {
                let a2 = grid.squared(last) + theta * h;
                for (j, s) in sigma.iter_mut().enumerate() {
                    *s = if j <= last {
                        2.0 * (a2 - grid.squared(j)).powf(gamma)
                    } else {
                        0.0
                    };
                }
                let range = edge_cell_means(
                    &grid,
                    gamma,
                    &sigma,
                    (last, theta),
                    8,
                    &mut shape,
                    &mut mean,
                );
                for j in range.clone() {
                    // Midpoint rule on 20 000 sub-cells of the cell ∩ [0, a²].
                    let (lo, hi) = (
                        grid.squared(j) - 0.5 * h,
                        (grid.squared(j) + 0.5 * h).min(a2),
                    );
                    let m = 20_000;
                    let exact = if hi > lo {
                        let dx = (hi - lo) / m as f64;
                        (0..m)
                            .map(|i| 2.0 * (a2 - (lo + (i as f64 + 0.5) * dx)).powf(gamma) * dx)
                            .sum::<f64>()
                            / h
                    } else {
                        0.0
                    };
                    assert!(
                        (mean[j] - exact).abs() < 2e-5 * 2.0 * h.powf(gamma),
                        "k = {k}, last {last}, θ {theta}, node {j}: {} vs {exact}",
                        mean[j]
                    );
                }
                // Continuity across the crossing of node 121: θ = 1 at 120 and θ → 0 at 121.
                let current: Vec<f64> = (110..123).map(|j| mean[j]).collect();
                if let (Some(p), true) = (&previous, last == 121) {
                    let jump = max_abs(p, &current);
                    assert!(jump < 1e-6, "k = {k}: jump {jump:e} at the crossing");
                }
                previous = Some(current);
            }
        }
    }

    /// The last node of a grazing annulus (no load inside, rounding-level stresses of either sign
    /// there; the last node loaded by its edge cell): its cell mean is the one of its own `π`
    /// times `c min(θ/θ₀, 1)` ([`OWN_FLOOR`]), whatever the sign of the rounding inside — the rule before took
    /// the extrapolation from the nodes inside (≈ 0) as soon as the rounding made it positive,
    /// and the adaptive runs stalled there (docs/fretting-wear.md, "The edge cells' stall") —
    /// and it is continuous in θ through `θ₀` and in the stresses inside.
    #[test]
    fn a_loaded_last_node_beyond_an_unloaded_inside_wears() {
        let grid = SquaredGrid::new(501, 1.78).unwrap();
        let n = grid.len();
        let h = grid.step();
        let (last, gamma) = (374, 0.25);
        // Rounding inside: its size and the factor on the odd nodes (`L − 1` is odd): 0.7 makes
        // the extrapolation `2π_{L−1} − π_{L−2}` positive, 0.3 negative.
        let own_mean = |theta: f64, (noise, odd): (f64, f64)| {
            let mut sigma = vec![0.0; n];
            for (j, s) in sigma.iter_mut().enumerate().take(last) {
                // Stick zone loaded, the annulus from node 300 on at rounding level.
                *s = if j < 300 {
                    1.0
                } else {
                    noise * if j % 2 == 0 { 1.0 } else { odd }
                };
            }
            sigma[last] = 2.12;
            let (mut shape, mut mean) = (vec![0.0; n], vec![0.0; n]);
            edge_cell_means(
                &grid,
                gamma,
                &sigma,
                (last, theta),
                16,
                &mut shape,
                &mut mean,
            );
            (shape[last], mean[last])
        };
        for theta in [0.05, 0.237, 0.5, 0.9] {
            let own = 2.12 / (theta * h).powf(gamma);
            // The inside extrapolates to ~0: the blend's share of `own`, or the floor.
            let blend = ((theta - BLEND.0) / (BLEND.1 - BLEND.0)).clamp(0.0, 1.0);
            let floor = (blend * own).max(OWN_FLOOR * (theta / BLEND.0).min(1.0) * own);
            let means: Vec<(f64, f64)> = [
                (-1e-11, 0.7),
                (0.0, 0.7),
                (8e-12, 0.7),
                (1e-11, 0.7),
                (1e-11, 0.3),
            ]
            .into_iter()
            .map(|rounding| own_mean(theta, rounding))
            .collect();
            for &(shape, mean) in &means {
                // π_L within rounding of that (the extrapolation inside is ~1e-12 of it).
                assert!(
                    (shape - floor).abs() <= 1e-8 * floor,
                    "θ {theta}: π_L {shape} vs floor {floor}"
                );
                assert!(mean > 0.0);
                // Continuity in the stresses inside: rounding there moves the mean by rounding.
                assert!(
                    (mean - means[1].1).abs() <= 1e-8 * means[1].1,
                    "θ {theta}: {mean}"
                );
            }
        }
        // Continuity in θ through θ₀: the two sides of BLEND.0 give the same π_L.
        let (below, above) = (
            own_mean(BLEND.0 - 1e-9, (1e-11, 0.7)).0,
            own_mean(BLEND.0 + 1e-9, (1e-11, 0.7)).0,
        );
        assert!((below - above).abs() <= 1e-6 * above, "{below} vs {above}");
    }

    /// An attempt whose first stage fails (GMRES on a non-finite right-hand side) leaves none of
    /// the previous attempt's diagnostics in [`StepAttempt`] (`adaptive_step` reports such an
    /// attempt to the observer with ratio ∞): projection 1, not first-order, no error terms, no
    /// opened holes.
    #[test]
    fn failed_attempt_reports_no_stale_diagnostics() {
        let mut sim = FrettingSimulation::new(FrettingParams {
            nodes: 201,
            tau_end: 0.1,
            ..FrettingParams::default()
        })
        .unwrap();
        sim.step().unwrap();
        let contact = sim.contact().unwrap();
        sim.linearize(contact).unwrap();
        sim.attempt.projection = 0.25;
        sim.attempt.first_order = true;
        sim.attempt.error_terms = [1.0, 2.0, 3.0];
        sim.attempt.opened_holes = 7;
        sim.rate.fill(f64::NAN);
        assert!(sim.ros2_attempt(1e-3).is_err());
        assert_eq!(sim.attempt.projection, 1.0);
        assert!(!sim.attempt.first_order);
        assert_eq!(sim.attempt.error_terms, [0.0; 3]);
        assert_eq!(sim.attempt.opened_holes, 0);
    }

    /// The projection onto the closed set ([`hole_projection`]) relies on `g` being linear in the
    /// profile: `g(f₁ + λ(f₂ − f₁)) = g₁ + λ(g₂ − g₁)`, checked to rounding on the profile of a
    /// graded run in its phase with holes (k = −0.5, χ = 0.9, N = 501, τ = 0.5) and that profile
    /// plus a bump; and `λ` keeps every hole closed and ignores the nodes that are not holes.
    /// A graded run (k = −0.5, χ = 0.9, N = 501) stepped to τ = 0.5, in its phase with holes.
    fn graded_phase_with_holes() -> FrettingSimulation {
        let (k, chi) = (-0.5, 0.9);
        let params = FrettingParams {
            nodes: 501,
            k,
            chi,
            length: FrettingParams::default_length(chi, k),
            tau_end: 0.5,
            snapshots: vec![],
            ..FrettingParams::default()
        };
        let mut sim = FrettingSimulation::new(params).unwrap();
        sim.run(|_| false).unwrap();
        sim
    }

    #[test]
    fn hole_projection_keeps_the_opened_nodes_closed() {
        let mut sim = graded_phase_with_holes();
        let f1 = sim.state.profile.clone();
        let g1 = sim.equivalent_profile().unwrap().to_vec();
        // A second profile: f₁ plus a wear-like bump over the annulus.
        let f2: Vec<f64> = f1
            .iter()
            .enumerate()
            .map(|(i, f)| f + 1e-3 * ((i as f64) * 0.37).sin().abs())
            .collect();
        sim.state.profile.copy_from_slice(&f2);
        sim.current = None;
        let g2 = sim.equivalent_profile().unwrap().to_vec();
        let scale = g1.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for lambda in [0.0, 0.3, 0.71, 1.0] {
            for ((f, a), b) in sim.state.profile.iter_mut().zip(&f1).zip(&f2) {
                *f = a + lambda * (b - a);
            }
            sim.current = None;
            let g = sim.equivalent_profile().unwrap().to_vec();
            let blend: Vec<f64> = g1
                .iter()
                .zip(&g2)
                .map(|(a, b)| a + lambda * (b - a))
                .collect();
            let d = max_abs(&g, &blend);
            assert!(d < 1e-12 * scale, "λ = {lambda}: {d:e}");
        }
        // λ on made-up gaps: nodes 2 and 4 open in g₂ and closed in g₁ (holes), node 3 open in
        // both (not a hole), node 5 closed in g₂ (the last contact node), node 1 opened by g₁.
        let g1 = [0.5, 1.2, 0.9, 1.1, 0.99, 0.5, 1.5];
        let g2 = [0.5, 0.8, 1.3, 1.2, 1.01, 0.9, 1.5];
        let lambda = hole_projection(1, &g2, &g1);
        let expected = (1.0 - HOLE_MARGIN) * (0.1f64 / 0.4).min(0.01 / 0.02);
        assert!((lambda - expected).abs() < 1e-15, "{lambda} vs {expected}");
        for i in [2, 4] {
            assert!(g1[i] + lambda * (g2[i] - g1[i]) < 1.0, "node {i}");
        }
        // No hole: no projection.
        assert_eq!(hole_projection(1, &g1, &g1), 1.0);
    }

    /// The sliding mode's pieces (docs/fretting-wear.md, "The sliding mode in the stages"),
    /// graded k = −0.5, χ = 0.9, N = 501 from τ = 0.5, at the first step start whose last contact
    /// node slides: the band of `G = P D` from its columns against finite differences of `g`
    /// (the dense twin: `g` is linear in `f`, so the differences are exact to rounding); the
    /// stages' constraint row `(W x)_s = (G x)_s/G_ss` against the same; and an attempt's result
    /// on the surface, `g_s = g*`, to the stage solves' tolerance (GMRES stops at a residual of
    /// `0.01 tol` in `f`, so `|c| ≲ 0.01 tol G_ss` in `g`; asserted 10 times that).
    #[test]
    fn sliding_node_is_held_on_the_surface() {
        let (k, chi) = (-0.5, 0.9);
        let tolerance = TimeStepping::DEFAULT_TOLERANCE;
        let params = FrettingParams {
            nodes: 501,
            k,
            chi,
            length: FrettingParams::default_length(chi, k),
            tau_end: 3.0,
            snapshots: vec![],
            stepping: TimeStepping::Adaptive { tolerance },
            // The sliding mode was built and measured on the central differences' nodal rate.
            gap_transform: GapTransform::CentralDifferences,
            edge_cells: false,
            ..FrettingParams::default()
        };
        let mut sim = FrettingSimulation::new(params).unwrap();
        sim.set_sliding_edge(true);
        sim.run(|s| s.tau() >= 0.5).unwrap();
        let (w, n) = (PRECONDITIONER_WIDTH, sim.grid.len());
        let mut found = None;
        for _ in 0..2000 {
            let contact = sim.contact().unwrap();
            sim.linearize(contact).unwrap();
            if let Some(c) = sim
                .slide_candidate
                .filter(|c| c.approach > 0.0 && c.approach.is_finite())
            {
                found = Some(c);
                break;
            }
            sim.step().unwrap();
        }
        let slide = found.expect("a sliding node off the surface within 2000 steps");
        let s = slide.node;
        let f0 = sim.state.profile.clone();
        let g0 = sim.equivalent_profile().unwrap().to_vec();
        // The band of G against finite differences (G is linear: exact to rounding).
        let eps = 1e-6;
        let mut worst = 0.0f64;
        let largest = (s - w..=s + w)
            .map(|j| sim.gap_band[s * (2 * w + 1) + (j + w - s)].abs())
            .fold(0.0, f64::max);
        for j in s - w..=s + w {
            sim.state.profile.copy_from_slice(&f0);
            sim.state.profile[j] += eps;
            sim.current = None;
            let g = sim.equivalent_profile().unwrap().to_vec();
            for i in j.saturating_sub(w)..=(j + w).min(n - 1) {
                let fd = (g[i] - g0[i]) / eps;
                worst = worst.max((fd - sim.gap_band[i * (2 * w + 1) + (j + w - i)]).abs());
            }
        }
        println!(
            "G band: G_ss {:.4e}, largest {largest:.3e}, |FD − band| {worst:.2e}",
            slide.self_gap
        );
        assert!(worst < 1e-6 * largest, "{worst:e} of {largest:e}");
        // The operator's row s against (G x)_s/G_ss by finite differences.
        let x: Vec<f64> = (0..n)
            .map(|i| {
                if i < sim.matrix.support() {
                    ((i as f64) * 0.73).sin()
                } else {
                    0.0
                }
            })
            .collect();
        sim.state.profile.copy_from_slice(&f0);
        for (f, v) in sim.state.profile.iter_mut().zip(&x) {
            *f += eps * v;
        }
        sim.current = None;
        let gx = (sim.equivalent_profile().unwrap()[s] - g0[s]) / eps;
        sim.state.profile.copy_from_slice(&f0);
        sim.current = None;
        let contact = sim.contact().unwrap();
        sim.linearize(contact).unwrap();
        let slide = sim.slide_candidate.unwrap();
        let dtau = 2.0 * slide.approach / SLIDING_REACH;
        sim.matrix.beta = ROS2_GAMMA * dtau;
        sim.set_sliding_for(dtau);
        assert_eq!(sim.sliding.map(|s| s.node), Some(s));
        let mut y = vec![0.0; n];
        sim.matrix.apply(&x, &mut y).unwrap();
        let row = gx / slide.self_gap;
        println!("row s = {s}: W x {:.6e}, (G x)_s/G_ss {row:.6e}", y[s]);
        assert!(
            (y[s] - row).abs() < 1e-6 * row.abs().max(1.0),
            "{} vs {row}",
            y[s]
        );
        // The preconditioner's row s is G's band over G_ss (the dense twin: the band checked
        // above): for y = M⁻¹x, Σ_j M_sj y_j = x_s.
        sim.precond.factor(sim.matrix.beta);
        assert!(sim.precond.is_factored());
        let mut z = vec![0.0; n];
        sim.precond.apply(&x, &mut z).unwrap();
        let row_dot: f64 = (s - w..=s + w)
            .map(|j| sim.gap_band[s * (2 * w + 1) + (j + w - s)] / slide.self_gap * z[j])
            .sum();
        println!(
            "preconditioner row s: Σ M_sj (M⁻¹x)_j {row_dot:.12e}, x_s {:.12e}",
            x[s]
        );
        assert!((row_dot - x[s]).abs() < 1e-10 * x[s].abs().max(1.0));
        // An attempt lands on the surface: the first one, from here on, that holds its node and
        // is neither projected onto the closed set nor failed (at the shortest step that holds
        // the node, `approach/SLIDING_REACH`).
        let mut checked = false;
        for _ in 0..2000 {
            if let Some(slide) = sim
                .slide_candidate
                .filter(|c| c.approach > 0.0 && c.approach.is_finite())
            {
                let dtau = 1.01 * slide.approach / SLIDING_REACH;
                let c0 = sim.g[slide.node] - slide.target;
                let held = sim.ros2_attempt(dtau).is_ok()
                    && sim.attempt.sliding_node == Some(slide.node)
                    && sim.attempt.projection == 1.0;
                if held {
                    let c = sim.g[slide.node] - slide.target;
                    println!(
                        "attempt Δτ {dtau:.3e} at τ {:.4}: c(f) {c0:.3e} → {c:.3e} (bound {:.3e})",
                        sim.tau(),
                        0.01 * tolerance * slide.self_gap
                    );
                    // Measured c(f) −2.7e-3 → −8.9e-7 at τ = 0.504; the bound is the stage
                    // solves' tolerance (0.01 tol in f) in g.
                    assert!(c.abs() < 0.01 * tolerance * slide.self_gap, "c = {c:e}");
                    assert!(c.abs() < 0.05 * c0.abs(), "c = {c:e} from {c0:e}");
                    checked = true;
                    break;
                }
                sim.restore_start().unwrap();
            }
            sim.step().unwrap();
            let contact = sim.contact().unwrap();
            sim.linearize(contact).unwrap();
        }
        assert!(checked, "no held, unprojected attempt within 2000 steps");
    }

    fn max_abs(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
    }

    /// The Jacobian of the rate at a frozen contact (`linearization`) against central differences
    /// of the rate itself, for a smooth direction `v` vanishing near the contact edge (so that the
    /// edge and the clipping pattern do not move).
    #[test]
    fn rate_jacobian_matches_central_differences() {
        let cases = [0.0, -0.5, 0.5].into_iter().flat_map(|k| {
            [
                GapTransform::CentralDifferences,
                GapTransform::PiecewiseLinear,
            ]
            .map(|t| (k, t))
        });
        for (k, gap_transform) in cases {
            let length = FrettingParams::default_length(0.5, k);
            let params = FrettingParams {
                nodes: 801,
                k,
                length,
                stepping: TimeStepping::ExplicitEuler {
                    dtau: FrettingParams::default_step(801, length, k)
                        * gap_transform.explicit_step_factor(),
                },
                tau_end: 0.2,
                snapshots: vec![],
                gap_transform,
                // The nodal rate (the edge cells' rows keep the nodal form in J by design).
                edge_cells: false,
                ..FrettingParams::default()
            };
            let (mut sim, contact) = run_and_linearize(params);
            let n = sim.grid.len();
            let a2 = sim.grid.squared(contact.edge - 1);
            let c2 = sim.stick * sim.stick;
            // A bump on (c² + 0.05, a² − 0.05) in ξ.
            let v: Vec<f64> = (0..n)
                .map(|i| {
                    let xi = sim.grid.squared(i);
                    let (lo, hi) = (c2 + 0.05, a2 - 0.05);
                    if xi > lo && xi < hi {
                        let t = (xi - lo) / (hi - lo);
                        (std::f64::consts::PI * t).sin().powi(3)
                    } else {
                        0.0
                    }
                })
                .collect();
            let mut jv = vec![0.0; n];
            sim.matrix.jacobian(&v, &mut jv).unwrap();
            let base = sim.start.clone();
            let sigma = sim.sigma.clone();
            let sigma_max = sigma.iter().fold(0.0f64, |m, x| m.max(*x));
            // The last contact node's rate is strongly curved in f (its stress goes like θ^γ):
            // the central difference's truncation (∝ ε²) at ε = 1e-6 reached 1e-4 of the scale
            // with the piecewise-linear transform at k = −0.5 (1.8e-2 of 170; 2.4e-4 at 1e-7).
            let eps = 1e-7;
            let mut rate_at = |sign: f64| {
                for ((f, b), vi) in sim.state.profile.iter_mut().zip(&base).zip(&v) {
                    *f = b + sign * eps * vi;
                }
                sim.current = None;
                let c = sim.contact().unwrap();
                assert_eq!((c.edge, c.theta.to_bits() != 0), (contact.edge, true));
                sim.rate.clone()
            };
            let plus = rate_at(1.0);
            let minus = rate_at(-1.0);
            let scale = jv.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            // The rate is differentiable where the clipping of p does not switch: rows with
            // |σ| > 1e-3 max σ. (J linearizes the nodal rate; with the edge cells
            // it keeps that form on their rows, docs/fretting-wear.md, "Edge cells".)
            let worst = (0..contact.edge)
                .filter(|&i| sigma[i].abs() > 1e-3 * sigma_max)
                .map(|i| ((plus[i] - minus[i]) / (2.0 * eps) - jv[i]).abs())
                .fold(0.0, f64::max);
            eprintln!("k = {k}, {gap_transform:?}: |J v − FD| {worst:e} of {scale:e}");
            // Measured at ε = 1e-7: 4e-8 (k = 0), 6e-8 (k = 0.5) and 8e-8 (k = −0.5) of the
            // largest entry; with the piecewise-linear transform 2.2e-6, 7.1e-6 and 1.4e-6 (the
            // rounding's `ε_mach/ε` shows there).
            assert!(scale > 0.0);
            assert!(
                worst < 1e-4 * scale,
                "k = {k}, {gap_transform:?}: |J v − FD| = {worst:e} of {scale:e}"
            );
        }
    }

    /// A run of `params` to its end, linearized at its last state (the frozen contact returned).
    fn run_and_linearize(params: FrettingParams) -> (FrettingSimulation, Contact) {
        let mut sim = FrettingSimulation::new(params).unwrap();
        sim.run(|_| false).unwrap();
        let contact = sim.contact().unwrap();
        sim.linearize(contact).unwrap();
        (sim, contact)
    }

    /// The stage products `W x` by `f32` transforms ([`FrettingSimulation::set_single_precision_products`])
    /// against the `f64` ones at the frozen state of adaptive runs to τ = 3 (k = 0 at N = 2001 and
    /// 8001, k = −0.5 at N = 2001; seeded random, smooth and stage vectors): within 1e-5 of
    /// `‖W x‖₂` (measured ≤ 1.2e-6; differencing the profile transform's sums in `f32` instead of
    /// convolving their increments gave 5e-3). A stage `W k = b` solved by GMRES with the `f32`
    /// products to [`SINGLE_PRECISION_FROM`] satisfies the `f64` `W` to that tolerance plus 2e-5
    /// (the products' error times `‖W‖ ‖k‖/‖b‖`; measured: the residual below 1e-4), which a
    /// product wrong by 1e-3 would not.
    #[test]
    fn single_precision_products_are_the_double_ones_to_their_rounding() {
        for (n, k) in [(2001usize, 0.0), (2001, -0.5), (8001, 0.0)] {
            let length = FrettingParams::default_length(0.5, k);
            let params = FrettingParams {
                nodes: n,
                k,
                length,
                tau_end: 3.0,
                snapshots: vec![],
                ..FrettingParams::default()
            };
            let (mut sim, _) = run_and_linearize(params);
            let beta = ROS2_GAMMA * 1e-2;
            sim.matrix.beta = beta;
            sim.precond.factor(beta);
            let m = sim.matrix.contact_nodes();
            let random = halfspace_numerics::testkit::lcg(12345, n);
            let smooth: Vec<f64> = (0..n)
                .map(|i| {
                    if i < m {
                        (7.0 * i as f64 / m as f64).sin()
                    } else {
                        0.0
                    }
                })
                .collect();
            let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
            for (name, v) in [
                ("random", random),
                ("smooth", smooth),
                ("k1", sim.k1.clone()),
            ] {
                let (mut w64, mut w32) = (vec![0.0; n], vec![0.0; n]);
                sim.matrix.apply(&v, &mut w64).unwrap();
                sim.matrix.set_precision(Precision::Single).unwrap();
                sim.matrix.apply(&v, &mut w32).unwrap();
                sim.matrix.set_precision(Precision::Double).unwrap();
                let error = norm(&w64.iter().zip(&w32).map(|(a, c)| a - c).collect::<Vec<_>>());
                eprintln!(
                    "N = {n}, k = {k}, {name}: ‖W₃₂x − W₆₄x‖ {:.2e} of ‖W₆₄x‖",
                    error / norm(&w64)
                );
                assert!(error <= 1e-5 * norm(&w64), "N = {n}, k = {k}, {name}");
                assert!(error > 1e-12 * norm(&w64), "the f32 path was not taken");
                let mut again = vec![0.0; n];
                sim.matrix.apply(&v, &mut again).unwrap();
                assert!(again
                    .iter()
                    .zip(&w64)
                    .all(|(a, c)| a.to_bits() == c.to_bits()));
            }
            let b = sim.rate.clone();
            let params = KrylovParams {
                tolerance: SINGLE_PRECISION_FROM,
                ..KRYLOV
            };
            let mut gmres = Gmres::new(n, KRYLOV.restart);
            gmres.confirm_residual(false);
            let mut x = vec![0.0; n];
            sim.matrix.set_precision(Precision::Single).unwrap();
            let info = gmres
                .solve(&mut sim.matrix, &mut sim.precond, &b, &mut x, &params)
                .unwrap();
            sim.matrix.set_precision(Precision::Double).unwrap();
            let mut wx = vec![0.0; n];
            sim.matrix.apply(&x, &mut wx).unwrap();
            let residual =
                norm(&wx.iter().zip(&b).map(|(a, c)| a - c).collect::<Vec<_>>()) / norm(&b);
            eprintln!(
                "N = {n}, k = {k}: f32 stage, {} iterations, f64 residual {residual:.2e}",
                info.iterations
            );
            assert!(
                residual <= SINGLE_PRECISION_FROM + 2e-5,
                "N = {n}, k = {k}: {residual:e}"
            );
        }
    }
}
