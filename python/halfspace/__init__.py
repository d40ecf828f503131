"""halfspace: contact mechanics of elastic half-spaces, from Python.

The library is Rust (``halfspace._halfspace``, built by maturin); this module adds the typed input
classes and the result objects. Every input class is also accepted as the command line's
``kind:key=value`` string (``Sphere(R=1e-4)`` is ``"sphere:R=0.0001"``), and both go through the
library's one parser, so a string that the CLI refuses is refused here with the same message
(as :class:`HalfspaceError`, a ``ValueError``). Solves release the GIL.

References: Willert, Li & Popov (2021) for the MDR (``axisym``); Leroux & Nélias (2011) for the
fretting loop with inhomogeneities (``FrettingLoop``); the equations are cited in the docstrings.
"""
from __future__ import annotations

import numbers
import os
from dataclasses import dataclass, fields
from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._halfspace import MAP_FIELDS as _MAP_FIELDS
from ._halfspace import HalfspaceError, _FrettingLoop
from ._halfspace import axisym as _axisym
from ._halfspace import contact3d as _contact3d
from ._halfspace import fretting_map as _fretting_map
from ._halfspace import fretting_map_point as _fretting_map_point
from ._halfspace import fretting_map_shape as _fretting_map_shape
from ._halfspace import fretting_wear as _fretting_wear
from ._halfspace import fretting_wear3d as _fretting_wear3d
from ._halfspace import fretting_wear3d_estimate as _fretting_wear3d_estimate

__all__ = [
    "HalfspaceError",
    "Sphere",
    "Ellipsoid",
    "Cone",
    "Flat",
    "PowerLaw",
    "Table",
    "Homogeneous",
    "Graded",
    "Inhomogeneity",
    "Result",
    "AxisymResult",
    "Contact3dResult",
    "WearResult",
    "Wear3dResult",
    "Wear3dEstimate",
    "LoopMetrics",
    "FatigueResult",
    "MapResult",
    "axisym",
    "contact3d",
    "fretting_wear",
    "fretting_wear3d",
    "fretting_wear3d_estimate",
    "FrettingLoop",
    "fretting_map",
]


def _real(v: Any, name: str) -> float:
    """``v`` as a float, or TypeError naming the argument (a string, None, a bool, an array are not
    real numbers here); the library checks the range."""
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"{name} must be a real number, got {v!r} ({type(v).__name__})")
    try:
        return float(v)
    except (OverflowError, ValueError) as e:
        raise HalfspaceError(f"{name} = {v!r}: {e}") from None


def _opt_real(v: Any, name: str) -> float | None:
    return None if v is None else _real(v, name)


def _count(v: Any, name: str, minimum: int = 0) -> int:
    """``v`` as an integer ≥ ``minimum`` that the library can hold (< 2**63), or TypeError /
    HalfspaceError naming the argument."""
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (numbers.Integral, np.integer)):
        raise TypeError(f"{name} must be an integer, got {v!r} ({type(v).__name__})")
    count = int(v)
    if count < minimum or count >= 2**63:
        raise HalfspaceError(f"{name} must be an integer ≥ {minimum} (and < 2**63), got {count}")
    return count


def _opt_count(v: Any, name: str, minimum: int = 0) -> int | None:
    return None if v is None else _count(v, name, minimum)


def _text(v: Any, name: str) -> str:
    if not isinstance(v, str):
        raise TypeError(f"{name} must be a string, got {v!r} ({type(v).__name__})")
    return v


def _flag(v: Any, name: str) -> bool:
    if not isinstance(v, (bool, np.bool_)):
        raise TypeError(f"{name} must be True or False, got {v!r} ({type(v).__name__})")
    return bool(v)


def _path(v: Any, name: str) -> str | os.PathLike[str]:
    if not isinstance(v, (str, os.PathLike)):
        raise TypeError(f"{name} must be a path, got {v!r} ({type(v).__name__})")
    return v


def _num(v: Any, name: str = "value") -> str:
    return repr(_real(v, name))


class _Checked:
    """Dataclass inputs: every field a real number (``None`` where optional), checked at
    construction so that the error names the class and the argument."""

    _optional: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        for f in fields(self):  # type: ignore[arg-type]
            value = getattr(self, f.name)
            if value is None and f.name in self._optional:
                continue
            _real(value, f"{type(self).__name__}: {f.name}")


@dataclass(frozen=True)
class Sphere(_Checked):
    """Paraboloid ``f(r) = r² / (2R)`` (m)."""

    R: float

    def spec(self) -> str:
        return f"sphere:R={_num(self.R, 'R')}"


@dataclass(frozen=True)
class Ellipsoid(_Checked):
    """3D indenter ``h(x, y) = x² / (2Rx) + y² / (2Ry)`` (m) (``contact3d`` only)."""

    Rx: float
    Ry: float

    def spec(self) -> str:
        return f"ellipsoid:Rx={_num(self.Rx, 'Rx')},Ry={_num(self.Ry, 'Ry')}"


@dataclass(frozen=True)
class Cone(_Checked):
    """Cone ``f(r) = slope · r``."""

    slope: float

    def spec(self) -> str:
        return f"cone:slope={_num(self.slope, 'slope')}"


@dataclass(frozen=True)
class Flat(_Checked):
    """Flat punch of radius ``a`` (m)."""

    a: float

    def spec(self) -> str:
        return f"flat:a={_num(self.a, 'a')}"


