"""Compares two fretting-loop results.h5 files (two builds, or two settings, of the same case):
the largest difference of the surface pressure and shears at the points A-D over the Hertz
pressure p0, of the von Mises fields over p0, of the slips over the largest slip of the first
file, the attributes that differ (relative differences of the floating-point ones), and how many
datasets are bit for bit equal.

    python verify/compare_loop_results.py A/results.h5 B/results.h5 [--limit 1e-6]

Exit status 0 when both files hold the same datasets with the same shapes, no difference is NaN,
and every pressure, shear and von Mises difference is within `limit` p0 (the issue-21 criterion
"same results to 1e-6 p0"); 1 otherwise. The report is printed either way.
"""

import sys

import h5py
import numpy as np

TRACTIONS = ("pressure", "shear_x", "shear_y")
POINTS = ("_A", "_B", "_C", "_D")


def parse(argv):
    files, limit, k = [], 1e-6, 0
    while k < len(argv):
        a = argv[k]
        if a.startswith("--limit="):
            limit = float(a.split("=", 1)[1])
        elif a == "--limit":
            if k + 1 >= len(argv):
                sys.exit("--limit needs a value\n" + __doc__)
            limit = float(argv[k + 1])
            k += 1
        elif a.startswith("--"):
            sys.exit(f"unknown option {a}\n" + __doc__)
        else:
            files.append(a)
        k += 1
    if len(files) != 2:
        sys.exit(__doc__)
    return files, limit


def datasets(h):
    names = []
    h.visit(lambda k: names.append(k) if isinstance(h[k], h5py.Dataset) else None)
    return names


def kind(name):
    base = name.removeprefix("homogeneous_")
    if base.startswith(TRACTIONS) and base.endswith(POINTS):
        return "traction"
    if base.startswith("von_mises"):
        return "von_mises"
    if base.startswith("slip"):
        return "slip"
    return None


def main():
    (path_a, path_b), limit = parse(sys.argv[1:])
    a, b = h5py.File(path_a, "r"), h5py.File(path_b, "r")
    p0 = float(a.attrs["hertz_pressure"])
    if abs(float(b.attrs["hertz_pressure"]) - p0) > 1e-12 * abs(p0):
        sys.exit("the two files are not the same case (hertz_pressure differs)")
    ok = True
    names_a, names_b = set(datasets(a)), set(datasets(b))
    if names_a != names_b:
        ok = False
        print("datasets only in A:", sorted(names_a - names_b))
        print("datasets only in B:", sorted(names_b - names_a))
    common = sorted(names_a & names_b)
    slip_scale = max(
        [float(np.max(np.abs(a[n]))) for n in common if kind(n) == "slip" and a[n].size] + [0.0]
    )
    worst = {"traction": (0.0, ""), "von_mises": (0.0, ""), "slip": (0.0, "")}
    seen = {"traction": 0, "von_mises": 0, "slip": 0}
    equal = 0
    for name in common:
        x, y = np.asarray(a[name]), np.asarray(b[name])
        if x.shape != y.shape:
            ok = False
            print(f"{name}: shapes {x.shape} and {y.shape}")
            continue
        if x.dtype == y.dtype and x.tobytes() == y.tobytes():
            equal += 1
        k = kind(name)
        if k is None or x.dtype.kind != "f" or not x.size:
            continue
        seen[k] += 1
        d = np.abs(x - y)
        if np.isnan(d).any() and not np.array_equal(np.isnan(x), np.isnan(y)):
            ok = False
            print(f"{name}: NaN in one file where the other has a number")
        d = float(np.nanmax(d)) if not np.isnan(d).all() else 0.0
        scale = p0 if k != "slip" else max(slip_scale, np.finfo(float).tiny)
        if d / scale > worst[k][0]:
            worst[k] = (d / scale, name)
    if seen["traction"] == 0:
        ok = False
        print("no pressure or shear field at the points A-D in common")
    print(f"{equal} of {len(common)} common datasets bit for bit equal")
    print(f"max |dp|, |dq| / p0     {worst['traction'][0]:.3e}  ({worst['traction'][1]})")
    print(f"max |d von Mises| / p0  {worst['von_mises'][0]:.3e}  ({worst['von_mises'][1]})")
    print(f"max |d slip| / max slip {worst['slip'][0]:.3e}  ({worst['slip'][1]})")
    for key in sorted(set(a.attrs) | set(b.attrs)):
        if key not in a.attrs or key not in b.attrs:
            print(f"attr {key}: only in {'A' if key in a.attrs else 'B'}")
            continue
        u, v = a.attrs[key], b.attrs[key]
        if isinstance(u, (float, np.floating)) and isinstance(v, (float, np.floating)):
            if u != v:
                rel = abs(float(u) - float(v)) / max(abs(float(u)), np.finfo(float).tiny)
                print(f"attr {key}: {float(u):.12g} -> {float(v):.12g} (relative {rel:.2e})")
        elif not np.array_equal(np.asarray(u), np.asarray(v)):
            print(f"attr {key}: {u!r} -> {v!r}")
    within = max(worst["traction"][0], worst["von_mises"][0]) <= limit
    print(f"within {limit:g} p0: {'yes' if within else 'NO'}")
    sys.exit(0 if ok and within else 1)


if __name__ == "__main__":
    main()
