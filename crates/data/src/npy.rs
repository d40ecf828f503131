use std::fs::File;
use std::io::{BufReader, BufWriter};
use std::path::Path;

use ndarray::Array1;
use ndarray_npy::NpzWriter;

use crate::{bounded, AttrValue, DataError, Record};

fn io(path: &Path) -> impl Fn(std::io::Error) -> DataError + '_ {
    move |source| DataError::Io {
        path: path.to_path_buf(),
        source,
    }
}

fn format_error(path: &Path, message: impl std::fmt::Display) -> DataError {
    DataError::Format {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}

/// Opens a `.npy` file and checks its header against the file's size and the memory available
/// (`copies` arrays of its size at once) before anything is allocated.
fn open_npy(path: &Path, copies: f64) -> Result<(BufReader<File>, bounded::NpyHeader), DataError> {
    let file = File::open(path).map_err(io(path))?;
    let len = file.metadata().map_err(io(path))?.len();
    let mut reader = BufReader::new(file);
    let header = bounded::read_header(&mut reader, path, None)?;
    bounded::check_claim(
        &header,
        len.saturating_sub(header.header_bytes),
        copies,
        path,
        None,
    )?;
    Ok((reader, header))
}

fn wrong_ndim(path: &Path, name: &str, expected: &str, shape: &[usize]) -> DataError {
    DataError::WrongShape {
        path: path.to_path_buf(),
        name: name.into(),
        expected: expected.into(),
        got: shape.to_vec(),
    }
}

/// Reads a profile table from `.npy`: a float64 array of shape `(n, 2)`, columns `r` and `f`.
/// Validation of the values (ordering, finiteness) is the profile's job.
pub fn read_profile_table(path: &Path) -> Result<(Vec<f64>, Vec<f64>), DataError> {
    let (mut reader, header) = open_npy(path, 2.0)?;
    if header.shape.len() != 2 || header.shape[1] != 2 {
        return Err(wrong_ndim(
            path,
            "profile table",
            "(n, 2): columns r and f",
            &header.shape,
        ));
    }
    let values = bounded::read_f64(&mut reader, &header, path, None)?;
    let r = values.iter().step_by(2).copied().collect();
    let f = values.iter().skip(1).step_by(2).copied().collect();
    Ok((r, f))
}

/// Reads a 1D float64 `.npy`.
pub fn read_npy_1d(path: &Path) -> Result<Vec<f64>, DataError> {
    let (mut reader, header) = open_npy(path, 1.0)?;
    if header.shape.len() != 1 {
        return Err(wrong_ndim(path, "array", "1 dimensions", &header.shape));
    }
    bounded::read_f64(&mut reader, &header, path, None)
}

/// Reads a 2D float64 `.npy` as `(rows, columns, row-major values)`.
pub fn read_npy_2d(path: &Path) -> Result<(usize, usize, Vec<f64>), DataError> {
    let (mut reader, header) = open_npy(path, 1.0)?;
    if header.shape.len() != 2 {
        return Err(wrong_ndim(path, "array", "2 dimensions", &header.shape));
    }
    let values = bounded::read_f64(&mut reader, &header, path, None)?;
    Ok((header.shape[0], header.shape[1], values))
}

pub(crate) fn write_npz(path: &Path, record: &Record) -> Result<(), DataError> {
    let file = File::create(path).map_err(io(path))?;
    let mut npz = NpzWriter::new(BufWriter::new(file));
    let err = |e: ndarray_npy::WriteNpzError| format_error(path, e);
    for (name, values) in &record.arrays {
        let shape = record.shape_of(name).unwrap_or_else(|| vec![values.len()]);
        let array = ndarray::ArrayD::from_shape_vec(ndarray::IxDyn(&shape), values.clone())
            .map_err(|e| format_error(path, format!("array '{name}': {e}")))?;
        npz.add_array(name.as_str(), &array).map_err(err)?;
    }
    let meta = serde_json::to_vec(&record.metadata_json()).expect("JSON of plain values");
    npz.add_array("metadata", &Array1::from(meta))
        .map_err(err)?;
    let writer = npz.finish().map_err(err)?;
    writer
        .into_inner()
        .map_err(|e| io(path)(e.into_error()))?
        .sync_all()
        .map_err(io(path))
}

/// Reads an `.npz` written by [`write_npz`] (stored members): each member's `.npy` header is
/// checked against the member's size, the file's size and the memory available before its data
/// is read.
pub(crate) fn read_npz(path: &Path) -> Result<Record, DataError> {
    let file = File::open(path).map_err(io(path))?;
    let file_len = file.metadata().map_err(io(path))?.len();
    let mut zip = zip::ZipArchive::new(BufReader::new(file))
        .map_err(|e| format_error(path, format!("not a valid .npz (zip) file: {e}")))?;
    let mut record = Record::default();
    let mut total = 0.0;
    for index in 0..zip.len() {
        let mut entry = zip
            .by_index(index)
            .map_err(|e| format_error(path, format!("member {index}: {e}")))?;
        let name = entry.name().to_string();
        let member = Some(name.as_str());
        if entry.compression() != zip::CompressionMethod::Stored {
            return Err(format_error(
                path,
                format!("member '{name}': compressed members are not read (write it uncompressed)"),
            ));
        }
        let size = entry.size();
        if size > file_len {
            return Err(format_error(
                path,
                format!("member '{name}' claims {size} bytes, the file has {file_len}"),
            ));
        }
        let header = bounded::read_header(&mut entry, path, member)?;
        let bytes = bounded::check_claim(
            &header,
            size.saturating_sub(header.header_bytes),
            1.0,
            path,
            member,
        )?;
        total += bytes as f64;
        bounded::check_memory(total, path, member)?;
        let short = name.trim_end_matches(".npy").to_string();
        if short == "metadata" {
            let bytes = bounded::read_bytes(&mut entry, &header, path, member)?;
            let meta: serde_json::Value = serde_json::from_slice(&bytes)
                .map_err(|e| format_error(path, format!("metadata is not JSON: {e}")))?;
            if let serde_json::Value::Object(map) = meta {
                for (k, v) in map {
                    let value = match v {
                        serde_json::Value::Number(n) if n.is_i64() => {
                            AttrValue::Int(n.as_i64().unwrap_or_default())
                        }
                        serde_json::Value::Number(n) => {
                            AttrValue::Float(n.as_f64().unwrap_or(f64::NAN))
                        }
                        serde_json::Value::String(s) => AttrValue::Text(s),
                        other => AttrValue::Text(other.to_string()),
                    };
                    record.attributes.push((k, value));
                }
            }
        } else {
            let values = bounded::read_f64(&mut entry, &header, path, member)?;
            if header.shape.len() > 1 {
                record.shapes.push((short.clone(), header.shape.clone()));
            }
            record.arrays.push((short, values));
        }
    }
    Ok(record)
}
