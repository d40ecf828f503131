//! Causal linear convolution with a fixed kernel, `y_i = Σ_{j=0}^{i} x_j b_{i−j}` for
//! `i < m`, where `m = x.len()` may be any length up to the capacity `n` the operator was built
//! for (the first `m` outputs of a causal convolution depend only on the first `m` inputs).
//!
//! Two backends evaluate the *same* sum (design.md: they agree to rounding):
//! * [`Backend::Fft`]: zero-padded to a 5-smooth length `P ≥ 2n − 1` ([`plan_length`]) (docs/theory-mdr.md#p7-fft-details: without the
//!   padding the product is circular), kernel spectrum computed once, `apply` allocation-free;
//!   O(P log P). With [`ToeplitzConvolution::plan_shorter_lengths`] it also plans a ladder of
//!   shorter lengths `P_l = 2c_l` ([`rung_lengths`]: a power of two times 1, 3, 5 or 7) and an
//!   input of length `m ≤ c_l` uses the shortest such plan: the same sum, `O(m log m)` for short inputs. An
//!   even `P` whose plan does not split is transformed as one complex FFT of length `P/2` each
//!   way on the packed samples, the spectrum product fused with the unpacking and packing
//!   (`PackedFft`); from [`SPLIT_FROM`] a plan whose `P` is a multiple of 4 runs its transforms
//!   as two halves that may take two threads (odd `P`: realfft's real transforms).
//! * [`Backend::Mvm`]: the lower-triangular Toeplitz matrix–vector product, O(m²), with four
//!   independent accumulators per row.

use std::sync::Arc;

use realfft::{ComplexToReal, FftNum, RealFftPlanner, RealToComplex};
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

use crate::NumericsError;

/// How a convolution sum is evaluated. Both give the same numbers to rounding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Backend {
    /// O(N log N) zero-padded real FFT.
    Fft,
    /// O(N²) matrix–vector product.
    Mvm,
}

impl Backend {
    /// `"fft"` or `"mvm"`.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Fft => "fft",
            Backend::Mvm => "mvm",
        }
    }
}

/// The floating-point type the FFT backend's transforms run in. Inputs and outputs are `f64`
/// either way (converted where the samples are copied into and out of the transform buffers).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Precision {
    /// `f64` transforms: the sum to `O(ε₆₄ log P)` of `‖x‖ ‖b‖` (the reference).
    Double,
    /// `f32` transforms on a kernel spectrum computed in `f64` and rounded once: the sum to
    /// `O(ε₃₂ log P)` of `‖x‖ ‖b‖` (`ε₃₂ = 2^{−24}`), for products that feed an iteration solved
    /// to a much looser tolerance (docs/performance.md, "The N = 8001 wear run: single-precision
    /// stage products (issue 20)").
    Single,
}

/// The sample type of a plan's transforms (`f64` or `f32`), with the conversions at the
/// boundary of [`ToeplitzConvolution::apply`].
trait Sample: FftNum {
    fn of(v: f64) -> Self;
    fn to_f64(self) -> f64;

    /// [`combine_split_bins`] (the same operations in the same order); a type may run it on
    /// wider registers.
    fn combine_split_bins(
        even: &mut [Complex<Self>],
        odd: &mut [Complex<Self>],
        twiddles: &[Complex<Self>],
        spectrum: &[Complex<Self>],
        half: usize,
        first: usize,
    ) {
        combine_split_bins(even, odd, twiddles, spectrum, half, first);
    }

    /// `freq_k ← freq_k · spectrum_k` (`num_complex`'s product) on the common bins; a type may
    /// run it on wider registers (the same bits).
    fn multiply_spectrum(freq: &mut [Complex<Self>], spectrum: &[Complex<Self>]) {
        for (f, s) in freq.iter_mut().zip(spectrum) {
            *f = *f * *s;
        }
    }

    /// [`fuse_packed_bins`] (the same operations in the same order); a type may run it on wider
    /// registers.
    fn fuse_packed_bins(z: &mut [Complex<Self>], alpha: &[Complex<Self>], beta: &[Complex<Self>]) {
        fuse_packed_bins(z, alpha, beta);
    }
}

impl Sample for f64 {
    fn of(v: f64) -> Self {
        v
    }
    fn to_f64(self) -> f64 {
        self
    }

    /// On x86-64 with AVX2 two bins a register ([`combine_avx::combine_split_bins`], the same
    /// bits), else [`combine_split_bins`].
    fn combine_split_bins(
        even: &mut [Complex<f64>],
        odd: &mut [Complex<f64>],
        twiddles: &[Complex<f64>],
        spectrum: &[Complex<f64>],
        half: usize,
        first: usize,
    ) {
        #[cfg(target_arch = "x86_64")]
        if combine_avx::combine_split_bins(even, odd, twiddles, spectrum, half, first) {
            return;
        }
        combine_split_bins(even, odd, twiddles, spectrum, half, first);
    }

    /// On x86-64 with AVX2 two bins a register ([`combine_avx::multiply_spectrum`], the same
    /// bits), else the scalar product.
    fn multiply_spectrum(freq: &mut [Complex<f64>], spectrum: &[Complex<f64>]) {
        #[cfg(target_arch = "x86_64")]
        if combine_avx::multiply_spectrum(freq, spectrum) {
            return;
        }
        scalar_spectrum_product(freq, spectrum);
    }

    /// On x86-64 with AVX2 two bins a register ([`combine_avx::fuse_packed_bins`], the same
    /// bits), else [`fuse_packed_bins`].
    fn fuse_packed_bins(z: &mut [Complex<f64>], alpha: &[Complex<f64>], beta: &[Complex<f64>]) {
        #[cfg(target_arch = "x86_64")]
        if combine_avx::fuse_packed_bins(z, alpha, beta) {
            return;
        }
        fuse_packed_bins(z, alpha, beta);
    }
}

/// `freq_k ← freq_k · spectrum_k` by `num_complex`'s `Mul` (the reference of the wide product).
#[allow(clippy::assign_op_pattern)] // `Mul`, not `MulAssign`: the reference is the product's expression
fn scalar_spectrum_product(freq: &mut [Complex<f64>], spectrum: &[Complex<f64>]) {
    for (f, s) in freq.iter_mut().zip(spectrum) {
        *f = *f * *s;
    }
}

impl Sample for f32 {
    fn of(v: f64) -> Self {
        v as f32
    }
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
}

/// Smallest `P ≥ min` of the form `2^a 3^b 5^c` (fast for rustfft's mixed-radix algorithms).
pub fn fast_length(min: usize) -> usize {
    let min = min.max(1);
    let mut best = usize::MAX;
    let mut p2 = 1usize;
    while p2 < best {
        let mut p3 = p2;
        while p3 < best {
            let mut p5 = p3;
            while p5 < min {
                p5 *= 5;
            }
            best = best.min(p5);
            p3 *= 3;
        }
        p2 *= 2;
    }
    best
}

/// Padded lengths from which a plan whose length is a multiple of 4 evaluates its real FFTs as
/// two of half the length, on the even and on the odd samples (`SplitFft`): two independent
/// transforms that run on two threads. Below it the hand-offs between threads cost more than
/// they save: at `N = 2001` (`P` of 2048–4050) the split was 9 % slower on one thread and slower
/// still on two (docs/performance.md, "Two threads in the MDR wear run").
pub const SPLIT_FROM: usize = 8192;

/// The padded length of a plan for `P ≥ min`: [`fast_length`]`(min)`, or from [`SPLIT_FROM`] on
/// the smallest multiple of 4 of the form `4 · 2^a 3^b 5^c` (so that the plan splits, `SplitFft`).
pub fn plan_length(min: usize) -> usize {
    let p = fast_length(min);
    if p >= SPLIT_FROM && p % 4 != 0 {
        4 * fast_length(min.div_ceil(4))
    } else {
        p
    }
}

struct FftPlan<T: Sample> {
    /// Longest input (the kernel entries it holds).
    capacity: usize,
    /// The padded length `P`.
    len: usize,
    /// FFT(b) / P: the normalization of the inverse transform is folded in (computed in `f64`,
    /// rounded to `T`).
    spectrum: Vec<Complex<T>>,
    transforms: Transforms<T>,
}

/// How a plan evaluates its real FFTs of length `P`.
enum Transforms<T: Sample> {
    /// One transform of length `P` each way, with its buffers (odd `P`).
    Whole(WholeFft<T>),
    /// Even `P` that does not split (below [`SPLIT_FROM`], or not a multiple of 4 — only
    /// `with_padded_length` gives those): one complex transform of length `P/2` each way on the packed
    /// samples, the spectrum product fused with the real transforms' pre- and post-processing.
    Packed(PackedFft<T>),
    /// Split in halves (padded lengths from [`SPLIT_FROM`], multiples of 4): no length-`P`
    /// transforms or buffers kept.
    Split(SplitFft<T>),
}

