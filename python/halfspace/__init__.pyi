from typing import Any, Iterator

import numpy as np

class HalfspaceError(ValueError): ...

class Sphere:
    R: float
    def __init__(self, R: float) -> None: ...
    def spec(self) -> str: ...

class Ellipsoid:
    Rx: float
    Ry: float
    def __init__(self, Rx: float, Ry: float) -> None: ...
    def spec(self) -> str: ...

class Cone:
    slope: float
    def __init__(self, slope: float) -> None: ...
    def spec(self) -> str: ...

class Flat:
    a: float
    def __init__(self, a: float) -> None: ...
    def spec(self) -> str: ...

class PowerLaw:
    c: float
    n: float
    def __init__(self, c: float, n: float) -> None: ...
    def spec(self) -> str: ...

class Table:
    r: np.ndarray
    f: np.ndarray
    def __init__(self, r: Any, f: Any) -> None: ...

class Homogeneous:
    E: float | None
    nu: float | None
    Estar: float | None
    def __init__(self, E: float | None = ..., nu: float | None = ..., Estar: float | None = ...) -> None: ...
    def spec(self) -> str: ...

class Graded:
    E0: float
    z0: float
    nu: float
    k: float
    def __init__(self, E0: float, z0: float, nu: float, k: float) -> None: ...
    def spec(self) -> str: ...

class Inhomogeneity:
    def __init__(self, spec: str) -> None: ...
    def spec(self) -> str: ...
    @classmethod
    def sphere(cls, *, x: float, y: float, z: float, r: float, E: float, nu: float) -> Inhomogeneity: ...
    @classmethod
    def cylinder(
        cls, *, axis: str, z: float, r: float, E: float, nu: float, x: float | None = ..., y: float | None = ...
    ) -> Inhomogeneity: ...
    @classmethod
    def cuboid(
        cls, *, x: float, y: float, z: float, hx: float, hy: float, hz: float, E: float, nu: float
    ) -> Inhomogeneity: ...

class Result:
    def __init__(self, values: dict[str, Any]) -> None: ...
    def to_dict(self) -> dict[str, Any]: ...
    def __getattr__(self, name: str) -> Any: ...

def axisym(
    profile: Sphere | Cone | Flat | PowerLaw | Table | str,
    material: Homogeneous | Graded | str,
    *,
    force: float | None = ...,
    depth: float | None = ...,
    n: int = ...,
    method: str = ...,
) -> Result: ...

def contact3d(
    indenter: Sphere | Ellipsoid | Cone | Flat | str,
    material: Homogeneous | str,
    *,
    force: float | None = ...,
    depth: float | None = ...,
    indenter_material: Homogeneous | str = ...,
    shift_x: float | None = ...,
    tangential_force: float | None = ...,
    friction: float = ...,
    grid: int = ...,
    extent: float | None = ...,
    tol: float = ...,
    inhomogeneities: Inhomogeneity | str | list[Inhomogeneity | str] | tuple[Inhomogeneity | str, ...] = ...,
    subsurface: float | None = ...,
) -> Result: ...

def fretting_wear(
    *,
    chi: float = ...,
    n: int = ...,
    tol: float | None = ...,
    dtau: float | None = ...,
    tau_end: float = ...,
    method: str = ...,
    material: str | None = ...,
    length: float | None = ...,
) -> Result: ...

class FrettingLoop:
    def __init__(self, config: dict[str, Any] | None = ..., *, case: str = ..., grid: int | None = ...) -> None: ...
    def __len__(self) -> int: ...
    def __iter__(self) -> Iterator[dict[str, float]]: ...
    @property
    def done(self) -> int: ...
    def run(self) -> FrettingLoop: ...
    def rows(self) -> dict[str, np.ndarray]: ...
    def points(self) -> dict[str, dict[str, Any]]: ...
    def metrics(self) -> Result: ...

def fretting_map(
    loads: Any,
    amplitudes: Any,
    *,
    config: dict[str, Any] | None = ...,
    case: str = ...,
    grid: int | None = ...,
    client: Any = ...,
) -> Result: ...
