//! The inhomogeneous body's surface response as an operator (docs/theory-sam.md#surface-response-operator):
//! the map from the surface tractions `(p, q₁, q₂)` on a set of candidate cells (those that can
//! touch) to the surface eigen-displacements `u^eig = (u₁, u₂, u₃)^eig` on the whole grid,
//!
//! `u^eig = T τ`,  `T = U ∘ 𝒟_s ∘ A⁻¹ ∘ ΔC ∘ L`,
//!
//! with `L` Love's applied strain of the tractions at the inclusion cells, `A = C^m − ΔC 𝒟` the
//! equivalency operator (\[LN11\] Eqs. 1–2), and `U ∘ 𝒟_s` the surface eigen-displacements of the
//! eigenstrains (\[LN11\] Eqs. 14–15). Every factor is linear and none depends on the load or the
//! surface geometry, so `T` is built once per body, column by column: column `(c, j)` is the
//! response to a unit traction component `c` on candidate cell `j`, one EIM solve from zero to the
//! full tolerance. This is the exact (uncompressed) operator; its cost is one EIM solve per column
//! (`3m` solves for `m` candidate cells with friction), so it suits regions of up to a few thousand
//! columns.

use super::solve::{EimParams, EimSystem};
use crate::SamError;

/// The dense surface response `T` over the candidate cells (docs/theory-sam.md#surface-response-operator).
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceResponse {
    /// Surface cells of the grid.
    n: usize,
    /// The candidate cells (grid indices, increasing).
    cells: Vec<usize>,
    /// Traction components: 1 (`p` only, frictionless) or 3 (`p, q₁, q₂`).
    components: usize,
    /// Column `c · m + j` (component `c`, candidate `j`) at `[k · 3n, (k + 1) · 3n)`: `u₁, u₂, u₃`
    /// on the whole grid (m per Pa).
    columns: Vec<f64>,
    /// EIM operator applications of the build.
    build_iterations: usize,
}

impl SurfaceResponse {
    /// Bytes of the operator for `n` grid cells, `m` candidates and `components` traction
    /// components: `3n · components · m` values.
    pub fn bytes(n: usize, m: usize, components: usize) -> f64 {
        8.0 * 3.0 * n as f64 * components as f64 * m as f64
    }

    /// Builds `T` column by column: for each component `c` and candidate `j`, the EIM solve of
    /// the unit traction `e_j` in component `c` (from zero eigenstrains, to `params.tolerance`),
    /// then its surface eigen-displacements. The memory is checked up front
    /// ([`halfspace_numerics::memory::check_fits`]).
    pub fn build(
        system: &mut EimSystem,
        cells: Vec<usize>,
        frictional: bool,
        params: &EimParams,
    ) -> Result<Self, SamError> {
        let grid = *system.fields().grid();
        let n = grid.len();
        if let Some(&bad) = cells.iter().find(|&&k| k >= n) {
            return Err(SamError::InvalidParameter {
                name: "surface-operator candidate cell",
                value: bad as f64,
                allowed: "a cell of the grid",
            });
        }
        if cells.windows(2).any(|w| w[0] >= w[1]) {
            return Err(SamError::InvalidInput(
                "surface-operator candidate cells must be increasing and distinct".into(),
            ));
        }
        let components = if frictional { 3 } else { 1 };
        let m = cells.len();
        halfspace_numerics::memory::check_fits(
            "the surface-response operator (3 · grid cells · 3 · candidate cells values)",
            Self::bytes(n, m, components),
        )?;
        let layers = system.set().layers.len();
        let window = system.set().window.len();
        let mut applied = vec![vec![0.0; window]; layers * 6];
        let mut eps = vec![0.0; 6 * system.set().len()];
        let mut traction = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        let mut columns = vec![0.0; 3 * n * components * m];
        let mut build_iterations = 0;
        for c in 0..components {
            for (j, &cell) in cells.iter().enumerate() {
                traction[c][cell] = 1.0;
                {
                    let [p, q1, q2] = &traction;
                    let q = frictional.then_some([q1.as_slice(), q2.as_slice()]);
                    system.fields().traction_strain(p, q, &mut applied)?;
                }
                traction[c][cell] = 0.0;
                eps.fill(0.0);
                build_iterations += system.solve(&applied, &mut eps, params)?.iterations;
                system.disturbance(&eps)?;
                let col = &mut columns[(c * m + j) * 3 * n..(c * m + j + 1) * 3 * n];
                let (u1, rest) = col.split_at_mut(n);
                let (u2, u3) = rest.split_at_mut(n);
                system.fields().eigen_displacements([u1, u2, u3])?;
            }
        }
        Ok(Self {
            n,
            cells,
            components,
            columns,
            build_iterations,
        })
    }