@dataclass(frozen=True)
class PowerLaw(_Checked):
    """Power-law profile ``f(r) = c rⁿ``."""

    c: float
    n: float

    def spec(self) -> str:
        return f"power:c={_num(self.c, 'c')},n={_num(self.n, 'n')}"


def _array(v: Any, name: str) -> NDArray[np.float64]:
    """``v`` as a 1D float array, or TypeError naming the argument."""
    if isinstance(v, (str, bytes)) or v is None:
        raise TypeError(f"{name} must be an array of real numbers, got {v!r}")
    try:
        a = np.asarray(v)
        if a.dtype.kind not in "fiu":
            raise TypeError
        return np.ascontiguousarray(a, dtype=float).ravel()
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be an array of real numbers, got {v!r}") from None


class Table:
    """A tabulated axisymmetric profile ``f(r)``: nodes ``r`` (m, increasing from 0) and heights
    ``f`` (m), interpolated linearly (``axisym`` only; the CLI's ``table:FILE.npy`` without the
    file)."""

    def __init__(self, r: Any, f: Any) -> None:
        self.r = _array(r, "Table: r")
        self.f = _array(f, "Table: f")
        if self.r.size != self.f.size:
            raise HalfspaceError(
                f"Table: r and f must have the same length, got {self.r.size} and {self.f.size}"
            )

    def __repr__(self) -> str:
        return f"Table(<{self.r.size} nodes>)"


@dataclass(frozen=True)
class Homogeneous(_Checked):
    """Homogeneous elastic half-space: ``E`` (Pa) and ``nu``, or the contact modulus ``Estar``
    (not both: as the CLI, a spec with both is refused rather than one silently dropped)."""

    E: float | None = None
    nu: float | None = None
    Estar: float | None = None

    _optional = ("E", "nu", "Estar")

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.Estar is not None and (self.E is not None or self.nu is not None):
            raise HalfspaceError(
                "Homogeneous: give E and nu, or Estar, not both (Estar = E/(1 − nu²) would "
                "override them)"
            )

    def spec(self) -> str:
        """The keys given, as the ``kind:key=value`` spec the library reads (``axisym`` needs E
        and nu or Estar; ``fretting_wear`` reads nu alone)."""
        if self.Estar is not None:
            return f"homogeneous:Estar={_num(self.Estar, 'Estar')}"
        if self.E is None and self.nu is None:
            return "homogeneous"
        keys = [f"{k}={_num(v, k)}" for k, v in (("E", self.E), ("nu", self.nu)) if v is not None]
        return "homogeneous:" + ",".join(keys)


@dataclass(frozen=True)
class Graded(_Checked):
    """Power-law graded half-space ``E(z) = E0 (z / z0)^k`` (Willert et al. 2021, Section 3)."""

    E0: float
    z0: float
    nu: float
    k: float

    def spec(self) -> str:
        return (
            f"graded:E0={_num(self.E0, 'E0')},z0={_num(self.z0, 'z0')},nu={_num(self.nu, 'nu')},k={_num(self.k, 'k')}"
        )


class Inhomogeneity:
    """An inhomogeneity below the surface, as the CLI's ``--inhomogeneity`` spec (``z`` is the depth
    of the centre, positive into the body; SI units)."""

    def __init__(self, spec: str) -> None:
        self._spec = _text(spec, "Inhomogeneity: spec")

    def spec(self) -> str:
        return self._spec

    def __repr__(self) -> str:
        return f"Inhomogeneity({self._spec!r})"

    @classmethod
    def sphere(cls, *, x: float, y: float, z: float, r: float, E: float, nu: float) -> "Inhomogeneity":
        return cls(f"sphere:x={_num(x, 'x')},y={_num(y, 'y')},z={_num(z, 'z')},r={_num(r, 'r')},"
                   f"E={_num(E, 'E')},nu={_num(nu, 'nu')}")

    @classmethod
    def cylinder(
        cls, *, axis: str, z: float, r: float, E: float, nu: float, x: float | None = None, y: float | None = None
    ) -> "Inhomogeneity":
        _text(axis, "axis")
        if axis == "y":
            pos = f"x={_num(x, 'x')}"
        elif axis == "x":
            pos = f"y={_num(y, 'y')}"
        else:
            raise HalfspaceError(f"Inhomogeneity.cylinder: axis must be 'x' or 'y', got {axis!r}")
        return cls(f"cylinder:axis={axis},{pos},z={_num(z, 'z')},r={_num(r, 'r')},E={_num(E, 'E')},"
                   f"nu={_num(nu, 'nu')}")

    @classmethod
    def cuboid(
        cls, *, x: float, y: float, z: float, hx: float, hy: float, hz: float, E: float, nu: float
    ) -> "Inhomogeneity":
        return cls(
            f"cuboid:x={_num(x, 'x')},y={_num(y, 'y')},z={_num(z, 'z')},hx={_num(hx, 'hx')},"
            f"hy={_num(hy, 'hy')},hz={_num(hz, 'hz')},E={_num(E, 'E')},nu={_num(nu, 'nu')}"
        )


def _spec(value: Any, name: str = "input") -> str:
    if isinstance(value, str):
        return value
    if hasattr(value, "spec"):
        return str(value.spec())
    raise TypeError(
        f"{name} must be a spec string or a halfspace input class, got {value!r} "
        f"({type(value).__name__})"
    )


