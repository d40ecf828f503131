//! Crossland and Dang Van: closed forms, invariances, errors (docs/fatigue.md, "Checks").
#![allow(clippy::needless_range_loop)]
mod common;

use common::{proportional_cycle, random_cycle, rotate_path, steel, Rng};
use halfspace_fatigue::invariant::{crossland_dang_van, InvariantScratch};
use halfspace_fatigue::tensor::{j2, Voigt};
use halfspace_fatigue::{FatigueError, Material};
use proptest::prelude::*;

fn uniaxial(amp: f64, n: usize) -> Vec<Voigt> {
    proportional_cycle([0.0; 6], [amp, 0.0, 0.0, 0.0, 0.0, 0.0], n)
}

fn torsion(amp: f64, n: usize) -> Vec<Voigt> {
    proportional_cycle([0.0; 6], [0.0, 0.0, 0.0, 0.0, 0.0, amp], n)
}

/// Fully reversed bending at f₋₁ and torsion at t₋₁ give exactly 1, in any frame, for every
/// admissible ratio t₋₁/f₋₁ (by construction of α_C, α_DV).
#[test]
fn unit_index_at_the_endurance_limits() {
    let mut rng = Rng::new(2220);
    let mut worst = 0.0f64;
    for ratio in [0.6, 0.65, 0.7, 0.8, 0.9, 1.0] {
        let m = Material {
            t_minus1: ratio * 400e6,
            ..steel()
        };
        // n = 4k increments so that sin reaches ±1 exactly.
        for path in [uniaxial(m.f_minus1, 40), torsion(m.t_minus1, 40)] {
            for _ in 0..5 {
                let rotated = rotate_path(&path, &rng.rotation());
                let (c, dv) =
                    crossland_dang_van(&rotated, &m, &mut InvariantScratch::default()).unwrap();
                worst = worst.max((c.index - 1.0).abs()).max((dv.index - 1.0).abs());
            }
        }
    }
    eprintln!("endurance limits: worst |index − 1| = {worst:.2e}");
    assert!(worst < 1e-13, "{worst}");
}

/// Proportional path σ = m + sin(ωt) A: √J₂,a = √J₂(A), centre = deviator of m.
#[test]
fn proportional_closed_form() {
    let mut rng = Rng::new(2221);
    for _ in 0..200 {
        let mean: Voigt = std::array::from_fn(|_| rng.range(-2e8, 2e8));
        let a: Voigt = std::array::from_fn(|_| rng.range(-2e8, 2e8));
        let path = proportional_cycle(mean, a, 40);
        let (c, dv) =
            crossland_dang_van(&path, &steel(), &mut InvariantScratch::default()).unwrap();
        let want = j2(&a).sqrt();
        assert!((c.sqrt_j2_amplitude - want).abs() <= 1e-13 * want);
        let h = (mean[0] + mean[1] + mean[2]) / 3.0;
        let dm = [
            mean[0] - h,
            mean[1] - h,
            mean[2] - h,
            mean[3],
            mean[4],
            mean[5],
        ];
        for k in 0..6 {
            assert!((dv.centre[k] - dm[k]).abs() <= 1e-12 * want, "{k}");
        }
    }
}

/// Adding a constant deviator changes neither √J₂,a (nor Crossland) nor Dang Van; adding a
/// hydrostatic mean p keeps √J₂,a and raises Crossland by α_C p/t₋₁.
#[test]
fn mean_stress_shifts() {
    let mut rng = Rng::new(2222);
    let m = steel();
    for _ in 0..200 {
        let path = random_cycle(&mut rng, 40, 1e8, 1e8);
        let (c0, dv0) = crossland_dang_van(&path, &m, &mut InvariantScratch::default()).unwrap();
        let mut shift: Voigt = std::array::from_fn(|_| rng.range(-3e8, 3e8));
        let h = (shift[0] + shift[1] + shift[2]) / 3.0;
        for v in shift.iter_mut().take(3) {
            *v -= h;
        }
        let moved: Vec<Voigt> = path
            .iter()
            .map(|s| std::array::from_fn(|k| s[k] + shift[k]))
            .collect();
        let (c1, dv1) = crossland_dang_van(&moved, &m, &mut InvariantScratch::default()).unwrap();
        assert!((c1.sqrt_j2_amplitude - c0.sqrt_j2_amplitude).abs() <= 1e-9 * c0.sqrt_j2_amplitude);
        assert!((c1.index - c0.index).abs() <= 1e-9);
        assert!(
            (dv1.index - dv0.index).abs() <= 1e-9,
            "{} {}",
            dv1.index,
            dv0.index
        );
        let p = rng.range(-3e8, 3e8);
        let pressed: Vec<Voigt> = path
            .iter()
            .map(|s| [s[0] + p, s[1] + p, s[2] + p, s[3], s[4], s[5]])
            .collect();
        let (c2, _) = crossland_dang_van(&pressed, &m, &mut InvariantScratch::default()).unwrap();
        assert!((c2.sqrt_j2_amplitude - c0.sqrt_j2_amplitude).abs() <= 1e-9 * c0.sqrt_j2_amplitude);
        let want = c0.index + m.alpha_crossland() * p / m.t_minus1;
        assert!((c2.index - want).abs() <= 1e-9);
    }
}

