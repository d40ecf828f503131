//! The fretting loop of two identical bodies (elastic indenter, E = 210 GPa, ν = 0.3, R = 105 μm,
//! W = 80 mN, μ = 0.3, Q*/μW = 0.5) against the independent cubature of the Boussinesq/Cerruti
//! stresses of the closed-form Mindlin–Deresiewicz tractions (verify/cattaneo_fatigue.py →
//! datasets/cattaneo_fatigue.json): the stress paths of the closed cycle at three cells and the
//! four fatigue indices of those paths, on 32² and 64²; and the maxima of the four indices over the
//! fatigue box and their locations against the same cubature over a window of cells around them
//! (verify/cattaneo_fatigue_maxima.py → datasets/cattaneo_fatigue_maxima.json), on 32², 64² and
//! 128² (docs/fatigue.md, "Checks"); the surface layer z = 0, where the box maxima are, against
//! the closed-form surface stresses of the same tractions (verify/cattaneo_fatigue_surface.py →
//! datasets/cattaneo_fatigue_surface.json), on 32², 64² and 128², and its rim error split into
//! the piecewise-constant evaluation's and the solver's tractions' shares.

use halfspace::config::FatigueConfig;
use halfspace::fatigue::{evaluate_field, FieldParams, Material};
use halfspace::loop_fatigue::evaluate_loop_fatigue;
use halfspace::sam::drivers::fretting_loop::{FrettingLoop, LoopCase};
use halfspace::sam::Body;

fn fixture() -> serde_json::Value {
    read_dataset("datasets/cattaneo_fatigue.json")
}

fn read_dataset(name: &str) -> serde_json::Value {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(name);
    serde_json::from_str(&std::fs::read_to_string(path).expect("the fixture")).unwrap()
}

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

#[test]
fn cattaneo_mindlin_cycle_matches_the_cubature_of_the_closed_form_tractions() {
    let fx = fixture();
    let mut errors = Vec::new();
    for n in [32usize, 64] {
        let lp = cattaneo_loop(n);
        let a = lp.case().hertz_radius();
        let p0 = lp.case().hertz_pressure();
        let h = lp.cycle_stress().unwrap().unwrap();
        assert_eq!(h.increments, 41);
        let mut worst_path: f64 = 0.0;
        let mut worst_index = [0.0f64; 4];
        for entry in fx["grids"][n.to_string()].as_array().unwrap() {
            let cell: Vec<usize> = entry["cell"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_u64().unwrap() as usize)
                .collect();
            let p = cell[2] * n * n + cell[0] * n + cell[1];
            let pos = h.position(p).unwrap();
            for (c, want) in entry["point"].as_array().unwrap().iter().enumerate() {
                assert!(
                    (pos[c] / a - want.as_f64().unwrap()).abs() < 1e-9,
                    "{pos:?}"
                );
            }
            let reference: Vec<f64> = entry["stress"]
                .as_array()
                .unwrap()
                .iter()
                .flat_map(|row| {
                    row.as_array()
                        .unwrap()
                        .iter()
                        .map(|v| v.as_f64().unwrap() * p0)
                        .collect::<Vec<_>>()
                })
                .collect();
            let computed = &h.stress[p * 41 * 6..(p + 1) * 41 * 6];
            let err = computed
                .iter()
                .zip(&reference)
                .map(|(x, y)| (x - y).abs() / p0)
                .fold(0.0, f64::max);
            worst_path = worst_path.max(err);
            let both: Vec<f64> = computed.iter().chain(&reference).copied().collect();
            let f = evaluate_field(&both, 2, 41, &steel(), &FieldParams::default()).unwrap();
            // Crossland and Dang Van are O(1) indices: absolute differences. SWT is near zero at
            // these cells (every plane mostly in compression): its difference on its scale
            // p₀²/E. Fatemi–Socie: relative.
            let diff = |v: &[f64]| (v[0] - v[1]).abs();
            let idx = [
                diff(&f.crossland),
                diff(&f.dang_van),
                diff(&f.swt) / (p0 * p0 / 210e9),
                diff(&f.fatemi_socie) / f.fatemi_socie[1].abs(),
            ];
            eprintln!(
                "{n}²: cell {cell:?} at {:?} a: max |Δσ|/p₀ = {err:.2e}; Crossland {:.4} vs {:.4}, \
                 Dang Van {:.4} vs {:.4}, SWT {:.4e} vs {:.4e} Pa, FS {:.4e} vs {:.4e}",
                entry["point"],
                f.crossland[0],
                f.crossland[1],
                f.dang_van[0],
                f.dang_van[1],
                f.swt[0],
                f.swt[1],
                f.fatemi_socie[0],
                f.fatemi_socie[1]
            );
            for k in 0..4 {
                worst_index[k] = worst_index[k].max(idx[k]);
            }
        }
        eprintln!("{n}²: worst |Δσ|/p₀ {worst_path:.2e}, index errors (Crossland, Dang Van abs.; SWT / (p₀²/E); FS rel.) {worst_index:?}");
        errors.push((worst_path, worst_index));
    }
    let (e32, e64) = (errors[0], errors[1]);
    assert!(
        e64.0 < e32.0,
        "no convergence of the paths: {e32:?} → {e64:?}"
    );
    // Measured: paths 2.65e-2 → 3.13e-3 p₀ (the trailing-edge cell, observed order 3.1);
    // indices at 64²: Crossland 2.6e-3, Dang Van 2.3e-3, SWT 7e-5 p₀²/E, FS 2.7e-3 relative.
    assert!(e64.0 < 5e-3, "64²: {:e} p₀", e64.0);
    for (k, tol) in [5e-3, 5e-3, 2e-4, 5e-3].iter().enumerate() {
        assert!(e64.1[k] < *tol, "64²: index {k} off by {:e}", e64.1[k]);
    }
}

/// The values of a field at the named points of a `[points × 41 × 6]` path set: the four indices.
fn indices_of(paths: &[f64], points: usize) -> [Vec<f64>; 4] {
    let f = evaluate_field(paths, points, 41, &steel(), &FieldParams::default()).unwrap();
    [f.crossland, f.dang_van, f.swt, f.fatemi_socie]
}