class Result:
    """A result: its attributes are the CLI's JSON keys (floats, ints, strings) and NumPy arrays.
    Each function returns its own subclass, which declares them (the summaries of
    ``halfspace_cases::records``); keys that a run may omit default to ``None``."""

    def __init__(self, values: dict[str, Any]) -> None:
        self.__dict__.update(values)

    def to_dict(self) -> dict[str, Any]:
        return dict(self.__dict__)

    def __repr__(self) -> str:
        scalars = {k: v for k, v in self.__dict__.items() if not isinstance(v, np.ndarray)}
        return f"{type(self).__name__}({scalars})"


class AxisymResult(Result):
    """:func:`axisym`: the keys of ``halfspace axisym --json`` and the arrays ``r``, ``pressure``,
    ``displacement`` (m, Pa, m)."""

    contact_radius: float
    depth: float
    force: float
    max_pressure: float
    mean_pressure: float
    pressure_singular: bool
    n: int
    method: str
    displacement_method: str
    k: float
    contact_modulus: float
    c_n: float
    normal_stiffness: float
    grid_length: float
    edge_index: int
    iterations: int
    profile: str
    material: str
    r: NDArray[np.float64]
    pressure: NDArray[np.float64]
    displacement: NDArray[np.float64]


class Contact3dResult(Result):
    """:func:`contact3d`: the keys of ``halfspace contact3d --json`` and the arrays of its
    ``--out`` (surface fields shaped (N₁, N₂); with ``subsurface`` the volume fields shaped
    (layers, N₁, N₂), read by ``to_dict()`` or attribute)."""

    contact_radius: float
    contact_area: float
    max_pressure: float
    force: float
    depth: float
    tangential_force: float
    tangential_force_y: float
    shift_x: float
    stick_radius: float
    iterations: int
    alternations: int
    residual: float
    kkt: float
    grid: int
    extent: float
    coupled: bool
    seconds: float
    setup_seconds: float
    solve_seconds: float
    friction: float
    inclusion_cells: int | None = None
    layers: int | None = None
    eim_iterations: int | None = None
    outer_iterations: int | None = None
    outer_change: float | None = None
    min_eigen_displacement: float | None = None
    correction_pressure_integral_over_force: float | None = None
    eim_method: str | None = None
    eim_spectra_bytes: int | None = None
    max_von_mises: float | None = None
    max_von_mises_at: list[float] | None = None
    max_tresca: float | None = None
    max_tresca_at: list[float] | None = None
    subsurface_layers: int | None = None
    subsurface_seconds: float | None = None
    x: NDArray[np.float64]
    y: NDArray[np.float64]
    pressure: NDArray[np.float64]
    shear_x: NDArray[np.float64]
    shear_y: NDArray[np.float64]
    slip_x: NDArray[np.float64]
    slip_y: NDArray[np.float64]
    stick: NDArray[np.float64]
    # With inhomogeneities: the eigen-displacements (N₁, N₂); with ``subsurface``: the volume
    # fields (layers, N₁, N₂) — ``contact3d --out``'s arrays.
    eigen_displacement_1: NDArray[np.float64] | None = None
    eigen_displacement_2: NDArray[np.float64] | None = None
    eigen_displacement_3: NDArray[np.float64] | None = None
    stress_xx: NDArray[np.float64] | None = None
    stress_yy: NDArray[np.float64] | None = None
    stress_zz: NDArray[np.float64] | None = None
    stress_yz: NDArray[np.float64] | None = None
    stress_xz: NDArray[np.float64] | None = None
    stress_xy: NDArray[np.float64] | None = None
    von_mises: NDArray[np.float64] | None = None
    tresca: NDArray[np.float64] | None = None
    principal_1: NDArray[np.float64] | None = None
    principal_2: NDArray[np.float64] | None = None
    principal_3: NDArray[np.float64] | None = None
    material: NDArray[np.float64] | None = None
    eigenstrain_xx: NDArray[np.float64] | None = None
    eigenstrain_yy: NDArray[np.float64] | None = None
    eigenstrain_zz: NDArray[np.float64] | None = None
    eigenstrain_yz: NDArray[np.float64] | None = None
    eigenstrain_xz: NDArray[np.float64] | None = None
    eigenstrain_xy: NDArray[np.float64] | None = None


class WearResult(Result):
    """:func:`fretting_wear`: the keys of ``halfspace fretting-wear --json`` and its arrays."""

    tau_final: float
    steps: int
    rejected_steps: int
    stepping: str
    contact_radius_over_a0: float
    loaded_radius_over_a0: float
    max_contact_radius_over_a0: float
    contact_radius_definition: str
    profile_at_a0_over_d: float
    limit_contact_radius_over_a0: float
    method: str
    gap_transform: str
    edge_cells: bool
    n: int
    chi: float
    length: float
    k: float
    wear_volume: float
    limit_wear_volume: float
    limit_deviation: float
    limit_deviation_definition: str
    wear_volume_definition: str
    tol: float | None = None
    adaptive_scheme: str | None = None
    edge_cell_rule: str | None = None
    dtau: float | None = None
    nu: float | None = None
    tangential_constant_ratio: float | None = None
    u_max_over_mu_d: float | None = None
    r: NDArray[np.float64]
    profile: NDArray[np.float64]
    limiting_profile: NDArray[np.float64]
    tau_history: NDArray[np.float64]
    contact_radius_history: NDArray[np.float64]
    loaded_radius_history: NDArray[np.float64]


