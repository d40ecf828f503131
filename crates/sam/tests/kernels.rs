//! The closed-form kernels of docs/theory-sam.md#cuboid-in-infinite-space to #love-rectangle-stresses against the values of docs/theory-sam.md#kernel-reference-values, their identities and
//! finite differences.
#![allow(clippy::needless_range_loop)]

use approx::{assert_abs_diff_eq, assert_relative_eq};
use halfspace_sam::kernels::cuboid::{
    displacement_kernel, newtonian_potential, strain_kernel, DisplacementPotentials,
    StrainPotentials,
};
use halfspace_sam::kernels::subsurface::{pressure_stress, shear_stress};
use halfspace_sam::kernels::Direction::{self, X1, X2, X3};
use halfspace_sam::kernels::{compliance, mul6, InPlane, VOIGT};

const CUBE: [f64; 3] = [0.5, 0.5, 0.5];
const NU: f64 = 0.3;

/// `D_ijkl` with a single (non-symmetrised) `kl`.
fn d(x: [f64; 3], i: Direction, j: Direction, k: Direction, l: Direction) -> f64 {
    StrainPotentials::new(x, CUBE).d(NU, i, j, k, l)
}

#[test]
fn cube_eshelby_tensor_at_its_centre_matches_spec() {
    let x = [0.0; 3];
    assert_abs_diff_eq!(d(x, X1, X1, X1, X1), 0.595871, epsilon = 5e-7);
    assert_abs_diff_eq!(d(x, X1, X1, X2, X2), 0.011588, epsilon = 5e-7);
    assert_abs_diff_eq!(d(x, X1, X2, X1, X2), 0.202065, epsilon = 5e-7);
    // S_1111 + 2 S_1122 = (1+ν)/(3(1−ν)).
    assert_relative_eq!(
        d(x, X1, X1, X1, X1) + 2.0 * d(x, X1, X1, X2, X2),
        (1.0 + NU) / (3.0 * (1.0 - NU)),
        max_relative = 1e-13
    );
}

#[test]
fn strain_and_displacement_kernels_match_spec_values_outside() {
    let x = [0.7, 0.4, -0.3];
    assert_relative_eq!(d(x, X1, X1, X1, X1), -0.235107, epsilon = 5e-7);
    assert_abs_diff_eq!(d(x, X2, X2, X1, X1), 0.063332, epsilon = 5e-7);
    assert_abs_diff_eq!(d(x, X3, X3, X1, X1), 0.068167, epsilon = 5e-7);
    assert_abs_diff_eq!(d(x, X1, X2, X1, X1), -0.146838, epsilon = 5e-7);
    // D_1312 "means ε*_12 = ε*_21 = 1".
    assert_abs_diff_eq!(
        d(x, X1, X3, X1, X2) + d(x, X1, X3, X2, X1),
        0.073956,
        epsilon = 5e-7
    );
    assert_abs_diff_eq!(d(x, X3, X3, X3, X3), 0.105608, epsilon = 5e-7);
    let ds = DisplacementPotentials::new(x, CUBE);
    assert_abs_diff_eq!(ds.ds(NU, X1, X1, X1), 0.158487, epsilon = 5e-7);
    assert_abs_diff_eq!(ds.ds(NU, X2, X1, X1), 0.030268, epsilon = 5e-7);
    assert_abs_diff_eq!(ds.ds(NU, X3, X3, X3), -0.038481, epsilon = 5e-7);
    assert_relative_eq!(
        ds.ds(NU, X1, X1, X3) + ds.ds(NU, X1, X3, X1),
        -0.077297,
        max_relative = 1e-5
    );
    assert_relative_eq!(ds.phi1(X1), -1.17933028, max_relative = 1e-8);
    assert_relative_eq!(ds.psi3(X1, X1, X1), -1.22146808, max_relative = 1e-8);
    let sp = StrainPotentials::new(x, CUBE);
    assert_relative_eq!(sp.phi2(X1, X1), 2.2784477, max_relative = 1e-7);
    assert_relative_eq!(sp.phi2(X1, X2), 1.64682819, max_relative = 1e-8);
    assert_relative_eq!(sp.psi4(X1, X1, X1, X1), 3.61051096, max_relative = 1e-8);
    assert_relative_eq!(sp.psi4(X1, X1, X2, X3), 0.31182079, max_relative = 1e-8);
    let x = [1.0, 0.0, 0.0];
    assert_abs_diff_eq!(d(x, X1, X1, X1, X1), -0.224919, epsilon = 5e-7);
    assert_abs_diff_eq!(d(x, X2, X2, X1, X1), 0.073950, epsilon = 5e-7);
    assert_abs_diff_eq!(d(x, X3, X3, X3, X3), 0.059518, epsilon = 5e-7);
    let ds = DisplacementPotentials::new(x, CUBE);
    assert_abs_diff_eq!(ds.ds(NU, X1, X1, X1), 0.154004, epsilon = 5e-7);
}

