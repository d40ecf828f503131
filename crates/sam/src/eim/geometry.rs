//! Inhomogeneities (spheres, cylinders along `x₁` or `x₂`, cuboids) and their cells on the volume
//! lattice: cubes of the surface cell size `2Δ` under every surface cell, layer `k` centred at depth
//! `(2k + 1)Δ` (docs/theory-sam.md#conventions, docs/theory-sam.md#layered-operators). A cell belongs to an inhomogeneity when its centre lies inside.

use halfspace_numerics::NumericsError;

use crate::{SamError, SurfaceGrid};

/// The axis of a cylinder (it runs through the whole domain along that axis).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// Along `x₁`.
    X,
    /// Along `x₂`.
    Y,
}

/// The shape of an inhomogeneity; `z` is the depth of the centre (m, positive into the body).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// Sphere of radius `r` centred at `(x, y, z)`.
    Sphere {
        /// Centre `x₁`.
        x: f64,
        /// Centre `x₂`.
        y: f64,
        /// Centre depth.
        z: f64,
        /// Radius.
        r: f64,
    },
    /// Circular cylinder of radius `r` along `axis`, its axis at in-plane position `position`
    /// (`x₁` for a cylinder along `x₂`, `x₂` for one along `x₁`) and depth `z`.
    Cylinder {
        /// Direction.
        axis: Axis,
        /// In-plane coordinate of the axis across its direction.
        position: f64,
        /// Depth of the axis.
        z: f64,
        /// Radius.
        r: f64,
    },
    /// Cuboid centred at `(x, y, z)` with half sizes `(hx, hy, hz)`.
    Cuboid {
        /// Centre `x₁`.
        x: f64,
        /// Centre `x₂`.
        y: f64,
        /// Centre depth.
        z: f64,
        /// Half sizes.
        half: [f64; 3],
    },
}

/// One inhomogeneity: a shape and its isotropic material (`E = 0`: a void).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inhomogeneity {
    /// Shape and position.
    pub shape: Shape,
    /// Young's modulus in Pa (`≥ 0`).
    pub e: f64,
    /// Poisson ratio in `(−1, 0.5)`.
    pub nu: f64,
}

fn invalid(name: &'static str, value: f64, allowed: &'static str) -> SamError {
    SamError::InvalidParameter {
        name,
        value,
        allowed,
    }
}

impl Inhomogeneity {
    /// Checks sizes, depth and material.
    pub fn validate(&self) -> Result<(), SamError> {
        if !(self.e.is_finite() && self.e >= 0.0) {
            return Err(invalid(
                "inhomogeneity Young's modulus E",
                self.e,
                "finite and ≥ 0 (0 = void)",
            ));
        }
        if !(self.nu.is_finite() && self.nu > -1.0 && self.nu < 0.5) {
            return Err(invalid(
                "inhomogeneity Poisson ratio nu",
                self.nu,
                "in (−1, 0.5)",
            ));
        }
        let coordinates: Vec<(&'static str, f64)> = match self.shape {
            Shape::Sphere { x, y, .. } | Shape::Cuboid { x, y, .. } => {
                vec![("inhomogeneity centre x", x), ("inhomogeneity centre y", y)]
            }
            Shape::Cylinder { position, axis, .. } => vec![(
                match axis {
                    Axis::X => "cylinder axis position y",
                    Axis::Y => "cylinder axis position x",
                },
                position,
            )],
        };
        for (name, v) in coordinates {
            if !v.is_finite() {
                return Err(invalid(name, v, "finite (m)"));
            }
        }
        let (z, top, sizes): (f64, f64, Vec<f64>) = match self.shape {
            Shape::Sphere { z, r, .. } | Shape::Cylinder { z, r, .. } => (z, z - r, vec![r]),
            Shape::Cuboid { z, half, .. } => (z, z - half[2], half.to_vec()),
        };
        for s in sizes {
            if !(s.is_finite() && s > 0.0) {
                return Err(invalid(
                    "inhomogeneity size (r, or hx, hy, hz)",
                    s,
                    "finite and > 0 (m)",
                ));
            }
        }
        if !(z.is_finite() && z > 0.0) {
            return Err(invalid(
                "inhomogeneity centre depth z",
                z,
                "finite and > 0 (m, positive into the body; not above the surface)",
            ));
        }
        if top < 0.0 {
            return Err(invalid(
                "inhomogeneity top depth z − r (or z − hz)",
                top,
                "≥ 0 (m; below 0 it cuts the surface)",
            ));
        }
        Ok(())
    }

