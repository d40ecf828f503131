//! Critical-plane search against brute force and closed forms (docs/fatigue.md, "Checks").
#![allow(clippy::needless_range_loop)]
mod common;

use common::{proportional_cycle, random_cycle, rotate_path, steel, Rng};
use halfspace_fatigue::critical_plane::*;
use halfspace_fatigue::tensor::Voigt;
use halfspace_fatigue::{FatigueError, Material};
use proptest::prelude::*;

fn angle_between_planes(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    let d = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]).abs().min(1.0);
    d.acos()
}

/// A very fine search: the reference the default search is measured against.
fn fine_params() -> CriticalPlaneParams {
    CriticalPlaneParams {
        coarse_normals: 20_000,
        coarse_directions: 90,
        candidates: 16,
        angular_tolerance: 1e-9,
    }
}

#[test]
fn diameter_matches_brute_force() {
    let mut rng = Rng::new(2230);
    let mut hull = Vec::new();
    for trial in 0..3000 {
        let n = 1 + trial % 70;
        let mut pts: Vec<[f64; 2]> = (0..n)
            .map(|_| [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)])
            .collect();
        match trial % 5 {
            // Collinear points.
            1 => pts.iter_mut().for_each(|p| p[1] = 0.3 * p[0] + 0.1),
            // Duplicates.
            2 => {
                let k = pts.len();
                for i in 0..k {
                    pts.push(pts[i]);
                }
            }
            // Points on a circle (all on the hull).
            3 => pts.iter_mut().enumerate().for_each(|(i, p)| {
                let t = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
                *p = [t.cos(), t.sin()];
            }),
            _ => {}
        }
        let (want, _) = diameter_brute_force(&pts);
        let (got, d) = diameter(&mut pts, &mut hull);
        assert!(
            (got - want).abs() <= 1e-12 * want,
            "{trial}: {got} vs {want}"
        );
        assert!((d[0] * d[0] + d[1] * d[1] - got).abs() <= 1e-14 * want.max(1e-300));
    }
}

/// The filtered diameter (above 64 points) is all pairs' result bit for bit (pair and sign too)
/// wherever the filter leaves at most 64 points, else the hull's bit for bit; in both cases the
/// all-pairs value to the hull's 1e-12. Thin loops like fretting cycles' shear paths (65–300
/// points) always take the first branch; uniform clouds, circles (nothing filtered), collinear
/// and duplicated points are covered too (fixed seeds).
#[test]
fn filtered_diameter_matches_brute_force_and_hull() {
    let mut rng = Rng::new(2232);
    let mut kept = Vec::new();
    let mut hull = Vec::new();
    let (mut by_pairs, mut by_hull) = (0, 0);
    for trial in 0..2000 {
        let n = 65 + trial % 236;
        let kind = trial % 6;
        let mut pts: Vec<[f64; 2]> = match kind {
            // A thin loop: an ellipse of aspect 1:20 at a random angle, noisy, off-centre.
            0 | 1 => {
                let (a, b) = (rng.range(0.5, 2.0), rng.range(0.0, 0.1));
                let phi = rng.range(0.0, std::f64::consts::PI);
                let (s, c) = phi.sin_cos();
                let centre = [rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)];
                (0..n)
                    .map(|i| {
                        let t = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
                        let (x, y) = (a * t.cos(), b * (2.0 * t).sin() + 0.01 * rng.normal());
                        [centre[0] + c * x - s * y, centre[1] + s * x + c * y]
                    })
                    .collect()
            }
            // Collinear (a proportional path).
            2 => {
                let slope = rng.range(-3.0, 3.0);
                (0..n)
                    .map(|_| {
                        let x = rng.range(-1.0, 1.0);
                        [x, slope * x + 0.2]
                    })
                    .collect()
            }
            // On a circle: the filter keeps every point.
            3 => (0..n)
                .map(|i| {
                    let t = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
                    [t.cos(), t.sin()]
                })
                .collect(),
            // Duplicated points.
            4 => {
                let half: Vec<[f64; 2]> = (0..n / 2 + 1)
                    .map(|_| [rng.range(-1.0, 1.0), rng.range(-0.2, 0.2)])
                    .collect();
                half.iter().chain(half.iter()).copied().collect()
            }
            _ => (0..n)
                .map(|_| [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)])
                .collect(),
        };
        let all_pairs = diameter_brute_force(&pts);
        let mut sorted = pts.clone();
        let by_the_hull = diameter_hull(&mut sorted, &mut hull);
        let got = diameter_filtered(&mut pts, &mut kept);
        let bits = |d: (f64, [f64; 2])| (d.0.to_bits(), d.1.map(f64::to_bits));
        if bits(got) == bits(all_pairs) {
            by_pairs += 1;
        } else {
            assert_eq!(bits(got), bits(by_the_hull), "{trial}: neither twin");
            by_hull += 1;
        }
        assert!(
            (got.0 - all_pairs.0).abs() <= 1e-12 * all_pairs.0,
            "{trial}: {} vs {}",
            got.0,
            all_pairs.0
        );
        if kind <= 2 {
            assert_eq!(
                bits(got),
                bits(all_pairs),
                "{trial}: a thin path took the hull"
            );
        }
        // `diameter` above 64 points is the filtered one.
        let mut again = pts.clone();
        assert_eq!(bits(diameter(&mut again, &mut hull)), bits(got));
    }
    assert!(by_pairs >= 1000 && by_hull >= 300, "{by_pairs} / {by_hull}");
}

