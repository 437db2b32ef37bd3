"""Linear analyses of the rotor: ``check`` and the Campbell diagram."""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from . import _options, _whirl
from ._summary import finite_or_none, head
from .model import Model, as_model

#: Undamped frequencies listed by ``check`` (as on the command line).
CHECK_FREQUENCIES = 6


@dataclass(frozen=True)
class CheckResult:
    """The model as read and summarised by ``whirl check``."""

    model: Model
    #: The first six undamped natural frequencies of the rotor at rest, Hz.
    frequencies_hz: np.ndarray
    #: Table names of :meth:`to_pandas`.
    tables: ClassVar[tuple[str, ...]] = ("frequencies", "nodes")

    def to_pandas(self, table: str = "frequencies"):
        """``frequencies`` (mode, frequency_hz) or ``nodes`` (node, z_m, features), the
        command line's frequencies.csv and nodes.csv."""
        import pandas as pd

        if table == "frequencies":
            return pd.DataFrame(
                {"mode": np.arange(1, len(self.frequencies_hz) + 1), "frequency_hz": self.frequencies_hz}
            )
        if table == "nodes":
            return pd.DataFrame(
                {
                    "node": np.arange(self.model.node_count),
                    "z_m": self.model.node_positions(),
                    "features": self.model.node_features(),
                }
            )
        raise ValueError(f"no table `{table}`: choose `frequencies` or `nodes`")

    def to_dict(self) -> dict[str, Any]:
        """The command line's summary.json (without the output folder and file list)."""
        m = self.model.to_dict()
        elements = sum(s["elements"] for s in m["sections"])
        shaft = self.model.shaft_mass
        disks = sum(d["mass"] for d in m["disks"])
        hz = lambda w: w / (2 * np.pi)  # noqa: E731
        summary = head("check", self.model)
        summary.update(
            nodes=self.model.node_count,
            dofs=4 * self.model.node_count,
            elements=elements,
            shaft_sections=len(m["sections"]),
            shaft_length_m=self.model.length,
            shaft_mass_kg=shaft,
            disk_mass_kg=disks,
            total_mass_kg=shaft + disks,
            gravity_m_per_s2=m["gravity"],
            disks=[
                {
                    "name": d["name"],
                    "node": d["station"]["node"],
                    "z_m": d["station"]["z"],
                    "mass_kg": d["mass"],
                    "polar_inertia_kg_m2": d["polar_inertia"],
                    "diametral_inertia_kg_m2": d["diametral_inertia"],
                }
                for d in m["disks"]
            ],
            bearings=[
                {
                    "name": b["name"],
                    "node": b["station"]["node"],
                    "z_m": b["station"]["z"],
                    "stiffness_n_per_m": _matrix(b["stiffness"], "k"),
                    "damping_n_s_per_m": _matrix(b["damping"], "c"),
                }
                for b in m["bearings"]
            ],
            roller_bearings=[
                {
                    "name": b["name"],
                    "node": b["station"]["node"],
                    "z_m": b["station"]["z"],
                    "rollers": b["rollers"],
                    "pitch_diameter_m": b["pitch_diameter"],
                    "roller_diameter_m": b["roller_diameter"],
                    "roller_length_m": b["roller_length"],
                    "clearance_at_rest_m": _clearance_at_rest(b["clearance"]),
                    "contact_stiffness_n_per_m_pow_n": b["contact_stiffness"],
                    "contact_exponent": b["contact_exponent"],
                    "contact_damping_n_s_per_m": b["contact_damping"],
                    "linear_stiffness_n_per_m": b["linear_stiffness"],
                    "linear_damping_n_s_per_m": b["linear_damping"],
                }
                for b in m["roller_bearings"]
            ],
            unbalances=[
                {
                    "node": u["station"]["node"],
                    "z_m": u["station"]["z"],
                    "mass_radius_kg_m": u["mass_radius"],
                    "phase_deg": float(np.degrees(u["phase"])),
                }
                for u in m["unbalances"]
            ],
            rayleigh_damping={"alpha_per_s": m["damping"]["alpha"], "beta_s": m["damping"]["beta"]},
            operating_speed_hz=None if m["operating"] is None else [hz(w) for w in m["operating"]],
            undamped_frequencies_hz=[finite_or_none(f) for f in self.frequencies_hz],
        )
        return summary