    /// Whether the point `p = (x₁, x₂, depth)` lies inside.
    pub fn contains(&self, p: [f64; 3]) -> bool {
        match self.shape {
            Shape::Sphere { x, y, z, r } => {
                let d = [p[0] - x, p[1] - y, p[2] - z];
                d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= r * r
            }
            Shape::Cylinder {
                axis,
                position,
                z,
                r,
            } => {
                let across = match axis {
                    Axis::X => p[1],
                    Axis::Y => p[0],
                };
                let (a, b) = (across - position, p[2] - z);
                a * a + b * b <= r * r
            }
            Shape::Cuboid { x, y, z, half } => {
                (p[0] - x).abs() <= half[0]
                    && (p[1] - y).abs() <= half[1]
                    && (p[2] - z).abs() <= half[2]
            }
        }
    }

    /// In-plane bounding box `[x_min, x_max, y_min, y_max]` (unbounded along a cylinder's axis) and
    /// the deepest point.
    /// The depth of its top (shallowest point), m.
    pub(crate) fn top(&self) -> f64 {
        match self.shape {
            Shape::Sphere { z, r, .. } | Shape::Cylinder { z, r, .. } => z - r,
            Shape::Cuboid { z, half, .. } => z - half[2],
        }
    }

    pub(crate) fn bounds(&self) -> ([f64; 4], f64) {
        match self.shape {
            Shape::Sphere { x, y, z, r } => ([x - r, x + r, y - r, y + r], z + r),
            Shape::Cylinder {
                axis,
                position,
                z,
                r,
            } => match axis {
                Axis::X => (
                    [f64::NEG_INFINITY, f64::INFINITY, position - r, position + r],
                    z + r,
                ),
                Axis::Y => (
                    [position - r, position + r, f64::NEG_INFINITY, f64::INFINITY],
                    z + r,
                ),
            },
            Shape::Cuboid { x, y, z, half } => (
                [x - half[0], x + half[0], y - half[1], y + half[1]],
                z + half[2],
            ),
        }
    }
}

/// The deepest layer index the geometry accepts (`depth/2Δ`): beyond it an inhomogeneity is
/// refused up front (its layers would not be indexed, nor its depth keys).
const MAX_LAYER_INDEX: f64 = 1e9;

/// Where the fibres of a unidirectional composite sit relative to the contact centre `x = 0`
/// (\[LN11\] does not give the positions: docs/theory-sam.md#inhomogeneity-references runs both).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FibreLayout {
    /// A fibre axis at `x = 0`.
    FibreCentred,
    /// The middle of a gap between two fibres at `x = 0`.
    GapCentred,
}

/// Parallel cylindrical fibres along `x₂` (perpendicular to a sliding motion along `x₁`) of radius
/// `r`, axes at depth `depth` and centre spacing `spacing`, every fibre whose section lies within
/// `|x₁| ≤ half_width` (\[LN11\]: `r = 0.13a`, spacing `3r`, depth `1.5r`).
pub fn fibres(
    r: f64,
    depth: f64,
    spacing: f64,
    half_width: f64,
    layout: FibreLayout,
    e: f64,
    nu: f64,
) -> Result<Vec<Inhomogeneity>, SamError> {
    for (name, v) in [
        ("fibre radius", r),
        ("fibre spacing", spacing),
        ("domain half width", half_width),
    ] {
        crate::error::positive(name, v)?;
    }
    if spacing < 2.0 * r {
        return Err(invalid(
            "fibre spacing (centre to centre) over the diameter",
            spacing / (2.0 * r),
            "≥ 1 (fibres must not overlap)",
        ));
    }
    let offset = match layout {
        FibreLayout::FibreCentred => 0.0,
        FibreLayout::GapCentred => 0.5 * spacing,
    };
    // Fibres on each side of the centre, counted before the list is allocated: a domain of 10¹²
    // fibre spacings is refused, not allocated (and cannot overflow the index).
    let reach = ((half_width - r) / spacing).floor() + 1.0;
    if !(reach.is_finite() && reach <= MAX_FIBRES_PER_SIDE) {
        return Err(SamError::InvalidInput(format!(
            "the domain (half width {half_width:e} m) holds about {:e} fibres of spacing \
             {spacing:e} m, more than {}: use a smaller domain (extent_over_a)",
            2.0 * reach + 1.0,
            2.0 * MAX_FIBRES_PER_SIDE + 1.0
        )));
    }
    let reach = reach as i64;
    let mut list = Vec::new();
    for k in -reach..=reach {
        let x = offset + k as f64 * spacing;
        if x.abs() + r <= half_width * (1.0 + 1e-12) {
            list.push(Inhomogeneity {
                shape: Shape::Cylinder {
                    axis: Axis::Y,
                    position: x,
                    z: depth,
                    r,
                },
                e,
                nu,
            });
        }
    }
    Ok(list)
}