/// Coordinates whose squared distances overflow (≈ 1e160) make the filter's cut-off non-finite:
/// the filter keeps every point instead of dropping them all (a diameter of 0 before the fix).
#[test]
fn filtered_diameter_keeps_every_point_when_the_cut_off_overflows() {
    let mut pts: Vec<[f64; 2]> = (0..80)
        .map(|i| {
            let t = 2.0 * std::f64::consts::PI * i as f64 / 80.0;
            [1e160 * t.cos(), 1e159 * t.sin()]
        })
        .collect();
    let mut kept = Vec::new();
    let got = diameter_filtered(&mut pts, &mut kept);
    // 80 points kept take the hull (which reuses `kept` as its scratch); dropping them all gave 0.
    // The squared diameter itself overflows, as all pairs say.
    assert_eq!(got.0, f64::INFINITY, "diameter {}", got.0);
    assert_eq!(got.0, diameter_brute_force(&pts).0);
    // Just below the overflow (squares ≈ 4e300) the filter cuts and the diameter is exact: the
    // x extent's 2e150, along ±x.
    let mut pts: Vec<[f64; 2]> = (0..80)
        .map(|i| {
            let t = 2.0 * std::f64::consts::PI * i as f64 / 80.0;
            [1e150 * t.cos(), 1e149 * t.sin()]
        })
        .collect();
    let (want, _) = diameter_brute_force(&pts);
    let (got, d) = diameter_filtered(&mut pts, &mut kept);
    assert!(
        want.is_finite() && (got - want).abs() <= 1e-12 * want,
        "{got} vs {want}"
    );
    assert!((got - 4e300).abs() <= 1e-12 * 4e300 && d[1].abs() <= 1e-12 * d[0].abs());
}