/// The real FFTs of an even length `P = 2M` as one complex FFT of length `M` each way, on the
/// packed samples `z_j = x_{2j} + i x_{2j+1}` (the classical two-for-one real transform; e.g.
/// Press et al., *Numerical Recipes*, 3rd ed., "FFT of real functions"), with the unpacking of `Z = DFT_M(z)`, the
/// spectrum product and the packing of the result fused into one pass over the bins:
///
/// `Z'_k = α_k Z_k + β_k conj(Z_{M−k})` (indices mod `M`), `y_{2j} + i y_{2j+1} = IDFT_M(Z')_j`
/// (unnormalized; the `1/P` is in `S`), with `w = e^{−2πi/P}`, `A = S_k`, `B = conj(S_{M−k})`,
///
/// `α_k = [A (1 − i w^k)(1 + i w^{−k}) + B (1 + i w^k)(1 − i w^{−k})]/2`,
/// `β_k = [A (1 + i w^k)(1 + i w^{−k}) + B (1 − i w^k)(1 − i w^{−k})]/2`.
///
/// Derivation: `E_k = (Z_k + conj(Z_{M−k}))/2` and `O_k = (Z_k − conj(Z_{M−k}))/(2i)` are the
/// spectra of the even and odd samples, `X_k = E_k + w^k O_k` and `X_{k+M} = E_k − w^k O_k`
/// (`SplitFft`'s formulas), `Y = X ⊙ S` with `S_{k+M} = conj(S_{M−k})` for the real kernel, and
/// the even and odd outputs are `IDFT_M(Y_k + Y_{k+M})` and `IDFT_M((Y_k − Y_{k+M}) w^{−k})`.
/// Against the length-`P` real transforms (`WholeFft`) this saves the real transforms' own
/// pre- and post-processing passes and the separate product pass (docs/performance.md, "The
/// convolutions as packed complex transforms").
struct PackedFft<T: Sample> {
    /// `M = P/2`.
    half: usize,
    forward: Arc<dyn Fft<T>>,
    inverse: Arc<dyn Fft<T>>,
    /// `α_k`, `β_k`, `k = 0..M` (computed in `f64`, rounded to `T`).
    alpha: Vec<Complex<T>>,
    beta: Vec<Complex<T>>,
    buffer: Vec<Complex<T>>,
    scratch: Vec<Complex<T>>,
}

impl<T: Sample> PackedFft<T> {
    /// The plan of even length `p` for the kernel spectrum `spectrum` (`p/2 + 1` bins of the
    /// length-`p` real transform, `1/p` folded in, in `f64`).
    fn new(p: usize, spectrum: &[Complex<f64>]) -> Self {
        debug_assert!(p % 2 == 0 && spectrum.len() == p / 2 + 1);
        let half = p / 2;
        let mut planner = FftPlanner::<T>::new();
        let forward = planner.plan_fft_forward(half);
        let inverse = planner.plan_fft_inverse(half);
        let scratch_len = forward
            .get_inplace_scratch_len()
            .max(inverse.get_inplace_scratch_len());
        let i = Complex::new(0.0, 1.0);
        let one = Complex::new(1.0, 0.0);
        let (alpha, beta) = (0..half)
            .map(|k| {
                let angle = -2.0 * std::f64::consts::PI * k as f64 / p as f64;
                let w = Complex::new(angle.cos(), angle.sin());
                let (a, b) = (spectrum[k], spectrum[half - k].conj());
                let (minus, plus) = (one - i * w, one + i * w);
                let (minus_c, plus_c) = (one - i * w.conj(), one + i * w.conj());
                let alpha = (a * minus * plus_c + b * plus * minus_c) * 0.5;
                let beta = (a * plus * plus_c + b * minus * minus_c) * 0.5;
                let round = |c: Complex<f64>| Complex::new(T::of(c.re), T::of(c.im));
                (round(alpha), round(beta))
            })
            .unzip();
        Self {
            half,
            forward,
            inverse,
            alpha,
            beta,
            buffer: vec![Complex::new(T::zero(), T::zero()); half],
            scratch: vec![Complex::new(T::zero(), T::zero()); scratch_len],
        }
    }

    /// `y = IDFT_P(DFT_P(x, zero-padded) ⊙ S)[..m]`, `m = x.len() = y.len() ≤ P`.
    fn convolve(&mut self, x: &[f64], y: &mut [f64]) {
        let m = x.len();
        let half = self.half;
        let buffer = &mut self.buffer;
        let mut pairs = x.chunks_exact(2);
        for (z, pair) in buffer.iter_mut().zip(&mut pairs) {
            *z = Complex::new(T::of(pair[0]), T::of(pair[1]));
        }
        let filled = m / 2;
        if let [last] = pairs.remainder() {
            buffer[filled] = Complex::new(T::of(*last), T::zero());
        }
        buffer[m.div_ceil(2)..].fill(Complex::new(T::zero(), T::zero()));
        self.forward.process_with_scratch(buffer, &mut self.scratch);
        T::fuse_packed_bins(buffer, &self.alpha, &self.beta);
        self.inverse.process_with_scratch(buffer, &mut self.scratch);
        let mut out = y.chunks_exact_mut(2);
        for (pair, z) in (&mut out).zip(buffer.iter()) {
            pair[0] = z.re.to_f64();
            pair[1] = z.im.to_f64();
        }
        if let [last] = out.into_remainder() {
            *last = buffer[filled].re.to_f64();
        }
        debug_assert!(m <= 2 * half);
    }
}

/// The fused pass of `PackedFft`, in place: `Z'_k = α_k Z_k + β_k conj(Z_{M−k})` for every bin
/// `k < M` (`M = z.len()`, indices mod `M`), bins `k` and `M − k` together. The reference for the
/// wider version ([`Sample::fuse_packed_bins`]).
fn fuse_packed_bins<T: Sample>(z: &mut [Complex<T>], alpha: &[Complex<T>], beta: &[Complex<T>]) {
    if z.is_empty() {
        return;
    }
    let z0 = z[0];
    z[0] = alpha[0] * z0 + beta[0] * z0.conj();
    fuse_packed_bins_from(z, alpha, beta, 1);
}

/// The pairs `k`, `M − k` of [`fuse_packed_bins`] from `k = first` on, and the middle bin of an
/// even `M` (bin 0 done): the scalar loop, and the wide version's remainder.
fn fuse_packed_bins_from<T: Sample>(
    z: &mut [Complex<T>],
    alpha: &[Complex<T>],
    beta: &[Complex<T>],
    first: usize,
) {
    let half = z.len();
    for k in first..half.div_ceil(2) {
        let (a, b) = (z[k], z[half - k]);
        z[k] = alpha[k] * a + beta[k] * b.conj();
        z[half - k] = alpha[half - k] * b + beta[half - k] * a.conj();
    }
    if half % 2 == 0 {
        let k = half / 2;
        let a = z[k];
        z[k] = alpha[k] * a + beta[k] * a.conj();
    }
}

/// The length-`P` real FFTs of a plan that does not split, and their buffers.
struct WholeFft<T: Sample> {
    forward: Arc<dyn RealToComplex<T>>,
    inverse: Arc<dyn ComplexToReal<T>>,
    time: Vec<T>,
    freq: Vec<Complex<T>>,
    scratch: Vec<Complex<T>>,
}

/// The real FFTs of length `P = 2M` (`M` even) of a plan as two of length `M`, one on the even
/// and one on the odd samples (radix-2 decimation in time; Cooley & Tukey 1965):
///
/// `X_k = E_k + w^k O_k`, `X_{M−k} = conj(E_k − w^k O_k)`, `k = 0..=M/2`, `w = e^{−2πi/P}`,
///
/// and for the inverse of `Y = X ⊙ S` (decimation in frequency)
///
/// `Ŷ^e_k = Y_k + conj(Y_{M−k})`, `Ŷ^o_k = (Y_k − conj(Y_{M−k})) w^{−k}`, `y_{2j} = IDFT_M(Ŷ^e)_j`,
/// `y_{2j+1} = IDFT_M(Ŷ^o)_j`
///
/// (`Y_{k+M} = conj(Y_{M−k})` for a real `y`). The two halves of each transform are independent:
/// they run on two threads of the pool (`rayon::join`) when called on a worker of a pool of two or
/// more (docs/performance.md, "Two threads in the MDR wear run"); the arithmetic is the same on
/// one thread, so the result is the same bit for bit on any number of threads.
struct SplitFft<T: Sample> {
    /// `M = P/2`.
    half: usize,
    forward: Arc<dyn RealToComplex<T>>,
    inverse: Arc<dyn ComplexToReal<T>>,
    /// `w^k`, `k = 0..=M/2` (computed in `f64`, rounded to `T`).
    twiddles: Vec<Complex<T>>,
    /// The even samples' lane and the odd samples'.
    lanes: [SplitLane<T>; 2],
}

/// One half of a `SplitFft`: its samples, their spectrum and the scratch of its transforms.
struct SplitLane<T: Sample> {
    time: Vec<T>,
    freq: Vec<Complex<T>>,
    scratch: Vec<Complex<T>>,
}

