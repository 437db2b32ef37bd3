"""The analyses whose results the library reports whole: each returns a
:class:`whirl.Report` (``to_dict()``, ``to_pandas(table)``) equal to the command line's
summary.json and CSV tables."""

from __future__ import annotations

import os
from collections.abc import Sequence


from . import _options, _progress, _whirl
from .model import Model, as_model
from .report import Report
from .response import report_nodes


def reduce(
    model: Model | str | os.PathLike[str],
    *,
    modes: int | None = None,
    nodes: Sequence[int] = (),
) -> Report:
    """The Craig-Bampton reduction (``whirl reduce``): the reduced model with ``modes``
    fixed-interface modes against the full model, and a study over 1 to max(24, 2 x modes)
    modes.

    Args:
        model: a :class:`Model` or a model file path.
        modes: fixed-interface modes of the reduced model reported (1-200; default 12).
        nodes: nodes added to the boundary besides the bearing nodes.

    Returns:
        A :class:`whirl.Report` with the tables ``reduce`` (the full and reduced natural
        frequencies and their relative errors) and ``study`` (per number of modes its
        coordinates, stable step and errors), as the command line writes them.
    """
    model = as_model(model)
    boundary = report_nodes(model, nodes) if nodes else []
    raw = _whirl.reduce(model._raw, modes, boundary)
    return Report("reduce", model, raw)


def static(model: Model | str | os.PathLike[str], *, rollers: str | None = None) -> Report:
    """The static response under gravity (``whirl static``): deflection, slope, bending
    moment and shear along the shaft, the bearing reactions and the roller loads.

    Args:
        model: a :class:`Model` or a model file path.
        rollers: how roller bearings carry the load: ``hertz`` (their contacts, the
            default) or ``linear`` (their linear stiffness).

    Returns:
        A :class:`whirl.Report` with the command line's tables ``stations`` (per node),
        ``reactions`` and, with roller bearings, ``rollers``.
    """
    model = as_model(model)
    return Report("static", model, _whirl.statics(model._raw, rollers))


def stiffness(
    model: Model | str | os.PathLike[str],
    *,
    bearing: int | None = None,
    clearances: str | Sequence[float | str] | None = None,
    load: str | float | None = None,
    load_angle: float | None = None,
    cage_angle: float | None = None,
    cage_steps: int | None = None,
    surface_clearances: str | Sequence[float | str] | None = None,
    grid: int | None = None,
) -> Report:
    """The equivalent stiffness of a roller bearing versus clearance and its
    force-deflection surfaces (``whirl stiffness``): per clearance the tangent at the
    frozen-cage equilibrium under the load, its average over one roller passage, and the
    tangent at one fixed journal displacement. Every option left ``None`` takes the
    library's default, the same as the command line's.

    Args:
        model: a :class:`Model` or a model file path.
        bearing: the roller bearing, numbered from 0 in file order.
        clearances: ``"10um:120um:12"`` (start:stop:count) or the values (plain numbers
            are m).
        load: the load the rotor puts on the bearing (``"60N"``, ``2000``); default the
            bearing's share of the rotor weight, from a linear static solve with gravity.
        load_angle: direction of ``load``, degrees from +x towards +y (-90 = down).
        cage_angle: angle of roller 0 of the frozen cage, degrees; default on the load line.
        cage_steps: cage positions across one roller passage for the averaged stiffness
            (1-1000).
        surface_clearances: clearances of the force-deflection surfaces, ``"20um,60um"`` or
            the values.
        grid: points per side of the surfaces' displacement grid (2-401), spanning twice the
            largest surface clearance each way.

    Returns:
        A :class:`whirl.Report` with the tables ``stiffness`` (one row per clearance),
        ``passage`` (per clearance and cage position) and ``surfaces_<clearance>`` (F_x,
        F_y, F_r on the grid), as the command line writes them.
    """
    model = as_model(model)
    options = {
        "bearing": bearing,
        "clearances": clearances,
        "load": load,
        "load_angle": load_angle,
        "cage_angle": cage_angle,
        "cage_steps": cage_steps,
        "surface_clearances": surface_clearances,
        "grid": grid,
    }
    return Report("stiffness", model, _whirl.stiffness(model._raw, options))


