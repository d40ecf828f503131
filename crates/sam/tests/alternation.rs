//! The normal–tangential alternation scheme of the fretting loop's contact solves
//! (`LoopCase::alternation`, config key `alternation`; docs/theory-sam.md#normal-tangential-alternation):
//! recorded in checkpoints (today's checkpoints, written without it, resume on the plain
//! alternation only) and resumed bit for bit on the gauged one.

mod support;

use halfspace_sam::contact::{
    Alternation, ContactParams, ContactProblem, InhomogeneousContact, NestedParams,
    REFERENCE_EIM_CHANGE_FACTOR,
};
use halfspace_sam::drivers::fretting_loop::{FrettingLoop, LoopCase, LoopSnapshot};
use halfspace_sam::eim::EimParams;
use halfspace_sam::eim::FibreLayout;
use halfspace_sam::normal::NormalLoad;
use halfspace_sam::{Body, Compliance, SurfaceGrid};

/// The 16² stiff-sphere loop (the outer passes re-solve every increment, where the gauged
/// alternation gauges its first alternation).
fn sphere_case() -> LoopCase {
    support::stiff_sphere_loop()
}

fn with(case: &LoopCase, alternation: Option<Alternation>) -> LoopCase {
    LoopCase {
        alternation,
        ..case.clone()
    }
}

/// A checkpoint's fingerprint records the scheme the loop uses (also when the case leaves it to
/// the library); a checkpoint written before it did (today's: the plain alternation, the only one
/// the drivers ran) resumes bit for bit under `alternation = "plain"` and is refused under
/// `"gauged"`, naming the key; a recorded scheme resumes only under the same one. An uncoupled
/// pair (identical bodies) does not alternate: the scheme is not used and recorded as `None`.
#[test]
fn a_checkpoint_records_the_alternation_scheme() {
    let case = sphere_case();
    let default = ContactParams::default().alternation;
    assert_eq!(case.alternation_scheme(), default);
    let defaulted = FrettingLoop::new(case.clone()).unwrap();
    assert!(defaulted
        .fingerprint()
        .contains(&format!(", alternation: Some({default:?})")));
    let plain = with(&case, Some(Alternation::Plain));
    let gauged = with(&case, Some(Alternation::Gauged));
    let mut whole = FrettingLoop::new(plain.clone()).unwrap();
    whole.step().unwrap().unwrap();
    let snap = whole.snapshot();
    assert!(snap.fingerprint.contains(", alternation: Some(Plain)"));
    // Today's checkpoint: the same fingerprint without the field.
    let legacy = LoopSnapshot {
        fingerprint: snap
            .fingerprint
            .replacen(", alternation: Some(Plain)", "", 1),
        ..snap.clone()
    };
    assert!(!legacy.fingerprint.contains("alternation"));
    let mut resumed = FrettingLoop::resume(plain.clone(), legacy.clone()).unwrap();
    whole.step().unwrap().unwrap();
    resumed.step().unwrap().unwrap();
    assert_eq!(resumed.snapshot(), whole.snapshot());
    let err = FrettingLoop::resume(gauged.clone(), legacy.clone())
        .err()
        .expect("refused");
    assert!(
        err.to_string()
            .contains("resume it with alternation = \"plain\""),
        "{err}"
    );
    // Left to the library: accepted while its default is the plain alternation.
    let by_default = FrettingLoop::resume(case.clone(), legacy.clone());
    assert_eq!(by_default.is_ok(), default == Alternation::Plain);
    // Recorded: only the same scheme continues it.
    let err = FrettingLoop::resume(gauged.clone(), snap.clone())
        .err()
        .expect("refused");
    assert!(err.to_string().contains("another configuration"), "{err}");
    let mut g = FrettingLoop::new(gauged.clone()).unwrap();
    g.step().unwrap().unwrap();
    let gsnap = g.snapshot();
    assert!(gsnap.fingerprint.contains(", alternation: Some(Gauged)"));
    let err = FrettingLoop::resume(plain.clone(), gsnap.clone())
        .err()
        .expect("refused");
    assert!(err.to_string().contains("another configuration"), "{err}");
    // A legacy checkpoint of another configuration is refused as such (not for the scheme).
    let other = LoopCase {
        friction: 0.25,
        ..gauged.clone()
    };
    let err = FrettingLoop::resume(other, legacy.clone())
        .err()
        .expect("refused");
    assert!(!err.to_string().contains("alternation"), "{err}");
    // Identical bodies: uncoupled, nothing alternates; not recorded, so either key resumes
    // today's checkpoints.
    let uncoupled = LoopCase {
        grid: 16,
        normal_steps: 2,
        indenter: Body::Elastic { e: 210e9, nu: 0.3 },
        ..LoopCase::default()
    };
    assert!(!uncoupled.is_coupled());
    let mut u = FrettingLoop::new(with(&uncoupled, Some(Alternation::Gauged))).unwrap();
    u.step().unwrap().unwrap();
    let usnap = u.snapshot();
    assert!(usnap.fingerprint.contains(", alternation: None"));
    let ulegacy = LoopSnapshot {
        fingerprint: usnap.fingerprint.replacen(", alternation: None", "", 1),
        ..usnap.clone()
    };
    for scheme in [None, Some(Alternation::Plain), Some(Alternation::Gauged)] {
        let mut r = FrettingLoop::resume(with(&uncoupled, scheme), ulegacy.clone()).unwrap();
        r.step().unwrap().unwrap();
        let mut again = FrettingLoop::resume(with(&uncoupled, scheme), usnap.clone()).unwrap();
        again.step().unwrap().unwrap();
        assert_eq!(r.snapshot(), again.snapshot());
    }
}

