//! The discrete operators of the equivalent inclusion method on the layered lattice (docs/theory-sam.md#mirror-image-and-correction-pressure,
//! docs/theory-sam.md#layered-operators, docs/theory-sam.md#eigen-displacements; \[LN11\] Eqs. 11–16):
//!
//! * eigenstrain `ε*` (6 components per cell of the source layers) → **disturbance strain** at the
//!   cell centres of the target layers, `ε^d = ε⁽¹⁾ + ε⁽²⁾ + ε⁽³⁾`: the cuboids in infinite space
//!   (kernel `D(Δx, x₃ − x₃′)`, by layer difference), their mirror images (`D(Δx, x₃ + x₃′)` with the
//!   13 and 23 columns negated, by layer sum) and the Boussinesq field of the correction pressure
//!   `p_c = 2 σ⁽¹⁾₃₃(x, 0)` (Love's rectangle stresses at the target depth, converted to strain);
//! * the **surface eigen-displacements** `u₃^eig = K^p₃ * p_c`, `u_α^eig = 2u_α⁽¹⁾ + K^p_α * p_c`;
//! * surface tractions `(p, q₁, q₂)` → the **applied strain** `ε⁰` at every target layer.
//!
//! Each is a layered DC-FFT ([`halfspace_numerics::layered`]). The eigenstrains and the volume
//! strains live on a [`Window`] of the surface grid (the bounding box of the inclusion cells): the
//! volume part (fields (1) + (2)) runs on the window's own plan, so its cost does not grow with the
//! contact grid; the surface parts (`p_c`, eigen-displacements, Love strains) run on the whole
//! surface grid's plan, where the window's fields are scattered. [`Backend::Dense`] evaluates the
//! same sums directly (the control of the tests).

use halfspace_numerics::fft2d::{Fft2d, C64};
use halfspace_numerics::fft_batch::FftBatch;
use halfspace_numerics::layered::{DenseLayered, Family, LayerKernel, LayeredSpectra};

use std::ops::Range;

use super::geometry::Window;
use crate::kernels::cuboid::{DisplacementPotentials, StrainPotentials};
use crate::kernels::subsurface::unit_traction_stresses;
use crate::kernels::surface::{corner_sum, primitive_a, primitive_b};
use crate::kernels::{compliance, stiffness};
use crate::{SamError, SurfaceGrid};

/// Infinite space or the half-space `x₃ ≥ 0` with a traction-free surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Space {
    /// Infinite space (field (1) only): for checks against Eshelby's solution.
    Infinite,
    /// Half-space: fields (1) + (2) + (3).
    HalfSpace,
}

/// How the sums are evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Backend {
    /// Layered DC-FFT, O(N log N) per layer pair.
    Fft,
    /// Direct summation, O(N²) per layer pair (the control).
    Dense,
}

/// How often the index 1 (`x₁`) and the index 2 (`x₂`) occur in each Voigt component: a tensor
/// component changes sign under `x_α → −x_α` when its index `α` occurs an odd number of times.
const VOIGT_COUNTS: [(usize, usize); 6] = [(2, 0), (0, 2), (0, 0), (0, 1), (1, 0), (1, 1)];

/// Parities of the blocks `out × in` from the index counts of each output and input.
fn parities(outs: &[(usize, usize)], ins: &[(usize, usize)]) -> Vec<(bool, bool)> {
    outs.iter()
        .flat_map(|o| {
            ins.iter()
                .map(move |i| ((o.0 + i.0) % 2 == 1, (o.1 + i.1) % 2 == 1))
        })
        .collect()
}

/// `D(x)` of a cube of half size `Δ`, all 36 blocks (infinite part, layer difference).
pub(crate) struct InfiniteStrain {
    pub(crate) half: f64,
    pub(crate) nu: f64,
}

impl LayerKernel for InfiniteStrain {
    fn blocks(&self) -> (usize, usize) {
        (6, 6)
    }
    fn eval(&self, key: i64, m: i64, n: i64, out: &mut [f64]) {
        let d = self.half;
        let x = [2.0 * d * m as f64, 2.0 * d * n as f64, d * key as f64];
        let v = StrainPotentials::new(x, [d; 3]).voigt(self.nu);
        for (o, row) in v.iter().enumerate() {
            out[o * 6..o * 6 + 6].copy_from_slice(row);
        }
    }
    fn parity(&self) -> Option<Vec<(bool, bool)>> {
        Some(parities(&VOIGT_COUNTS, &VOIGT_COUNTS))
    }
}

