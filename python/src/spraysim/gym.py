"""A Gymnasium environment in which an agent moves a spray nozzle over a target.

Needs ``gymnasium`` (``pip install "./python[gym]"``); ``import spraysim`` alone does not.

The nozzle stays square to the target at a fixed standoff and moves in the target's plane.
Each action sets its velocity (``action_mode="velocity"``: a fraction of ``max_speed`` m/s along
the target's ``right`` and ``up`` axes) or its displacement (``action_mode="pose"``: a fraction
of ``max_step`` m) for the next ``control_dt`` seconds, in which the simulation runs; the
nozzle is kept over the target. The observation is the nozzle's position on the target
(``"nozzle"``, -1 to 1 across its width and height) and the target's thickness averaged down to
``obs_shape`` cells and divided by ``target_thickness`` (``"thickness"``, row 0 at the bottom,
capped at ``obs_max``).

The reward is the step's gain in the score

    coverage - excess_weight * excess - waste_weight * waste

where ``coverage`` is the mean over cells of min(t, T) / T (1 once every cell holds the target
thickness T), ``excess`` the mean of max(t - T, 0) / T (material past the target) and ``waste``
the volume emitted that is not in the target's layer (rebound, overspray), in units of a layer
of thickness T over the whole target. An episode's return is therefore its final score. An
episode ends (truncated) after ``episode_steps`` actions; it never terminates otherwise.

The environment is registered as ``"spraysim/Spray-v0"`` (``gymnasium.make("spraysim/Spray-v0")``).

>>> from spraysim.gym import SprayEnv
>>> env = SprayEnv()
>>> obs, info = env.reset(seed=1)
>>> obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
"""

from __future__ import annotations

from typing import Any, Optional, Union

import gymnasium
import numpy as np
from gymnasium import spaces

from ._core import Scenario, Simulation

__all__ = ["SprayEnv", "default_scenario", "ENV_ID"]

ENV_ID = "spraysim/Spray-v0"
"""The id under which ``gymnasium.make`` finds :class:`SprayEnv`."""


def default_scenario() -> Scenario:
    """The environment's default scene: the built-in default scene (shotcrete onto a
    2 m × 2 m wall from 1 m, a floor collecting the rebound) with a coarser wall grid
    (128 × 128 cells of 15.6 mm) for speed."""
    return Scenario.default().set_many(
        {"target[0].resolution": [128, 128], "target[1].resolution": [80, 60], "simulation.duration": 2.0}
    )


def _block_edges(n: int, parts: int) -> np.ndarray:
    """Start indices of ``parts`` nearly equal blocks of ``n`` cells."""
    return np.linspace(0, n, parts + 1).astype(np.int64)[:-1]


