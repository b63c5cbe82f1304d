"""Reachable workspace of the Panda's hand, sampled on a Dask cluster.

Each task loads nothing: it receives the pickled ``kinetree.Model``, samples ``samples_per_task``
random configurations from its own seed (``seed0 + task``) in parallel on its worker's cores,
and returns the voxel map of the hand positions. The maps are merged (counts add, maxima
combine), so the result is exactly the single-process result with the same seeds, however the
tasks are spread.

Run it on a local cluster of two worker processes:

    python examples/python/distributed_reachability.py --tasks 8 --samples 50000

On a real cluster, start a scheduler (``dask scheduler``) and workers on each machine
(``dask worker tcp://scheduler:8786``), each with ``pip install ./crates/kinetree-py`` done, and
pass the scheduler's address:

    python examples/python/distributed_reachability.py --scheduler tcp://scheduler:8786 \
        --tasks 1000 --samples 1000000

Each task then uses every core of the machine it lands on (kinetree releases the GIL and runs on
rayon's threads), so give each worker one thread (``--nthreads 1``) and as many workers as
machines.
"""

from __future__ import annotations

import argparse
import functools
import pathlib

import kinetree

ROOT = pathlib.Path(__file__).resolve().parents[2]
PANDA = ROOT / "tests" / "data" / "robots" / "panda.urdf"
FRAME = "panda_hand_tcp"


def sample_task(model: kinetree.Model, frame: str, samples: int, seed: int, voxel: float) -> kinetree.VoxelMap:
    """One task: ``samples`` configurations from ``seed``, as a voxel map."""
    return model.sample_workspace(frame, samples=samples, seed=seed).voxelize(voxel)


def merge(maps):
    return functools.reduce(lambda a, b: a.merge(b), maps)


def reachability(client, model, frame=FRAME, tasks=8, samples_per_task=10_000, seed0=0, voxel=0.05):
    """The merged voxel map of ``tasks`` tasks run on a ``dask.distributed`` client (or in this
    process when ``client`` is None), task ``i`` sampling with seed ``seed0 + i``."""
    seeds = [seed0 + i for i in range(tasks)]
    if client is None:
        return merge(sample_task(model, frame, samples_per_task, s, voxel) for s in seeds)
    shared = client.scatter(model, broadcast=True)  # the model travels pickled, once per worker
    futures = [client.submit(sample_task, shared, frame, samples_per_task, s, voxel, pure=False) for s in seeds]
    # Merge as a tree on the workers, then fetch one map.
    while len(futures) > 1:
        futures = [
            client.submit(lambda a, b: a.merge(b), futures[i], futures[i + 1]) if i + 1 < len(futures) else futures[i]
            for i in range(0, len(futures), 2)
        ]
    return futures[0].result()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scheduler", help="address of a running Dask scheduler (default: a local cluster)")
    parser.add_argument("--workers", type=int, default=2, help="worker processes of the local cluster")
    parser.add_argument("--tasks", type=int, default=8)
    parser.add_argument("--samples", type=int, default=50_000, help="samples per task")
    parser.add_argument("--voxel", type=float, default=0.05, help="voxel side (m)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the first task")
    args = parser.parse_args()

    from dask.distributed import Client, LocalCluster

    model = kinetree.Model.from_urdf(PANDA)
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        client = Client(LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True))
    with client:
        voxels = reachability(client, model, FRAME, args.tasks, args.samples, args.seed, args.voxel)
    print(f"{args.tasks * args.samples} samples: {len(voxels)} voxels of {args.voxel} m, "
          f"reachable volume >= {voxels.volume:.3f} m^3")
    print("reaches (0.5, 0, 0.5):", voxels.is_reachable([0.5, 0.0, 0.5]))


if __name__ == "__main__":
    main()
