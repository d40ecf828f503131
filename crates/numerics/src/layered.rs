//! Layered 3D DC-FFT (docs/theory-sam.md#layered-operators): fields on a stack of layers of `N₁ × N₂` cells that share
//! the surface lattice, at depths `x₃ = z Δ₃` with integer depth keys `z` (a layer of cubes of side
//! `2Δ₃` centred at `(2k + 1)Δ₃` has `z = 2k + 1`; the surface has `z = 0`). The output at target
//! layer `a` is
//!
//! `y_{a,o} = Σ_b Σ_i Σ_F K^F_{oi}(·, ·, key_F(a, b)) * x_{b,i}`,
//!
//! a sum over kernel **families** `F` whose kernels depend on the layers only through the difference
//! `z_a − z_b` (the infinite-space part) or the sum `z_a + z_b` (the mirror image). Each family stores
//! one set of `n_out × n_in` kernel spectra per distinct key — `N_t + N_s − 1` sets, not `N_t N_s` — and
//! the input spectra are computed once per application and shared by every family and target
//! ([`LayeredSpectra::accumulate`]). [`LayeredOperator`] is the operator of the fields (transforms,
//! products, inverse transforms); [`DenseLayered`] evaluates the same sums directly, as its twin.

use std::collections::BTreeMap;

use rayon::prelude::*;

use crate::fft2d::{multiply_accumulate, Fft2d, C64};
use crate::op::{check_fields, GridOperator, OperatorShape};
use crate::NumericsError;

/// How a family's kernel depends on the target and source depth keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// On `z_a − z_b` (infinite-space kernels: `x₃ − x₃′`).
    Difference,
    /// On `z_a + z_b` (mirror images: `x₃ + x₃′`).
    Sum,
}

impl Family {
    /// The key of target depth `za` and source depth `zb`.
    pub fn key(self, za: i64, zb: i64) -> i64 {
        match self {
            Family::Difference => za - zb,
            Family::Sum => za + zb,
        }
    }
}

/// The kernels of one family: all `n_out × n_in` blocks at one in-plane offset and depth key at once
/// (they share the potentials they are built from).
pub trait LayerKernel: Sync {
    /// `(n_out, n_in)`.
    fn blocks(&self) -> (usize, usize);
    /// `out[o · n_in + i] = K_oi(m, n, key)` for the in-plane offset `(m, n)` in cells.
    fn eval(&self, key: i64, m: i64, n: i64, out: &mut [f64]);
    /// Per block, whether it is odd (`true`) or even in `m` and in `n`, when every block has a
    /// parity; then only the quadrant `m, n ≥ 0` is evaluated for the stored spectra. The dense
    /// control always evaluates every offset, so a wrong parity fails the twin tests.
    fn parity(&self) -> Option<Vec<(bool, bool)>> {
        None
    }
}

/// Kernel tables `(2N₁ − 1)(2N₂ − 1)` per block, for one key, tabulated in parallel over rows; with
/// `use_parity` and a kernel that declares its parities, only the quadrant `m, n ≥ 0` is evaluated
/// and the rest is filled by symmetry.
fn tabulate(
    n1: usize,
    n2: usize,
    kernel: &dyn LayerKernel,
    key: i64,
    use_parity: bool,
) -> Vec<Vec<f64>> {
    let (n_out, n_in) = kernel.blocks();
    let nb = n_out * n_in;
    let w = 2 * n2 - 1;
    let parity = if use_parity { kernel.parity() } else { None };
    let mut flat = vec![0.0; (2 * n1 - 1) * w * nb];
    let (c1, c2) = (n1 - 1, n2 - 1);
    let quadrant = parity.is_some();
    flat.par_chunks_mut(w * nb)
        .enumerate()
        .for_each(|(r, row)| {
            if quadrant && r < c1 {
                return;
            }
            let m = r as i64 - c1 as i64;
            for (c, vals) in row.chunks_mut(nb).enumerate() {
                if quadrant && c < c2 {
                    continue;
                }
                let n = c as i64 - c2 as i64;
                kernel.eval(key, m, n, vals);
            }
        });
    if let Some(par) = parity {
        // Mirror the quadrant: K(m, −n) = ±K(m, n), then K(−m, n) = ±K(m, n).
        for r in c1..2 * n1 - 1 {
            for c in 0..c2 {
                let src = (r * w + (2 * c2 - c)) * nb;
                let dst = (r * w + c) * nb;
                for b in 0..nb {
                    let v = flat[src + b];
                    flat[dst + b] = if par[b].1 { -v } else { v };
                }
            }
        }
        for r in 0..c1 {
            let src_row = 2 * c1 - r;
            for c in 0..w {
                let src = (src_row * w + c) * nb;
                let dst = (r * w + c) * nb;
                for b in 0..nb {
                    let v = flat[src + b];
                    flat[dst + b] = if par[b].0 { -v } else { v };
                }
            }
        }
    }
    (0..nb)
        .map(|blk| flat.iter().skip(blk).step_by(nb).copied().collect())
        .collect()
}

/// Frequencies per cache block in [`LayeredSpectra::accumulate`].
const FREQUENCY_CHUNK: usize = 64;

/// Spectra up to this length (a 64² plan: 8 320 values) are accumulated without frequency blocks.
const SMALL_SPECTRUM: usize = 8320;

/// Per depth key, the spectra of the `n_out × n_in` blocks (`None` = identically zero block).
type SpectraByKey = BTreeMap<i64, Vec<Option<Vec<C64>>>>;
/// Per depth key, the kernel tables of the blocks.
type TablesByKey = BTreeMap<i64, Vec<Vec<f64>>>;
/// Per depth key, the quarter-stored spectra of the blocks ([`Quarters`]; `None` = zero block).
type QuartersByKey = BTreeMap<i64, Vec<Option<Vec<f64>>>>;

/// The stored kernel spectra of a layered operator.
pub struct LayeredSpectra {
    n1: usize,
    n2: usize,
    n_in: usize,
    n_out: usize,
    targets: Vec<i64>,
    sources: Vec<i64>,
    /// Per family: key → blocks (`None` = identically zero block); empty when `depth` or
    /// `quarters` holds the operator.
    families: Vec<(Family, SpectraByKey)>,
    /// The same per-key spectra stored by quarter when every block has a parity in `m` and `n`.
    quarters: Option<Quarters>,
    /// The same operator with the depth sums done by FFT, when targets and sources are one
    /// contiguous stack of layers.
    depth: Option<Box<DepthSpectra>>,
    /// The output pieces of the parallel products, kept between applications.
    pieces: PieceStore,
}

/// Per-key spectra stored by quarter (docs/performance.md, "The difference family's real spectra
/// and the per-pass fields"): a block even or odd in `m` and in `n` has a 2D spectrum that is real
/// (the same parity in both) or imaginary, `K̂ = i^c R`, and even or odd under `ξ₁ → −ξ₁`
/// (`K̂(2N₁ − r) = s K̂(r)`, `s = −1` when odd in `m`): one real number per frequency of the rows
/// `r ≤ N₁` is stored (a quarter of the bytes of the complex spectrum), and a product is a real
/// times a complex number, turned by `i^c` and signed by `s` (exact).
struct Quarters {
    /// Per block: (odd in `m`: `s = −1`, imaginary: `c = 1`).
    kinds: Vec<(bool, bool)>,
    /// Per family: key → per block `R[col · (N₁ + 1) + r]` (`None` = identically zero block).
    families: Vec<(Family, QuartersByKey)>,
    /// Per block, the largest dropped part (the imaginary part of `K̂ (−i)^c` and the mirrored
    /// rows' departure from `s K̂(r)`) over the largest kept `|R|`: the largest of these.
    discarded: f64,
    /// The CPU's AVX2 level, detected once (`None`: the products run one value at a time;
    /// [`real_times_complex`]).
    level: Option<Avx2>,
}

/// pulp's AVX2 level (x86-64-v3) where the CPU has it.
#[cfg(target_arch = "x86_64")]
type Avx2 = pulp::x86::V3;
/// No AVX2 level off x86-64.
#[cfg(not(target_arch = "x86_64"))]
#[derive(Clone, Copy, Debug)]
enum Avx2 {}

/// The CPU's AVX2 level, if any.
fn avx2_level() -> Option<Avx2> {
    #[cfg(target_arch = "x86_64")]
    {
        pulp::x86::V3::try_new()
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        None
    }
}

impl Quarters {
    /// The quarter of a block's spectrum `k` (`2N₁ × (N₂ + 1)` values, column-major), with the
    /// largest dropped part and the largest kept value.
    fn store(
        k: &[C64],
        (n1, n2): (usize, usize),
        (odd_m, imag): (bool, bool),
    ) -> (Vec<f64>, f64, f64) {
        let (p1, h) = (2 * n1, n1 + 1);
        let turn = |v: C64| if imag { C64::new(v.im, -v.re) } else { v };
        let mut out = vec![0.0; (n2 + 1) * h];
        let (mut kept, mut dropped) = (0.0f64, 0.0f64);
        for col in 0..=n2 {
            for r in 0..p1 {
                let v = turn(k[col * p1 + r]);
                if r <= n1 {
                    out[col * h + r] = v.re;
                    kept = kept.max(v.re.abs());
                    dropped = dropped.max(v.im.abs());
                } else {
                    let sign = if odd_m { -1.0 } else { 1.0 };
                    let mirror = turn(k[col * p1 + (p1 - r)]);
                    dropped = dropped.max((v - mirror * sign).norm());
                }
            }
        }
        (out, dropped, kept)
    }
}

/// Largest part of a 2D spectrum the quarter storage may drop, relative to the block's largest
/// kept value (the 2D FFT's rounding of an exactly (anti)symmetric table: measured ≤ 3.3e-15 for
/// the EIM's Love and surface kernels at 128², ≤ 4.9e-16 for the test kernels); above it the
/// complex spectra are kept. (A wrongly declared parity is already imposed on the table by
/// [`tabulate`], before any spectrum: only the dense twin tests catch that.)
const QUARTER_TOLERANCE: f64 = 1e-12;

/// `acc[j] += K̂(start + j) x[j]` for a block stored by quarter ([`Quarters`]): `R` (`(N₂ + 1) ·
/// (N₁ + 1)` values), odd in `m` (`s = −1` on the mirrored rows), imaginary (`K̂ = i R`).
#[inline(always)]
fn quarter_accumulate(
    level: Option<Avx2>,
    acc: &mut [C64],
    start: usize,
    r_quarter: &[f64],
    x: &[C64],
    n1: usize,
    (odd_m, imag): (bool, bool),
) {
    let (p1, h) = (2 * n1, n1 + 1);
    let end = start + acc.len();
    let mut f = start;
    while f < end {
        let (col, r) = (f / p1, f % p1);
        let base = col * h;
        let j = f - start;
        if r <= n1 {
            let run = (h - r).min(end - f);
            let ks = &r_quarter[base + r..base + r + run];
            let (a, xs) = (&mut acc[j..j + run], &x[j..j + run]);
            real_times_complex(level, a, ks, (false, false, imag), xs);
            f += run;
        } else {
            // Rows r, r + 1, … read the stored rows 2N₁ − r, 2N₁ − r − 1, … (times s).
            let run = (p1 - r).min(end - f);
            let top = base + p1 - r;
            let ks = &r_quarter[top + 1 - run..=top];
            let (a, xs) = (&mut acc[j..j + run], &x[j..j + run]);
            real_times_complex(level, a, ks, (true, odd_m, imag), xs);
            f += run;
        }
    }
}

/// `acc[j] += k_j x[j]` (`imag`: `acc[j] += i k_j x[j]`) with `k_j = ks[j]` (`reversed`:
/// `ks[len − 1 − j]`), negated with `negate`: per value `re += k x.re, im += k x.im` (turned:
/// `re += (−k) x.im, im += k x.re`, the bits of `re −= k x.im`). With AVX2, four values at a time
/// on interleaved lanes (`k` duplicated per value and signed by multiplying with ±1, `x` swapped
/// when turned; [`real_times_complex_avx2`]), the rest one by one: the same operations in the
/// same order (no fused multiply-adds), so the same bits on either path.
#[inline(always)]
fn real_times_complex(
    level: Option<Avx2>,
    acc: &mut [C64],
    ks: &[f64],
    (reversed, negate, imag): (bool, bool, bool),
    x: &[C64],
) {
    let len = acc.len();
    #[cfg(target_arch = "x86_64")]
    let done = match level {
        Some(simd) => real_times_complex_avx2(simd, acc, ks, (reversed, negate, imag), x),
        None => 0,
    };
    #[cfg(not(target_arch = "x86_64"))]
    let done = {
        let _ = level;
        0
    };
    for j in done..len {
        let v = if reversed { ks[len - 1 - j] } else { ks[j] };
        let kj = if negate { -v } else { v };
        let (a, xv) = (&mut acc[j], x[j]);
        if imag {
            a.re += -kj * xv.im;
            a.im += kj * xv.re;
        } else {
            a.re += kj * xv.re;
            a.im += kj * xv.im;
        }
    }
}

