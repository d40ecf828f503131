//! The surface-response operator of an inhomogeneous body (docs/theory-sam.md#surface-response-operator):
//! its columns against the EIM solve of the same tractions, its reciprocity, and the fretting
//! loop on it against the nested contact ↔ EIM loop (the reference path), including the
//! subsurface stresses at the points A–D and a resumed loop.

mod support;

use halfspace_sam::contact::{BodyResponse, ContactParams, ContactProblem};
use halfspace_sam::contact::{
    InhomogeneousContact, NestedParams, DEFAULT_EIM_CHANGE_FACTOR, DEFAULT_EIM_RECYCLED_DEPTH,
    REFERENCE_EIM_CHANGE_FACTOR,
};
use halfspace_sam::drivers::fretting_loop::{FrettingLoop, LoopCase};
use halfspace_sam::eim::{solve_under_tractions, EimParams, FibreLayout, Inhomogeneity, Shape};
use halfspace_sam::normal::NormalLoad;
use halfspace_sam::{Body, Compliance, SamError, SurfaceGrid};

const R: f64 = 105e-6;
const E: f64 = 210e9;
const NU: f64 = 0.3;

fn hertz_radius(w: f64) -> f64 {
    let e_star = E / (1.0 - NU * NU);
    (3.0 * w * R / (4.0 * e_star)).cbrt()
}

fn sphere(a: f64, ratio: f64) -> Inhomogeneity {
    Inhomogeneity {
        shape: Shape::Sphere {
            x: 0.1 * a,
            y: -0.05 * a,
            z: 0.45 * a,
            r: 0.3 * a,
        },
        e: ratio * E,
        nu: NU,
    }
}

fn contact(grid: SurfaceGrid, inh: &[Inhomogeneity], body: BodyResponse) -> InhomogeneousContact {
    let c = Compliance::pair(Body::Rigid, Body::elastic(E, NU).unwrap()).unwrap();
    let geometry = (0..grid.len())
        .map(|k| {
            let (x, y) = grid.centre(k / grid.n2, k % grid.n2);
            (x * x + y * y) / (2.0 * R)
        })
        .collect();
    let problem = ContactProblem::new(grid, c, geometry, ContactParams::default()).unwrap();
    let params = NestedParams {
        body,
        ..Default::default()
    };
    InhomogeneousContact::new(problem, E, NU, inh, params).unwrap()
}

