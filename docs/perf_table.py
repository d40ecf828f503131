"""Builds the tables of docs/performance.md from criterion's estimates (target/criterion).

Run after `cargo bench -p halfspace-mdr --bench transforms`:  python3 docs/perf_table.py
"""
import json
import pathlib
import sys

root = pathlib.Path(__file__).resolve().parent.parent / "target" / "criterion"


def median(group, fn, n):
    path = root / group / fn / str(n) / "new" / "estimates.json"
    if not path.exists():
        return None
    return json.loads(path.read_text())["median"]["point_estimate"]  # ns


def fmt(ns):
    if ns is None:
        return "—"
    for unit, scale in (("s", 1e9), ("ms", 1e6), ("µs", 1e3)):
        if ns >= scale:
            return f"{ns / scale:.3g} {unit}"
    return f"{ns:.3g} ns"


sizes = [100, 1000, 2001, 10000, 20001, 100000, 1000000]
out = []
for group in ("profile_transform", "stress_transform", "graded_profile_transform", "graded_stress_transform"):
    out.append(f"\n**{group.replace('_', ' ')}** (apply only, planned beforehand)\n")
    out.append("| N | FFT | MVM | MVM / FFT | bare realfft conv. | FFT / bare |")
    out.append("|---:|---:|---:|---:|---:|---:|")
    for n in sizes:
        f, m, b = median(group, "fft", n), median(group, "mvm", n), median("bare_realfft_convolution", "fft", n)
        ratio = f"{m / f:.1f}×" if (f and m) else "—"
        over = f"{f / b:.2f}" if (f and b) else "—"
        out.append(f"| {n} | {fmt(f)} | {fmt(m)} | {ratio} | {fmt(b)} | {over} |")
out.append("\n**convolution engine alone** (`ToeplitzConvolution::apply`, FFT backend)\n")
out.append("| N | engine | bare realfft conv. | engine / bare |")
out.append("|---:|---:|---:|---:|")
for n in sizes:
    e, b = median("engine_convolution", "fft", n), median("bare_realfft_convolution", "fft", n)
    over = f"{e / b:.2f}" if (e and b) else "—"
    out.append(f"| {n} | {fmt(e)} | {fmt(b)} | {over} |")
out.append("\n**graded displacement** (k = 0.5): Eq. 25 kernel build (once per N) and one apply\n")
out.append("| N | Eq. 25 kernel build | Eq. 25 apply | Eq. 26 apply (FFT) | Eq. 25 / Eq. 26 apply |")
out.append("|---:|---:|---:|---:|---:|")
for n in (101, 1001, 2001, 4001):
    b = median("eq25_kernel_build", "build", n)
    d, f = median("graded_displacement_apply", "eq25", n), median("graded_displacement_apply", "eq26_fft", n)
    ratio = f"{d / f:.1f}×" if (d and f) else "—"
    out.append(f"| {n} | {fmt(b)} | {fmt(d)} | {fmt(f)} | {ratio} |")
text = "\n".join(out)
print(text)
if len(sys.argv) > 1:
    pathlib.Path(sys.argv[1]).write_text(text + "\n")
