# The Rust extension (python/src/lib.rs), as built; checked against the module by
# `python -m mypy.stubtest halfspace` in .ci/run.
import os
from typing import Any, final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "HalfspaceError",
    "axisym",
    "fretting_wear",
    "fretting_wear3d",
    "fretting_wear3d_estimate",
    "contact3d",
    "fretting_map",
    "fretting_map_point",
    "fretting_map_shape",
    "MAP_FIELDS",
    "FATIGUE_FIELDS",
    "_FrettingLoop",
]

class HalfspaceError(ValueError): ...

MAP_FIELDS: list[str]
FATIGUE_FIELDS: list[str]

def axisym(config: dict[str, Any]) -> dict[str, Any]: ...
def fretting_wear(
    config: dict[str, Any], resume: str | os.PathLike[str] | None = None
) -> dict[str, Any]: ...
# `config` of fretting_wear3d and _FrettingLoop: the `--config` keys of `fretting-wear3d` /
# `fretting-loop` (docs/sam.md, docs/wear3d.md), one spelling each, e.g. `eim_change_factor`
# (η in (0, 1], default 3e-3) and `eim_recycled_depth` (0 to 50, default 5; both for the nested
# loop with inhomogeneities only), and `alternation` ("plain", the default, or "gauged": the
# contact solves' normal–tangential alternation; coupled pairs only).
def fretting_wear3d(config: dict[str, Any], grid: int | None = None) -> dict[str, Any]: ...
def fretting_wear3d_estimate(config: dict[str, Any], grid: int | None = None) -> dict[str, Any]: ...
def contact3d(
    config: dict[str, Any],
) -> tuple[dict[str, Any], dict[str, NDArray[np.float64]]]: ...
def fretting_map(
    config: dict[str, Any] | None,
    case: str,
    grid: int | None,
    loads: list[float],
    amplitudes: list[float],
) -> dict[str, NDArray[np.float64]]: ...
def fretting_map_shape(
    config: dict[str, Any] | None,
    case: str,
    grid: int | None,
    loads: list[float],
    amplitudes: list[float],
) -> tuple[int, int]: ...
def fretting_map_point(
    config: dict[str, Any] | None,
    case: str,
    grid: int | None,
    loads: list[float],
    amplitudes: list[float],
    i: int,
    j: int,
) -> list[float]: ...

@final
class _FrettingLoop:
    def __new__(
        cls, config: dict[str, Any] | None = None, case: str = "homogeneous", grid: int | None = None
    ) -> _FrettingLoop: ...
    def __len__(self) -> int: ...
    @property
    def done(self) -> int: ...
    def step(self) -> dict[str, float] | None: ...
    def run(self) -> None: ...
    def rows(self) -> dict[str, NDArray[np.float64]]: ...
    def points(self) -> dict[str, dict[str, Any]]: ...
    def metrics(self) -> dict[str, Any]: ...
    def fatigue(self) -> tuple[dict[str, Any], dict[str, NDArray[np.float64]]]: ...
    @staticmethod
    def point_labels() -> list[str]: ...
