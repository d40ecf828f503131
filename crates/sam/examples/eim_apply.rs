//! One application of the composite fretting loop's EIM system `A ε* = C^m ε* − ΔC 𝒟ε*`
//! ([LN11]'s stiff fibres, fibre-centred, as `InhomogeneousContact` builds it; docs/performance.md,
//! "One EIM application at 128²: where the time goes"): the build time and stored spectra, wall
//! and process-CPU milliseconds per application over `reps` applications to a fixed seeded
//! eigenstrain, and an FNV-1a hash of the output's bits (equal hashes from two binaries: the same
//! operator bit for bit); then a warm block-Jacobi solve under a pressure bump: milliseconds per
//! application of the whole iteration and a hash of the solution. Peak memory of the build: run under `/usr/bin/time -v`.
//!
//! Run: `cargo run --release -p halfspace-sam --example eim_apply -- [N=128] [reps=20]`
//! (one thread for CPU comparisons: `RAYON_NUM_THREADS=1`).

use halfspace_numerics::linop::LinearOperator;
use halfspace_sam::contact::DEFAULT_EIM_RECYCLED_DEPTH;
use halfspace_sam::drivers::fretting_loop::LoopCase;
use halfspace_sam::eim::{EimFields, EimMethod, EimParams, EimSystem, FibreLayout, InclusionSet};
use halfspace_sam::SurfaceGrid;

