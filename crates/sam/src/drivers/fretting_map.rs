//! Fretting maps (Vingsbo & Söderberg 1988): the fretting loop over a grid of normal loads ×
//! shift amplitudes, the regime and the dissipated energy of each point.

use std::time::Instant;

use super::fretting_loop::{FrettingLoop, FrettingRegime, LoopCase};
use crate::contact::NestedParams;
use crate::SamError;

/// The points of a fretting map: the loop of `base` at every `(W_i, A_j)` of `loads × amplitudes`.
///
/// Every point keeps `base`'s physical set-up — the same cells (`base.grid²` over `base.extent()`),
/// the same inhomogeneities, normal steps and steps per quarter cycle `q` (so every loop has the
/// same increments) — and changes only `W` and `A` (shift step `A / q`). Size `base` for the
/// largest load (the drivers build it with `force = max W`) so that every contact stays inside
/// the domain; a smaller load has `a(W)/a(W_max) = (W/W_max)^{1/3}` as many cells per radius.
#[derive(Debug, Clone, PartialEq)]
pub struct FrettingMap {
    base: LoopCase,
    loads: Vec<f64>,
    amplitudes: Vec<f64>,
    quarter: usize,
}

/// One point of a map: the loop's [`LoopMetrics`](super::fretting_loop::LoopMetrics) that classify it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapPoint {
    /// Normal load W (N).
    pub load: f64,
    /// Shift amplitude A (m).
    pub amplitude: f64,
    /// The regime ([`FrettingRegime`]).
    pub regime: FrettingRegime,
    /// Dissipated energy per cycle `|∮ Q₁ dδx|` (J).
    pub dissipated_energy: f64,
    /// Fouvry's energy ratio `E_d / (4 Q* δ*)`.
    pub energy_ratio: f64,
    /// Shift travelled without a stick cell over `4A`.
    pub sliding_fraction: f64,
    /// `Q₁/μW` at `δx = +A` (first reach).
    pub tangential_force_over_mu_w_at_amplitude: f64,
    /// `Q₁/μW` at the end of the loop minus at its start, both at `δx = +A`.
    pub ratchet: f64,
    /// Wall-clock seconds of the loop (not part of the result's identity).
    pub seconds: f64,
    /// The crack risk: the larger of the Crossland and Dang Van maxima over the box below the
    /// contact in the closed cycle (both ≥ 1 predict crack initiation; docs/fatigue.md,
    /// "Crack–wear fretting maps"); `NaN` when the map evaluates no criteria.
    pub crack_risk: f64,
}

impl MapPoint {
    /// Names of [`MapPoint::values`], in order (the columns of the map's table).
    pub const FIELDS: [&'static str; 10] = [
        "load",
        "amplitude",
        "regime",
        "dissipated_energy",
        "energy_ratio",
        "sliding_fraction",
        "tangential_force_over_mu_w_at_amplitude",
        "ratchet",
        "seconds",
        "crack_risk",
    ];

    /// The point as numbers in the order of [`MapPoint::FIELDS`] (regime 0, 1, 2).
    pub fn values(&self) -> [f64; 10] {
        [
            self.load,
            self.amplitude,
            f64::from(self.regime as u8),
            self.dissipated_energy,
            self.energy_ratio,
            self.sliding_fraction,
            self.tangential_force_over_mu_w_at_amplitude,
            self.ratchet,
            self.seconds,
            self.crack_risk,
        ]
    }

    /// The inverse of [`MapPoint::values`]; `None` for a regime other than 0, 1, 2.
    pub fn from_values(v: [f64; 10]) -> Option<Self> {
        let regime = [
            FrettingRegime::PartialSlip,
            FrettingRegime::Mixed,
            FrettingRegime::GrossSlip,
        ]
        .into_iter()
        .find(|&r| f64::from(r as u8) == v[2])?;
        Some(Self {
            load: v[0],
            amplitude: v[1],
            regime,
            dissipated_energy: v[3],
            energy_ratio: v[4],
            sliding_fraction: v[5],
            tangential_force_over_mu_w_at_amplitude: v[6],
            ratchet: v[7],
            seconds: v[8],
            crack_risk: v[9],
        })
    }
}

