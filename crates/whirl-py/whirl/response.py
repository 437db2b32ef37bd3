"""Steady responses of the linearised rotor: the unbalance response (``whirl unbalance``)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from . import _options, _whirl
from .model import Model, as_model
from .report import Report, Reported


@dataclass(frozen=True)
class ResponsePeak:
    """A resonance peak of an orbit's major semi-axis over speed."""

    speed_hz: float
    #: Major semi-axis at the peak, m.
    amplitude: float
    #: Half-power speeds (N1, N2), Hz, when both lie in the sweep.
    half_power_hz: tuple[float, float] | None
    #: Amplification factor Nc / (N2 - N1).
    amplification_factor: float | None
    #: Separation margin API 617 requires, percent.
    required_margin_pct: float | None
    #: Actual margin from the operating range, percent (negative inside it).
    actual_margin_pct: float | None
    #: Whether the margin meets API 617 (None without a range, or when not applicable).
    meets_api617: bool | None


@dataclass(frozen=True)
class NodeResponse:
    """The unbalance response at one node over the speeds."""

    node: int
    #: Axial position, m.
    z: float
    #: Amplitudes (m, zero-to-peak) and phases (degrees) of ux and uy.
    ux_amplitude: np.ndarray
    ux_phase_deg: np.ndarray
    uy_amplitude: np.ndarray
    uy_phase_deg: np.ndarray
    #: Orbit semi-axes, m.
    major: np.ndarray
    minor: np.ndarray
    #: Whirl direction of the orbit at each speed.
    whirl: list[str]
    peaks: list[ResponsePeak]
    #: Speeds, Hz, of local maxima of the major semi-axis within the curve's round-off,
    #: which are no peaks (fine meshes; one at a resonance means its top is lost).
    maxima_within_round_off_hz: np.ndarray


@dataclass(frozen=True, repr=False)
class UnbalanceResult(Reported):
    """The steady unbalance response (``whirl unbalance``): per node the amplitude and phase
    of ux and uy and the orbit's semi-axes over speed, and the resonance peaks with their
    amplification factors and API 617 separation margins."""

    model: Model
    #: Spin speeds, Hz (uneven: speeds are added inside each peak's half-power band).
    speeds_hz: np.ndarray
    nodes: list[NodeResponse]
    #: Operating speed range, Hz, when the model gives one.
    operating_hz: tuple[float, float] | None
    #: Why the API 617 margins were not assessed, when they mean nothing for the range.
    api617_note: str | None
    #: The library's report: tables ``unbalance`` and ``peaks``, the summary.
    report: Report

    def node(self, node: int) -> NodeResponse:
        """The response at node ``node``."""
        for r in self.nodes:
            if r.node == node:
                return r
        raise KeyError(f"node {node} was not reported: the nodes are {[r.node for r in self.nodes]}")

    @property
    def api617_status(self) -> str:
        """"assessed", why the margins are not applicable, or that there is no range."""
        if self.api617_note is not None:
            return self.api617_note
        if self.operating_hz is not None:
            return "assessed"
        return (
            "no operating range: give [operating] min_speed and max_speed to assess "
            "separation margins"
        )


def report_nodes(model: Model, given: Sequence[int] | None) -> list[int]:
    """The nodes to report: those given (checked, repeats removed, in order), or every disk
    and bearing node, ascending."""
    last = model.node_count - 1
    if not given:
        m = model.to_dict()
        nodes = sorted({d["station"]["node"] for d in m["disks"]} | set(model.bearing_nodes()))
        if not nodes:
            raise _whirl.InputError(
                "invalid `nodes`: the model has no disk or bearing to report by default\n"
                "  help: give the nodes to report, e.g. nodes=[0, 10]"
            )
        return nodes
    nodes: list[int] = []
    for n in given:
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 0 <= n <= last:
            raise _whirl.InputError(
                f"invalid `nodes`: node {n} is not on the shaft\n"
                f"  help: nodes are numbered 0 (z = 0) to {last} (z = {model.length} m)"
            )
        if int(n) not in nodes:
            nodes.append(int(n))
    return nodes


def unbalance(
    model: Model | str | os.PathLike[str],
    speeds: _options.Speeds = None,
    *,
    nodes: Sequence[int] | None = None,
) -> UnbalanceResult:
    """The steady unbalance response (``whirl unbalance``).

    Args:
        model: a :class:`Model` or a model file path.
        speeds: a range ``"1:800Hz:800"`` or numbers in rad/s; default 800 speeds from 1 Hz
            to 1.2 x the model's top operating speed. Speeds are added inside each peak's
            half-power band until it holds 40 steps.
        nodes: nodes to report; default every disk and bearing node.
    """
    model = as_model(model)
    raw, report = _whirl.unbalance(
        model._raw,
        _options.speeds(speeds),
        report_nodes(model, nodes),
    )
    return UnbalanceResult(
        model=model,
        speeds_hz=np.asarray(raw["speeds_hz"], dtype=float),
        nodes=[
            NodeResponse(
                node=r["node"],
                z=r["z"],
                **{k: np.asarray(r[k], dtype=float) for k in _ARRAYS},
                whirl=list(r["whirl"]),
                peaks=[ResponsePeak(**p) for p in r["peaks"]],
                maxima_within_round_off_hz=np.asarray(
                    r["maxima_within_round_off_hz"], dtype=float
                ),
            )
            for r in raw["nodes"]
        ],
        operating_hz=None if raw["operating_hz"] is None else tuple(raw["operating_hz"]),
        api617_note=raw["api617_note"],
        report=Report("unbalance", model, report),
    )


_ARRAYS = ("ux_amplitude", "ux_phase_deg", "uy_amplitude", "uy_phase_deg", "major", "minor")