#[path = "probe/mod.rs"]
mod probe;
use probe::process_cpu_seconds as cpu;

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
    // The volume's difference family stored real: its dropped parts over the kept, per block.
    if let Some(d) = fields.real_storage_discarded() {
        println!("difference family stored real, dropped / kept ≤ {d:.2e}");
    }
    // The surface and Love spectra stored by quarter.
    if let Some(d) = fields.quarter_storage_discarded() {
        println!("surface and Love spectra by quarter, dropped / kept ≤ {d:.2e}");
    }
    let mut system = EimSystem::new(fields, set, case.e, case.nu).unwrap();
    let dim = system.dim();
    let x: Vec<f64> = (0..dim)
        .map(|i| 1e-4 * (((i * 7919) % 1013) as f64 / 1013.0 - 0.5))
        .collect();
    let mut y = vec![0.0; dim];
    system.apply(&x, &mut y).unwrap();
    // `EIM_APPLY_FIELDS_ONLY` set: the application's timing loop is skipped (to profile the
    // per-pass fields below alone).
    let apply_reps = if std::env::var_os("EIM_APPLY_FIELDS_ONLY").is_some() {
        1
    } else {
        reps
    };
    let (t, c) = (std::time::Instant::now(), cpu());
    for _ in 0..apply_reps {
        system.apply(&x, &mut y).unwrap();
    }
    println!(
        "apply {:.2} ms wall, {:.1} ms CPU",
        t.elapsed().as_secs_f64() * 1e3 / apply_reps as f64,
        (cpu() - c) * 1e3 / apply_reps as f64
    );
    let h = y.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, v| {
        (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3)
    });
    println!("output bits {h:016x}");
    // The same applications run on one of rayon's workers with a partner, as the nested loop
    // runs its increments (`halfspace_numerics::parallel::on_pool`).
    let (t, c) = (std::time::Instant::now(), cpu());
    halfspace_numerics::parallel::on_pool(n * n, || {
        for _ in 0..apply_reps {
            system.apply(&x, &mut y).unwrap();
        }
    });
    println!(
        "apply on the pool {:.2} ms wall, {:.1} ms CPU",
        t.elapsed().as_secs_f64() * 1e3 / apply_reps as f64,
        (cpu() - c) * 1e3 / apply_reps as f64
    );
    // Block-Jacobi solves (Anderson depth of the nested loop's default) under a pressure bump
    // on the grid: milliseconds per application of the whole iteration (the
    // application, the preconditioner, the residual and mixing vector operations), against the
    // application alone above.
    let bump: Vec<f64> = (0..n * n)
        .map(|k| {
            let (i, j) = (
                (k / n) as f64 - n as f64 / 2.0,
                (k % n) as f64 - n as f64 / 2.0,
            );
            (1.0 - (i * i + j * j) / (n * n / 16) as f64).max(0.0)
        })
        .collect();
    let layers = system.set().layers.len();
    let mut applied = vec![vec![0.0; system.set().window.len()]; layers * 6];
    system
        .fields()
        .traction_strain(&bump, None, &mut applied)
        .unwrap();
    let params = EimParams {
        method: EimMethod::BlockJacobi,
        tolerance: 1e-8,
        recycled_depth: DEFAULT_EIM_RECYCLED_DEPTH,
        ..EimParams::default()
    };
    let mut eps = vec![0.0; dim];
    // A first solve plans the iteration's work arrays; the timed one is warm, under 1.05 × the
    // load (as the loop's next pass).
    let start = eps.clone();
    let first = applied.clone();
    system.solve(&applied, &mut eps, &params).unwrap();
    applied.iter_mut().flatten().for_each(|v| *v *= 1.05);
    let (t, c) = (std::time::Instant::now(), cpu());
    let info = system.solve(&applied, &mut eps, &params).unwrap();
    let its = info.iterations.max(1) as f64;
    println!(
        "solve {} applications, {:.2} ms wall, {:.1} ms CPU per application",
        info.iterations,
        t.elapsed().as_secs_f64() * 1e3 / its,
        (cpu() - c) * 1e3 / its
    );
    let h = eps.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, v| {
        (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3)
    });
    println!("solution bits {h:016x}");
    // The same warm solve again from the same start, on the pool (as the loop).
    eps.copy_from_slice(&start);
    system.forget_recycled();
    system.solve(&first, &mut eps, &params).unwrap();
    let (t, c) = (std::time::Instant::now(), cpu());
    let info = halfspace_numerics::parallel::on_pool(n * n, || {
        system.solve(&applied, &mut eps, &params).unwrap()
    });
    let its = info.iterations.max(1) as f64;
    let h = eps.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, v| {
        (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3)
    });
    println!(
        "solve on the pool {} applications, {:.2} ms wall, {:.1} ms CPU per application, bits {h:016x}",
        info.iterations,
        t.elapsed().as_secs_f64() * 1e3 / its,
        (cpu() - c) * 1e3 / its
    );
    // The outer pass's other EIM-family work, per call: the applied strain of the tractions
    // (p and a shear q = 0.3 p: Love's strains at the inclusion layers) and the surface fields
    // of the solution with its eigen-displacements; and, for scale, the 2D transforms alone on
    // the grid's plan (the count one traction strain makes: 3 forward, 6 per layer inverse).
    let q: Vec<f64> = bump.iter().map(|v| 0.3 * v).collect();
    let (t, c) = (std::time::Instant::now(), cpu());
    for _ in 0..reps {
        system
            .fields()
            .traction_strain(&bump, Some([&q, &q]), &mut applied)
            .unwrap();
    }
    let h = applied
        .iter()
        .flatten()
        .fold(0xcbf2_9ce4_8422_2325u64, |h, v| {
            (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3)
        });
    println!(
        "traction strain {:.2} ms wall, {:.1} ms CPU per call, bits {h:016x}",
        t.elapsed().as_secs_f64() * 1e3 / reps as f64,
        (cpu() - c) * 1e3 / reps as f64
    );
    let mut u = vec![vec![0.0; n * n]; 3];
    let (t, c) = (std::time::Instant::now(), cpu());
    for _ in 0..reps {
        system.surface_disturbance(&eps).unwrap();
        let [a, b, d] = &mut u[..] else {
            unreachable!("three fields")
        };
        system.fields().eigen_displacements([a, b, d]).unwrap();
    }
    let h = u.iter().flatten().fold(0xcbf2_9ce4_8422_2325u64, |h, v| {
        (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3)
    });
    println!(
        "surface fields and eigen-displacements {:.2} ms wall, {:.1} ms CPU per call, bits {h:016x}",
        t.elapsed().as_secs_f64() * 1e3 / reps as f64,
        (cpu() - c) * 1e3 / reps as f64
    );
    let mut fft = halfspace_numerics::fft2d::Fft2d::new(n, n).unwrap();
    let mut spec = fft.new_spectrum();
    fft.forward(&bump, &mut spec).unwrap();
    let (kept, mut work) = (spec.clone(), spec.clone());
    let mut out = vec![0.0; n * n];
    let count = 6 * layers;
    let (t, c) = (std::time::Instant::now(), cpu());
    for _ in 0..reps {
        for _ in 0..count {
            fft.forward(&bump, &mut spec).unwrap();
        }
    }
    let (fw, fc) = (t.elapsed().as_secs_f64(), cpu() - c);
    let (t, c) = (std::time::Instant::now(), cpu());
    for _ in 0..reps {
        for _ in 0..count {
            work.copy_from_slice(&kept);
            fft.inverse(&mut work, &mut out).unwrap();
        }
    }
    let (iw, ic) = (t.elapsed().as_secs_f64(), cpu() - c);
    let per = 1e3 / (reps * count) as f64;
    println!(
        "one 2D FFT on the grid's plan: forward {:.3} ms wall ({:.3} CPU), inverse {:.3} ms wall ({:.3} CPU)",
        fw * per,
        fc * per,
        iw * per,
        ic * per
    );
}
