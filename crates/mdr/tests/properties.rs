//! Invariants as property tests (proptest, fixed case counts) and finite-difference checks of the
//! analytic derivatives of the macroscopic relations (docs/theory-mdr.md#profile-transform).

mod common;

use common::relative_max_norm;
use halfspace_mdr::*;
use proptest::prelude::*;

/// A smooth convex profile `f = s₀ r + c₁ r² + c₂ r⁴ + c₃ r⁶` sampled as a table on `[0, 2]`
/// (so the table path, its interpolation and the closed-form splits are all exercised).
fn table_profile(s0: f64, c: [f64; 3], rows: usize) -> Profile {
    let r: Vec<f64> = (0..rows)
        .map(|i| 2.0 * i as f64 / (rows - 1) as f64)
        .collect();
    let f: Vec<f64> = r
        .iter()
        .map(|&x| s0 * x + c[0] * x * x + c[1] * x.powi(4) + c[2] * x.powi(6))
        .collect();
    Profile::tabulated(r, f).unwrap()
}

fn unit() -> Material {
    Material::from_e_star(1.0).unwrap()
}

fn lcg_vec(seed: u64, n: usize) -> Vec<f64> {
    halfspace_numerics::testkit::lcg(seed.wrapping_add(0x9E37_79B9_7F4A_7C15), n)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, rng_seed: proptest::test_runner::RngSeed::Fixed(11), ..ProptestConfig::default() })]

    /// docs/theory-mdr.md#p7-fft-details: MVM and FFT evaluate the same sums and agree to ~1e-12 relative (max norm).
    #[test]
    fn fft_and_mvm_agree_on_every_transform(
        n in 8usize..3000,
        s0 in prop_oneof![Just(0.0), 0.0..0.5f64],
        c1 in 0.05..2.0f64, c2 in 0.0..1.0f64, c3 in 0.0..0.5f64,
        length in 0.2..1.9f64,
    ) {
        let profile = table_profile(s0, [c1, c2, c3], 257);
        let grid = SquaredGrid::new(n, length).unwrap();
        let mut g = [vec![0.0; n], vec![0.0; n]];
        let mut p = [vec![0.0; n], vec![0.0; n]];
        let mut u = [vec![0.0; n], vec![0.0; n]];
        let m = (n * 2 / 3).max(3);
        // Each transform gets the same input under both backends (the MVM's g), so the comparison
        // measures the backend alone, not rounding carried in from the previous transform.
        for (k, backend) in [Backend::Mvm, Backend::Fft].into_iter().enumerate() {
            let mut pt = ProfileTransform::new(n, &unit(), backend).unwrap();
            pt.profile_to_equivalent(&profile, &grid, &mut g[k]).unwrap();
        }
        let delta = g[0][m - 1];
        let q: Vec<f64> = g[0][..m].iter().map(|gi| delta - gi).collect();
        for (k, backend) in [Backend::Mvm, Backend::Fft].into_iter().enumerate() {
            let mut st = StressTransform::new(n, &unit(), backend).unwrap();
            st.line_load_to_stress(&grid, &q, 0.0, &mut p[k][..m]).unwrap();
            let mut dt = DisplacementTransform::new(n, &unit_material(), DisplacementMethod::Convolution(backend)).unwrap();
            dt.apply_unchecked(&grid, &q, -std::f64::consts::FRAC_PI_2 * s0, &mut u[k]).unwrap();
        }
        prop_assert!(relative_max_norm(&p[1], &p[0]) < 1e-12, "p: {}", relative_max_norm(&p[1], &p[0]));
        prop_assert!(relative_max_norm(&u[1], &u[0]) < 1e-12, "u: {}", relative_max_norm(&u[1], &u[0]));
    }

    /// Every transform is linear: T(α a + β b) = α T(a) + β T(b).
    #[test]
    fn transforms_are_linear(n in 8usize..1500, seed in 0u64..1000, alpha in -3.0..3.0f64, beta in -3.0..3.0f64) {
        let grid = SquaredGrid::new(n, 1.0).unwrap();
        // Smooth random inputs: the transforms difference their inputs, so white noise would test
        // rounding amplified by 1/h² rather than linearity.
        let smooth = |seed: u64| -> Vec<f64> {
            let c = lcg_vec(seed, 4);
            (0..n)
                .map(|i| {
                    let t = i as f64 / (n - 1) as f64;
                    c[0] + c[1] * t + c[2] * (3.0 * t).sin() + c[3] * (2.0 * t).cos()
                })
                .collect()
        };
        let a = smooth(seed);
        let b = smooth(seed + 7);
        let mix: Vec<f64> = a.iter().zip(&b).map(|(x, y)| alpha * x + beta * y).collect();
        // |T(αa + βb) − αT(a) − βT(b)| relative to the size of the terms α T(a), β T(b): rounding
        // is relative to them, not to their (possibly cancelling) sum. The transforms difference
        // their input, dividing its rounding by h = L²/(N−1): tolerance 1e-12, or 2e-15·N above
        // N = 500.
        let tol = 1e-12f64.max(2e-15 * n as f64);
        let defect = |tm: &[f64], ta: &[f64], tb: &[f64]| -> f64 {
            let scale = ta.iter().zip(tb).map(|(x, y)| (alpha * x).abs().max((beta * y).abs())).fold(0.0, f64::max);
            tm.iter().zip(ta.iter().zip(tb)).map(|(m, (x, y))| (m - alpha * x - beta * y).abs()).fold(0.0, f64::max) / scale
        };
        let mut pt = ProfileTransform::new(n, &unit(), Backend::Fft).unwrap();
        let (mut ga, mut gb, mut gm) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        pt.apply(&grid, &a, &mut ga).unwrap();
        pt.apply(&grid, &b, &mut gb).unwrap();
        pt.apply(&grid, &mix, &mut gm).unwrap();
        prop_assert!(defect(&gm, &ga, &gb) < tol, "{}", defect(&gm, &ga, &gb));
        let mut st = StressTransform::new(n, &unit(), Backend::Fft).unwrap();
        st.line_load_to_stress(&grid, &a, 0.0, &mut ga).unwrap();
        st.line_load_to_stress(&grid, &b, 0.0, &mut gb).unwrap();
        st.line_load_to_stress(&grid, &mix, 0.0, &mut gm).unwrap();
        prop_assert!(defect(&gm, &ga, &gb) < tol, "{}", defect(&gm, &ga, &gb));
        for method in [DisplacementMethod::DenseKernel, DisplacementMethod::Convolution(Backend::Fft)] {
            let mut dt = DisplacementTransform::new(n, &unit_material(), method).unwrap();
            let m = n / 2 + 2;
            dt.apply_unchecked(&grid, &a[..m], 0.3, &mut ga).unwrap();
            dt.apply_unchecked(&grid, &b[..m], -0.2, &mut gb).unwrap();
            dt.apply_unchecked(&grid, &mix[..m], alpha * 0.3 - beta * 0.2, &mut gm).unwrap();
            prop_assert!(defect(&gm, &ga, &gb) < tol, "{method:?} {}", defect(&gm, &ga, &gb));
        }
    }

    /// F(δ) and a(δ) increase with δ, and the two backends agree on the contact.
    #[test]
    fn force_and_radius_increase_with_depth(
        s0 in prop_oneof![Just(0.0), 0.0..0.3f64],
        c1 in 0.05..2.0f64, c2 in 0.0..1.0f64,
        a1 in 0.1..1.2f64, ratio in 1.01..2.0f64,
        nodes in 64usize..1200,
    ) {
        let profile = table_profile(s0, [c1, c2, 0.0], 401);
        // The depth is drawn through the contact radius a₁ of the quadratic term alone
        // (δ = g(a₁) = 2c₁a₁² for f = c₁r², docs/theory-mdr.md#profile-transform): the other terms only shrink the contact, so
        // a(δ·ratio) ≤ a₁√2 < 1.7 stays inside the table on [0, 2]. Drawing δ directly let
        // c₁ = 0.05, δ = 0.45 put the edge at 2.1, outside the table (a CI failure, not a bug).
        let d1 = 2.0 * c1 * a1 * a1;
        // Radius tolerance 1e-13, not the default 1e-12: the iteration's stopping error in a (up to
        // 1e-12 relative) reaches the pressure amplified ~100× (measured 1.06e-10 between the backends
        // at 766 nodes with the default); 1e-14 is below what the iteration reaches (it stalls at
        // 2.4e-14 on some profiles). Checked over nine seeds.
        let params = |backend| ContactParams { nodes, backend, tolerance: 1e-13, ..Default::default() };
        let mut fft = ContactSolver::new(unit(), params(Backend::Fft)).unwrap();
        let mut mvm = ContactSolver::new(unit(), params(Backend::Mvm)).unwrap();
        let lo = fft.solve(&profile, Load::Depth(d1)).unwrap();
        let hi = fft.solve(&profile, Load::Depth(d1 * ratio)).unwrap();
        prop_assert!(hi.force > lo.force, "F({}) = {} ≤ F({d1}) = {}", d1 * ratio, hi.force, lo.force);
        prop_assert!(hi.contact_radius > lo.contact_radius);
        let twin = mvm.solve(&profile, Load::Depth(d1)).unwrap();
        // Whole solves: the contact-radius iteration carries the backends' ~1e-13 differences in g
        // into the grid step, and the pressure's square-root edge amplifies them (measured ≤ 2e-11 over seeds).
        prop_assert!(((twin.force - lo.force) / lo.force).abs() < 1e-11);
        prop_assert!(relative_max_norm(&twin.pressure, &lo.pressure) < 1e-10, "{}", relative_max_norm(&twin.pressure, &lo.pressure));
    }
}