/// [`real_times_complex`] on the first `4⌊len/4⌋` values with AVX2 (returns that count): per four
/// values, the four kernel values loaded at once, duplicated per complex value by a lane
/// permutation (reversed runs by the reversed permutation), multiplied by the lane signs `±1`
/// (exact), and `acc += k ⊙ x` on two vectors of two complex values each (`x` with re and im
/// swapped when turned).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn real_times_complex_avx2(
    simd: pulp::x86::V3,
    acc: &mut [C64],
    ks: &[f64],
    (reversed, negate, imag): (bool, bool, bool),
    x: &[C64],
) -> usize {
    use pulp::f64x4;
    let len = acc.len().min(x.len()).min(ks.len());
    let blocks = len / 4;
    let sign_im = if negate { -1.0 } else { 1.0 };
    let sign_re = if imag { -sign_im } else { sign_im };
    let signs = f64x4(sign_re, sign_im, sign_re, sign_im);
    let acc_f: &mut [f64] = pulp::bytemuck::cast_slice_mut(&mut acc[..4 * blocks]);
    let x_f: &[f64] = pulp::bytemuck::cast_slice(&x[..4 * blocks]);
    for b in 0..blocks {
        let j = 4 * b;
        let kv = if reversed {
            let t = len - 4 - j;
            f64x4(ks[t], ks[t + 1], ks[t + 2], ks[t + 3])
        } else {
            f64x4(ks[j], ks[j + 1], ks[j + 2], ks[j + 3])
        };
        let km: core::arch::x86_64::__m256d = pulp::cast(kv);
        // Lanes (k₀ k₀ k₁ k₁), (k₂ k₂ k₃ k₃) of the values j … j + 3 (reversed: the loaded
        // four from the last).
        let (lo, hi) = if reversed {
            (
                simd.avx2._mm256_permute4x64_pd::<0b1010_1111>(km),
                simd.avx2._mm256_permute4x64_pd::<0b0000_0101>(km),
            )
        } else {
            (
                simd.avx2._mm256_permute4x64_pd::<0b0101_0000>(km),
                simd.avx2._mm256_permute4x64_pd::<0b1111_1010>(km),
            )
        };
        let lo: f64x4 = simd.mul_f64x4(pulp::cast(lo), signs);
        let hi: f64x4 = simd.mul_f64x4(pulp::cast(hi), signs);
        let xs = &x_f[2 * j..2 * j + 8];
        let mut x0 = f64x4(xs[0], xs[1], xs[2], xs[3]);
        let mut x1 = f64x4(xs[4], xs[5], xs[6], xs[7]);
        if imag {
            x0 = pulp::cast(simd.avx._mm256_permute_pd::<0b0101>(pulp::cast(x0)));
            x1 = pulp::cast(simd.avx._mm256_permute_pd::<0b0101>(pulp::cast(x1)));
        }
        let a = &mut acc_f[2 * j..2 * j + 8];
        let a0 = simd.add_f64x4(f64x4(a[0], a[1], a[2], a[3]), simd.mul_f64x4(lo, x0));
        let a1 = simd.add_f64x4(f64x4(a[4], a[5], a[6], a[7]), simd.mul_f64x4(hi, x1));
        let (a0, a1): ([f64; 4], [f64; 4]) = (pulp::cast(a0), pulp::cast(a1));
        a[..4].copy_from_slice(&a0);
        a[4..].copy_from_slice(&a1);
    }
    4 * blocks
}

/// The layered operator on one contiguous stack of `L` layers (targets = sources, depth keys
/// `z₀ + 2b`), with the sums over source layers done by a length-`P = 2L` FFT in depth, per in-plane
/// frequency (docs/theory-sam.md#layered-operators, "3D DC-FFT / DC-FFT-CC", Liu & Wang 2005): the difference family is a
/// Toeplitz product in `a − b` (a linear convolution, zero-padded to `P`); the sum family a Hankel
/// product in `a + b`, i.e. a Toeplitz product with the source order reversed, whose depth spectrum
/// is the input's at `−ω` times a phase folded into the stored kernel. `O(P log P + P·blocks)` per
/// frequency instead of `O(L²·blocks)`.
struct DepthSpectra {
    layers: usize,
    p: usize,
    /// Whether each part stored complex in `data` is the sum family (the families in their given
    /// order, without a difference family stored real in `real`).
    part_is_sum: Vec<bool>,
    /// The difference family stored as one real number per value, when its depth spectra are real
    /// or imaginary.
    real: Option<RealPart>,
    /// In-plane plan: `2N₁` rows per column; stored rows (`N₁ + 1` with the row symmetry).
    p1: usize,
    stored_rows: usize,
    /// Depth frequencies stored (`P/2 + 1` when the depth spectra are Hermitian).
    stored_k: usize,
    /// The blocks' parities, factored per output and input, when the quarter is stored.
    symmetry: Option<Symmetry>,
    /// `w^{(L−1)k}`: the phase of the reversed stack's spectrum (sum family).
    phase: Vec<C64>,
    /// `data[((g · stored_k + k) · n_out + o) · parts · n_in + part · n_in + i]`: the kernel's depth
    /// spectrum / P at the stored in-plane frequency `g` (the parts of `part_is_sum`).
    data: Vec<C64>,
    fwd: std::sync::Arc<dyn rustfft::Fft<f64>>,
    inv: std::sync::Arc<dyn rustfft::Fft<f64>>,
    /// Work arrays kept between applications.
    pool: std::sync::Mutex<Vec<DepthBuffers>>,
    /// The CPU's SIMD level, detected once.
    arch: pulp::Arch,
}

/// Work arrays borrowed from a pool, returned when dropped.
struct Pooled<'a> {
    pool: &'a std::sync::Mutex<Vec<DepthBuffers>>,
    buffers: Option<DepthBuffers>,
}

impl Drop for Pooled<'_> {
    fn drop(&mut self) {
        if let (Some(b), Ok(mut pool)) = (self.buffers.take(), self.pool.lock()) {
            pool.push(b);
        }
    }
}

/// The difference family's depth spectra stored real (docs/performance.md, "The difference
/// family's real spectra and the per-pass fields"): a block's 2D spectrum is real or imaginary by
/// its parities in `m` and `n` (`t_o t_i`), and its depth sequence, zero-padded to `P` around
/// `d = a − b = 0`, is even or odd in `d` (`K(−d) = ±K(d)`: a tensor component changes sign under
/// `x₃ → −x₃` with the count of the index 3), so its depth spectrum is real or imaginary. Both
/// factor per output and input: `K̂_{oi}(g, k) = i^{c_o} i^{c_i} r_{oi}(g, k)` with `r` real.
struct RealPart {
    /// `c_o`, `c_i`: the factor `i` per output and input.
    c_out: Vec<bool>,
    c_in: Vec<bool>,
    /// `data[((g · stored_k + k) · n_out + o) · n_in + i] = r_{oi}(g, k)`.
    data: Vec<f64>,
    /// Per block, the largest dropped part (`K̂ − i^{c_o + c_i} r`) over the largest kept `|r|`
    /// (0 for a zero block): the largest of these.
    discarded: f64,
}

/// Largest departure from the even/odd parity of a block's depth sequence allowed, relative to
/// the block's largest 2D spectrum value (`max |K(2d) ∓ K(−2d)| / max |K|`): above it the family
/// is stored complex. The exact kernels are exactly even or odd; their tabulation is not to the
/// bit (the strain potentials of a cube at `x₃` and `−x₃` round differently): measured ≤ 6.8e-13
/// at 64² and ≤ 1.6e-12 at 128² for the EIM's strain kernels (growing ≈ 2.4× per doubling of N),
/// O(1) for a block of no parity; 1e-10 leaves ≈ 60× for the finer grids. Storing the even or odd
/// part drops that departure (the tabulation's rounding). The check is against the block's largest
/// value, not per frequency.
const DEPTH_PARITY_TOLERANCE: f64 = 1e-10;

/// Per block, whether its 2D spectra are odd in the depth difference `d` (`K(−d) = −K(d)`, `true`)
/// or even, from the spectra at keys `2d`, `|d| < L` (`None` when a block is neither to
/// [`DEPTH_PARITY_TOLERANCE`] of its largest value, or is zero).
fn depth_parities(map: &SpectraByKey, layers: i64, blocks: usize) -> Option<Vec<Option<bool>>> {
    (0..blocks)
        .map(|b| {
            let (mut even, mut odd, mut scale) = (0.0f64, 0.0f64, 0.0f64);
            for d in 0..layers {
                let get = |key: i64| map.get(&key).and_then(|bl| bl[b].as_deref());
                let (plus, minus) = (get(2 * d), get(-2 * d));
                let len = plus.or(minus).map_or(0, |v| v.len());
                for f in 0..len {
                    let u = plus.map_or(C64::new(0.0, 0.0), |v| v[f]);
                    let w = minus.map_or(C64::new(0.0, 0.0), |v| v[f]);
                    even = even.max((u - w).norm());
                    odd = odd.max((u + w).norm());
                    scale = scale.max(u.norm()).max(w.norm());
                }
            }
            if scale == 0.0 {
                Some(None)
            } else if odd <= DEPTH_PARITY_TOLERANCE * scale {
                Some(Some(true))
            } else if even <= DEPTH_PARITY_TOLERANCE * scale {
                Some(Some(false))
            } else {
                None
            }
        })
        .collect()
}

/// `(u_o, v_i)` with `odd[o · n_in + i] = u_o ⊕ v_i` for every block whose parity is known
/// (`None`: a zero block, either), if such a factorisation exists.
fn factor_parities(
    odd: &[Option<bool>],
    n_out: usize,
    n_in: usize,
) -> Option<(Vec<bool>, Vec<bool>)> {
    let (mut u, mut v): (Vec<Option<bool>>, Vec<Option<bool>>) =
        (vec![None; n_out], vec![None; n_in]);
    // Propagate from each unassigned output (a bipartite 2-colouring with edge labels).
    for start in 0..n_out {
        if u[start].is_some() {
            continue;
        }
        u[start] = Some(false);
        let mut changed = true;
        while changed {
            changed = false;
            for o in 0..n_out {
                for i in 0..n_in {
                    let Some(x) = odd[o * n_in + i] else { continue };
                    match (u[o], v[i]) {
                        (Some(a), None) => {
                            v[i] = Some(a ^ x);
                            changed = true;
                        }
                        (None, Some(b)) => {
                            u[o] = Some(b ^ x);
                            changed = true;
                        }
                        (Some(a), Some(b)) if a ^ b != x => return None,
                        _ => {}
                    }
                }
            }
        }
    }
    Some((
        u.into_iter().map(|x| x.unwrap_or(false)).collect(),
        v.into_iter().map(|x| x.unwrap_or(false)).collect(),
    ))
}

impl DepthSpectra {
    /// Whether `targets` = `sources` = `z₀, z₀ + 2, …` and the families are at most one
    /// difference and one sum family.
    fn eligible(targets: &[i64], sources: &[i64], families: &[Family]) -> bool {
        let diffs = families
            .iter()
            .filter(|f| **f == Family::Difference)
            .count();
        let sums = families.iter().filter(|f| **f == Family::Sum).count();
        !targets.is_empty()
            && targets == sources
            && targets.windows(2).all(|w| w[1] - w[0] == 2)
            && diffs <= 1
            && sums <= 1
    }

