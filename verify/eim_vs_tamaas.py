"""Side-by-side: one application of the eigenstrain volume operator, halfspace against Tamaas 2.9
(`mindlin_gradient`: eigenstress -> strain gradient on a volume_2d model), at equal cell counts,
same run.

halfspace: `halfspace study eim-operator --grid N --layers L` (eigenstrain on every layer -> strain on
every layer of the half-space: cuboids + mirror images + correction pressure, non-periodic DC-FFT,
kernel spectra stored by layer difference / sum); Tamaas: periodic in-plane, Fourier in-plane and
analytic in depth (Frerot et al. 2019). Both on this machine's cores (Tamaas as installed).

Run: verify/.venv/bin/python verify/eim_vs_tamaas.py target/release/halfspace 8x64 32x64 8x128 32x128
Prints a markdown table (docs/performance.md).
"""
import json
import subprocess
import sys
import time

import numpy as np
import tamaas as tm


def tamaas_apply(layers, n, repeats=5):
    model = tm.ModelFactory.createModel(tm.model_type.volume_2d, [1.0, 1.0, 1.0], [layers, n, n])
    model.E, model.nu = 1.0, 0.3
    t = time.perf_counter()
    tm.ModelFactory.registerVolumeOperators(model)
    op = model.operators["mindlin_gradient"]
    x = np.random.default_rng(1).random((layers, n, n, 6))
    y = np.zeros((layers, n, n, 6))
    op(x, y)
    build = time.perf_counter() - t
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        op(x, y)
        times.append(time.perf_counter() - t)
    return build, float(np.median(times))


def ours(binary, layers, n):
    out = subprocess.run([binary, "study", "eim-operator", "--grid", str(n), "--layers", str(layers), "--json"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def main(argv):
    binary = argv[1]
    cases = [tuple(int(v) for v in c.split("x")) for c in argv[2:]] or [(8, 64), (32, 64), (8, 128), (32, 128)]
    tm.set_log_level(tm.LogLevel.error)
    print("| layers × N² | halfspace build (s) | halfspace apply (s) | stored spectra (MB) | "
          "Tamaas build (s) | Tamaas apply (s) | Tamaas / halfspace |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for layers, n in cases:
        h = ours(binary, layers, n)
        tb, ta = tamaas_apply(layers, n)
        print(f"| {layers} × {n}² | {h['build_seconds']:.2f} | {h['apply_seconds_median']:.3f} | "
              f"{h['spectra_bytes'] / 1e6:.0f} | {tb:.2f} | {ta:.3f} | {ta / h['apply_seconds_median']:.2f} |",
              flush=True)


if __name__ == "__main__":
    main(sys.argv)
