//! The equivalent inclusion method: layered operators against their dense twin, the solvers on
//! both and against a direct LU solve, Eshelby's sphere and Mindlin–Cheng's nucleus (docs/theory-sam.md#kernel-reference-values).
#![allow(clippy::needless_range_loop)]

use faer::linalg::solvers::Solve;
use faer::Mat;
use halfspace_numerics::linop::{DenseMatrix, LinearOperator};
use halfspace_sam::analytic::{eshelby_sphere_interior_stress, mindlin_cheng_surface};
use halfspace_sam::eim::{
    Axis, Backend, EimFields, EimMethod, EimParams, EimSystem, InclusionSet, Inhomogeneity, Shape,
    Space, Window,
};
use halfspace_sam::kernels::{mul6, stiffness};
use halfspace_sam::{SamError, SurfaceGrid};

const E: f64 = 1.0;
const NU: f64 = 0.3;

/// `n` fixed-seed values uniform in `[−0.5, 0.5)`.
fn lcg(seed: u64, n: usize) -> Vec<f64> {
    let mut rng = halfspace_numerics::testkit::Lcg::new(seed);
    (0..n).map(|_| rng.unit() - 0.5).collect()
}

fn max_diff(a: &[Vec<f64>], b: &[Vec<f64>]) -> (f64, f64) {
    let scale = b.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let err = a
        .iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    (err, scale)
}

#[test]
fn layered_operators_equal_their_dense_twin_and_the_window_equals_the_full_grid() {
    let grid = SurfaceGrid::square(8, 8.0).unwrap();
    let (sources, targets) = ([1usize, 2, 4], [0usize, 1, 2, 3, 4, 6]);
    let n = grid.len();
    let sub = Window {
        i0: 2,
        n1: 4,
        j0: 1,
        n2: 5,
    };
    let full = Window::full(&grid);
    let eigen_sub: Vec<Vec<f64>> = (0..sources.len() * 6)
        .map(|k| lcg(k as u64 + 1, sub.len()))
        .collect();
    let eigen_full: Vec<Vec<f64>> = eigen_sub
        .iter()
        .map(|f| {
            let mut g = vec![0.0; n];
            sub.scatter(&grid, f, &mut g).unwrap();
            g
        })
        .collect();
    let p = lcg(99, n).iter().map(|v| v + 0.5).collect::<Vec<_>>();
    let (q1, q2) = (lcg(5, n), lcg(6, n));
    type Fields = (Vec<Vec<f64>>, Vec<Vec<f64>>, Vec<Vec<f64>>, Vec<Vec<f64>>);
    let run = |window: Window, eigen: &[Vec<f64>], backend: Backend| -> Fields {
        let mut f = EimFields::new(
            grid,
            E,
            NU,
            &sources,
            &targets,
            window,
            Space::HalfSpace,
            backend,
        )
        .unwrap();
        let mut strain = vec![vec![0.0; window.len()]; targets.len() * 6];
        f.disturbance(eigen, &mut strain).unwrap();
        let mut u = vec![vec![0.0; n]; 3];
        {
            let [a, b, c] = &mut u[..] else {
                unreachable!()
            };
            f.eigen_displacements([a, b, c]).unwrap();
        }
        let mut applied = vec![vec![0.0; window.len()]; targets.len() * 6];
        f.traction_strain(&p, Some([&q1, &q2]), &mut applied)
            .unwrap();
        (strain, vec![f.correction_pressure().to_vec()], u, applied)
    };
    let fast = run(sub, &eigen_sub, Backend::Fft);
    let dense = run(sub, &eigen_sub, Backend::Dense);
    for (name, (err, scale)) in [
        ("disturbance strain", max_diff(&fast.0, &dense.0)),
        ("correction pressure", max_diff(&fast.1, &dense.1)),
        ("eigen-displacements", max_diff(&fast.2, &dense.2)),
        ("applied strain", max_diff(&fast.3, &dense.3)),
    ] {
        assert!(err <= 1e-12 * scale, "{name}: {err:e} of {scale:e}");
    }
    // The whole grid, cropped to the window, gives the same fields.
    let whole = run(full, &eigen_full, Backend::Fft);
    let crop = |fields: &[Vec<f64>]| -> Vec<Vec<f64>> {
        fields
            .iter()
            .map(|f| {
                let mut l = vec![0.0; sub.len()];
                sub.gather_add(&grid, f, &mut l).unwrap();
                l
            })
            .collect()
    };
    for (name, (err, scale)) in [
        ("windowed strain", max_diff(&fast.0, &crop(&whole.0))),
        ("windowed p_c", max_diff(&fast.1, &whole.1)),
        (
            "windowed applied strain",
            max_diff(&fast.3, &crop(&whole.3)),
        ),
    ] {
        assert!(err <= 1e-12 * scale, "{name}: {err:e} of {scale:e}");
    }
}

/// The windows and backends the disturbance tests run on: a sub-window on the FFT and on the
/// dense twin, and the shared whole-grid path.
fn disturbance_cases(grid: &SurfaceGrid) -> [(Window, Backend); 3] {
    let sub = Window {
        i0: 2,
        n1: 4,
        j0: 1,
        n2: 5,
    };
    [
        (sub, Backend::Fft),
        (sub, Backend::Dense),
        (Window::full(grid), Backend::Fft),
    ]
}

