//! 3D fretting wear on the semi-analytical solver (docs/wear3d.md): the fretting loop of
//! [`crate::drivers::fretting_loop`] cycled `+A → −A → +A` under a fixed normal force or approach,
//! the local wear of one cycle (Archard `k p |Δu|` or Fouvry's `α |q| |Δu|`, summed over the
//! cycle's increments from the computed stick–slip state) added to the gap, one computed cycle
//! standing for `ΔN` cycles (cycle jumping bounded by accuracy and by the explicit step's
//! stability).
//!
//! * [`WearCase`]: the configuration; [`WearLaw`], [`WornBody`].
//! * [`FrettingWear3d`]: the run, wear step by wear step ([`FrettingWear3d::step`]) or to the end
//!   with an observer ([`FrettingWear3d::run`]); a [`WearRow`] per computed cycle, the
//!   [`WearRecord`]s at the record cycles, a [`WearSnapshot`] to resume bit for bit.

mod case;
mod laws;
mod run;

pub use case::{
    WearCase, WearEstimate, DEFAULT_STABILITY_FRACTION, DEFAULT_STEP_FRACTION,
    INHOMOGENEITY_DEPTH_CELLS,
};
pub use laws::{WearLaw, WornBody};
pub use run::{
    checkerboard_compliance, CycleEigen, FrettingWear3d, WearRecord, WearRow, WearSeconds,
    WearSnapshot, WORN_OUT_OF_LOAD_FRACTION,
};
