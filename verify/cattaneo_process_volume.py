"""The Cattaneo–Mindlin fretting cycle of two identical bodies (issue 22, "Checks"; docs/fatigue.md,
"Process volume"): the stress paths averaged over process volumes — cubes of side ℓ whose top face
lies on the surface (Fouvry, Kapsa & Vincent 2000) — at a lattice of cube positions around the
contact rim, for ℓ = 0.25a and 0.5a: the reference of the process-volume maxima.

Independent of halfspace's solver and of its Love rectangle kernels and of its averaging:
* the stress at a point is the Boussinesq/Cerruti point-force cubature over the closed-form
  Mindlin–Deresiewicz tractions of the closed cycle (verify/cattaneo_fatigue_maxima.py `path`,
  Johnson 1985 Eqs. 3.19, 3.22a, §7.3), with half its nodes (`refine = 0.5`: 1.5e-6 p₀ from the
  full cubature at z = 0.01a next to the rim, printed by `--check`);
* the cube average (1/ℓ³)∫σ dV by composite two-point Gauss–Legendre on panels of side d = ℓ/4
  in x, y and z (8 × 8 × 8 points per cube), the panels shared by the cubes of the lattice,
  whose centres are d apart (the cubes with top faces at z = 0 and z = d);
* the cycle's mirror symmetry y → −y (σ₂₃, σ₁₂ change sign) gives the nodes at y < 0.
`--check` also compares one cube at the rim with three-point Gauss per panel (printed).

Writes datasets/cattaneo_process_volume.h5 (+ npy, MANIFEST.json) through verify/store.py: per ℓ
the case `cattaneo_pv_<ℓ/a>` with `centres` (M × 3: x, y, centre depth of the cube, over a) and
`stress` (M × 41 × 6: the averaged paths per p₀, Voigt 11, 22, 33, 23, 13, 12, tension
positive). Run: verify/.venv/bin/python -m verify process-volume (about ten minutes; the node
paths are cached in /tmp so an interrupted run resumes).
"""
import pathlib
import sys
import time

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from verify.cattaneo_fatigue import CHI, EXTENT, MU, QUARTER  # noqa: E402
from verify.cattaneo_fatigue_maxima import path  # noqa: E402
from verify.subsurface import NU  # noqa: E402

REFINE = 0.5
# ℓ/a → (first x centre, number of x centres, number of y centres from y = 0), centres d = ℓ/4 apart.
SIDES = {
    0.25: (0.75, 12, 7),
    0.5: (0.625, 9, 4),
}
TOPS = 2  # cubes with top faces at z = 0 and z = d
MIRROR = np.array([1, 1, 1, -1, 1, -1])


def panel_nodes(lo, panels, d, g):
    """Gauss–Legendre nodes and weights (over d) of `panels` panels of width d from `lo`."""
    t, w = np.polynomial.legendre.leggauss(g)
    x = np.concatenate([lo + (k + 0.5) * d + 0.5 * d * t for k in range(panels)])
    return x, np.tile(0.5 * w, panels)


def lattice(side, g=2):
    """The node coordinates (x, y ≥ 0, z) and the cube centres of one ℓ."""
    x0, nx, ny = SIDES[side]
    d = side / 4
    xs, _ = panel_nodes(x0 - side / 2, nx - 1 + 4, d, g)
    ys, _ = panel_nodes(0.0, ny - 1 + 2, d, g)
    zs, _ = panel_nodes(0.0, TOPS - 1 + 4, d, g)
    return xs, ys, zs


def node_paths(side, cache):
    """The 41 × 6 path at every node (x, y ≥ 0, z) of the lattice, resumable from `cache`."""
    xs, ys, zs = lattice(side)
    shape = (len(xs), len(ys), len(zs), 4 * QUARTER + 1, 6)
    done = np.full(shape, np.nan)
    if cache.exists():
        # A run on fewer x centres (the same first x): its nodes are the first along x.
        old = np.load(cache)
        done[:old.shape[0]] = old
    todo = [(i, j, k) for i in range(shape[0]) for j in range(shape[1]) for k in range(shape[2])
            if np.isnan(done[i, j, k, 0, 0])]
    start = time.time()
    for n, (i, j, k) in enumerate(todo):
        done[i, j, k] = path([xs[i], ys[j], zs[k]], refine=REFINE)
        if (n + 1) % 200 == 0 or n + 1 == len(todo):
            np.save(cache, done)
            print(f"ℓ = {side}a: {n + 1}/{len(todo)} nodes, {time.time() - start:.0f} s", flush=True)
    return done