/// A deterministic pseudo-random number in [−1, 1) (fixed seed, no dependency).
fn lcg(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

/// `T τ` of the built operator against the EIM solve of the same tractions (the matrix-free
/// route of the nested loop), for random tractions on the candidate cells; and the reciprocity
/// of the restricted operator.
#[test]
fn operator_columns_match_the_eim_solve_of_the_same_tractions() {
    let a = hertz_radius(0.08);
    let grid = SurfaceGrid::square(16, 4.0 * a).unwrap();
    for ratio in [2.0, 0.5] {
        let inh = [sphere(a, ratio)];
        let solver = contact(
            grid,
            &inh,
            BodyResponse::SurfaceOperator { radius: 1.2 * a },
        );
        let op = solver.surface_response().expect("operator path");
        let m = op.cells().len();
        assert!(m > 50 && m < 120, "{m} candidates");
        let n = grid.len();
        let mut seed = 20261126u64;
        let mut t = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        for &k in op.cells() {
            for f in &mut t {
                f[k] = 1e9 * lcg(&mut seed);
            }
        }
        let mut u = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        {
            let [u1, u2, u3] = &mut u;
            op.apply(&t[0], Some([&t[1], &t[2]]), [u1, u2, u3]).unwrap();
        }
        let direct = solve_under_tractions(
            grid,
            E,
            NU,
            &inh,
            &t[0],
            Some([&t[1], &t[2]]),
            &EimParams::default(),
        )
        .unwrap();
        let scale = u.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
        let diff = u
            .iter()
            .flatten()
            .zip(direct.eigen_displacements.iter().flatten())
            .fold(0.0f64, |s, (x, y)| s.max((x - y).abs()));
        let asym = op.asymmetry();
        eprintln!(
            "E_I/E = {ratio}: {m} candidates, build {} EIM applications; max|Tτ − EIM(τ)|/max|u| = {:.2e}; asymmetry {asym:.2e}",
            op.build_iterations(),
            diff / scale
        );
        // Both routes solve the same EIM to a relative residual of 1e-10.
        assert!(diff <= 1e-8 * scale, "{} relative", diff / scale);
        // Reciprocity (Betti) holds up to the collocation of the discretisation.
        assert!(asym < 0.1, "asymmetry {asym}");
    }
}

/// Tractions past the candidate region are refused with the typed error.
#[test]
fn contact_outside_the_candidate_region_is_refused() {
    let a = hertz_radius(0.08);
    let grid = SurfaceGrid::square(16, 4.0 * a).unwrap();
    let inh = [sphere(a, 2.0)];
    let mut solver = contact(
        grid,
        &inh,
        BodyResponse::SurfaceOperator { radius: 0.5 * a },
    );
    let err = solver
        .increment(NormalLoad::Force(0.08), [0.0; 2])
        .unwrap_err();
    assert!(
        matches!(err, SamError::ContactOutsideSurfaceOperator { cells } if cells > 0),
        "{err}"
    );
}

/// The composite loop at 32² (2 cells per fibre radius), short path.
fn composite(e_ratio: f64, operator: Option<f64>) -> LoopCase {
    let mut case = LoopCase {
        normal_steps: 4,
        shift_step: 0.01e-6,
        ..LoopCase::default()
    }
    .composite(FibreLayout::FibreCentred, e_ratio)
    .unwrap();
    case.grid = 32;
    case.subsurface_depth = Some(0.5 * case.hertz_radius());
    // The closed cycle's stress history (the fatigue input) reads the eigenstrains at every
    // increment: on the operator path they must be synced to the tractions first.
    case.fatigue_depth = Some(0.5 * case.hertz_radius());
    case.surface_operator_over_a = operator;
    case
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// The loop on the operator against the nested loop, increment by increment: p, q₁, q₂ within
/// 1e-6 p₀ at every increment; the von Mises fields at A–D (one EIM solve from the final
/// tractions on the operator path) within 1e-6 of their largest value.
#[test]
fn the_loop_on_the_operator_reproduces_the_nested_loop() {
    for ratio in [2.0, 0.5] {
        let mut nested = FrettingLoop::new(composite(ratio, None)).unwrap();
        let clock = std::time::Instant::now();
        let mut fast = FrettingLoop::new(composite(ratio, Some(1.3))).unwrap();
        let build = clock.elapsed().as_secs_f64();
        let p0 = nested.case().hertz_pressure();
        let mut worst: f64 = 0.0;
        while nested.step().unwrap().is_some() {
            fast.step().unwrap().unwrap();
            let (s, f) = (
                nested.solver().problem().state(),
                fast.solver().problem().state(),
            );
            worst = worst
                .max(max_diff(&s.pressure, &f.pressure))
                .max(max_diff(&s.shear[0], &f.shear[0]))
                .max(max_diff(&s.shear[1], &f.shear[1]));
        }
        assert!(fast.is_done());
        let mut vm_worst: f64 = 0.0;
        for (pn, pf) in nested.points().iter().zip(fast.points()) {
            let (vn, vf) = (
                pn.von_mises.as_ref().unwrap(),
                pf.von_mises.as_ref().unwrap(),
            );
            let scale = vn.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            vm_worst = vm_worst.max(max_diff(vn, vf) / scale);
        }
        let (hn, hf) = (
            nested.cycle_stress().unwrap().unwrap(),
            fast.cycle_stress().unwrap().unwrap(),
        );
        assert_eq!(hn.recorded, hn.increments);
        let sigma = hn.stress.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let history_worst = max_diff(&hn.stress, &hf.stress) / sigma;
        let outer = |lp: &FrettingLoop| lp.rows().iter().map(|r| r.outer_iterations).sum::<usize>();
        eprintln!(
            "E_I/E = {ratio}: max |Δp|, |Δq| over {} increments = {:.2e} p0; von Mises at A–D {:.2e}; outer passes {} (nested) / {} (operator); increments {:.2} s / {:.2} s, operator build {build:.1} s ({} columns, {} EIM applications)",
            nested.rows().len(),
            worst / p0,
            vm_worst,
            outer(&nested),
            outer(&fast),
            nested.seconds().increments,
            fast.seconds().increments,
            {
                let op = fast.solver().nested().unwrap().surface_response().unwrap();
                op.components() * op.cells().len()
            },
            fast.solver()
                .nested()
                .unwrap()
                .surface_response()
                .unwrap()
                .build_iterations(),
        );
        assert!(worst <= 1e-6 * p0, "{} p0", worst / p0);
        assert!(vm_worst <= 1e-6, "von Mises {vm_worst}");
        eprintln!("E_I/E = {ratio}: cycle stress history max |Δσ| / max |σ| = {history_worst:.2e}");
        assert!(history_worst <= 1e-6, "stress history {history_worst}");
    }
}

/// A loop on the operator snapshotted midway and resumed (the operator rebuilt: it is
/// deterministic) repeats the uninterrupted loop bit for bit.
#[test]
fn a_resumed_loop_on_the_operator_repeats_the_uninterrupted_one() {
    // Past the point A (an EIM sync) and into the shift.
    support::assert_resumes_bit_for_bit::<FrettingLoop>(&composite(2.0, Some(1.3)), 7);
}

/// A loop with the nested path's defaults (the recycled EIM iterations,
/// `DEFAULT_EIM_RECYCLED_DEPTH`) snapshotted midway and resumed repeats the uninterrupted one bit
/// for bit (the recycled history is forgotten at every increment's start).
#[test]
fn a_resumed_loop_with_recycled_eim_iterations_repeats_the_uninterrupted_one() {
    let case = composite(2.0, None);
    assert_eq!(
        NestedParams::default().eim.recycled_depth,
        DEFAULT_EIM_RECYCLED_DEPTH
    );
    const { assert!(DEFAULT_EIM_RECYCLED_DEPTH > 0) };
    // Past the point A and into the shift.
    let (_, snap) = support::assert_resumes_bit_for_bit::<FrettingLoop>(&case, 7);
    assert!(snap.fingerprint.contains(&format!(
        "eim_recycled_depth: Some({DEFAULT_EIM_RECYCLED_DEPTH})"
    )));
}

/// The nested loop with its defaults (the EIM change factor `NestedParams::eim_change_factor` =
/// 3·10⁻³: each pass's EIM solved to 3·10⁻³ of the last outer change, docs/theory-sam.md#outer-loop-tolerances;
/// the block-Jacobi history recycled across an increment's passes, `DEFAULT_EIM_RECYCLED_DEPTH`)
/// against the reference nested loop (10⁻³, plain block Jacobi), increment by increment over the
/// whole loop: p, q₁, q₂ within 1e-6 p₀ with fewer EIM applications; a factor outside (0, 1] is
/// refused.
#[test]
fn the_loop_with_looser_eim_solves_reproduces_the_reference() {
    let case = composite(2.0, None);
    assert_eq!(
        NestedParams::default().eim_change_factor,
        DEFAULT_EIM_CHANGE_FACTOR
    );
    let reference_params = NestedParams {
        eim_change_factor: REFERENCE_EIM_CHANGE_FACTOR,
        eim: EimParams::default(),
        ..NestedParams::default()
    };
    // The reference path is the plain alternation whatever the library's default.
    let reference_case = LoopCase {
        alternation: Some(halfspace_sam::contact::Alternation::Plain),
        ..case.clone()
    };
    let mut reference = FrettingLoop::with_params(reference_case, reference_params).unwrap();
    let mut fast = FrettingLoop::new(case.clone()).unwrap();
    // The factor set on the case (the config key `eim_change_factor`) is the same loop as the
    // one passed as a parameter, bit for bit.
    let keyed_case = LoopCase {
        eim_change_factor: Some(REFERENCE_EIM_CHANGE_FACTOR),
        eim_recycled_depth: Some(0),
        alternation: Some(halfspace_sam::contact::Alternation::Plain),
        ..case.clone()
    };
    let mut keyed = FrettingLoop::new(keyed_case.clone()).unwrap();
    let p0 = reference.case().hertz_pressure();
    let mut worst: f64 = 0.0;
    while reference.step().unwrap().is_some() {
        fast.step().unwrap().unwrap();
        keyed.step().unwrap().unwrap();
        assert_eq!(
            keyed.solver().problem().state(),
            reference.solver().problem().state()
        );
        let (s, f) = (
            reference.solver().problem().state(),
            fast.solver().problem().state(),
        );
        worst = worst
            .max(max_diff(&s.pressure, &f.pressure))
            .max(max_diff(&s.shear[0], &f.shear[0]))
            .max(max_diff(&s.shear[1], &f.shear[1]));
    }
    assert!(fast.is_done());
    let eim = |lp: &FrettingLoop| lp.rows().iter().map(|r| r.eim_iterations).sum::<usize>();
    let outer = |lp: &FrettingLoop| lp.rows().iter().map(|r| r.outer_iterations).sum::<usize>();
    eprintln!(
        "EIM factor {DEFAULT_EIM_CHANGE_FACTOR:e} vs {REFERENCE_EIM_CHANGE_FACTOR:e}: max |Δp|, |Δq| over {} increments = {:.2e} p0; EIM applications {} / {}; outer passes {} / {}",
        reference.rows().len(),
        worst / p0,
        eim(&fast),
        eim(&reference),
        outer(&fast),
        outer(&reference),
    );
    assert!(worst <= 1e-6 * p0, "{} p0", worst / p0);
    assert!(eim(&fast) < eim(&reference));
    for bad in [0.0, -1e-2, 1.5, f64::NAN] {
        let params = NestedParams {
            eim_change_factor: bad,
            ..NestedParams::default()
        };
        let err = FrettingLoop::with_params(case.clone(), params)
            .err()
            .expect("refused");
        assert!(err.to_string().contains("EIM change factor"), "{err}");
        let keyed_bad = LoopCase {
            eim_change_factor: Some(bad),
            ..keyed_case.clone()
        };
        let err = FrettingLoop::new(keyed_bad).err().expect("refused");
        assert!(err.to_string().contains("EIM change factor"), "{err}");
    }
}

/// A checkpoint's fingerprint records the EIM change factor the nested loop uses, not `None`
/// when the case leaves it to the library (a later change of the default is caught); a
/// checkpoint written before `ce12b57` (the case as given, `None`, meaning 10⁻², the default
/// then) is accepted while the run uses 10⁻² and depth 0 — the same loop — and continues bit
/// for bit, and refused with another factor;
/// without inhomogeneities the factor is not used and not recorded (fingerprint unchanged). The
/// recycled EIM depth is recorded likewise; a checkpoint written before it was (the plain
/// iteration) resumes bit for bit with `eim_recycled_depth = 0` and is refused, naming that key,
/// under the default depth.
#[test]
fn a_checkpoint_records_the_eim_change_factor_used() {
    let case = support::stiff_sphere_loop();
    let used = LoopCase {
        eim_change_factor: Some(DEFAULT_EIM_CHANGE_FACTOR),
        eim_recycled_depth: Some(DEFAULT_EIM_RECYCLED_DEPTH),
        alternation: Some(case.alternation_scheme()),
        ..case.clone()
    };
    {
        let mut whole = FrettingLoop::new(case.clone()).unwrap();
        whole.step().unwrap().unwrap();
        let snap = whole.snapshot();
        let window = format!(
            "{}{}",
            case.window_fingerprint().unwrap(),
            case.stopping_fingerprint(NestedParams::default())
        );
        assert_eq!(snap.fingerprint, format!("{used:?}{window}"));
        assert!(snap.fingerprint.contains("eim_change_factor: Some(0.003)"));
        let mut resumed = FrettingLoop::resume(case.clone(), snap.clone()).unwrap();
        whole.step().unwrap().unwrap();
        resumed.step().unwrap().unwrap();
        assert_eq!(resumed.snapshot(), whole.snapshot());
    }
    // Checkpoints written before the recycled depth was recorded (the plain block Jacobi, depth
    // 0, and the factor 10⁻², then the default): after commit `ce12b57` the fingerprint holds the
    // factor used and lacks the depth. Accepted with `eim_recycled_depth = 0` and
    // `eim_change_factor = 1e-2` (the same loop, bit for bit); refused, naming the keys, under the
    // defaults. One written before `ce12b57` (the case as given, `None` meaning 10⁻²) is the same
    // loop: accepted with the same keys, refused naming them under the defaults.
    // (Those checkpoints lack the alternation scheme too: the plain alternation, the default
    // then and now.) Since stop 46 every checkpoint of a build before the contact window is
    // refused before these rules (tests/contact_window.rs), and since stop 47 every one without
    // the outer loop's stopping rule (tests/outer_stopping.rs), so the old forms are written here
    // with both fields, as checks of the rules themselves.
    let window = format!(
        "{}{}",
        case.window_fingerprint().unwrap(),
        case.stopping_fingerprint(NestedParams::default())
    );
    let without_depth = |s: String| {
        s.replacen(", eim_recycled_depth: None", "", 1)
            .replacen(", alternation: None", "", 1)
    };
    let plain = LoopCase {
        eim_change_factor: Some(1e-2),
        eim_recycled_depth: Some(0),
        ..case.clone()
    };
    let mut whole = FrettingLoop::new(plain.clone()).unwrap();
    whole.step().unwrap().unwrap();
    let snap = whole.snapshot();
    assert!(snap.fingerprint.contains("eim_recycled_depth: Some(0)"));
    let legacy = |fingerprint: String| halfspace_sam::drivers::fretting_loop::LoopSnapshot {
        fingerprint,
        ..snap.clone()
    };
    let after_ce12b57 = legacy(without_depth(format!(
        "{:?}{window}",
        LoopCase {
            eim_change_factor: Some(1e-2),
            ..case.clone()
        }
    )));
    let before_ce12b57 = legacy(without_depth(format!("{case:?}{window}")));
    for old in [&after_ce12b57, &before_ce12b57] {
        assert!(!old.fingerprint.contains("eim_recycled_depth"));
        let err = FrettingLoop::resume(case.clone(), old.clone())
            .err()
            .expect("refused");
        assert!(
            err.to_string()
                .contains("resume it with eim_recycled_depth = 0"),
            "{err}"
        );
    }
    let mut resumed = FrettingLoop::resume(plain.clone(), after_ce12b57.clone()).unwrap();
    assert_eq!(resumed.snapshot(), snap);
    whole.step().unwrap().unwrap();
    resumed.step().unwrap().unwrap();
    assert_eq!(resumed.snapshot(), whole.snapshot());
    let mut whole_again = FrettingLoop::new(plain.clone()).unwrap();
    whole_again.step().unwrap().unwrap();
    let mut resumed = FrettingLoop::resume(plain.clone(), before_ce12b57.clone()).unwrap();
    whole_again.step().unwrap().unwrap();
    resumed.step().unwrap().unwrap();
    assert_eq!(resumed.snapshot(), whole_again.snapshot());
    let other = LoopCase {
        eim_change_factor: Some(REFERENCE_EIM_CHANGE_FACTOR),
        ..case.clone()
    };
    let err = FrettingLoop::resume(other.clone(), snap)
        .err()
        .expect("refused");
    assert!(err.to_string().contains("another configuration"), "{err}");
    for s in [after_ce12b57, before_ce12b57] {
        let err = FrettingLoop::resume(other.clone(), s)
            .err()
            .expect("refused");
        assert!(err.to_string().contains("eim_recycled_depth = 0"), "{err}");
    }
    let plain = LoopCase {
        grid: 16,
        ..LoopCase::default()
    };
    let fingerprint = FrettingLoop::new(plain.clone()).unwrap().fingerprint();
    assert_eq!(
        fingerprint,
        format!(
            "{:?}{}",
            LoopCase {
                alternation: Some(plain.alternation_scheme()),
                ..plain.clone()
            },
            plain.window_fingerprint().unwrap()
        )
    );
}

/// The nested loop with the EIM's block Jacobi recycling its iterations across an increment's
/// passes (`EimParams::recycled_depth`, docs/theory-sam.md#solving-the-eim-equations) against the
/// reference path (`REFERENCE_EIM_CHANGE_FACTOR`, plain block Jacobi), increment by increment
/// through the normal loading and into the tangential cycle: within 1e-6 p₀ in p and q, with
/// fewer EIM applications than the plain iteration at the same factor.
#[test]
fn recycled_eim_iterations_keep_the_loop_on_the_reference_path() {
    let mut case = LoopCase {
        grid: 16,
        normal_steps: 3,
        ..LoopCase::default()
    };
    let a = case.hertz_radius();
    case.inhomogeneities.push(sphere(a, 2.0));
    // The reference path's alternation, whatever the library's default.
    case.alternation = Some(halfspace_sam::contact::Alternation::Plain);
    let p0 = case.hertz_pressure();
    let params = |eta: f64, depth: usize| NestedParams {
        eim_change_factor: eta,
        eim: EimParams {
            recycled_depth: depth,
            ..EimParams::default()
        },
        ..NestedParams::default()
    };
    let mut loops: Vec<FrettingLoop> = [
        params(REFERENCE_EIM_CHANGE_FACTOR, 0),
        params(DEFAULT_EIM_CHANGE_FACTOR, 0),
        params(DEFAULT_EIM_CHANGE_FACTOR, 5),
    ]
    .into_iter()
    .map(|p| FrettingLoop::with_params(case.clone(), p).unwrap())
    .collect();
    let mut worst: f64 = 0.0;
    for _ in 0..10 {
        for lp in loops.iter_mut() {
            lp.step().unwrap().unwrap();
        }
        let reference = loops[0].solver().problem().state();
        let recycled = loops[2].solver().problem().state();
        for (x, y) in [
            (&reference.pressure, &recycled.pressure),
            (&reference.shear[0], &recycled.shear[0]),
            (&reference.shear[1], &recycled.shear[1]),
        ] {
            worst = x
                .iter()
                .zip(y)
                .fold(worst, |m, (p, q)| m.max((p - q).abs()));
        }
    }
    let eim = |lp: &FrettingLoop| -> usize { lp.rows().iter().map(|r| r.eim_iterations).sum() };
    // Observed with η = 10⁻² (the default before it became 3·10⁻³): 6.6e-8 p₀; EIM applications
    // 144 (reference), 113 (plain), 82 (recycled).
    assert!(worst < 1e-6 * p0, "{:e} p0", worst / p0);
    assert!(
        eim(&loops[2]) < eim(&loops[1]),
        "{} against {}",
        eim(&loops[2]),
        eim(&loops[1])
    );
}
