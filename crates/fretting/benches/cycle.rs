//! Time per wear cycle (one step of the loop of docs/theory-mdr.md#fretting-wear), FFT vs MVM, N = 2001 and 20001.
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use halfspace_fretting::{FrettingParams, FrettingSimulation, TimeStepping};
use halfspace_numerics::Backend;

fn cycle(c: &mut Criterion) {
    let mut group = c.benchmark_group("fretting_cycle");
    for n in [2001usize, 20001] {
        for backend in [Backend::Fft, Backend::Mvm] {
            let params = FrettingParams {
                nodes: n,
                backend,
                stepping: TimeStepping::ExplicitEuler { dtau: 1e-5 },
                tau_end: 1.0,
                ..FrettingParams::default()
            };
            let mut sim = FrettingSimulation::new(params).unwrap();
            group.bench_with_input(BenchmarkId::new(backend.name(), n), &n, |b, _| {
                b.iter(|| sim.step().unwrap())
            });
        }
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_millis(1500)).without_plots();
    targets = cycle
}
criterion_main!(benches);
