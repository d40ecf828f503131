//! The MDR cross-check of 3D fretting wear on CI's grids (docs/wear3d.md#the-mdr-cross-check):
//! the tolerances are those of the convergence table there (32² and 64², default steps), with a
//! margin of about a third: 32² to τ = 3 (cell 0.1 a₀) and 64² to τ = 1 (cell 0.05 a₀).

use halfspace::wear3d_mdr::{mdr_cross_check, CrossCheckParams};

fn check(grid: usize, taus: Vec<f64>, radius_tol: f64, profile_tol: f64, volume_tol: f64) {
    let c = mdr_cross_check(&CrossCheckParams {
        grid,
        taus: taus.clone(),
        ..CrossCheckParams::default()
    })
    .expect("cross-check");
    assert_eq!(c.rows.len(), taus.len());
    for r in &c.rows {
        let rel = |a: f64, b: f64| (a - b).abs() / b;
        assert!(
            rel(r.contact_radius_3d, r.contact_radius_mdr) < radius_tol,
            "{grid}² τ = {}: a {} vs {}",
            r.tau,
            r.contact_radius_3d,
            r.contact_radius_mdr
        );
        assert!(
            rel(r.profile_at_a0_3d, r.profile_at_a0_mdr) < profile_tol,
            "{grid}² τ = {}: f(a0) {} vs {}",
            r.tau,
            r.profile_at_a0_3d,
            r.profile_at_a0_mdr
        );
        assert!(
            rel(r.volume_3d, r.volume_mdr) < volume_tol,
            "{grid}² τ = {}: V {} vs {}",
            r.tau,
            r.volume_3d,
            r.volume_mdr
        );
        // The stick radius √(1 − χ) a₀ to one cell: the stick zone never wears.
        assert!(
            (r.stick_radius_3d - 0.5f64.sqrt()).abs() < c.cell_over_a0,
            "{grid}² τ = {}: c {}",
            r.tau,
            r.stick_radius_3d
        );
    }
}

#[test]
fn wear3d_matches_mdr_at_32() {
    // Measured: a 0.09/0.77/0.92 %, f(a0) 0.37/0.50/0.75 %, V 1.3/0.8/3.3 %.
    check(32, vec![0.1, 1.0, 3.0], 0.013, 0.01, 0.045);
}

#[test]
fn wear3d_matches_mdr_at_64() {
    // Measured: a 0.54/0.00 %, f(a0) 0.01/0.18 %, V 1.3/1.0 %.
    check(64, vec![0.1, 1.0], 0.0075, 0.003, 0.018);
}
