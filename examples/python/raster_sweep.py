"""The sweep shared by the optimisation examples: a raster over a region of the default wall,
its three parameters (step-over, travel speed, standoff) and its score.

The region is 0.8 m × 0.6 m in the middle of the default scene's 2 m × 2 m wall; the goal is a
mean thickness of TARGET_MM over it with the smallest coefficient of variation (CV).
"""

import numpy as np

import spraysim

TARGET_MM = 8.0
REGION = (0.8, 0.6)  # m, [width, height] of the raster's rectangle, centred on the wall
BOUNDS = {"step_over": (0.08, 0.25), "speed": (0.5, 1.5), "standoff": (1.0, 2.0)}  # m, m/s, m


def scenario(step_over, speed, standoff):
    """The default scene with the nozzle on a horizontal raster over the region. The run lasts
    until the raster's last pass ends plus 0.3 s for the last particles to land."""
    base = spraysim.Scenario().set_many(
        {
            "emitter.spawn_rate": 4e3,  # particles/s: fewer, heavier particles, for speed
            "target[0].resolution": [128, 128],
            "target[0].splat_radius": 0.02,
            "target[1].resolution": [100, 75],
            "nozzle": {
                "raster": {
                    "target": "wall",
                    "size": list(REGION),
                    "step_over": step_over,
                    "speed": speed,
                    "standoff": standoff,
                }
            },
        }
    )
    # When the raster stops spraying, worked out from its size, step-over and speed.
    return base.set("simulation.duration", round(base.spray_end + 0.3, 3))


def region_of(thickness):
    """The cells of a (rows, cols) wall map inside the raster's region."""
    rows, cols = thickness.shape
    h, w = REGION[1] / 2.0, REGION[0] / 2.0  # wall is 2 m × 2 m, centred
    r0, r1 = int(round((1 - h) / 2 * rows)), int(round((1 + h) / 2 * rows))
    c0, c1 = int(round((1 - w) / 2 * cols)), int(round((1 + w) / 2 * cols))
    return thickness[r0:r1, c0:c1]


def score(thickness):
    """(objective, mean in mm, CV): the relative miss of the target mean plus the CV (openings,
    NaN in the map, left out)."""
    region = region_of(thickness)
    mean = float(np.nanmean(region))
    cv = float(np.nanstd(region) / mean) if mean > 0 else float("inf")
    return abs(mean * 1e3 - TARGET_MM) / TARGET_MM + cv, mean * 1e3, cv


def describe(params, mean_mm, cv):
    return (
        f"step-over {params['step_over'] * 1e3:.0f} mm, speed {params['speed']:.2f} m/s, "
        f"standoff {params['standoff']:.2f} m -> mean {mean_mm:.2f} mm (target {TARGET_MM}), CV {cv:.3f}"
    )


def evaluate(params):
    """Runs one set of parameters; returns (objective, mean in mm, CV)."""
    sim = spraysim.Simulation(scenario(**params), threads=1)
    sim.run()
    return score(sim.thickness("wall"))


if __name__ == "__main__":
    p = {"step_over": 0.15, "speed": 1.0, "standoff": 1.5}
    print(describe(p, *evaluate(p)[1:]))
    print("score", np.round(evaluate(p)[0], 4))
