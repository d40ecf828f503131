//! Fretting wear of an axisymmetric contact on the MDR (Willert 2021, Section 4; docs/theory-mdr.md#fretting-wear).
//!
//! A paraboloid pressed to a fixed depth `d` (`a₀ = √(Rd)`) oscillates tangentially with amplitude
//! `u_A = χ u_max` in partial slip; Archard wear removes material where it slips. In the normalized
//! variables `r̃ = r/a₀`, `f̃ = f/d`, `p̃ = p a₀²/F₀`, `Δũ = Δu/u_A`, `τ = N/N₀` the wear law is
//! parameter-free: `∂f̃/∂τ = p̃ Δũ` (Eq. 30–31). Each step (one wear increment `Δτ`):
//! `f → g` (Eq. 7), contact edge (docs/theory-mdr.md#p9-contact-radius-of-a-worn-profile), `q → p` (Eq. 17), slip (Cattaneo–Mindlin in MDR form),
//! ROS2 (linearly implicit, error-controlled) or explicit Euler. [`limit`] has the closed forms: Popov's limiting profile `f̃∞`, the limiting
//! contact radius `r*`, the Hertz slip.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod checkpoint;
mod error;
pub mod limit;
mod linearization;
mod params;
mod simulation;
pub mod studies;

pub use error::FrettingError;
pub use params::{FrettingParams, GapTransform, TimeStepping};
pub use simulation::{
    AttemptObserver, ContactRadii, FrettingSimulation, FrettingState, Snapshot, StepAttempt,
    ADAPTIVE_SCHEME, EDGE_CELL_RULE, EULER_SCHEME, FIXED_STEP_SCHEME, GAP_TOLERANCE,
    LOAD_THRESHOLD, SINGLE_PRECISION_FROM, SLIDING_EDGE_SCHEME,
};
