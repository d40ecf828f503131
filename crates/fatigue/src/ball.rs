//! Minimum enclosing (circumscribed) ball of a point set in the 5D deviatoric space, exact up to
//! rounding: Welzl's move-to-front recursion with Gärtner's pivoting and his incremental
//! circumcentre update (Welzl 1991; Gärtner 1999, "Fast and robust smallest enclosing balls",
//! ESA'99, LNCS 1643; docs/fatigue.md, "Minimum enclosing ball").
//!
//! The ball is determined by a support set of at most `DIM + 1 = 6` affinely independent points on
//! its boundary; its centre is the circumcentre of the support in the support's affine hull.
//! Gärtner's update builds the circumcentres incrementally: with `q₀` the first support point,
//! `Q_m = v_m − Σ_{i<m} (2 Q_i·v_m / z_i) Q_i` (`v_m = p_m − q₀`, Gram–Schmidt), `z_m = 2|Q_m|²`,
//! `e = |p_m − c_{m−1}|² − r²_{m−1}`, `c_m = c_{m−1} + (e/z_m) Q_m`, `r²_m = r²_{m−1} + e²/(2 z_m)`.
//! A push whose `z_m ≤ ε_push r²` (the new point is affinely dependent on the support to
//! rounding: duplicates, cospherical and collinear points) is refused, which is what makes the
//! algorithm robust (Gärtner 1999, Section 4).
use crate::error::FatigueError;

/// Dimension of the points (the deviatoric space).
pub const DIM: usize = 5;
const MAX_SUPPORT: usize = DIM + 1;
/// A point is outside the current ball when its excess `|p − c|² − r²` exceeds this fraction of
/// `r²` (coordinates are normalised to unit range first).
const EXCESS_RELATIVE: f64 = 1e-14;
/// A push is refused when `z_m = 2|Q_m|²` is below this fraction of `r²`: `|Q_m| < 7e-11 r`.
const PUSH_RELATIVE: f64 = 1e-20;

/// A ball `{x : |x − centre| ≤ radius}` in the 5D deviatoric space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball {
    pub centre: [f64; DIM],
    pub radius: f64,
}

/// What the ball search did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BallInfo {
    /// Number of points of the support set on the boundary (1 ..= 6).
    pub support_size: usize,
    /// Pivot iterations of the outer loop (Gärtner 1999, `pivot_mb`).
    pub iterations: usize,
}

/// Reusable buffers of [`min_enclosing_ball`]: no allocation once they have grown to the path
/// length.
#[derive(Clone, Debug, Default)]
pub struct BallScratch {
    points: Vec<[f64; DIM]>,
    order: Vec<usize>,
}

/// The minimum enclosing ball of `points` (exact to rounding; Welzl 1991, Gärtner 1999).
///
/// The returned radius is `max_i |points_i − centre|` for the computed centre, so the ball
/// encloses every point by construction; it equals the exact minimum radius to a relative
/// `1e-12` or better (tests/ball.rs measures it against brute force).
pub fn min_enclosing_ball(
    points: &[[f64; DIM]],
    scratch: &mut BallScratch,
) -> Result<(Ball, BallInfo), FatigueError> {
    let first = *points.first().ok_or(FatigueError::EmptyPath)?;
    for (i, p) in points.iter().enumerate() {
        if let Some((k, &v)) = p.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(FatigueError::NonFiniteStress {
                increment: i,
                component: k,
                value: v,
            });
        }
    }
    // Normalise: y = (x − x₀)/scale with scale the largest coordinate deviation.
    let scale = points
        .iter()
        .flat_map(|p| p.iter().zip(&first).map(|(a, b)| (a - b).abs()))
        .fold(0.0, f64::max);
    if scale == 0.0 {
        return Ok((
            Ball {
                centre: first,
                radius: 0.0,
            },
            BallInfo {
                support_size: 1,
                iterations: 0,
            },
        ));
    }
    scratch.points.clear();
    scratch.points.extend(points.iter().map(|p| {
        let mut y = [0.0; DIM];
        for k in 0..DIM {
            y[k] = (p[k] - first[k]) / scale;
        }
        y
    }));
    scratch.order.clear();
    scratch.order.extend(0..points.len());
    let mut mb = Miniball::new(&scratch.points, &mut scratch.order);
    let iterations = mb.pivot_mb()?;
    let c = mb.c[mb.current];
    let support_size = mb.s;
    let mut centre = [0.0; DIM];
    for k in 0..DIM {
        centre[k] = first[k] + scale * c[k];
    }
    let radius = points
        .iter()
        .map(|p| distance(p, &centre))
        .fold(0.0, f64::max);
    Ok((
        Ball { centre, radius },
        BallInfo {
            support_size,
            iterations,
        },
    ))
}