    /// Builds the depth spectra. With `parity` (every block even or odd in m and in n, the same for
    /// all families), a block's 2D spectrum is (anti)symmetric under ξ₁ → −ξ₁ and purely real
    /// (same parity in m and n) or purely imaginary: only the rows ξ₁ ≥ 0 and the depth
    /// frequencies k ≤ P/2 are stored (a quarter of the memory and of the memory traffic). With
    /// `allow_real` and a difference family whose blocks are each even or odd in the depth
    /// difference (found from its 2D spectra, [`depth_parities`]) with parities that factor, that
    /// family's depth spectra are real or imaginary and stored as one real number each
    /// ([`RealPart`]: half its memory and half its multiplies).
    /// `spectra(part)` gives the 2D kernel spectra of family `part`, by key: they are requested one
    /// family at a time (the difference family first) and dropped once that family's depth spectra
    /// are stored (the build holds one family's 2D spectra, not all).
    #[allow(clippy::too_many_arguments)]
    fn build(
        families: &[Family],
        spectra: &mut dyn FnMut(usize) -> Result<SpectraByKey, NumericsError>,
        z0: i64,
        layers: usize,
        (n1, n2): (usize, usize),
        (n_out, n_in): (usize, usize),
        parity: Option<&[(bool, bool)]>,
        allow_real: bool,
    ) -> Result<Self, NumericsError> {
        let blocks = n_out * n_in;
        let p = 2 * layers;
        let mut planner = rustfft::FftPlanner::<f64>::new();
        let fwd = planner.plan_fft_forward(p);
        let inv = planner.plan_fft_inverse(p);
        let l = layers as i64;
        let p1 = 2 * n1;
        let cols = n2 + 1;
        let symmetry = parity.and_then(|par| Symmetry::factor(par, n_out, n_in));
        let (stored_rows, stored_k) = if symmetry.is_some() {
            (n1 + 1, p / 2 + 1)
        } else {
            (p1, p)
        };
        let phase: Vec<C64> = (0..p)
            .map(|k| {
                let a = -2.0 * std::f64::consts::PI * (k * (layers - 1)) as f64 / p as f64;
                C64::new(a.cos(), a.sin())
            })
            .collect();
        let scratch_len = fwd.get_inplace_scratch_len();
        let fwd_ref = &fwd;
        let stored = cols * stored_rows * stored_k * blocks;
        // The difference family first: whether it is stored real decides the complex parts.
        let mut order: Vec<usize> = (0..families.len()).collect();
        order.sort_by_key(|&part| families[part] != Family::Difference);
        let mut real: Option<RealPart> = None;
        let mut data: Vec<C64> = Vec::new();
        for part in order {
            let family = families[part];
            let map = spectra(part)?;
            // Per depth slot m ∈ 0..P, per block: the key spectrum (if any) that goes there.
            let mut per_slot: Vec<Vec<Option<&[C64]>>> = vec![vec![None; blocks]; p];
            let entries: Vec<(i64, i64)> = match family {
                // d = a − b ∈ [−(L−1), L−1], key 2d, slot d mod P.
                Family::Difference => (-(l - 1)..l).map(|d| (2 * d, d)).collect(),
                // s = a + b ∈ [0, 2L−2], key 2z₀ + 2s, slot (s − (L−1)) mod P.
                Family::Sum => (0..2 * l - 1)
                    .map(|s| (2 * z0 + 2 * s, s - (l - 1)))
                    .collect(),
            };
            for (key, m) in entries {
                if let Some(bl) = map.get(&key) {
                    let slot = m.rem_euclid(p as i64) as usize;
                    for (b, v) in bl.iter().enumerate() {
                        per_slot[slot][b] = v.as_deref();
                    }
                }
            }
            let per_slot = &per_slot;
            // The depth spectrum / P of block b at stored frequency g into `t`.
            let depth_spectrum = move |g: usize, b: usize, t: &mut [C64], scratch: &mut [C64]| {
                let f = (g / stored_rows) * p1 + g % stored_rows;
                for (m, v) in t.iter_mut().enumerate() {
                    *v = per_slot[m][b].map_or(C64::new(0.0, 0.0), |s| s[f]);
                }
                fwd_ref.process_with_scratch(t, scratch);
                for v in t.iter_mut() {
                    *v /= p as f64;
                }
            };
            let init = || {
                (
                    vec![C64::new(0.0, 0.0); p],
                    vec![C64::new(0.0, 0.0); scratch_len],
                )
            };
            let classes = match (&symmetry, family) {
                (Some(sy), Family::Difference) if allow_real => {
                    depth_parities(&map, l, blocks)
                        .and_then(|odd| factor_parities(&odd, n_out, n_in))
                        .map(|(u, v)| {
                            // i per index: an imaginary 2D spectrum (t = −1) xor an odd depth
                            // sequence.
                            let c_out: Vec<bool> = sy
                                .t_out
                                .iter()
                                .zip(&u)
                                .map(|(t, &u)| (*t < 0.0) ^ u)
                                .collect();
                            let c_in: Vec<bool> = sy
                                .t_in
                                .iter()
                                .zip(&v)
                                .map(|(t, &v)| (*t < 0.0) ^ v)
                                .collect();
                            (c_out, c_in)
                        })
                }
                _ => None,
            };
            if let Some((c_out, c_in)) = classes {
                let mut values = vec![0.0; stored];
                // Per block: (largest kept |r|, largest dropped part).
                let extremes = values
                    .par_chunks_mut(stored_k * blocks)
                    .enumerate()
                    .map_init(init, |(t, scratch), (g, chunk)| {
                        let mut ext = vec![(0.0f64, 0.0f64); blocks];
                        let pairs = (0..n_out).flat_map(|o| (0..n_in).map(move |i| (o, i)));
                        for (b, (o, i)) in pairs.enumerate() {
                            depth_spectrum(g, b, t, scratch);
                            // K = i^{c_o + c_i} r: r = K · (−i)^{c_o + c_i}.
                            let turns = usize::from(c_out[o]) + usize::from(c_in[i]);
                            for (k, v) in t.iter().enumerate().take(stored_k) {
                                let w = match turns {
                                    0 => *v,
                                    1 => C64::new(v.im, -v.re),
                                    _ => -*v,
                                };
                                chunk[(k * n_out + o) * n_in + i] = w.re;
                                ext[b].0 = ext[b].0.max(w.re.abs());
                                ext[b].1 = ext[b].1.max(w.im.abs());
                            }
                        }
                        ext
                    })
                    .reduce(
                        || vec![(0.0, 0.0); blocks],
                        |a, b| {
                            a.iter()
                                .zip(&b)
                                .map(|(x, y)| (x.0.max(y.0), x.1.max(y.1)))
                                .collect()
                        },
                    );
                let discarded = extremes
                    .iter()
                    .map(|&(kept, dropped)| if kept > 0.0 { dropped / kept } else { 0.0 })
                    .fold(0.0, f64::max);
                real = Some(RealPart {
                    c_out,
                    c_in,
                    data: values,
                    discarded,
                });
                continue;
            }
            if data.is_empty() {
                let complex_parts = families.len() - usize::from(real.is_some());
                data = vec![C64::new(0.0, 0.0); stored * complex_parts];
            }
            let parts = families.len() - usize::from(real.is_some());
            // This family's index among the complex parts (the families' order).
            let cpart = (0..part)
                .filter(|&q| !(real.is_some() && families[q] == Family::Difference))
                .count();
            data.par_chunks_mut(parts * stored_k * blocks)
                .enumerate()
                .for_each_init(init, |(t, scratch), (g, chunk)| {
                    let pairs = (0..n_out).flat_map(|o| (0..n_in).map(move |i| (o, i)));
                    for (b, (o, i)) in pairs.enumerate() {
                        depth_spectrum(g, b, t, scratch);
                        for (k, v) in t.iter().enumerate().take(stored_k) {
                            chunk[((k * n_out + o) * parts + cpart) * n_in + i] = *v;
                        }
                    }
                });
        }
        let part_is_sum: Vec<bool> = families
            .iter()
            .filter(|f| !(real.is_some() && **f == Family::Difference))
            .map(|f| *f == Family::Sum)
            .collect();
        Ok(Self {
            layers,
            p,
            part_is_sum,
            real,
            p1,
            stored_rows,
            stored_k,
            symmetry,
            phase,
            data,
            fwd,
            inv,
            pool: std::sync::Mutex::new(Vec::new()),
            arch: pulp::Arch::new(),
        })
    }

    /// `outs[a · n_out + o][row] += Σ_b Σ_i K_{oi}(a, b) x̂[b · n_in + i][col · 2N₁ + row]` for every
    /// row of one in-plane column (`outs` are that column's slices; with `write`, `=` instead of
    /// `+=`: the sum is written as `0 + Σ`, the bits of a cleared output added to). With the
    /// symmetries the rows `r` and `2N₁ − r` and the depth frequencies `k` and `P − k` share one
    /// stored kernel value, read once for all four.
    // Several arrays share the frequency and layer indices.
    #[allow(clippy::too_many_arguments)]
    fn apply_column(
        &self,
        n_out: usize,
        n_in: usize,
        col: usize,
        inputs_hat: &[Vec<C64>],
        skip: &[bool],
        outs: &mut [&mut [C64]],
        write: bool,
        buffers: &mut DepthBuffers,
    ) {
        // The widest SIMD level of this CPU (pulp's runtime dispatch: AVX2 on x86-64-v3): the
        // same operations in the same order (no fused multiply-adds), so the same bits as the
        // baseline build, on wider lanes.
        self.arch.dispatch(ColumnTask {
            depth: self,
            n_out,
            n_in,
            col,
            inputs_hat,
            skip,
            outs,
            write,
            buffers,
        });
    }

    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn apply_column_generic<S: pulp::Simd>(
        &self,
        simd: S,
        n_out: usize,
        n_in: usize,
        col: usize,
        inputs_hat: &[Vec<C64>],
        skip: &[bool],
        outs: &mut [&mut [C64]],
        write: bool,
        buffers: &mut DepthBuffers,
    ) {
        let parts = self.part_is_sum.len();
        let per_g = parts * self.stored_k * n_out * n_in;
        let p1 = self.p1;
        // The column of every input and output, copied into contiguous buffers (sequential reads
        // and writes instead of one stream per layer and component).
        for (v, input) in inputs_hat.iter().enumerate() {
            if !skip[v] {
                buffers.column_in[v * p1..(v + 1) * p1]
                    .copy_from_slice(&input[col * p1..(col + 1) * p1]);
            }
        }
        let zero = C64::new(0.0, 0.0);
        for stored_row in 0..self.stored_rows {
            let g = col * self.stored_rows + stored_row;
            let stored = &self.data[g * per_g..(g + 1) * per_g];
            let per_real = self.stored_k * n_out * n_in;
            let real_stored = self
                .real
                .as_ref()
                .map_or(&[][..], |r| &r.data[g * per_real..(g + 1) * per_real]);
            let mirror = (self.symmetry.is_some() && stored_row > 0 && stored_row < self.p1 / 2)
                .then_some(self.p1 - stored_row);
            let DepthBuffers {
                first,
                second,
                lanes,
                real_lanes,
                acc,
                column_in,
                column_out,
                scratch,
            } = &mut *buffers;
            self.load(n_in, stored_row, column_in, skip, first, scratch);
            if let Some(row) = mirror {
                self.load(n_in, row, column_in, skip, second, scratch);
            }
            self.product(
                simd,
                n_out,
                n_in,
                (stored, real_stored),
                mirror.is_some(),
                first,
                second,
                (lanes, real_lanes),
                acc,
            );
            // Every row of the column is written once: r ≤ N₁ here, the others as mirrors.
            let rows = std::iter::once((stored_row, first)).chain(mirror.map(|row| (row, second)));
            for (row, side) in rows {
                self.inv.process_with_scratch(&mut side.y, scratch);
                for a in 0..self.layers {
                    for o in 0..n_out {
                        column_out[(a * n_out + o) * p1 + row] = side.y[o * self.p + a];
                    }
                }
            }
        }
        // Added (or written as `0 + c`) in one sequential pass per output.
        for (v, out) in outs.iter_mut().enumerate() {
            let column = &buffers.column_out[v * p1..(v + 1) * p1];
            if write {
                for (y, c) in out.iter_mut().zip(column) {
                    *y = zero + c;
                }
            } else {
                for (y, c) in out.iter_mut().zip(column) {
                    *y += c;
                }
            }
        }
    }

    /// The depth spectra of the inputs at row `row` of the column (`column[v · 2N₁ + row]`):
    /// `x[i · P + k]`, and those of the reversed stack `X'(k) = w^{(L−1)k} X(−k)` (sum family).
    #[inline(always)]
    fn load(
        &self,
        n_in: usize,
        row: usize,
        column: &[C64],
        skip: &[bool],
        side: &mut DepthSide,
        scratch: &mut [C64],
    ) {
        let (p, l) = (self.p, self.layers);
        for i in 0..n_in {
            let x = &mut side.x[i * p..(i + 1) * p];
            for (b, v) in x.iter_mut().enumerate() {
                *v = if b < l && !skip[b * n_in + i] {
                    column[(b * n_in + i) * self.p1 + row]
                } else {
                    C64::new(0.0, 0.0)
                };
            }
        }
        self.fwd.process_with_scratch(&mut side.x, scratch);
        for i in 0..n_in {
            let (x, xr) = (
                &side.x[i * p..(i + 1) * p],
                &mut side.xr[i * p..(i + 1) * p],
            );
            xr[0] = x[0];
            for k in 1..p {
                xr[k] = self.phase[k] * x[p - k];
            }
        }
    }

    /// `y[o · P + k] = Σ_F Σ_i K̂^F_{oi}(k) x^F[i · P + k]` on the first side and, with `mirrored`,
    /// on the second (row `2N₁ − r`), from one read of the stored quarter. With the factored signs
    /// (`K(−ξ₁) = s_o s_i K(ξ₁)`, `K(P − k) = t_o t_i conj K(k)`), the four products of one stored
    /// value are plain complex products on four lanes:
    /// `y(k) = Σ K(k) x(k)`, `y(P−k) = t_o conj Σ K(k) conj(t_i x(P−k))`, and the same on the
    /// mirrored row with `s_i` on the inputs and `s_o` on the outputs. A difference family stored
    /// real (`K = i^{c_o} i^{c_i} r`, [`RealPart`]) has its lanes turned by `i^{c_i}`, the real
    /// products summed apart and turned by `i^{c_o}`, then added to the complex parts' sum.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn product<S: pulp::Simd>(
        &self,
        simd: S,
        n_out: usize,
        n_in: usize,
        (stored, real_stored): (&[C64], &[f64]),
        mirrored: bool,
        first: &mut DepthSide,
        second: &mut DepthSide,
        (lanes, real_lanes): (&mut [[f64; 8]], &mut [[f64; 8]]),
        acc: &mut [[f64; 8]],
    ) {
        let p = self.p;
        let sk = self.stored_k;
        let parts = self.part_is_sum.len();
        let zero = C64::new(0.0, 0.0);
        // The four lanes of input i at stored depth frequency kk from the depth spectra `in1`
        // (row r) and `in2` (row 2N₁ − r), multiplied by `turn` (1 or i).
        let four = |in1: &[C64], in2: &[C64], kk: usize, i: usize, turn: bool| -> [f64; 8] {
            let k2 = p - kk;
            let paired = self.symmetry.is_some() && kk > 0 && k2 != kk;
            let (s_i, t_i) = self
                .symmetry
                .as_ref()
                .map_or((1.0, 1.0), |sy| (sy.s_in[i], sy.t_in[i]));
            let v = [
                in1[i * p + kk],
                if paired {
                    (in1[i * p + k2] * t_i).conj()
                } else {
                    zero
                },
                if mirrored {
                    in2[i * p + kk] * s_i
                } else {
                    zero
                },
                if mirrored && paired {
                    (in2[i * p + k2] * (s_i * t_i)).conj()
                } else {
                    zero
                },
            ];
            let mut lane = [0.0; 8];
            for (j, c) in v.iter().enumerate() {
                // c · i = (−c.im, c.re): exact.
                let c = if turn { C64::new(-c.im, c.re) } else { *c };
                lane[j] = c.re;
                lane[4 + j] = c.im;
            }
            lane
        };
        // Lanes: re 0..4, im 4..8 of [x₁(k), conj(t x₁(P−k)), s x₂(k), conj(s t x₂(P−k))].
        for (part, &is_sum) in self.part_is_sum.iter().enumerate() {
            let (in1, in2) = if is_sum {
                (&first.xr, &second.xr)
            } else {
                (&first.x, &second.x)
            };
            for kk in 0..sk {
                for i in 0..n_in {
                    lanes[(kk * parts + part) * n_in + i] = four(in1, in2, kk, i, false);
                }
            }
        }
        if let Some(real) = &self.real {
            for kk in 0..sk {
                for i in 0..n_in {
                    real_lanes[kk * n_in + i] = four(&first.x, &second.x, kk, i, real.c_in[i]);
                }
            }
        }
        for kk in 0..sk {
            let k2 = p - kk;
            let paired = self.symmetry.is_some() && kk > 0 && k2 != kk;
            // Per output, the (part, input) row of kernel values against the same row of lanes,
            // both contiguous (the stored order is the order of these reads).
            let lane = &lanes[kk * parts * n_in..][..parts * n_in];
            for (o, a) in acc.iter_mut().enumerate().take(n_out) {
                let kernel = &stored[(kk * n_out + o) * parts * n_in..][..parts * n_in];
                let (mut re, mut im) = lane_products(simd, kernel, lane);
                if let Some(real) = &self.real {
                    let r = &real_stored[(kk * n_out + o) * n_in..][..n_in];
                    let (rr, ri) = real_lane_products(simd, r, &real_lanes[kk * n_in..][..n_in]);
                    // Turned by i^{c_o}, added to the complex parts' sum.
                    let (rr, ri) = if real.c_out[o] {
                        (ri.map(|v| -v), rr)
                    } else {
                        (rr, ri)
                    };
                    for j in 0..4 {
                        re[j] += rr[j];
                        im[j] += ri[j];
                    }
                }
                a[..4].copy_from_slice(&re);
                a[4..].copy_from_slice(&im);
                let (s_o, t_o) = self
                    .symmetry
                    .as_ref()
                    .map_or((1.0, 1.0), |sy| (sy.s_out[o], sy.t_out[o]));
                first.y[o * p + kk] = C64::new(a[0], a[4]);
                if paired {
                    first.y[o * p + k2] = C64::new(a[1], -a[5]) * t_o;
                }
                if mirrored {
                    second.y[o * p + kk] = C64::new(a[2], a[6]) * s_o;
                    if paired {
                        second.y[o * p + k2] = C64::new(a[3], -a[7]) * (s_o * t_o);
                    }
                }
            }
        }
    }
}

