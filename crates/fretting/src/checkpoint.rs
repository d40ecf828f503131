//! The content of a saved [`FrettingState`] checked against the run it is to continue, before a
//! resume uses it: the checksum of a file says it was written whole, not that it makes sense.
//! Members are named as `fretting-wear` stores them in `checkpoint.npz` (`profile`,
//! `contact_radius_history`, `snapshot{k}_profile`, …).

use halfspace_numerics::SquaredGrid;

use crate::{FrettingError, FrettingParams, FrettingState};

/// Checks `state` for a run of `params` on `grid` whose contact radius tends to `r_star`:
/// * shapes: the profile and every snapshot's profile, pressure and slip have `N` nodes; one
///   history entry per step done; no more steps than the run has;
/// * values: everything finite; the contact radius `a/a₀` of the history and of the snapshots in
///   `(0, r* + 3 cells]` (the run stops as unstable beyond: `FrettingError::Unstable`); the
///   history non-decreasing to within one cell (the worn contact only grows, Willert 2021
///   Section 4; docs/fretting-wear.md); pressures ≥ 0 up to rounding;
/// * snapshots at distinct steps of the run's snapshot steps, in order, none after the state.
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
    let total = params.total_steps();
    if state.step > total {
        return Err(bad(
            "step",
            format!("{} steps done, the run has {total}", state.step),
        ));
    }
    let nodes = |member: &str, v: &[f64]| -> Result<(), FrettingError> {
        if v.len() != n {
            return Err(bad(
                member,
                format!("{} values, the run has N = {n} nodes", v.len()),
            ));
        }
        if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(bad(member, format!("value [{i}] = {x} is not finite")));
        }
        Ok(())
    };
    nodes("profile", &state.profile)?;
    let history = &state.contact_radius_history;
    if history.len() as u64 != state.step {
        return Err(bad(
            "contact_radius_history",
            format!(
                "{} entries for {} steps done (one per step)",
                history.len(),
                state.step
            ),
        ));
    }
    let cell = grid.step() / (2.0 * r_star);
    let largest = r_star + 3.0 * cell;
    let radius_ok = |a: f64| a.is_finite() && a > 0.0 && a <= largest;
    if let Some((i, a)) = history.iter().enumerate().find(|(_, a)| !radius_ok(**a)) {
        return Err(bad(
            "contact_radius_history",
            format!("value [{i}] = {a}: a/a0 must be finite and in (0, {largest:.4}] (r*/a0 = {r_star:.4} and 3 cells)"),
        ));
    }
    if let Some(i) = (1..history.len()).find(|&i| history[i] < history[i - 1] - 2.0 * cell) {
        return Err(bad(
            "contact_radius_history",
            format!(
                "value [{i}] = {} after {}: the worn contact only grows",
                history[i],
                history[i - 1]
            ),
        ));
    }
    let steps = params.snapshot_steps();
    let mut previous = None;
    for (k, s) in state.snapshots.iter().enumerate() {
        let member = |name: &str| format!("snapshot{k}_{name}");
        if s.step > state.step || steps.binary_search(&s.step).is_err() {
            return Err(bad(
                &member("step"),
                format!(
                    "step {} is not one of the run's snapshot steps up to step {}",
                    s.step, state.step
                ),
            ));
        }
        if previous.is_some_and(|p| s.step <= p) {
            return Err(bad(
                &member("step"),
                format!("step {} is not after the previous snapshot's", s.step),
            ));
        }
        previous = Some(s.step);
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
        if !radius_ok(s.contact_radius) {
            return Err(bad(
                &member("contact_radius"),
                format!(
                    "{}: a/a0 must be finite and in (0, {largest:.4}]",
                    s.contact_radius
                ),
            ));
        }
    }
    Ok(())
}
