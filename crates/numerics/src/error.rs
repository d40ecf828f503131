use thiserror::Error;

/// Errors of the numerical engine. Every variant names the offending value and what is allowed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NumericsError {
    /// A length does not match what the operator was built for.
    #[error("{what}: expected length {expected}, got {got}")]
    LengthMismatch {
        /// Which array.
        what: &'static str,
        /// Length the operator needs.
        expected: usize,
        /// Length that was passed.
        got: usize,
    },
    /// Too few nodes for the requested operation.
    #[error("{what} needs at least {min} nodes, got {n}")]
    TooFewNodes {
        /// Which operation.
        what: &'static str,
        /// Minimum number of nodes.
        min: usize,
        /// Number passed.
        n: usize,
    },
    /// A scalar parameter is out of its allowed range or not finite.
    #[error("{name} must be {allowed}, got {value}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Value passed.
        value: f64,
        /// Allowed range in words.
        allowed: &'static str,
    },
    /// An iterative solver stopped before its tolerance (iteration limit, stagnation or divergence).
    #[error("{solver} did not converge: {iterations} iterations, relative residual {residual:e}")]
    NoConvergence {
        /// Which solver.
        solver: &'static str,
        /// Iterations done.
        iterations: usize,
        /// Last relative residual.
        residual: f64,
    },
    /// A request that would not fit in the machine's memory, refused before allocating.
    #[error(
        "{what} needs about {needed_gib:.2} GiB, more than the {available_gib:.2} GiB available: \
         use a smaller grid (or fewer nodes)"
    )]
    OutOfMemory {
        /// What was asked for.
        what: &'static str,
        /// Estimated bytes, in GiB.
        needed_gib: f64,
        /// Available bytes (`MemAvailable`, or `HALFSPACE_MEMORY_LIMIT`), in GiB.
        available_gib: f64,
    },
}
