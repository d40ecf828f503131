//! Helpers of the sam tests: the resume check of the long runs (the fretting loop's increments,
//! the wear run's wear steps) — a run snapshotted after some steps, as a killed run would have
//! checkpointed it, is resumed from the snapshot and must end bit for bit where the uninterrupted
//! run ends.
#![allow(dead_code)]

use std::ops::ControlFlow;

use halfspace_sam::drivers::fretting_loop::{FrettingLoop, LoopCase, LoopSnapshot};
use halfspace_sam::drivers::fretting_wear3d::{FrettingWear3d, WearCase, WearRow, WearSnapshot};
use halfspace_sam::eim::{Inhomogeneity, Shape};
use halfspace_sam::SamError;

/// A run of steps that snapshots and resumes from a snapshot.
pub trait Resumable: Sized {
    type Case: Clone;
    type Snapshot: Clone;
    /// A new run of `case`.
    fn start(case: Self::Case) -> Result<Self, SamError>;
    /// `case` continued from `snapshot`.
    fn resume_from(case: Self::Case, snapshot: Self::Snapshot) -> Result<Self, SamError>;
    /// Steps to the end, `observer` called after every step (`Break` stops early); whether the
    /// run is complete.
    fn run_observed(
        &mut self,
        observer: impl FnMut(&Self) -> ControlFlow<()>,
    ) -> Result<bool, SamError>;
    /// The state to continue from.
    fn take_snapshot(&self) -> Self::Snapshot;
    /// Asserts that this run ended bit for bit where `whole` ended.
    fn assert_same_end(&self, whole: &Self);
}

/// The bits of `v`.
pub fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

impl Resumable for FrettingLoop {
    type Case = LoopCase;
    type Snapshot = LoopSnapshot;
    fn start(case: LoopCase) -> Result<Self, SamError> {
        FrettingLoop::new(case)
    }
    fn resume_from(case: LoopCase, snapshot: LoopSnapshot) -> Result<Self, SamError> {
        FrettingLoop::resume(case, snapshot)
    }
    fn run_observed(
        &mut self,
        observer: impl FnMut(&Self) -> ControlFlow<()>,
    ) -> Result<bool, SamError> {
        self.run(observer)
    }
    fn take_snapshot(&self) -> LoopSnapshot {
        self.snapshot()
    }
    /// The final snapshot (contact state, warm starts, the cycle's sources) and every row.
    fn assert_same_end(&self, whole: &Self) {
        assert_eq!(self.snapshot(), whole.snapshot());
        assert_eq!(self.rows(), whole.rows());
    }
}

impl Resumable for FrettingWear3d {
    type Case = WearCase;
    type Snapshot = WearSnapshot;
    fn start(case: WearCase) -> Result<Self, SamError> {
        FrettingWear3d::new(case)
    }
    fn resume_from(case: WearCase, snapshot: WearSnapshot) -> Result<Self, SamError> {
        FrettingWear3d::resume(case, snapshot)
    }
    fn run_observed(
        &mut self,
        observer: impl FnMut(&Self) -> ControlFlow<()>,
    ) -> Result<bool, SamError> {
        self.run(observer)
    }
    fn take_snapshot(&self) -> WearSnapshot {
        self.snapshot()
    }
    /// The worn depth and every history row bit for bit, and the records.
    fn assert_same_end(&self, whole: &Self) {
        let rows = |r: &[WearRow]| r.iter().flat_map(|w| bits(&w.values())).collect::<Vec<_>>();
        assert_eq!(bits(self.wear_depth()), bits(whole.wear_depth()));
        assert_eq!(rows(self.history()), rows(whole.history()));
        assert_eq!(self.records(), whole.records());
    }
}

/// `case` run to its end.
pub fn run_to_end<R: Resumable>(case: &R::Case) -> R {
    let mut run = R::start(case.clone()).expect("plan");
    assert!(run
        .run_observed(|_| ControlFlow::Continue(()))
        .expect("run"));
    run
}

/// `case` run to its end with `observe` called after every step, and its snapshot after the
/// `steps`-th step (what a run stopped there would have checkpointed).
pub fn run_with_snapshot<R: Resumable>(
    case: &R::Case,
    steps: usize,
    mut observe: impl FnMut(&R),
) -> (R, R::Snapshot) {
    let mut run = R::start(case.clone()).expect("plan");
    let (mut done, mut snapshot) = (0, None);
    let complete = run
        .run_observed(|r| {
            observe(r);
            done += 1;
            if done == steps {
                snapshot = Some(r.take_snapshot());
            }
            ControlFlow::Continue(())
        })
        .expect("run");
    assert!(complete);
    let snapshot = snapshot.unwrap_or_else(|| panic!("the run ended before {steps} steps"));
    (run, snapshot)
}

/// `case` resumed from `snapshot` and run to its end.
pub fn resumed<R: Resumable>(case: &R::Case, snapshot: R::Snapshot) -> R {
    let mut run = R::resume_from(case.clone(), snapshot).expect("resume");
    assert!(run
        .run_observed(|_| ControlFlow::Continue(()))
        .expect("run"));
    run
}

/// `case` snapshotted after `steps` steps and resumed ends bit for bit where the uninterrupted
/// run ends ([`Resumable::assert_same_end`]); returns the uninterrupted run and the snapshot.
pub fn assert_resumes_bit_for_bit<R: Resumable>(case: &R::Case, steps: usize) -> (R, R::Snapshot) {
    let (whole, snapshot) = run_with_snapshot(case, steps, |_: &R| {});
    resumed::<R>(case, snapshot.clone()).assert_same_end(&whole);
    (whole, snapshot)
}

/// A small nested loop: one stiff sphere (E = 420 GPa, ν = 0.3, radius 0.4 a at depth 0.6 a) below
/// the contact, 16², two normal steps (the outer passes re-solve every increment).
pub fn stiff_sphere_loop() -> LoopCase {
    let mut case = LoopCase {
        grid: 16,
        normal_steps: 2,
        ..LoopCase::default()
    };
    let a = case.hertz_radius();
    case.inhomogeneities.push(Inhomogeneity {
        shape: Shape::Sphere {
            x: 0.0,
            y: 0.0,
            z: 0.6 * a,
            r: 0.4 * a,
        },
        e: 420e9,
        nu: 0.3,
    });
    case
}
