use halfspace_data::{read_profile_table, read_record, write_record, AttrValue, DataError, Record};
use ndarray::{arr2, Array1};
use ndarray_npy::WriteNpyExt;

fn sample() -> Record {
    Record::default()
        .array("r", vec![0.0, 0.5, 1.0])
        .array("pressure", vec![1.0, 0.5, 0.0])
        .attr("e_star", AttrValue::Float(2.3e11))
        .attr("n", AttrValue::Int(3))
        .attr("profile", AttrValue::Text("sphere:R=1.05e-4 µm".into()))
}

#[test]
fn npz_round_trip_keeps_arrays_and_metadata() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.npz");
    write_record(&path, &sample()).unwrap();
    let back = read_record(&path).unwrap();
    assert_eq!(back.get("r").unwrap(), &[0.0, 0.5, 1.0]);
    assert_eq!(back.get("pressure").unwrap(), &[1.0, 0.5, 0.0]);
    assert_eq!(back.get_attr("e_star"), Some(&AttrValue::Float(2.3e11)));
    assert_eq!(back.get_attr("n"), Some(&AttrValue::Int(3)));
    // No temporary file left behind.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[cfg(feature = "hdf5")]
#[test]
fn h5_round_trip_keeps_arrays_and_attributes() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.h5");
    write_record(&path, &sample()).unwrap();
    let back = read_record(&path).unwrap();
    assert_eq!(back.get("r").unwrap(), &[0.0, 0.5, 1.0]);
    assert_eq!(back.get_attr("e_star"), Some(&AttrValue::Float(2.3e11)));
    assert_eq!(back.get_attr("n"), Some(&AttrValue::Int(3)));
    assert_eq!(
        back.get_attr("profile"),
        Some(&AttrValue::Text("sphere:R=1.05e-4 µm".into()))
    );
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn profile_tables_are_read_and_bad_ones_named() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("t.npy");
    arr2(&[[0.0, 0.0], [1.0, 0.5], [2.0, 2.0]])
        .write_npy(std::fs::File::create(&good).unwrap())
        .unwrap();
    let (r, f) = read_profile_table(&good).unwrap();
    assert_eq!(r, vec![0.0, 1.0, 2.0]);
    assert_eq!(f, vec![0.0, 0.5, 2.0]);

    let shape = dir.path().join("shape.npy");
    arr2(&[[0.0, 0.0, 1.0]])
        .write_npy(std::fs::File::create(&shape).unwrap())
        .unwrap();
    assert!(matches!(
        read_profile_table(&shape),
        Err(DataError::WrongShape { .. })
    ));

    let dtype = dir.path().join("dtype.npy");
    arr2(&[[0i32, 0], [1, 1]])
        .write_npy(std::fs::File::create(&dtype).unwrap())
        .unwrap();
    let e = read_profile_table(&dtype).unwrap_err();
    assert!(e.to_string().contains("dtype"), "{e}");

    let one_d = dir.path().join("1d.npy");
    Array1::from(vec![0.0, 1.0])
        .write_npy(std::fs::File::create(&one_d).unwrap())
        .unwrap();
    assert!(read_profile_table(&one_d).is_err());

    let missing = dir.path().join("missing.npy");
    let e = read_profile_table(&missing).unwrap_err();
    assert!(e.to_string().contains("missing.npy"), "{e}");
}

#[test]
fn unknown_extension_and_missing_directory_are_errors() {
    assert!(matches!(
        write_record(std::path::Path::new("x.csv"), &sample()),
        Err(DataError::UnknownFormat { .. })
    ));
    assert!(write_record(std::path::Path::new("/nonexistent-dir/x.npz"), &sample()).is_err());
}