class Wear3dResult(Result):
    """:func:`fretting_wear3d`: the keys of ``halfspace fretting-wear3d --json`` (without ``out``),
    ``x``, ``y`` (cell centres, m), ``wear_depth`` (N₁, N₂; m) and the history per wear step,
    ``{field}_history`` — the datasets of its results.h5 (``cycles``, ``wear_volume``, …)."""

    cycles: int
    wear_steps: int
    wear_volume: float
    # Of the last wear step (``None`` only for a run without one).
    max_wear_depth: float | None
    contact_radius: float | None
    stick_radius: float | None
    dissipated_energy_total: float | None
    seconds: float
    seconds_per_computed_cycle: float
    # With inhomogeneities: the contact ↔ EIM outer passes and EIM applications of the computed
    # cycles (0 without).
    outer_passes: int
    eim_applications: int
    x: NDArray[np.float64]
    y: NDArray[np.float64]
    wear_depth: NDArray[np.float64]
    cycles_history: NDArray[np.float64]
    delta_cycles_history: NDArray[np.float64]
    wear_volume_history: NDArray[np.float64]
    max_wear_depth_history: NDArray[np.float64]
    contact_radius_history: NDArray[np.float64]
    stick_radius_history: NDArray[np.float64]
    dissipated_energy_history: NDArray[np.float64]
    dissipated_energy_total_history: NDArray[np.float64]
    max_slip_path_history: NDArray[np.float64]
    max_rate_history: NDArray[np.float64]


class Wear3dEstimate(Result):
    """:func:`fretting_wear3d_estimate`: the keys of ``halfspace fretting-wear3d --estimate --json``
    (docs/wear3d.md, "The work estimate"): ``cycles`` asked; ``wear_steps`` (= ``computed_cycles``,
    the final state's cycle included) and ``first_delta_cycles`` ``ΔN₁``, the cycles one computed
    cycle stands for at the first wear step (every step is given it, so the count errs towards more
    steps for a homogeneous pair); ``increments_per_cycle`` ``4q`` and ``increments`` of the whole
    run (the loading ``n + q`` and ``wear_steps · 4q``); ``cells`` of the surface grid; ``bytes``
    the peak memory; ``hours`` of work on this machine's cores."""

    cycles: int
    wear_steps: float
    computed_cycles: float
    first_delta_cycles: float
    increments_per_cycle: float
    increments: float
    cells: float
    bytes: float
    hours: float


class LoopMetrics(Result):
    """:meth:`FrettingLoop.metrics`: the metrics of a completed loop (the keys of
    ``halfspace fretting-loop --json`` without its times)."""

    dissipated_energy: float
    ratchet: float
    tangential_force_over_mu_w_at_amplitude: float
    max_pressure_over_p0_end_of_normal_loading: float
    contact_area_over_hertz_end_of_normal_loading: float
    approach_over_hertz_end_of_normal_loading: float
    max_transverse_slip: float
    sliding_fraction: float
    regime: int
    energy_ratio: float
    unloading_stiffness: float
    increments: int
    grid: int
    inclusion_cells: int | None = None
    layers: int | None = None


class FatigueResult(Result):
    """:meth:`FrettingLoop.fatigue`: the fatigue indices of the loop's closed cycle (docs/fatigue.md,
    "On the fretting loop") — the keys that a ``[fatigue]`` table adds to ``halfspace fretting-loop
    --json`` (the same summary, ``halfspace_cases::loop_fatigue::LoopFatigue::summary``) and the
    datasets it adds to results.h5 (the same record). ``*_max`` is the largest index over the box
    (Crossland, Dang Van: dimensionless; SWT: Pa; Fatemi–Socie: dimensionless), ``None`` if not
    finite; ``*_max_at`` its cell centre ``[x, y, z]`` (m, z the depth). ``fatigue``: the
    evaluation's counts and seconds (``cells``, ``layers``, ``increments``,
    ``surface_layer``, ``levels_computed``, ``invariant_evaluated``, ``swt_evaluated``,
    ``fatemi_socie_evaluated``, ``seconds`` and its parts ``level_bounds_seconds``,
    ``history_seconds``, ``criteria_seconds``)."""

    crossland_max: float | None
    crossland_max_at: list[float]
    dang_van_max: float | None
    dang_van_max_at: list[float]
    swt_max: float | None
    swt_max_at: list[float]
    fatemi_socie_max: float | None
    fatemi_socie_max_at: list[float]
    fatigue: dict[str, Any]
    #: Cell centres (m): ``x`` (N₁), ``y`` (N₂), ``z`` (layers, the depth of each layer;
    #: ``z[0] = 0`` is the surface layer, docs/fatigue.md, "The surface layer").
    x: NDArray[np.float64]
    y: NDArray[np.float64]
    z: NDArray[np.float64]
    #: The index fields shaped (layers, N₁, N₂); SWT and Fatemi–Socie are NaN where the screen
    #: (``screen_fraction``) skipped the cell, all four on the levels it cannot reach
    #: (docs/fatigue.md, "Layers the screen cannot reach").
    crossland: NDArray[np.float64]
    dang_van: NDArray[np.float64]
    swt: NDArray[np.float64]
    fatemi_socie: NDArray[np.float64]
    #: With ``process_volume`` (m) in the fatigue dict (docs/fatigue.md, "Process volume"): the
    #: maxima of the four indices on the stress history averaged over a cube of that side, the
    #: centres ``[x, y, z]`` (m) of their cubes, the ``process_volume`` block (``side``,
    #: ``cells_inside``, counts, ``seconds``) and the fields ``crossland_pv``, … (layers, N₁, N₂;
    #: NaN where the cube leaves the box or the screen skipped the cell); ``None`` without it.
    crossland_pv_max: float | None = None
    crossland_pv_max_at: list[float] | None = None
    dang_van_pv_max: float | None = None
    dang_van_pv_max_at: list[float] | None = None
    swt_pv_max: float | None = None
    swt_pv_max_at: list[float] | None = None
    fatemi_socie_pv_max: float | None = None
    fatemi_socie_pv_max_at: list[float] | None = None
    process_volume: dict[str, Any] | None = None
    crossland_pv: NDArray[np.float64] | None = None
    dang_van_pv: NDArray[np.float64] | None = None
    swt_pv: NDArray[np.float64] | None = None
    fatemi_socie_pv: NDArray[np.float64] | None = None


