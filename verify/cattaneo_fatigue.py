"""The stress paths of the Cattaneo–Mindlin fretting cycle of two identical bodies (issue 22,
"Checks") by cubature of the point-force solutions of Boussinesq and Cerruti (verify/subsurface.py,
Johnson 1985 Eqs. 3.19, 3.22a) over the closed-form Mindlin–Deresiewicz tractions — independent of
halfspace's solver and of its Love rectangle kernels.

Identical bodies (no normal–tangential coupling, Mindlin's solution exact): Hertz
p = (p0/a) sqrt(a^2 - r^2); with Q*/muW = 0.5 the shift amplitude A = K (1 - 0.5^(2/3)),
K = 3 mu W (2 - nu) / (8 G a). The closed cycle from delta = +A (point B) in 10 steps per quarter:
unloading to -A, q = (mu p0/a) [-S(a) - S(c*) + 2 S(b)], b/a = sqrt(1 - (A - delta)/(2K));
reloading to +A, q = (mu p0/a) [S(a) + S(c*) - 2 S(b')], b'/a = sqrt(1 - (delta + A)/(2K)),
c*/a = sqrt(1 - A/K), S(c) = sqrt(c^2 - r^2) on r < c (Johnson 1985 §7.3). Each S(c) is
integrated once per point (r = c sin t), so a path costs a few cubatures.

Points: cell centres of the fretting loop's 32^2 and 64^2 grids over 4.16 a (layer k at depth
(2k + 1) h/2), near the axis, inside the contact and at the trailing edge, in units of a.
Writes datasets/cattaneo_fatigue.json (stresses per p0, Voigt 11, 22, 33, 23, 13, 12, tension
positive). Run: verify/.venv/bin/python verify/cattaneo_fatigue.py  (about a minute).
"""
import json
import pathlib
import sys

import numpy as np
from scipy.integrate import quad_vec

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from verify.subsurface import NU, check_surface_green, disp_normal, disp_tangential, stress  # noqa: E402

MU = 0.3
CHI = 0.5  # Q*/mu W
QUARTER = 10
EXTENT = 4.16  # over a
# (x, y, z) / a targets, snapped to the nearest cell centre of each grid.
TARGETS = [(0.0, 0.0, 0.48), (-0.9, 0.0, 0.1), (0.5, 0.3, 0.25)]
GRIDS = [32, 64]


def cattaneo(point, c, kind):
    """Stress at `point` of the traction sqrt(c^2 - r^2) on r < c (normal or along +x)."""
    x0, y0, z0 = point
    disp = disp_normal if kind == "normal" else disp_tangential

    def over_t(t):
        r = c * np.sin(t)
        weight = c**3 * np.cos(t) ** 2 * np.sin(t)

        def inner(theta):
            return stress(disp, x0 - r * np.cos(theta), y0 - r * np.sin(theta), z0)

        return weight * quad_vec(inner, 0, 2 * np.pi, epsabs=1e-12, epsrel=1e-10, limit=400)[0]

    return quad_vec(over_t, 0, np.pi / 2, epsabs=1e-12, epsrel=1e-10, limit=400)[0]


def snap(n, target):
    h = EXTENT / n
    i = int(round((target[0] + EXTENT / 2) / h - 0.5))
    j = int(round((target[1] + EXTENT / 2) / h - 0.5))
    k = max(0, int(round(target[2] / h - 0.5)))
    return [(i + 0.5) * h - EXTENT / 2, (j + 0.5) * h - EXTENT / 2, (k + 0.5) * h], [i, j, k]


def path(point):
    """The 4 QUARTER + 1 stresses of the closed cycle at `point`, per p0 (a = p0 = 1)."""
    # Units a = 1: K/a and A/a only enter through b/a; A/K = 1 - (1 - CHI)^(2/3).
    a_over_k = 1 - (1 - CHI) ** (2 / 3)
    c_star = np.sqrt(1 - a_over_k)
    sp = cattaneo(point, 1.0, "normal")
    cache = {}

    def shear(c):
        key = round(c, 14)
        if key not in cache:
            cache[key] = cattaneo(point, c, "tangential") if c > 0 else np.zeros(6)
        return cache[key]

    out = []
    for t in range(4 * QUARTER + 1):
        if t <= 2 * QUARTER:
            travel = t / QUARTER * a_over_k  # (A - delta)/K
            b = np.sqrt(1 - travel / 2)
            q = -shear(1.0) - shear(c_star) + 2 * shear(b)
        else:
            travel = (t - 2 * QUARTER) / QUARTER * a_over_k  # (delta + A)/K
            b = np.sqrt(1 - travel / 2)
            q = shear(1.0) + shear(c_star) - 2 * shear(b)
        out.append(sp + MU * q)
    return np.array(out)


def main():
    check_surface_green()
    fixture = {
        "generator": "verify/cattaneo_fatigue.py",
        "method": "cubature (scipy quad_vec) of Boussinesq/Cerruti point-force stresses (verify/subsurface.py) "
                  "over Hertz p and the Mindlin-Deresiewicz q of the closed cycle",
        "nu": NU, "friction": MU, "q_star_over_mu_w": CHI, "steps_per_quarter": QUARTER,
        "extent_over_a": EXTENT,
        "layout": "stress[point][increment][component]: per p0, Voigt 11,22,33,23,13,12, tension positive; "
                  "points (x, y, z)/a; cells (i, j, layer)",
        "grids": {},
    }
    for n in GRIDS:
        entries = []
        for target in TARGETS:
            point, cell = snap(n, target)
            entries.append({"point": point, "cell": cell, "stress": path(point).tolist()})
            print(f"{n}: {point} done", flush=True)
        fixture["grids"][str(n)] = entries
    out = pathlib.Path(__file__).resolve().parent.parent / "datasets" / "cattaneo_fatigue.json"
    tmp = out.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(fixture, indent=1))
    tmp.replace(out)
    print(out)


if __name__ == "__main__":
    main()
