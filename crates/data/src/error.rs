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
    /// Built without the `hdf5` feature.
    #[error("{path}: this build has no HDF5 support (build with the 'hdf5' feature)")]
    Hdf5Unavailable {
        /// The file.
        path: PathBuf,
    },
}
