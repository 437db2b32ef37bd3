"""The NSV cascade (``whirl cascade``): the rotor simulated on its nonlinear roller
bearings at each speed, the spectrum of the settled response, and the largest
non-synchronous peak classified; on this machine's cores or on a Dask cluster.
"""

from __future__ import annotations

import math
import os
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from . import _options, _progress, _whirl
from .model import Model, as_model
from .report import Report, Reported

#: Speeds of a cascade without ``speeds``: this many over the model's operating range.
DEFAULT_SPEEDS = _whirl.DEFAULT_SPEED_COUNT


def default_speeds(model: Model) -> np.ndarray:
    """The cascade's default speeds, rad/s: 150 over the model's ``[operating]`` range, from
    its low bound (or from top / 150 when it starts at rest) to its top; the library's, as
    on the command line and in a study."""
    return _whirl.cascade_default_speeds(model._raw)


def _given(speeds: _options.Speeds, options: dict[str, Any]) -> dict[str, Any]:
    """The keyword arguments as the library reads them: those given, speeds as a list."""
    if speeds is not None and not isinstance(speeds, str):
        speeds = np.asarray(speeds, dtype=float).ravel().tolist()
    return {k: v for k, v in {"speeds": speeds, **options}.items() if v is not None}


def options(model: Model, speeds: _options.Speeds = None, **cascade_options: Any) -> dict[str, Any]:
    """The cascade's options as the library resolves them for ``model`` from the command
    line's options (same names; times and frequencies as text with a unit or as SI
    numbers; every option left out at the library's default): speeds in rad/s, times in s,
    frequencies in Hz."""
    return _whirl.cascade_resolved(model._raw, _given(speeds, cascade_options))


@dataclass(frozen=True, repr=False)
class CascadeResult(Reported):
    """A computed cascade: per speed the spectrum of the analysed displacement and the
    largest non-synchronous peak (NSV), classified; and the library's report:
    ``to_dict()`` is the command line's summary.json (the NSV summary under ``nsv``, with
    ``compare_starts=True`` the comparison under ``starts``), ``to_pandas(name)`` its tables
    ``cascade``, ``full_cascade`` (with ``full=True``), ``nsv`` and ``starts`` (with
    ``compare_starts=True``). The summary's keys read as attributes too
    (``result.resumed_speeds``, ``result.checkpoint_folder``)."""

    model: Model
    #: Speeds, requested and added, ascending, Hz.
    speeds_hz: np.ndarray
    #: Frequencies of the one-sided spectrum's bins, Hz.
    frequency_hz: np.ndarray
    #: ``amplitude[i, k]``: zero-to-peak amplitude at speed i and bin k, m.
    amplitude: np.ndarray
    #: Frequencies of the full spectrum's bins (only with ``full=True``), Hz.
    full_frequency_hz: np.ndarray
    #: ``full_amplitude[i, k]`` over ``full_frequency_hz`` (forward whirl at +f), m.
    full_amplitude: np.ndarray
    #: Per speed, as the library holds it: added, settled, settle_s, records, one_x_m, peak
    #: (the largest non-synchronous peak or None), diverged, start_fallback.
    points: list[dict[str, Any]]
    #: Per speed, the classified NSV (class, explanation, direction, slope in Hz per Hz of
    #: speed or None, peak) or None.
    nsv: list[dict[str, Any] | None]
    report: Report


def _result(model: Model, raw: dict[str, Any], report: Report) -> CascadeResult:
    points = raw["points"]
    bins, full_bins = len(raw["frequency_hz"]), len(raw["full_frequency_hz"])
    spectra = lambda key, n: np.array(  # noqa: E731
        [p[key] if len(p[key]) == n else [math.nan] * n for p in points], dtype=float
    ).reshape(len(points), n)
    return CascadeResult(
        model=model,
        speeds_hz=np.array([p["speed_hz"] for p in points], dtype=float),
        frequency_hz=np.asarray(raw["frequency_hz"], dtype=float),
        amplitude=spectra("amplitude", bins),
        full_frequency_hz=np.asarray(raw["full_frequency_hz"], dtype=float),
        full_amplitude=spectra("full_amplitude", full_bins),
        points=[{k: v for k, v in p.items() if k not in ("amplitude", "full_amplitude")} for p in points],
        nsv=raw["nsv"],
        report=report,
    )


