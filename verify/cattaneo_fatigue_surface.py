"""The Cattaneo–Mindlin fretting cycle of two identical bodies (issue 22, "Checks"; docs/fatigue.md)
AT THE SURFACE z = 0, in closed form: the reference for the fatigue box's surface layer, its
criteria's maxima and their locations.

The Mindlin–Deresiewicz tractions of the closed cycle are superpositions of Hertzian-shaped
distributions (a = p₀ = 1): the pressure p = √(1 − r²) and the shear
q₁ = μ(∓S(1) ∓ S(c*) ± 2 S(b)), S(c) the traction √(c² − r²) along +x (the same superposition as
verify/cattaneo_fatigue.py and verify/cattaneo_fatigue_maxima.py). Their surface stresses:

* pressure (Johnson 1985, Eqs. 3.41a–c inside, 3.42 outside):
  inside σ_r = (1 − 2ν)/(3r²)(1 − (1 − r²)^{3/2}) − √(1 − r²),
         σ_θ = −(1 − 2ν)/(3r²)(1 − (1 − r²)^{3/2}) − 2ν√(1 − r²), σ_z = −√(1 − r²);
  outside σ_r = −σ_θ = (1 − 2ν)/(3r²), σ_z = 0.
* shear √(1 − r²) along +x (Hamilton & Goodman 1966, Hamilton 1983 at z = 0; inside it reduces
  to Johnson 1985 Eq. 7.47: σ_x = −(4 + ν)πx/8, σ_y = −3νπx/8, σ_xy = −(2 − ν)πy/8): from the
  surface displacements of Cerruti's point force (Johnson Eq. 2.19 at z = 0),
      u_x = [(1 − ν)V + ν W_yy]/(2πG),   u_y = −ν W_xy/(2πG),
  V = ∫ q/ρ dA, W = ∫ q ρ dA (∇²W = V), both radial in closed form:
      V = π²(2 − r²)/4 (r ≤ 1),  (π/2)[(2 − r²) asin(1/r) + √(r² − 1)] (r > 1)
      (the Hertz surface deflection, Johnson Eqs. 3.41, 3.42),
      W' = F/r, F = ∫₀^r sV ds = π²(r² − r⁴/4)/4 (r ≤ 1),
      (π/2)[(r² − r⁴/4) asin(1/r) + (3/4)√(r² − 1) + (r² − 1)^{3/2}/4] (r > 1), W'' = V − W'/r;
  the in-plane strains by complex-step derivatives (exact to rounding), σ_z = 0 so
  σ_xx = 2G(ε_xx + νε_yy)/(1 − ν), σ_yy = 2G(ε_yy + νε_xx)/(1 − ν), σ_xy = 2Gε_xy; σ_xz = −q.
  A distribution of radius c: c·S(x/c, y/c).

Checked (printed, asserted): the shear's inside closed form against Johnson Eq. 7.47; both
against the fixed cubature of the Boussinesq/Cerruti stresses (verify/cattaneo_fatigue_maxima.py)
at z → 0 (the difference falls like z). Then the paths (41 increments of the closed cycle) at the
surface-cell centres of a window around the contact edge on 32², 64², 128² (the fretting loop's N²
cells over 4.16 a): datasets/cattaneo_fatigue_surface.json (per grid: cells (i, j), points
(x, y)/a, stress per p₀ Voigt 11, 22, 33, 23, 13, 12, tension positive, rounded to 1e-7 p₀), and on a fine patch of points around the maxima
(`fine`: points, stress) for the reference's supremum over the surface.
Run: verify/.venv/bin/python verify/cattaneo_fatigue_surface.py  (seconds, plus ~1 min for the
cubature check).
"""
import json
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from verify.cattaneo_fatigue import CHI, EXTENT, MU, QUARTER  # noqa: E402
from verify.subsurface import G, NU, disp_normal, disp_tangential  # noqa: E402

GRIDS = [32, 64, 128]
# x/a and y/a ranges of the window (the cycle is mirror-symmetric in x and y): around the edge.
WINDOW = ((0.80, 1.25), (0.0, 0.45))
# A fine patch of points (not cell centres) around the maxima at the contact edge, for the
# reference's own supremum over the surface: x/a in steps of a/400, y/a in steps of 0.06 a.
FINE = [(x, y) for x in np.round(np.arange(0.9750, 1.00501, 0.0025), 6) for y in (0.0, 0.06, 0.12, 0.18)]


