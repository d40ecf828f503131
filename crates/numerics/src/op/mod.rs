//! The one operator convention of the workspace: a linear map from `inputs` fields to `outputs`
//! fields on one `N₁ × N₂` grid (row-major, index `i N₂ + j`), built once (plans, kernel spectra,
//! scratch) and applied without allocating ([`GridOperator`]).
//!
//! Every fast operator has a dense twin, a type implementing the same trait that evaluates the same
//! sum directly; the tests check each pair with one helper ([`crate::testkit::twin_error`]) and run
//! the solvers on either. The solvers of the contact problem are generic over an
//! [`OperatorSet`]: [`FftOperators`] (the fast ones) or [`DenseOperators`] (their twins).
//!
//! | operator | fast | twin |
//! | --- | --- | --- |
//! | block convolution (`n_out × n_in` kernels) | [`crate::conv2d::DcFft2d`] | [`crate::conv2d::DenseConvolution2d`] |
//! | even kernel (normal compliance) | [`EvenConvolution2d`] | [`DenseEvenConvolution2d`] |
//! | layered 3D (depth keys) | [`crate::layered::LayeredOperator`] | [`crate::layered::DenseLayered`] |
//! | circulant (preconditioner) | [`crate::circulant::Circulant2d`] | — (a preconditioner: only its effect on the iteration count is tested) |
//!
//! The flat view `y = A x` of [`crate::linop::LinearOperator`] (used by GMRES) is a blanket adapter
//! over every square grid operator: the fields are stacked one after the other.

mod even;

pub use even::{DenseEvenConvolution2d, EvenConvolution2d};

use std::borrow::Cow;

use crate::conv2d::{DcFft2d, DenseConvolution2d};
use crate::fft2d::{Fft2d, KernelFn, C64};
use crate::linop::LinearOperator;
use crate::NumericsError;

/// The shape of a grid operator: `inputs` fields in, `outputs` fields out, each of `N₁ × N₂` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OperatorShape {
    /// Grid rows `N₁`.
    pub n1: usize,
    /// Grid columns `N₂`.
    pub n2: usize,
    /// Input fields.
    pub inputs: usize,
    /// Output fields.
    pub outputs: usize,
}

impl OperatorShape {
    /// `fields` fields in and out.
    pub fn square(n1: usize, n2: usize, fields: usize) -> Self {
        Self {
            n1,
            n2,
            inputs: fields,
            outputs: fields,
        }
    }

    /// Values per field, `N₁ N₂`.
    pub fn field_len(&self) -> usize {
        self.n1 * self.n2
    }
}

/// A linear operator from `inputs` grids to `outputs` grids of `N₁ × N₂` values. Applying does not
/// allocate.
pub trait GridOperator {
    /// Grid and field counts.
    fn shape(&self) -> OperatorShape;
    /// `y_o = Σ_i K_{oi} x_i` for every output `o` (`x`: `inputs` fields, `y`: `outputs` fields).
    fn apply(&mut self, x: &[&[f64]], y: &mut [&mut [f64]]) -> Result<(), NumericsError>;
}

/// Checks the field counts and lengths of `x` and `y` against `shape`.
pub fn check_fields(
    shape: OperatorShape,
    x: &[&[f64]],
    y: &[&mut [f64]],
) -> Result<(), NumericsError> {
    if x.len() != shape.inputs {
        return Err(NumericsError::LengthMismatch {
            what: "grid operator inputs (fields)",
            expected: shape.inputs,
            got: x.len(),
        });
    }
    if y.len() != shape.outputs {
        return Err(NumericsError::LengthMismatch {
            what: "grid operator outputs (fields)",
            expected: shape.outputs,
            got: y.len(),
        });
    }
    let len = shape.field_len();
    for v in x.iter().map(|v| v.len()).chain(y.iter().map(|v| v.len())) {
        if v != len {
            return Err(NumericsError::LengthMismatch {
                what: "grid operator field",
                expected: len,
                got: v,
            });
        }
    }
    Ok(())
}

/// Fields the flat adapter splits without allocating.
pub const FLAT_MAX_FIELDS: usize = 8;

/// The flat view of a square grid operator (`inputs = outputs`): `x` and `y` hold the fields one
/// after the other, `n = inputs · N₁N₂`.
impl<T: GridOperator> LinearOperator for T {
    fn dim(&self) -> usize {
        let s = GridOperator::shape(self);
        s.inputs * s.field_len()
    }

    fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        let s = GridOperator::shape(self);
        if s.inputs != s.outputs || s.inputs > FLAT_MAX_FIELDS || s.inputs == 0 {
            return Err(NumericsError::LengthMismatch {
                what: "fields of a grid operator seen as a flat square operator (≤ 8, in = out)",
                expected: s.inputs,
                got: s.outputs,
            });
        }
        crate::linop::check_lengths(s.inputs * s.field_len(), x, y)?;
        let len = s.field_len();
        let mut xs: [&[f64]; FLAT_MAX_FIELDS] = [&[]; FLAT_MAX_FIELDS];
        for (slot, chunk) in xs.iter_mut().zip(x.chunks(len)) {
            *slot = chunk;
        }
        let mut ys: [&mut [f64]; FLAT_MAX_FIELDS] = Default::default();
        for (slot, chunk) in ys.iter_mut().zip(y.chunks_mut(len)) {
            *slot = chunk;
        }
        GridOperator::apply(self, &xs[..s.inputs], &mut ys[..s.outputs])
    }
}

/// A block convolution `y_o = Σ_i K_{oi} * x_i` with kernels given by their values at the cell
/// offsets (docs/sam.md): the DC-FFT operator or its direct-sum twin.
pub trait BlockConvolution: GridOperator + Send + Sized {
    /// Builds the operator for kernels `kernels[o · n_in + i]` (`None` = zero block) on the grid of
    /// the padded core `fft` (the fast operator shares it; the twin only reads its shape).
    fn build(
        fft: &Fft2d,
        n_in: usize,
        n_out: usize,
        kernels: &[Option<KernelFn<'_>>],
    ) -> Result<Self, NumericsError>;

    /// The spectrum of block `(out, input)` divided by `4N₁N₂` ([`Fft2d::kernel_spectrum`]), or
    /// `None` for a zero block (the twin transforms its table on a core of its own).
    fn block_spectrum(
        &self,
        out: usize,
        input: usize,
    ) -> Result<Option<Cow<'_, [C64]>>, NumericsError>;
}

/// A convolution with a kernel even in both offsets, `K(m, n) = K(|m|, |n|)`, given by its quadrant
/// (the normal compliance): the real-spectrum DC-FFT operator or its direct-sum twin. Both add
/// single columns of the kernel directly (the incremental update of the normal solver).
pub trait EvenKernelOperator: GridOperator + Send + Sized {
    /// Builds the operator from `quadrant[m N₂ + n] = K(m, n)` (`0 ≤ m < N₁`, `0 ≤ n < N₂`) on the
    /// grid of the padded core `fft` (the fast operator shares it).
    fn build(fft: &Fft2d, quadrant: Vec<f64>) -> Result<Self, NumericsError>;

    /// `y += Σ_c v_c K(· − x_c)` for the cells `(c, v_c)` of `cells` (direct, column by column).
    fn add_columns(&self, cells: &[(usize, f64)], y: &mut [f64]);

    /// `y = K * x` (one field in, one out).
    fn apply_field(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        GridOperator::apply(self, &[x], &mut [y])
    }

    /// `y ≈ K * x` in single precision, for the early iterations of a solver (relative error of
    /// order `1e-7`; docs/performance.md, "Mixed precision"): the fast operator's `f32` DC-FFT
    /// product (planned at the first call), the twin's exact product.
    fn apply_field_single(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        self.apply_field(x, y)
    }

    /// Frees what [`EvenKernelOperator::apply_field_single`] holds (the solver is done with it).
    fn drop_single(&mut self) {}
}

/// The operator types a contact solver runs on: the fast ones or their dense twins.
pub trait OperatorSet: Send + 'static {
    /// The even-kernel (normal) operator.
    type Even: EvenKernelOperator;
    /// The block (tangential, coupling) convolution.
    type Blocks: BlockConvolution;
}

/// The DC-FFT operators.
#[derive(Debug, Clone, Copy)]
pub enum FftOperators {}

impl OperatorSet for FftOperators {
    type Even = EvenConvolution2d;
    type Blocks = DcFft2d;
}

/// The dense (direct-sum) twins: every product is O(N²) per output cell pair; for tests.
#[derive(Debug, Clone, Copy)]
pub enum DenseOperators {}

impl OperatorSet for DenseOperators {
    type Even = DenseEvenConvolution2d;
    type Blocks = DenseConvolution2d;
}