/// The mirror image: `D(x₁, x₂, x₃ + x₃′)` acting on `ε*ˢ = (ε*₁₁, ε*₂₂, ε*₃₃, −ε*₂₃, −ε*₁₃, ε*₁₂)`.
pub(crate) struct ImageStrain(pub(crate) InfiniteStrain);

impl LayerKernel for ImageStrain {
    fn blocks(&self) -> (usize, usize) {
        (6, 6)
    }
    fn eval(&self, key: i64, m: i64, n: i64, out: &mut [f64]) {
        self.0.eval(key, m, n, out);
        for o in 0..6 {
            out[o * 6 + 3] = -out[o * 6 + 3];
            out[o * 6 + 4] = -out[o * 6 + 4];
        }
    }
    fn parity(&self) -> Option<Vec<(bool, bool)>> {
        self.0.parity()
    }
}

/// Surface fields of the cuboid and its image at `x₃ = 0`: `p_c = 2 (C:D)₃₃`, `2 Dˢ₁`, `2 Dˢ₂`.
pub(crate) struct SurfaceFields {
    pub(crate) half: f64,
    pub(crate) nu: f64,
    pub(crate) c: [[f64; 6]; 6],
}

impl LayerKernel for SurfaceFields {
    fn blocks(&self) -> (usize, usize) {
        (3, 6)
    }
    fn eval(&self, key: i64, m: i64, n: i64, out: &mut [f64]) {
        let d = self.half;
        let x = [2.0 * d * m as f64, 2.0 * d * n as f64, d * key as f64];
        let strain = StrainPotentials::new(x, [d; 3]).voigt(self.nu);
        let disp = DisplacementPotentials::new(x, [d; 3]).voigt(self.nu);
        for i in 0..6 {
            let s33: f64 = (0..6).map(|r| self.c[2][r] * strain[r][i]).sum();
            out[i] = 2.0 * s33;
            out[6 + i] = 2.0 * disp[0][i];
            out[12 + i] = 2.0 * disp[1][i];
        }
    }
    fn parity(&self) -> Option<Vec<(bool, bool)>> {
        // Rows: σ₃₃, u₁, u₂.
        Some(parities(&[(0, 0), (1, 0), (0, 1)], &VOIGT_COUNTS))
    }
}

/// Strain at depth `key Δ` per unit traction `(p, q₁, q₂)` on a surface cell (Love, docs/theory-sam.md#love-rectangle-stresses,
/// then `C⁻¹`).
pub(crate) struct LoveStrain {
    pub(crate) half: f64,
    pub(crate) nu: f64,
    pub(crate) s: [[f64; 6]; 6],
}

impl LayerKernel for LoveStrain {
    fn blocks(&self) -> (usize, usize) {
        (6, 3)
    }
    fn eval(&self, key: i64, m: i64, n: i64, out: &mut [f64]) {
        let stresses = unit_traction_stresses(key, m, n, self.half, self.nu);
        for (i, sigma) in stresses.iter().enumerate() {
            for o in 0..6 {
                out[o * 3 + i] = (0..6).map(|r| self.s[o][r] * sigma[r]).sum();
            }
        }
    }
    fn parity(&self) -> Option<Vec<(bool, bool)>> {
        // Inputs: p, q₁, q₂.
        Some(parities(&VOIGT_COUNTS, &[(0, 0), (1, 0), (0, 1)]))
    }
}

/// One layered operator under either backend.
enum Layered {
    Fast(LayeredSpectra),
    Dense(DenseLayered),
}

impl Layered {
    fn new(
        backend: Backend,
        fft: &mut Fft2d,
        targets: &[i64],
        sources: &[i64],
        families: &[(Family, &dyn LayerKernel)],
    ) -> Result<Self, SamError> {
        let (n1, n2) = fft.shape();
        Ok(match backend {
            Backend::Fft => Layered::Fast(LayeredSpectra::new(fft, targets, sources, families)?),
            Backend::Dense => Layered::Dense(DenseLayered::new(n1, n2, targets, sources, families)),
        })
    }

    fn bytes(&self) -> usize {
        match self {
            Layered::Fast(s) => s.bytes(),
            Layered::Dense(_) => 0,
        }
    }

