"""The NSV map (``whirl map``): where the rotor's synchronous orbit is unstable over speed
and one model parameter, by which bifurcation, where resonance lines give non-synchronous
vibration on a stable orbit, and how well that explains cascades run beside it."""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Any

from . import _progress, _whirl
from .model import Model, as_model
from .report import Report


def map(  # noqa: A001 - the command's name
    model: Model | str | os.PathLike[str],
    values: str | Sequence[str | float],
    speeds: str | Sequence[float] | None = None,
    *,
    parameter: str | None = None,
    harmonics: int | None = None,
    samples: int | None = None,
    contact: str | None = None,
    cage: str | None = None,
    cage_positions: int | None = None,
    contact_smoothing: str | float | None = None,
    stability_modes: int | None = None,
    reduce: int | None = None,
    clear_below: str | float | None = None,
    check: str | Sequence[str | float] | None = None,
    check_level: str | float | None = None,
    confirm: bool | None = None,
    progress: bool | _progress.Report = True,
    client: Any = None,
) -> Report:
    """The NSV map (``whirl map``): one harmonic-balance sweep with Floquet stability per
    value of a model parameter. Every option left ``None`` takes the library's default, the
    same as the command line's; the library reads each, as the command line's flags.

    Args:
        model: a :class:`Model` or a model file path.
        values: the parameter's values as the model file writes them, ``"10um,20um,60um"``
            or a list (``["20 um", "60 um"]``, ``[12, 16]``).
        speeds: the range ``"1:750Hz"`` or speeds in rad/s (the first and last are used);
            default 1 Hz to 1.2 x the model's top operating speed.
        parameter: the parameter's path as a study file writes it, default
            ``roller_bearing[*].clearance``.
        harmonics, samples, contact, cage, cage_positions, contact_smoothing,
            stability_modes, reduce: the sweeps' discretisation and bearing model, as
            :func:`whirl.hbm` takes them.
        clear_below: the design query's speed (``"600Hz"`` or rad/s): which values keep
            the orbit free of unstable bands below it.
        check: values (among ``values``) at which the default cascade is run over the
            map's range and compared with the map.
        check_level: the check's NSV level, ``"10um"`` or metres (default 10 um).
        confirm: run the default cascade of the largest value clear below
            ``clear_below``, up to that speed, and report whether its NSV stays below the
            check level (the summary's ``confirmation``).
        progress: True for a tqdm bar when tqdm is installed, False, or ``progress(done,
            1000)`` told the share of the values done (a true return stops it).
        client: a ``dask.distributed.Client``: each value's sweep is one task on its
            workers (the checks' and the confirmation's cascades run here); the map is
            the same to the bit as on this machine.

    Returns:
        A :class:`whirl.Report` with the tables ``bands`` (one row per unstable band),
        ``lines`` (one row per resonance line), ``values`` (per value: first loss of
        stability, cost) and ``checks`` (per checked value), and the summary (the
        disagreements with each cascade speed by speed).
    """
    model = as_model(model)
    sweep = {
        "speeds": speeds,
        "harmonics": harmonics,
        "samples": samples,
        "contact": contact,
        "cage": cage,
        "cage_positions": cage_positions,
        "contact_smoothing": contact_smoothing,
        "stability_modes": stability_modes,
        "reduce": reduce,
    }
    options = {
        "parameter": parameter,
        "values": values,
        "clear_below": clear_below,
        "check": check,
        "check_level": check_level,
        "confirm": confirm,
    }
    runner = None
    if client is not None:
        from .dask import value_runner

        runner = value_runner(client, model, options, sweep)
    with _progress.display(progress, "map", "permille") as report:
        raw = _whirl.map(model._raw, options, sweep, report, runner)
    return Report("map", model, raw)
