"""Side-by-side: the Python package against the command line on the same cases (same run, this
machine), and a fretting map run serially (the points on the local cores) against a Dask
LocalCluster of two single-threaded workers.

The CLI time is the whole process (start, parse, solve, write JSON); the Python time is the call
(inputs converted, GIL released during the solve, NumPy arrays out), the package already imported.

Run (after `cargo build --release` and `python/develop.sh`):
    verify/.venv/bin/python verify/python_overhead.py target/release/halfspace
Prints a markdown table (docs/python.md).
"""
import json
import subprocess
import sys
import tempfile
import time

import numpy as np

import halfspace as hs

MAP = {"grid": 64, "normal_steps": 20, "shift_step": 0.004e-6, "subsurface_over_a": 0.0}
LOADS = [0.04, 0.08, 0.16]
AMPLITUDES = [0.01e-6, 0.02e-6, 0.04e-6, 0.08e-6]


def best(f, repeats):
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)


def cli(binary, *args):
    subprocess.run([binary, *args, "--json"], check=True, capture_output=True)


def toml(cfg):
    return "\n".join(f"{k} = {v!r}" for k, v in cfg.items()) + "\n"


def main(binary):
    rows = []
    rows.append((
        "axisym Hertz, n = 2001 (FFT)",
        best(lambda: cli(binary, "axisym", "--profile", "sphere:R=0.1", "--material",
                         "homogeneous:E=210e9,nu=0.3", "--force", "10"), 20),
        best(lambda: hs.axisym(hs.Sphere(R=0.1), hs.Homogeneous(E=210e9, nu=0.3), force=10.0), 20),
    ))
    inc = "sphere:x=0,y=0,z=1.50554e-6,r=0.90332e-6,E=420e9,nu=0.3"
    rows.append((
        "contact3d, stiff sphere inclusion, 64²",
        best(lambda: cli(binary, "contact3d", "--indenter", "sphere:R=105e-6", "--material",
                         "homogeneous:E=210e9,nu=0.3", "--force", "0.08", "--grid", "64",
                         "--inhomogeneity", inc), 3),
        best(lambda: hs.contact3d("sphere:R=105e-6", "homogeneous:E=210e9,nu=0.3", force=0.08,
                                  grid=64, inhomogeneities=[inc]), 3),
    ))
    with tempfile.TemporaryDirectory() as tmp:
        config = f"{tmp}/map.toml"
        with open(config, "w") as f:
            f.write(toml(MAP) + f"\n[map]\nloads = {LOADS!r}\namplitudes = {AMPLITUDES!r}\n")

        def run_cli_map():
            subprocess.run([binary, "fretting-map", "--config", config, "--out", f"{tmp}/out",
                            "--json"], check=True, capture_output=True)

        t_cli = best(run_cli_map, 1)
    serial = None

    def run_serial():
        nonlocal serial
        serial = hs.fretting_map(LOADS, AMPLITUDES, config=MAP)

    t_serial = best(run_serial, 1)
    rows.append((f"fretting map {len(LOADS)}×{len(AMPLITUDES)}, 64², local cores", t_cli, t_serial))
    print("| case | CLI (s) | Python (s) | Python / CLI |")
    print("|---|---|---|---|")
    for name, c, p in rows:
        print(f"| {name} | {c:.4f} | {p:.4f} | {p / c:.3f} |")

    from distributed import Client, LocalCluster

    start = time.perf_counter()
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        up = time.perf_counter() - start
        dist = None

        def run_dist():
            nonlocal dist
            dist = hs.fretting_map(LOADS, AMPLITUDES, config=MAP, client=client)

        t_dist = best(run_dist, 1)
    same = all(np.array_equal(getattr(dist, k), getattr(serial, k))
               for k in ("regime", "dissipated_energy", "energy_ratio"))
    print()
    print("| fretting map 3×4, 64² | seconds | |")
    print("|---|---|---|")
    print(f"| serial (rayon over points, 2 cores) | {t_serial:.2f} | |")
    print(f"| LocalCluster(n_workers=2, threads_per_worker=1) | {t_dist:.2f} | "
          f"{t_dist / t_serial:.2f}× serial; cluster start {up:.1f} s; identical: {same} |")
    print(f"| sum of the points' own times | {serial.seconds.sum():.2f} | |")
    print(json.dumps({"regime": serial.regime.tolist()}))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "target/release/halfspace")
