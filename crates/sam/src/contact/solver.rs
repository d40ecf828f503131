//! The contact solver with or without inhomogeneities behind one interface.

use crate::contact::ContactState;
use crate::contact::{ContactProblem, IncrementInfo};
use crate::contact::{InhomogeneousContact, NestedInfo, NestedParams, NestedWarmStart};
use crate::eim::Inhomogeneity;
use crate::normal::NormalLoad;
use crate::subsurface::{subsurface_stress, StressField};
use crate::SamError;

/// A contact problem on a homogeneous half-space ([`ContactProblem`]) or, with inhomogeneities,
/// the nested contact ↔ EIM loop ([`InhomogeneousContact`], docs/theory-sam.md#nested-loops).
pub enum ContactSolver {
    /// No inhomogeneity.
    Plain(Box<ContactProblem>),
    /// With inhomogeneities.
    Nested(Box<InhomogeneousContact>),
}

impl ContactSolver {
    /// `problem` alone when `inhomogeneities` is empty, else nested with the EIM in the matrix
    /// `(e, nu)`.
    pub fn new(
        problem: ContactProblem,
        e: f64,
        nu: f64,
        inhomogeneities: &[Inhomogeneity],
        params: NestedParams,
    ) -> Result<Self, SamError> {
        Ok(if inhomogeneities.is_empty() {
            Self::Plain(Box::new(problem))
        } else {
            Self::Nested(Box::new(InhomogeneousContact::new(
                problem,
                e,
                nu,
                inhomogeneities,
                params,
            )?))
        })
    }

    /// One increment (begin → solve → commit); the nested loop's report with inhomogeneities.
    pub fn increment(
        &mut self,
        load: NormalLoad,
        shift: [f64; 2],
    ) -> Result<(IncrementInfo, Option<NestedInfo>), SamError> {
        Ok(match self {
            Self::Plain(p) => (p.increment(load, shift)?, None),
            Self::Nested(n) => {
                let info = n.increment(load, shift)?;
                (info.contact, Some(info))
            }
        })
    }

    /// The contact problem (grid, state).
    pub fn problem(&self) -> &ContactProblem {
        match self {
            Self::Plain(p) => p,
            Self::Nested(n) => n.problem(),
        }
    }

    /// The contact problem, mutable (to restore a state).
    pub fn problem_mut(&mut self) -> &mut ContactProblem {
        match self {
            Self::Plain(p) => p,
            Self::Nested(n) => n.problem_mut(),
        }
    }

    /// The nested solver, with inhomogeneities.
    pub fn nested(&self) -> Option<&InhomogeneousContact> {
        match self {
            Self::Plain(_) => None,
            Self::Nested(n) => Some(n),
        }
    }

    /// The nested solver, with inhomogeneities, mutable (to set its warm start).
    pub fn nested_mut(&mut self) -> Option<&mut InhomogeneousContact> {
        match self {
            Self::Plain(_) => None,
            Self::Nested(n) => Some(n),
        }
    }

    /// Restores a checkpoint's converged state and, with inhomogeneities, the nested loop's warm
    /// start ([`ContactProblem::restore_state`], [`InhomogeneousContact::set_warm_start`]); the
    /// warm start must be present exactly when the solver has inhomogeneities.
    pub fn restore(
        &mut self,
        state: &ContactState,
        eigen: Option<&NestedWarmStart>,
    ) -> Result<(), SamError> {
        self.problem_mut().restore_state(state)?;
        match (self, eigen) {
            (Self::Nested(n), Some(w)) => n.set_warm_start(w),
            (Self::Plain(_), None) => Ok(()),
            _ => Err(SamError::InvalidInput(
                "checkpoint member eigenstrain: the checkpoint's eigenstrains do not match the \
                 inhomogeneities"
                    .into(),
            )),
        }
    }

    /// Brings the eigenstrains up to the current tractions before they are read for stresses
    /// ([`InhomogeneousContact::sync_eigenstrain`]; nothing to do without inhomogeneities or on
    /// the nested path, where they are always current).
    pub fn sync_eigenstrain(&mut self) -> Result<(), SamError> {
        if let Self::Nested(n) = self {
            n.sync_eigenstrain()?;
        }
        Ok(())
    }

    /// The stress field below the current state down to `depth` in the matrix `(e, nu)`: the
    /// surface tractions and, with inhomogeneities, the eigenstrains ([`subsurface_stress`]; on
    /// the surface-operator path one EIM solve of the current tractions first,
    /// [`InhomogeneousContact::sync_eigenstrain`]).
    pub fn subsurface(&mut self, e: f64, nu: f64, depth: f64) -> Result<StressField, SamError> {
        self.sync_eigenstrain()?;
        let problem = self.problem();
        let st = problem.state();
        let q =
            (problem.friction() > 0.0).then(|| [st.shear[0].as_slice(), st.shear[1].as_slice()]);
        let inclusions = self.nested().map(|n| (n.inclusions(), n.eigenstrain()));
        subsurface_stress(problem.grid(), e, nu, &st.pressure, q, depth, inclusions)
    }
}
