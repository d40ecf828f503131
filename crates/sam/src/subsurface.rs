//! The stress field below the surface (docs/theory-sam.md#mirror-image-and-correction-pressure to #layered-operators): at the centres of the cubic cells under
//! every surface cell, from the surface down to a given depth,
//!
//! `ε = ε⁰[p + p_c, q] + ε⁽¹⁾[ε*] + ε⁽²⁾[ε*]`, `σ = C_m : ε` in the matrix, `σ = C_I : ε` in an
//! inhomogeneity cell,
//!
//! where `ε⁰` are Love's rectangle strains of the surface tractions (docs/theory-sam.md#love-rectangle-stresses) — with the
//! correction pressure `p_c` of the eigenstrains added to `p` (field (3)) — and `ε⁽¹⁾ + ε⁽²⁾` the
//! cuboid eigenstrains in infinite space and their mirror images. Love's kernel spectra are stored
//! once per plan ([`SubsurfacePlan`]: one key per layer, reused at every increment of a loop); the
//! eigenstrain products are streamed key by key
//! ([`halfspace_numerics::layered::accumulate_streamed`]). Von Mises `√(3J₂)`, Tresca `σ₁ − σ₃` and the principal stresses (eigenvalues of the 3 × 3
//! tensor, trigonometric form) are computed per cell.

use halfspace_numerics::fft2d::{multiply_accumulate, Fft2d, C64};
use halfspace_numerics::layered::{accumulate_streamed, Family, LayerKernel, LayeredSpectra};
use rayon::prelude::*;

use crate::eim::operator::{ImageStrain, InfiniteStrain, LoveStrain, SurfaceFields};
use crate::eim::InclusionSet;
use crate::error::check_lengths;
use crate::kernels::cuboid::strain_kernel;
use crate::kernels::subsurface::{pressure_stress, shear_stress, unit_traction_stresses};
use crate::kernels::{compliance, mul6, stiffness, InPlane};
use crate::{SamError, SurfaceGrid};

/// The stress field on `layers` layers of `N₁ × N₂` cells (index `k N₁N₂ + i N₂ + j`, layer `k`
/// centred at depth `(2k + 1)Δ`), with its invariants.
#[derive(Debug, Clone, PartialEq)]
pub struct StressField {
    /// The surface grid.
    pub grid: SurfaceGrid,
    /// Number of layers.
    pub layers: usize,
    /// `σ` in Voigt order `(11, 22, 33, 23, 13, 12)`, tension positive, per cell.
    pub stress: [Vec<f64>; 6],
    /// Von Mises stress `√(½[(σ₁₁−σ₂₂)² + (σ₂₂−σ₃₃)² + (σ₃₃−σ₁₁)²] + 3(σ₂₃² + σ₁₃² + σ₁₂²))`.
    pub von_mises: Vec<f64>,
    /// Tresca stress `σ₁ − σ₃` (twice the maximum shear).
    pub tresca: Vec<f64>,
    /// Principal stresses `σ₁ ≥ σ₂ ≥ σ₃`.
    pub principal: [Vec<f64>; 3],
    /// Inhomogeneity material index + 1 per cell (0 = matrix).
    pub material: Vec<u16>,
}

impl StressField {
    /// The position `(x₁, x₂, depth)` of cell `index`.
    pub fn position(&self, index: usize) -> [f64; 3] {
        let per = self.grid.len();
        let (k, flat) = (index / per, index % per);
        let (x, y) = self.grid.centre(flat / self.grid.n2, flat % self.grid.n2);
        [x, y, (2 * k + 1) as f64 * self.grid.half1]
    }

    /// Depth of layer `k`.
    pub fn depth(&self, k: usize) -> f64 {
        (2 * k + 1) as f64 * self.grid.half1
    }

    /// The largest value of `field` and where it is.
    pub fn maximum(&self, field: &[f64]) -> (f64, [f64; 3]) {
        let (idx, v) =
            field
                .iter()
                .enumerate()
                .fold((0, f64::NEG_INFINITY), |(bi, bv), (i, &v)| {
                    if v > bv {
                        (i, v)
                    } else {
                        (bi, bv)
                    }
                });
        (v, self.position(idx))
    }
}

/// Principal stresses of a symmetric tensor (Voigt), descending, by the trigonometric solution of
/// the characteristic cubic (Smith 1961).
pub fn principal_stresses(s: &[f64; 6]) -> [f64; 3] {
    let (a, b, c, d, e, f) = (s[0], s[1], s[2], s[3], s[4], s[5]);
    let p1 = d * d + e * e + f * f;
    let q = (a + b + c) / 3.0;
    if p1 == 0.0 {
        let mut v = [a, b, c];
        v.sort_by(|x, y| y.total_cmp(x));
        return v;
    }
    let p2 = (a - q).powi(2) + (b - q).powi(2) + (c - q).powi(2) + 2.0 * p1;
    let p = (p2 / 6.0).sqrt();
    // B = (A − qI)/p; r = det(B)/2.
    let (ba, bb, bc) = ((a - q) / p, (b - q) / p, (c - q) / p);
    let (bd, be, bf) = (d / p, e / p, f / p);
    let det = ba * (bb * bc - bd * bd) - bf * (bf * bc - bd * be) + be * (bf * bd - bb * be);
    let r = (0.5 * det).clamp(-1.0, 1.0);
    let phi = r.acos() / 3.0;
    let s1 = q + 2.0 * p * phi.cos();
    let s3 = q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
    [s1, 3.0 * q - s1 - s3, s3]
}

/// Von Mises stress of a Voigt tensor.
pub fn von_mises(s: &[f64; 6]) -> f64 {
    (0.5 * ((s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2))
        + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]))
        .sqrt()
}

/// Memory above which a stress-field request is refused up front.
pub const FIELD_LIMIT_BYTES: f64 = 8.0 * (1u64 << 30) as f64;

/// Love's strain operator of the surface tractions on the box's layers with its kernel spectra
/// stored (docs/theory-sam.md#love-rectangle-stresses, #layered-operators): built once, applied to
/// every increment's `p, q` (the fretting loop's stress history, [`crate::drivers::fretting_loop`]).
/// With inclusions, the eigenstrain fields (1) + (2) and `p_c` are streamed key by key at each
/// application ([`halfspace_numerics::layered::accumulate_streamed`]). The one algorithm behind
/// [`subsurface_stress`].
pub struct SubsurfacePlan {
    grid: SurfaceGrid,
    e: f64,
    nu: f64,
    layers: usize,
    /// Whether the surface layer `z = 0` is one of the levels (docs/fatigue.md, "The
    /// surface layer").
    surface: bool,
    /// The levels computed, in their order in the output: `k < layers` the layer centred at
    /// `(2k + 1)Δ`, `k = layers` the surface layer ([`SubsurfacePlan::with_levels`]).
    levels: Vec<usize>,
    targets: Vec<i64>,
    fft: Fft2d,
    /// Love's kernel spectra, one per level (in the order of `levels`; each a product per depth
    /// key, so a level's stresses do not depend on the others): `None` once dropped by
    /// [`SubsurfacePlan::retain_levels`].
    love: Vec<Option<LayeredSpectra>>,
    /// The spectra of the absolute stress functionals of Love's kernels per level
    /// ([`SubsurfacePlan::deviation_bounds`]), built at the first bound of a level and kept for
    /// the next ones (the screen of the fatigue box bounds some levels twice).
    abs: Vec<Option<LayeredSpectra>>,
    /// Scratch of one application, kept between the applications of a loop (no fresh pages
    /// per increment): the strain spectra and the strains of every layer.
    spectra: Vec<Vec<C64>>,
    strain: Vec<Vec<f64>>,
}

impl SubsurfacePlan {
    /// Layers of a box of depth `depth` on cells of half side `half`: `⌈depth / 2Δ⌉`, at least 1.
    pub fn layers_for(depth: f64, half: f64) -> usize {
        ((depth / (2.0 * half)).ceil() as usize).max(1)
    }

