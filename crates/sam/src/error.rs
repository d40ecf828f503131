use halfspace_numerics::NumericsError;
use thiserror::Error;

/// Errors of the 3D contact solvers.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SamError {
    /// A parameter is out of range.
    #[error("{name} must be {allowed}, got {value}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Value passed.
        value: f64,
        /// Allowed range in words.
        allowed: &'static str,
    },
    /// An iterative solver stopped before its tolerance.
    #[error("{solver} did not converge: {iterations} iterations, residual {residual:e}")]
    NoConvergence {
        /// Which solver.
        solver: &'static str,
        /// Iterations done.
        iterations: usize,
        /// Last residual.
        residual: f64,
    },
    /// The contact reaches the edge of the computational domain.
    #[error("the contact reaches the edge of the domain (pressure on the boundary cells); enlarge the domain extent")]
    ContactAtDomainEdge,
    /// The contact solved on a window of the grid (`ContactProblem::set_window`) would close the
    /// gap outside the window.
    #[error(
        "the contact reaches beyond its window of {} × {} cells (deformed gap {gap:e} m outside it): \
         the window must be larger",
        cells[0],
        cells[1]
    )]
    ContactOutsideWindow {
        /// The window's rows and columns.
        cells: [usize; 2],
        /// The smallest deformed gap outside the window (m).
        gap: f64,
    },
    /// No contact at all (the indenter does not touch).
    #[error("no contact: the indenter does not reach the surface at this load")]
    NoContact,
    /// A prescribed tangential force at or beyond gross slip.
    #[error(
        "tangential force {force:e} N ≥ μW = {limit:e} N: gross slip (no partial-slip solution)"
    )]
    GrossSlip {
        /// Requested |Q|.
        force: f64,
        /// μ W.
        limit: f64,
    },
    /// An input that does not fit the request (a checkpoint of another configuration, the metrics
    /// of an unfinished loop).
    #[error("{0}")]
    InvalidInput(String),
    /// The caller asked the run to stop (Ctrl-C); what was done before is intact.
    #[error("cancelled (interrupted)")]
    Cancelled,
    /// A wear run whose worn flat comes within reach of its inhomogeneities: the EIM geometry was
    /// built for the unworn surface (docs/wear3d.md#inhomogeneities-under-wear). The wear step
    /// that would pass the limit is not applied; the run's state before it is intact.
    #[error(
        "the worn depth over an inhomogeneity would reach {depth:e} m after {cycles} cycles, past \
         the limit {limit:e} m (inhomogeneity_depth_cells of a cell): the inhomogeneities were placed for the \
         unworn surface; the run stops here (see docs/wear3d.md, inhomogeneities under wear)"
    )]
    WornIntoInhomogeneity {
        /// Cycles the step would have reached.
        cycles: u64,
        /// Worn depth the step would have reached over an inhomogeneity (m).
        depth: f64,
        /// The limit (m).
        limit: f64,
    },
    /// A wear run under approach control whose wear has removed the interference: the normal
    /// force at the end of a computed cycle has fallen below [`WORN_OUT_OF_LOAD_FRACTION`] of the
    /// Hertz force of the approach (docs/wear3d.md, "A wear that removes the load"). The step is
    /// not applied; the run's state before it is intact.
    ///
    /// [`WORN_OUT_OF_LOAD_FRACTION`]: crate::drivers::fretting_wear3d::WORN_OUT_OF_LOAD_FRACTION
    #[error(
        "after {cycles} cycles the normal force under the fixed approach {approach:e} m has fallen \
         to {force:e} N, {ratio:e} of the unworn contact's {hertz:e} N: the wear has removed the \
         load (largest worn depth {depth:e} m); the run stops here with its results so far (ask \
         for fewer cycles, or use force control)"
    )]
    WornOutOfLoad {
        /// Cycles reached.
        cycles: u64,
        /// The normal force at the end of the cycle (N).
        force: f64,
        /// The Hertz force of the approach, unworn (N).
        hertz: f64,
        /// `force / hertz`.
        ratio: f64,
        /// The largest worn depth (m).
        depth: f64,
        /// The approach δ (m).
        approach: f64,
    },
    /// Tractions on cells outside the candidate region of the surface-response operator
    /// (docs/theory-sam.md#surface-response-operator): the contact grew past the cells the operator
    /// was built for.
    #[error(
        "the contact reached {cells} traction value(s) outside the surface-response operator's \
         candidate region: enlarge surface_operator_radius_over_a or use inhomogeneous_body = \"nested\""
    )]
    ContactOutsideSurfaceOperator {
        /// Traction values (cell × component) outside the region.
        cells: usize,
    },
    /// Grid shape or array length problems.
    #[error(transparent)]
    Numerics(#[from] NumericsError),
}

/// Every field of `fields` holds `expected` values; the first that does not is refused
/// ([`NumericsError::LengthMismatch`] naming `what`, its length got).
pub(crate) fn check_lengths<'a>(
    what: &'static str,
    expected: usize,
    fields: impl IntoIterator<Item = &'a [f64]>,
) -> Result<(), SamError> {
    match fields.into_iter().find(|f| f.len() != expected) {
        Some(bad) => Err(SamError::Numerics(NumericsError::LengthMismatch {
            what,
            expected,
            got: bad.len(),
        })),
        None => Ok(()),
    }
}

pub(crate) fn positive(name: &'static str, v: f64) -> Result<f64, SamError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(SamError::InvalidParameter {
            name,
            value: v,
            allowed: "finite and > 0",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first field of another length is refused, with its own length.
    #[test]
    fn check_lengths_names_the_first_bad_field() {
        let (a, b, c) = (vec![0.0; 4], vec![0.0; 3], vec![0.0; 2]);
        assert!(check_lengths("f", 4, [&a[..], &a[..]]).is_ok());
        let e = check_lengths("f", 4, [&a[..], &b[..], &c[..]]).unwrap_err();
        assert_eq!(
            e,
            SamError::Numerics(NumericsError::LengthMismatch {
                what: "f",
                expected: 4,
                got: 3
            })
        );
    }
}
