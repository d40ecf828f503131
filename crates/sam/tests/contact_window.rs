//! The contact solved on a window of the grid (`ContactProblem::set_window`, docs/performance.md
//! "A contact window for the 3D loops"): the window's solve is the whole grid's (to the solvers'
//! tolerances) on the DC-FFT operators and on their dense twins, a window too small for the
//! contact falls back to the whole grid, a restored state continues bit for bit, and the fretting
//! loop's checkpoints record the window.

mod support;

use halfspace_numerics::op::{DenseOperators, OperatorSet};
use halfspace_sam::contact::{ContactParams, ContactProblem, ContactState, GridWindow};
use halfspace_sam::drivers::fretting_loop::{
    FrettingLoop, LoopCase, LoopSnapshot, CONTACT_WINDOW_FIELD,
};
use halfspace_sam::normal::NormalLoad;
use halfspace_sam::{Body, Compliance, SurfaceGrid};

/// [LN11]'s homogeneous case (rigid sphere on steel, `κ ≠ 0`: coupled) on `n²` cells over 4.16a,
/// on the operators of `S`, with smooth eigen-displacements (a bump of `u₃` and a tilt of `u₁`
/// across the whole grid, so that the window's gather and the whole grid's gap check both read
/// them), and the window of half-width `window_over_a · a` (`None`: the whole grid).
fn problem<S: OperatorSet>(n: usize, window_over_a: Option<f64>) -> (ContactProblem<S>, f64) {
    let case = LoopCase::default();
    let a = case.hertz_radius();
    let grid = SurfaceGrid::square(n, 4.16 * a).unwrap();
    let pair = Compliance::pair(Body::Rigid, Body::elastic(case.e, case.nu).unwrap()).unwrap();
    assert!(pair.coupling != 0.0);
    let centres: Vec<(f64, f64)> = (0..grid.len())
        .map(|k| grid.centre(k / grid.n2, k % grid.n2))
        .collect();
    let geometry = centres
        .iter()
        .map(|(x, y)| (x * x + y * y) / (2.0 * case.radius))
        .collect();
    let params = ContactParams {
        friction: case.friction,
        ..ContactParams::default()
    };
    let mut p = ContactProblem::<S>::with_operators(grid, pair, geometry, params).unwrap();
    let delta = a * a / case.radius;
    let u3: Vec<f64> = centres
        .iter()
        .map(|(x, y)| 0.02 * delta * (-(x * x + y * y) / (a * a)).exp())
        .collect();
    let u1: Vec<f64> = centres.iter().map(|(x, _)| 1e-3 * delta * x / a).collect();
    let u2 = vec![0.0; grid.len()];
    p.set_eigen_displacements(Some([&u1, &u2, &u3])).unwrap();
    if let Some(r) = window_over_a {
        let window = GridWindow::central(&grid, r * a).unwrap();
        assert!(window.is_some());
        p.set_window(window).unwrap();
    }
    (p, case.force)
}

/// The loop of the test: the normal force ramped in 4 increments, then the shift cycled
/// `0 → +A → −A` in 6 (A = [LN11]'s 0.04 μm), each increment recorded.
fn run<S: OperatorSet>(p: &mut ContactProblem<S>, force: f64, steps: usize) -> Vec<ContactState> {
    let amplitude = 0.04e-6;
    let path: Vec<(f64, f64)> = (1..=4)
        .map(|i| (force * i as f64 / 4.0, 0.0))
        .chain([0.5, 1.0, 0.5, 0.0, -0.5, -1.0].map(|s| (force, s * amplitude)))
        .take(steps)
        .collect();
    path.iter()
        .map(|&(w, d)| {
            p.increment(NormalLoad::Force(w), [d, 0.0]).unwrap();
            p.state().clone()
        })
        .collect()
}

/// The largest difference of pressure, shear, slip (over `p_max`, per unit of the fields: the
/// slip and displacements over their own largest) between two states.
fn differences(a: &ContactState, b: &ContactState) -> [f64; 3] {
    let max = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let diff = |x: &[f64], y: &[f64]| {
        x.iter()
            .zip(y)
            .fold(0.0f64, |m, (u, v)| m.max((u - v).abs()))
    };
    let p_max = max(&a.pressure);
    let slip_max = max(&a.slip[0]).max(max(&a.slip[1])).max(1e-300);
    let u_max = max(&a.tangential_displacement[0]).max(max(&a.tangential_displacement[1]));
    [
        diff(&a.pressure, &b.pressure)
            .max(diff(&a.shear[0], &b.shear[0]))
            .max(diff(&a.shear[1], &b.shear[1]))
            / p_max,
        diff(&a.slip[0], &b.slip[0]).max(diff(&a.slip[1], &b.slip[1])) / slip_max,
        diff(&a.tangential_displacement[0], &b.tangential_displacement[0]).max(diff(
            &a.tangential_displacement[1],
            &b.tangential_displacement[1],
        )) / u_max,
    ]
}

