//! A run owns its output directory (`fretting-wear`, `fretting-loop`, `fretting-map`, and every
//! later command that writes a directory):
//!
//! * **a lock** (`run.lock`: the holder's pid and start time) is held while the run works; a
//!   second process on the same directory is refused, naming the holder; a lock left by a killed
//!   process (its pid gone, or reused by another process) is taken over;
//! * **a manifest** (`run.json`: the command, its parameters, whether it completed, the files it
//!   wrote): a directory holding another run is refused unless `--force` (or `--resume` of an
//!   interrupted run with the same parameters); with `--force` the old run's files are removed
//!   *before* the new run starts, so that a kill never leaves a mixture of two runs;
//! * the files are written atomically by the commands (`data::write_atomic`, the figures too),
//!   and [`RunDir::complete`] records the files of the run, so that no figure of an earlier run is
//!   left beside the new one's.
//!
//! A directory that holds files but no manifest (not made by a run) is refused; with `--force` only
//! the files a run of the command writes ([`RunKind::owns`]) are removed.

use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use crate::data::{read_text_bounded, write_atomic, DataError};

/// The manifest's file name (the application layer's `run_files`, which front ends that only
/// read a run directory share: `halfspace_cases::fretting_wear::check_run_scheme`).
pub use crate::cases::run_files::MANIFEST;
/// The lock's file name.
pub const LOCK: &str = "run.lock";

/// How a run starts in its directory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start {
    /// A new run: the directory must be new, empty, or hold nothing of another run.
    Fresh,
    /// Continue the interrupted run of the same command and parameters (`--resume`).
    Resume,
    /// Replace whatever run the directory holds (`--force`): its files go first.
    Force,
}

impl Start {
    /// From the `--resume` / `--force` flags (refusing both at once).
    pub fn of_flags(resume: bool, force: bool) -> Result<Self, RunDirError> {
        match (resume, force) {
            (true, true) => Err(RunDirError::Conflict),
            (true, false) => Ok(Start::Resume),
            (false, true) => Ok(Start::Force),
            (false, false) => Ok(Start::Fresh),
        }
    }
}

/// What a command writes into its directory.
#[derive(Debug, Clone, Copy)]
pub struct RunKind {
    /// The command (`fretting-wear`, …), recorded in the manifest.
    pub command: &'static str,
    /// Names this command writes (results, checkpoints, `points/`).
    pub files: &'static [&'static str],
    /// Extensions of its figures (`svg`, `png`).
    pub figure_extensions: &'static [&'static str],
}

impl RunKind {
    /// Whether `name` (a directory entry) is a file a run of this kind writes.
    pub fn owns(&self, name: &str) -> bool {
        name == MANIFEST
            || self.files.contains(&name)
            || Path::new(name)
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| self.figure_extensions.contains(&e))
            || (name.starts_with('.') && name.contains(".tmp"))
    }
}

