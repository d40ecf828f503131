//! Force control of a tangential increment: the shift at which the tangential force reaches a
//! target, by bracketing and Brent's method on the monotone map `D₁ ↦ Q₁(D₁)` (used by
//! [`super::ContactProblem::increment_with_force`] and [`super::InhomogeneousContact`]).

use crate::SamError;

/// The shift `D₁` at which a monotone `D₁ ↦ Q₁(D₁)` reaches a target: `eval(D₁)` returns
/// `(Q₁(D₁) − target, info)`; bracketed from `start` in steps of `bracket` (doubling) toward the
/// target, then Brent's method to `|Q₁ − target| ≤ tol_q`. The last evaluation is at the returned
/// shift (so the caller's state is that solution). One search for every force-controlled
/// increment (with and without inhomogeneities).
pub fn shift_for_force<I>(
    start: f64,
    bracket: f64,
    tol_q: f64,
    eval: &mut impl FnMut(f64) -> Result<(f64, I), SamError>,
) -> Result<(I, f64), SamError> {
    // Bracket: from the previous shift, step by `bracket` toward the target until the sign flips.
    let (mut a, (mut fa, _)) = (start, eval(start)?);
    let mut last;
    let dir = if fa < 0.0 { 1.0 } else { -1.0 };
    let mut step = bracket.abs().max(f64::MIN_POSITIVE);
    let (mut b, (mut fb, mut info_b)) = (start + dir * step, eval(start + dir * step)?);
    last = b;
    let mut expansions = 0;
    while fa * fb > 0.0 {
        expansions += 1;
        if expansions > 60 {
            return Err(SamError::NoConvergence {
                solver: "tangential force bracket",
                iterations: expansions,
                residual: fb,
            });
        }
        a = b;
        fa = fb;
        step *= 2.0;
        b = a + dir * step;
        let r = eval(b)?;
        last = b;
        fb = r.0;
        info_b = r.1;
    }
    // Brent's method.
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..100 {
        if fb.abs() <= tol_q {
            break;
        }
        if (fc > 0.0) == (fb > 0.0) {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 1e-15;
        let m = 0.5 * (c - b);
        if m.abs() <= tol {
            break;
        }
        if e.abs() >= tol && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol { d } else { tol * m.signum() };
        let r = eval(b)?;
        last = b;
        fb = r.0;
        info_b = r.1;
    }
    // The state must be the solution at the returned shift (Brent swaps b and c).
    if last != b {
        info_b = eval(b)?.1;
    }
    Ok((info_b, b))
}
