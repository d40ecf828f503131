//! The stress history averaged over a process volume (docs/fatigue.md, "Process volume"): exact
//! on linear fields, equal to a brute-force cubature of the trilinear interpolant over the cube
//! (fixed seeds), the pointwise indices for a spatially constant path, typed refusals.
mod common;

use common::Rng;
use halfspace_fatigue::field::evaluate_field;
use halfspace_fatigue::{
    average_over_volume, evaluate_process_volume, BoxNodes, FatigueError, FieldParams, Material,
    VolumeParams,
};

/// The fretting loop's box: N₁ × N₂ cells of side `h` centred about 0, layers at depth
/// `(2k + 1) h/2` and the surface layer `z = 0` stored last.
fn loop_box(n1: usize, n2: usize, layers: usize, h: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let axis = |n: usize| -> Vec<f64> {
        (0..n)
            .map(|i| (i as f64 + 0.5) * h - 0.5 * n as f64 * h)
            .collect()
    };
    let mut depth: Vec<f64> = (0..layers).map(|k| (k as f64 + 0.5) * h).collect();
    depth.push(0.0);
    (axis(n1), axis(n2), depth)
}

fn material() -> Material {
    Material {
        f_minus1: 400e6,
        t_minus1: 280e6,
        young: 210e9,
        poisson: 0.3,
        fs_k: 0.5,
        yield_stress: 600e6,
    }
}

/// The window of one axis (the module's definition, written again).
fn window(u: f64, side: f64, top: bool) -> (f64, f64) {
    let a = if top {
        (u - side / 2.0).max(0.0)
    } else {
        u - side / 2.0
    };
    (a, a + side)
}

/// `(1/ℓ) ∫_a^b f(u) du` of the piecewise-linear interpolant of node values, brute force: the
/// window split at every node, two-point Gauss on each piece (exact for a linear piece), the
/// interpolant evaluated by locating each Gauss point.
fn brute_weights(nodes: &[f64], a: f64, b: f64) -> Vec<f64> {
    let mut cuts = vec![a];
    cuts.extend(nodes.iter().copied().filter(|&u| u > a && u < b));
    cuts.push(b);
    let g = 0.5 / 3f64.sqrt();
    let mut w = vec![0.0; nodes.len()];
    for pair in cuts.windows(2) {
        let (lo, hi) = (pair[0], pair[1]);
        for s in [0.5 - g, 0.5 + g] {
            let u = lo + s * (hi - lo);
            let m = nodes
                .iter()
                .rposition(|&v| v <= u)
                .unwrap()
                .min(nodes.len() - 2);
            let t = (u - nodes[m]) / (nodes[m + 1] - nodes[m]);
            let weight = 0.5 * (hi - lo) / (b - a);
            w[m] += weight * (1.0 - t);
            w[m + 1] += weight * t;
        }
    }
    w
}

