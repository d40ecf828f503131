//! The line-load → pressure transform with the edge between nodes (`CellStressTransform`, product
//! integration of Eq. 14/28): exact for a load linear in ξ wherever the edge is, converging for
//! the quartic pair of docs/theory-mdr.md#graded-closed-forms, continuous as the edge crosses a node, MVM == FFT, and bad input.

mod common;

use approx::assert_relative_eq;
use common::observed_order;
use halfspace_mdr::{analytic, Backend, CellStressTransform, Material};
use halfspace_numerics::SquaredGrid;

fn material(k: f64) -> Material {
    if k == 0.0 {
        Material::from_e_star(1.0).unwrap()
    } else {
        Material::power_law(1.0, 1.0, 0.3, k).unwrap()
    }
}

/// `(M, θ)` of the edge `a² = ξ_{M−1} + θh` on `grid`.
fn edge_cell(grid: &SquaredGrid, a: f64) -> (usize, f64) {
    let t = a * a / grid.step();
    let last = (t.ceil() as usize).saturating_sub(1);
    (last + 1, t - last as f64)
}

#[test]
fn a_load_linear_in_xi_is_exact_wherever_the_edge_is() {
    // q = a² − ξ (the paraboloid) ↦ σ = (a² − ρ)^γ / (πγ), γ = (1+k)/2.
    for k in [-0.5, 0.0, 0.5] {
        let grid = SquaredGrid::new(301, 1.3).unwrap();
        for backend in [Backend::Fft, Backend::Mvm] {
            let mut tf = CellStressTransform::new(301, &material(k), backend).unwrap();
            for a in [0.5, 0.77, 1.0, 1.003, 1.2] {
                let (m, theta) = edge_cell(&grid, a);
                let q: Vec<f64> = (0..m).map(|i| a * a - grid.squared(i)).collect();
                let mut sigma = vec![0.0; m];
                tf.line_load_to_stress(&grid, &q, theta, &mut sigma)
                    .unwrap();
                let gamma = 0.5 * (1.0 + k);
                for (j, s) in sigma.iter().enumerate() {
                    let want =
                        (a * a - grid.squared(j)).powf(gamma) / (std::f64::consts::PI * gamma);
                    assert_relative_eq!(*s, want, max_relative = 1e-11, epsilon = 1e-13);
                }
            }
        }
    }
}

#[test]
fn the_quartic_pair_converges_at_order_one_plus_gamma() {
    // q = a⁴ − x⁴ ↦ the graded quartic pressure of docs/theory-mdr.md#graded-closed-forms; a = 1 sits inside a cell (θ ≠ 1).
    for k in [-0.5, 0.0, 0.5] {
        let mut errors = Vec::new();
        let sizes = [251, 501, 1001, 2001];
        for n in sizes {
            let grid = SquaredGrid::new(n, 1.37).unwrap();
            let (m, theta) = edge_cell(&grid, 1.0);
            assert!(theta < 0.99, "the edge must sit inside a cell");
            let mut tf = CellStressTransform::new(n, &material(k), Backend::Fft).unwrap();
            let q: Vec<f64> = (0..m).map(|i| 1.0 - grid.squared(i).powi(2)).collect();
            let mut sigma = vec![0.0; m];
            tf.line_load_to_stress(&grid, &q, theta, &mut sigma)
                .unwrap();
            let peak = analytic::graded_quartic_pressure(0.0, 1.0, 1.0, k);
            let err = (0..m)
                .map(|j| {
                    let want = analytic::graded_quartic_pressure(grid.coordinate(j), 1.0, 1.0, k);
                    (sigma[j] - want).abs()
                })
                .fold(0.0, f64::max)
                / peak;
            errors.push(err);
        }
        let order = observed_order(&sizes, &errors);
        // Measured (max norm over the contact nodes, N = 251 … 2001): orders 1.25 / 1.50 / 1.72 at
        // k = −0.5 / 0 / 0.5, i.e. 1 + γ — the linear-in-cell load meets the singular
        // (ξ − ρ)^{γ−1} in the cell next to each ρ; at N = 2001 the errors are 2.6e-4 / 1.8e-5 /
        // 1.4e-6 of the peak.
        let want = 1.0 + 0.5 * (1.0 + k) - 0.05;
        assert!(order > want, "k={k}: errors {errors:?}, order {order}");
        assert!(errors[3] < 3e-4, "k={k}: {errors:?}");
    }
}

