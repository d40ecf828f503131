"""Subsurface stresses of a Hertz pressure (and of the shear q = mu p along x) by cubature of the
point-force solutions of Boussinesq and Cerruti (Johnson 1985, Eqs. 3.19 and 3.22a):

normal force P (into the body, +z), rho = |x|:
  u_x = P/(4 pi G) [x z / rho^3 - (1 - 2 nu) x / (rho (rho + z))]        (u_y likewise)
  u_z = P/(4 pi G) [z^2 / rho^3 + 2 (1 - nu) / rho]
tangential force Q along +x:
  u_x = Q/(4 pi G) [1/rho + x^2/rho^3 + (1 - 2 nu) (1/(rho + z) - x^2 / (rho (rho + z)^2))]
  u_y = Q/(4 pi G) [x y / rho^3 - (1 - 2 nu) x y / (rho (rho + z)^2)]
  u_z = Q/(4 pi G) [x z / rho^3 + (1 - 2 nu) x / (rho (rho + z))]
(at z = 0 these are the surface Green's functions of spec sam.md 1.1, checked below). Strains come
from complex-step derivatives of u (exact to rounding), stresses from Hooke's law (tension
positive), and the integral over the contact disc r <= a of p = p0 sqrt(1 - r^2/a^2) uses
r = a sin t (smooth integrand) and adaptive vector quadrature (scipy quad_vec). Units: a = p0 = 1,
E = 1 (stresses do not depend on E), nu = 0.3. Independent of halfspace's Love rectangle kernels.
"""
import numpy as np
from scipy.integrate import quad_vec

NU = 0.3
E = 1.0
G = E / (2 * (1 + NU))
LAM = 2 * G * NU / (1 - 2 * NU)
MU_FRICTION = 0.3

# Observation points (x, y, z) / a: off the axis, inside and outside the contact, three depths.
POINTS = [(x, y, z) for z in (0.25, 0.5, 1.0) for (x, y) in ((0.0, 0.0), (0.5, 0.0), (0.7, 0.4), (1.2, 0.3))]


def disp_normal(x, y, z):
    rho = np.sqrt(x * x + y * y + z * z)
    k = 1 / (4 * np.pi * G)
    ux = k * (x * z / rho**3 - (1 - 2 * NU) * x / (rho * (rho + z)))
    uy = k * (y * z / rho**3 - (1 - 2 * NU) * y / (rho * (rho + z)))
    uz = k * (z * z / rho**3 + 2 * (1 - NU) / rho)
    return np.array([ux, uy, uz])


def disp_tangential(x, y, z):
    rho = np.sqrt(x * x + y * y + z * z)
    k = 1 / (4 * np.pi * G)
    ux = k * (1 / rho + x * x / rho**3 + (1 - 2 * NU) * (1 / (rho + z) - x * x / (rho * (rho + z) ** 2)))
    uy = k * (x * y / rho**3 - (1 - 2 * NU) * x * y / (rho * (rho + z) ** 2))
    uz = k * (x * z / rho**3 + (1 - 2 * NU) * x / (rho * (rho + z)))
    return np.array([ux, uy, uz])


def stress(disp, x, y, z):
    """Voigt (11, 22, 33, 23, 13, 12) stress of a unit point force, by complex-step gradients."""
    h = 1e-30
    grad = np.empty((3, 3))
    base = [x, y, z]
    for j in range(3):
        arg = [complex(v) for v in base]
        arg[j] += 1j * h
        grad[:, j] = np.imag(disp(*arg)) / h
    eps = 0.5 * (grad + grad.T)
    tr = np.trace(eps)
    s = 2 * G * eps + LAM * tr * np.eye(3)
    return np.array([s[0, 0], s[1, 1], s[2, 2], s[1, 2], s[0, 2], s[0, 1]])


def check_surface_green():
    """At z -> 0 the fields reduce to spec 1.1 (a guard on the transcription)."""
    x, y, z = 0.7, -0.4, 1e-12
    r = np.hypot(x, y)
    un, ut = disp_normal(x, y, z), disp_tangential(x, y, z)
    want_n = [-(1 - 2 * NU) / (4 * np.pi * G) * x / r**2, -(1 - 2 * NU) / (4 * np.pi * G) * y / r**2,
              (1 - NU**2) / (np.pi * E) / r]
    want_t = [((1 - NU) / r + NU * x * x / r**3) / (2 * np.pi * G), NU / (2 * np.pi * G) * x * y / r**3,
              (1 - 2 * NU) / (4 * np.pi * G) * x / r**2]
    assert np.allclose(un, want_n, rtol=1e-9) and np.allclose(ut, want_t, rtol=1e-9)


def hertz_stress(point, with_shear):
    x0, y0, z0 = point

    def over_theta(t):
        r = np.sin(t)
        weight = np.cos(t) * np.cos(t) * r  # p = cos t, dr = cos t dt, area element r dr dtheta

        def inner(theta):
            xs, ys = r * np.cos(theta), r * np.sin(theta)
            s = stress(disp_normal, x0 - xs, y0 - ys, z0)
            if with_shear:
                s = s + MU_FRICTION * stress(disp_tangential, x0 - xs, y0 - ys, z0)
            return s

        return weight * quad_vec(inner, 0, 2 * np.pi, epsabs=1e-13, epsrel=1e-11, limit=400)[0]

    return quad_vec(over_theta, 0, np.pi / 2, epsabs=1e-13, epsrel=1e-11, limit=400)[0]


def generate():
    check_surface_green()
    pts = np.array(POINTS, dtype=float)
    cases = []
    for name, shear in (("pressure", False), ("pressure_and_shear", True)):
        values = np.array([hertz_stress(p, shear) for p in POINTS])
        cases.append({
            "case": f"hertz_subsurface_{name}",
            "arrays": {"points": pts.reshape(-1), "stress": values.reshape(-1)},
            "attrs": {"a": 1.0, "p0": 1.0, "nu": NU, "friction": MU_FRICTION if shear else 0.0,
                      "layout": "points: (n, 3) x, y, z / a row-major; stress: (n, 6) Voigt 11,22,33,23,13,12, "
                                "tension positive, per p0",
                      "method": "cubature of Boussinesq/Cerruti point-force stresses (complex-step "
                                "gradients of Johnson Eqs. 3.19, 3.22a) over p0 sqrt(1-r^2/a^2)"},
        })
    return cases