/// A field linear in x, y, z and the increment is averaged exactly: the average is the value at
/// the volume's centre `(x, y, max(z, ℓ/2))`, for sides cutting cells anywhere (seeded).
#[test]
fn a_linear_field_is_averaged_exactly() {
    let mut rng = Rng::new(22);
    let (n1, n2, layers, h) = (9, 7, 6, 0.1);
    let (x, y, depth) = loop_box(n1, n2, layers, h);
    let nodes = BoxNodes {
        x: &x,
        y: &y,
        depth: &depth,
    };
    let increments = 3;
    for round in 0..6 {
        let side = rng.range(h, 0.55);
        let coef: Vec<[f64; 5]> = (0..6)
            .map(|_| std::array::from_fn(|_| rng.range(-1.0, 1.0)))
            .collect();
        let value = |p: [f64; 3], t: usize, c: usize| {
            let k = &coef[c];
            k[0] + k[1] * p[0] + k[2] * p[1] + k[3] * p[2] + k[4] * t as f64
        };
        let per = n1 * n2;
        let mut stress = vec![0.0; depth.len() * per * increments * 6];
        for (p, chunk) in stress.chunks_exact_mut(increments * 6).enumerate() {
            let at = [x[(p % per) / n2], y[p % n2], depth[p / per]];
            for t in 0..increments {
                for c in 0..6 {
                    chunk[t * 6 + c] = value(at, t, c);
                }
            }
        }
        let inside = average_over_volume(&mut stress, increments, &nodes, side).unwrap();
        let mut checked = 0;
        for (p, chunk) in stress.chunks_exact(increments * 6).enumerate() {
            if !inside[p] {
                continue;
            }
            checked += 1;
            let at = [x[(p % per) / n2], y[p % n2], depth[p / per].max(side / 2.0)];
            for t in 0..increments {
                for c in 0..6 {
                    let want = value(at, t, c);
                    assert!(
                        (chunk[t * 6 + c] - want).abs() < 1e-13,
                        "round {round}, side {side}, point {p}: {} vs {want}",
                        chunk[t * 6 + c]
                    );
                }
            }
        }
        assert!(checked > 0, "round {round}: no point inside");
    }
}

/// Random node values (seeded): the three banded passes equal the brute-force cubature of the
/// trilinear interpolant over each point's cube, and the points inside are exactly those whose
/// cube lies in the nodes.
#[test]
fn the_average_is_the_brute_force_cubature_of_the_interpolant() {
    let mut rng = Rng::new(7);
    let (n1, n2, layers, h) = (8, 7, 5, 0.2);
    let (x, y, depth) = loop_box(n1, n2, layers, h);
    let nodes = BoxNodes {
        x: &x,
        y: &y,
        depth: &depth,
    };
    let mut sorted = depth.clone();
    sorted.sort_by(f64::total_cmp);
    let increments = 2;
    let block = increments * 6;
    let per = n1 * n2;
    for side in [0.2, 0.37, 0.61, 0.79] {
        let original: Vec<f64> = (0..depth.len() * per * block)
            .map(|_| rng.range(-1.0, 1.0))
            .collect();
        let mut stress = original.clone();
        let inside = average_over_volume(&mut stress, increments, &nodes, side).unwrap();
        let mut checked = 0;
        for p in 0..depth.len() * per {
            let (k, i, j) = (p / per, (p % per) / n2, p % n2);
            let (ax, bx) = window(x[i], side, false);
            let (ay, by) = window(y[j], side, false);
            let (az, bz) = window(depth[k], side, true);
            let slack = 1e-12;
            let fits = ax >= x[0] - slack
                && bx <= x[n1 - 1] + slack
                && ay >= y[0] - slack
                && by <= y[n2 - 1] + slack
                && az >= -slack
                && bz <= sorted[sorted.len() - 1] + slack;
            assert_eq!(inside[p], fits, "side {side}, point {p}");
            if !fits {
                continue;
            }
            checked += 1;
            let (wx, wy, wz) = (
                brute_weights(&x, ax, bx),
                brute_weights(&y, ay, by),
                brute_weights(&sorted, az, bz),
            );
            for e in 0..block {
                let mut want = 0.0;
                for (r, &w3) in wz.iter().enumerate() {
                    if w3 == 0.0 {
                        continue;
                    }
                    let level = depth.iter().position(|&d| d == sorted[r]).unwrap();
                    for (a, &w1) in wx.iter().enumerate() {
                        for (b, &w2) in wy.iter().enumerate() {
                            want += w1 * w2 * w3 * original[(level * per + a * n2 + b) * block + e];
                        }
                    }
                }
                let got = stress[p * block + e];
                assert!(
                    (got - want).abs() < 1e-13,
                    "side {side}, point {p}, entry {e}: {got} vs {want}"
                );
            }
        }
        assert!(checked > 0);
    }
}

