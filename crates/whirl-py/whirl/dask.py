"""Studies, cascades and maps on a Dask cluster.

``whirl.cascade(..., client=client)``, ``whirl.study(..., client=client)`` and
``whirl.map(..., client=client)`` send the work to the workers of a
``dask.distributed.Client`` and gather it: each speed of a cascade (every round of the
refinement), each point of a study or each value of a map is one task (a map's checks and
confirmation, a few cascades, run on this machine). A worker computes
exactly what this machine would (the same library call on the same model text and options),
and results come back as exact JSON, so the result is the same to the bit wherever a task
ran. A worker that dies mid-task has its task run again on another by Dask; the client
saves each result in the checkpoint folder as it arrives, so an interrupted client resumes
where it stopped.

The same script runs on a SLURM or PBS cluster through dask-jobqueue::

    from dask.distributed import Client
    from dask_jobqueue import SLURMCluster   # or PBSCluster

    cluster = SLURMCluster(cores=8, memory="8GB", walltime="02:00:00")
    cluster.scale(jobs=10)
    client = Client(cluster)
    result = whirl.cascade("rotor.toml", client=client, checkpoint="/shared/run.partial")
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

from . import _whirl
from .model import Model


def _cascade_point(model: Model, options: dict[str, Any], speed: float) -> str:
    """On a worker: one speed of the cascade, as exact JSON."""
    return _whirl.cascade_point(model._raw, options, speed)


def point_runner(client: Any, model: Model, options: dict[str, Any]) -> Callable[[list[tuple[int, float]]], Iterator[tuple[int, str]]]:
    """The runner the library's distributed cascade calls with each round of speeds: one
    task per speed, yielded as each finishes."""
    def run(batch: list[tuple[int, float]]) -> Iterator[tuple[int, str]]:
        # pure=False: a task is a computation to run, never a cached value; retries: a
        # task on a worker that died is run again elsewhere.
        futures = {
            client.submit(_cascade_point, model, options, speed, pure=False, retries=3): index
            for index, speed in batch
        }
        yield from _as_finished(client, futures)

    return run


def _map_value(model: Model, options: dict[str, Any], sweep: dict[str, Any], index: int) -> str:
    """On a worker: value ``index``'s sweep of the map, as exact JSON."""
    return _whirl.map_value(model._raw, options, sweep, index)


def value_runner(client: Any, model: Model, options: dict[str, Any], sweep: dict[str, Any]) -> Callable[[list[int]], Iterator[tuple[int, str]]]:
    """The runner the library's distributed map calls with the values' indices: one task
    per value, yielded as each finishes."""
    def run(indices: list[int]) -> Iterator[tuple[int, str]]:
        futures = {
            client.submit(_map_value, model, options, sweep, j, pure=False, retries=3): j for j in indices
        }
        yield from _as_finished(client, futures)

    return run


def _study_point(path: str, index: int, checkpoint: str) -> str:
    """On a worker: point ``index`` of the study file, as exact JSON."""
    return _whirl.study_point(path, index, checkpoint)


def study_runner(client: Any, path: str, checkpoint: str) -> Callable[[list[int]], Iterator[tuple[int, str]]]:
    """The runner the study calls with the points not yet finished: one task per point
    (the study file and the checkpoint folder must be on a path the workers share)."""
    def run(points: list[int]) -> Iterator[tuple[int, str]]:
        futures = {
            client.submit(_study_point, path, k, checkpoint, pure=False, retries=3): k for k in points
        }
        yield from _as_finished(client, futures)

    return run


def _as_finished(client: Any, futures: dict[Any, int]) -> Iterator[tuple[int, str]]:
    """Each task's index and result as it finishes; the rest cancelled if the caller stops."""
    from dask.distributed import as_completed

    try:
        for future in as_completed(futures):
            yield futures[future], future.result()
    finally:
        client.cancel(list(futures))
