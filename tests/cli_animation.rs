//! The animations through the binary: `wear_depth.gif` of `fretting-wear3d`
//! (docs/wear3d.md#figures) and `loop_pq.gif` of `fretting-loop` (docs/composite.md#animation),
//! decoded with the image crate: one frame per record (per increment of the cycle), the frame
//! size, frames that differ; after a resume inside the cycle, one frame per loop point A–D;
//! `--no-animation` writes none. A wear run with more records than
//! `halfspace::animation::MAX_FRAMES`, and a loop with more increments in its cycle, draw that
//! many frames, chosen by `frame_records` (its rule checked here over all small cases).

mod common;

use common::{ok_json, run};
use image::AnimationDecoder;

/// The frames of a GIF file, decoded.
fn frames(path: &std::path::Path) -> Vec<image::RgbaImage> {
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    image::codecs::gif::GifDecoder::new(file)
        .unwrap()
        .into_frames()
        .collect_frames()
        .unwrap()
        .into_iter()
        .map(|f| f.into_buffer())
        .collect()
}

/// Every frame of the size given, no dimension above 480 px, and each frame differs from the
/// one before (the field changes between records and between increments).
fn check_frames(frames: &[image::RgbaImage], size: (u32, u32)) {
    for f in frames {
        assert_eq!(f.dimensions(), size);
    }
    assert!(size.0 <= 480 && size.1 <= 480);
    for (k, w) in frames.windows(2).enumerate() {
        assert_ne!(w[0], w[1], "frames {k} and {} are identical", k + 1);
    }
}

/// The MDR twin of docs/wear3d.md on 16², N₀ = 1000 cycles, to τ = 1, recorded at 100, 300 and
/// 600 cycles (and the end).
const TWIN: &str = "radius = 105e-6\ne = 210e9\nnu = 0.0\nfriction = 0.3\n\
normal_steps = 1\namplitude = 1.5e-8\nshift_step = 1.5e-8\ngrid = 16\nextent_over_a = 3.2\n\
approach = 1e-7\nindenter_e = 210e9\nindenter_nu = 0.0\n\
[wear]\nlaw = \"archard\"\ncoefficient = 1.5430335e-12\nbody = \"gap\"\ncycles = 1000\n\
record_cycles = [100, 300, 600]\n";

#[test]
fn wear3d_animation_has_one_frame_per_record() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("wear.toml");
    std::fs::write(&cfg, TWIN).unwrap();
    let out = dir.path().join("w");
    let go = |out: &std::path::Path, extra: &[&str]| {
        let mut v = vec![
            "fretting-wear3d",
            "--config",
            cfg.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--json",
        ];
        v.extend_from_slice(extra);
        ok_json(&run(&v))
    };
    go(&out, &[]);
    let gif = out.join("wear_depth.gif");
    let f = frames(&gif);
    assert_eq!(f.len(), 4, "records at 100, 300, 600 and 1000 cycles");
    check_frames(&f, (400, 360));
    assert!(std::fs::metadata(&gif).unwrap().len() < 2_000_000);
    let none = dir.path().join("none");
    go(&none, &["--no-animation"]);
    assert!(none.join("wear_depth_map.svg").is_file() && !none.join("wear_depth.gif").exists());
}

/// The frame rule of docs/wear3d.md#figures, for every record count up to 300 and every cap up
/// to 70: `min(n, most)` frames, strictly increasing record indices, the first and the last
/// record drawn, each index within half a record of `j (n − 1) / (most − 1)` (evenly spaced).
#[test]
fn frame_records_are_evenly_spaced_with_the_first_and_the_last() {
    use halfspace::animation::{frame_records, MAX_FRAMES};
    assert_eq!(MAX_FRAMES, 60);
    for n in 0..=300usize {
        for most in 0..=70usize {
            let k = frame_records(n, most);
            assert_eq!(k.len(), n.min(most), "n = {n}, most = {most}");
            assert!(k.windows(2).all(|w| w[0] < w[1]), "n = {n}, most = {most}");
            assert!(k.iter().all(|&i| i < n));
            if k.is_empty() {
                continue;
            }
            assert_eq!(
                *k.last().unwrap(),
                n - 1,
                "the last record, n = {n}, most = {most}"
            );
            if most >= 2 {
                assert_eq!(k[0], 0, "the first record, n = {n}, most = {most}");
            }
            if n > most && most >= 2 {
                // |i − j (n − 1)/(most − 1)| ≤ 1/2, in integers (exact at the halves).
                let (span, gaps) = ((n - 1) as i64, (most - 1) as i64);
                for (j, &i) in k.iter().enumerate() {
                    let off = 2 * gaps * i as i64 - 2 * j as i64 * span;
                    assert!(off.abs() <= gaps, "n = {n}, most = {most}, j = {j}");
                }
            }
        }
    }
    // 150 records (the size of run that passed 2 MB): spacing 149/59 ≈ 2.53.
    let k = frame_records(150, 60);
    assert_eq!(&k[..5], &[0, 3, 5, 8, 10]);
    assert_eq!(&k[55..], &[139, 141, 144, 146, 149]);
}