class MapResult(Result):
    """:func:`fretting_map`: ``loads``, ``amplitudes`` and the fields shaped (len(loads),
    len(amplitudes))."""

    loads: NDArray[np.float64]
    amplitudes: NDArray[np.float64]
    regime: NDArray[np.int64]
    dissipated_energy: NDArray[np.float64]
    energy_ratio: NDArray[np.float64]
    sliding_fraction: NDArray[np.float64]
    tangential_force_over_mu_w_at_amplitude: NDArray[np.float64]
    ratchet: NDArray[np.float64]
    seconds: NDArray[np.float64]
    #: With a ``fatigue`` dict in the config: each point's largest of its loop's Crossland and
    #: Dang Van maxima (docs/fatigue.md, "Crack–wear fretting maps"); NaN without one.
    crack_risk: NDArray[np.float64]


def axisym(
    profile: Sphere | Cone | Flat | PowerLaw | Table | str,
    material: Homogeneous | Graded | str,
    *,
    force: float | None = None,
    depth: float | None = None,
    n: int = 2001,
    method: str = "fft",
) -> AxisymResult:
    """Axisymmetric normal contact by the MDR: the profile transform (Willert et al. 2021, Eq. 7;
    graded Eq. 23), the contact radius from the force or the depth, the pressure (Eq. 17; graded
    Eq. 29) and the surface displacement (Eqs. 12/13; graded 25/26) on ``n`` nodes, by FFT
    convolution (``method="fft"``) or the O(N²) products (``"mvm"``). As ``halfspace axisym``."""
    # The keys of `halfspace axisym --config`: the library reads and checks them (one case, as
    # the CLI); a profile object or a material goes as its spec, a Table as its arrays.
    config = {"profile": ({"r": profile.r.tolist(), "f": profile.f.tolist()}
                          if isinstance(profile, Table) else _spec(profile, "profile")),
              "material": _spec(material, "material"),
              "force": _opt_real(force, "force"), "depth": _opt_real(depth, "depth"),
              "n": _count(n, "n"), "method": _text(method, "method")}
    values = _axisym(config)
    return AxisymResult(values)


def contact3d(
    indenter: Sphere | Ellipsoid | Cone | Flat | str,
    material: Homogeneous | str,
    *,
    force: float | None = None,
    depth: float | None = None,
    indenter_material: Homogeneous | str = "rigid",
    shift_x: float | None = None,
    tangential_force: float | None = None,
    friction: float = 0.0,
    grid: int = 128,
    extent: float | None = None,
    tol: float = 1e-10,
    inhomogeneities: Inhomogeneity | str | Sequence[Inhomogeneity | str] = (),
    subsurface: float | None = None,
) -> Contact3dResult:
    """One 3D contact by the semi-analytical method, as ``halfspace contact3d``: the normal contact
    under ``force`` (N) or ``depth`` (m) by DC-FFT influence coefficients and a CG active set
    (spec ``sam.md`` §3–4; Polonsky & Keer), then optionally a tangential step — a rigid-body
    ``shift_x`` (m) or a ``tangential_force`` (N) — in stick–slip with Coulomb ``friction``
    (§4.2–4.5, coupled when the bodies are dissimilar). With ``inhomogeneities`` (a list of
    :class:`Inhomogeneity` or spec strings) the nested contact ↔ equivalent-inclusion loop
    (Eshelby's EIM, §6–7; Leroux & Nélias 2011). ``subsurface`` (m): the stresses to that depth
    (Love/Boussinesq–Cerruti plus the inclusions' fields, §8).

    Returns a :class:`Result`: the CLI's JSON keys, the surface fields (``x``, ``y``, ``pressure``,
    ``shear_x/y``, ``slip_x/y``, ``stick``) shaped (N₁, N₂), and with ``subsurface`` the volume
    fields (``stress_xx`` … ``stress_xy``, ``von_mises``, ``tresca``, ``principal_1..3``,
    ``material``, ``eigenstrain_*``) shaped (layers, N₁, N₂) — the arrays of ``contact3d --out``."""
    if isinstance(inhomogeneities, (str, Inhomogeneity)):
        inhomogeneities = [inhomogeneities]
    if not isinstance(inhomogeneities, (list, tuple)):
        raise TypeError(
            f"inhomogeneities must be a list of Inhomogeneity or spec strings, got {inhomogeneities!r}"
        )
    # The keys of `halfspace contact3d --config`, read and checked by the library (one case).
    summary, arrays = _contact3d({
        "indenter": _spec(indenter, "indenter"),
        "material": _spec(material, "material"),
        "force": _opt_real(force, "force"),
        "depth": _opt_real(depth, "depth"),
        "indenter_material": _spec(indenter_material, "indenter_material"),
        "shift_x": _opt_real(shift_x, "shift_x"),
        "tangential_force": _opt_real(tangential_force, "tangential_force"),
        "friction": _real(friction, "friction"),
        "grid": _count(grid, "grid"),
        "extent": _opt_real(extent, "extent"),
        "tol": _real(tol, "tol"),
        "inhomogeneity": [_spec(i, f"inhomogeneities[{k}]") for k, i in enumerate(inhomogeneities)],
        "subsurface": _opt_real(subsurface, "subsurface"),
    })
    values = dict(summary)
    values.update(arrays)
    return Contact3dResult(values)


