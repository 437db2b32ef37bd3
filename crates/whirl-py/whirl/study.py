"""Studies (``whirl study``): the sensitivity of the NSV to model parameters, every point
a cascade (thesis ch. 5); on this machine or on a Dask cluster."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

from . import _progress, _whirl
from ._display import Figured
from ._summary import jsonable

#: NSV fields of points.csv, by the library's names.
_POINT_NSV = [
    ("largest_nsv_m", "largest"),
    ("largest_nsv_speed_hz", "largest_speed_hz"),
    ("largest_nsv_frequency_hz", "largest_frequency_hz"),
    ("largest_nsv_class", "largest_class"),
    ("onset_speed_hz", "onset_speed_hz"),
    ("median_nsv_m", "median"),
    ("p90_nsv_m", "p90"),
    ("mean_nsv_m", "mean"),
    ("dominant_class", "dominant_class"),
    ("largest_1x_m", "largest_synchronous"),
]


@dataclass(frozen=True)
class StudyResult(Figured):
    """A finished study: each distinct point's NSV summary (or why it failed), each sweep's
    values and fit, and the ranking of the sweeps and parameters by their effect; the command
    line's figures (``save_figures``, ``figure_spec``)."""

    study_file: str
    title: str
    model_file: str
    metric: str
    metric_description: str
    #: The folder of finished points.
    checkpoint: str
    #: Per point: key, label, changes, and result (nsv, map, wall_time_s) or error.
    points: list[dict[str, Any]]
    sweeps: list[dict[str, Any]]
    ranking: list[dict[str, Any]]
    ranking_by_parameter: list[dict[str, Any]]
    #: The command line's figures as specifications (:meth:`figure_specs`).
    specs: list[dict[str, Any]] = field(default_factory=list, repr=False)
    tables: ClassVar[tuple[str, ...]] = ("points", "sweeps", "fits", "ranking", "ranking_by_parameter")

    def figure_specs(self) -> list[dict[str, Any]]:
        return self.specs

    @property
    def figures(self) -> tuple[str, ...]:
        """The names of the command line's figures (``cascades_<i>``, ``nsv_<i>``)."""
        return self._spec_names()

    def to_pandas(self, table: str = "points"):
        """The command line's CSV tables: ``points`` (one row per distinct point: its
        changes and NSV summary), ``sweeps`` (one row per sweep and value), ``fits`` (eq.
        5.1's coefficients, highest power first, and R^2 of each sweep that asks for a
        fit), ``ranking`` (the sweeps by their effect on the metric, largest first) or
        ``ranking_by_parameter`` (each parameter by the largest effect among its sweeps)."""
        import pandas as pd

        if table == "points":
            rows = []
            for k, p in enumerate(self.points):
                nsv = p.get("result", {}).get("nsv")
                row = [k, p["label"]]
                row += [None if nsv is None else nsv[key] for _, key in _POINT_NSV]
                row += [p["result"]["wall_time_s"] if "result" in p else None, p.get("error")]
                rows.append(row)
            columns = ["point", "changes", *[c for c, _ in _POINT_NSV], "wall_time_s", "error"]
            return pd.DataFrame(rows, columns=columns)
        if table == "sweeps":
            rows = [
                [i, s["name"], s["parameter"], s["values"][j], s["values_si"][j], s["largest_nsv"][j],
                 s["metric_nsv"][j], s["onset_speed_hz"][j]]
                for i, s in enumerate(self.sweeps)
                for j in range(len(s["values"]))
            ]
            columns = ["sweep", "name", "parameter", "value", "value_si", "largest_nsv_m",
                       "metric_nsv_m", "onset_speed_hz"]
            return pd.DataFrame(rows, columns=columns)
        if table == "fits":
            rows = [
                [i, s["name"], len(c) - 1, *c, *[None] * (4 - len(c)), f["r_squared"], f["rms_residual"]]
                for i, s in enumerate(self.sweeps)
                if (f := s["fit"]) is not None
                for c in [f["coefficients"]]
            ]
            columns = ["sweep", "name", "degree", "p1", "p2", "p3", "p4", "r_squared", "rms_residual_m"]
            return pd.DataFrame(rows, columns=columns)
        if table in ("ranking", "ranking_by_parameter"):
            effects = self.ranking if table == "ranking" else self.ranking_by_parameter
            rows = [
                [k + 1, e["sweep"], e["parameter"], e["smallest"], e["largest"], e["relative_change"]]
                for k, e in enumerate(effects)
            ]
            columns = ["rank", "sweep", "parameter", "smallest_metric_m", "largest_metric_m", "relative_change"]
            return pd.DataFrame(rows, columns=columns)
        raise ValueError(f"no table `{table}`: choose one of {self.tables}")

    def to_dict(self) -> dict[str, Any]:
        """The command line's summary.json (without the output folder and file list)."""
        done = [p["result"] for p in self.points if "result" in p]
        points = [
            {"key": p["key"], "label": p["label"], "nsv": p["result"]["nsv"], "wall_time_s": p["result"]["wall_time_s"]}
            if "result" in p
            else {"key": p["key"], "label": p["label"], "error": p["error"]}
            for p in self.points
        ]
        return jsonable(
            {
                "command": "study",
                "whirl_version": _whirl.__version__,
                "study_file": self.study_file,
                "model_file": self.model_file,
                "title": self.title,
                "metric": self.metric,
                "metric_description": self.metric_description,
                "checkpoint": self.checkpoint,
                "points": points,
                "sweeps": self.sweeps,
                "ranking": self.ranking,
                "ranking_by_parameter": self.ranking_by_parameter,
                "failed_points": len(self.points) - len(done),
                "cascade_time_s": sum(r["wall_time_s"] for r in done),
            }
        )


def study(
    path: str | os.PathLike[str],
    *,
    checkpoint: str | os.PathLike[str] = "out/study.points",
    restart: bool = False,
    progress: bool | Any = True,
    client: Any = None,
) -> StudyResult:
    """Runs a study file (``whirl study``, docs/study-file.md).

    Args:
        path: the study file, e.g. ``examples/quick_study.toml``.
        checkpoint: folder of finished points, kept between runs (shared by the workers,
            with ``client``): running the same study again computes only the points not
            yet there. The command line's default, ``out/study.points``.
        restart: discard the finished points and start again.
        progress: True for a tqdm bar (points) when tqdm is installed, False for none, or
            a callable ``progress(done, total)`` whose true return stops the study.
        client: a ``dask.distributed.Client``: each point is one task on its workers;
            the result is the same, to the bit, as on this machine.
    """
    path = os.fspath(path)
    runner = None
    if client is not None:
        from .dask import study_runner

        runner = study_runner(client, path, os.fspath(Path(checkpoint).resolve()))
    with _progress.display(progress, "study", "points") as report:
        raw = _whirl.study(path, os.fspath(checkpoint), restart, report, runner)
    analysis = raw["analysis"]
    return StudyResult(
        study_file=path,
        title=raw["title"],
        model_file=str(raw["model_file"]),
        metric=raw["metric"],
        metric_description=raw["metric_description"],
        checkpoint=str(raw["checkpoint"]),
        points=raw["points"],
        sweeps=analysis["sweeps"],
        ranking=analysis["ranking"],
        ranking_by_parameter=analysis["ranking_by_parameter"],
        specs=raw["figures"],
    )
