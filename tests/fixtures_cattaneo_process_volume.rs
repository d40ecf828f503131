//! The maxima of the four fatigue indices on the stress history averaged over a process volume
//! (a cube of side ℓ, its top face on the surface within ℓ/2 of it; docs/fatigue.md, "Process
//! volume"), of the Cattaneo–Mindlin fretting loop of two identical bodies (E = 210 GPa, ν = 0.3,
//! R = 105 μm, W = 80 mN, μ = 0.3, Q*/μW = 0.5; the loop of tests/fixtures_cattaneo_fatigue.rs),
//! against the independent Gauss cubature over the cubes of the Boussinesq/Cerruti integrals of
//! the closed-form Mindlin–Deresiewicz tractions (verify/cattaneo_process_volume.py →
//! datasets/cattaneo_process_volume.h5), for ℓ = 0.25a, on 32² and 64² (and 128² with
//! `GRIDS=32,64,128`): the maxima and the centres of their cubes converge to the reference's.

use std::path::Path;

use halfspace::config::FatigueConfig;
use halfspace::data::{read_h5_group, Manifest};
use halfspace::fatigue::{evaluate_field, FieldParams, Material};
use halfspace::loop_fatigue::evaluate_loop_fatigue;
use halfspace::sam::drivers::fretting_loop::{FrettingLoop, LoopCase};
use halfspace::sam::Body;

const NAMES: [&str; 4] = ["Crossland", "Dang Van", "SWT", "Fatemi–Socie"];

/// The completed Cattaneo–Mindlin loop on `n²` with its stress history down to 0.6a.
fn cattaneo_loop(n: usize) -> FrettingLoop {
    let mut case = LoopCase {
        indenter: Body::Elastic { e: 210e9, nu: 0.3 },
        normal_steps: 8,
        grid: n,
        ..LoopCase::default()
    };
    case.amplitude = case.mindlin_slip_shift() * (1.0 - 0.5f64.powf(2.0 / 3.0));
    case.shift_step = case.amplitude / 10.0;
    case.fatigue_depth = Some(0.6 * case.hertz_radius());
    let mut lp = FrettingLoop::new(case).unwrap();
    lp.run(|_| std::ops::ControlFlow::Continue(())).unwrap();
    lp
}

fn steel() -> Material {
    Material {
        f_minus1: 400e6,
        t_minus1: 280e6,
        young: 210e9,
        poisson: 0.3,
        fs_k: 0.5,
        yield_stress: 600e6,
    }
}

/// The reference of one side: the maximum of each criterion over the lattice of cubes with top
/// faces on the surface, refined by a parabola through the largest lattice value and its
/// neighbours along x and along y (y mirrored at 0), and its cube centre `(x, y, ℓ/2)/a`; and the
/// largest value of the cubes one lattice step deeper.
struct Reference {
    max: [f64; 4],
    at: [[f64; 3]; 4],
    deeper: [f64; 4],
}