def cascade(
    model: Model | str | os.PathLike[str],
    speeds: _options.Speeds = None,
    *,
    threshold: str | float | None = None,
    checkpoint: str | os.PathLike[str] | None = None,
    restart: bool = False,
    compare_starts: bool = False,
    progress: bool | Any = True,
    client: Any = None,
    **cascade_options: Any,
) -> CascadeResult:
    """The NSV cascade (``whirl cascade``), with the command line's options and defaults.

    Args:
        model: a :class:`Model` or a model file path.
        speeds: a range ``"1:750Hz:150"`` or speeds in rad/s; default 150 speeds over the
            model's operating range. Speeds are added where the NSV changes sharply unless
            ``no_refine=True``.
        threshold: NSV amplitude (zero-to-peak) from which a speed counts in the summary
            (default 1 um).
        checkpoint: a folder (shared by the workers, with ``client``) in which each
            finished speed is kept, in ``<checkpoint>/<key>`` (one folder per model and
            options): a run started again computes only the missing speeds and gives the
            same result. The command line uses ``out/cascade.partial``.
        restart: delete this cascade's checkpoint first and compute every speed again.
        compare_starts: run every speed again from the other start (rest after the static
            equilibrium, or the reverse) and mark the speeds where the NSV differs beyond
            three standard errors: coexisting motions (``starts`` in the summary, the table
            ``starts``; twice the computing). Its checkpoint sits beside this one's.
        progress: True for a tqdm bar when tqdm is installed, False for none, or a callable
            ``progress(done, total)`` (a true return stops the run, as Ctrl-C does; the
            finished speeds stay in the checkpoint).
        client: a ``dask.distributed.Client``: every round of speeds is sent to its
            workers and gathered (see :mod:`whirl.dask`); the result is the same, to the
            bit, as on this machine.
        **cascade_options: the command line's options by their names (``settle``,
            ``settle_max``, ``start``, ``no_refine``, ``refine_budget``, ``refine_spacing``,
            ``record``, ``max_records``, ``average_tolerance``, ``contact``, ``reduce``,
            ``full_model``, ``step``, ``node``, ``component``, ``window``,
            ``max_frequency``, ``tolerance``, ``full``), each left out or None at the
            library's default (see :func:`options`).
    """
    model = as_model(model)
    o = _given(speeds, {"threshold": threshold, **cascade_options})
    raw, first, folder = _run(model, o, checkpoint, restart, progress, client)
    second = None
    if compare_starts:
        other = _whirl.other_start(first, o)
        second = _run(model, other, checkpoint, restart, progress, client)[1]
    folder = None if folder is None else str(folder)
    report = _whirl.cascade_report(first, folder, second)
    return _result(model, raw, Report("cascade", model, report))


def _run(
    model: Model,
    o: dict[str, Any],
    checkpoint: str | os.PathLike[str] | None,
    restart: bool,
    progress: bool | Any,
    client: Any,
) -> tuple[dict[str, Any], Any, Path | None]:
    """One cascade with the keyword arguments ``o``, in its folder inside ``checkpoint``:
    the cascade as a dict and as the library holds it, and the folder."""
    folder = None
    if checkpoint is not None:
        folder = Path(_whirl.cascade_checkpoint(model._raw, o, os.fspath(checkpoint)))
        if restart and folder.exists():
            shutil.rmtree(folder)
    runner = None
    if client is not None:
        from .dask import point_runner

        runner = point_runner(client, model, o)
    with _progress.display(progress, "cascade", "speeds") as report:
        raw, held = _whirl.cascade(model._raw, o, None if folder is None else os.fspath(folder), report, runner)
    return raw, held, folder
