//! The bookkeeping passes of the Polonsky–Keer iteration (docs/theory-sam.md#normal-contact steps
//! 1–10: gap, means, conjugate direction, step length, projection, force scaling) over fixed chunks
//! of [`CHUNK`] cells, on rayon's threads on large grids (docs/performance.md, "3D normal contact").
//!
//! Sums are taken per chunk in four interleaved lanes (a sum's dependency chain four times shorter)
//! and the partial sums of the chunks added in chunk order: the result depends on the grid only,
//! not on the number of threads (bit for bit the same on 1 and 2 threads; tested).

use std::ops::Range;

/// Cells per chunk (16 KiB of each field): 8 chunks at 128², 32 at 256².
pub(crate) const CHUNK: usize = 2048;

/// Grids with at least this many cells run their passes on rayon's threads (below, the hand-offs
/// cost more than the passes; measured in docs/performance.md).
pub(crate) const PARALLEL_PASS_CELLS: usize = 128 * 128;

/// The chunks of a grid of `n` cells.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Chunks {
    n: usize,
    parallel: bool,
}

impl Chunks {
    /// The chunks of `n` cells; on threads when `n ≥ PARALLEL_PASS_CELLS` and rayon has more than one.
    pub(crate) fn new(n: usize) -> Self {
        Self {
            n,
            parallel: n >= PARALLEL_PASS_CELLS && rayon::current_num_threads() > 1,
        }
    }

    /// Number of chunks, `⌈n / CHUNK⌉`.
    pub(crate) fn count(&self) -> usize {
        self.n.div_ceil(CHUNK)
    }

    /// `out[c] = body(range_c, [fields restricted to range_c])` for every chunk `c` (in parallel
    /// or in order; `out` has [`Chunks::count`] entries). The body reads other fields by the range.
    pub(crate) fn run<const M: usize, R: Send>(
        &self,
        out: &mut [R],
        fields: [&mut [f64]; M],
        body: impl Fn(Range<usize>, [&mut [f64]; M]) -> R + Sync,
    ) {
        assert_eq!(out.len(), self.count(), "one result per chunk");
        for f in &fields {
            assert_eq!(f.len(), self.n, "a field of the grid");
        }
        split_run(0..self.n, out, fields, self.parallel, &body);
    }
}

/// [`Chunks::run`] on the cells `cells` (whole chunks from a chunk boundary, the last one possibly
/// short) and their results `out`: halved recursively (`rayon::join` when `parallel`).
fn split_run<const M: usize, R: Send>(
    cells: Range<usize>,
    out: &mut [R],
    fields: [&mut [f64]; M],
    parallel: bool,
    body: &(impl Fn(Range<usize>, [&mut [f64]; M]) -> R + Sync),
) {
    if out.len() == 1 {
        // Every slice of the chunk has the range's length (lets the passes drop bounds checks).
        let len = cells.len();
        out[0] = body(cells, fields.map(|f| &mut f[..len]));
        return;
    }
    let half = out.len() / 2;
    let mid = half * CHUNK;
    let mut right: [&mut [f64]; M] = std::array::from_fn(|_| Default::default());
    let left = {
        let mut slots = right.iter_mut();
        fields.map(|f| {
            let (a, b) = f.split_at_mut(mid);
            *slots.next().expect("one slot per field") = b;
            a
        })
    };
    let (out_left, out_right) = out.split_at_mut(half);
    let (cl, cr) = (cells.start..cells.start + mid, cells.start + mid..cells.end);
    if parallel {
        rayon::join(
            || split_run(cl, out_left, left, parallel, body),
            || split_run(cr, out_right, right, parallel, body),
        );
    } else {
        split_run(cl, out_left, left, parallel, body);
        split_run(cr, out_right, right, parallel, body);
    }
}

/// `Σ_i f(i)` over `i < len` (each of the `S` components), in four interleaved lanes added as
/// `(l₀ + l₁) + (l₂ + l₃)`. `f` may write the cell `i` of the chunk's fields.
#[inline(always)]
pub(crate) fn sum_lanes<const S: usize>(
    len: usize,
    mut f: impl FnMut(usize) -> [f64; S],
) -> [f64; S] {
    let mut acc = [[0.0; S]; 4];
    let full = len / 4 * 4;
    for b in 0..len / 4 {
        for (l, lane) in acc.iter_mut().enumerate() {
            let v = f(4 * b + l);
            for s in 0..S {
                lane[s] += v[s];
            }
        }
    }
    for i in full..len {
        let v = f(i);
        for s in 0..S {
            acc[i - full][s] += v[s];
        }
    }
    std::array::from_fn(|s| (acc[0][s] + acc[1][s]) + (acc[2][s] + acc[3][s]))
}

/// `Σ_c parts[c]` in chunk order, componentwise.
pub(crate) fn total<const S: usize>(parts: &[[f64; S]]) -> [f64; S] {
    let mut t = [0.0; S];
    for p in parts {
        for s in 0..S {
            t[s] += p[s];
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every cell is visited once with its own slice, on grids below and above the parallel
    /// threshold and with a short last chunk; the lanes sum as the plain sum to rounding.
    #[test]
    fn chunks_cover_the_grid_once_and_lanes_sum() {
        for n in [7, 2048, 128 * 128 + 5] {
            let chunks = Chunks::new(n);
            let mut a = vec![0.0; n];
            let mut b: Vec<f64> = (0..n).map(|k| k as f64).collect();
            let mut out = vec![[0.0; 2]; chunks.count()];
            chunks.run(&mut out, [&mut a, &mut b], |r, [a, b]| {
                let start = r.start;
                sum_lanes(r.len(), |i| {
                    a[i] += 1.0;
                    assert_eq!(b[i], (start + i) as f64);
                    b[i] = -b[i];
                    [1.0, (start + i) as f64]
                })
            });
            let t = total(&out);
            assert_eq!(t[0], n as f64);
            assert_eq!(t[1], (n * (n - 1) / 2) as f64);
            assert!(a.iter().all(|v| *v == 1.0));
            assert!(b.iter().enumerate().all(|(k, v)| *v == -(k as f64)));
        }
    }
}