/// `(re, im)` of the four lanes' sums `Σ_j r_j z_j` over one row of real kernel values and lanes
/// (lanes: re 0..4, im 4..8): in each lane `re += r z.re`, `im += r z.im`, in this order (no fused
/// multiply-adds: the same bits on every SIMD level), on `S`'s vectors where they hold whole lanes.
#[inline(always)]
fn real_lane_products<S: pulp::Simd>(
    simd: S,
    kernel: &[f64],
    lanes: &[[f64; 8]],
) -> ([f64; 4], [f64; 4]) {
    let (mut re, mut im) = ([0.0f64; 4], [0.0f64; 4]);
    {
        let (re_v, re_t) = S::as_mut_simd_f64s(&mut re);
        let (im_v, im_t) = S::as_mut_simd_f64s(&mut im);
        for (kv, z) in kernel.iter().zip(lanes) {
            let (zr, zi) = z.split_at(4);
            let (zr_v, zr_t) = S::as_simd_f64s(zr);
            let (zi_v, zi_t) = S::as_simd_f64s(zi);
            let k = simd.splat_f64s(*kv);
            for (((r, i), a), b) in re_v.iter_mut().zip(im_v.iter_mut()).zip(zr_v).zip(zi_v) {
                *r = simd.add_f64s(*r, simd.mul_f64s(k, *a));
                *i = simd.add_f64s(*i, simd.mul_f64s(k, *b));
            }
            for (((r, i), a), b) in re_t.iter_mut().zip(im_t.iter_mut()).zip(zr_t).zip(zi_t) {
                *r += kv * a;
                *i += kv * b;
            }
        }
    }
    (re, im)
}

/// `(re, im)` of the four lanes' sums `Σ_j K_j z_j` over one row of kernel values and lanes
/// (lanes: re 0..4, im 4..8): in each lane `re += K.re z.re − K.im z.im`, `im += K.re z.im + K.im
/// z.re`, in this order (no fused multiply-adds: the same bits on every SIMD level), on `S`'s
/// vectors where they hold whole lanes.
#[inline(always)]
fn lane_products<S: pulp::Simd>(
    simd: S,
    kernel: &[C64],
    lanes: &[[f64; 8]],
) -> ([f64; 4], [f64; 4]) {
    let (mut re, mut im) = ([0.0f64; 4], [0.0f64; 4]);
    {
        let (re_v, re_t) = S::as_mut_simd_f64s(&mut re);
        let (im_v, im_t) = S::as_mut_simd_f64s(&mut im);
        for (kv, z) in kernel.iter().zip(lanes) {
            let (zr, zi) = z.split_at(4);
            let (zr_v, zr_t) = S::as_simd_f64s(zr);
            let (zi_v, zi_t) = S::as_simd_f64s(zi);
            let (kr, ki) = (simd.splat_f64s(kv.re), simd.splat_f64s(kv.im));
            for (((r, i), a), b) in re_v.iter_mut().zip(im_v.iter_mut()).zip(zr_v).zip(zi_v) {
                let t = simd.sub_f64s(simd.mul_f64s(kr, *a), simd.mul_f64s(ki, *b));
                *r = simd.add_f64s(*r, t);
                let t = simd.add_f64s(simd.mul_f64s(kr, *b), simd.mul_f64s(ki, *a));
                *i = simd.add_f64s(*i, t);
            }
            for (((r, i), a), b) in re_t.iter_mut().zip(im_t.iter_mut()).zip(zr_t).zip(zi_t) {
                *r += kv.re * a - kv.im * b;
                *i += kv.re * b + kv.im * a;
            }
        }
    }
    (re, im)
}

/// One column of [`DepthSpectra::apply_column`], compiled for each SIMD level pulp dispatches to.
struct ColumnTask<'a, 'b> {
    depth: &'a DepthSpectra,
    n_out: usize,
    n_in: usize,
    col: usize,
    inputs_hat: &'a [Vec<C64>],
    skip: &'a [bool],
    outs: &'a mut [&'b mut [C64]],
    write: bool,
    buffers: &'a mut DepthBuffers,
}

impl pulp::WithSimd for ColumnTask<'_, '_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) {
        self.depth.apply_column_generic(
            simd,
            self.n_out,
            self.n_in,
            self.col,
            self.inputs_hat,
            self.skip,
            self.outs,
            self.write,
            self.buffers,
        );
    }
}

/// The parities of a layered operator's blocks, factored per output and input: a block `(o, i)` is
/// odd in `m` when exactly one of `o`, `i` is (`s = −1`), and its 2D spectrum is imaginary when its
/// parities in `m` and `n` differ (`t = −1` for an index odd in one of them).
#[derive(Debug, Clone)]
struct Symmetry {
    s_out: Vec<f64>,
    s_in: Vec<f64>,
    t_out: Vec<f64>,
    t_in: Vec<f64>,
}

impl Symmetry {
    /// The factorisation of per-block parities `par[o · n_in + i]`, if one exists.
    fn factor(par: &[(bool, bool)], n_out: usize, n_in: usize) -> Option<Self> {
        if par.len() != n_out * n_in || n_in == 0 || n_out == 0 {
            return None;
        }
        let sign = |odd: bool| if odd { -1.0 } else { 1.0 };
        let m_in: Vec<bool> = (0..n_in).map(|i| par[i].0).collect();
        let n_in_: Vec<bool> = (0..n_in).map(|i| par[i].1).collect();
        let m_out: Vec<bool> = (0..n_out).map(|o| par[o * n_in].0 ^ m_in[0]).collect();
        let n_out_: Vec<bool> = (0..n_out).map(|o| par[o * n_in].1 ^ n_in_[0]).collect();
        let factors = (0..n_out).all(|o| {
            (0..n_in).all(|i| par[o * n_in + i] == (m_out[o] ^ m_in[i], n_out_[o] ^ n_in_[i]))
        });
        factors.then(|| Self {
            s_out: m_out.iter().map(|&m| sign(m)).collect(),
            s_in: m_in.iter().map(|&m| sign(m)).collect(),
            t_out: m_out
                .iter()
                .zip(&n_out_)
                .map(|(&m, &n)| sign(m ^ n))
                .collect(),
            t_in: m_in
                .iter()
                .zip(&n_in_)
                .map(|(&m, &n)| sign(m ^ n))
                .collect(),
        })
    }
}

/// One in-plane frequency's depth arrays in [`DepthSpectra::apply_column`].
struct DepthSide {
    x: Vec<C64>,
    xr: Vec<C64>,
    y: Vec<C64>,
}

/// Per-thread work arrays of [`DepthSpectra::apply_column`].
struct DepthBuffers {
    /// The row `r` and its mirror `2N₁ − r`.
    first: DepthSide,
    second: DepthSide,
    /// Per (part, stored depth frequency, input): the four lanes of [`DepthSpectra::product`].
    lanes: Vec<[f64; 8]>,
    /// Per (stored depth frequency, input): those of the difference family stored real.
    real_lanes: Vec<[f64; 8]>,
    /// Per output: the four lanes' sums.
    acc: Vec<[f64; 8]>,
    /// The column's input and output spectra, `[v · 2N₁ + row]`.
    column_in: Vec<C64>,
    column_out: Vec<C64>,
    scratch: Vec<C64>,
}

impl LayeredSpectra {
    /// Tabulates and transforms every kernel needed between `sources` and `targets` (depth keys).
    /// All families must have the same block shape. On one contiguous stack of layers the depth
    /// sums run by FFT, and a difference family whose blocks are even or odd in the depth
    /// difference is stored real (docs/performance.md, "The difference family's real spectra and
    /// the per-pass fields"; [`LayeredSpectra::real_storage_discarded`]); otherwise, with every
    /// block of a parity in `m` and `n`, each key's spectra are stored by quarter
    /// ([`LayeredSpectra::quarter_storage_discarded`]).
    pub fn new(
        fft: &mut Fft2d,
        targets: &[i64],
        sources: &[i64],
        families: &[(Family, &dyn LayerKernel)],
    ) -> Result<Self, NumericsError> {
        Self::build(fft, targets, sources, families, true, true)
    }

    /// [`LayeredSpectra::new`] with the products always per depth key (never the depth FFT of a
    /// contiguous stack): each target's output is then the same sum, bit for bit, whatever the
    /// other targets (a subset of a box's layers equals the whole box's on those layers).
    pub fn per_key(
        fft: &mut Fft2d,
        targets: &[i64],
        sources: &[i64],
        families: &[(Family, &dyn LayerKernel)],
    ) -> Result<Self, NumericsError> {
        Self::build(fft, targets, sources, families, false, false)
    }

    fn build(
        fft: &mut Fft2d,
        targets: &[i64],
        sources: &[i64],
        families: &[(Family, &dyn LayerKernel)],
        allow_depth: bool,
        real: bool,
    ) -> Result<Self, NumericsError> {
        let (n1, n2) = fft.shape();
        let Some((_, first)) = families.first() else {
            return Err(NumericsError::TooFewNodes {
                what: "a layered operator's kernel families",
                min: 1,
                n: 0,
            });
        };
        let (n_out, n_in) = first.blocks();
        for &(_, kernel) in families {
            if kernel.blocks() != (n_out, n_in) {
                return Err(NumericsError::LengthMismatch {
                    what: "layered kernel blocks",
                    expected: n_out * n_in,
                    got: kernel.blocks().0 * kernel.blocks().1,
                });
            }
        }
        // The 2D spectra of one family, by key.
        let mut family_spectra = |part: usize| -> Result<SpectraByKey, NumericsError> {
            let (family, kernel) = families[part];
            let mut keys: Vec<i64> = targets
                .iter()
                .flat_map(|&a| sources.iter().map(move |&b| family.key(a, b)))
                .collect();
            keys.sort_unstable();
            keys.dedup();
            let mut map = BTreeMap::new();
            for key in keys {
                map.insert(key, key_spectra(fft, kernel, key)?);
            }
            Ok(map)
        };
        // One parity for every family (then the depth spectra are stored by quarter).
        let parities: Vec<Option<Vec<(bool, bool)>>> =
            families.iter().map(|(_, k)| k.parity()).collect();
        let parity = match parities.first() {
            Some(Some(first)) if parities.iter().all(|q| q.as_ref() == Some(first)) => {
                Some(first.clone())
            }
            _ => None,
        };
        let kinds: Vec<Family> = families.iter().map(|f| f.0).collect();
        let mut stored = Vec::new();
        let depth = if allow_depth && DepthSpectra::eligible(targets, sources, &kinds) {
            Some(Box::new(DepthSpectra::build(
                &kinds,
                &mut family_spectra,
                targets[0],
                targets.len(),
                (n1, n2),
                (n_out, n_in),
                parity.as_deref(),
                real,
            )?))
        } else {
            for (part, &family) in kinds.iter().enumerate() {
                stored.push((family, family_spectra(part)?));
            }
            None
        };
        // Per key by quarter (not `per_key`'s operators: their bits stay those of the complex
        // spectra).
        let quarters = match &parity {
            Some(par) if depth.is_none() && allow_depth && real => {
                let kinds: Vec<(bool, bool)> = par.iter().map(|&(m, n)| (m, m != n)).collect();
                let mut discarded = 0.0f64;
                let families: Vec<(Family, QuartersByKey)> = stored
                    .iter()
                    .map(|(family, map)| {
                        let map = map
                            .iter()
                            .map(|(&key, blocks)| {
                                let blocks = blocks
                                    .iter()
                                    .zip(&kinds)
                                    .map(|(b, &kind)| {
                                        b.as_ref().map(|k| {
                                            let (q, dropped, kept) =
                                                Quarters::store(k, (n1, n2), kind);
                                            if kept > 0.0 {
                                                discarded = discarded.max(dropped / kept);
                                            }
                                            q
                                        })
                                    })
                                    .collect();
                                (key, blocks)
                            })
                            .collect();
                        (*family, map)
                    })
                    .collect();
                // A declared parity the spectra do not have: the complex spectra are kept.
                (discarded <= QUARTER_TOLERANCE).then_some(Quarters {
                    kinds,
                    families,
                    discarded,
                    level: avx2_level(),
                })
            }
            _ => None,
        };
        if quarters.is_some() {
            stored.clear();
        }
        Ok(Self {
            n1,
            n2,
            n_in,
            n_out,
            targets: targets.to_vec(),
            sources: sources.to_vec(),
            families: stored,
            quarters,
            depth,
            pieces: PieceStore::default(),
        })
    }