    /// `y = K x` for fields of the plan's shape (FFT: `x` transformed into `x_hat`, products in
    /// `y_hat`; dense: direct sums). The inputs are zero outside the rows `rows.0` and only the
    /// rows `rows.1` of the outputs are wanted (FFT: the other row transforms are skipped; the other
    /// output rows are left stale). `y` may hold only the first outputs of an operator with one
    /// target (the surface fields: `p_c` alone); those are the same, bit for bit.
    #[allow(clippy::too_many_arguments)]
    fn apply<X: AsRef<[f64]> + Sync, Y: AsMut<[f64]> + Send>(
        &self,
        batch: &FftBatch,
        x: &[X],
        x_hat: &mut [Vec<C64>],
        skip: &mut [bool],
        y_hat: &mut [Vec<C64>],
        y: &mut [Y],
        rows: (Range<usize>, Range<usize>),
    ) -> Result<(), SamError> {
        match self {
            Layered::Fast(spectra) => {
                let n1 = batch.shape().0;
                let rows_in = rows.0.start.min(n1)..rows.0.end.min(n1);
                let rows_out = rows.1.start.min(n1)..rows.1.end.min(n1);
                // The zero checks and the transforms, one field per task (batched).
                batch.forward(x, rows_in, &mut x_hat[..x.len()], &mut skip[..x.len()])?;
                let outputs = match spectra.targets().len() {
                    0 => spectra.blocks().0,
                    nt => y.len() / nt,
                };
                // The dense twin reads `y[a · n_out + o]`: fewer outputs only with one target.
                if outputs != spectra.blocks().0 && spectra.targets().len() != 1 {
                    return Err(SamError::Numerics(
                        halfspace_numerics::NumericsError::LengthMismatch {
                            what: "layered operator outputs (fewer than all only with one target)",
                            expected: spectra.targets().len() * spectra.blocks().0,
                            got: y.len(),
                        },
                    ));
                }
                let y_hat = &mut y_hat[..y.len()];
                spectra.assign_leading(x_hat, skip, outputs, y_hat)?;
                batch.inverse(y_hat, rows_out, y)?;
            }
            Layered::Dense(dense) => {
                let x: Vec<&[f64]> = x.iter().map(AsRef::as_ref).collect();
                let mut y: Vec<&mut [f64]> = y.iter_mut().map(AsMut::as_mut).collect();
                dense.direct_sum(&x, &mut y);
            }
        }
        Ok(())
    }
}

/// `strain += crop(Love(x))`: Love's strains of the surface tractions `x = (p, q₁, q₂)` (whole grid)
/// at the target layers, only the window's rows transformed back, added to the window fields.
fn love_into_window(
    love: &Layered,
    batch: &FftBatch,
    work: &mut Work,
    love_full: &mut [Vec<f64>],
    (window, grid): (&Window, &SurfaceGrid),
    x: &[&[f64]; 3],
    strain: &mut [Vec<f64>],
) -> Result<(), SamError> {
    let rows = window.i0..window.i0 + window.n1;
    love.apply(
        batch,
        x,
        &mut work.x_hat,
        &mut work.skip,
        &mut work.y_hat,
        love_full,
        (0..usize::MAX, rows),
    )?;
    for (full, local) in love_full.iter().zip(strain.iter_mut()) {
        window.gather_add(grid, full, local)?;
    }
    Ok(())
}

/// Spectra bytes a layered operator with these counts would store, per docs/theory-sam.md#layered-operators:
/// `keys · blocks · 2n₁(n₂+1)` complex values.
pub fn estimated_bytes(n1: usize, n2: usize, keys: usize, blocks: usize) -> f64 {
    keys as f64 * blocks as f64 * (2 * n1 * (n2 + 1)) as f64 * 16.0
}

/// Memory the machine may use for stored spectra before a request is refused up front.
pub const SPECTRA_LIMIT_BYTES: f64 = 16.0 * (1u64 << 30) as f64;

/// Work arrays of one plan: input spectra, skip flags, output spectra.
struct Work {
    x_hat: Vec<Vec<C64>>,
    skip: Vec<bool>,
    y_hat: Vec<Vec<C64>>,
}

impl Work {
    fn new(fft: &Fft2d, backend: Backend, inputs: usize, outputs: usize) -> Self {
        let on = usize::from(backend == Backend::Fft);
        Self {
            x_hat: (0..inputs * on).map(|_| fft.new_spectrum()).collect(),
            skip: vec![false; inputs],
            y_hat: (0..outputs * on).map(|_| fft.new_spectrum()).collect(),
        }
    }

    /// The spectra of the eigenstrain components `eigen` on the whole grid into `x_hat`; `skip`
    /// marks the components zero everywhere (not transformed; [`LayeredSpectra::accumulate`]
    /// passes over them).
    fn transform_inputs(&mut self, batch: &FftBatch, eigen: &[Vec<f64>]) -> Result<(), SamError> {
        batch.forward(eigen, 0..batch.shape().0, &mut self.x_hat, &mut self.skip)?;
        Ok(())
    }

