"""Time simulation (``whirl simulate``): the rotor on its (nonlinear) bearings marched in
time at a speed, by central difference, Newmark or Runge-Kutta, full or reduced."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from . import _options, _progress, _whirl
from .model import Model, as_model
from .report import Report, Reported
from .response import report_nodes


@dataclass(frozen=True, repr=False)
class SimulationResult(Reported):
    """Recorded time histories, ``values[channel, sample]`` at ``time`` with channels named
    ``n<node>.ux`` / ``n<node>.uy`` (m), and the library's report: ``to_dict()`` is the
    command line's summary.json, ``to_pandas(name)`` its tables ``time_history``,
    ``spectrum``, ``peaks`` and per roller bearing ``contacts_<bearing>``. The summary's
    keys read as attributes too (``result.step_s``, ``result.contact``)."""

    _figures = ("spectrum", "orbit")

    model: Model
    #: Times, s.
    time: np.ndarray
    #: ``values[i, k]``: channel i at time k, m.
    values: np.ndarray
    #: Channel names, ``n10.ux``.
    names: list[str]
    #: Node of each channel.
    nodes: list[int]
    #: Settling time (the steady-state numbers come from after it), s.
    settle: float
    #: Time step, s, and steps per recorded sample.
    step: float
    record_every: int
    report: Report

    def channel(self, name: str) -> np.ndarray:
        """The values of channel ``name`` (``n10.uy``), m."""
        return self.values[self.names.index(name)]


def simulate(
    model: Model | str | os.PathLike[str],
    speed: str | float,
    *,
    duration: str | float | None = None,
    method: str | None = None,
    hht_alpha: float | None = None,
    step: str | float | None = None,
    reduce: int | None = None,
    settle: str | float | None = None,
    nodes: Sequence[int] | None = None,
    contact: str | None = None,
    record_every: int | None = None,
    ramp_to: str | float | None = None,
    start: str | None = None,
    divergence_bound: str | float | None = None,
    progress: bool | Any = True,
) -> SimulationResult:
    """The time response at a speed (``whirl simulate``), with the command line's options;
    every option left None takes the library's default.

    Args:
        model: a :class:`Model` or a model file path.
        speed: spin speed, ``"50Hz"``, ``"3000rpm"`` or rad/s.
        duration: simulated time.
        method: ``cd`` (central difference at 0.9 x its stability limit unless ``step``),
            ``newmark`` (``hht_alpha`` in [-1/3, 0] damps the highest frequencies) or
            ``rk`` (adaptive Dormand-Prince; ``step`` is the output interval).
        reduce: Craig-Bampton with this many fixed-interface modes; default the full model.
        settle: time discarded before the steady-state numbers; default half the duration.
        nodes: nodes recorded; default every disk and bearing node (a contact law adds the
            roller bearings' nodes).
        contact: ``hertz``, ``lagrange``, ``forcing`` or ``linear``; default hertz with
            roller bearings.
        record_every: record every N-th step; default as many as fit in 1e-5 s.
        ramp_to: raise the speed linearly to this over the settling time, then hold it.
        start: ``static`` (the static equilibrium under gravity) or ``rest``.
        divergence_bound: a recorded displacement beyond this (m) means divergence.
        progress: True for a tqdm bar when tqdm is installed, False, or ``progress(done,
            1000)``.

    Returns:
        A :class:`SimulationResult`: the recorded channels as arrays, and the command
        line's summary and tables (``time_history``, ``spectrum``, ``peaks``,
        ``contacts_<bearing>``).
    """
    model = as_model(model)
    # The keywords given (the parameters, read before any local is made), the nodes
    # resolved as every analysis reports them.
    given = {k: v for k, v in locals().items() if k not in ("model", "progress") and v is not None}
    given["nodes"] = report_nodes(model, nodes)
    with _progress.display(progress, "simulate", "permille") as report:
        raw, summary = _whirl.simulate(model._raw, given, report)
    return SimulationResult(model=model, report=Report("simulate", model, summary), **raw)
