//! Bad input gets a typed error that names the value, never a panic or NaN.

use halfspace_mdr::*;

fn solver(n: usize) -> Result<ContactSolver, MdrError> {
    ContactSolver::new(
        Material::from_e_star(1.0).unwrap(),
        ContactParams {
            nodes: n,
            ..Default::default()
        },
    )
}

#[test]
fn too_few_nodes() {
    let e = solver(7).err().expect("N = 7 is refused");
    assert!(e.to_string().contains("at least 8"), "{e}");
    assert!(solver(8).is_ok());
}

#[test]
fn non_finite_and_non_positive_loads() {
    let mut s = solver(101).unwrap();
    let sphere = Profile::sphere(1.0).unwrap();
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = s.solve(&sphere, Load::Depth(bad)).unwrap_err();
        assert!(matches!(e, MdrError::InvalidParameter { .. }), "{e}");
        assert!(e.to_string().contains("depth"), "{e}");
        let e = s.solve(&sphere, Load::Force(bad)).unwrap_err();
        assert!(e.to_string().contains("force"), "{e}");
    }
}

#[test]
fn bad_solver_parameters() {
    for ratio in [0.5, f64::NAN] {
        let e = ContactSolver::new(
            Material::from_e_star(1.0).unwrap(),
            ContactParams {
                domain_ratio: ratio,
                ..Default::default()
            },
        )
        .err()
        .unwrap();
        assert!(e.to_string().contains("domain ratio"), "{e}");
    }
    // A domain so large that the contact keeps fewer than 8 nodes.
    let mut s = ContactSolver::new(
        Material::from_e_star(1.0).unwrap(),
        ContactParams {
            nodes: 101,
            domain_ratio: 50.0,
            ..Default::default()
        },
    )
    .unwrap();
    let e = s
        .solve(&Profile::sphere(1.0).unwrap(), Load::Depth(0.1))
        .unwrap_err();
    assert!(e.to_string().contains("domain ratio"), "{e}");
}

#[test]
fn contact_beyond_the_table_is_refused() {
    let r: Vec<f64> = (0..51).map(|i| i as f64 * 0.01).collect();
    let f: Vec<f64> = r.iter().map(|x| x * x).collect();
    let table = Profile::tabulated(r, f).unwrap();
    let mut s = solver(501).unwrap();
    // g = 2x² for f = r²: a = √(δ/2); the table ends at 0.5, so δ = 0.6 needs a = 0.55.
    let e = s.solve(&table, Load::Depth(0.6)).unwrap_err();
    assert!(matches!(e, MdrError::ContactOutsideDomain { .. }), "{e}");
    assert!(e.to_string().contains("table"), "{e}");
    let e = s.solve(&table, Load::Force(10.0)).unwrap_err();
    assert!(matches!(e, MdrError::ContactOutsideDomain { .. }), "{e}");
    // Inside the table it works and matches the paraboloid closed form (c = 1 ↔ R = 1/2).
    let sol = s.solve(&table, Load::Depth(0.2)).unwrap();
    assert!((sol.contact_radius - 0.1f64.sqrt()).abs() < 1e-6 * 0.1f64.sqrt());
}

#[test]
fn non_convex_profile_is_named() {
    // f = r² − r⁴ on [0, 1.2] turns over at r = 0.707: g stops increasing before the contact edge.
    let r: Vec<f64> = (0..121).map(|i| i as f64 * 0.01).collect();
    let f: Vec<f64> = r.iter().map(|x| x * x - x.powi(4)).collect();
    let table = Profile::tabulated(r, f).unwrap();
    let mut s = solver(1001).unwrap();
    let e = s.solve(&table, Load::Depth(0.6)).unwrap_err();
    assert!(matches!(e, MdrError::NonConvexProfile { .. }), "{e}");
    assert!(e.to_string().contains("convex"), "{e}");
}

#[test]
fn transforms_refuse_wrong_lengths() {
    let grid = SquaredGrid::new(16, 1.0).unwrap();
    let mut pt =
        ProfileTransform::new(8, &Material::from_e_star(1.0).unwrap(), Backend::Fft).unwrap();
    let mut g = vec![0.0; 16];
    assert!(
        pt.apply(&grid, &[0.0; 16], &mut g).is_err(),
        "grid larger than the capacity"
    );
    let mut st =
        StressTransform::new(16, &Material::from_e_star(1.0).unwrap(), Backend::Fft).unwrap();
    assert!(st
        .line_load_to_stress(&grid, &[1.0, 0.0], 0.0, &mut [0.0; 2])
        .is_err());
    let mut dt =
        DisplacementTransform::new(16, &unit_material(), DisplacementMethod::DenseKernel).unwrap();
    assert!(dt.apply(&grid, &[1.0; 4], f64::NAN, &mut g).is_err());
    assert!(dt.apply(&grid, &[1.0; 17], 0.0, &mut g).is_err());
}

fn unit_material() -> Material {
    Material::from_e_star(1.0).unwrap()
}