impl<T: Sample> SplitFft<T> {
    fn new(p: usize, planner: &mut RealFftPlanner<T>) -> Self {
        debug_assert!(p % 4 == 0);
        let half = p / 2;
        let forward = planner.plan_fft_forward(half);
        let inverse = planner.plan_fft_inverse(half);
        let scratch_len = forward.get_scratch_len().max(inverse.get_scratch_len());
        let lane = || SplitLane {
            time: vec![T::zero(); half],
            freq: forward.make_output_vec(),
            scratch: vec![Complex::new(T::zero(), T::zero()); scratch_len],
        };
        let lanes = [lane(), lane()];
        let twiddles = (0..=half / 2)
            .map(|k| {
                if 4 * k == p {
                    // w^{P/4} = −i exactly.
                    Complex::new(T::zero(), -T::one())
                } else {
                    let angle = -2.0 * std::f64::consts::PI * k as f64 / p as f64;
                    Complex::new(T::of(angle.cos()), T::of(angle.sin()))
                }
            })
            .collect();
        Self {
            half,
            forward,
            inverse,
            twiddles,
            lanes,
        }
    }

    /// `y = IDFT_P(DFT_P(x, zero-padded) ⊙ spectrum)[..m]` (`spectrum` the `P/2 + 1` bins of a
    /// real signal's transform, the normalization folded in), `m = x.len() = y.len()`.
    fn convolve(&mut self, spectrum: &[Complex<T>], x: &[f64], y: &mut [f64]) {
        let half = self.half;
        let [even, odd] = &mut self.lanes;
        let (forward, inverse) = (&self.forward, &self.inverse);
        join_if_on_pool(
            || even.forward(forward, x, 0),
            || odd.forward(forward, x, 1),
        );
        // Both spectra become the halves' spectra of Y = X ⊙ S, in place (bin k reads and writes
        // bin k only), the bins in two halves (on two threads as the transforms are).
        let mid = even.freq.len() / 2;
        let (even_low, even_high) = even.freq.split_at_mut(mid);
        let (odd_low, odd_high) = odd.freq.split_at_mut(mid);
        let (twiddles_low, twiddles_high) = self.twiddles.split_at(mid);
        join_if_on_pool(
            || T::combine_split_bins(even_low, odd_low, twiddles_low, spectrum, half, 0),
            || T::combine_split_bins(even_high, odd_high, twiddles_high, spectrum, half, mid),
        );
        // Real DC and Nyquist bins of the halves' real signals: clear the rounding there so the
        // inverse transforms accept them.
        for lane in [&mut *even, &mut *odd] {
            let last = lane.freq.len() - 1;
            lane.freq[0].im = T::zero();
            lane.freq[last].im = T::zero();
        }
        join_if_on_pool(|| even.inverse(inverse), || odd.inverse(inverse));
        let m = y.len();
        debug_assert!(m <= 2 * half);
        let mut pairs = y.chunks_exact_mut(2);
        for ((pair, e), o) in (&mut pairs).zip(&even.time).zip(&odd.time) {
            pair[0] = e.to_f64();
            pair[1] = o.to_f64();
        }
        if let [last] = pairs.into_remainder() {
            *last = even.time[m / 2].to_f64();
        }
    }
}

/// The spectrum product of [`SplitFft::convolve`] on the halves' bins, in place: with the even
/// and odd samples' spectra `E_k`, `O_k` (`k = 0..=M/2`),
///
/// `t = w^k O_k`, `X_k = E_k + t`, `X_{M−k} = conj(E_k − t)`, `Y_k = X_k S_k`,
/// `Y_{M−k} = X_{M−k} S_{M−k}`, then `E_k ← Y_k + conj(Y_{M−k})`,
/// `O_k ← (Y_k − conj(Y_{M−k})) conj(w^k)`
///
/// (`SplitFft`'s formulas; bin `k` reads and writes bin `k` only), on the bins
/// `k = first..first + even.len()` (`even`, `odd` and `twiddles` start at bin `first`). The
/// reference for the wider versions ([`Sample::combine_split_bins`]), which must give its bits.
fn combine_split_bins<T: Sample>(
    even: &mut [Complex<T>],
    odd: &mut [Complex<T>],
    twiddles: &[Complex<T>],
    spectrum: &[Complex<T>],
    half: usize,
    first: usize,
) {
    for (i, ((e, o), w)) in even
        .iter_mut()
        .zip(odd.iter_mut())
        .zip(twiddles)
        .enumerate()
    {
        let k = first + i;
        let t = *w * *o;
        let xk = *e + t;
        let xmk = (*e - t).conj();
        let yk = xk * spectrum[k];
        let ymk = (xmk * spectrum[half - k]).conj();
        *e = yk + ymk;
        *o = (yk - ymk) * w.conj();
    }
}

/// [`combine_split_bins`] on AVX2 registers, two bins a register, for `f64`.
#[cfg(target_arch = "x86_64")]
mod combine_avx {
    use core::arch::x86_64::__m256d;

    use pulp::x86::V3;
    use pulp::Simd;
    use rustfft::num_complex::Complex;

    /// [`super::combine_split_bins`] for `f64` with the same operations in the same order on each
    /// bin — a complex product as `num_complex`'s, `(a.re b.re − a.im b.im, a.re b.im + a.im b.re)`,
    /// from two vector products and one `addsub` (no fused multiply-add), a conjugate as a sign
    /// flip — so the same bits. `false` (nothing done) when the CPU has no AVX2/FMA level (pulp's
    /// `V3`).
    pub(super) fn combine_split_bins(
        even: &mut [Complex<f64>],
        odd: &mut [Complex<f64>],
        twiddles: &[Complex<f64>],
        spectrum: &[Complex<f64>],
        half: usize,
        first: usize,
    ) -> bool {
        let Some(simd) = V3::try_new() else {
            return false;
        };
        Simd::vectorize(
            simd,
            Combine {
                simd,
                even,
                odd,
                twiddles,
                spectrum,
                half,
                first,
            },
        );
        true
    }

    /// `freq_k ← freq_k · spectrum_k` with `num_complex`'s operations on each bin
    /// (`(a.re b.re − a.im b.im, a.re b.im + a.im b.re)`: two vector products and one `addsub`, no
    /// fused multiply-add), two bins a register: the scalar loop's bits. `false` (nothing done)
    /// without AVX2/FMA (pulp's `V3`).
    pub(super) fn multiply_spectrum(freq: &mut [Complex<f64>], spectrum: &[Complex<f64>]) -> bool {
        let Some(simd) = V3::try_new() else {
            return false;
        };
        Simd::vectorize(
            simd,
            Multiply {
                simd,
                freq,
                spectrum,
            },
        );
        true
    }

    /// [`super::fuse_packed_bins`] for `f64`, bins `k, k + 1` and `M − k, M − k − 1` two a
    /// register, with the same operations in the same order on each bin (products as
    /// `num_complex`'s, no fused multiply-add; a conjugate as a sign flip): the same bits. `false`
    /// (nothing done) without AVX2/FMA (pulp's `V3`).
    pub(super) fn fuse_packed_bins(
        z: &mut [Complex<f64>],
        alpha: &[Complex<f64>],
        beta: &[Complex<f64>],
    ) -> bool {
        let Some(simd) = V3::try_new() else {
            return false;
        };
        Simd::vectorize(
            simd,
            Fuse {
                simd,
                z,
                alpha,
                beta,
            },
        );
        true
    }