    /// `fields` = the surface operator `spectra` applied to the input spectra of `inputs`
    /// ([`Work::transform_inputs`]): accumulated in this work's output spectra, one inverse
    /// transform per field (docs/theory-sam.md#eigen-displacements). `fields` may be the first of
    /// the three (`p_c` alone).
    fn surface_fields(
        &mut self,
        batch: &FftBatch,
        spectra: &LayeredSpectra,
        inputs: &Work,
        fields: &mut [Vec<f64>],
    ) -> Result<(), SamError> {
        let y_hat = &mut self.y_hat[..fields.len()];
        spectra.assign_leading(&inputs.x_hat, &inputs.skip, fields.len(), y_hat)?;
        batch.inverse(y_hat, 0..batch.shape().0, fields)?;
        Ok(())
    }
}

/// The EIM field operators between source layers (where the eigenstrain lives) and target layers
/// (where strains are wanted), planned once.
pub struct EimFields {
    grid: SurfaceGrid,
    window: Window,
    space: Space,
    /// Plan of the whole surface grid (surface fields, Love strains).
    fft: Fft2d,
    /// Batched transforms on `fft`'s plan (one transform per task: docs/performance.md, "One EIM
    /// application on two cores").
    batch: FftBatch,
    /// Batched transforms on the window's plan (volume fields).
    wbatch: FftBatch,
    sources: Vec<i64>,
    targets: Vec<i64>,
    volume: Layered,
    surface: Option<Layered>,
    love: Layered,
    /// Surface compliance spectra of the half-space alone, per unit pressure: `u₁, u₂, u₃`.
    boussinesq: Option<[Vec<C64>; 3]>,
    volume_work: Work,
    surface_work: Work,
    love_work: Work,
    /// `p_c`, `2u₁⁽¹⁾`, `2u₂⁽¹⁾` of the last disturbance (whole grid).
    surface_fields: [Vec<f64>; 3],
    /// Whether `2u_α⁽¹⁾` are those of the last disturbance (not after
    /// [`EimFields::disturbance_strain`], which computes `p_c` alone).
    displacements_current: bool,
    /// Window eigenstrains scattered on the whole grid.
    scattered: Vec<Vec<f64>>,
    /// Love strains on the whole grid at the target layers.
    love_full: Vec<Vec<f64>>,
    /// Spectra of `p_c` and of one eigen-displacement component.
    eig_hat: [Vec<C64>; 2],
    zero: Vec<f64>,
}

impl EimFields {
    /// The operators the contact solvers use for `set` (docs/theory-sam.md#nested-loops): sources
    /// and targets on the set's layers and window, in the half-space `(E, ν)`, FFT backend
    /// ([`EimFields::new`]).
    pub fn for_inclusions(
        grid: SurfaceGrid,
        e: f64,
        nu: f64,
        set: &super::geometry::InclusionSet,
    ) -> Result<Self, SamError> {
        Self::new(
            grid,
            e,
            nu,
            &set.layers,
            &set.layers,
            set.window,
            Space::HalfSpace,
            Backend::Fft,
        )
    }