/// The unidirectional composite of \[LN11\] (§4 of the paper, docs/theory-sam.md#inhomogeneity-references) below a contact of Hertz
/// radius `a`: fibres along `x₂` of radius `0.13a`, centre spacing `3r`, axes at depth `1.5r`,
/// Young's modulus `e_ratio · e_matrix` and the matrix's Poisson ratio, over `|x₁| ≤ half_width`.
pub fn composite_fibres(
    a: f64,
    half_width: f64,
    layout: FibreLayout,
    e_matrix: f64,
    nu: f64,
    e_ratio: f64,
) -> Result<Vec<Inhomogeneity>, SamError> {
    crate::error::positive("Hertz radius a", a)?;
    crate::error::positive("fibre_e_ratio (fibre to matrix modulus ratio)", e_ratio)?;
    let r = COMPOSITE_FIBRE_RADIUS * a;
    fibres(
        r,
        1.5 * r,
        3.0 * r,
        half_width,
        layout,
        e_ratio * e_matrix,
        nu,
    )
}

/// Fibre radius of \[LN11\]'s composite over the Hertz radius.
pub const COMPOSITE_FIBRE_RADIUS: f64 = 0.13;

/// Cells per fibre radius at the paper's resolution (128² over 4.16a).
pub const COMPOSITE_CELLS_PER_RADIUS: f64 = 4.0;

/// One inclusion cell: its layer, its surface cell and its material.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cell {
    /// Position of the layer in [`InclusionSet::layers`].
    pub layer: usize,
    /// Surface cell index `i N₂ + j`.
    pub flat: usize,
    /// Index `(i − i₀) n₂ + (j − j₀)` in the set's [`Window`].
    pub local: usize,
    /// Index into [`InclusionSet::materials`].
    pub material: usize,
}

/// A rectangle of surface cells `[i₀, i₀ + n₁) × [j₀, j₀ + n₂)`: the in-plane extent of the volume
/// lattice (the bounding box of the inclusion cells). Eigenstrains live on it, so the volume
/// operators cost `O(n₁n₂)` per layer pair, not `O(N₁N₂)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Window {
    /// First row.
    pub i0: usize,
    /// Rows.
    pub n1: usize,
    /// First column.
    pub j0: usize,
    /// Columns.
    pub n2: usize,
}

impl Window {
    /// The whole grid.
    pub fn full(grid: &SurfaceGrid) -> Self {
        Self {
            i0: 0,
            n1: grid.n1,
            j0: 0,
            n2: grid.n2,
        }
    }

    /// Cells in the window.
    pub fn len(&self) -> usize {
        self.n1 * self.n2
    }

    /// Whether the window is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether it covers the whole grid.
    pub fn is_full(&self, grid: &SurfaceGrid) -> bool {
        *self == Self::full(grid)
    }

    /// Copies a window field into a zeroed full-grid field. Errors: the window not inside `grid`,
    /// `local` not of the window's length or `full` not of the grid's.
    pub fn scatter(
        &self,
        grid: &SurfaceGrid,
        local: &[f64],
        full: &mut [f64],
    ) -> Result<(), SamError> {
        self.check_fields(grid, local.len(), full.len())?;
        full.fill(0.0);
        for a in 0..self.n1 {
            let row = (self.i0 + a) * grid.n2 + self.j0;
            full[row..row + self.n2].copy_from_slice(&local[a * self.n2..(a + 1) * self.n2]);
        }
        Ok(())
    }

    /// `local += full` restricted to the window. Errors as [`Window::scatter`].
    pub fn gather_add(
        &self,
        grid: &SurfaceGrid,
        full: &[f64],
        local: &mut [f64],
    ) -> Result<(), SamError> {
        self.check_fields(grid, local.len(), full.len())?;
        for a in 0..self.n1 {
            let row = (self.i0 + a) * grid.n2 + self.j0;
            for (l, f) in local[a * self.n2..(a + 1) * self.n2]
                .iter_mut()
                .zip(&full[row..row + self.n2])
            {
                *l += f;
            }
        }
        Ok(())
    }

    /// The window inside `grid`, else the typed error.
    pub fn check_inside(&self, grid: &SurfaceGrid) -> Result<(), SamError> {
        if self.i0 + self.n1 > grid.n1 || self.j0 + self.n2 > grid.n2 {
            return Err(invalid(
                "volume window rows/columns beyond the grid",
                (self.i0 + self.n1).max(self.j0 + self.n2) as f64,
                "inside the surface grid",
            ));
        }
        Ok(())
    }