#[test]
fn float_attributes_round_trip_bit_for_bit() {
    // Checkpoints rely on it: a resumed run must continue from exactly the saved numbers.
    let dir = tempfile::tempdir().unwrap();
    let values = [
        1.0 / 3.0,
        1.1353237423748348,
        2.0f64.sqrt(),
        1e-300,
        6.02214076e23,
    ];
    for ext in ["npz", "h5"] {
        let path = dir.path().join(format!("f.{ext}"));
        let mut rec = Record::default().array("x", values.to_vec());
        for (i, v) in values.iter().enumerate() {
            rec = rec.attr(&format!("v{i}"), AttrValue::Float(*v));
        }
        write_record(&path, &rec).unwrap();
        let back = read_record(&path).unwrap();
        for (i, v) in values.iter().enumerate() {
            match back.get_attr(&format!("v{i}")) {
                Some(AttrValue::Float(b)) => assert_eq!(b.to_bits(), v.to_bits(), "{ext} v{i}"),
                other => panic!("{other:?}"),
            }
        }
    }
}

#[test]
fn shaped_arrays_keep_their_shape_in_both_formats_and_bad_shapes_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let values: Vec<f64> = (0..24).map(f64::from).collect();
    let rec = Record::default().shaped("volume", values.clone(), &[2, 3, 4]);
    let mut exts = vec!["npz"];
    if cfg!(feature = "hdf5") {
        exts.push("h5");
    }
    for ext in exts {
        let path = dir.path().join(format!("v.{ext}"));
        write_record(&path, &rec).unwrap();
        let back = read_record(&path).unwrap();
        assert_eq!(back.get("volume").unwrap(), values.as_slice(), "{ext}");
        assert_eq!(back.shape_of("volume").unwrap(), vec![2, 3, 4], "{ext}");
    }
    let bad = Record::default().shaped("volume", values, &[5, 5]);
    let err = write_record(&dir.path().join("bad.npz"), &bad).unwrap_err();
    assert!(err.to_string().contains("shape"), "{err}");
}

#[test]
fn xdmf_describes_the_volume_datasets() {
    let dir = tempfile::tempdir().unwrap();
    let xdmf = dir.path().join("v.xdmf");
    let volume = halfspace_data::UniformVolume {
        dims: [2, 3, 4],
        origin: [0.5, -1.0, -1.5],
        spacing: [1.0, 1.0, 1.0],
    };
    halfspace_data::write_xdmf(
        &xdmf,
        &dir.path().join("v.h5"),
        &volume,
        &["von_mises"],
        "test",
    )
    .unwrap();
    let text = std::fs::read_to_string(&xdmf).unwrap();
    assert!(text.contains(r#"TopologyType="3DCoRectMesh" Dimensions="2 3 4""#));
    assert!(text.contains("v.h5:/von_mises"));
}

#[test]
fn xdmf_describes_a_rectilinear_volume_on_coordinate_datasets() {
    let dir = tempfile::tempdir().unwrap();
    let xdmf = dir.path().join("r.xdmf");
    let volume = halfspace_data::RectilinearVolume {
        dims: [3, 4, 5],
        axes: ["z".into(), "x".into(), "y".into()],
    };
    halfspace_data::write_xdmf_rectilinear(
        &xdmf,
        &dir.path().join("r.h5"),
        &volume,
        &["crossland"],
        "test",
    )
    .unwrap();
    let text = std::fs::read_to_string(&xdmf).unwrap();
    assert!(text.contains(r#"TopologyType="3DRectMesh" Dimensions="3 4 5""#));
    // VXVYVZ: the fastest axis first.
    let (vx, vy, vz) = (
        text.find("r.h5:/y").unwrap(),
        text.find("r.h5:/x").unwrap(),
        text.find("r.h5:/z").unwrap(),
    );
    assert!(vx < vy && vy < vz);
    assert!(text.contains(
        r#"<DataItem Dimensions="5" NumberType="Float" Precision="8" Format="HDF">r.h5:/y"#
    ));
    assert!(text.contains("r.h5:/crossland"));
}
