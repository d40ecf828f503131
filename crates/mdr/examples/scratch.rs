use halfspace_mdr::*;
fn main() {
    // 1. raw Eq 7 sphere
    for n in [101usize, 1001, 2001] {
        let grid = SquaredGrid::new(n, 1.0).unwrap();
        let mut t =
            ProfileTransform::new(n, &Material::from_e_star(1.0).unwrap(), Backend::Fft).unwrap();
        let slope = vec![0.5; n];
        let mut g = vec![0.0; n];
        t.apply(&grid, &slope, &mut g).unwrap();
        let e = (0..n)
            .map(|i| (g[i] - grid.squared(i)).abs())
            .fold(0.0, f64::max);
        // r^3 via split
        let p = Profile::power(1.0, 3.0).unwrap();
        t.profile_to_equivalent(&p, &grid, &mut g).unwrap();
        let e3 = (0..n)
            .map(|i| (g[i] - analytic::power_depth(grid.coordinate(i), 1.0, 3.0)).abs())
            .fold(0.0, f64::max);
        let p = Profile::power(1.0, 4.0).unwrap();
        t.profile_to_equivalent(&p, &grid, &mut g).unwrap();
        let e4 = (0..n)
            .map(|i| (g[i] - analytic::power_depth(grid.coordinate(i), 1.0, 4.0)).abs())
            .fold(0.0, f64::max);
        let p = Profile::cone(0.1).unwrap();
        t.profile_to_equivalent(&p, &grid, &mut g).unwrap();
        let ec = (0..n)
            .map(|i| (g[i] - analytic::cone_depth(grid.coordinate(i), 0.1)).abs())
            .fold(0.0, f64::max);
        println!("eq7 N={n}: sphere raw {e:.3e}  r3 split {e3:.3e} r4 {e4:.3e} cone {ec:.3e}");
    }
    // 4. U = x^4
    for n in [101usize, 1001, 2001, 10001] {
        let grid = SquaredGrid::new(n, 1.0).unwrap();
        let u: Vec<f64> = (0..n).map(|i| grid.squared(i).powi(2)).collect();
        for m in [
            DisplacementMethod::ArccosKernel,
            DisplacementMethod::Convolution(Backend::Fft),
        ] {
            let mut t = DisplacementTransform::new(n, m).unwrap();
            let mut out = vec![0.0; n];
            t.apply(&grid, &u, 0.0, &mut out).unwrap();
            let e: f64 = (1..n)
                .map(|j| {
                    ((out[j] - analytic::quartic_displacement(grid.coordinate(j)))
                        / analytic::quartic_displacement(grid.coordinate(j)))
                    .abs()
                })
                .sum::<f64>()
                / (n - 1) as f64;
            let emax = (1..n)
                .map(|j| (out[j] - analytic::quartic_displacement(grid.coordinate(j))).abs())
                .fold(0.0, f64::max);
            println!("x4 N={n} {m:?}: mean rel {e:.3e} max abs {emax:.3e}");
        }
    }
    // 5. Hertz a=0.7 L=1
    for n in [101usize, 1001, 4001] {
        let grid = SquaredGrid::new(n, 1.0).unwrap();
        let m = ((n - 1) as f64 * 0.49).round() as usize;
        let a = 0.7;
        let u: Vec<f64> = (0..=m).map(|i| a * a - grid.squared(i)).collect();
        for meth in [
            DisplacementMethod::ArccosKernel,
            DisplacementMethod::Convolution(Backend::Fft),
        ] {
            let mut t = DisplacementTransform::new(n, meth).unwrap();
            let mut out = vec![0.0; n];
            t.apply(&grid, &u, 0.0, &mut out).unwrap();
            let emax = (0..n)
                .map(|j| (out[j] - analytic::sphere_displacement(grid.coordinate(j), a, 1.0)).abs())
                .fold(0.0, f64::max);
            println!("hertz N={n} {meth:?}: max abs {emax:.3e}");
        }
    }
    // 6. Eq 18
    for n in [11usize, 101, 1001, 2001, 10001, 100001] {
        let grid = SquaredGrid::new(n, 1.0).unwrap();
        let q: Vec<f64> = (0..n).map(|i| 1.0 - grid.squared(i).powi(2)).collect();
        let mut t =
            StressTransform::new(n, &Material::from_e_star(1.0).unwrap(), Backend::Fft).unwrap();
        let mut s = vec![0.0; n];
        t.line_load_to_stress(&grid, &q, 0.0, &mut s).unwrap();
        let e: f64 = (0..n - 1)
            .map(|j| {
                ((s[j] - analytic::quartic_load_stress(grid.coordinate(j), 1.0))
                    / analytic::quartic_load_stress(grid.coordinate(j), 1.0))
                .abs()
            })
            .sum::<f64>()
            / (n - 1) as f64;
        println!("eq18 N={n}: eps {e:.3e}");
    }
    // 3. contacts at N=2001
    let mut s = ContactSolver::new(
        Material::from_e_star(1.0).unwrap(),
        ContactParams::default(),
    )
    .unwrap();
    for (name, prof, load, a_ex, d_ex, f_ex) in [
        (
            "cone",
            Profile::cone(0.1).unwrap(),
            Load::Depth(analytic::cone_depth(0.5, 0.1)),
            0.5,
            analytic::cone_depth(0.5, 0.1),
            analytic::cone_force(0.5, 0.1, 1.0),
        ),
        (
            "r3",
            Profile::power(1.0, 3.0).unwrap(),
            Load::Depth(analytic::power_depth(0.5, 1.0, 3.0)),
            0.5,
            analytic::power_depth(0.5, 1.0, 3.0),
            analytic::power_force(0.5, 1.0, 3.0, 1.0),
        ),
        (
            "r4",
            Profile::power(1.0, 4.0).unwrap(),
            Load::Force(analytic::power_force(0.5, 1.0, 4.0, 1.0)),
            0.5,
            analytic::power_depth(0.5, 1.0, 4.0),
            analytic::power_force(0.5, 1.0, 4.0, 1.0),
        ),
        (
            "r1.5",
            Profile::power(1.0, 1.5).unwrap(),
            Load::Force(analytic::power_force(0.5, 1.0, 1.5, 1.0)),
            0.5,
            analytic::power_depth(0.5, 1.0, 1.5),
            analytic::power_force(0.5, 1.0, 1.5, 1.0),
        ),
    ] {
        let sol = s.solve(&prof, load).unwrap();
        let mut pe = 0.0;
        let mut cnt = 0;
        if name == "cone" {
            for j in 1..sol.edge_index {
                let r = sol.grid.coordinate(j);
                pe += ((sol.pressure[j]
                    - analytic::cone_pressure(r, sol.contact_radius, 0.1, 1.0))
                    / analytic::cone_pressure(r, sol.contact_radius, 0.1, 1.0))
                .abs();
                cnt += 1;
            }
        }
        println!(
            "{name}: a {:.2e} d {:.2e} F {:.2e} p_cone_meanrel {:.2e}",
            (sol.contact_radius - a_ex) / a_ex,
            (sol.depth - d_ex) / d_ex,
            (sol.force - f_ex) / f_ex,
            pe / (cnt.max(1) as f64)
        );
    }
}
