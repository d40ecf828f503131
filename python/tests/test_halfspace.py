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
    # The newest of the two: a release binary left from an older checkout must not stand in for the
    # debug binary that `cargo test` just built.
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    built = [target / profile / "halfspace" for profile in ("release", "debug")]
    built = [path for path in built if path.is_file()]
    if not built:
        pytest.skip("no halfspace binary: run cargo build first")
    return str(max(built, key=lambda path: path.stat().st_mtime))


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
    # One summary (halfspace_cases::records::axisym_summary): the CLI's keys, but its wall clock.
    summary = {k: v for k, v in got.to_dict().items() if not isinstance(v, np.ndarray)}
    assert set(summary) == set(ref) - {"seconds"}
    for key in set(ref) - {"seconds", "profile", "material"}:
        assert summary[key] == ref[key] and type(summary[key]) is type(ref[key]), key


def test_fretting_wear_equals_the_cli(tmp_path):
    out = tmp_path / "wear"
    ref = cli("fretting-wear", "--chi", "0.5", "--n", "301", "--dtau", "0.005", "--tau-end", "1.0",
              "--out", str(out))
    got = hs.fretting_wear(chi=0.5, n=301, dtau=0.005, tau_end=1.0)
    for key in ("steps", "contact_radius_over_a0", "profile_at_a0_over_d", "limit_contact_radius_over_a0"):
        assert getattr(got, key) == ref[key], key
    with h5py.File(out / "results.h5") as f:
        assert np.array_equal(got.contact_radius_history, f["contact_radius_history"][:])
        assert np.array_equal(got.limiting_profile, f["limiting_profile"][:])
    with pytest.raises(hs.HalfspaceError):
        hs.fretting_wear(chi=1.5)
    # The defaults (since stop 45): the piecewise-linear transform with the edge cells.
    assert got.gap_transform == ref["gap_transform"] == "piecewise-linear"
    assert got.edge_cells is True and ref["edge_cells"] is True
    cd = hs.fretting_wear(chi=0.5, n=301, tau_end=0.5, gap_transform="central-differences",
                          edge_cells=False)
    assert cd.gap_transform == "central-differences" and cd.edge_cells is False
    with pytest.raises(TypeError, match="edge_cells"):
        hs.fretting_wear(n=301, tau_end=0.5, edge_cells="yes")
    with pytest.raises(hs.HalfspaceError, match="piecewise-linear"):
        hs.fretting_wear(n=301, tau_end=0.5, gap_transform="linear")


