"""The Dask example on a LocalCluster of two worker processes gives exactly the single-process
voxel map with the same seeds."""

import importlib.util

import numpy as np
import pytest

import kinetree
from conftest import PANDA, ROOT

import dask.distributed as distributed  # a test dependency: cargo xtask test installs it


def example():
    spec = importlib.util.spec_from_file_location("distributed_reachability", ROOT / "examples" / "python" / "distributed_reachability.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_two_worker_processes_equal_one_process():
    ex = example()
    model = kinetree.Model.from_urdf(PANDA)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            assert len(client.scheduler_info()["workers"]) == 2
            spread = ex.reachability(client, model, tasks=6, samples_per_task=3000, seed0=10, voxel=0.1)
    local = ex.reachability(None, model, tasks=6, samples_per_task=3000, seed0=10, voxel=0.1)
    assert spread == local
    idx_s, counts_s, max_s, _ = spread.voxels()
    idx_l, counts_l, max_l, _ = local.voxels()
    assert np.array_equal(idx_s, idx_l) and np.array_equal(counts_s, counts_l) and np.array_equal(max_s, max_l)
    assert counts_s.sum() == 6 * 3000
    # and equal to sampling the seeds one by one by hand
    by_hand = model.sample_workspace("panda_hand_tcp", samples=3000, seed=10).voxelize(0.1)
    for s in range(11, 16):
        by_hand = by_hand.merge(model.sample_workspace("panda_hand_tcp", samples=3000, seed=s).voxelize(0.1))
    assert by_hand == local
