//! Stress-invariant criteria on the minimum enclosing ball of the deviatoric path: Crossland
//! (1956) and Dang Van (1989) (docs/fatigue.md, Eqs. F2–F4).
use crate::ball::{min_enclosing_ball, BallInfo, BallScratch};
use crate::error::FatigueError;
use crate::material::Material;
use crate::tensor::{
    deviator, deviator_coordinates, deviator_from_coordinates, hydrostatic, tresca_shear, Voigt,
};

/// Reusable buffers of the invariant criteria (no allocation once grown to the path length).
#[derive(Clone, Debug, Default)]
pub struct InvariantScratch {
    ball: BallScratch,
    deviators: Vec<[f64; 5]>,
}

/// Crossland's index and its ingredients.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossland {
    /// `(√J₂,a + α_C σ_H,max)/t₋₁`: ≥ 1 predicts crack initiation at the endurance limit.
    pub index: f64,
    /// `√J₂,a`, the radius of the minimum enclosing ball of the deviatoric path, Pa.
    pub sqrt_j2_amplitude: f64,
    /// `σ_H,max = max_t tr σ(t)/3`, Pa.
    pub hydrostatic_max: f64,
    pub ball: BallInfo,
}

/// Dang Van's index and where in the cycle it is reached.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DangVan {
    /// `max_t (τ_Tresca(ŝ(t)) + α_DV σ_H(t))/t₋₁`.
    pub index: f64,
    /// The increment `t` of the maximum.
    pub critical_increment: usize,
    /// `τ_Tresca(ŝ)` at the critical increment, Pa.
    pub mesoscopic_shear: f64,
    /// `σ_H` at the critical increment, Pa.
    pub hydrostatic: f64,
    /// The deviatoric stress at the ball's centre (mesoscopic residual stress with sign
    /// reversed), Voigt, Pa.
    pub centre: Voigt,
    pub ball: BallInfo,
}

/// Checks a path: non-empty and every component finite.
pub(crate) fn check_path(path: &[Voigt]) -> Result<(), FatigueError> {
    if path.is_empty() {
        return Err(FatigueError::EmptyPath);
    }
    for (increment, s) in path.iter().enumerate() {
        if let Some((component, &value)) = s.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(FatigueError::NonFiniteStress {
                increment,
                component,
                value,
            });
        }
    }
    Ok(())
}

/// Both indices from one minimum enclosing ball of the deviatoric path `y(σ(t))`
/// (docs/fatigue.md, Eq. F1):
/// Crossland (1956) `(√J₂,a + α_C σ_H,max)/t₋₁`, `√J₂,a` the ball's radius,
/// `α_C = (t₋₁ − f₋₁/√3)/(f₋₁/3)`;
/// Dang Van (1989) `max_t (τ_Tresca(ŝ(t)) + α_DV σ_H(t))/t₋₁`, `ŝ(t) = s(t) − s_c` with `s_c`
/// the ball's centre (the stabilised mesoscopic state), `α_DV = (t₋₁ − f₋₁/2)/(f₋₁/3)`,
/// `τ_Tresca = (ŝ₁ − ŝ₃)/2`.
pub fn crossland_dang_van(
    path: &[Voigt],
    material: &Material,
    scratch: &mut InvariantScratch,
) -> Result<(Crossland, DangVan), FatigueError> {
    material.validate_limits()?;
    check_path(path)?;
    scratch.deviators.clear();
    scratch
        .deviators
        .extend(path.iter().map(deviator_coordinates));
    let (ball, info) = min_enclosing_ball(&scratch.deviators, &mut scratch.ball)?;
    let t = material.t_minus1;
    let hydrostatic_max = path
        .iter()
        .map(hydrostatic)
        .fold(f64::NEG_INFINITY, f64::max);
    let crossland = Crossland {
        index: (ball.radius + material.alpha_crossland() * hydrostatic_max) / t,
        sqrt_j2_amplitude: ball.radius,
        hydrostatic_max,
        ball: info,
    };
    let centre = deviator_from_coordinates(&ball.centre);
    let alpha = material.alpha_dang_van();
    let mut dv = DangVan {
        index: f64::NEG_INFINITY,
        critical_increment: 0,
        mesoscopic_shear: 0.0,
        hydrostatic: 0.0,
        centre,
        ball: info,
    };
    for (i, s) in path.iter().enumerate() {
        let d = deviator(s);
        let meso: Voigt = std::array::from_fn(|k| d[k] - centre[k]);
        let tau = tresca_shear(&meso);
        let h = hydrostatic(s);
        let index = (tau + alpha * h) / t;
        if index > dv.index {
            dv.index = index;
            dv.critical_increment = i;
            dv.mesoscopic_shear = tau;
            dv.hydrostatic = h;
        }
    }
    Ok((crossland, dv))
}

/// Crossland's index alone (see [`crossland_dang_van`]).
pub fn crossland(
    path: &[Voigt],
    material: &Material,
    scratch: &mut InvariantScratch,
) -> Result<Crossland, FatigueError> {
    crossland_dang_van(path, material, scratch).map(|r| r.0)
}

/// Dang Van's index alone (see [`crossland_dang_van`]).
pub fn dang_van(
    path: &[Voigt],
    material: &Material,
    scratch: &mut InvariantScratch,
) -> Result<DangVan, FatigueError> {
    crossland_dang_van(path, material, scratch).map(|r| r.1)
}
