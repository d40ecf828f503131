//! The profile transform of sampled profiles exact for piecewise-linear profiles in `ξ = r²`
//! (`ProfileTransform::values_to_equivalent`, docs/theory-mdr.md#profile-transform): exact on
//! paraboloids, order `1 + γ` on smooth profiles against the closed form `κ_n(k) x^n` of `r^n`,
//! the same on the MVM and FFT backends, and no node-to-node mode it cannot see (the central
//! differences of Eq. 7 leave `(−1)^i` out).

use halfspace_mdr::{analytic, Backend, Material, ProfileTransform};
use halfspace_numerics::SquaredGrid;

fn graded(k: f64) -> Material {
    Material::power_law(1.0, 1.0, 0.3, k).unwrap()
}

/// `g` of the samples `v_i = f(√ξ_i)` on `n` nodes over `[0, L]`.
fn transform(k: f64, n: usize, length: f64, backend: Backend, f: impl Fn(f64) -> f64) -> Vec<f64> {
    let grid = SquaredGrid::new(n, length).unwrap();
    let values: Vec<f64> = (0..n).map(|i| f(grid.coordinate(i))).collect();
    let mut g = vec![0.0; n];
    ProfileTransform::new(n, &graded(k), backend)
        .unwrap()
        .values_to_equivalent(&grid, &values, &mut g)
        .unwrap();
    g
}

fn max_error(k: f64, n: usize, power: i32) -> f64 {
    let length = 1.0;
    let grid = SquaredGrid::new(n, length).unwrap();
    let g = transform(k, n, length, Backend::Fft, |r| r.powi(power));
    let kappa = analytic::graded_power_law_factor(power as f64, k);
    (0..n)
        .map(|i| (g[i] - kappa * grid.coordinate(i).powi(power)).abs())
        .fold(0.0, f64::max)
}

#[test]
fn a_paraboloid_is_exact_without_a_split() {
    for k in [-0.5, 0.0, 0.5] {
        for n in [8, 401, 2001] {
            let c = 1.7;
            let grid = SquaredGrid::new(n, 1.3).unwrap();
            let g = transform(k, n, 1.3, Backend::Fft, |r| c * r * r);
            let kappa2 = 2.0 / (1.0 + k);
            for (i, gi) in g.iter().enumerate() {
                let exact = kappa2 * c * grid.squared(i);
                // The increments are differences of sums of size N: rounding ~ 1e-15·N.
                assert!(
                    (gi - exact).abs() < 2e-15 * n as f64 * (1.0 + exact.abs()),
                    "k {k}, n {n}, node {i}: {gi} against {exact}"
                );
            }
        }
    }
}

/// The max-norm error on `r⁴` and `r⁶` (`L = 1`) falls like `h^{1+γ}`, `γ = (1+k)/2`: observed
/// orders from N = 501 → 1001 → 2001 within 0.15 of `1 + γ` (1.25, 1.5, 1.75 at k = −0.5, 0, 0.5).
#[test]
fn smooth_profiles_converge_at_order_one_plus_gamma() {
    for k in [-0.5, 0.0, 0.5] {
        let gamma = 0.5 * (1.0 + k);
        for power in [4, 6] {
            let e: Vec<f64> = [501, 1001, 2001]
                .iter()
                .map(|&n| max_error(k, n, power))
                .collect();
            for w in e.windows(2) {
                let order = (w[0] / w[1]).log2();
                assert!(
                    (order - (1.0 + gamma)).abs() < 0.15,
                    "k {k}, r^{power}: errors {e:?}, order {order}"
                );
            }
            assert!(e[2] < 2e-3, "k {k}, r^{power}: {e:?}");
        }
    }
}

#[test]
fn mvm_and_fft_agree() {
    for k in [-0.5, 0.0, 0.5] {
        for n in [9, 300, 1500] {
            let f = |r: f64| 0.3 * r * r + 0.8 * r.powi(4) - 0.2 * (3.0 * r).sin().powi(2);
            let a = transform(k, n, 1.2, Backend::Mvm, f);
            let b = transform(k, n, 1.2, Backend::Fft, f);
            let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let diff = a
                .iter()
                .zip(&b)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(
                diff < 1e-12 * scale.max(1.0) * n as f64,
                "k {k}, n {n}: {diff:e}"
            );
        }
    }
}

/// The odd–even mode `v_i = ε (−1)^i` moves `g_j` by `(2ε/γ) j^{1−γ} A_j`, `A_j = Σ_{m=1}^{j}
/// (−1)^{j−m+1} e_m` (an alternating sum of the decreasing `e_m`: `(−1)^j A_j` lies between
/// `2 − 2^γ` and 1), i.e. `ε (ξ_j/h)^{1−γ}`: the largest response of any mode (the transform is of
/// order `1 − γ`), where the central differences of `slope_to_equivalent` give none inside the
/// grid.
#[test]
fn the_odd_even_mode_is_seen() {
    for k in [-0.5, 0.0, 0.5] {
        let gamma = 0.5 * (1.0 + k);
        let (n, length) = (1001, 1.0);
        let eps = 1e-6;
        let base = |r: f64| r * r + r.powi(4);
        let plain = transform(k, n, length, Backend::Fft, base);
        let grid = SquaredGrid::new(n, length).unwrap();
        let values: Vec<f64> = (0..n)
            .map(|i| base(grid.coordinate(i)) + if i % 2 == 0 { eps } else { -eps })
            .collect();
        let mut g = vec![0.0; n];
        ProfileTransform::new(n, &graded(k), Backend::Fft)
            .unwrap()
            .values_to_equivalent(&grid, &values, &mut g)
            .unwrap();
        for i in 1..n {
            let response = (g[i] - plain[i]) / eps;
            let scale = 2.0 * (i as f64).powf(1.0 - gamma) / gamma;
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            let low = 2.0 - 2f64.powf(gamma);
            assert!(
                sign * response / scale > low - 1e-6 && sign * response / scale < 1.0 + 1e-6,
                "k {k}, node {i}: {}",
                response / scale
            );
        }
    }
}
