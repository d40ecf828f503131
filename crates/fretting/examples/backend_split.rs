//! Where adaptive FFT and MVM runs part (docs/fretting-wear.md, "The contact set within a step"):
//! both runs' attempts through the attempt observer, compared attempt by attempt; prints the first
//! attempt whose discrete outcome (accepted, edges, entered nodes) differs, the largest relative
//! difference of the steps before it, and the attempts around it.
//!
//! `cargo run --release -p halfspace-fretting --example backend_split -- N K CHI [TAU_END] [FROZEN]`

use std::sync::{Arc, Mutex};

use halfspace_fretting::{FrettingParams, FrettingSimulation, StepAttempt, TimeStepping};
use halfspace_numerics::Backend;

/// A run's attempts, final profile and steps.
type Traced = (Vec<StepAttempt>, Vec<f64>, u64);

fn trace(params: FrettingParams, frozen: bool) -> Result<Traced, Box<dyn std::error::Error>> {
    let attempts: Arc<Mutex<Vec<StepAttempt>>> = Arc::default();
    let mut sim = FrettingSimulation::new(params)?;
    sim.set_frozen_contact_stages(frozen);
    let sink = Arc::clone(&attempts);
    sim.set_attempt_observer(Box::new(move |a| sink.lock().expect("lock").push(*a)));
    sim.run(|_| false)?;
    let out = attempts.lock().expect("lock").clone();
    Ok((out, sim.state().profile.clone(), sim.state().step))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().is_some_and(|a| a == "ref") {
        return reference(&args[1..]);
    }
    let get = |i: usize, default: &str| args.get(i).cloned().unwrap_or_else(|| default.into());
    let nodes: usize = get(0, "401").parse()?;
    let k: f64 = get(1, "0").parse()?;
    let chi: f64 = get(2, "0.5").parse()?;
    let tau_end: f64 = get(3, "1").parse()?;
    let frozen: bool = get(4, "true").parse()?;
    let base = FrettingParams {
        nodes,
        k,
        chi,
        length: FrettingParams::default_length(chi, k),
        tau_end,
        snapshots: vec![0.5 * tau_end],
        stepping: TimeStepping::Adaptive { tolerance: 1e-4 },
        ..FrettingParams::default()
    };
    let (fft, pf, sf) = trace(
        FrettingParams {
            backend: Backend::Fft,
            ..base.clone()
        },
        frozen,
    )?;
    let (mvm, pm, sm) = trace(
        FrettingParams {
            backend: Backend::Mvm,
            ..base
        },
        frozen,
    )?;
    let diff = pf
        .iter()
        .zip(&pm)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!(
        "steps {sf} vs {sm}, attempts {} vs {}, max |f_fft − f_mvm| = {diff:.3e}",
        fft.len(),
        mvm.len()
    );
    let discrete = |a: &StepAttempt| {
        (
            a.accepted,
            a.edge_start,
            a.edge_trial,
            a.edge_end,
            a.entered_nodes,
            a.trial_outermost,
        )
    };
    let mut worst: f64 = 0.0;
    let mut krylov_reported = false;
    let mut thresholds = vec![1e-12, 1e-9, 1e-6, 1e-3];
    for (i, (a, b)) in fft.iter().zip(&mvm).enumerate() {
        let rel = (a.dtau - b.dtau).abs() / a.dtau;
        let dr = (a.error_ratio - b.error_ratio).abs();
        if !krylov_reported && a.krylov_iterations != b.krylov_iterations {
            krylov_reported = true;
            println!("first GMRES count difference at attempt {i} (τ = {:.6}): {:?} vs {:?}, rel Δτ diff {rel:.2e}, ratio diff {dr:.2e}", a.tau, a.krylov_iterations, b.krylov_iterations);
        }
        while thresholds.first().is_some_and(|&t| rel.max(dr) > t) {
            println!("  attempt {i} (τ = {:.6}): rel Δτ diff {rel:.2e}, ratio diff {dr:.2e} > {:.0e}; GMRES {:?} vs {:?}", a.tau, thresholds[0], a.krylov_iterations, b.krylov_iterations);
            thresholds.remove(0);
        }
        if discrete(a) != discrete(b) {
            println!("first discrete difference at attempt {i} (τ = {:.6}); max rel. Δτ difference before: {worst:.2e}", a.tau);
            for j in i.saturating_sub(2)..(i + 3).min(fft.len()).min(mvm.len()) {
                println!("  fft {j}: {:?}", fft[j]);
                println!("  mvm {j}: {:?}", mvm[j]);
            }
            return Ok(());
        }
        worst = worst
            .max((a.dtau - b.dtau).abs() / a.dtau)
            .max((a.error_ratio - b.error_ratio).abs());
    }
    println!("no discrete difference; max rel. Δτ / ratio difference {worst:.2e}");
    Ok(())
}

/// `backend_split ref N K CHI TAU_END`: the tol-1e-4 FFT and MVM runs against tight-tolerance
/// references (FFT, tol 1e-6 and 1e-7), at every snapshot.
fn reference(args: &[String]) -> Result<(), Box<dyn std::error::Error>> {
    let nodes: usize = args[0].parse()?;
    let k: f64 = args[1].parse()?;
    let chi: f64 = args[2].parse()?;
    let tau_end: f64 = args[3].parse()?;
    let base = FrettingParams {
        nodes,
        k,
        chi,
        length: FrettingParams::default_length(chi, k),
        tau_end,
        snapshots: vec![0.5 * tau_end, tau_end],
        ..FrettingParams::default()
    };
    let go = |backend: Backend,
              tolerance: f64|
     -> Result<FrettingSimulation, Box<dyn std::error::Error>> {
        let mut sim = FrettingSimulation::new(FrettingParams {
            backend,
            stepping: TimeStepping::Adaptive { tolerance },
            ..base.clone()
        })?;
        sim.run(|_| false)?;
        Ok(sim)
    };
    let refs = [go(Backend::Fft, 1e-6)?, go(Backend::Fft, 1e-7)?];
    let runs = [
        ("fft 1e-4", go(Backend::Fft, 1e-4)?),
        ("mvm 1e-4", go(Backend::Mvm, 1e-4)?),
        ("fft 1e-5", go(Backend::Fft, 1e-5)?),
        ("fft 1e-6", go(Backend::Fft, 1e-6)?),
    ];
    let r_star = refs[1].limit_contact_radius();
    let cell = refs[1].grid().step() / (2.0 * r_star);
    for (name, sim) in &runs {
        for (s, r) in sim.state().snapshots.iter().zip(&refs[1].state().snapshots) {
            let df = s
                .profile
                .iter()
                .zip(&r.profile)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            println!(
                "{name}: steps {}, τ = {}: |f − f_ref(1e-7)| = {df:.3e}, a/a0 − ref {:+.2} cells",
                sim.state().step,
                s.tau,
                (s.contact_radius - r.contact_radius) / cell
            );
        }
    }
    let (a, b) = (&refs[0].state().snapshots, &refs[1].state().snapshots);
    for (s, r) in a.iter().zip(b) {
        let df = s
            .profile
            .iter()
            .zip(&r.profile)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        println!(
            "ref 1e-6 vs 1e-7 τ = {}: {df:.3e}, {:+.2} cells; steps {} / {}",
            s.tau,
            (s.contact_radius - r.contact_radius) / cell,
            refs[0].state().step,
            refs[1].state().step
        );
    }
    Ok(())
}
