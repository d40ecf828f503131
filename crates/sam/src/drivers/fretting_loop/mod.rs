//! The fretting loop of \[LN11\] (Leroux & Nélias 2011, §3–4) as a library driver: a rigid sphere on a
//! half-space (with or without inhomogeneities), the normal load ramped in steps, then the rigid
//! shift `δx` cycled `0 → +A → −A → +A`, each increment the coupled stick–slip contact (docs/theory-sam.md#normal-tangential-alternation)
//! or, with inhomogeneities, the nested contact ↔ EIM loop (docs/theory-sam.md#nested-loops).
//!
//! * [`LoopCase`]: the configuration (the paper's constants by default; [`LoopCase::composite`] for
//!   its fibre case) and [`LoadPath`], the increments and the points A–D.
//! * [`ContactSolver`](crate::contact::solver::ContactSolver): the plain or nested solver behind one interface (also used by one-off
//!   contacts).
//! * [`FrettingLoop`]: the loop, increment by increment ([`FrettingLoop::step`]) or to the end with
//!   an observer ([`FrettingLoop::run`]); the rows of every increment, the fields at A–D
//!   ([`PointFields`]), a [`LoopSnapshot`] to resume bit for bit, and the [`LoopMetrics`]
//!   (dissipated energy, ratchet, regime).
//! * [`FrettingMap`](super::fretting_map::FrettingMap): the loop over loads × amplitudes, one [`MapPoint`](super::fretting_map::MapPoint) (regime, dissipated
//!   energy) per point (Vingsbo & Söderberg's fretting map).

mod case;
mod history;
mod metrics;
mod row;
mod run;

pub use case::{
    recycled_history_bytes, work_limit_hours, LoadPath, LoopCase, LoopEstimate, LoopKeys,
    CELL_INCREMENTS_PER_SECOND, CONTACT_WINDOW_FIELD, CONTACT_WINDOW_OVER_A, OUTER_STOPPING_FIELD,
    POINT_LABELS, PREDICTOR_IMAGE_FIELD, ROW_BYTES, UNRECORDED_EIM_CHANGE_FACTOR,
};
pub use history::{CycleSources, CycleStress};
pub use metrics::{FrettingRegime, LoopMetrics};
pub use row::LoopRow;
pub use run::{FrettingLoop, LoopSeconds, LoopSnapshot, PointFields};