    /// Bytes of the stored Love spectra of `layers` layers on an `n1 × n2` grid: at most 18 blocks
    /// (6 strains × 3 tractions) of `2N₁(N₂ + 1)` complex values per layer.
    pub fn spectra_bytes(n1: usize, n2: usize, layers: usize) -> f64 {
        layers as f64 * 18.0 * 2.0 * n1 as f64 * (n2 as f64 + 1.0) * 16.0
    }

    /// Bytes of one application: the `6 · layers` strain spectra and the `15 · layers · N₁N₂`
    /// values of the field and its invariants.
    pub fn field_bytes(n1: usize, n2: usize, layers: usize) -> f64 {
        let (layers, n1, n2) = (layers as f64, n1 as f64, n2 as f64);
        layers * 6.0 * 2.0 * n1 * (n2 + 1.0) * 16.0 + layers * 15.0 * n1 * n2 * 8.0
    }

    /// The plan of the layers from the surface to `depth` below `grid` in the half-space
    /// `(e, nu)`; refused up front above [`FIELD_LIMIT_BYTES`].
    pub fn new(grid: &SurfaceGrid, e: f64, nu: f64, depth: f64) -> Result<Self, SamError> {
        Self::with_surface(grid, e, nu, depth, false)
    }

    /// [`SubsurfacePlan::new`] and, with `surface`, the surface layer `z = 0` after the
    /// `layers` layers (cells `layers · N₁N₂ + i N₂ + j`; docs/fatigue.md, "The surface layer"):
    /// Love's rectangle stresses (docs/theory-sam.md#love-rectangle-stresses) in the limit
    /// `z → 0⁺` at the cell centres, where a cell's own traction gives `σ₃₃ = −p`,
    /// `σ₁₃ = −q₁`, `σ₂₃ = −q₂` and the in-plane stresses are the corner sums of the
    /// primitives at `z = 0` (`Φ_z = ∓π/2`, finite logarithms and arctangents: the corners
    /// `c_α = x_α ± Δ` of a cell centre are never 0). The stresses of the layers below are bit
    /// for bit those without it (each target depth is an independent product).
    pub fn with_surface(
        grid: &SurfaceGrid,
        e: f64,
        nu: f64,
        depth: f64,
        surface: bool,
    ) -> Result<Self, SamError> {
        let layers = Self::check(grid, e, nu, depth)?;
        // Refused before the list of levels is built (a depth of thousands of cells would
        // otherwise allocate that list, or overflow, first).
        Self::check_fits(grid, layers.saturating_add(usize::from(surface)))?;
        let levels: Vec<usize> = (0..layers + usize::from(surface)).collect();
        Self::with_levels(grid, e, nu, depth, &levels)
    }