#[test]
fn dilatation_identity_inside_and_outside_any_cuboid() {
    // D_iikk = (1+ν)/(1−ν) inside, 0 outside; ψ,kkij = 2 φ,ij.
    let a = [0.3, 0.7, 1.1];
    for (x, inside) in [
        ([0.1, -0.2, 0.5], true),
        ([-0.25, 0.6, -1.0], true),
        ([0.9, 0.1, 0.2], false),
        ([0.2, -1.5, 2.0], false),
    ] {
        let p = StrainPotentials::new(x, a);
        let trace: f64 = Direction::ALL
            .iter()
            .flat_map(|&i| Direction::ALL.map(move |k| (i, k)))
            .map(|(i, k)| p.d(NU, i, i, k, k))
            .sum();
        let want = if inside { (1.0 + NU) / (1.0 - NU) } else { 0.0 };
        assert!((trace - want).abs() < 1e-12, "{x:?}: {trace} vs {want}");
        for i in Direction::ALL {
            for j in Direction::ALL {
                let lap: f64 = Direction::ALL.iter().map(|&k| p.psi4(k, k, i, j)).sum();
                assert!((lap - 2.0 * p.phi2(i, j)).abs() < 1e-11, "{x:?} {i:?}{j:?}");
            }
        }
        // ∇²φ = −4π inside, 0 outside.
        let lap_phi: f64 = Direction::ALL.iter().map(|&k| p.phi2(k, k)).sum();
        let want = if inside {
            -4.0 * std::f64::consts::PI
        } else {
            0.0
        };
        assert!((lap_phi - want).abs() < 1e-11, "{x:?}: ∇²φ = {lap_phi}");
    }
}

#[test]
fn potentials_and_kernels_agree_with_finite_differences() {
    let a = [0.5, 0.4, 0.6];
    let h = 1e-4;
    for x in [[0.9, 0.3, -0.8], [0.1, 0.2, 0.3], [-1.4, 0.6, 0.2]] {
        // φ,i from φ.
        let dp = DisplacementPotentials::new(x, a);
        for i in Direction::ALL {
            let mut xp = x;
            let mut xm = x;
            xp[i.index()] += h;
            xm[i.index()] -= h;
            let fd = (newtonian_potential(xp, a) - newtonian_potential(xm, a)) / (2.0 * h);
            assert!(
                (fd - dp.phi1(i)).abs() < 1e-7,
                "φ,{i:?} at {x:?}: {fd} vs {}",
                dp.phi1(i)
            );
        }
        // D_ijkl = sym ∂_j Dˢ_ikl (the strain of the displacement kernel).
        let dv = strain_kernel(x, a, NU);
        for (row, &(i, j)) in VOIGT.iter().enumerate() {
            for col in 0..6 {
                let grad = |i: usize, j: usize| {
                    let mut xp = x;
                    let mut xm = x;
                    xp[j] += h;
                    xm[j] -= h;
                    (displacement_kernel(xp, a, NU)[i][col]
                        - displacement_kernel(xm, a, NU)[i][col])
                        / (2.0 * h)
                };
                let fd = 0.5 * (grad(i, j) + grad(j, i));
                assert!(
                    (fd - dv[row][col]).abs() < 2e-7,
                    "D[{row}][{col}] at {x:?}: {fd} vs {}",
                    dv[row][col]
                );
            }
        }
    }
}

