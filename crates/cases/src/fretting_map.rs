//! Fretting maps as a driver shared by the CLI (`halfspace fretting-map`) and Python
//! (`halfspace.fretting_map`): the points of a [`FrettingMap`] in parallel on the local cores,
//! each checkpointed when it completes so that a killed map resumes where it stopped, and the
//! results as a table (CSV) and a [`Record`] (HDF5).

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use rayon::prelude::*;
use serde_json::json;

use crate::data::{write_atomic, AttrValue, DataError, Record};
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
    if value["fingerprint"].as_str() != Some(map.point_fingerprint(i, j)?.as_str()) {
        return Err(bad(
            "made with another configuration (remove it, or write this map elsewhere)".into(),
        ));
    }
    let values: Vec<f64> = value["values"]
        .as_array()
        .map(|a| a.iter().filter_map(|v| v.as_f64()).collect())
        .unwrap_or_default();
    let values: [f64; 9] = values
        .try_into()
        .map_err(|_| bad(format!("expected {} values", MapPoint::FIELDS.len())))?;
    let point = MapPoint::from_values(values)
        .ok_or_else(|| bad(format!("member regime = {}: must be 0, 1 or 2", values[2])))?;
    check_point(map, &point, i, j).map_err(bad)?;
    Ok(Some(point))
}

/// The content of a checkpointed point: its load and amplitude are the map's `(i, j)` (bit for
/// bit), every number finite, the energy and the times ≥ 0, the sliding fraction in [0, 1] and
/// `|Q/μW|` at most 1 (Coulomb) within the solver's tolerance. The message names the member.
fn check_point(map: &FrettingMap, p: &MapPoint, i: usize, j: usize) -> Result<(), String> {
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
            _ => x.is_finite(),
        };
        if !ok {
            return Err(format!(
                "member {name} = {x}: outside what the loop can produce (finite; energies and \
                 times ≥ 0, sliding fraction in [0, 1], |Q/μW| ≤ 1)"
            ));
        }
    }
    Ok(())
}

fn write_checkpoint(
    map: &FrettingMap,
    path: &Path,
    i: usize,
    j: usize,
    p: &MapPoint,
) -> Result<(), MapError> {
    let text = json!({
        "fingerprint": map.point_fingerprint(i, j)?,
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
    let (rows, cols) = map.shape();
    let total = rows * cols;
    let mut points: Vec<Option<MapPoint>> = vec![None; total];
    if let Some(dir) = checkpoints {
        for (k, slot) in points.iter_mut().enumerate() {
            let (i, j) = (k / cols, k % cols);
            *slot = read_checkpoint(map, &point_checkpoint(dir, i, j), i, j)?;
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
            let p = map
                .run_point_until(i, j, cancelled)
                .map_err(|source| match source {
                    SamError::Cancelled => MapError::Cancelled,
                    source => MapError::Point {
                        load: map.loads()[i],
                        amplitude: map.amplitudes()[j],
                        source,
                    },
                })?;
            if let Some(dir) = checkpoints {
                write_checkpoint(map, &point_checkpoint(dir, i, j), i, j, &p)?;
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
/// (`regime`: 0 partial slip, 1 mixed, 2 gross slip); the seconds summed as an attribute.
pub fn map_record(map: &FrettingMap, points: &[MapPoint]) -> Record {
    let (rows, cols) = map.shape();
    let mut rec = Record::default()
        .array("loads", map.loads().to_vec())
        .array("amplitudes", map.amplitudes().to_vec());
    for (f, name) in MapPoint::FIELDS.iter().enumerate().take(8).skip(2) {
        let v = points.iter().map(|p| p.values()[f]).collect();
        rec = rec.shaped(name, v, &[rows, cols]);
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

    #[test]
    fn a_resumed_map_equals_an_uninterrupted_one() {
        let m = map();
        let all = run_map(&m, None, None, |_, _| {})
            .unwrap()
            .complete()
            .unwrap();
        let dir = tempfile::tempdir().unwrap();
        // "Killed" after one point: only its checkpoint exists.
        let first = run_map(&m, Some(dir.path()), Some(1), |_, _| {}).unwrap();
        assert_eq!(first.points.iter().flatten().count(), 1);
        assert!(first.complete().is_none() && has_checkpoints(dir.path()));
        let calls = Mutex::new(Vec::new());
        let resumed = run_map(&m, Some(dir.path()), None, |n, _| {
            calls.lock().unwrap().push(n)
        })
        .unwrap();
        assert_eq!(resumed.resumed, 1);
        assert_eq!(calls.into_inner().unwrap().len(), 3, "three points ran");
        for (a, b) in all.iter().zip(&resumed.complete().unwrap()) {
            assert_eq!(a.values()[..8], b.values()[..8]);
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
        let e = run_map(&other, Some(dir.path()), None, |_, _| {}).unwrap_err();
        assert!(e.to_string().contains("another configuration"), "{e}");
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
        assert_eq!(second, points[1].values().to_vec());
        let rec = map_record(&m, &points);
        assert_eq!(rec.shape_of("regime"), Some(vec![2, 2]));
    }
}