fn reference(side: f64, p0: f64) -> Reference {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let manifest = Manifest::load(root).expect("datasets/MANIFEST.json");
    let h5 = manifest
        .verified("datasets/cattaneo_process_volume.h5")
        .unwrap();
    let rec = read_h5_group(&h5, &format!("cattaneo_pv_{side}")).unwrap();
    let centres = rec.get("centres").unwrap().to_vec();
    let stress: Vec<f64> = rec
        .get("stress")
        .unwrap()
        .to_vec()
        .iter()
        .map(|s| s * p0)
        .collect();
    let cubes = centres.len() / 3;
    assert_eq!(stress.len(), cubes * 41 * 6);
    let f = evaluate_field(&stress, cubes, 41, &steel(), &FieldParams::default()).unwrap();
    let fields = [f.crossland, f.dang_van, f.swt, f.fatemi_socie];
    // The lattice: x slow, then y, then the two tops.
    let d = side / 4.0;
    let x0 = centres[0];
    let nx = ((centres[3 * (cubes - 1)] - x0) / d).round() as usize + 1;
    let ny = cubes / (2 * nx);
    assert_eq!(nx * ny * 2, cubes);
    let mut out = Reference {
        max: [0.0; 4],
        at: [[0.0; 3]; 4],
        deeper: [f64::NEG_INFINITY; 4],
    };
    for (c, field) in fields.iter().enumerate() {
        let v = |a: usize, b: isize| field[(a * ny + b.unsigned_abs()) * 2];
        let (mut ba, mut bb) = (0, 0);
        for a in 0..nx {
            for b in 0..ny {
                if v(a, b as isize) > v(ba, bb as isize) {
                    (ba, bb) = (a, b);
                }
                out.deeper[c] = out.deeper[c].max(field[(a * ny + b) * 2 + 1]);
            }
        }
        if std::env::var("PV_DEBUG").is_ok() {
            for a in 0..nx {
                let row: Vec<String> = (0..ny)
                    .map(|b| format!("{:.4e}", v(a, b as isize)))
                    .collect();
                eprintln!("{} x={:.4}: {}", NAMES[c], x0 + a as f64 * d, row.join(" "));
            }
        }
        assert!(
            ba > 0 && ba + 1 < nx && bb + 1 < ny,
            "ℓ = {side}a, {}: the lattice maximum at ({ba}, {bb}) is on the lattice's edge",
            NAMES[c]
        );
        let f0 = v(ba, bb as isize);
        // Parabola through three values: vertex offset (in steps) and value.
        let vertex = |m: f64, p: f64| {
            let curv = m - 2.0 * f0 + p;
            let off = 0.5 * (m - p) / curv;
            (off, -0.125 * (m - p) * (m - p) / curv)
        };
        let (ox, gx) = vertex(v(ba - 1, bb as isize), v(ba + 1, bb as isize));
        let (oy, gy) = vertex(v(ba, bb as isize - 1), v(ba, bb as isize + 1));
        out.max[c] = f0 + gx + gy;
        out.at[c] = [
            x0 + (ba as f64 + ox) * d,
            (bb as f64 + oy).abs() * d,
            side / 2.0,
        ];
    }
    out
}