/// Why a run may not use its directory.
#[derive(Debug, thiserror::Error)]
pub enum RunDirError {
    /// `--resume` and `--force` together.
    #[error("give --resume or --force, not both")]
    Conflict,
    /// Another process holds the lock.
    #[error("--out {dir}: another process (pid {pid}) is running in this directory (lock {lock}); wait for it, or use another --out")]
    Locked {
        /// The directory.
        dir: PathBuf,
        /// The holder.
        pid: u32,
        /// The lock file.
        lock: PathBuf,
    },
    /// The directory holds another run (or foreign files).
    #[error("--out {dir}: {reason}")]
    Occupied {
        /// The directory.
        dir: PathBuf,
        /// What it holds and what to do.
        reason: String,
    },
    /// Reading or writing the directory failed.
    #[error("--out {dir}: {source}")]
    Io {
        /// The directory.
        dir: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The manifest could not be read or written.
    #[error(transparent)]
    Data(#[from] DataError),
}

/// A claimed output directory: the lock is released when this is dropped.
#[derive(Debug)]
pub struct RunDir {
    dir: PathBuf,
    kind: RunKind,
    parameters: Value,
    lock: PathBuf,
}

/// The pid and start time (clock ticks since boot, `/proc/PID/stat` field 22) of a process;
/// `None` for the start time where `/proc` is not there.
fn process_start(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // Fields after the command name (which may hold spaces) start after the last ')'.
    let rest = &stat[stat.rfind(')')? + 1..];
    rest.split_whitespace().nth(19)?.parse().ok()
}

/// Whether the holder recorded in a lock file is a live process (the same one: pid and start
/// time). Without `/proc`, a lock is taken as live only when it is this process's.
fn holder_alive(text: &str) -> Option<u32> {
    let mut parts = text.split_whitespace();
    let pid: u32 = parts.next()?.parse().ok()?;
    let start: Option<u64> = parts.next().and_then(|s| s.parse().ok());
    if pid == std::process::id() {
        return Some(pid);
    }
    if !Path::new("/proc/self/stat").exists() {
        return None;
    }
    match (process_start(pid), start) {
        (Some(now), Some(then)) if now == then => Some(pid),
        (Some(_), None) => Some(pid),
        _ => None,
    }
}

impl RunDir {
    /// Claims `dir` for a run of `kind` with `parameters` (the manifest's identity of the run):
    /// creates it, takes the lock, and checks what it holds against `start` (module doc). Nothing
    /// in the directory is changed when the claim is refused.
    pub fn claim(
        dir: &Path,
        kind: RunKind,
        parameters: Value,
        start: Start,
    ) -> Result<Self, RunDirError> {
        let io = |source| RunDirError::Io {
            dir: dir.to_path_buf(),
            source,
        };
        if start == Start::Resume && !dir.is_dir() {
            return Err(RunDirError::Occupied {
                dir: dir.to_path_buf(),
                reason: "--resume: no interrupted run here (it has no checkpoints: the directory does not exist)".into(),
            });
        }
        if dir.exists() && !dir.is_dir() {
            return Err(RunDirError::Occupied {
                dir: dir.to_path_buf(),
                reason: "is a file, not a directory: choose a directory for --out".into(),
            });
        }
        std::fs::create_dir_all(dir).map_err(io)?;
        let lock = dir.join(LOCK);
        take_lock(dir, &lock)?;
        let claimed = Self {
            dir: dir.to_path_buf(),
            kind,
            parameters,
            lock,
        };
        // From here on, dropping `claimed` releases the lock on every refusal.
        claimed.check_and_prepare(start)?;
        Ok(claimed)
    }

    fn check_and_prepare(&self, start: Start) -> Result<(), RunDirError> {
        let dir = &self.dir;
        let occupied = |reason: String| RunDirError::Occupied {
            dir: dir.clone(),
            reason,
        };
        let entries = self.entries()?;
        let manifest = match entries.iter().any(|n| n == MANIFEST) {
            true => Some(self.read_manifest()?),
            false => None,
        };
        let same = manifest.as_ref().is_some_and(|m| {
            m["command"] == json!(self.kind.command) && m["parameters"] == self.parameters
        });
        let complete = manifest
            .as_ref()
            .is_some_and(|m| m["status"] == json!("complete"));
        // A run that stopped on an error ([`RunDir::fail`]): its message.
        let failure = manifest
            .as_ref()
            .filter(|m| m["status"] == json!("failed"))
            .map(|m| m["error"].as_str().unwrap_or("?").to_string());
        let others: Vec<&String> = entries.iter().filter(|n| *n != LOCK).collect();
        match start {
            Start::Resume => {
                let Some(m) = &manifest else {
                    return Err(occupied(
                        "--resume: no interrupted run here (it has no checkpoints and no run.json manifest)"
                            .into(),
                    ));
                };
                if m["command"] != json!(self.kind.command) {
                    return Err(occupied(format!(
                        "--resume: this directory holds a {} run, not a {} run",
                        m["command"].as_str().unwrap_or("?"),
                        self.kind.command
                    )));
                }
                if !same {
                    return Err(occupied(format!(
                        "--resume: the run here was made with another configuration (other parameters: {}); resume \
                         with the same ones, or start over with --force",
                        differences(&m["parameters"], &self.parameters)
                    )));
                }
                if complete {
                    return Err(occupied(
                        "--resume: the run here is complete; --force runs it again".into(),
                    ));
                }
                self.write_manifest("running", &[])
            }
            Start::Fresh => {
                if others.iter().all(|n| n.as_str() == MANIFEST) {
                    return self.write_manifest("running", &[]);
                }
                Err(occupied(match &manifest {
                    Some(_) if same && failure.is_some() => format!(
                        "holds a run of these parameters that stopped on an error ({}); its \
                         results hold what was done before it: --force starts it over, \
                         --resume retries from its last checkpoint (if it wrote one)",
                        failure.as_deref().unwrap_or("?")
                    ),
                    Some(_) if !complete && same => {
                        "holds an interrupted run of these parameters: \
                         --resume continues it, --force starts it over"
                            .to_string()
                    }
                    Some(m) => format!(
                        "holds {} {} run ({}): --force replaces it, or choose another --out{}",
                        if complete {
                            "a complete"
                        } else {
                            "an interrupted"
                        },
                        m["command"].as_str().unwrap_or("?"),
                        if same {
                            "the same parameters".to_string()
                        } else {
                            differences(&m["parameters"], &self.parameters)
                        },
                        if complete {
                            " (--resume continues only an interrupted run)"
                        } else {
                            " (--resume continues it with its own parameters)"
                        }
                    ),
                    None => format!(
                        "is not empty and holds no run manifest ({MANIFEST}; {} entries, e.g. \
                         '{}'): choose an empty or new directory, or --force to remove the files \
                         a {} run writes there",
                        others.len(),
                        others[0],
                        self.kind.command
                    ),
                }))
            }
            Start::Force => {
                // The old run's files go first (its manifest last), then the new manifest.
                let listed: Vec<String> = manifest
                    .as_ref()
                    .and_then(|m| m["files"].as_array())
                    .map(|a| {
                        a.iter()
                            .filter_map(|v| v.as_str())
                            .filter(|n| is_plain_name(n))
                            .map(str::to_string)
                            .collect()
                    })
                    .unwrap_or_default();
                for name in &others {
                    if name.as_str() == MANIFEST {
                        continue;
                    }
                    if self.kind.owns(name) || listed.contains(*name) {
                        let path = dir.join(name);
                        let removed = if path.is_dir() {
                            std::fs::remove_dir_all(&path)
                        } else {
                            std::fs::remove_file(&path)
                        };
                        removed.map_err(|source| RunDirError::Io {
                            dir: path.clone(),
                            source,
                        })?;
                    }
                }
                self.write_manifest("running", &[])
            }
        }
    }

    fn entries(&self) -> Result<Vec<String>, RunDirError> {
        let read = std::fs::read_dir(&self.dir).map_err(|source| RunDirError::Io {
            dir: self.dir.clone(),
            source,
        })?;
        let mut names: Vec<String> = read
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        Ok(names)
    }

    fn read_manifest(&self) -> Result<Value, RunDirError> {
        let path = self.dir.join(MANIFEST);
        let text = read_text_bounded(&path, 1 << 20)?;
        serde_json::from_str(&text).map_err(|e| {
            RunDirError::Data(DataError::Format {
                path,
                message: format!("not a run manifest: {e}"),
            })
        })
    }

    fn write_manifest(&self, status: &str, files: &[String]) -> Result<(), RunDirError> {
        self.write_manifest_with(status, files, None)
    }

    fn write_manifest_with(
        &self,
        status: &str,
        files: &[String],
        error: Option<&str>,
    ) -> Result<(), RunDirError> {
        let mut manifest = json!({
            "command": self.kind.command,
            "generator": format!("halfspace {}", env!("CARGO_PKG_VERSION")),
            "status": status,
            "parameters": self.parameters,
            "files": files,
        });
        if let Some(error) = error {
            manifest["error"] = json!(error);
        }
        let text = serde_json::to_string_pretty(&manifest).unwrap_or_default();
        let path = self.dir.join(MANIFEST);
        write_atomic(&path, |tmp| {
            std::fs::write(tmp, &text).map_err(|source| DataError::Io {
                path: tmp.to_path_buf(),
                source,
            })
        })?;
        Ok(())
    }

    /// The directory.
    pub fn path(&self) -> &Path {
        &self.dir
    }

    /// `dir/name`.
    pub fn join(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Marks the run complete with every file of its kind now in the directory (it started
    /// without any: module doc).
    pub fn complete_present(&self) -> Result<(), RunDirError> {
        let names: Vec<String> = self
            .entries()?
            .into_iter()
            .filter(|n| n != MANIFEST && n != LOCK && self.kind.owns(n) && !n.starts_with('.'))
            .collect();
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        self.complete(&refs)
    }

    /// Marks the run as stopped on `error` (status `failed`, the message recorded): a later run of
    /// the same parameters is told so instead of being offered an interrupted run; `--resume`
    /// retries it from its checkpoint, `--force` starts over.
    pub fn fail(&self, error: &str) -> Result<(), RunDirError> {
        self.write_manifest_with("failed", &[], Some(error))
    }

    /// Marks the run complete with the files it wrote (names in the directory): a later `--force`
    /// removes exactly these.
    pub fn complete(&self, files: &[&str]) -> Result<(), RunDirError> {
        let files: Vec<String> = files.iter().map(|s| s.to_string()).collect();
        self.write_manifest("complete", &files)
    }
}

impl Drop for RunDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.lock);
    }
}

/// A name inside the directory (no separators, not `.`/`..`): a manifest cannot make `--force`
/// remove anything outside it.
fn is_plain_name(name: &str) -> bool {
    !name.is_empty() && name != "." && name != ".." && !name.contains(['/', '\\'])
}

/// Takes the lock file (created exclusively); a lock whose holder is gone is taken over.
fn take_lock(dir: &Path, lock: &Path) -> Result<(), RunDirError> {
    let me = format!(
        "{} {}\n",
        std::process::id(),
        process_start(std::process::id())
            .map(|s| s.to_string())
            .unwrap_or_default()
    );
    for _ in 0..2 {
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(lock)
        {
            Ok(mut file) => {
                use std::io::Write;
                file.write_all(me.as_bytes())
                    .and_then(|_| file.sync_all())
                    .map_err(|source| RunDirError::Io {
                        dir: lock.to_path_buf(),
                        source,
                    })?;
                return Ok(());
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                let text = read_text_bounded(lock, 4096).unwrap_or_default();
                if let Some(pid) = holder_alive(&text) {
                    return Err(RunDirError::Locked {
                        dir: dir.to_path_buf(),
                        pid,
                        lock: lock.to_path_buf(),
                    });
                }
                // Left by a killed process: take it over.
                let _ = std::fs::remove_file(lock);
            }
            Err(source) => {
                return Err(RunDirError::Io {
                    dir: dir.to_path_buf(),
                    source,
                })
            }
        }
    }
    let text = read_text_bounded(lock, 4096).unwrap_or_default();
    Err(RunDirError::Locked {
        dir: dir.to_path_buf(),
        pid: text
            .split_whitespace()
            .next()
            .and_then(|p| p.parse().ok())
            .unwrap_or(0),
        lock: lock.to_path_buf(),
    })
}

/// The parameters that differ between two manifests, as `key: old → new`.
/// The byte offset in `a` where the `, `-separated field holding the first difference between
/// `a` and `b` starts (0 when the difference is in the first field or the texts are short).
fn field_start(a: &str, b: &str) -> usize {
    if a.chars().count() <= 60 && b.chars().count() <= 60 {
        return 0;
    }
    let common = a
        .char_indices()
        .zip(b.chars())
        .find(|((_, x), y)| x != y)
        .map_or(a.len().min(b.len()), |((i, _), _)| i);
    // Both texts are equal up to `common`, so a boundary found in `a` is one in `b` too.
    let common = (0..=common)
        .rev()
        .find(|&i| a.is_char_boundary(i))
        .unwrap_or(0);
    let start = a[..common].rfind(", ").map_or(0, |i| i + 2);
    if b.is_char_boundary(start) {
        start
    } else {
        0
    }
}

/// At most 60 characters of `t` from the byte offset `from` (a char boundary of `t`), with `…`
/// where text is left out.
fn excerpt(t: &str, from: usize) -> String {
    let from = if t.is_char_boundary(from) { from } else { 0 };
    let rest = &t[from..];
    let lead = if from > 0 { "…" } else { "" };
    match rest.char_indices().nth(57) {
        Some((i, _)) if rest.chars().count() > 60 => format!("{lead}{}…", &rest[..i]),
        _ => format!("{lead}{rest}"),
    }
}

fn differences(old: &Value, new: &Value) -> String {
    let (Some(a), Some(b)) = (old.as_object(), new.as_object()) else {
        return "other parameters".into();
    };
    let mut diffs: Vec<String> = b
        .iter()
        .filter(|(k, v)| a.get(*k) != Some(*v))
        .map(|(k, v)| {
            let old = a.get(k).map(Value::to_string);
            let new = v.to_string();
            // Long values (a configuration's whole dump) are shown around their first
            // difference, from the start of the field that holds it.
            let from = old.as_deref().map_or(0, |o| field_start(o, &new));
            format!(
                "{k}: {} here, {} now",
                old.as_deref().map_or("absent".into(), |o| excerpt(o, from)),
                excerpt(&new, from)
            )
        })
        .collect();
    diffs.extend(
        a.keys()
            .filter(|k| !b.contains_key(*k))
            .map(|k| format!("{k}: absent now")),
    );
    if diffs.is_empty() {
        "other parameters".into()
    } else {
        diffs.join("; ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const KIND: RunKind = RunKind {
        command: "test-run",
        files: &["results.h5", "checkpoint.npz", "points"],
        figure_extensions: &["svg", "png"],
    };

    #[test]
    fn a_second_claim_is_refused_while_the_first_holds_the_lock() {
        let dir = tempfile::tempdir().unwrap();
        let first = RunDir::claim(dir.path(), KIND, json!({"a": 1}), Start::Fresh).unwrap();
        let e = RunDir::claim(dir.path(), KIND, json!({"a": 1}), Start::Resume).unwrap_err();
        assert!(
            e.to_string()
                .contains(&format!("pid {}", std::process::id())),
            "{e}"
        );
        std::fs::write(dir.path().join("checkpoint.npz"), "x").unwrap();
        drop(first);
        // Interrupted (no completion): resume with the same parameters only.
        let e = RunDir::claim(dir.path(), KIND, json!({"a": 2}), Start::Resume).unwrap_err();
        assert!(e.to_string().contains("a: 1 here, 2 now"), "{e}");
        let e = RunDir::claim(dir.path(), KIND, json!({"a": 1}), Start::Fresh).unwrap_err();
        assert!(e.to_string().contains("--resume continues it"), "{e}");
        let r = RunDir::claim(dir.path(), KIND, json!({"a": 1}), Start::Resume).unwrap();
        std::fs::write(dir.path().join("old.svg"), "x").unwrap();
        r.complete(&["old.svg"]).unwrap();
        drop(r);
        let e = RunDir::claim(dir.path(), KIND, json!({"a": 1}), Start::Fresh).unwrap_err();
        assert!(e.to_string().contains("--force replaces it"), "{e}");
        std::fs::write(dir.path().join("notes.txt"), "mine").unwrap();
        let r = RunDir::claim(dir.path(), KIND, json!({"a": 3}), Start::Force).unwrap();
        assert!(!dir.path().join("old.svg").exists());
        assert!(dir.path().join("notes.txt").exists(), "foreign files stay");
        drop(r);
        assert!(!dir.path().join(LOCK).exists());
    }

    /// A run that stopped on an error is reported as such (not as an interrupted run), can be
    /// retried with `--resume` or replaced with `--force`; a configuration dump that differs in
    /// one field is reported around that field.
    #[test]
    fn a_failed_run_is_named_and_long_parameters_show_their_difference() {
        let dir = tempfile::tempdir().unwrap();
        let r = RunDir::claim(dir.path(), KIND, json!({"a": 1}), Start::Fresh).unwrap();
        std::fs::write(dir.path().join("results.h5"), "x").unwrap();
        r.fail("Polonsky–Keer did not converge").unwrap();
        drop(r);
        let e = RunDir::claim(dir.path(), KIND, json!({"a": 1}), Start::Fresh).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("stopped on an error (Polonsky–Keer did not converge)")
                && text.contains("--force starts it over"),
            "{text}"
        );
        drop(RunDir::claim(dir.path(), KIND, json!({"a": 1}), Start::Resume).unwrap());
        drop(RunDir::claim(dir.path(), KIND, json!({"a": 1}), Start::Force).unwrap());

        let dump = |cycles: u32| {
            json!({"case": format!(
                "WearCase {{ fretting: LoopCase {{ radius: 0.000105, e: 210000000000.0, nu: 0.3, \
                 friction: 0.3, force: 0.08 }}, law: Archard, coefficient: 1e-15, cycles: {cycles}, \
                 step_fraction: 0.0065 }}"
            )})
        };
        let text = differences(&dump(300), &dump(400));
        assert!(
            text.contains("…cycles: 300, step_fraction") && text.contains("…cycles: 400, step"),
            "{text}"
        );
        assert_eq!(
            differences(&json!({"a": 1}), &json!({"a": 2})),
            "a: 1 here, 2 now"
        );
    }

    #[test]
    fn a_file_given_as_the_directory_is_refused_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("results");
        std::fs::write(&file, "mine").unwrap();
        let e = RunDir::claim(&file, KIND, json!({}), Start::Force).unwrap_err();
        assert!(e.to_string().contains("is a file, not a directory"), "{e}");
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
    }

    #[test]
    fn a_lock_of_a_dead_process_is_taken_over_and_foreign_dirs_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        // pid 4194304 is above Linux's pid_max: never alive.
        std::fs::write(dir.path().join(LOCK), "4194304 1\n").unwrap();
        let r = RunDir::claim(dir.path(), KIND, json!({}), Start::Fresh);
        assert!(r.is_ok(), "{r:?}");
        drop(r);
        let other = tempfile::tempdir().unwrap();
        std::fs::write(other.path().join("thesis.tex"), "x").unwrap();
        let e = RunDir::claim(other.path(), KIND, json!({}), Start::Fresh).unwrap_err();
        assert!(e.to_string().contains("holds no run manifest"), "{e}");
        assert!(Start::of_flags(true, true).is_err());
    }
}
