//! Reads bounded before they allocate: every `.npy` header (a file, or a member of an `.npz`) is
//! parsed and checked against the bytes the file really holds and against the memory available
//! ([`halfspace_numerics::memory::available_bytes`]) before the array is allocated; text inputs
//! (TOML, JSON) are read up to a size limit. A crafted header claiming 10¹¹ values is refused with
//! one line naming the file, the member and the claim, instead of aborting in the allocator.

use std::io::Read;
use std::path::Path;

use crate::DataError;

/// The largest `.npy` header accepted (NumPy writes a few hundred bytes; format 1.0 allows 64 KiB).
const MAX_HEADER_BYTES: usize = 1 << 20;

/// The element type of an array: little-endian float64 (`<f8`) or bytes (`|u1`, the metadata).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Dtype {
    F8,
    U1,
}

impl Dtype {
    fn size(self) -> u64 {
        match self {
            Dtype::F8 => 8,
            Dtype::U1 => 1,
        }
    }
}

/// A parsed `.npy` header.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct NpyHeader {
    pub dtype: Dtype,
    pub fortran_order: bool,
    pub shape: Vec<usize>,
    /// Bytes of the magic, version, length and header text (where the data starts).
    pub header_bytes: u64,
}

impl NpyHeader {
    /// Number of values (the product of the shape, checked).
    pub fn count(&self) -> Option<u64> {
        self.shape
            .iter()
            .try_fold(1u64, |n, &d| n.checked_mul(d as u64))
    }

    /// Bytes of the data the header announces.
    pub fn data_bytes(&self) -> Option<u64> {
        self.count()?.checked_mul(self.dtype.size())
    }
}

fn format_error(path: &Path, member: Option<&str>, message: impl std::fmt::Display) -> DataError {
    DataError::Format {
        path: path.to_path_buf(),
        message: match member {
            Some(m) => format!("member '{m}': {message}"),
            None => message.to_string(),
        },
    }
}

/// The value of `'key': value` in a NumPy header dict (up to the next top-level comma or brace).
fn header_value<'a>(text: &'a str, key: &str) -> Option<&'a str> {
    let at = text
        .find(&format!("'{key}'"))
        .or_else(|| text.find(&format!("\"{key}\"")))?;
    let rest = text[at + key.len() + 2..].trim_start().strip_prefix(':')?;
    let rest = rest.trim_start();
    let end = if rest.starts_with('(') {
        rest.find(')').map(|e| e + 1)?
    } else {
        rest.find([',', '}']).unwrap_or(rest.len())
    };
    Some(rest[..end].trim())
}

