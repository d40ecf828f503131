//! halfspace timed in one process exactly as `verify/peers_3d.py` times ASPHER
//! (docs/performance.md, "In process, as ASPHER is timed"): frictionless Hertz (R = 105 μm,
//! E = 210 GPa, ν = 0.3, W = 80 mN, square domain 4a, N² cells), the gap `(x² + y²)/(2R)` built
//! outside the timing (ASPHER's comes from numpy), then **one warm-up solve at 128², tolerance 1e-6**
//! (ASPHER's warm-up: thread pool, allocator pages and the process's FFT plans warm), then one timed
//! solve at N², tolerance `TOL`: a NEW problem and solver (`ContactProblem::new` with its kernels,
//! spectra and nested grids, then `ContactSolver::increment`, the library path of `contact3d`) —
//! what a user who solves a second contact in the same session waits for. Prints one JSON line:
//! wall `seconds` (setup + solve), `setup` (the problem's construction), `cpu` (processor time of
//! every thread of the process during the timed solve, `CLOCK_PROCESS_CPUTIME_ID`, as Python's
//! `time.process_time()` around ASPHER's call), fine `iterations`, `peak_mb` (VmHWM).
//! With `--dump PATH` the pressure (N² little-endian f64, row-major, `x` along rows) is written
//! after the timing, for the accuracy columns of `peers_3d.py`.
//!
//! With `--cold` the warm-up is skipped: the timed solve is then the process's first, as the CLI's
//! (plan cache empty, buffers touched for the first time, the thread pool started inside it).
//!
//! Run: `cargo build --release -p halfspace-sam --example inprocess_hertz`, then
//! `target/release/examples/inprocess_hertz N TOL [--dump PATH] [--cold]` (threads:
//! `RAYON_NUM_THREADS`).

use std::io::Write;
use std::time::Instant;

use halfspace_sam::contact::{ContactParams, ContactProblem, ContactSolver, NestedParams};
use halfspace_sam::normal::{NormalLoad, NormalParams};
use halfspace_sam::tangential::TangentialParams;
use halfspace_sam::{Body, Compliance, SurfaceGrid};

const R: f64 = 105e-6;
const E: f64 = 210e9;
const NU: f64 = 0.3;
const W: f64 = 0.08;

/// Processor time (s) of every thread of this process so far: `CLOCK_PROCESS_CPUTIME_ID`, what
/// Python's `time.process_time()` reads (exact to the nanosecond; `/proc/self/task/*/schedstat`
/// lags by up to a scheduler tick for the running thread).
fn process_cpu() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid, writable timespec; the clock id is a constant of the platform.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_PROCESS_CPUTIME_ID)");
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

/// Peak resident memory (MB) of this process (`VmHWM`).
fn peak_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|v| v.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

struct Case {
    grid: SurfaceGrid,
    compliance: Compliance,
    gap: Vec<f64>,
}

impl Case {
    /// Grid, bodies and gap: the part ASPHER's timing leaves out (numpy's gap).
    fn new(n: usize) -> Case {
        let e_star = E / (1.0 - NU * NU);
        let a = halfspace_mdr::analytic::sphere_radius_for_force(W, R, e_star);
        let grid = SurfaceGrid::square(n, 4.0 * a).expect("grid");
        let gap = (0..grid.len())
            .map(|k| {
                let (x, y) = grid.centre(k / grid.n2, k % grid.n2);
                (x * x + y * y) / (2.0 * R)
            })
            .collect();
        let compliance =
            Compliance::pair(Body::Rigid, Body::elastic(E, NU).expect("body")).expect("pair");
        Case {
            grid,
            compliance,
            gap,
        }
    }

    /// A new problem and solver and one increment to force `W`: (setup s, total s, cpu s, fine
    /// iterations, pressure). The gap's copy (the problem owns it) is made before the clock starts.
    fn solve(&self, tol: f64) -> (f64, f64, f64, usize, Vec<f64>) {
        let gap = self.gap.clone();
        let params = ContactParams {
            friction: 0.0,
            normal: NormalParams {
                tolerance: tol,
                ..NormalParams::default()
            },
            tangential: TangentialParams {
                tolerance: tol,
                ..TangentialParams::default()
            },
            ..ContactParams::default()
        };
        let (c0, t0) = (process_cpu(), Instant::now());
        let problem =
            ContactProblem::new(self.grid, self.compliance, gap, params).expect("problem");
        let mut solver =
            ContactSolver::new(problem, E, NU, &[], NestedParams::default()).expect("solver");
        let setup = t0.elapsed().as_secs_f64();
        let (info, _) = solver
            .increment(NormalLoad::Force(W), [0.0, 0.0])
            .expect("solve");
        let (seconds, cpu) = (t0.elapsed().as_secs_f64(), process_cpu() - c0);
        let p = solver.problem().state().pressure.clone();
        (setup, seconds, cpu, info.normal.iterations, p)
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: inprocess_hertz N TOL [--dump PATH] [--cold]";
    let n: usize = args.first().and_then(|s| s.parse().ok()).expect(usage);
    let tol: f64 = args.get(1).and_then(|s| s.parse().ok()).expect(usage);
    let (mut dump, mut cold) = (None, false);
    let mut rest = args.iter().skip(2);
    while let Some(a) = rest.next() {
        match a.as_str() {
            "--dump" => dump = Some(rest.next().expect(usage).clone()),
            "--cold" => cold = true,
            _ => panic!("{usage}"),
        }
    }
    if !cold {
        // ASPHER's warm-up in peers_3d.py: one solve at 128², tolerance 1e-6, in the same process.
        Case::new(128).solve(1e-6);
    }
    let case = Case::new(n);
    let (setup, seconds, cpu, iterations, p) = case.solve(tol);
    if let Some(path) = dump {
        let bytes: Vec<u8> = p.iter().flat_map(|v| v.to_le_bytes()).collect();
        std::fs::write(&path, bytes).expect("write the pressure");
    }
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "{{\"seconds\": {seconds:e}, \"setup\": {setup:e}, \"cpu\": {cpu:e}, \"iterations\": {iterations}, \"peak_mb\": {:.1}}}",
        peak_mb()
    )
    .expect("stdout");
}
