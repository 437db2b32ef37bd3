"""Steady responses of the linearised rotor: the unbalance response (``whirl unbalance``)."""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from . import _options, _whirl
from ._summary import head
from .model import Model, as_model


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


@dataclass(frozen=True)
class UnbalanceResult:
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
    #: Table names of :meth:`to_pandas`.
    tables: ClassVar[tuple[str, ...]] = ("unbalance", "peaks")

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

    def to_pandas(self, table: str = "unbalance"):
        """``unbalance`` (one row per speed; per node ``n{node}_`` amplitudes, phases,
        semi-axes, whirl) or ``peaks``: the command line's CSV tables."""
        import pandas as pd

        if table == "unbalance":
            columns: dict[str, Any] = {"speed_hz": self.speeds_hz, "speed_rpm": 60.0 * self.speeds_hz}
            for r in self.nodes:
                n = f"n{r.node}_"
                columns[n + "ux_amplitude_m"] = r.ux_amplitude
                columns[n + "ux_phase_deg"] = r.ux_phase_deg
                columns[n + "uy_amplitude_m"] = r.uy_amplitude
                columns[n + "uy_phase_deg"] = r.uy_phase_deg
                columns[n + "major_semi_axis_m"] = r.major
                columns[n + "minor_semi_axis_m"] = r.minor
                columns[n + "whirl"] = r.whirl
            return pd.DataFrame(columns)
        if table == "peaks":
            rows = []
            for r in self.nodes:
                for p in r.peaks:
                    low, high = p.half_power_hz if p.half_power_hz is not None else (None, None)
                    if p.meets_api617 is not None:
                        meets: Any = p.meets_api617
                    else:
                        meets = "not applicable" if self.api617_note is not None else None
                    rows.append(
                        [r.node, r.z, p.speed_hz, 60.0 * p.speed_hz, p.amplitude, low, high,
                         p.amplification_factor, p.required_margin_pct, p.actual_margin_pct, meets]
                    )
            return pd.DataFrame(
                rows,
                columns=[
                    "node", "z_m", "speed_hz", "speed_rpm", "major_semi_axis_m",
                    "half_power_low_hz", "half_power_high_hz", "amplification_factor",
                    "api617_required_margin_pct", "api617_actual_margin_pct", "meets_api617",
                ],
            )
        raise ValueError(f"no table `{table}`: choose one of {self.tables}")

    def to_dict(self) -> dict[str, Any]:
        """The command line's summary.json (without the output folder and file list)."""
        s = self.speeds_hz
        summary = head("unbalance", self.model)
        summary.update(
            speed_range_hz=[float(s[0]), float(s[-1])] if len(s) else [None, None],
            speed_count=len(s),
            operating_speed_hz=None if self.operating_hz is None else list(self.operating_hz),
            api617_status=self.api617_status,
            nodes=[_node_summary(r, s) for r in self.nodes],
        )
        return summary


def _node_summary(r: NodeResponse, speeds_hz: np.ndarray) -> dict[str, Any]:
    k, largest = _largest(r.major)
    return {
        "node": r.node,
        "z_m": r.z,
        "max_major_semi_axis_m": None if math.isnan(largest) else largest,
        "max_major_semi_axis_speed_hz": float(speeds_hz[k]) if k < len(speeds_hz) else None,
        "peaks": [
            {
                "speed_hz": p.speed_hz,
                "speed_rpm": 60.0 * p.speed_hz,
                "major_semi_axis_m": p.amplitude,
                "half_power_hz": None if p.half_power_hz is None else list(p.half_power_hz),
                "amplification_factor": p.amplification_factor,
                "api617_required_margin_pct": p.required_margin_pct,
                "api617_actual_margin_pct": p.actual_margin_pct,
                "meets_api617": p.meets_api617,
            }
            for p in r.peaks
        ],
    }


def _largest(values: np.ndarray) -> tuple[int, float]:
    """The index and value of the largest entry: the first of equals, NaN when all are."""
    k, best = 0, math.nan
    for i, v in enumerate(values.tolist()):
        if v > best or math.isnan(best):
            k, best = i, v
    return k, best


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
    raw = _whirl.unbalance(
        model._raw,
        _options.speeds(speeds, model, 2.0 * math.pi, 800),
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
            )
            for r in raw["nodes"]
        ],
        operating_hz=None if raw["operating_hz"] is None else tuple(raw["operating_hz"]),
        api617_note=raw["api617_note"],
    )


_ARRAYS = ("ux_amplitude", "ux_phase_deg", "uy_amplitude", "uy_phase_deg", "major", "minor")