/// The surface-only disturbance (what the outer loop's eigen-displacements read) gives the
/// correction pressure and the eigen-displacements of the full disturbance bit for bit, on the
/// windowed FFT, the dense twin and the shared whole-grid path.
#[test]
fn the_surface_disturbance_is_the_full_disturbances_surface_bit_for_bit() {
    let grid = SurfaceGrid::square(8, 8.0).unwrap();
    let (sources, targets) = ([1usize, 2, 4], [1usize, 2, 4]);
    let n = grid.len();
    for (window, backend) in disturbance_cases(&grid) {
        let eigen: Vec<Vec<f64>> = (0..sources.len() * 6)
            .map(|k| lcg(k as u64 + 11, window.len()))
            .collect();
        let mut f = EimFields::new(
            grid,
            E,
            NU,
            &sources,
            &targets,
            window,
            Space::HalfSpace,
            backend,
        )
        .unwrap();
        let u_of = |f: &mut EimFields| {
            let mut u = vec![vec![0.0; n]; 3];
            let [a, b, c] = &mut u[..] else {
                unreachable!()
            };
            f.eigen_displacements([a, b, c]).unwrap();
            (f.correction_pressure().to_vec(), u)
        };
        let mut strain = vec![vec![0.0; window.len()]; targets.len() * 6];
        f.disturbance(&eigen, &mut strain).unwrap();
        let full = u_of(&mut f);
        // Overwrite the surface fields with another disturbance first, so nothing is left over.
        let other: Vec<Vec<f64>> = eigen
            .iter()
            .map(|e| e.iter().map(|v| -v).collect())
            .collect();
        f.disturbance(&other, &mut strain).unwrap();
        f.surface_disturbance(&eigen).unwrap();
        let surface = u_of(&mut f);
        assert!(full.0.iter().any(|v| *v != 0.0));
        assert_eq!(full, surface, "{backend:?}, window {window:?}");
    }
}

/// The strain-only disturbance (what the EIM iteration applies) gives the strain and the
/// correction pressure of the full disturbance bit for bit, on the windowed FFT, the dense twin
/// and the shared whole-grid path; the eigen-displacements are refused after it until a full
/// (or surface) disturbance.
#[test]
fn the_strain_only_disturbance_is_the_full_disturbances_strain_bit_for_bit() {
    let grid = SurfaceGrid::square(8, 8.0).unwrap();
    let (sources, targets) = ([1usize, 2, 4], [1usize, 2, 4]);
    let n = grid.len();
    for (window, backend) in disturbance_cases(&grid) {
        let eigen: Vec<Vec<f64>> = (0..sources.len() * 6)
            .map(|k| lcg(k as u64 + 5, window.len()))
            .collect();
        let fields = || {
            EimFields::new(
                grid,
                E,
                NU,
                &sources,
                &targets,
                window,
                Space::HalfSpace,
                backend,
            )
            .unwrap()
        };
        // The full disturbance on one instance, the strain-only one on a fresh instance (so a
        // p_c left over from a full call cannot stand in for one not computed), after another
        // eigenstrain's strain-only disturbance there.
        let mut whole = fields();
        let mut full = vec![vec![0.0; window.len()]; targets.len() * 6];
        whole.disturbance(&eigen, &mut full).unwrap();
        let pc = whole.correction_pressure().to_vec();
        let mut f = fields();
        let mut strain = vec![vec![0.0; window.len()]; targets.len() * 6];
        let other: Vec<Vec<f64>> = eigen
            .iter()
            .map(|e| e.iter().map(|v| 0.5 - v).collect())
            .collect();
        f.disturbance_strain(&other, &mut strain).unwrap();
        assert_ne!(pc, f.correction_pressure());
        f.disturbance_strain(&eigen, &mut strain).unwrap();
        assert!(pc.iter().any(|v| *v != 0.0));
        assert_eq!(full, strain, "{backend:?}, window {window:?}");
        assert_eq!(
            pc,
            f.correction_pressure(),
            "{backend:?}, window {window:?}"
        );
        let mut u = vec![vec![0.0; n]; 3];
        let [a, b, c] = &mut u[..] else {
            unreachable!()
        };
        assert!(f.eigen_displacements([a, b, c]).is_err());
        f.surface_disturbance(&eigen).unwrap();
        assert!(f.eigen_displacements([a, b, c]).is_ok());
    }
}

/// Mean interior stress of a cell-discretised sphere of `radius` cells, centred on a lattice
/// vertex, `E_I = ratio E`, under a remote uniaxial `σ₃₃ = 1`, in infinite space.
fn eshelby_sphere(
    radius: usize,
    ratio: f64,
    method: EimMethod,
) -> Result<([f64; 6], usize, usize, [f64; 6]), SamError> {
    let n = (2 * radius + 2).max(8);
    let grid = SurfaceGrid::square(n, n as f64).unwrap();
    let inh = Inhomogeneity {
        shape: Shape::Sphere {
            x: 0.0,
            y: 0.0,
            z: radius as f64 + 2.0,
            r: radius as f64,
        },
        e: ratio * E,
        nu: NU,
    };
    let set = InclusionSet::new(&grid, &[inh]).unwrap();
    let fields = EimFields::new(
        grid,
        E,
        NU,
        &set.layers,
        &set.layers,
        set.window,
        Space::Infinite,
        Backend::Fft,
    )
    .unwrap();
    let remote = [-NU / E, -NU / E, 1.0 / E, 0.0, 0.0, 0.0];
    let applied: Vec<Vec<f64>> = (0..set.layers.len() * 6)
        .map(|k| vec![remote[k % 6]; set.window.len()])
        .collect();
    let mut sys = EimSystem::new(fields, set.clone(), E, NU).unwrap();
    let mut x = vec![0.0; 6 * set.len()];
    let info = sys.solve(
        &applied,
        &mut x,
        &EimParams {
            method,
            tolerance: 1e-9,
            ..Default::default()
        },
    )?;
    let strain = sys.disturbance(&x).unwrap().to_vec();
    let ci = stiffness(ratio * E, NU);
    let mut mean = [0.0; 6];
    let mut centre = [0.0; 6];
    let depth = radius as f64 + 2.0;
    for cell in &set.cells {
        let (i, j) = (cell.flat / grid.n2, cell.flat % grid.n2);
        let (cx, cy) = grid.centre(i, j);
        let cz = (2 * set.layers[cell.layer] + 1) as f64 * 0.5 - depth;
        let near = cx.abs() < 1.0 && cy.abs() < 1.0 && cz.abs() < 1.0;
        let mut eps = [0.0; 6];
        for o in 0..6 {
            eps[o] = remote[o] + strain[cell.layer * 6 + o][cell.local];
        }
        let s = mul6(&ci, &eps);
        for o in 0..6 {
            mean[o] += s[o] / set.len() as f64;
            if near {
                centre[o] += s[o] / 8.0;
            }
        }
    }
    Ok((mean, set.len(), info.iterations, centre))
}

