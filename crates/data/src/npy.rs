use std::fs::File;
use std::io::{BufReader, BufWriter};
use std::path::Path;

use ndarray::{Array1, Array2};
use ndarray_npy::{NpzReader, NpzWriter, ReadNpyError, ReadNpyExt, ReadNpzError};

use crate::{AttrValue, DataError, Record};

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

fn npy_error(path: &Path, e: ReadNpyError) -> DataError {
    match e {
        ReadNpyError::Io(source) => DataError::Io {
            path: path.to_path_buf(),
            source,
        },
        ReadNpyError::WrongNdim(expected, got) => DataError::WrongShape {
            path: path.to_path_buf(),
            name: "array".into(),
            expected: format!("{} dimensions", expected.unwrap_or(0)),
            got: vec![got],
        },
        ReadNpyError::WrongDescriptor(d) => format_error(
            path,
            format!("wrong dtype {d:?}: expected little-endian float64 ('<f8')"),
        ),
        other => format_error(path, format!("not a valid .npy file: {other}")),
    }
}

/// Reads a profile table from `.npy`: a float64 array of shape `(n, 2)`, columns `r` and `f`.
/// Validation of the values (ordering, finiteness) is the profile's job.
pub fn read_profile_table(path: &Path) -> Result<(Vec<f64>, Vec<f64>), DataError> {
    let file = File::open(path).map_err(io(path))?;
    let table = Array2::<f64>::read_npy(BufReader::new(file)).map_err(|e| npy_error(path, e))?;
    if table.ncols() != 2 {
        return Err(DataError::WrongShape {
            path: path.to_path_buf(),
            name: "profile table".into(),
            expected: "(n, 2): columns r and f".into(),
            got: table.shape().to_vec(),
        });
    }
    Ok((table.column(0).to_vec(), table.column(1).to_vec()))
}

/// Reads a 1D float64 `.npy`.
pub fn read_npy_1d(path: &Path) -> Result<Vec<f64>, DataError> {
    let file = File::open(path).map_err(io(path))?;
    let a = Array1::<f64>::read_npy(BufReader::new(file)).map_err(|e| npy_error(path, e))?;
    Ok(a.to_vec())
}

/// Reads a 2D float64 `.npy` as `(rows, columns, row-major values)`.
pub fn read_npy_2d(path: &Path) -> Result<(usize, usize, Vec<f64>), DataError> {
    let file = File::open(path).map_err(io(path))?;
    let a = Array2::<f64>::read_npy(BufReader::new(file)).map_err(|e| npy_error(path, e))?;
    Ok((a.nrows(), a.ncols(), a.iter().copied().collect()))
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

pub(crate) fn read_npz(path: &Path) -> Result<Record, DataError> {
    let file = File::open(path).map_err(io(path))?;
    let err = |e: ReadNpzError| format_error(path, e);
    let mut npz = NpzReader::new(BufReader::new(file)).map_err(err)?;
    let mut record = Record::default();
    for name in npz.names().map_err(err)? {
        let short = name.trim_end_matches(".npy").to_string();
        if short == "metadata" {
            let bytes: Array1<u8> = npz.by_name(&name).map_err(err)?;
            let meta: serde_json::Value =
                serde_json::from_slice(bytes.as_slice().unwrap_or(&[]))
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
            let values: ndarray::ArrayD<f64> = npz.by_name(&name).map_err(err)?;
            if values.ndim() > 1 {
                record.shapes.push((short.clone(), values.shape().to_vec()));
            }
            record
                .arrays
                .push((short, values.iter().copied().collect()));
        }
    }
    Ok(record)
}
