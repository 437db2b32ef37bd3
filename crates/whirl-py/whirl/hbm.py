"""Harmonic balance (``whirl hbm``): the periodic (synchronous) response of the rotor on its
roller bearings followed over speed by continuation, with Floquet stability and the
bifurcations where it changes."""

from __future__ import annotations

import os
from collections.abc import Sequence

from . import _options, _progress, _whirl
from .model import Model, as_model
from .report import Report

#: Harmonics of the running speed at most (the stability matrix grows with 2H + 1, its
#: cost with the cube of that): the library's limit, as on the command line.
MAX_HARMONICS = _whirl.MAX_HARMONICS

#: Time samples per period at most: 40 times the default (32 H) at the largest H, checked
#: before any buffer is made: the library's limit, as on the command line.
MAX_SAMPLES = _whirl.MAX_AFT_SAMPLES


def hbm(
    model: Model | str | os.PathLike[str],
    speeds: _options.Speeds = None,
    *,
    harmonics: int | None = None,
    nodes: Sequence[int] | None = None,
    contact: str | None = None,
    cage: str | None = None,
    cage_positions: int | None = None,
    contact_smoothing: str | float | None = None,
    samples: int | None = None,
    reduce: int | None = None,
    no_stability: bool | None = None,
    stability_modes: int | None = None,
    compare_time: Sequence[str | float] | None = None,
    settle: str | float | None = None,
    record: str | float | None = None,
    harmonics_study: str | Sequence[int] | None = None,
    progress: bool | _progress.Report = True,
) -> Report:
    """The periodic response by harmonic balance over speed (``whirl hbm``), with the
    command line's options; every option left None takes the library's default.

    Args:
        model: a :class:`Model` or a model file path.
        speeds: the range ``"1:750Hz"`` (continuation chooses its steps) or speeds in
            rad/s (the first and last are used); default 1 Hz to 1.2 x the model's top
            operating speed.
        harmonics: harmonics H of the running speed (1 to 50).
        nodes: nodes whose harmonics the ``branch`` table gives; the first is compared
            and studied; default every disk and bearing node, disks first.
        contact: ``hertz`` (default) or ``forcing`` (harmonic balance needs a force law of
            the displacement).
        cage: how the roller passage is made periodic (Hertz only): ``passage`` (the force
            averaged over ``cage_positions`` cage positions per roller pitch; the
            default) or ``frozen``.
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
    # The keywords given (the parameters, read before any local is made), as the library
    # reads them.
    given = {k: v for k, v in locals().items() if k not in ("model", "progress") and v is not None}
    with _progress.display(progress, "hbm", "permille") as report:
        raw = _whirl.hbm(model._raw, given, report)
    return Report("hbm", model, raw)