def hertz_normal_surface(x, y):
    """Voigt surface stresses (6, M) of the pressure √(1 − r²) (Johnson 1985 Eqs. 3.41, 3.42)."""
    r2 = x * x + y * y
    r = np.sqrt(r2)
    inside = r < 1
    s = np.sqrt(np.maximum(1 - r2, 0.0))
    a = (1 - 2 * NU) / (3 * r2) * (1 - s**3)
    sr = np.where(inside, a - s, (1 - 2 * NU) / (3 * r2))
    st = np.where(inside, -a - 2 * NU * s, -(1 - 2 * NU) / (3 * r2))
    c, sn = x / r, y / r
    out = np.zeros((6,) + x.shape)
    out[0] = sr * c * c + st * sn * sn
    out[1] = sr * sn * sn + st * c * c
    out[2] = -s
    out[5] = (sr - st) * sn * c
    return out


def _v_f(r, inside):
    """V(r) and F(r) = ∫₀^r s V ds of the unit Hertzian distribution (module docstring)."""
    if inside:
        return np.pi**2 * (2 - r * r) / 4, np.pi**2 * (r * r - r**4 / 4) / 4
    t = np.sqrt(r * r - 1)
    asn = np.arcsin(1 / r)
    v = np.pi / 2 * ((2 - r * r) * asn + t)
    f = np.pi / 2 * ((r * r - r**4 / 4) * asn + 0.75 * t + t**3 / 4)
    return v, f


def _surface_disp(x, y, inside):
    """(u_x, u_y) at the surface of the unit shear √(1 − r²) along +x (complex arguments)."""
    r2 = x * x + y * y
    r = np.sqrt(r2)
    v, f = _v_f(r, inside)
    w1 = f / r  # W'
    w2 = v - w1 / r  # W''
    wyy = w2 * y * y / r2 + w1 / r * x * x / r2
    wxy = (w2 - w1 / r) * x * y / r2
    k = 1 / (2 * np.pi * G)
    return k * ((1 - NU) * v + NU * wyy), -k * NU * wxy


def hertz_shear_surface(x, y):
    """Voigt surface stresses (6,) of the shear √(1 − r²) along +x at one point (x, y)."""
    inside = np.hypot(x, y) < 1
    h = 1e-30
    gx = [np.imag(u) / h for u in _surface_disp(complex(x, h), complex(y), inside)]
    gy = [np.imag(u) / h for u in _surface_disp(complex(x), complex(y, h), inside)]
    exx, eyy, exy = gx[0], gy[1], 0.5 * (gy[0] + gx[1])
    out = np.zeros(6)
    out[0] = 2 * G * (exx + NU * eyy) / (1 - NU)
    out[1] = 2 * G * (eyy + NU * exx) / (1 - NU)
    out[4] = -np.sqrt(max(1 - x * x - y * y, 0.0))
    out[5] = 2 * G * exy
    return out


def shear_of_radius(x, y, c):
    """The traction √(c² − r²) along +x: c · S(x/c, y/c)."""
    return c * hertz_shear_surface(x / c, y / c) if c > 0 else np.zeros(6)


def surface_path(x, y):
    """The 4 QUARTER + 1 surface stresses of the closed cycle at (x, y), per p₀ (the
    superposition of verify/cattaneo_fatigue_maxima.py's `path`)."""
    a_over_k = 1 - (1 - CHI) ** (2 / 3)
    c_star = np.sqrt(1 - a_over_k)
    sp = hertz_normal_surface(np.array([x]), np.array([y]))[:, 0]
    s1, sc = shear_of_radius(x, y, 1.0), shear_of_radius(x, y, c_star)
    out = []
    for t in range(4 * QUARTER + 1):
        if t <= 2 * QUARTER:
            b = np.sqrt(1 - t / QUARTER * a_over_k / 2)
            q = -s1 - sc + 2 * shear_of_radius(x, y, b)
        else:
            b = np.sqrt(1 - (t - 2 * QUARTER) / QUARTER * a_over_k / 2)
            q = s1 + sc - 2 * shear_of_radius(x, y, b)
        out.append(sp + MU * q)
    return np.array(out)


