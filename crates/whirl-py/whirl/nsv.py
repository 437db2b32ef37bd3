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
from typing import Any, ClassVar

import numpy as np

from . import _options, _progress, _whirl
from ._summary import head, jsonable
from .model import Model, as_model

#: Speeds of a cascade without ``speeds``: this many over the model's operating range.
DEFAULT_SPEEDS = 150


def _time(name: str, value: str | float) -> float:
    t = _whirl.parse_quantity(name, str(value), "time")
    if t < 0:
        raise _whirl.InputError(f"invalid `{name}`: `{value}`: a time must not be negative")
    return t


def _frequency_hz(name: str, value: str | float) -> float:
    f = _whirl.parse_quantity(name, str(value), "frequency")
    if not (math.isfinite(f) and f > 0):
        raise _whirl.InputError(f"invalid `{name}`: `{value}`: the frequency must be positive")
    return f


def default_speeds(model: Model) -> np.ndarray:
    """150 speeds over the model's operating range (from top / 150 when it starts at rest)."""
    operating = model.to_dict()["operating"]
    if operating is None:
        raise _whirl.InputError(
            "invalid `speeds`: the model states no operating speed range\n"
            "  help: give the speeds, e.g. speeds=\"1:750Hz:150\", or add [operating] to the model"
        )
    low, high = operating
    low = low if low > 0 else high / DEFAULT_SPEEDS
    return _whirl.parse_speeds(f"{low!r}:{high!r}:{DEFAULT_SPEEDS}")


def options(
    model: Model,
    speeds: _options.Speeds = None,
    *,
    settle: str | float = "0.5s",
    settle_max: str | float = "4s",
    start: str = "static",
    no_refine: bool = False,
    refine_budget: int = _whirl.DEFAULT_MAX_ADDED,
    refine_spacing: str | float = "0.5Hz",
    record: str | float = "0.5s",
    max_records: int = _whirl.DEFAULT_MAX_RECORDS,
    average_tolerance: float = _whirl.DEFAULT_RELATIVE_ERROR,
    contact: str | None = None,
    reduce: int = _whirl.DEFAULT_MODES,
    full_model: bool = False,
    step: str | float | None = None,
    node: int | None = None,
    component: str = "uy",
    window: str = "hann",
    max_frequency: str | float | None = None,
    tolerance: float = _whirl.DEFAULT_TOLERANCE_BINS,
    full: bool = False,
) -> dict[str, Any]:
    """The cascade's options as the library takes them, from the command line's options
    (same names, same defaults; times and frequencies as text with a unit or as SI numbers)."""
    if speeds is None:
        w = default_speeds(model)
    else:
        w = _options.speeds(speeds, model, 0.0, DEFAULT_SPEEDS)
    if not (isinstance(tolerance, (int, float)) and math.isfinite(tolerance) and tolerance >= 0):
        raise _whirl.InputError(
            f"invalid `tolerance`: `{tolerance}` is not a number of bins (0 or more, e.g. 2)"
        )
    return {
        "speeds": [float(x) for x in w],
        "settle": _time("settle", settle),
        "settle_max": _time("settle_max", settle_max),
        "start": start,
        "refine": not no_refine,
        "refine_budget": int(refine_budget),
        "refine_spacing_hz": _frequency_hz("refine_spacing", refine_spacing),
        "record": _time("record", record),
        "max_records": int(max_records),
        "average_tolerance": float(average_tolerance),
        "contact": contact,
        "reduce": None if full_model else _options.mode_count(reduce, "reduce"),
        "step": None if step is None else _time("step", step),
        "node": node,
        "component": component,
        "window": window,
        "max_frequency_hz": None if max_frequency is None else _frequency_hz("max_frequency", max_frequency),
        "tolerance": float(tolerance),
        "full": bool(full),
    }