def fretting_wear(
    *,
    chi: float = 0.5,
    n: int = 2001,
    tol: float | None = None,
    dtau: float | None = None,
    tau_end: float = 30.0,
    method: str = "fft",
    material: Graded | Homogeneous | str | None = None,
    length: float | None = None,
    gap_transform: str = "piecewise-linear",
    edge_cells: bool = True,
    resume: str | os.PathLike[str] | None = None,
) -> WearResult:
    """Fretting wear of a parabolic indenter in partial slip by the MDR (Willert et al. 2021,
    Section 4; spec ``mdr.md`` §5), dimensionless: amplitude ratio ``chi = u_A/u_max``, ``n`` nodes,
    adaptive wear steps (ROS2) at the local error tolerance ``tol`` (default 1e-4, units of d) or
    a fixed step ``dtau``, to ``tau_end``, domain ``length`` L/a₀. ``material``: ``None`` or
    ``"homogeneous"``, or a power-law graded medium ``"graded:k=..,nu=.."`` (E ∝ z^k; the
    normalized run depends on k alone, ν gives ``tangential_constant_ratio`` c_T/c_N and
    ``u_max_over_mu_d``; docs/fretting-wear.md, "Graded media"). The worn ``profile`` approaches the
    ``limiting_profile``; ``contact_radius_history`` is a/a₀ per step (the extent of the touching
    region; ``loaded_radius_history``: where p > 1e-3 max p), at ``tau_history``; ``steps`` counts
    the time steps; ``wear_volume`` and
    ``limit_wear_volume`` are V/(π a₀² d). ``gap_transform``: ``"piecewise-linear"`` (default: no
    node-to-node mode near the contact edge) or ``"central-differences"`` (the paper's Eq. 7 as
    written; docs/fretting-wear.md, "The profile transform of the worn profile");
    ``edge_cells`` (default ``True``): the edge cells' rate as cell means (docs/fretting-wear.md,
    "The defaults"). As ``halfspace fretting-wear``. ``resume``: a run
    directory of ``halfspace fretting-wear`` (killed, or stopped) made with the same parameters —
    the run continues from its checkpoint to the uninterrupted run's result bit for bit, with the
    command line's ``--resume`` checks (a run of another adaptive scheme is refused); the
    directory is only read."""
    # The keys of `halfspace fretting-wear --config`, read and checked by the library (one case):
    # a typed medium goes as its spec; only k and ν enter the run (E0, z0, E set the scales a0,
    # F0, N0 and are not used; Estar, which gives no ν, is refused).
    if material is not None and not isinstance(material, (str, Graded, Homogeneous)):
        raise TypeError(f"material must be a spec string, Graded or Homogeneous, got {material!r}")
    return WearResult(_fretting_wear({
        "chi": _real(chi, "chi"), "n": _count(n, "n"), "tol": _opt_real(tol, "tol"),
        "dtau": _opt_real(dtau, "dtau"), "tau_end": _real(tau_end, "tau_end"),
        "method": _text(method, "method"),
        "material": None if material is None else _spec(material, "material"),
        "length": _opt_real(length, "length"),
        "gap_transform": _text(gap_transform, "gap_transform"),
        "edge_cells": _flag(edge_cells, "edge_cells")},
        None if resume is None else _path(resume, "resume")))


def fretting_wear3d(config: dict[str, Any], grid: int | None = None) -> Wear3dResult:
    """3D fretting wear on the semi-analytical solver (docs/wear3d.md), as ``halfspace
    fretting-wear3d``: the fretting loop's cycle, repeated with the worn depth h updated by
    ``ḣ = k p |ṡ|`` (Archard) or ``k |q| |ṡ|`` (energy) in adaptive jumps of cycles
    (docs/wear3d.md, "Wear steps"). ``config`` is a dict of the ``fretting-wear3d --config`` keys:
    the fretting-loop keys (``force`` or ``approach``, ``indenter_e``/``indenter_nu``,
    ``eim_change_factor``, …; those of :class:`FrettingLoop`) and a
    ``wear`` dict (``law``, ``coefficient``, ``body``, ``cycles``, ``record_cycles``,
    ``step_fraction``, ``stability_fraction``, ``inhomogeneity_depth_cells``); ``grid`` overrides
    its grid. Bad keys raise :class:`HalfspaceError` (``TypeError`` for a value of the wrong type)
    naming the key. Runs with the GIL released; Ctrl-C stops after the wear step in progress."""
    if not isinstance(config, dict):
        raise TypeError(f"config must be a dict of the fretting-wear3d keys, got {config!r}")
    return Wear3dResult(_fretting_wear3d(config, grid=_opt_count(grid, "grid")))


