use std::path::Path;

use hdf5::types::VarLenUnicode;

use crate::{AttrValue, DataError, Record};

fn h5err(path: &Path) -> impl Fn(hdf5::Error) -> DataError + '_ {
    move |e| DataError::Hdf5 {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

pub(crate) fn write(path: &Path, record: &Record) -> Result<(), DataError> {
    let e = h5err(path);
    let file = hdf5::File::create(path).map_err(&e)?;
    for (name, values) in &record.arrays {
        let shape = record.shape_of(name).unwrap_or_else(|| vec![values.len()]);
        let view = ndarray::ArrayViewD::from_shape(ndarray::IxDyn(&shape), values.as_slice())
            .map_err(|err| DataError::InvalidContent {
                path: path.to_path_buf(),
                message: format!("array '{name}': {err}"),
            })?;
        file.new_dataset_builder()
            .with_data(view)
            .create(name.as_str())
            .map_err(&e)?;
    }
    for (name, value) in &record.attributes {
        match value {
            AttrValue::Float(v) => file
                .new_attr::<f64>()
                .create(name.as_str())
                .and_then(|a| a.write_scalar(v)),
            AttrValue::Int(v) => file
                .new_attr::<i64>()
                .create(name.as_str())
                .and_then(|a| a.write_scalar(v)),
            AttrValue::Text(v) => {
                let text: VarLenUnicode = v.parse().map_err(|err| DataError::InvalidContent {
                    path: path.to_path_buf(),
                    message: format!("attribute '{name}' is not storable text: {err}"),
                })?;
                file.new_attr::<VarLenUnicode>()
                    .create(name.as_str())
                    .and_then(|a| a.write_scalar(&text))
            }
        }
        .map_err(&e)?;
    }
    file.flush().map_err(&e)?;
    file.close().map_err(&e)
}

pub(crate) fn read(path: &Path, group: &str) -> Result<Record, DataError> {
    let e = h5err(path);
    if !path.exists() {
        return Err(DataError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"),
        });
    }
    let file = hdf5::File::open(path).map_err(&e)?;
    let file = if group == "/" || group.is_empty() {
        file.as_group().map_err(&e)?
    } else {
        file.group(group).map_err(|_| DataError::Missing {
            path: path.to_path_buf(),
            message: format!("no group '{group}'"),
        })?
    };
    let mut record = Record::default();
    let mut total = 0.0;
    for ds in file.datasets().map_err(&e)? {
        let name = ds.name().rsplit('/').next().unwrap_or_default().to_string();
        if ds.ndim() == 0 {
            return Err(DataError::WrongShape {
                path: path.to_path_buf(),
                name,
                expected: "at least 1 dimension".into(),
                got: ds.shape(),
            });
        }
        if ds.ndim() > 1 {
            record.shapes.push((name.clone(), ds.shape()));
        }
        check_dataset(&ds, path, &name, &mut total)?;
        let values: Vec<f64> = ds.read_raw::<f64>().map_err(|err| DataError::Format {
            path: path.to_path_buf(),
            message: format!("dataset '{name}' is not readable as float64: {err}"),
        })?;
        record.arrays.push((name, values));
    }
    for name in file.attr_names().map_err(&e)? {
        let attr = file.attr(&name).map_err(&e)?;
        let dtype = attr.dtype().map_err(&e)?;
        let value = if attr.ndim() > 0 {
            // Array attributes (e.g. a list of domain sizes) are kept as their text form.
            match attr.read_raw::<f64>() {
                Ok(v) => AttrValue::Text(format!("{v:?}")),
                Err(_) => AttrValue::Text(format!("<array attribute of type {dtype:?}>")),
            }
        } else if dtype.is::<f64>() {
            AttrValue::Float(attr.read_scalar::<f64>().map_err(&e)?)
        } else if dtype.is::<i64>() {
            AttrValue::Int(attr.read_scalar::<i64>().map_err(&e)?)
        } else if let Ok(text) = attr.read_scalar::<VarLenUnicode>() {
            AttrValue::Text(text.to_string())
        } else if let Ok(v) = attr.read_scalar::<f64>() {
            AttrValue::Float(v)
        } else {
            // h5py writes Python str as variable-length UTF-8; anything else is reported as such.
            AttrValue::Text(format!("<unreadable attribute of type {dtype:?}>"))
        };
        record.attributes.push((name, value));
    }
    Ok(record)
}

/// Checks a dataset before it is read: its shape's product must be countable, an unfiltered
/// dataset must store the bytes its shape announces (a crafted file cannot make the reader
/// allocate what is not there), and all datasets read so far must fit in memory.
fn check_dataset(
    ds: &hdf5::Dataset,
    path: &Path,
    name: &str,
    total: &mut f64,
) -> Result<(), DataError> {
    let bad = |message: String| DataError::Format {
        path: path.to_path_buf(),
        message: format!("dataset '{name}': {message}"),
    };
    let shape = ds.shape();
    let count = shape
        .iter()
        .try_fold(1u64, |n, &d| n.checked_mul(d as u64))
        .ok_or_else(|| {
            bad(format!(
                "shape {shape:?} has more values than can be counted"
            ))
        })?;
    let element = ds.dtype().map(|t| t.size() as u64).unwrap_or(8);
    let stored = ds.storage_size();
    if ds.filters().is_empty() && stored < count.saturating_mul(element) {
        return Err(bad(format!(
            "shape {shape:?} announces {} bytes, the file stores {stored}",
            count.saturating_mul(element)
        )));
    }
    *total += count as f64 * 8.0;
    crate::bounded::check_memory(*total, path, Some(name))
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_dataset_declaring_more_than_it_stores_is_refused_before_reading() {
        // A chunked dataset of 10¹¹ values with no chunk written: a few KB on disk; reading it
        // would allocate 800 GB of fill values.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("crafted.h5");
        let file = hdf5::File::create(&path).unwrap();
        file.new_dataset::<f64>()
            .chunk(1024)
            .shape(100_000_000_000usize)
            .create("huge")
            .unwrap();
        file.close().unwrap();
        let e = super::read(&path, "/").unwrap_err().to_string();
        assert!(e.contains("'huge'") && e.contains("stores"), "{e}");
    }
}