def test_fretting_wear_resumes_a_cli_run_and_refuses_another_schemes(tmp_path):
    """``resume=``: a CLI run stopped after 30 adaptive steps continues in Python to the
    uninterrupted run's result bit for bit; a checkpoint of other parameters, and a run directory
    (run.json) or a checkpoint of another adaptive scheme, are refused with the library's message
    (halfspace_cases::fretting_wear::ResumeError), as the CLI's --resume refuses them."""
    out = tmp_path / "wear"
    args = ("--chi", "0.5", "--n", "401", "--tau-end", "0.5")
    subprocess.run([binary(), "fretting-wear", *args, "--out", str(out), "--stop-after", "30"],
                   check=True, capture_output=True)
    whole = hs.fretting_wear(chi=0.5, n=401, tau_end=0.5)
    resumed = hs.fretting_wear(chi=0.5, n=401, tau_end=0.5, resume=out)
    assert resumed.steps == whole.steps
    assert np.array_equal(resumed.profile, whole.profile)
    assert np.array_equal(resumed.tau_history, whole.tau_history)
    # Other parameters than the checkpoint's.
    with pytest.raises(hs.HalfspaceError, match="the checkpoint was made with chi"):
        hs.fretting_wear(chi=0.4, n=401, tau_end=0.5, resume=out)
    manifest = out / "run.json"
    intact = manifest.read_text()
    for found in (None, "ros2"):
        m = json.loads(intact)
        if found is None:
            del m["parameters"]["adaptive_scheme"]
        else:
            m["parameters"]["adaptive_scheme"] = found
        manifest.write_text(json.dumps(m))
        with pytest.raises(hs.HalfspaceError) as e:
            hs.fretting_wear(chi=0.5, n=401, tau_end=0.5, resume=str(out))
        text = str(e.value)
        assert f"the run in {out} was made by another build's adaptive scheme" in text, text
        assert "cannot resume it bit for bit: only starting the run over helps" in text, text
        assert (found or "not recorded") in text, text
    manifest.write_text(intact)
    # The checkpoint of another scheme (the manifest agreeing): its `metadata` member holds the
    # attributes as JSON bytes.
    checkpoint = out / "checkpoint.npz"
    with np.load(checkpoint) as z:
        arrays = {name: z[name] for name in z.files}
    original = dict(arrays)
    meta = json.loads(bytes(arrays["metadata"]).decode())
    meta["adaptive_scheme"] = "ros2"
    arrays["metadata"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    np.savez(checkpoint, **arrays)
    with pytest.raises(hs.HalfspaceError,
                       match="the checkpoint .* was made by another build's adaptive scheme "
                             r"\(adaptive_scheme = ros2\)"):
        hs.fretting_wear(chi=0.5, n=401, tau_end=0.5, resume=out)
    np.savez(checkpoint, **original)
    assert hs.fretting_wear(chi=0.5, n=401, tau_end=0.5, resume=out).steps == whole.steps
    with pytest.raises(hs.HalfspaceError, match="no checkpoint.npz"):
        hs.fretting_wear(chi=0.5, n=401, tau_end=0.5, resume=tmp_path / "empty")
    with pytest.raises(TypeError, match="resume"):
        hs.fretting_wear(resume=5)  # type: ignore[arg-type]


def test_contact3d_with_an_inhomogeneity_equals_the_cli_bit_for_bit(tmp_path):
    """The stiff sphere of docs/theory-sam.md#inhomogeneity-references below a Hertz contact, coarse, with the subsurface field."""
    out = tmp_path / "c.h5"
    inc = "sphere:x=0,y=0,z=1.50554e-6,r=0.90332e-6,E=420e9,nu=0.3"
    ref = cli("contact3d", "--indenter", "sphere:R=105e-6", "--material", "homogeneous:E=210e9,nu=0.3",
              "--force", "0.08", "--grid", "32", "--inhomogeneity", inc, "--subsurface", "3e-6",
              "--out", str(out))
    got = hs.contact3d(hs.Sphere(R=105e-6), hs.Homogeneous(E=210e9, nu=0.3), force=0.08, grid=32,
                       inhomogeneities=[hs.Inhomogeneity.sphere(x=0, y=0, z=1.50554e-6, r=0.90332e-6,
                                                                E=420e9, nu=0.3)],
                       subsurface=3e-6)
    for key in ("contact_radius", "max_pressure", "force", "depth", "inclusion_cells", "eim_iterations",
                "outer_iterations", "max_von_mises", "max_von_mises_at"):
        assert getattr(got, key) == ref[key], key
    assert got.pressure.shape == (32, 32)
    assert got.von_mises.ndim == 3 and got.von_mises.shape[1:] == (32, 32)
    assert got.eigen_displacement_3.shape == (32, 32)
    with h5py.File(out) as f:
        for name in ("x", "y", "pressure", "stick"):
            assert np.array_equal(getattr(got, name).ravel(), f[name][:]), name
        for name in ("von_mises", "stress_zz", "material", "eigenstrain_zz"):
            assert np.array_equal(getattr(got, name), f[name][:]), name


def test_contact3d_stick_slip_and_errors():
    kw = dict(force=1.0, grid=32, friction=0.3, indenter_material=hs.Homogeneous(E=210e9, nu=0.3))
    got = hs.contact3d(hs.Sphere(R=0.01), hs.Homogeneous(E=210e9, nu=0.3), tangential_force=0.15, **kw)
    assert abs(got.tangential_force / 0.15 - 1.0) < 1e-6
    # Cattaneo–Mindlin: stick radius c = a (1 − Q/μW)^{1/3}, to a cell on this coarse grid.
    c = got.contact_radius * (1.0 - 0.15 / 0.3) ** (1.0 / 3.0)
    assert abs(got.stick_radius - c) < 2.0 * got.extent / 32
    with pytest.raises(hs.HalfspaceError, match=r"at most one of shift_x= and tangential_force="):
        hs.contact3d(hs.Sphere(R=0.01), "homogeneous:E=210e9,nu=0.3", shift_x=1e-7, tangential_force=0.1, **kw)
    with pytest.raises(hs.HalfspaceError, match=r"unknown indenter 'pyramid'"):
        hs.contact3d("pyramid:a=1", "homogeneous:E=210e9,nu=0.3", force=1.0)


def test_a_table_profile_equals_the_sphere_it_samples():
    r = np.linspace(0.0, 2e-3, 4001)
    table = hs.axisym(hs.Table(r, r**2 / 0.2), hs.Homogeneous(E=210e9, nu=0.3), force=10.0)
    sphere = hs.axisym(hs.Sphere(R=0.1), hs.Homogeneous(E=210e9, nu=0.3), force=10.0)
    # Linear interpolation of r²/2R on Δr = 0.5 µm: the radius to 1e-5.
    assert abs(table.contact_radius / sphere.contact_radius - 1.0) < 1e-5
    with pytest.raises(hs.HalfspaceError, match=r"profile table"):
        hs.axisym(hs.Table([0.0, 1.0, 0.5], [0.0, 1.0, 2.0]), hs.Homogeneous(E=1e9, nu=0.3), force=1.0)


def test_graded_fretting_wear_equals_the_cli(tmp_path):
    out = tmp_path / "graded"
    ref = cli("fretting-wear", "--material", "graded:k=0.5,nu=0.3", "--chi", "0.5", "--n", "301",
              "--dtau", "0.005", "--tau-end", "1.0", "--out", str(out))
    got = hs.fretting_wear(chi=0.5, n=301, dtau=0.005, tau_end=1.0, material="graded:k=0.5,nu=0.3")
    typed = hs.fretting_wear(chi=0.5, n=301, dtau=0.005, tau_end=1.0,
                             material=hs.Graded(E0=1e9, z0=1e-3, nu=0.3, k=0.5))
    for key in ("k", "nu", "wear_volume", "limit_wear_volume", "tangential_constant_ratio",
                "u_max_over_mu_d", "contact_radius_over_a0", "limit_contact_radius_over_a0", "length"):
        assert getattr(got, key) == ref[key], key
        assert getattr(typed, key) == ref[key], key
    with h5py.File(out / "results.h5") as f:
        assert np.array_equal(got.contact_radius_history, f["contact_radius_history"][:])
        assert np.array_equal(got.limiting_profile, f["limiting_profile"][:])
    with pytest.raises(hs.HalfspaceError, match=r"nu = 0.7 must be in"):
        hs.fretting_wear(material="graded:k=0.5,nu=0.7")


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
    # Library messages name parameters, not CLI flags (the CLI adds those).
    with pytest.raises(hs.HalfspaceError, match=r"the MVM backend") as info:
        hs.axisym(hs.PowerLaw(c=1.0, n=1.5), hs.Graded(E0=1.0, z0=1.0, nu=0.3, k=0.5), depth=0.01)
    assert "--" not in str(info.value)
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
    table = {"kind": "sphere", "x": 0.0, "y": 0.0, "z": 0.6 * a, "r": 0.3 * a, "E": 420e9, "nu": 0.3}
    again = hs.FrettingLoop(dict(SMALL, grid=16, inhomogeneity=[table])).run()
    assert np.array_equal(again.rows()["tangential_force"], lp.rows()["tangential_force"])


# The small loop of docs/fatigue.md ("On the fretting loop"; tests/cli_fatigue.rs): identical steel
# bodies, approach 0.135 μm (W ≈ 80 mN), amplitude 0.02 μm, the box to depth a.
FATIGUE_LOOP = {"grid": 32, "normal_steps": 4, "amplitude": 0.02e-6, "shift_step": 0.005e-6,
                "subsurface_over_a": 0.0, "indenter_e": 210e9, "indenter_nu": 0.3, "approach": 1.35e-7}
FATIGUE = {"f_minus1": 400e6, "t_minus1": 280e6, "fs_k": 0.5, "yield_stress": 600e6,
           "depth_over_a": 1.0}
INDICES = ("crossland", "dang_van", "swt", "fatemi_socie")


def test_fretting_loop_fatigue_equals_the_cli_bit_for_bit(tmp_path):
    (tmp_path / "loop.toml").write_text(toml(FATIGUE_LOOP) + "[fatigue]\n" + toml(FATIGUE))
    out = tmp_path / "out"
    ref = cli("fretting-loop", "--config", str(tmp_path / "loop.toml"), "--out", str(out))
    lp = hs.FrettingLoop(dict(FATIGUE_LOOP, fatigue=FATIGUE))
    with pytest.raises(hs.HalfspaceError, match="not done"):
        lp.fatigue()
    lp.run()
    # The evaluation releases the GIL: this thread runs meanwhile.
    box: dict = {}
    worker = threading.Thread(target=lambda: box.setdefault("f", lp.fatigue()))
    count = 0
    worker.start()
    while worker.is_alive():
        count += 1
    worker.join()
    assert count > 1000, count
    f = box["f"]
    assert isinstance(f, hs.FatigueResult)
    assert lp.metrics().dissipated_energy == ref["dissipated_energy"]
    for name in INDICES:
        # The CLI's JSON keys and values (one summary, LoopFatigue::summary).
        assert getattr(f, f"{name}_max") == ref[f"{name}_max"], name
        assert getattr(f, f"{name}_max_at") == ref[f"{name}_max_at"], name
        assert ref[f"{name}_max"] > 0, name
    # Every key but the clocks (seconds and the parts' *_seconds).
    assert {k: v for k, v in f.fatigue.items() if not k.endswith("seconds")} == \
        {k: v for k, v in ref["fatigue"].items() if not k.endswith("seconds")}
    with h5py.File(out / "results.h5") as h5:
        # The CLI's results.h5 datasets (one record, LoopFatigue::record), NaN where screened.
        assert np.array_equal(f.z, h5["z"][:])
        assert np.array_equal(f.x, h5["x"][:]) and np.array_equal(f.y, h5["y"][:])
        for name in INDICES:
            field = getattr(f, name)
            assert field.shape == (f.z.size, 32, 32) == h5[name].shape, name
            assert np.array_equal(field, h5[name][:], equal_nan=True), name
    # Each maximum is its field's largest value, at the cell centre it names.
    for name in INDICES:
        field = getattr(f, name)
        k, i, j = np.unravel_index(np.nanargmax(field), field.shape)
        assert field[k, i, j] == getattr(f, f"{name}_max"), name
        assert [f.x[i], f.y[j], f.z[k]] == getattr(f, f"{name}_max_at"), name
    assert lp.fatigue().crossland_max == f.crossland_max  # kept, not evaluated again


def test_fretting_loop_fatigue_with_an_inhomogeneity_and_its_constants_equals_the_cli(tmp_path):
    """A stiff sphere below the contact with its own constants ([fatigue.inhomogeneity], nested
    tables from a dict): the per-material path, against the CLI."""
    a = 3.76e-6
    sphere = {"kind": "sphere", "x": 0.0, "y": 0.0, "z": 0.5 * a, "r": 0.25 * a, "E": 420e9,
              "nu": 0.3}
    own = {"f_minus1": 500e6, "t_minus1": 330e6, "fs_k": 0.6, "yield_stress": 900e6}
    cfg = dict(FATIGUE_LOOP, grid=16, inhomogeneity=[sphere], fatigue=dict(FATIGUE, inhomogeneity=own))
    text = (toml(dict(FATIGUE_LOOP, grid=16)) + "[[inhomogeneity]]\n" + toml(sphere)
            + "[fatigue]\n" + toml(FATIGUE) + "[fatigue.inhomogeneity]\n" + toml(own))
    (tmp_path / "loop.toml").write_text(text)
    ref = cli("fretting-loop", "--config", str(tmp_path / "loop.toml"), "--out", str(tmp_path / "out"))
    f = hs.FrettingLoop(cfg).run().fatigue()
    for name in INDICES:
        assert getattr(f, f"{name}_max") == ref[f"{name}_max"], name
        assert getattr(f, f"{name}_max_at") == ref[f"{name}_max_at"], name
    with h5py.File(tmp_path / "out" / "results.h5") as h5:
        for name in INDICES:
            assert np.array_equal(getattr(f, name), h5[name][:], equal_nan=True), name
    # The constants matter: with every cell evaluated (screen_fraction = 0; at the default 0.5 the
    # screen skips the sphere's cells here, so the evaluated fields coincide), the sphere's own
    # constants give another Crossland field than the matrix's constants everywhere — exactly at
    # the sphere's cells.
    full = dict(FATIGUE, screen_fraction=0.0)
    own_all = hs.FrettingLoop(dict(cfg, fatigue=dict(full, inhomogeneity=own))).run().fatigue()
    plain = hs.FrettingLoop(dict(cfg, fatigue=full)).run().fatigue()
    assert not np.isnan(own_all.crossland).any() and not np.isnan(plain.crossland).any()
    assert not np.array_equal(plain.crossland, own_all.crossland)


def test_an_inhomogeneitys_own_fatigue_table_from_a_dict_equals_the_cli(tmp_path):
    """An inhomogeneity's own ``fatigue`` table (docs/fatigue.md, "Materials") in a config dict:
    the CLI's fields bit for bit; it changes only Crossland and Dang Van (the keys it gives), and
    a bad value is refused naming the entry."""
    a = 3.76e-6
    sphere = {"kind": "sphere", "x": 0.0, "y": 0.0, "z": 0.5 * a, "r": 0.25 * a, "E": 420e9,
              "nu": 0.3}
    own = {"f_minus1": 250e6, "t_minus1": 160e6}
    cfg = dict(FATIGUE_LOOP, grid=16, inhomogeneity=[dict(sphere, fatigue=own)],
               fatigue=dict(FATIGUE, screen_fraction=0.0))
    text = (toml(dict(FATIGUE_LOOP, grid=16)) + "[[inhomogeneity]]\n" + toml(sphere)
            + "fatigue = { f_minus1 = 250e6, t_minus1 = 160e6 }\n"
            + "[fatigue]\n" + toml(dict(FATIGUE, screen_fraction=0.0)))
    (tmp_path / "loop.toml").write_text(text)
    cli("fretting-loop", "--config", str(tmp_path / "loop.toml"), "--out", str(tmp_path / "out"))
    f = hs.FrettingLoop(cfg).run().fatigue()
    with h5py.File(tmp_path / "out" / "results.h5") as h5:
        for name in INDICES:
            assert np.array_equal(getattr(f, name), h5[name][:], equal_nan=True), name
    plain = hs.FrettingLoop(dict(cfg, inhomogeneity=[sphere])).run().fatigue()
    assert not np.array_equal(plain.crossland, f.crossland)
    assert not np.array_equal(plain.dang_van, f.dang_van)
    assert np.array_equal(plain.swt, f.swt) and np.array_equal(plain.fatemi_socie, f.fatemi_socie)
    with pytest.raises(hs.HalfspaceError, match=r"\[\[inhomogeneity\]\] 1 fatigue.*t_minus1"):
        hs.FrettingLoop(dict(cfg, inhomogeneity=[dict(sphere, fatigue={"t_minus1": 500e6})]))


def test_fretting_loop_fatigue_errors_name_the_key():
    with pytest.raises(hs.HalfspaceError, match="bogus"):
        hs.FrettingLoop(dict(FATIGUE_LOOP, fatigue=dict(FATIGUE, bogus=1.0)))
    with pytest.raises(hs.HalfspaceError, match="screen_fraction"):
        hs.FrettingLoop(dict(FATIGUE_LOOP, fatigue=dict(FATIGUE, screen_fraction=2.0)))
    with pytest.raises(TypeError, match="f_minus1"):
        hs.FrettingLoop(dict(FATIGUE_LOOP, fatigue=dict(FATIGUE, f_minus1="high")))
    with pytest.raises(hs.HalfspaceError, match=r"no \[fatigue\]"):
        hs.FrettingLoop(dict(SMALL, grid=16)).run().fatigue()


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


MAP = {"grid": 32, "nu": 0.49, "normal_steps": 10, "shift_step": 0.004e-6, "subsurface_over_a": 0.0}
LOADS, AMPLITUDES = [0.04, 0.08], [0.01e-6, 0.02e-6, 0.04e-6, 0.08e-6]


def test_fretting_map_equals_the_cli_bit_for_bit(tmp_path):
    text = toml(MAP) + f"\n[map]\nloads = {LOADS!r}\namplitudes = {AMPLITUDES!r}\n"
    (tmp_path / "map.toml").write_text(text)
    ref = cli("fretting-map", "--config", str(tmp_path / "map.toml"), "--out", str(tmp_path / "out"))
    got = hs.fretting_map(LOADS, AMPLITUDES, config=MAP)
    assert got.regime.dtype == np.int64 and got.regime.shape == (2, 4)
    assert got.regime.tolist() == ref["regime"]
    with h5py.File(tmp_path / "out" / "results.h5") as f:
        for name in ("regime", "dissipated_energy", "energy_ratio", "sliding_fraction", "ratchet",
                     "tangential_force_over_mu_w_at_amplitude"):
            assert np.array_equal(getattr(got, name), f[name][:]), name
        assert np.array_equal(got.loads, f["loads"][:])
    # Mindlin (ν = 0.49: nearly uncoupled): partial slip below A/K = 1, gross slip above.
    assert got.regime[1].tolist() == [0, 0, 2, 2]


def test_fretting_map_on_a_local_dask_cluster_equals_the_serial_map():
    distributed = pytest.importorskip("distributed")
    serial = hs.fretting_map(LOADS, AMPLITUDES, config=MAP)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        dist = hs.fretting_map(LOADS, AMPLITUDES, config=MAP, client=client)
        with pytest.raises(hs.HalfspaceError, match=r"every value must be finite and > 0"):
            hs.fretting_map([0.08, -1.0], AMPLITUDES, config=MAP, client=client)
    for name in ("regime", "dissipated_energy", "energy_ratio", "sliding_fraction", "ratchet",
                 "tangential_force_over_mu_w_at_amplitude", "loads", "amplitudes"):
        assert np.array_equal(getattr(dist, name), getattr(serial, name)), name
    assert dist.regime.dtype == serial.regime.dtype


def test_a_crack_wear_map_equals_the_cli_bit_for_bit(tmp_path):
    """A ``fatigue`` dict in a map's config: each point's ``crack_risk`` (max of its loop's Crossland
    and Dang Van maxima) as ``halfspace fretting-map`` writes it, on the local cores and through the
    per-point task of a distributed map (tests/cli_fretting_map.rs's map)."""
    cfg = {"grid": 16, "normal_steps": 4, "shift_step": 0.01e-6, "subsurface_over_a": 0.0}
    loads, amplitudes = [0.04, 0.08], [0.01e-6, 0.08e-6]
    text = (toml(cfg) + f"\n[map]\nloads = {loads!r}\namplitudes = {amplitudes!r}\n"
            + "[fatigue]\n" + toml(FATIGUE))
    (tmp_path / "map.toml").write_text(text)
    ref = cli("fretting-map", "--config", str(tmp_path / "map.toml"), "--out", str(tmp_path / "out"))
    got = hs.fretting_map(loads, amplitudes, config=dict(cfg, fatigue=FATIGUE))
    with h5py.File(tmp_path / "out" / "results.h5") as f:
        assert np.array_equal(got.crack_risk, f["crack_risk"][:])
        assert np.array_equal(got.dissipated_energy, f["dissipated_energy"][:])
    assert np.all(np.isfinite(got.crack_risk)) and np.all(got.crack_risk > 0)
    assert ref["crack_risk_threshold"] == 1.0
    fields = list(hs._MAP_FIELDS)
    point = hs._map_point(dict(cfg, fatigue=FATIGUE), "homogeneous", None, loads, amplitudes, 1, 0)
    assert point[fields.index("crack_risk")] == got.crack_risk[1, 0]
    # Without the table the risk is NaN, as before.
    plain = hs.fretting_map(loads[:1], amplitudes[:1], config=cfg)
    assert np.isnan(plain.crack_risk).all()


def test_fretting_map_errors():
    with pytest.raises(hs.HalfspaceError, match=r"at least one of its amplitudes"):
        hs.fretting_map([0.08], [], config=MAP)
    with pytest.raises(hs.HalfspaceError, match=r"unknown field `gird`"):
        hs.fretting_map([0.08], [1e-8], config={"gird": 32})


@pytest.mark.parametrize("example", sorted(p.name for p in (ROOT / "examples").glob("*.py")))
def test_the_examples_run(example):
    """Every script under examples/ runs to the end (each asserts its own numbers)."""
    import sys

    out = subprocess.run([sys.executable, str(ROOT / "examples" / example)], capture_output=True,
                         text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]


# The MDR twin of tests/cli_fretting_wear3d.rs (16², N = 1000 cycles).
TWIN3D = {"radius": 105e-6, "e": 210e9, "nu": 0.0, "friction": 0.3, "normal_steps": 1,
          "amplitude": 1.5e-8, "shift_step": 1.5e-8, "grid": 16, "extent_over_a": 3.2,
          "approach": 1e-7, "indenter_e": 210e9, "indenter_nu": 0.0,
          "wear": {"law": "archard", "coefficient": 1.5430335e-12, "body": "gap", "cycles": 1000,
                   "record_cycles": [100]}}


def test_fretting_wear3d_equals_the_cli_bit_for_bit(tmp_path):
    text = toml({k: v for k, v in TWIN3D.items() if k != "wear"}) + "[wear]\n" + toml(TWIN3D["wear"])
    (tmp_path / "wear.toml").write_text(text.replace("'", '"'))
    ref = cli("fretting-wear3d", "--config", str(tmp_path / "wear.toml"), "--out", str(tmp_path / "out"))
    w = hs.fretting_wear3d(TWIN3D)
    assert isinstance(w, hs.Wear3dResult)
    for key in ("cycles", "wear_steps", "wear_volume", "max_wear_depth", "contact_radius",
                "stick_radius", "dissipated_energy_total"):
        assert getattr(w, key) == ref[key], key
        assert type(getattr(w, key)) is type(ref[key]), key
    assert w.cycles == 1000 and w.wear_volume > 0.0
    assert w.seconds > 0.0 and w.seconds_per_computed_cycle > 0.0
    with h5py.File(tmp_path / "out" / "results.h5") as f:
        assert w.wear_depth.shape == (16, 16)
        assert np.array_equal(w.wear_depth, f["wear_depth"][:])
        assert np.array_equal(w.x, f["x"][:]) and np.array_equal(w.y, f["y"][:])
        for name in ("cycles", "delta_cycles", "wear_volume", "max_wear_depth", "contact_radius",
                     "stick_radius", "dissipated_energy", "dissipated_energy_total",
                     "max_slip_path", "max_rate"):
            assert np.array_equal(getattr(w, f"{name}_history"), f[name][:]), name
    assert len(w.cycles_history) == w.wear_steps and w.cycles_history[-1] == 1000
    # The grid override is the CLI's --grid.
    assert hs.fretting_wear3d(TWIN3D, grid=8).wear_depth.shape == (8, 8)


def test_fretting_wear3d_estimate_equals_the_cli_and_runs_nothing(tmp_path):
    text = toml({k: v for k, v in TWIN3D.items() if k != "wear"}) + "[wear]\n" + toml(TWIN3D["wear"])
    (tmp_path / "wear.toml").write_text(text.replace("'", '"'))
    out = tmp_path / "out"
    ref = cli("fretting-wear3d", "--config", str(tmp_path / "wear.toml"), "--out", str(out),
              "--estimate")
    e = hs.fretting_wear3d_estimate(TWIN3D)
    assert isinstance(e, hs.Wear3dEstimate)
    assert not out.exists() and sorted(tmp_path.iterdir()) == [tmp_path / "wear.toml"]
    # The same keys, values and types as the CLI's JSON (one summary,
    # halfspace_cases::records::wear3d_estimate_summary).
    assert e.to_dict() == ref
    for key, value in ref.items():
        assert type(getattr(e, key)) is type(value), key
    # The hand calculation of tests/cli_fretting_wear3d.rs (docs/wear3d.md#the-work-estimate):
    # p0 = 2E*a/(πR) = 2.062 GPa, k p0 4A = 1.909e-10 m per cycle, ΔN1 = ⌊0.01 · 0.1 μm /
    # 1.909e-10 m⌋ = 5, 1 + ⌈100/5⌉ + ⌈900/5⌉ = 201 steps, n + q + 201 · 4q = 806 increments.
    assert e.cycles == 1000 and e.first_delta_cycles == 5.0
    assert e.wear_steps == e.computed_cycles == 201.0
    assert e.increments_per_cycle == 4.0 and e.increments == 806.0 and e.cells == 256.0
    assert e.bytes > 0.0 and e.hours > 0.0
    # The grid override is the CLI's --grid; a refused config is refused as by fretting_wear3d.
    assert hs.fretting_wear3d_estimate(TWIN3D, grid=8).cells == 64.0
    with pytest.raises(hs.HalfspaceError, match=re.escape("wear law")):
        hs.fretting_wear3d_estimate(dict(TWIN3D, wear=dict(TWIN3D["wear"], law="hard")))
    with pytest.raises(hs.HalfspaceError, match="eim_change_factor"):
        hs.fretting_wear3d_estimate(dict(TWIN3D, eim_change_factor=0.5))
    # The alternation scheme: another value is refused naming both; the twin's identical bodies
    # do not alternate, so the key would be ignored there and is refused too.
    with pytest.raises(hs.HalfspaceError, match=re.escape('alternation = "fast": "plain" or "gauged"')):
        hs.fretting_wear3d_estimate(dict(TWIN3D, alternation="fast"))
    with pytest.raises(hs.HalfspaceError, match="read only by a coupled pair"):
        hs.fretting_wear3d_estimate(dict(TWIN3D, alternation="gauged"))
    with pytest.raises(TypeError, match="dict of the fretting-wear3d keys"):
        hs.fretting_wear3d_estimate("wear.toml")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="grid"):
        hs.fretting_wear3d_estimate(TWIN3D, grid=2.5)  # type: ignore[arg-type]