    /// `(n_out, n_in)`.
    pub fn blocks(&self) -> (usize, usize) {
        (self.n_out, self.n_in)
    }

    /// Target depth keys.
    pub fn targets(&self) -> &[i64] {
        &self.targets
    }

    /// Source depth keys.
    pub fn sources(&self) -> &[i64] {
        &self.sources
    }

    /// The spectra of depth key `key` of family `family` (block `o · n_in + i`, `None` an
    /// identically zero block) of an operator stored per key; `None` when it has no such key
    /// (or holds the depth FFT). Read by products that apply one key to many layer pairs.
    pub fn key_blocks(&self, family: Family, key: i64) -> Option<&[Option<Vec<C64>>]> {
        self.families
            .iter()
            .find(|(f, _)| *f == family)
            .and_then(|(_, map)| map.get(&key))
            .map(Vec::as_slice)
    }

    /// With the depth FFT and the difference family stored real (its blocks' depth spectra are
    /// real or imaginary, [`LayeredSpectra::new`]): per block, the largest part of the computed
    /// depth spectra dropped by that storage over the largest value kept, the largest over the
    /// blocks (rounding: the 2D spectra's and the depth FFT's). `None` when nothing is stored real.
    pub fn real_storage_discarded(&self) -> Option<f64> {
        self.depth
            .as_ref()
            .and_then(|d| d.real.as_ref())
            .map(|r| r.discarded)
    }

    /// Per-key spectra stored by quarter ([`LayeredSpectra::new`] with every block of a parity in
    /// `m` and `n`, not a contiguous stack): per block, the largest dropped part over the largest
    /// kept value, the largest over the blocks (the 2D FFT's rounding). `None` otherwise.
    pub fn quarter_storage_discarded(&self) -> Option<f64> {
        self.quarters.as_ref().map(|q| q.discarded)
    }

    /// Bytes held by the stored spectra.
    pub fn bytes(&self) -> usize {
        if let Some(d) = &self.depth {
            return d.data.len() * std::mem::size_of::<C64>()
                + d.real.as_ref().map_or(0, |r| r.data.len() * 8);
        }
        if let Some(q) = &self.quarters {
            let per = (self.n1 + 1) * (self.n2 + 1) * 8;
            return q
                .families
                .iter()
                .flat_map(|(_, m)| m.values())
                .flat_map(|blocks| blocks.iter())
                .filter(|b| b.is_some())
                .count()
                * per;
        }
        let per = 2 * self.n1 * (self.n2 + 1) * std::mem::size_of::<C64>();
        self.families
            .iter()
            .flat_map(|(_, m)| m.values())
            .flat_map(|blocks| blocks.iter())
            .filter(|b| b.is_some())
            .count()
            * per
    }

    /// `out_hat[a · n_out + o] += Σ_b Σ_i Σ_F K̂^F_{oi}(key_F(a, b)) · x̂[b · n_in + i]` for every target
    /// `a` and output `o` (in parallel over them). `inputs_hat` holds the spectra of the source fields
    /// ([`Fft2d::forward`]); `skip[b · n_in + i]` marks inputs known to be zero. The products are
    /// **added** to `out_hat`, so several operators can sum into one output
    /// ([`LayeredSpectra::assign_leading`] writes them instead).
    pub fn accumulate(
        &self,
        inputs_hat: &[Vec<C64>],
        skip: &[bool],
        out_hat: &mut [Vec<C64>],
    ) -> Result<(), NumericsError> {
        self.products(inputs_hat, skip, self.n_out, out_hat, false)
    }

    /// [`LayeredSpectra::accumulate`] of the first `outputs` outputs of each target only
    /// (`out_hat[a · outputs + o]`, `o < outputs`): each output's sum is the same, bit for bit, as
    /// in the whole accumulation. Per-key operators only (an operator with the depth FFT accepts
    /// `outputs = n_out`, the whole accumulation).
    pub fn accumulate_leading(
        &self,
        inputs_hat: &[Vec<C64>],
        skip: &[bool],
        outputs: usize,
        out_hat: &mut [Vec<C64>],
    ) -> Result<(), NumericsError> {
        self.products(inputs_hat, skip, outputs, out_hat, false)
    }

    /// `out_hat[a · outputs + o] = Σ_b Σ_i Σ_F K̂^F_{oi}(key_F(a, b)) · x̂[b · n_in + i]`: the products
    /// of [`LayeredSpectra::accumulate_leading`] written over `out_hat` (its values are not read),
    /// bit for bit those of clearing `out_hat` and accumulating (each output's first contribution
    /// is added to zero where it is written, in the chunk being computed): no separate pass
    /// clears the outputs (docs/performance.md, "Overheads of one EIM application and one outer
    /// pass").
    pub fn assign_leading(
        &self,
        inputs_hat: &[Vec<C64>],
        skip: &[bool],
        outputs: usize,
        out_hat: &mut [Vec<C64>],
    ) -> Result<(), NumericsError> {
        self.products(inputs_hat, skip, outputs, out_hat, true)
    }

    /// [`LayeredSpectra::accumulate_leading`] (`write`: [`LayeredSpectra::assign_leading`]).
    fn products(
        &self,
        inputs_hat: &[Vec<C64>],
        skip: &[bool],
        outputs: usize,
        out_hat: &mut [Vec<C64>],
        write: bool,
    ) -> Result<(), NumericsError> {
        let (nt, ns) = (self.targets.len(), self.sources.len());
        if inputs_hat.len() != ns * self.n_in || skip.len() != ns * self.n_in {
            return Err(NumericsError::LengthMismatch {
                what: "layered operator input spectra",
                expected: ns * self.n_in,
                got: inputs_hat.len().min(skip.len()),
            });
        }
        if outputs == 0 || outputs > self.n_out || (self.depth.is_some() && outputs != self.n_out) {
            return Err(NumericsError::InvalidParameter {
                name: "leading outputs of a layered operator",
                value: outputs as f64,
                allowed: "1..=n_out (n_out with the depth FFT)",
            });
        }
        if out_hat.len() != nt * outputs {
            return Err(NumericsError::LengthMismatch {
                what: "layered operator output spectra",
                expected: nt * outputs,
                got: out_hat.len(),
            });
        }
        let len = out_hat.first().map_or(0, |v| v.len());
        if out_hat.iter().any(|v| v.len() != len) {
            return Err(NumericsError::LengthMismatch {
                what: "layered operator output spectra (one length)",
                expected: len,
                got: out_hat
                    .iter()
                    .map(Vec::len)
                    .find(|&l| l != len)
                    .unwrap_or(len),
            });
        }
        let count = out_hat.len();
        // Block over frequencies: every (target, output) of a chunk of frequencies is accumulated
        // while that chunk of every kernel spectrum is in cache, so each stored spectrum is read
        // from memory once per application (instead of once per target).
        if let Some(depth) = &self.depth {
            // One task per in-plane column: its rows r and 2N₁ − r share a stored kernel.
            let column = depth.p1;
            let mut pieces = self.pieces.split(out_hat, column);
            let p = depth.p;
            let scratch = depth
                .fwd
                .get_inplace_scratch_len()
                .max(depth.inv.get_inplace_scratch_len());
            let (n_in, n_out) = (self.n_in, self.n_out);
            let side = || DepthSide {
                x: vec![C64::new(0.0, 0.0); n_in * p],
                xr: vec![C64::new(0.0, 0.0); n_in * p],
                y: vec![C64::new(0.0, 0.0); n_out * p],
            };
            let lanes = depth.part_is_sum.len() * depth.stored_k * n_in;
            let real_lanes = usize::from(depth.real.is_some()) * depth.stored_k * n_in;
            // Work arrays from the operator's pool (allocated at the first application only: a
            // fresh allocation per task costs page faults on every application).
            pieces.par_chunks_mut(count).enumerate().for_each_init(
                || {
                    let buffers = depth.pool.lock().ok().and_then(|mut pool| pool.pop());
                    Pooled {
                        pool: &depth.pool,
                        buffers: Some(buffers.unwrap_or_else(|| DepthBuffers {
                            first: side(),
                            second: side(),
                            lanes: vec![[0.0; 8]; lanes],
                            real_lanes: vec![[0.0; 8]; real_lanes],
                            acc: vec![[0.0; 8]; n_out],
                            column_in: vec![C64::new(0.0, 0.0); inputs_hat.len() * column],
                            column_out: vec![C64::new(0.0, 0.0); count * column],
                            scratch: vec![C64::new(0.0, 0.0); scratch],
                        })),
                    }
                },
                |pooled, (c, outs)| {
                    if let Some(buffers) = pooled.buffers.as_mut() {
                        depth.apply_column(n_out, n_in, c, inputs_hat, skip, outs, write, buffers);
                    }
                },
            );
            self.pieces.keep(pieces);
            return Ok(());
        }
        if len <= SMALL_SPECTRUM {
            // Small plans (an inhomogeneity's window) stay in cache: parallel over outputs.
            out_hat.par_iter_mut().enumerate().for_each(|(ao, acc)| {
                if write {
                    acc.fill(C64::new(0.0, 0.0));
                }
                self.accumulate_one((ao / outputs, ao % outputs), 0, inputs_hat, skip, acc);
            });
            return Ok(());
        }
        let mut pieces = self.pieces.split(out_hat, FREQUENCY_CHUNK);
        pieces
            .par_chunks_mut(count)
            .enumerate()
            .for_each(|(c, outs)| {
                let start = c * FREQUENCY_CHUNK;
                for (ao, acc) in outs.iter_mut().enumerate() {
                    if write {
                        // Cleared where it is accumulated (in cache), not in a pass of its own.
                        acc.fill(C64::new(0.0, 0.0));
                    }
                    self.accumulate_one((ao / outputs, ao % outputs), start, inputs_hat, skip, acc);
                }
            });
        self.pieces.keep(pieces);
        Ok(())
    }
}

/// The per-task pieces of the output spectra of [`LayeredSpectra::accumulate`] (`pieces[c · V + v]`
/// = frequencies `c · len ..` of output `v`, `V` outputs), in vectors whose allocations are kept
/// between applications (they borrow one application's outputs, so they are kept empty: an empty
/// vector's allocation is carried to the next application's lifetime by an in-place collect).
#[derive(Default)]
struct PieceStore {
    /// `(pieces, tails)`: the pieces, and each output's part not yet cut into pieces.
    kept: std::sync::Mutex<(Pieces<'static>, Pieces<'static>)>,
}

/// Borrowed pieces of output spectra.
type Pieces<'a> = Vec<&'a mut [C64]>;

impl PieceStore {
    /// Each output of `out_hat` (all of one length) cut into pieces of `len` values (the last
    /// may be shorter), in the order `pieces[c · V + v]`.
    fn split<'a>(&self, out_hat: &'a mut [Vec<C64>], len: usize) -> Vec<&'a mut [C64]> {
        let (mut pieces, mut tails): (Vec<&'a mut [C64]>, Vec<&'a mut [C64]>) = self
            .kept
            .lock()
            .map(|mut kept| std::mem::take(&mut *kept))
            .unwrap_or_default();
        let total = out_hat.first().map_or(0, Vec::len);
        tails.extend(out_hat.iter_mut().map(Vec::as_mut_slice));
        pieces.reserve(tails.len() * total.div_ceil(len.max(1)));
        for _ in 0..total.div_ceil(len.max(1)) {
            for tail in tails.iter_mut() {
                let cut = len.min(tail.len());
                let (piece, rest) = std::mem::take(tail).split_at_mut(cut);
                pieces.push(piece);
                *tail = rest;
            }
        }
        tails.clear();
        let tails = erase(tails);
        if let Ok(mut kept) = self.kept.lock() {
            kept.1 = tails;
        }
        pieces
    }

    /// Keeps the allocation of `pieces` (emptied) for the next application.
    fn keep(&self, mut pieces: Vec<&mut [C64]>) {
        pieces.clear();
        let empty = erase(pieces);
        if let Ok(mut kept) = self.kept.lock() {
            kept.0 = empty;
        }
    }
}

