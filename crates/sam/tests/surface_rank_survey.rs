//! Survey (ignored; `cargo test --release -p halfspace-sam --test surface_rank_survey -- --ignored
//! --nocapture`): the singular values of [LN11]'s composite surface response `T` (stiff fibres,
//! fibre-centred) restricted to the candidate cells within 1.3a, at 32² and 40² (coarser grids
//! put the fibres in the first layer) — the numerical rank a compressed (low-rank) surface
//! operator would need (docs/theory-sam.md#surface-response-operator, issue 21). `T` is compared with the homogeneous compliance of the same cells (Boussinesq's
//! self term `K₀`, the largest entry of the contact's own operator): roughly, an error `δT` moves
//! the pressure by `δT/K₀` of `p₀`, so the count of `σ_k > tol · K₀` is printed too. Measured
//! (docs/theory-sam.md#surface-response-operator): full rank at 1e-6 (946 of 948, 1412 of 1452).
use halfspace_sam::contact::NestedParams;
use halfspace_sam::drivers::fretting_loop::{FrettingLoop, LoopCase};
use halfspace_sam::eim::FibreLayout;

#[test]
#[ignore]
fn singular_values_of_the_composite_surface_response() {
    for n in [32usize, 40] {
        let mut case = LoopCase::default()
            .composite(FibreLayout::FibreCentred, 2.0)
            .unwrap();
        case.grid = n;
        case.surface_operator_over_a = Some(1.3);
        let t0 = std::time::Instant::now();
        // Coarse grids put the fibres' tops in the first layer (refused).
        let Ok(lp) =
            FrettingLoop::with_params(case.clone(), case.nested_params(NestedParams::default()))
        else {
            println!("{n}²: refused (fibres in the first layer)");
            continue;
        };
        let build = t0.elapsed().as_secs_f64();
        let response = lp.solver().nested().unwrap().surface_response().unwrap();
        let m = response.cells().len();
        let cols = response.components() * m;
        let t = response.restricted();
        let x = faer::Mat::<f64>::from_fn(3 * m, cols, |i, j| t[i * cols + j]);
        let sv = x.singular_values().unwrap();
        // Boussinesq's self compliance of a square cell of side h: u₃ = 4 ln(1 + √2) h (1 − ν²)/(π E)
        // per unit pressure (docs/theory-sam.md#influence-coefficients).
        let h = case.extent() / n as f64;
        let k0 = 4.0 * (1.0 + 2f64.sqrt()).ln() * h * (1.0 - case.nu * case.nu)
            / (std::f64::consts::PI * case.e);
        println!(
            "{n}²: {m} candidates, {cols} columns, build {build:.1} s ({} EIM applications); σ₁ = {:.3e} = {:.3e} K₀",
            response.build_iterations(),
            sv[0],
            sv[0] / k0
        );
        for tol in [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
            let r1 = sv.iter().filter(|v| **v > tol * sv[0]).count();
            let rk = sv.iter().filter(|v| **v > tol * k0).count();
            println!("  tol {tol:e}: rank {r1} (σ > tol·σ₁), {rk} (σ > tol·K₀) of {cols}");
        }
    }
}