@dataclass(frozen=True)
class CascadeResult:
    """A computed cascade: per speed the spectrum of the analysed displacement and the
    largest non-synchronous peak (NSV), classified; and the NSV summary."""

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
    #: Per speed, the classified NSV (class, explanation, direction, peak) or None.
    nsv: list[dict[str, Any] | None]
    #: The NSV in a few numbers (onsets, largest, statistics, classes).
    summary: dict[str, Any]
    #: The library's options and the step, sampling and band they resolve to.
    options: dict[str, Any]
    resolved: dict[str, Any]
    contact: str
    window: str
    #: Speeds loaded from the checkpoint rather than computed.
    resumed: int
    wall_time_s: float
    #: The checkpoint folder of this cascade, when there was one.
    checkpoint: str | None
    #: With ``compare_starts=True``: the cascade again from the other start at the same
    #: speeds, compared speed by speed (other_start, compared_speeds, differing_speeds_hz,
    #: sigmas, other_start_nsv, and per speed the ``pairs``); else None.
    starts: dict[str, Any] | None = None
    tables: ClassVar[tuple[str, ...]] = ("cascade", "nsv")

    def to_pandas(self, table: str = "nsv"):
        """``nsv`` (one row per speed: 1X, the NSV with its class and whirl direction, ...),
        ``cascade`` (speed_hz, frequency_hz, amplitude_m, added: every speed's spectrum),
        ``full_cascade`` (with ``full=True``) or ``starts`` (with ``compare_starts=True``:
        per speed the NSV and its standard error from both starts, whether they could be
        compared and whether they differ): the command line's CSV tables."""
        import pandas as pd

        added = np.array([int(p["added"]) for p in self.points])
        if table in ("cascade", "full_cascade"):
            f, a = (
                (self.frequency_hz, self.amplitude)
                if table == "cascade"
                else (self.full_frequency_hz, self.full_amplitude)
            )
            bins = len(f)
            return pd.DataFrame(
                {
                    "speed_hz": np.repeat(self.speeds_hz, bins),
                    "frequency_hz": np.tile(f, len(self.points)),
                    "amplitude_m": a.reshape(-1),
                    "added": np.repeat(added, bins),
                }
            )
        if table == "nsv":
            rows = []
            for p, n in zip(self.points, self.nsv):
                peak = None if n is None else n["peak"]
                cell = lambda key: None if peak is None else peak[key]  # noqa: E731
                rows.append(
                    [
                        p["speed_hz"], int(p["added"]), int(p["settled"]), p["settle_s"],
                        p["records"], p["one_x_m"], cell("frequency_hz"), cell("amplitude_m"),
                        cell("order"), None if n is None else n["class"],
                        None if n is None else n["direction"], cell("forward_m"),
                        cell("backward_m"), cell("decay_ratio"), cell("settling_ratio"),
                        cell("standard_error_m"), cell("variation"),
                        None if n is None else n["explanation"], p["diverged"], p["start_fallback"],
                    ]
                )
            return pd.DataFrame(rows, columns=NSV_COLUMNS)
        if table == "starts" and self.starts is not None:
            rows = [
                [p["speed_hz"], p["first_m"], p["first_error_m"], p["other_m"], p["other_error_m"],
                 int(p["comparable"]), int(p["differs"])]
                for p in self.starts["pairs"]
            ]
            return pd.DataFrame(rows, columns=STARTS_COLUMNS)
        raise ValueError(
            f"no table `{table}`: choose cascade, nsv, full_cascade (full=True) or starts "
            "(compare_starts=True)"
        )

    def to_dict(self) -> dict[str, Any]:
        """The command line's summary.json (without the output folder, the file list and
        the notes that explain its fields)."""
        o, r = self.options, self.resolved
        s = head("cascade", self.model)
        s.update(
            speeds=len(self.points),
            speed_range_hz=[float(self.speeds_hz.min()), float(self.speeds_hz.max())],
            contact=self.contact,
            reduction_modes=o["reduction"],
            node=o["node"],
            component=o["component"],
            settle_s=o["settle"],
            settle_max_s=o["settle_max"],
            start=o["initial"],
            refinement=o["refine"],
            record_s=o["record"],
            averaging=o["averaging"],
            step_s=r["step"],
            sample_interval_s=1.0 / r["sample_rate_hz"],
            samples_per_record=r["samples"],
            window=self.window,
            resolution_hz=r["resolution_hz"],
            max_frequency_hz=r["max_frequency_hz"],
            tolerance_bins=o["tolerance_bins"],
            full_spectrum=o["full"],
            nsv=self.summary,
            resumed_speeds=self.resumed,
            wall_time_s=self.wall_time_s,
            checkpoint_folder=self.checkpoint,
        )
        if self.starts is not None:
            s["starts"] = {k: v for k, v in self.starts.items() if k != "pairs"}
        return jsonable(s)