    struct Fuse<'a> {
        simd: V3,
        z: &'a mut [Complex<f64>],
        alpha: &'a [Complex<f64>],
        beta: &'a [Complex<f64>],
    }

    impl pulp::WithSimd for Fuse<'_> {
        type Output = ();

        #[inline(always)]
        fn with_simd<S: Simd>(self, _: S) {
            let Self {
                simd,
                z,
                alpha,
                beta,
            } = self;
            let half = z.len();
            if half == 0 || alpha.len() < half || beta.len() < half {
                super::fuse_packed_bins(z, alpha, beta);
                return;
            }
            let avx = simd.avx;
            // (c_{j}, c_{j+1}) → (c_{j+1}, c_j).
            let swap = |v: __m256d| avx._mm256_permute2f128_pd::<0x01>(v, v);
            let conj = |v: __m256d| conjugate(simd, v);
            let mul = |a: __m256d, b: __m256d| product(simd, a, b);
            let z0 = z[0];
            z[0] = alpha[0] * z0 + beta[0] * z0.conj();
            // Bins k, k + 1 (forward) with M − k, M − k − 1 (backward, loaded swapped), while the
            // two ranges do not meet: k + 1 < M − k − 1.
            let mut k = 1;
            while 2 * k + 2 < half {
                let j = half - k - 1;
                let a = load(&z[k..k + 2]);
                let b = swap(load(&z[j..j + 2]));
                let alpha_f = load(&alpha[k..k + 2]);
                let beta_f = load(&beta[k..k + 2]);
                let alpha_b = swap(load(&alpha[j..j + 2]));
                let beta_b = swap(load(&beta[j..j + 2]));
                let forward = avx._mm256_add_pd(mul(alpha_f, a), mul(beta_f, conj(b)));
                let backward = avx._mm256_add_pd(mul(alpha_b, b), mul(beta_b, conj(a)));
                store(&mut z[k..k + 2], forward);
                store(&mut z[j..j + 2], swap(backward));
                k += 2;
            }
            // The bins left between (the scalar loop's operations on each).
            super::fuse_packed_bins_from(z, alpha, beta, k);
        }
    }

    /// Bins `c[0]`, `c[1]` as one register `[re, im, re, im]`.
    #[inline(always)]
    fn load(c: &[Complex<f64>]) -> __m256d {
        pulp::cast([c[0].re, c[0].im, c[1].re, c[1].im])
    }

    /// A register `[re, im, re, im]` into bins `c[0]`, `c[1]`.
    #[inline(always)]
    fn store(c: &mut [Complex<f64>], v: __m256d) {
        let [a, b, d, e]: [f64; 4] = pulp::cast(v);
        c[0] = Complex::new(a, b);
        c[1] = Complex::new(d, e);
    }

    /// The conjugates of both bins of a register (a sign flip of the imaginary parts).
    #[inline(always)]
    fn conjugate(simd: V3, v: __m256d) -> __m256d {
        let sign: __m256d = pulp::cast([0.0f64, -0.0, 0.0, -0.0]);
        simd.avx._mm256_xor_pd(v, sign)
    }

    /// Two complex products `a · b` (bins `[re, im, re, im]`) with `num_complex`'s operations,
    /// `(a.re b.re − a.im b.im, a.re b.im + a.im b.re)`: two vector products and one `addsub`,
    /// no fused multiply-add — the scalar product's bits.
    #[inline(always)]
    fn product(simd: V3, a: __m256d, b: __m256d) -> __m256d {
        let avx = simd.avx;
        let re = avx._mm256_movedup_pd(a);
        let im = avx._mm256_permute_pd::<0b1111>(a);
        let swapped = avx._mm256_permute_pd::<0b0101>(b);
        avx._mm256_addsub_pd(avx._mm256_mul_pd(re, b), avx._mm256_mul_pd(im, swapped))
    }

    struct Multiply<'a> {
        simd: V3,
        freq: &'a mut [Complex<f64>],
        spectrum: &'a [Complex<f64>],
    }

    impl pulp::WithSimd for Multiply<'_> {
        type Output = ();

        #[inline(always)]
        fn with_simd<S: Simd>(self, _: S) {
            let Self {
                simd,
                freq,
                spectrum,
            } = self;
            let bins = freq.len().min(spectrum.len());
            let (freq, spectrum) = (&mut freq[..bins], &spectrum[..bins]);
            let mut f_pairs = freq.chunks_exact_mut(2);
            let mut s_pairs = spectrum.chunks_exact(2);
            for (f, s) in (&mut f_pairs).zip(&mut s_pairs) {
                let a: __m256d = pulp::cast([f[0].re, f[0].im, f[1].re, f[1].im]);
                let b: __m256d = pulp::cast([s[0].re, s[0].im, s[1].re, s[1].im]);
                let v = product(simd, a, b);
                let [p, q, r, t]: [f64; 4] = pulp::cast(v);
                f[0] = Complex::new(p, q);
                f[1] = Complex::new(r, t);
            }
            super::scalar_spectrum_product(f_pairs.into_remainder(), s_pairs.remainder());
        }
    }

    struct Combine<'a> {
        simd: V3,
        even: &'a mut [Complex<f64>],
        odd: &'a mut [Complex<f64>],
        twiddles: &'a [Complex<f64>],
        spectrum: &'a [Complex<f64>],
        half: usize,
        first: usize,
    }

    impl pulp::WithSimd for Combine<'_> {
        type Output = ();

        #[inline(always)]
        fn with_simd<S: Simd>(self, _: S) {
            let Self {
                simd,
                even,
                odd,
                twiddles,
                spectrum,
                half,
                first,
            } = self;
            let avx = simd.avx;
            let bins = even.len().min(odd.len()).min(twiddles.len());
            let pairs = bins / 2;
            let conj = |v: __m256d| conjugate(simd, v);
            let mul = |a: __m256d, b: __m256d| product(simd, a, b);
            for p in 0..pairs {
                // Local bin i, global bin k.
                let (i, k) = (2 * p, first + 2 * p);
                let e = load(&even[i..i + 2]);
                let o = load(&odd[i..i + 2]);
                let w = load(&twiddles[i..i + 2]);
                let forward = load(&spectrum[k..k + 2]);
                // (S_{M−k−1}, S_{M−k}) with its two bins swapped: (S_{M−k}, S_{M−k−1}).
                let backward = load(&spectrum[half - k - 1..half - k + 1]);
                let backward = avx._mm256_permute2f128_pd::<0x01>(backward, backward);
                let t = mul(w, o);
                let xk = avx._mm256_add_pd(e, t);
                let xmk = conj(avx._mm256_sub_pd(e, t));
                let yk = mul(xk, forward);
                let ymk = conj(mul(xmk, backward));
                store(&mut even[i..i + 2], avx._mm256_add_pd(yk, ymk));
                store(&mut odd[i..i + 2], mul(avx._mm256_sub_pd(yk, ymk), conj(w)));
            }
            // An odd last bin: the scalar loop's operations on it.
            let done = 2 * pairs;
            super::combine_split_bins(
                &mut even[done..bins],
                &mut odd[done..bins],
                &twiddles[done..bins],
                spectrum,
                half,
                first + done,
            );
        }
    }
}

impl<T: Sample> SplitLane<T> {
    /// The spectrum of the samples `x_{2j + parity}` (zero beyond `x`).
    fn forward(&mut self, plan: &Arc<dyn RealToComplex<T>>, x: &[f64], parity: usize) {
        // x_{2j + parity}, j < ⌈(m − parity)/2⌉.
        let filled = (x.len() + 1 - parity) / 2;
        let mut pairs = x.chunks_exact(2);
        for (t, pair) in self.time.iter_mut().zip(&mut pairs) {
            *t = T::of(pair[parity]);
        }
        if let [last] = pairs.remainder() {
            if parity == 0 {
                self.time[x.len() / 2] = T::of(*last);
            }
        }
        self.time[filled..].fill(T::zero());
        plan.process_with_scratch(&mut self.time, &mut self.freq, &mut self.scratch)
            .expect("buffer lengths come from the plan");
    }

    /// The samples of the spectrum `freq` (unnormalized inverse), into `time`.
    fn inverse(&mut self, plan: &Arc<dyn ComplexToReal<T>>) {
        plan.process_with_scratch(&mut self.freq, &mut self.time, &mut self.scratch)
            .expect("buffer lengths come from the plan");
    }
}

/// `(a(), b())`, on two threads (`rayon::join`) when called on a worker of a pool of two or more,
/// else one after the other on the calling thread (a join from outside the pool would hand both
/// to the pool and wait: a wake-up per call). The same results either way.
fn join_if_on_pool(a: impl FnOnce() + Send, b: impl FnOnce() + Send) {
    if rayon::current_thread_index().is_some() && rayon::current_num_threads() > 1 {
        rayon::join(a, b);
    } else {
        a();
        b();
    }
}

enum Engine {
    /// The plans by increasing length; the last one takes the whole capacity.
    Fft(Vec<FftPlan<f64>>),
    Mvm,
}

/// Shortest capacity `c_l` of a rung of [`ToeplitzConvolution::plan_shorter_lengths`]; below it
/// one FFT costs little more than the copies around it.
const SHORTEST_RUNG: usize = 256;

/// The padded lengths of the rungs of [`ToeplitzConvolution::plan_shorter_lengths`] in
/// `[from, below)`: `P = 2^a s` with `s ∈ {1, 3, 5, 7}` and `a ≥ 2`, increasing. Consecutive
/// lengths are at most 5/4 apart (`4 → 5 → 6 → 7 → 8` times a power of two), and a length of this
/// form from [`SPLIT_FROM`] on is a multiple of 4, so it splits like [`plan_length`]'s.
pub fn rung_lengths(from: usize, below: usize) -> Vec<usize> {
    let mut lengths = Vec::new();
    let mut power = 4usize;
    while power < below {
        for s in [1, 3, 5, 7] {
            match power.checked_mul(s) {
                Some(p) if (from..below).contains(&p) => lengths.push(p),
                _ => {}
            }
        }
        match power.checked_mul(2) {
            Some(next) => power = next,
            None => break,
        }
    }
    // `s` is odd, so no length repeats.
    lengths.sort_unstable();
    lengths
}

/// Causal linear convolution with a fixed kernel `b_0 … b_{n−1}` (see the module docs).
/// Built once (plans and kernel spectrum); [`ToeplitzConvolution::apply`] does not allocate.
pub struct ToeplitzConvolution {
    kernel: Vec<f64>,
    engine: Engine,
    /// The FFT plans' twins with `f32` transforms (the same lengths), once
    /// [`ToeplitzConvolution::set_precision`] asked for them.
    single: Option<Vec<FftPlan<f32>>>,
    /// The precision [`ToeplitzConvolution::apply`] takes.
    precision: Precision,
}

impl ToeplitzConvolution {
    /// Builds the operator for the kernel `b` (its length is the capacity).
    pub fn new(kernel: Vec<f64>, backend: Backend) -> Result<Self, NumericsError> {
        if kernel.is_empty() {
            return Err(NumericsError::TooFewNodes {
                what: "a convolution kernel",
                min: 1,
                n: 0,
            });
        }
        if let Some(&bad) = kernel.iter().find(|v| !v.is_finite()) {
            return Err(NumericsError::InvalidParameter {
                name: "convolution kernel entry",
                value: bad,
                allowed: "finite",
            });
        }
        let engine = match backend {
            Backend::Mvm => Engine::Mvm,
            Backend::Fft => {
                let p = plan_length(2 * kernel.len() - 1);
                Engine::Fft(vec![FftPlan::new(&kernel, p)])
            }
        };
        Ok(Self {
            kernel,
            engine,
            single: None,
            precision: Precision::Double,
        })
    }