def check_johnson_747():
    """The inside closed form against Johnson 1985 Eq. 7.47 (q₀ = 1)."""
    worst = 0.0
    for x, y in ((0.3, 0.2), (-0.7, 0.5), (0.05, -0.9), (0.95, 0.1)):
        s = hertz_shear_surface(x, y)
        want = [-(4 + NU) * np.pi * x / 8, -3 * NU * np.pi * x / 8, -(2 - NU) * np.pi * y / 8]
        worst = max(worst, np.abs(np.array([s[0], s[1], s[5]]) - want).max())
    print(f"shear inside vs Johnson Eq. 7.47: {worst:.1e} q0", flush=True)
    assert worst < 1e-12, worst
    return worst


def check_against_cubature():
    """Closed forms vs the fixed cubature (verify/cattaneo_fatigue_maxima.py) at z → 0: the
    difference falls like z."""
    from verify.cattaneo_fatigue_maxima import disc_stress

    points = [(0.2, 0.1), (0.6, 0.5), (0.93, 0.1), (1.06, 0.13), (1.3, 0.4), (0.5, 0.0)]
    rows = []
    for z in (1e-3, 1e-4):
        worst = 0.0
        for x, y in points:
            for disp, closed in (
                (disp_normal, hertz_normal_surface(np.array([x]), np.array([y]))[:, 0]),
                (disp_tangential, hertz_shear_surface(x, y)),
            ):
                worst = max(worst, np.abs(disc_stress((x, y, z), 1.0, disp) - closed).max())
        rows.append((z, worst))
        print(f"closed forms vs cubature at z = {z:g} a: max |Δσ| = {worst:.2e} p0", flush=True)
    (z1, e1), (z2, e2) = rows
    order = np.log(e1 / e2) / np.log(z1 / z2)
    print(f"  observed order in z: {order:.2f}", flush=True)
    assert e2 < 2e-3 and order > 0.8, rows
    return rows


def window_cells(n):
    h = EXTENT / n
    (x0, x1), (y0, y1) = WINDOW
    cells = []
    for i in range(n):
        x = (i + 0.5) * h - EXTENT / 2
        for j in range(n):
            y = (j + 0.5) * h - EXTENT / 2
            if x0 <= x <= x1 and y0 <= y <= y1:
                cells.append(([i, j], [x, y]))
    return cells


def main():
    johnson = check_johnson_747()
    cubature = check_against_cubature()
    fixture = {
        "generator": "verify/cattaneo_fatigue_surface.py",
        "method": "closed-form surface stresses (z = 0) of the Hertzian-shaped pressure (Johnson 1985 Eqs. 3.41, "
                  "3.42) and shear distributions (Hamilton & Goodman 1966 at z = 0, Johnson Eq. 7.47 inside) "
                  "superposed as the Mindlin-Deresiewicz tractions of the closed cycle",
        "check_vs_johnson_7_47": johnson,
        "check_vs_cubature_small_z": cubature,
        "nu": NU, "friction": MU, "q_star_over_mu_w": CHI, "steps_per_quarter": QUARTER,
        "extent_over_a": EXTENT, "window": WINDOW,
        "layout": "grids[n]: cells (i, j) of the surface layer, points (x, y)/a, stress[cell][increment][component] "
                  "per p0, Voigt 11,22,33,23,13,12, tension positive, rounded to 1e-7 p0; fine: the same at points (not cells) around the maxima",
        "grids": {},
    }
    for n in GRIDS:
        cells = window_cells(n)
        fixture["grids"][str(n)] = {
            "cells": [c for c, _ in cells],
            "points": [p for _, p in cells],
            "stress": [np.round(surface_path(*p), 7).tolist() for _, p in cells],
        }
        print(f"{n}²: {len(cells)} surface cells", flush=True)
    fixture["fine"] = {
        "points": [list(p) for p in FINE],
        "stress": [np.round(surface_path(*p), 7).tolist() for p in FINE],
    }
    out = pathlib.Path(__file__).resolve().parent.parent / "datasets" / "cattaneo_fatigue_surface.json"
    tmp = out.with_name(out.name + ".tmp")
    tmp.write_text(json.dumps(fixture, separators=(",", ":"), sort_keys=True))
    tmp.replace(out)
    print(f"-> {out} ({out.stat().st_size} bytes)")


if __name__ == "__main__":
    main()
