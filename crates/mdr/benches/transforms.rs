//! Profile (Eq. 7) and stress (Eq. 17) transforms, apply only (planned beforehand), FFT vs MVM,
//! and the FFT apply against a bare realfft convolution of the same padded length.
//! Run: `cargo bench -p halfspace-mdr --bench transforms`; the table in docs/performance.md comes
//! from `python3 docs/perf_table.py` over target/criterion.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use halfspace_mdr::{
    Backend, CellStressTransform, DisplacementMethod, DisplacementTransform, Material,
    ProfileTransform, SquaredGrid, StressTransform,
};
use halfspace_numerics::conv1d::fast_length;
use halfspace_numerics::ToeplitzConvolution;
use realfft::num_complex::Complex;
use realfft::RealFftPlanner;

const SIZES: [usize; 7] = [100, 1_000, 2_001, 10_000, 20_001, 100_000, 1_000_000];
const MVM_LIMIT: usize = 20_001;

fn unit() -> Material {
    Material::from_e_star(1.0).unwrap()
}

fn graded() -> Material {
    Material::power_law(1.0, 1.0, 0.3, 0.5).unwrap()
}

fn profile_transform(c: &mut Criterion) {
    profile_transform_in(c, "profile_transform", unit());
    profile_transform_in(c, "graded_profile_transform", graded());
}

fn profile_transform_in(c: &mut Criterion, name: &str, material: Material) {
    let mut group = c.benchmark_group(name);
    for &n in &SIZES {
        let grid = SquaredGrid::new(n, 1.0).unwrap();
        let slope: Vec<f64> = (0..n).map(|i| 0.5 + 0.1 * grid.squared(i)).collect();
        let mut g = vec![0.0; n];
        for backend in [Backend::Fft, Backend::Mvm] {
            if backend == Backend::Mvm && n > MVM_LIMIT {
                continue;
            }
            let mut t = ProfileTransform::new(n, &material, backend).unwrap();
            group.bench_with_input(BenchmarkId::new(backend.name(), n), &n, |b, _| {
                b.iter(|| t.apply(&grid, black_box(&slope), &mut g).unwrap())
            });
        }
    }
    group.finish();
}

fn stress_transform(c: &mut Criterion) {
    stress_transform_in(c, "stress_transform", unit());
    stress_transform_in(c, "graded_stress_transform", graded());
}

fn stress_transform_in(c: &mut Criterion, name: &str, material: Material) {
    let mut group = c.benchmark_group(name);
    for &n in &SIZES {
        let grid = SquaredGrid::new(n, 1.0).unwrap();
        let q: Vec<f64> = (0..n).map(|i| 1.0 - grid.squared(i).powi(2)).collect();
        let mut sigma = vec![0.0; n];
        for backend in [Backend::Fft, Backend::Mvm] {
            if backend == Backend::Mvm && n > MVM_LIMIT {
                continue;
            }
            let mut t = StressTransform::new(n, &material, backend).unwrap();
            group.bench_with_input(BenchmarkId::new(backend.name(), n), &n, |b, _| {
                b.iter(|| {
                    t.line_load_to_stress(&grid, black_box(&q), 0.0, &mut sigma)
                        .unwrap()
                })
            });
        }
    }
    group.finish();
}

/// Graded displacement: building the Eq. 25 kernel (O(N²) ₂F₁ evaluations, once) and applying
/// Eq. 25 (dense) and Eq. 26 (FFT) to a Hertz-like U.
fn graded_displacement(c: &mut Criterion) {
    let mut group = c.benchmark_group("eq25_kernel_build");
    for n in [101usize, 1001, 2001, 4001] {
        group.bench_with_input(BenchmarkId::new("build", n), &n, |b, &n| {
            b.iter(|| {
                DisplacementTransform::new(n, &graded(), DisplacementMethod::DenseKernel).unwrap()
            })
        });
    }
    group.finish();
    let mut group = c.benchmark_group("graded_displacement_apply");
    for n in [1001usize, 2001, 4001] {
        let grid = SquaredGrid::new(n, 1.5).unwrap();
        let m = (n - 1) * 4 / 9;
        let u: Vec<f64> = (0..=m).map(|i| grid.squared(m) - grid.squared(i)).collect();
        let mut out = vec![0.0; n];
        for (name, method) in [
            ("eq25", DisplacementMethod::DenseKernel),
            ("eq26_fft", DisplacementMethod::Convolution(Backend::Fft)),
        ] {
            let mut t = DisplacementTransform::new(n, &graded(), method).unwrap();
            group.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                b.iter(|| t.apply(&grid, black_box(&u), 0.0, &mut out).unwrap())
            });
        }
    }
    group.finish();
}