    /// The window inside `grid`, a window field of `local` values and a grid field of `full`.
    fn check_fields(&self, grid: &SurfaceGrid, local: usize, full: usize) -> Result<(), SamError> {
        self.check_inside(grid)?;
        for (what, expected, got) in [
            ("window field", self.len(), local),
            ("full-grid field", grid.len(), full),
        ] {
            if expected != got {
                return Err(SamError::Numerics(NumericsError::LengthMismatch {
                    what,
                    expected,
                    got,
                }));
            }
        }
        Ok(())
    }
}

/// The cells of all inhomogeneities on the volume lattice of a surface grid.
#[derive(Debug, Clone, PartialEq)]
pub struct InclusionSet {
    /// Layer numbers `k` (centre depth `(2k+1)Δ`) that hold cells, ascending.
    pub layers: Vec<usize>,
    /// The cells, layer by layer, in surface order.
    pub cells: Vec<Cell>,
    /// Distinct materials `(E, ν)`.
    pub materials: Vec<(f64, f64)>,
    /// The cell half size `Δ`.
    pub half: f64,
    /// The bounding box of the cells (at least 2 × 2 cells).
    pub window: Window,
}

/// The most fibres on each side of the centre [`fibres`] lays out (a 10⁵-fibre row is far beyond
/// any grid the EIM can hold).
const MAX_FIBRES_PER_SIDE: f64 = 1e5;

/// "number k (counting from 1)" of `inh` in `list`.
fn position_of(list: &[Inhomogeneity], inh: &Inhomogeneity) -> usize {
    list.iter()
        .position(|i| std::ptr::eq(i, inh))
        .map_or(0, |p| p + 1)
}