NSV_COLUMNS = [
    "speed_hz", "added", "settled", "settle_s", "records", "one_x_m", "nsv_frequency_hz",
    "nsv_amplitude_m", "nsv_order", "class", "direction", "forward_m", "backward_m",
    "decay_ratio", "settling_ratio", "nsv_standard_error_m", "nsv_variation", "explanation",
    "diverged", "start_fallback",
]

STARTS_COLUMNS = [
    "speed_hz", "nsv_m", "nsv_standard_error_m", "other_start_nsv_m",
    "other_start_standard_error_m", "comparable", "differs",
]


def _result(
    model: Model, raw: dict[str, Any], checkpoint: Path | None, starts: dict[str, Any] | None = None
) -> CascadeResult:
    c = raw["cascade"]
    points = c["points"]
    bins, full_bins = len(c["frequency_hz"]), len(c["full_frequency_hz"])
    spectra = lambda key, n: np.array(  # noqa: E731
        [p[key] if len(p[key]) == n else [math.nan] * n for p in points], dtype=float
    ).reshape(len(points), n)
    return CascadeResult(
        model=model,
        speeds_hz=np.array([p["speed_hz"] for p in points], dtype=float),
        frequency_hz=np.asarray(c["frequency_hz"], dtype=float),
        amplitude=spectra("amplitude", bins),
        full_frequency_hz=np.asarray(c["full_frequency_hz"], dtype=float),
        full_amplitude=spectra("full_amplitude", full_bins),
        points=[{k: v for k, v in p.items() if k not in ("amplitude", "full_amplitude")} for p in points],
        nsv=c["nsv"],
        summary=raw["nsv"],
        options=c["options"],
        resolved=c["resolved"],
        contact=raw["contact"],
        window=raw["window"],
        resumed=c["resumed"],
        wall_time_s=c["wall_time_s"],
        checkpoint=None if checkpoint is None else str(checkpoint),
        starts=starts,
    )


def cascade(
    model: Model | str | os.PathLike[str],
    speeds: _options.Speeds = None,
    *,
    threshold: str | float = _whirl.DEFAULT_THRESHOLD_M,
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
        threshold: NSV amplitude (zero-to-peak) from which a speed counts in the summary.
        checkpoint: a folder (shared by the workers, with ``client``) in which each
            finished speed is kept, in ``<checkpoint>/<key>`` (one folder per model and
            options): a run started again computes only the missing speeds and gives the
            same result. The command line uses ``out/cascade.partial``.
        restart: delete this cascade's checkpoint first and compute every speed again.
        compare_starts: run every speed again from the other start (rest after the static
            equilibrium, or the reverse) and mark the speeds where the NSV differs beyond
            three standard errors: coexisting motions (:attr:`CascadeResult.starts`, the
            table ``starts``; twice the computing). Its checkpoint sits beside this one's.
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
            ``max_frequency``, ``tolerance``, ``full``); see :func:`options`.
    """
    model = as_model(model)
    o = options(model, speeds, **cascade_options)
    threshold_m = _whirl.parse_quantity("threshold", str(threshold), "length")
    if not threshold_m > 0:
        raise _whirl.InputError(f"invalid `threshold`: `{threshold}`: the length must be positive")
    first = _run(model, o, threshold_m, checkpoint, restart, progress, client)
    starts = None
    if compare_starts:
        other = {**o, **_whirl.other_start(first["raw"])}
        second = _run(model, other, threshold_m, checkpoint, restart, progress, client)
        starts = _whirl.compare_starts(first["raw"], second["raw"], threshold_m)
    return _result(model, first, first["folder"], starts)


def _run(
    model: Model,
    o: dict[str, Any],
    threshold_m: float,
    checkpoint: str | os.PathLike[str] | None,
    restart: bool,
    progress: bool | Any,
    client: Any,
) -> dict[str, Any]:
    """One cascade with the library's options ``o``, in its folder inside ``checkpoint``."""
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
        raw = _whirl.cascade(
            model._raw, o, threshold_m, None if folder is None else os.fspath(folder), report, runner
        )
    return {**raw, "folder": folder}