#[test]
fn eshelby_sphere_by_cuboids_matches_spec_and_converges() {
    let remote = [-NU / E, -NU / E, 1.0 / E, 0.0, 0.0, 0.0];
    // docs/theory-sam.md#kernel-reference-values: radius 3/5/6 cells (136/552/912 cells): mean σ₃₃ = 1.3128/1.3177/1.3165,
    // mean σ₁₁ = −0.0365/−0.0391/−0.0389; exact 1.3150 / −0.0398.
    let exact = eshelby_sphere_interior_stress(E, NU, 2.0 * E, NU, &remote);
    let mut errors = Vec::new();
    for (radius, cells, s33, s11) in [
        (3, 136, 1.3128, -0.0365),
        (5, 552, 1.3177, -0.0391),
        (6, 912, 1.3165, -0.0389),
    ] {
        let (mean, count, it, _) = eshelby_sphere(radius, 2.0, EimMethod::BlockJacobi).unwrap();
        assert_eq!(count, cells, "cells of the radius-{radius} sphere");
        assert!(
            (mean[2] - s33).abs() < 1e-4,
            "r = {radius}: σ33 {} ({it} it)",
            mean[2]
        );
        assert!(
            (mean[0] - s11).abs() < 1e-4,
            "r = {radius}: σ11 {}",
            mean[0]
        );
        errors.push((mean[2] - exact[2]).abs() / exact[2]);
    }
    // Within 0.3 % of Eshelby at every radius; the staircase error is not monotone but small.
    assert!(errors.iter().all(|e| *e < 3e-3), "{errors:?}");
    // Soft (E_I = E/2): spec 0.6848 (radius 3) vs exact 0.6789.
    let (soft, _, _, _) = eshelby_sphere(3, 0.5, EimMethod::BlockJacobi).unwrap();
    assert!((soft[2] - 0.6848).abs() < 1e-4, "{}", soft[2]);
    // Stiff (E_I = 10 E): block Jacobi has spectral radius ≈ 1 there; GMRES converges in ~30
    // iterations. The mean over the staircase cells converges slowly (observed order ≈ 0.6 in h:
    // 1.79 %, 1.60 %, 1.06 % at radius 4, 6, 10 cells).
    let exact10 = eshelby_sphere_interior_stress(E, NU, 10.0 * E, NU, &remote);
    let mut errs = Vec::new();
    for radius in [4, 6, 10] {
        let (stiff, _, it, _) = eshelby_sphere(radius, 10.0, EimMethod::Gmres).unwrap();
        assert!(it < 60, "radius {radius}: {it} GMRES iterations");
        errs.push((stiff[2] - exact10[2]).abs() / exact10[2]);
    }
    assert!(
        errs[2] < errs[1] && errs[1] < errs[0] && errs[2] < 0.012,
        "{errs:?}"
    );
}

/// A sphere of radius 1.6 cells, `E_I = 3E`, `ν_I = 0.25`, on 8² cells of size 1.
fn small_sphere() -> (SurfaceGrid, InclusionSet) {
    let grid = SurfaceGrid::square(8, 8.0).unwrap();
    let inh = Inhomogeneity {
        shape: Shape::Sphere {
            x: 0.0,
            y: 0.0,
            z: 3.0,
            r: 1.6,
        },
        e: 3.0,
        nu: 0.25,
    };
    let set = InclusionSet::new(&grid, &[inh]).unwrap();
    (grid, set)
}

