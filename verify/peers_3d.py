"""3D normal contact side by side: halfspace `contact3d`, ASPHER (`aspher.solve_nested`, backend
"fft") and Tamaas (non-periodic `dcfft` + PolonskyKeerRey), the same frictionless Hertz case in the
same run (verify/README.md, docs/performance.md).

Case: R = 105 μm, E = 210 GPa, ν = 0.3, W = 80 mN, square domain 4a, N² cells. For every tool and
(N, tol): total time = setup + solve (what a user waits for, output writing excluded), iterations on
the finest grid, the L2 error of p against Hertz, and the peak resident memory of the process
that ran the case (each case runs in its own process; ASPHER and Tamaas in Python, whose baseline
with numpy and the module imported is printed once). Up to 512² each case runs three times and the
fastest counts (millisecond timings vary by ±30 % between runs).

Optional, not in CI: `pip install -r verify/requirements-peers.txt` (ASPHER builds from its sdist;
install Debian's `libeigen3-dev` first, or its build tries to download Eigen). Threads: 2 each
(rayon's default on 2 cores; OMP_NUM_THREADS=2 for the others).

Run: verify/.venv/bin/python verify/peers_3d.py target/release/halfspace --sizes 128 256 512 1024 2048
Prints a markdown table (docs/performance.md). `--threads 1` on a loaded machine: wall times then
depend on the other load, the processor-time ratio (its own column) much less.
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

R, E, NU, W = 105e-6, 210e9, 0.3, 0.08
E_STAR = E / (1 - NU * NU)
A = (3 * W * R / (4 * E_STAR)) ** (1 / 3)
P0 = 3 * W / (2 * np.pi * A * A)
L = 4 * A


def hertz_l2(x, y, p):
    r2 = (x ** 2 + y ** 2) / (A * A)
    ph = np.where(r2 < 1, P0 * np.sqrt(np.clip(1 - r2, 0, None)), 0.0)
    return float(np.sqrt(np.sum((p - ph) ** 2) / np.sum(ph ** 2)))


def centres(n):
    x = (np.arange(n) + 0.5) * L / n - L / 2
    return np.meshgrid(x, x, indexing="ij")


def peak_mb(who):
    return resource.getrusage(who).ru_maxrss / 1024.0


def case_halfspace(binary, n, tol):
    cmd = [binary, "contact3d", "--indenter", f"sphere:R={R}", "--material", f"homogeneous:E={E},nu={NU}",
           "--force", str(W), "--grid", str(n), "--extent", repr(L), "--tol", str(tol), "--json"]
    # Timing and memory without output; the L2 error from a second run that writes the pressure.
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    summary = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    # Processor time of the whole process (start-up and parsing included: a bias against halfspace).
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    mem = peak_mb(resource.RUSAGE_CHILDREN)
    with tempfile.TemporaryDirectory() as tmp:
        out = f"{tmp}/hertz.npz"
        subprocess.run(cmd + ["--out", out], check=True, capture_output=True, text=True)
        data = np.load(out)
        l2 = hertz_l2(data["x"], data["y"], data["pressure"])
    return {"seconds": summary["seconds"], "cpu": cpu, "setup": summary["setup_seconds"],
            "iterations": summary["iterations"], "l2": l2, "peak_mb": mem}


def warm_up(solve):
    """One small solve first: one-off initialisation (thread pools, FFT planning caches) is not
    charged to the timed case (the halfspace binary plans inside its timed solve)."""
    solve(128, 1e-6)


def case_aspher(n, tol, warm=True):
    import aspher
    if warm:
        warm_up(lambda m, t: case_aspher(m, t, warm=False))
    X, Y = centres(n)
    gap = (X ** 2 + Y ** 2) / (2 * R)
    t, c = time.perf_counter(), time.process_time()
    res = aspher.solve_nested(n, gap.ravel(), W / (L * L), domain_size=L, E_star=E_STAR, backend="fft", tol=tol)
    seconds, cpu = time.perf_counter() - t, time.process_time() - c
    p = np.asarray(res.pressure).reshape(n, n)
    return {"seconds": seconds, "cpu": cpu, "iterations": int(res.iterations), "l2": hertz_l2(X, Y, p),
            "status": str(res.status), "peak_mb": peak_mb(resource.RUSAGE_SELF)}


def case_tamaas(n, tol, warm=True):
    import tamaas as tm
    tm.set_log_level(tm.LogLevel.error)
    if warm:
        warm_up(lambda m, t: case_tamaas(m, t, warm=False))
    X, Y = centres(n)
    t = time.perf_counter()
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [L, L], [n, n])
    model.E, model.nu = E, NU
    tm.ModelFactory.registerNonPeriodic(model, "dcfft")
    solver = tm.PolonskyKeerRey(model, -(X ** 2 + Y ** 2) / (2 * R), tol, tm.PolonskyKeerRey.pressure,
                                tm.PolonskyKeerRey.pressure)
    solver.setIntegralOperator("dcfft")
    solver.max_iter = 20000
    solver.solve(W / (L * L))
    seconds = time.perf_counter() - t
    p = np.array(model.traction).reshape(n, n)
    return {"seconds": seconds, "iterations": None, "l2": hertz_l2(X, Y, p),
            "peak_mb": peak_mb(resource.RUSAGE_SELF)}


def baseline(tool):
    """Peak memory of the Python process with numpy and the module imported, before any solve."""
    __import__(tool)
    return {"peak_mb": peak_mb(resource.RUSAGE_SELF)}


def in_subprocess(args, repeat=1, threads=2):
    """The case in a fresh process; with `repeat` > 1 the fastest of that many (timings of a few
    milliseconds vary by ±30 % from run to run on this machine), and the least processor time."""
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), RAYON_NUM_THREADS=str(threads))
    best = None
    for _ in range(repeat):
        out = subprocess.run([sys.executable, __file__, "--case", *map(str, args)], check=True,
                             capture_output=True, text=True, env=env)
        r = json.loads(out.stdout.strip().splitlines()[-1])
        if best is None or r["seconds"] < best["seconds"]:
            best = dict(r, cpu=min(r.get("cpu", 0.0), best["cpu"]) if best else r.get("cpu", 0.0))
        elif "cpu" in r:
            best["cpu"] = min(best["cpu"], r["cpu"])
    return best


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary", nargs="?")
    ap.add_argument("--sizes", type=int, nargs="+", default=[128, 256, 512, 1024, 2048])
    ap.add_argument("--tols", type=float, nargs="+", default=[1e-8, 1e-10])
    ap.add_argument("--tamaas-max", type=int, default=1024, help="largest N for Tamaas (minutes beyond)")
    ap.add_argument("--threads", type=int, default=2,
                    help="threads of every tool (OMP_NUM_THREADS, RAYON_NUM_THREADS); 1 on a loaded machine, "
                         "where the processor-time ratio is the steadier one")
    ap.add_argument("--case", nargs="+")
    a = ap.parse_args()
    if a.case:
        tool = a.case[0]
        if tool == "baseline":
            r = baseline(a.case[1])
        else:
            n, tol = int(a.case[1]), float(a.case[2])
            r = {"halfspace": lambda: case_halfspace(a.case[3], n, tol), "aspher": lambda: case_aspher(n, tol),
                 "tamaas": lambda: case_tamaas(n, tol)}[tool]()
        print(json.dumps(r), flush=True)
        return
    base = {t: in_subprocess(["baseline", t])["peak_mb"] for t in ("aspher", "tamaas")}
    print(f"Python baseline (numpy + module imported): ASPHER {base['aspher']:.0f} MB, "
          f"Tamaas {base['tamaas']:.0f} MB\n")
    print("| N² | tol | halfspace total (setup) | it | L2 | peak | ASPHER total | it | L2 | peak | "
          "ASPHER / halfspace | same, processor time | Tamaas total | L2 | Tamaas / halfspace |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for n in a.sizes:
        for tol in a.tols:
            repeat = 3 if n <= 512 else 1
            h = in_subprocess(["halfspace", n, tol, a.binary], repeat, a.threads)
            s = in_subprocess(["aspher", n, tol], repeat, a.threads)
            row = (f"| {n}² | {tol:g} | {h['seconds']:.3f} s ({h['setup']:.3f}) | {h['iterations']} | "
                   f"{100 * h['l2']:.3f} % | {h['peak_mb']:.0f} MB | {s['seconds']:.3f} s | {s['iterations']} | "
                   f"{100 * s['l2']:.3f} % | {s['peak_mb']:.0f} MB | {s['seconds'] / h['seconds']:.2f}× | "
                   f"{s['cpu'] / h['cpu']:.2f}× |")
            if n <= a.tamaas_max:
                t = in_subprocess(["tamaas", n, tol], repeat, a.threads)
                row += f" {t['seconds']:.3f} s | {100 * t['l2']:.3f} % | {t['seconds'] / h['seconds']:.1f}× |"
            else:
                row += " – | – | – |"
            print(row, flush=True)


if __name__ == "__main__":
    main()
