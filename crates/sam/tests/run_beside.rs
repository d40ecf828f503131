//! A fretting loop run beside other work (`FrettingLoop::run_beside`, the composite command's
//! homogeneous reference): on its own one-thread pool it is the plain loop bit for bit, and it is
//! dropped when the work beside it is not kept.

use std::ops::ControlFlow;

use halfspace_sam::drivers::fretting_loop::{FrettingLoop, LoopCase};

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn a_loop_run_beside_is_the_plain_loop_bit_for_bit() {
    let case = LoopCase {
        grid: 32,
        ..LoopCase::default()
    };
    let mut plain = FrettingLoop::new(case.clone()).unwrap();
    assert!(plain.run(|_| ControlFlow::Continue(())).unwrap());
    // The work beside it: the same loop on the global pool.
    let (main, beside) = FrettingLoop::run_beside(
        case.clone(),
        || {
            let mut lp = FrettingLoop::new(case.clone()).unwrap();
            lp.run(|_| ControlFlow::Continue(())).unwrap();
            lp
        },
        |_| true,
    );
    let beside = beside.expect("kept").unwrap();
    for lp in [&main, &beside] {
        assert_eq!(lp.rows().len(), plain.rows().len());
        for (a, b) in lp.rows().iter().zip(plain.rows()) {
            assert_eq!(bits(&a.values()), bits(&b.values()));
        }
        let (s, t) = (
            lp.solver().problem().state(),
            plain.solver().problem().state(),
        );
        assert_eq!(bits(&s.pressure), bits(&t.pressure));
        assert_eq!(bits(&s.shear[0]), bits(&t.shear[0]));
        assert_eq!(bits(&s.shear[1]), bits(&t.shear[1]));
    }
}

#[test]
fn a_loop_beside_work_that_is_not_kept_is_dropped() {
    let case = LoopCase {
        grid: 32,
        ..LoopCase::default()
    };
    let (main, beside) = FrettingLoop::run_beside(case, || 7, |&x| x != 7);
    assert_eq!(main, 7);
    assert!(beside.is_none());
}

#[test]
fn an_invalid_loop_beside_reports_its_error() {
    let case = LoopCase {
        grid: 32,
        radius: -1.0,
        ..LoopCase::default()
    };
    let (_, beside) = FrettingLoop::run_beside(case, || (), |_| true);
    assert!(beside.expect("kept").is_err());
}

/// A panic of the work beside the loop reaches the caller (the loop is cancelled at its next
/// increment and joined first).
#[test]
fn a_panic_beside_the_loop_reaches_the_caller() {
    let case = LoopCase {
        grid: 32,
        ..LoopCase::default()
    };
    let result = std::panic::catch_unwind(|| {
        FrettingLoop::run_beside(case, || panic!("the work beside failed"), |_: &()| true)
    });
    assert!(result.is_err());
}
