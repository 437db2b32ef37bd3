"""Rotors from ROSS, the Python rotordynamics library: files saved by ``Rotor.save`` and
live ``ross.Rotor`` objects, translated by whirl's reader (``whirl import-ross``).

Shaft elements, disks and linear bearings are translated; what whirl cannot represent
(speed-dependent bearings, seals, ...) is refused with a message naming the element. What
the translation dropped or changed is said as a :class:`whirl.WhirlWarning` each.
"""

from __future__ import annotations

import os
import tempfile
import warnings
from pathlib import Path
from typing import Any

from . import _whirl
from .model import Model, WhirlWarning


def read_ross(path: str | os.PathLike[str], name: str | None = None) -> Model:
    """The whirl model of a rotor file written by ROSS's ``Rotor.save``; ``name`` names the
    model (default the file's stem)."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as e:
        raise _whirl.WhirlError(
            f"cannot read `{path}`: {e}\n  help: give a file written by ROSS's Rotor.save"
        ) from e
    toml, notes = _whirl.ross_to_toml(text, name or path.stem or "rotor")
    for note in notes:
        warnings.warn(f"{path}: {note}", WhirlWarning, stacklevel=2)
    return Model.from_toml(toml)


def from_ross(rotor: Any, name: str = "rotor") -> Model:
    """The whirl model of a live ``ross.Rotor``: saved by ROSS itself to a temporary file and
    read by :func:`read_ross`, so both ways in give the same model."""
    with tempfile.TemporaryDirectory(prefix="whirl-ross-") as folder:
        path = Path(folder) / f"{name}.toml"
        rotor.save(path)
        return read_ross(path, name)