def cube_averages(side, nodes, g=2):
    """The averaged paths of every cube of the lattice: centres (M, 3) and paths (M, 41, 6)."""
    x0, nx, ny = SIDES[side]
    d = side / 4
    _, w = np.polynomial.legendre.leggauss(g)
    w = 0.5 * w / 4  # one panel of d over ℓ = 4d
    # y nodes over [−ℓ/2, y_max + ℓ/2]: the mirrored nodes of the first two panels, then the rest.
    full_y = np.concatenate([nodes[:, 2 * g - 1::-1] * MIRROR, nodes], axis=1)
    centres, paths = [], []
    for a in range(nx):
        for b in range(ny):
            for c in range(TOPS):
                block = full_y[a * g:(a + 4) * g, b * g:(b + 4) * g, c * g:(c + 4) * g]
                wx = np.tile(w, 4)
                avg = np.einsum("i,j,k,ijktc->tc", wx, wx, wx, block)
                centres.append([x0 + a * d, b * d, c * d + side / 2])
                paths.append(avg)
    return np.array(centres), np.array(paths)


def check():
    """The reduced point cubature against the full one next to the rim, and one cube with
    two- against three-point Gauss per panel (ℓ = 0.25a, at (1.0, 0)a, top face on the surface)."""
    worst = 0.0
    for p in ([0.97, 0.05, 0.01], [1.03, 0.2, 0.02], [0.9, 0.1, 0.1]):
        worst = max(worst, np.abs(path(p, refine=REFINE) - path(p)).max())
    print(f"point cubature refine {REFINE} vs 1: max |Δσ|/p₀ = {worst:.2e}", flush=True)
    side, d = 0.25, 0.0625
    out = []
    for g in (2, 3):
        t, w = np.polynomial.legendre.leggauss(g)
        u = np.concatenate([(k + 0.5) * d + 0.5 * d * t for k in range(4)])
        wu = np.tile(0.5 * w / 4, 4)
        acc = 0.0
        for i, x in enumerate(1.0 - side / 2 + u):
            for j, y in enumerate(-side / 2 + u):
                for k, z in enumerate(u):
                    acc = acc + wu[i] * wu[j] * wu[k] * path([x, y, z], refine=REFINE)
        out.append(acc)
        print(f"cube at (1.0, 0)a, {g}-point Gauss per panel: done", flush=True)
    diff = np.abs(out[0] - out[1]).max()
    print(f"cube average, 2- vs 3-point Gauss per panel: max |Δσ̄|/p₀ = {diff:.2e}", flush=True)
    return worst, diff


def generate(sides=None):
    """The cases of `sides` (default: PV_SIDES=0.25,0.5 from the environment, else all)."""
    import os
    if sides is None and os.environ.get("PV_SIDES"):
        sides = [float(v) for v in os.environ["PV_SIDES"].split(",")]
    cases = []
    for side in sides or SIDES:
        cache = pathlib.Path(f"/tmp/cattaneo_pv_nodes_{side}.npy")
        nodes = node_paths(side, cache)
        centres, paths = cube_averages(side, nodes)
        x0, nx, ny = SIDES[side]
        cases.append({
            "case": f"cattaneo_pv_{side}",
            "arrays": {"centres": centres, "stress": np.round(paths, 10)},
            "attrs": {
                "side_over_a": side, "first_x_over_a": x0, "x_centres": nx, "y_centres": ny,
                "tops": TOPS, "spacing_over_a": side / 4, "nu": NU, "friction": MU,
                "q_star_over_mu_w": CHI, "steps_per_quarter": QUARTER, "extent_over_a": EXTENT,
                "point_cubature_refine": REFINE,
                "layout": "centres[m] = (x, y, centre depth)/a of cube m (x slow, then y, then top); "
                          "stress[m][increment][component] per p0, Voigt 11,22,33,23,13,12, tension positive",
                "method": "two-point Gauss-Legendre per panel of l/4 over the cube of the Boussinesq/Cerruti "
                          "point-force cubature (verify/cattaneo_fatigue_maxima.py) of the Mindlin-Deresiewicz "
                          "tractions",
            },
        })
    return cases


if __name__ == "__main__":
    if "--check" in sys.argv:
        check()
    else:
        print(generate()[0]["arrays"]["centres"][:3])