/// An empty vector of borrowed pieces as one of any lifetime, in the same allocation (the
/// standard library collects a mapped `into_iter` of equal layout in place; nothing is mapped).
fn erase<'a, 'b>(empty: Vec<&'a mut [C64]>) -> Vec<&'b mut [C64]> {
    debug_assert!(empty.is_empty());
    empty
        .into_iter()
        .map(|_| -> &'b mut [C64] { unreachable!("an empty vector") })
        .collect()
}

impl LayeredSpectra {
    /// `acc += Σ_b Σ_i Σ_F K̂^F_{oi} · x̂_{b,i}` over the frequencies `start .. start + acc.len()` of
    /// output `o` of target `a`.
    fn accumulate_one(
        &self,
        (a, o): (usize, usize),
        start: usize,
        inputs_hat: &[Vec<C64>],
        skip: &[bool],
        acc: &mut [C64],
    ) {
        let end = start + acc.len();
        if let Some(q) = &self.quarters {
            let task = QuarterOutput {
                spectra: self,
                quarters: q,
                output: (a, o),
                start,
                inputs_hat,
                skip,
                acc,
            };
            match q.level {
                #[cfg(target_arch = "x86_64")]
                Some(simd) => pulp::Simd::vectorize(simd, task),
                _ => pulp::WithSimd::with_simd(task, pulp::Scalar::new()),
            }
            return;
        }
        for (family, map) in &self.families {
            for (b, &zb) in self.sources.iter().enumerate() {
                let blocks = &map[&family.key(self.targets[a], zb)];
                for i in 0..self.n_in {
                    if skip[b * self.n_in + i] {
                        continue;
                    }
                    if let Some(k) = &blocks[o * self.n_in + i] {
                        multiply_accumulate(
                            acc,
                            &k[start..end],
                            &inputs_hat[b * self.n_in + i][start..end],
                        );
                    }
                }
            }
        }
    }
}

/// One output's per-key products over a chunk of frequencies from spectra stored by quarter
/// ([`LayeredSpectra::accumulate_one`]), compiled for AVX2 where the CPU has it (pulp's V3) and
/// for the baseline (docs/performance.md, "One EIM application on two cores"): the
/// contributions in the order of the complex storage (family, source, input), each
/// [`quarter_accumulate`].
struct QuarterOutput<'a> {
    spectra: &'a LayeredSpectra,
    quarters: &'a Quarters,
    output: (usize, usize),
    start: usize,
    inputs_hat: &'a [Vec<C64>],
    skip: &'a [bool],
    acc: &'a mut [C64],
}

impl pulp::WithSimd for QuarterOutput<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) {
        let QuarterOutput {
            spectra: sp,
            quarters: q,
            output: (a, o),
            start,
            inputs_hat,
            skip,
            acc,
        } = self;
        let end = start + acc.len();
        for (family, map) in &q.families {
            for (b, &zb) in sp.sources.iter().enumerate() {
                let blocks = &map[&family.key(sp.targets[a], zb)];
                for i in 0..sp.n_in {
                    if skip[b * sp.n_in + i] {
                        continue;
                    }
                    if let Some(k) = &blocks[o * sp.n_in + i] {
                        quarter_accumulate(
                            q.level,
                            acc,
                            start,
                            k,
                            &inputs_hat[b * sp.n_in + i][start..end],
                            sp.n1,
                            q.kinds[o * sp.n_in + i],
                        );
                    }
                }
            }
        }
    }
}

/// The spectra of one key: the blocks' tables transformed (`None` = identically zero block).
fn key_spectra(
    fft: &mut Fft2d,
    kernel: &dyn LayerKernel,
    key: i64,
) -> Result<Vec<Option<Vec<C64>>>, NumericsError> {
    let (n1, n2) = fft.shape();
    let tables = tabulate(n1, n2, kernel, key, true);
    let mut blocks = Vec::with_capacity(tables.len());
    for t in tables {
        if t.iter().all(|v| *v == 0.0) {
            blocks.push(None);
        } else {
            let mut s = fft.new_spectrum();
            fft.table_spectrum(&t, &mut s)?;
            blocks.push(Some(s));
        }
    }
    Ok(blocks)
}

/// The same products as [`LayeredSpectra::accumulate`] without storing the kernels: each key's
/// spectra are built, used for every (target, source) pair with that key, and dropped. Memory is
/// one key's blocks instead of all keys' (for one-off evaluations such as the subsurface stress
/// field on many layers); the cost of building the spectra is paid at every call.
pub fn accumulate_streamed(
    fft: &mut Fft2d,
    targets: &[i64],
    sources: &[i64],
    families: &[(Family, &dyn LayerKernel)],
    inputs_hat: &[Vec<C64>],
    skip: &[bool],
    out_hat: &mut [Vec<C64>],
) -> Result<(), NumericsError> {
    let Some((_, first)) = families.first() else {
        return Ok(());
    };
    let (n_out, n_in) = first.blocks();
    let (nt, ns) = (targets.len(), sources.len());
    if inputs_hat.len() != ns * n_in || skip.len() != ns * n_in || out_hat.len() != nt * n_out {
        return Err(NumericsError::LengthMismatch {
            what: "streamed layered operator spectra",
            expected: ns * n_in,
            got: inputs_hat.len(),
        });
    }
    for &(family, kernel) in families {
        let mut keys: Vec<i64> = targets
            .iter()
            .flat_map(|&a| sources.iter().map(move |&b| family.key(a, b)))
            .collect();
        keys.sort_unstable();
        keys.dedup();
        for key in keys {
            let blocks = key_spectra(fft, kernel, key)?;
            out_hat.par_iter_mut().enumerate().for_each(|(ao, acc)| {
                let (a, o) = (ao / n_out, ao % n_out);
                for (b, &zb) in sources.iter().enumerate() {
                    if family.key(targets[a], zb) != key {
                        continue;
                    }
                    for i in 0..n_in {
                        if skip[b * n_in + i] {
                            continue;
                        }
                        if let Some(k) = &blocks[o * n_in + i] {
                            multiply_accumulate(acc, k, &inputs_hat[b * n_in + i]);
                        }
                    }
                }
            });
        }
    }
    Ok(())
}

/// The direct sum of the same layered operator (O((N₁N₂)² N_t N_s)), the control of
/// [`LayeredSpectra`] in tests.
pub struct DenseLayered {
    n1: usize,
    n2: usize,
    n_in: usize,
    n_out: usize,
    targets: Vec<i64>,
    sources: Vec<i64>,
    families: Vec<(Family, TablesByKey)>,
}

impl DenseLayered {
    /// Tabulates the kernels.
    pub fn new(
        n1: usize,
        n2: usize,
        targets: &[i64],
        sources: &[i64],
        families: &[(Family, &dyn LayerKernel)],
    ) -> Self {
        let (n_out, n_in) = families.first().map_or((0, 0), |f| f.1.blocks());
        let families = families
            .iter()
            .map(|&(family, kernel)| {
                let mut map = BTreeMap::new();
                for &a in targets {
                    for &b in sources {
                        let key = family.key(a, b);
                        map.entry(key)
                            .or_insert_with(|| tabulate(n1, n2, kernel, key, false));
                    }
                }
                (family, map)
            })
            .collect();
        Self {
            n1,
            n2,
            n_in,
            n_out,
            targets: targets.to_vec(),
            sources: sources.to_vec(),
            families,
        }
    }

    /// `y[a · n_out + o] = Σ_b Σ_i Σ_F K^F_{oi} * x[b · n_in + i]` by direct summation (unchecked
    /// field counts: see [`GridOperator::apply`]).
    pub fn direct_sum(&self, x: &[&[f64]], y: &mut [&mut [f64]]) {
        let (n1, n2) = (self.n1, self.n2);
        let w = 2 * n2 - 1;
        for (ao, yo) in y.iter_mut().enumerate() {
            let (a, o) = (ao / self.n_out, ao % self.n_out);
            yo.fill(0.0);
            for (family, map) in &self.families {
                for (b, &zb) in self.sources.iter().enumerate() {
                    let tables = &map[&family.key(self.targets[a], zb)];
                    for i in 0..self.n_in {
                        let t = &tables[o * self.n_in + i];
                        let xi = x[b * self.n_in + i];
                        for p in 0..n1 {
                            for q in 0..n2 {
                                let mut s = 0.0;
                                for k in 0..n1 {
                                    let row = (p + n1 - 1 - k) * w + q + n2 - 1;
                                    for l in 0..n2 {
                                        s += t[row - l] * xi[k * n2 + l];
                                    }
                                }
                                yo[p * n2 + q] += s;
                            }
                        }
                    }
                }
            }
        }
    }
}

impl GridOperator for DenseLayered {
    fn shape(&self) -> OperatorShape {
        OperatorShape {
            n1: self.n1,
            n2: self.n2,
            inputs: self.sources.len() * self.n_in,
            outputs: self.targets.len() * self.n_out,
        }
    }

    fn apply(&mut self, x: &[&[f64]], y: &mut [&mut [f64]]) -> Result<(), NumericsError> {
        check_fields(GridOperator::shape(self), x, y)?;
        self.direct_sum(x, y);
        Ok(())
    }
}

/// The layered operator on the fields: `x` (`N_s · n_in` fields, `x[b · n_in + i]`) transformed on a
/// (shared) padded core, [`LayeredSpectra::accumulate`], and the `N_t · n_out` outputs transformed
/// back; inputs that are zero are not transformed. The fast twin of [`DenseLayered`].
pub struct LayeredOperator {
    fft: Fft2d,
    spectra: LayeredSpectra,
    x_hat: Vec<Vec<C64>>,
    skip: Vec<bool>,
    y_hat: Vec<Vec<C64>>,
}

impl LayeredOperator {
    /// Tabulates and transforms the kernels ([`LayeredSpectra::new`]) on the core `fft`.
    pub fn new(
        fft: &Fft2d,
        targets: &[i64],
        sources: &[i64],
        families: &[(Family, &dyn LayerKernel)],
    ) -> Result<Self, NumericsError> {
        let mut fft = fft.clone();
        let spectra = LayeredSpectra::new(&mut fft, targets, sources, families)?;
        let (n_out, n_in) = spectra.blocks();
        let inputs = sources.len() * n_in;
        Ok(Self {
            x_hat: (0..inputs).map(|_| fft.new_spectrum()).collect(),
            skip: vec![false; inputs],
            y_hat: (0..targets.len() * n_out)
                .map(|_| fft.new_spectrum())
                .collect(),
            fft,
            spectra,
        })
    }

    /// The stored spectra.
    pub fn spectra(&self) -> &LayeredSpectra {
        &self.spectra
    }
}

impl GridOperator for LayeredOperator {
    fn shape(&self) -> OperatorShape {
        let (n1, n2) = self.fft.shape();
        OperatorShape {
            n1,
            n2,
            inputs: self.x_hat.len(),
            outputs: self.y_hat.len(),
        }
    }