def _matrix(m: list[list[float]], letter: str) -> dict[str, float]:
    return {f"{letter}{a}{b}": m[i][j] for i, a in enumerate("xy") for j, b in enumerate("xy")}


def _clearance_at_rest(clearance: dict[str, Any]) -> float:
    # {"Constant": c} or {"Polynomial": [c0, c1, ...]}: at rest, c0.
    (kind, value), = clearance.items()
    return value if kind == "Constant" else value[0]


def check(model: Model | str | os.PathLike[str]) -> CheckResult:
    """Validates and summarises a model (``whirl check``): mesh, masses, supports and the
    first six undamped natural frequencies of the linearised rotor at rest."""
    model = as_model(model)
    return CheckResult(model, _whirl.undamped_frequencies(model._raw, CHECK_FREQUENCIES))


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


@dataclass(frozen=True)
class CampbellResult:
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
    #: Table names of :meth:`to_pandas`.
    tables: ClassVar[tuple[str, ...]] = ("campbell", "critical_speeds")

    def branch(self, label: str) -> Branch:
        """The branch labelled ``label`` (``1F``, ``2B``, ...)."""
        for b in self.branches:
            if b.label == label:
                return b
        raise KeyError(f"no branch `{label}`: the branches are {[b.label for b in self.branches]}")

    def to_pandas(self, table: str = "campbell"):
        """``campbell`` (one row per speed; per branch its frequency, damping ratio, log
        decrement and whirl) or ``critical_speeds``: the command line's CSV tables."""
        import pandas as pd

        if table == "campbell":
            columns: dict[str, Any] = {"speed_hz": self.speeds_hz, "speed_rpm": 60.0 * self.speeds_hz}
            for b in self.branches:
                columns[f"{b.label}_frequency_hz"] = b.frequency_hz
                columns[f"{b.label}_damping_ratio"] = b.damping_ratio
                columns[f"{b.label}_log_decrement"] = b.log_decrement
                columns[f"{b.label}_whirl"] = [
                    w if np.isfinite(f) else None for w, f in zip(b.whirl_at, b.frequency_hz)
                ]
            return pd.DataFrame(columns)
        if table == "critical_speeds":
            names = ["speed_hz", "speed_rpm", "frequency_hz", "order", "branch", "whirl", "damping_ratio"]
            return pd.DataFrame(
                [[getattr(c, n) for n in names] for c in self.critical_speeds], columns=names
            )
        raise ValueError(f"no table `{table}`: choose one of {self.tables}")

    def to_dict(self) -> dict[str, Any]:
        """The command line's summary.json (without the output folder and file list)."""
        s = self.speeds_hz
        summary = head("campbell", self.model)
        summary.update(
            speed_range_hz=[float(s[0]), float(s[-1])] if len(s) else [None, None],
            speed_count=len(s),
            orders=list(self.orders),
            basis_size=self.basis_size,
            branches=[
                {
                    "label": b.label,
                    "whirl": b.whirl,
                    "frequency_at_first_speed_hz": _first_last(b.frequency_hz, 0),
                    "frequency_at_last_speed_hz": _first_last(b.frequency_hz, -1),
                    "min_log_decrement": finite_or_none(
                        np.min(b.log_decrement[np.isfinite(b.log_decrement)], initial=np.inf)
                    ),
                }
                for b in self.branches
            ],
            critical_speeds=[
                {
                    "speed_hz": c.speed_hz,
                    "speed_rpm": c.speed_rpm,
                    "frequency_hz": c.frequency_hz,
                    "order": c.order,
                    "branch": c.branch,
                    "whirl": c.whirl,
                    "damping_ratio": c.damping_ratio,
                }
                for c in self.critical_speeds
            ],
        )
        return summary


def _first_last(x: np.ndarray, i: int) -> float | None:
    return finite_or_none(x[i]) if len(x) else None


