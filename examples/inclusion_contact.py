"""A 3D contact above a stiff spherical inhomogeneity (spec sam.md §7.6: E_I = 2E, radius 0.3a,
centre 0.5a deep), from Python: pressure, eigenstrains and the subsurface von Mises stress.

    python examples/inclusion_contact.py [grid]   (default 64)
"""
import sys

import numpy as np

import halfspace as hs


def main(grid: int = 64) -> None:
    a = 3.0111e-6                                   # Hertz radius of this case (m)
    p0 = 1.5 * 0.08 / (np.pi * a**2)
    stiff = hs.Inhomogeneity.sphere(x=0.0, y=0.0, z=0.5 * a, r=0.3 * a, E=420e9, nu=0.3)
    c = hs.contact3d(hs.Sphere(R=105e-6), hs.Homogeneous(E=210e9, nu=0.3), force=0.08, grid=grid,
                     inhomogeneities=[stiff], subsurface=a)
    print(f"{grid}²: p_max/p0 = {c.max_pressure / p0:.4f} (docs/theory-sam.md#inhomogeneity-references at 64²: 1.277), "
          f"contact area / πa² = {c.contact_area / (np.pi * a**2):.4f}")
    print(f"{c.inclusion_cells} inclusion cells, {c.outer_iterations} outer / {c.eim_iterations} EIM iterations")
    # Present with ``subsurface`` (None without): the volume fields and their maxima.
    assert c.max_von_mises is not None and c.von_mises is not None and c.eigenstrain_zz is not None
    print(f"max von Mises {c.max_von_mises / p0:.4f} p0 at (x, y, z) = {c.max_von_mises_at} m")
    assert c.max_von_mises == c.von_mises.max()
    assert c.max_pressure > p0                      # the stiff sphere raises the peak
    assert c.eigenstrain_zz.shape == c.von_mises.shape


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 64)