#[test]
fn process_volume_maxima_and_their_locations_converge_to_the_cubature() {
    let grids: Vec<usize> = std::env::var("GRIDS")
        .map(|g| g.split(',').map(|v| v.trim().parse().unwrap()).collect())
        .unwrap_or_else(|_| vec![32, 64]);
    // ℓ = 0.5a: the generator has it (verify/cattaneo_process_volume.py SIDES), not yet in the
    // committed fixture.
    let sides = [0.25];
    // errors[side][grid][criterion]: (relative |Δmax|, distance of the cube centres in cells).
    let mut errors = vec![Vec::new(); sides.len()];
    for &n in &grids {
        let lp = cattaneo_loop(n);
        let (a, p0) = (lp.case().hertz_radius(), lp.case().hertz_pressure());
        let cell = 4.16 / n as f64;
        for (s, &side) in sides.iter().enumerate() {
            let cfg = FatigueConfig {
                f_minus1: 400e6,
                t_minus1: 280e6,
                fs_k: 0.5,
                yield_stress: 600e6,
                depth_over_a: 0.6,
                screen_fraction: 0.5,
                inhomogeneity: None,
                process_volume: Some(side * a),
                own: Vec::new(),
            };
            let f = evaluate_loop_fatigue(&lp, &cfg).unwrap();
            let v = f.process_volume.as_ref().unwrap();
            // The JSON keys and the results.h5 record carry the same maxima.
            let summary = f.summary();
            assert_eq!(
                summary["crossland_pv_max"].as_f64(),
                Some(v.indices.crossland_max.value)
            );
            assert_eq!(summary["swt_pv_max_at"][0].as_f64(), Some(v.at[2][0]));
            assert_eq!(summary["process_volume"]["side"].as_f64(), Some(side * a));
            let rec = f.record(halfspace::data::Record::default());
            // Every field the XDMF file lists is in the record with the lattice's shape.
            assert_eq!(f.volume_fields().len(), 8);
            for name in f.volume_fields() {
                assert_eq!(rec.shape_of(&name), Some(vec![f.layers, n, n]), "{name}");
            }
            let r = reference(side, p0);
            let i = &v.indices;
            let got = [
                i.crossland_max.value,
                i.dang_van_max.value,
                i.swt_max.value,
                i.fatemi_socie_max.value,
            ];
            let pointwise = [
                f.indices.crossland_max.value,
                f.indices.dang_van_max.value,
                f.indices.swt_max.value,
                f.indices.fatemi_socie_max.value,
            ];
            let mut row = [(0.0, 0.0); 4];
            for c in 0..4 {
                let at = v.at[c];
                let at = [at[0].abs() / a, at[1].abs() / a, at[2] / a];
                let rel = (got[c] - r.max[c]).abs() / r.max[c].abs();
                let dist = ((at[0] - r.at[c][0]).powi(2)
                    + (at[1] - r.at[c][1]).powi(2)
                    + (at[2] - r.at[c][2]).powi(2))
                .sqrt()
                    / cell;
                eprintln!(
                    "ℓ = {side}a, {n}², {:>12}: grid {:.5e} at ({:.4}, {:.4}, {:.4})a, reference \
                     {:.5e} at ({:.4}, {:.4}, {:.4})a (one step deeper {:.5e}): rel. {rel:.2e}, \
                     {dist:.2} cells apart; pointwise max {:.5e}",
                    NAMES[c],
                    got[c],
                    at[0],
                    at[1],
                    at[2],
                    r.max[c],
                    r.at[c][0],
                    r.at[c][1],
                    r.at[c][2],
                    r.deeper[c],
                    pointwise[c]
                );
                // The reference's maximum sits in the cubes at the surface.
                assert!(r.deeper[c] < r.max[c], "ℓ = {side}a, {}", NAMES[c]);
                // Averaging lowers the surface maxima.
                assert!(got[c] < pointwise[c], "ℓ = {side}a, {n}², {}", NAMES[c]);
                row[c] = (rel, dist);
            }
            errors[s].push(row);
        }
    }
    for (s, &side) in sides.iter().enumerate() {
        for c in 0..4 {
            let e: Vec<f64> = errors[s].iter().map(|r| r[c].0).collect();
            let orders: Vec<f64> = e.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
            eprintln!(
                "ℓ = {side}a, {}: relative errors {:?} on {grids:?}, orders {orders:.2?}",
                NAMES[c],
                e.iter().map(|v| format!("{v:.2e}")).collect::<Vec<_>>()
            );
            // Measured (ℓ = 0.25a): 32² → 64² → 128² Crossland 7.1e-2 → 1.0e-2 → 6.9e-3, Dang
            // Van 3.0e-2 → 2.4e-3 → 5.1e-3, SWT 3.3e-2 → 5.3e-3 → 7.8e-3, Fatemi–Socie 4.8e-2 →
            // 2.7e-3 → 3.1e-4 (orders 2.6–4.2, then a plateau at 0.3–0.8 %: the reference's own
            // error or the tractions', not separated); the cube centres ≤ 1.54 cells apart on
            // 32², ≤ 0.63 on 64² and 128² (the grid has no cell on y = 0: half a cell is the
            // closest it can be).
            assert!(
                orders.first().is_none_or(|&o| o > 1.5),
                "ℓ = {side}a, {}: no convergence {e:?}",
                NAMES[c]
            );
            let finest = grids.iter().zip(&errors[s]).next_back().unwrap();
            if *finest.0 >= 64 {
                assert!(
                    finest.1[c].0 < 1.5e-2,
                    "ℓ = {side}a, {}, {}²: {:e}",
                    NAMES[c],
                    finest.0,
                    finest.1[c].0
                );
                assert!(
                    finest.1[c].1 <= 1.0,
                    "ℓ = {side}a, {}: {} cells apart",
                    NAMES[c],
                    finest.1[c].1
                );
            }
        }
    }
}