    /// The operator of [`ToeplitzConvolution::new`] with the FFT backend zero-padded to the given
    /// length `2n − 1 ≤ p ≤ 4(2n − 1)` (`n = kernel.len()`) instead of [`plan_length`]`(2n − 1)`:
    /// the same sum to rounding (split from [`SPLIT_FROM`] when `p` is a multiple of 4; at
    /// `p = plan_length(2n − 1)` the operator of `new`, bit for bit). For measuring the cost of a
    /// length (the bench `conv_lengths`). A length outside that range is an error.
    pub fn with_padded_length(kernel: Vec<f64>, p: usize) -> Result<Self, NumericsError> {
        let mut op = Self::new(kernel, Backend::Mvm)?;
        // n ≥ 1 (new refuses an empty kernel); 4(2n − 1) does not overflow (n values are held).
        let shortest = 2 * op.kernel.len() - 1;
        if p < shortest || p > 4 * shortest {
            return Err(NumericsError::InvalidParameter {
                name: "padded FFT length",
                value: p as f64,
                allowed: "from 2n − 1 to 4(2n − 1), n the kernel length",
            });
        }
        op.engine = Engine::Fft(vec![FftPlan::new(&op.kernel, p)]);
        op.single = None;
        Ok(op)
    }

    /// Largest input length accepted.
    pub fn capacity(&self) -> usize {
        self.kernel.len()
    }

    /// The kernel `b`.
    pub fn kernel(&self) -> &[f64] {
        &self.kernel
    }

    /// Which backend evaluates the sum.
    pub fn backend(&self) -> Backend {
        match self.engine {
            Engine::Fft(_) => Backend::Fft,
            Engine::Mvm => Backend::Mvm,
        }
    }

    /// The precision [`ToeplitzConvolution::apply`] takes (`Double` unless set).
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// Selects the precision of the FFT backend's transforms for the following applications (no
    /// effect with the MVM backend). The first request for [`Precision::Single`] plans twins of
    /// the FFT plans (the same padded lengths and capacities, the ladder of
    /// [`ToeplitzConvolution::plan_shorter_lengths`] included, split from [`SPLIT_FROM`] alike)
    /// with `f32` transforms on the `f64` kernel spectrum rounded once; later switches allocate
    /// nothing. [`Precision::Double`] is the operator of `new`, bit for bit. Single precision
    /// evaluates the same sum to `O(ε₃₂ log P) ‖x‖₂ ‖b‖₂` in the worst case (`ε₃₂ = 2^{−24}`;
    /// Higham 2002, "Accuracy and Stability of Numerical Algorithms", chapter 24): about `10⁻⁷` of
    /// the outputs' largest for the kernels of the MDR transforms (docs/performance.md, "The
    /// N = 8001 wear run: single-precision stage products (issue 20)").
    pub fn set_precision(&mut self, precision: Precision) {
        if matches!(self.engine, Engine::Mvm) {
            return;
        }
        if precision == Precision::Single && self.single.is_none() {
            self.single = Some(build_plans(&self.kernel, &self.shapes()));
        }
        self.precision = precision;
    }

    /// `(capacity, P)` of the FFT plans, by increasing length (empty for the MVM backend).
    fn shapes(&self) -> Vec<(usize, usize)> {
        match &self.engine {
            Engine::Fft(plans) => plans.iter().map(|p| (p.capacity, p.len)).collect(),
            Engine::Mvm => Vec::new(),
        }
    }

    /// Padded FFT length of a full-capacity input (`None` for the MVM backend).
    pub fn padded_length(&self) -> Option<usize> {
        self.padded_length_for(self.capacity())
    }

    /// Padded FFT length used for an input of length `m ≤ capacity` (`None` for the MVM backend).
    pub fn padded_length_for(&self, m: usize) -> Option<usize> {
        match &self.engine {
            Engine::Fft(plans) => plans
                .iter()
                .find(|plan| plan.capacity >= m)
                .map(|plan| plan.len),
            Engine::Mvm => None,
        }
    }

    /// Adds FFT plans for shorter inputs (no effect with the MVM backend): a rung for every
    /// length `P_l` of [`rung_lengths`] (a power of two times 1, 3, 5 or 7, split from
    /// [`SPLIT_FROM`] on) with `256 ≤ P_l/2 < n` below the full-capacity plan's length, holding the kernel
    /// `b_0 … b_{c_l−1}`, `c_l = P_l/2` (for inputs of length `m ≤ c_l` the outputs `i < m` need
    /// no more, and `P_l ≥ m + c_l − 1` keeps the product linear). An input of length `m` then
    /// uses the shortest plan with `c_l ≥ m`: the same sum, in `O(m log m)`; the result differs
    /// from the full-length plan's by rounding only. For callers whose inputs are much shorter
    /// than the capacity (the implicit wear steps' Jacobian on the contact nodes,
    /// docs/fretting-wear.md, "Time integration"). The rungs take the plans' precision.
    ///
    /// The lengths are the fast ones of the convolution's cost per length (bench
    /// `conv_lengths`; docs/performance.md, "The rungs of the shorter plans"): one odd factor
    /// at most, so that rustfft's radix-2/4/8 passes do most of the work; consecutive rungs
    /// are at most 5/4 apart.
    pub fn plan_shorter_lengths(&mut self) {
        let shapes = self.shapes();
        if shapes.len() != 1 {
            return;
        }
        let longest = shapes[0].1;
        let mut rungs: Vec<(usize, usize)> = rung_lengths(2 * SHORTEST_RUNG, longest)
            .into_iter()
            .filter(|&p| p / 2 < self.kernel.len())
            .map(|p| (p / 2, p))
            .collect();
        rungs.sort_unstable();
        if let Engine::Fft(plans) = &mut self.engine {
            let mut longer = std::mem::take(plans);
            *plans = build_plans(&self.kernel, &rungs);
            plans.append(&mut longer);
        }
        if self.single.is_some() {
            self.single = Some(build_plans(&self.kernel, &self.shapes()));
        }
    }

    /// `y_i = Σ_{j=0}^{i} x_j b_{i−j}`, `i = 0..m−1`, with `m = x.len() = y.len() ≤ capacity`.
    pub fn apply(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), NumericsError> {
        let m = x.len();
        if y.len() != m {
            return Err(NumericsError::LengthMismatch {
                what: "convolution output",
                expected: m,
                got: y.len(),
            });
        }
        if m > self.kernel.len() {
            return Err(NumericsError::LengthMismatch {
                what: "convolution input (at most the capacity)",
                expected: self.kernel.len(),
                got: m,
            });
        }
        match &mut self.engine {
            Engine::Mvm => toeplitz_lower_mvm(&self.kernel, x, y),
            Engine::Fft(plans) => match (&mut self.single, self.precision) {
                (Some(single), Precision::Single) => shortest_fitting(single, m).apply(x, y),
                _ => shortest_fitting(plans, m).apply(x, y),
            },
        }
        Ok(())
    }
}

/// The plans of the given `(capacity, P)` for the kernel (each holds `b_0 … b_{capacity−1}`).
fn build_plans<T: Sample>(kernel: &[f64], shapes: &[(usize, usize)]) -> Vec<FftPlan<T>> {
    shapes
        .iter()
        .map(|&(capacity, p)| FftPlan::new(&kernel[..capacity], p))
        .collect()
}

/// The shortest plan that takes an input of length `m`.
fn shortest_fitting<T: Sample>(plans: &mut [FftPlan<T>], m: usize) -> &mut FftPlan<T> {
    plans
        .iter_mut()
        .find(|plan| plan.capacity >= m)
        .expect("the last plan takes the whole capacity")
}

