//! XDMF (eXtensible Data Model and Format, version 3) descriptions of volume fields stored in an
//! HDF5 file, so that ParaView or VisIt open the volume directly: a `3DCoRectMesh` (uniform
//! lattice of the cell centres) with one scalar attribute per dataset.

use std::fmt::Write as _;
use std::path::Path;

use crate::{write_atomic, DataError};

/// A uniform lattice of `dims = (n_slow, n_mid, n_fast)` points with `origin` and `spacing` in the
/// same order (XDMF's `Z Y X` order).
#[derive(Debug, Clone, PartialEq)]
pub struct UniformVolume {
    /// Points per axis, slowest first.
    pub dims: [usize; 3],
    /// Coordinates of the first point, slowest axis first.
    pub origin: [f64; 3],
    /// Spacing, slowest axis first.
    pub spacing: [f64; 3],
}

/// A rectilinear lattice of `dims = (n_slow, n_mid, n_fast)` points whose coordinates along each
/// axis are the 1D datasets `axes` (slowest first, of lengths `dims`) of the same HDF5 file
/// (XDMF's `3DRectMesh` with `VXVYVZ` geometry: unequal spacings, e.g. a surface layer above
/// uniformly spaced layers).
#[derive(Debug, Clone, PartialEq)]
pub struct RectilinearVolume {
    /// Points per axis, slowest first.
    pub dims: [usize; 3],
    /// Names of the coordinate datasets, slowest axis first.
    pub axes: [String; 3],
}

/// Writes `xdmf_path` describing the datasets `fields` (each of shape `dims`, C order) of the HDF5
/// file `h5_path` on the lattice `volume` whose coordinates are datasets of that file
/// ([`RectilinearVolume`]). Atomic.
pub fn write_xdmf_rectilinear(
    xdmf_path: &Path,
    h5_path: &Path,
    volume: &RectilinearVolume,
    fields: &[&str],
    note: &str,
) -> Result<(), DataError> {
    let d = volume.dims;
    let (mut x, h5_name, dims) = header(note, h5_path, "3DRectMesh", d);
    let _ = writeln!(x, r#"      <Geometry GeometryType="VXVYVZ">"#);
    // X is the fastest axis.
    for k in [2, 1, 0] {
        let _ = writeln!(
            x,
            r#"        <DataItem Dimensions="{}" NumberType="Float" Precision="8" Format="HDF">{h5_name}:/{}</DataItem>"#,
            d[k], volume.axes[k]
        );
    }
    let _ = writeln!(x, "      </Geometry>");
    finish(xdmf_path, x, &h5_name, &dims, fields)
}

fn file_name(h5_path: &Path) -> String {
    h5_path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// The document up to the grid's topology (`topology` of `dims` points, slowest first), the HDF5
/// file's name as the datasets reference it, and the dimensions as XDMF writes them.
fn header(
    note: &str,
    h5_path: &Path,
    topology: &str,
    dims: [usize; 3],
) -> (String, String, String) {
    let dims = format!("{} {} {}", dims[0], dims[1], dims[2]);
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" ?>"#);
    let _ = writeln!(x, r#"<Xdmf Version="3.0">"#);
    let _ = writeln!(x, "  <!-- {} -->", note.replace("--", "-"));
    let _ = writeln!(x, "  <Domain>");
    let _ = writeln!(x, r#"    <Grid Name="volume" GridType="Uniform">"#);
    let _ = writeln!(
        x,
        r#"      <Topology TopologyType="{topology}" Dimensions="{dims}"/>"#
    );
    (x, file_name(h5_path), dims)
}

/// Writes `xdmf_path` describing the datasets `fields` (each of shape `dims`, C order) of the HDF5
/// file `h5_path` (referenced by file name, so the two files travel together). Atomic.
pub fn write_xdmf(
    xdmf_path: &Path,
    h5_path: &Path,
    volume: &UniformVolume,
    fields: &[&str],
    note: &str,
) -> Result<(), DataError> {
    let (mut x, h5_name, dims) = header(note, h5_path, "3DCoRectMesh", volume.dims);
    let _ = writeln!(x, r#"      <Geometry GeometryType="ORIGIN_DXDYDZ">"#);
    let o = volume.origin;
    let s = volume.spacing;
    let _ = writeln!(
        x,
        r#"        <DataItem Dimensions="3" Format="XML">{:e} {:e} {:e}</DataItem>"#,
        o[0], o[1], o[2]
    );
    let _ = writeln!(
        x,
        r#"        <DataItem Dimensions="3" Format="XML">{:e} {:e} {:e}</DataItem>"#,
        s[0], s[1], s[2]
    );
    let _ = writeln!(x, "      </Geometry>");
    finish(xdmf_path, x, &h5_name, &dims, fields)
}

/// The attributes and the closing tags, written atomically.
fn finish(
    xdmf_path: &Path,
    mut x: String,
    h5_name: &str,
    dims: &str,
    fields: &[&str],
) -> Result<(), DataError> {
    for f in fields {
        let _ = writeln!(
            x,
            r#"      <Attribute Name="{f}" AttributeType="Scalar" Center="Node">"#
        );
        let _ = writeln!(
            x,
            r#"        <DataItem Dimensions="{dims}" NumberType="Float" Precision="8" Format="HDF">{h5_name}:/{f}</DataItem>"#
        );
        let _ = writeln!(x, "      </Attribute>");
    }
    let _ = writeln!(x, "    </Grid>");
    let _ = writeln!(x, "  </Domain>");
    let _ = writeln!(x, "</Xdmf>");
    write_atomic(xdmf_path, |tmp| {
        std::fs::write(tmp, x.as_bytes()).map_err(|source| DataError::Io {
            path: tmp.to_path_buf(),
            source,
        })
    })
}