/// Out of phase tension–torsion σ_xx = σ sin ωt, τ_xy = τ cos ωt (90°): the deviatoric path is an
/// ellipse with semi-axes σ/√3 and τ, so √J₂,a = max(σ/√3, τ); Dang Van has centre 0.
#[test]
fn out_of_phase_tension_torsion() {
    let m = steel();
    for (sig, tau) in [(2e8, 0.5e8), (2e8, 1.5e8), (1e8, 1e8)] {
        let path: Vec<Voigt> = (0..64)
            .map(|i| {
                let w = 2.0 * std::f64::consts::PI * i as f64 / 64.0;
                [sig * w.sin(), 0.0, 0.0, 0.0, 0.0, tau * w.cos()]
            })
            .collect();
        let (c, dv) = crossland_dang_van(&path, &m, &mut InvariantScratch::default()).unwrap();
        let want = (sig / 3f64.sqrt()).max(tau);
        assert!((c.sqrt_j2_amplitude - want).abs() <= 1e-12 * want);
        assert!(dv.centre.iter().all(|x| x.abs() < 1e-6));
        // Dang Van by hand on the same increments: τ_Tresca = √(σ²/4 + τ²), σ_H = σ/3.
        let want_dv = path
            .iter()
            .map(|s| ((s[0] / 2.0).powi(2) + s[5] * s[5]).sqrt() + m.alpha_dang_van() * s[0] / 3.0)
            .fold(f64::NEG_INFINITY, f64::max)
            / m.t_minus1;
        assert!(
            (dv.index - want_dv).abs() <= 1e-12,
            "{} {want_dv}",
            dv.index
        );
    }
}

#[test]
fn material_and_path_errors() {
    let mut s = InvariantScratch::default();
    let path = uniaxial(1e8, 8);
    let bad = |m: Material| crossland_dang_van(&path, &m, &mut InvariantScratch::default());
    assert!(matches!(
        bad(Material {
            f_minus1: -1.0,
            ..steel()
        }),
        Err(FatigueError::InvalidMaterial {
            name: "f_minus1",
            ..
        })
    ));
    assert!(matches!(
        bad(Material {
            t_minus1: f64::NAN,
            ..steel()
        }),
        Err(FatigueError::InvalidMaterial {
            name: "t_minus1",
            ..
        })
    ));
    assert!(matches!(
        bad(Material {
            t_minus1: 200e6,
            ..steel()
        }),
        Err(FatigueError::TorsionBendingRatio { .. })
    ));
    assert!(matches!(
        bad(Material {
            t_minus1: 401e6,
            ..steel()
        }),
        Err(FatigueError::TorsionBendingRatio { .. })
    ));
    let m = steel();
    assert!(matches!(
        Material { poisson: 0.5, ..m }.validate(),
        Err(FatigueError::InvalidMaterial {
            name: "poisson",
            ..
        })
    ));
    assert!(matches!(
        Material { young: 0.0, ..m }.validate(),
        Err(FatigueError::InvalidMaterial { name: "young", .. })
    ));
    assert!(matches!(
        Material { fs_k: -0.1, ..m }.validate(),
        Err(FatigueError::InvalidMaterial { name: "fs_k", .. })
    ));
    assert!(matches!(
        Material {
            yield_stress: f64::INFINITY,
            ..m
        }
        .validate(),
        Err(FatigueError::InvalidMaterial {
            name: "yield_stress",
            ..
        })
    ));
    assert_eq!(
        crossland_dang_van(&[], &m, &mut s).unwrap_err(),
        FatigueError::EmptyPath
    );
    let mut p2 = path.clone();
    p2[3][4] = f64::NAN;
    assert!(matches!(
        crossland_dang_van(&p2, &m, &mut s),
        Err(FatigueError::NonFiniteStress {
            increment: 3,
            component: 4,
            ..
        })
    ));
    let msg = bad(Material {
        t_minus1: 200e6,
        ..steel()
    })
    .unwrap_err()
    .to_string();
    assert!(msg.contains("t_minus1"), "{msg}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]
    /// Both indices are invariant under a rotation of the stress path.
    #[test]
    fn rotation_invariance(seed in 0u64..1_000_000, g in prop::array::uniform9(-1.0f64..1.0)) {
        prop_assume!(g.iter().map(|x| x * x).sum::<f64>() > 0.1);
        let mut rng = Rng::new(seed);
        let path = random_cycle(&mut rng, 40, 1e8, 1e8);
        let rotated = rotate_path(&path, &common::rotation_from(g));
        let m = steel();
        let (c0, d0) = crossland_dang_van(&path, &m, &mut InvariantScratch::default()).unwrap();
        let (c1, d1) = crossland_dang_van(&rotated, &m, &mut InvariantScratch::default()).unwrap();
        prop_assert!((c0.index - c1.index).abs() <= 1e-12 * c0.index.abs().max(1.0));
        prop_assert!((d0.index - d1.index).abs() <= 1e-12 * d0.index.abs().max(1.0));
    }
}
