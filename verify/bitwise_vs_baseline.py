"""Runs the same CLI commands with a baseline binary and a candidate binary and compares every
output exactly: the --json objects (all keys but wall-clock times) and every array of the .h5 / .npz
files the commands write (bit for bit: same dtype, shape and bytes; NaN equal to NaN).

    python verify/bitwise_vs_baseline.py BASELINE_BINARY CANDIDATE_BINARY [WORKDIR]

Exit status 0 when everything is identical, 1 otherwise (each difference is printed).
"""

import json
import math
import pathlib
import shutil
import subprocess
import sys

import h5py
import numpy as np

R = "sphere:R=105e-6"
STEEL = "homogeneous:E=210e9,nu=0.3"

LOOP_TOML = """grid = 32
normal_steps = 4
amplitude = 0.02e-6
shift_step = 0.01e-6
subsurface_over_a = 1.0
"""

COMPOSITE_TOML = """normal_steps = 3
amplitude = 0.01e-6
shift_step = 0.01e-6
subsurface_over_a = 0.0
"""

WEAR_TOML = """chi = 0.4
n = 301
dtau = 0.01
tau_end = 0.5
snapshots = [0.1, 0.5]
method = "mvm"
"""

MAP_TOML = """grid = 32
normal_steps = 4
amplitude = 0.02e-6
shift_step = 0.01e-6
subsurface_over_a = 0.0

[map]
loads = [0.04, 0.08]
amplitudes = [0.01e-6, 0.04e-6]
case = "homogeneous"
"""


def cases(out):
    """(name, argv after the binary) for every compared run; `out` is the run's output folder."""
    c3 = ["contact3d", "--indenter", R, "--material", STEEL, "--force", "0.08", "--json"]
    return [
        ("hertz", c3 + ["--grid", "64", "--out", f"{out}/hertz.h5"]),
        ("hertz-256", c3 + ["--grid", "256", "--out", f"{out}/hertz256.npz"]),
        ("hertz-depth", ["contact3d", "--indenter", R, "--material", STEEL, "--depth", "8e-8",
                         "--grid", "64", "--json", "--out", f"{out}/depth.h5"]),
        ("friction-shift", c3 + ["--grid", "64", "--friction", "0.3", "--shift-x", "0.01e-6",
                                 "--out", f"{out}/shift.h5"]),
        ("coupled-shift", c3 + ["--grid", "64", "--friction", "0.3", "--shift-x", "0.01e-6",
                                "--indenter-material", "homogeneous:E=70e9,nu=0.33",
                                "--out", f"{out}/coupled.h5"]),
        ("tangential-force", c3 + ["--grid", "64", "--friction", "0.3",
                                   "--tangential-force", "0.012", "--out", f"{out}/qforce.npz"]),
        ("inhomogeneity-subsurface", c3 + [
            "--grid", "64", "--friction", "0.3", "--shift-x", "0.005e-6",
            "--inhomogeneity", "sphere:x=0,y=0,z=2.5e-6,r=1e-6,E=420e9,nu=0.3",
            "--inhomogeneity", "cuboid:x=1e-6,y=0,z=4e-6,hx=0.5e-6,hy=0.5e-6,hz=0.5e-6,E=100e9,nu=0.25",
            "--subsurface", "6e-6", "--out", f"{out}/inhom.h5"]),
        ("subsurface", c3 + ["--grid", "64", "--subsurface", "6e-6", "--out", f"{out}/sub.npz"]),
        ("fretting-loop", ["fretting-loop", "--config", f"{out}/loop.toml", "--out",
                           f"{out}/loop", "--json"]),
        ("fretting-loop-composite", ["fretting-loop", "--case", "composite", "--config",
                                     f"{out}/composite.toml", "--out", f"{out}/composite",
                                     "--json"]),
        ("fretting-map", ["fretting-map", "--config", f"{out}/map.toml", "--out", f"{out}/map",
                          "--json"]),
        ("fretting-wear", ["fretting-wear", "--chi", "0.5", "--n", "301", "--dtau", "0.005",
                           "--tau-end", "1.0", "--out", f"{out}/wear", "--json"]),
        ("fretting-wear-graded", ["fretting-wear", "--material", "graded:k=0.5,nu=0.3", "--n",
                                  "301", "--tau-end", "0.3", "--out", f"{out}/wear-graded",
                                  "--json"]),
        ("fretting-wear-config", ["fretting-wear", "--config", f"{out}/wear.toml", "--out",
                                  f"{out}/wear-config", "--json"]),
        ("axisym", ["axisym", "--profile", "sphere:R=1e-3", "--material", STEEL, "--force", "10",
                    "--json", "--out", f"{out}/axisym.h5"]),
        ("axisym-graded", ["axisym", "--profile", "sphere:R=1e-3", "--material",
                           "graded:E0=210e9,z0=1e-3,nu=0.3,k=0.3", "--depth", "1e-6",
                           "--method", "mvm", "--n", "800", "--json",
                           "--out", f"{out}/graded.npz"]),
    ]


TIME_KEYS = ("seconds", "elapsed")


def strip_times(v):
    if isinstance(v, dict):
        return {k: strip_times(x) for k, x in v.items() if not any(t in k for t in TIME_KEYS)}
    if isinstance(v, list):
        return [strip_times(x) for x in v]
    return v


