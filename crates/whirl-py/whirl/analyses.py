"""The analyses whose results the library reports whole: each returns a
:class:`whirl.Report` (``to_dict()``, ``to_pandas(table)``) equal to the command line's
summary.json and CSV tables."""

from __future__ import annotations

import os
from collections.abc import Sequence

from . import _options, _whirl
from .model import Model, as_model
from .report import Report
from .response import report_nodes


def reduce(
    model: Model | str | os.PathLike[str],
    *,
    modes: int = _whirl.DEFAULT_MODES,
    nodes: Sequence[int] = (),
) -> Report:
    """The Craig-Bampton reduction (``whirl reduce``): the reduced model with ``modes``
    fixed-interface modes against the full model, and a study over 1 to max(24, 2 x modes)
    modes.

    Args:
        model: a :class:`Model` or a model file path.
        modes: fixed-interface modes of the reduced model reported (1-200).
        nodes: nodes added to the boundary besides the bearing nodes.

    Returns:
        A :class:`whirl.Report` with the tables ``reduce`` (the full and reduced natural
        frequencies and their relative errors) and ``study`` (per number of modes its
        coordinates, stable step and errors), as the command line writes them.
    """
    model = as_model(model)
    boundary = report_nodes(model, nodes) if nodes else []
    raw = _whirl.reduce(model._raw, _options.mode_count(modes), boundary)
    return Report("reduce", model, raw)
