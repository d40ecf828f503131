"""A probe, not a fixture generator (docs/fatigue.md, "Where the surface error sits"): does
subtracting a fitted Hertzian edge make the Cattaneo–Mindlin cycle's SURFACE stresses converge?

The solver's cycle tractions (per grid, dumped by
`DUMP_TRACTIONS=DIR cargo test -p halfspace --test fixtures_cattaneo_fatigue surface_error_sources
-- --nocapture`: DIR/tractions_N.f64 = [increment][p, q1, q2][cell] in Pa, DIR/tractions_N.json)
are split into a fitted Hertzian part and a residual:

* the pressure p_H = p0' sqrt(1 - r^2/a'^2) about the pressure's centroid, with a'^2 = (5/2) <r^2>_p
  (the second moment of a Hertzian pressure is 2a^2/5) and p0' = 3W/(2 pi a'^2);
* the shear k(t) p_H along x, k the least-squares ratio q1/p_H over a' - 4h < r < a' - h (the slip
  zone at the rim, where |q| = mu p);
* the residual t - t_fit at the cell centres, set to zero within `ZERO_BAND` cells of r = a' (the
  fit replaces the solver's rim cells), evaluated piecewise constant by Love's rectangle
  stresses at z = 0 (docs/theory-sam.md#love-rectangle-stresses, ported below);
* the fitted part by its closed-form surface stresses (Johnson 1985 Eqs. 3.41, 3.42; the shear
  by Cerruti's surface displacements, verify/cattaneo_fatigue_surface.py).

Printed per grid: the piecewise-constant evaluation's error at the rim cells (reproduces the Rust
test's numbers), the fit's a', p0', and for the fit the largest path error and Crossland's index
(f-1 = 400 MPa, t-1 = 280 MPa; minimum ball by Badoiu–Clarkson iterations, ~1e-4) at the
fixture's fine points (datasets/cattaneo_fatigue_surface.json), for the solver's tractions and for
the exact Mindlin–Deresiewicz tractions sampled at the same cell centres.
Run: python3 verify/cattaneo_surface_rim_fit.py DIR  (numpy only; about a minute).
"""
import json
import pathlib
import sys

import numpy as np

NU, MU = 0.3, 0.3
G = 1 / (2 * (1 + NU))
C_STAR = 0.5 ** (1 / 3)
A_OVER_K = 1 - 0.5 ** (2 / 3)
ZERO_BAND = 1.5
ROOT = pathlib.Path(__file__).resolve().parent.parent


def md_traction(x, y, t):
    """The exact (p, q1) per p0 at (x, y)/a, increment t of the closed cycle (Johnson 1985 7.3)."""
    r2 = x * x + y * y

    def s(c):
        return np.sqrt(np.maximum(c * c - r2, 0.0))

    tt, sign = (t, 1.0) if t <= 20 else (t - 20, -1.0)
    b = np.sqrt(1 - tt / 10 * A_OVER_K / 2)
    return s(1.0), sign * MU * (-s(1.0) - s(C_STAR) + 2 * s(b))


def _rho_plus(rho, c, rest2):
    return np.where(c >= 0, rho + c, rest2 / np.where(rho - c == 0, 1, rho - c))


def _pressure_primitive(c1, c2):
    """Love's corner primitive of a unit pressure at z = 0 (the z -> 0 limit of the Rust kernel)."""
    rho = np.sqrt(c1 * c1 + c2 * c2)
    phi_z = -np.pi / 2 * np.sign(c1 * c2)
    k, zero = 1 / (2 * np.pi), np.zeros_like(c1)
    s11 = 2 * NU * phi_z - (1 - 2 * NU) * np.arctan(c2 / c1)
    s22 = 2 * NU * phi_z - (1 - 2 * NU) * np.arctan(c1 / c2)
    return k * np.array([s11, s22, phi_z, zero, zero, -(1 - 2 * NU) * np.log(rho)])