#[test]
fn solvers_agree_on_the_fft_operator_its_dense_twin_and_a_direct_lu() {
    let (grid, set) = small_sphere();
    let applied: Vec<Vec<f64>> = (0..set.layers.len() * 6)
        .map(|k| {
            lcg(k as u64 + 40, set.window.len())
                .iter()
                .map(|v| 1e-3 * v)
                .collect()
        })
        .collect();
    let mut solutions = Vec::new();
    for backend in [Backend::Fft, Backend::Dense] {
        let fields = EimFields::new(
            grid,
            E,
            NU,
            &set.layers,
            &set.layers,
            set.window,
            Space::HalfSpace,
            backend,
        )
        .unwrap();
        let mut sys = EimSystem::new(fields, set.clone(), E, NU).unwrap();
        for method in [EimMethod::BlockJacobi, EimMethod::Gmres] {
            let mut x = vec![0.0; sys.dim()];
            sys.solve(
                &applied,
                &mut x,
                &EimParams {
                    method,
                    tolerance: 1e-13,
                    ..Default::default()
                },
            )
            .unwrap();
            solutions.push(x);
        }
        if backend == Backend::Dense {
            // Direct LU of the assembled matrix (faer) as the reference.
            let a = DenseMatrix::assemble(&mut sys).unwrap();
            let dim = sys.dim();
            let mut b = vec![0.0; dim];
            sys.rhs(&applied, &mut b).unwrap();
            // Mis-sized right-hand sides or applied fields are refused (typed errors).
            assert!(sys.rhs(&applied, &mut b[..dim - 1]).is_err());
            assert!(sys.rhs(&applied[..applied.len() - 1], &mut b).is_err());
            let mut short = applied.clone();
            short[0].pop();
            assert!(sys.rhs(&short, &mut b).is_err());
            let m = Mat::<f64>::from_fn(dim, dim, |i, j| a.a[i * dim + j]);
            let rhs = Mat::<f64>::from_fn(dim, 1, |i, _| b[i]);
            let x = m.partial_piv_lu().solve(&rhs);
            solutions.push((0..dim).map(|i| x[(i, 0)]).collect());
        }
    }
    let reference = solutions.last().unwrap().clone();
    let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (k, s) in solutions.iter().enumerate() {
        let err = s
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-10 * scale, "solution {k}: {err:e} of {scale:e}");
    }
}

/// Block Jacobi recycling its iterations across solves (`EimParams::recycled_depth`,
/// docs/theory-sam.md#solving-the-eim-equations) against plain block Jacobi (the naive control),
/// on the FFT operator and its dense twin: the same solutions to the stopping error, and a
/// sequence of right-hand sides (an outer loop's passes) in fewer operator applications; after
/// `forget_recycled` the next solve applies the operator for its first residual again.
#[test]
fn recycled_block_jacobi_matches_the_plain_iteration_in_fewer_applications() {
    let (grid, set) = small_sphere();
    // Right-hand sides drifting as an outer loop's tractions do: a base field plus 1e-2, 1e-3,
    // 1e-4 of a second one.
    let base = |k: usize, seed: u64, scale: f64| -> Vec<f64> {
        lcg(k as u64 + seed, set.window.len())
            .iter()
            .map(|v| scale * v)
            .collect()
    };
    let sequence: Vec<Vec<Vec<f64>>> = [0.0, 1e-2, 1e-3, 1e-4]
        .iter()
        .map(|&d| {
            (0..set.layers.len() * 6)
                .map(|k| {
                    base(k, 40, 1e-3)
                        .iter()
                        .zip(base(k, 90, 1e-3 * d))
                        .map(|(a, b)| a + b)
                        .collect()
                })
                .collect()
        })
        .collect();
    for backend in [Backend::Fft, Backend::Dense] {
        let fields = |set: &InclusionSet| {
            EimFields::new(
                grid,
                E,
                NU,
                &set.layers,
                &set.layers,
                set.window,
                Space::HalfSpace,
                backend,
            )
            .unwrap()
        };
        let mut plain = EimSystem::new(fields(&set), set.clone(), E, NU).unwrap();
        let mut recycled = EimSystem::new(fields(&set), set.clone(), E, NU).unwrap();
        let params = |depth| EimParams {
            method: EimMethod::BlockJacobi,
            tolerance: 1e-9,
            recycled_depth: depth,
            ..Default::default()
        };
        let (mut x_plain, mut x_recycled) = (vec![0.0; plain.dim()], vec![0.0; plain.dim()]);
        let (mut n_plain, mut n_recycled) = (0, 0);
        for applied in &sequence {
            n_plain += plain
                .solve(applied, &mut x_plain, &params(0))
                .unwrap()
                .iterations;
            n_recycled += recycled
                .solve(applied, &mut x_recycled, &params(5))
                .unwrap()
                .iterations;
            let scale = x_plain.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let err = x_plain
                .iter()
                .zip(&x_recycled)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            // Both stop on a step of 1e-9 of max|ε*| at a contraction rate ≈ 0.2.
            assert!(err < 1e-8 * scale, "{backend:?}: {err:e} of {scale:e}");
        }
        // Observed on both backends: 63 applications plain, 43 recycled.
        assert!(
            n_recycled < n_plain,
            "{backend:?}: {n_recycled} against {n_plain} applications"
        );
        // Forgotten: the first residual is applied again (the last solve's is not reused), and
        // the solve from the last result with the first right-hand side agrees with plain.
        recycled.forget_recycled();
        let (mut a, mut b) = (x_recycled.clone(), x_recycled.clone());
        let info = recycled.solve(&sequence[0], &mut a, &params(5)).unwrap();
        assert!(info.iterations >= 1);
        plain.solve(&sequence[0], &mut b, &params(0)).unwrap();
        let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let err = a
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
        assert!(err < 1e-8 * scale, "{backend:?}: {err:e}");
    }
}

/// Strength `e` of the unit nucleus and its layer (centre depth 8.5).
const NUCLEUS: (f64, usize) = (1e-3, 8);

/// The field operators after the disturbance of a unit cube with ε* = e·1 at depth 8.5 under the
/// cell (n/2, n/2) of an `n × n` surface of unit cells (a 2 × 2 window around it).
fn nucleus_fields(n: usize) -> EimFields {
    let grid = SurfaceGrid::square(n, n as f64).unwrap();
    let (e, layer) = NUCLEUS;
    let window = Window {
        i0: n / 2 - 1,
        n1: 2,
        j0: n / 2 - 1,
        n2: 2,
    };
    let mut fields = EimFields::new(
        grid,
        E,
        NU,
        &[layer],
        &[],
        window,
        Space::HalfSpace,
        Backend::Fft,
    )
    .unwrap();
    let eigen: Vec<Vec<f64>> = (0..6)
        .map(|c| {
            let mut f = vec![0.0; window.len()];
            if c < 3 {
                f[3] = e;
            }
            f
        })
        .collect();
    fields.disturbance(&eigen, &mut []).unwrap();
    fields
}