def campbell(
    model: Model | str | os.PathLike[str],
    speeds: _options.Speeds = None,
    *,
    modes: int = 8,
    orders: Sequence[float] | float = (1.0,),
    full: bool = False,
) -> CampbellResult:
    """The Campbell diagram (``whirl campbell``).

    Args:
        model: a :class:`Model` or a model file path.
        speeds: spin speeds: a range ``"0:800Hz:161"`` (``rpm`` too), or numbers in rad/s;
            default 161 speeds from rest to 1.2 x the model's top operating speed (800 Hz
            when it states none).
        modes: number of whirl branches to follow (1-200).
        orders: excitation orders whose crossings are critical speeds (1 = synchronous).
        full: solve the full system at every speed instead of a basis of 2 x modes + 8
            undamped modes (slower; the basis keeps branches within 2e-4 of the full solve).
    """
    model = as_model(model)
    raw = _whirl.campbell(
        model._raw,
        _options.speeds(speeds, model, 0.0, 161),
        _options.mode_count(modes),
        _options.orders(orders),
        bool(full),
    )
    branches = [Branch(**b) for b in raw["branches"]]
    label = {b.index: b.label for b in branches}
    critical = [
        CriticalSpeed(**{**c, "branch": label.get(c["branch"], f"branch {c['branch']}")})
        for c in raw["critical_speeds"]
    ]
    return CampbellResult(
        model=model,
        speeds_hz=raw["speeds_hz"],
        branches=branches,
        orders=raw["orders"],
        critical_speeds=critical,
        basis_size=raw["basis_size"],
    )


@dataclass(frozen=True)
class ConvergenceResult:
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
    tables: ClassVar[tuple[str, ...]] = ("convergence",)

    @property
    def meshes_with_fewer_modes(self) -> list[tuple[int, int]]:
        """(element count, modes found) of each mesh with fewer modes than asked for."""
        return [
            (n, found)
            for n, found in zip(self.element_counts, self.modes_found)
            if found < self.modes_requested
        ]

    def to_pandas(self, table: str = "convergence"):
        """The command line's convergence.csv: per element count each mode's frequency and
        its relative change from the previous mesh."""
        import pandas as pd

        if table != "convergence":
            raise ValueError(f"no table `{table}`: choose one of {self.tables}")
        modes = self.frequencies_hz.shape[1]
        columns: dict[str, Any] = {"elements": self.element_counts}
        for j in range(modes):
            columns[f"mode{j + 1}_frequency_hz"] = self.frequencies_hz[:, j]
        for j in range(modes):
            columns[f"mode{j + 1}_relative_change"] = self.relative_change[:, j]
        return pd.DataFrame(columns)

    def to_dict(self) -> dict[str, Any]:
        """The command line's summary.json (without the output folder and file list)."""
        rows = lambda a: [[finite_or_none(x) for x in row] for row in a]  # noqa: E731
        summary = head("convergence", self.model)
        summary.update(
            element_counts=list(self.element_counts),
            modes_requested=self.modes_requested,
            modes_found=list(self.modes_found),
            meshes_with_fewer_modes=[
                {"elements": n, "modes": m} for n, m in self.meshes_with_fewer_modes
            ],
            skipped_element_counts=list(self.skipped),
            frequencies_hz=rows(self.frequencies_hz),
            finest_mesh_frequencies_hz=rows(self.frequencies_hz)[-1],
            finest_mesh_relative_change=rows(self.relative_change)[-1],
        )
        return summary


def convergence(
    model: Model | str | os.PathLike[str],
    counts: Sequence[int] | None = None,
    *,
    modes: int = 6,
) -> ConvergenceResult:
    """Natural frequencies versus the number of elements (``whirl convergence``, thesis
    fig. 2.8).

    Args:
        model: a :class:`Model` or a model file path.
        counts: total element counts, each shared among the sections in proportion to their
            lengths (1-500); default 2, 4, ..., 40. A mesh on which a disk or bearing would
            fall between nodes is skipped (``skipped``).
        modes: number of modes to follow (1-200).
    """
    model = as_model(model)
    counts = list(range(2, 41, 2)) if not counts else list(counts)
    for n in counts:
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= 500:
            raise _whirl.InputError(
                f"invalid `counts`: `{n}` is not a whole number of elements from 1 to 500"
            )
    modes = _options.mode_count(modes)
    raw = _whirl.convergence(model._raw, [int(n) for n in counts], modes)
    if not raw["element_counts"]:
        raise _whirl.InputError(
            f"invalid `counts`: on none of the meshes {raw['skipped']} do all disks, bearings "
            "and unbalances sit on a node\n  help: choose element counts that put a node at "
            "every feature, e.g. multiples of the model's own count"
        )
    return ConvergenceResult(
        model=model,
        element_counts=raw["element_counts"],
        frequencies_hz=np.asarray(raw["frequencies_hz"], dtype=float),
        relative_change=np.asarray(raw["relative_change"], dtype=float),
        modes_found=raw["modes_found"],
        skipped=raw["skipped"],
        modes_requested=modes,
    )