def same_json(a, b, path, diffs):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                diffs.append(f"{path}.{k}: only in {'baseline' if k in a else 'candidate'}")
            else:
                same_json(a[k], b[k], f"{path}.{k}", diffs)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            diffs.append(f"{path}: length {len(a)} vs {len(b)}")
        for i, (x, y) in enumerate(zip(a, b)):
            same_json(x, y, f"{path}[{i}]", diffs)
    elif isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        pass
    elif a != b or type(a) is not type(b):
        diffs.append(f"{path}: {a!r} vs {b!r}")


def arrays(path):
    """name -> array (and attributes as 0-d arrays) of one .h5 or .npz file."""
    out = {}
    if path.suffix == ".npz":
        with np.load(path, allow_pickle=False) as z:
            for k in z.files:
                out[k] = z[k]
    else:
        with h5py.File(path, "r") as f:
            def visit(name, obj):
                for k, v in obj.attrs.items():
                    if not any(t in k for t in TIME_KEYS):
                        out[f"{name}@{k}"] = np.asarray(v)
                if isinstance(obj, h5py.Dataset):
                    out[name] = obj[()]
            visit("/", f)
            f.visititems(visit)
    return out


def metadata(x, root):
    """The JSON attributes an .npz stores as `metadata` (uint8), without times, paths relative."""
    text = bytes(np.asarray(x, dtype=np.uint8)).decode()
    return strip_times(json.loads(text.replace(str(root), "ROOT")))


def same_arrays(a, b, label, diffs, roots):
    for k in sorted(set(a) | set(b)):
        if k not in a or k not in b:
            diffs.append(f"{label}:{k}: only in {'baseline' if k in a else 'candidate'}")
            continue
        x, y = np.asarray(a[k]), np.asarray(b[k])
        if k == "metadata" and x.dtype == np.uint8:
            same_json(metadata(x, roots[0]), metadata(y, roots[1]), f"{label}:metadata", diffs)
            continue
        if x.dtype.kind in "SUO" and x.shape == ():
            x = np.asarray(str(x.item()).replace(str(roots[0]), "ROOT"))
            y = np.asarray(str(y.item()).replace(str(roots[1]), "ROOT"))
        if x.dtype != y.dtype or x.shape != y.shape:
            diffs.append(f"{label}:{k}: {x.dtype}{x.shape} vs {y.dtype}{y.shape}")
        elif x.dtype.kind in "fc":
            if np.ascontiguousarray(x).tobytes() != np.ascontiguousarray(y).tobytes():
                d = np.nanmax(np.abs(x - y)) if x.size else 0.0
                diffs.append(f"{label}:{k}: differs (max |Δ| {d:.3e})")
        elif not np.array_equal(x, y):
            diffs.append(f"{label}:{k}: differs")


def run(binary, root):
    root.mkdir(parents=True, exist_ok=True)
    (root / "loop.toml").write_text(LOOP_TOML)
    (root / "composite.toml").write_text(COMPOSITE_TOML)
    (root / "map.toml").write_text(MAP_TOML)
    (root / "wear.toml").write_text(WEAR_TOML)
    results = {}
    for name, argv in cases(root):
        p = subprocess.run([binary, *argv], capture_output=True, text=True)
        if p.returncode != 0:
            results[name] = {"error": p.returncode, "stderr": p.stderr.strip()}
            continue
        lines = [l for l in p.stdout.splitlines() if l.startswith("{")]
        text = lines[-1].replace(str(root), "ROOT") if lines else "{}"
        results[name] = strip_times(json.loads(text))
    return results


def main():
    base, cand = sys.argv[1], sys.argv[2]
    work = pathlib.Path(sys.argv[3] if len(sys.argv) > 3 else "bitwise-work")
    shutil.rmtree(work, ignore_errors=True)
    rb, rc = run(base, work / "baseline"), run(cand, work / "candidate")
    diffs = []
    for name in rb:
        d = []
        same_json(rb[name], rc.get(name), name, d)
        print(f"{name:26s} json {'identical' if not d else 'DIFFERS'}"
              + (f" ({rb[name]['stderr']})" if "error" in rb[name] else ""))
        diffs += d
    files = sorted(p.relative_to(work / "baseline") for p in (work / "baseline").rglob("*")
                   if p.suffix in (".h5", ".npz"))
    cand_files = sorted(p.relative_to(work / "candidate") for p in (work / "candidate").rglob("*")
                        if p.suffix in (".h5", ".npz"))
    if files != cand_files:
        diffs.append(f"files: {files} vs {cand_files}")
    for rel in files:
        if not (work / "candidate" / rel).exists():
            continue
        d = []
        a, b = arrays(work / "baseline" / rel), arrays(work / "candidate" / rel)
        same_arrays(a, b, str(rel), d, (work / "baseline", work / "candidate"))
        print(f"{str(rel):40s} {len(a):3d} arrays {'identical' if not d else 'DIFFER'}")
        diffs += d
    for d in diffs:
        print("DIFF", d)
    print("bit for bit:", "yes" if not diffs else f"NO ({len(diffs)} differences)")
    sys.exit(1 if diffs else 0)


if __name__ == "__main__":
    main()
