//! 3D semi-analytical contact of elastic half-spaces (docs/theory-sam.md; Leroux & Nélias 2011), one
//! module per family: influence coefficients and the volume kernels ([`kernels`]), the
//! Polonsky–Keer normal solver ([`normal`]), the stick–slip tangential solver ([`tangential`]),
//! the contact problem with its Panagiotopoulos coupling, force control and inhomogeneities
//! ([`contact`]), the equivalent inclusion method ([`eim`]), subsurface stresses ([`subsurface`]),
//! the drivers of the front ends ([`drivers`]) and the closed forms the tests compare with
//! ([`analytic`]).
//!
//! Conventions (docs/theory-sam.md#conventions): body 2 is the half-space `x₃ ≥ 0` (depth), body 1 the indenter; tractions
//! are those of body 1 on body 2 (`p ≥ 0` compressive, `q` along `+x_α`); displacements of body 2,
//! two-body quantities relative. SI units.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Numerical kernels here index several same-length fields by one cell index; iterator chains over
// four or five zipped slices read worse than the index.
#![allow(clippy::needless_range_loop)]

pub mod analytic;
pub mod contact;
pub mod drivers;
pub mod eim;
mod error;
pub mod grid;
pub mod indenter;
pub mod kernels;
pub mod memory;
pub mod normal;
pub mod subsurface;
pub mod tangential;

pub use error::SamError;
pub use grid::SurfaceGrid;
pub use kernels::surface::{Body, Compliance};