fn distance(a: &[f64; DIM], b: &[f64; DIM]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

fn sqr_dist(a: &[f64; DIM], b: &[f64; DIM]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
}

/// Gärtner's `Miniball_b` (the ball through the forced points) and the move-to-front list.
struct Miniball<'a> {
    pts: &'a [[f64; DIM]],
    /// The move-to-front list: a permutation of the point indices.
    order: &'a mut [usize],
    /// Position in `order` one past the current support.
    support_end: usize,
    /// Number of forced (pushed) points.
    m: usize,
    /// Size of the support of the current ball.
    s: usize,
    q0: [f64; DIM],
    z: [f64; MAX_SUPPORT],
    f: [f64; MAX_SUPPORT],
    v: [[f64; DIM]; MAX_SUPPORT],
    a: [[f64; MAX_SUPPORT]; MAX_SUPPORT],
    c: [[f64; DIM]; MAX_SUPPORT],
    sqr_r: [f64; MAX_SUPPORT],
    /// Index into `c`/`sqr_r` of the current ball.
    current: usize,
    current_sqr_r: f64,
}

impl<'a> Miniball<'a> {
    fn new(pts: &'a [[f64; DIM]], order: &'a mut [usize]) -> Self {
        Self {
            pts,
            order,
            support_end: 0,
            m: 0,
            s: 0,
            q0: [0.0; DIM],
            z: [0.0; MAX_SUPPORT],
            f: [0.0; MAX_SUPPORT],
            v: [[0.0; DIM]; MAX_SUPPORT],
            a: [[0.0; MAX_SUPPORT]; MAX_SUPPORT],
            c: [[0.0; DIM]; MAX_SUPPORT],
            sqr_r: [0.0; MAX_SUPPORT],
            current: 0,
            // The empty ball: c = 0, r² = −1 (every point has positive excess).
            current_sqr_r: -1.0,
        }
    }

    fn excess(&self, p: &[f64; DIM]) -> f64 {
        sqr_dist(p, &self.c[self.current]) - self.current_sqr_r
    }

    fn outside(&self, e: f64) -> bool {
        e > EXCESS_RELATIVE * self.current_sqr_r.max(0.0)
    }

    /// Force `p` onto the boundary; `false` if it is affinely dependent on the forced points.
    fn push(&mut self, p: &[f64; DIM]) -> bool {
        let m = self.m;
        if m == 0 {
            self.q0 = *p;
            self.c[0] = *p;
            self.sqr_r[0] = 0.0;
        } else {
            let mut vm = [0.0; DIM];
            for k in 0..DIM {
                vm[k] = p[k] - self.q0[k];
            }
            for i in 1..m {
                let dot: f64 = self.v[i].iter().zip(&vm).map(|(x, y)| x * y).sum();
                self.a[m][i] = 2.0 * dot / self.z[i];
            }
            for i in 1..m {
                let aim = self.a[m][i];
                for k in 0..DIM {
                    vm[k] -= aim * self.v[i][k];
                }
            }
            let zm = 2.0 * vm.iter().map(|x| x * x).sum::<f64>();
            if zm <= PUSH_RELATIVE * self.current_sqr_r {
                return false;
            }
            self.v[m] = vm;
            self.z[m] = zm;
            let e = sqr_dist(p, &self.c[m - 1]) - self.sqr_r[m - 1];
            self.f[m] = e / zm;
            for k in 0..DIM {
                self.c[m][k] = self.c[m - 1][k] + self.f[m] * vm[k];
            }
            self.sqr_r[m] = self.sqr_r[m - 1] + e * self.f[m] / 2.0;
        }
        self.current = m;
        self.current_sqr_r = self.sqr_r[m];
        self.m += 1;
        self.s = self.m;
        true
    }

    fn pop(&mut self) {
        self.m -= 1;
    }

    /// Move the point at position `j` of the list to the front (positions `0..j` shift by one).
    fn move_to_front(&mut self, j: usize) {
        if self.support_end <= j {
            self.support_end += 1;
        }
        self.order[..=j].rotate_right(1);
    }

    /// Welzl's move-to-front recursion over the list positions `0..end` with the forced points.
    fn mtf_mb(&mut self, end: usize) {
        self.support_end = 0;
        if self.m == MAX_SUPPORT {
            return;
        }
        let mut k = 0;
        while k < end {
            let j = k;
            k += 1;
            let p = self.pts[self.order[j]];
            if self.outside(self.excess(&p)) && self.push(&p) {
                self.mtf_mb(j);
                self.pop();
                self.move_to_front(j);
            }
        }
    }