def _shear_primitive(c1, c2):
    """Love's corner primitive of a unit shear along +x at z = 0."""
    rho = np.sqrt(c1 * c1 + c2 * c2)
    l1, l2 = np.log(_rho_plus(rho, c1, c2 * c2)), np.log(_rho_plus(rho, c2, c1 * c1))
    k, zero = 1 / (2 * np.pi), np.zeros_like(c1)
    s11 = 2 * l2 + c2 / rho - (1 - 2 * NU) * c2 / rho
    s22 = 2 * NU * l2 - c2 / rho + (1 - 2 * NU) * c2 / rho
    s12 = l1 - c1 / rho + (1 - 2 * NU) * c1 / rho
    return k * np.array([s11, s22, zero, zero, -np.pi / 2 * np.sign(c1 * c2), s12])


def _corner(f, x1, x2, d):
    return sum(s1 * s2 * f(x1 + s1 * d, x2 + s2 * d) for s1, s2 in ((1, 1), (1, -1), (-1, 1), (-1, -1)))


def piecewise_constant_paths(tr, xc, yc, h, points):
    """Surface stress paths (M, 41, 6) per p0 of piecewise-constant tractions tr (41, 3, cells)."""
    out = []
    for x, y in points:
        kp = _corner(_pressure_primitive, x - xc, y - yc, h / 2)
        kq = _corner(_shear_primitive, x - xc, y - yc, h / 2)
        out.append(np.einsum("kn,tn->tk", kp, tr[:, 0]) + np.einsum("kn,tn->tk", kq, tr[:, 1]))
    return np.array(out)


def _v_f(r, inside):
    if inside:
        return np.pi**2 * (2 - r * r) / 4, np.pi**2 * (r * r - r**4 / 4) / 4
    t, asn = np.sqrt(r * r - 1), np.arcsin(1 / r)
    return np.pi / 2 * ((2 - r * r) * asn + t), np.pi / 2 * ((r * r - r**4 / 4) * asn + 0.75 * t + t**3 / 4)


def _shear_disp(x, y, inside):
    r2 = x * x + y * y
    r = np.sqrt(r2)
    v, f = _v_f(r, inside)
    w1 = f / r
    w2 = v - w1 / r
    wyy, wxy = w2 * y * y / r2 + w1 / r * x * x / r2, (w2 - w1 / r) * x * y / r2
    k = 1 / (2 * np.pi * G)
    return k * ((1 - NU) * v + NU * wyy), -k * NU * wxy


def hertz_shear_surface(x, y):
    """Surface stresses of the shear sqrt(1 - r^2) along +x (verify/cattaneo_fatigue_surface.py)."""
    inside, step = np.hypot(x, y) < 1, 1e-30
    gx = [np.imag(u) / step for u in _shear_disp(complex(x, step), complex(y), inside)]
    gy = [np.imag(u) / step for u in _shear_disp(complex(x), complex(y, step), inside)]
    exx, eyy, exy = gx[0], gy[1], 0.5 * (gy[0] + gx[1])
    out = np.zeros(6)
    out[0], out[1] = 2 * G * (exx + NU * eyy) / (1 - NU), 2 * G * (eyy + NU * exx) / (1 - NU)
    out[4], out[5] = -np.sqrt(max(1 - x * x - y * y, 0.0)), 2 * G * exy
    return out


def hertz_normal_surface(x, y):
    """Surface stresses of the pressure sqrt(1 - r^2) (Johnson 1985 Eqs. 3.41, 3.42)."""
    r2 = x * x + y * y
    r, s = np.sqrt(r2), np.sqrt(max(1 - r2, 0.0))
    a = (1 - 2 * NU) / (3 * r2) * (1 - s**3)
    sr = a - s if r < 1 else (1 - 2 * NU) / (3 * r2)
    st = -a - 2 * NU * s if r < 1 else -(1 - 2 * NU) / (3 * r2)
    c, sn = x / r, y / r
    out = np.zeros(6)
    out[0], out[1], out[2], out[5] = sr * c * c + st * sn * sn, sr * sn * sn + st * c * c, -s, (sr - st) * sn * c
    return out


