//! The content of a saved [`FrettingState`] checked against the run it is to continue, before a
//! resume uses it: the checksum of a file says it was written whole, not that it makes sense.
//! Members are named as `fretting-wear` stores them in `checkpoint.npz` (`profile`, `tau`,
//! `tau_history`, `contact_radius_history`, `loaded_radius_history`, `next_step`,
//! `previous_error`, `snapshot{k}_profile`, …).

use halfspace_numerics::SquaredGrid;

use crate::{FrettingError, FrettingParams, FrettingState, TimeStepping};

/// Checks `state` for a run of `params` on `grid` whose contact radius tends to `r_star`
/// (docs/fretting-wear.md, "Output, checkpoints and resume"):
/// * shapes: the profile and every snapshot's profile, pressure and slip have `N` nodes; one entry
///   per step done in each of `tau_history`, `contact_radius_history`, `loaded_radius_history`;
///   with a fixed step no more steps than the run has;
/// * time: `τ` finite in `[0, τ_end]`; `tau_history` strictly increasing in `(0, τ]` and ending at
///   `τ` (`τ = 0` before the first step); with a fixed step entry `i` is exactly the `τ` of step
///   `i + 1` ([`FrettingParams::fixed_tau`]);
/// * radii: everything finite; the contact radius `a/a₀` (the touching region) in `(0, L]` and
///   never below the unworn contact `a₀` by more than two cells `h/(2r*)` (wear only widens the
///   contact, Willert 2021 Section 4; the discrete touching radius is not monotone: near grazing it
///   falls by up to 3.3 cells from one step to the next, docs/fretting-wear.md, "Output,
///   checkpoints and resume", so no step-to-step rule is checked); the loaded radius in `[0, L]` (it
///   falls back to the stick radius at the limit, so it is not monotone). Both are at most `L` by
///   construction: they are interpolated on the grid;
/// * the step controller: the next step finite and ≥ 0 (0 before the first adaptive step and with
///   a fixed step), the last error ratio finite in `[0, 1]` (it is that of an accepted step);
/// * snapshots at distinct, increasing `τ` among the run's snapshot times, none after the state,
///   each at `τ` of its step (`tau_history[step − 1]`, or 0 at step 0); pressures ≥ 0 up to
///   rounding.
///
/// The error names the member and the rule it breaks.
pub(crate) fn check_state(
    state: &FrettingState,
    params: &FrettingParams,
    grid: &SquaredGrid,
    r_star: f64,
) -> Result<(), FrettingError> {
    let bad =
        |member: &str, rule: String| FrettingError::Checkpoint(format!("member {member}: {rule}"));
    let n = params.nodes;
    if let Some(total) = params.total_steps() {
        if state.step > total {
            return Err(bad(
                "step",
                format!("{} steps done, the run has {total}", state.step),
            ));
        }
    }
    let finite = |member: &str, v: &[f64]| -> Result<(), FrettingError> {
        match v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            Some((i, x)) => Err(bad(member, format!("value [{i}] = {x} is not finite"))),
            None => Ok(()),
        }
    };
    let nodes = |member: &str, v: &[f64]| -> Result<(), FrettingError> {
        if v.len() != n {
            return Err(bad(
                member,
                format!("{} values, the run has N = {n} nodes", v.len()),
            ));
        }
        finite(member, v)
    };
    nodes("profile", &state.profile)?;
    for (member, history) in [
        ("tau_history", &state.tau_history),
        ("contact_radius_history", &state.contact_radius_history),
        ("loaded_radius_history", &state.loaded_radius_history),
    ] {
        if history.len() as u64 != state.step {
            return Err(bad(
                member,
                format!(
                    "{} entries for {} steps done (one per step)",
                    history.len(),
                    state.step
                ),
            ));
        }
        finite(member, history)?;
    }

    // Time.
    let end = params.fixed_end();
    if !(state.tau.is_finite() && (0.0..=end).contains(&state.tau)) {
        return Err(bad(
            "tau",
            format!("{} is not in [0, {end}] (tau_end)", state.tau),
        ));
    }
    let taus = &state.tau_history;
    if taus.last().copied().unwrap_or(0.0) != state.tau {
        return Err(bad(
            "tau_history",
            format!(
                "ends at {:?}, the state is at tau = {} (the last step's tau)",
                taus.last(),
                state.tau
            ),
        ));
    }
    if let Some(&first) = taus.first() {
        if first <= 0.0 {
            return Err(bad(
                "tau_history",
                format!("value [0] = {first}: tau after a step is > 0"),
            ));
        }
    }
    if let Some(i) = (1..taus.len()).find(|&i| taus[i] <= taus[i - 1]) {
        return Err(bad(
            "tau_history",
            format!(
                "value [{i}] = {} after {}: tau increases with every step",
                taus[i],
                taus[i - 1]
            ),
        ));
    }
    if params.stepping.fixed_step().is_some() {
        let off = taus
            .iter()
            .enumerate()
            .find(|&(i, t)| params.fixed_tau(i as u64 + 1) != Some(*t));
        if let Some((i, t)) = off {
            return Err(bad(
                "tau_history",
                format!(
                    "value [{i}] = {t}: with a fixed step step {} ends at tau = {:?}",
                    i + 1,
                    params.fixed_tau(i as u64 + 1)
                ),
            ));
        }
    }

    // Radii.
    let length = grid.length() * (1.0 + 1e-12);
    let cell = grid.step() / (2.0 * r_star);
    let history = &state.contact_radius_history;
    if let Some((i, a)) = history
        .iter()
        .enumerate()
        .find(|(_, a)| !(**a > 0.0 && **a <= length))
    {
        return Err(bad(
            "contact_radius_history",
            format!("value [{i}] = {a}: a/a0 must be in (0, {length:.4}] (L/a0)"),
        ));
    }
    if let Some((i, a)) = history
        .iter()
        .enumerate()
        .find(|(_, a)| **a < 1.0 - 2.0 * cell)
    {
        return Err(bad(
            "contact_radius_history",
            format!(
                "value [{i}] = {a}: the worn contact is never smaller than the unworn one \
                 (a/a0 >= 1 - 2 cells = {:.4})",
                1.0 - 2.0 * cell
            ),
        ));
    }
    let loaded_ok = |a: f64| (0.0..=length).contains(&a);
    if let Some((i, a)) = state
        .loaded_radius_history
        .iter()
        .enumerate()
        .find(|(_, a)| !loaded_ok(**a))
    {
        return Err(bad(
            "loaded_radius_history",
            format!("value [{i}] = {a}: a_p/a0 must be in [0, {length:.4}] (L/a0)"),
        ));
    }

    // The step controller's memory.
    if !(state.next_step.is_finite() && state.next_step >= 0.0) {
        return Err(bad(
            "next_step",
            format!("{}: a step must be finite and ≥ 0", state.next_step),
        ));
    }
    if !(0.0..=1.0).contains(&state.previous_error) {
        return Err(bad(
            "previous_error",
            format!(
                "{}: the error ratio of an accepted step is in [0, 1]",
                state.previous_error
            ),
        ));
    }
    if matches!(params.stepping, TimeStepping::Adaptive { .. })
        && state.step > 0
        && !(state.next_step > 0.0 && state.previous_error > 0.0)
    {
        return Err(bad(
            "next_step",
            format!(
                "{} (previous_error {}): after an adaptive step both are > 0",
                state.next_step, state.previous_error
            ),
        ));
    }

    // Snapshots.
    let times = params.snapshot_times();
    let mut previous: Option<f64> = None;
    for (k, s) in state.snapshots.iter().enumerate() {
        let member = |name: &str| format!("snapshot{k}_{name}");
        if s.step > state.step {
            return Err(bad(
                &member("step"),
                format!("step {} is after the state's step {}", s.step, state.step),
            ));
        }
        if !times.contains(&s.tau) {
            return Err(bad(
                &member("tau"),
                format!(
                    "tau {} (step {}) is not one of the run's snapshot times {times:?} up to step {}",
                    s.tau, s.step, state.step
                ),
            ));
        }
        let tau_of_step = match s.step {
            0 => 0.0,
            step => taus[step as usize - 1],
        };
        if s.tau != tau_of_step {
            return Err(bad(
                &member("step"),
                format!(
                    "step {} ends at tau = {tau_of_step}, the snapshot is at tau = {}",
                    s.step, s.tau
                ),
            ));
        }
        if previous.is_some_and(|p| s.tau <= p) {
            return Err(bad(
                &member("tau"),
                format!("{} is not after the previous snapshot's", s.tau),
            ));
        }
        previous = Some(s.tau);
        nodes(&member("profile"), &s.profile)?;
        nodes(&member("pressure"), &s.pressure)?;
        nodes(&member("slip"), &s.slip)?;
        let scale = s.pressure.iter().fold(0.0f64, |m, p| m.max(p.abs()));
        if let Some((i, p)) = s
            .pressure
            .iter()
            .enumerate()
            .find(|(_, p)| **p < -1e-6 * scale.max(1.0))
        {
            return Err(bad(
                &member("pressure"),
                format!("value [{i}] = {p}: a contact pressure is ≥ 0"),
            ));
        }
        if !(s.contact_radius > 0.0 && s.contact_radius <= length) {
            return Err(bad(
                &member("contact_radius"),
                format!(
                    "{}: a/a0 must be finite and in (0, {length:.4}] (L/a0)",
                    s.contact_radius
                ),
            ));
        }
        if !loaded_ok(s.loaded_radius) {
            return Err(bad(
                &member("loaded_radius"),
                format!(
                    "{}: a_p/a0 must be finite and in [0, {length:.4}] (L/a0)",
                    s.loaded_radius
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::{FrettingParams, FrettingSimulation, FrettingState, TimeStepping};

    /// A state of an adaptive run after a few steps, and its parameters.
    fn adaptive_state() -> (FrettingParams, FrettingState) {
        let params = FrettingParams {
            nodes: 201,
            stepping: TimeStepping::Adaptive { tolerance: 1e-3 },
            tau_end: 0.4,
            snapshots: vec![0.001, 0.1],
            ..FrettingParams::default()
        };
        let mut sim = FrettingSimulation::new(params.clone()).unwrap();
        let mut steps = 0;
        sim.run(|_| {
            steps += 1;
            steps == 5
        })
        .unwrap();
        (params, sim.state().clone())
    }

    /// The state as the run left it resumes; each tampered member is refused by name.
    #[test]
    fn tampered_adaptive_states_are_refused_by_member() {
        let (params, state) = adaptive_state();
        assert_eq!(state.step, 5);
        assert!(!state.snapshots.is_empty());
        FrettingSimulation::resume(params.clone(), state.clone()).unwrap();
        type Edit = fn(&mut FrettingState);
        let cases: Vec<(&str, Edit)> = vec![
            ("member next_step", |s| s.next_step = f64::NAN),
            ("member next_step", |s| s.next_step = f64::INFINITY),
            ("member next_step", |s| s.next_step = 0.0),
            ("member previous_error", |s| s.previous_error = f64::NAN),
            ("member previous_error", |s| s.previous_error = 1.5),
            ("member tau", |s| s.tau = f64::NAN),
            ("member tau", |s| s.tau = 1.0),
            ("member tau_history", |s| s.tau_history[2] = f64::NAN),
            ("member tau_history", |s| s.tau_history.swap(1, 2)),
            ("member tau_history", |s| s.tau_history[0] = 0.0),
            ("member loaded_radius_history", |s| {
                s.loaded_radius_history[1] = f64::NAN
            }),
            ("member loaded_radius_history", |s| {
                s.loaded_radius_history.pop();
            }),
            ("member contact_radius_history", |s| {
                s.contact_radius_history[3] = 9.0
            }),
            ("member snapshot0_loaded_radius", |s| {
                s.snapshots[0].loaded_radius = f64::NAN
            }),
            ("member snapshot0_tau", |s| s.snapshots[0].tau = 0.05),
        ];
        for (needle, edit) in cases {
            let mut tampered = state.clone();
            edit(&mut tampered);
            let err = FrettingSimulation::resume(params.clone(), tampered)
                .err()
                .unwrap_or_else(|| panic!("{needle}: accepted"))
                .to_string();
            assert!(err.contains(needle), "{needle}: {err}");
        }
    }
}
