//! Influence matrices: symmetry and reciprocity (proptest), and the DC-FFT operators of the contact
//! kernels against their dense O(N⁴) control (docs/theory-sam.md#dc-fft).

use halfspace_numerics::conv2d::{DcFft2d, DenseConvolution2d, GridOperator, KernelFn};
use halfspace_sam::kernels::InPlane;
use halfspace_sam::{Body, Compliance, SurfaceGrid};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, rng_seed: proptest::test_runner::RngSeed::Fixed(13), ..ProptestConfig::default() })]

    /// K^p_3 is even and symmetric under exchanging the axes on square cells; T is symmetric
    /// (T₁₂ = T₂₁) and even; the coupling blocks make the full (p, q₁, q₂) matrix symmetric:
    /// entry (u₃ at x_i, q_α at x_k) = κ⟦P_B^{(α)}⟧(x_i − x_k) equals entry (u_α at x_k, p at x_i)
    /// = −κ⟦P_B^{(α)}⟧(x_k − x_i) (Betti reciprocity).
    #[test]
    fn symmetry_and_reciprocity(
        e1 in 1e9..5e11f64, nu1 in -0.5..0.5f64, e2 in 1e9..5e11f64, nu2 in -0.5..0.5f64,
        rigid in any::<bool>(), half in 1e-7..1e-5f64, m in -20i64..20, n in -20i64..20,
    ) {
        let tool = if rigid { Body::Rigid } else { Body::elastic(e1, nu1).unwrap() };
        let c = Compliance::pair(tool, Body::elastic(e2, nu2).unwrap()).unwrap();
        let g = SurfaceGrid { n1: 64, n2: 64, half1: half, half2: half };
        let (x1, x2) = (2.0 * half * m as f64, 2.0 * half * n as f64);
        let k = c.normal_from_pressure(&g, x1, x2);
        let scale = c.normal_from_pressure(&g, 0.0, 0.0);
        prop_assert!((k - c.normal_from_pressure(&g, -x1, -x2)).abs() <= 1e-12 * scale);
        prop_assert!((k - c.normal_from_pressure(&g, x2, x1)).abs() <= 1e-12 * scale);
        prop_assert!(k > 0.0 && k <= scale * (1.0 + 1e-12));
        let (i1, i2) = (InPlane::X1, InPlane::X2);
        let t = c.tangential(&g, i1, i1, 0.0, 0.0);
        for (a, b) in [(i1, i2), (i2, i1), (i1, i1), (i2, i2)] {
            let v = c.tangential(&g, a, b, x1, x2);
            prop_assert!((v - c.tangential(&g, b, a, x1, x2)).abs() <= 1e-12 * t);
            prop_assert!((v - c.tangential(&g, a, b, -x1, -x2)).abs() <= 1e-12 * t);
        }
        // T₁₁ at (x₁, x₂) equals T₂₂ at (x₂, x₁).
        prop_assert!((c.tangential(&g, i1, i1, x1, x2) - c.tangential(&g, i2, i2, x2, x1)).abs() <= 1e-12 * t);
        for alpha in InPlane::ALL {
            let u3_from_q = c.coupling * c.coupling_shape(&g, alpha, x1, x2);
            let ua_from_p = -c.coupling * c.coupling_shape(&g, alpha, -x1, -x2);
            prop_assert!((u3_from_q - ua_from_p).abs() <= 1e-12 * scale.max(u3_from_q.abs()));
        }
    }
}

#[test]
fn dcfft_of_the_contact_kernels_matches_the_dense_control() {
    let c = Compliance::pair(
        Body::elastic(100e9, 0.2).unwrap(),
        Body::elastic(210e9, 0.3).unwrap(),
    )
    .unwrap();
    let g = SurfaceGrid {
        n1: 12,
        n2: 10,
        half1: 0.5e-6,
        half2: 0.7e-6,
    };
    let (d1, d2) = (2.0 * g.half1, 2.0 * g.half2);
    let at = |m: i64, n: i64| (m as f64 * d1, n as f64 * d2);
    let kp = |m: i64, n: i64| {
        let (x, y) = at(m, n);
        c.normal_from_pressure(&g, x, y)
    };
    let t11 = |m: i64, n: i64| {
        let (x, y) = at(m, n);
        c.tangential(&g, InPlane::X1, InPlane::X1, x, y)
    };
    let t12 = |m: i64, n: i64| {
        let (x, y) = at(m, n);
        c.tangential(&g, InPlane::X1, InPlane::X2, x, y)
    };
    let t22 = |m: i64, n: i64| {
        let (x, y) = at(m, n);
        c.tangential(&g, InPlane::X2, InPlane::X2, x, y)
    };
    let cp1 = |m: i64, n: i64| {
        let (x, y) = at(m, n);
        c.coupling * c.coupling_shape(&g, InPlane::X1, x, y)
    };
    let cp2 = |m: i64, n: i64| {
        let (x, y) = at(m, n);
        c.coupling * c.coupling_shape(&g, InPlane::X2, x, y)
    };
    let cm1 = |m: i64, n: i64| -cp1(m, n);
    let cm2 = |m: i64, n: i64| -cp2(m, n);
    // The full 3 × 3 block operator (p, q₁, q₂) → (u₃, u₁, u₂).
    let kernels: [Option<KernelFn>; 9] = [
        Some(&kp),
        Some(&cp1),
        Some(&cp2),
        Some(&cm1),
        Some(&t11),
        Some(&t12),
        Some(&cm2),
        Some(&t12),
        Some(&t22),
    ];
    let mut fast = DcFft2d::new(12, 10, 3, 3, &kernels).unwrap();
    let mut dense = DenseConvolution2d::new(12, 10, 3, 3, &kernels).unwrap();
    let x: Vec<Vec<f64>> = (0..3)
        .map(|s| {
            (0..120)
                .map(|k| ((k * 7 + s * 13) % 17) as f64 * 1e8)
                .collect()
        })
        .collect();
    let (mut f, mut d) = (vec![vec![0.0; 120]; 3], vec![vec![0.0; 120]; 3]);
    {
        let [f0, f1, f2] = &mut f[..] else {
            unreachable!()
        };
        fast.apply(&[&x[0], &x[1], &x[2]], &mut [f0, f1, f2])
            .unwrap();
        let [d0, d1, d2] = &mut d[..] else {
            unreachable!()
        };
        dense
            .apply(&[&x[0], &x[1], &x[2]], &mut [d0, d1, d2])
            .unwrap();
    }
    let scale = d.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let err = f
        .iter()
        .flatten()
        .zip(d.iter().flatten())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(err <= 1e-12 * scale, "{err:e} of {scale:e}");
}
