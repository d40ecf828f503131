//! Axisymmetric normal contact of elastic half-spaces by the Method of Dimensionality Reduction
//! (MDR), after E. Willert, *FFT-based implementation of the MDR transformations for homogeneous
//! and power-law graded materials*, Facta Univ. Mech. Eng. 19 (2021) 805–816, and the project
//! docs/theory-mdr.md (equation numbers below are the paper's).
//!
//! * [`material`]: the elastic half-space (`E*`, later power-law graded with `c_N`).
//! * [`profile`]: indenter profiles `f(r)` with `f(0) = 0`.
//! * [`transform`]: the three MDR transforms, each built once for a grid size and a
//!   [`halfspace_numerics::Backend`] and applied many times:
//!   profile `f → g` (Eq. 7), displacement `U → u` (Eqs. 12, 13), line load `q → σ` (Eq. 17).
//! * [`contact`]: macroscopic relations and the contact solve by depth or by force (docs/theory-mdr.md#profile-transform).
//! * [`analytic`]: closed forms used by tests, docs and benches.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod analytic;
pub mod contact;
mod error;
pub mod material;
pub mod profile;
pub mod studies;
pub mod tangential;
pub mod transform;

pub use contact::{ContactParams, ContactSolution, ContactSolver, Load};
pub use error::MdrError;
pub use halfspace_numerics::{Backend, SquaredGrid};
pub use material::Material;
pub use profile::{Profile, ProfileTable};
pub use transform::{
    CellStressTransform, DisplacementMethod, DisplacementTransform, ProfileTransform,
    StressTransform,
};
