//! Cost of the fatigue criteria: per point (one 40-increment path) and over a field of
//! 64 × 64 points × 40 increments, serial and parallel, and with `FATIGUE_BENCH_FULL=1` the
//! 64 × 64 × 16 field in parallel (docs/fatigue.md, "Cost").
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use halfspace_fatigue::critical_plane::{fatemi_socie, swt, CriticalPlaneParams, PlaneScratch};
use halfspace_fatigue::invariant::{crossland_dang_van, InvariantScratch};
use halfspace_fatigue::{evaluate_field, FieldParams, Material, Voigt};

const INCREMENTS: usize = 40;

/// Fixed-seed two-harmonic cycles, amplitudes ~100 MPa around means ~100 MPa (SplitMix64).
fn histories(points: usize) -> Vec<f64> {
    let mut state = 22u64;
    let mut uniform = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut out = Vec::with_capacity(points * INCREMENTS * 6);
    for _ in 0..points {
        let mean: [f64; 6] = std::array::from_fn(|_| 1e8 * uniform());
        let c: [[f64; 6]; 4] = std::array::from_fn(|_| std::array::from_fn(|_| 1e8 * uniform()));
        for i in 0..INCREMENTS {
            let w = 2.0 * std::f64::consts::PI * i as f64 / INCREMENTS as f64;
            for k in 0..6 {
                out.push(
                    mean[k]
                        + c[0][k] * w.cos()
                        + c[1][k] * w.sin()
                        + 0.3 * (c[2][k] * (2.0 * w).cos() + c[3][k] * (2.0 * w).sin()),
                );
            }
        }
    }
    out
}

fn material() -> Material {
    Material {
        f_minus1: 400e6,
        t_minus1: 280e6,
        young: 210e9,
        poisson: 0.3,
        fs_k: 0.5,
        yield_stress: 600e6,
    }
}

fn per_point(c: &mut Criterion) {
    let flat = histories(1);
    let path: Vec<Voigt> = flat
        .chunks_exact(6)
        .map(|c| [c[0], c[1], c[2], c[3], c[4], c[5]])
        .collect();
    let m = material();
    let p = CriticalPlaneParams::default();
    let mut group = c.benchmark_group("fatigue_per_point_40_increments");
    let mut inv = InvariantScratch::default();
    group.bench_function("crossland_dang_van", |b| {
        b.iter(|| crossland_dang_van(&path, &m, &mut inv).unwrap())
    });
    let mut ps = PlaneScratch::default();
    group.bench_function("swt", |b| b.iter(|| swt(&path, &m, &p, &mut ps).unwrap()));
    group.bench_function("fatemi_socie", |b| {
        b.iter(|| fatemi_socie(&path, &m, &p, &mut ps).unwrap())
    });
    group.finish();
}

fn field(c: &mut Criterion) {
    let mut group = c.benchmark_group("fatigue_field_40_increments");
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    let m = material();
    // The full 64 × 64 × 16 field takes minutes per sample: only with FATIGUE_BENCH_FULL=1.
    let mut sizes = vec![("64x64", 64 * 64)];
    if std::env::var_os("FATIGUE_BENCH_FULL").is_some() {
        sizes.push(("64x64x16", 64 * 64 * 16));
    }
    for (name, points) in sizes {
        let flat = histories(points);
        for parallel in [false, true] {
            if points > 4096 && !parallel {
                continue; // the per-point cost is uniform: serial 64x64x16 = 16 × serial 64x64
            }
            let params = FieldParams {
                parallel,
                ..Default::default()
            };
            let id = BenchmarkId::new(if parallel { "parallel" } else { "serial" }, name);
            group.bench_with_input(id, &points, |b, &points| {
                b.iter(|| evaluate_field(&flat, points, INCREMENTS, &m, &params).unwrap())
            });
        }
    }
    group.finish();
}

criterion_group!(benches, per_point, field);
criterion_main!(benches);