/// Finite-difference checks of docs/theory-mdr.md#profile-transform: dF/dδ = 2E* a and dF/da = 2E* a g'(a), against central
/// differences of the solver's own outputs. Step ε = 1e-4 δ: the truncation error of the central
/// difference is O(ε²) ≈ 1e-8 relative, rounding ~1e-16/1e-4 = 1e-12; what remains is the
/// variation of the discretization error with δ (measured ≤ 2e-6 relative for r³ at N = 2001).
#[test]
fn force_derivatives_match_central_differences() {
    let cases = [
        (Profile::sphere(1.0).unwrap(), 0.2),
        (Profile::power(1.0, 3.0).unwrap(), 0.2),
        (Profile::cone(0.1).unwrap(), 0.05),
        (table_profile(0.05, [0.5, 0.3, 0.1], 401), 0.1),
    ];
    let mut solver = ContactSolver::new(
        Material::from_e_star(2.5).unwrap(),
        ContactParams::default(),
    )
    .unwrap();
    for (profile, delta) in cases {
        let eps = 1e-4 * delta;
        let mid = solver.solve(&profile, Load::Depth(delta)).unwrap();
        let plus = solver.solve(&profile, Load::Depth(delta + eps)).unwrap();
        let minus = solver.solve(&profile, Load::Depth(delta - eps)).unwrap();
        let df_ddelta = (plus.force - minus.force) / (2.0 * eps);
        let want = mid.normal_stiffness();
        assert!(
            ((df_ddelta - want) / want).abs() < 1e-5,
            "{}: dF/dδ {df_ddelta} vs 2E*a {want}",
            profile.kind()
        );
        let df_da = (plus.force - minus.force) / (plus.contact_radius - minus.contact_radius);
        let want = mid.force_radius_slope();
        assert!(
            ((df_da - want) / want).abs() < 1e-5,
            "{}: dF/da {df_da} vs 2E*a g'(a) {want}",
            profile.kind()
        );
    }
}

fn unit_material() -> Material {
    Material::from_e_star(1.0).unwrap()
}
