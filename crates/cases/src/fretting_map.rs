//! Fretting maps as a driver shared by the CLI (`halfspace fretting-map`) and Python
//! (`halfspace.fretting_map`): the points of a [`FrettingMap`] in parallel on the local cores,
//! each checkpointed when it completes so that a killed map resumes where it stopped, and the
//! results as a table (CSV) and a [`Record`] (HDF5). With a `[fatigue]` table each point adds its
//! crack risk (the fatigue criteria of its closed cycle, [`crate::loop_fatigue`]) and the map its
//! material response (no damage, cracking, wear, both; docs/fatigue.md, "Crack–wear fretting maps").

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use rayon::prelude::*;
use serde_json::json;

use crate::config::FatigueConfig;
use crate::data::{write_atomic, AttrValue, DataError, Record};
use crate::loop_fatigue::evaluate_loop_fatigue;
use crate::sam::drivers::fretting_map::{FrettingMap, MapPoint};
use crate::sam::SamError;

/// Why a map could not run or resume.
#[derive(Debug, thiserror::Error)]
pub enum MapError {
    /// A point's loop failed (the point is named).
    #[error("fretting map point W = {load} N, A = {amplitude} m: {source}")]
    Point {
        /// Its load (N).
        load: f64,
        /// Its amplitude (m).
        amplitude: f64,
        /// The loop's error.
        source: SamError,
    },
    /// The caller stopped the map (Ctrl-C); completed points keep their checkpoints.
    #[error("cancelled (interrupted)")]
    Cancelled,
    /// The map itself was refused.
    #[error(transparent)]
    Sam(#[from] SamError),
    /// Reading or writing a checkpoint failed.
    #[error(transparent)]
    Data(#[from] DataError),
    /// A checkpoint exists but belongs to another configuration, or cannot be read.
    #[error("{path}: {reason}")]
    Checkpoint {
        /// The checkpoint file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
}

/// Crack risk at or above which the material response counts cracking: a Crossland or Dang Van
/// index of 1 is the endurance limit (docs/fatigue.md, Eqs. F3–F4).
pub const CRACK_RISK_THRESHOLD: f64 = 1.0;

/// Fouvry's energy ratio `E_d/(4Q*δ*)` at or above which the material response counts wear: the
/// gross-slip transition `A_t = 0.2` of a sphere on a flat (Fouvry, Kapsa & Vincent 1996).
pub const WEAR_ENERGY_RATIO_THRESHOLD: f64 = 0.2;

/// The material response of a point (the classic fretting map of Vincent, Berthier & Godet 1992):
/// 0 no damage, 1 cracking (`crack_risk ≥` [`CRACK_RISK_THRESHOLD`]), 2 wear (`energy_ratio ≥`
/// [`WEAR_ENERGY_RATIO_THRESHOLD`]), 3 both; `NaN` without a crack risk.
pub fn material_response(p: &MapPoint) -> f64 {
    if p.crack_risk.is_nan() {
        return f64::NAN;
    }
    let crack = p.crack_risk >= CRACK_RISK_THRESHOLD;
    let wear = p.energy_ratio >= WEAR_ENERGY_RATIO_THRESHOLD;
    f64::from(u8::from(crack) + 2 * u8::from(wear))
}

/// The crack risk of a completed loop: the larger of its Crossland and Dang Van maxima
/// ([`evaluate_loop_fatigue`] with the constants of `cfg`).
pub fn crack_risk(
    lp: &crate::sam::drivers::fretting_loop::FrettingLoop,
    cfg: &FatigueConfig,
) -> Result<f64, SamError> {
    let f = evaluate_loop_fatigue(lp, cfg).map_err(|e| SamError::InvalidInput(e.0))?;
    Ok(f.indices
        .crossland_max
        .value
        .max(f.indices.dang_van_max.value))
}

/// The configuration of point `(i, j)` as text: the loop's and the fatigue constants.
fn point_fingerprint(
    map: &FrettingMap,
    fatigue: Option<&FatigueConfig>,
    i: usize,
    j: usize,
) -> Result<String, SamError> {
    Ok(format!("{}{fatigue:?}", map.point_fingerprint(i, j)?))
}

/// The checkpoint of point `(i, j)` in `dir`.
pub fn point_checkpoint(dir: &Path, i: usize, j: usize) -> PathBuf {
    dir.join(format!("point_{i:03}_{j:03}.json"))
}

/// Whether `dir` holds checkpoints of completed points.
pub fn has_checkpoints(dir: &Path) -> bool {
    std::fs::read_dir(dir)
        .map(|entries| {
            entries.flatten().any(|e| {
                let name = e.file_name();
                let name = name.to_string_lossy();
                name.starts_with("point_") && name.ends_with(".json")
            })
        })
        .unwrap_or(false)
}

fn read_checkpoint(
    map: &FrettingMap,
    fatigue: Option<&FatigueConfig>,
    path: &Path,
    i: usize,
    j: usize,
) -> Result<Option<MapPoint>, MapError> {
    if !path.exists() {
        return Ok(None);
    }
    let bad = |reason: String| MapError::Checkpoint {
        path: path.to_path_buf(),
        reason,
    };
    let text = crate::data::read_text_bounded(path, 1 << 20).map_err(|e| bad(e.to_string()))?;
    let value: serde_json::Value = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
    let recorded = value["fingerprint"].as_str().unwrap_or_default();
    if !map.accepts_point_fingerprint(i, j, recorded, &format!("{fatigue:?}"))? {
        return Err(bad(
            "made with another configuration (remove it, or write this map elsewhere)".into(),
        ));
    }
    // `null` is a NaN (the crack risk of a map without criteria).
    let values: Vec<f64> = value["values"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|v| {
                    if v.is_null() {
                        Some(f64::NAN)
                    } else {
                        v.as_f64()
                    }
                })
                .collect()
        })
        .unwrap_or_default();
    let values: [f64; 10] = values
        .try_into()
        .map_err(|_| bad(format!("expected {} values", MapPoint::FIELDS.len())))?;
    let point = MapPoint::from_values(values)
        .ok_or_else(|| bad(format!("member regime = {}: must be 0, 1 or 2", values[2])))?;
    check_point(map, &point, i, j, fatigue.is_some()).map_err(bad)?;
    Ok(Some(point))
}

/// The content of a checkpointed point: its load and amplitude are the map's `(i, j)` (bit for
/// bit), every number finite, the energy and the times ≥ 0, the sliding fraction in [0, 1] and
/// `|Q/μW|` at most 1 (Coulomb) within the solver's tolerance, the crack risk finite with criteria
/// and `NaN` without. The message names the member.
fn check_point(
    map: &FrettingMap,
    p: &MapPoint,
    i: usize,
    j: usize,
    with_risk: bool,
) -> Result<(), String> {
    let (load, amplitude) = (map.loads()[i], map.amplitudes()[j]);
    if p.load.to_bits() != load.to_bits() || p.amplitude.to_bits() != amplitude.to_bits() {
        return Err(format!(
            "members load, amplitude = ({}, {}): this map's point ({i}, {j}) is ({load}, {amplitude})",
            p.load, p.amplitude
        ));
    }
    let v = p.values();
    for (f, name) in MapPoint::FIELDS.iter().enumerate() {
        let x = v[f];
        let ok = match *name {
            "dissipated_energy" | "energy_ratio" | "seconds" => x.is_finite() && x >= 0.0,
            "sliding_fraction" => (0.0..=1.0).contains(&x),
            "tangential_force_over_mu_w_at_amplitude" => x.is_finite() && x.abs() <= 1.0 + 1e-3,
            "crack_risk" => x.is_finite() == with_risk && (with_risk || x.is_nan()),
            _ => x.is_finite(),
        };
        if !ok {
            return Err(format!(
                "member {name} = {x}: outside what the loop can produce (finite; energies and \
                 times ≥ 0, sliding fraction in [0, 1], |Q/μW| ≤ 1; crack risk finite with \
                 [fatigue], NaN without)"
            ));
        }
    }
    Ok(())
}

fn write_checkpoint(
    map: &FrettingMap,
    fatigue: Option<&FatigueConfig>,
    path: &Path,
    i: usize,
    j: usize,
    p: &MapPoint,
) -> Result<(), MapError> {
    let text = json!({
        "fingerprint": point_fingerprint(map, fatigue, i, j)?,
        "fields": MapPoint::FIELDS,
        "values": p.values().to_vec(),
    })
    .to_string();
    write_atomic(path, |tmp| {
        std::fs::write(tmp, &text).map_err(|source| DataError::Io {
            path: tmp.to_path_buf(),
            source,
        })
    })?;
    Ok(())
}

/// A map's points after [`run_map`]: `points[i · columns + j]` (`None` where not run yet).
#[derive(Debug, Clone, PartialEq)]
pub struct MapRun {
    /// The points, row-major (load index slow).
    pub points: Vec<Option<MapPoint>>,
    /// How many were read from checkpoints instead of run.
    pub resumed: usize,
}

impl MapRun {
    /// Every point, when all are there.
    pub fn complete(&self) -> Option<Vec<MapPoint>> {
        self.points.iter().copied().collect()
    }
}

/// Runs the points of `map` (row-major: load index slow) on the local cores (rayon; each loop's
/// FFTs share the same pool). With `checkpoints`, a point whose checkpoint is there is read instead
/// of run (its configuration must be the same), and each point writes its checkpoint atomically
/// when it completes; `max_new` bounds the points run in this call (the rest stay `None`, as if
/// the run had been killed); `on_point(done, total)` is called after each point. Results do not
/// depend on the order or the number of threads (every operation of a loop is deterministic), so a
/// resumed or a distributed map equals a serial one bit for bit.
pub fn run_map(
    map: &FrettingMap,
    checkpoints: Option<&Path>,
    max_new: Option<usize>,
    on_point: impl Fn(usize, usize) + Sync,
) -> Result<MapRun, MapError> {
    run_map_until(map, checkpoints, max_new, on_point, &|| false)
}

/// [`run_map`], asking `cancelled` before each point and after every increment of the loops
/// running: when it answers true the map stops with [`MapError::Cancelled`] (Ctrl-C in the front
/// ends); the points completed before keep their checkpoints.
pub fn run_map_until(
    map: &FrettingMap,
    checkpoints: Option<&Path>,
    max_new: Option<usize>,
    on_point: impl Fn(usize, usize) + Sync,
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<MapRun, MapError> {
    run_map_with(map, None, checkpoints, max_new, on_point, cancelled)
}

/// [`run_map_until`] with the fatigue criteria of `fatigue` at every point: each point's
/// `crack_risk` ([`crack_risk`]; the map's base case must record the stress history,
/// `LoopCase::fatigue_depth`, as [`crate::config::LoopConfig::map`] makes it with `[fatigue]`).
pub fn run_map_with(
    map: &FrettingMap,
    fatigue: Option<&FatigueConfig>,
    checkpoints: Option<&Path>,
    max_new: Option<usize>,
    on_point: impl Fn(usize, usize) + Sync,
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<MapRun, MapError> {
    if fatigue.is_some() != map.base().fatigue_depth.is_some() {
        return Err(MapError::Sam(SamError::InvalidInput(
            "fretting map: fatigue constants need a base case with a fatigue box \
             (LoopCase::fatigue_depth) and the other way round"
                .into(),
        )));
    }
    let (rows, cols) = map.shape();
    let total = rows * cols;
    let mut points: Vec<Option<MapPoint>> = vec![None; total];
    if let Some(dir) = checkpoints {
        for (k, slot) in points.iter_mut().enumerate() {
            let (i, j) = (k / cols, k % cols);
            *slot = read_checkpoint(map, fatigue, &point_checkpoint(dir, i, j), i, j)?;
        }
    }
    let resumed = points.iter().filter(|p| p.is_some()).count();
    let done = Mutex::new(resumed);
    let todo: Vec<usize> = (0..total)
        .filter(|&k| points[k].is_none())
        .take(max_new.unwrap_or(total))
        .collect();
    let computed: Vec<(usize, MapPoint)> = todo
        .par_iter()
        .map(|&k| {
            let (i, j) = (k / cols, k % cols);
            if cancelled() {
                return Err(MapError::Cancelled);
            }
            let risk = |lp: &crate::sam::drivers::fretting_loop::FrettingLoop| match fatigue {
                Some(cfg) => crack_risk(lp, cfg),
                None => Ok(f64::NAN),
            };
            let p = map
                .run_point_with(i, j, cancelled, &risk)
                .map_err(|source| match source {
                    SamError::Cancelled => MapError::Cancelled,
                    source => MapError::Point {
                        load: map.loads()[i],
                        amplitude: map.amplitudes()[j],
                        source,
                    },
                })?;
            if let Some(dir) = checkpoints {
                write_checkpoint(map, fatigue, &point_checkpoint(dir, i, j), i, j, &p)?;
            }
            let mut n = done.lock().unwrap_or_else(|e| e.into_inner());
            *n += 1;
            on_point(*n, total);
            Ok((k, p))
        })
        .collect::<Result<_, MapError>>()?;
    for (k, p) in computed {
        points[k] = Some(p);
    }
    Ok(MapRun { points, resumed })
}

/// The map's results as named arrays: `loads` (N), `amplitudes` (m), and each field of
/// [`MapPoint::FIELDS`] but the axes and the wall-clock `seconds` shaped `(loads, amplitudes)`
/// (`regime`: 0 partial slip, 1 mixed, 2 gross slip); the seconds summed as an attribute. With
/// crack risks (a map with `[fatigue]`): `crack_risk` and `material_response` ([`material_response`]),
/// the thresholds as attributes.
pub fn map_record(map: &FrettingMap, points: &[MapPoint]) -> Record {
    let (rows, cols) = map.shape();
    let mut rec = Record::default()
        .array("loads", map.loads().to_vec())
        .array("amplitudes", map.amplitudes().to_vec());
    for (f, name) in MapPoint::FIELDS.iter().enumerate().take(8).skip(2) {
        let v = points.iter().map(|p| p.values()[f]).collect();
        rec = rec.shaped(name, v, &[rows, cols]);
    }
    if points.iter().all(|p| p.crack_risk.is_finite()) {
        rec = rec
            .shaped(
                "crack_risk",
                points.iter().map(|p| p.crack_risk).collect(),
                &[rows, cols],
            )
            .shaped(
                "material_response",
                points.iter().map(material_response).collect(),
                &[rows, cols],
            )
            .attr(
                "material_response_codes",
                AttrValue::Text("0 no damage, 1 cracking, 2 wear, 3 both".into()),
            )
            .attr(
                "crack_risk_threshold",
                AttrValue::Float(CRACK_RISK_THRESHOLD),
            )
            .attr(
                "wear_energy_ratio_threshold",
                AttrValue::Float(WEAR_ENERGY_RATIO_THRESHOLD),
            )
            .attr(
                "crack_risk_definition",
                AttrValue::Text("max(crossland_max, dang_van_max) over the fatigue box".into()),
            );
    }
    let base = map.base();
    rec.attr(
        "regime_codes",
        AttrValue::Text("0 partial slip, 1 mixed, 2 gross slip".into()),
    )
    .attr(
        "point_seconds",
        AttrValue::Float(points.iter().map(|p| p.seconds).sum()),
    )
    .attr("grid", AttrValue::Int(base.grid as i64))
    .attr("extent", AttrValue::Float(base.extent()))
    .attr("friction", AttrValue::Float(base.friction))
    .attr("radius", AttrValue::Float(base.radius))
    .attr(
        "inclusion_count",
        AttrValue::Int(base.inhomogeneities.len() as i64),
    )
}

/// The map's results as CSV: a header of [`MapPoint::FIELDS`], one row per point (load index
/// slow), every number in Rust's shortest round-trip form.
pub fn map_csv(points: &[MapPoint]) -> String {
    let mut out = MapPoint::FIELDS.join(",");
    out.push('\n');
    for p in points {
        let row: Vec<String> = p.values().iter().map(|v| format!("{v:e}")).collect();
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sam::drivers::fretting_loop::LoopCase;

    fn map() -> FrettingMap {
        let base = LoopCase {
            grid: 16,
            normal_steps: 2,
            shift_step: 0.02e-6,
            ..LoopCase::default()
        };
        FrettingMap::new(base, vec![0.04, 0.08], vec![0.01e-6, 0.06e-6]).unwrap()
    }

    /// The resume check of a map of four points (with `fatigue`'s constants, when given):
    /// "killed" after one point (only its checkpoint in `dir`, the map incomplete), then resumed
    /// — that point reused, the three others run. Returns the resumed map's points.
    fn stopped_after_one_point_and_resumed(
        m: &FrettingMap,
        fatigue: Option<&FatigueConfig>,
        dir: &Path,
    ) -> Vec<MapPoint> {
        let first = run_map_with(m, fatigue, Some(dir), Some(1), |_, _| {}, &|| false).unwrap();
        assert_eq!(first.points.iter().flatten().count(), 1);
        assert!(first.complete().is_none() && has_checkpoints(dir));
        let calls = Mutex::new(Vec::new());
        let resumed = run_map_with(
            m,
            fatigue,
            Some(dir),
            None,
            |n, _| calls.lock().unwrap().push(n),
            &|| false,
        )
        .unwrap();
        assert_eq!(resumed.resumed, 1);
        assert_eq!(calls.into_inner().unwrap().len(), 3, "three points ran");
        resumed.complete().unwrap()
    }

    /// A map run on checkpoints of another configuration is refused, saying so.
    fn refused_as_another_configuration(result: Result<MapRun, MapError>) {
        let e = result.unwrap_err();
        assert!(e.to_string().contains("another configuration"), "{e}");
    }

    #[test]
    fn a_resumed_map_equals_an_uninterrupted_one() {
        let m = map();
        let all = run_map(&m, None, None, |_, _| {})
            .unwrap()
            .complete()
            .unwrap();
        let dir = tempfile::tempdir().unwrap();
        let resumed = stopped_after_one_point_and_resumed(&m, None, dir.path());
        for (a, b) in all.iter().zip(&resumed) {
            assert_eq!(a.values()[..8], b.values()[..8]);
            assert!(b.crack_risk.is_nan());
        }
        // Another configuration does not reuse them.
        let other = FrettingMap::new(
            LoopCase {
                friction: 0.5,
                ..m.base().clone()
            },
            m.loads().to_vec(),
            m.amplitudes().to_vec(),
        )
        .unwrap();
        refused_as_another_configuration(run_map(&other, Some(dir.path()), None, |_, _| {}));
    }

    #[test]
    fn a_crack_wear_map_holds_each_points_loop_indices_and_resumes() {
        let fatigue = FatigueConfig {
            f_minus1: 400e6,
            t_minus1: 280e6,
            fs_k: 0.5,
            yield_stress: 600e6,
            depth_over_a: 1.0,
            screen_fraction: 0.5,
            inhomogeneity: None,
            process_volume: None,
            own: Vec::new(),
        };
        let plain = map();
        let mut base = plain.base().clone();
        base.fatigue_depth = Some(base.hertz_radius());
        let m =
            FrettingMap::new(base, plain.loads().to_vec(), plain.amplitudes().to_vec()).unwrap();
        // The constants and the box go together.
        assert!(run_map_with(&m, None, None, None, |_, _| {}, &|| false).is_err());
        assert!(run_map_with(&plain, Some(&fatigue), None, None, |_, _| {}, &|| false).is_err());
        let all = run_map_with(&m, Some(&fatigue), None, None, |_, _| {}, &|| false)
            .unwrap()
            .complete()
            .unwrap();
        // Each point: the larger of the Crossland and Dang Van maxima of its own loop, whose box
        // is depth_over_a · a(W) deep; the regime columns are the plain map's.
        let without = run_map(&plain, None, None, |_, _| {})
            .unwrap()
            .complete()
            .unwrap();
        for (k, p) in all.iter().enumerate() {
            let (i, j) = (k / 2, k % 2);
            let case = m.point_case(i, j).unwrap();
            let (depth, a) = (case.fatigue_depth.unwrap(), case.hertz_radius());
            assert!((depth / a - 1.0).abs() < 1e-14, "{depth} vs a = {a}");
            let mut lp = crate::sam::drivers::fretting_loop::FrettingLoop::new(case).unwrap();
            lp.run(|_| std::ops::ControlFlow::Continue(())).unwrap();
            let f = evaluate_loop_fatigue(&lp, &fatigue).unwrap();
            let risk = f
                .indices
                .crossland_max
                .value
                .max(f.indices.dang_van_max.value);
            assert_eq!(p.crack_risk, risk);
            assert_eq!(p.values()[..8], without[k].values()[..8]);
            let code = material_response(p);
            assert_eq!(code >= 2.0, p.energy_ratio >= WEAR_ENERGY_RATIO_THRESHOLD);
            assert_eq!(code % 2.0 == 1.0, p.crack_risk >= CRACK_RISK_THRESHOLD);
        }
        // Killed after one point and resumed: the same risks; another set of constants does not
        // reuse the checkpoints.
        let dir = tempfile::tempdir().unwrap();
        let resumed = stopped_after_one_point_and_resumed(&m, Some(&fatigue), dir.path());
        for (a, b) in all.iter().zip(&resumed) {
            assert_eq!(a.crack_risk, b.crack_risk);
        }
        let other = FatigueConfig {
            t_minus1: 300e6,
            ..fatigue.clone()
        };
        refused_as_another_configuration(run_map_with(
            &m,
            Some(&other),
            Some(dir.path()),
            None,
            |_, _| {},
            &|| false,
        ));
        let rec = map_record(&m, &all);
        assert_eq!(rec.shape_of("crack_risk"), Some(vec![2, 2]));
        assert_eq!(rec.shape_of("material_response"), Some(vec![2, 2]));
        assert_eq!(map_record(&plain, &without).shape_of("crack_risk"), None);
    }

    #[test]
    fn the_table_has_a_row_per_point() {
        let m = map();
        let points = run_map(&m, None, None, |_, _| {})
            .unwrap()
            .complete()
            .unwrap();
        let csv = map_csv(&points);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 5);
        let second: Vec<f64> = lines[2].split(',').map(|v| v.parse().unwrap()).collect();
        // The crack risk is NaN (no criteria): the other columns bit for bit.
        assert_eq!(second[..9], points[1].values()[..9]);
        assert!(second[9].is_nan() && points[1].crack_risk.is_nan());
        let rec = map_record(&m, &points);
        assert_eq!(rec.shape_of("regime"), Some(vec![2, 2]));
    }
}