impl<T: Sample> FftPlan<T> {
    /// The plan of length `p ≥ 2 kernel.len() − 1` for inputs up to `kernel.len()`. The kernel's
    /// spectrum comes from one length-`p` transform in `f64` (rounded to `T` once), planned here
    /// and dropped; the plan's own transforms are planned in `T`.
    fn new(kernel: &[f64], p: usize) -> Self {
        let n = kernel.len();
        debug_assert!(p + 1 >= 2 * n);
        let spectrum64: Vec<Complex<f64>> = {
            let forward = RealFftPlanner::<f64>::new().plan_fft_forward(p);
            let mut time = vec![0.0; p];
            time[..n].copy_from_slice(kernel);
            let mut spectrum = forward.make_output_vec();
            let mut scratch = vec![Complex::new(0.0, 0.0); forward.get_scratch_len()];
            forward
                .process_with_scratch(&mut time, &mut spectrum, &mut scratch)
                .expect("buffer lengths come from the plan");
            let scale = 1.0 / p as f64;
            spectrum.iter().map(|s| *s * scale).collect()
        };
        let split = p >= SPLIT_FROM && p % 4 == 0;
        let packed = !split && p % 2 == 0;
        // The packed plans hold their own coefficients instead of the spectrum.
        let spectrum = if packed {
            Vec::new()
        } else {
            spectrum64
                .iter()
                .map(|s| Complex::new(T::of(s.re), T::of(s.im)))
                .collect()
        };
        let mut planner = RealFftPlanner::<T>::new();
        let transforms = if split {
            Transforms::Split(SplitFft::new(p, &mut planner))
        } else if packed {
            Transforms::Packed(PackedFft::new(p, &spectrum64))
        } else {
            let forward = planner.plan_fft_forward(p);
            let inverse = planner.plan_fft_inverse(p);
            let scratch_len = inverse.get_scratch_len().max(forward.get_scratch_len());
            Transforms::Whole(WholeFft {
                freq: forward.make_output_vec(),
                time: vec![T::zero(); p],
                scratch: vec![Complex::new(T::zero(), T::zero()); scratch_len],
                forward,
                inverse,
            })
        };
        Self {
            capacity: n,
            len: p,
            spectrum,
            transforms,
        }
    }

    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        match &mut self.transforms {
            Transforms::Split(split) => split.convolve(&self.spectrum, x, y),
            Transforms::Packed(packed) => packed.convolve(x, y),
            Transforms::Whole(whole) => whole.convolve(&self.spectrum, x, y),
        }
    }
}

impl<T: Sample> WholeFft<T> {
    /// `y = IDFT_P(DFT_P(x, zero-padded) ⊙ spectrum)[..m]`, `m = x.len() = y.len()`.
    fn convolve(&mut self, spectrum: &[Complex<T>], x: &[f64], y: &mut [f64]) {
        let m = x.len();
        for (t, v) in self.time.iter_mut().zip(x) {
            *t = T::of(*v);
        }
        self.time[m..].fill(T::zero());
        self.forward
            .process_with_scratch(&mut self.time, &mut self.freq, &mut self.scratch)
            .expect("buffer lengths come from the plan");
        T::multiply_spectrum(&mut self.freq, spectrum);
        // The spectrum of a real signal has real DC (and Nyquist) bins; clear the rounding noise
        // there so the inverse transform accepts it.
        self.freq[0].im = T::zero();
        if self.time.len() % 2 == 0 {
            let last = self.freq.len() - 1;
            self.freq[last].im = T::zero();
        }
        self.inverse
            .process_with_scratch(&mut self.freq, &mut self.time, &mut self.scratch)
            .expect("buffer lengths come from the plan");
        for (v, t) in y.iter_mut().zip(&self.time) {
            *v = t.to_f64();
        }
    }
}

