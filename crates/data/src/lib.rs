//! Fixtures and results of halfspace: 1D arrays with metadata, written as `.npz` (ndarray-npy;
//! metadata as a JSON byte array named `metadata`) or `.h5` (hdf5-metno; metadata as attributes of
//! the root group), always atomically (temporary file in the same directory + rename), and read
//! back with typed errors that name the file and the problem.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod atomic;
mod bounded;
mod error;
#[cfg(feature = "hdf5")]
mod h5;
mod manifest;
mod npy;
mod record;
mod xdmf;

pub use atomic::write_atomic;
pub use bounded::read_text_bounded;
pub use error::DataError;
pub use manifest::Manifest;
pub use npy::{read_npy_1d, read_npy_2d, read_profile_table};
pub use record::{AttrValue, Record};
pub use xdmf::{write_xdmf, write_xdmf_rectilinear, RectilinearVolume, UniformVolume};

use std::path::Path;

/// File formats for [`Record`]s, chosen by extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// `.npz`: one `.npy` per array plus `metadata` (JSON as `u8`).
    Npz,
    /// `.h5` / `.hdf5`: one dataset per array, metadata as root attributes.
    Hdf5,
}

impl Format {
    /// The format of a path by its extension.
    pub fn of(path: &Path) -> Result<Self, DataError> {
        match path.extension().and_then(|e| e.to_str()) {
            Some("npz") => Ok(Format::Npz),
            Some("h5") | Some("hdf5") => Ok(Format::Hdf5),
            _ => Err(DataError::UnknownFormat {
                path: path.to_path_buf(),
            }),
        }
    }
}

/// Writes `record` to `path` (`.npz`, `.h5`, `.hdf5`) atomically.
pub fn write_record(path: &Path, record: &Record) -> Result<(), DataError> {
    record.validate(path)?;
    match Format::of(path)? {
        Format::Npz => write_atomic(path, |tmp| npy::write_npz(tmp, record)),
        Format::Hdf5 => write_hdf5(path, record),
    }
}

/// Reads a record written by [`write_record`].
pub fn read_record(path: &Path) -> Result<Record, DataError> {
    match Format::of(path)? {
        Format::Npz => npy::read_npz(path),
        Format::Hdf5 => read_hdf5(path),
    }
}

#[cfg(feature = "hdf5")]
fn write_hdf5(path: &Path, record: &Record) -> Result<(), DataError> {
    write_atomic(path, |tmp| h5::write(tmp, record))
}

#[cfg(not(feature = "hdf5"))]
fn write_hdf5(path: &Path, _record: &Record) -> Result<(), DataError> {
    Err(DataError::Hdf5Unavailable {
        path: path.to_path_buf(),
    })
}

#[cfg(feature = "hdf5")]
fn read_hdf5(path: &Path) -> Result<Record, DataError> {
    h5::read(path, "/")
}

/// Reads one group of an HDF5 file (its 1D datasets and its attributes) as a [`Record`].
#[cfg(feature = "hdf5")]
pub fn read_h5_group(path: &Path, group: &str) -> Result<Record, DataError> {
    h5::read(path, group)
}

/// Reads one group of an HDF5 file (needs the `hdf5` feature).
#[cfg(not(feature = "hdf5"))]
pub fn read_h5_group(path: &Path, _group: &str) -> Result<Record, DataError> {
    Err(DataError::Hdf5Unavailable {
        path: path.to_path_buf(),
    })
}

#[cfg(not(feature = "hdf5"))]
fn read_hdf5(path: &Path) -> Result<Record, DataError> {
    Err(DataError::Hdf5Unavailable {
        path: path.to_path_buf(),
    })
}
