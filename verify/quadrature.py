"""scipy.integrate.quad references for the MDR transforms, homogeneous and graded, on profiles that
have no closed form. Every singular end is handled by QAWS (weight="alg"), never by the trapezoid
rule. Formulas are the continuous ones of shared/spec/mdr.md (Eqs. 1/20, 2, 8/24, 14/28); nothing
from halfspace is used.

For each profile f and exponent k (E0 = z0 = 1, nu = 0.3):
  g(x)  = x ∫_0^1 f'(xs) (1 - s²)^((k-1)/2) ds                        (Eq. 20 with r = xs)
  g'(x) = ∫_0^1 [f'(xs) + xs f''(xs)] (1 - s²)^((k-1)/2) ds
  δ     = g(a),  F = 2 c_N ∫_0^a x^k (δ - g) dx                         (§4.2)
  p(r)  = (c_N/π) ∫_r^a g'(x) (x² - r²)^((k-1)/2) dx                    (Eq. 28; Eq. 14 at k = 0)
  u(r)  = (2/π) cos(kπ/2) ∫_0^min(r,a) x^k (δ - g(x)) (r² - x²)^(-(1+k)/2) dx   (Eq. 24; Eq. 8)
at the sample points of the fixture (chosen to be nodes of the Rust tests' grids).
"""
import math

import numpy as np
from scipy import integrate
from scipy.special import gamma

KS = [0.0, -0.5, -0.2, 0.3, 0.6]
NU = 0.3
A = 0.8            # contact radius of the contact cases
J_G, J_P, J_U = 25, 24, 20
U_EXTENT2 = 2000.0 / 960.0   # (L/a)² of the Rust contact grid: N = 2001, edge node 960
EPS = 1e-13


def c_n(k, nu=NU):
    """Spec §4.2 closed form (E0 = z0 = 1)."""
    beta = math.sqrt((1 + k) * (1 - k * nu / (1 - nu)))
    num = (1 + k) ** 2 * math.cos(math.pi * k / 2) * gamma(1 + k / 2) ** 2
    den = beta * math.sin(math.pi * beta / 2) * gamma((3 + k + beta) / 2) * gamma((3 + k - beta) / 2)
    return num / den / (1 - nu * nu)


def profiles(rng_seed=20261121):
    """(name, f, f', f'', description); the table profile is also returned as its samples."""
    d, w = 0.02, 0.3
    c = np.random.default_rng(rng_seed).uniform(0.2, 1.0, size=3)
    out = [
        ("sphere_quartic", lambda r: r * r / 2 + 0.5 * r ** 4, lambda r: r + 2 * r ** 3,
         lambda r: 1 + 6 * r * r, "f = r^2/2 + r^4/2"),
        ("worn", lambda r: r * r / 2 - d * (1 - math.exp(-r * r / w / w)),
         lambda r: r - d * 2 * r / w / w * math.exp(-r * r / w / w),
         lambda r: 1 - 2 * d / w / w * (1 - 2 * r * r / w / w) * math.exp(-r * r / w / w),
         f"f = r^2/2 - {d} (1 - exp(-r^2/{w}^2)) (flattened centre)"),
        ("table", lambda r: c[0] * r * r + c[1] * r ** 3 + c[2] * r ** 4,
         lambda r: 2 * c[0] * r + 3 * c[1] * r * r + 4 * c[2] * r ** 3,
         lambda r: 2 * c[0] + 6 * c[1] * r + 12 * c[2] * r * r,
         f"f = {c[0]:.17g} r^2 + {c[1]:.17g} r^3 + {c[2]:.17g} r^4, given as a 301-row table on [0, 1.5]"),
    ]
    r = np.linspace(0.0, 1.5, 301)
    table = np.column_stack([r, [out[2][1](x) for x in r]])
    return out, table


def quad(fun, a, b, **kw):
    v, err = integrate.quad(fun, a, b, epsabs=0.0, epsrel=EPS, limit=400, **kw)
    return v, err