    fn apply(&mut self, x: &[&[f64]], y: &mut [&mut [f64]]) -> Result<(), NumericsError> {
        check_fields(GridOperator::shape(self), x, y)?;
        for ((xi, hat), sk) in x
            .iter()
            .zip(self.x_hat.iter_mut())
            .zip(self.skip.iter_mut())
        {
            *sk = xi.iter().all(|v| *v == 0.0);
            if !*sk {
                self.fft.forward(xi, hat)?;
            }
        }
        let zero = C64::new(0.0, 0.0);
        self.y_hat.iter_mut().for_each(|s| s.fill(zero));
        self.spectra
            .accumulate(&self.x_hat, &self.skip, &mut self.y_hat)?;
        for (hat, yo) in self.y_hat.iter_mut().zip(y.iter_mut()) {
            self.fft.inverse(hat, yo)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Smooth(f64);
    impl LayerKernel for Smooth {
        fn blocks(&self) -> (usize, usize) {
            (2, 3)
        }
        fn eval(&self, key: i64, m: i64, n: i64, out: &mut [f64]) {
            for (k, v) in out.iter_mut().enumerate() {
                let r2 = (m * m + 2 * n * n + key * key) as f64 + 1.0 + k as f64;
                *v = self.0 * (1.0 + 0.1 * m as f64 + 0.05 * key as f64) / r2.sqrt();
            }
        }
    }

    /// `y = K x` through the stored spectra: forward transforms, products, inverse transforms.
    fn via_spectra(
        fft: &mut Fft2d,
        spectra: &LayeredSpectra,
        xs: &[Vec<f64>],
        skip: &[bool],
        outputs: usize,
    ) -> Vec<Vec<f64>> {
        let (n1, n2) = fft.shape();
        let mut hats: Vec<Vec<C64>> = xs.iter().map(|_| fft.new_spectrum()).collect();
        for (x, h) in xs.iter().zip(hats.iter_mut()) {
            fft.forward(x, h).unwrap();
        }
        let mut out: Vec<Vec<C64>> = (0..outputs).map(|_| fft.new_spectrum()).collect();
        spectra.accumulate(&hats, skip, &mut out).unwrap();
        let mut fields = vec![vec![0.0; n1 * n2]; outputs];
        for (o, f) in out.iter_mut().zip(fields.iter_mut()) {
            fft.inverse(o, f).unwrap();
        }
        fields
    }

    /// `y = K x` by direct summation.
    fn direct(dense: &DenseLayered, xs: &[Vec<f64>], outputs: usize) -> Vec<Vec<f64>> {
        let mut slow = vec![vec![0.0; dense.n1 * dense.n2]; outputs];
        let xr: Vec<&[f64]> = xs.iter().map(|v| v.as_slice()).collect();
        let mut yr: Vec<&mut [f64]> = slow.iter_mut().map(|v| v.as_mut_slice()).collect();
        dense.direct_sum(&xr, &mut yr);
        slow
    }

    /// (max |a − b|, max |b|).
    fn max_error(a: &[Vec<f64>], b: &[Vec<f64>]) -> (f64, f64) {
        let scale = b.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let err = a
            .iter()
            .flatten()
            .zip(b.iter().flatten())
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        (err, scale)
    }

    /// Blocks with every combination of parities: `m^{odd_m} n^{odd_n}` times an even function.
    struct Parity;
    impl LayerKernel for Parity {
        fn blocks(&self) -> (usize, usize) {
            (2, 3)
        }
        fn eval(&self, key: i64, m: i64, n: i64, out: &mut [f64]) {
            for (b, v) in out.iter_mut().enumerate() {
                let (om, on) = (b % 2 == 1, (b / 2) % 2 == 1);
                let r2 = (m * m + 2 * n * n + key * key) as f64 + 1.0 + b as f64;
                let mut w = (1.0 + 0.05 * key as f64) / r2.sqrt();
                if om {
                    w *= m as f64;
                }
                if on {
                    w *= n as f64;
                }
                *v = w;
            }
        }
        fn parity(&self) -> Option<Vec<(bool, bool)>> {
            Some((0..6).map(|b| (b % 2 == 1, (b / 2) % 2 == 1)).collect())
        }
    }

    /// Blocks whose parities factor per output and input (as the strain kernels' do): the depth
    /// products then use the row and depth-frequency symmetries.
    struct Factored;
    impl Factored {
        const OUTS: [(bool, bool); 2] = [(false, false), (true, true)];
        const INS: [(bool, bool); 3] = [(false, false), (true, false), (false, true)];
    }
    impl LayerKernel for Factored {
        fn blocks(&self) -> (usize, usize) {
            (2, 3)
        }
        fn eval(&self, key: i64, m: i64, n: i64, out: &mut [f64]) {
            let par = self.parity().expect("declared");
            for (b, v) in out.iter_mut().enumerate() {
                let r2 = (m * m + 2 * n * n + key * key) as f64 + 1.0 + b as f64;
                let mut w = (1.0 + 0.05 * key as f64) / r2.sqrt();
                if par[b].0 {
                    w *= m as f64;
                }
                if par[b].1 {
                    w *= n as f64;
                }
                *v = w;
            }
        }
        fn parity(&self) -> Option<Vec<(bool, bool)>> {
            Some(
                Self::OUTS
                    .iter()
                    .flat_map(|o| Self::INS.iter().map(move |i| (o.0 ^ i.0, o.1 ^ i.1)))
                    .collect(),
            )
        }
    }

    /// [`Factored`] with blocks also even or odd in the depth key, with parities that factor (as
    /// the strain kernels' do in `x₃ − x₃′`): the difference family is then stored real.
    struct FactoredDepth;
    impl FactoredDepth {
        /// Per output and input: odd in (m, n, key).
        const OUTS: [(bool, bool, bool); 2] = [(false, false, false), (true, true, true)];
        const INS: [(bool, bool, bool); 3] = [
            (false, false, false),
            (true, false, true),
            (false, true, false),
        ];
        fn odd(b: usize) -> (bool, bool, bool) {
            let (o, i) = (Self::OUTS[b / 3], Self::INS[b % 3]);
            (o.0 ^ i.0, o.1 ^ i.1, o.2 ^ i.2)
        }
    }
    impl LayerKernel for FactoredDepth {
        fn blocks(&self) -> (usize, usize) {
            (2, 3)
        }
        fn eval(&self, key: i64, m: i64, n: i64, out: &mut [f64]) {
            for (b, v) in out.iter_mut().enumerate() {
                let r2 = (m * m + 2 * n * n + key * key) as f64 + 1.0 + b as f64;
                // Even in key: key² only; odd: key · (even), exactly antisymmetric.
                let mut w = (1.0 + 0.05 * (key * key) as f64) / r2.sqrt();
                let (om, on, ok) = Self::odd(b);
                if om {
                    w *= m as f64;
                }
                if on {
                    w *= n as f64;
                }
                if ok {
                    w *= key as f64;
                }
                *v = w;
            }
        }
        fn parity(&self) -> Option<Vec<(bool, bool)>> {
            Some(
                (0..6)
                    .map(|b| {
                        let (om, on, _) = Self::odd(b);
                        (om, on)
                    })
                    .collect(),
            )
        }
    }

    #[test]
    fn depth_fft_products_equal_the_direct_sum() {
        // Targets = sources = a contiguous stack: the depth sums go through the depth FFT.
        let (n1, n2) = (6, 5);
        let layers = [5i64, 7, 9, 11];
        let (k1, k2) = (Smooth(1.0), Smooth(-0.4));
        for (case, families) in [
            vec![
                (Family::Difference, &k1 as &dyn LayerKernel),
                (Family::Sum, &k2),
            ],
            vec![(Family::Difference, &k1 as &dyn LayerKernel)],
            vec![(Family::Sum, &k2 as &dyn LayerKernel)],
            // Parities that do not factor: every spectrum stored.
            vec![
                (Family::Difference, &Parity as &dyn LayerKernel),
                (Family::Sum, &Parity),
            ],
            // Factored parities: a quarter stored, the rest by symmetry.
            vec![
                (Family::Difference, &Factored as &dyn LayerKernel),
                (Family::Sum, &Factored),
            ],
            vec![(Family::Sum, &Factored as &dyn LayerKernel)],
            // Depth parities as well: the difference family stored real.
            vec![
                (Family::Difference, &FactoredDepth as &dyn LayerKernel),
                (Family::Sum, &FactoredDepth),
            ],
            vec![(Family::Difference, &FactoredDepth as &dyn LayerKernel)],
        ]
        .into_iter()
        .enumerate()
        {
            // The last two: the difference family stored real.
            let real = case >= 6;
            let mut fft = Fft2d::new(n1, n2).unwrap();
            let spectra = LayeredSpectra::new(&mut fft, &layers, &layers, &families).unwrap();
            let depth = spectra.depth.as_ref().expect("a contiguous stack");
            let factored = families[0]
                .1
                .parity()
                .is_some_and(|p| p[4] == (false, true));
            assert_eq!(depth.symmetry.is_some(), factored);
            assert_eq!(spectra.real_storage_discarded().is_some(), real);
            let dense = DenseLayered::new(n1, n2, &layers, &layers, &families);
            let xs: Vec<Vec<f64>> = (0..layers.len() * 3)
                .map(|k| {
                    (0..n1 * n2)
                        .map(|i| ((i * 7 + k * 5) % 11) as f64 - 5.0)
                        .collect()
                })
                .collect();
            let mut skip = vec![false; xs.len()];
            skip[4] = true; // a zero input, skipped
            let xs: Vec<Vec<f64>> = xs
                .into_iter()
                .enumerate()
                .map(|(k, v)| if skip[k] { vec![0.0; v.len()] } else { v })
                .collect();
            let fast = via_spectra(&mut fft, &spectra, &xs, &skip, layers.len() * 2);
            let slow = direct(&dense, &xs, layers.len() * 2);
            let (err, scale) = max_error(&fast, &slow);
            assert!(err < 1e-12 * scale, "{err:e} of {scale:e}");
        }
    }

    /// The leading outputs alone are the whole accumulation's, bit for bit, on the frequency-chunked
    /// path of large plans (more than `SMALL_SPECTRUM` values) as on the small one; no leading
    /// outputs, more than the operator has, or fewer than all with the depth FFT are refused.
    #[test]
    fn leading_outputs_equal_the_whole_accumulation_bit_for_bit() {
        let (k1, k2) = (Smooth(1.0), Smooth(-0.4));
        let families: [(Family, &dyn LayerKernel); 2] =
            [(Family::Difference, &k1), (Family::Sum, &k2)];
        for (n1, n2) in [(5, 4), (72, 64)] {
            let mut fft = Fft2d::new(n1, n2).unwrap();
            assert_eq!(fft.spectrum_len() > SMALL_SPECTRUM, n1 == 72);
            let (targets, sources) = ([0i64], [3i64, 5]);
            let spectra = LayeredSpectra::new(&mut fft, &targets, &sources, &families).unwrap();
            let hats = random_spectra(&mut fft, sources.len() * 3, 5);
            let skip = vec![false; hats.len()];
            let mut whole: Vec<Vec<C64>> = (0..2).map(|_| fft.new_spectrum()).collect();
            spectra.accumulate(&hats, &skip, &mut whole).unwrap();
            let mut leading = vec![fft.new_spectrum()];
            spectra
                .accumulate_leading(&hats, &skip, 1, &mut leading)
                .unwrap();
            assert_eq!(leading[0], whole[0]);
            for bad in [0, 3] {
                assert!(spectra
                    .accumulate_leading(&hats, &skip, bad, &mut leading)
                    .is_err());
            }
        }
        // A depth-FFT operator: only all outputs.
        let layers = [5i64, 7, 9];
        let mut fft = Fft2d::new(6, 5).unwrap();
        let spectra = LayeredSpectra::new(&mut fft, &layers, &layers, &families).unwrap();
        assert!(spectra.depth.is_some());
        let hats: Vec<Vec<C64>> = (0..9).map(|_| fft.new_spectrum()).collect();
        let mut out: Vec<Vec<C64>> = (0..3).map(|_| fft.new_spectrum()).collect();
        assert!(spectra
            .accumulate_leading(&hats, &[false; 9], 1, &mut out)
            .is_err());
    }

    /// The products written over the outputs ([`LayeredSpectra::assign_leading`], whatever the
    /// outputs held: NaN here) are bit for bit those of clearing the outputs and accumulating, on
    /// the small, the frequency-chunked and the depth-FFT paths, with a zero input skipped; the
    /// output pieces' vectors keep their allocation from one application to the next.
    #[test]
    fn assigned_products_equal_the_cleared_accumulation_bit_for_bit() {
        let (k1, k2) = (Smooth(1.0), Smooth(-0.4));
        let families: [(Family, &dyn LayerKernel); 2] =
            [(Family::Difference, &k1), (Family::Sum, &k2)];
        let factored: [(Family, &dyn LayerKernel); 2] = [
            (Family::Difference, &FactoredDepth),
            (Family::Sum, &FactoredDepth),
        ];
        let stack = [5i64, 7, 9];
        type Case<'a> = (
            usize,
            usize,
            &'a [i64],
            &'a [i64],
            &'a [(Family, &'a dyn LayerKernel)],
        );
        let cases: [Case; 5] = [
            (5, 4, &[0], &[3, 5], &families),
            (72, 64, &[0, 2], &[3, 5], &families),
            (72, 64, &[0], &[3, 5], &[(Family::Difference, &Factored)]),
            (6, 5, &stack, &stack, &families),
            (16, 12, &stack, &stack, &factored),
        ];
        for (n1, n2, targets, sources, families) in cases {
            let mut fft = Fft2d::new(n1, n2).unwrap();
            let spectra = LayeredSpectra::new(&mut fft, targets, sources, families).unwrap();
            let n_in = spectra.blocks().1;
            let hats = random_spectra(&mut fft, sources.len() * n_in, 11);
            let mut skip = vec![false; hats.len()];
            skip[1] = true;
            let outputs = spectra.blocks().0;
            let count = targets.len() * outputs;
            let mut added: Vec<Vec<C64>> = (0..count).map(|_| fft.new_spectrum()).collect();
            spectra
                .accumulate_leading(&hats, &skip, outputs, &mut added)
                .unwrap();
            let nan = C64::new(f64::NAN, f64::NAN);
            let mut written: Vec<Vec<C64>> =
                (0..count).map(|_| vec![nan; added[0].len()]).collect();
            spectra
                .assign_leading(&hats, &skip, outputs, &mut written)
                .unwrap();
            let bits = |v: &[Vec<C64>]| -> Vec<u64> {
                v.iter()
                    .flatten()
                    .flat_map(|c| [c.re.to_bits(), c.im.to_bits()])
                    .collect()
            };
            assert!(added.iter().flatten().any(|v| v.norm() > 0.0));
            assert_eq!(
                bits(&written),
                bits(&added),
                "{n1}×{n2}, {} targets",
                targets.len()
            );
            // Written again over the last result: the same bits, in the kept piece vectors.
            let kept = |s: &LayeredSpectra| {
                let k = s.pieces.kept.lock().unwrap();
                (k.0.as_ptr(), k.0.capacity())
            };
            let before = kept(&spectra);
            spectra
                .assign_leading(&hats, &skip, outputs, &mut written)
                .unwrap();
            assert_eq!(bits(&written), bits(&added));
            if written[0].len() > SMALL_SPECTRUM || spectra.depth.is_some() {
                assert!(before.1 > 0);
                assert_eq!(kept(&spectra), before, "the pieces' allocation is kept");
            }
        }
    }

    /// `count` spectra of fields uniform in [−½, ½) from the seeded generator `seed`.
    fn random_spectra(fft: &mut Fft2d, count: usize, seed: u64) -> Vec<Vec<C64>> {
        let (n1, n2) = fft.shape();
        let mut rng = crate::testkit::Lcg::new(seed);
        (0..count)
            .map(|_| {
                let x: Vec<f64> = (0..n1 * n2).map(|_| rng.unit() - 0.5).collect();
                let mut h = fft.new_spectrum();
                fft.forward(&x, &mut h).unwrap();
                h
            })
            .collect()
    }

    /// The products `acc += k x` of [`real_times_complex`] (the per-key products of spectra
    /// stored by quarter) against a naive control, the complex product `acc[j] += K x[j]` with
    /// `K = ±k` or `±ik` one value at a time, bit for bit (adding a product and its sign are exact
    /// either way), on fixed-seed inputs of every length to 13 (the AVX2 path's four-value blocks
    /// and its tails), reversed or not, negated or not, real or imaginary: on the scalar path on
    /// every host, and on the AVX2 path where the CPU has it (reported when it does not: then the
    /// AVX2 path is not checked here, nor by the level comparisons below).
    #[test]
    fn per_key_products_equal_a_naive_control_on_every_level() {
        let mut levels = vec![("scalar", None)];
        match avx2_level() {
            Some(simd) => levels.push(("AVX2", Some(simd))),
            None => eprintln!(
                "per-key products: this CPU has no AVX2 level (x86-64-v3); only the scalar \
                 path is checked against the naive control"
            ),
        }
        let mut rng = crate::testkit::Lcg::new(20261128);
        let mut value = || rng.unit() - 0.5;
        for len in 0..=13usize {
            let ks: Vec<f64> = (0..len).map(|_| value()).collect();
            let x: Vec<C64> = (0..len).map(|_| C64::new(value(), value())).collect();
            let acc0: Vec<C64> = (0..len).map(|_| C64::new(value(), value())).collect();
            for flags in 0..8u32 {
                let (reversed, negate, imag) = (flags & 1 != 0, flags & 2 != 0, flags & 4 != 0);
                let mut naive = acc0.clone();
                for (j, a) in naive.iter_mut().enumerate() {
                    let k = if reversed { ks[len - 1 - j] } else { ks[j] };
                    let k = if negate { -k } else { k };
                    let kk = if imag {
                        C64::new(0.0, k)
                    } else {
                        C64::new(k, 0.0)
                    };
                    *a += kk * x[j];
                }
                for &(name, level) in &levels {
                    let mut acc = acc0.clone();
                    real_times_complex(level, &mut acc, &ks, (reversed, negate, imag), &x);
                    for (j, (a, b)) in acc.iter().zip(&naive).enumerate() {
                        assert!(
                            a.re.to_bits() == b.re.to_bits() && a.im.to_bits() == b.im.to_bits(),
                            "{name}, length {len}, (reversed, negate, imag) = \
                             {:?}, value {j}: {a} vs {b}",
                            (reversed, negate, imag)
                        );
                    }
                }
            }
        }
    }

    /// The depth products give the same bits on the scalar level as on the CPU's SIMD level
    /// (pulp's dispatch: the same operations in the same order on wider lanes). Reported when
    /// the CPU's level is the scalar one (the comparison then checks nothing).
    #[test]
    fn depth_products_are_the_same_bits_on_every_simd_level() {
        if matches!(pulp::Arch::new(), pulp::Arch::Scalar) {
            eprintln!(
                "depth products: this CPU has no SIMD level above pulp's scalar one; the \
                 comparison of levels checks nothing here"
            );
        }
        let (n1, n2) = (6, 5);
        let layers = [5i64, 7, 9, 11];
        // Complex storage ([`Factored`]) and the difference family stored real
        // ([`FactoredDepth`]).
        let kernels: [&dyn LayerKernel; 2] = [&Factored, &FactoredDepth];
        for kernel in kernels {
            let families: [(Family, &dyn LayerKernel); 2] =
                [(Family::Difference, kernel), (Family::Sum, kernel)];
            let mut fft = Fft2d::new(n1, n2).unwrap();
            let fast = LayeredSpectra::new(&mut fft, &layers, &layers, &families).unwrap();
            let mut scalar = LayeredSpectra::new(&mut fft, &layers, &layers, &families).unwrap();
            scalar.depth.as_mut().expect("a contiguous stack").arch = pulp::Arch::Scalar;
            let hats = random_spectra(&mut fft, layers.len() * 3, 7);
            let skip = vec![false; hats.len()];
            let mut a: Vec<Vec<C64>> = (0..layers.len() * 2).map(|_| fft.new_spectrum()).collect();
            let mut b = a.clone();
            fast.accumulate(&hats, &skip, &mut a).unwrap();
            scalar.accumulate(&hats, &skip, &mut b).unwrap();
            assert!(a.iter().flatten().any(|v| v.norm() > 0.0));
            assert_eq!(a, b);
        }
    }

    /// The difference family stored real gives the complex storage's products to rounding on
    /// seeded random inputs, at half that family's bytes ([`FactoredDepth`], two grids and
    /// stacks). Bound: 1e-14 of the largest output value (≈ 45 ulps); measured 5.9e-17 and
    /// 1.7e-16, and the dropped parts 2.0e-16 and 7.9e-17 of the kept (the FFTs' rounding).
    /// The strain kernels of the EIM (sam) are checked against their dense twin there.
    #[test]
    fn real_difference_spectra_reproduce_the_complex_storage() {
        {
            let kernel = &FactoredDepth;
            for (n1, n2, layers) in [
                (6usize, 5usize, vec![5i64, 7, 9, 11]),
                (16, 12, vec![3, 5, 7]),
            ] {
                let families: [(Family, &dyn LayerKernel); 2] =
                    [(Family::Difference, kernel), (Family::Sum, kernel)];
                let mut fft = Fft2d::new(n1, n2).unwrap();
                let real = LayeredSpectra::new(&mut fft, &layers, &layers, &families).unwrap();
                let complex =
                    LayeredSpectra::build(&mut fft, &layers, &layers, &families, true, false)
                        .unwrap();
                let discarded = real.real_storage_discarded().expect("stored real");
                assert!(discarded < 1e-14, "{discarded:e}");
                assert!(complex.real_storage_discarded().is_none());
                // Sum family complex, difference real: 3/4 of the bytes.
                assert_eq!(4 * real.bytes(), 3 * complex.bytes());
                let hats = random_spectra(&mut fft, layers.len() * 3, 13);
                let mut skip = vec![false; hats.len()];
                skip[1] = true;
                let mut a: Vec<Vec<C64>> =
                    (0..layers.len() * 2).map(|_| fft.new_spectrum()).collect();
                let mut b = a.clone();
                real.accumulate(&hats, &skip, &mut a).unwrap();
                complex.accumulate(&hats, &skip, &mut b).unwrap();
                let scale = b.iter().flatten().fold(0.0f64, |m, v| m.max(v.norm()));
                let err = a
                    .iter()
                    .flatten()
                    .zip(b.iter().flatten())
                    .fold(0.0f64, |m, (x, y)| m.max((x - y).norm()));
                assert!(scale > 0.0);
                assert!(err <= 1e-14 * scale, "{err:e} of {scale:e}");
            }
        }
    }

    /// Per-key spectra stored by quarter (every block of a parity in `m` and `n`, targets ≠
    /// sources) equal the direct sum, and the complex per-key storage (`per_key`) to rounding, on
    /// the small and the frequency-chunked path; the leading outputs alone are the whole
    /// accumulation's bit for bit there too. Bound 1e-14 of the largest output (≈ 45 ulps;
    /// measured ≤ 4.9e-16, dropped parts ≤ 4.8e-16 of the kept).
    #[test]
    fn quarter_stored_spectra_equal_the_direct_sum_and_the_complex_storage() {
        let kernels: [&dyn LayerKernel; 3] = [&Parity, &Factored, &FactoredDepth];
        let (targets, sources) = ([0i64, 3, 5, 9], [3i64, 5, 7]);
        for kernel in kernels {
            let families: [(Family, &dyn LayerKernel); 2] =
                [(Family::Difference, kernel), (Family::Sum, kernel)];
            for (n1, n2) in [(5, 4), (72, 64)] {
                let mut fft = Fft2d::new(n1, n2).unwrap();
                let quarter = LayeredSpectra::new(&mut fft, &targets, &sources, &families).unwrap();
                let complex =
                    LayeredSpectra::per_key(&mut fft, &targets, &sources, &families).unwrap();
                let discarded = quarter.quarter_storage_discarded().expect("by quarter");
                assert!(discarded < 1e-14, "{discarded:e}");
                assert!(complex.quarter_storage_discarded().is_none());
                // (N₁ + 1)(N₂ + 1) reals against 2N₁(N₂ + 1) complex values.
                assert_eq!(quarter.bytes() * 4 * n1, complex.bytes() * (n1 + 1));
                let hats = random_spectra(&mut fft, sources.len() * 3, 17);
                let mut skip = vec![false; hats.len()];
                skip[2] = true;
                let outputs = targets.len() * 2;
                let mut a: Vec<Vec<C64>> = (0..outputs).map(|_| fft.new_spectrum()).collect();
                let mut b = a.clone();
                quarter.accumulate(&hats, &skip, &mut a).unwrap();
                complex.accumulate(&hats, &skip, &mut b).unwrap();
                let scale = b.iter().flatten().fold(0.0f64, |m, v| m.max(v.norm()));
                let err = a
                    .iter()
                    .flatten()
                    .zip(b.iter().flatten())
                    .fold(0.0f64, |m, (x, y)| m.max((x - y).norm()));
                assert!(scale > 0.0 && err <= 1e-14 * scale, "{err:e} of {scale:e}");
                // The same products on the scalar path: the same bits as the AVX2 path (the
                // small and the frequency-chunked path); without AVX2 both are the scalar path
                // (reported by `per_key_products_equal_a_naive_control_on_every_level`).
                assert_eq!(
                    quarter
                        .quarters
                        .as_ref()
                        .expect("by quarter")
                        .level
                        .is_some(),
                    avx2_level().is_some()
                );
                let mut scalar =
                    LayeredSpectra::new(&mut fft, &targets, &sources, &families).unwrap();
                scalar.quarters.as_mut().expect("by quarter").level = None;
                let mut c: Vec<Vec<C64>> = (0..outputs).map(|_| fft.new_spectrum()).collect();
                scalar.accumulate(&hats, &skip, &mut c).unwrap();
                for (x, y) in a.iter().flatten().zip(c.iter().flatten()) {
                    assert_eq!(x.re.to_bits(), y.re.to_bits());
                    assert_eq!(x.im.to_bits(), y.im.to_bits());
                }
                // Leading outputs (one per target) bit for bit.
                let mut lead: Vec<Vec<C64>> =
                    (0..targets.len()).map(|_| fft.new_spectrum()).collect();
                quarter
                    .accumulate_leading(&hats, &skip, 1, &mut lead)
                    .unwrap();
                for (t, l) in lead.iter().enumerate() {
                    assert_eq!(*l, a[t * 2]);
                }
                if n1 == 5 {
                    // Against the direct sum.
                    let dense = DenseLayered::new(n1, n2, &targets, &sources, &families);
                    let mut rng = crate::testkit::Lcg::new(3);
                    let xs: Vec<Vec<f64>> = (0..sources.len() * 3)
                        .map(|_| (0..n1 * n2).map(|_| rng.unit() - 0.5).collect())
                        .collect();
                    let fast = via_spectra(&mut fft, &quarter, &xs, &[false; 9], outputs);
                    let slow = direct(&dense, &xs, outputs);
                    let (err, scale) = max_error(&fast, &slow);
                    assert!(err < 1e-13 * scale, "{err:e} of {scale:e}");
                }
            }
        }
    }

    /// Depth parities factor per output and input when they exist (zero blocks take either);
    /// a pattern with no factorisation is refused.
    #[test]
    fn depth_parities_factor_or_are_refused() {
        let t = Some(true);
        let f = Some(false);
        // odd = u ⊕ v with u = (0, 1), v = (0, 1, 1); block (1, 0) zero.
        let (u, v) = factor_parities(&[f, t, t, None, f, f], 2, 3).expect("factors");
        for o in 0..2 {
            for i in 0..3 {
                if (o, i) != (1, 0) {
                    assert_eq!(
                        u[o] ^ v[i],
                        [false, true, true, true, false, false][o * 3 + i]
                    );
                }
            }
        }
        assert!(factor_parities(&[f, f, f, t], 2, 2).is_none());
    }

    #[test]
    fn layered_dcfft_equals_the_direct_sum() {
        let (n1, n2) = (5, 4);
        let targets = [0i64, 3, 5, 9];
        let sources = [3i64, 5, 7];
        let (k1, k2) = (Smooth(1.0), Smooth(-0.4));
        let families: [(Family, &dyn LayerKernel); 2] =
            [(Family::Difference, &k1), (Family::Sum, &k2)];
        let mut fft = Fft2d::new(n1, n2).unwrap();
        let spectra = LayeredSpectra::new(&mut fft, &targets, &sources, &families).unwrap();
        let dense = DenseLayered::new(n1, n2, &targets, &sources, &families);
        let mut rng = crate::testkit::Lcg::new(11);
        let xs: Vec<Vec<f64>> = (0..sources.len() * 3)
            .map(|_| (0..n1 * n2).map(|_| rng.unit() - 0.5).collect())
            .collect();
        let skip = vec![false; xs.len()];
        // The operator on the fields against its twin (the shared fixed-seed check).
        let mut op = LayeredOperator::new(&fft, &targets, &sources, &families).unwrap();
        let mut twin = DenseLayered::new(n1, n2, &targets, &sources, &families);
        let err = crate::testkit::twin_error(&mut op, &mut twin, &[1, 2]).unwrap();
        assert!(err < 1e-13, "layered operator: {err:e}");
        let fast = via_spectra(&mut fft, &spectra, &xs, &skip, targets.len() * 2);
        let slow = direct(&dense, &xs, targets.len() * 2);
        let (err, scale) = max_error(&fast, &slow);
        let mut hats: Vec<Vec<C64>> = xs.iter().map(|_| fft.new_spectrum()).collect();
        for (x, h) in xs.iter().zip(hats.iter_mut()) {
            fft.forward(x, h).unwrap();
        }
        assert!(err < 1e-13 * scale, "{err:e} of {scale:e}");
        assert!(spectra.bytes() > 0);
        // The streamed products equal the stored ones.
        let mut streamed: Vec<Vec<C64>> =
            (0..targets.len() * 2).map(|_| fft.new_spectrum()).collect();
        accumulate_streamed(
            &mut fft,
            &targets,
            &sources,
            &families,
            &hats,
            &skip,
            &mut streamed,
        )
        .unwrap();
        let mut again = vec![vec![0.0; n1 * n2]; targets.len() * 2];
        for (o, f) in streamed.iter_mut().zip(again.iter_mut()) {
            fft.inverse(o, f).unwrap();
        }
        let (err, scale) = max_error(&again, &slow);
        assert!(err < 1e-13 * scale, "streamed: {err:e} of {scale:e}");
    }
}