/// `y_i = Σ_{j≤i} x_j b_{i−j}`: the lower-triangular Toeplitz product, O(m²).
fn toeplitz_lower_mvm(b: &[f64], x: &[f64], y: &mut [f64]) {
    for (i, yi) in y.iter_mut().enumerate() {
        // Σ_{j=0}^{i} x_j b_{i-j}: pair x[0..=i] with b[0..=i] reversed.
        let xs = &x[..=i];
        let bs = &b[..=i];
        let mut acc = [0.0f64; 4];
        let chunks = xs.len() / 4;
        for c in 0..chunks {
            let j = 4 * c;
            acc[0] += xs[j] * bs[i - j];
            acc[1] += xs[j + 1] * bs[i - j - 1];
            acc[2] += xs[j + 2] * bs[i - j - 2];
            acc[3] += xs[j + 3] * bs[i - j - 3];
        }
        let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
        for j in 4 * chunks..=i {
            s += xs[j] * bs[i - j];
        }
        *yi = s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testkit::lcg;

    /// The obviously-correct control: the defining double loop.
    fn naive(b: &[f64], x: &[f64]) -> Vec<f64> {
        (0..x.len())
            .map(|i| (0..=i).map(|j| x[j] * b[i - j]).sum())
            .collect()
    }

    /// The whole plans' spectrum product on AVX2 registers ([`Sample::multiply_spectrum`] for
    /// `f64`) gives `num_complex`'s product's bits, bin for bin, on random bins (fixed seeds) of
    /// even and odd counts, with extreme magnitudes among them.
    #[test]
    fn wide_whole_spectrum_product_gives_the_scalar_bits() {
        let complex = |seed: u64, n: usize| -> Vec<Complex<f64>> {
            let v = lcg(seed, 2 * n);
            v.chunks(2).map(|c| Complex::new(c[0], c[1])).collect()
        };
        for bins in [1usize, 2, 3, 8, 129, 2026, 2049] {
            let mut freq = complex(bins as u64, bins);
            let mut spectrum = complex(7 + bins as u64, bins);
            freq[0] = Complex::new(1e300, -1e-300);
            spectrum[bins - 1] = Complex::new(-3e-310, 2e200);
            #[cfg(target_arch = "x86_64")]
            if pulp::x86::V3::try_new().is_some() {
                // The wide path runs on this CPU (else the comparison is scalar against scalar).
                let mut f = freq.clone();
                assert!(combine_avx::multiply_spectrum(&mut f, &spectrum));
            }
            let mut wide = freq.clone();
            <f64 as Sample>::multiply_spectrum(&mut wide, &spectrum);
            for (k, ((w, f), s)) in wide.iter().zip(&freq).zip(&spectrum).enumerate() {
                let scalar = *f * *s;
                assert_eq!(
                    (w.re.to_bits(), w.im.to_bits()),
                    (scalar.re.to_bits(), scalar.im.to_bits()),
                    "{bins} bins, bin {k}"
                );
            }
        }
    }

    /// The packed plans' fused pass on AVX2 registers ([`Sample::fuse_packed_bins`] for `f64`)
    /// gives the bin-at-a-time loop's bits ([`fuse_packed_bins`]) on random bins (fixed seeds),
    /// for even and odd `M` from 1 up, with extreme magnitudes among them.
    #[test]
    fn wide_fused_packed_bins_give_the_scalar_bits() {
        let complex = |seed: u64, n: usize| -> Vec<Complex<f64>> {
            let v = lcg(seed, 2 * n);
            v.chunks(2).map(|c| Complex::new(c[0], c[1])).collect()
        };
        for half in (1usize..=12).chain([63, 64, 1600, 2025]) {
            let mut z = complex(half as u64, half);
            let alpha = complex(3 + half as u64, half);
            let beta = complex(5 + half as u64, half);
            z[half - 1] = Complex::new(1e300, -3e-310);
            #[cfg(target_arch = "x86_64")]
            if pulp::x86::V3::try_new().is_some() {
                // The wide path runs on this CPU (else the comparison is scalar against scalar).
                let mut w = z.clone();
                assert!(combine_avx::fuse_packed_bins(&mut w, &alpha, &beta));
            }
            let mut wide = z.clone();
            <f64 as Sample>::fuse_packed_bins(&mut wide, &alpha, &beta);
            let mut scalar = z.clone();
            fuse_packed_bins(&mut scalar, &alpha, &beta);
            let bits = |v: &[Complex<f64>]| -> Vec<(u64, u64)> {
                v.iter().map(|c| (c.re.to_bits(), c.im.to_bits())).collect()
            };
            assert_eq!(bits(&wide), bits(&scalar), "M = {half}");
            // And the pass is the formula: Z'_k = α_k Z_k + β_k conj(Z_{M−k}).
            for k in 0..half {
                let want = alpha[k] * z[k] + beta[k] * z[(half - k) % half].conj();
                assert_eq!(
                    (scalar[k].re.to_bits(), scalar[k].im.to_bits()),
                    (want.re.to_bits(), want.im.to_bits()),
                    "M = {half}, bin {k}"
                );
            }
        }
    }

    /// The spectrum product on AVX2 registers ([`Sample::combine_split_bins`] for `f64`) gives
    /// the bin-at-a-time loop's bits ([`combine_split_bins`]), on random bins (fixed seeds) with
    /// an even and an odd number of bins, the split plans' twiddles, and both ends of `half`; in
    /// one call and in two parts split at an odd bin.
    #[test]
    fn wide_spectrum_product_gives_the_scalar_bits() {
        for half in [2usize, 4, 6, 10, 16, 250, 4096, 8100] {
            let bins = half / 2 + 1;
            let complex = |seed: u64, n: usize| -> Vec<Complex<f64>> {
                let v = lcg(seed, 2 * n);
                v.chunks(2).map(|c| Complex::new(c[0], c[1])).collect()
            };
            let spectrum = complex(half as u64, half + 1);
            let (even, odd) = (complex(1, bins), complex(2, bins));
            let twiddles: Vec<Complex<f64>> = (0..bins)
                .map(|k| {
                    let angle = -std::f64::consts::PI * k as f64 / half as f64;
                    Complex::new(angle.cos(), angle.sin())
                })
                .collect();
            #[cfg(target_arch = "x86_64")]
            if pulp::x86::V3::try_new().is_some() {
                // The wide path runs on this CPU (else the comparison below is scalar against
                // scalar).
                let (mut e, mut o) = (even.clone(), odd.clone());
                assert!(combine_avx::combine_split_bins(
                    &mut e, &mut o, &twiddles, &spectrum, half, 0
                ));
            }
            let (mut e_wide, mut o_wide) = (even.clone(), odd.clone());
            <f64 as Sample>::combine_split_bins(
                &mut e_wide,
                &mut o_wide,
                &twiddles,
                &spectrum,
                half,
                0,
            );
            let (mut e_ref, mut o_ref) = (even.clone(), odd.clone());
            combine_split_bins(&mut e_ref, &mut o_ref, &twiddles, &spectrum, half, 0);
            // In two parts from an odd bin (as `SplitFft::convolve` splits them, at any bin).
            let (mut e_parts, mut o_parts) = (even.clone(), odd.clone());
            let mid = (bins / 2) | 1;
            let (e_low, e_high) = e_parts.split_at_mut(mid);
            let (o_low, o_high) = o_parts.split_at_mut(mid);
            <f64 as Sample>::combine_split_bins(e_low, o_low, &twiddles, &spectrum, half, 0);
            <f64 as Sample>::combine_split_bins(
                e_high,
                o_high,
                &twiddles[mid..],
                &spectrum,
                half,
                mid,
            );
            let bits = |v: &[Complex<f64>]| -> Vec<(u64, u64)> {
                v.iter().map(|c| (c.re.to_bits(), c.im.to_bits())).collect()
            };
            assert_eq!(bits(&e_wide), bits(&e_ref), "half {half}: even bins");
            assert_eq!(bits(&o_wide), bits(&o_ref), "half {half}: odd bins");
            assert_eq!(
                bits(&e_parts),
                bits(&e_ref),
                "half {half}: even bins in parts"
            );
            assert_eq!(
                bits(&o_parts),
                bits(&o_ref),
                "half {half}: odd bins in parts"
            );
            assert_ne!(bits(&e_ref), bits(&even), "half {half}: nothing computed");
        }
    }

    #[test]
    fn fast_length_is_five_smooth_and_minimal() {
        assert_eq!(fast_length(1), 1);
        assert_eq!(fast_length(7), 8);
        assert_eq!(fast_length(4001), 4050);
        assert_eq!(fast_length(17), 18);
        for min in 1..2000 {
            let p = fast_length(min);
            assert!(p >= min);
            let mut q = p;
            for f in [2, 3, 5] {
                while q % f == 0 {
                    q /= f;
                }
            }
            assert_eq!(q, 1, "{p} is not 5-smooth");
        }
    }

    #[test]
    fn both_backends_match_the_naive_sum_with_fixed_seeds() {
        for (seed, n) in [(1u64, 1usize), (2, 2), (3, 7), (4, 64), (5, 257), (6, 1000)] {
            let b = lcg(seed, n);
            let x = lcg(seed + 100, n);
            let want = naive(&b, &x);
            let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1.0);
            for backend in [Backend::Fft, Backend::Mvm] {
                let mut op = ToeplitzConvolution::new(b.clone(), backend).unwrap();
                let mut y = vec![0.0; n];
                op.apply(&x, &mut y).unwrap();
                for i in 0..n {
                    assert!(
                        (y[i] - want[i]).abs() <= 1e-13 * scale * (n as f64).sqrt(),
                        "{backend:?} n={n} i={i}: {} vs {}",
                        y[i],
                        want[i]
                    );
                }
                // A shorter input reuses the same plan: the first m outputs are unchanged.
                let m = n / 2 + 1;
                let mut ys = vec![0.0; m];
                op.apply(&x[..m], &mut ys).unwrap();
                for i in 0..m {
                    assert!((ys[i] - want[i]).abs() <= 1e-13 * scale * (n as f64).sqrt());
                }
            }
        }
    }

    /// The ladder of shorter plans: every 37th input length from 1 to the capacity and the rungs'
    /// boundaries against the naive sum (fixed seeds), the shortest plan that fits is used, and a
    /// full-length input gives the full plan's bits.
    #[test]
    fn shorter_plans_match_the_naive_sum() {
        let n = 1500;
        let b = lcg(7, n);
        let x = lcg(8, n);
        let mut full = ToeplitzConvolution::new(b.clone(), Backend::Fft).unwrap();
        let mut ladder = ToeplitzConvolution::new(b.clone(), Backend::Fft).unwrap();
        ladder.plan_shorter_lengths();
        assert_eq!(ladder.padded_length(), full.padded_length());
        // n = 1500 (P = 3000): rungs P = 512, 640, 768, 896, 1024, …, 2048, 2560, capacity P/2.
        assert_eq!(ladder.padded_length_for(1), Some(512));
        assert_eq!(ladder.padded_length_for(256), Some(512));
        assert_eq!(ladder.padded_length_for(257), Some(640));
        assert_eq!(ladder.padded_length_for(1025), Some(2560));
        assert_eq!(ladder.padded_length_for(1280), Some(2560));
        assert_eq!(ladder.padded_length_for(1281), Some(3000));
        let want = naive(&b, &x);
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1.0);
        for m in (1..=n)
            .step_by(37)
            .chain([255, 256, 257, 300, 320, 321, 1279, 1280, 1281, n])
        {
            let p = ladder.padded_length_for(m).unwrap();
            assert!(p + 1 >= 2 * m, "m = {m}: P = {p}");
            let mut y = vec![0.0; m];
            ladder.apply(&x[..m], &mut y).unwrap();
            for i in 0..m {
                assert!(
                    (y[i] - want[i]).abs() <= 1e-13 * scale * (n as f64).sqrt(),
                    "m = {m}, P = {p}, i = {i}: {} vs {}",
                    y[i],
                    want[i]
                );
            }
        }
        let (mut y_full, mut y_ladder) = (vec![0.0; n], vec![0.0; n]);
        full.apply(&x, &mut y_full).unwrap();
        ladder.apply(&x, &mut y_ladder).unwrap();
        assert!(y_full
            .iter()
            .zip(&y_ladder)
            .all(|(a, c)| a.to_bits() == c.to_bits()));
    }

    /// The rungs' lengths: `2^a s` with `s ∈ {1, 3, 5, 7}`, increasing, at most 5/4 apart, every
    /// one of that form in the range (against a brute-force list), multiples of 4 (so those from
    /// [`SPLIT_FROM`] on split).
    #[test]
    fn rung_lengths_are_powers_of_two_times_one_small_odd_factor() {
        let lengths = rung_lengths(512, 40_000);
        let brute: Vec<usize> = (512usize..40_000)
            .filter(|&p| {
                let odd = p >> p.trailing_zeros();
                p % 4 == 0 && [1, 3, 5, 7].contains(&odd)
            })
            .collect();
        assert_eq!(lengths, brute);
        assert!(lengths.iter().all(|p| p % 4 == 0));
        assert_eq!(&lengths[..6], &[512, 640, 768, 896, 1024, 1280]);
        // No overflow near the top of `usize`.
        let top = rung_lengths(usize::MAX / 2, usize::MAX);
        assert!(!top.is_empty() && top.windows(2).all(|w| w[0] < w[1]));
        for pair in lengths.windows(2) {
            assert!(pair[0] < pair[1] && 4 * pair[1] <= 5 * pair[0], "{pair:?}");
        }
        assert!(rung_lengths(600, 600).is_empty());
    }

    /// The plans from [`SPLIT_FROM`] on are split (a multiple of 4): every input length of a
    /// ladder against the naive sum (fixed seeds), and the same bits on a pool of one thread, on a
    /// worker of a pool of two (inside `install` `on_pool_with_partner` runs inline, no partner:
    /// the halves joined with `rayon::join`, the other worker stealing one), from a thread outside
    /// any pool through `on_pool_with_partner` (the work handed to a worker of the global pool,
    /// a partner polling, when that pool has two or more threads) and on a plain thread outside
    /// any pool (the halves one after the other).
    #[test]
    fn split_plans_match_the_naive_sum_on_any_number_of_threads() {
        for min in [SPLIT_FROM, 8193, 10001, 12001, 16001] {
            let p = plan_length(min);
            assert!(p >= min && p % 4 == 0, "{min}: {p}");
            assert!(p <= fast_length(min.div_ceil(4)) * 4);
        }
        assert_eq!(plan_length(4001), fast_length(4001));
        let n = 6000;
        {
            let mut op = ToeplitzConvolution::new(lcg(17, n), Backend::Fft).unwrap();
            op.plan_shorter_lengths();
            assert_eq!(op.padded_length_for(4096), Some(8192));
            assert_eq!(op.padded_length_for(4097), Some(10_240));
            assert_eq!(op.padded_length_for(5121), op.padded_length());
        }
        let b = lcg(17, n);
        let x = lcg(18, n);
        let want = naive(&b, &x);
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1.0);
        let (b, x) = (&b, &x);
        for precision in [Precision::Double, Precision::Single] {
            // `Some(t)`: inside a pool of `t` threads; `Some(0)`: from a spawned thread through the
            // global pool; `None`: on this thread, no pool involved.
            let run = |threads: Option<usize>| -> Vec<Vec<f64>> {
                let mut op = ToeplitzConvolution::new(b.clone(), Backend::Fft).unwrap();
                op.plan_shorter_lengths();
                op.set_precision(precision);
                let mut go = move || {
                    // The split rungs 8192 (capacity 4096) and 10 240 (5120) and their
                    // boundaries, the packed ones below.
                    [n, n - 1, 5121, 5120, 5001, 4800, 4097, 4096, 3000, 700]
                        .iter()
                        .map(|&m| {
                            let mut y = vec![0.0; m];
                            op.apply(&x[..m], &mut y).unwrap();
                            y
                        })
                        .collect::<Vec<_>>()
                };
                match threads {
                    None => go(),
                    Some(0) => std::thread::scope(|s| {
                        s.spawn(|| crate::parallel::on_pool_with_partner(go))
                            .join()
                            .unwrap()
                    }),
                    Some(t) => rayon::ThreadPoolBuilder::new()
                        .num_threads(t)
                        .build()
                        .unwrap()
                        .install(|| crate::parallel::on_pool_with_partner(go)),
                }
            };
            let one = run(Some(1));
            // Single precision: the bound of `single_precision_matches_double_and_the_naive_sum`
            // taken entrywise (‖·‖∞ ≤ ‖·‖₂).
            let bound = match precision {
                Precision::Double => 1e-13 * scale * (n as f64).sqrt(),
                Precision::Single => single_bound(&b[..], &x[..], 2 * n),
            };
            for y in &one {
                for (i, (a, w)) in y.iter().zip(&want).enumerate() {
                    assert!(
                        (a - w).abs() <= bound,
                        "{precision:?}, m = {}, i = {i}: {a} vs {w}",
                        y.len()
                    );
                }
            }
            for other in [run(Some(2)), run(Some(0)), run(None)] {
                for (a, c) in one.iter().zip(&other) {
                    assert!(a.iter().zip(c).all(|(u, v)| u.to_bits() == v.to_bits()));
                }
            }
        }
    }

    /// `ε₃₂ log₂ P ‖x‖₂ ‖b‖₁`, `ε₃₂ = 2^{−24}`: the normwise bound of an FFT convolution in single
    /// precision, `‖ŷ − y‖₂ ≲ c ε log₂ P ‖x‖₂ ‖b‖₁` (the transforms' error `O(ε log₂ P)` of
    /// `‖X‖₂ = √P ‖x‖₂`, Higham 2002, "Accuracy and Stability of Numerical Algorithms", Theorem 24.2;
    /// the spectrum `|B_k| ≤ ‖b‖₁`; the inverse divides by `√P`), with `c = 1`.
    fn single_bound(b: &[f64], x: &[f64], p: usize) -> f64 {
        let x2 = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        let b1 = b.iter().map(|v| v.abs()).sum::<f64>();
        f64::from(f32::EPSILON) * 0.5 * (p as f64).log2() * x2 * b1
    }

    /// Single-precision plans ([`ToeplitzConvolution::set_precision`]) against the `f64` plans
    /// and the naive sum (fixed seeds, `N = 121 … 8001`, the ladder of shorter plans and the split
    /// lengths included): within [`single_bound`] in the 2-norm (measured: at most 0.042 of it;
    /// relative to `‖y‖₂` at most 2.1e-7), and not the `f64` result
    /// (the `f32` path is taken: the difference is above `f64` rounding). Switching back to
    /// `Double` gives the `f64` plans' bits.
    #[test]
    fn single_precision_matches_double_and_the_naive_sum() {
        let mut worst_ratio = 0.0f64;
        let mut worst_relative = 0.0f64;
        for (seed, n) in [
            (41u64, 121usize),
            (42, 1000),
            (43, 2001),
            (44, 4097),
            (45, 8001),
        ] {
            let x = lcg(seed + 100, n);
            // A seeded kernel and the two kernels of the MDR transforms (γ = 1/2): the cells'
            // weights (m + 1)^γ − m^γ and the power sum's increments m^γ − (m − 1)^γ.
            let kernels = [
                lcg(seed, n),
                (0..n)
                    .map(|m| ((m + 1) as f64).sqrt() - (m as f64).sqrt())
                    .collect::<Vec<_>>(),
                (0..n)
                    .map(|m| {
                        if m == 0 {
                            0.0
                        } else {
                            (m as f64).sqrt() - ((m - 1) as f64).sqrt()
                        }
                    })
                    .collect(),
            ];
            for b in kernels {
                let want = naive(&b, &x);
                let mut double = ToeplitzConvolution::new(b.clone(), Backend::Fft).unwrap();
                double.plan_shorter_lengths();
                let mut single = ToeplitzConvolution::new(b.clone(), Backend::Fft).unwrap();
                single.plan_shorter_lengths();
                single.set_precision(Precision::Single);
                assert_eq!(single.precision(), Precision::Single);
                for m in [n, n / 2 + 1, (n / 5).max(1)] {
                    let (mut y64, mut y32) = (vec![0.0; m], vec![0.0; m]);
                    double.apply(&x[..m], &mut y64).unwrap();
                    single.apply(&x[..m], &mut y32).unwrap();
                    let p = single.padded_length_for(m).unwrap();
                    let bound = single_bound(&b[..m], &x[..m], p);
                    let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
                    let diff = |u: &[f64], v: &[f64]| {
                        u.iter()
                            .zip(v)
                            .map(|(a, c)| (a - c) * (a - c))
                            .sum::<f64>()
                            .sqrt()
                    };
                    let to_naive = diff(&y32, &want[..m]);
                    let to_double = diff(&y32, &y64);
                    assert!(
                        to_naive <= bound,
                        "n = {n}, m = {m}: {to_naive:e} > {bound:e}"
                    );
                    assert!(
                        to_double <= bound,
                        "n = {n}, m = {m}: {to_double:e} > {bound:e}"
                    );
                    assert!(
                        to_double > 1e-12 * norm(&y64),
                        "n = {n}, m = {m}: the f32 plans were not used"
                    );
                    worst_ratio = worst_ratio.max(to_naive / bound);
                    worst_relative = worst_relative.max(to_naive / norm(&want[..m]));
                }
                single.set_precision(Precision::Double);
                let (mut y64, mut back) = (vec![0.0; n], vec![0.0; n]);
                double.apply(&x, &mut y64).unwrap();
                single.apply(&x, &mut back).unwrap();
                assert!(y64
                    .iter()
                    .zip(&back)
                    .all(|(a, c)| a.to_bits() == c.to_bits()));
            }
        }
        eprintln!("f32 plans: ‖y − naive‖₂ at most {worst_ratio:.3} of the bound, {worst_relative:.2e} of ‖y‖₂");
        // The MVM backend has no f32 path.
        let mut mvm = ToeplitzConvolution::new(vec![1.0; 4], Backend::Mvm).unwrap();
        mvm.set_precision(Precision::Single);
        assert_eq!(mvm.precision(), Precision::Double);
    }

    #[test]
    fn bad_lengths_and_kernels_are_errors() {
        let mut op = ToeplitzConvolution::new(vec![1.0; 4], Backend::Fft).unwrap();
        let mut y = vec![0.0; 5];
        assert!(op.apply(&[1.0; 5], &mut y).is_err());
        let mut y = vec![0.0; 3];
        assert!(op.apply(&[1.0; 2], &mut y).is_err());
        assert!(ToeplitzConvolution::new(vec![], Backend::Mvm).is_err());
        assert!(ToeplitzConvolution::new(vec![1.0, f64::NAN], Backend::Fft).is_err());
        assert!(ToeplitzConvolution::with_padded_length(vec![1.0; 4], 6).is_err());
        assert!(ToeplitzConvolution::with_padded_length(vec![1.0; 4], 29).is_err());
        assert!(ToeplitzConvolution::with_padded_length(vec![1.0; 4], usize::MAX).is_err());
        assert!(ToeplitzConvolution::with_padded_length(vec![1.0; 4], 28).is_ok());
        let mut padded = ToeplitzConvolution::with_padded_length(vec![1.0; 4], 7).unwrap();
        assert_eq!(padded.padded_length(), Some(7));
        let mut y = vec![0.0; 4];
        padded.apply(&[1.0, 2.0, 3.0, 4.0], &mut y).unwrap();
        for (a, b) in y.iter().zip([1.0, 3.0, 6.0, 10.0]) {
            assert!((a - b).abs() < 1e-13, "{a} vs {b}");
        }
        // A split length (8192 = plan_length(2 · 4096 − 1)): new's operator bit for bit, and
        // the naive sum to rounding at another split length.
        let (b, x) = (lcg(31, 4096), lcg(32, 4096));
        let want = naive(&b, &x);
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1.0);
        let mut plain = ToeplitzConvolution::new(b.clone(), Backend::Fft).unwrap();
        assert_eq!(plain.padded_length(), Some(8192));
        let mut y_plain = vec![0.0; 4096];
        plain.apply(&x, &mut y_plain).unwrap();
        for p in [8192, 8640] {
            let mut op = ToeplitzConvolution::with_padded_length(b.clone(), p).unwrap();
            let mut y = vec![0.0; 4096];
            op.apply(&x, &mut y).unwrap();
            for (a, w) in y.iter().zip(&want) {
                assert!((a - w).abs() <= 1e-13 * scale * 64.0, "P = {p}: {a} vs {w}");
            }
            if p == 8192 {
                assert!(y
                    .iter()
                    .zip(&y_plain)
                    .all(|(a, c)| a.to_bits() == c.to_bits()));
            }
        }
    }
}
