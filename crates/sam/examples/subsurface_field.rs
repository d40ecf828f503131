//! What one von Mises field of the composite fretting loop costs (issue 21, docs/performance.md
//! "The 128² composite command outside the EIM (issue 21)"): [LN11]'s stiff fibres
//! (fibre-centred) at `N²`, `k` increments of the loop, then the stress field below the state down
//! to the loop's subsurface depth `a` (the field stored at each of the points A–D), timed
//! `repeats` times (wall and process CPU), with the homogeneous field (the reference loop's) of
//! the same tractions; a hash of the von Mises bits (equal hashes from two binaries: the same
//! field bit for bit) and the peak RSS before and after.
//!
//! Run: `cargo run --release -p halfspace-sam --example subsurface_field -- N [k] [repeats]`.

use halfspace_sam::drivers::fretting_loop::{FrettingLoop, LoopCase};
use halfspace_sam::eim::FibreLayout;
use halfspace_sam::subsurface::{subsurface_stress, von_mises_fields, FieldSources};

#[path = "probe/mod.rs"]
mod probe;
use probe::process_cpu_seconds as cpu;

/// `VmHWM` and `VmRSS` of this process (MB).
fn memory() -> (f64, f64) {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kb = |key: &str| {
        status
            .lines()
            .find(|l| l.starts_with(key))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(0.0)
            / 1024.0
    };
    (kb("VmHWM:"), kb("VmRSS:"))
}

fn hash(v: &[f64]) -> u64 {
    v.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, x| {
        (h ^ x.to_bits()).wrapping_mul(0x100_0000_01b3)
    })
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.first().and_then(|v| v.parse().ok()).unwrap_or(64);
    let k: usize = args.get(1).and_then(|v| v.parse().ok()).unwrap_or(3);
    let repeats: usize = args.get(2).and_then(|v| v.parse().ok()).unwrap_or(1);
    let mut case = LoopCase::default()
        .composite(FibreLayout::FibreCentred, 2.0)
        .unwrap();
    case.grid = n;
    let depth = case.hertz_radius();
    let mut lp = FrettingLoop::new(case.clone()).unwrap();
    for _ in 0..k {
        lp.step().unwrap();
    }
    // Four states (the increments k, k + 1, k + 2, k + 3), as the points A–D are four.
    let mut states = Vec::new();
    for _ in 0..4 {
        lp.step().unwrap();
        let st = lp.solver().problem().state();
        let eps = lp.solver().nested().unwrap().eigenstrain().to_vec();
        states.push((st.pressure.clone(), st.shear.clone(), eps));
    }
    let (hwm, rss) = memory();
    println!(
        "{n}², {} increments: VmHWM {hwm:.0} MB, VmRSS {rss:.0} MB before the fields",
        k + 4
    );
    let solver = lp.solver();
    let grid = *solver.problem().grid();
    let set = solver.nested().unwrap().inclusions();
    for r in 0..repeats {
        if std::env::var_os("SUBSURFACE_FIELD_NEW_ONLY").is_none() {
            let (t, c) = (std::time::Instant::now(), cpu());
            let mut bits = Vec::new();
            for (p, q, eps) in &states {
                let f = subsurface_stress(
                    &grid,
                    case.e,
                    case.nu,
                    p,
                    Some([q[0].as_slice(), q[1].as_slice()]),
                    depth,
                    Some((set, eps.as_slice())),
                )
                .unwrap();
                bits.push(format!("{:016x}", hash(&f.von_mises)));
            }
            let (wall, used) = (t.elapsed().as_secs_f64(), cpu() - c);
            let (hwm, rss) = memory();
            println!(
                "round {r}: 4 composite fields one by one (subsurface_stress): {wall:.2} s wall, {used:.2} s CPU, von Mises bits {}, VmHWM {hwm:.0} MB, VmRSS {rss:.0} MB",
                bits.join(" ")
            );
        }
        let (t, c) = (std::time::Instant::now(), cpu());
        let sources: Vec<FieldSources> = states
            .iter()
            .map(|(p, q, eps)| FieldSources {
                pressure: p,
                shear: Some([q[0].as_slice(), q[1].as_slice()]),
                eigenstrain: Some(eps),
            })
            .collect();
        let fields = von_mises_fields(&grid, case.e, case.nu, depth, Some(set), &sources).unwrap();
        let (wall, used) = (t.elapsed().as_secs_f64(), cpu() - c);
        let (hwm, rss) = memory();
        let bits: Vec<String> = fields.iter().map(|f| format!("{:016x}", hash(f))).collect();
        println!(
            "round {r}: 4 composite fields at once (von_mises_fields): {wall:.2} s wall, {used:.2} s CPU, von Mises bits {}, VmHWM {hwm:.0} MB, VmRSS {rss:.0} MB",
            bits.join(" ")
        );
    }
}
