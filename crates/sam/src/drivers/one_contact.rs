//! One 3D contact as a library driver (what `halfspace contact3d` and the Python `contact3d` do):
//! an indenter pressed by a normal load, then at most one tangential increment (a shift or a
//! tangential force), on a half-space with or without inhomogeneities, optionally with the stress
//! field below.

use std::time::Instant;

use crate::contact::ContactSolver;
use crate::contact::{ContactParams, ContactProblem, IncrementInfo};
use crate::contact::{NestedInfo, NestedParams};
use crate::eim::Inhomogeneity;
use crate::indenter::Indenter;
use crate::kernels::surface::{Body, Compliance};
use crate::normal::{NormalLoad, NormalParams};
use crate::subsurface::StressField;
use crate::tangential::TangentialParams;
use crate::{SamError, SurfaceGrid};

/// The tangential increment after the normal one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TangentialLoad {
    /// A rigid shift `δx` (m).
    Shift(f64),
    /// A tangential force `Q_x` (N), the shift found by Brent's method (docs/theory-sam.md#stick-slip-solver-and-force-control).
    Force(f64),
}

/// The request.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactCase {
    /// The indenter's shape.
    pub indenter: Indenter,
    /// The indenter's material (rigid or elastic).
    pub indenter_body: Body,
    /// The half-space (elastic).
    pub half_space: Body,
    /// Normal force or approach.
    pub load: NormalLoad,
    /// The tangential increment, if any (needs `friction > 0`).
    pub tangential: Option<TangentialLoad>,
    /// Coulomb friction coefficient μ ≥ 0.
    pub friction: f64,
    /// Cells per side.
    pub grid: usize,
    /// Side of the square domain (m); `None`: four times the estimated contact radius.
    pub extent: Option<f64>,
    /// Relative tolerance of the normal and tangential solvers.
    pub tolerance: f64,
    /// Inhomogeneities below the surface.
    pub inhomogeneities: Vec<Inhomogeneity>,
    /// Depth (m) of the stress field below the surface, if wanted.
    pub subsurface_depth: Option<f64>,
}

/// The solution and what it took.
pub struct ContactOutcome {
    /// The solver with the final state (grid, fields, inclusions).
    pub solver: ContactSolver,
    /// The last increment.
    pub info: IncrementInfo,
    /// The nested loop's report (with inhomogeneities).
    pub nested: Option<NestedInfo>,
    /// The final shift `δx` (m).
    pub shift: f64,
    /// Normal plus tangential solver iterations over the increments.
    pub iterations: usize,
    /// The stress field below, if asked for.
    pub field: Option<StressField>,
    /// Side of the domain used (m).
    pub extent: f64,
    /// Contact modulus `E*` of the pair.
    pub e_star: f64,
    /// Wall times (s): setup, solve, subsurface.
    pub seconds: [f64; 3],
}

/// Solves `case`: the domain (from the Hertz / Sneddon estimate when not given), the memory check
/// before any field is allocated, the normal increment, then the tangential one.
pub fn solve_contact(case: &ContactCase) -> Result<ContactOutcome, SamError> {
    let start = Instant::now();
    let (e_half, nu_half) = match case.half_space {
        Body::Elastic { e, nu } => (e, nu),
        Body::Rigid => {
            return Err(SamError::InvalidInput(
                "the half-space must be elastic (homogeneous:E=..,nu=..)".into(),
            ))
        }
    };
    if !(case.friction.is_finite() && case.friction >= 0.0) {
        return Err(SamError::InvalidParameter {
            name: "friction coefficient μ",
            value: case.friction,
            allowed: "finite and ≥ 0",
        });
    }
    if case.tangential.is_some() && case.friction == 0.0 {
        return Err(SamError::InvalidInput(
            "a tangential load needs a friction coefficient μ > 0 (a frictionless contact carries none)"
                .into(),
        ));
    }
    if !(case.tolerance.is_finite() && case.tolerance > 0.0 && case.tolerance < 1e-2) {
        return Err(SamError::InvalidParameter {
            name: "solver tolerance",
            value: case.tolerance,
            allowed: "in (0, 1e-2)",
        });
    }
    let e_star = 1.0 / (case.indenter_body.normal_term() + case.half_space.normal_term());
    let extent = match (
        case.extent,
        case.indenter.contact_radius_estimate(e_star, case.load),
    ) {
        (Some(x), _) => x,
        (None, Some(a)) => 4.0 * a,
        (None, None) => {
            return Err(SamError::InvalidInput(
                "a height-table indenter needs the domain's extent".into(),
            ))
        }
    };
    let grid = SurfaceGrid::square(case.grid, extent)?;
    let compliance = Compliance::pair(case.indenter_body, case.half_space)?;
    let frictional = case.friction > 0.0;
    crate::memory::check_problem(&grid, frictional, compliance.is_coupled(case.friction))?;
    let geometry = case.indenter.gap(&grid)?;
    let params = ContactParams {
        friction: case.friction,
        normal: NormalParams {
            tolerance: case.tolerance,
            ..NormalParams::default()
        },
        tangential: TangentialParams {
            tolerance: case.tolerance,
            ..TangentialParams::default()
        },
        ..ContactParams::default()
    };
    let problem = ContactProblem::new(grid, compliance, geometry, params)?;
    let mut solver = ContactSolver::new(
        problem,
        e_half,
        nu_half,
        &case.inhomogeneities,
        NestedParams::default(),
    )?;
    let setup = start.elapsed().as_secs_f64();
    let solve_start = Instant::now();
    let (mut info, mut nested) = solver.increment(case.load, [0.0, 0.0])?;
    let mut iterations = info.normal.iterations + info.tangential.iterations;
    let mut shift = 0.0;
    match case.tangential {
        None => {}
        Some(TangentialLoad::Shift(dx)) => {
            (info, nested) = solver.increment(case.load, [dx, 0.0])?;
            iterations += info.normal.iterations + info.tangential.iterations;
            shift = dx;
        }
        Some(TangentialLoad::Force(qx)) => {
            let bracket = 0.05 * extent * 1e-3;
            shift = match &mut solver {
                ContactSolver::Plain(problem) => {
                    let (i, d) = problem.increment_with_force(case.load, qx, bracket)?;
                    info = i;
                    d
                }
                ContactSolver::Nested(n) => {
                    let (ni, d) = n.increment_with_force(case.load, qx, bracket)?;
                    info = ni.contact;
                    nested = Some(ni);
                    d
                }
            };
            iterations += info.normal.iterations + info.tangential.iterations;
        }
    }
    let solve = solve_start.elapsed().as_secs_f64();
    let sub_start = Instant::now();
    let field = match case.subsurface_depth {
        None => None,
        Some(depth) => Some(solver.subsurface(e_half, nu_half, depth)?),
    };
    Ok(ContactOutcome {
        solver,
        info,
        nested,
        shift,
        iterations,
        field,
        extent,
        e_star,
        seconds: [setup, solve, sub_start.elapsed().as_secs_f64()],
    })
}