/// The average is continuous in the side: a change of `1e-9 h` moves it by `O(1e-9)`.
#[test]
fn the_average_is_continuous_in_the_side() {
    let mut rng = Rng::new(3);
    let (x, y, depth) = loop_box(7, 7, 5, 1.0);
    let nodes = BoxNodes {
        x: &x,
        y: &y,
        depth: &depth,
    };
    let original: Vec<f64> = (0..depth.len() * 49 * 6)
        .map(|_| rng.range(-1.0, 1.0))
        .collect();
    // Sides at node spacings (2 h, 3 h): where a cut crosses a node.
    for side in [2.0, 3.0, 2.5] {
        let mut a = original.clone();
        let mut b = original.clone();
        let ia = average_over_volume(&mut a, 1, &nodes, side).unwrap();
        let ib = average_over_volume(&mut b, 1, &nodes, side + 1e-9).unwrap();
        for p in 0..ia.len() {
            if ia[p] && ib[p] {
                for e in 0..6 {
                    assert!((a[p * 6 + e] - b[p * 6 + e]).abs() < 1e-8, "side {side}");
                }
            }
        }
    }
}

/// A spatially constant history: every point inside gets the pointwise indices of that path
/// (to rounding of the weights' sum), and the maxima are at points inside.
#[test]
fn a_constant_path_gives_the_pointwise_indices() {
    let mut rng = Rng::new(11);
    let (n1, n2, layers, h) = (6, 6, 4, 1e-6);
    let (x, y, depth) = loop_box(n1, n2, layers, h);
    let nodes = BoxNodes {
        x: &x,
        y: &y,
        depth: &depth,
    };
    let increments = 9;
    let path: Vec<f64> = (0..increments * 6)
        .map(|_| rng.range(-300e6, 300e6))
        .collect();
    let points = depth.len() * n1 * n2;
    let stress: Vec<f64> = (0..points).flat_map(|_| path.iter().copied()).collect();
    let m = material();
    let pointwise = evaluate_field(&path, 1, increments, &m, &FieldParams::default()).unwrap();
    let got = evaluate_process_volume(
        stress,
        increments,
        &nodes,
        &[m],
        &vec![0; points],
        &VolumeParams {
            side: 2.5 * h,
            fraction: 0.0,
            field: FieldParams::default(),
        },
    )
    .unwrap();
    let i = &got.indices;
    assert!(got.inside > 0 && got.inside < points);
    let mut evaluated = 0;
    for p in 0..points {
        let v = [i.crossland[p], i.dang_van[p], i.swt[p], i.fatemi_socie[p]];
        if v[0].is_nan() {
            continue;
        }
        evaluated += 1;
        let want = [
            pointwise.crossland[0],
            pointwise.dang_van[0],
            pointwise.swt[0],
            pointwise.fatemi_socie[0],
        ];
        // The weights sum to one to a few ulps, so the averaged path is the path to ~1e-16
        // relative; measured here up to 2.8e-16 relative in the indices. 1e-12: margin for the
        // critical-plane searches' rounding, far below any modelling effect.
        for c in 0..4 {
            assert!(
                (v[c] - want[c]).abs() <= 1e-12 * want[c].abs(),
                "point {p}, criterion {c}: {} vs {}",
                v[c],
                want[c]
            );
        }
    }
    assert_eq!(evaluated, got.inside);
    for (field, mx) in [
        (&i.crossland, i.crossland_max),
        (&i.dang_van, i.dang_van_max),
        (&i.swt, i.swt_max),
        (&i.fatemi_socie, i.fatemi_socie_max),
    ] {
        assert_eq!(field[mx.point], mx.value);
    }
}