#[test]
fn the_pressure_is_continuous_as_the_edge_crosses_a_node() {
    // Edge exactly on node M: (M nodes, θ = 1) and (M + 1 nodes with q_M = 0, any θ) are the same
    // load, so the same pressure; and θ → 0⁺ on M + 1 nodes tends to θ = 1 on M.
    for k in [-0.5, 0.0, 0.5] {
        let grid = SquaredGrid::new(401, 1.2).unwrap();
        let mut tf = CellStressTransform::new(401, &material(k), Backend::Fft).unwrap();
        let m = 300;
        let a2 = grid.squared(m);
        let q: Vec<f64> = (0..=m)
            .map(|i| (a2 - grid.squared(i)) * (1.5 + grid.squared(i)))
            .collect();
        let mut on_node = vec![0.0; m];
        tf.line_load_to_stress(&grid, &q[..m], 1.0, &mut on_node)
            .unwrap();
        for theta in [1e-9, 0.3, 1.0] {
            let mut past = vec![0.0; m + 1];
            tf.line_load_to_stress(&grid, &q, theta, &mut past).unwrap();
            for j in 0..m {
                assert_relative_eq!(past[j], on_node[j], max_relative = 1e-12, epsilon = 1e-14);
            }
        }
    }
}

#[test]
fn mvm_and_fft_agree() {
    // Fixed-seed loads (a linear congruential sequence), edges anywhere in their cells.
    let mut rng = halfspace_numerics::testkit::Lcg::new(0x2545_f491_4f6c_dd1d);
    let mut next = || rng.unit();
    for k in [-0.75, 0.0, 0.6] {
        let grid = SquaredGrid::new(700, 1.0).unwrap();
        let mut fft = CellStressTransform::new(700, &material(k), Backend::Fft).unwrap();
        let mut mvm = CellStressTransform::new(700, &material(k), Backend::Mvm).unwrap();
        for _ in 0..5 {
            let m = 2 + (next() * 697.0) as usize;
            let theta = 1e-3 + next() * (1.0 - 1e-3);
            let q: Vec<f64> = (0..m).map(|_| next()).collect();
            let (mut a, mut b) = (vec![0.0; m], vec![0.0; m]);
            fft.line_load_to_stress(&grid, &q, theta, &mut a).unwrap();
            mvm.line_load_to_stress(&grid, &q, theta, &mut b).unwrap();
            let scale = b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            for (x, y) in a.iter().zip(&b) {
                assert!((x - y).abs() <= 1e-12 * scale, "k={k} m={m}: {x} vs {y}");
            }
        }
    }
}

#[test]
fn bad_edges_and_sizes_are_errors() {
    let grid = SquaredGrid::new(100, 1.0).unwrap();
    let mut tf = CellStressTransform::new(100, &material(0.0), Backend::Fft).unwrap();
    let q = vec![1.0; 10];
    let mut s = vec![0.0; 10];
    for theta in [0.0, -0.1, 1.5, f64::NAN] {
        let err = tf
            .line_load_to_stress(&grid, &q, theta, &mut s)
            .unwrap_err();
        assert!(err.to_string().contains("θ"), "{err}");
    }
    assert!(tf
        .line_load_to_stress(&grid, &q[..1], 0.5, &mut s[..1])
        .is_err());
    assert!(tf.line_load_to_stress(&grid, &q, 0.5, &mut s[..9]).is_err());
    let big = SquaredGrid::new(200, 1.0).unwrap();
    assert!(tf.line_load_to_stress(&big, &q, 0.5, &mut s).is_err());
}