impl FrettingMap {
    /// The map of `base` over `loads × amplitudes` (each finite, > 0, non-empty); `base` must be
    /// a valid case (its `force` sizes the domain: give the largest load).
    pub fn new(base: LoopCase, loads: Vec<f64>, amplitudes: Vec<f64>) -> Result<Self, SamError> {
        base.validate()?;
        for (what, values) in [("loads", &loads), ("amplitudes", &amplitudes)] {
            if values.is_empty() {
                return Err(SamError::InvalidInput(format!(
                    "a fretting map needs at least one of its {what}"
                )));
            }
            if let Some(v) = values.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
                return Err(SamError::InvalidInput(format!(
                    "fretting map {what}: every value must be finite and > 0, got {v}"
                )));
            }
        }
        Self::estimate_of(&base, loads.len() * amplitudes.len()).check("the fretting map")?;
        let quarter = base.path().quarter;
        Ok(Self {
            base,
            loads,
            amplitudes,
            quarter,
        })
    }

    /// The cost of the map ([`super::fretting_loop::LoopEstimate`]): `points` loops of `base`'s increments and
    /// cells, as many at once as there are threads, plus the points' results.
    pub fn estimate(&self) -> super::fretting_loop::LoopEstimate {
        Self::estimate_of(&self.base, self.len())
    }

    fn estimate_of(base: &LoopCase, points: usize) -> super::fretting_loop::LoopEstimate {
        let one = base.estimate();
        let loops = points as f64;
        let concurrent = loops.min(rayon::current_num_threads() as f64).max(1.0);
        super::fretting_loop::LoopEstimate {
            loops,
            concurrent,
            bytes: one.bytes * concurrent + loops * 2.0 * 10.0 * 8.0,
            work: one.work * loops,
            ..one
        }
    }

    /// The case every point derives from.
    pub fn base(&self) -> &LoopCase {
        &self.base
    }

    /// Normal loads W (N), the map's rows.
    pub fn loads(&self) -> &[f64] {
        &self.loads
    }

    /// Shift amplitudes A (m), the map's columns.
    pub fn amplitudes(&self) -> &[f64] {
        &self.amplitudes
    }

    /// `(rows, columns) = (loads, amplitudes)`.
    pub fn shape(&self) -> (usize, usize) {
        (self.loads.len(), self.amplitudes.len())
    }

    /// Points in the map.
    pub fn len(&self) -> usize {
        self.loads.len() * self.amplitudes.len()
    }

    /// Whether the map has no point (never, by construction).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The loop case of point `(i, j)`: `base` with `W = loads[i]`, `A = amplitudes[j]`, shift
    /// step `A / q`, and `extent_over_a = base.extent() / a(W)` (the same physical domain and
    /// cells); no subsurface fields; with `base.fatigue_depth`, the fatigue box scaled with the
    /// contact, `depth · a(W)/a(W_base)` (the same depth over `a` at every point).
    pub fn point_case(&self, i: usize, j: usize) -> Result<LoopCase, SamError> {
        let (Some(&load), Some(&amplitude)) = (self.loads.get(i), self.amplitudes.get(j)) else {
            return Err(SamError::InvalidInput(format!(
                "fretting map point ({i}, {j}) outside the {} × {} map",
                self.loads.len(),
                self.amplitudes.len()
            )));
        };
        let extent = self.base.extent();
        let base_radius = self.base.hertz_radius();
        let mut case = LoopCase {
            force: load,
            approach: None,
            amplitude,
            shift_step: amplitude / self.quarter as f64,
            subsurface_depth: None,
            fatigue_depth: None,
            ..self.base.clone()
        };
        case.extent_over_a = extent / case.hertz_radius();
        case.fatigue_depth = self
            .base
            .fatigue_depth
            .map(|d| d / base_radius * case.hertz_radius());
        case.validate()?;
        Ok(case)
    }

    /// Runs the loop of point `(i, j)` and classifies it.
    pub fn run_point(&self, i: usize, j: usize) -> Result<MapPoint, SamError> {
        self.run_point_until(i, j, &|| false)
    }

    /// [`FrettingMap::run_point`], asking `cancelled` after every increment: when it answers
    /// true the loop stops and [`SamError::Cancelled`] is returned (Ctrl-C in the front ends).
    pub fn run_point_until(
        &self,
        i: usize,
        j: usize,
        cancelled: &(dyn Fn() -> bool + Sync),
    ) -> Result<MapPoint, SamError> {
        self.run_point_with(i, j, cancelled, &|_| Ok(f64::NAN))
    }

    /// [`FrettingMap::run_point_until`] with the point's `crack_risk` from `risk` applied to the
    /// completed loop (the application layer evaluates the fatigue criteria on its stress
    /// history; `NaN` for none).
    pub fn run_point_with(
        &self,
        i: usize,
        j: usize,
        cancelled: &(dyn Fn() -> bool + Sync),
        risk: &(dyn Fn(&FrettingLoop) -> Result<f64, SamError> + Sync),
    ) -> Result<MapPoint, SamError> {
        let start = Instant::now();
        let case = self.point_case(i, j)?;
        let mut lp = FrettingLoop::new(case)?;
        let done = lp.run(|_| {
            if cancelled() {
                std::ops::ControlFlow::Break(())
            } else {
                std::ops::ControlFlow::Continue(())
            }
        })?;
        if !done {
            return Err(SamError::Cancelled);
        }
        let m = lp.metrics()?;
        let crack_risk = risk(&lp)?;
        Ok(MapPoint {
            load: self.loads[i],
            amplitude: self.amplitudes[j],
            regime: m.regime,
            dissipated_energy: m.dissipated_energy,
            energy_ratio: m.energy_ratio,
            sliding_fraction: m.sliding_fraction,
            tangential_force_over_mu_w_at_amplitude: m.tangential_force_over_mu_w_at_amplitude,
            ratchet: m.ratchet,
            seconds: start.elapsed().as_secs_f64(),
            crack_risk,
        })
    }

    /// The configuration of point `(i, j)` as text, the EIM change factor the one its loop uses
    /// ([`LoopCase::as_run`] with the parameters of [`FrettingLoop::new`]); a checkpointed point
    /// is reused only when [`FrettingMap::accepts_point_fingerprint`].
    pub fn point_fingerprint(&self, i: usize, j: usize) -> Result<String, SamError> {
        let case = self.point_case(i, j)?;
        Ok(format!(
            "{:?}{}{}",
            case.as_run(NestedParams::default()),
            case.window_fingerprint()?,
            case.stopping_fingerprint(NestedParams::default())
        ))
    }

    /// Whether a checkpointed point's fingerprint `recorded` belongs to point `(i, j)` of this
    /// map, `suffix` being what the caller appended to [`FrettingMap::point_fingerprint`] (the
    /// fatigue constants): equal to the current fingerprint, or — a point written before the
    /// fingerprint held the factor used (the case as given, `eim_change_factor: None`) — equal
    /// to that while the run uses the factor those points were computed with
    /// ([`LoopCase::check_fingerprint`]).
    pub fn accepts_point_fingerprint(
        &self,
        i: usize,
        j: usize,
        recorded: &str,
        suffix: &str,
    ) -> Result<bool, SamError> {
        let case = self.point_case(i, j)?;
        let window = format!(
            "{}{}",
            case.window_fingerprint()?,
            case.stopping_fingerprint(NestedParams::default())
        );
        let current = format!("{:?}{window}{suffix}", case.as_run(NestedParams::default()));
        let given = format!("{case:?}{window}{suffix}");
        Ok(case
            .check_fingerprint(NestedParams::default(), recorded, &current, &given)
            .is_ok())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> LoopCase {
        LoopCase {
            grid: 16,
            normal_steps: 2,
            shift_step: 0.02e-6,
            ..LoopCase::default()
        }
    }

    #[test]
    fn points_keep_the_cells_and_the_increments() {
        let map = FrettingMap::new(small(), vec![0.04, 0.08], vec![0.02e-6, 0.06e-6]).unwrap();
        let base = map.base();
        for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            let c = map.point_case(i, j).unwrap();
            approx::assert_relative_eq!(c.extent(), base.extent(), max_relative = 1e-14);
            assert_eq!(c.path().len(), base.path().len());
            assert_eq!(c.grid, base.grid);
        }
        // W = 0.08 N is the base: its case is the base's (up to the amplitude).
        let c = map.point_case(1, 0).unwrap();
        approx::assert_relative_eq!(c.extent_over_a, base.extent_over_a, max_relative = 1e-14);
        assert!(map.point_case(2, 0).is_err());
    }

    /// A point's fingerprint holds the EIM change factor its loop uses; a point written with the
    /// case as given (`None`) is reused only while that factor is the one those points had.
    #[test]
    fn point_fingerprints_hold_the_factor_used() {
        use crate::contact::inhomogeneous::DEFAULT_EIM_CHANGE_FACTOR;
        use crate::eim::{Inhomogeneity, Shape};
        let mut base = small();
        let a = base.hertz_radius();
        base.inhomogeneities.push(Inhomogeneity {
            shape: Shape::Sphere {
                x: 0.0,
                y: 0.0,
                z: 0.6 * a,
                r: 0.4 * a,
            },
            e: 420e9,
            nu: 0.3,
        });
        let map = FrettingMap::new(base.clone(), vec![0.08], vec![0.02e-6]).unwrap();
        let current = map.point_fingerprint(0, 0).unwrap();
        assert!(current.contains(&format!(
            "eim_change_factor: Some({DEFAULT_EIM_CHANGE_FACTOR:?})"
        )));
        let given = format!("{:?}", map.point_case(0, 0).unwrap());
        assert!(given.contains("eim_change_factor: None"));
        for suffix in ["", "Some(FatigueConfig)"] {
            let accepts = |recorded: String| {
                map.accepts_point_fingerprint(0, 0, &recorded, suffix)
                    .unwrap()
            };
            assert!(accepts(format!("{current}{suffix}")));
            // The old spelling: reused while the default is the factor it was computed with.
            assert_eq!(
                accepts(format!("{given}{suffix}")),
                DEFAULT_EIM_CHANGE_FACTOR
                    == crate::drivers::fretting_loop::UNRECORDED_EIM_CHANGE_FACTOR
            );
            assert!(!accepts(format!("{given}{suffix}x")));
        }
        // Another factor given: the old spelling of the default is refused.
        let other = FrettingMap::new(
            LoopCase {
                eim_change_factor: Some(1e-3),
                ..base
            },
            vec![0.08],
            vec![0.02e-6],
        )
        .unwrap();
        assert!(!other.accepts_point_fingerprint(0, 0, &given, "").unwrap());
        let other_current = other.point_fingerprint(0, 0).unwrap();
        assert!(other
            .accepts_point_fingerprint(0, 0, &other_current, "")
            .unwrap());
    }

    #[test]
    fn bad_axes_are_refused() {
        for (loads, amps) in [
            (vec![], vec![1e-8]),
            (vec![0.08], vec![]),
            (vec![0.08, -1.0], vec![1e-8]),
            (vec![0.08], vec![f64::NAN]),
        ] {
            let e = FrettingMap::new(small(), loads, amps).unwrap_err();
            assert!(e.to_string().contains("fretting map"), "{e}");
        }
    }

    #[test]
    fn values_round_trip() {
        let p = MapPoint {
            load: 0.08,
            amplitude: 4e-8,
            regime: FrettingRegime::Mixed,
            dissipated_energy: 1.5e-9,
            energy_ratio: 0.3,
            sliding_fraction: 0.01,
            tangential_force_over_mu_w_at_amplitude: 0.99,
            ratchet: 0.001,
            seconds: 2.0,
            crack_risk: 0.7,
        };
        assert_eq!(MapPoint::from_values(p.values()), Some(p));
        let mut v = p.values();
        v[2] = 3.0;
        assert_eq!(MapPoint::from_values(v), None);
    }

    #[test]
    fn the_regime_follows_the_amplitude() {
        // Mindlin: gross slip once A exceeds δ_s = 3μW/(2k) ≈ 0.031 μm at 80 mN (issue 11 note);
        // well below it partial slip.
        let map = FrettingMap::new(small(), vec![0.08], vec![0.01e-6, 0.08e-6]).unwrap();
        let low = map.run_point(0, 0).unwrap();
        let high = map.run_point(0, 1).unwrap();
        assert_eq!(low.regime, FrettingRegime::PartialSlip);
        assert_eq!(high.regime, FrettingRegime::GrossSlip);
        assert!(high.dissipated_energy > low.dissipated_energy);
        assert!(low.energy_ratio < 0.2 && high.energy_ratio > 0.2);
    }
}
