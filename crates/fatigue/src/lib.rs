//! Multiaxial fatigue criteria of one steady stress cycle (docs/fatigue.md):
//!
//! - stress-invariant criteria on the minimum enclosing ball of the deviatoric path
//!   ([`ball`]): Crossland (1956) and Dang Van (1989) in [`invariant`];
//! - critical-plane criteria: Smith–Watson–Topper (1970) and Fatemi–Socie (1988) in
//!   [`critical_plane`];
//! - all four over the stress histories of many points in [`field`];
//! - all four on the histories averaged over a process volume in [`process_volume`].
//!
//! A stress path is a slice of Voigt tensors `[σxx, σyy, σzz, σyz, σxz, σxy]` (Pa, tension
//! positive), one per increment of the cycle. The crate knows nothing of the contact solver.
// Index loops read like the formulas they implement (Σ_k over components).
#![allow(clippy::needless_range_loop)]

pub mod ball;
pub mod critical_plane;
pub mod error;
pub mod field;
pub mod invariant;
pub mod material;
pub mod process_volume;
pub mod screened;
pub mod tensor;

pub use error::FatigueError;
pub use field::{evaluate_field, FieldIndices, FieldParams};
pub use material::Material;
pub use process_volume::{
    average_over_volume, evaluate_process_volume, BoxNodes, VolumeIndices, VolumeParams,
};
pub use screened::{evaluate_screened, ScreenedIndices};
pub use tensor::Voigt;