#: What summary.json of ``whirl modal`` says of its numbers.
_MODAL_NOTES = [
    "undamped shapes are mass-normalised (phi^T M phi = 1)",
    "damped shapes are scaled so that the largest translation is 1",
    "roots with damping ratio above 0.9 are left out",
]


@dataclass(frozen=True)
class ModalResult:
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
    tables: ClassVar[tuple[str, ...]] = ("undamped_modes", "undamped_shapes", "damped_modes", "damped_shapes")

    def to_pandas(self, table: str = "damped_modes"):
        """The command line's undamped_modes, undamped_shapes, damped_modes or
        damped_shapes table."""
        import pandas as pd

        f, z, n = self.undamped_frequencies_hz, self.model.node_positions(), self.model.node_count
        if table == "undamped_modes":
            return pd.DataFrame({"mode": np.arange(1, len(f) + 1), "frequency_hz": f})
        if table == "undamped_shapes":
            shapes = self.undamped_shapes.reshape(n, 4, len(f))
            frames = [
                pd.DataFrame(
                    {"mode": j + 1, "frequency_hz": fj, "node": np.arange(n), "z_m": z,
                     **{d: shapes[:, k, j] for k, d in enumerate(("ux", "uy", "tx", "ty"))}}
                )
                for j, fj in enumerate(f)
            ]
            return pd.concat(frames, ignore_index=True)
        if table == "damped_modes":
            keys = ["label", "damped_frequency_hz", "natural_frequency_hz", "damping_ratio", "log_decrement", "whirl"]
            rows = [[i + 1, *[m[k] for k in keys], *m["eigenvalue"]] for i, m in enumerate(self.damped)]
            return pd.DataFrame(rows, columns=["mode", *keys, "eigenvalue_real_per_s", "eigenvalue_imag_rad_per_s"])
        if table == "damped_shapes":
            keys = ["ux_amplitude", "ux_phase_deg", "uy_amplitude", "uy_phase_deg", "forward_radius", "backward_radius"]
            frames = [
                pd.DataFrame({"mode": i + 1, "label": m["label"], "node": np.arange(n), "z_m": z, **{k: m[k] for k in keys}})
                for i, m in enumerate(self.damped)
            ]
            return pd.concat(frames, ignore_index=True)
        raise ValueError(f"no table `{table}`: choose one of {self.tables}")

    def to_dict(self) -> dict[str, Any]:
        """The command line's summary.json (without the output folder and file list)."""
        speed_hz = self.speed / (2 * math.pi)
        summary = head("modal", self.model)
        summary.update(
            speed_hz=speed_hz,
            speed_rpm=60.0 * speed_hz,
            undamped_frequencies_hz=[finite_or_none(x) for x in self.undamped_frequencies_hz],
            damped_modes=[
                {k: m[k] for k in ("label", "damped_frequency_hz", "natural_frequency_hz", "damping_ratio", "log_decrement", "whirl")}
                for m in self.damped
            ],
            notes=list(_MODAL_NOTES),
        )
        return summary


def modal(model: Model | str | os.PathLike[str], speed: str | float = 0.0, *, modes: int = 6) -> ModalResult:
    """Undamped modes and damped whirl modes at a speed (``whirl modal``).

    Args:
        model: a :class:`Model` or a model file path.
        speed: spin speed of the damped modes, ``"300Hz"``, ``"3000rpm"`` or rad/s (a speed
            below 1e-3 rad/s is solved at 1e-3 rad/s, where forward and backward separate).
        modes: number of modes, undamped and damped (1-200).
    """
    model = as_model(model)
    w = _whirl.parse_speed(str(speed))
    raw = _whirl.modal(model._raw, w, _options.mode_count(modes))
    return ModalResult(model=model, speed=w, **raw)
