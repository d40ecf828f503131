//! The transforms of the wear run's stage product `W x` (docs/fretting-wear.md, "Time
//! integration"): the profile transform on `m + 3` nodes (`slope_to_equivalent`) and the cell
//! stress transform on the `m` contact nodes (`line_load_to_stress`), `m = N/2` as in the grazing
//! phase, with the shorter plans the stages use, in `f64` and with `f32` transforms
//! (`set_precision`; docs/performance.md, "The N = 8001 wear run: single-precision stage
//! products (issue 20)"), at N = 401, 2001 and 8001.
//! Run: `RAYON_NUM_THREADS=1 cargo bench -p halfspace-mdr --bench stage_product`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use halfspace_mdr::{CellStressTransform, Material, ProfileTransform, SquaredGrid};
use halfspace_numerics::{Backend, Precision};

fn stage_product(c: &mut Criterion) {
    let mut group = c.benchmark_group("stage_product");
    group
        .sample_size(60)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    let material = Material::from_e_star(1.0).unwrap();
    for n in [401usize, 2001, 8001] {
        let m = n / 2;
        let h = 4.0 / (n - 1) as f64;
        let prefix = SquaredGrid::with_step(m + 3, h).unwrap();
        let grid = SquaredGrid::with_step(n, h).unwrap();
        let mut profile = ProfileTransform::new(n, &material, Backend::Fft).unwrap();
        profile.plan_shorter_lengths();
        let mut stress = CellStressTransform::new(n, &material, Backend::Fft).unwrap();
        stress.plan_shorter_lengths();
        let slope0: Vec<f64> = (0..m + 3).map(|i| (0.37 * i as f64).sin()).collect();
        let mut slope = slope0.clone();
        let mut g = vec![0.0; m + 3];
        let mut sigma = vec![0.0; m];
        for precision in [Precision::Double, Precision::Single] {
            profile.set_precision(precision).unwrap();
            stress.set_precision(precision);
            let name = match precision {
                Precision::Double => "f64",
                Precision::Single => "f32",
            };
            group.bench_with_input(BenchmarkId::new(name, n), &n, |bench, _| {
                bench.iter(|| {
                    slope.copy_from_slice(&slope0);
                    profile
                        .slope_to_equivalent(&prefix, &mut slope, &mut g)
                        .unwrap();
                    stress
                        .line_load_to_stress(&grid, black_box(&g[..m]), 0.5, &mut sigma)
                        .unwrap();
                    black_box(&sigma);
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, stage_product);
criterion_main!(benches);
