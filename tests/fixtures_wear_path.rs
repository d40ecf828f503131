//! The fretting-wear path of the library (grid uniform in r², power sums, the edge between nodes,
//! explicit Euler) against an independent solver (datasets/wear_path.h5 and
//! datasets/npy/wear_path__*, written by `python -m verify wear-path`; verify/wear_path.py: grid
//! uniform in r, exact cell integrals by scipy's incomplete beta and ₂F₁, Heun steps): the contact
//! radius a/a0, the worn depth f(a0)/d and the wear volume V/(π a0² d) along the path, for
//! (k, χ) = (0, 0.5) (the reference run of docs/theory-mdr.md#fretting-wear), (0.5, 0.9) and (−0.5, 0.5). Both file formats are
//! read; every file's sha256 is checked against datasets/MANIFEST.json.

use std::path::Path;

use halfspace::data::{read_h5_group, read_npy_1d, Manifest, Record};
use halfspace::fretting::limit::initial_profile;
use halfspace::fretting::{FrettingParams, FrettingSimulation, GapTransform, TimeStepping};

fn attr(rec: &Record, name: &str) -> f64 {
    rec.float_attr(name)
        .unwrap_or_else(|| panic!("attribute {name}: {:?}", rec.get_attr(name)))
}

#[test]
fn the_wear_path_matches_the_independent_solver() {
    let manifest = Manifest::load(Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap();
    let h5 = manifest.verified("datasets/wear_path.h5").unwrap();
    for case in [
        "wear_path/k+0.00_chi0.5",
        "wear_path/k+0.50_chi0.9",
        "wear_path/k-0.50_chi0.5",
    ] {
        let rec = read_h5_group(&h5, case).unwrap();
        let stem = case.replace('/', "__");
        for array in ["tau", "contact_radius", "profile_at_a0", "wear_volume"] {
            let npy = manifest
                .verified(&format!("datasets/npy/{stem}__{array}.npy"))
                .unwrap();
            assert_eq!(read_npy_1d(&npy).unwrap(), rec.get(array).unwrap());
        }
        let (k, chi) = (attr(&rec, "k"), attr(&rec, "chi"));
        let taus = rec.get("tau").unwrap().to_vec();
        let (nodes, length) = (2001, attr(&rec, "length"));
        // The central differences by explicit Euler (the path this reference was made for), and
        // the default discretization (the piecewise-linear transform with the edge cells, since
        // stop 45) by the default adaptive steps.
        let base = FrettingParams {
            chi,
            k,
            nodes,
            length,
            tau_end: *taus.last().unwrap(),
            snapshots: taus.clone(),
            ..FrettingParams::default()
        };
        let runs = [
            (
                "central differences, explicit Euler",
                FrettingParams {
                    stepping: TimeStepping::ExplicitEuler {
                        dtau: FrettingParams::default_step(nodes, length, k),
                    },
                    gap_transform: GapTransform::CentralDifferences,
                    edge_cells: false,
                    ..base.clone()
                },
            ),
            ("default, adaptive", base),
        ];
        for (label, params) in runs {
            let mut sim = FrettingSimulation::new(params).unwrap();
            sim.run(|_| false).unwrap();
            let grid = sim.grid();
            let t = grid.fractional_index(1.0);
            let (i0, w) = (t.floor() as usize, t - t.floor());
            let snaps = &sim.state().snapshots;
            assert_eq!(snaps.len(), taus.len());
            for (j, s) in snaps.iter().enumerate() {
                let f_a0 = (1.0 - w) * s.profile[i0] + w * s.profile[i0 + 1];
                let worn: Vec<f64> = grid
                    .coordinates()
                    .iter()
                    .zip(&s.profile)
                    .map(|(&r, &f)| f - initial_profile(r, k))
                    .collect();
                let volume = halfspace::numerics::quad::trapezoid_uniform(&worn, grid.step());
                let (a_ref, f_ref, v_ref) = (
                    rec.get("contact_radius").unwrap()[j],
                    rec.get("profile_at_a0").unwrap()[j],
                    rec.get("wear_volume").unwrap()[j],
                );
                // The reference's own error: its fine grid against a grid of half the cells.
                let own = |name: &str| {
                    (rec.get(name).unwrap()[j] - rec.get(&format!("{name}_coarse")).unwrap()[j])
                        .abs()
                };
                let (da, df, dv) = (
                    (s.contact_radius - a_ref).abs(),
                    (f_a0 - f_ref).abs(),
                    (volume / v_ref - 1.0).abs(),
                );
                println!(
                "{case} ({label}) τ = {}: a {:.5} vs {a_ref:.5} (Δ {da:.1e}, ref ±{:.1e}), f(a0) {f_a0:.5} vs \
                 {f_ref:.5} (Δ {df:.1e}, ref ±{:.1e}), V {volume:.5} vs {v_ref:.5} (Δ {:.1e} rel, ref \
                 ±{:.1e})",
                taus[j],
                s.contact_radius,
                own("contact_radius"),
                own("profile_at_a0"),
                dv,
                own("wear_volume") / v_ref
            );
                // Both solvers converge (library: f(a0, τ = 1) 0.56069 / 0.56068 / 0.56068 at
                // N = 1001 / 2001 / 4001; reference: fine vs coarse above); the bounds are a few times
                // the larger of the two own errors.
                assert!(da < 2e-3, "{case} ({label}) τ = {}: a {da:e}", taus[j]);
                assert!(df < 5e-4, "{case} ({label}) τ = {}: f(a0) {df:e}", taus[j]);
                assert!(dv < 1e-2, "{case} ({label}) τ = {}: V {dv:e}", taus[j]);
            }
        }
    }
}
