"""Run-up and coast-down (``whirl runup``): one transient through a speed range at a constant
acceleration, its time-frequency cascade beside the steady cascade, and the hysteresis
between the two directions."""

from __future__ import annotations

import os
from collections.abc import Sequence

from . import _whirl
from .model import Model, as_model
from .report import Report


def runup(
    model: Model | str | os.PathLike[str],
    *,
    speeds: str | Sequence[float] | None = None,
    rate: str | float | None = None,
    direction: str | None = None,
    hold: str | float | None = None,
    window_length: str | float | None = None,
    overlap: float | None = None,
    steady: str | None = None,
    steady_speeds: int | None = None,
    hysteresis_ratio: float | None = None,
    threshold: str | float | None = None,
    smoothing: str | float | None = None,
    steady_smoothing: str | float | None = None,
    start: str | None = None,
    contact: str | None = None,
    reduce: int | None = None,
    full_model: bool | None = None,
    step: str | float | None = None,
    node: int | None = None,
    component: str | None = None,
    window: str | None = None,
    max_frequency: str | float | None = None,
    tolerance: float | None = None,
) -> Report:
    """Run-up and coast-down through a speed range (``whirl runup``). Every option left
    None takes the library's default, as on the command line.

    Args:
        model: a :class:`Model` or a model file path.
        speeds: ``"1:750Hz"``, or (low, high) in rad/s; default the model's operating range.
        rate: acceleration, ``"20Hz/s"`` or ``"1200rpm/s"``, or rad/s^2 (default 20 Hz/s).
        direction: ``up``, ``down`` or ``both`` (default).
        hold: time at the starting speed before the ramp (``"1s"``).
        window_length: short-time window (default 1 / sqrt(rate in Hz/s)).
        overlap: overlap of consecutive windows (0.75).
        steady: the steady cascade compared with: ``none``, ``cascade``, ``starts``
            (default: from both starts, marking coexisting motions).
        steady_speeds: speeds of the steady cascade (60).
        hysteresis_ratio: run-up and coast-down differ beyond this ratio (2) ...
        threshold: ... at this amplitude or more (``"1um"``).
        smoothing: span of speed each sweep's NSV is averaged over before run-up and
            coast-down are compared (``"10Hz"``).
        steady_smoothing: the same before the comparison with the steady cascade (``"2Hz"``).
        start, contact, reduce, full_model, step, node, component, window, max_frequency,
            tolerance: the cascade's run settings and measurement, as for :func:`cascade`.

    Returns:
        A :class:`whirl.Report` with the tables ``runup``, ``runup_spectra`` and, as
        computed, ``steady``, ``hysteresis`` and ``bands``, as the command line writes them.
    """
    model = as_model(model)
    given = {k: v for k, v in locals().items() if k != "model" and v is not None}
    return Report("runup", model, _whirl.runup(model._raw, given))
