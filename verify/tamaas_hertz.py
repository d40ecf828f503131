"""Side-by-side Hertz benchmark: Tamaas (pip `tamaas`, its non-periodic `dcfft` operator with
PolonskyKeerRey) on the case halfspace's `sam` benchmark solves (verify/README.md).

R = 105 μm, E = 210 GPa, ν = 0.3, W = 80 mN, square domain 4a, N² cells, tolerance 1e-10.
Prints one JSON line per N: seconds, iterations (Tamaas's own count when available), the L2 error of
p against Hertz and p_max/p0. Run: verify/.venv/bin/python verify/tamaas_hertz.py 128 256 512 1024
"""
import json
import sys
import time

import numpy as np
import tamaas as tm

R, E, NU, W = 105e-6, 210e9, 0.3, 0.08


def run(n):
    e_star = E / (1 - NU * NU)
    a = (3 * W * R / (4 * e_star)) ** (1 / 3)
    p0 = 3 * W / (2 * np.pi * a * a)
    L = 4 * a
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [L, L], [n, n])
    model.E, model.nu = E, NU
    tm.ModelFactory.registerNonPeriodic(model, "dcfft")
    x = (np.arange(n) + 0.5) * L / n - L / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    surface = -(X ** 2 + Y ** 2) / (2 * R)
    solver = tm.PolonskyKeerRey(model, surface, 1e-10, tm.PolonskyKeerRey.pressure, tm.PolonskyKeerRey.pressure)
    solver.setIntegralOperator("dcfft")
    solver.max_iter = 10000
    t = time.perf_counter()
    solver.solve(W / (L * L))
    seconds = time.perf_counter() - t
    p = np.array(model.traction).reshape(n, n)
    r2 = (X ** 2 + Y ** 2) / (a * a)
    ph = np.where(r2 < 1, p0 * np.sqrt(np.clip(1 - r2, 0, None)), 0.0)
    l2 = float(np.sqrt(np.sum((p - ph) ** 2) / np.sum(ph ** 2)))
    return {"n": n, "seconds": seconds, "l2": l2, "p_max_over_p0": float(p.max() / p0),
            "force_over_w": float(p.sum() * (L / n) ** 2 / W)}


if __name__ == "__main__":
    tm.set_log_level(tm.LogLevel.error)
    for n in [int(v) for v in sys.argv[1:]] or [128, 256, 512]:
        print(json.dumps(run(n)), flush=True)
