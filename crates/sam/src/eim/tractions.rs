//! The equivalent inclusion method under known surface tractions (no contact loop): the applied
//! strain of `p, q` (docs/theory-sam.md#love-rectangle-stresses), the equivalency equations (docs/theory-sam.md#solving-the-eim-equations), the correction pressure and the
//! surface eigen-displacements (docs/theory-sam.md#mirror-image-and-correction-pressure, docs/theory-sam.md#eigen-displacements) in one call — what a stress analysis of a loaded
//! surface (and the reference comparisons) needs.

use super::{EimFields, EimInfo, EimParams, EimSystem, InclusionSet, Inhomogeneity};
use crate::{SamError, SurfaceGrid};

/// The eigenstrains and what they do to the surface.
#[derive(Debug, Clone, PartialEq)]
pub struct TractionSolution {
    /// The inclusion cells.
    pub set: InclusionSet,
    /// `ε*`, 6 per inclusion cell (Voigt, tensor shear).
    pub eigenstrain: Vec<f64>,
    /// The correction pressure `p_c` on the grid.
    pub correction_pressure: Vec<f64>,
    /// Surface eigen-displacements `(u₁, u₂, u₃)^eig` on the grid.
    pub eigen_displacements: [Vec<f64>; 3],
    /// The EIM solve.
    pub info: EimInfo,
}

/// Solves the EIM of `inhomogeneities` in the half-space `(e, nu)` under the surface tractions `p`
/// (and `q`) on `grid`.
pub fn solve_under_tractions(
    grid: SurfaceGrid,
    e: f64,
    nu: f64,
    inhomogeneities: &[Inhomogeneity],
    p: &[f64],
    q: Option<[&[f64]; 2]>,
    params: &EimParams,
) -> Result<TractionSolution, SamError> {
    let set = InclusionSet::new(&grid, inhomogeneities)?;
    let fields = EimFields::for_inclusions(grid, e, nu, &set)?;
    let mut sys = EimSystem::new(fields, set.clone(), e, nu)?;
    let mut applied = vec![vec![0.0; set.window.len()]; set.layers.len() * 6];
    sys.fields().traction_strain(p, q, &mut applied)?;
    let mut eigenstrain = vec![0.0; 6 * set.len()];
    let info = sys.solve(&applied, &mut eigenstrain, params)?;
    sys.disturbance(&eigenstrain)?;
    let n = grid.len();
    let mut u: [Vec<f64>; 3] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    {
        let [a, b, c] = &mut u;
        sys.fields().eigen_displacements([a, b, c])?;
    }
    Ok(TractionSolution {
        correction_pressure: sys.fields().correction_pressure().to_vec(),
        set,
        eigenstrain,
        eigen_displacements: u,
        info,
    })
}
