"""A study (NSV at two clearances) with its points on a Dask cluster: here a local one of
two worker processes; on SLURM or PBS, a dask_jobqueue cluster instead (docs/python.md).
The result is the same, to the bit, as on this machine.

Run from the repository's root: python examples/python/study_on_cluster.py
"""

from dask.distributed import Client, LocalCluster

import whirl

if __name__ == "__main__":
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster, Client(cluster) as client:
        study = whirl.study(
            "examples/quick_study.toml", client=client, checkpoint="out/python-study.points"
        )
    print(study.to_pandas("sweeps")[["value", "largest_nsv_m", "onset_speed_hz"]])