#[test]
fn nucleus_of_strain_reproduces_mindlin_cheng_near_the_axis() {
    // 128² unit cells (±64); the cube under the cell (64, 64), centred at (0.5, 0.5).
    let mut fields = nucleus_fields(128);
    let (e, layer) = NUCLEUS;
    let depth = (2 * layer + 1) as f64 * 0.5;
    let n = 128 * 128;
    let centre = 64 * 128 + 64;
    let mut u = vec![vec![0.0; n]; 3];
    {
        let [a, b, c] = &mut u[..] else {
            unreachable!()
        };
        fields.eigen_displacements([a, b, c]).unwrap();
    }
    // On the axis and at r = 4 along x₁.
    let (_, u3_exact) = mindlin_cheng_surface(0.0, depth, e, NU);
    let rel3 = (u[2][centre] - u3_exact).abs() / u3_exact.abs();
    assert!(
        rel3 < 5e-3,
        "u3(0) = {:e} vs {u3_exact:e} ({rel3:e})",
        u[2][centre]
    );
    let (ur_exact, _) = mindlin_cheng_surface(4.0, depth, e, NU);
    let at4 = (64 + 4) * 128 + 64;
    let rel1 = (u[0][at4] - ur_exact).abs() / ur_exact;
    assert!(
        rel1 < 5e-3,
        "u1(4) = {:e} vs {ur_exact:e} ({rel1:e})",
        u[0][at4]
    );
}

/// `∫p_c dA / (E e V)` for the unit nucleus at depth 8.5 under an `n × n` surface of unit cells.
fn correction_pressure_integral(n: usize) -> f64 {
    let fields = nucleus_fields(n);
    fields.correction_pressure().iter().sum::<f64>() * fields.grid().cell_area() / (E * NUCLEUS.0)
}

#[test]
fn correction_pressure_integral_vanishes_as_the_domain_grows() {
    // p_c ~ r⁻³, so the truncated integral decays like 1/L: halves when the domain doubles.
    // docs/theory-sam.md#kernel-reference-values: −0.01 eV at ±128 (depth 8); here at ±16 … ±128.
    let values: Vec<f64> = [32, 64, 128, 256]
        .iter()
        .map(|&n| correction_pressure_integral(n))
        .collect();
    let ratios: Vec<f64> = values.windows(2).map(|w| w[0] / w[1]).collect();
    // Ratios 1.59, 1.88, ≈ 1.95: tending to 2 (the 1/L tail) once L ≫ depth.
    assert!(ratios.windows(2).all(|r| r[1] > r[0]), "{values:?}");
    assert!((1.85..2.1).contains(&ratios[2]), "{values:?}");
    assert!(values[3].abs() < 0.012, "{values:?}");
}

#[test]
fn bad_inhomogeneities_are_refused_with_the_reason() {
    let grid = SurfaceGrid::square(16, 16.0).unwrap();
    let sphere = |z: f64, r: f64, e: f64, nu: f64| Inhomogeneity {
        shape: Shape::Sphere {
            x: 0.0,
            y: 0.0,
            z,
            r,
        },
        e,
        nu,
    };
    let msg = |list: &[Inhomogeneity]| InclusionSet::new(&grid, list).unwrap_err().to_string();
    assert!(msg(&[sphere(4.0, -1.0, 1.0, 0.3)]).contains("size"));
    assert!(msg(&[sphere(-4.0, 1.0, 1.0, 0.3)]).contains("above the surface"));
    assert!(msg(&[sphere(4.0, 1.0, 1.0, 0.5)]).contains("Poisson"));
    assert!(msg(&[sphere(4.0, 1.0, -1.0, 0.3)]).contains("Young"));
    assert!(msg(&[sphere(1.0, 2.0, 1.0, 0.3)]).contains("cuts the surface"));
    assert!(msg(&[sphere(1.2, 1.0, 1.0, 0.3)]).contains("first layer"));
    let far = Inhomogeneity {
        shape: Shape::Sphere {
            x: 7.5,
            y: 0.0,
            z: 4.0,
            r: 1.0,
        },
        e: 1.0,
        nu: 0.3,
    };
    assert!(msg(&[far]).contains("domain"));
    let overlap = [sphere(4.0, 2.0, 1.0, 0.3), sphere(4.5, 2.0, 2.0, 0.3)];
    assert!(msg(&overlap).contains("overlapping"));
    // Same material may overlap; a cylinder along y through the domain is fine.
    let same = [sphere(4.0, 2.0, 1.0, 0.3), sphere(4.5, 2.0, 1.0, 0.3)];
    assert!(InclusionSet::new(&grid, &same).is_ok());
    let fibre = Inhomogeneity {
        shape: Shape::Cylinder {
            axis: Axis::Y,
            position: 0.0,
            z: 4.0,
            r: 1.5,
        },
        e: 2.0,
        nu: 0.3,
    };
    let set = InclusionSet::new(&grid, &[fibre]).unwrap();
    assert_eq!(
        set.len() % 16,
        0,
        "a fibre has the same section in every row"
    );
    let tiny = sphere(4.0, 0.1, 1.0, 0.3);
    assert!(msg(&[tiny]).contains("no cell"));
    // Voids are accepted (E = 0).
    assert!(InclusionSet::new(&grid, &[sphere(4.0, 1.0, 0.0, 0.3)]).is_ok());
}