/// A history varying from point to point (seeded) and two materials by depth: every point inside
/// carries the pointwise criteria of its own averaged history ([`average_over_volume`]) with its
/// own material, every point outside is `NaN`, and each maximum is its own field's value at its
/// point and that field's largest value — the compaction of the points inside and the mapping
/// back to the box.
#[test]
fn each_point_gets_the_criteria_of_its_own_average_and_material() {
    let mut rng = Rng::new(29);
    let (n1, n2, layers, h) = (7, 6, 5, 1e-6);
    let (x, y, depth) = loop_box(n1, n2, layers, h);
    let nodes = BoxNodes {
        x: &x,
        y: &y,
        depth: &depth,
    };
    let increments = 6;
    let block = increments * 6;
    let points = depth.len() * n1 * n2;
    let per = n1 * n2;
    let stress: Vec<f64> = (0..points * block)
        .map(|_| rng.range(-300e6, 300e6))
        .collect();
    let soft = Material {
        f_minus1: 300e6,
        t_minus1: 200e6,
        young: 110e9,
        poisson: 0.34,
        fs_k: 0.3,
        yield_stress: 400e6,
    };
    let materials = [material(), soft];
    // The deeper layers of the second material: an interface at depth 2.2 h.
    let material_of: Vec<u16> = (0..points)
        .map(|p| u16::from(depth[p / per] > 2.2 * h))
        .collect();
    assert!(material_of.contains(&0) && material_of.contains(&1));
    let side = 2.5 * h;
    let mut averaged = stress.clone();
    let inside = average_over_volume(&mut averaged, increments, &nodes, side).unwrap();
    let got = evaluate_process_volume(
        stress,
        increments,
        &nodes,
        &materials,
        &material_of,
        &VolumeParams {
            side,
            fraction: 0.0,
            field: FieldParams::default(),
        },
    )
    .unwrap();
    let i = &got.indices;
    assert_eq!(got.inside, inside.iter().filter(|&&b| b).count());
    assert!(got.inside > 0 && got.inside < points);
    let mut by_material = [0; 2];
    for p in 0..points {
        let v = [i.crossland[p], i.dang_van[p], i.swt[p], i.fatemi_socie[p]];
        if !inside[p] {
            assert!(v.iter().all(|v| v.is_nan()), "point {p} outside: {v:?}");
            continue;
        }
        let m = &materials[usize::from(material_of[p])];
        by_material[usize::from(material_of[p])] += 1;
        let want = evaluate_field(
            &averaged[p * block..(p + 1) * block],
            1,
            increments,
            m,
            &FieldParams::default(),
        )
        .unwrap();
        let want = [
            want.crossland[0],
            want.dang_van[0],
            want.swt[0],
            want.fatemi_socie[0],
        ];
        for c in 0..4 {
            // The same history and algorithm: equal to rounding of the search (1e-12).
            assert!(
                (v[c] - want[c]).abs() <= 1e-12 * want[c].abs(),
                "point {p}, criterion {c}: {} vs {}",
                v[c],
                want[c]
            );
        }
    }
    assert!(by_material[0] > 0 && by_material[1] > 0, "{by_material:?}");
    for (field, mx) in [
        (&i.crossland, i.crossland_max),
        (&i.dang_van, i.dang_van_max),
        (&i.swt, i.swt_max),
        (&i.fatemi_socie, i.fatemi_socie_max),
    ] {
        assert_eq!(field[mx.point], mx.value);
        let largest = field
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .fold(f64::MIN, f64::max);
        assert_eq!(mx.value, largest);
    }
}