def fitted_paths(tr, xc, yc, h, points):
    """The fitted Hertzian part in closed form + the residual piecewise constant (docstring)."""
    p = tr[:, 0]
    w = p.sum(1)
    xb, yb = (p * xc).sum(1) / w, (p * yc).sum(1) / w
    r2 = (xc - xb[:, None]) ** 2 + (yc - yb[:, None]) ** 2
    a = np.sqrt(2.5 * (p * r2).sum(1) / w)
    p0 = 3 * w * h * h / (2 * np.pi * a * a)
    ph = p0[:, None] * np.sqrt(np.maximum(1 - r2 / a[:, None] ** 2, 0))
    r = np.sqrt(r2)
    band = (r > a[:, None] - 4 * h) & (r < a[:, None] - h)
    k = (tr[:, 1] * ph * band).sum(1) / (ph * ph * band).sum(1)
    res = tr.copy()
    res[:, 0] -= ph
    res[:, 1] -= k[:, None] * ph
    res *= ~(np.abs(r - a[:, None]) < ZERO_BAND * h)[:, None, :]
    out = piecewise_constant_paths(res, xc, yc, h, points)
    for m, (x, y) in enumerate(points):
        for t in range(out.shape[1]):
            u, v = (x - xb[t]) / a[t], (y - yb[t]) / a[t]
            out[m, t] += p0[t] * (hertz_normal_surface(u, v) + k[t] * hertz_shear_surface(u, v))
    return out, a[0], p0[0]


def crossland(path, p0):
    """Crossland's index of a path (41, 6) per p0 (docs/fatigue.md Eq. F3), approximate ball."""
    s = path * p0
    sh = s[:, :3].sum(1) / 3
    d = s.copy()
    d[:, :3] -= sh[:, None]
    y = np.stack([np.sqrt(3) / 2 * d[:, 2], (d[:, 0] - d[:, 1]) / 2, d[:, 3], d[:, 4], d[:, 5]], 1) / 1e9
    c = y.mean(0)
    for i in range(4000):
        j = np.linalg.norm(y - c, axis=1).argmax()
        c = c + (y[j] - c) / (i + 2)
    f, t = 400e6, 280e6
    return (np.linalg.norm(y - c, axis=1).max() * 1e9 + (t - f / np.sqrt(3)) / (f / 3) * sh.max()) / t


def main(directory):
    fx = json.loads((ROOT / "datasets" / "cattaneo_fatigue_surface.json").read_text())
    fine_points = [(x + 1e-9, y + 1e-9) for x, y in fx["fine"]["points"]]  # off the cell edges
    fine_ref = np.array(fx["fine"]["stress"])
    for n in (32, 64, 128):
        meta = json.loads((pathlib.Path(directory) / f"tractions_{n}.json").read_text())
        p0 = meta["p0"]
        tr = np.fromfile(pathlib.Path(directory) / f"tractions_{n}.f64").reshape(41, 3, n * n) / p0
        h = 2 * meta["half"] / meta["a"]
        cell = np.arange(n * n)
        xc, yc = (cell // n + 0.5) * h - n * h / 2, (cell % n + 0.5) * h - n * h / 2
        exact = np.zeros_like(tr)
        for t in range(41):
            exact[t, 0], exact[t, 1] = md_traction(xc, yc, t)
        window = fx["grids"][str(n)]
        pts, ref = window["points"], np.array(window["stress"])
        rim = np.abs(np.hypot(*np.array(pts).T) - 1) < 1.5 * h
        pc = piecewise_constant_paths(tr, xc, yc, h, pts)
        print(f"{n}²: piecewise constant, rim cells max |Δσ|/p0 {np.abs(pc - ref)[rim].max():.3e}")
        for label, tractions in (("solver", tr), ("exact MD at the centres", exact)):
            got, a_fit, p0_fit = fitted_paths(tractions, xc, yc, h, fine_points)
            c_got = np.array([crossland(got[m], p0) for m in range(len(fine_points))])
            c_ref = np.array([crossland(fine_ref[m], p0) for m in range(len(fine_points))])
            print(f"{n}²: Hertz fit of the {label}: a' = {a_fit:.5f} a, p0' = {p0_fit:.5f} p0; fine points: "
                  f"max |Δσ|/p0 {np.abs(got - fine_ref).max():.3e}, max |ΔCrossland| "
                  f"{np.abs(c_got - c_ref).max():.3f}, Crossland max {c_got.max():.4f} at "
                  f"{np.round(fine_points[int(c_got.argmax())], 4).tolist()} (closed form {c_ref.max():.4f})",
                  flush=True)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "/tmp")
