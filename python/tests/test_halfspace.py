"""The Python package against the command line (same library, same numbers bit for bit), its typed
inputs, its errors and its GIL release. Run: verify/.venv/bin/python -m pytest python/tests."""
from __future__ import annotations

import json
import os
import pathlib
import re
import subprocess
import threading

import h5py
import numpy as np
import pytest

import halfspace as hs

ROOT = pathlib.Path(__file__).resolve().parents[2]


def binary() -> str:
    """The CLI built by `cargo test` (debug) or `cargo build --release`."""
    env = os.environ.get("HALFSPACE_BIN")
    if env:
        return env
    for profile in ("release", "debug"):
        path = ROOT / "target" / profile / "halfspace"
        if path.is_file():
            return str(path)
    pytest.skip("no halfspace binary: run cargo build first")


def cli(*args: str) -> dict:
    out = subprocess.run([binary(), *args, "--json"], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def test_axisym_equals_the_cli_bit_for_bit(tmp_path):
    out = tmp_path / "hertz.npz"
    ref = cli("axisym", "--profile", "sphere:R=0.1", "--material", "homogeneous:E=210e9,nu=0.3",
              "--force", "10", "--out", str(out))
    got = hs.axisym(hs.Sphere(R=0.1), hs.Homogeneous(E=210e9, nu=0.3), force=10.0)
    for key in ("contact_radius", "depth", "force", "max_pressure", "mean_pressure"):
        assert getattr(got, key) == ref[key], key
    with np.load(out) as z:
        assert np.array_equal(got.pressure, z["pressure"])
        assert np.array_equal(got.displacement, z["displacement"])
    # The spec string and the typed class are the same input.
    same = hs.axisym("sphere:R=0.1", "homogeneous:E=210e9,nu=0.3", force=10.0)
    assert np.array_equal(same.pressure, got.pressure)
    assert set(got.to_dict()) >= {"contact_radius", "r", "pressure", "displacement"}


def test_fretting_wear_equals_the_cli(tmp_path):
    out = tmp_path / "wear"
    ref = cli("fretting-wear", "--chi", "0.5", "--n", "301", "--dtau", "0.005", "--tau-end", "1.0",
              "--out", str(out))
    got = hs.fretting_wear(chi=0.5, n=301, dtau=0.005, tau_end=1.0)
    for key in ("cycles", "contact_radius_over_a0", "profile_at_a0_over_d", "limit_contact_radius_over_a0"):
        assert getattr(got, key) == ref[key], key
    with h5py.File(out / "results.h5") as f:
        assert np.array_equal(got.contact_radius_history, f["contact_radius_history"][:])
        assert np.array_equal(got.limiting_profile, f["limiting_profile"][:])
    with pytest.raises(hs.HalfspaceError):
        hs.fretting_wear(chi=1.5)


def test_graded_and_mvm_paths():
    fft = hs.axisym(hs.Sphere(R=0.1), hs.Graded(E0=210e9, z0=1e-3, nu=0.3, k=0.5), depth=1e-6, n=401)
    mvm = hs.axisym(hs.Sphere(R=0.1), hs.Graded(E0=210e9, z0=1e-3, nu=0.3, k=0.5), depth=1e-6, n=401,
                    method="mvm")
    assert fft.k == 0.5
    assert abs(fft.force / mvm.force - 1.0) < 1e-6


def test_errors_are_halfspace_errors_with_the_librarys_message():
    with pytest.raises(hs.HalfspaceError, match=r"missing key 'nu'"):
        hs.axisym(hs.Sphere(R=0.1), "homogeneous:E=1e9", force=1.0)
    with pytest.raises(ValueError, match=r"unknown profile 'ellipse'"):
        hs.axisym("ellipse:R=1", hs.Homogeneous(E=1e9, nu=0.3), force=1.0)
    with pytest.raises(hs.HalfspaceError, match=r"exactly one of force= and depth="):
        hs.axisym(hs.Sphere(R=0.1), hs.Homogeneous(E=1e9, nu=0.3))
    with pytest.raises(hs.HalfspaceError, match=r"grading exponent k"):
        hs.axisym(hs.Sphere(R=0.1), hs.Graded(E0=1e9, z0=1.0, nu=0.3, k=1.0), force=1.0)
    with pytest.raises(hs.HalfspaceError, match=r"unknown field `bogus`"):
        hs.FrettingLoop({"bogus": 1})
    with pytest.raises(hs.HalfspaceError, match=r"need all 180 increments, 0 done"):
        hs.FrettingLoop({"grid": 16}).metrics()


SMALL = {"grid": 24, "normal_steps": 3, "shift_step": 0.02e-6, "subsurface_over_a": 0.0}


def toml(cfg: dict) -> str:
    return "\n".join(f"{k} = {v!r}" for k, v in cfg.items()) + "\n"


def test_fretting_loop_equals_the_cli_bit_for_bit(tmp_path):
    (tmp_path / "loop.toml").write_text(toml(SMALL))
    ref = cli("fretting-loop", "--config", str(tmp_path / "loop.toml"), "--out", str(tmp_path / "out"))
    lp = hs.FrettingLoop(SMALL)
    rows = list(lp)  # increment by increment
    assert len(rows) == len(lp) == ref["increments"] == lp.done
    m = lp.metrics()
    assert m.dissipated_energy == ref["dissipated_energy"]
    assert m.ratchet == ref["ratchet"]
    with h5py.File(tmp_path / "out" / "results.h5") as f:
        for name, values in lp.rows().items():
            assert np.array_equal(values, f[name][:]), name
        points = lp.points()
        assert np.array_equal(points["B"]["shear_x"], f["shear_x_B"][:])
        assert points["B"]["pressure"].shape == (24, 24)
    assert rows[-1]["tangential_force"] == lp.rows()["tangential_force"][-1]


def test_fretting_loop_with_an_inhomogeneity_and_typed_inputs():
    a = 3.0111e-6
    sphere = hs.Inhomogeneity.sphere(x=0.0, y=0.0, z=0.6 * a, r=0.3 * a, E=420e9, nu=0.3)
    cfg = dict(SMALL, grid=16, inhomogeneity=[sphere])
    lp = hs.FrettingLoop(cfg).run()
    m = lp.metrics()
    assert m.inclusion_cells > 0 and m.regime in (0, 1, 2)
    assert lp.rows()["outer_iterations"].min() >= 1
    # The same as a TOML-style table.
    table = {"kind": "sphere", "x": 0.0, "y": 0.0, "z": 0.6 * a, "r": 0.3 * a, "e": 420e9, "nu": 0.3}
    again = hs.FrettingLoop(dict(SMALL, grid=16, inhomogeneity=[table])).run()
    assert np.array_equal(again.rows()["tangential_force"], lp.rows()["tangential_force"])


def test_solves_release_the_gil():
    lp = hs.FrettingLoop(dict(SMALL, grid=32, normal_steps=6, shift_step=0.01e-6))
    worker = threading.Thread(target=lp.run)
    count = 0
    worker.start()
    while worker.is_alive():
        count += 1
    worker.join()
    assert lp.done == len(lp)
    # With the GIL held for the whole run this thread would not have run in between.
    assert count > 1000, count


def test_the_worked_examples_of_docs_python_md_run():
    text = (ROOT / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks
    scope: dict = {}
    for block in blocks:
        exec(compile(block, "docs/python.md", "exec"), scope)
