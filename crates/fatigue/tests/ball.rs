//! The minimum enclosing ball against brute force and closed forms (docs/fatigue.md, "Checks").
#![allow(clippy::needless_range_loop)]
mod common;

use common::Rng;
use halfspace_fatigue::ball::{min_enclosing_ball, min_enclosing_ball_brute_force, BallScratch};
use halfspace_fatigue::FatigueError;
use proptest::prelude::*;

fn dist(a: &[f64; 5], b: &[f64; 5]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// Compares with brute force; returns (relative radius error, centre distance / radius).
fn against_brute(points: &[[f64; 5]]) -> (f64, f64) {
    let mut scratch = BallScratch::default();
    let (ball, info) = min_enclosing_ball(points, &mut scratch).unwrap();
    let brute = min_enclosing_ball_brute_force(points).unwrap();
    assert!((1..=6).contains(&info.support_size), "{info:?}");
    for p in points {
        assert!(dist(p, &ball.centre) <= ball.radius * (1.0 + 1e-14));
    }
    (
        (ball.radius - brute.radius).abs() / brute.radius,
        dist(&ball.centre, &brute.centre) / brute.radius,
    )
}

#[test]
fn random_sets_match_brute_force() {
    let mut rng = Rng::new(2201);
    let (mut worst_r, mut worst_c) = (0.0f64, 0.0f64);
    let mut supports = [0usize; 7];
    for trial in 0..300 {
        let n = 2 + trial % 13;
        // Stress-like magnitudes with a large offset: amplitude 1e8 Pa around 3e8 Pa.
        let pts: Vec<[f64; 5]> = (0..n)
            .map(|_| rng.point5().map(|x| 3e8 + 1e8 * x))
            .collect();
        let (r, c) = against_brute(&pts);
        worst_r = worst_r.max(r);
        worst_c = worst_c.max(c);
        let (_, info) = min_enclosing_ball(&pts, &mut BallScratch::default()).unwrap();
        supports[info.support_size] += 1;
    }
    eprintln!("random sets: worst radius rel. error {worst_r:.2e}, centre {worst_c:.2e}, supports {supports:?}");
    assert!(worst_r < 1e-12, "{worst_r}");
    assert!(worst_c < 1e-12, "{worst_c}");
}

#[test]
fn random_cycles_match_brute_force() {
    // Deviatoric coordinates of random two-harmonic cycles of 24 increments.
    let mut rng = Rng::new(2202);
    let mut worst = 0.0f64;
    for _ in 0..4 {
        let path = common::random_cycle(&mut rng, 24, 1e8, 2e8);
        let pts: Vec<[f64; 5]> = path
            .iter()
            .map(halfspace_fatigue::tensor::deviator_coordinates)
            .collect();
        let (r, c) = against_brute(&pts);
        worst = worst.max(r);
        assert!(c < 1e-12, "{c}");
    }
    eprintln!("random cycles (24 increments): worst radius rel. error {worst:.2e}");
    assert!(worst < 1e-12, "{worst}");
}

#[test]
fn proportional_paths_have_half_the_range() {
    let mut rng = Rng::new(2203);
    for _ in 0..100 {
        let a = rng.point5().map(|x| 1e8 * x);
        let d = rng.point5();
        let n = 3 + (rng.next_u64() % 60) as usize;
        let lambdas: Vec<f64> = (0..n).map(|_| rng.range(-2e8, 3e8)).collect();
        let pts: Vec<[f64; 5]> = lambdas
            .iter()
            .map(|l| std::array::from_fn(|k| a[k] + l * d[k]))
            .collect();
        let (lo, hi) = lambdas
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &l| {
                (lo.min(l), hi.max(l))
            });
        let dn = d.iter().map(|x| x * x).sum::<f64>().sqrt();
        let expected = 0.5 * (hi - lo) * dn;
        let mid: [f64; 5] = std::array::from_fn(|k| a[k] + 0.5 * (hi + lo) * d[k]);
        let (ball, info) = min_enclosing_ball(&pts, &mut BallScratch::default()).unwrap();
        assert!(
            (ball.radius - expected).abs() <= 1e-13 * expected,
            "{} vs {expected}",
            ball.radius
        );
        assert!(dist(&ball.centre, &mid) <= 1e-12 * expected);
        assert_eq!(info.support_size, 2);
    }
}