/// The exact in-plane maximum of Fatemi–Socie equals a fine scan of directions.
#[test]
fn fatemi_socie_in_plane_direction_is_exact() {
    let mut rng = Rng::new(2231);
    let m = steel();
    let g = m.shear_modulus();
    for _ in 0..100 {
        let path = random_cycle(&mut rng, 40, 1e8, 1e8);
        let n: [f64; 3] = {
            let g3: [f64; 3] = std::array::from_fn(|_| rng.normal());
            let l = (g3[0] * g3[0] + g3[1] * g3[1] + g3[2] * g3[2]).sqrt();
            g3.map(|x| x / l)
        };
        let fs = fatemi_socie_on_plane(&path, &m, &n).unwrap();
        let (u, v) = tangent_basis(&n);
        let mut scan: f64 = 0.0;
        for j in 0..20_000 {
            let psi = std::f64::consts::PI * j as f64 / 20_000.0;
            let dir: [f64; 3] = std::array::from_fn(|k| psi.cos() * u[k] + psi.sin() * v[k]);
            let w = halfspace_fatigue::tensor::bilinear_weights(&dir, &n);
            let (lo, hi) = path
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                    let t = halfspace_fatigue::tensor::dot6(&w, s);
                    (lo.min(t), hi.max(t))
                });
            scan = scan.max(0.5 * (hi - lo) / g);
        }
        let ga = fs.shear_strain_amplitude;
        assert!(ga >= scan * (1.0 - 1e-14), "{ga} < {scan}");
        // Grid step π/20000: cos(π/40000) = 1 − 3e-9.
        assert!(ga <= scan * (1.0 + 1e-8), "{ga} vs {scan}");
        // The direction is in the plane and attains γ_a.
        let dn: f64 = (0..3).map(|k| fs.direction[k] * n[k]).sum();
        assert!(dn.abs() < 1e-12);
        let w = halfspace_fatigue::tensor::bilinear_weights(&fs.direction, &n);
        let (lo, hi) = path
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                let t = halfspace_fatigue::tensor::dot6(&w, s);
                (lo.min(t), hi.max(t))
            });
        let along = 0.5 * (hi - lo) / g;
        assert!(
            (along - ga).abs() <= 1e-12 * ga,
            "γ_a {ga}, along the direction {along}"
        );
    }
}

fn uniaxial(amp: f64) -> Vec<Voigt> {
    proportional_cycle([0.0; 6], [amp, 0.0, 0.0, 0.0, 0.0, 0.0], 40)
}

fn torsion(amp: f64) -> Vec<Voigt> {
    proportional_cycle([0.0; 6], [0.0, 0.0, 0.0, 0.0, 0.0, amp], 40)
}