def ucs(
    model: Model | str | os.PathLike[str],
    *,
    stiffness: str | Sequence[float] | None = None,
    modes: int | None = None,
    at_rest: bool | None = None,
) -> Report:
    """The undamped critical-speed map (``whirl ucs``, API 684): the lowest critical speeds
    against a stiffness every bearing shares, and where the bearings' own stiffness cuts
    them. Every option left ``None`` takes the library's default, the same as the command
    line's.

    Args:
        model: a :class:`Model` or a model file path.
        stiffness: ``"1e5:1e10:51"`` (N/m, spaced logarithmically) or the values; default
            61 values from 1/100 of the softest bearing's stiffness to 100 times the
            stiffest's, widened to whole decades.
        modes: number of critical speeds (curves), 1-200 (default 4).
        at_rest: natural frequencies at rest instead of synchronous critical speeds (no
            gyroscopic moments).

    Returns:
        A :class:`whirl.Report` with the tables ``ucs`` and ``bearings``.
    """
    model = as_model(model)
    options = {"stiffness": stiffness, "modes": modes, "at_rest": at_rest}
    return Report("ucs", model, _whirl.ucs(model._raw, options))


def frf(
    model: Model | str | os.PathLike[str],
    input: str | tuple[int, str],
    *,
    output: str | Sequence[str | tuple[int, str]] | tuple[int, str] | None = None,
    speed: str | float | None = None,
    frequencies: _options.Speeds = None,
    force: str | float | None = None,
) -> Report:
    """Frequency response functions (``whirl frf``): receptance, mobility and accelerance
    from a harmonic force to displacements, at a spin speed.

    Args:
        model: a :class:`Model` or a model file path.
        input: where the force acts, ``"10:uy"`` or ``(10, "uy")`` (ux, uy, tx, ty).
        output: where the response is read; default the input DOF.
        speed: spin speed, ``"50Hz"``, ``"3000rpm"`` or rad/s (default rest).
        frequencies: excitation frequencies ``"0:500Hz:1001"`` or rad/s; default 1001 from
            0 to 1.5 x the sixth undamped natural frequency.
        force: amplitude of the harmonic force (``100``, ``"2kN"``; default 1 N), for the
            response columns.

    Returns:
        A :class:`whirl.Report` with the tables ``frf`` and ``peaks``.
    """
    model = as_model(model)
    options = {"input": input, "output": output, "speed": speed, "frequencies": frequencies, "force": force}
    raw = _whirl.frf(model._raw, options)
    return Report("frf", model, raw)


def fit_forcing(
    model: Model | str | os.PathLike[str],
    speeds: _options.Speeds,
    *,
    bearing: int | None = None,
    duration: str | float | None = None,
    settle: str | float | None = None,
    reduce: int | None = None,
    progress: bool | _progress.Report = True,
) -> Report:
    """The forcing-function law (thesis eq. 3.12) fitted to a roller bearing's Hertz
    response over speed (``whirl fit-forcing``).

    Args:
        model: a :class:`Model` or a model file path.
        speeds: spin speeds to fit at, ``"100Hz:500Hz:5"`` or rad/s; the law is meant for
            speeds inside this range.
        bearing: the roller bearing, numbered from 0 in file order (default the first).
        duration: simulated time per speed (default 0.3 s).
        settle: time discarded before sampling (default 0.2 s).
        reduce: Craig-Bampton fixed-interface modes (the bearing nodes are the boundary).
        progress: True for a tqdm bar when tqdm is installed, False, or ``progress(done,
            1000)`` told the share of the simulated time done (a true return stops it).

    Returns:
        A :class:`whirl.Report` with the fitted coefficients in its summary and the table
        ``fit`` (the samples and the law's force at each).
    """
    model = as_model(model)
    options = {"speeds": speeds, "bearing": bearing, "duration": duration, "settle": settle, "reduce": reduce}
    with _progress.display(progress, "fit-forcing", "permille") as report:
        raw = _whirl.fit_forcing(model._raw, options, report)
    return Report("fit-forcing", model, raw)
