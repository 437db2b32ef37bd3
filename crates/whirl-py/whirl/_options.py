"""Options as the command line reads them: speeds with units, counts."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from . import _whirl

Speeds = str | Sequence[float] | np.ndarray | None


def speeds(given: Speeds, name: str = "speeds") -> np.ndarray | None:
    """Speeds in rad/s: a range with a unit (``"0:800Hz:161"``) or numbers in rad/s, as on
    the command line; ``None`` when none are given (the library's default)."""
    if given is None:
        return None
    if isinstance(given, str):
        return _whirl.parse_speeds(given)
    w = np.asarray(given, dtype=float).ravel()
    if w.size == 0 or not np.all(np.isfinite(w)) or np.any(w < 0):
        raise _whirl.InputError(
            f"invalid `{name}`: give a range such as \"0:800Hz:161\" or finite, non-negative "
            "speeds in rad/s"
        )
    return w