/// Reuse: one transform applied at a repeated edge position `θ` with contacts of changing size
/// (the kept partial-cell powers), and with the shorter FFT plans, against a fresh transform for
/// every call — the same bits without the shorter plans, the same values to rounding with them.
#[test]
fn repeated_edges_and_shorter_plans_give_the_fresh_transform() {
    let n = 2001;
    let grid = SquaredGrid::new(n, 1.6).unwrap();
    for k in [-0.5, 0.0] {
        let mut kept = CellStressTransform::new(n, &material(k), Backend::Fft).unwrap();
        let mut short = CellStressTransform::new(n, &material(k), Backend::Fft).unwrap();
        short.plan_shorter_lengths();
        for (m, theta) in [(900, 0.3), (1200, 0.3), (700, 0.3), (700, 1.0), (1800, 0.3)] {
            let q: Vec<f64> = (0..m)
                .map(|i| (1.0 - grid.squared(i) / grid.squared(m)).powf(1.5) + 0.1)
                .collect();
            let mut fresh = CellStressTransform::new(n, &material(k), Backend::Fft).unwrap();
            let (mut want, mut got, mut shorter) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
            fresh
                .line_load_to_stress(&grid, &q, theta, &mut want)
                .unwrap();
            kept.line_load_to_stress(&grid, &q, theta, &mut got)
                .unwrap();
            short
                .line_load_to_stress(&grid, &q, theta, &mut shorter)
                .unwrap();
            assert!(want
                .iter()
                .zip(&got)
                .all(|(a, b)| a.to_bits() == b.to_bits()));
            let scale = want.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            let diff = want
                .iter()
                .zip(&shorter)
                .fold(0.0f64, |s, (a, b)| s.max((a - b).abs()));
            assert!(
                diff < 1e-13 * scale,
                "k = {k}, m = {m}: {diff:e} of {scale:e}"
            );
        }
    }
}

#[test]
fn edge_difference_is_the_difference_of_two_transforms() {
    // σ(θ_a) − σ(θ_b) without the cells' sums (they cancel) against two single transforms'
    // difference, to the rounding of those transforms' sums (their cancellation); on both
    // backends, and including the central difference of the Jacobian's θ-derivative (δ = 1e-6).
    for k in [-0.5, 0.0] {
        let grid = SquaredGrid::new(401, 1.3).unwrap();
        for backend in [Backend::Fft, Backend::Mvm] {
            let mut tf = CellStressTransform::new(401, &material(k), backend).unwrap();
            tf.plan_shorter_lengths();
            for (m, thetas) in [
                (300, (0.4 + 1e-6, 0.4 - 1e-6)),
                (97, (1.0, 0.9)),
                (2, (0.3, 0.7)),
            ] {
                let q: Vec<f64> = (0..m)
                    .map(|i| (1.0 - grid.squared(i)).abs().sqrt() + 0.1)
                    .collect();
                let mut d = vec![0.0; m];
                tf.line_load_edge_difference(&grid, &q, thetas, &mut d)
                    .unwrap();
                let (mut a, mut b) = (vec![0.0; m], vec![0.0; m]);
                tf.line_load_to_stress(&grid, &q, thetas.0, &mut a).unwrap();
                tf.line_load_to_stress(&grid, &q, thetas.1, &mut b).unwrap();
                let size = a.iter().chain(&b).fold(0.0f64, |s, v| s.max(v.abs()));
                for j in 0..m {
                    assert!(
                        (d[j] - (a[j] - b[j])).abs() <= 1e-13 * size,
                        "k {k}, m {m}, node {j}: {} vs {}",
                        d[j],
                        a[j] - b[j]
                    );
                }
                assert!(d.iter().any(|v| *v != 0.0));
            }
            let q = vec![1.0; 10];
            let mut d = vec![0.0; 9];
            assert!(tf
                .line_load_edge_difference(&grid, &q, (0.5, 0.6), &mut d)
                .is_err());
            let mut d = vec![0.0; 10];
            assert!(tf
                .line_load_edge_difference(&grid, &q, (0.5, 1.5), &mut d)
                .is_err());
        }
    }
}