#[test]
fn voids_solve_by_gmres_and_block_jacobi_reports_divergence() {
    // E_I = 0: docs/theory-sam.md#solving-the-eim-equations — block Jacobi's spectral radius is 1.54 (diverges), GMRES is slow but
    // converges; neither hangs.
    let err = eshelby_sphere(3, 0.0, EimMethod::BlockJacobi).unwrap_err();
    // Reported as soon as the steps have grown a thousandfold, not at the iteration limit.
    assert!(
        matches!(err, SamError::NoConvergence { iterations, .. } if iterations < 200),
        "{err}"
    );
    let (void, _, it, _) = eshelby_sphere(3, 0.0, EimMethod::Gmres).unwrap();
    assert!(
        void.iter().all(|s| s.abs() < 1e-12),
        "stress in a void: {void:?} ({it} it)"
    );
    assert!(err.to_string().contains("did not converge"));
}

/// The EIM operators take the compact storages (docs/performance.md, "The difference family's
/// real spectra and the per-pass fields"): on a contiguous stack the volume's difference family is
/// stored real, and the surface and Love spectra by quarter, each dropping only rounding (the
/// strain kernels' tabulation is even or odd in `x₃` to ≈ 1e-12 of a block's largest value at
/// 64²–128²; the quarters drop the 2D FFT's rounding). A kernel change that broke either would fall
/// back to the complex spectra silently (same results, twice the bytes): this pins it. Observed
/// here (16², 4 layers): real 3.9e-14, quarter 9.2e-16.
#[test]
fn the_eim_operators_store_real_and_quarter_spectra() {
    let grid = SurfaceGrid::square(16, 16.0).unwrap();
    let layers = [1usize, 2, 3, 4];
    let f = EimFields::new(
        grid,
        E,
        NU,
        &layers,
        &layers,
        Window::full(&grid),
        Space::HalfSpace,
        Backend::Fft,
    )
    .unwrap();
    let real = f
        .real_storage_discarded()
        .expect("difference family stored real");
    let quarter = f
        .quarter_storage_discarded()
        .expect("surface and Love by quarter");
    assert!(real < 1e-11, "{real:e}");
    assert!(quarter < 1e-13, "{quarter:e}");
}

