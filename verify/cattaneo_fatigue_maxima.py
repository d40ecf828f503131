"""The Cattaneo–Mindlin fretting cycle of two identical bodies (issue 22, "Checks"; docs/fatigue.md)
at every cell centre of a window of the fatigue box around the criteria's maxima, on several grids:
the reference for the maxima of the indices and their locations.

Same physics as verify/cattaneo_fatigue.py (Boussinesq/Cerruti point-force stresses, Johnson 1985
Eqs. 3.19, 3.22a, integrated over the closed-form Mindlin–Deresiewicz tractions of the closed cycle,
Johnson §7.3), but a fixed vectorised cubature instead of scipy's adaptive quad_vec, so that a
window of hundreds of cells costs minutes, not hours:

  stress(P, z) = ∫_disc K(P − ξ, z) sqrt(c² − |ξ|²) dξ  in polar coordinates (ρ, φ) about the
  field point's projection P (ξ = P + ρ e(φ)), so the near-singular kernel (scale z) sits at ρ = 0:
  * P inside the disc: ρ ∈ [0, ρ_b(φ)]; [0, ρ_b/2] by ρ = z sinh u (removes the 1/(ρ² + z²) peak),
    [ρ_b/2, ρ_b] by ρ = ρ_b − (ρ_b/2) s² (removes the square root of the traction at the rim);
  * P outside: φ over the cone that meets the disc, ρ over the chord by ρ = m + h sin θ (the
    traction is h cos θ);
  * φ by Gauss–Legendre on panels graded geometrically towards the direction of the nearest rim
    point (where the ray length or the kernel changes fastest), both ρ pieces by Gauss–Legendre.
The cubature is checked against the adaptive quad_vec paths of datasets/cattaneo_fatigue.json
(six cells, 41 increments; asserted 1e-8 p₀) and against itself with twice the nodes (printed).

Grids: the fretting loop's N² cells over 4.16 a, layers at depth (2k + 1) h/2. The window, from the
solver's maxima on 32² and 64² (all four criteria peak in the first layer at |x| ≈ 0.9–1.0 a,
|y| ≤ 0.4 a, on the side where the tangential traction at B points away, by the cycle's mirror
symmetries in x and y the same on both sides): WINDOWS below. Writes datasets/cattaneo_fatigue_maxima.json (per grid: cells (i, j, k), points
(x, y, z)/a, stress paths per p₀, Voigt 11, 22, 33, 23, 13, 12, tension positive, rounded to 1e-9 p₀).
Run: verify/.venv/bin/python verify/cattaneo_fatigue_maxima.py  (a few minutes).
"""
import json
import pathlib
import sys
import time

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from verify.cattaneo_fatigue import CHI, EXTENT, MU, QUARTER  # noqa: E402
from verify.subsurface import G, LAM, NU, check_surface_green, disp_normal, disp_tangential  # noqa: E402

GRIDS = [32, 64, 128]
# Per grid: x/a range, y/a range, layers (the finest grid's window is narrower and one layer deep
# to keep the cost in minutes: the two coarser grids show that the maxima sit in the first layer).
WINDOWS = {
    32: ((0.80, 1.25), (0.0, 0.50), 2),
    64: ((0.80, 1.25), (0.0, 0.40), 2),
    128: ((0.86, 1.15), (0.0, 0.30), 1),
}


def kernel(disp, x, y, z):
    """Voigt stresses (6, M) of a unit point force at the origin, at points (x, y, z) (arrays),
    by complex-step gradients of the displacement (exact to rounding)."""
    h = 1e-30
    grad = np.empty((3, 3) + x.shape)
    base = [x.astype(complex), y.astype(complex), np.full(x.shape, z, dtype=complex)]
    for j in range(3):
        arg = list(base)
        arg[j] = arg[j] + 1j * h
        grad[:, j] = np.imag(np.array(disp(*arg))) / h
    eps = 0.5 * (grad + grad.transpose(1, 0, *range(2, grad.ndim)))
    tr = eps[0, 0] + eps[1, 1] + eps[2, 2]
    s = 2 * G * eps
    for k in range(3):
        s[k, k] = s[k, k] + LAM * tr
    return np.array([s[0, 0], s[1, 1], s[2, 2], s[1, 2], s[0, 2], s[0, 1]])


