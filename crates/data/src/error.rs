use std::path::PathBuf;

use thiserror::Error;

/// Errors reading or writing data files; each names the file.
#[derive(Debug, Error)]
pub enum DataError {
    /// The file could not be opened, read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Unknown extension.
    #[error("{path}: unknown format (use .npz, .h5 or .hdf5)")]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// An array has the wrong shape.
    #[error("{path}: array '{name}' has shape {got:?}, expected {expected}")]
    WrongShape {
        /// The file.
        path: PathBuf,
        /// The array.
        name: String,
        /// What was expected, in words.
        expected: String,
        /// The shape found.
        got: Vec<usize>,
    },
    /// An array has the wrong element type, or the file is not a valid NPY/NPZ.
    #[error("{path}: {message}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A value is unusable (non-finite, mismatched lengths, bad names).
    #[error("{path}: {message}")]
    InvalidContent {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// HDF5 library error.
    #[error("{path}: HDF5: {message}")]
    Hdf5 {
        /// The file.
        path: PathBuf,
        /// The library's message.
        message: String,
    },
    /// A fixture's content does not match the checksum recorded in its manifest.
    #[error("{path}: checksum mismatch (MANIFEST.json has {expected}, the file hashes to {actual}); regenerate with `python -m verify` or restore the file")]
    ChecksumMismatch {
        /// The file.
        path: PathBuf,
        /// sha256 in the manifest.
        expected: String,
        /// sha256 of the file.
        actual: String,
    },
    /// A fixture or group is not listed where it should be.
    #[error("{path}: {message}")]
    Missing {
        /// The file.
        path: PathBuf,
        /// What is missing.
        message: String,
    },
    /// Built without the `hdf5` feature.
    #[error("{path}: this build has no HDF5 support (build with the 'hdf5' feature)")]
    Hdf5Unavailable {
        /// The file.
        path: PathBuf,
    },
}
