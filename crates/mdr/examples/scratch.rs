use halfspace_mdr::*;
fn main() {
    for backend in [Backend::Fft, Backend::Mvm] {
        let mut s = ContactSolver::new(
            Material::from_e_star(1.0).unwrap(),
            ContactParams {
                backend,
                ..Default::default()
            },
        )
        .unwrap();
        for (name, prof, load) in [
            ("sphere", Profile::sphere(1.0).unwrap(), Load::Depth(0.25)),
            (
                "sphereF",
                Profile::sphere(1.0).unwrap(),
                Load::Force(1.0 / 6.0),
            ),
            (
                "cone",
                Profile::cone(0.1).unwrap(),
                Load::Depth(0.0785398163397448),
            ),
            (
                "r3",
                Profile::power(1.0, 3.0).unwrap(),
                Load::Depth(0.2945243112740431),
            ),
            (
                "r4",
                Profile::power(1.0, 4.0).unwrap(),
                Load::Force(0.1333333333333333),
            ),
            ("flat", Profile::flat_punch(0.5).unwrap(), Load::Depth(0.1)),
        ] {
            let sol = s.solve(&prof, load).unwrap();
            let a = sol.contact_radius;
            let mut maxerr_u: f64 = 0.0;
            let mut maxerr_p: f64 = 0.0;
            for (i, r) in sol.radii().iter().enumerate() {
                if name.starts_with("sphere") {
                    maxerr_u = maxerr_u.max(
                        (sol.displacement[i] - analytic::sphere_displacement(*r, a, 1.0)).abs(),
                    );
                    if i < sol.edge_index {
                        maxerr_p = maxerr_p.max(
                            (sol.pressure[i] - analytic::sphere_pressure(*r, a, 1.0, 1.0)).abs(),
                        );
                    }
                }
                if name == "flat" {
                    maxerr_u = maxerr_u.max(
                        (sol.displacement[i] - analytic::flat_punch_displacement(*r, a, 0.1)).abs(),
                    );
                    if i < sol.edge_index {
                        maxerr_p = maxerr_p.max(
                            ((sol.pressure[i] - analytic::flat_punch_pressure(*r, a, 0.1, 1.0))
                                / sol.pressure[i])
                                .abs(),
                        );
                    }
                }
                if name == "cone" && i > 0 && i < sol.edge_index {
                    maxerr_p = maxerr_p
                        .max((sol.pressure[i] - analytic::cone_pressure(*r, a, 0.1, 1.0)).abs());
                }
            }
            println!("{backend:?} {name}: a={a:.9} d={:.9} F={:.9} p0={:.9} it={} |du|={maxerr_u:.2e} |dp|={maxerr_p:.2e}", sol.depth, sol.force, sol.pressure[0], sol.iterations);
        }
    }
}