/// Uniaxial fully reversed σ_a: SWT = σ_a²/E on n = the axis; pure torsion τ_a: SWT = τ_a²(1+ν)/E
/// on the 45° planes; Fatemi–Socie with k = 0: τ_a/G on the shear planes; with k > 0 the plane
/// tilts by u/2 and FS = (τ_a/G) cos u (1 + c sin u), c = kτ_a/σ_y, sin u = (√(1+8c²) − 1)/(4c).
/// In random frames.
#[test]
fn closed_forms() {
    let mut rng = Rng::new(2232);
    let m = steel();
    let p = CriticalPlaneParams::default();
    let mut s = PlaneScratch::default();
    let (mut worst_value, mut worst_angle) = (0.0f64, 0.0f64);
    for _ in 0..20 {
        let r = rng.rotation();
        // σ' = R σ Rᵀ: the image of the axis e_i is the column i of R.
        let col = |i: usize| -> [f64; 3] { std::array::from_fn(|k| r[k][i]) };
        let axis = col(0);
        let (sa, ta) = (250e6, 180e6);
        let swt_u = swt(&rotate_path(&uniaxial(sa), &r), &m, &p, &mut s).unwrap();
        worst_value =
            worst_value.max((swt_u.value - sa * sa / m.young).abs() / (sa * sa / m.young));
        worst_angle = worst_angle.max(angle_between_planes(&swt_u.normal, &axis));
        let tor = rotate_path(&torsion(ta), &r);
        let swt_t = swt(&tor, &m, &p, &mut s).unwrap();
        let want = ta * ta * (1.0 + m.poisson) / m.young;
        worst_value = worst_value.max((swt_t.value - want).abs() / want);
        // 45° between x and y in the rotated frame.
        let diag: [f64; 3] = std::array::from_fn(|k| (r[k][0] + r[k][1]) / 2f64.sqrt());
        let anti: [f64; 3] = std::array::from_fn(|k| (r[k][0] - r[k][1]) / 2f64.sqrt());
        worst_angle = worst_angle.max(
            angle_between_planes(&swt_t.normal, &diag)
                .min(angle_between_planes(&swt_t.normal, &anti)),
        );
        let m0 = Material { fs_k: 0.0, ..m };
        let fs0 = fatemi_socie(&tor, &m0, &p, &mut s).unwrap();
        let want = ta / m.shear_modulus();
        worst_value = worst_value.max((fs0.value - want).abs() / want);
        worst_angle = worst_angle.max(
            angle_between_planes(&fs0.normal, &col(0))
                .min(angle_between_planes(&fs0.normal, &col(1))),
        );
        assert!(fs0.normal_stress_max.abs() < 1e-4 * ta);
        let fs = fatemi_socie(&tor, &m, &p, &mut s).unwrap();
        let c = m.fs_k * ta / m.yield_stress;
        let su = ((1.0 + 8.0 * c * c).sqrt() - 1.0) / (4.0 * c);
        let want = ta / m.shear_modulus() * (1.0 - su * su).sqrt() * (1.0 + c * su);
        worst_value = worst_value.max((fs.value - want).abs() / want);
        let half = 0.5 * su.asin();
        let tilted: Vec<[f64; 3]> = [
            (half, 0usize, 1usize),
            (-half, 0, 1),
            (half, 1, 0),
            (-half, 1, 0),
        ]
        .iter()
        .map(|&(a, i, j)| std::array::from_fn(|k| a.cos() * r[k][i] + a.sin() * r[k][j]))
        .collect();
        worst_angle = worst_angle.max(
            tilted
                .iter()
                .map(|t| angle_between_planes(&fs.normal, t))
                .fold(f64::INFINITY, f64::min),
        );
    }
    eprintln!("closed forms: worst relative value error {worst_value:.2e}, worst plane angle {worst_angle:.2e} rad");
    // Smooth maxima 1 − 2θ² (cos⁴θ, cos 2θ): an angle error θ ≤ 1.5 × tolerance (1e-4 rad)
    // costs at most 2θ² = 4.5e-8.
    assert!(worst_value < 4.5e-8, "{worst_value}");
    assert!(worst_angle < 2e-4, "{worst_angle}");
}

struct Comparison {
    below_reference: f64,
    above_grid: f64,
}

fn compare(path: &[Voigt], m: &Material, step: f64) -> (Comparison, Comparison) {
    let mut s = PlaneScratch::default();
    let d = CriticalPlaneParams::default();
    let swt_d = swt(path, m, &d, &mut s).unwrap();
    let swt_f = swt(path, m, &fine_params(), &mut s).unwrap();
    let swt_b = swt_brute_force(path, m, step).unwrap();
    let fs_d = fatemi_socie(path, m, &d, &mut s).unwrap();
    let fs_f = fatemi_socie(path, m, &fine_params(), &mut s).unwrap();
    let fs_b = fatemi_socie_brute_force(path, m, step).unwrap();
    let rel = |a: f64, b: f64| (a - b) / b.abs();
    let swt_ref = swt_f.value.max(swt_b.value);
    let fs_ref = fs_f.value.max(fs_b.value);
    (
        Comparison {
            below_reference: rel(swt_ref, swt_d.value),
            above_grid: rel(swt_d.value, swt_b.value),
        },
        Comparison {
            below_reference: rel(fs_ref, fs_d.value),
            above_grid: rel(fs_d.value, fs_b.value),
        },
    )
}