/// The window's solves against the whole grid's, increment by increment: pressure and shear
/// within 1e-6 p_max (the solvers' tolerances: alternation 1e-7, their preconditioners and
/// iterates being the window's; measured ≤ 2e-8 on the 48² FFT loop), slip and the tangential
/// displacement on the whole grid (computed there after every solve) within 1e-5 of their
/// largest, no solve off the window.
fn check_window_against_the_whole_grid<S: OperatorSet>(n: usize) {
    let (mut whole, force) = problem::<S>(n, None);
    let (mut windowed, _) = problem::<S>(n, Some(1.3));
    let reference = run(&mut whole, force, 10);
    let states = run(&mut windowed, force, 10);
    assert_eq!(windowed.window_misses(), 0);
    let mut worst = [0.0f64; 3];
    for (a, b) in reference.iter().zip(&states) {
        let d = differences(a, b);
        for (w, x) in worst.iter_mut().zip(d) {
            *w = w.max(x);
        }
        assert!((a.approach - b.approach).abs() <= 1e-6 * a.approach.abs());
    }
    eprintln!(
        "{n}²: window against the whole grid: p, q / p_max {:.2e}, slip {:.2e}, Δu {:.2e}",
        worst[0], worst[1], worst[2]
    );
    assert!(worst[0] <= 1e-6, "{worst:?}");
    assert!(worst[1] <= 1e-5 && worst[2] <= 1e-5, "{worst:?}");
    // Nothing outside the window.
    let window = windowed.window().unwrap();
    let last = states.last().unwrap();
    for k in 0..n * n {
        let (i, j) = (k / n, k % n);
        let inside = (window.first[0]..window.first[0] + window.cells[0]).contains(&i)
            && (window.first[1]..window.first[1] + window.cells[1]).contains(&j);
        if !inside {
            assert_eq!(last.pressure[k], 0.0);
            assert_eq!(last.shear[0][k], 0.0);
        }
    }
}

#[test]
fn a_windowed_problem_solves_the_whole_grids_problem() {
    check_window_against_the_whole_grid::<halfspace_numerics::op::FftOperators>(48);
}

#[test]
fn a_windowed_problem_solves_the_whole_grids_problem_on_the_dense_twin() {
    check_window_against_the_whole_grid::<DenseOperators>(24);
}

/// A window of ±0.5a cannot hold the contact (≈ a): every loaded solve reaches its edge and runs
/// on the whole grid instead — the same loop as without a window, to the solvers' tolerances.
#[test]
fn a_window_too_small_falls_back_to_the_whole_grid() {
    let (mut whole, force) = problem::<halfspace_numerics::op::FftOperators>(32, None);
    let (mut small, _) = problem::<halfspace_numerics::op::FftOperators>(32, Some(0.5));
    let reference = run(&mut whole, force, 6);
    let states = run(&mut small, force, 6);
    assert!(small.window_misses() >= 4, "{}", small.window_misses());
    for (a, b) in reference.iter().zip(&states) {
        let d = differences(a, b);
        assert!(d[0] <= 1e-6 && d[1] <= 1e-5 && d[2] <= 1e-5, "{d:?}");
    }
}

/// A windowed problem restored from another's state after 6 increments (a checkpoint's) repeats
/// the other's next increments bit for bit.
#[test]
fn a_restored_windowed_problem_continues_bit_for_bit() {
    let (mut first, force) = problem::<halfspace_numerics::op::FftOperators>(32, Some(1.3));
    let states = run(&mut first, force, 10);
    let (mut second, _) = problem::<halfspace_numerics::op::FftOperators>(32, Some(1.3));
    second.restore_state(&states[5]).unwrap();
    let bits = |s: &ContactState| -> Vec<u64> {
        s.pressure
            .iter()
            .chain(s.shear.iter().flatten())
            .chain(s.tangential_displacement.iter().flatten())
            .chain(s.slip.iter().flatten())
            .chain(&[s.approach, s.force, s.shift[0], s.shift[1]])
            .map(|v| v.to_bits())
            .collect()
    };
    for (k, d) in [(6, 0.5), (7, 0.0), (8, -0.5), (9, -1.0)] {
        second
            .increment(NormalLoad::Force(force), [d * 0.04e-6, 0.0])
            .unwrap();
        assert_eq!(bits(second.state()), bits(&states[k]), "increment {k}");
    }
}