/// More records than frames: the twin recorded every 10 cycles (99 records with the end) draws
/// `MAX_FRAMES` = 60 frames, each differing from the one before, well under 2 MB.
#[test]
fn wear3d_animation_caps_the_frames() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("wear.toml");
    let records: Vec<String> = (1..99).map(|k| (10 * k).to_string()).collect();
    let toml = TWIN.replace(
        "record_cycles = [100, 300, 600]",
        &format!("record_cycles = [{}]", records.join(", ")),
    );
    assert_ne!(toml, TWIN);
    std::fs::write(&cfg, toml).unwrap();
    let out = dir.path().join("w");
    ok_json(&run(&[
        "fretting-wear3d",
        "--config",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]));
    let gif = out.join("wear_depth.gif");
    let f = frames(&gif);
    assert_eq!(
        f.len(),
        halfspace::animation::MAX_FRAMES,
        "99 records, 60 frames"
    );
    check_frames(&f, (400, 360));
    assert!(std::fs::metadata(&gif).unwrap().len() < 2_000_000);
}

#[test]
fn loop_animation_has_one_frame_per_increment_of_the_cycle() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("loop.toml");
    // 4 normal steps, q = 4 increments per quarter: the cycle is rows n + q − 1 … n + 5q − 1,
    // 4q + 1 = 17 increments.
    std::fs::write(&cfg, "grid = 32\nnormal_steps = 4\nshift_step = 0.01e-6\n").unwrap();
    let out = dir.path().join("loop");
    let v = ok_json(&run(&[
        "fretting-loop",
        "--config",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]));
    let increments = v["increments"].as_u64().unwrap() as usize;
    let (n, q) = (4, (increments - 4) / 5);
    let gif = out.join("loop_pq.gif");
    let f = frames(&gif);
    assert_eq!(f.len(), (n + 5 * q) - (n + q - 1));
    check_frames(&f, (480, 232));
    assert!(std::fs::metadata(&gif).unwrap().len() < 2_000_000);
    // Stopped inside the cycle and resumed: the increments before the stop were not observed,
    // so the animation has one frame per loop point A–D.
    let resumed = dir.path().join("resumed");
    let go = |extra: &[&str]| {
        let mut v = vec![
            "fretting-loop",
            "--config",
            cfg.to_str().unwrap(),
            "--out",
            resumed.to_str().unwrap(),
        ];
        v.extend_from_slice(extra);
        run(&v)
    };
    assert!(go(&["--stop-after", &(n + q + 2).to_string()])
        .status
        .success());
    assert!(!resumed.join("loop_pq.gif").exists());
    ok_json(&go(&["--resume", "--json"]));
    let f = frames(&resumed.join("loop_pq.gif"));
    assert_eq!(f.len(), 4, "A–D");
    check_frames(&f, (480, 232));
    // --no-animation: the figures, no GIF.
    let none = dir.path().join("none");
    ok_json(&run(&[
        "fretting-loop",
        "--config",
        cfg.to_str().unwrap(),
        "--out",
        none.to_str().unwrap(),
        "--json",
        "--no-animation",
    ]));
    assert!(none.join("fretting_loop.svg").is_file() && !none.join("loop_pq.gif").exists());
}

/// More increments in the cycle than frames (docs/composite.md#animation): q = 16 increments per
/// quarter, 4q + 1 = 65 increments, draw `MAX_FRAMES` = 60 frames (the first and the last
/// increment among them, by `frame_records`), each differing from the one before, well under 2 MB.
#[test]
fn loop_animation_caps_the_frames() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("loop.toml");
    std::fs::write(
        &cfg,
        "grid = 16\nnormal_steps = 4\namplitude = 0.04e-6\nshift_step = 0.0025e-6\n",
    )
    .unwrap();
    let out = dir.path().join("loop");
    let v = ok_json(&run(&[
        "fretting-loop",
        "--config",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]));
    let increments = v["increments"].as_u64().unwrap() as usize;
    let q = (increments - 4) / 5;
    assert!(4 * q + 1 > halfspace::animation::MAX_FRAMES, "q = {q}");
    let gif = out.join("loop_pq.gif");
    let f = frames(&gif);
    assert_eq!(f.len(), halfspace::animation::MAX_FRAMES);
    check_frames(&f, (480, 232));
    assert!(std::fs::metadata(&gif).unwrap().len() < 2_000_000);
}
