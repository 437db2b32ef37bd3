"""Cascades on a real Dask cluster of worker processes: the same result to the bit as on
this machine, and a worker killed mid-run recovered with nothing lost."""

from __future__ import annotations

import os
import signal

import pytest
from dask.distributed import Client, LocalCluster

import whirl
from conftest import REFERENCE
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
    assert resumed.resumed == len(local.speeds_hz)
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