/// The central window: the cells within the half-width, as many outside on either side, at
/// least 8 a side, `None` when that is the whole grid; a bad half-width refused.
#[test]
fn central_windows_hold_the_cells_within_the_half_width() {
    let grid = SurfaceGrid::square(16, 16.0).unwrap(); // unit cells, centres at ±0.5, ±1.5, …
    let w = GridWindow::central(&grid, 4.6).unwrap().unwrap();
    assert_eq!((w.first, w.cells), ([3, 3], [10, 10])); // centres ±0.5, …, ±4.5
                                                        // Fewer than 8 cells within the half-width: 8.
    for half_width in [0.1, 2.6] {
        let w = GridWindow::central(&grid, half_width).unwrap().unwrap();
        assert_eq!((w.first, w.cells), ([4, 4], [8, 8]));
    }
    assert_eq!(GridWindow::central(&grid, 7.6).unwrap(), None);
    assert_eq!(GridWindow::central(&grid, 100.0).unwrap(), None);
    let odd = SurfaceGrid::square(17, 17.0).unwrap(); // centres at 0, ±1, …
    let w = GridWindow::central(&odd, 4.5).unwrap().unwrap();
    assert_eq!((w.first, w.cells), ([4, 4], [9, 9]));
    // At least 8 cells, centred: 9 on an odd grid.
    let w = GridWindow::central(&odd, 0.1).unwrap().unwrap();
    assert_eq!((w.first, w.cells), ([4, 4], [9, 9]));
    assert!(GridWindow::central(&grid, f64::NAN).is_err());
    assert!(GridWindow::central(&grid, 0.0).is_err());
    // A window outside the grid or under 8 cells is refused.
    let (mut p, _) = problem::<halfspace_numerics::op::FftOperators>(16, None);
    for bad in [
        GridWindow {
            first: [10, 0],
            cells: [8, 8],
        },
        GridWindow {
            first: [0, 0],
            cells: [7, 8],
        },
    ] {
        assert!(p.set_window(Some(bad)).is_err());
    }
}

/// The fretting loop solves its contact on its window and records it in its checkpoints'
/// fingerprint; a checkpoint without it (a build whose solves ran on the whole grid) is refused,
/// saying why.
#[test]
fn the_fretting_loop_records_its_contact_window() {
    let case = support::stiff_sphere_loop();
    let window = case.contact_window().unwrap().expect("a window at 16²");
    let mut lp = FrettingLoop::new(case.clone()).unwrap();
    assert_eq!(lp.solver().problem().window(), Some(window));
    lp.step().unwrap().unwrap();
    let snap = lp.snapshot();
    assert!(snap
        .fingerprint
        .contains(&format!("{CONTACT_WINDOW_FIELD}Some({:?})", window.cells)));
    assert!(FrettingLoop::resume(case.clone(), snap.clone()).is_ok());
    let legacy = LoopSnapshot {
        fingerprint: snap.fingerprint[..snap.fingerprint.find(CONTACT_WINDOW_FIELD).unwrap()]
            .to_string(),
        ..snap
    };
    let err = FrettingLoop::resume(case, legacy).err().expect("refused");
    assert!(err.to_string().contains("start the loop over"), "{err}");
}

/// A force-controlled tangential increment (`increment_with_force`: Brent on the shift) on the
/// window and, with a ±0.5a window the contact does not fit in, on its whole-grid fallback
/// (every evaluation on the whole grid): the same shift, pressure and shear as the whole grid's
/// (to the solvers' tolerances), the history committed on the whole grid.
#[test]
fn a_force_controlled_increment_on_the_window_is_the_whole_grids() {
    type F = halfspace_numerics::op::FftOperators;
    let (mut whole, force) = problem::<F>(32, None);
    let (mut windowed, _) = problem::<F>(32, Some(1.3));
    let (mut small, _) = problem::<F>(32, Some(0.5));
    let ramp = |p: &mut ContactProblem<F>| {
        for i in 1..=4 {
            p.increment(NormalLoad::Force(force * i as f64 / 4.0), [0.0, 0.0])
                .unwrap();
        }
    };
    ramp(&mut whole);
    ramp(&mut windowed);
    ramp(&mut small);
    let misses = small.window_misses();
    let q = 0.5 * LoopCase::default().friction * force;
    let (_, d_whole) = whole
        .increment_with_force(NormalLoad::Force(force), q, 0.04e-6)
        .unwrap();
    for (p, name) in [(&mut windowed, "window"), (&mut small, "fallback")] {
        let (info, d) = p
            .increment_with_force(NormalLoad::Force(force), q, 0.04e-6)
            .unwrap();
        assert!((info.tangential_force[0] / q - 1.0).abs() < 1e-5, "{name}");
        assert!(
            (d / d_whole - 1.0).abs() < 1e-5,
            "{name}: shift {d} vs {d_whole}"
        );
        let diff = differences(whole.state(), p.state());
        assert!(diff[0] <= 1e-6 && diff[2] <= 1e-5, "{name}: {diff:?}");
        assert_eq!(p.state().shift, [d, 0.0]);
    }
    assert_eq!(windowed.window_misses(), 0);
    assert_eq!(small.window_misses(), misses + 1);
}
