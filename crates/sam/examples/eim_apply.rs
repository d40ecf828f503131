//! One application of the composite fretting loop's EIM system `A ε* = C^m ε* − ΔC 𝒟ε*`
//! ([LN11]'s stiff fibres, fibre-centred, as `InhomogeneousContact` builds it; docs/performance.md,
//! "One EIM application at 128²: where the time goes"): the build time and stored spectra, wall
//! and process-CPU milliseconds per application over `reps` applications to a fixed seeded
//! eigenstrain, and an FNV-1a hash of the output's bits (equal hashes from two binaries: the same
//! operator bit for bit). Peak memory of the build: run under `/usr/bin/time -v`.
//!
//! Run: `cargo run --release -p halfspace-sam --example eim_apply -- [N=128] [reps=20]`
//! (one thread for CPU comparisons: `RAYON_NUM_THREADS=1`).

use halfspace_numerics::linop::LinearOperator;
use halfspace_sam::drivers::fretting_loop::LoopCase;
use halfspace_sam::eim::{EimFields, EimSystem, FibreLayout, InclusionSet};
use halfspace_sam::SurfaceGrid;

/// CPU seconds of this process (utime + stime of /proc/self/stat, 100 ticks per second).
fn cpu() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<f64> = stat
        .rsplit(')')
        .next()
        .unwrap_or("")
        .split_whitespace()
        .map(|v| v.parse().unwrap_or(0.0))
        .collect();
    (fields.get(11).unwrap_or(&0.0) + fields.get(12).unwrap_or(&0.0)) / 100.0
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.first().and_then(|v| v.parse().ok()).unwrap_or(128);
    let reps: usize = args.get(1).and_then(|v| v.parse().ok()).unwrap_or(20);
    let mut case = LoopCase::default()
        .composite(FibreLayout::FibreCentred, 2.0)
        .unwrap();
    case.grid = n;
    let grid = SurfaceGrid::square(n, case.extent()).unwrap();
    let set = InclusionSet::new(&grid, &case.inhomogeneities).unwrap();
    println!(
        "{n}²: window {:?}, layers {:?}, {} inclusion cells",
        set.window,
        set.layers,
        set.cells.len()
    );
    let t = std::time::Instant::now();
    let fields = EimFields::for_inclusions(grid, case.e, case.nu, &set).unwrap();
    println!(
        "build {:.2} s, stored spectra {} MB",
        t.elapsed().as_secs_f64(),
        fields.spectra_bytes() / 1_000_000
    );
    let mut system = EimSystem::new(fields, set, case.e, case.nu).unwrap();
    let dim = system.dim();
    let x: Vec<f64> = (0..dim)
        .map(|i| 1e-4 * (((i * 7919) % 1013) as f64 / 1013.0 - 0.5))
        .collect();
    let mut y = vec![0.0; dim];
    system.apply(&x, &mut y).unwrap();
    let (t, c) = (std::time::Instant::now(), cpu());
    for _ in 0..reps {
        system.apply(&x, &mut y).unwrap();
    }
    println!(
        "apply {:.2} ms wall, {:.1} ms CPU",
        t.elapsed().as_secs_f64() * 1e3 / reps as f64,
        (cpu() - c) * 1e3 / reps as f64
    );
    let h = y.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, v| {
        (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3)
    });
    println!("output bits {h:016x}");
}