    /// Gärtner's pivoting: returns the number of pivot iterations.
    fn pivot_mb(&mut self) -> Result<usize, FatigueError> {
        let n = self.order.len();
        let mut t = 1;
        self.mtf_mb(t);
        let max_iterations = 64 * n + 64;
        let mut iterations = 0;
        loop {
            let mut max_e = 0.0;
            let mut pivot = t;
            for pos in t..n {
                let e = self.excess(&self.pts[self.order[pos]]);
                if e > max_e {
                    max_e = e;
                    pivot = pos;
                }
            }
            if !self.outside(max_e) {
                return Ok(iterations);
            }
            iterations += 1;
            if iterations > max_iterations {
                return Err(FatigueError::NoConvergence { iterations });
            }
            t = self.support_end;
            if t == pivot {
                t += 1;
            }
            let old_sqr_r = self.current_sqr_r;
            let p = self.pts[self.order[pivot]];
            // The pivot has positive excess, so the (empty-forced) push always succeeds.
            if !self.push(&p) {
                return Ok(iterations);
            }
            self.mtf_mb(self.support_end);
            self.pop();
            self.move_to_front(pivot);
            if t < pivot {
                t += 1;
            }
            if self.current_sqr_r <= old_sqr_r {
                return Ok(iterations);
            }
        }
    }
}

/// The minimum enclosing ball by brute force (the dense twin of [`min_enclosing_ball`], for
/// verification, `O(n⁷)`): over all subsets of at most 6 affinely independent points, the
/// circumball in their affine hull (centre `q₀ + Σ λ_j v_j`, `Σ_j 2 v_i·v_j λ_j = |v_i|²`,
/// `v_i = p_i − q₀`), keep the smallest that contains every point to a relative `1e-9`.
/// `None` for an empty set.
pub fn min_enclosing_ball_brute_force(points: &[[f64; DIM]]) -> Option<Ball> {
    let n = points.len();
    let mut best: Option<Ball> = None;
    let mut subset = Vec::with_capacity(MAX_SUPPORT);
    let scale = points
        .iter()
        .flat_map(|p| points.iter().map(move |q| distance(p, q)))
        .fold(0.0, f64::max);
    fn recurse(
        points: &[[f64; DIM]],
        start: usize,
        subset: &mut Vec<usize>,
        scale: f64,
        best: &mut Option<Ball>,
    ) {
        if !subset.is_empty() {
            if let Some(ball) = circumball(points, subset) {
                let contains = points
                    .iter()
                    .all(|p| distance(p, &ball.centre) <= ball.radius + 1e-9 * scale);
                if contains && best.is_none_or(|b| ball.radius < b.radius) {
                    *best = Some(ball);
                }
            }
        }
        if subset.len() == MAX_SUPPORT {
            return;
        }
        for i in start..points.len() {
            subset.push(i);
            recurse(points, i + 1, subset, scale, best);
            subset.pop();
        }
    }
    if n == 0 {
        return None;
    }
    recurse(points, 0, &mut subset, scale, &mut best);
    best
}

/// Circumball of the points `subset` in their affine hull, `None` if they are affinely dependent
/// (Gram matrix pivot below `1e-10` of its largest diagonal entry).
fn circumball(points: &[[f64; DIM]], subset: &[usize]) -> Option<Ball> {
    let q0 = points[subset[0]];
    let m = subset.len() - 1;
    let mut v = [[0.0; DIM]; MAX_SUPPORT];
    for (i, &s) in subset[1..].iter().enumerate() {
        for k in 0..DIM {
            v[i][k] = points[s][k] - q0[k];
        }
    }
    let dot = |a: &[f64; DIM], b: &[f64; DIM]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    // Augmented Gram system [2 v_i·v_j | |v_i|²].
    let mut g = [[0.0; MAX_SUPPORT + 1]; MAX_SUPPORT];
    let mut max_diag: f64 = 0.0;
    for i in 0..m {
        for j in 0..m {
            g[i][j] = 2.0 * dot(&v[i], &v[j]);
        }
        g[i][m] = dot(&v[i], &v[i]);
        max_diag = max_diag.max(g[i][i]);
    }
    // Gaussian elimination with partial pivoting.
    for col in 0..m {
        let piv = (col..m).max_by(|&a, &b| g[a][col].abs().total_cmp(&g[b][col].abs()))?;
        if g[piv][col].abs() <= 1e-10 * max_diag {
            return None;
        }
        g.swap(col, piv);
        for row in 0..m {
            if row != col {
                let factor = g[row][col] / g[col][col];
                for k in col..=m {
                    g[row][k] -= factor * g[col][k];
                }
            }
        }
    }
    let mut centre = q0;
    for i in 0..m {
        let lambda = g[i][m] / g[i][i];
        for k in 0..DIM {
            centre[k] += lambda * v[i][k];
        }
    }
    let radius = distance(&q0, &centre);
    Some(Ball { centre, radius })
}
