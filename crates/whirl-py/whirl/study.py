"""Studies (``whirl study``): the sensitivity of the NSV to model parameters, every point
a cascade (thesis ch. 5); on this machine or on a Dask cluster."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from . import _progress, _whirl
from .model import as_model
from .report import Report, _Read

class StudyResult(Report):
    """A finished study, as the library reports it: each distinct point's NSV summary (or
    why it failed), each sweep's values and fit, and the ranking of the sweeps and
    parameters by their effect (``to_dict()``, its keys as attributes: ``points``,
    ``sweeps``, ``ranking``); the command line's tables (``to_pandas("points")``,
    ``sweeps``, ``fits``, ``ranking``, ``ranking_by_parameter``) and figures."""

    __slots__ = ("study_file", "checkpoint")

    def __init__(self, raw: _whirl.Report, study_file: str, checkpoint: str):
        super().__init__("study", as_model(raw.summary()["model_file"]), raw)
        self.study_file = study_file
        self.checkpoint = checkpoint

    def to_dict(self) -> dict[str, Any]:
        """The command line's summary.json (without the output folder, the file list and
        the wall time)."""
        head = {"command": "study", "whirl_version": _whirl.__version__}
        return {**head, "study_file": self.study_file, "checkpoint": self.checkpoint, **self._raw.summary()}

    def __reduce__(self):
        raw = _Read(self._raw.summary(), {t: self._raw.table(t) for t in self.tables}, self._raw.figures())
        return (StudyResult, (raw, self.study_file, self.checkpoint))


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
        raw, folder = _whirl.study(path, os.fspath(checkpoint), restart, report, runner)
    return StudyResult(raw, path, str(folder))
