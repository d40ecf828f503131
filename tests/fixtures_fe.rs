//! The MDR against scikit-fem axisymmetric finite elements (datasets/fe.h5 and datasets/npy/fe_*,
//! written by `python -m verify fe`; see verify/fe.py): a sphere pressed into a homogeneous and two
//! graded half-spaces (k = ±0.3), and the Hertz pressure applied to a homogeneous one.

use std::path::Path;

use halfspace::data::{read_h5_group, read_npy_1d, Manifest, Record};
use halfspace::mdr::{ContactParams, ContactSolution, ContactSolver, Load, Material, Profile};

fn attr(rec: &Record, name: &str) -> f64 {
    rec.float_attr(name)
        .unwrap_or_else(|| panic!("attribute {name}: {:?}", rec.get_attr(name)))
}

/// Linear interpolation in ξ = r² of a field on the MDR grid.
fn at(sol: &ContactSolution, field: &[f64], r: f64) -> f64 {
    let t = sol.grid.fractional_index(r);
    let i = (t.floor() as usize).min(sol.grid.len() - 2);
    let w = t - i as f64;
    (1.0 - w) * field[i] + w * field[i + 1]
}

fn mdr(k: f64, depth: f64) -> ContactSolution {
    let params = ContactParams {
        nodes: 8001,
        domain_ratio: 3.05,
        ..ContactParams::default()
    };
    ContactSolver::new(Material::power_law(1.0, 1.0, 0.3, k).unwrap(), params)
        .unwrap()
        .solve(&Profile::sphere(10.0).unwrap(), Load::Depth(depth))
        .unwrap()
}

#[test]
fn mdr_matches_scikit_fem() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let manifest = Manifest::load(root).unwrap();
    let h5 = manifest.verified("datasets/fe.h5").unwrap();
    let mut report = Vec::new();
    for k in [0.0, 0.3, -0.3] {
        let case = format!("fe_sphere_k{k:+.1}");
        let rec = read_h5_group(&h5, &case).unwrap();
        for array in ["r", "displacement", "pressure_r", "pressure"] {
            let p = manifest
                .verified(&format!("datasets/npy/{case}__{array}.npy"))
                .unwrap();
            assert_eq!(read_npy_1d(&p).unwrap(), rec.get(array).unwrap());
        }
        let depth = attr(&rec, "depth");
        let sol = mdr(k, depth);
        assert!(
            (sol.contact_radius - 1.0).abs() < 1e-9,
            "a = {}",
            sol.contact_radius
        );
        // Pressure: relative L2 over r < 0.95a (the reaction-recovered FE pressure oscillates at the edge).
        let (pr, p) = (rec.get("pressure_r").unwrap(), rec.get("pressure").unwrap());
        let (mut num, mut den) = (0.0, 0.0);
        for (r, pf) in pr.iter().zip(p) {
            if *r < 0.95 {
                let pm = at(&sol, &sol.pressure, *r);
                num += (pm - pf).powi(2);
                den += pm * pm;
            }
        }
        let e_p = (num / den).sqrt();
        // Displacement: max over r ≤ 3a relative to δ, inside and outside the contact.
        let (ru, u) = (rec.get("r").unwrap(), rec.get("displacement").unwrap());
        let e_u = ru
            .iter()
            .zip(u)
            .map(|(r, uf)| (at(&sol, &sol.displacement, *r) - uf).abs() / depth)
            .fold(0.0, f64::max);
        let e_f = (sol.force / attr(&rec, "force") - 1.0).abs();
        let est_p = attr(&rec, "discretization_error_pressure_l2");
        report.push(format!(
            "{case}: pressure L2 {e_p:.2e} (FE discretization estimate {est_p:.1e}), force {e_f:.2e}, displacement {e_u:.2e} δ"
        ));
        // Issue 4 targets: pressure within 2 % (L2, r < 0.95a), displacement within 1 %. Measured
        // well inside them; the pressure difference is of the size of the FE's own discretization
        // estimate (the MDR is exact for a paraboloid up to ~1e-6 here), asserted within 3× of it.
        assert!(
            e_p < 0.02 && e_f < 0.02 && e_u < 0.01,
            "{}",
            report.last().unwrap()
        );
        assert!(e_p < 3.0 * est_p, "{}", report.last().unwrap());
        assert!(e_u < 1e-3 && e_f < 1e-3, "{}", report.last().unwrap());
    }
    // Hertz pressure applied: surface displacement against the MDR's Hertz (δ = a²/R).
    let rec = read_h5_group(&h5, "fe_hertz_load").unwrap();
    let depth = attr(&rec, "depth");
    let sol = mdr(0.0, depth);
    let (ru, u) = (rec.get("r").unwrap(), rec.get("displacement").unwrap());
    let e_u = ru
        .iter()
        .zip(u)
        .map(|(r, uf)| (at(&sol, &sol.displacement, *r) - uf).abs() / depth)
        .fold(0.0, f64::max);
    report.push(format!(
        "fe_hertz_load: displacement {e_u:.2e} δ (FE estimate {:.1e})",
        attr(&rec, "discretization_error_displacement")
    ));
    assert!(e_u < 1e-3, "{}", report.last().unwrap());
    eprintln!("{}", report.join("\n"));
}