impl InclusionSet {
    /// Assigns cells to inhomogeneities. Errors: invalid inhomogeneities, a square-cell grid is
    /// required, an inhomogeneity outside the domain or without a cell, overlaps of different
    /// materials, cells in the first layer (an inhomogeneity within `2Δ` of the surface).
    pub fn new(grid: &SurfaceGrid, list: &[Inhomogeneity]) -> Result<Self, SamError> {
        if (grid.half1 - grid.half2).abs() > 1e-12 * grid.half1 {
            return Err(SamError::InvalidInput(format!(
                "inhomogeneities need cubic cells: the cell aspect ratio Δ₂/Δ₁ is {}, it must be 1",
                grid.half2 / grid.half1
            )));
        }
        let d = grid.half1;
        let (lx, ly) = (grid.n1 as f64 * grid.half1, grid.n2 as f64 * grid.half2);
        let mut deepest: f64 = 0.0;
        for inh in list {
            inh.validate()?;
            let (b, deep) = inh.bounds();
            // A cylinder's bounds are infinite along its axis: it runs through the domain.
            // Touching the edge is inside (to the rounding of typed values: a thousandth of a cell).
            let outside = |v: f64, limit: f64| v.is_finite() && v > limit + 1e-3 * d;
            if outside(-b[0], lx) || outside(b[1], lx) || outside(-b[2], ly) || outside(b[3], ly) {
                let worst = [-lx - b[0], b[1] - lx, -ly - b[2], b[3] - ly]
                    .into_iter()
                    .filter(|v| v.is_finite())
                    .fold(0.0f64, f64::max);
                return Err(SamError::InvalidInput(format!(
                    "inhomogeneity {} reaches {worst:e} m beyond the domain edge: move it inside, \
                     or enlarge the domain extent",
                    position_of(list, inh)
                )));
            }
            deepest = deepest.max(deep);
        }
        // Layer k is centred at (2k + 1)Δ. Only the layers some inhomogeneity spans are scanned
        // (a deep one would otherwise cost a scan of every layer above it), in increasing order.
        if (deepest / (2.0 * d)).is_nan() || deepest / (2.0 * d) >= MAX_LAYER_INDEX {
            return Err(SamError::InvalidInput(format!(
                "an inhomogeneity reaches {deepest:e} m below the surface, more than {MAX_LAYER_INDEX:e} \
                 layers of 2Δ = {:e} m: move it up, or coarsen the grid",
                2.0 * d
            )));
        }
        let mut spanned: Vec<usize> = list
            .iter()
            .flat_map(|inh| {
                let lo = ((inh.top() / d - 1.0) / 2.0).floor().max(0.0) as usize;
                let hi = ((inh.bounds().1 / d - 1.0) / 2.0).ceil().max(0.0) as usize;
                lo..=hi
            })
            .collect();
        spanned.sort_unstable();
        spanned.dedup();
        let mut materials: Vec<(f64, f64)> = Vec::new();
        let mut layers = Vec::new();
        let mut cells = Vec::new();
        let mut owned = vec![false; list.len()];
        for k in spanned {
            let depth = (2 * k + 1) as f64 * d;
            let mut any = false;
            for i in 0..grid.n1 {
                for j in 0..grid.n2 {
                    let (x, y) = grid.centre(i, j);
                    let mut found: Option<(f64, f64)> = None;
                    for (idx, inh) in list.iter().enumerate() {
                        if !inh.contains([x, y, depth]) {
                            continue;
                        }
                        owned[idx] = true;
                        match found {
                            Some(m) if m != (inh.e, inh.nu) => {
                                return Err(SamError::InvalidInput(format!(
                                    "overlapping inhomogeneities of different materials (at \
                                     depth {depth:e} m): make them disjoint, or give them the \
                                     same E and nu"
                                )));
                            }
                            _ => found = Some((inh.e, inh.nu)),
                        }
                    }
                    let Some(m) = found else { continue };
                    if k == 0 {
                        return Err(SamError::InvalidInput(format!(
                            "an inhomogeneity has cells in the first layer below the surface \
                             (depth {depth:e} m, its top within 2Δ = {:e} m of the surface): \
                             refine the grid or move it down",
                            2.0 * d
                        )));
                    }
                    let material = match materials.iter().position(|q| *q == m) {
                        Some(p) => p,
                        None => {
                            materials.push(m);
                            materials.len() - 1
                        }
                    };
                    if !any {
                        layers.push(k);
                        any = true;
                    }
                    cells.push(Cell {
                        layer: layers.len() - 1,
                        flat: i * grid.n2 + j,
                        local: 0,
                        material,
                    });
                }
            }
        }
        // The bounding box, at least 2 × 2 (an FFT plan needs two cells a side).
        let (mut i_lo, mut i_hi, mut j_lo, mut j_hi) = (usize::MAX, 0, usize::MAX, 0);
        for c in &cells {
            let (i, j) = (c.flat / grid.n2, c.flat % grid.n2);
            i_lo = i_lo.min(i);
            i_hi = i_hi.max(i);
            j_lo = j_lo.min(j);
            j_hi = j_hi.max(j);
        }
        let widen = |lo: usize, hi: usize, n: usize| -> (usize, usize) {
            if cells.is_empty() {
                (0, n)
            } else if hi > lo {
                (lo, hi - lo + 1)
            } else if hi + 1 < n {
                (lo, 2)
            } else {
                (lo - 1, 2)
            }
        };
        let (i0, w1) = widen(i_lo, i_hi, grid.n1);
        let (j0, w2) = widen(j_lo, j_hi, grid.n2);
        let window = Window {
            i0,
            n1: w1,
            j0,
            n2: w2,
        };
        for c in cells.iter_mut() {
            let (i, j) = (c.flat / grid.n2, c.flat % grid.n2);
            c.local = (i - i0) * w2 + (j - j0);
        }
        if let Some(idx) = owned.iter().position(|o| !o) {
            return Err(SamError::InvalidInput(format!(
                "inhomogeneity {} (counting from 1) holds no cell centre: it is smaller than a \
                 cell (Δ = {:e} m) — refine the grid or enlarge it",
                idx + 1,
                2.0 * d
            )));
        }
        Ok(Self {
            layers,
            cells,
            materials,
            half: d,
            window,
        })
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// Whether there is no cell.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// Checks a set built or edited by hand (its fields are public) before operators index with
    /// it: every cell's layer, window position and material exist, its `flat` index is its
    /// window position on `grid`, and the window lies inside `grid`.
    pub fn check(&self, grid: &SurfaceGrid) -> Result<(), SamError> {
        let w = &self.window;
        w.check_inside(grid)?;
        for (c, cell) in self.cells.iter().enumerate() {
            let flat =
                (w.i0 + cell.local / w.n2.max(1)) * grid.n2 + w.j0 + cell.local % w.n2.max(1);
            if cell.layer >= self.layers.len()
                || cell.local >= w.len()
                || cell.material >= self.materials.len()
                || cell.flat != flat
            {
                return Err(SamError::InvalidInput(format!(
                    "inclusion set cell {c} ({cell:?}): its layer, window position, material or \
                     grid index does not exist in the set ({} layers, {} window cells, {} \
                     materials)",
                    self.layers.len(),
                    w.len(),
                    self.materials.len()
                )));
            }
        }
        Ok(())
    }
}