class SprayEnv(gymnasium.Env):
    """Move a spray nozzle over a target to build a layer of ``target_thickness`` (m).

    Parameters: ``scenario`` (a Scenario, dict or path; ``default_scenario()`` when None),
    ``target`` (name of the target to cover), ``target_thickness`` (m), ``episode_steps``
    (actions per episode), ``control_dt`` (s of simulation per action, rounded to whole steps),
    ``action_mode`` (``"velocity"`` or ``"pose"``), ``max_speed`` (m/s), ``max_step`` (m),
    ``obs_shape`` (rows, cols of the thickness observation), ``obs_max`` (cap of the
    thickness observation, in units of ``target_thickness``), ``excess_weight`` and
    ``waste_weight`` (penalties of the score), ``threads`` (worker threads per simulation).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 20}

    def __init__(
        self,
        scenario: Union[Scenario, dict, str, None] = None,
        target: str = "wall",
        target_thickness: float = 0.5e-3,
        episode_steps: int = 40,
        control_dt: float = 0.05,
        action_mode: str = "velocity",
        max_speed: float = 1.0,
        max_step: float = 0.05,
        obs_shape: tuple[int, int] = (16, 16),
        obs_max: float = 10.0,
        excess_weight: float = 1.0,
        waste_weight: float = 0.25,
        threads: int = 1,
        render_mode: Optional[str] = None,
    ) -> None:
        if action_mode not in ("velocity", "pose"):
            raise ValueError(f"action_mode must be 'velocity' or 'pose', got {action_mode!r}")
        if not target_thickness > 0 or not episode_steps > 0 or not control_dt > 0:
            raise ValueError("target_thickness, episode_steps and control_dt must be positive")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self.scenario = Scenario(scenario) if scenario is not None else default_scenario()
        self.target = target
        self.target_thickness = float(target_thickness)
        self.episode_steps = int(episode_steps)
        self.steps_per_action = max(1, round(control_dt / self.scenario.dt))
        self.control_dt = self.steps_per_action * self.scenario.dt
        self.action_mode = action_mode
        self.max_speed = float(max_speed)
        self.max_step = float(max_step)
        self.obs_shape = (int(obs_shape[0]), int(obs_shape[1]))
        self.obs_max = float(obs_max)
        self.excess_weight = float(excess_weight)
        self.waste_weight = float(waste_weight)
        self.threads = int(threads)
        self.render_mode = render_mode

        probe = Simulation(self.scenario, threads=self.threads)
        info = probe.target_info(target)
        self._center, self._right, self._up = info["center"], info["right"], info["up"]
        self._normal = info["normal"]
        self._half = np.array(info["size"]) / 2.0
        self._area = info["size"][0] * info["size"][1]
        self._cell_area = info["cell_size"][0] * info["cell_size"][1]
        self._rows = _block_edges(info["rows"], self.obs_shape[0])
        self._cols = _block_edges(info["cols"], self.obs_shape[1])
        counts_r = np.diff(np.append(self._rows, info["rows"]))
        counts_c = np.diff(np.append(self._cols, info["cols"]))
        self._counts = np.outer(counts_r, counts_c).astype(np.float64)
        # The nozzle keeps the scenario's standoff from the target, square to it.
        start = probe.nozzle()["position"] - self._center
        self._standoff = float(start @ self._normal)
        self._start = np.clip(np.array([start @ self._right, start @ self._up]), -self._half, self._half)

        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self.observation_space = spaces.Dict(
            {
                "nozzle": spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32),
                "thickness": spaces.Box(0.0, self.obs_max, shape=self.obs_shape, dtype=np.float32),
            }
        )
        self.sim: Optional[Simulation] = None
        self._uv = self._start.copy()
        self._score = 0.0
        self._steps = 0

    def _position(self, uv: np.ndarray) -> np.ndarray:
        return self._center + uv[0] * self._right + uv[1] * self._up + self._standoff * self._normal

    def _thickness(self) -> np.ndarray:
        assert self.sim is not None
        return self.sim.thickness(self.target)

    def _observation(self, t: np.ndarray) -> dict[str, np.ndarray]:
        blocks = np.add.reduceat(np.add.reduceat(t, self._rows, axis=0), self._cols, axis=1)
        mean = np.minimum(blocks / self._counts / self.target_thickness, self.obs_max)
        return {
            "nozzle": (self._uv / self._half).astype(np.float32),
            "thickness": mean.astype(np.float32),
        }

    def _measure(self, t: np.ndarray) -> dict[str, float]:
        assert self.sim is not None
        T = self.target_thickness
        coverage = float(np.minimum(t, T).mean() / T)
        excess = float(np.maximum(t - T, 0.0).mean() / T)
        layer = float(t.sum() * self._cell_area)
        emitted = self.sim.emitted()[1]
        waste = max(emitted - layer, 0.0) / (T * self._area)
        score = coverage - self.excess_weight * excess - self.waste_weight * waste
        return {
            "coverage": coverage,
            "excess": excess,
            "waste": waste,
            "score": score,
            "mean_thickness": float(t.mean()),
            "time": self.sim.time,
        }

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """Starts an episode at time 0 with the nozzle at the scenario's start. The
        simulation's own seed is ``seed`` when given, else drawn from the environment's random
        generator."""
        super().reset(seed=seed)
        sim_seed = seed if seed is not None else int(self.np_random.integers(0, 2**31 - 1))
        scenario = self.scenario.set("simulation.seed", int(sim_seed))
        self.sim = Simulation(scenario, threads=self.threads)
        self._uv = self._start.copy()
        axis = -self._normal
        self.sim.set_nozzle(self._position(self._uv), axis)
        self._steps = 0
        t = self._thickness()
        info = self._measure(t)
        self._score = info["score"]
        return self._observation(t), info

    def step(
        self, action: np.ndarray
    ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """Moves the nozzle as ``action`` says for ``control_dt`` seconds of simulation."""
        if self.sim is None:
            raise RuntimeError("call reset() before step()")
        a = np.clip(np.asarray(action, dtype=np.float64).reshape(2), -1.0, 1.0)
        move = a * (self.max_speed * self.control_dt if self.action_mode == "velocity" else self.max_step)
        end = np.clip(self._uv + move, -self._half, self._half)
        t0 = self.sim.time
        axis = -self._normal
        self.sim.set_nozzle_path(
            [
                {"time": t0, "position": self._position(self._uv), "axis": axis},
                {"time": t0 + self.control_dt, "position": self._position(end), "axis": axis},
            ]
        )
        self.sim.step(self.steps_per_action)
        self._uv = end
        self._steps += 1
        t = self._thickness()
        info = self._measure(t)
        reward = info["score"] - self._score
        self._score = info["score"]
        truncated = self._steps >= self.episode_steps
        return self._observation(t), float(reward), False, truncated, info

    def render(self) -> Optional[np.ndarray]:
        """An RGB image of the thickness observation (black: bare, white: target thickness or
        more; the nozzle's cell in red), top row up."""
        if self.render_mode != "rgb_array" or self.sim is None:
            return None
        obs = self._observation(self._thickness())
        grey = (np.clip(obs["thickness"], 0.0, 1.0) * 255).astype(np.uint8)
        img = np.repeat(grey[:, :, None], 3, axis=2)
        rows, cols = self.obs_shape
        r = min(rows - 1, int((obs["nozzle"][1] + 1) / 2 * rows))
        c = min(cols - 1, int((obs["nozzle"][0] + 1) / 2 * cols))
        img[r, c] = (255, 0, 0)
        return np.ascontiguousarray(img[::-1])


if ENV_ID not in gymnasium.envs.registry:
    gymnasium.register(id=ENV_ID, entry_point="spraysim.gym:SprayEnv")