/// The composite loop on the gauged alternation snapshotted midway (past the point A, into the
/// shift) and resumed repeats the uninterrupted loop bit for bit: a re-solve gauges itself only by
/// the solves of its own increment since `ContactProblem::begin`, which a snapshot does not need.
/// Its homogeneous reference loop likewise.
#[test]
fn a_resumed_gauged_loop_repeats_the_uninterrupted_one() {
    let mut composite = LoopCase {
        normal_steps: 4,
        shift_step: 0.01e-6,
        ..LoopCase::default()
    }
    .composite(FibreLayout::FibreCentred, 2.0)
    .unwrap();
    composite.grid = 32;
    composite.subsurface_depth = Some(0.5 * composite.hertz_radius());
    composite.alternation = Some(Alternation::Gauged);
    for case in [composite.clone(), composite.homogeneous()] {
        let (_, snap) = support::assert_resumes_bit_for_bit::<FrettingLoop>(&case, 7);
        assert!(snap.fingerprint.contains(", alternation: Some(Gauged)"));
    }
}

/// The gauged loop through the driver (`LoopCase::alternation = Some(Gauged)`, the library's other
/// defaults) against the reference path (the plain alternation, the EIM factor 10⁻³, the plain
/// block Jacobi) increment by increment over the whole 32² composite loop, and its homogeneous
/// loop against the plain one: p, q₁, q₂ within 1e-6 p₀ (measured 2.2e-8 / 5.5e-8 p₀ composite
/// with `composite_outer 32`; the homogeneous loop 1.6e-8 / 7.1e-8 with `reference_loop 32`).
#[test]
fn the_gauged_loop_stays_on_the_reference_path() {
    let mut composite = LoopCase::default()
        .composite(FibreLayout::FibreCentred, 2.0)
        .unwrap();
    composite.grid = 32;
    composite.subsurface_depth = None;
    let reference_params = NestedParams {
        eim_change_factor: REFERENCE_EIM_CHANGE_FACTOR,
        eim: EimParams::default(),
        ..NestedParams::default()
    };
    let cases = [
        (composite.clone(), reference_params),
        (composite.homogeneous(), NestedParams::default()),
    ];
    for (case, params) in cases {
        let mut reference =
            FrettingLoop::with_params(with(&case, Some(Alternation::Plain)), params).unwrap();
        let mut gauged = FrettingLoop::new(with(&case, Some(Alternation::Gauged))).unwrap();
        let p0 = case.hertz_pressure();
        let (mut dp, mut dq) = (0.0f64, 0.0f64);
        while reference.step().unwrap().is_some() {
            gauged.step().unwrap().unwrap();
            let (r, g) = (
                reference.solver().problem().state(),
                gauged.solver().problem().state(),
            );
            dp = dp.max(max_diff(&r.pressure, &g.pressure));
            dq = dq
                .max(max_diff(&r.shear[0], &g.shear[0]))
                .max(max_diff(&r.shear[1], &g.shear[1]));
        }
        assert!(gauged.is_done());
        eprintln!(
            "{} inhomogeneities: gauged vs reference over {} increments: max |Δp| {:.2e} p0, \
             |Δq| {:.2e} p0",
            case.inhomogeneities.len(),
            reference.rows().len(),
            dp / p0,
            dq / p0
        );
        assert!(
            dp <= 1e-6 * p0 && dq <= 1e-6 * p0,
            "{} {} p0",
            dp / p0,
            dq / p0
        );
    }
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// A nested contact (one stiff sphere under a rigid sphere on the `ν = 0.3` flat: coupled) on
/// 16² cells, its contact solves on the alternation `alternation`, loaded to `W = 80 mN`.
fn loaded_nested(alternation: Alternation, inexact_contact: bool) -> InhomogeneousContact {
    let case = sphere_case();
    let grid = SurfaceGrid::square(case.grid, case.extent()).unwrap();
    let pair = Compliance::pair(Body::Rigid, Body::elastic(case.e, case.nu).unwrap()).unwrap();
    assert!(pair.coupling != 0.0);
    let geometry = (0..grid.len())
        .map(|k| {
            let (x, y) = grid.centre(k / grid.n2, k % grid.n2);
            (x * x + y * y) / (2.0 * case.radius)
        })
        .collect();
    let params = ContactParams {
        friction: case.friction,
        alternation,
        ..ContactParams::default()
    };
    let problem = ContactProblem::new(grid, pair, geometry, params).unwrap();
    let mut nested = InhomogeneousContact::new(
        problem,
        case.e,
        case.nu,
        &case.inhomogeneities,
        NestedParams {
            inexact_contact,
            ..NestedParams::default()
        },
    )
    .unwrap();
    nested
        .increment(NormalLoad::Force(case.force), [0.0; 2])
        .unwrap();
    nested
}

/// Every evaluation of the nested force control (`InhomogeneousContact::increment_with_force`:
/// Brent's method on `D₁ ↦ Q₁(D₁)`, each evaluation the nested loop from the same warm start) is
/// the first solve of its increment (docs/theory-sam.md#normal-tangential-alternation: a re-solve
/// gauges its first alternation by the last solve's right-hand side, which for an evaluation
/// would be the previous evaluation's, at another `D₁`). So the force-controlled increment is,
/// bit for bit, the displacement-controlled increment at the shift it returns, whatever the
/// evaluations before the last one, on either alternation, with two brackets (other evaluations
/// before the last). With the nested loop's inexact contact solves (the default) the first pass's
/// tolerances sit at their ceilings, gauged or not; with `inexact_contact = false` an evaluation
/// gauged by the previous one's solves differed (before `ContactProblem::restore_state` started
/// the solve count afresh: gauged, bracket 2e-9, 20 tangential products in the last solve where
/// the displacement-controlled increment takes 22, other bits).
#[test]
fn every_evaluation_of_the_nested_force_control_is_a_first_solve() {
    let case = sphere_case();
    let q = 0.5 * case.friction * case.force;
    for (alternation, inexact) in [
        (Alternation::Plain, true),
        (Alternation::Plain, false),
        (Alternation::Gauged, true),
        (Alternation::Gauged, false),
    ] {
        for bracket in [2e-9, 7e-9] {
            let mut by_force = loaded_nested(alternation, inexact);
            let (_, d) = by_force
                .increment_with_force(NormalLoad::Force(case.force), q, bracket)
                .unwrap();
            let mut by_shift = loaded_nested(alternation, inexact);
            by_shift
                .increment(NormalLoad::Force(case.force), [d, 0.0])
                .unwrap();
            assert!(
                by_force.problem().state() == by_shift.problem().state(),
                "{alternation:?} (inexact contact solves: {inexact}), bracket {bracket:e}: the force-controlled increment at \
                 D₁ = {d:e} is not the displacement-controlled one"
            );
        }
    }
}