/// Random and proportional paths: the default search against a brute-force grid of 0.25° and a
/// very fine search (20 000 normals, 16 candidates, 1e-9 rad); the reference is the larger.
#[test]
fn search_matches_brute_force() {
    let mut rng = Rng::new(2233);
    let m = steel();
    let step = 0.25f64.to_radians();
    let mut worst = [0.0f64; 2];
    let mut worst_grid = [f64::INFINITY; 2];
    for trial in 0..12 {
        let path = if trial % 3 == 2 {
            let mean: Voigt = std::array::from_fn(|_| rng.range(-1e8, 1e8));
            let a: Voigt = std::array::from_fn(|_| rng.range(-2e8, 2e8));
            proportional_cycle(mean, a, 40)
        } else {
            random_cycle(&mut rng, 40, 1e8, 1e8)
        };
        let (sw, fs) = compare(&path, &m, step);
        for (k, c) in [sw, fs].iter().enumerate() {
            worst[k] = worst[k].max(c.below_reference);
            worst_grid[k] = worst_grid[k].min(c.above_grid);
        }
    }
    eprintln!(
        "critical plane, default search: SWT at most {:.2e} below the reference, FS {:.2e}; \
         vs the 0.25° grid: SWT ≥ grid·(1 {:+.2e}), FS ≥ grid·(1 {:+.2e})",
        worst[0], worst[1], worst_grid[0], worst_grid[1]
    );
    // SWT: a smooth local maximum, found to the angular tolerance (1e-4 rad ⇒ ~1e-8). FS is a
    // maximum over increment pairs: nearby local maxima (0.03–0.06 rad apart, values within
    // 2e-4) exist and the default search may stop on the lower one — 1.4e-4 worst over 120
    // paths (search_accuracy_survey; docs/fatigue.md, "Accuracy of the critical-plane search").
    assert!(worst[0] < 1e-7, "{worst:?}");
    assert!(worst[1] < 5e-4, "{worst:?}");
    assert!(
        worst_grid[0] > -1e-12 && worst_grid[1] > -1e-12,
        "{worst_grid:?}"
    );
}

/// The same on cycles of 81 increments — the fretting loop's 4q + 1 — where the phase-2 pair
/// screening (`PAIR_SCREEN_UP_TO`) replaces the hull above `DIAMETER_PAIRS_UP_TO` = 64.
#[test]
fn search_matches_brute_force_on_the_loops_81_increments() {
    let mut rng = Rng::new(8181);
    let m = steel();
    let step = 0.25f64.to_radians();
    let mut worst = [0.0f64; 2];
    let mut worst_grid = [f64::INFINITY; 2];
    for trial in 0..4 {
        let path = if trial == 3 {
            let mean: Voigt = std::array::from_fn(|_| rng.range(-1e8, 1e8));
            let a: Voigt = std::array::from_fn(|_| rng.range(-2e8, 2e8));
            proportional_cycle(mean, a, 81)
        } else {
            random_cycle(&mut rng, 81, 1e8, 1e8)
        };
        assert_eq!(path.len(), 81);
        let (sw, fs) = compare(&path, &m, step);
        for (k, c) in [sw, fs].iter().enumerate() {
            worst[k] = worst[k].max(c.below_reference);
            worst_grid[k] = worst_grid[k].min(c.above_grid);
        }
    }
    eprintln!(
        "81 increments: SWT at most {:.2e} below the reference, FS {:.2e}; vs the 0.25° grid: \
         SWT ≥ grid·(1 {:+.2e}), FS ≥ grid·(1 {:+.2e})",
        worst[0], worst[1], worst_grid[0], worst_grid[1]
    );
    assert!(worst[0] < 1e-7, "{worst:?}");
    assert!(worst[1] < 5e-4, "{worst:?}");
    assert!(
        worst_grid[0] > -1e-12 && worst_grid[1] > -1e-12,
        "{worst_grid:?}"
    );
}