    /// Plans the operators for eigenstrains on `source_layers` and strains on `target_layers` (layer
    /// numbers `k`, centre depth `(2k+1)Δ`, `Δ` = the grid's half cell size), both on `window`, in a
    /// matrix `(E, ν)`. Refuses up front a request whose stored spectra would not fit in memory.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        grid: SurfaceGrid,
        e: f64,
        nu: f64,
        source_layers: &[usize],
        target_layers: &[usize],
        window: Window,
        space: Space,
        backend: Backend,
    ) -> Result<Self, SamError> {
        crate::error::positive("matrix Young's modulus", e)?;
        if !(nu > -1.0 && nu < 0.5) {
            return Err(SamError::InvalidParameter {
                name: "matrix Poisson ratio (with inhomogeneities)",
                value: nu,
                allowed: "in (−1, 0.5)",
            });
        }
        window.check_inside(&grid)?;
        let key = |k: &usize| (2 * k + 1) as i64;
        let sources: Vec<i64> = source_layers.iter().map(key).collect();
        let targets: Vec<i64> = target_layers.iter().map(key).collect();
        let (ns, nt) = (sources.len(), targets.len());
        let families = if space == Space::HalfSpace { 2 } else { 1 };
        // An upper bound of the build's peak: the complex 2D spectra of every family's keys (when
        // targets = sources, the EIM's case, the depth-FFT build holds one family's at a time,
        // then the quarter-stored depth spectra, the difference family's stored real, ≈ 0.4 of one
        // family's) and of the surface and Love operators (their build holds one operator's
        // complex spectra, then stores them by quarter: a quarter of the bytes). Stored at 128²
        // (composite, 8 layers): 169 MB (326 MB with complex storage), against 1.3 GB here.
        let need = estimated_bytes(
            window.n1,
            window.n2,
            families * (ns + nt).saturating_sub(1),
            36,
        ) + estimated_bytes(grid.n1, grid.n2, ns + nt, 18);
        if backend == Backend::Fft && need > SPECTRA_LIMIT_BYTES {
            return Err(SamError::InvalidParameter {
                name: "memory for the stored eigenstrain kernel spectra (bytes)",
                value: need,
                allowed: "≤ 16 GiB: use fewer cells or layers",
            });
        }
        let mut fft = Fft2d::new(grid.n1, grid.n2)?;
        let mut wfft = Fft2d::new(window.n1, window.n2)?;
        let half = grid.half1;
        let inf = InfiniteStrain { half, nu };
        let img = ImageStrain(InfiniteStrain { half, nu });
        let vol_families: Vec<(Family, &dyn LayerKernel)> = match space {
            Space::Infinite => vec![(Family::Difference, &inf)],
            Space::HalfSpace => vec![(Family::Difference, &inf), (Family::Sum, &img)],
        };
        let volume = Layered::new(backend, &mut wfft, &targets, &sources, &vol_families)?;
        let love_kernel = LoveStrain {
            half,
            nu,
            s: compliance(e, nu),
        };
        let love = Layered::new(
            backend,
            &mut fft,
            &targets,
            &[0],
            &[(Family::Difference, &love_kernel)],
        )?;
        let (surface, boussinesq) = if space == Space::HalfSpace {
            let sk = SurfaceFields {
                half,
                nu,
                c: stiffness(e, nu),
            };
            let surface = Layered::new(
                backend,
                &mut fft,
                &[0],
                &sources,
                &[(Family::Difference, &sk)],
            )?;
            let body = crate::kernels::surface::Compliance::pair(
                crate::Body::Rigid,
                crate::Body::elastic(e, nu)?,
            )?;
            let (d1, d2) = (2.0 * grid.half1, 2.0 * grid.half2);
            let mut b = [fft.new_spectrum(), fft.new_spectrum(), fft.new_spectrum()];
            let k1 = |m: i64, n: i64| {
                -body.coupling * corner_sum(primitive_b, m as f64 * d1, n as f64 * d2, half, half)
            };
            let k2 = |m: i64, n: i64| {
                -body.coupling
                    * corner_sum(
                        |a, c| primitive_b(c, a),
                        m as f64 * d1,
                        n as f64 * d2,
                        half,
                        half,
                    )
            };
            let k3 = |m: i64, n: i64| {
                body.normal * corner_sum(primitive_a, m as f64 * d1, n as f64 * d2, half, half)
            };
            fft.kernel_spectrum(&k1, &mut b[0])?;
            fft.kernel_spectrum(&k2, &mut b[1])?;
            fft.kernel_spectrum(&k3, &mut b[2])?;
            (Some(surface), Some(b))
        } else {
            (None, None)
        };
        let n = grid.len();
        let half_space = usize::from(space == Space::HalfSpace);
        // The window's eigenstrains scattered on the whole grid and their spectra: only off the
        // shared path (a whole-grid window on the FFT backend shares the volume's input spectra,
        // `disturbance_shared`).
        let windowed = usize::from(!(window.is_full(&grid) && backend == Backend::Fft));
        Ok(Self {
            eig_hat: [fft.new_spectrum(), fft.new_spectrum()],
            volume_work: Work::new(&wfft, backend, ns * 6, nt * 6),
            surface_work: Work::new(
                &fft,
                backend,
                ns * 6 * half_space * windowed,
                3 * half_space,
            ),
            love_work: Work::new(&fft, backend, 3, nt * 6),
            grid,
            window,
            space,
            batch: FftBatch::new(&fft),
            wbatch: FftBatch::new(&wfft),
            fft,
            sources,
            targets,
            volume,
            surface,
            love,
            boussinesq,
            surface_fields: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            displacements_current: true,
            scattered: vec![vec![0.0; n]; ns * 6 * half_space * windowed],
            // Off the shared path only (a whole-grid window on the FFT backend transforms Love's
            // strains back into the window fields themselves).
            love_full: vec![vec![0.0; n]; nt * 6 * windowed],
            zero: vec![0.0; n],
        })
    }

    /// The surface grid.
    pub fn grid(&self) -> &SurfaceGrid {
        &self.grid
    }

    /// The window the eigenstrains and volume strains live on.
    pub fn window(&self) -> &Window {
        &self.window
    }

    /// Number of source and target layers.
    pub fn layer_counts(&self) -> (usize, usize) {
        (self.sources.len(), self.targets.len())
    }

    /// The volume operator's difference family stored real (its depth spectra are real or
    /// imaginary: [`LayeredSpectra::real_storage_discarded`]): the largest dropped part over the
    /// largest kept value, per block; `None` when it is stored complex (or dense).
    pub fn real_storage_discarded(&self) -> Option<f64> {
        match &self.volume {
            Layered::Fast(s) => s.real_storage_discarded(),
            Layered::Dense(_) => None,
        }
    }

    /// The surface and Love operators' spectra stored by quarter
    /// ([`LayeredSpectra::quarter_storage_discarded`]): the largest dropped part over the largest
    /// kept value, per block, the larger of the two operators'; `None` when neither is.
    pub fn quarter_storage_discarded(&self) -> Option<f64> {
        let of = |l: &Layered| match l {
            Layered::Fast(s) => s.quarter_storage_discarded(),
            Layered::Dense(_) => None,
        };
        [Some(&self.love), self.surface.as_ref()]
            .into_iter()
            .flatten()
            .filter_map(of)
            .reduce(f64::max)
    }

    /// Bytes of stored kernel spectra.
    pub fn spectra_bytes(&self) -> usize {
        self.volume.bytes()
            + self.love.bytes()
            + self.surface.as_ref().map_or(0, |s| s.bytes())
            + self.boussinesq.as_ref().map_or(0, |b| 3 * b[0].len() * 16)
    }

    /// `strain[a · 6 + o] = ε^d_o` on target layer `a` from `eigen[b · 6 + i] = ε*_i` on source layer
    /// `b` (each a window field): fields (1) + (2) + (3) of docs/theory-sam.md#mirror-image-and-correction-pressure in the half-space, (1) in
    /// infinite space. Keeps `p_c` and `2u_α⁽¹⁾` for [`EimFields::eigen_displacements`].
    pub fn disturbance(
        &mut self,
        eigen: &[Vec<f64>],
        strain: &mut [Vec<f64>],
    ) -> Result<(), SamError> {
        self.disturbance_with(eigen, strain, 3)
    }

    /// [`EimFields::disturbance`] without the surface displacements `2u_α⁽¹⁾`: the strain at the
    /// target layers and `p_c` (field (3) reads `p_c` alone), bit for bit those of the full
    /// disturbance, with a third of its surface products and two inverse transforms fewer — what
    /// the EIM iteration applies ([`super::EimSystem`]). Until the next [`EimFields::disturbance`]
    /// or [`EimFields::surface_disturbance`], [`EimFields::eigen_displacements`] is refused.
    pub fn disturbance_strain(
        &mut self,
        eigen: &[Vec<f64>],
        strain: &mut [Vec<f64>],
    ) -> Result<(), SamError> {
        self.disturbance_with(eigen, strain, 1)
    }

    /// The disturbance with the first `surface` of the surface fields (`p_c`, `2u₁⁽¹⁾`,
    /// `2u₂⁽¹⁾`): 3 or 1.
    fn disturbance_with(
        &mut self,
        eigen: &[Vec<f64>],
        strain: &mut [Vec<f64>],
        surface: usize,
    ) -> Result<(), SamError> {
        let (ns, nt) = (self.sources.len(), self.targets.len());
        let wl = self.window.len();
        if eigen.len() != ns * 6
            || strain.len() != nt * 6
            || eigen.iter().chain(strain.iter()).any(|f| f.len() != wl)
        {
            return Err(SamError::Numerics(
                halfspace_numerics::NumericsError::LengthMismatch {
                    what: "eigenstrain / strain fields (6 per layer, window-sized)",
                    expected: if eigen.len() != ns * 6 {
                        ns * 6
                    } else {
                        nt * 6
                    },
                    got: if eigen.len() != ns * 6 {
                        eigen.len()
                    } else {
                        strain.len()
                    },
                },
            ));
        }
        if self.window.is_full(&self.grid) && self.surface.is_some() {
            if let (Layered::Fast(_), Layered::Fast(_)) = (&self.volume, &self.love) {
                return self.disturbance_shared(eigen, strain, surface);
            }
        }
        // Fields (1) + (2) on the window.
        {
            let w = &mut self.volume_work;
            self.volume.apply(
                &self.wbatch,
                eigen,
                &mut w.x_hat,
                &mut w.skip,
                &mut w.y_hat,
                strain,
                (0..usize::MAX, 0..usize::MAX),
            )?;
        }
        if self.surface.is_none() {
            return Ok(());
        }
        self.surface_fields_from_window(eigen, surface)?;
        // Field (3): Love strains of p_c, cropped to the window and added.
        let x: [&[f64]; 3] = [&self.surface_fields[0], &self.zero, &self.zero];
        love_into_window(
            &self.love,
            &self.batch,
            &mut self.love_work,
            &mut self.love_full,
            (&self.window, &self.grid),
            &x,
            strain,
        )
    }

    /// Only the surface fields `p_c` and `2u_α⁽¹⁾` of [`EimFields::disturbance`] (what
    /// [`EimFields::eigen_displacements`] and [`EimFields::correction_pressure`] read;
    /// docs/theory-sam.md#eigen-displacements): the same transforms and products in the same
    /// order, so the fields are bit for bit those of the full disturbance, without the strain at
    /// the inclusion layers (the volume and Love products, most of an operator application). Zero
    /// work in infinite space (no surface fields).
    pub fn surface_disturbance(&mut self, eigen: &[Vec<f64>]) -> Result<(), SamError> {
        let wl = self.window.len();
        if eigen.len() != self.sources.len() * 6 || eigen.iter().any(|f| f.len() != wl) {
            return Err(SamError::Numerics(
                halfspace_numerics::NumericsError::LengthMismatch {
                    what: "eigenstrain fields (6 per layer, window-sized)",
                    expected: self.sources.len() * 6,
                    got: eigen.len(),
                },
            ));
        }
        let Some(surface) = &self.surface else {
            return Ok(());
        };
        let shared = self.window.is_full(&self.grid)
            && matches!(
                (&self.volume, &self.love, surface),
                (Layered::Fast(_), Layered::Fast(_), Layered::Fast(_))
            );
        if shared {
            // As in `disturbance_shared`: the eigenstrain spectra, the surface accumulation.
            let Layered::Fast(surface) = surface else {
                unreachable!("matched above")
            };
            self.volume_work.transform_inputs(&self.batch, eigen)?;
            self.displacements_current = true;
            return self.surface_work.surface_fields(
                &self.batch,
                surface,
                &self.volume_work,
                &mut self.surface_fields,
            );
        }
        self.surface_fields_from_window(eigen, 3)
    }

    /// `p_c` and `2u_α⁽¹⁾` on the whole surface from the window's eigenstrains (scattered to the
    /// grid, the surface operator applied over the window's rows;
    /// docs/theory-sam.md#eigen-displacements): the one computation behind
    /// [`EimFields::disturbance`] and [`EimFields::surface_disturbance`] off the shared path, the
    /// first `count` fields (3, or 1: `p_c` alone). Nothing in infinite space.
    fn surface_fields_from_window(
        &mut self,
        eigen: &[Vec<f64>],
        count: usize,
    ) -> Result<(), SamError> {
        let Some(surface) = &self.surface else {
            return Ok(());
        };
        self.displacements_current = count == 3;
        for (local, full) in eigen.iter().zip(self.scattered.iter_mut()) {
            self.window.scatter(&self.grid, local, full)?;
        }
        let w = &mut self.surface_work;
        let rows = self.window.i0..self.window.i0 + self.window.n1;
        surface.apply(
            &self.batch,
            &self.scattered,
            &mut w.x_hat,
            &mut w.skip,
            &mut w.y_hat,
            &mut self.surface_fields[..count],
            (rows, 0..usize::MAX),
        )
    }

    /// [`EimFields::disturbance`] when the window is the whole grid (FFT backend, half-space): the
    /// eigenstrain spectra serve the volume and the surface operators, and field (3) is added to the
    /// volume's output spectra before the one inverse transform per output (2 × 6 N_s fewer FFTs).
    /// The first `surface` surface fields (3, or 1: `p_c` alone).
    fn disturbance_shared(
        &mut self,
        eigen: &[Vec<f64>],
        strain: &mut [Vec<f64>],
        surface_count: usize,
    ) -> Result<(), SamError> {
        let (Layered::Fast(volume), Some(Layered::Fast(surface)), Layered::Fast(love)) =
            (&self.volume, &self.surface, &self.love)
        else {
            unreachable!("checked by the caller")
        };
        self.volume_work.transform_inputs(&self.batch, eigen)?;
        let vw = &mut self.volume_work;
        let outputs = volume.blocks().0;
        volume.assign_leading(&vw.x_hat, &vw.skip, outputs, &mut vw.y_hat)?;
        self.displacements_current = surface_count == 3;
        self.surface_work.surface_fields(
            &self.batch,
            surface,
            &self.volume_work,
            &mut self.surface_fields[..surface_count],
        )?;
        let lw = &mut self.love_work;
        self.fft
            .forward(&self.surface_fields[0], &mut lw.x_hat[0])?;
        let vw = &mut self.volume_work;
        love.accumulate(&lw.x_hat, &[false, true, true], &mut vw.y_hat)?;
        self.batch.inverse(&mut vw.y_hat, 0..self.grid.n1, strain)?;
        Ok(())
    }

    /// The correction pressure `p_c` of the last [`EimFields::disturbance`] (zero in infinite
    /// space).
    pub fn correction_pressure(&self) -> &[f64] {
        &self.surface_fields[0]
    }

    /// Surface eigen-displacements of the last disturbance (docs/theory-sam.md#eigen-displacements, \[LN11\] Eqs. 14–15):
    /// `u₃^eig = K^p₃ * p_c`, `u_α^eig = 2u_α⁽¹⁾ + K^p_α * p_c` (half-space alone), on the whole
    /// grid. The `p_c` product is a plain 2D DC-FFT in both backends (its dense twin is tested in
    /// `numerics::conv2d`).
    pub fn eigen_displacements(&mut self, u: [&mut [f64]; 3]) -> Result<(), SamError> {
        let Some(b) = &self.boussinesq else {
            return Err(SamError::InvalidParameter {
                name: "eigen-displacements in infinite space",
                value: 0.0,
                allowed: "a half-space operator",
            });
        };
        if !self.displacements_current {
            return Err(SamError::InvalidInput(
                "eigen-displacements after a strain-only disturbance: call disturbance or \
                 surface_disturbance first"
                    .into(),
            ));
        }
        let n = self.grid.len();
        let [p_hat, work] = &mut self.eig_hat;
        self.fft.forward(&self.surface_fields[0], p_hat)?;
        for (c, out) in u.into_iter().enumerate() {
            if out.len() != n {
                return Err(SamError::Numerics(
                    halfspace_numerics::NumericsError::LengthMismatch {
                        what: "eigen-displacement field",
                        expected: n,
                        got: out.len(),
                    },
                ));
            }
            for ((w, k), p) in work.iter_mut().zip(&b[c]).zip(p_hat.iter()) {
                *w = k * p;
            }
            self.fft.inverse(work, out)?;
            if c < 2 {
                out.iter_mut()
                    .zip(&self.surface_fields[c + 1])
                    .for_each(|(o, s)| *o += s);
            }
        }
        Ok(())
    }

    /// The applied strain `ε⁰` on every target layer (`strain[a · 6 + o]`, window fields) of the
    /// surface tractions `p`, `q₁`, `q₂` (whole grid; `None` = zero shear), by Love's rectangle
    /// kernels.
    pub fn traction_strain(
        &mut self,
        p: &[f64],
        q: Option<[&[f64]; 2]>,
        strain: &mut [Vec<f64>],
    ) -> Result<(), SamError> {
        let nt = self.targets.len();
        if strain.len() != nt * 6 || strain.iter().any(|f| f.len() != self.window.len()) {
            return Err(SamError::Numerics(
                halfspace_numerics::NumericsError::LengthMismatch {
                    what: "applied strain fields (6 per layer, window-sized)",
                    expected: nt * 6,
                    got: strain.len(),
                },
            ));
        }
        let x: [&[f64]; 3] = match q {
            Some([q1, q2]) => [p, q1, q2],
            None => [p, &self.zero, &self.zero],
        };
        if self.window.is_full(&self.grid) {
            // The window is the grid: Love's strains are transformed back into `strain` itself
            // (no whole-grid copy to clear, crop and add).
            let w = &mut self.love_work;
            return self.love.apply(
                &self.batch,
                &x,
                &mut w.x_hat,
                &mut w.skip,
                &mut w.y_hat,
                strain,
                (0..usize::MAX, 0..usize::MAX),
            );
        }
        strain.iter_mut().for_each(|f| f.fill(0.0));
        love_into_window(
            &self.love,
            &self.batch,
            &mut self.love_work,
            &mut self.love_full,
            (&self.window, &self.grid),
            &x,
            strain,
        )
    }

    /// Whether this is the half-space operator.
    pub fn space(&self) -> Space {
        self.space
    }
}