/// `(apply(x), rhs(applied), P⁻¹ x)` of `sys`.
fn per_cell_outputs(sys: &mut EimSystem, x: &[f64], applied: &[Vec<f64>]) -> [Vec<f64>; 3] {
    let n = sys.dim();
    let (mut y, mut b, mut z) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    sys.apply(x, &mut y).unwrap();
    sys.rhs(applied, &mut b).unwrap();
    sys.preconditioner().clone().apply(x, &mut z).unwrap();
    [y, b, z]
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The per-cell loops of the EIM (the right-hand side, the restriction of `A`, the block
/// preconditioner: tasks of 2048 cells on the pool) and the scatter of the eigenstrains (layer by
/// layer on the pool, or on one thread when the cells are not listed layer by layer), on two
/// thread: a stiff and a soft sphere of 2 × 2145 = 4290 cells (three tasks at the default size)
/// give the same bits split into tasks of 7 cells, of 2048 (the default) and as one task; the
/// restriction and the right-hand side are the cell-by-cell formulas `C^m x − ΔC ε(x)` (`ε` the
/// disturbance strain of [`EimSystem::disturbance`]) and `ΔC ε⁰`; the same cells listed in
/// reverse (every layer's cells apart: the scatter on one thread) give the same values, cell for
/// cell.
#[test]
fn per_cell_tasks_and_the_serial_scatter_give_the_same_bits() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    pool.install(per_cell_tasks_check);
}

fn per_cell_tasks_check() {
    let r = 8.0;
    let grid = SurfaceGrid::square(40, 40.0).unwrap();
    let sphere = |x: f64, ratio: f64| Inhomogeneity {
        shape: Shape::Sphere {
            x,
            y: 0.0,
            z: r + 2.0,
            r,
        },
        e: ratio * E,
        nu: 0.25,
    };
    let set = InclusionSet::new(&grid, &[sphere(-r - 1.0, 3.0), sphere(r + 1.0, 0.4)]).unwrap();
    assert!(set.len() > 2 * 2048, "{} cells", set.len());
    assert_eq!(set.materials.len(), 2);
    let system = |set: &InclusionSet| {
        let fields = EimFields::for_inclusions(grid, E, NU, set).unwrap();
        EimSystem::new(fields, set.clone(), E, NU).unwrap()
    };
    let mut sys = system(&set);
    assert!(sys.scatters_by_layer());
    let x = lcg(31, sys.dim());
    let applied: Vec<Vec<f64>> = (0..6 * set.layers.len())
        .map(|k| lcg(100 + k as u64, set.window.len()))
        .collect();
    sys.set_cells_per_task(usize::MAX);
    let whole = per_cell_outputs(&mut sys, &x, &applied);
    for task in [7, 2048] {
        sys.set_cells_per_task(task);
        let split = per_cell_outputs(&mut sys, &x, &applied);
        for (a, b) in split.iter().zip(&whole) {
            assert_eq!(bits(a), bits(b), "tasks of {task} cells");
        }
    }
    // The formulas, cell by cell.
    let cm = stiffness(E, NU);
    let dc: Vec<[[f64; 6]; 6]> = set
        .materials
        .iter()
        .map(|&(e, nu)| {
            let ci = stiffness(e, nu);
            let mut d = [[0.0; 6]; 6];
            for i in 0..6 {
                for j in 0..6 {
                    d[i][j] = cm[i][j] - ci[i][j];
                }
            }
            d
        })
        .collect();
    let strain = sys.disturbance(&x).unwrap().to_vec();
    for (c, cell) in set.cells.iter().enumerate() {
        let at = |fields: &[Vec<f64>]| {
            let mut v = [0.0; 6];
            for o in 0..6 {
                v[o] = fields[cell.layer * 6 + o][cell.local];
            }
            v
        };
        let xc: [f64; 6] = x[6 * c..6 * c + 6].try_into().unwrap();
        let (a, d) = (mul6(&cm, &xc), mul6(&dc[cell.material], &at(&strain)));
        let b = mul6(&dc[cell.material], &at(&applied));
        for o in 0..6 {
            assert_eq!((a[o] - d[o]).to_bits(), whole[0][6 * c + o].to_bits());
            assert_eq!(b[o].to_bits(), whole[1][6 * c + o].to_bits());
        }
    }
    // The cells in reverse: the scatter on one thread, the same values per cell.
    let mut reversed = set.clone();
    reversed.cells.reverse();
    let mut serial = system(&reversed);
    assert!(!serial.scatters_by_layer());
    let m = set.len();
    let flip = |v: &[f64]| -> Vec<f64> {
        (0..m)
            .rev()
            .flat_map(|c| v[6 * c..6 * c + 6].to_vec())
            .collect()
    };
    for task in [7, 2048] {
        serial.set_cells_per_task(task);
        let out = per_cell_outputs(&mut serial, &flip(&x), &applied);
        for (a, b) in out.iter().zip(&whole) {
            assert_eq!(bits(a), bits(&flip(b)), "reversed cells, tasks of {task}");
        }
    }
}

/// The block preconditioner the system keeps (and lends by reference, no copy) is `P⁻¹`,
/// `P_I = C^m − ΔC_I S₀` (`S₀` the cube's strain kernel at its centre, `ΔC = C^m − C^I`; module
/// documentation of `eim::solve`): rebuilt here from the stiffnesses and the kernel, `P_I (P⁻¹ x)_I`
/// is `x_I` in every cell to rounding (`|x| ≤ 0.5`; the LU's backward error plus the 6-term
/// products, `~6 ε ‖P‖ ‖P⁻¹x‖` with both norms of order 1–10: ≲ 1e-14; measured 1.7e-16); and solves of either method,
/// which move it out of the system and back, leave the same operator (the same bits of `P⁻¹ x`).
#[test]
fn the_kept_block_preconditioner_inverts_the_blocks_and_survives_solves() {
    use halfspace_sam::kernels::cuboid::StrainPotentials;
    let (grid, set) = small_sphere();
    let fields = EimFields::for_inclusions(grid, E, NU, &set).unwrap();
    let mut sys = EimSystem::new(fields, set.clone(), E, NU).unwrap();
    let n = sys.dim();
    let x = lcg(500, n);
    let mut z = vec![0.0; n];
    sys.preconditioner().clone().apply(&x, &mut z).unwrap();
    let cm = stiffness(E, NU);
    let s0 = StrainPotentials::new([0.0; 3], [set.half; 3]).voigt(NU);
    let mut worst = 0.0f64;
    for (c, cell) in set.cells.iter().enumerate() {
        let (ei, nui) = set.materials[cell.material];
        let ci = stiffness(ei, nui);
        let mut p = [[0.0; 6]; 6];
        for i in 0..6 {
            for j in 0..6 {
                let ds0: f64 = (0..6).map(|k| (cm[i][k] - ci[i][k]) * s0[k][j]).sum();
                p[i][j] = cm[i][j] - ds0;
            }
        }
        let back = mul6(&p, &z[6 * c..6 * c + 6]);
        for (b, v) in back.iter().zip(&x[6 * c..6 * c + 6]) {
            worst = worst.max((b - v).abs());
        }
    }
    assert!(worst < 1e-14, "max |P (P⁻¹x) − x| = {worst:e}");
    let applied: Vec<Vec<f64>> = (0..set.layers.len() * 6)
        .map(|k| lcg(600 + k as u64, set.window.len()))
        .collect();
    for method in [EimMethod::BlockJacobi, EimMethod::Gmres] {
        let params = EimParams {
            method,
            ..EimParams::default()
        };
        let mut eps = vec![0.0; n];
        sys.solve(&applied, &mut eps, &params).unwrap();
        let mut after = vec![0.0; n];
        sys.preconditioner().clone().apply(&x, &mut after).unwrap();
        assert_eq!(bits(&after), bits(&z), "{method:?}");
    }
}

/// A solve interrupted by a panic in an operator application (the test hook
/// `EimSystem::panic_at_next_application`) leaves a system that solves again: the kept
/// preconditioner is put back (before, it was left out of the system and the next solve failed
/// with a length error), and the next solves on both methods give the bits of an uninterrupted
/// system's.
#[test]
fn a_solve_interrupted_by_a_panic_leaves_a_system_that_solves() {
    let (grid, set) = small_sphere();
    let applied: Vec<Vec<f64>> = (0..set.layers.len() * 6)
        .map(|k| lcg(700 + k as u64, set.window.len()))
        .collect();
    let system = || {
        let fields = EimFields::for_inclusions(grid, E, NU, &set).unwrap();
        EimSystem::new(fields, set.clone(), E, NU).unwrap()
    };
    let (mut interrupted, mut control) = (system(), system());
    let n = control.dim();
    let x = lcg(710, n);
    // P⁻¹x by the system's kept preconditioner.
    let kept_preconditioner_of = |sys: &EimSystem| {
        let mut y = vec![0.0; n];
        sys.preconditioner().clone().apply(&x, &mut y).unwrap();
        y
    };
    let before = kept_preconditioner_of(&control);
    for method in [EimMethod::BlockJacobi, EimMethod::Gmres] {
        let params = EimParams {
            method,
            tolerance: 1e-10,
            ..EimParams::default()
        };
        interrupted.panic_at_next_application();
        let mut eps = vec![0.0; n];
        let caught = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            interrupted.solve(&applied, &mut eps, &params)
        }));
        assert!(caught.is_err(), "{method:?}: the hook did not panic");
        let kept = kept_preconditioner_of(&interrupted);
        assert_eq!(bits(&kept), bits(&before), "{method:?}");
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        let ia = interrupted.solve(&applied, &mut a, &params).unwrap();
        let ib = control.solve(&applied, &mut b, &params).unwrap();
        assert_eq!(ia.iterations, ib.iterations, "{method:?}");
        assert_eq!(bits(&a), bits(&b), "{method:?}");
    }
}

