"""Linear analyses of the rotor: ``check``, the Campbell diagram, mesh convergence and the
modes at a speed; their summaries and tables are the library's reports."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from . import _options, _whirl
from .model import Model, as_model
from .report import Report, Reported


class CheckResult(Report):
    """The model as read and summarised by ``whirl check``: mesh, masses, supports and the
    first six undamped natural frequencies (tables ``frequencies`` and ``nodes``)."""

    __slots__ = ()

    @property
    def frequencies_hz(self) -> np.ndarray:
        """The first six undamped natural frequencies of the rotor at rest, Hz."""
        return self.columns("frequencies")["frequency_hz"]


def check(model: Model | str | os.PathLike[str]) -> CheckResult:
    """Validates and summarises a model (``whirl check``): mesh, masses, supports and the
    first six undamped natural frequencies of the linearised rotor at rest."""
    model = as_model(model)
    return CheckResult("check", model, _whirl.check(model._raw))


@dataclass(frozen=True)
class Branch:
    """One whirl branch of a Campbell diagram, followed over the speeds."""

    #: ``1F`` is the lowest forward branch, ``1B`` the lowest backward one.
    label: str
    #: Branch number, 0-based, by frequency at the first speed.
    index: int
    #: Whirl direction at the highest speed: forward, backward or mixed.
    whirl: str
    #: Damped frequency at each speed, Hz (NaN where the branch was lost).
    frequency_hz: np.ndarray
    #: Damping ratio at each speed.
    damping_ratio: np.ndarray
    #: Logarithmic decrement at each speed.
    log_decrement: np.ndarray
    #: Whirl direction at each speed.
    whirl_at: list[str]


@dataclass(frozen=True)
class CriticalSpeed:
    """A crossing of a branch with an excitation order."""

    speed_hz: float
    speed_rpm: float
    frequency_hz: float
    order: float
    #: The branch's label (``1F``).
    branch: str
    whirl: str
    damping_ratio: float


@dataclass(frozen=True, repr=False)
class CampbellResult(Reported):
    """A Campbell diagram (``whirl campbell``): whirl frequencies over speed, forward and
    backward branches, critical speeds where they cross the excitation orders."""

    model: Model
    #: Spin speeds, Hz.
    speeds_hz: np.ndarray
    #: The followed branches, ascending in frequency at the highest speed.
    branches: list[Branch]
    #: Excitation orders (1 = synchronous).
    orders: list[float]
    #: Critical speeds, ascending.
    critical_speeds: list[CriticalSpeed]
    #: Size of the modal basis (the DOF count when solved in full).
    basis_size: int
    #: The library's report: tables ``campbell`` and ``critical_speeds``, the summary.
    report: Report

    def branch(self, label: str) -> Branch:
        """The branch labelled ``label`` (``1F``, ``2B``, ...)."""
        for b in self.branches:
            if b.label == label:
                return b
        raise KeyError(f"no branch `{label}`: the branches are {[b.label for b in self.branches]}")


def campbell(
    model: Model | str | os.PathLike[str],
    speeds: _options.Speeds = None,
    *,
    modes: int | None = None,
    orders: Sequence[float] | float | None = None,
    full: bool | None = None,
) -> CampbellResult:
    """The Campbell diagram (``whirl campbell``). Every option left ``None`` takes the
    library's default, the same as the command line's.

    Args:
        model: a :class:`Model` or a model file path.
        speeds: spin speeds: a range ``"0:800Hz:161"`` (``rpm`` too), or numbers in rad/s;
            default 161 speeds from rest to 1.2 x the model's top operating speed (800 Hz
            when it states none).
        modes: number of whirl branches to follow (1-200; default 8).
        orders: excitation orders whose crossings are critical speeds (1 = synchronous,
            the default), each above 0 and at most 100.
        full: solve the full system at every speed instead of a basis of 2 x modes + 8
            undamped modes (slower; the basis keeps branches within 2e-4 of the full solve).
    """
    model = as_model(model)
    options = {"speeds": speeds, "modes": modes, "orders": orders, "full": full}
    raw = _whirl.campbell(model._raw, options)
    branches = [
        Branch(**{**b, "label": label, **_arrays(b, "frequency_hz", "damping_ratio", "log_decrement")})
        for b, label in zip(raw["branches"], raw["labels"])
    ]
    label = {b.index: b.label for b in branches}
    critical = [
        CriticalSpeed(**{**c, "branch": label.get(c["branch"], f"branch {c['branch']}")})
        for c in raw["critical_speeds"]
    ]
    return CampbellResult(
        model=model,
        speeds_hz=np.asarray(raw["speeds_hz"], dtype=float),
        branches=branches,
        orders=raw["orders"],
        critical_speeds=critical,
        basis_size=raw["basis_size"],
        report=Report("campbell", model, raw["report"]),
    )


def _arrays(raw: dict[str, Any], *names: str) -> dict[str, np.ndarray]:
    """The library's lists ``names`` of ``raw`` as float arrays."""
    return {name: np.asarray(raw[name], dtype=float) for name in names}


@dataclass(frozen=True, repr=False)
class ConvergenceResult(Reported):
    """Natural frequencies versus the number of beam elements (``whirl convergence``)."""

    model: Model
    #: Total element counts that could be meshed, ascending.
    element_counts: list[int]
    #: ``frequencies_hz[i, j]``: mode j on mesh i, Hz (NaN where the mesh lacks the mode).
    frequencies_hz: np.ndarray
    #: Relative change of each frequency from the previous mesh (0 for the first).
    relative_change: np.ndarray
    #: Number of modes each mesh has, at most the number asked for.
    modes_found: list[int]
    #: Element counts left out because a feature would not sit on a node.
    skipped: list[int]
    #: Modes asked for.
    modes_requested: int
    #: The library's report: table ``convergence``, the summary.
    report: Report

    @property
    def meshes_with_fewer_modes(self) -> list[tuple[int, int]]:
        """(element count, modes found) of each mesh with fewer modes than asked for."""
        return [
            (n, found)
            for n, found in zip(self.element_counts, self.modes_found)
            if found < self.modes_requested
        ]


