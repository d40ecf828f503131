//! The equivalent inclusion method: one application of the layered EIM field operator (8 layers,
//! the whole grid as the window) and the whole frictionless contact with the stiff sphere of
//! docs/theory-sam.md#inhomogeneity-references (E_I = 2E, r = 0.3a at depth 0.5a) on 64² and 128² grids over 4a;
//! one application of the EIM system `A ε* = C^m ε* − ΔC 𝒟ε*` of [LN11]'s composite (stiff fibres,
//! fibre-centred, the composite fretting loop's operator, docs/performance.md issue 21) at 64² and
//! 128².
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use halfspace_numerics::linop::LinearOperator;
use halfspace_sam::contact::{ContactParams, ContactProblem};
use halfspace_sam::contact::{InhomogeneousContact, NestedParams};
use halfspace_sam::drivers::fretting_loop::LoopCase;
use halfspace_sam::eim::{
    Backend, EimFields, EimSystem, FibreLayout, InclusionSet, Inhomogeneity, Shape, Space, Window,
};
use halfspace_sam::normal::NormalLoad;
use halfspace_sam::{Body, Compliance, SurfaceGrid};

fn operator(c: &mut Criterion) {
    let mut group = c.benchmark_group("eim_operator_8_layers");
    for n in [64usize, 128] {
        let grid = SurfaceGrid::square(n, n as f64).unwrap();
        let layers: Vec<usize> = (0..8).collect();
        let mut f = EimFields::new(
            grid,
            1.0,
            0.3,
            &layers,
            &layers,
            Window::full(&grid),
            Space::HalfSpace,
            Backend::Fft,
        )
        .unwrap();
        let eigen: Vec<Vec<f64>> = (0..48)
            .map(|k| (0..n * n).map(|i| ((i * 7 + k) % 13) as f64).collect())
            .collect();
        let mut strain = vec![vec![0.0; n * n]; 48];
        group.bench_with_input(BenchmarkId::new("apply", n), &n, |b, _| {
            b.iter(|| f.disturbance(&eigen, &mut strain).unwrap())
        });
    }
    group.finish();
}

/// The composite loop's EIM system at `n²` (as `InhomogeneousContact` builds it).
fn composite_system(n: usize) -> EimSystem {
    let mut case = LoopCase::default()
        .composite(FibreLayout::FibreCentred, 2.0)
        .unwrap();
    case.grid = n;
    let grid = SurfaceGrid::square(n, case.extent()).unwrap();
    let set = InclusionSet::new(&grid, &case.inhomogeneities).unwrap();
    let fields = EimFields::for_inclusions(grid, case.e, case.nu, &set).unwrap();
    EimSystem::new(fields, set, case.e, case.nu).unwrap()
}

fn composite(c: &mut Criterion) {
    let mut group = c.benchmark_group("eim_composite_apply");
    for n in [64usize, 128] {
        let mut system = composite_system(n);
        let dim = system.dim();
        let x: Vec<f64> = (0..dim)
            .map(|i| 1e-4 * (((i * 7919) % 1013) as f64 / 1013.0 - 0.5))
            .collect();
        let mut y = vec![0.0; dim];
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| system.apply(&x, &mut y).unwrap())
        });
    }
    group.finish();
}

fn stiff_sphere(c: &mut Criterion) {
    let (r, w, e, nu): (f64, f64, f64, f64) = (105e-6, 0.08, 210e9, 0.3);
    let a = halfspace_mdr::analytic::sphere_radius_for_force(w, r, e / (1.0 - nu * nu));
    let mut group = c.benchmark_group("stiff_sphere_contact");
    for n in [64usize, 128] {
        group.bench_with_input(BenchmarkId::new("setup_and_solve", n), &n, |b, _| {
            b.iter(|| {
                let grid = SurfaceGrid::square(n, 4.0 * a).unwrap();
                let comp = Compliance::pair(Body::Rigid, Body::elastic(e, nu).unwrap()).unwrap();
                let h: Vec<f64> = (0..grid.len())
                    .map(|k| {
                        let (x, y) = grid.centre(k / n, k % n);
                        (x * x + y * y) / (2.0 * r)
                    })
                    .collect();
                let params = ContactParams {
                    friction: 0.0,
                    ..Default::default()
                };
                let problem = ContactProblem::new(grid, comp, h, params).unwrap();
                let inh = Inhomogeneity {
                    shape: Shape::Sphere {
                        x: 0.0,
                        y: 0.0,
                        z: 0.5 * a,
                        r: 0.3 * a,
                    },
                    e: 2.0 * e,
                    nu,
                };
                let mut nested =
                    InhomogeneousContact::new(problem, e, nu, &[inh], NestedParams::default())
                        .unwrap();
                nested.increment(NormalLoad::Force(w), [0.0; 2]).unwrap()
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3)).without_plots();
    targets = composite, operator, stiff_sphere
}
criterion_main!(benches);