/// The cube average of a field quadratic along each axis against its closed form
/// (`(1/(b − a)) ∫_a^b u² du = (a² + ab + b²)/3` per axis): the trilinear interpolant's error
/// falls as `O(h²)` when the spacing is halved twice (a fixed side cutting cells anywhere; the
/// surface node `z = 0` and the cube on it included). Measured: max errors 9.6e-4, 2.3e-4,
/// 5.9e-5 on h = 0.1, 0.05, 0.025 (side 0.37): orders 2.04, 1.99.
#[test]
fn a_quadratic_field_converges_at_second_order() {
    let (extent, side) = (1.0, 0.37);
    let mean_sq = |a: f64, b: f64| (a * a + a * b + b * b) / 3.0;
    let coef = [[0.3, 1.0, -2.0, 0.5], [-1.0, 0.25, 0.7, -1.5]];
    let mut errors = Vec::new();
    for n in [10usize, 20, 40] {
        let h = extent / n as f64;
        // Vertex-centred nodes: x, y on [−extent/2, extent/2], depth on [0, extent]; the points
        // compared (x = y = 0, depths multiples of 0.1) are nodes of every grid.
        let x: Vec<f64> = (0..=n).map(|i| i as f64 * h - 0.5 * extent).collect();
        let depth: Vec<f64> = (0..=n).map(|k| k as f64 * h).collect();
        let nodes = BoxNodes {
            x: &x,
            y: &x,
            depth: &depth,
        };
        let (n1, per) = (n + 1, (n + 1) * (n + 1));
        let block = 6;
        let mut stress = vec![0.0; depth.len() * per * block];
        for (p, chunk) in stress.chunks_exact_mut(block).enumerate() {
            let at = [x[(p % per) / n1], x[p % n1], depth[p / per]];
            for (c, v) in chunk.iter_mut().enumerate() {
                let k = coef[c % 2];
                *v = k[0] + k[1] * at[0] * at[0] + k[2] * at[1] * at[1] + k[3] * at[2] * at[2];
            }
        }
        let inside = average_over_volume(&mut stress, 1, &nodes, side).unwrap();
        let mut worst = 0.0f64;
        let mut compared = 0;
        for k in (0..=n).step_by(n / 10) {
            let p = k * per + (n / 2) * n1 + n / 2;
            assert!(x[n / 2].abs() < 1e-15);
            if !inside[p] {
                continue;
            }
            compared += 1;
            let z0 = (depth[k] - 0.5 * side).max(0.0);
            let (ax, bx) = (-0.5 * side, 0.5 * side);
            for c in 0..block {
                let q = coef[c % 2];
                let want = q[0]
                    + q[1] * mean_sq(ax, bx)
                    + q[2] * mean_sq(ax, bx)
                    + q[3] * mean_sq(z0, z0 + side);
                worst = worst.max((stress[p * block + c] - want).abs());
            }
        }
        // The surface point and the deeper ones: the same points on every grid.
        assert_eq!(compared, 9, "n = {n}");
        errors.push(worst);
    }
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        assert!(order >= 1.8, "errors {errors:?}: order {order}");
    }
}

/// Sides below a cell or beyond the box, unordered nodes and a wrong shape are typed errors.
#[test]
fn sides_below_a_cell_or_beyond_the_box_are_refused() {
    let (x, y, depth) = loop_box(6, 5, 4, 1.0);
    let nodes = BoxNodes {
        x: &x,
        y: &y,
        depth: &depth,
    };
    let mut stress = vec![0.0; depth.len() * 30 * 6];
    assert!(matches!(
        average_over_volume(&mut stress, 1, &nodes, 0.9),
        Err(FatigueError::ProcessVolumeBelowCell { .. })
    ));
    assert!(matches!(
        average_over_volume(&mut stress, 1, &nodes, 4.01),
        Err(FatigueError::ProcessVolumeBeyondBox { .. })
    ));
    for bad in [f64::NAN, f64::INFINITY, -1.0] {
        assert!(average_over_volume(&mut stress, 1, &nodes, bad).is_err());
    }
    let mut short = vec![0.0; 5];
    assert!(matches!(
        average_over_volume(&mut short, 1, &nodes, 2.0),
        Err(FatigueError::FieldShape { .. })
    ));
    let reversed: Vec<f64> = x.iter().rev().copied().collect();
    let bad = BoxNodes {
        x: &reversed,
        ..nodes
    };
    assert!(matches!(
        average_over_volume(&mut stress, 1, &bad, 2.0),
        Err(FatigueError::ProcessVolumeNodes { axis: "x", .. })
    ));
    assert!(average_over_volume(&mut stress, 1, &nodes, 2.0).is_ok());
    // Infinite nodes are not increasing finite nodes.
    let mut infinite = x.clone();
    *infinite.last_mut().unwrap() = f64::INFINITY;
    let bad = BoxNodes {
        x: &infinite,
        ..nodes
    };
    assert!(matches!(
        average_over_volume(&mut stress, 1, &bad, 2.0),
        Err(FatigueError::ProcessVolumeNodes { axis: "x", .. })
    ));
}

