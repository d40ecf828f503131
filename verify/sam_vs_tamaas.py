"""Side-by-side: halfspace `contact3d` (frictionless Hertz, DC-FFT + Polonsky–Keer) against Tamaas
(`verify/tamaas_hertz.py`: its non-periodic dcfft operator with PolonskyKeerRey), same case, same
tolerance (1e-10), same run. Solve times only (operator setup excluded on both sides).

Run: verify/.venv/bin/python verify/sam_vs_tamaas.py target/release/halfspace 128 256 512 1024
Prints a markdown table (append it to docs/performance.md).
"""
import json
import subprocess
import sys
import tempfile

import numpy as np

from tamaas_hertz import R, W, run as tamaas_run  # noqa: E402

E, NU = 210e9, 0.3


def ours(binary, n):
    e_star = E / (1 - NU * NU)
    a = (3 * W * R / (4 * e_star)) ** (1 / 3)
    p0 = 3 * W / (2 * np.pi * a * a)
    with tempfile.TemporaryDirectory() as tmp:
        out = f"{tmp}/hertz.npz"
        cmd = [binary, "contact3d", "--indenter", f"sphere:R={R}", "--material", f"homogeneous:E={E},nu={NU}",
               "--force", str(W), "--friction", "0", "--grid", str(n), "--extent", repr(4 * a),
               "--tol", "1e-10", "--json", "--out", out]
        summary = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
        data = np.load(out)
        x, y, p = data["x"], data["y"], data["pressure"]
    r2 = (x ** 2 + y ** 2) / (a * a)
    ph = np.where(r2 < 1, p0 * np.sqrt(np.clip(1 - r2, 0, None)), 0.0)
    l2 = float(np.sqrt(np.sum((p - ph) ** 2) / np.sum(ph ** 2)))
    return {"seconds": summary["solve_seconds"], "iterations": summary["iterations"], "l2": l2,
            "p_max_over_p0": summary["max_pressure"] / p0}


if __name__ == "__main__":
    import tamaas as tm
    tm.set_log_level(tm.LogLevel.error)
    binary = sys.argv[1]
    sizes = [int(v) for v in sys.argv[2:]] or [128, 256, 512]
    print("| N² | halfspace solve | iterations | L2 error | Tamaas solve | L2 error | Tamaas / halfspace |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for n in sizes:
        a, b = ours(binary, n), tamaas_run(n)
        print(f"| {n}² | {a['seconds']:.3f} s | {a['iterations']} | {100 * a['l2']:.3f} % | "
              f"{b['seconds']:.3f} s | {100 * b['l2']:.3f} % | {b['seconds'] / a['seconds']:.1f}× |", flush=True)
