//! Footprint of the 3D contact problems, estimated from the grid before anything is allocated
//! (bytes per surface cell; the padded spectra hold `2N₁(N₂+1) ≈ 2N` values). A grid that would
//! not fit is refused with the estimate ([`halfspace_numerics::memory::check_fits`]).

use halfspace_numerics::memory::check_fits;

use crate::{SamError, SurfaceGrid};

/// Bytes per cell of the normal solver: padded row spectra (32), the kernel's real spectrum (16),
/// the input spectrum (32), the kernel quadrant (8), five work fields (40), the `|k|`
/// preconditioner (24), the single-precision twins of the mixed-precision start (52: row
/// spectra 16, kernel 8, input spectrum 16, preconditioner 12; the operator's dropped at the
/// switch to double precision, the preconditioner's kept), and the coarser grids of the nested
/// continuation (+1/3).
pub const NORMAL_BYTES_PER_CELL: f64 = (32.0 + 16.0 + 32.0 + 8.0 + 40.0 + 24.0 + 52.0) * 4.0 / 3.0;

/// Bytes per cell of the tangential solver: padded row spectra (32), four complex block spectra
/// (128), two input and one output spectra (96), fourteen work fields (112), the stick flags (1)
/// and the `|k|` preconditioner (16).
pub const TANGENTIAL_BYTES_PER_CELL: f64 = 32.0 + 128.0 + 96.0 + 112.0 + 1.0 + 16.0;

/// Bytes per cell of the two coupling operators `q → Δu₃`, `p → Δu_α` (each: row spectra, two
/// block spectra, inputs and output).
pub const COUPLING_BYTES_PER_CELL: f64 = 2.0 * (32.0 + 64.0 + 96.0);

/// Estimated bytes of a contact problem on `grid`: the normal solver, the geometry, `h` and `p`,
/// and with friction the tangential solver, its 19 fields (shear, slip, history, work) and the
/// rim flags of the warm start (1 byte), with coupling the two coupling operators and four more
/// fields.
pub fn problem_bytes(grid: &SurfaceGrid, frictional: bool, coupled: bool) -> f64 {
    problem_bytes_per_cell(frictional, coupled) * grid.n1 as f64 * grid.n2 as f64
}

/// Bytes per surface cell of [`problem_bytes`] (the one formula the drivers' estimates share).
pub fn problem_bytes_per_cell(frictional: bool, coupled: bool) -> f64 {
    let mut per_cell = NORMAL_BYTES_PER_CELL + 3.0 * 8.0;
    if frictional {
        per_cell += TANGENTIAL_BYTES_PER_CELL + 19.0 * 8.0 + 1.0;
    }
    if coupled {
        per_cell += COUPLING_BYTES_PER_CELL + 4.0 * 8.0;
    }
    per_cell
}

/// Estimated bytes that a contact window adds to a contact problem of `grid_cells` cells
/// ([`ContactProblem::set_window`](crate::contact::ContactProblem::set_window)): the inner
/// problem on the window's `window_cells` cells ([`problem_bytes_per_cell`]), the whole grid's
/// deformed gap of the outside check (8 bytes a cell) and, with `eigen` (an inhomogeneous body),
/// the window's three eigen-displacement fields and their three gathered copies (48 bytes a
/// window cell).
pub fn window_bytes(
    grid_cells: f64,
    window_cells: f64,
    frictional: bool,
    coupled: bool,
    eigen: bool,
) -> f64 {
    let eigen = if eigen { 48.0 } else { 0.0 };
    (problem_bytes_per_cell(frictional, coupled) + eigen) * window_cells + 8.0 * grid_cells
}

/// Refuses a problem whose [`problem_bytes`] exceeds the available memory.
pub fn check_problem(grid: &SurfaceGrid, frictional: bool, coupled: bool) -> Result<(), SamError> {
    check_fits(
        "the 3D contact problem",
        problem_bytes(grid, frictional, coupled),
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_grid_of_1e5_squared_is_refused() {
        let grid = SurfaceGrid::square(100_000, 1e-3).unwrap();
        let err = check_problem(&grid, false, false).unwrap_err();
        assert!(err.to_string().contains("needs about"), "{err}");
        let small = SurfaceGrid::square(64, 1e-3).unwrap();
        assert!(check_problem(&small, true, true).is_ok());
    }
}