/// Plain block Jacobi (`EimParams::recycled_depth = 0`) on the work vectors the system keeps
/// between solves is the iteration on vectors allocated per solve (`richardson_mixed` without a
/// recycled state, the path before the system kept them) bit for bit: the first solve, and a
/// second one from the same start on the now dirty vectors, each with its count.
#[test]
fn plain_block_jacobi_on_kept_work_vectors_is_the_allocating_iteration_bit_for_bit() {
    use halfspace_numerics::krylov::{richardson_mixed, KrylovParams};
    let (grid, set) = small_sphere();
    let fields = EimFields::for_inclusions(grid, E, NU, &set).unwrap();
    let mut sys = EimSystem::new(fields, set.clone(), E, NU).unwrap();
    let applied: Vec<Vec<f64>> = (0..set.layers.len() * 6)
        .map(|k| lcg(300 + k as u64, set.window.len()))
        .collect();
    let params = EimParams {
        method: EimMethod::BlockJacobi,
        tolerance: 1e-10,
        recycled_depth: 0,
        ..EimParams::default()
    };
    let n = sys.dim();
    let mut b = vec![0.0; n];
    sys.rhs(&applied, &mut b).unwrap();
    let mut control = vec![0.0; n];
    let kp = KrylovParams {
        tolerance: params.tolerance,
        max_iterations: params.max_iterations,
        restart: params.restart,
    };
    let mut pre = sys.preconditioner().clone();
    let k = richardson_mixed(&mut sys, &mut pre, &b, &mut control, &kp, None)
        .unwrap()
        .iterations;
    assert!(k > 3, "{k} applications");
    for _ in 0..2 {
        let mut x = vec![0.0; n];
        let info = sys.solve(&applied, &mut x, &params).unwrap();
        assert_eq!(info.iterations, k);
        assert_eq!(bits(&x), bits(&control));
    }
}

/// Public inputs that indexed out of bounds are refused with typed errors: an inclusion set
/// edited by hand (its fields are public) whose cell names a layer, window position, material or
/// grid index it does not have; eigenstrains or layer fields of the wrong size for
/// `EimSystem::disturbance`, `surface_disturbance` and `scatter`; a window field, grid field or
/// window outside the grid for `Window::scatter` and `gather_add`.
#[test]
fn hand_made_sets_and_mis_sized_fields_are_refused() {
    let (grid, set) = small_sphere();
    let fields = || EimFields::for_inclusions(grid, E, NU, &set).unwrap();
    set.check(&grid).unwrap();
    let last = set.len() - 1;
    for edit in [
        |c: &mut halfspace_sam::eim::Cell| c.layer += 100,
        |c: &mut halfspace_sam::eim::Cell| c.local += 10_000,
        |c: &mut halfspace_sam::eim::Cell| c.material += 1,
        |c: &mut halfspace_sam::eim::Cell| c.flat += 1,
    ] {
        let mut bad = set.clone();
        edit(&mut bad.cells[last]);
        let err = EimSystem::new(fields(), bad, E, NU).err().expect("refused");
        assert!(err.to_string().contains("inclusion set cell"), "{err}");
    }
    let mut sys = EimSystem::new(fields(), set.clone(), E, NU).unwrap();
    let n = sys.dim();
    let short = vec![0.0; n - 6];
    for err in [
        sys.disturbance(&short).expect_err("refused"),
        sys.surface_disturbance(&short).expect_err("refused"),
    ] {
        assert!(matches!(err, SamError::Numerics(_)), "{err}");
    }
    let wl = set.window.len();
    let mut layer_fields = vec![vec![0.0; wl]; 6 * set.layers.len()];
    assert!(sys.scatter(&short, &mut layer_fields).is_err());
    assert!(sys.scatter(&vec![0.0; n], &mut layer_fields[1..]).is_err());
    layer_fields[0].pop();
    assert!(sys.scatter(&vec![0.0; n], &mut layer_fields).is_err());
    layer_fields[0].push(0.0);
    sys.scatter(&lcg(3, n), &mut layer_fields).unwrap();
    // Window fields.
    let w = set.window;
    let mut full = vec![0.0; grid.len()];
    let mut local = vec![0.0; wl];
    assert!(w.scatter(&grid, &local[1..], &mut full).is_err());
    assert!(w.scatter(&grid, &local, &mut full[1..]).is_err());
    assert!(w.gather_add(&grid, &full, &mut local[1..]).is_err());
    let outside = Window {
        i0: grid.n1 - 1,
        ..w
    };
    assert!(outside.scatter(&grid, &local, &mut full).is_err());
    assert!(outside.gather_add(&grid, &full, &mut local).is_err());
    w.scatter(&grid, &local, &mut full).unwrap();
    w.gather_add(&grid, &full, &mut local).unwrap();
}