/// Parses the header of a `.npy` stream (magic, version, header dict), reading only the header.
pub(crate) fn read_header(
    reader: &mut impl Read,
    path: &Path,
    member: Option<&str>,
) -> Result<NpyHeader, DataError> {
    let bad = |m: String| format_error(path, member, m);
    let io = |source: std::io::Error| match source.kind() {
        std::io::ErrorKind::UnexpectedEof => bad("not a valid .npy file: truncated header".into()),
        _ => DataError::Io {
            path: path.to_path_buf(),
            source,
        },
    };
    let mut magic = [0u8; 8];
    reader.read_exact(&mut magic).map_err(io)?;
    if &magic[..6] != b"\x93NUMPY" {
        return Err(bad("not a valid .npy file: no \\x93NUMPY magic".into()));
    }
    let (len, prefix) = match magic[6] {
        1 => {
            let mut b = [0u8; 2];
            reader.read_exact(&mut b).map_err(io)?;
            (u16::from_le_bytes(b) as usize, 10u64)
        }
        2 | 3 => {
            let mut b = [0u8; 4];
            reader.read_exact(&mut b).map_err(io)?;
            (u32::from_le_bytes(b) as usize, 12u64)
        }
        v => return Err(bad(format!("not a valid .npy file: format version {v}"))),
    };
    if len > MAX_HEADER_BYTES {
        return Err(bad(format!(
            "not a valid .npy file: header of {len} bytes (at most {MAX_HEADER_BYTES})"
        )));
    }
    let mut text = vec![0u8; len];
    reader.read_exact(&mut text).map_err(io)?;
    let text = String::from_utf8(text)
        .map_err(|_| bad("not a valid .npy file: header is not text".into()))?;
    let descr = header_value(&text, "descr")
        .ok_or_else(|| bad("not a valid .npy file: header has no 'descr'".into()))?
        .trim_matches(['\'', '"']);
    let dtype = match descr {
        "<f8" | "f8" | "<d" => Dtype::F8,
        "|u1" | "<u1" | "u1" | "|b1" => Dtype::U1,
        other => {
            return Err(bad(format!(
                "wrong dtype '{other}': expected little-endian float64 ('<f8')"
            )))
        }
    };
    let fortran_order = match header_value(&text, "fortran_order") {
        Some("False") => false,
        Some("True") => true,
        other => {
            return Err(bad(format!(
                "not a valid .npy file: fortran_order is {other:?}"
            )))
        }
    };
    let shape_text = header_value(&text, "shape")
        .ok_or_else(|| bad("not a valid .npy file: header has no 'shape'".into()))?;
    let inner = shape_text
        .strip_prefix('(')
        .and_then(|s| s.strip_suffix(')'))
        .ok_or_else(|| bad(format!("not a valid .npy file: shape {shape_text}")))?;
    let shape = inner
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|d| {
            d.trim_end_matches('L').parse::<usize>().map_err(|_| {
                bad(format!(
                    "not a valid .npy file: shape {shape_text} (dimension '{d}')"
                ))
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    if shape.len() > 32 {
        return Err(bad(format!(
            "not a valid .npy file: {} dimensions",
            shape.len()
        )));
    }
    Ok(NpyHeader {
        dtype,
        fortran_order,
        shape,
        header_bytes: prefix + len as u64,
    })
}

/// Checks that the data a header announces is what the file holds (`available` bytes after the
/// header) and fits in memory (`copies` arrays of its size at once), before anything is allocated.
pub(crate) fn check_claim(
    header: &NpyHeader,
    available: u64,
    copies: f64,
    path: &Path,
    member: Option<&str>,
) -> Result<u64, DataError> {
    let bad = |m: String| format_error(path, member, m);
    let bytes = header.data_bytes().ok_or_else(|| {
        bad(format!(
            "header claims shape {:?}: more values than can be counted",
            header.shape
        ))
    })?;
    if bytes != available {
        return Err(bad(format!(
            "header claims shape {:?} ({bytes} bytes of data), the file holds {available} bytes \
             after the header",
            header.shape
        )));
    }
    check_memory(bytes as f64 * copies, path, member)?;
    Ok(bytes)
}

/// Refuses reading `bytes` when they exceed the memory available.
pub(crate) fn check_memory(bytes: f64, path: &Path, member: Option<&str>) -> Result<(), DataError> {
    if let Some(available) = halfspace_numerics::memory::available_bytes() {
        if bytes > available {
            const GIB: f64 = 1024.0 * 1024.0 * 1024.0;
            return Err(format_error(
                path,
                member,
                format!(
                    "reading it needs about {:.3} GiB, {:.3} GiB are available",
                    bytes / GIB,
                    available / GIB
                ),
            ));
        }
    }
    Ok(())
}

/// Reads the data of a checked header as float64 values in C order.
pub(crate) fn read_f64(
    reader: &mut impl Read,
    header: &NpyHeader,
    path: &Path,
    member: Option<&str>,
) -> Result<Vec<f64>, DataError> {
    let count = header.count().unwrap_or(0) as usize;
    let io = |source: std::io::Error| DataError::Io {
        path: path.to_path_buf(),
        source,
    };
    let values = match header.dtype {
        Dtype::F8 => {
            let mut values = Vec::with_capacity(count);
            let mut chunk = vec![0u8; 8 * 8192];
            let mut left = count;
            while left > 0 {
                let take = left.min(8192);
                let buf = &mut chunk[..8 * take];
                reader.read_exact(buf).map_err(io)?;
                values.extend(
                    buf.chunks_exact(8)
                        .map(|b| f64::from_le_bytes(b.try_into().unwrap_or([0; 8]))),
                );
                left -= take;
            }
            values
        }
        Dtype::U1 => {
            return Err(format_error(
                path,
                member,
                "wrong dtype: bytes where float64 ('<f8') was expected",
            ))
        }
    };
    Ok(if header.fortran_order && header.shape.len() > 1 {
        fortran_to_c(&values, &header.shape)
    } else {
        values
    })
}

/// Reads the data of a checked `|u1` header.
pub(crate) fn read_bytes(
    reader: &mut impl Read,
    header: &NpyHeader,
    path: &Path,
    member: Option<&str>,
) -> Result<Vec<u8>, DataError> {
    if header.dtype != Dtype::U1 {
        return Err(format_error(path, member, "expected bytes ('|u1')"));
    }
    let mut bytes = vec![0u8; header.count().unwrap_or(0) as usize];
    reader
        .read_exact(&mut bytes)
        .map_err(|source| DataError::Io {
            path: path.to_path_buf(),
            source,
        })?;
    Ok(bytes)
}

/// Column-major values of `shape` in row-major order.
fn fortran_to_c(values: &[f64], shape: &[usize]) -> Vec<f64> {
    let mut out = vec![0.0; values.len()];
    let mut index = vec![0usize; shape.len()];
    for v in out.iter_mut() {
        // Fortran offset of the current C multi-index.
        let mut offset = 0;
        let mut stride = 1;
        for (i, &n) in index.iter().zip(shape) {
            offset += i * stride;
            stride *= n;
        }
        *v = values[offset];
        for d in (0..shape.len()).rev() {
            index[d] += 1;
            if index[d] < shape[d] {
                break;
            }
            index[d] = 0;
        }
    }
    out
}

/// Reads a text file (TOML, JSON) of at most `limit` bytes, refusing a larger one (or an endless
/// stream) before reading it whole.
pub fn read_text_bounded(path: &Path, limit: u64) -> Result<String, DataError> {
    let io = |source| DataError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::new();
    file.take(limit + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(DataError::Format {
            path: path.to_path_buf(),
            message: format!("larger than {limit} bytes: not a configuration or checkpoint file"),
        });
    }
    String::from_utf8(bytes).map_err(|_| DataError::Format {
        path: path.to_path_buf(),
        message: "not UTF-8 text".into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn npy(header: &str, data: &[u8]) -> Vec<u8> {
        let mut h = header.to_string();
        while (10 + h.len() + 1) % 64 != 0 {
            h.push(' ');
        }
        h.push('\n');
        let mut out = b"\x93NUMPY\x01\x00".to_vec();
        out.extend((h.len() as u16).to_le_bytes());
        out.extend(h.as_bytes());
        out.extend(data);
        out
    }

    #[test]
    fn a_header_claiming_1e11_values_is_refused_before_allocating() {
        let bytes = npy(
            "{'descr': '<f8', 'fortran_order': False, 'shape': (100000000000, 2), }",
            &[0u8; 16],
        );
        let path = Path::new("F.npy");
        let h = read_header(&mut bytes.as_slice(), path, None).unwrap();
        assert_eq!(h.shape, vec![100_000_000_000, 2]);
        let e = check_claim(&h, 16, 1.0, path, None)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("header claims shape") && e.contains("16 bytes"),
            "{e}"
        );
    }

    #[test]
    fn overflowing_shapes_and_bad_headers_are_refused() {
        let path = Path::new("F.npy");
        let h = npy(
            "{'descr': '<f8', 'fortran_order': False, 'shape': (18446744073709551615, 3), }",
            &[],
        );
        let h = read_header(&mut h.as_slice(), path, None).unwrap();
        assert!(check_claim(&h, 0, 1.0, path, None).is_err());
        for header in [
            "{'descr': '<i8', 'fortran_order': False, 'shape': (2,), }",
            "{'descr': '<f8', 'fortran_order': Maybe, 'shape': (2,), }",
            "{'descr': '<f8', 'fortran_order': False, 'shape': (-2,), }",
            "{'descr': '<f8', 'fortran_order': False}",
        ] {
            let b = npy(header, &[0u8; 16]);
            assert!(
                read_header(&mut b.as_slice(), path, None).is_err(),
                "{header}"
            );
        }
        assert!(read_header(&mut &b"\x93NUMPY\x01"[..], path, None).is_err());
    }

    #[test]
    fn fortran_order_is_read_in_c_order() {
        // [[1, 2, 3], [4, 5, 6]] stored column-major.
        let c = fortran_to_c(&[1.0, 4.0, 2.0, 5.0, 3.0, 6.0], &[2, 3]);
        assert_eq!(c, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    }
}