#[test]
fn cattaneo_mindlin_maxima_and_their_locations_converge_to_the_cubature() {
    const NAMES: [&str; 4] = ["Crossland", "Dang Van", "SWT", "Fatemi–Socie"];
    let fx = read_dataset("datasets/cattaneo_fatigue_maxima.json");
    let cfg = FatigueConfig {
        f_minus1: 400e6,
        t_minus1: 280e6,
        fs_k: 0.5,
        yield_stress: 600e6,
        depth_over_a: 0.6,
        // Every cell worth at least 0.15 × the box's maximum is evaluated exactly: the first
        // layer's maximum is (asserted below).
        screen_fraction: 0.15,
        inhomogeneity: None,
        process_volume: None,
        own: Vec::new(),
    };
    // errors[grid][criterion]: (|first-layer max − reference window max| (relative for SWT, FS),
    // max over the window of the per-cell index error (same scale)).
    let mut errors = Vec::new();
    let mut first_layer_maxima = Vec::new();
    for n in [32usize, 64, 128] {
        let lp = cattaneo_loop(n);
        let (a, p0) = (lp.case().hertz_radius(), lp.case().hertz_pressure());
        let cell = 4.16 / n as f64; // cell side over a (the loop's extent_over_a)
        let fatigue = evaluate_loop_fatigue(&lp, &cfg).unwrap();
        let h = lp.cycle_stress().unwrap().unwrap();
        let grid = &fx["grids"][n.to_string()];
        let cells: Vec<[usize; 3]> = grid["cells"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| {
                let c: Vec<usize> = c
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_u64().unwrap() as usize)
                    .collect();
                [c[0], c[1], c[2]]
            })
            .collect();
        let points: Vec<[f64; 3]> = grid["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                let p: Vec<f64> = p
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_f64().unwrap())
                    .collect();
                [p[0], p[1], p[2]]
            })
            .collect();
        let reference: Vec<f64> = grid["stress"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|path| path.as_array().unwrap().clone())
            .flat_map(|row| {
                row.as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_f64().unwrap() * p0)
                    .collect::<Vec<_>>()
            })
            .collect();
        let mut computed = Vec::with_capacity(reference.len());
        for (c, want) in cells.iter().zip(&points) {
            let p = c[2] * n * n + c[0] * n + c[1];
            let pos = h.position(p).unwrap();
            for k in 0..3 {
                assert!((pos[k] / a - want[k]).abs() < 1e-9, "{pos:?} vs {want:?}");
            }
            computed.extend_from_slice(&h.stress[p * 41 * 6..(p + 1) * 41 * 6]);
        }
        let want = indices_of(&reference, cells.len());
        let got = indices_of(&computed, cells.len());
        // The box's maxima are on the surface layer z = 0 (docs/fatigue.md, "The surface layer";
        // checked against the closed form in the next test); this window is the first layer
        // below it, z = h/2: the maximum of each index over that layer (layer 1 of the fields,
        // which list the surface first).
        let per = n * n;
        let fields = [
            &fatigue.indices.crossland,
            &fatigue.indices.dang_van,
            &fatigue.indices.swt,
            &fatigue.indices.fatemi_socie,
        ];
        let box_max = [
            fatigue.indices.crossland_max.value,
            fatigue.indices.dang_van_max.value,
            fatigue.indices.swt_max.value,
            fatigue.indices.fatemi_socie_max.value,
        ];
        let mut maxima = [0.0; 4];
        let mut first_layer_at = [[0.0; 3]; 4];
        for k in 0..4 {
            assert_eq!(
                fatigue.at[k][2], 0.0,
                "{n}²: {} box maximum below the surface",
                NAMES[k]
            );
            let (flat, value) = fields[k][per..2 * per]
                .iter()
                .enumerate()
                .filter(|(_, v)| !v.is_nan())
                .fold(
                    (0, f64::NEG_INFINITY),
                    |b, (i, &v)| if v > b.1 { (i, v) } else { b },
                );
            // Evaluated exactly wherever ≥ screen_fraction × the box max: this is the layer's max.
            assert!(
                value >= cfg.screen_fraction * box_max[k],
                "{n}²: {}",
                NAMES[k]
            );
            maxima[k] = value;
            first_layer_at[k] = h.position(flat).unwrap();
            assert!((first_layer_at[k][2] / a - cell / 2.0).abs() < 1e-9);
        }
        let (window_x, window_y) = (
            points.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min)
                ..=points
                    .iter()
                    .map(|p| p[0])
                    .fold(f64::NEG_INFINITY, f64::max),
            points
                .iter()
                .map(|p| p[1])
                .fold(f64::NEG_INFINITY, f64::max),
        );
        let mut row = [Row::default(); 4];
        for k in 0..4 {
            let (best, best_value) =
                want[k]
                    .iter()
                    .enumerate()
                    .fold(
                        (0, f64::NEG_INFINITY),
                        |b, (i, &v)| if v > b.1 { (i, v) } else { b },
                    );
            let r = points[best];
            // The reference's maximum is inside its window (not on its lateral edges), so the
            // window holds a maximum of the cubature's field.
            assert!(
                r[0] > *window_x.start() + 1e-9
                    && r[0] < *window_x.end() - 1e-9
                    && r[1] < window_y - 1e-9,
                "{n}²: {}: the reference's maximum {r:?} is on the window's edge",
                NAMES[k]
            );
            // The solver's maximum over its first layer, mirrored into the window (the case is
            // mirror-symmetric in x and in y): it must be one of the window's cells.
            let at = first_layer_at[k];
            let s = [at[0].abs() / a, at[1].abs() / a, at[2] / a];
            let own = points
                .iter()
                .position(|p| (0..3).all(|c| (p[c] - s[c]).abs() < 1e-6))
                .unwrap_or_else(|| {
                    panic!(
                        "{n}²: {} maximum at {s:?} a is outside the window",
                        NAMES[k]
                    )
                });
            let scale = if k < 2 { 1.0 } else { best_value.abs() };
            row[k] = Row {
                max_error: (maxima[k] - best_value).abs() / scale,
                field_error: want[k]
                    .iter()
                    .zip(&got[k])
                    .map(|(w, g)| (w - g).abs())
                    .fold(0.0, f64::max)
                    / scale,
                cells_apart: (0..3)
                    .map(|c| ((s[c] - r[c]) / cell).abs().round())
                    .fold(0.0, f64::max),
                shortfall: (best_value - want[k][own]) / scale,
            };
            eprintln!(
                "{n}²: {:<12} first-layer max {:.6e} at {:?} a; reference {:.6e} at {:?} a; {:?}{}",
                NAMES[k],
                maxima[k],
                s.map(|v| (v * 1e4).round() / 1e4),
                best_value,
                r.map(|v| (v * 1e4).round() / 1e4),
                row[k],
                if k < 2 { " (abs.)" } else { " (rel.)" }
            );
        }
        errors.push(row);
        first_layer_maxima.push(maxima);
    }
    for k in 0..4 {
        let e: Vec<f64> = errors.iter().map(|r| r[k].max_error).collect();
        let f: Vec<f64> = errors.iter().map(|r| r[k].field_error).collect();
        let apart: Vec<f64> = errors.iter().map(|r| r[k].cells_apart).collect();
        eprintln!(
            "{}: |Δmax| {:.2e} {:.2e} {:.2e}, window field {:.2e} {:.2e} {:.2e}; observed orders \
             (field) {:.2}, {:.2}; maxima cells apart {apart:?}",
            NAMES[k],
            e[0],
            e[1],
            e[2],
            f[0],
            f[1],
            f[2],
            (f[0] / f[1]).log2(),
            (f[1] / f[2]).log2()
        );
    }
    for k in 0..4 {
        for r in &errors {
            // Where the solver puts the maximum, the reference is within twice the solver's
            // field error of its own maximum (the field is flat along y near the edge: the two
            // maxima are up to 5 cells apart in y on 128², measured).
            assert!(
                r[k].shortfall <= 2.0 * r[k].field_error,
                "{}: {r:?}",
                NAMES[k]
            );
        }
        // The first layer is half a cell below the surface, which the finer grids bring closer
        // to the contact edge: both the solver's and the reference's maxima there grow with the
        // grid (towards the surface value, like √z).
        assert!(
            first_layer_maxima[2][k] > first_layer_maxima[1][k]
                && first_layer_maxima[1][k] > first_layer_maxima[0][k]
        );
        // Measured on 64² and 128² (docs/fatigue.md, "Checks"): |first-layer max − reference| ≤ 2.2e-2
        // (Crossland, Dang Van absolute; SWT, Fatemi–Socie relative), the worst cell of the
        // window 5.8e-2. The first layer's error does not decrease with the grid (it sits at
        // z = h/2, where the piecewise-constant tractions' error does not shrink relative to the
        // field); these bounds are regression bounds at the measured level, not a convergence.
        for r in &errors[1..] {
            assert!(r[k].max_error < 2.5e-2, "{}: {r:?}", NAMES[k]);
            assert!(r[k].field_error < 6.5e-2, "{}: {r:?}", NAMES[k]);
        }
    }
}

/// One criterion on one grid: |first-layer max (solver) − the reference's window max|, the largest per-cell error
/// over the window, how many cells apart the two maxima are, and how far below its own maximum
/// the reference is at the solver's location (Crossland and Dang Van absolute, SWT and
/// Fatemi–Socie relative to the reference's maximum).
#[derive(Clone, Copy, Debug, Default)]
struct Row {
    max_error: f64,
    field_error: f64,
    cells_apart: f64,
    shortfall: f64,
}

/// `[[f64]]` of a JSON array of arrays.
fn rows(v: &serde_json::Value) -> Vec<Vec<f64>> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|r| {
            r.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        })
        .collect()
}

/// The stick radius at the turning points ±A of the cycle, `c* = a (1 − Q*/μW)^{1/3}` (Johnson
/// 1985 Eq. 7.38), over a.
const C_STAR: f64 = 0.793_700_525_984_099_7;