/// The engine alone: `ToeplitzConvolution::apply` (copy in, forward FFT, product, inverse, copy
/// out), to compare with the bare realfft floor below.
fn engine(c: &mut Criterion) {
    let mut group = c.benchmark_group("engine_convolution");
    for &n in &SIZES {
        let kernel: Vec<f64> = (0..n).map(|m| (m as f64).sqrt()).collect();
        let mut op = ToeplitzConvolution::new(kernel, Backend::Fft).unwrap();
        let x: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut y = vec![0.0; n];
        group.bench_with_input(BenchmarkId::new("fft", n), &n, |b, _| {
            b.iter(|| op.apply(black_box(&x), &mut y).unwrap())
        });
    }
    group.finish();
}

/// The floor: forward real FFT, spectrum product, inverse real FFT of the same padded length,
/// with everything planned and allocated beforehand.
fn bare_realfft(c: &mut Criterion) {
    let mut group = c.benchmark_group("bare_realfft_convolution");
    for &n in &SIZES {
        let p = fast_length(2 * n - 1);
        let mut planner = RealFftPlanner::<f64>::new();
        let fwd = planner.plan_fft_forward(p);
        let inv = planner.plan_fft_inverse(p);
        let mut time = vec![0.0; p];
        let mut freq = fwd.make_output_vec();
        let spectrum: Vec<Complex<f64>> = (0..freq.len())
            .map(|k| Complex::new(1.0 / (1.0 + k as f64), 0.0))
            .collect();
        let mut scratch =
            vec![Complex::new(0.0, 0.0); fwd.get_scratch_len().max(inv.get_scratch_len())];
        let x: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        group.bench_with_input(BenchmarkId::new("fft", n), &n, |b, _| {
            b.iter(|| {
                time[..n].copy_from_slice(black_box(&x));
                time[n..].fill(0.0);
                fwd.process_with_scratch(&mut time, &mut freq, &mut scratch)
                    .unwrap();
                for (f, s) in freq.iter_mut().zip(&spectrum) {
                    *f *= *s;
                }
                freq[0].im = 0.0;
                let last = freq.len() - 1;
                if p % 2 == 0 {
                    freq[last].im = 0.0;
                }
                inv.process_with_scratch(&mut freq, &mut time, &mut scratch)
                    .unwrap();
                black_box(time[0])
            })
        });
    }
    group.finish();
}

/// The cell stress transform (Eq. 14 with the edge between nodes) on the first half of the grid
/// (about the wear run's contact), FFT: `new_edge` alternates the edge `θ` every call (the wear
/// rate's evaluations: the partial-cell series is evaluated again), `same_edge` keeps it (the
/// implicit stages' products: the series kept).
fn cell_stress_transform(c: &mut Criterion) {
    let mut group = c.benchmark_group("cell_stress_transform");
    for &n in &[2_001usize, 8_001] {
        let grid = SquaredGrid::new(n, 1.0).unwrap();
        let m = n / 2;
        let q: Vec<f64> = (0..m)
            .map(|i| 1.0 - grid.squared(i) / grid.squared(m))
            .collect();
        let mut sigma = vec![0.0; m];
        let mut t = CellStressTransform::new(n, &unit(), Backend::Fft).unwrap();
        let mut flip = false;
        group.bench_with_input(BenchmarkId::new("new_edge", n), &n, |b, _| {
            b.iter(|| {
                flip = !flip;
                let theta = if flip { 0.37 } else { 0.38 };
                t.line_load_to_stress(&grid, black_box(&q), theta, &mut sigma)
                    .unwrap()
            })
        });
        group.bench_with_input(BenchmarkId::new("same_edge", n), &n, |b, _| {
            b.iter(|| {
                t.line_load_to_stress(&grid, black_box(&q), 0.37, &mut sigma)
                    .unwrap()
            })
        });
    }
    group.finish();
}

fn config() -> Criterion {
    Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_millis(1200))
        .without_plots()
}

criterion_group! {
    name = benches;
    config = config();
    targets = profile_transform, stress_transform, cell_stress_transform, engine, bare_realfft, graded_displacement
}
criterion_main!(benches);
