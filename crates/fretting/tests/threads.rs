//! `FrettingSimulation::run` on grids whose FFT plans split (`2N − 1` padded to
//! `halfspace_numerics::conv1d::SPLIT_FROM` or more): each step runs on a pool worker with a
//! polling partner and the split FFTs' halves joined on two threads (docs/performance.md, "Two
//! threads in the MDR wear run"). The final state must be the same bit for bit on a pool of one
//! thread, on a pool of two, and called from a thread outside any pool (the global pool: the step
//! handed to a worker, the partner polling).

use halfspace_fretting::{FrettingParams, FrettingSimulation, FrettingState};
use halfspace_numerics::conv1d::{plan_length, SPLIT_FROM};

/// The smallest grid whose plans split: `2N − 1 = 8193` pads to `P ≥ SPLIT_FROM`.
const NODES: usize = 4097;

fn params() -> FrettingParams {
    FrettingParams {
        nodes: NODES,
        tau_end: TAU_END,
        snapshots: vec![TAU_END],
        ..FrettingParams::default()
    }
}

/// 18 adaptive steps (the first is 1e-4, growing): the step loop, the controller and a
/// snapshot; the three runs take 0.26 s (the test profile is optimized).
const TAU_END: f64 = 0.02;

fn run() -> FrettingState {
    let mut sim = FrettingSimulation::new(params()).unwrap();
    sim.run(|_| false).unwrap();
    sim.state().clone()
}

/// Every number of the state, as bits (the `f64`s by `to_bits`).
fn bits(state: &FrettingState) -> Vec<u64> {
    let mut out = vec![
        state.step,
        state.tau.to_bits(),
        state.next_step.to_bits(),
        state.previous_error.to_bits(),
        state.rejected_steps,
    ];
    let floats = |out: &mut Vec<u64>, v: &[f64]| {
        out.push(v.len() as u64);
        out.extend(v.iter().map(|x| x.to_bits()));
    };
    floats(&mut out, &state.profile);
    floats(&mut out, &state.tau_history);
    floats(&mut out, &state.contact_radius_history);
    floats(&mut out, &state.loaded_radius_history);
    out.push(state.snapshots.len() as u64);
    for s in &state.snapshots {
        out.extend([
            s.step,
            s.tau.to_bits(),
            s.contact_radius.to_bits(),
            s.loaded_radius.to_bits(),
        ]);
        floats(&mut out, &s.profile);
        floats(&mut out, &s.pressure);
        floats(&mut out, &s.slip);
    }
    out
}

#[test]
fn split_plan_runs_give_the_same_bits_on_one_and_two_threads() {
    assert!(
        plan_length(2 * NODES - 1) >= SPLIT_FROM,
        "the plans must split"
    );
    let in_pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(run)
    };
    let one = in_pool(1);
    println!(
        "{} steps ({} rejected) to τ = {TAU_END}",
        one.step, one.rejected_steps
    );
    assert!(one.step >= 3, "{} steps", one.step);
    assert_eq!(one.tau, TAU_END);
    let want = bits(&one);
    let two = in_pool(2);
    assert!(bits(&two) == want, "a pool of two threads changed the bits");
    // From a thread outside any pool: `run` hands each step to a worker of the global pool (two
    // or more threads unless RAYON_NUM_THREADS says otherwise) with a polling partner.
    let outside = std::thread::spawn(run).join().unwrap();
    assert!(bits(&outside) == want, "the global pool changed the bits");
}