#[test]
fn search_errors() {
    let m = steel();
    let path = uniaxial(1e8);
    let mut s = PlaneScratch::default();
    let bad = CriticalPlaneParams {
        angular_tolerance: 0.0,
        ..Default::default()
    };
    assert!(matches!(
        swt(&path, &m, &bad, &mut s),
        Err(FatigueError::InvalidSearch {
            name: "angular_tolerance",
            ..
        })
    ));
    let bad = CriticalPlaneParams {
        coarse_normals: 3,
        ..Default::default()
    };
    assert!(matches!(
        fatemi_socie(&path, &m, &bad, &mut s),
        Err(FatigueError::InvalidSearch {
            name: "coarse_normals",
            ..
        })
    ));
    assert!(matches!(
        fatemi_socie(
            &path,
            &Material {
                yield_stress: 0.0,
                ..m
            },
            &Default::default(),
            &mut s
        ),
        Err(FatigueError::InvalidMaterial {
            name: "yield_stress",
            ..
        })
    ));
    assert_eq!(
        swt(&[], &m, &Default::default(), &mut s).unwrap_err(),
        FatigueError::EmptyPath
    );
    // A constant path: no amplitude, zero on every plane.
    let c = swt(
        &[[1e8, 2e7, 0.0, 0.0, 3e7, 0.0]; 5],
        &m,
        &Default::default(),
        &mut s,
    )
    .unwrap();
    assert_eq!(c.value, 0.0);
    let c = fatemi_socie(
        &[[1e8, 2e7, 0.0, 0.0, 3e7, 0.0]; 5],
        &m,
        &Default::default(),
        &mut s,
    )
    .unwrap();
    assert_eq!(c.value, 0.0);
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 32,
        // Fixed, so that CI replays the same 32 cases (RustFFT-style fixed seeds); the
        // tolerances below come from random seeds run outside CI.
        rng_seed: proptest::test_runner::RngSeed::Fixed(20_261_126),
        ..ProptestConfig::default()
    })]
    /// SWT and Fatemi–Socie are invariant under a rotation of the stress path. This checks the
    /// criteria, so it runs a dense search (4000 normals, 8 candidates, 1e-7 rad): the default
    /// search can stop on a nearby lower local maximum on some paths (proptest found SWT 1.7e-5
    /// and FS 1.8e-3 below; docs/fatigue.md, "Accuracy of the critical-plane search"). The dense
    /// search is still local: with random seeds the two frames' values differed by up to 3.8e-6
    /// relative (SWT) and 1.3e-4 (Fatemi–Socie, seed 467030: 1.85490e-3 vs 1.85514e-3) — a
    /// maximum reached from two different coarse normals — so invariance is asserted to 1e-5
    /// (SWT) and 5e-4 (FS), the dense search's accuracy, not the criteria's: a formula error (a
    /// missed factor, a wrong strain from Hooke's law) changes the value by O(1).
    #[test]
    fn rotation_invariance(seed in 0u64..1_000_000, g in prop::array::uniform9(-1.0f64..1.0)) {
        let mut rng = Rng::new(seed);
        let path = random_cycle(&mut rng, 40, 1e8, 1e8);
        let r = common::rotation_from(g);
        let rotated = rotate_path(&path, &r);
        let m = steel();
        let p = CriticalPlaneParams {
            coarse_normals: 4000,
            coarse_directions: 24,
            candidates: 8,
            angular_tolerance: 1e-7,
        };
        let mut s = PlaneScratch::default();
        let a = swt(&path, &m, &p, &mut s).unwrap();
        let b = swt(&rotated, &m, &p, &mut s).unwrap();
        prop_assert!((a.value - b.value).abs() <= 1e-5 * a.value.abs(), "{} {}", a.value, b.value);
        let a = fatemi_socie(&path, &m, &p, &mut s).unwrap();
        let b = fatemi_socie(&rotated, &m, &p, &mut s).unwrap();
        prop_assert!((a.value - b.value).abs() <= 5e-4 * a.value.abs(), "{} {}", a.value, b.value);
    }
}

