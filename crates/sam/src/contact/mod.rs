//! One contact problem on a surface grid: the problem with its history ([`problem`]: begin / solve
//! / commit, the Panagiotopoulos alternation of the normal and tangential solvers), force control
//! ([`force_control`]), the contact of a half-space with inhomogeneities ([`inhomogeneous`]: the
//! contact ↔ EIM outer loop) and the solver that is either ([`solver`]).

pub mod force_control;
pub mod inhomogeneous;
pub mod problem;
pub mod solver;

pub use force_control::shift_for_force;
pub use inhomogeneous::{
    BodyResponse, ContactWork, EimIterate, InhomogeneousContact, NestedInfo, NestedParams,
    NestedSeconds, NestedWarmStart, OuterStopping, CONTRACTION_MAX_RATE, DEFAULT_EIM_CHANGE_FACTOR,
    DEFAULT_EIM_RECYCLED_DEPTH, LOOSE_CONTACT_CEILING, MAX_EIM_RECYCLED_DEPTH,
    REFERENCE_EIM_CHANGE_FACTOR,
};
pub use problem::{
    Alternation, AlternationStep, ContactParams, ContactProblem, ContactState, GridWindow,
    IncrementInfo, INEXACT_CEILING, NORMAL_CEILING, NORMAL_GAUGE, TRACE_LIMIT,
};
pub use solver::ContactSolver;