def fretting_wear3d_estimate(config: dict[str, Any], grid: int | None = None) -> Wear3dEstimate:
    """What :func:`fretting_wear3d` of the same ``config`` and ``grid`` would compute, as
    ``halfspace fretting-wear3d --estimate``: runs nothing and writes nothing (the surface grid and
    its checkerboard compliance ``C_min`` are evaluated, no contact is solved). Every wear step is
    given the first step's ``ΔN₁ = ⌊min(η δ / r₀, β C_min / (k_p 4A))⌋ ≥ 1`` (docs/wear3d.md,
    "The wear step and cycle jumping"; ``r₀`` the law's rate at Hertz's ``p₀ = 2E*a/(πR)``, over
    the slip path ``4A``), so ``wear_steps = Σ ⌈L / ΔN₁⌉ + 1`` over the segments ``L`` between 0,
    the ``record_cycles`` and ``cycles`` (docs/wear3d.md, "The work estimate"). The config is
    checked as by :func:`fretting_wear3d`, with the same errors."""
    if not isinstance(config, dict):
        raise TypeError(f"config must be a dict of the fretting-wear3d keys, got {config!r}")
    return Wear3dEstimate(_fretting_wear3d_estimate(config, grid=_opt_count(grid, "grid")))


def _config(config: Any) -> dict[str, Any] | None:
    """The fretting-loop config as given: a dict goes to the library as data (serde, the schema of
    ``halfspace fretting-loop --config``), which names any key it refuses."""
    if config is not None and not isinstance(config, dict):
        raise TypeError(f"config must be a dict of the fretting-loop keys, got {config!r}")
    return config


class FrettingLoop:
    """The fretting loop of Leroux & Nélias (2011): normal load ramped in steps, then the shift
    cycled 0 → +A → −A → +A, each increment the coupled stick–slip contact (docs/theory-sam.md#normal-tangential-alternation) or, with
    inhomogeneities, the nested contact ↔ EIM loop (docs/theory-sam.md#nested-loops).

    ``config`` holds the keys of ``halfspace fretting-loop --config`` (``radius``, ``e``, ``nu``,
    ``friction``, ``force`` or ``approach`` (exactly one), ``indenter_e`` and ``indenter_nu`` (an
    elastic sphere; absent: rigid), ``normal_steps``, ``amplitude``, ``shift_step``, ``grid``,
    ``extent_over_a``, ``subsurface_over_a``, ``layout``, ``fibre_e_ratio``, ``inhomogeneous_body``,
    ``surface_operator_radius_over_a``, ``eim_change_factor`` (η in (0, 1], default 3e-3: the
    nested loop's EIM solved to η × the last outer change, docs/theory-sam.md#outer-loop-tolerances;
    only with inhomogeneities on the nested loop), ``eim_recycled_depth`` (0 to 50, default 5: the
    Anderson differences the nested loop's EIM iteration keeps across an increment's outer passes,
    0 the plain iteration, docs/theory-sam.md#solving-the-eim-equations; same restriction),
    ``alternation`` (``"plain"``, the default, or ``"gauged"``: the normal–tangential alternation
    of the contact solves, docs/theory-sam.md#normal-tangential-alternation; for the composite loop
    and its homogeneous reference alike; refused for identical bodies, which do not alternate);
    ``inhomogeneity``: a
    list of tables ``{"kind": "sphere", "x": .., "E": ..}`` — the keys of the spec, and with
    ``fatigue`` that inhomogeneity's own ``{"fatigue": {"f_minus1": .., ...}}`` (see
    :meth:`fatigue`) — or of :class:`Inhomogeneity` / spec strings); the dict goes to the library
    as data, which checks it.
    ``fatigue``: a dict of the ``[fatigue]`` keys — the loop then records its closed cycle's stress
    history and :meth:`fatigue` gives the fatigue indices. ``case="composite"`` adds the paper's
    fibres. Iterating yields each increment's row (a dict);
    :meth:`run` does the rest with the GIL released.
    """

    def __init__(self, config: dict[str, Any] | None = None, *, case: str = "homogeneous", grid: int | None = None):
        self._inner = _FrettingLoop(_config(config), case=_text(case, "case"),
                                    grid=_opt_count(grid, "grid"))

    def __len__(self) -> int:
        return len(self._inner)

    def __iter__(self) -> Iterator[dict[str, float]]:
        while True:
            row = self._inner.step()
            if row is None:
                return
            yield row

    @property
    def done(self) -> int:
        """Increments done."""
        return self._inner.done

    def run(self) -> "FrettingLoop":
        """Every remaining increment (GIL released)."""
        self._inner.run()
        return self

    def rows(self) -> dict[str, NDArray[np.float64]]:
        """One array per field: normal_force, shift_x, tangential_force(_y), max_pressure,
        contact_area, stick_area, alternations, approach, outer_iterations, eim_iterations."""
        return self._inner.rows()

    def points(self) -> dict[str, dict[str, Any]]:
        """The fields at the points A–D reached so far: label → {name: (N₁, N₂) array}. With a
        subsurface depth, the four von Mises fields are computed together when D is reached
        (docs/performance.md, "The 128² composite command outside the EIM"): before that, A–C
        hold no ``von_mises``."""
        return self._inner.points()

    def metrics(self) -> LoopMetrics:
        """Dissipated energy, ratchet, regime (0 partial slip, 1 mixed, 2 gross slip), … of the
        completed loop."""
        return LoopMetrics(self._inner.metrics())

    def fatigue(self) -> FatigueResult:
        """The fatigue indices of the completed loop (Crossland, Dang Van, Smith–Watson–Topper,
        Fatemi–Socie over the stress history of its closed cycle; docs/fatigue.md), as
        ``halfspace fretting-loop`` with the same ``[fatigue]`` table: ``config["fatigue"]`` holds
        its keys (``f_minus1``, ``t_minus1``, ``fs_k``, ``yield_stress``, ``depth_over_a``,
        ``screen_fraction``, ``inhomogeneity``, ``process_volume``), and an ``inhomogeneity`` entry's dict may hold
        ``"fatigue": {"f_minus1": …, "t_minus1": …, "fs_k": …, "yield_stress": …}`` (any subset:
        that inhomogeneity's own constants, the others from ``fatigue["inhomogeneity"]``, else
        the matrix's; docs/fatigue.md, "Materials"). Evaluated once (GIL released), then kept.
        :class:`HalfspaceError` without a ``fatigue`` table or before the loop is done."""
        summary, arrays = self._inner.fatigue()
        values = dict(summary)
        values.update(arrays)
        return FatigueResult(values)