def convergence(
    model: Model | str | os.PathLike[str],
    counts: Sequence[int] | None = None,
    *,
    modes: int | None = None,
) -> ConvergenceResult:
    """Natural frequencies versus the number of elements (``whirl convergence``, thesis
    fig. 2.8). Every option left ``None`` takes the library's default, the same as the
    command line's.

    Args:
        model: a :class:`Model` or a model file path.
        counts: total element counts, each shared among the sections in proportion to their
            lengths (1-10,000); default 2, 4, ..., 40. A mesh on which a disk or bearing would
            fall between nodes is skipped (``skipped``).
        modes: number of modes to follow (1-200; default 6).
    """
    model = as_model(model)
    raw, report = _whirl.convergence(model._raw, _counts(counts), modes)
    return ConvergenceResult(
        model=model,
        element_counts=raw["element_counts"],
        frequencies_hz=np.asarray(raw["frequencies_hz"], dtype=float),
        relative_change=np.asarray(raw["relative_change"], dtype=float),
        modes_found=raw["modes_found"],
        skipped=raw["skipped"],
        modes_requested=raw["modes_requested"],
        report=Report("convergence", model, report),
    )


def _counts(given: Sequence[int] | None) -> list[int]:
    """Element counts as whole numbers (the library checks their range; none for its
    default)."""
    counts = list(given or [])
    for n in counts:
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise _whirl.InputError(f"invalid `counts`: `{n}` is not a whole number of elements")
    return [int(n) for n in counts]


@dataclass(frozen=True, repr=False)
class ModalResult(Reported):
    """Undamped modes and damped whirl modes at a speed (``whirl modal``)."""

    model: Model
    #: Spin speed of the damped modes, rad/s.
    speed: float
    #: Undamped natural frequencies, Hz, and mass-normalised shapes ``[dof, mode]`` (DOFs
    #: node by node: ux, uy, tx, ty).
    undamped_frequencies_hz: np.ndarray
    undamped_shapes: np.ndarray
    #: Per damped mode: label, damped and natural frequency (Hz), damping ratio, log
    #: decrement, whirl, eigenvalue (re 1/s, im rad/s), and per node the amplitude and phase
    #: of ux and uy and the forward and backward orbit radii (largest translation 1).
    damped: list[dict[str, Any]]
    #: The library's report: tables ``undamped_modes``, ``undamped_shapes``,
    #: ``damped_modes`` and ``damped_shapes``, the summary.
    report: Report


def modal(
    model: Model | str | os.PathLike[str], speed: str | float | None = None, *, modes: int | None = None
) -> ModalResult:
    """Undamped modes and damped whirl modes at a speed (``whirl modal``). Every option left
    ``None`` takes the library's default, the same as the command line's.

    Args:
        model: a :class:`Model` or a model file path.
        speed: spin speed of the damped modes, ``"300Hz"``, ``"3000rpm"`` or rad/s (default
            rest; a speed below 1e-3 rad/s is solved at 1e-3 rad/s, where forward and
            backward separate).
        modes: number of modes, undamped and damped (1-200; default 6).
    """
    model = as_model(model)
    raw, w = _whirl.modal(model._raw, {"speed": speed, "modes": modes})
    report = Report("modal", model, raw)
    frequencies = report.columns("undamped_modes")["frequency_hz"]
    return ModalResult(
        model=model,
        speed=w,
        undamped_frequencies_hz=frequencies,
        undamped_shapes=_undamped_shapes(report, len(frequencies)),
        damped=_damped_modes(report),
        report=report,
    )


#: The per-node columns of a damped mode, in the report's ``damped_shapes``.
_ORBIT_COLUMNS = ("ux_amplitude", "ux_phase_deg", "uy_amplitude", "uy_phase_deg", "forward_radius", "backward_radius")


def _undamped_shapes(report: Report, count: int) -> np.ndarray:
    """The report's ``undamped_shapes`` (a row per mode and node) as ``[dof, mode]``, the
    DOFs node by node (ux, uy, tx, ty)."""
    table = report.columns("undamped_shapes")
    by_row = np.stack([table[d] for d in ("ux", "uy", "tx", "ty")], axis=-1)
    return by_row.reshape(count, -1).T.copy()


def _damped_modes(report: Report) -> list[dict[str, Any]]:
    """Each damped mode of the report's ``damped_modes`` with its rows of ``damped_shapes``."""
    modes, shapes = report.columns("damped_modes"), report.columns("damped_shapes")
    out = []
    for i, mode in enumerate(modes["mode"]):
        rows = shapes["mode"] == mode
        out.append(
            {
                "label": modes["label"][i],
                "damped_frequency_hz": float(modes["damped_frequency_hz"][i]),
                "natural_frequency_hz": float(modes["natural_frequency_hz"][i]),
                "damping_ratio": float(modes["damping_ratio"][i]),
                "log_decrement": float(modes["log_decrement"][i]),
                "whirl": modes["whirl"][i],
                "eigenvalue": (float(modes["eigenvalue_real_per_s"][i]), float(modes["eigenvalue_imag_rad_per_s"][i])),
                **{name: shapes[name][rows] for name in _ORBIT_COLUMNS},
            }
        )
    return out