    /// The plan of some levels of the box of [`SubsurfacePlan::with_surface`] only: `levels`
    /// (increasing) holds `k < ⌈depth/2Δ⌉` for the layer centred at `(2k + 1)Δ` and
    /// `k = ⌈depth/2Δ⌉` for the surface layer `z = 0`; the output's cells are
    /// `position-in-levels · N₁N₂ + i N₂ + j`. Each depth is an independent product, so every
    /// level is bit for bit that of the full plan (docs/fatigue.md, "Layers the screen cannot
    /// reach").
    pub fn with_levels(
        grid: &SurfaceGrid,
        e: f64,
        nu: f64,
        depth: f64,
        levels: &[usize],
    ) -> Result<Self, SamError> {
        let layers = Self::check(grid, e, nu, depth)?;
        let half = grid.half1;
        if levels.is_empty()
            || levels.windows(2).any(|w| w[1] <= w[0])
            || levels.iter().any(|&k| k > layers)
        {
            return Err(SamError::InvalidInput(format!(
                "subsurface levels {levels:?}: increasing, at most {layers} (the surface layer)"
            )));
        }
        let surface = levels.contains(&layers);
        Self::check_fits(grid, levels.len())?;
        // Depth keys in units of Δ: (2k + 1) for layer k, 0 for the surface layer.
        let targets: Vec<i64> = levels
            .iter()
            .map(|&k| if k == layers { 0 } else { (2 * k + 1) as i64 })
            .collect();
        let mut fft = Fft2d::new(grid.n1, grid.n2)?;
        let love_kernel = LoveStrain {
            half,
            nu,
            s: compliance(e, nu),
        };
        // Per level and depth key: a level's stresses do not depend on the other levels
        // computed (the products of one target are those of a plan of several, bit for bit).
        let love = targets
            .iter()
            .map(|&t| {
                LayeredSpectra::per_key(&mut fft, &[t], &[0], &[(Family::Difference, &love_kernel)])
                    .map(Some)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let abs = targets.iter().map(|_| None).collect();
        Ok(Self {
            grid: *grid,
            e,
            nu,
            layers,
            surface,
            levels: levels.to_vec(),
            targets,
            fft,
            love,
            abs,
            spectra: Vec::new(),
            strain: Vec::new(),
        })
    }

    /// The inputs of a plan checked (a positive depth and modulus, `ν ∈ (−1, 0.5)`, cubic cells):
    /// the layers of the box, [`SubsurfacePlan::layers_for`].
    /// Refuses `levels` levels on `grid` above [`FIELD_LIMIT_BYTES`] (their stored spectra and one
    /// application's fields).
    fn check_fits(grid: &SurfaceGrid, levels: usize) -> Result<(), SamError> {
        let need = Self::spectra_bytes(grid.n1, grid.n2, levels)
            + Self::field_bytes(grid.n1, grid.n2, levels);
        if need > FIELD_LIMIT_BYTES {
            return Err(SamError::InvalidParameter {
                name: "memory for the subsurface stress field (bytes)",
                value: need,
                allowed: "≤ 8 GiB: a shallower subsurface depth or a coarser grid",
            });
        }
        Ok(())
    }

    fn check(grid: &SurfaceGrid, e: f64, nu: f64, depth: f64) -> Result<usize, SamError> {
        crate::error::positive("subsurface depth", depth)?;
        crate::error::positive("Young's modulus", e)?;
        if !(nu > -1.0 && nu < 0.5) {
            return Err(SamError::InvalidParameter {
                name: "Poisson ratio (subsurface stresses)",
                value: nu,
                allowed: "in (−1, 0.5)",
            });
        }
        if (grid.half1 - grid.half2).abs() > 1e-12 * grid.half1 {
            return Err(SamError::InvalidParameter {
                name: "cell aspect ratio Δ₂/Δ₁ (subsurface stresses need cubic cells)",
                value: grid.half2 / grid.half1,
                allowed: "1",
            });
        }
        Ok(Self::layers_for(depth, grid.half1))
    }

    /// Layers of the box below the surface.
    pub fn layers(&self) -> usize {
        self.layers
    }

    /// Whether the surface layer `z = 0` is one of the levels ([`SubsurfacePlan::with_surface`]).
    pub fn surface(&self) -> bool {
        self.surface
    }

    /// The levels computed ([`SubsurfacePlan::with_levels`]).
    pub fn levels(&self) -> &[usize] {
        &self.levels
    }

    /// The surface grid.
    pub fn grid(&self) -> &SurfaceGrid {
        &self.grid
    }

    /// Bytes held by the stored spectra (Love's and, once built, the deviation bounds').
    pub fn bytes(&self) -> usize {
        self.love
            .iter()
            .chain(&self.abs)
            .flatten()
            .map(LayeredSpectra::bytes)
            .sum()
    }

    /// Keeps the spectra of the levels `keep` only (the others' memory is returned; their
    /// stresses and bounds are refused after this): the fatigue box's screen builds the plan of
    /// every level, then applies it to the levels it cannot rule out
    /// ([`SubsurfacePlan::stress_of_levels`]).
    pub fn retain_levels(&mut self, keep: &[usize]) {
        for (i, k) in self.levels.iter().enumerate() {
            if !keep.contains(k) {
                self.love[i] = None;
                self.abs[i] = None;
            }
        }
    }

    /// Drops the deviation bounds' spectra ([`SubsurfacePlan::deviation_bounds`]).
    pub fn drop_bound_spectra(&mut self) {
        self.abs.iter_mut().for_each(|a| *a = None);
    }

    /// The positions in the plan's levels of the box levels `levels` (increasing, each a level
    /// of the plan whose spectra are kept).
    fn positions(&self, levels: &[usize]) -> Result<Vec<usize>, SamError> {
        let at: Vec<Option<usize>> = levels
            .iter()
            .map(|k| {
                self.levels
                    .iter()
                    .position(|l| l == k)
                    .filter(|&i| self.love[i].is_some())
            })
            .collect();
        if levels.windows(2).any(|w| w[1] <= w[0]) || at.iter().any(Option::is_none) {
            return Err(SamError::InvalidInput(format!(
                "subsurface levels {levels:?}: increasing levels of the plan's kept {:?}",
                self.levels
                    .iter()
                    .zip(&self.love)
                    .filter(|(_, l)| l.is_some())
                    .map(|(k, _)| *k)
                    .collect::<Vec<_>>()
            )));
        }
        Ok(at.into_iter().flatten().collect())
    }

    /// The six stress components `σ` (Voigt `(11, 22, 33, 23, 13, 12)`, per cell
    /// `k N₁N₂ + i N₂ + j`) and the material of each cell (0 the matrix, `m + 1` inclusion material `m`) of the
    /// tractions `p` (and `q`) and, with `inclusions`, the eigenstrains `eps_star` (6 per
    /// inclusion cell): `ε = ε⁰[p + p_c, q] + ε⁽¹⁾[ε*] + ε⁽²⁾[ε*]`, `σ = C : ε` with the stiffness
    /// of the cell (module doc).
    pub fn stress(
        &mut self,
        p: &[f64],
        q: Option<[&[f64]; 2]>,
        inclusions: Option<(&InclusionSet, &[f64])>,
    ) -> Result<([Vec<f64>; 6], Vec<u16>), SamError> {
        let grid = self.grid;
        let (e, nu) = (self.e, self.nu);
        // The levels (the surface layer z = 0, if any, last: the matrix).
        let layers = self.levels.len();
        let half = grid.half1;
        let n = grid.len();
        check_tractions(n, p, q)?;
        let fft = &mut self.fft;
        let targets = &self.targets;
        // The strain spectra, zeroed (the products are added into them).
        let mut out = std::mem::take(&mut self.spectra);
        if out.len() == layers * 6 {
            out.iter_mut().for_each(|o| o.fill(C64::default()));
        } else {
            out = (0..layers * 6).map(|_| fft.new_spectrum()).collect();
        }
        let mut pressure = p.to_vec();
        let mut material = vec![0u16; layers * n];
        if let Some((set, eps_star)) = inclusions {
            if eps_star.len() != 6 * set.len() {
                return Err(SamError::Numerics(
                    halfspace_numerics::NumericsError::LengthMismatch {
                        what: "eigenstrains (6 per inclusion cell)",
                        expected: 6 * set.len(),
                        got: eps_star.len(),
                    },
                ));
            }
            if self.surface && set.layers.contains(&0) {
                // The surface point z = 0 would lie on the top face of an inclusion cuboid,
                // where the strain of its eigenstrain jumps.
                return Err(SamError::InvalidInput(
                    "the fatigue box's surface layer z = 0: an inhomogeneity reaches the first \
                     layer of cells below the surface, whose top face is the surface (its \
                     stress there is not defined by the cell model); use a finer grid or a \
                     deeper inhomogeneity"
                        .into(),
                ));
            }
            let sources: Vec<i64> = set.layers.iter().map(|k| (2 * k + 1) as i64).collect();
            let mut fields = vec![vec![0.0; n]; sources.len() * 6];
            for (c, cell) in set.cells.iter().enumerate() {
                for o in 0..6 {
                    fields[cell.layer * 6 + o][cell.flat] = eps_star[c * 6 + o];
                }
                let k = set.layers[cell.layer];
                if let Some(at) = self.levels.iter().position(|&l| l == k && l < self.layers) {
                    material[at * n + cell.flat] = cell.material as u16 + 1;
                }
            }
            let mut hats: Vec<Vec<C64>> = fields.iter().map(|_| fft.new_spectrum()).collect();
            let mut skip = vec![false; fields.len()];
            for ((f, h), s) in fields.iter().zip(hats.iter_mut()).zip(skip.iter_mut()) {
                *s = f.iter().all(|v| *v == 0.0);
                if !*s {
                    fft.forward(f, h)?;
                }
            }
            // Fields (1) + (2).
            let inf = InfiniteStrain { half, nu };
            let img = ImageStrain(InfiniteStrain { half, nu });
            let fam: [(Family, &dyn LayerKernel); 2] =
                [(Family::Difference, &inf), (Family::Sum, &img)];
            accumulate_streamed(fft, targets, &sources, &fam, &hats, &skip, &mut out)?;
            // p_c, added to the pressure (field (3) is Love's field of p_c).
            let sk = SurfaceFields {
                half,
                nu,
                c: stiffness(e, nu),
            };
            let mut surf: Vec<Vec<C64>> = (0..3).map(|_| fft.new_spectrum()).collect();
            accumulate_streamed(
                fft,
                &[0],
                &sources,
                &[(Family::Difference, &sk)],
                &hats,
                &skip,
                &mut surf,
            )?;
            let mut pc = vec![0.0; n];
            fft.inverse(&mut surf[0], &mut pc)?;
            pressure.iter_mut().zip(&pc).for_each(|(a, b)| *a += b);
        }
        let ci: Vec<[[f64; 6]; 6]> = inclusions
            .map(|(set, _)| {
                set.materials
                    .iter()
                    .map(|&(a, b)| stiffness(a, b))
                    .collect()
            })
            .unwrap_or_default();
        let all: Vec<usize> = (0..layers).collect();
        let stress = self.love_stress(&all, &pressure, q, out, &material, &ci)?;
        Ok((stress, material))
    }

    /// The stresses of the box levels `levels` (increasing levels of the plan whose spectra are
    /// kept, [`SubsurfacePlan::retain_levels`]) of the tractions `p` (and `q`), without
    /// inclusions: [`SubsurfacePlan::stress`] on those levels only, each level bit for bit the
    /// same (cells `position-in-levels · N₁N₂ + i N₂ + j`).
    pub fn stress_of_levels(
        &mut self,
        levels: &[usize],
        p: &[f64],
        q: Option<[&[f64]; 2]>,
    ) -> Result<[Vec<f64>; 6], SamError> {
        let n = self.grid.len();
        check_tractions(n, p, q)?;
        let positions = self.positions(levels)?;
        let mut out = std::mem::take(&mut self.spectra);
        if out.len() == positions.len() * 6 {
            out.iter_mut().for_each(|o| o.fill(C64::default()));
        } else {
            out = (0..positions.len() * 6)
                .map(|_| self.fft.new_spectrum())
                .collect();
        }
        let material = vec![0u16; positions.len() * n];
        self.love_stress(&positions, p, q, out, &material, &[])
    }

    /// Love's strains of `(pressure, q₁, q₂)` added to the strain spectra `out` (6 per position,
    /// zeroed or holding the eigenstrains' fields) on the plan's levels at `positions`, and the
    /// stresses `σ = C : ε` with the stiffness of each cell's `material` (0 the matrix, `m + 1`
    /// the stiffness `ci[m]`).
    fn love_stress(
        &mut self,
        positions: &[usize],
        pressure: &[f64],
        q: Option<[&[f64]; 2]>,
        mut out: Vec<Vec<C64>>,
        material: &[u16],
        ci: &[[[f64; 6]; 6]],
    ) -> Result<[Vec<f64>; 6], SamError> {
        let n = self.grid.len();
        let layers = positions.len();
        let fft = &mut self.fft;
        // Love's strains of (p + p_c, q₁, q₂).
        let zero = vec![0.0; n];
        let inputs: [&[f64]; 3] = match q {
            Some([q1, q2]) => [pressure, q1, q2],
            None => [pressure, &zero, &zero],
        };
        let mut hats: Vec<Vec<C64>> = (0..3).map(|_| fft.new_spectrum()).collect();
        let mut skip = [false; 3];
        for i in 0..3 {
            skip[i] = inputs[i].iter().all(|v| *v == 0.0);
            if !skip[i] {
                fft.forward(inputs[i], &mut hats[i])?;
            }
        }
        for (&at, out) in positions.iter().zip(out.chunks_mut(6)) {
            love_of(&self.love[at])?.accumulate(&hats, &skip, out)?;
        }
        // Strains → stresses.
        let mut strain = std::mem::take(&mut self.strain);
        if strain.len() != layers * 6 {
            strain = vec![vec![0.0; n]; layers * 6];
        }
        for (h, f) in out.iter_mut().zip(strain.iter_mut()) {
            fft.inverse(h, f)?;
        }
        self.spectra = out;
        let cm = stiffness(self.e, self.nu);
        let total = layers * n;
        let mut stress: [Vec<f64>; 6] = std::array::from_fn(|_| vec![0.0; total]);
        for k in 0..layers {
            for c in 0..n {
                let idx = k * n + c;
                let mut eps = [0.0; 6];
                for o in 0..6 {
                    eps[o] = strain[k * 6 + o][c];
                }
                let m = material[idx];
                let sig = if m == 0 {
                    mul6(&cm, &eps)
                } else {
                    mul6(&ci[m as usize - 1], &eps)
                };
                for o in 0..6 {
                    stress[o][idx] = sig[o];
                }
            }
        }
        self.strain = strain;
        Ok(stress)
    }
}

/// The tractions `p` (and `q`) of a grid of `n` cells: one value per cell each.
fn check_tractions(n: usize, p: &[f64], q: Option<[&[f64]; 2]>) -> Result<(), SamError> {
    check_lengths(
        "surface traction field",
        n,
        std::iter::once(p).chain(q.into_iter().flatten()),
    )
}

/// The stored spectra of a level, or an error once [`SubsurfacePlan::retain_levels`] dropped them.
fn love_of(love: &Option<LayeredSpectra>) -> Result<&LayeredSpectra, SamError> {
    love.as_ref().ok_or_else(|| {
        SamError::InvalidInput("subsurface plan: a level's spectra were dropped".into())
    })
}

impl SubsurfacePlan {
    /// Bounds of the stress paths' deviation from a reference state, for the screen of the
    /// fatigue box (docs/fatigue.md, "Layers the screen cannot reach"). For tractions
    /// `τ_j(t, x') = τ_j^ref(x') + δ_j(t, x')` with `|δ_j(t, x')| ≤ amplitude[j][x']`
    /// (`j` = `p, q₁, q₂`; no inhomogeneities), the stress of a cell `x` of the levels is
    /// `σ(t) = σ^ref + Σ_j Σ_x' K_j(x − x') δ_j(t, x')` (Love's rectangle stresses, linear), so
    /// every linear functional `f` of the stress satisfies
    ///
    /// `|f(σ(t)) − f(σ^ref)| ≤ B_f(x) = Σ_j Σ_x' |f(K_j(x − x'))| amplitude_j(x')`,
    ///
    /// for the six functionals `f = (y₀, …, y₄, σ_H)` of [`stress_functionals`]
    /// (docs/fatigue.md Eq. F1). Returns `B[f][position-in-levels · N₁N₂ + cell]`, one FFT
    /// convolution per level with the kernels' absolute values (tabulated at every offset),
    /// enlarged by `10⁻⁹` of itself and of its largest value for the rounding of the transforms.
    pub fn deviation_bounds(&mut self, amplitude: [&[f64]; 3]) -> Result<[Vec<f64>; 6], SamError> {
        let mut all = self.deviation_bounds_of(&[amplitude])?;
        Ok(all.remove(0))
    }

    /// [`SubsurfacePlan::deviation_bounds`] of several amplitude maps `amplitudes[g]` (one
    /// result each, in order), the kernels' spectra built once for all of them.
    pub fn deviation_bounds_of(
        &mut self,
        amplitudes: &[[&[f64]; 3]],
    ) -> Result<Vec<[Vec<f64>; 6]>, SamError> {
        let levels = self.levels.clone();
        self.deviation_bounds_of_levels(&levels, amplitudes)
    }

    /// [`SubsurfacePlan::deviation_bounds_of`] on the box levels `levels` only (increasing levels
    /// of the plan whose spectra are kept, [`SubsurfacePlan::retain_levels`]): `B[f][position in
    /// levels · N₁N₂ + cell]`, each level bit for bit the same. The kernels' spectra of a level
    /// are built at its first bound and kept ([`SubsurfacePlan::drop_bound_spectra`]).
    pub fn deviation_bounds_of_levels(
        &mut self,
        levels: &[usize],
        amplitudes: &[[&[f64]; 3]],
    ) -> Result<Vec<[Vec<f64>; 6]>, SamError> {
        let n = self.grid.len();
        check_lengths(
            "traction amplitude field",
            n,
            amplitudes.iter().flatten().copied(),
        )?;
        let positions = self.positions(levels)?;
        let kernel = AbsLoveFunctionals {
            half: self.grid.half1,
            nu: self.nu,
        };
        let fft = &mut self.fft;
        for &at in &positions {
            if self.abs[at].is_none() {
                // Per depth key: the products of a plan of several levels, bit for bit.
                self.abs[at] = Some(LayeredSpectra::per_key(
                    fft,
                    &[self.targets[at]],
                    &[0],
                    &[(Family::Difference, &kernel)],
                )?);
            }
        }
        let count = positions.len();
        let mut hats: Vec<Vec<C64>> = (0..3).map(|_| fft.new_spectrum()).collect();
        let mut out: Vec<Vec<C64>> = (0..count * 6).map(|_| fft.new_spectrum()).collect();
        let mut field = vec![0.0; n];
        let mut results = Vec::with_capacity(amplitudes.len());
        for amplitude in amplitudes {
            let mut skip = [false; 3];
            for j in 0..3 {
                skip[j] = amplitude[j].iter().all(|v| *v == 0.0);
                if !skip[j] {
                    fft.forward(amplitude[j], &mut hats[j])?;
                }
            }
            out.iter_mut().for_each(|o| o.fill(C64::default()));
            for (&at, out) in positions.iter().zip(out.chunks_mut(6)) {
                love_of(&self.abs[at])?.accumulate(&hats, &skip, out)?;
            }
            let mut bounds: [Vec<f64>; 6] = std::array::from_fn(|_| vec![0.0; count * n]);
            for (a, h) in out.iter_mut().enumerate() {
                let (level, f) = (a / 6, a % 6);
                fft.inverse(h, &mut field)?;
                bounds[f][level * n..(level + 1) * n].copy_from_slice(&field);
            }
            for b in bounds.iter_mut() {
                let largest = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                b.iter_mut()
                    .for_each(|v| *v = v.max(0.0) * (1.0 + 1e-9) + 1e-9 * largest);
            }
            results.push(bounds);
        }
        Ok(results)
    }
}

/// The six linear functionals of a stress tensor (Voigt `(11, 22, 33, 23, 13, 12)`) the fatigue
/// screen bounds: the deviator coordinates `y = ((2σ₃₃ − σ₁₁ − σ₂₂)/(2√3), (σ₁₁ − σ₂₂)/2, σ₂₃,
/// σ₁₃, σ₁₂)` (`|y|² = J₂`, docs/fatigue.md Eq. F1) and the hydrostatic stress
/// `σ_H = (σ₁₁ + σ₂₂ + σ₃₃)/3`.
pub fn stress_functionals(s: &[f64; 6]) -> [f64; 6] {
    [
        (2.0 * s[2] - s[0] - s[1]) / (2.0 * 3f64.sqrt()),
        0.5 * (s[0] - s[1]),
        s[3],
        s[4],
        s[5],
        (s[0] + s[1] + s[2]) / 3.0,
    ]
}

/// `|f(K_j)|`: the absolute values of the [`stress_functionals`] of Love's stress kernels of
/// `p, q₁, q₂` (blocks `f · 3 + j`). Each block is even in both offsets: for a fixed traction
/// the normal stresses share one parity (even–even for `p`, odd in `m` for `q₁`, odd in `n` for
/// `q₂`) and `y₀, y₁, σ_H` combine only normal stresses, `y₂ … y₄` are single components.
struct AbsLoveFunctionals {
    half: f64,
    nu: f64,
}

impl LayerKernel for AbsLoveFunctionals {
    fn blocks(&self) -> (usize, usize) {
        (6, 3)
    }
    fn eval(&self, key: i64, m: i64, n: i64, out: &mut [f64]) {
        let stresses = unit_traction_stresses(key, m, n, self.half, self.nu);
        for (j, sigma) in stresses.iter().enumerate() {
            for (f, v) in stress_functionals(sigma).iter().enumerate() {
                out[f * 3 + j] = v.abs();
            }
        }
    }
    fn parity(&self) -> Option<Vec<(bool, bool)>> {
        Some(vec![(false, false); 18])
    }
}

/// The stress field of the surface tractions `p` (and `q`) and, with `inclusions`, of the
/// eigenstrains `eps_star` (6 per inclusion cell) in the half-space `(e, nu)`, on the layers from
/// the surface to `depth` (at least one layer): [`SubsurfacePlan::stress`] of a new plan, with the
/// invariants per cell.
pub fn subsurface_stress(
    grid: &SurfaceGrid,
    e: f64,
    nu: f64,
    p: &[f64],
    q: Option<[&[f64]; 2]>,
    depth: f64,
    inclusions: Option<(&InclusionSet, &[f64])>,
) -> Result<StressField, SamError> {
    let mut plan = SubsurfacePlan::new(grid, e, nu, depth)?;
    let (stress, material) = plan.stress(p, q, inclusions)?;
    Ok(StressField::of(*grid, plan.layers, stress, material))
}

/// The sources of one state's stress field for [`von_mises_fields`]: the tractions `p` (and
/// `q`) and, with inclusions, their eigenstrains (6 per inclusion cell).
#[derive(Debug, Clone, Copy)]
pub struct FieldSources<'a> {
    /// Pressure `p` per cell.
    pub pressure: &'a [f64],
    /// Shear `(q₁, q₂)` per cell (`None`: frictionless).
    pub shear: Option<[&'a [f64]; 2]>,
    /// Eigenstrains, 6 per cell of the [`InclusionSet`] given to [`von_mises_fields`].
    pub eigenstrain: Option<&'a [f64]>,
}

/// Bytes of strain spectra [`von_mises_fields`] accumulates at once (all states, a group of
/// layers): the layers are taken in groups that fit, each group streaming the kernels of its
/// own depth keys.
const FIELD_GROUP_BYTES: f64 = 128.0 * (1u64 << 20) as f64;

/// The von Mises fields `√(3J₂)` of several states on the layers from the surface to `depth`
/// (`⌈depth/2Δ⌉` layers, cell `k N₁N₂ + i N₂ + j`), each bit for bit the `von_mises` of
/// [`subsurface_stress`] of that state (the same sums in the same order,
/// docs/theory-sam.md#love-rectangle-stresses to #layered-operators): the kernels' spectra of
/// every depth key (the eigenstrains' fields (1) + (2), the correction pressure `p_c`, Love's
/// strains of each layer) are built once and applied to every state, instead of once per state;
/// the layers are processed in groups whose strain spectra fit in `FIELD_GROUP_BYTES` (128 MiB), Love's
/// spectra one layer at a time (the stored plan of [`SubsurfacePlan`] holds every layer's). The
/// fretting loop's fields at the points A–D (docs/performance.md, "The 128² composite command
/// outside the EIM (issue 21)").
pub fn von_mises_fields(
    grid: &SurfaceGrid,
    e: f64,
    nu: f64,
    depth: f64,
    inclusions: Option<&InclusionSet>,
    states: &[FieldSources<'_>],
) -> Result<Vec<Vec<f64>>, SamError> {
    fields_in_groups(grid, (e, nu), depth, inclusions, states, FIELD_GROUP_BYTES)
}

/// Bytes [`von_mises_fields`] holds at once for `count` states on an `n1 × n2` grid, `layers`
/// layers down, with eigenstrains on `source_layers` inclusion layers (0 without inclusions): the
/// states' input spectra (`6 · source_layers + 3` each) and the strain spectra of a group of
/// layers (at most `FIELD_GROUP_BYTES`), two depth keys' kernel blocks and their tables (36
/// each; or a layer's 18 Love blocks), the eigenstrain fields, the outputs (`count · layers`
/// fields), the cells' materials, the states' corrected pressures and their surface spectra, one
/// layer's strains and a second FFT plan. What the fretting loop's estimate counts for the fields at
/// the points A–D ([`crate::drivers::fretting_loop::LoopCase::estimate`]).
pub fn von_mises_fields_bytes(
    (n1, n2): (usize, usize),
    layers: usize,
    source_layers: usize,
    count: usize,
) -> f64 {
    fields_working_bytes((n1, n2), layers, source_layers, count, FIELD_GROUP_BYTES)
}

/// The layers of one group of [`von_mises_fields`]: as many as keep `count` states' strain
/// spectra (6 per layer, `spectrum` bytes each) within `group_bytes`, at least 1.
fn field_group(count: usize, layers: usize, spectrum: f64, group_bytes: f64) -> usize {
    ((group_bytes / (count.max(1) as f64 * 6.0 * spectrum)) as usize)
        .min(layers)
        .max(1)
}

/// [`von_mises_fields_bytes`] with the groups held to `group_bytes`.
fn fields_working_bytes(
    (n1, n2): (usize, usize),
    layers: usize,
    source_layers: usize,
    count: usize,
    group_bytes: f64,
) -> f64 {
    // In floating point throughout: a hostile depth or grid must give a large estimate (and a
    // refusal), never an integer overflow.
    let (n1, n2) = (n1 as f64, n2 as f64);
    let (layers, source_layers, count) = (layers as f64, source_layers as f64, count as f64);
    let n = n1 * n2;
    let spectrum = 2.0 * n1 * (n2 + 1.0) * 16.0;
    let group = field_group(count as usize, layers as usize, spectrum, group_bytes) as f64;
    let table = (2.0 * n1 - 1.0) * (2.0 * n2 - 1.0) * 8.0;
    count * ((source_layers * 6.0 + 3.0) + group * 6.0) * spectrum
        + 2.0 * 36.0 * (spectrum + table)
        + source_layers * 6.0 * n * 8.0
        + count * layers * n * 8.0
        + layers * n * 2.0
        // The states' pressures with the correction `p_c` and their surface spectra, `p_c`, one
        // layer's six strains and a second FFT plan's scratch (two spectra).
        + count * n * 8.0
        + count * spectrum
        + 7.0 * n * 8.0
        + 2.0 * spectrum
}

/// [`von_mises_fields`] with the strain spectra of a group of layers held to `group_bytes`.
fn fields_in_groups(
    grid: &SurfaceGrid,
    (e, nu): (f64, f64),
    depth: f64,
    inclusions: Option<&InclusionSet>,
    states: &[FieldSources<'_>],
    group_bytes: f64,
) -> Result<Vec<Vec<f64>>, SamError> {
    let layers = SubsurfacePlan::check(grid, e, nu, depth)?;
    let n = grid.len();
    let half = grid.half1;
    if states.is_empty() {
        return Ok(Vec::new());
    }
    if let Some(set) = inclusions {
        let fits = (set.half - half).abs() <= 1e-12 * half
            && set
                .cells
                .iter()
                .all(|c| c.flat < n && c.layer < set.layers.len());
        if !fits {
            return Err(SamError::InvalidInput(format!(
                "subsurface fields: the inclusion set (cells of half side {:e}) was not built on \
                 this grid ({} cells of half side {half:e})",
                set.half, n
            )));
        }
    }
    for s in states {
        check_tractions(n, s.pressure, s.shear)?;
        let expected = inclusions.map_or(0, |set| 6 * set.len());
        let got = s.eigenstrain.map_or(0, <[f64]>::len);
        if s.eigenstrain.is_some() != inclusions.is_some() || got != expected {
            return Err(SamError::Numerics(
                halfspace_numerics::NumericsError::LengthMismatch {
                    what: "eigenstrains (6 per inclusion cell)",
                    expected,
                    got,
                },
            ));
        }
    }
    let count = states.len();
    let (n1, n2) = (grid.n1, grid.n2);
    let spectrum = 2.0 * n1 as f64 * (n2 + 1) as f64 * 16.0;
    let sources: Vec<i64> = inclusions.map_or(Vec::new(), |set| {
        set.layers.iter().map(|k| (2 * k + 1) as i64).collect()
    });
    let group = field_group(count, layers, spectrum, group_bytes);
    let need = fields_working_bytes((n1, n2), layers, sources.len(), count, group_bytes);
    if need > FIELD_LIMIT_BYTES {
        return Err(SamError::InvalidParameter {
            name: "memory for the subsurface stress fields (bytes)",
            value: need,
            allowed: "≤ 8 GiB: a shallower subsurface depth, a coarser grid or fewer fields",
        });
    }
    let targets: Vec<i64> = (0..layers).map(|k| (2 * k + 1) as i64).collect();
    let mut fft = Fft2d::new(n1, n2)?;
    // The material of each cell of the layers (0 the matrix), and the inclusions' stiffnesses.
    let mut material = vec![0u16; layers * n];
    let mut ci = Vec::new();
    if let Some(set) = inclusions {
        for cell in &set.cells {
            let k = set.layers[cell.layer];
            if k < layers {
                material[k * n + cell.flat] = cell.material as u16 + 1;
            }
        }
        ci = set
            .materials
            .iter()
            .map(|&(a, b)| stiffness(a, b))
            .collect();
    }
    // Per state: the eigenstrains' spectra, then p + p_c and the spectra of (p + p_c, q₁, q₂).
    let mut eigen_hats: Vec<Vec<Vec<C64>>> = Vec::with_capacity(count);
    let mut eigen_skip: Vec<Vec<bool>> = Vec::with_capacity(count);
    let mut pressures: Vec<Vec<f64>> = states.iter().map(|s| s.pressure.to_vec()).collect();
    if let Some(set) = inclusions {
        let mut fields = vec![vec![0.0; n]; sources.len() * 6];
        for s in states {
            let eps_star = s.eigenstrain.unwrap_or(&[]);
            fields.iter_mut().for_each(|f| f.fill(0.0));
            for (c, cell) in set.cells.iter().enumerate() {
                for o in 0..6 {
                    fields[cell.layer * 6 + o][cell.flat] = eps_star[c * 6 + o];
                }
            }
            let mut hats: Vec<Vec<C64>> = fields.iter().map(|_| fft.new_spectrum()).collect();
            let mut skip = vec![false; fields.len()];
            for ((f, h), s) in fields.iter().zip(hats.iter_mut()).zip(skip.iter_mut()) {
                *s = f.iter().all(|v| *v == 0.0);
                if !*s {
                    fft.forward(f, h)?;
                }
            }
            eigen_hats.push(hats);
            eigen_skip.push(skip);
        }
        // p_c = the first surface field of the eigenstrains (field (3) is Love's field of p_c).
        let sk = SurfaceFields {
            half,
            nu,
            c: stiffness(e, nu),
        };
        let mut surf: Vec<Vec<C64>> = (0..count).map(|_| fft.new_spectrum()).collect();
        stream_keys(
            &mut fft,
            &[0],
            &sources,
            &[(Family::Difference, &sk)],
            (&eigen_hats, &eigen_skip),
            1,
            &mut surf,
        )?;
        let mut pc = vec![0.0; n];
        for (h, pressure) in surf.iter_mut().zip(pressures.iter_mut()) {
            fft.inverse(h, &mut pc)?;
            pressure.iter_mut().zip(&pc).for_each(|(a, b)| *a += b);
        }
    }
    let zero = vec![0.0; n];
    let mut love_hats: Vec<Vec<Vec<C64>>> = Vec::with_capacity(count);
    let mut love_skip: Vec<Vec<bool>> = Vec::with_capacity(count);
    for (s, pressure) in states.iter().zip(&pressures) {
        let inputs: [&[f64]; 3] = match s.shear {
            Some([q1, q2]) => [pressure, q1, q2],
            None => [pressure, &zero, &zero],
        };
        let mut hats: Vec<Vec<C64>> = (0..3).map(|_| fft.new_spectrum()).collect();
        let mut skip = vec![false; 3];
        for i in 0..3 {
            skip[i] = inputs[i].iter().all(|v| *v == 0.0);
            if !skip[i] {
                fft.forward(inputs[i], &mut hats[i])?;
            }
        }
        love_hats.push(hats);
        love_skip.push(skip);
    }
    drop(pressures);
    let love_kernel = LoveStrain {
        half,
        nu,
        s: compliance(e, nu),
    };
    let inf = InfiniteStrain { half, nu };
    let img = ImageStrain(InfiniteStrain { half, nu });
    let fam: [(Family, &dyn LayerKernel); 2] = [(Family::Difference, &inf), (Family::Sum, &img)];
    let cm = stiffness(e, nu);
    let mut out: Vec<Vec<f64>> = (0..count).map(|_| vec![0.0; layers * n]).collect();
    let mut acc: Vec<Vec<C64>> = (0..count * group.min(layers) * 6)
        .map(|_| fft.new_spectrum())
        .collect();
    let mut strain = vec![vec![0.0; n]; 6];
    for k0 in (0..layers).step_by(group) {
        let k1 = (k0 + group).min(layers);
        let width = k1 - k0;
        // acc[(s · width + a) · 6 + o]: state s, layer k0 + a, strain o.
        let acc = &mut acc[..count * width * 6];
        acc.iter_mut().for_each(|a| a.fill(C64::default()));
        if inclusions.is_some() {
            // Fields (1) + (2), the keys of this group's layers.
            stream_keys(
                &mut fft,
                &targets[k0..k1],
                &sources,
                &fam,
                (&eigen_hats, &eigen_skip),
                6,
                acc,
            )?;
        }
        for a in 0..width {
            let k = k0 + a;
            // Love's strains of (p + p_c, q₁, q₂) at this layer.
            let love = LayeredSpectra::per_key(
                &mut fft,
                &[targets[k]],
                &[0],
                &[(Family::Difference, &love_kernel)],
            )?;
            for s in 0..count {
                let at = (s * width + a) * 6;
                love.accumulate(&love_hats[s], &love_skip[s], &mut acc[at..at + 6])?;
                for (h, f) in acc[at..at + 6].iter_mut().zip(strain.iter_mut()) {
                    fft.inverse(h, f)?;
                }
                let vm = &mut out[s][k * n..(k + 1) * n];
                for c in 0..n {
                    let eps: [f64; 6] = std::array::from_fn(|o| strain[o][c]);
                    let m = material[k * n + c];
                    let sig = if m == 0 {
                        mul6(&cm, &eps)
                    } else {
                        mul6(&ci[m as usize - 1], &eps)
                    };
                    vm[c] = von_mises(&sig);
                }
            }
        }
    }
    Ok(out)
}

/// `acc[(s · T + a) · outputs + o] += Σ_F Σ_b Σ_i K̂^F_{oi}(key_F(z_a, z_b)) x̂^s_{b,i}` for every
/// state `s` (inputs `hats.0[s][b · n_in + i]`, zero where `hats.1[s]` says), target `a` of
/// `targets` (`T` of them) and the first `outputs` outputs `o`: each key's spectra built once
/// ([`LayeredSpectra::per_key`]) and applied to every state, the sums of each output in the order
/// of [`halfspace_numerics::layered::accumulate_streamed`] (family, key ascending, source, input),
/// so bit for bit its products state by state.
fn stream_keys(
    fft: &mut Fft2d,
    targets: &[i64],
    sources: &[i64],
    families: &[(Family, &dyn LayerKernel)],
    hats: (&[Vec<Vec<C64>>], &[Vec<bool>]),
    outputs: usize,
    acc: &mut [Vec<C64>],
) -> Result<(), SamError> {
    let (inputs, skips) = hats;
    let width = targets.len();
    let len = acc.first().map_or(0, Vec::len);
    let (n1, n2) = fft.shape();
    let mut partner = Fft2d::new(n1, n2)?;
    for &(family, kernel) in families {
        let n_in = kernel.blocks().1;
        let mut keys: Vec<i64> = targets
            .iter()
            .flat_map(|&a| sources.iter().map(move |&b| family.key(a, b)))
            .collect();
        keys.sort_unstable();
        keys.dedup();
        // Two keys' spectra built at once, one on each FFT core (each key's spectra do not
        // depend on the other's), then applied in key order.
        for pair in keys.chunks(2) {
            let build = |core: &mut Fft2d, key: i64| {
                LayeredSpectra::per_key(core, &[key], &[0], &[(family, kernel)])
            };
            let (first, second) = rayon::join(
                || build(fft, pair[0]),
                || pair.get(1).map(|&key| build(&mut partner, key)),
            );
            let built = [Some(first?), second.transpose()?];
            for (&key, spectra) in pair.iter().zip(built.iter().flatten()) {
                let blocks = spectra.key_blocks(family, key).ok_or_else(|| {
                    SamError::InvalidInput(format!(
                        "subsurface fields: no spectra of depth key {key}"
                    ))
                })?;
                // The (target, source) pairs of this key, targets in order, sources in order.
                let pairs: Vec<(usize, usize)> = (0..width)
                    .flat_map(|a| (0..sources.len()).map(move |b| (a, b)))
                    .filter(|&(a, b)| family.key(targets[a], sources[b]) == key)
                    .collect();
                // Frequency chunks on rayon's threads: a chunk of the key's blocks stays in cache
                // while every state and pair reads it.
                let mut per_chunk: Vec<Vec<&mut [C64]>> = (0..len.div_ceil(PRODUCT_CHUNK))
                    .map(|_| Vec::with_capacity(acc.len()))
                    .collect();
                for out in acc.iter_mut() {
                    for (c, piece) in out.chunks_mut(PRODUCT_CHUNK).enumerate() {
                        per_chunk[c].push(piece);
                    }
                }
                per_chunk
                    .into_par_iter()
                    .enumerate()
                    .for_each(|(c, mut outs)| {
                        let start = c * PRODUCT_CHUNK;
                        for (s, (x, skip)) in inputs.iter().zip(skips).enumerate() {
                            for &(a, b) in &pairs {
                                for o in 0..outputs {
                                    let out = &mut outs[(s * width + a) * outputs + o];
                                    let end = start + out.len();
                                    for i in 0..n_in {
                                        if skip[b * n_in + i] {
                                            continue;
                                        }
                                        if let Some(k) = &blocks[o * n_in + i] {
                                            multiply_accumulate(
                                                out,
                                                &k[start..end],
                                                &x[b * n_in + i][start..end],
                                            );
                                        }
                                    }
                                }
                            }
                        }
                    });
            }
        }
    }
    Ok(())
}

/// Frequencies per task of [`stream_keys`]' products.
const PRODUCT_CHUNK: usize = 512;

impl StressField {
    /// The field of the stresses `stress` (and cell materials) with its invariants per cell:
    /// von Mises, Tresca `σ₁ − σ₃`, the principal stresses.
    pub fn of(grid: SurfaceGrid, layers: usize, stress: [Vec<f64>; 6], material: Vec<u16>) -> Self {
        let total = stress[0].len();
        let mut vm = vec![0.0; total];
        let mut tresca = vec![0.0; total];
        let mut principal: [Vec<f64>; 3] = std::array::from_fn(|_| vec![0.0; total]);
        for idx in 0..total {
            let sig: [f64; 6] = std::array::from_fn(|o| stress[o][idx]);
            let pr = principal_stresses(&sig);
            for o in 0..3 {
                principal[o][idx] = pr[o];
            }
            vm[idx] = von_mises(&sig);
            tresca[idx] = pr[0] - pr[2];
        }
        Self {
            grid,
            layers,
            stress,
            von_mises: vm,
            tresca,
            principal,
            material,
        }
    }
}

/// Eigenstrains for [`stress_at_points`]: the inclusion cells, their eigenstrains (6 per cell) and
/// the correction pressure `p_c` on the grid ([`crate::eim::EimFields::correction_pressure`]).
pub type EigenSources<'a> = (&'a InclusionSet, &'a [f64], &'a [f64]);

/// The stress at arbitrary points `(x₁, x₂, depth > 0)` by direct summation (the twin of
/// [`subsurface_stress`] at the cell centres, and the evaluation off the lattice for reference
/// fixtures): Love's rectangle stresses of the piecewise-constant tractions `p + p_c` (and `q`) on
/// the grid cells (docs/theory-sam.md#love-rectangle-stresses), `σ⁰(x) = Σ_c p_c Σ^p(x − x_c) + q₁,c Σ^{q₁} + q₂,c Σ^{q₂}`, plus, with
/// `eigen`, the strain of every inclusion cuboid and its mirror image (docs/theory-sam.md#cuboid-in-infinite-space to #mirror-image-and-correction-pressure),
/// `ε^d(x) = Σ_b D(x − x_b) ε*_b + D(x − x̄_b) ε*ˢ_b`; `σ = C : (C_m⁻¹ σ⁰ + ε^d)` with `C` the
/// stiffness of the cell the point lies in. O(cells) per point.
pub fn stress_at_points(
    grid: &SurfaceGrid,
    e: f64,
    nu: f64,
    p: &[f64],
    q: Option<[&[f64]; 2]>,
    eigen: Option<EigenSources<'_>>,
    points: &[[f64; 3]],
) -> Result<Vec<[f64; 6]>, SamError> {
    let n = grid.len();
    let bad_len = |v: &[f64]| v.len() != n;
    if bad_len(p)
        || q.is_some_and(|q| bad_len(q[0]) || bad_len(q[1]))
        || eigen.is_some_and(|(set, eps, pc)| bad_len(pc) || eps.len() != 6 * set.len())
    {
        return Err(SamError::Numerics(
            halfspace_numerics::NumericsError::LengthMismatch {
                what: "surface traction, correction pressure or eigenstrain field",
                expected: n,
                got: p.len(),
            },
        ));
    }
    crate::error::positive("Young's modulus", e)?;
    let (d1, d2) = (grid.half1, grid.half2);
    let pressure: Vec<f64> = match eigen {
        Some((_, _, pc)) => p.iter().zip(pc).map(|(a, b)| a + b).collect(),
        None => p.to_vec(),
    };
    let cm = stiffness(e, nu);
    let sm = compliance(e, nu);
    points
        .iter()
        .map(|pt| {
            if !(pt[2].is_finite() && pt[2] > 0.0) {
                return Err(SamError::InvalidParameter {
                    name: "depth of a stress point",
                    value: pt[2],
                    allowed: "> 0",
                });
            }
            let mut s = [0.0; 6];
            for c in 0..n {
                let (xc, yc) = grid.centre(c / grid.n2, c % grid.n2);
                let (dx, dy) = (pt[0] - xc, pt[1] - yc);
                let mut add = |w: f64, sig: [f64; 6]| {
                    for o in 0..6 {
                        s[o] += w * sig[o];
                    }
                };
                if pressure[c] != 0.0 {
                    add(pressure[c], pressure_stress(dx, dy, pt[2], d1, d2, nu));
                }
                if let Some([q1, q2]) = q {
                    if q1[c] != 0.0 {
                        add(q1[c], shear_stress(InPlane::X1, dx, dy, pt[2], d1, d2, nu));
                    }
                    if q2[c] != 0.0 {
                        add(q2[c], shear_stress(InPlane::X2, dx, dy, pt[2], d1, d2, nu));
                    }
                }
            }
            let Some((set, eps, _)) = eigen else {
                return Ok(s);
            };
            let mut strain = mul6(&sm, &s);
            let half = set.half;
            let mut material = None;
            for (b, cell) in set.cells.iter().enumerate() {
                let (xb, yb) = grid.centre(cell.flat / grid.n2, cell.flat % grid.n2);
                let zb = (2 * set.layers[cell.layer] + 1) as f64 * half;
                let rel = [pt[0] - xb, pt[1] - yb, pt[2] - zb];
                if rel.iter().all(|v| v.abs() < half) {
                    material = Some(cell.material);
                }
                let e_b = &eps[6 * b..6 * b + 6];
                let mirrored = [e_b[0], e_b[1], e_b[2], -e_b[3], -e_b[4], e_b[5]];
                let d_inf = strain_kernel(rel, [half; 3], nu);
                let d_img = strain_kernel([rel[0], rel[1], pt[2] + zb], [half; 3], nu);
                let (a, b2) = (mul6(&d_inf, e_b), mul6(&d_img, &mirrored));
                for o in 0..6 {
                    strain[o] += a[o] + b2[o];
                }
            }
            Ok(match material {
                None => mul6(&cm, &strain),
                Some(m) => {
                    let (ei, nui) = set.materials[m];
                    mul6(&stiffness(ei, nui), &strain)
                }
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn principal_stresses_of_known_tensors() {
        let p = principal_stresses(&[3.0, 1.0, 2.0, 0.0, 0.0, 0.0]);
        assert_eq!(p, [3.0, 2.0, 1.0]);
        // Pure shear σ₁₂ = τ: ±τ and 0.
        let p = principal_stresses(&[0.0, 0.0, 0.0, 0.0, 0.0, 2.0]);
        assert!((p[0] - 2.0).abs() < 1e-14 && p[1].abs() < 1e-14 && (p[2] + 2.0).abs() < 1e-14);
        // A general tensor: invariants preserved.
        let s = [1.0, -2.0, 0.5, 0.3, -0.7, 1.1];
        let p = principal_stresses(&s);
        assert!((p.iter().sum::<f64>() - (s[0] + s[1] + s[2])).abs() < 1e-13);
        let det = s[0] * (s[1] * s[2] - s[3] * s[3]) - s[5] * (s[5] * s[2] - s[3] * s[4])
            + s[4] * (s[5] * s[3] - s[1] * s[4]);
        assert!((p[0] * p[1] * p[2] - det).abs() < 1e-12);
        let vm_p =
            (0.5 * ((p[0] - p[1]).powi(2) + (p[1] - p[2]).powi(2) + (p[2] - p[0]).powi(2))).sqrt();
        assert!((von_mises(&s) - vm_p).abs() < 1e-12);
    }

    /// The von Mises fields of several states at once (with eigenstrains, shear on some states
    /// only, the layers in one group and in groups of one layer) are each state's
    /// [`subsurface_stress`] field bit for bit; a wrong eigenstrain length is refused.
    #[test]
    fn the_fields_of_several_states_are_each_states_field_bit_for_bit() {
        use crate::eim::{solve_under_tractions, EimParams, Inhomogeneity, Shape};
        let n = 12;
        let grid = SurfaceGrid::square(n, 3.0).unwrap();
        let (e, nu, depth) = (1.0, 0.3, 1.3);
        let inh = Inhomogeneity {
            shape: Shape::Sphere {
                x: 0.1,
                y: -0.1,
                z: 0.6,
                r: 0.35,
            },
            e: 3.0,
            nu: 0.25,
        };
        let mut states = Vec::new();
        for (s, scale) in [(0.0, 1.0), (0.2, 0.8), (-0.3, 1.1)].iter().enumerate() {
            let p: Vec<f64> = (0..n * n)
                .map(|k| {
                    let (x, y) = grid.centre(k / n, k % n);
                    scale.1 * (1.0 - (x - scale.0).powi(2) - y * y).max(0.0).sqrt()
                })
                .collect();
            let q: Option<[Vec<f64>; 2]> = (s != 1).then(|| {
                [
                    p.iter().map(|v| 0.2 * v).collect(),
                    p.iter().map(|v| -0.05 * scale.0 * v).collect(),
                ]
            });
            let qs = q.as_ref().map(|q| [q[0].as_slice(), q[1].as_slice()]);
            let sol =
                solve_under_tractions(grid, e, nu, &[inh], &p, qs, &EimParams::default()).unwrap();
            states.push((p, q, sol.eigenstrain, sol.set));
        }
        let set = &states[0].3;
        let sources: Vec<FieldSources> = states
            .iter()
            .map(|(p, q, eps, _)| FieldSources {
                pressure: p,
                shear: q.as_ref().map(|q| [q[0].as_slice(), q[1].as_slice()]),
                eigenstrain: Some(eps),
            })
            .collect();
        let one = |s: &FieldSources| {
            subsurface_stress(
                &grid,
                e,
                nu,
                s.pressure,
                s.shear,
                depth,
                Some((set, s.eigenstrain.unwrap())),
            )
            .unwrap()
            .von_mises
        };
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for budget in [FIELD_GROUP_BYTES, 1.0] {
            let fields =
                fields_in_groups(&grid, (e, nu), depth, Some(set), &sources, budget).unwrap();
            assert_eq!(fields.len(), 3);
            for (s, f) in sources.iter().zip(&fields) {
                assert_eq!(bits(f), bits(&one(s)), "group budget {budget}");
            }
        }
        // Without inclusions: Love's field alone.
        let plain: Vec<FieldSources> = sources
            .iter()
            .map(|s| FieldSources {
                eigenstrain: None,
                ..*s
            })
            .collect();
        let fields = von_mises_fields(&grid, e, nu, depth, None, &plain).unwrap();
        for (s, f) in plain.iter().zip(&fields) {
            let want = subsurface_stress(&grid, e, nu, s.pressure, s.shear, depth, None).unwrap();
            assert_eq!(bits(f), bits(&want.von_mises));
        }
        let short = FieldSources {
            eigenstrain: Some(&states[0].2[1..]),
            ..sources[0]
        };
        assert!(von_mises_fields(&grid, e, nu, depth, Some(set), &[short]).is_err());
        assert!(von_mises_fields(&grid, e, nu, depth, Some(set), &[])
            .unwrap()
            .is_empty());
        // A set built on another grid is refused, not indexed out of bounds.
        let coarse = SurfaceGrid::square(8, 3.0).unwrap();
        let plain8 = vec![0.0; 64];
        let other = FieldSources {
            pressure: &plain8,
            shear: None,
            eigenstrain: Some(&states[0].2),
        };
        assert!(von_mises_fields(&coarse, e, nu, depth, Some(set), &[other]).is_err());
    }

    /// A traction field of the wrong length is refused by the stresses of the whole box and of
    /// some levels, naming the bad field's own length (a short `q₁` after a good `p`), and so is an
    /// amplitude map of the bounds.
    #[test]
    fn tractions_of_another_length_are_refused_with_their_length() {
        let grid = SurfaceGrid::square(8, 1e-4).unwrap();
        let mut plan = SubsurfacePlan::new(&grid, 210e9, 0.3, 3e-5).unwrap();
        let (ok, short) = (vec![1.0; grid.len()], vec![1.0; 5]);
        let want = SamError::Numerics(halfspace_numerics::NumericsError::LengthMismatch {
            what: "surface traction field",
            expected: 64,
            got: 5,
        });
        let q = Some([&short[..], &ok[..]]);
        assert_eq!(plan.stress(&ok, q, None).unwrap_err(), want);
        assert_eq!(plan.stress_of_levels(&[0], &ok, q).unwrap_err(), want);
        let e = plan
            .deviation_bounds_of_levels(&[0], &[[&ok[..], &ok[..], &short[..]]])
            .unwrap_err();
        assert!(
            e.to_string()
                .contains("traction amplitude field: expected length 64, got 5"),
            "{e}"
        );
    }
}