#[test]
fn degenerate_inputs() {
    let mut s = BallScratch::default();
    let p = [1.0, -2.0, 3.0, 4e8, 5.0];
    let (b, info) = min_enclosing_ball(&[p], &mut s).unwrap();
    assert_eq!((b.centre, b.radius, info.support_size), (p, 0.0, 1));
    let (b, _) = min_enclosing_ball(&[p; 17], &mut s).unwrap();
    assert_eq!((b.centre, b.radius), (p, 0.0));
    let q = [3.0, -2.0, 3.0, 4e8, 5.0];
    let (b, info) = min_enclosing_ball(&[p, q], &mut s).unwrap();
    assert_eq!(b.radius, 1.0);
    assert_eq!(b.centre[0], 2.0);
    assert_eq!(info.support_size, 2);
    // Two points repeated many times, interleaved.
    let pts: Vec<[f64; 5]> = (0..40).map(|i| if i % 3 == 0 { p } else { q }).collect();
    let (b, info) = min_enclosing_ball(&pts, &mut s).unwrap();
    assert_eq!(b.radius, 1.0);
    assert_eq!(info.support_size, 2);
    assert_eq!(
        min_enclosing_ball(&[], &mut s).unwrap_err(),
        FatigueError::EmptyPath
    );
    assert!(matches!(
        min_enclosing_ball(&[p, [0.0, f64::NAN, 0.0, 0.0, 0.0]], &mut s),
        Err(FatigueError::NonFiniteStress {
            increment: 1,
            component: 1,
            ..
        })
    ));
}

#[test]
fn cospherical_points() {
    let mut rng = Rng::new(2204);
    let mut s = BallScratch::default();
    // Points on a circle in a random 2D plane of 5D, each repeated: radius 1, centre c.
    for _ in 0..50 {
        let c = rng.point5();
        let u = rng.point5();
        let un = u.iter().map(|x| x * x).sum::<f64>().sqrt();
        let u = u.map(|x| x / un);
        let w = rng.point5();
        let d: f64 = w.iter().zip(&u).map(|(a, b)| a * b).sum();
        let v: [f64; 5] = std::array::from_fn(|k| w[k] - d * u[k]);
        let vn = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let v = v.map(|x| x / vn);
        let n = 24;
        let pts: Vec<[f64; 5]> = (0..2 * n)
            .map(|i| {
                let t = 2.0 * std::f64::consts::PI * (i % n) as f64 / n as f64;
                std::array::from_fn(|k| c[k] + t.cos() * u[k] + t.sin() * v[k])
            })
            .collect();
        let (b, info) = min_enclosing_ball(&pts, &mut s).unwrap();
        assert!((b.radius - 1.0).abs() < 1e-14, "{}", b.radius);
        assert!(dist(&b.centre, &c) < 1e-14);
        assert!(info.support_size <= 3, "{info:?}");
    }
    // ±e_k and random points of the unit 5-sphere: the unit ball, every point on the boundary.
    for _ in 0..50 {
        let mut pts: Vec<[f64; 5]> = Vec::new();
        for k in 0..5 {
            for sign in [1.0, -1.0] {
                let mut e = [0.0; 5];
                e[k] = sign;
                pts.push(e);
            }
        }
        for _ in 0..30 {
            let g: [f64; 5] = std::array::from_fn(|_| rng.normal());
            let l = g.iter().map(|x| x * x).sum::<f64>().sqrt();
            pts.push(g.map(|x| x / l));
        }
        // Shuffle deterministically.
        for i in (1..pts.len()).rev() {
            let j = (rng.next_u64() % (i as u64 + 1)) as usize;
            pts.swap(i, j);
        }
        let (b, _) = min_enclosing_ball(&pts, &mut s).unwrap();
        assert!((b.radius - 1.0).abs() < 1e-14, "{}", b.radius);
        assert!(dist(&b.centre, &[0.0; 5]) < 1e-12);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    #[test]
    fn ball_matches_brute_force(
        pts in prop::collection::vec(prop::array::uniform5(-1e3f64..1e3), 1..10),
    ) {
        let mut s = BallScratch::default();
        let (ball, _) = min_enclosing_ball(&pts, &mut s).unwrap();
        let brute = min_enclosing_ball_brute_force(&pts).unwrap();
        prop_assert!((ball.radius - brute.radius).abs() <= 1e-12 * brute.radius.max(1e-300));
    }

    #[test]
    fn ball_is_translation_and_scale_equivariant(
        pts in prop::collection::vec(prop::array::uniform5(-1.0f64..1.0), 1..30),
        shift in prop::array::uniform5(-1e3f64..1e3),
        scale in 1e-3f64..1e9,
    ) {
        let mut s = BallScratch::default();
        let (b0, _) = min_enclosing_ball(&pts, &mut s).unwrap();
        let moved: Vec<[f64; 5]> = pts
            .iter()
            .map(|p| std::array::from_fn(|k| shift[k] + scale * p[k]))
            .collect();
        let (b1, _) = min_enclosing_ball(&moved, &mut s).unwrap();
        prop_assert!((b1.radius - scale * b0.radius).abs() <= 1e-9 * scale * b0.radius.max(1e-12));
    }
}
