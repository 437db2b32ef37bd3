"""Type stubs of the compiled module whirl._whirl (the Python API is in whirl/*.py)."""

import os
from pathlib import Path
from typing import Any, final

import numpy as np
import numpy.typing as npt

# What the compiled module exports (pyo3 lists every function, class and constant added).
__all__ = [
    "BUILD_ID",
    "DEFAULT_CAGE_POSITIONS",
    "DEFAULT_MODES",
    "DEFAULT_SPEED_COUNT",
    "DEFAULT_STABILITY_MODES",
    "InputError",
    "MAX_AFT_SAMPLES",
    "MAX_HARMONICS",
    "Model",
    "NumericalError",
    "PALETTE",
    "RawCascade",
    "Report",
    "WhirlError",
    "__version__",
    "campbell",
    "cascade",
    "cascade_checkpoint",
    "cascade_default_speeds",
    "cascade_point",
    "cascade_report",
    "cascade_resolved",
    "check",
    "convergence",
    "fit_forcing",
    "frf",
    "hbm",
    "map",
    "map_value",
    "modal",
    "other_start",
    "parse_quantity",
    "parse_range",
    "parse_speed",
    "parse_speeds",
    "reduce",
    "ross_to_toml",
    "runup",
    "save_figures",
    "simulate",
    "statics",
    "stiffness",
    "study",
    "study_point",
    "ucs",
    "unbalance",
]
__version__: str
BUILD_ID: str

class WhirlError(Exception): ...
class InputError(WhirlError): ...
class NumericalError(WhirlError): ...

@final
class Model:
    @staticmethod
    def from_file(path: str) -> Model: ...
    @staticmethod
    def from_toml(text: str, file: str | None = None) -> Model: ...
    def with_values(self, edits: list[tuple[str, Any]]) -> Model: ...
    @property
    def name(self) -> str: ...
    @property
    def toml(self) -> str: ...
    @property
    def file(self) -> Any: ...
    @property
    def node_count(self) -> int: ...
    @property
    def length(self) -> float: ...
    @property
    def shaft_mass(self) -> float: ...
    def to_json(self) -> str: ...
    def warnings(self) -> list[str]: ...
    def node_positions(self) -> npt.NDArray[np.float64]: ...
    def node_features(self) -> list[str]: ...
    def bearing_nodes(self) -> list[int]: ...
    def default_speeds(self, start: float, count: int) -> npt.NDArray[np.float64]: ...

def parse_speed(text: str) -> float: ...
def parse_speeds(text: str) -> npt.NDArray[np.float64]: ...
def check(model: Model) -> Report: ...
def campbell(model: Model, options: dict[str, Any]) -> dict[str, Any]: ...
def unbalance(model: Model, speeds: Any, nodes: list[int]) -> tuple[dict[str, Any], Report]: ...
def convergence(model: Model, counts: list[int], modes: int) -> tuple[dict[str, Any], Report]: ...
def ross_to_toml(text: str, name: str) -> tuple[str, list[str]]: ...
DEFAULT_SPEED_COUNT: int
DEFAULT_MODES: int
DEFAULT_CAGE_POSITIONS: int

def parse_quantity(name: str, text: str, dimension: str) -> float: ...
def parse_range(name: str, text: str, dimension: str) -> npt.NDArray[np.float64]: ...


def stiffness(model: Model, options: dict[str, Any]) -> Report: ...
def runup(model: Model, options: dict[str, Any]) -> Report: ...
def cascade_default_speeds(model: Model) -> npt.NDArray[np.float64]: ...
def cascade_resolved(model: Model, options: dict[str, Any]) -> dict[str, Any]: ...
def cascade_checkpoint(model: Model, options: dict[str, Any], parent: str) -> Any: ...
def cascade(
    model: Model,
    options: dict[str, Any],
    checkpoint: str | None = None,
    progress: Any = None,
    runner: Any = None,
) -> tuple[dict[str, Any], RawCascade]: ...
def cascade_point(model: Model, options: dict[str, Any], speed: float) -> str: ...

@final
class RawCascade:
    """A computed cascade as the library holds it (``cascade(...)[1]``)."""

def other_start(first: RawCascade, options: dict[str, Any]) -> dict[str, Any]: ...
def cascade_report(
    first: RawCascade,
    checkpoint_folder: str | None = None,
    second: RawCascade | None = None,
) -> Report: ...
def study(
    path: str, checkpoint: str, restart: bool, progress: Any = None, runner: Any = None
) -> tuple[Report, Path]: ...
def study_point(path: str, index: int, checkpoint: str) -> str: ...
def simulate(
    model: Model, options: dict[str, Any], progress: Any = None
) -> tuple[dict[str, Any], Report]: ...
def modal(model: Model, options: dict[str, Any]) -> tuple[Report, float]: ...

DEFAULT_STABILITY_MODES: int
MAX_HARMONICS: int
MAX_AFT_SAMPLES: int

@final
class Report:
    """A library report: its summary and its named tables."""

    @property
    def tables(self) -> list[str]: ...
    def summary(self) -> dict[str, Any]: ...
    def table(self, name: str) -> dict[str, npt.NDArray[np.float64] | list[str | None]]: ...
    def figures(self) -> list[dict[str, Any]]: ...

def save_figures(specs: list[dict[str, Any]], folder: str | os.PathLike[str], rpm: bool) -> list[Path]: ...

PALETTE: list[str]

def hbm(model: Model, options: dict[str, Any], progress: Any = None) -> Report: ...
def map(  # noqa: A001
    model: Model,
    options: dict[str, Any],
    sweep: dict[str, Any],
    progress: Any = None,
    runner: Any = None,
) -> Report: ...
def map_value(model: Model, options: dict[str, Any], sweep: dict[str, Any], index: int) -> str: ...
def reduce(model: Model, modes: int, nodes: list[int]) -> Report: ...
def statics(model: Model, rollers: str) -> Report: ...
def ucs(model: Model, options: dict[str, Any]) -> Report: ...
def frf(
    model: Model,
    input: tuple[int, str],
    outputs: list[tuple[int, str]],
    speed: float,
    frequencies: list[float] | None,
    force: float,
) -> Report: ...
def fit_forcing(model: Model, options: dict[str, Any], progress: Any = None) -> Report: ...
