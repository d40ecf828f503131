//! The fretting loop's up-front memory estimate (`LoopCase::estimate`) against the measured peak
//! of the von Mises fields at the points A–D (`subsurface::von_mises_fields`, the four states at
//! once): a counting global allocator records the bytes live at once during the call. One test
//! in this binary, so no other test allocates meanwhile.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use halfspace_sam::drivers::fretting_loop::{FrettingLoop, LoopCase};
use halfspace_sam::eim::FibreLayout;
use halfspace_sam::subsurface::{von_mises_fields, von_mises_fields_bytes, FieldSources};

/// The system allocator, counting the bytes live and their largest value since the last reset.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(by: usize) {
    let now = LIVE.fetch_add(by, Ordering::SeqCst) + by;
    PEAK.fetch_max(now, Ordering::SeqCst);
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc_zeroed(layout);
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        LIVE.fetch_sub(layout.size(), Ordering::SeqCst);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = System.realloc(ptr, layout, new_size);
        if !p.is_null() {
            LIVE.fetch_sub(layout.size(), Ordering::SeqCst);
            grew(new_size);
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// One state's pressure, shear and eigenstrains.
type State = (Vec<f64>, [Vec<f64>; 2], Vec<f64>);

/// \[LN11\]'s composite (stiff fibres) with the von Mises fields down to `a` (the CLI's default
/// `subsurface_over_a = 1`), at `n²`: the bytes the four points' fields hold at once, measured,
/// lie within the estimate's component (`von_mises_fields_bytes`, and the estimate with the
/// fields against without), and both are at most twice the measured peak.
#[test]
fn the_loop_estimate_bounds_the_von_mises_fields_peak() {
    for n in [32, 64] {
        let mut case = LoopCase::default()
            .composite(FibreLayout::FibreCentred, 2.0)
            .unwrap();
        case.grid = n;
        let depth = case.hertz_radius();
        case.subsurface_depth = Some(depth);
        let lp = FrettingLoop::new(case.clone()).unwrap();
        let grid = *lp.solver().problem().grid();
        let set = lp.solver().nested().expect("inhomogeneities").inclusions();
        let cells = grid.len();
        // Four states: Hertz-like tractions and eigenstrains at every inclusion cell (no field
        // is skipped as zero).
        let states: Vec<State> = (0..4)
            .map(|s| {
                let p: Vec<f64> = (0..cells)
                    .map(|k| {
                        let (x, y) = grid.centre(k / grid.n2, k % grid.n2);
                        let r2 = (x * x + y * y) / (grid.half1 * grid.n1 as f64).powi(2);
                        1e9 * (1.0 - r2).max(0.0).sqrt()
                    })
                    .collect();
                let q = [
                    p.iter().map(|v| 0.1 * v * (s as f64 - 1.5)).collect(),
                    p.iter().map(|v| 0.01 * v).collect(),
                ];
                let eps = (0..6 * set.len())
                    .map(|i| 1e-4 * (1.0 + (i % 7) as f64))
                    .collect();
                (p, q, eps)
            })
            .collect();
        let sources: Vec<FieldSources> = states
            .iter()
            .map(|(p, q, eps)| FieldSources {
                pressure: p,
                shear: Some([&q[0], &q[1]]),
                eigenstrain: Some(eps),
            })
            .collect();
        let before = LIVE.load(Ordering::SeqCst);
        PEAK.store(before, Ordering::SeqCst);
        let fields = von_mises_fields(&grid, case.e, case.nu, depth, Some(set), &sources).unwrap();
        let peak = (PEAK.load(Ordering::SeqCst) - before) as f64;
        let layers = fields[0].len() / cells;
        let component = von_mises_fields_bytes((n, n), layers, set.layers.len(), 4);
        let without = LoopCase {
            subsurface_depth: None,
            ..case.clone()
        };
        let counted = case.estimate().bytes - without.estimate().bytes;
        eprintln!(
            "{n}²: {layers} layers, {} inclusion layers (bound {}): measured peak {:.1} MB, \
             von_mises_fields_bytes {:.1} MB, counted by the estimate {:.1} MB",
            set.layers.len(),
            case.inclusion_layers_bound(),
            peak / 1e6,
            component / 1e6,
            counted / 1e6
        );
        assert!(set.layers.len() <= case.inclusion_layers_bound());
        assert!(component >= peak, "{component} < {peak}");
        assert!(component <= 2.0 * peak, "{component} > 2 × {peak}");
        assert!(counted >= component, "{counted} < {component}");
        // The estimate's inclusion layers are a bound (the layers down to the deepest
        // inhomogeneity), not the set's: still within twice the measured peak.
        assert!(counted <= 2.0 * peak, "{counted} > 2 × {peak}");
    }
}
