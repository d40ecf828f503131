"""Hertz contact by the MDR from Python, against Hertz's closed form, homogeneous and graded.

    python examples/hertz_mdr.py
"""
import numpy as np

import halfspace as hs


def main() -> None:
    steel = hs.Homogeneous(E=210e9, nu=0.3)
    hertz = hs.axisym(hs.Sphere(R=0.1), steel, force=10.0)
    e_star = 210e9 / (1 - 0.3**2)
    a = (3 * 10.0 * 0.1 / (4 * e_star)) ** (1 / 3)
    p0 = 3 * 10.0 / (2 * np.pi * a**2)
    print(f"a = {hertz.contact_radius:.6e} m (Hertz {a:.6e}), p0 = {hertz.max_pressure:.5e} Pa (Hertz {p0:.5e})")
    assert abs(hertz.contact_radius / a - 1) < 1e-4
    assert abs(hertz.max_pressure / p0 - 1) < 1e-3
    inside = hertz.r < 0.9 * a
    closed = p0 * np.sqrt(1 - (hertz.r[inside] / a) ** 2)
    print(f"max |p − p_Hertz| / p0 inside 0.9a: {np.abs(hertz.pressure[inside] - closed).max() / p0:.2e}")
    # A power-law graded half-space E(z) = E0 (z/z0)^k, z0 = 1 mm: at 1 μm indentation the material
    # near the surface is softer the larger k, so the force falls and the contact widens
    # (Willert et al. 2021, Eqs. 23–29).
    for k in (-0.5, 0.0, 0.5):
        g = hs.axisym(hs.Sphere(R=0.1), hs.Graded(E0=210e9, z0=1e-3, nu=0.3, k=k), depth=1e-6)
        print(f"k = {k:+.1f}: F = {g.force:.4e} N, a = {g.contact_radius:.4e} m")


if __name__ == "__main__":
    main()
