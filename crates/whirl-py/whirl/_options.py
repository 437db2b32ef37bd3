"""Options as the command line reads them: speeds with units, counts."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from . import _whirl
from .model import Model

Speeds = str | Sequence[float] | np.ndarray | None


def speeds(given: Speeds, model: Model, start: float, count: int, name: str = "speeds") -> np.ndarray:
    """Speeds in rad/s: a range with a unit (``"0:800Hz:161"``), numbers in rad/s, or by
    default ``count`` speeds from ``start`` to 1.2 x the model's top operating speed (or
    800 Hz), as on the command line."""
    if given is None:
        return model._raw.default_speeds(start, count)
    if isinstance(given, str):
        return _whirl.parse_speeds(given)
    w = np.asarray(given, dtype=float).ravel()
    if w.size == 0 or not np.all(np.isfinite(w)) or np.any(w < 0):
        raise _whirl.InputError(
            f"invalid `{name}`: give a range such as \"0:800Hz:161\" or finite, non-negative "
            "speeds in rad/s"
        )
    return w
