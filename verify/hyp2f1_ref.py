"""Reference values of the Gauss hypergeometric function 2F1 (mpmath, 40 digits) over the domain
the graded MDR uses, written to datasets/hyp2f1_mpmath.npy as float64 rows (a, b, c, z, value).

Domains (spec mdr.md §4.3, §4.4, §7 P12), for k in K:
  * Eq. 25 kernel:        2F1((1+k)/2, (1+k)/2; (3+k)/2; y),   0 <= y <= 1 (dense near 1)
  * graded cone pressure: 2F1((1+k)/2, 1+k/2; (3+k)/2; z),     0 <= z < 1
  * graded cone displacement (incomplete beta): 2F1((2+k)/2, (1+k)/2; (4+k)/2; z)
plus random (a, b, c) in [-2, 3] x [-2, 3] x [0.1, 4] and z in [-5, 0.95] for the series/Pfaff paths.

Run: verify/.venv/bin/python -m verify hyp2f1
"""

import mpmath
import numpy as np

mpmath.mp.dps = 40
K = [-0.9, -0.75, -0.5, -0.25, -0.1, 0.0, 0.1, 0.3, 0.5, 0.75, 0.9]
ys = sorted(set(
    [i / 40 for i in range(41)] + [1 - 10.0 ** (-e) for e in range(2, 13)] + [0.5 + 1e-9, 0.5 - 1e-9]
))


def generate():
    rows = []
    for k in K:
        a = (1 + k) / 2
        for y in ys:
            rows.append((a, a, a + 1, y))
            if y < 1:
                rows.append((a, 1 + k / 2, a + 1, y))
                rows.append(((2 + k) / 2, (1 + k) / 2, (4 + k) / 2, y))
    rng = np.random.default_rng(20261121)
    for _ in range(200):
        a, b = rng.uniform(-2, 3, size=2)
        c = rng.uniform(0.1, 4)
        z = rng.uniform(-5, 0.95)
        rows.append((a, b, c, z))
    out = []
    for a, b, c, z in rows:
        v = mpmath.hyp2f1(a, b, c, z)
        if mpmath.isfinite(v) and abs(mpmath.im(v)) == 0:
            out.append((a, b, c, z, float(mpmath.re(v))))
    arr = np.array(out, dtype="<f8")
    return arr