/// Depths starting below the surface (no surface layer): no cube fits, a typed error naming the
/// depths (not a `NaN` reach), and the history is left as it was.
#[test]
fn depths_below_the_surface_with_no_cube_inside_are_refused() {
    let (x, y, _) = loop_box(6, 5, 4, 1.0);
    // Two layers at 0.5 and 1.5: the shallow cube [0, 2] and the deep [0.5, 2.5] leave them.
    let depth = [0.5, 1.5];
    let nodes = BoxNodes {
        x: &x,
        y: &y,
        depth: &depth,
    };
    let original: Vec<f64> = (0..depth.len() * 30 * 6).map(|v| v as f64).collect();
    let mut stress = original.clone();
    let e = average_over_volume(&mut stress, 1, &nodes, 1.2).unwrap_err();
    assert!(
        matches!(e, FatigueError::ProcessVolumeNoPointInside { .. }),
        "{e:?}"
    );
    let message = e.to_string();
    assert!(!message.contains("NaN"), "{message}");
    assert!(message.contains("0.5 m to 1.5 m"), "{message}");
    assert_eq!(stress, original);
}

/// The cell threshold is per axis and, in depth, where the surface cubes sit: one coarse deep
/// layer does not refuse a side of a few fine cells; a side below the fine spacing still is.
#[test]
fn a_coarse_deep_layer_does_not_refuse_the_side() {
    let (x, y, _) = loop_box(12, 12, 4, 1.0);
    // Fine layers to 6, then one coarse interval of 14.
    let depth = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 20.0];
    let nodes = BoxNodes {
        x: &x,
        y: &y,
        depth: &depth,
    };
    let mut stress = vec![1.0; depth.len() * 144 * 6];
    let inside = average_over_volume(&mut stress, 1, &nodes, 3.0).unwrap();
    assert!(inside.iter().any(|&b| b));
    assert!(stress.iter().all(|&v| (v - 1.0).abs() < 1e-15));
    assert!(matches!(
        average_over_volume(&mut stress, 1, &nodes, 0.9),
        Err(FatigueError::ProcessVolumeBelowCell { cell, .. }) if cell == 1.0
    ));
}

/// Sizes overflowing `usize` and a material map of the wrong length are typed errors, not
/// panics (the map is checked before the history is averaged).
#[test]
fn overflowing_sizes_and_a_short_material_map_are_refused() {
    let (x, y, depth) = loop_box(6, 5, 4, 1.0);
    let nodes = BoxNodes {
        x: &x,
        y: &y,
        depth: &depth,
    };
    let points = depth.len() * 30;
    let params = VolumeParams {
        side: 2.0,
        fraction: 0.0,
        field: FieldParams::default(),
    };
    let mut stress = vec![0.0; points * 6];
    assert!(matches!(
        average_over_volume(&mut stress, usize::MAX / 3, &nodes, 2.0),
        Err(FatigueError::SizeOverflow { .. })
    ));
    assert!(matches!(
        evaluate_process_volume(
            vec![0.0; 6],
            usize::MAX / 3,
            &nodes,
            &[material()],
            &vec![0; points],
            &params
        ),
        Err(FatigueError::SizeOverflow { .. })
    ));
    assert!(matches!(
        evaluate_process_volume(
            vec![0.0; points * 6],
            1,
            &nodes,
            &[material()],
            &vec![0; points - 1],
            &params
        ),
        Err(FatigueError::MaterialMapLength { len, points: p }) if len == points - 1 && p == points
    ));
}