def transform(fp, fpp, k):
    beta = (k - 1) / 2

    def g(x):
        if x == 0.0:
            return 0.0, 0.0
        v, e = quad(lambda s: fp(x * s) * (1 + s) ** beta, 0, 1, weight="alg", wvar=(0, beta))
        return x * v, x * e

    def gprime_over_x(x):
        # g'(x)/x = ∫ [f'(xs)/x + s f''(xs)] (1-s²)^β ds; f'(y)/x = s f'(y)/y, f'(y)/y -> f''(0) at 0.
        def h(s):
            y = x * s
            ratio = fp(y) / y if y != 0.0 else fpp(0.0)
            return (s * ratio + s * fpp(y)) * (1 + s) ** beta
        return quad(h, 0, 1, weight="alg", wvar=(0, beta))[0]

    def gprime(x):
        return quad(lambda s: (fp(x * s) + x * s * fpp(x * s)) * (1 + s) ** beta, 0, 1,
                    weight="alg", wvar=(0, beta))[0]

    return g, gprime, gprime_over_x


def case_values(fp, fpp, k):
    g, gprime, gprime_over_x = transform(fp, fpp, k)
    cn = c_n(k)
    errs = []
    # Profile transform on x_j = sqrt(j/J_G) (L = 1).
    xg = np.sqrt(np.arange(J_G + 1) / J_G)
    gv = []
    for x in xg:
        v, e = g(x)
        gv.append(v)
        errs.append(e / max(abs(v), 1e-300) if v else 0.0)
    delta = g(A)[0]
    # Force.
    force_int, e = quad(lambda x: delta - g(x)[0], 0, A, weight="alg", wvar=(k, 0))
    force = 2 * cn * force_int
    errs.append(e / force_int)
    # Pressure at rho_j = a² j / J_P.
    rp = A * np.sqrt(np.arange(J_P) / J_P)
    pv = []
    for r in rp:
        if r == 0.0:
            v, e = quad(gprime_over_x, 0, A, weight="alg", wvar=(k, 0))
        else:
            beta = (k - 1) / 2
            v, e = quad(lambda x: gprime(x) * (x + r) ** beta, r, A, weight="alg", wvar=(beta, 0))
        pv.append(cn / math.pi * v)
        errs.append(e / abs(v))
    # Displacement at rho_j = (L/a)² a² j / J_U, inside and outside the contact.
    ru = A * np.sqrt(U_EXTENT2 * np.arange(J_U + 1) / J_U)
    pref = 2 / math.pi * math.cos(k * math.pi / 2)
    uv = []
    for r in ru:
        if r == 0.0:
            uv.append(delta)
            continue
        gam = -(1 + k) / 2
        if r <= A:
            v, e = quad(lambda x: (delta - g(x)[0]) * (r + x) ** gam, 0, r, weight="alg", wvar=(k, gam))
        else:
            v, e = quad(lambda x: (delta - g(x)[0]) * (r * r - x * x) ** gam, 0, A, weight="alg", wvar=(k, 0))
        uv.append(pref * v)
        errs.append(e / max(abs(v), 1e-300))
    return {
        "x": xg, "g": np.array(gv), "r_pressure": rp, "pressure": np.array(pv),
        "r_displacement": ru, "displacement": np.array(uv),
    }, {"depth": delta, "force": force, "contact_modulus": cn,
        "estimated_relative_error": float(max(errs))}


def generate():
    profs, table = profiles()
    cases = [{"case": "profile_table", "arrays": {"table": table},
              "attrs": {"description": profs[2][4], "units": "dimensionless"}}]
    for name, f, fp, fpp, desc in profs:
        for k in KS:
            arrays, scalars = case_values(fp, fpp, k)
            attrs = {"profile": name, "description": desc, "k": k, "nu": NU, "E0": 1.0, "z0": 1.0,
                     "contact_radius": A, "units": "dimensionless (E0 = z0 = 1)",
                     "method": "scipy.integrate.quad (QAWS for the algebraic end points), epsrel 1e-13",
                     **scalars}
            cases.append({"case": f"{name}/k{k:+.1f}", "arrays": arrays, "attrs": attrs})
    return cases