/// The measurement behind docs/fatigue.md, "Accuracy of the critical-plane search": 120 paths
/// (random two-harmonic cycles and, every fourth, proportional ones), the default search against
/// the very fine one. Run with
/// `cargo test --release -p halfspace-fatigue --test critical_plane -- --ignored --nocapture`.
#[test]
#[ignore]
fn search_accuracy_survey() {
    let mut rng = Rng::new(99);
    let m = steel();
    let mut s = PlaneScratch::default();
    let d = CriticalPlaneParams::default();
    let (mut ws, mut wf) = (0.0f64, 0.0f64);
    let (mut misses, mut es, mut ef) = (0usize, 0usize, 0usize);
    let n = 120;
    for i in 0..n {
        let path = if i % 4 == 3 {
            let mean: Voigt = std::array::from_fn(|_| rng.range(-1e8, 1e8));
            let a: Voigt = std::array::from_fn(|_| rng.range(-2e8, 2e8));
            proportional_cycle(mean, a, 40)
        } else {
            random_cycle(&mut rng, 40, 1e8, 1e8)
        };
        let rs = swt(&path, &m, &fine_params(), &mut s).unwrap().value;
        let reference = fatemi_socie(&path, &m, &fine_params(), &mut s).unwrap();
        let rf = reference.value;
        let a = swt(&path, &m, &d, &mut s).unwrap();
        let b = fatemi_socie(&path, &m, &d, &mut s).unwrap();
        ws = ws.max((rs - a.value) / rs.abs());
        let gap = (rf - b.value) / rf.abs();
        if gap > 1e-7 {
            misses += 1;
            eprintln!(
                "path {i}: FS {gap:.1e} below the reference, {:.3} rad from its plane",
                angle_between_planes(&b.normal, &reference.normal)
            );
        }
        wf = wf.max(gap);
        es += a.evaluations;
        ef += b.evaluations;
    }
    eprintln!(
        "{n} paths: SWT at most {ws:.1e} below the reference ({} planes per search); FS at most \
         {wf:.1e} below ({misses} paths more than 1e-7 below; {} planes per search)",
        es / n,
        ef / n
    );
    assert!(ws < 1e-7 && wf < 5e-4);
}

/// A plane normal given by the caller: scaled to unit length (any positive multiple names the same
/// plane, also beyond the square's overflow), and refused when it is zero or not finite (returned
/// `+∞` / NaN before; review, stop 45).
#[test]
fn on_plane_criteria_check_the_normal() {
    let mut rng = Rng::new(2240);
    let m = steel();
    let path = random_cycle(&mut rng, 24, 1e8, 5e7);
    let unit = [0.6, 0.0, 0.8];
    let a = swt_on_plane(&path, &m, &unit).unwrap();
    let f = fatemi_socie_on_plane(&path, &m, &unit).unwrap();
    for scale in [1e-200, 3.0, 1e200] {
        let n = unit.map(|c| c * scale);
        let b = swt_on_plane(&path, &m, &n).unwrap();
        assert!(
            (a.value - b.value).abs() <= 1e-14 * a.value.abs(),
            "{scale}"
        );
        let g = fatemi_socie_on_plane(&path, &m, &n).unwrap();
        assert!(
            (f.value - g.value).abs() <= 1e-14 * f.value.abs(),
            "{scale}"
        );
    }
    for n in [[0.0; 3], [f64::NAN, 1.0, 0.0], [0.0, f64::INFINITY, 0.0]] {
        assert!(
            matches!(
                swt_on_plane(&path, &m, &n),
                Err(FatigueError::InvalidSearch { name: "normal", .. })
            ),
            "{n:?}"
        );
        assert!(
            matches!(
                fatemi_socie_on_plane(&path, &m, &n),
                Err(FatigueError::InvalidSearch { name: "normal", .. })
            ),
            "{n:?}"
        );
    }
}