/// The surface layer z = 0 of the box against the closed-form surface stresses of the
/// Mindlin–Deresiewicz tractions (verify/cattaneo_fatigue_surface.py →
/// datasets/cattaneo_fatigue_surface.json: Johnson 1985 Eqs. 3.41, 3.42 for the pressure,
/// Hamilton & Goodman 1966 at z = 0 / Johnson Eq. 7.47 for the shear) at the surface-cell centres
/// of a window around the contact edge, on 32², 64², 128²: the stress paths, the four indices,
/// the box maxima and their locations, and the reference's supremum over a fine patch of points.
#[test]
fn cattaneo_mindlin_surface_layer_matches_the_closed_form_surface_stresses() {
    const NAMES: [&str; 4] = ["Crossland", "Dang Van", "SWT", "Fatemi–Socie"];
    let fx = read_dataset("datasets/cattaneo_fatigue_surface.json");
    let cfg = FatigueConfig {
        f_minus1: 400e6,
        t_minus1: 280e6,
        fs_k: 0.5,
        yield_stress: 600e6,
        depth_over_a: 0.6,
        screen_fraction: 0.5,
        inhomogeneity: None,
        process_volume: None,
        own: Vec::new(),
    };
    // Per grid: stress errors (all window cells, cells r ≥ 1.1a r = a), and per
    // criterion (|Δmax|, cells apart, shortfall, worst window cell, worst cell r ≥ 1.1a).
    let mut stress_errors = Vec::new();
    let mut index_errors = Vec::new();
    let mut solver_maxima = Vec::new();
    let mut hertz_p0 = 0.0;
    for n in [32usize, 64, 128] {
        let lp = cattaneo_loop(n);
        let (a, p0) = (lp.case().hertz_radius(), lp.case().hertz_pressure());
        let cell = 4.16 / n as f64;
        let fatigue = evaluate_loop_fatigue(&lp, &cfg).unwrap();
        let h = lp.cycle_stress().unwrap().unwrap();
        assert!(h.surface);
        let grid = &fx["grids"][n.to_string()];
        let cells = rows(&grid["cells"]);
        let points = rows(&grid["points"]);
        let reference: Vec<f64> = grid["stress"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(rows)
            .flatten()
            .map(|v| v * p0)
            .collect();
        let mut computed = Vec::with_capacity(reference.len());
        let (mut worst_all, mut worst_away) = (0.0f64, 0.0f64);
        let (mut worst_traction, mut worst_turning) = (0.0f64, 0.0f64);
        // Cells outside the contact by at least 0.1a (a fixed set of points).
        let away: Vec<bool> = points.iter().map(|p| p[0].hypot(p[1]) >= 1.1).collect();
        for (m, (c, want)) in cells.iter().zip(&points).enumerate() {
            let p = h.layers * n * n + c[0] as usize * n + c[1] as usize;
            let pos = h.position(p).unwrap();
            assert!((pos[0] / a - want[0]).abs() < 1e-9 && (pos[1] / a - want[1]).abs() < 1e-9);
            assert_eq!(pos[2], 0.0);
            let path = &h.stress[p * 41 * 6..(p + 1) * 41 * 6];
            let err = path
                .iter()
                .zip(&reference[m * 41 * 6..(m + 1) * 41 * 6])
                .map(|(x, y)| (x - y).abs() / p0)
                .fold(0.0, f64::max);
            worst_all = worst_all.max(err);
            if away[m] {
                worst_away = worst_away.max(err);
            }
            // σ₃₃ = −p, σ₂₃, σ₁₃ = −q: the solver's tractions at the cell centre themselves.
            let traction = path
                .iter()
                .zip(&reference[m * 41 * 6..(m + 1) * 41 * 6])
                .enumerate()
                .filter(|(i, _)| (2..5).contains(&(i % 6)))
                .map(|(_, (x, y))| (x - y).abs() / p0)
                .fold(0.0, f64::max);
            worst_traction = worst_traction.max(traction);
            // The turning points ±A (t = 0, 20, 40: the annulus c* < r < a in full slip, the
            // traction smooth there) at cells ≥ 1.5 cells from the stick circle c* and the rim.
            let r = want[0].hypot(want[1]);
            if (r - C_STAR).abs() >= 1.5 * cell && (r - 1.0).abs() >= 1.5 * cell {
                for t in [0, 20, 40] {
                    for c in 0..6 {
                        let q = (m * 41 + t) * 6 + c;
                        worst_turning =
                            worst_turning.max((path[t * 6 + c] - reference[q]).abs() / p0);
                    }
                }
            }
            computed.extend_from_slice(path);
        }
        eprintln!(
            "{n}²: surface stresses vs the closed form, max |Δσ|/p₀ over the window {worst_all:.3e} \
             (the tractions σ₃₃, σ₂₃, σ₁₃ alone {worst_traction:.3e}), cells at r ≥ 1.1a \
             {worst_away:.3e}, turning points ≥ 1.5 cells from r = c*, a {worst_turning:.3e}"
        );
        stress_errors.push((worst_all, worst_away, worst_traction, worst_turning));
        let want = indices_of(&reference, cells.len());
        let got = indices_of(&computed, cells.len());
        let maxima = [
            fatigue.indices.crossland_max.value,
            fatigue.indices.dang_van_max.value,
            fatigue.indices.swt_max.value,
            fatigue.indices.fatemi_socie_max.value,
        ];
        let x_range = points.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min)
            ..=points
                .iter()
                .map(|p| p[0])
                .fold(f64::NEG_INFINITY, f64::max);
        let y_top = points
            .iter()
            .map(|p| p[1])
            .fold(f64::NEG_INFINITY, f64::max);
        let mut row = Vec::new();
        for k in 0..4 {
            let (best, best_value) =
                want[k]
                    .iter()
                    .enumerate()
                    .fold(
                        (0, f64::NEG_INFINITY),
                        |b, (i, &v)| if v > b.1 { (i, v) } else { b },
                    );
            let r = &points[best];
            assert!(
                r[0] > *x_range.start() + 1e-9
                    && r[0] < *x_range.end() - 1e-9
                    && r[1] < y_top - 1e-9,
                "{n}²: {}: the reference's maximum {r:?} is on the window's edge",
                NAMES[k]
            );
            // The solver's box maximum: on the surface, mirrored into the window.
            let at = fatigue.at[k];
            assert_eq!(at[2], 0.0, "{n}²: {} maximum below the surface", NAMES[k]);
            let s = [at[0].abs() / a, at[1].abs() / a];
            let own = points
                .iter()
                .position(|p| (p[0] - s[0]).abs() < 1e-6 && (p[1] - s[1]).abs() < 1e-6)
                .unwrap_or_else(|| {
                    panic!("{n}²: {} maximum at {s:?} a outside the window", NAMES[k])
                });
            assert!(
                (s[0].hypot(s[1]) - 1.0).abs() < cell,
                "{n}²: {} at {s:?}",
                NAMES[k]
            );
            let scale = if k < 2 { 1.0 } else { best_value.abs() };
            let cell_errors: Vec<f64> = want[k]
                .iter()
                .zip(&got[k])
                .map(|(w, g)| (w - g).abs() / scale)
                .collect();
            let e = (
                (maxima[k] - best_value).abs() / scale,
                ((s[0] - r[0]) / cell)
                    .abs()
                    .round()
                    .max(((s[1] - r[1]) / cell).abs().round()),
                (best_value - want[k][own]) / scale,
                cell_errors.iter().copied().fold(0.0, f64::max),
                cell_errors
                    .iter()
                    .zip(&away)
                    .filter(|(_, &w)| w)
                    .map(|(e, _)| *e)
                    .fold(0.0, f64::max),
            );
            eprintln!(
                "{n}²: {:<12} solver {:.5e} at ({:.4}, {:.4}, 0) a; reference {:.5e} at ({:.4}, {:.4}, 0) a; \
                 |Δmax| {:.2e}, cells apart {}, reference shortfall at the solver's cell {:.2e}, \
                 worst window cell {:.2e}, r ≥ 1.1a {:.2e}{}",
                NAMES[k], maxima[k], s[0], s[1], best_value, r[0], r[1], e.0, e.1, e.2, e.3, e.4,
                if k < 2 { " (abs.)" } else { " (rel.)" }
            );
            row.push(e);
        }
        index_errors.push(row);
        solver_maxima.push(maxima);
        hertz_p0 = p0;
    }
    // The reference's supremum over the surface: its maximum over a fine patch of points around
    // the contact edge (steps a/400 in x, 0.06a in y), against which the solver's box maxima.
    let fine = &fx["fine"];
    let fine_points = rows(&fine["points"]);
    let fine_paths: Vec<f64> = fine["stress"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(rows)
        .flatten()
        .map(|v| v * hertz_p0)
        .collect();
    let sup = indices_of(&fine_paths, fine_points.len());
    let mut to_sup = [[0.0; 3]; 4];
    for k in 0..4 {
        let (best, value) = sup[k]
            .iter()
            .enumerate()
            .fold(
                (0, f64::NEG_INFINITY),
                |b, (i, &v)| if v > b.1 { (i, v) } else { b },
            );
        let scale = if k < 2 { 1.0 } else { value };
        for g in 0..3 {
            to_sup[k][g] = (value - solver_maxima[g][k]) / scale;
        }
        eprintln!(
            "{}: reference supremum {:.5e} at {:?} a; solver box max 32², 64², 128² {:.5e} {:.5e} {:.5e}: \
             below it by {:.2e} {:.2e} {:.2e}{} (orders {:.2}, {:.2})",
            NAMES[k],
            value,
            fine_points[best],
            solver_maxima[0][k],
            solver_maxima[1][k],
            solver_maxima[2][k],
            to_sup[k][0],
            to_sup[k][1],
            to_sup[k][2],
            if k < 2 { " (abs.)" } else { " (rel.)" },
            (to_sup[k][0] / to_sup[k][1]).log2(),
            (to_sup[k][1] / to_sup[k][2]).log2()
        );
    }
    let order = |a: f64, b: f64| (a / b).log2();
    let (s32, s64, s128) = (stress_errors[0], stress_errors[1], stress_errors[2]);
    eprintln!(
        "tractions: {:.2e} {:.2e} {:.2e} (orders {:.2}, {:.2}); turning points: {:.2e} {:.2e} {:.2e}",
        s32.2, s64.2, s128.2, order(s32.2, s64.2), order(s64.2, s128.2), s32.3, s64.3, s128.3
    );
    eprintln!(
        "surface stresses: window {:.2e} {:.2e} {:.2e} (orders {:.2}, {:.2}); r ≥ 1.1a \
         {:.2e} {:.2e} {:.2e} (orders {:.2}, {:.2})",
        s32.0,
        s64.0,
        s128.0,
        order(s32.0, s64.0),
        order(s64.0, s128.0),
        s32.1,
        s64.1,
        s128.1,
        order(s32.1, s64.1),
        order(s64.1, s128.1)
    );
    for k in 0..4 {
        let e: Vec<_> = index_errors.iter().map(|r| r[k]).collect();
        eprintln!(
            "{}: |Δmax| {:.2e} {:.2e} {:.2e} (orders {:.2}, {:.2}); worst window cell {:.2e} {:.2e} {:.2e}; \
             r ≥ 1.1a {:.2e} {:.2e} {:.2e} (orders {:.2}, {:.2})",
            NAMES[k], e[0].0, e[1].0, e[2].0, order(e[0].0, e[1].0), order(e[1].0, e[2].0),
            e[0].3, e[1].3, e[2].3, e[0].4, e[1].4, e[2].4, order(e[0].4, e[1].4), order(e[1].4, e[2].4)
        );
    }

    // What converges (docs/fatigue.md, "The surface: against the closed form"):
    // * outside the contact (r ≥ 1.1a, a fixed set of points) the surface stresses and the four
    //   indices, measured 1.71e-2 → 3.16e-3 → 1.39e-3 p₀ (orders 2.4, 1.2);
    assert!(
        s32.1 > s64.1 && s64.1 > s128.1 && s128.1 < 2e-3,
        "{stress_errors:?}"
    );
    for (k, tol) in [6e-3, 1e-2, 2.5e-3, 3.2e-3].iter().enumerate() {
        let e: Vec<f64> = index_errors.iter().map(|r| r[k].4).collect();
        assert!(
            e[0] > e[1] && e[1] > e[2] && e[2] < *tol,
            "{}: {e:?}",
            NAMES[k]
        );
    }
    // * over the window around the edge (the slip annulus, where the stick circle sweeps
    //   c* < b < a over the cycle, the traction's √ kinks next to some cell at some increment)
    //   only like √h: 2.20e-1 → 1.55e-1 → 1.14e-1 p₀ (orders 0.50, 0.45) — the rate asserted,
    //   and the level as a regression bound at the measured 0.114 p₀ on 128²;
    assert!(
        order(s32.0, s64.0) > 0.4 && order(s64.0, s128.0) > 0.4,
        "{stress_errors:?}"
    );
    assert!(s128.0 < 0.12, "{stress_errors:?}");
    // * the box maxima stay below the reference's supremum (at the rim r = a on the x axis) and
    //   approach it, slowly (orders 0.3–0.6): Crossland 2.263 − {1.351, 1.632, 1.772}.
    for (k, d) in to_sup.iter().enumerate() {
        assert!(
            d[0] > d[1] && d[1] > d[2] && d[2] > 0.0,
            "{}: {d:?}",
            NAMES[k]
        );
    }
    // Locations: the solver's maximum is in a cell touching the rim (|r − a| < a cell), within
    // two cells of the reference's maximum over the same cells (measured ≤ 1 on 64², ≤ 2 on
    // 128²; Fatemi–Socie 4 cells along y on 64², where its field is flat along the rim).
    for (k, e) in index_errors[2].iter().enumerate() {
        assert!(e.1 <= 2.0, "128²: {}: {e:?}", NAMES[k]);
    }
}

/// Surface stress paths at arbitrary surface points (not on a cell edge line) from the loop's
/// recorded cycle tractions, by the direct sum of Love's rectangle stresses at z = 0
/// (docs/theory-sam.md#love-rectangle-stresses) — for the survey below only. With `shifted`,
/// the tractions are first interpolated bilinearly to the cell centres shifted by the point's
/// offset from its own cell's centre, so that the point is a cell centre of the shifted grid.
fn surface_paths_at(lp: &FrettingLoop, points: &[[f64; 2]], shifted: bool) -> Vec<f64> {
    let mut weights: Vec<Vec<(usize, f64)>> = Vec::new();
    use halfspace::sam::kernels::subsurface::{pressure_stress, shear_stress};
    use halfspace::sam::kernels::InPlane;
    let grid = *lp.solver().problem().grid();
    let nu = lp.case().nu;
    let src = lp.cycle_sources().unwrap();
    let n = grid.len();
    let inc = src.recorded;
    let mut out = vec![0.0; points.len() * inc * 6];
    let mut infl = vec![0.0; n * 18];
    for (m, pt) in points.iter().enumerate() {
        // The point's offset from the centre of its cell; with SHIFTED the tractions are
        // interpolated (bilinearly) to the cell centres shifted by it, so the point is a centre.
        let (h1, h2) = (2.0 * grid.half1, 2.0 * grid.half2);
        let ci = ((pt[0] / h1 + grid.n1 as f64 / 2.0).floor()) as usize;
        let cj = ((pt[1] / h2 + grid.n2 as f64 / 2.0).floor()) as usize;
        let (x0, y0) = grid.centre(ci, cj);
        let shift = if shifted {
            [pt[0] - x0, pt[1] - y0]
        } else {
            [0.0, 0.0]
        };
        weights.clear();
        for c in 0..n {
            let (i, j) = (c / grid.n2, c % grid.n2);
            let u = i as f64 + shift[0] / h1;
            let v = j as f64 + shift[1] / h2;
            let (iu, jv) = (u.floor(), v.floor());
            let (fu, fv) = (u - iu, v - jv);
            let mut w = Vec::with_capacity(4);
            for (di, dj, wt) in [
                (0, 0, (1.0 - fu) * (1.0 - fv)),
                (1, 0, fu * (1.0 - fv)),
                (0, 1, (1.0 - fu) * fv),
                (1, 1, fu * fv),
            ] {
                let (a, b) = (iu as i64 + di, jv as i64 + dj);
                if wt != 0.0 && a >= 0 && b >= 0 && (a as usize) < grid.n1 && (b as usize) < grid.n2
                {
                    w.push((a as usize * grid.n2 + b as usize, wt));
                }
            }
            weights.push(w);
        }
        for c in 0..n {
            let (xc, yc) = grid.centre(c / grid.n2, c % grid.n2);
            let (dx, dy) = (pt[0] - shift[0] - xc, pt[1] - shift[1] - yc);
            let k = [
                pressure_stress(dx, dy, 0.0, grid.half1, grid.half2, nu),
                shear_stress(InPlane::X1, dx, dy, 0.0, grid.half1, grid.half2, nu),
                shear_stress(InPlane::X2, dx, dy, 0.0, grid.half1, grid.half2, nu),
            ];
            for (j, kj) in k.iter().enumerate() {
                infl[c * 18 + j * 6..c * 18 + j * 6 + 6].copy_from_slice(kj);
            }
        }
        for t in 0..inc {
            let (p, q, _) = src.increment(t);
            let mut s = [0.0; 6];
            for c in 0..n {
                let mut w = [0.0; 3];
                for &(k, wt) in &weights[c] {
                    w[0] += wt * p[k];
                    w[1] += wt * q[0][k];
                    w[2] += wt * q[1][k];
                }
                for (j, &wj) in w.iter().enumerate() {
                    if wj != 0.0 {
                        for (o, so) in s.iter_mut().enumerate() {
                            *so += wj * infl[c * 18 + j * 6 + o];
                        }
                    }
                }
            }
            out[(m * inc + t) * 6..(m * inc + t) * 6 + 6].copy_from_slice(&s);
        }
    }
    out
}

/// Why the surface maxima do not converge by refining the evaluation (docs/fatigue.md,
/// "Refining the surface evaluation does not converge"): the four indices on a lattice of
/// `SUB × SUB` points per cell (`SUB=3`, `5`; offsets `(k + ½)/SUB` of a cell) over the cells of
/// x ∈ [0.85, 1.15]a, y ∈ [0, 0.25]a, from each grid's piecewise-constant tractions (and, with
/// `SHIFTED=1`, from the tractions interpolated to the shifted cell centres), against the closed
/// form's supremum; and the surface paths at the fixture's fine points off the cell edges.
/// `SHIFTED=1 GRIDS=32,64,128 SUB=3 cargo test -p halfspace --test fixtures_cattaneo_fatigue
/// surface_refinement_survey -- --ignored --nocapture` (128² sub 5: ~1 min). Asserts what it
/// reports on every grid: the error at the rim is above 5e-2 p₀ and ten times the error outside
/// the contact (which is below 1e-2 p₀), the fixture's fine points differ by more than 5e-2 p₀,
/// every refined index is finite.
#[test]
#[ignore]
fn surface_refinement_survey() {
    const NAMES: [&str; 4] = ["Crossland", "Dang Van", "SWT", "Fatemi–Socie"];
    let fx = read_dataset("datasets/cattaneo_fatigue_surface.json");
    let grids: Vec<usize> = std::env::var("GRIDS")
        .unwrap_or("32,64".into())
        .split(',')
        .map(|s| s.parse().unwrap())
        .collect();
    let sub: usize = std::env::var("SUB")
        .map(|s| s.parse().unwrap())
        .unwrap_or(3);
    let fine = &fx["fine"];
    let fine_points = rows(&fine["points"]);
    let mut p0 = 0.0;
    for &n in &grids {
        let t0 = std::time::Instant::now();
        let lp = cattaneo_loop(n);
        let (a, pz) = (lp.case().hertz_radius(), lp.case().hertz_pressure());
        p0 = pz;
        let grid = *lp.solver().problem().grid();
        let h = 2.0 * grid.half1;
        // Fixed points: the fixture's fine patch off the cell edge lines.
        let on_edge = |x: f64| {
            let u = (x + grid.n1 as f64 * grid.half1) / h;
            (u - u.round()).abs() < 1e-6
        };
        let (fixed, fixed_ref): (Vec<[f64; 2]>, Vec<usize>) = fine_points
            .iter()
            .enumerate()
            .filter(|(_, p)| !on_edge(p[0] * a) && !on_edge(p[1] * a))
            .map(|(i, p)| ([p[0] * a, p[1] * a], i))
            .unzip();
        let shifted = std::env::var("SHIFTED").is_ok();
        let got = surface_paths_at(&lp, &fixed, shifted);
        let mut worst = 0.0f64;
        for (m, &i) in fixed_ref.iter().enumerate() {
            let want = &fine["stress"][i];
            for t in 0..41 {
                for c in 0..6 {
                    let w = want[t][c].as_f64().unwrap() * pz;
                    worst = worst.max((got[(m * 41 + t) * 6 + c] - w).abs() / pz);
                }
            }
        }
        eprintln!(
            "{n}²: fixed fine points ({}) max |Δσ|/p₀ {worst:.3e}",
            fixed.len()
        );
        // Refined lattice: SUB × SUB points per cell over the cells of x ∈ [0.93, 1.07]a,
        // y ∈ [0, 0.25]a.
        let mut pts = Vec::new();
        for i in 0..grid.n1 {
            for j in 0..grid.n2 {
                let (xc, yc) = grid.centre(i, j);
                if !(0.85 * a..=1.15 * a).contains(&xc) || !(0.0..=0.25 * a).contains(&yc) {
                    continue;
                }
                for u in 0..sub {
                    for v in 0..sub {
                        let fu = (u as f64 + 0.5) / sub as f64 - 0.5;
                        let fv = (v as f64 + 0.5) / sub as f64 - 0.5;
                        pts.push([xc + fu * h, yc + fv * h]);
                    }
                }
            }
        }
        let paths = surface_paths_at(&lp, &pts, shifted);
        let idx = indices_of(&paths, pts.len());
        for k in 0..4 {
            let (b, v) = idx[k]
                .iter()
                .enumerate()
                .fold(
                    (0, f64::NEG_INFINITY),
                    |b, (i, &v)| if v > b.1 { (i, v) } else { b },
                );
            eprintln!(
                "{n}² sub {sub}: {:<12} refined max {v:.5e} at ({:.5}, {:.5}) a ({} points)",
                NAMES[k],
                pts[b][0] / a,
                pts[b][1] / a,
                pts.len()
            );
        }
        // Where the surface layer's error sits: its cell-centre paths against the closed form
        // (datasets/cattaneo_fatigue_surface.json), by region — within 1.5 cells of the rim
        // r = a, the rest of the slip annulus swept by the stick circle (c* − 1.5h < r < a −
        // 1.5h), the stick zone inside it, and outside the rim.
        let hist = lp.cycle_stress().unwrap().unwrap();
        let sf = &fx["grids"][n.to_string()];
        let (cells, centres) = (rows(&sf["cells"]), rows(&sf["points"]));
        let stress = sf["stress"].as_array().unwrap();
        let cell_a = h / a;
        let mut region_err = [[0.0f64; 2]; 4];
        let mut paths = Vec::new();
        let mut reference = Vec::new();
        let mut region_of = Vec::new();
        for (m, (c, x)) in cells.iter().zip(&centres).enumerate() {
            let r = x[0].hypot(x[1]);
            let region = if (r - 1.0).abs() < 1.5 * cell_a {
                0
            } else if r > 1.0 {
                3
            } else if r > C_STAR - 1.5 * cell_a {
                1
            } else {
                2
            };
            let q = hist.layers * n * n + c[0] as usize * n + c[1] as usize;
            let path = &hist.stress[q * 41 * 6..(q + 1) * 41 * 6];
            let want: Vec<f64> = rows(&stress[m])
                .into_iter()
                .flatten()
                .map(|v| v * pz)
                .collect();
            let e = path
                .iter()
                .zip(&want)
                .map(|(g, w)| (g - w).abs() / pz)
                .fold(0.0, f64::max);
            region_err[region][0] = region_err[region][0].max(e);
            paths.extend_from_slice(path);
            reference.extend_from_slice(&want);
            region_of.push(region);
        }
        let (got, want) = (
            indices_of(&paths, cells.len()),
            indices_of(&reference, cells.len()),
        );
        for (m, &region) in region_of.iter().enumerate() {
            region_err[region][1] = region_err[region][1].max((got[0][m] - want[0][m]).abs());
        }
        eprintln!(
            "{n}²: surface layer vs the closed form, max |Δσ|/p₀ (Crossland |Δ|): rim ±1.5h {:.2e} ({:.2e}), \
             slip annulus {:.2e} ({:.2e}), stick zone {:.2e} ({:.2e}), outside {:.2e} ({:.2e})",
            region_err[0][0], region_err[0][1], region_err[1][0], region_err[1][1],
            region_err[2][0], region_err[2][1], region_err[3][0], region_err[3][1]
        );
        // What the survey reports, asserted (measured 32²/64²/128²: rim 0.220/0.148/0.114 p₀,
        // outside 4.6e-3/3.2e-3/2.6e-3; fixed fine points 0.12–0.29 p₀): the error sits at the
        // rim (and, from 64², in the slip annulus), the stresses outside the contact are close,
        // and the fine points' paths are not.
        // A change that converges the rim (a finer contact solution there) fails this survey
        // on purpose: its findings, and docs/fatigue.md's, then need measuring again.
        assert!(
            region_err[3][0] < 6e-3,
            "{n}²: outside the rim {:.2e} p₀",
            region_err[3][0]
        );
        assert!(
            region_err[0][0] > 0.1 && region_err[0][0] > 10.0 * region_err[3][0],
            "{n}²: the rim error {:.2e} p₀ against {:.2e} outside",
            region_err[0][0],
            region_err[3][0]
        );
        assert!(
            worst > 5e-2 && worst.is_finite(),
            "{n}²: fixed fine points {worst:.2e} p₀"
        );
        for (values, name) in idx.iter().zip(NAMES) {
            assert!(values.iter().all(|v| v.is_finite()), "{n}²: {name}");
        }
        eprintln!("{n}²: {:.1} s", t0.elapsed().as_secs_f64());
    }
    let fine_paths: Vec<f64> = fine["stress"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(rows)
        .flatten()
        .map(|v| v * p0)
        .collect();
    let sup = indices_of(&fine_paths, fine_points.len());
    for k in 0..4 {
        let v = sup[k].iter().copied().fold(f64::NEG_INFINITY, f64::max);
        eprintln!("{}: reference supremum {v:.5e}", NAMES[k]);
    }
}

/// The near-surface maxima at a fixed depth converge with the grid: the stress paths at the
/// fixed points of the cubature's windows (datasets/cattaneo_fatigue_maxima.json: the cell
/// centres of 32²'s first layer, z = 0.065a, and of 64²'s, z = 0.0325a) computed from each
/// grid's tractions by Love's rectangle stresses at arbitrary points
/// ([`FrettingLoop::cycle_stress_at`]), on 32², 64², 128²: their four indices against the
/// cubature's, the window maxima and their locations, and the observed order
/// (docs/fatigue.md, "Near-surface maxima at a fixed depth").
#[test]
fn near_surface_maxima_at_a_fixed_depth_converge_with_the_grid() {
    const NAMES: [&str; 4] = ["Crossland", "Dang Van", "SWT", "Fatemi–Socie"];
    let fx = read_dataset("datasets/cattaneo_fatigue_maxima.json");
    // The two windows' first layers: (points / a, reference paths per p₀).
    let windows: Vec<(f64, Vec<Vec<f64>>, Vec<f64>)> = ["32", "64"]
        .iter()
        .map(|g| {
            let w = &fx["grids"][*g];
            let points = rows(&w["points"]);
            let z = points.iter().map(|p| p[2]).fold(f64::INFINITY, f64::min);
            let keep: Vec<usize> = (0..points.len())
                .filter(|&i| (points[i][2] - z).abs() < 1e-9)
                .collect();
            let stress = w["stress"].as_array().unwrap();
            let paths = keep
                .iter()
                .flat_map(|&i| rows(&stress[i]).into_iter().flatten())
                .collect();
            (z, keep.iter().map(|&i| points[i].clone()).collect(), paths)
        })
        .collect();
    let grids: Vec<usize> = std::env::var("HALFSPACE_FIXED_DEPTH_GRIDS")
        .unwrap_or("32,64,128".into())
        .split(',')
        .map(|s| s.parse().unwrap())
        .collect();
    // The observed orders need three grids, each twice the last, and the limits below are
    // those of 128² as the third: anything else is refused, not silently passed.
    assert!(
        grids.len() == 3 && grids[1] == 2 * grids[0] && grids[2] == 2 * grids[1] && grids[2] >= 128,
        "HALFSPACE_FIXED_DEPTH_GRIDS = {grids:?}: three grids, each twice the last, up to at \
         least 128 (default 32,64,128)"
    );
    // errors[grid][window][criterion] = (worst cell, |Δ window max|, cells apart).
    let mut errors = Vec::new();
    let mut maxima = Vec::new();
    for &n in &grids {
        let t0 = std::time::Instant::now();
        let lp = cattaneo_loop(n);
        let (a, p0) = (lp.case().hertz_radius(), lp.case().hertz_pressure());
        // The twin: at the box's own cell centres of the first layer the paths are the history's.
        let h = lp.cycle_stress().unwrap().unwrap();
        let probe: Vec<usize> = (0..n * n).step_by(n * n / 7 + 1).collect();
        let at: Vec<[f64; 3]> = probe.iter().map(|&p| h.position(p).unwrap()).collect();
        let direct = lp.cycle_stress_at(&at).unwrap();
        let twin = probe
            .iter()
            .enumerate()
            .flat_map(|(m, &p)| (0..41 * 6).map(move |i| (m, p, i)))
            .map(|(m, p, i)| (direct[m * 41 * 6 + i] - h.stress[p * 41 * 6 + i]).abs() / p0)
            .fold(0.0, f64::max);
        assert!(
            twin < 1e-10,
            "{n}²: the direct sum vs the box's layer: {twin:e} p₀"
        );
        let mut per_window = Vec::new();
        let mut window_maxima = Vec::new();
        for (z, points, reference) in &windows {
            let at: Vec<[f64; 3]> = points
                .iter()
                .map(|p| [p[0] * a, p[1] * a, p[2] * a])
                .collect();
            let got = lp.cycle_stress_at(&at).unwrap();
            let reference: Vec<f64> = reference.iter().map(|v| v * p0).collect();
            let (want, got) = (
                indices_of(&reference, points.len()),
                indices_of(&got, points.len()),
            );
            let argmax = |v: &[f64]| {
                v.iter().enumerate().fold(
                    (0, f64::NEG_INFINITY),
                    |b, (i, &x)| if x > b.1 { (i, x) } else { b },
                )
            };
            let mut row = Vec::new();
            let mut row_max = Vec::new();
            for k in 0..4 {
                let (iw, vw) = argmax(&want[k]);
                let (ig, vg) = argmax(&got[k]);
                let scale = if k < 2 { 1.0 } else { vw.abs() };
                let worst = want[k]
                    .iter()
                    .zip(&got[k])
                    .map(|(w, g)| (w - g).abs() / scale)
                    .fold(0.0, f64::max);
                let spacing = 2.0 * z; // the window's cells: 2z wide
                let apart = ((points[ig][0] - points[iw][0]).abs() / spacing)
                    .max((points[ig][1] - points[iw][1]).abs() / spacing)
                    .round();
                eprintln!(
                    "{n}²: z = {z:.4}a {:<12} max {vg:.5e} at ({:.4}, {:.4}) a; reference {vw:.5e} at \
                     ({:.4}, {:.4}) a; |Δmax| {:.2e}, worst point {worst:.2e}{}, points apart {apart}",
                    NAMES[k],
                    points[ig][0],
                    points[ig][1],
                    points[iw][0],
                    points[iw][1],
                    (vg - vw).abs() / scale,
                    if k < 2 { " (abs.)" } else { " (rel.)" }
                );
                row.push((worst, (vg - vw).abs() / scale, apart));
                row_max.push(vg);
            }
            per_window.push(row);
            window_maxima.push(row_max);
        }
        eprintln!(
            "{n}²: {:.1} s (twin {twin:.1e} p₀)",
            t0.elapsed().as_secs_f64()
        );
        errors.push(per_window);
        maxima.push(window_maxima);
    }
    let order = |a: f64, b: f64| (a / b).log2();
    for (w, (z, _, _)) in windows.iter().enumerate() {
        for k in 0..4 {
            let e: Vec<(f64, f64, f64)> = errors.iter().map(|g| g[w][k]).collect();
            let m: Vec<f64> = maxima.iter().map(|g| g[w][k]).collect();
            let p = order((m[1] - m[0]).abs(), (m[2] - m[1]).abs());
            eprintln!(
                "z = {z:.4}a {:<12} worst point {:.2e} {:.2e} {:.2e} (orders {:.2}, {:.2}); |Δmax| {:.2e} {:.2e} {:.2e}; \
                 maxima {:.5e} {:.5e} {:.5e}, successive differences' order {p:.2}",
                NAMES[k],
                e[0].0,
                e[1].0,
                e[2].0,
                order(e[0].0, e[1].0),
                order(e[1].0, e[2].0),
                e[0].1,
                e[1].1,
                e[2].1,
                m[0],
                m[1],
                m[2]
            );
            // Every point of the window converges (the worst point's error falls on both
            // refinements); at z = 0.0325a — h/4, h/2, h of the three grids — with observed
            // orders ≥ 1 (measured 1.14–2.70), at z = 0.065a more slowly (orders 0.04–3.2: the
            // tractions' own error, ~1e-2 at 128², sets the level there).
            assert!(
                e[0].0 > e[1].0 && e[1].0 > e[2].0 && e[2].0 < 2.5e-2,
                "z = {z}a {}: {e:?}",
                NAMES[k]
            );
            if w == 1 {
                assert!(
                    order(e[0].0, e[1].0) >= 1.0 && order(e[1].0, e[2].0) >= 1.0,
                    "z = {z}a {}: {e:?}",
                    NAMES[k]
                );
            }
            // The window maximum on 128² within 1e-2 of the reference's (absolute for Crossland
            // and Dang Van, relative for SWT and Fatemi–Socie; measured ≤ 8.1e-3), at most one
            // point from its location (the index is flat along y there).
            assert!(
                e[2].1 < 1e-2 && e[2].2 <= 1.0,
                "z = {z}a {}: {e:?}",
                NAMES[k]
            );
        }
    }
}

/// The exact Mindlin–Deresiewicz tractions of the closed cycle at `(x, y)/a`, increment `t`
/// (per p₀; the fixture's superposition, verify/cattaneo_fatigue_surface.py `surface_path`):
/// `p = √(1 − r²)`, `q₁ = μ(∓√(1 − r²) ∓ √(c*² − r²) ± 2√(b² − r²))` (upper signs on unloading
/// `t ≤ 20`), `q₂ = 0`; `σ₁₃ = −q₁` (Johnson 1985 §7.3).
fn md_traction(x: f64, y: f64, t: usize) -> [f64; 3] {
    const MU: f64 = 0.3;
    let r2 = x * x + y * y;
    let s = |c: f64| (c * c - r2).max(0.0).sqrt();
    let a_over_k = 1.0 - 0.5f64.powf(2.0 / 3.0);
    let (tt, sign) = if t <= 20 { (t, 1.0) } else { (t - 20, -1.0) };
    let b = (1.0 - tt as f64 / 10.0 * a_over_k / 2.0).sqrt();
    [s(1.0), sign * MU * (-s(1.0) - s(C_STAR) + 2.0 * s(b)), 0.0]
}

/// Surface stress paths at arbitrary surface points from piecewise-constant tractions
/// `tractions[(t · 3 + c) · cells + k]` (Pa) on `grid`, by the direct sum of Love's rectangle
/// stresses at z = 0 (docs/theory-sam.md#love-rectangle-stresses). Points on a cell edge line
/// are not allowed (the log singularities of the piecewise-constant tractions).
fn surface_paths_of(
    grid: &halfspace::sam::SurfaceGrid,
    nu: f64,
    tractions: &[f64],
    points: &[[f64; 2]],
) -> Vec<f64> {
    use halfspace::sam::kernels::subsurface::{pressure_stress, shear_stress};
    use halfspace::sam::kernels::InPlane;
    let n = grid.len();
    let inc = tractions.len() / (3 * n);
    let mut out = vec![0.0; points.len() * inc * 6];
    let mut infl = vec![0.0; n * 18];
    for (m, pt) in points.iter().enumerate() {
        for c in 0..n {
            let (xc, yc) = grid.centre(c / grid.n2, c % grid.n2);
            let (dx, dy) = (pt[0] - xc, pt[1] - yc);
            let k = [
                pressure_stress(dx, dy, 0.0, grid.half1, grid.half2, nu),
                shear_stress(InPlane::X1, dx, dy, 0.0, grid.half1, grid.half2, nu),
                shear_stress(InPlane::X2, dx, dy, 0.0, grid.half1, grid.half2, nu),
            ];
            for (j, kj) in k.iter().enumerate() {
                infl[c * 18 + j * 6..c * 18 + j * 6 + 6].copy_from_slice(kj);
            }
        }
        for t in 0..inc {
            let tr = &tractions[t * 3 * n..(t + 1) * 3 * n];
            let mut s = [0.0; 6];
            for c in 0..n {
                for j in 0..3 {
                    let w = tr[j * n + c];
                    if w != 0.0 {
                        for (o, so) in s.iter_mut().enumerate() {
                            *so += w * infl[c * 18 + j * 6 + o];
                        }
                    }
                }
            }
            out[(m * inc + t) * 6..(m * inc + t) * 6 + 6].copy_from_slice(&s);
        }
    }
    out
}

/// The two error sources of the surface layer at the rim, separated (docs/fatigue.md, "The two
/// error sources, separated"): (a) the surface stresses of the EXACT Mindlin–Deresiewicz tractions
/// sampled as the solver does (piecewise constant, the value at each cell centre; and the cell
/// average) against the closed form at the window's cell centres — the discretisation error of
/// the surface evaluation alone; (b) the solver's tractions against the exact ones (at the cell
/// centre and the cell average), by region, and their share of the stress error. `cargo test -p
/// halfspace --test fixtures_cattaneo_fatigue surface_error_sources -- --nocapture` (with
/// `DUMP_TRACTIONS=DIR` it also writes the loops' tractions for
/// verify/cattaneo_surface_rim_fit.py).
#[test]
fn surface_error_sources() {
    let fx = read_dataset("datasets/cattaneo_fatigue_surface.json");
    let grids = [32usize, 64, 128];
    // Per grid: [exact at centres, exact averages, solver history] × region (rim, annulus,
    // outside) × (max |Δσ|/p₀, max |ΔCrossland|); solver tractions vs exact [centre, average] ×
    // region × (p, q₁).
    let mut rows_a = Vec::new();
    let mut rows_b = Vec::new();
    for &n in &grids {
        let lp = cattaneo_loop(n);
        let (a, p0) = (lp.case().hertz_radius(), lp.case().hertz_pressure());
        let grid = *lp.solver().problem().grid();
        let h = 2.0 * grid.half1;
        let cell_a = h / a;
        let cells = grid.len();
        let src = lp.cycle_sources().unwrap();
        assert_eq!(src.recorded, 41);
        // Exact tractions at the cell centres and as cell averages (16 × 16 midpoint rule).
        let mut at_centre = vec![0.0; 41 * 3 * cells];
        let mut average = vec![0.0; 41 * 3 * cells];
        const SUBS: usize = 16;
        for c in 0..cells {
            let (xc, yc) = grid.centre(c / grid.n2, c % grid.n2);
            let (xa, ya) = (xc / a, yc / a);
            if xa.hypot(ya) > 1.0 + 1.5 * cell_a {
                continue;
            }
            for t in 0..41 {
                let e = md_traction(xa, ya, t);
                let mut avg = [0.0; 3];
                for u in 0..SUBS {
                    for v in 0..SUBS {
                        let du = ((u as f64 + 0.5) / SUBS as f64 - 0.5) * cell_a;
                        let dv = ((v as f64 + 0.5) / SUBS as f64 - 0.5) * cell_a;
                        let s = md_traction(xa + du, ya + dv, t);
                        for k in 0..3 {
                            avg[k] += s[k] / (SUBS * SUBS) as f64;
                        }
                    }
                }
                for k in 0..3 {
                    at_centre[(t * 3 + k) * cells + c] = e[k] * p0;
                    average[(t * 3 + k) * cells + c] = avg[k] * p0;
                }
            }
        }
        // (b) the solver's tractions by region (rim band |r − a| < 1.5 cells, the rest of the
        // slip annulus, the stick zone r < c* − 1.5 cells, outside r > a + 1.5 cells).
        let region_of = |r: f64| {
            if (r - 1.0).abs() < 1.5 * cell_a {
                0
            } else if r > 1.0 {
                3
            } else if r > C_STAR - 1.5 * cell_a {
                1
            } else {
                2
            }
        };
        let mut trac = [[[0.0f64; 2]; 4]; 2];
        for c in 0..cells {
            let (xc, yc) = grid.centre(c / grid.n2, c % grid.n2);
            let region = region_of((xc / a).hypot(yc / a));
            for t in 0..41 {
                for k in 0..2 {
                    let got = src.tractions[(t * 3 + k) * cells + c];
                    for (w, exact) in [&at_centre, &average].iter().enumerate() {
                        let d = (got - exact[(t * 3 + k) * cells + c]).abs() / p0;
                        trac[w][region][k] = trac[w][region][k].max(d);
                    }
                }
            }
        }
        eprintln!(
            "{n}²: (b) solver tractions − exact at the cell centres, max |Δ|/p₀ (p, q₁): rim {:.2e} {:.2e}, \
             slip annulus {:.2e} {:.2e}, stick zone {:.2e} {:.2e}, outside {:.2e} {:.2e}",
            trac[0][0][0], trac[0][0][1], trac[0][1][0], trac[0][1][1],
            trac[0][2][0], trac[0][2][1], trac[0][3][0], trac[0][3][1]
        );
        eprintln!(
            "{n}²: (b) solver tractions − exact cell averages: rim {:.2e} {:.2e}, slip annulus {:.2e} {:.2e}, \
             stick zone {:.2e} {:.2e}, outside {:.2e} {:.2e}",
            trac[1][0][0], trac[1][0][1], trac[1][1][0], trac[1][1][1],
            trac[1][2][0], trac[1][2][1], trac[1][3][0], trac[1][3][1]
        );
        // The contact area and the load of the solver's last increment.
        let (p_last, _, _) = src.increment(40);
        let area = p_last.iter().filter(|&&v| v > 0.0).count() as f64 * h * h;
        let load: f64 = p_last.iter().sum::<f64>() * h * h;
        eprintln!(
            "{n}²: contact radius from the area √(A/π) = {:.5} a, load {:.6} W",
            (area / std::f64::consts::PI).sqrt() / a,
            load / lp.case().hertz_force()
        );
        // (a) the surface evaluation alone: the window's surface-cell centres.
        let sf = &fx["grids"][n.to_string()];
        let centres = rows(&sf["points"]);
        let stress = sf["stress"].as_array().unwrap();
        let points: Vec<[f64; 2]> = centres.iter().map(|p| [p[0] * a, p[1] * a]).collect();
        let reference: Vec<f64> = stress
            .iter()
            .flat_map(rows)
            .flatten()
            .map(|v| v * p0)
            .collect();
        let hist = lp.cycle_stress().unwrap().unwrap();
        let sf_cells = rows(&sf["cells"]);
        let history: Vec<f64> = sf_cells
            .iter()
            .flat_map(|c| {
                let q = hist.layers * n * n + c[0] as usize * n + c[1] as usize;
                hist.stress[q * 41 * 6..(q + 1) * 41 * 6].to_vec()
            })
            .collect();
        let want = indices_of(&reference, points.len());
        let mut row = [[[0.0f64; 2]; 3]; 3];
        let mut maxima = [[0.0f64; 4]; 3];
        let evaluated = [
            surface_paths_of(&grid, lp.case().nu, &at_centre, &points),
            surface_paths_of(&grid, lp.case().nu, &average, &points),
            history,
        ];
        // The solver's tractions' own share: its surface layer against the surface stresses of
        // the exact tractions evaluated the same way (both piecewise constant, at the centres).
        let exact_indices = indices_of(&evaluated[0], points.len());
        let solver_indices = indices_of(&evaluated[2], points.len());
        let mut share = [[0.0f64; 2]; 3];
        for (m, x) in centres.iter().enumerate() {
            let region = match region_of(x[0].hypot(x[1])) {
                0 => 0,
                3 => 2,
                _ => 1,
            };
            let e = evaluated[2][m * 246..(m + 1) * 246]
                .iter()
                .zip(&evaluated[0][m * 246..(m + 1) * 246])
                .map(|(g, r)| (g - r).abs() / p0)
                .fold(0.0, f64::max);
            share[region][0] = share[region][0].max(e);
            share[region][1] =
                share[region][1].max((solver_indices[0][m] - exact_indices[0][m]).abs());
        }
        eprintln!(
            "{n}²: (b) the solver's tractions' share: its surface layer − the exact tractions' (both \
             piecewise constant), max |Δσ|/p₀ (|ΔCrossland|): rim {:.3e} ({:.3e}), slip annulus {:.3e} \
             ({:.3e}), outside {:.3e} ({:.3e})",
            share[0][0], share[0][1], share[1][0], share[1][1], share[2][0], share[2][1]
        );
        for (w, paths) in evaluated.iter().enumerate() {
            let got = indices_of(paths, points.len());
            for (m, x) in centres.iter().enumerate() {
                let region = match region_of(x[0].hypot(x[1])) {
                    0 => 0,
                    3 => 2,
                    _ => 1,
                };
                let e = paths[m * 246..(m + 1) * 246]
                    .iter()
                    .zip(&reference[m * 246..(m + 1) * 246])
                    .map(|(g, r)| (g - r).abs() / p0)
                    .fold(0.0, f64::max);
                row[w][region][0] = row[w][region][0].max(e);
                row[w][region][1] = row[w][region][1].max((got[0][m] - want[0][m]).abs());
            }
            for k in 0..4 {
                maxima[w][k] = got[k].iter().copied().fold(f64::NEG_INFINITY, f64::max);
            }
        }
        let ref_max: Vec<f64> = (0..4)
            .map(|k| want[k].iter().copied().fold(f64::NEG_INFINITY, f64::max))
            .collect();
        for (w, name) in [
            "exact tractions at the centres",
            "exact cell averages",
            "solver (the loop's surface layer)",
        ]
        .iter()
        .enumerate()
        {
            eprintln!(
                "{n}²: (a) {name:<34} vs the closed form, max |Δσ|/p₀ (|ΔCrossland|): rim {:.3e} ({:.3e}), \
                 slip annulus {:.3e} ({:.3e}), outside {:.3e} ({:.3e}); cell-centre maxima C {:.4} DV {:.4} \
                 SWT {:.4e} FS {:.4e} (closed form at the centres {:.4} {:.4} {:.4e} {:.4e})",
                row[w][0][0], row[w][0][1], row[w][1][0], row[w][1][1], row[w][2][0], row[w][2][1],
                maxima[w][0], maxima[w][1], maxima[w][2], maxima[w][3],
                ref_max[0], ref_max[1], ref_max[2], ref_max[3]
            );
        }
        if let Ok(dir) = std::env::var("DUMP_TRACTIONS") {
            let bytes: Vec<u8> = src.tractions.iter().flat_map(|v| v.to_le_bytes()).collect();
            std::fs::write(format!("{dir}/tractions_{n}.f64"), bytes).unwrap();
            std::fs::write(
                format!("{dir}/tractions_{n}.json"),
                format!(
                    "{{\"n\":{n},\"half\":{},\"a\":{a},\"p0\":{p0},\"nu\":{},\"w\":{}}}",
                    grid.half1,
                    lp.case().nu,
                    lp.case().hertz_force()
                ),
            )
            .unwrap();
        }
        rows_a.push(row);
        rows_b.push((trac, share));
    }
    for g in 0..3 {
        let (a, (trac, share)) = (&rows_a[g], &rows_b[g]);
        // (a) The evaluation alone: the exact tractions sampled at the cell centres carry at
        // least 90 % of the solver's error at the rim, on every grid (measured 2.17e-1, 1.44e-1,
        // 1.10e-1 against the solver's 2.20e-1, 1.48e-1, 1.14e-1 p₀), and their Crossland error
        // there is as large (0.78, 0.43, 0.38 against 0.75, 0.38, 0.37).
        assert!(a[0][0][0] >= 0.9 * a[2][0][0], "grid {g}: {a:?}");
        assert!(a[0][0][1] >= 0.9 * a[2][0][1], "grid {g}: {a:?}");
        // The cell averages instead of the centre values do no better (2.18e-1, 1.42e-1,
        // 1.15e-1): the error is the piecewise-constant representation's, not the sampling rule's.
        assert!(a[1][0][0] >= 0.9 * a[2][0][0], "grid {g}: {a:?}");
        // (b) The solver's tractions differ from the exact ones at the rim cells by 2–5e-2 p₀
        // (measured p 3.5e-2, 2.3e-2, 2.3e-2; q₁ 5.2e-2, 3.4e-2, 3.0e-2 at the centres) and
        // inside the stick zone by < 2e-3; their share of the rim's stress error is
        // 5.2e-2, 3.3e-2, 3.1e-2 p₀ — at most 0.3 of the evaluation's own.
        assert!(
            trac[0][0][0] < 4e-2 && trac[0][0][1] < 6e-2,
            "grid {g}: {trac:?}"
        );
        assert!(
            trac[0][2][0] < 2e-3 && trac[0][2][1] < 2e-3,
            "grid {g}: {trac:?}"
        );
        assert!(
            share[0][0] < 0.3 * a[0][0][0],
            "grid {g}: {share:?} vs {a:?}"
        );
    }
    // The evaluation's own rim error falls only like √h (observed orders 0.59, 0.39).
    let order = |g: usize| (rows_a[g][0][0][0] / rows_a[g + 1][0][0][0]).log2();
    eprintln!(
        "(a) exact tractions at the centres, rim: observed orders {:.2}, {:.2}",
        order(0),
        order(1)
    );
    assert!(order(0) > 0.3 && order(1) > 0.3 && order(0) < 1.0 && order(1) < 1.0);
}
