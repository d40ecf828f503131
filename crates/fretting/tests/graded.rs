//! Fretting wear of power-law graded media (docs/fretting-wear.md, "Graded media"): k = 0 is the
//! homogeneous run of before the graded code bit for bit, graded runs approach their limiting
//! contact radius from below, both backends agree, the closed forms are consistent.

use halfspace_fretting::limit::{
    annulus_response, initial_profile, limit_contact_radius, limit_wear_volume, limiting_profile,
    stick_radius,
};
use halfspace_fretting::{FrettingParams, FrettingSimulation};
use halfspace_numerics::{Backend, SquaredGrid};

fn run(params: FrettingParams) -> FrettingSimulation {
    let mut sim = FrettingSimulation::new(params).unwrap();
    sim.run(|_| false).unwrap();
    sim
}

#[test]
fn k0_reproduces_the_homogeneous_run_of_before_bit_for_bit() {
    // `halfspace fretting-wear --n 301 --dtau 0.005 --tau-end 1 --chi 0.5` of commit 6c39993
    // (before the graded code): profile at nodes 100 and 200, a/a0 and p at node 50, final state.
    let sim = run(FrettingParams {
        nodes: 301,
        dtau: 0.005,
        tau_end: 1.0,
        snapshots: vec![0.1, 1.0],
        ..FrettingParams::default()
    });
    let last = sim.state().snapshots.last().unwrap();
    assert_eq!(last.profile[100].to_bits(), 0x3fe00515e36f8620);
    assert_eq!(last.profile[200].to_bits(), 0x3feb4e81b4e81b50);
    assert_eq!(
        sim.state().contact_radius_history.last().unwrap().to_bits(),
        0x3ff18cebfb0391dc
    );
    assert_eq!(last.pressure[50].to_bits(), 0x3fdbb973234d1c72);
}

/// A run of `k`, `chi` on N = 501 nodes with half the a-priori stable step, to `tau_end`.
fn graded(k: f64, chi: f64, tau_end: f64, backend: Backend) -> FrettingSimulation {
    let length = FrettingParams::default_length(chi, k);
    let grid = SquaredGrid::new(501, length).unwrap();
    run(FrettingParams {
        chi,
        k,
        nodes: 501,
        length,
        dtau: 0.5 * FrettingParams::step_limit(&grid, k),
        tau_end,
        snapshots: vec![],
        backend,
    })
}

#[test]
fn graded_runs_approach_the_limiting_radius_from_below() {
    for k in [-0.5, 0.5] {
        for chi in [0.3, 0.9] {
            let sim = graded(k, chi, 3.0, Backend::Fft);
            let r_star = sim.limit_contact_radius();
            let length = sim.grid().length();
            // One cell at the edge: Δr = h / (2 r*) on the grid uniform in r².
            let cell = sim.grid().step() / (2.0 * r_star);
            let history = &sim.state().contact_radius_history;
            let top = history.iter().copied().fold(0.0, f64::max);
            assert!(
                top <= r_star + cell,
                "k {k} χ {chi}: a/a0 reached {top}, r* = {r_star} (cell {cell}, L {length})"
            );
            // It grows (monotonically up to the snapping of the edge to nodes) towards r*.
            let drop = history.windows(2).map(|w| w[0] - w[1]).fold(0.0, f64::max);
            assert!(
                drop <= 3.0 * cell,
                "k {k} χ {chi}: a/a0 fell by {drop} (cell {cell})"
            );
            let last = *history.last().unwrap();
            assert!(last > 1.0 && last <= r_star + cell, "k {k} χ {chi}: {last}");
            // The worn volume grows towards its limit.
            assert!(sim.wear_volume() > 0.0);
            println!(
                "k {k:+} χ {chi}: a/a0 {last:.4} → r* {r_star:.4} (largest fall {:.2} cells), V {:.4e} → V∞ {:.4e}",
                drop / cell,
                sim.wear_volume(),
                sim.limit_wear_volume()
            );
        }
    }
}

#[test]
fn mvm_and_fft_agree_over_300_steps() {
    for k in [-0.5, 0.5] {
        let length = FrettingParams::default_length(0.5, k);
        let grid = SquaredGrid::new(501, length).unwrap();
        let dtau = 0.5 * FrettingParams::step_limit(&grid, k);
        let params = |backend| FrettingParams {
            chi: 0.5,
            k,
            nodes: 501,
            length,
            dtau,
            tau_end: 300.0 * dtau,
            snapshots: vec![],
            backend,
        };
        let fft = run(params(Backend::Fft));
        let mvm = run(params(Backend::Mvm));
        assert_eq!(fft.state().step, 300);
        let worst = fft
            .state()
            .profile
            .iter()
            .zip(&mvm.state().profile)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-10, "k {k}: {worst:e}");
        assert_eq!(
            fft.state().contact_radius_history,
            mvm.state().contact_radius_history
        );
    }
}

#[test]
fn graded_closed_forms_are_consistent() {
    for k in [-0.5, -0.25, 0.25, 0.5, 0.9] {
        for chi in [0.1, 0.5, 0.9] {
            let c = stick_radius(chi);
            // f∞ is continuous at c and meets f₀ at r*.
            // f∞ − f₀ rises like (r² − c²)^{(1−k)/2} beyond c (the incomplete beta near 1).
            let delta: f64 = 1e-12;
            let jump = (limiting_profile(c * (1.0 + delta), chi, k) - initial_profile(c, k)).abs();
            assert!(
                jump < (2.0 * delta).powf(0.5 * (1.0 - k)),
                "k {k} χ {chi}: {jump:e}"
            );
            let r_star = limit_contact_radius(chi, k);
            approx::assert_abs_diff_eq!(
                limiting_profile(r_star, chi, k),
                initial_profile(r_star, k),
                epsilon = 1e-13
            );
            // A unit 1D displacement everywhere gives a unit 3D displacement (c → 0).
            approx::assert_relative_eq!(annulus_response(1.0, 1e-300, k), 1.0, epsilon = 1e-14);
            assert!(limit_wear_volume(chi, k) > 0.0);
        }
    }
    // The homogeneous values of spec §5.
    approx::assert_abs_diff_eq!(limit_contact_radius(0.5, 0.0), 1.1397, epsilon = 5e-5);
}

#[test]
fn bad_grading_is_refused() {
    for k in [-1.0, 1.0, f64::NAN] {
        let e = FrettingSimulation::new(FrettingParams {
            k,
            ..FrettingParams::default()
        })
        .err()
        .unwrap();
        assert!(e.to_string().contains("grading exponent k"), "{e}");
    }
    // A domain too small for the graded contact's growth.
    let e = FrettingSimulation::new(FrettingParams {
        k: -0.5,
        chi: 0.9,
        length: 1.5,
        dtau: 1e-4,
        ..FrettingParams::default()
    })
    .err()
    .unwrap();
    assert!(e.to_string().contains("r* ="), "{e}");
}
