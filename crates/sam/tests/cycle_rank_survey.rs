//! Survey (ignored; `cargo test --release -p halfspace-sam --test cycle_rank_survey -- --ignored
//! --nocapture`): the singular values of the closed cycle's traction snapshots `(p, q₁, q₂)` of
//! [LN11]'s homogeneous 64² loop — the numerical rank that a low-rank stress history would need
//! (docs/fatigue.md, "Cost on the loop": 81 of 81 at 1e-12, 64 at 1e-4: it does not pay).
use halfspace_sam::drivers::fretting_loop::{FrettingLoop, LoopCase};

#[test]
#[ignore]
fn singular_values_of_the_cycle_tractions() {
    let mut case = LoopCase::default();
    case.fatigue_depth = Some(0.1 * case.hertz_radius());
    let mut lp = FrettingLoop::new(case).unwrap();
    lp.run(|_| std::ops::ControlFlow::Continue(())).unwrap();
    let s = lp.snapshot().cycle_sources.unwrap();
    let (m, t) = (3 * s.cells + s.eigen_len, s.recorded);
    let x = faer::Mat::<f64>::from_fn(m, t, |i, j| {
        let (p, q, _) = s.increment(j);
        let n = s.cells;
        if i < n {
            p[i]
        } else if i < 2 * n {
            q[0][i - n]
        } else {
            q[1][i - 2 * n]
        }
    });
    let sv = x.singular_values().unwrap();
    // The spectrum is complete: Σ σ_k² = ‖X‖_F², and sorted.
    let fro2: f64 = (0..t)
        .flat_map(|j| (0..m).map(move |i| (i, j)))
        .map(|(i, j)| x[(i, j)].powi(2))
        .sum();
    let sum2: f64 = sv.iter().map(|v| v * v).sum();
    assert!((sum2 - fro2).abs() < 1e-12 * fro2, "{sum2} {fro2}");
    assert!(sv.windows(2).all(|w| w[0] >= w[1]));
    for tol in [1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14] {
        let r = sv.iter().filter(|v| **v > tol * sv[0]).count();
        println!("tol {tol:e}: rank {r} of {t}");
    }
    println!("{:?}", sv.iter().map(|v| v / sv[0]).collect::<Vec<_>>());
    // Pressure alone and shear alone.
    for (name, lo, hi) in [("p", 0, s.cells), ("q", s.cells, 3 * s.cells)] {
        let x = faer::Mat::<f64>::from_fn(hi - lo, t, |i, j| s.tractions[j * 3 * s.cells + lo + i]);
        let sv = x.singular_values().unwrap();
        let r: Vec<usize> = [1e-6, 1e-9, 1e-12]
            .iter()
            .map(|tol| sv.iter().filter(|v| **v > tol * sv[0]).count())
            .collect();
        println!("{name}: ranks at 1e-6, 1e-9, 1e-12: {r:?}");
    }
}
