"""Cascades on a real Dask cluster of worker processes: the same result to the bit as on
this machine, and a worker killed mid-run recovered with nothing lost."""

from __future__ import annotations

import os
import signal

import pytest
from dask.distributed import Client, LocalCluster

import whirl
from conftest import REFERENCE, timeless
from test_nsv import OPTIONS, SPEEDS, assert_same_cascade


@pytest.fixture(scope="module")
def client():
    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, Client(cluster) as client:
        yield client


@pytest.fixture(scope="module")
def local():
    return whirl.cascade(REFERENCE, SPEEDS, progress=False, **OPTIONS)


def test_a_cascade_on_the_cluster_is_the_local_one(client, local, tmp_path):
    remote = whirl.cascade(REFERENCE, SPEEDS, client=client, checkpoint=tmp_path, progress=False, **OPTIONS)
    assert_same_cascade(remote, local)
    # Every speed, refined ones included, is in the checkpoint: a local run resumes them all.
    resumed = whirl.cascade(REFERENCE, SPEEDS, checkpoint=tmp_path, progress=False, **OPTIONS)
    assert resumed.resumed_speeds == len(local.speeds_hz)
    assert_same_cascade(resumed, local)


def test_a_worker_killed_mid_run_loses_nothing(client, local):
    pids = list(client.run(os.getpid).values())
    killed = []

    def kill_one_worker(done, total):
        # After the first speed came back, while the others run: kill a worker outright.
        if done >= 1 and not killed:
            os.kill(pids[0], signal.SIGKILL)
            killed.append(pids[0])
        return False

    remote = whirl.cascade(REFERENCE, SPEEDS, client=client, progress=kill_one_worker, **OPTIONS)
    assert killed, "no worker was killed: the test proved nothing"
    assert pids[0] not in client.run(os.getpid).values()
    assert_same_cascade(remote, local)


QUICK_STUDY = REFERENCE.parent / "quick_study.toml"


def test_a_study_on_the_cluster_is_the_local_one(client, tmp_path):
    local = whirl.study(QUICK_STUDY, checkpoint=tmp_path / "local", progress=False)
    remote = whirl.study(QUICK_STUDY, checkpoint=tmp_path / "remote", client=client, progress=False)
    assert len(remote.points) == 2 and all("nsv" in p for p in remote.points)
    # The points' NSV summaries are the same to the bit; only the wall times and the
    # folder differ.
    strip = lambda r: [{**p, "wall_time_s": 0} for p in r.points]  # noqa: E731
    assert strip(remote) == strip(local)
    assert (remote.sweeps, remote.ranking) == (local.sweeps, local.ranking)


def test_a_map_on_the_cluster_is_the_local_one(client):
    # Two values through the first resonance (seconds each), one task per value: the
    # bands, lines and first losses come back as exact JSON, so the summary and every
    # table are the local map's to the bit, computing times aside.
    kwargs = dict(values=["20um", "60um"], speeds="1:30Hz", harmonics=2, reduce=12, progress=False)
    local = whirl.map(REFERENCE, **kwargs)
    remote = whirl.map(REFERENCE, client=client, **kwargs)
    assert timeless(remote.to_dict()) == timeless(local.to_dict())
    for table in local.tables:
        times = ["cpu_s", "wall_s"] if table == "values" else []
        assert remote.to_pandas(table).drop(columns=times).equals(local.to_pandas(table).drop(columns=times))
    assert len(local.to_pandas("values")) == 2
