//! Survey (ignored; `cargo test --release -p halfspace-cases --test level_bound_survey --
//! --ignored --nocapture`): on [LN11]'s homogeneous 64² loop with the docs' `[fatigue]` table,
//! per level of the box and criterion, the level's exact maximum (the screened evaluation of the
//! whole box's history with `screen_fraction = 1` per level) against the level bounds of
//! docs/fatigue.md, "Layers the screen cannot reach": the reference bound and the anchored bound
//! of [`AnchoredBound`] (8 groups of increments), the reference bound with the exact deviation
//! of each functional, and the anchored bound with every increment an anchor (its best).
// Index loops read like the tables they print.
#![allow(clippy::needless_range_loop)]
use halfspace_cases::config::LoopConfig;
use halfspace_cases::fatigue::field::FieldParams;
use halfspace_cases::fatigue::screened::{anchored_bounds, reference_bounds};
use halfspace_cases::fatigue::{evaluate_screened, Voigt};
use halfspace_cases::loop_fatigue::AnchoredBound;
use halfspace_cases::sam::drivers::fretting_loop::FrettingLoop;
use halfspace_cases::sam::subsurface::{stress_functionals, SubsurfacePlan};

const LN11: &str = "subsurface_over_a = 0.0\n[fatigue]\nf_minus1 = 400e6\nt_minus1 = 280e6\n\
                    fs_k = 0.5\nyield_stress = 600e6\n";

#[test]
#[ignore]
fn level_bounds_against_the_level_maxima() {
    let cfg: LoopConfig = toml::from_str(LN11).unwrap();
    let fatigue = cfg.fatigue_config().unwrap();
    let case = cfg.case("homogeneous", None).unwrap();
    let matrix = fatigue.matrix(case.e, case.nu);
    let mut lp = FrettingLoop::new(case.clone()).unwrap();
    lp.run(|_| std::ops::ControlFlow::Continue(())).unwrap();
    let h = lp.cycle_stress().unwrap().unwrap();
    let sources = lp.cycle_sources().unwrap();
    let (n, inc, levels) = (h.grid.len(), h.increments, h.levels());
    // The exact maximum of each level and criterion.
    let mut exact = vec![[0.0f64; 4]; levels];
    for k in 0..levels {
        let s = &h.stress[k * n * inc * 6..(k + 1) * n * inc * 6];
        let r = evaluate_screened(s, inc, &[matrix], &vec![0; n], &FieldParams::default(), 1.0)
            .unwrap();
        exact[k] = [
            r.crossland_max.value,
            r.dang_van_max.value,
            r.swt_max.value,
            r.fatemi_socie_max.value,
        ];
    }
    let global: [f64; 4] =
        std::array::from_fn(|c| exact.iter().fold(f64::NEG_INFINITY, |m, e| m.max(e[c])));
    println!("global maxima {global:?}");
    let depth = case.fatigue_depth.unwrap();
    let all: Vec<usize> = (0..levels).collect();
    let mut plan = SubsurfacePlan::with_levels(&h.grid, case.e, case.nu, depth, &all).unwrap();
    let tr = |t: usize, c: usize, cell: usize| sources.tractions[(t * 3 + c) * n + cell];
    // The reference bound (as reachable_levels).
    let mut reference = vec![vec![0.0; n]; 3];
    let mut amplitude = vec![vec![0.0; n]; 3];
    for c in 0..3 {
        for cell in 0..n {
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for t in 0..inc {
                lo = lo.min(tr(t, c, cell));
                hi = hi.max(tr(t, c, cell));
            }
            reference[c][cell] = 0.5 * (hi + lo);
            amplitude[c][cell] = 0.5 * (hi - lo);
        }
    }
    let (sigma_ref, _) = plan
        .stress(&reference[0], Some([&reference[1], &reference[2]]), None)
        .unwrap();
    let bound = plan
        .deviation_bounds([&amplitude[0], &amplitude[1], &amplitude[2]])
        .unwrap();
    let scale = sigma_ref
        .iter()
        .chain(bound.iter())
        .flat_map(|f| f.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let level_max = |f: &dyn Fn(usize) -> [f64; 4]| -> Vec<[f64; 4]> {
        (0..levels)
            .map(|k| {
                let mut m = [f64::NEG_INFINITY; 4];
                for cell in 0..n {
                    let b = f(k * n + cell);
                    for c in 0..4 {
                        m[c] = m[c].max(b[c]);
                    }
                }
                m
            })
            .collect()
    };
    let old = level_max(&|p| {
        let r: Voigt = std::array::from_fn(|k| sigma_ref[k][p]);
        let d: [f64; 6] = std::array::from_fn(|f| bound[f][p] + 1e-9 * scale);
        reference_bounds(&r, &d, &matrix).unwrap()
    });
    let mut tables = vec![("reference".to_string(), old)];
    // The reference bound with the exact deviation of each functional from σ^ref.
    let exact_dev = level_max(&|p| {
        let r: Voigt = std::array::from_fn(|k| sigma_ref[k][p]);
        let fr = stress_functionals(&r);
        let mut d = [0.0f64; 6];
        for t in 0..inc {
            let s: [f64; 6] = std::array::from_fn(|k| h.stress[(p * inc + t) * 6 + k]);
            let f = stress_functionals(&s);
            for i in 0..6 {
                d[i] = d[i].max((f[i] - fr[i]).abs());
            }
        }
        reference_bounds(&r, &d, &matrix).unwrap()
    });
    tables.push(("ref, exact dev".to_string(), exact_dev));
    // Every increment an anchor, no residual: the best an anchored bound can do.
    let all_anchors = level_max(&|p| {
        let path: Vec<Voigt> = (0..inc)
            .map(|t| std::array::from_fn(|k| h.stress[(p * inc + t) * 6 + k]))
            .collect();
        anchored_bounds(&path, &vec![[0.0; 6]; inc - 1], &matrix).unwrap()
    });
    tables.push(("all anchors".to_string(), all_anchors));
    // The loop's anchored bound (8 groups, one residual bound per group).
    let bound = AnchoredBound::new(&lp, sources, &all).unwrap().unwrap();
    let anchored = level_max(&|p| {
        bound
            .cell(p, &matrix, &mut (Vec::new(), Vec::new()))
            .unwrap()
    });
    tables.push(("anchored (8 groups)".to_string(), anchored));
    let names = ["Crossland", "Dang Van", "SWT", "Fatemi–Socie"];
    for c in 0..4 {
        println!(
            "\n{}: level, exact max / global, then bound / (0.5 · global) per bound [{}]",
            names[c],
            tables
                .iter()
                .map(|t| t.0.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        );
        for k in (0..levels).filter(|&k| k <= 10 || k + 1 == levels) {
            let row: Vec<String> = tables
                .iter()
                .map(|t| {
                    assert!(t.1[k][c] >= exact[k][c], "{} below the level maximum", t.0);
                    format!("{:6.2}", t.1[k][c] / (0.5 * global[c]))
                })
                .collect();
            println!(
                "level {k:2} (box level {:2}): {:6.3} | {}",
                h.level_of[k],
                exact[k][c] / global[c],
                row.join(" ")
            );
        }
    }
}
