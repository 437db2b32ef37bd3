"""Harmonic balance (``whirl hbm``): the periodic (synchronous) response of the rotor on its
roller bearings followed over speed by continuation, with Floquet stability and the
bifurcations where it changes."""

from __future__ import annotations

import math
import os
from collections.abc import Sequence

from . import _options, _progress, _whirl
from .model import Model, as_model
from .nsv import _time
from .report import Report
from .response import report_nodes

#: Harmonics of the running speed at most (the stability matrix grows with 2H + 1, its
#: cost with the cube of that): the library's limit, as on the command line.
MAX_HARMONICS = _whirl.MAX_HARMONICS

#: Time samples per period at most: 40 times the default (32 H) at the largest H, checked
#: before any buffer is made: the library's limit, as on the command line.
MAX_SAMPLES = _whirl.MAX_AFT_SAMPLES


def _harmonics(h: int, name: str = "harmonics") -> int:
    if isinstance(h, bool) or not isinstance(h, int) or not 1 <= h <= MAX_HARMONICS:
        raise _whirl.InputError(
            f"invalid `{name}`: `{h}`: a harmonic count is a whole number from 1 to {MAX_HARMONICS}"
        )
    return h


def _study(given: str | Sequence[int] | None) -> list[int]:
    """Harmonic counts of the study: ``"1..5"``, ``"1,3,5"`` or a list."""
    if given is None:
        return []
    if isinstance(given, str):
        if ".." in given:
            a, b = (int(x) for x in given.split("..", 1))
            if b < a:
                raise _whirl.InputError(f"invalid `harmonics_study`: `{given}`: the range must not run backwards")
            given = range(a, b + 1)
        else:
            given = [int(x) for x in given.split(",")]
    return [_harmonics(h, "harmonics_study") for h in given]


def _smoothing(given: str | float) -> float:
    """The contact smoothing length, m: 0 for the exact law, else positive."""
    length = _whirl.parse_quantity("contact_smoothing", str(given), "length")
    if not (math.isfinite(length) and length >= 0):
        raise _whirl.InputError(
            f"invalid `contact_smoothing`: `{given}`: the length must be positive, or 0 for the exact law"
        )
    return length


def _span(speeds: _options.Speeds, model: Model) -> tuple[float, float]:
    """First and last speed, rad/s: ``"1:750Hz"`` (a count, if given, is ignored), numbers,
    or 1 Hz to 1.2 x the model's top operating speed."""
    if isinstance(speeds, str) and speeds.count(":") == 1:
        speeds += ":2"
    w = _options.speeds(speeds, model, 2.0 * math.pi, 2)
    if not (len(w) >= 2 and 0 < w[0] < w[-1]):
        raise _whirl.InputError(
            "invalid `speeds`: harmonic balance needs a rising range of positive speeds, e.g. \"1:750Hz\""
        )
    return float(w[0]), float(w[-1])


def hbm(
    model: Model | str | os.PathLike[str],
    speeds: _options.Speeds = None,
    *,
    harmonics: int = 5,
    nodes: Sequence[int] | None = None,
    contact: str = "hertz",
    cage: str = "passage",
    cage_positions: int = _whirl.DEFAULT_CAGE_POSITIONS,
    contact_smoothing: str | float = 0.0,
    samples: int | None = None,
    reduce: int | None = None,
    no_stability: bool = False,
    stability_modes: int = _whirl.DEFAULT_STABILITY_MODES,
    compare_time: Sequence[str | float] = (),
    settle: str | float = "0.5s",
    record: str | float = "0.5s",
    harmonics_study: str | Sequence[int] | None = None,
    progress: bool | _progress.Report = True,
) -> Report:
    """The periodic response by harmonic balance over speed (``whirl hbm``), with the
    command line's options and defaults.

    Args:
        model: a :class:`Model` or a model file path.
        speeds: the range ``"1:750Hz"`` (continuation chooses its steps) or speeds in
            rad/s (the first and last are used); default 1 Hz to 1.2 x the model's top
            operating speed.
        harmonics: harmonics H of the running speed (1 to 50).
        nodes: nodes whose harmonics the ``branch`` table gives; the first is compared
            and studied; default every disk and bearing node, disks first.
        contact: ``hertz`` or ``forcing`` (harmonic balance needs a force law of the
            displacement).
        cage: how the roller passage is made periodic (Hertz only): ``passage`` (the force
            averaged over ``cage_positions`` cage positions per roller pitch) or
            ``frozen``.
        contact_smoothing: approach below which the Hertz law is blended to bounded
            curvature (harmonic balance only; docs/theory.md section 7), ``"0.01um"`` or
            metres; 0 (the default) for the exact law.
        samples: time samples per period of the alternating frequency-time transform;
            default 32 H, at least 64.
        reduce: solve on a Craig-Bampton model with this many fixed-interface modes;
            default the full model.
        no_stability: skip the Floquet stability (faster; no bifurcations).
        stability_modes: fixed-interface modes of the stability model.
        compare_time: speeds (``"100Hz"`` or rad/s) at which to run the time integrator
            (``settle``, then ``record`` analysed) and compare its settled amplitudes with
            every harmonic-balance solution there: the table ``compare_time``.
        harmonics_study: repeat the sweep (without stability) for these harmonic counts,
            ``"1..5"`` or ``[1, 3, 5]``: the table ``harmonics_study``.
        progress: True for a tqdm bar when tqdm is installed, False, or ``progress(done,
            1000)`` told each sweep's fraction of the speed range (a true return stops it).

    Returns:
        A :class:`whirl.Report` with the tables ``branch`` (one row per continuation
        point in path order: speed, stability, largest real part of the Floquet
        exponents, iterations, and per node the amplitude of each harmonic of u_x and
        u_y), ``bifurcations``, and ``compare_time`` and ``harmonics_study`` when asked.
    """
    model = as_model(model)
    h = _harmonics(harmonics)
    if samples is not None and not 2 * h < samples <= MAX_SAMPLES:
        raise _whirl.InputError(
            f"invalid `samples`: {samples} samples per period: the transform needs more than "
            f"2 H = {2 * h} and at most {MAX_SAMPLES}\n  help: leave it out for the default (32 H, at least 64)"
        )
    chosen = report_nodes(model, nodes)
    if not nodes:
        # Disks first: the first node is the one compared and studied.
        disks = {d["station"]["node"] for d in model.to_dict()["disks"]}
        chosen.sort(key=lambda n: n not in disks)
    start, stop = _span(speeds, model)
    options = {
        "from": start,
        "to": stop,
        "harmonics": h,
        "nodes": chosen,
        "contact": contact,
        "cage": cage,
        "cage_positions": _options.mode_count(cage_positions, "cage_positions"),
        "contact_smoothing": _smoothing(contact_smoothing),
        "samples": samples,
        "reduce": None if reduce is None else _options.mode_count(reduce, "reduce"),
        "stability": not no_stability,
        "stability_modes": _options.mode_count(stability_modes, "stability_modes"),
        "compare_time": [_whirl.parse_speed(str(w)) for w in compare_time],
        "settle": _time("settle", settle),
        "record": _time("record", record),
        "harmonics_study": _study(harmonics_study),
    }
    with _progress.display(progress, "hbm", "permille") as report:
        raw = _whirl.hbm(model._raw, options, report)
    return Report("hbm", model, raw)
