"""The raster sweep of optuna_raster.py distributed with Ray: a grid over step-over, travel
speed and standoff, one Ray task per raster.

`ray.init()` starts a local Ray cluster on this machine; started on a node of a running Ray
cluster (`ray start --head` / `ray start --address=...`, or `ray job submit`), the same script
runs its tasks across the whole cluster unchanged (every node needs `pip install ./python`).

    pip install ./python "ray>=2.9"
    python examples/python/ray_raster.py [--points 3]

About 10 s on 2 cores with the defaults (27 rasters), most of it Ray's start-up.

On a Slurm cluster without Ray, a job array runs the same sweep with the command alone, one
raster per array task, each writing its own outputs (metrics.json holds the results):

    #SBATCH --array=0-26
    STEPS=(0.08 0.165 0.25); SPEEDS=(0.5 1.0 1.5); STANDOFFS=(1.0 1.5 2.0)
    i=$SLURM_ARRAY_TASK_ID
    spraysim run wall.toml -j "$SLURM_CPUS_PER_TASK" -q -o "out/ray_raster/$i" \\
        --set nozzle.raster.step_over=${STEPS[i / 9]} \\
        --set nozzle.raster.speed=${SPEEDS[i / 3 % 3]} \\
        --set nozzle.raster.standoff=${STANDOFFS[i % 3]}

where wall.toml is a scenario with a `[nozzle.raster]` (`raster_sweep.scenario(...).to_toml()`
writes one) and `simulation.duration` long enough for the slowest raster.
"""

import argparse
import itertools
import time

import numpy as np
import ray

import raster_sweep
from raster_sweep import BOUNDS, describe

# The task's code travels with it to every node, so raster_sweep.py need not be installed there.
ray.cloudpickle.register_pickle_by_value(raster_sweep)


@ray.remote(num_cpus=1)
def evaluate(params):
    """One raster, single-threaded (Ray runs one task per CPU)."""
    return params, raster_sweep.evaluate(params)


def main():
    parser = argparse.ArgumentParser(description="distribute the raster sweep with Ray")
    parser.add_argument("--points", type=int, default=3, help="grid points per parameter")
    a = parser.parse_args()

    ray.init()  # a local cluster, or the running cluster this node belongs to
    start = time.perf_counter()
    axes = [np.linspace(lo, hi, a.points) for lo, hi in BOUNDS.values()]
    grid = [dict(zip(BOUNDS, map(float, p))) for p in itertools.product(*axes)]
    results = ray.get([evaluate.remote(p) for p in grid])
    print(f"{len(grid)} rasters in {time.perf_counter() - start:.1f} s on {int(ray.cluster_resources()['CPU'])} CPUs")
    results.sort(key=lambda r: r[1][0])
    for params, (objective, mean_mm, cv) in results[:5]:
        print(f"{objective:.4f}  {describe(params, mean_mm, cv)}")
    ray.shutdown()


if __name__ == "__main__":
    main()