    /// `u^eig = T τ` for the tractions `p` and (with friction) `q = (q₁, q₂)` on the whole grid;
    /// every traction outside the candidate cells must be zero (else
    /// [`SamError::ContactOutsideSurfaceOperator`]).
    pub fn apply(
        &self,
        p: &[f64],
        q: Option<[&[f64]; 2]>,
        u: [&mut [f64]; 3],
    ) -> Result<(), SamError> {
        let n = self.n;
        for f in std::iter::once(p).chain(q.into_iter().flatten()) {
            if f.len() != n {
                return Err(length("surface traction", n, f.len()));
            }
        }
        for f in &u {
            if f.len() != n {
                return Err(length("eigen-displacement field", n, f.len()));
            }
        }
        // Tractions off the candidates have no column.
        let outside = |f: &[f64]| {
            let mut inside = self.cells.iter().peekable();
            f.iter()
                .enumerate()
                .filter(|&(k, v)| {
                    while inside.peek().is_some_and(|&&c| c < k) {
                        inside.next();
                    }
                    *v != 0.0 && inside.peek() != Some(&&k)
                })
                .count()
        };
        let fields: Vec<&[f64]> = match q {
            Some([q1, q2]) if self.components == 3 => vec![p, q1, q2],
            Some([q1, q2]) => {
                if q1.iter().chain(q2).any(|v| *v != 0.0) {
                    return Err(SamError::InvalidInput(
                        "shear on a surface operator built without friction".into(),
                    ));
                }
                vec![p]
            }
            None => vec![p],
        };
        let stray: usize = fields.iter().map(|f| outside(f)).sum();
        if stray > 0 {
            return Err(SamError::ContactOutsideSurfaceOperator { cells: stray });
        }
        let [u1, u2, u3] = u;
        u1.fill(0.0);
        u2.fill(0.0);
        u3.fill(0.0);
        let m = self.cells.len();
        for (c, f) in fields.iter().enumerate() {
            for (j, &cell) in self.cells.iter().enumerate() {
                let t = f[cell];
                if t == 0.0 {
                    continue;
                }
                let col = &self.columns[(c * m + j) * 3 * n..(c * m + j + 1) * 3 * n];
                for (out, part) in [&mut *u1, &mut *u2, &mut *u3]
                    .into_iter()
                    .zip(col.chunks(n))
                {
                    out.iter_mut().zip(part).for_each(|(o, v)| *o += t * v);
                }
            }
        }
        Ok(())
    }

    /// The candidate cells.
    pub fn cells(&self) -> &[usize] {
        &self.cells
    }

    /// Traction components (1 or 3).
    pub fn components(&self) -> usize {
        self.components
    }

    /// EIM operator applications the build took.
    pub fn build_iterations(&self) -> usize {
        self.build_iterations
    }

    /// The restriction of `T` to the candidates, `T_{(a,i),(c,j)}` = `u_a` at candidate `i` of a
    /// unit traction `c` on candidate `j` (`3m × components·m`, row-major).
    pub fn restricted(&self) -> Vec<f64> {
        let m = self.cells.len();
        let cols = self.components * m;
        let mut out = vec![0.0; 3 * m * cols];
        for k in 0..cols {
            let col = &self.columns[k * 3 * self.n..(k + 1) * 3 * self.n];
            for a in 0..3 {
                for (i, &cell) in self.cells.iter().enumerate() {
                    out[(a * m + i) * cols + k] = col[a * self.n + cell];
                }
            }
        }
        out
    }

    /// The asymmetry of the square operator work-conjugate pairs make of `T` (pressure with
    /// `u₃`, `q_α` with `u_α`), `max |S − Sᵀ| / max |S|` with `S_{(c,i),(c',j)}` = the
    /// displacement conjugate to `c` at candidate `i` of a unit traction `c'` on candidate `j`: zero
    /// in the continuum by Betti's reciprocity; the discretisation (uniform tractions on cells in,
    /// point displacements at cell centres out) leaves a part of the order of the collocation
    /// error.
    pub fn asymmetry(&self) -> f64 {
        let m = self.cells.len();
        let cols = self.components * m;
        let t = self.restricted();
        // The displacement conjugate to traction component c: p ↔ u₃, q₁ ↔ u₁, q₂ ↔ u₂.
        let conjugate = |k: usize| {
            let (c, j) = (k / m, k % m);
            [2, 0, 1][c] * m + j
        };
        let s = |r: usize, k: usize| t[conjugate(r) * cols + k];
        let mut scale: f64 = 0.0;
        let mut worst: f64 = 0.0;
        for r in 0..cols {
            for k in 0..cols {
                scale = scale.max(s(r, k).abs());
                worst = worst.max((s(r, k) - s(k, r)).abs());
            }
        }
        if scale > 0.0 {
            worst / scale
        } else {
            0.0
        }
    }
}

fn length(what: &'static str, expected: usize, got: usize) -> SamError {
    SamError::Numerics(halfspace_numerics::NumericsError::LengthMismatch {
        what,
        expected,
        got,
    })
}
