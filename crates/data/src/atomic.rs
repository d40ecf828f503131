use std::path::{Path, PathBuf};

use crate::DataError;

/// Writes a file atomically: `write` fills a temporary file in the same directory, which is then
/// synced to disk and renamed over `path` (readers see the old file or the new one, never a
/// partial one; after a crash the same), then the directory is synced (best effort). The
/// temporary file is removed on failure.
pub fn write_atomic<F>(path: &Path, write: F) -> Result<(), DataError>
where
    F: FnOnce(&Path) -> Result<(), DataError>,
{
    let tmp = temporary_path(path);
    let io = |source| DataError::Io {
        path: path.to_path_buf(),
        source,
    };
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        if !dir.is_dir() {
            return Err(io(std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!("directory {} does not exist", dir.display()),
            )));
        }
    }
    // The temporary file's data on disk before the rename (so that a crash leaves the old file
    // or the whole new one, not a renamed empty one), and the rename itself after it (the
    // directory's entry; best effort: not every file system syncs a directory).
    let result = write(&tmp)
        .and_then(|_| {
            std::fs::File::open(&tmp)
                .and_then(|f| f.sync_all())
                .map_err(io)
        })
        .and_then(|_| std::fs::rename(&tmp, path).map_err(io));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    } else if let Some(dir) = path.parent() {
        let dir = if dir.as_os_str().is_empty() {
            Path::new(".")
        } else {
            dir
        };
        let _ = std::fs::File::open(dir).and_then(|d| d.sync_all());
    }
    result
}

fn temporary_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    // Keep the extension last: some writers choose the format by it.
    let ext = path.extension().map(|e| e.to_string_lossy().into_owned());
    let tmp_name = match ext {
        Some(e) => format!(".{name}.{}.tmp.{e}", std::process::id()),
        None => format!(".{name}.{}.tmp", std::process::id()),
    };
    path.with_file_name(tmp_name)
}
