"""The limiting worn profile of fretting wear on power-law graded media (docs/fretting-wear.md,
"Graded media"), by direct scipy quadrature of the graded inverse MDR transform (spec mdr.md §4.3,
Eq. 24) — independent of the library's incomplete-beta closed form.

Normalized variables a0 = d = 1: f0 = (1+k) r²/2, g0 = x², stick radius c = sqrt(1 − χ); at the end
of wear g∞ = g0 on [0, c] and 1 beyond, so for r > c

    f∞(r) = (2/π) cos(kπ/2) [ ∫_0^c x^(k+2) (r² − x²)^(−(1+k)/2) dx + ∫_c^r x^k (r² − x²)^(−(1+k)/2) dx ]

(quad with the algebraic weight (r − x)^(−(1+k)/2) for the end singularity). r* solves f∞(r*) = f0(r*)
(brentq), the final wear volume over π a0² d is V∞ = ∫_{c²}^{r*²} (f∞ − f0) dξ (quad in ξ = r²).

Case `graded_wear/k{k}_chi{chi}`: arrays `r` (12 radii in (c, r*]), `limiting_profile` f∞(r),
attributes `k`, `chi`, `r_star`, `wear_volume`.
"""
import warnings

import numpy as np
from scipy.integrate import IntegrationWarning, quad
from scipy.optimize import brentq

KS = [-0.5, -0.25, 0.25, 0.5, 0.75, 0.9]
CHIS = [0.1, 0.3, 0.5, 0.7, 0.9]


def limiting_profile(r, chi, k):
    c = np.sqrt(1.0 - chi)
    if r <= c:
        return 0.5 * (1.0 + k) * r * r
    e = -(1.0 + k) / 2.0
    # On [0, c] the kernel is regular (r > c), though steep when r is close to c; on [c, r]
    # (r² − x²)^e = (r − x)^e (r + x)^e, the first factor quad's algebraic weight.
    stick = quad(lambda x: x ** (k + 2.0) * (r * r - x * x) ** e, 0.0, c, epsabs=1e-15,
                 epsrel=1e-13, limit=400, points=[c * (1 - 1e-3), c * (1 - 1e-6)] if r < 1.01 * c else None)[0]
    annulus = quad(lambda x: x ** k * (r + x) ** e, c, r, weight="alg", wvar=(0.0, e),
                   epsabs=1e-15, epsrel=1e-13, limit=200)[0]
    return 2.0 / np.pi * np.cos(0.5 * np.pi * k) * (stick + annulus)


def r_star(chi, k):
    c = np.sqrt(1.0 - chi)
    gap = lambda r: limiting_profile(r, chi, k) - 0.5 * (1.0 + k) * r * r
    hi = 2.0
    while gap(hi) > 0.0:
        hi *= 2.0
    return brentq(gap, c * (1.0 + 1e-9), hi, xtol=1e-15, rtol=1e-15, maxiter=500)


def wear_volume(chi, k, rs):
    f = lambda xi: limiting_profile(np.sqrt(xi), chi, k) - 0.5 * (1.0 + k) * xi
    return quad(f, 1.0 - chi, rs * rs, epsabs=1e-15, epsrel=1e-12, limit=400)[0]


def generate():
    # quad flags roundoff near its tolerance on the steep kernels when r is close to c; the values
    # agree with the incomplete-beta closed form to 2e-15 (r*, f∞) and 3e-14 (V∞) all the same.
    warnings.simplefilter("ignore", IntegrationWarning)
    cases = []
    for k in KS:
        for chi in CHIS:
            rs = r_star(chi, k)
            c = np.sqrt(1.0 - chi)
            r = c + (rs - c) * np.linspace(0.05, 1.0, 12)
            prof = np.array([limiting_profile(x, chi, k) for x in r])
            cases.append({
                "case": f"graded_wear/k{k:+.2f}_chi{chi:.1f}",
                "arrays": {"r": r, "limiting_profile": prof},
                "attrs": {"k": k, "chi": chi, "r_star": rs, "wear_volume": wear_volume(chi, k, rs)},
            })
    return cases


if __name__ == "__main__":
    for case in generate():
        a = case["attrs"]
        print(f"k={a['k']:+.2f} chi={a['chi']:.1f} r*={a['r_star']:.10f} V={a['wear_volume']:.10e}")
