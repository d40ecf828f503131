"""Wall time of the same CLI runs with a baseline and a candidate binary, interleaved, min of
`repeats` runs each (the `seconds` the --json object reports: setup + solve), and the ratio
candidate / baseline (< 1: the candidate is faster). Run it on a quiet machine.

    python verify/speed_vs_baseline.py BASELINE CANDIDATE [REPEATS] [--composite]

--composite adds a short composite fretting loop (seconds per increment, one run each: ~1-2 min).
"""

import json
import pathlib
import subprocess
import sys
import tempfile

HERTZ = ["contact3d", "--indenter", "sphere:R=105e-6", "--material", "homogeneous:E=210e9,nu=0.3",
         "--force", "0.08", "--tol", "1e-8", "--json"]


def seconds(binary, argv):
    p = subprocess.run([binary, *argv], capture_output=True, text=True, check=True)
    d = json.loads([l for l in p.stdout.splitlines() if l.startswith("{")][-1])
    return d["seconds"], d


def main():
    base, cand = sys.argv[1], sys.argv[2]
    repeats = int(sys.argv[3]) if len(sys.argv) > 3 and sys.argv[3].isdigit() else 3
    for n in (256, 512):
        argv = HERTZ + ["--grid", str(n)]
        tb, tc = [], []
        for _ in range(repeats):
            tb.append(seconds(base, argv)[0])
            tc.append(seconds(cand, argv)[0])
        print(f"contact3d Hertz {n}²: baseline {min(tb):.4f} s, candidate {min(tc):.4f} s, "
              f"ratio {min(tc) / min(tb):.3f}")
    if "--composite" in sys.argv:
        with tempfile.TemporaryDirectory() as tmp:
            cfg = pathlib.Path(tmp) / "c.toml"
            cfg.write_text("normal_steps = 2\namplitude = 0.01e-6\nshift_step = 0.01e-6\n"
                           "subsurface_over_a = 0.0\n")
            per = []
            for b in (base, cand):
                s, d = seconds(b, ["fretting-loop", "--case", "composite", "--config", str(cfg),
                                   "--out", f"{tmp}/out", "--json"])
                per.append(s / d["increments"])
            print(f"composite loop ({d['increments']} increments): baseline {per[0]:.3f} s, "
                  f"candidate {per[1]:.3f} s per increment, ratio {per[1] / per[0]:.3f}")


if __name__ == "__main__":
    main()
