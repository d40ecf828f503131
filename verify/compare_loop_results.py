"""Compares two fretting-loop results.h5 files (two builds, or two settings, of the same case):
the largest difference of the surface pressure and shears at the points A-D over the Hertz
pressure p0, of the von Mises fields over p0, of the slips over the largest slip, and the relative
differences of the scalar attributes (dissipated energy, energy ratio, ...).

    python verify/compare_loop_results.py A/results.h5 B/results.h5 [--limit 1e-6]

Exit status 0 when every pressure, shear and von Mises difference is within `limit` p0 (the
issue-21 criterion "same results to 1e-6 p0"), 1 otherwise; the report is printed either way.
"""

import sys

import h5py
import numpy as np

TRACTIONS = ("pressure", "shear_x", "shear_y")


def datasets(h):
    names = []
    h.visit(lambda k: names.append(k) if isinstance(h[k], h5py.Dataset) else None)
    return names


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    limit = 1e-6
    if "--limit" in sys.argv:
        limit = float(sys.argv[sys.argv.index("--limit") + 1])
        args.remove(sys.argv[sys.argv.index("--limit") + 1])
    if len(args) != 2:
        sys.exit(__doc__)
    a, b = h5py.File(args[0], "r"), h5py.File(args[1], "r")
    p0 = float(a.attrs["hertz_pressure"])
    if float(b.attrs["hertz_pressure"]) != p0:
        sys.exit("the two files are not the same case (hertz_pressure differs)")
    names_a, names_b = set(datasets(a)), set(datasets(b))
    if names_a != names_b:
        print("datasets only in A:", sorted(names_a - names_b))
        print("datasets only in B:", sorted(names_b - names_a))
    worst = {"traction": (0.0, ""), "von_mises": (0.0, ""), "slip": (0.0, "")}
    equal = 0
    for name in sorted(names_a & names_b):
        x, y = np.asarray(a[name]), np.asarray(b[name])
        if x.shape != y.shape:
            print(f"{name}: shapes {x.shape} and {y.shape}")
            continue
        if x.tobytes() == y.tobytes():
            equal += 1
        if x.dtype.kind != "f":
            continue
        base = name.removeprefix("homogeneous_")
        d = float(np.max(np.abs(x - y))) if x.size else 0.0
        if base.startswith(TRACTIONS) and base[-2:] in ("_A", "_B", "_C", "_D"):
            key, scale = "traction", p0
        elif base.startswith("von_mises"):
            key, scale = "von_mises", p0
        elif base.startswith("slip"):
            key, scale = "slip", max(float(np.max(np.abs(x))), 1e-300)
        else:
            continue
        if d / scale > worst[key][0]:
            worst[key] = (d / scale, name)
    print(f"{equal} of {len(names_a & names_b)} datasets bit for bit equal")
    print(f"max |dp|, |dq| / p0     {worst['traction'][0]:.3e}  ({worst['traction'][1]})")
    print(f"max |d von Mises| / p0  {worst['von_mises'][0]:.3e}  ({worst['von_mises'][1]})")
    print(f"max |d slip| / max slip {worst['slip'][0]:.3e}  ({worst['slip'][1]})")
    for key in sorted(set(a.attrs) & set(b.attrs)):
        u, v = a.attrs[key], b.attrs[key]
        if isinstance(u, (float, np.floating)) and u != v:
            rel = abs(float(u) - float(v)) / max(abs(float(u)), 1e-300)
            print(f"attr {key}: {float(u):.12g} -> {float(v):.12g} (relative {rel:.2e})")
    ok = max(worst["traction"][0], worst["von_mises"][0]) <= limit
    print(f"within {limit:g} p0: {'yes' if ok else 'NO'}")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
