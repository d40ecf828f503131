//! The causal convolution (`ToeplitzConvolution::apply`, FFT backend) at every even padded length
//! `P = 2^a 3^b 5^c 7^d` from 1000 to 17 000 (odd lengths: realfft's odd transforms took about
//! twice an even length's time nearby, e.g. 6561 against 6480), with the input as long as the plan takes
//! (`m = ⌈P/2⌉`): the cost of a length, for choosing the plan lengths of
//! `ToeplitzConvolution::plan_shorter_lengths` (docs/performance.md, "Cost per attempt of the MDR
//! wear run: plan lengths, eight-sum dot products, band substitutions"). Lengths from
//! `SPLIT_FROM` on that are multiples of 4 run split (one thread: the halves one after the other).
//! Run: `RAYON_NUM_THREADS=1 cargo bench -p halfspace-numerics --bench conv_lengths`; a quick
//! pass: `-- --quick`. The ns per apply per length are read from target/criterion
//! (`conv_length/fft/P/new/sample.json`: the fastest sample's time per iteration, which a loaded
//! machine disturbs least).

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use halfspace_numerics::ToeplitzConvolution;

/// Whether `p` has no prime factor above 7.
fn seven_smooth(mut p: usize) -> bool {
    for f in [2, 3, 5, 7] {
        while p % f == 0 {
            p /= f;
        }
    }
    p == 1
}

fn conv_lengths(c: &mut Criterion) {
    let mut group = c.benchmark_group("conv_length");
    group
        .sample_size(40)
        .warm_up_time(Duration::from_millis(100))
        .measurement_time(Duration::from_millis(400));
    for p in (1000..=17_000).step_by(2).filter(|&p| seven_smooth(p)) {
        let m = p.div_ceil(2);
        let kernel: Vec<f64> = (0..m).map(|i| (i as f64).powf(0.75)).collect();
        let x: Vec<f64> = (0..m).map(|i| (0.01 * i as f64).sin()).collect();
        let mut y = vec![0.0; m];
        let mut op = ToeplitzConvolution::with_padded_length(kernel, p).unwrap();
        group.bench_with_input(BenchmarkId::new("fft", p), &p, |b, _| {
            b.iter(|| op.apply(black_box(&x), &mut y).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, conv_lengths);
criterion_main!(benches);
