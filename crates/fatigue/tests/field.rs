//! The field evaluator: equal to the per-point criteria, serial = parallel bit for bit, argmax,
//! shape and input errors.
mod common;

use common::{random_cycle, steel, Rng};
use halfspace_fatigue::critical_plane::{fatemi_socie, swt, PlaneScratch};
use halfspace_fatigue::invariant::{crossland_dang_van, InvariantScratch};
use halfspace_fatigue::{evaluate_field, FatigueError, FieldParams, Voigt};

fn field(points: usize, increments: usize) -> (Vec<f64>, Vec<Vec<Voigt>>) {
    let mut rng = Rng::new(2240);
    let paths: Vec<Vec<Voigt>> = (0..points)
        .map(|_| random_cycle(&mut rng, increments, 1e8, 1e8))
        .collect();
    let flat = paths.iter().flatten().flatten().copied().collect();
    (flat, paths)
}

#[test]
fn field_equals_per_point_criteria() {
    let (points, increments) = (37, 16);
    let (flat, paths) = field(points, increments);
    let m = steel();
    let serial = FieldParams {
        parallel: false,
        ..Default::default()
    };
    let a = evaluate_field(&flat, points, increments, &m, &serial).unwrap();
    let b = evaluate_field(&flat, points, increments, &m, &FieldParams::default()).unwrap();
    assert_eq!(a, b, "serial and parallel differ");
    let (mut inv, mut pl) = (InvariantScratch::default(), PlaneScratch::default());
    for (p, path) in paths.iter().enumerate() {
        let (c, dv) = crossland_dang_van(path, &m, &mut inv).unwrap();
        let s = swt(path, &m, &serial.plane, &mut pl).unwrap();
        let f = fatemi_socie(path, &m, &serial.plane, &mut pl).unwrap();
        assert_eq!(a.crossland[p], c.index);
        assert_eq!(a.dang_van[p], dv.index);
        assert_eq!(a.swt[p], s.value);
        assert_eq!(a.fatemi_socie[p], f.value);
        assert_eq!(a.swt_normal[p], s.normal);
        assert_eq!(a.fatemi_socie_normal[p], f.normal);
        assert_eq!(a.fatemi_socie_direction[p], f.direction);
    }
    for (max, values) in [
        (a.crossland_max, &a.crossland),
        (a.dang_van_max, &a.dang_van),
        (a.swt_max, &a.swt),
        (a.fatemi_socie_max, &a.fatemi_socie),
    ] {
        assert_eq!(max.value, values[max.point]);
        assert!(values.iter().all(|&v| v <= max.value));
    }
}

#[test]
fn field_input_errors() {
    let (flat, _) = field(3, 4);
    let m = steel();
    let p = FieldParams::default();
    assert!(matches!(
        evaluate_field(&flat, 3, 5, &m, &p),
        Err(FatigueError::FieldShape {
            len: 72,
            points: 3,
            increments: 5
        })
    ));
    assert!(matches!(
        evaluate_field(&flat, usize::MAX, usize::MAX, &m, &p),
        Err(FatigueError::FieldShape { .. })
    ));
    assert_eq!(
        evaluate_field(&[], 0, 4, &m, &p).unwrap_err(),
        FatigueError::EmptyPath
    );
    let mut bad = flat.clone();
    bad[2 * 24 + 3 * 6 + 5] = f64::INFINITY;
    assert!(matches!(
        evaluate_field(&bad, 3, 4, &m, &p),
        Err(FatigueError::NonFiniteField {
            point: 2,
            increment: 3,
            component: 5,
            ..
        })
    ));
    let m2 = halfspace_fatigue::Material { poisson: 0.7, ..m };
    assert!(matches!(
        evaluate_field(&flat, 3, 4, &m2, &p),
        Err(FatigueError::InvalidMaterial {
            name: "poisson",
            ..
        })
    ));
}
