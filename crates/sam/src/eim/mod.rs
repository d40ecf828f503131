//! Inhomogeneities below the surface by Eshelby's equivalent inclusion method (docs/theory-sam.md#equivalent-inclusion-method to #eigen-displacements-and-nested-loops;
//! \[LN11\]; Liu & Wang 2005; Zhou et al. 2009): the inhomogeneities on the volume lattice
//! ([`geometry`]), the layered field operators of a cuboid eigenstrain in the half-space with their
//! dense twin ([`operator`]) and the equivalency equations solved by block Jacobi or GMRES
//! ([`solve`]).

pub mod geometry;
pub mod operator;
pub mod solve;
pub mod surface_response;
pub mod tractions;

pub use geometry::{
    composite_fibres, fibres, Axis, Cell, FibreLayout, InclusionSet, Inhomogeneity, Shape, Window,
    COMPOSITE_CELLS_PER_RADIUS, COMPOSITE_FIBRE_RADIUS,
};
pub use operator::{Backend, EimFields, Space};
pub use solve::{EimInfo, EimMethod, EimParams, EimSystem};
pub use surface_response::SurfaceResponse;
pub use tractions::{solve_under_tractions, TractionSolution};
