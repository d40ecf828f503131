use halfspace_mdr::MdrError;
use thiserror::Error;

/// Errors of the fretting simulation.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FrettingError {
    /// A parameter is out of range.
    #[error("{name} must be {allowed}, got {value}")]
    InvalidParameter {
        /// Parameter name (as in the config file and CLI).
        name: &'static str,
        /// Value passed.
        value: f64,
        /// Allowed range in words.
        allowed: String,
    },
    /// The explicit wear step went unstable: the contact radius passed its limit `r*`, which wear
    /// (that only raises f) can approach but never cross.
    #[error(
        "the explicit wear step is unstable or inaccurate: a/a0 = {contact_radius:.5} passed the \
         limit r*/a0 = {limit:.5} at tau = {tau:.4}; use a smaller time step dtau (at most {suggested:.1e})"
    )]
    Unstable {
        /// τ at detection.
        tau: f64,
        /// Contact radius `a/a₀` at detection.
        contact_radius: f64,
        /// `r*/a₀`.
        limit: f64,
        /// A step that is stable for this grid (half the current one).
        suggested: f64,
    },
    /// The adaptive step fell below what `τ` can resolve.
    #[error("the adaptive wear step fell to {dtau:e} at tau = {tau}; loosen --tol")]
    StepTooSmall {
        /// τ reached.
        tau: f64,
        /// The step that was refused.
        dtau: f64,
    },
    /// The contact reached the end of the grid.
    #[error(
        "the contact reached the end of the grid (L/a0 = {length}); use a larger domain length L"
    )]
    ContactOutsideGrid {
        /// Domain size `L/a₀`.
        length: f64,
    },
    /// A checkpoint does not belong to these parameters or is damaged.
    #[error("checkpoint: {0}")]
    Checkpoint(String),
    /// An MDR transform refused its input.
    #[error(transparent)]
    Mdr(#[from] MdrError),
}