def _map_point(config: dict[str, Any] | None, case: str, grid: int | None, loads: list[float],
               amplitudes: list[float], i: int, j: int) -> list[float]:
    """One point of a fretting map (a task on a Dask worker; the GIL is released while it runs)."""
    return _fretting_map_point(config, case, grid, loads, amplitudes, i, j)


def _items(v: Any, name: str) -> list[Any]:
    """A scalar or a sequence (list, tuple, 1D array) as a list, or TypeError naming it."""
    if isinstance(v, (str, bytes)) or v is None or isinstance(v, dict):
        raise TypeError(f"{name} must be a number or a sequence of numbers, got {v!r}")
    if isinstance(v, np.ndarray):
        return list(v.ravel())
    if isinstance(v, (list, tuple)):
        return list(v)
    return [v]


def fretting_map(
    loads: float | Sequence[float] | NDArray[np.float64],
    amplitudes: float | Sequence[float] | NDArray[np.float64],
    *,
    config: dict[str, Any] | None = None,
    case: str = "homogeneous",
    grid: int | None = None,
    client: Any = None,
) -> MapResult:
    """A fretting map (Vingsbo & Söderberg 1988): the fretting loop of :class:`FrettingLoop` at every
    normal load ``W`` in ``loads`` (N) × shift amplitude ``A`` in ``amplitudes`` (m), as
    ``halfspace fretting-map``. ``config`` holds the fretting-loop keys (``grid``, ``normal_steps``,
    ``shift_step`` — its ratio to ``amplitude`` fixes the steps per quarter cycle of every point —,
    ``inhomogeneity``, …); the domain (and any composite fibres) is sized for the largest load,
    and every point keeps those cells and the same increments.

    Returns a :class:`Result` with ``loads``, ``amplitudes`` and, shaped (len(loads),
    len(amplitudes)), ``regime`` (int: 0 partial slip, 1 mixed, 2 gross slip — a stick zone
    throughout, sliding ≤ 5 % of the travel 4A, more), ``dissipated_energy`` (J per cycle,
    ``|∮ Q dδ|``), ``energy_ratio`` (Fouvry's ``E_d / 4Q*δ*``), ``sliding_fraction``,
    ``tangential_force_over_mu_w_at_amplitude``, ``ratchet`` and ``seconds`` (per point).

    Without ``client`` the points run in parallel on this machine's cores (GIL released). With a
    ``dask.distributed.Client`` each point is one task on its cluster (the workers need this package
    installed); the numbers are the same bit for bit (every loop is deterministic)."""
    loads = [_real(w, f"loads[{k}]") for k, w in enumerate(_items(loads, "loads"))]
    amplitudes = [_real(a, f"amplitudes[{k}]") for k, a in enumerate(_items(amplitudes, "amplitudes"))]
    cfg = _config(config)
    case, grid = _text(case, "case"), _opt_count(grid, "grid")
    if client is not None and not all(callable(getattr(client, m, None)) for m in ("map", "gather")):
        raise TypeError(
            f"client must be a dask.distributed.Client (with map and gather), got {client!r}"
        )
    if client is None:
        values = _fretting_map(cfg, case, grid, loads, amplitudes)
    else:
        # A bad map is refused here, with the library's message, before any task is sent.
        shape = _fretting_map_shape(cfg, case, grid, loads, amplitudes)
        tasks = [(i, j) for i in range(shape[0]) for j in range(shape[1])]
        futures = client.map(
            _map_point,
            [cfg] * len(tasks),
            [case] * len(tasks),
            [grid] * len(tasks),
            [loads] * len(tasks),
            [amplitudes] * len(tasks),
            [i for i, _ in tasks],
            [j for _, j in tasks],
            pure=False,
        )
        points = np.asarray(client.gather(futures), dtype=float).reshape(*shape, -1)
        values = {"loads": np.asarray(loads), "amplitudes": np.asarray(amplitudes)}
        # The columns of MapPoint::FIELDS after load and amplitude.
        for f, name in enumerate(_MAP_FIELDS[2:], start=2):
            values[name] = points[:, :, f].copy()
    values["regime"] = np.asarray(values["regime"]).astype(np.int64)
    return MapResult(values)