def test_fretting_wear3d_errors_name_the_key():
    def wear(**changes: object) -> dict:
        return dict(TWIN3D, wear=dict(TWIN3D["wear"], **changes))

    for cfg, kind, needle in [
        ({k: v for k, v in TWIN3D.items() if k != "wear"}, hs.HalfspaceError, "[wear] table is required"),
        (wear(law="hard"), hs.HalfspaceError, "wear law"),
        (wear(cycles=0), hs.HalfspaceError, "cycles"),
        (wear(coefficient=-1.0), hs.HalfspaceError, "coefficient"),
        (wear(body="both"), hs.HalfspaceError, "wear body"),
        (wear(colour=1), hs.HalfspaceError, "colour"),
        (wear(cycles="many"), TypeError, "cycles"),
        (dict(TWIN3D, approach="x"), TypeError, "approach"),
        (dict(TWIN3D, colour=1), hs.HalfspaceError, "colour"),
        (dict(TWIN3D, force=0.08), hs.HalfspaceError, "exactly one of force"),
        (dict(TWIN3D, wear=3), TypeError, "wear"),
        (dict(TWIN3D, fatigue={"f_minus1": 1.0, "t_minus1": 1.0, "fs_k": 1.0, "yield_stress": 1.0}),
         hs.HalfspaceError, "[fatigue]"),
    ]:
        with pytest.raises(kind, match=re.escape(needle)):
            hs.fretting_wear3d(cfg)
    with pytest.raises(TypeError, match="dict of the fretting-wear3d keys"):
        hs.fretting_wear3d("wear.toml")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="grid"):
        hs.fretting_wear3d(TWIN3D, grid=2.5)  # type: ignore[arg-type]
