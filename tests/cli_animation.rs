//! The animations through the binary: `wear_depth.gif` of `fretting-wear3d`
//! (docs/wear3d.md#figures) and `loop_pq.gif` of `fretting-loop` (docs/composite.md#animation),
//! decoded with the image crate: one frame per record (per increment of the cycle), the frame
//! size, frames that differ; after a resume inside the cycle, one frame per loop point A–D;
//! `--no-animation` writes none.

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
