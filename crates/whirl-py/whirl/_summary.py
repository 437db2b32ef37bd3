"""What every summary starts with, as the command line's summary.json."""

from __future__ import annotations

from typing import Any

from . import _whirl
from .model import Model


def head(command: str, model: Model) -> dict[str, Any]:
    """The first keys of a summary: which command, which whirl, which model."""
    return {
        "command": command,
        "whirl_version": _whirl.__version__,
        "model_file": model.file,
        "model_name": model.name,
    }


def jsonable(x: Any) -> Any:
    """``x`` as summary.json reads back: tuples (Rust's pairs) as lists, throughout."""
    if isinstance(x, dict):
        return {k: jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    return x
