//! A flat linear operator `y = A x` on `R^n`, the one interface that the Krylov solver
//! ([`crate::krylov`]), the block-Jacobi (preconditioned Richardson) iteration and the dense twins
//! share. Fast operators (DC-FFT, layered eigenstrain operators) and their dense O(n²) controls both
//! implement it, so every solver can be run on either.

use crate::NumericsError;

/// `y = A x`, `x, y ∈ R^n`. Applying does not allocate.
pub trait LinearOperator {
    /// The dimension `n`.
    fn dim(&self) -> usize;
    /// `y = A x`.
    fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError>;
}

/// The identity (no preconditioning).
#[derive(Debug, Clone, Copy)]
pub struct Identity(pub usize);

impl LinearOperator for Identity {
    fn dim(&self) -> usize {
        self.0
    }
    fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        check_lengths(self.0, x, y)?;
        y.copy_from_slice(x);
        Ok(())
    }
}

/// A dense row-major matrix as an operator (the O(n²) control of the fast operators).
#[derive(Debug, Clone, PartialEq)]
pub struct DenseMatrix {
    n: usize,
    /// `a[i * n + j] = A_ij`.
    pub a: Vec<f64>,
}

impl DenseMatrix {
    /// Assembles `A` column by column from any operator: `A e_j` for every unit vector `e_j`.
    pub fn assemble(op: &mut dyn LinearOperator) -> Result<Self, NumericsError> {
        let n = op.dim();
        let mut a = vec![0.0; n * n];
        let mut e = vec![0.0; n];
        let mut col = vec![0.0; n];
        for j in 0..n {
            e[j] = 1.0;
            op.apply(&e, &mut col)?;
            e[j] = 0.0;
            for i in 0..n {
                a[i * n + j] = col[i];
            }
        }
        Ok(Self { n, a })
    }

    /// From a row-major array of `n²` values.
    pub fn from_row_major(n: usize, a: Vec<f64>) -> Result<Self, NumericsError> {
        if a.len() != n * n {
            return Err(NumericsError::LengthMismatch {
                what: "dense matrix entries",
                expected: n * n,
                got: a.len(),
            });
        }
        Ok(Self { n, a })
    }
}

impl LinearOperator for DenseMatrix {
    fn dim(&self) -> usize {
        self.n
    }
    fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        check_lengths(self.n, x, y)?;
        for (i, yi) in y.iter_mut().enumerate() {
            *yi = self.a[i * self.n..(i + 1) * self.n]
                .iter()
                .zip(x)
                .map(|(a, b)| a * b)
                .sum();
        }
        Ok(())
    }
}

/// Checks `|x| = |y| = n`.
pub fn check_lengths(n: usize, x: &[f64], y: &[f64]) -> Result<(), NumericsError> {
    for len in [x.len(), y.len()] {
        if len != n {
            return Err(NumericsError::LengthMismatch {
                what: "linear operator vector",
                expected: n,
                got: len,
            });
        }
    }
    Ok(())
}
