//! Which records an animation draws (docs/wear3d.md#figures, docs/composite.md#animation): at
//! most [`MAX_FRAMES`] frames, evenly spaced over the records, the first and the last always
//! among them, so that the file size of a long run (about 11 kB per frame at 32², 400 × 360 px;
//! about 18 kB at 64², 480 × 232 px) stays bounded.

/// The most frames of `wear_depth.gif` (docs/wear3d.md#figures: 60 frames of 0.4 s, a 24 s
/// animation of well under 2 MB) and of `loop_pq.gif` (docs/composite.md#animation: 60 frames of
/// 0.15 s).
pub const MAX_FRAMES: usize = 60;

/// The indices of the records drawn out of `records`, at most `most`: all of them when
/// `records ≤ most`, else `k_j = round(j (records − 1) / (most − 1))` for `j = 0 … most − 1`
/// (round half up) — evenly spaced, strictly increasing (the spacing exceeds 1), `k_0 = 0`
/// (the first record) and `k_{most−1} = records − 1` (the last). `most = 1` draws the last
/// record only; `most = 0` or no records draw nothing.
pub fn frame_records(records: usize, most: usize) -> Vec<usize> {
    if records <= most {
        return (0..records).collect();
    }
    match most {
        0 => Vec::new(),
        1 => vec![records - 1],
        _ => {
            let (span, gaps) = (records - 1, most - 1);
            (0..most)
                .map(|j| (2 * j * span + gaps) / (2 * gaps))
                .collect()
        }
    }
}
