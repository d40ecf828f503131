use halfspace_numerics::NumericsError;
use thiserror::Error;

/// Errors of the MDR crate. Each says what was wrong and what is allowed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MdrError {
    /// A scalar input is non-finite or outside its range.
    #[error("{name} must be {allowed}, got {value}")]
    InvalidParameter {
        /// Parameter name as the user knows it.
        name: &'static str,
        /// Value passed.
        value: f64,
        /// Allowed range in words.
        allowed: &'static str,
    },
    /// A tabulated profile is unusable.
    #[error("profile table: {0}")]
    InvalidTable(String),
    /// The contact would reach beyond where the profile or grid is defined.
    #[error("contact radius would exceed {limit:e} m ({what}); {hint}")]
    ContactOutsideDomain {
        /// What limits the domain.
        what: &'static str,
        /// The limit.
        limit: f64,
        /// What to do about it.
        hint: &'static str,
    },
    /// The method needs `g(x)` increasing (a convex profile) and it is not.
    #[error(
        "non-convex profile: the equivalent profile g(x) decreases near x = {x:e} m; the \
         contact-radius rule g(a) = δ (docs/theory-mdr.md#profile-transform) needs g increasing, i.e. a convex f(r)"
    )]
    NonConvexProfile {
        /// Where `g` decreases.
        x: f64,
    },
    /// An iteration stopped before reaching its tolerance.
    #[error("{what} did not converge after {iterations} iterations (residual {residual:e})")]
    NoConvergence {
        /// Which iteration.
        what: &'static str,
        /// Iterations done.
        iterations: usize,
        /// Last residual.
        residual: f64,
    },
    /// A numerical-engine error (lengths, grid size).
    #[error(transparent)]
    Numerics(#[from] NumericsError),
}

pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, MdrError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(MdrError::InvalidParameter {
            name,
            value,
            allowed: "finite and > 0",
        })
    }
}
