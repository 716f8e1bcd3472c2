"""Optimise a raster's step-over, travel speed and standoff with optuna, to reach a target mean
thickness on a wall region with the smallest coefficient of variation (see raster_sweep.py).

Trials are asked for in batches and each batch runs in parallel inside Rust with
spraysim.run_many; the best raster is printed and run again to write its outputs, among them
the heatmap out/optuna_raster/wall_thickness.png.

    pip install ./python optuna
    python examples/python/optuna_raster.py [--trials 40] [--batch 4] [--threads 0]

About 5 s on 2 cores with the defaults.
"""

import argparse
import time

import optuna

import spraysim
from raster_sweep import BOUNDS, describe, scenario, score


def main():
    parser = argparse.ArgumentParser(description="optimise a raster with optuna")
    parser.add_argument("--trials", type=int, default=40)
    parser.add_argument("--batch", type=int, default=4, help="trials run in parallel at once")
    parser.add_argument("--threads", type=int, default=0, help="worker threads (0: one per core)")
    parser.add_argument("--output", default="out/optuna_raster", help="output folder")
    a = parser.parse_args()

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = optuna.create_study(direction="minimize", sampler=optuna.samplers.TPESampler(seed=1))
    start = time.perf_counter()
    while len(study.trials) < a.trials:
        trials = [study.ask() for _ in range(min(a.batch, a.trials - len(study.trials)))]
        params = [{k: t.suggest_float(k, lo, hi) for k, (lo, hi) in BOUNDS.items()} for t in trials]
        results = spraysim.run_many([scenario(**p) for p in params], threads=a.threads, maps=True)
        for trial, p, (metrics, maps) in zip(trials, params, results):
            objective, mean_mm, cv = score(maps["wall"])
            trial.set_user_attr("mean_mm", mean_mm)
            trial.set_user_attr("cv", cv)
            study.tell(trial, objective)
        best = study.best_trial
        print(f"{len(study.trials):3d} trials, best {best.value:.4f}: "
              f"{describe(best.params, best.user_attrs['mean_mm'], best.user_attrs['cv'])}")
    print(f"{len(study.trials)} trials in {time.perf_counter() - start:.1f} s")

    best = study.best_trial
    print("best raster:", describe(best.params, best.user_attrs["mean_mm"], best.user_attrs["cv"]))
    sim = spraysim.Simulation(scenario(**best.params), threads=a.threads)
    waypoints = sim.nozzle_waypoints()
    print(f"best path: {len(waypoints)} waypoints over {waypoints[-1]['time']:.2f} s, "
          f"from {waypoints[0]['position'].round(3).tolist()} to {waypoints[-1]['position'].round(3).tolist()} m")
    sim.run()
    files = sim.write_outputs(a.output)
    print(f"wrote {len(files)} files to {a.output}/ (heatmap: {a.output}/wall_thickness.png)")


if __name__ == "__main__":
    main()
