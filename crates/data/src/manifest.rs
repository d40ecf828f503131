//! `datasets/MANIFEST.json`: every fixture with its generator, parameters and sha256.

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use crate::DataError;

/// The fixture manifest of a repository (`<root>/datasets/MANIFEST.json`).
#[derive(Debug, Clone)]
pub struct Manifest {
    root: PathBuf,
    files: Vec<(String, String, String)>,
}

impl Manifest {
    /// Loads `<root>/datasets/MANIFEST.json`.
    pub fn load(root: &Path) -> Result<Self, DataError> {
        let path = root.join("datasets").join("MANIFEST.json");
        let text = std::fs::read_to_string(&path).map_err(|source| DataError::Io {
            path: path.clone(),
            source,
        })?;
        let json: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| DataError::Format {
                path: path.clone(),
                message: format!("not JSON: {e}"),
            })?;
        let files = json["files"]
            .as_array()
            .ok_or_else(|| DataError::Format {
                path: path.clone(),
                message: "no 'files' list".into(),
            })?
            .iter()
            .filter_map(|f| {
                Some((
                    f["path"].as_str()?.to_string(),
                    f["sha256"].as_str()?.to_string(),
                    f["generator"].as_str().unwrap_or_default().to_string(),
                ))
            })
            .collect();
        Ok(Self {
            root: root.to_path_buf(),
            files,
        })
    }

    /// Paths (relative to the root) of the files a generator wrote.
    pub fn files_of(&self, generator: &str) -> Vec<&str> {
        self.files
            .iter()
            .filter(|(_, _, g)| g == generator)
            .map(|(p, _, _)| p.as_str())
            .collect()
    }

    /// Checks the file's sha256 against the manifest and returns its absolute path.
    pub fn verified(&self, relative: &str) -> Result<PathBuf, DataError> {
        let path = self.root.join(relative);
        let expected = self
            .files
            .iter()
            .find(|(p, _, _)| p == relative)
            .map(|(_, s, _)| s.clone())
            .ok_or_else(|| DataError::Missing {
                path: path.clone(),
                message: "not listed in datasets/MANIFEST.json".into(),
            })?;
        let bytes = std::fs::read(&path).map_err(|source| DataError::Io {
            path: path.clone(),
            source,
        })?;
        let actual = format!("{:x}", Sha256::digest(&bytes));
        if actual != expected {
            return Err(DataError::ChecksumMismatch {
                path,
                expected,
                actual,
            });
        }
        Ok(path)
    }
}