#[test]
fn love_rectangle_stresses_match_spec_values() {
    // Rectangle a = 1, b = 0.6, ν = 0.3, unit traction, point (0.2, 0.1, 0.3); spec order
    // (11, 22, 33, 12, 13, 23) → Voigt (11, 22, 33, 23, 13, 12).
    let p = pressure_stress(0.2, 0.1, 0.3, 1.0, 0.6, NU);
    let want = [
        -0.394449, -0.335086, -0.947287, -0.033199, -0.014226, -0.000698,
    ];
    for (g, w) in p.iter().zip(want) {
        assert!((g - w).abs() < 1.5e-6, "pressure: {p:?}");
    }
    let q = shear_stress(InPlane::X1, 0.2, 0.1, 0.3, 1.0, 0.6, NU);
    let want = [
        -0.135863, -0.003191, -0.014226, -0.002810, -0.552864, -0.053219,
    ];
    for (g, w) in q.iter().zip(want) {
        assert!((g - w).abs() < 1.5e-6, "shear q1: {q:?}");
    }
    // Σ₃₃[q₁] = Σ₁₃[p]; the q₂ field is q₁'s with 1 ↔ 2 swapped.
    assert!((q[2] - p[4]).abs() < 1e-14);
    let q2 = shear_stress(InPlane::X2, 0.1, 0.2, 0.3, 0.6, 1.0, NU);
    for (a, b) in [(0, 1), (1, 0), (2, 2), (3, 4), (4, 3), (5, 5)] {
        assert!((q2[a] - q[b]).abs() < 1e-14);
    }
    // Surface limits: σ₃₃ → −1 under a pressure, σ₁₃ → −1 under a shear.
    let z = 1e-7;
    assert!((pressure_stress(0.1, 0.05, z, 1.0, 0.6, NU)[2] + 1.0).abs() < 1e-6);
    assert!((shear_stress(InPlane::X1, 0.1, 0.05, z, 1.0, 0.6, NU)[4] + 1.0).abs() < 1e-6);
}

#[test]
fn love_stresses_satisfy_equilibrium() {
    // ∂_j σ_ij = 0 by central differences, for the pressure and both shears.
    let h = 1e-4;
    let (d1, d2) = (0.5, 0.3);
    let field = |k: usize, x: [f64; 3]| match k {
        0 => pressure_stress(x[0], x[1], x[2], d1, d2, NU),
        a => shear_stress(InPlane::ALL[a - 1], x[0], x[1], x[2], d1, d2, NU),
    };
    // Voigt index of (i, j).
    let v = |i: usize, j: usize| {
        VOIGT
            .iter()
            .position(|&p| p == (i.min(j), i.max(j)))
            .unwrap()
    };
    for k in 0..3 {
        for x in [[0.2, 0.1, 0.3], [0.9, -0.4, 0.5], [-0.3, 0.35, 1.2]] {
            for i in 0..3 {
                let mut div = 0.0;
                for j in 0..3 {
                    let mut xp = x;
                    let mut xm = x;
                    xp[j] += h;
                    xm[j] -= h;
                    div += (field(k, xp)[v(i, j)] - field(k, xm)[v(i, j)]) / (2.0 * h);
                }
                assert!(
                    div.abs() < 1e-6,
                    "load {k}, {x:?}, row {i}: div σ = {div:e}"
                );
            }
        }
    }
    // And the strain of a Love field is compatible with Hooke's law (finite): a smoke check that
    // the compliance helper keeps the Voigt order.
    let s = compliance(2.0, NU);
    let e = mul6(&s, &pressure_stress(0.2, 0.1, 0.3, 1.0, 0.6, NU));
    assert!(e.iter().all(|v| v.is_finite()));
}

/// The tensor indices are [`Direction`]s, so an index out of `{1, 2, 3}` cannot be written:
/// `ALL[i]` is position `i`, and the Voigt matrices of both kernels are the index forms `D_ijkl`,
/// `Dˢ_ikl` at the [`VOIGT`] pairs, bit for bit (off-diagonal columns `kl + lk`).
#[test]
fn voigt_matrices_are_the_index_forms_at_the_voigt_pairs() {
    for (i, dir) in Direction::ALL.into_iter().enumerate() {
        assert_eq!(dir.index(), i);
    }
    let dir = |i: usize| Direction::ALL[i];
    let a = [0.5, 0.4, 0.6];
    for x in [[0.9, 0.3, -0.8], [0.1, 0.2, 0.3], [0.0; 3]] {
        let sp = StrainPotentials::new(x, a);
        let dv = sp.voigt(NU);
        let dp = DisplacementPotentials::new(x, a);
        let dsv = dp.voigt(NU);
        for (col, &(k, l)) in VOIGT.iter().enumerate() {
            let (k, l) = (dir(k), dir(l));
            for (row, &(i, j)) in VOIGT.iter().enumerate() {
                let (i, j) = (dir(i), dir(j));
                let mut want = sp.d(NU, i, j, k, l);
                if k != l {
                    want += sp.d(NU, i, j, l, k);
                }
                assert_eq!(dv[row][col].to_bits(), want.to_bits(), "D {row} {col}");
            }
            for i in Direction::ALL {
                let mut want = dp.ds(NU, i, k, l);
                if k != l {
                    want += dp.ds(NU, i, l, k);
                }
                let got = dsv[i.index()][col];
                assert_eq!(got.to_bits(), want.to_bits(), "Ds {i:?} {col}");
            }
        }
    }
}