def graded_panels(half_width, first, nodes):
    """Gauss–Legendre nodes and weights on [−half_width, half_width], panels graded geometrically
    (ratio 2) from ±first towards 0."""
    g, w = np.polynomial.legendre.leggauss(nodes)
    edges = [0.0]
    e = min(first, half_width)
    while e < half_width:
        edges.append(e)
        e *= 2
    edges.append(half_width)
    xs, ws = [], []
    for lo, hi in zip(edges[:-1], edges[1:]):
        mid, half = (lo + hi) / 2, (hi - lo) / 2
        for sign in (1, -1):
            xs.append(sign * (mid + half * g))
            ws.append(half * w)
    return np.concatenate(xs), np.concatenate(ws)


def gauss(lo, hi, nodes):
    g, w = np.polynomial.legendre.leggauss(nodes)
    return (lo + hi) / 2 + (hi - lo) / 2 * g, (hi - lo) / 2 * w


def disc_stress(point, c, disp, refine=1):
    """∫ K(P − ξ, z) sqrt(c² − |ξ|²) dξ over |ξ| < c: the stress (6,) at `point` = (x, y, z)."""
    x0, y0, z0 = point
    pr = np.hypot(x0, y0)
    n_phi, n_rho = int(round(16 * refine)), int(round(32 * refine))
    if pr < c:
        # φ about the outward direction (shortest ray); ρ_b(φ) from the quadratic of the rim.
        phi_out = np.arctan2(y0, x0) if pr > 0 else 0.0
        dphi, wphi = graded_panels(np.pi, 1e-4, n_phi)
        phi = phi_out + dphi
        ex, ey = np.cos(phi), np.sin(phi)
        pe = x0 * ex + y0 * ey
        root = np.sqrt(c * c - pr * pr + pe * pe)
        rb, ra = root - pe, root + pe  # f² = (ρ_b − ρ)(ρ + ρ_a)
        total = np.zeros(6)
        # [0, ρ_b/2]: ρ = z sinh u.
        gu, wu = np.polynomial.legendre.leggauss(n_rho)
        umax = np.arcsinh(rb / 2 / z0)
        u = (gu[None, :] + 1) / 2 * umax[:, None]
        rho = z0 * np.sinh(u)
        jac = z0 * np.cosh(u) * (umax[:, None] / 2) * wu[None, :]
        f = np.sqrt(np.maximum((rb[:, None] - rho) * (rho + ra[:, None]), 0.0))
        k = kernel(disp, -rho * ex[:, None], -rho * ey[:, None], z0)
        total += np.einsum("kij,ij,i->k", k, f * rho * jac, wphi)
        # [ρ_b/2, ρ_b]: ρ = ρ_b − (ρ_b/2) s².
        gs, ws = gauss(0.0, 1.0, n_rho)
        s = gs[None, :]
        rho = rb[:, None] * (1 - s * s / 2)
        jac = rb[:, None] * s * ws[None, :]
        f = np.sqrt((rb[:, None] * s * s / 2) * (rho + ra[:, None]))
        k = kernel(disp, -rho * ex[:, None], -rho * ey[:, None], z0)
        total += np.einsum("kij,ij,i->k", k, f * rho * jac, wphi)
        return total
    # Outside: the cone towards the centre, half-angle α; chord ρ = m + h sin θ.
    alpha = np.arcsin(min(c / pr, 1.0))
    phi_in = np.arctan2(-y0, -x0)
    dphi, wphi = graded_panels(alpha, min(1e-4, alpha / 4), n_phi)
    phi = phi_in + dphi
    ex, ey = np.cos(phi), np.sin(phi)
    pe = x0 * ex + y0 * ey  # < 0
    half = np.sqrt(np.maximum(c * c - (pr * np.sin(dphi)) ** 2, 0.0))
    mid = -pe
    # θ graded towards the near end (−π/2), where the kernel is largest.
    # graded_panels on [−π, π] graded towards 0, shifted by −π/2: the half in [−π/2, π/2] is kept.
    gt, wt = graded_panels(np.pi, np.pi / 64, n_rho // 2)
    theta = gt - np.pi / 2
    keep = theta >= -np.pi / 2
    theta, wt = theta[keep], wt[keep]
    rho = mid[:, None] + half[:, None] * np.sin(theta[None, :])
    f = half[:, None] * np.cos(theta[None, :])
    jac = half[:, None] * np.cos(theta[None, :]) * wt[None, :]
    k = kernel(disp, -rho * ex[:, None], -rho * ey[:, None], z0)
    return np.einsum("kij,ij,i->k", k, f * rho * jac, wphi)


def path(point, refine=1):
    """The 4 QUARTER + 1 stresses of the closed cycle at `point`, per p₀ (a = p₀ = 1); the same
    tractions as verify/cattaneo_fatigue.py's `path`."""
    a_over_k = 1 - (1 - CHI) ** (2 / 3)
    c_star = np.sqrt(1 - a_over_k)
    # p = p₀ sqrt(1 − r²) = sqrt(c² − r²) with c = a = 1.
    sp = disc_stress(point, 1.0, disp_normal, refine)
    cache = {}

    def shear(c):
        key = round(c, 14)
        if key not in cache:
            cache[key] = disc_stress(point, c, disp_tangential, refine) if c > 0 else np.zeros(6)
        return cache[key]

    out = []
    for t in range(4 * QUARTER + 1):
        if t <= 2 * QUARTER:
            b = np.sqrt(1 - t / QUARTER * a_over_k / 2)
            q = -shear(1.0) - shear(c_star) + 2 * shear(b)
        else:
            b = np.sqrt(1 - (t - 2 * QUARTER) / QUARTER * a_over_k / 2)
            q = shear(1.0) + shear(c_star) - 2 * shear(b)
        out.append(sp + MU * q)
    return np.array(out)


def window_cells(n):
    h = EXTENT / n
    (x0, x1), (y0, y1), layers = WINDOWS[n]
    cells = []
    for i in range(n):
        x = (i + 0.5) * h - EXTENT / 2
        if not x0 <= x <= x1:
            continue
        for j in range(n):
            y = (j + 0.5) * h - EXTENT / 2
            if not y0 <= y <= y1:
                continue
            for k in range(layers):
                cells.append(([i, j, k], [x, y, (k + 0.5) * h]))
    return cells


def check_against_adaptive():
    """The fixed cubature against quad_vec's paths (datasets/cattaneo_fatigue.json)."""
    root = pathlib.Path(__file__).resolve().parent.parent
    fx = json.loads((root / "datasets" / "cattaneo_fatigue.json").read_text())
    worst = 0.0
    for entries in fx["grids"].values():
        for e in entries:
            worst = max(worst, np.abs(path(e["point"]) - np.array(e["stress"])).max())
    print(f"fixed cubature vs quad_vec at the six cells: max |Δσ|/p₀ = {worst:.2e}", flush=True)
    assert worst < 1e-8, worst
    return worst


def main():
    """`cattaneo_fatigue_maxima.py [N ...]`: the grids N (default all); each grid is merged into
    the fixture as it completes."""
    grids = [int(v) for v in sys.argv[1:]] or GRIDS
    check_surface_green()
    adaptive = check_against_adaptive()
    # Self-convergence at the hardest cells: the first layer of the finest grid nearest the rim.
    h = EXTENT / GRIDS[-1]
    self_check = 0.0
    for x in (0.98, 1.0, 1.02):
        i = int(np.floor((x + EXTENT / 2) / h))
        p = [(i + 0.5) * h - EXTENT / 2, 0.5 * h, 0.5 * h]
        self_check = max(self_check, np.abs(path(p) - path(p, refine=2)).max())
    print(f"fixed cubature vs twice the nodes, first layer of {GRIDS[-1]}² at the rim: {self_check:.2e}")
    assert self_check < 1e-8, self_check
    out = pathlib.Path(__file__).resolve().parent.parent / "datasets" / "cattaneo_fatigue_maxima.json"
    for n in grids:
        start = time.time()
        cells = window_cells(n)
        stress = [np.round(path(p), 9).tolist() for _, p in cells]
        entry = {"cells": [c for c, _ in cells], "points": [p for _, p in cells], "stress": stress,
                 "window": WINDOWS[n], "seconds": round(time.time() - start)}
        fixture = json.loads(out.read_text()) if out.exists() else {"grids": {}}
        fixture.update({
            "generator": "verify/cattaneo_fatigue_maxima.py",
            "method": "fixed graded Gauss cubature in polar coordinates about each point of Boussinesq/Cerruti "
                      "point-force stresses over Hertz p and the Mindlin-Deresiewicz q of the closed cycle",
            "check_vs_quad_vec": adaptive, "check_vs_double_nodes": self_check,
            "nu": NU, "friction": MU, "q_star_over_mu_w": CHI, "steps_per_quarter": QUARTER,
            "extent_over_a": EXTENT,
            "layout": "grids[n]: cells (i, j, layer), points (x, y, z)/a, stress[cell][increment][component] "
                      "per p0, Voigt 11,22,33,23,13,12, tension positive; window ((x0, x1), (y0, y1), layers) / a",
        })
        fixture["grids"][str(n)] = entry
        tmp = out.with_name(f"{out.name}.{n}.tmp")
        tmp.write_text(json.dumps(fixture, separators=(",", ":"), sort_keys=True))
        tmp.replace(out)
        print(f"{n}²: {len(cells)} cells in {time.time() - start:.0f} s -> {out}", flush=True)


if __name__ == "__main__":
    main()
