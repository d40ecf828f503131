//! The three MDR transforms on the grid uniform in `ξ = x²` (docs/theory-mdr.md#squared-grid). Each is a struct built
//! once for a capacity (largest grid size), a material and a [`Backend`]; `apply` methods take the
//! grid (any size up to the capacity, any step) and do not allocate.
//!
//! | transform | paper | sum | backends |
//! |---|---|---|---|
//! | [`ProfileTransform`] `f → g` | Eq. 7 | causal, `γ = 1/2` | FFT, MVM |
//! | [`StressTransform`] `q → σ` | Eq. 17 | anti-causal, `γ = 1/2` | FFT, MVM |
//! | [`CellStressTransform`] `q → σ`, edge between nodes | Eq. 14, product integration | anti-causal, `(m+1)^γ − m^γ` | FFT, MVM |
//! | [`DisplacementTransform`] `U → u` | Eq. 12 | dense kernel `arccos √(ξ/ρ)` | MVM only |
//! | [`DisplacementTransform`] `U → u` | Eq. 13 | causal, `γ = 1/2` | FFT, MVM |
//!
//! [`Backend`]: halfspace_numerics::Backend

mod displacement;
mod profile_transform;
mod stress;
mod stress_cells;

pub use displacement::{DisplacementMethod, DisplacementTransform};
pub use profile_transform::{EquivalentSplit, ProfileTransform};
pub use stress::StressTransform;
pub use stress_cells::{cell_weights, node_powers, stress_scale, CellStressTransform};

use halfspace_numerics::{NumericsError, SquaredGrid};

pub(crate) fn check_fits(
    what: &'static str,
    grid: &SquaredGrid,
    capacity: usize,
) -> Result<(), NumericsError> {
    if grid.len() > capacity {
        return Err(NumericsError::LengthMismatch {
            what,
            expected: capacity,
            got: grid.len(),
        });
    }
    Ok(())
}

pub(crate) fn check_len(
    what: &'static str,
    expected: usize,
    got: usize,
) -> Result<(), NumericsError> {
    if expected != got {
        return Err(NumericsError::LengthMismatch {
            what,
            expected,
            got,
        });
    }
    Ok(())
}
