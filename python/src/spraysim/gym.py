"""A Gymnasium environment in which an agent sprays a target: shotcrete, paint or blasting.

Needs ``gymnasium`` (``pip install "./python[gym]"``); ``import spraysim`` alone does not.

The agent moves a nozzle over a rectangle or a cylinder shell (tunnel linings, arches: the
shell's unrolled map) in the surface's own coordinates ``(u, v)``, m from the middle of its map
(``u`` along the map's columns, the viewer's right; ``v`` along its rows, up). Each action
holds for ``control_dt`` seconds of simulation. Which parts of the motion the agent controls is
set by ``actions``, a tuple of:

- ``"move"`` (2 values): the travel in ``(u, v)``: a fraction of ``max_speed`` m/s
  (``action_mode="velocity"``) or of ``max_step`` m (``action_mode="pose"``); with ``"speed"``
  it gives the direction only;
- ``"standoff"`` (1): the distance from the surface, across ``standoff_range`` (m);
- ``"tilt"`` (2): the spray axis tilted from square-on towards ``+u`` and ``+v``, up to
  ``max_tilt_deg`` degrees;
- ``"speed"`` (1): the travel speed, 0 to ``max_speed`` m/s;
- ``"spray"`` (1): spray (> 0) or not.

Every value is in [-1, 1]; the action is a ``Box`` of their values in that order. The nozzle
stays over the target; what the agent does not control keeps its initial value (``standoff``,
square-on, spraying).

The observation is a dict: ``"thickness"`` the target's map resampled to ``obs_shape`` (row 0
at the bottom) and divided by the goal's reference thickness (the coating's initial thickness
when cleaning), capped at ``obs_max``; ``"mask"`` the share of each observed cell that is
surface (0 in openings); ``"nozzle"`` the pose ``(u, v, standoff, tilt_u, tilt_v, spray)``
scaled to [-1, 1] (``u``, ``v`` by the half size, the standoff across its range, the tilts by
``max_tilt_deg``, spray ±1). The world pose is ``env.sim.nozzle()``.

The task (``task``) is ``"thickness"``, a layer inside a band, or ``"cleaning"``, blasting a
coating off. For ``"thickness"`` the goal is a thickness (m; the band is ``goal × (1 ±
tolerance)``), a ``(low, high)`` band (m), or a map of thicknesses (m, any 2-D shape, resampled to
the target's map; the band is ``map × (1 ± tolerance)``). The score is

    -error - waste_weight * waste

where ``error`` is the mean over the target's cells (openings left out) of how far each cell's
thickness lies outside its band, in units of the band's mean, and ``waste`` the volume emitted
that is not on the target, in units of a layer of that thickness over the target. For
``"cleaning"`` the score is the share of cells blasted to bare substrate less ``wear_weight`` times
the substrate's mean wear in units of the coating's thickness. The reward is each step's gain in
the score, so an episode's return is its final score less its initial one. An episode ends
(truncated) after ``episode_steps`` actions.

Defaults by process (``process``; the scenario's own preset when a scenario is given):

======== ============================== ========= ==================== =========
process  task                           standoff  standoff range       max speed
======== ============================== ========= ==================== =========
shotcrete a 50 mm layer (40 to 60 mm)   1.0 m     0.6 to 1.5 m         0.5 m/s
painting a 40 µm wet film (35 to 45 µm) 0.3 m     0.15 to 0.45 m       1.0 m/s
blasting clean a 0.1 mm coat off        0.4 m     0.2 to 0.8 m         0.2 m/s
======== ============================== ========= ==================== =========

``render()`` (``render_mode="rgb_array"``) returns the map as a heatmap of ``render_size``
pixels (top row up): dark blue bare, blue below the band, green in it, red above (cleaning:
brown coated, light grey clean), grey openings, a white cross at the nozzle's footprint.

The environment is registered as ``"spraysim/Spray-v0"`` (``gymnasium.make("spraysim/Spray-v0")``).

>>> from spraysim.gym import SprayEnv
>>> env = SprayEnv(process="painting", actions=("move", "standoff", "spray"))
>>> obs, info = env.reset(seed=1)
>>> obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
"""

from __future__ import annotations

import math
import warnings
from typing import Any, Optional, Sequence, Tuple, Union

import gymnasium
import gymnasium.vector
import numpy as np
from gymnasium import spaces

from ._core import Scenario, Simulation, step_together

__all__ = ["SprayEnv", "SprayVectorEnv", "default_scenario", "ENV_ID", "ACTIONS", "PROCESSES"]

ENV_ID = "spraysim/Spray-v0"
"""The id under which ``gymnasium.make`` finds :class:`SprayEnv`."""

ACTIONS = {"move": 2, "standoff": 1, "tilt": 2, "speed": 1, "spray": 1}
"""The parts of an action and how many values each takes, in the order the action holds them."""

PROCESSES = {
    "shotcrete": {
        "task": "thickness",
        "goal": 0.05,
        "tolerance": 0.2,
        "standoff": 1.0,
        "standoff_range": (0.6, 1.5),
        "max_speed": 0.5,
    },
    "painting": {
        "task": "thickness",
        "goal": 40e-6,
        "tolerance": 0.125,
        "standoff": 0.3,
        "standoff_range": (0.15, 0.45),
        "max_speed": 1.0,
    },
    "blasting": {
        "task": "cleaning",
        "goal": None,
        "tolerance": 0.0,
        "standoff": 0.4,
        "standoff_range": (0.2, 0.8),
        "max_speed": 0.2,
    },
}
"""The default task of each process: its goal (m; None when cleaning), tolerance, standoff
(m), standoff range (m) and maximum travel speed (m/s)."""

_BLAST_COAT = 1e-4
"""The coating, m, on the default blasting scene's wall: an old 0.1 mm paint coat."""


def default_scenario(process: str = "shotcrete") -> Scenario:
    """The environment's default scene for ``process`` (``"shotcrete"``, ``"painting"`` or
    ``"blasting"``): the built-in default scene (a 2 m × 2 m wall, a floor collecting the
    rebound) with that process's preset and a coarser wall grid (128 × 128 cells of 15.6 mm)
    for speed; blasting with Oka's erosion model and a 0.1 mm coating on the wall."""
    if process not in PROCESSES:
        raise ValueError(f"process: must be one of {', '.join(PROCESSES)}, got {process!r}")
    scenario = Scenario.default().set_many(
        {
            "process.preset": process,
            "target[0].resolution": [128, 128],
            "target[1].resolution": [80, 60],
            "simulation.duration": 2.0,
        }
    )
    if process == "blasting":
        scenario = scenario.set_many({"process.erosion.model": "oka", "target[0].coating": _BLAST_COAT})
    return scenario


def _resample_axis(a: np.ndarray, size: int, axis: int) -> np.ndarray:
    """Sums of ``a``'s entries along ``axis`` into ``size`` nearly equal blocks (fewer cells), or
    its entries repeated (more cells)."""
    n = a.shape[axis]
    moved = np.moveaxis(a, axis, 0)
    if size <= n:
        out = np.zeros((size,) + moved.shape[1:])
        np.add.at(out, np.arange(n) * size // n, moved)
    else:
        out = moved[np.arange(size) * n // size]
    return np.moveaxis(out, 0, axis)


def resample(values: np.ndarray, shape: Tuple[int, int]) -> Tuple[np.ndarray, np.ndarray]:
    """A 2-D map averaged down (or repeated up) to ``shape``, NaN cells left out: the mean of
    each new cell's finite values (0 where there are none) and the share of them that is finite."""
    finite = np.isfinite(values)
    sums = np.where(finite, values, 0.0)
    weights = finite.astype(np.float64)
    counts = np.ones_like(weights)
    for axis, size in enumerate(shape):
        sums = _resample_axis(sums, size, axis)
        weights = _resample_axis(weights, size, axis)
        counts = _resample_axis(counts, size, axis)
    mean = np.divide(sums, weights, out=np.zeros_like(sums), where=weights > 0)
    return mean, weights / counts


def _positive(name: str, value: Any) -> float:
    v = float(value)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name}: must be a positive number, got {value!r}")
    return v


class SprayEnv(gymnasium.Env):
    """Spray a target (a rectangle or a cylinder shell) to a goal: a layer's thickness, or a
    coating blasted off. See the module's documentation for the actions, observations, reward
    and the defaults of each process.

    Parameters: ``scenario`` (a Scenario, dict or path; ``default_scenario(process)`` when None),
    ``process`` (``"shotcrete"``, ``"painting"``, ``"blasting"``; the scenario's preset when
    None), ``target`` (name; the first substrate target when None), ``actions`` (a tuple of
    ``ACTIONS``' names), ``task`` (``"thickness"`` or ``"cleaning"``), ``goal`` (m, a
    ``(low, high)`` band or a map), ``tolerance`` (share of the goal), ``standoff`` and
    ``standoff_range`` (m), ``max_tilt_deg``, ``max_speed`` (m/s), ``max_step`` (m),
    ``action_mode`` (``"velocity"`` or ``"pose"``), ``start`` (``(u, v)``, m), ``episode_steps``,
    ``control_dt`` (s, rounded to whole steps), ``obs_shape`` (rows, cols), ``obs_max``,
    ``waste_weight``, ``wear_weight``, ``render_size`` (height, width in pixels), ``threads``
    (worker threads per simulation), ``backend`` (what flies the particles, as for
    :class:`Simulation`: ``"cpu"``, ``"gpu"`` or ``"auto"``; the scenario's when None). Unset values take the process's defaults
    (:data:`PROCESSES`). A value out of range raises ``ValueError`` naming it.
    ``target_thickness`` is the deprecated former name of ``goal``.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 20}

    def __init__(
        self,
        scenario: Union[Scenario, dict, str, None] = None,
        process: Optional[str] = None,
        target: Optional[str] = None,
        actions: Sequence[str] = ("move",),
        task: Optional[str] = None,
        goal: Union[float, Tuple[float, float], np.ndarray, None] = None,
        tolerance: Optional[float] = None,
        standoff: Optional[float] = None,
        standoff_range: Optional[Tuple[float, float]] = None,
        max_tilt_deg: float = 30.0,
        max_speed: Optional[float] = None,
        max_step: float = 0.05,
        action_mode: str = "velocity",
        start: Tuple[float, float] = (0.0, 0.0),
        episode_steps: int = 40,
        control_dt: float = 0.05,
        obs_shape: Tuple[int, int] = (32, 32),
        obs_max: float = 4.0,
        waste_weight: float = 0.1,
        wear_weight: float = 0.1,
        render_size: Tuple[int, int] = (256, 256),
        threads: int = 1,
        backend: Optional[str] = None,
        render_mode: Optional[str] = None,
        target_thickness: Optional[float] = None,
    ) -> None:
        if target_thickness is not None:
            warnings.warn(
                "target_thickness is deprecated: give goal (a thickness in m, a (low, high) band or a map)",
                DeprecationWarning,
                stacklevel=2,
            )
            if goal is not None:
                raise ValueError("goal and target_thickness were both given: give goal only")
            goal = target_thickness
        if action_mode not in ("velocity", "pose"):
            raise ValueError(f"action_mode: must be 'velocity' or 'pose', got {action_mode!r}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode: must be None or 'rgb_array', got {render_mode!r}")
        if isinstance(actions, str):
            actions = (actions,)
        unknown = [a for a in actions if a not in ACTIONS]
        if unknown or not actions or len(set(actions)) != len(actions):
            raise ValueError(
                f"actions: must be distinct names among {', '.join(ACTIONS)} (at least one), got {tuple(actions)!r}"
            )
        self.actions = tuple(a for a in ACTIONS if a in actions)
        if scenario is None:
            process = process or "shotcrete"
            self.scenario = default_scenario(process)
        else:
            self.scenario = Scenario(scenario)
            process = process or str(self.scenario.get("process.preset"))
        if process not in PROCESSES:
            raise ValueError(f"process: must be one of {', '.join(PROCESSES)}, got {process!r}")
        self.process = process
        defaults = PROCESSES[process]
        self.task = task or defaults["task"]
        if self.task not in ("thickness", "cleaning"):
            raise ValueError(f"task: must be 'thickness' or 'cleaning', got {self.task!r}")

        names = self.scenario.target_names
        if target is None:
            roles = [self.scenario.get(f"target[{i}].role") for i in range(len(names))]
            target = next((n for n, r in zip(names, roles) if r == "substrate"), names[0])
        if target not in names:
            raise ValueError(f"target: no target named {target!r}; the targets are {', '.join(names)}")
        self.target = target
        self._target_index = names.index(target)

        self.tolerance = float(defaults["tolerance"] if tolerance is None else tolerance)
        if not (math.isfinite(self.tolerance) and 0 <= self.tolerance < 1):
            raise ValueError(f"tolerance: must be from 0 to less than 1, got {tolerance!r}")
        rng = defaults["standoff_range"] if standoff_range is None else standoff_range
        self.standoff_range = (_positive("standoff_range[0]", rng[0]), _positive("standoff_range[1]", rng[1]))
        if self.standoff_range[0] > self.standoff_range[1]:
            raise ValueError(f"standoff_range: must be (low, high) with low ≤ high, got {tuple(rng)!r}")
        self.standoff = _positive("standoff", defaults["standoff"] if standoff is None else standoff)
        self.max_tilt_deg = float(max_tilt_deg)
        if not (math.isfinite(self.max_tilt_deg) and 0 <= self.max_tilt_deg < 90):
            raise ValueError(f"max_tilt_deg: must be from 0 to less than 90, got {max_tilt_deg!r}")
        self.max_speed = _positive("max_speed", defaults["max_speed"] if max_speed is None else max_speed)
        self.max_step = _positive("max_step", max_step)
        self.action_mode = action_mode
        if int(episode_steps) != episode_steps or episode_steps < 1:
            raise ValueError(f"episode_steps: must be a whole number ≥ 1, got {episode_steps!r}")
        self.episode_steps = int(episode_steps)
        self.steps_per_action = max(1, round(_positive("control_dt", control_dt) / self.scenario.dt))
        self.control_dt = self.steps_per_action * self.scenario.dt
        self.obs_shape = self._shape("obs_shape", obs_shape)
        self.render_size = self._shape("render_size", render_size)
        self.obs_max = _positive("obs_max", obs_max)
        self.waste_weight = float(waste_weight)
        self.wear_weight = float(wear_weight)
        self.threads = int(threads)
        self.backend = backend
        self.render_mode = render_mode

        probe = Simulation(self.scenario, threads=self.threads, backend=self.backend)
        info = probe.target_info(target)
        if info["shape"] not in ("rectangle", "cylinder"):
            raise ValueError(
                f"target: {target!r} is a {info['shape']}; the environment sprays rectangles and cylinder shells"
            )
        self._info = info
        self._half = np.array(info["size"], dtype=np.float64) / 2.0
        self._map_shape = (int(info["rows"]), int(info["cols"]))
        self._mask = probe.mask(target)
        self._cell_area = info["cell_size"][0] * info["cell_size"][1]
        self._area = self._cell_area * float(self._mask.sum())
        self._coat = 0.0
        if self.task == "cleaning":
            self._coat = float(self.scenario.get(f"target[{self._target_index}].coating"))
            if probe.coating(target) is None or not self._coat > 0:
                raise ValueError(
                    f"task: cleaning needs erosion (process.erosion.model) and a coating on target {target!r} "
                    f"(target[{self._target_index}].coating > 0)"
                )
            self._low = self._high = np.full(self._map_shape, self._coat)
            self._ref = self._coat
        else:
            self._low, self._high = self._band(defaults["goal"] if goal is None else goal)
            solid = self._mask
            self._ref = float((self._low[solid] + self._high[solid]).mean() / 2.0)
            if not self._ref > 0:
                raise ValueError(f"goal: must be a positive thickness (m), got {goal!r}")
        self._start = np.clip(np.asarray(start, dtype=np.float64).reshape(2), -self._half, self._half)

        size = sum(ACTIONS[a] for a in self.actions)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(size,), dtype=np.float32)
        self.observation_space = spaces.Dict(
            {
                "thickness": spaces.Box(0.0, self.obs_max, shape=self.obs_shape, dtype=np.float32),
                "mask": spaces.Box(0.0, 1.0, shape=self.obs_shape, dtype=np.float32),
                "nozzle": spaces.Box(-1.0, 1.0, shape=(6,), dtype=np.float32),
            }
        )
        self.sim: Optional[Simulation] = None
        self._pose = self._initial_pose()
        self._score = 0.0
        self._steps = 0

    @staticmethod
    def _shape(name: str, value: Any) -> Tuple[int, int]:
        shape = tuple(int(x) for x in value)
        if len(shape) != 2 or min(shape) < 1 or max(shape) > 4096:
            raise ValueError(f"{name}: must be (rows, cols), each from 1 to 4096, got {value!r}")
        return (shape[0], shape[1])

    def _band(self, goal: Any) -> Tuple[np.ndarray, np.ndarray]:
        """The band (low, high maps, m) a thickness goal stands for."""
        tol = self.tolerance
        if np.ndim(goal) == 0:
            g = _positive("goal", goal)
            return np.full(self._map_shape, g * (1 - tol)), np.full(self._map_shape, g * (1 + tol))
        arr = np.asarray(goal, dtype=np.float64)
        if arr.shape == (2,):
            low, high = float(arr[0]), float(arr[1])
            if not (math.isfinite(low) and math.isfinite(high) and 0 <= low <= high and high > 0):
                raise ValueError(f"goal: a band must be (low, high) with 0 ≤ low ≤ high, m, got {tuple(arr)!r}")
            return np.full(self._map_shape, low), np.full(self._map_shape, high)
        if arr.ndim != 2 or not np.all(np.isfinite(arr)) or arr.min() < 0:
            raise ValueError(f"goal: a map must be a 2-D array of thicknesses ≥ 0 (m), got shape {arr.shape}")
        rows = np.arange(self._map_shape[0]) * arr.shape[0] // self._map_shape[0]
        cols = np.arange(self._map_shape[1]) * arr.shape[1] // self._map_shape[1]
        g = arr[np.ix_(rows, cols)]
        return g * (1 - tol), g * (1 + tol)

    def _initial_pose(self) -> dict:
        return {
            "uv": self._start.copy(),
            "standoff": float(np.clip(self.standoff, *self.standoff_range)) if "standoff" in self.actions else self.standoff,
            "tilt": np.zeros(2),
            "spray": True,
        }

    def _world(self, uv: np.ndarray, standoff: float, tilt: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """Position and spray axis of a pose given on the surface."""
        assert self.sim is not None
        f = self.sim.surface_frame(self.target, float(uv[0]), float(uv[1]), float(standoff))
        t = np.tan(np.radians(tilt))
        axis = -f["normal"] + t[0] * f["right"] + t[1] * f["up"]
        return f["position"], axis / np.linalg.norm(axis)

    def _map(self) -> np.ndarray:
        assert self.sim is not None
        if self.task == "cleaning":
            return self.sim.coating(self.target)
        return self.sim.thickness(self.target, copy=True)

    def _observation(self, values: np.ndarray) -> dict[str, np.ndarray]:
        mean, share = resample(values / self._ref, self.obs_shape)
        p = self._pose
        lo, hi = self.standoff_range
        standoff = 0.0 if hi == lo else 2 * (p["standoff"] - lo) / (hi - lo) - 1
        tilt = p["tilt"] / self.max_tilt_deg if self.max_tilt_deg > 0 else np.zeros(2)
        nozzle = np.concatenate([p["uv"] / self._half, [standoff], tilt, [1.0 if p["spray"] else -1.0]])
        return {
            "thickness": np.clip(mean, 0.0, self.obs_max).astype(np.float32),
            "mask": np.clip(share, 0.0, 1.0).astype(np.float32),
            "nozzle": np.clip(nozzle, -1.0, 1.0).astype(np.float32),
        }

    def _measure(self, values: np.ndarray) -> dict[str, Any]:
        assert self.sim is not None
        solid = self._mask
        v = values[solid]
        out: dict[str, Any] = {"time": self.sim.time}
        if self.task == "cleaning":
            cleaned = float(np.mean(v <= 0.0))
            eroded = self.sim.erosion(self.target)
            wear = float(np.mean(np.maximum(eroded[solid] - (self._coat - v), 0.0))) / self._coat
            out.update(cleaned_fraction=cleaned, wear=wear, score=cleaned - self.wear_weight * wear)
            return out
        low, high = self._low[solid], self._high[solid]
        error = float(np.mean(np.maximum(low - v, 0.0) + np.maximum(v - high, 0.0)) / self._ref)
        in_band = float(np.mean((v >= low) & (v <= high)))
        layer = float(v.sum() * self._cell_area)
        emitted = self.sim.emitted()[1]
        waste = max(emitted - layer, 0.0) / (self._ref * self._area)
        out.update(
            error=error,
            in_band=in_band,
            waste=waste,
            score=-error - self.waste_weight * waste,
            mean_thickness=float(v.mean()),
        )
        return out

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """Starts an episode at time 0 with the nozzle at ``start``, square to the surface at
        ``standoff``, spraying. The simulation's own seed is ``seed`` when given, else drawn
        from the environment's random generator."""
        super().reset(seed=seed)
        sim_seed = seed if seed is not None else int(self.np_random.integers(0, 2**31 - 1))
        scenario = self.scenario.set("simulation.seed", int(sim_seed))
        self.sim = Simulation(scenario, threads=self.threads, backend=self.backend)
        self._pose = self._initial_pose()
        p = self._pose
        position, axis = self._world(p["uv"], p["standoff"], p["tilt"])
        self.sim.set_nozzle(position, axis, spray=p["spray"])
        self._steps = 0
        values = self._map()
        info = self._measure(values)
        self._score = info["score"]
        return self._observation(values), info

    def _next_pose(self, action: np.ndarray) -> dict:
        """The pose an action asks for, from the present one."""
        p = self._pose
        parts, k = {}, 0
        for name in self.actions:
            parts[name] = action[k : k + ACTIONS[name]]
            k += ACTIONS[name]
        uv, standoff, tilt, spray = p["uv"], p["standoff"], p["tilt"], p["spray"]
        if "move" in parts:
            move = parts["move"]
            if "speed" in parts:
                length = float(np.linalg.norm(move))
                direction = move / length if length > 1e-6 else np.zeros(2)
                move = direction * (parts["speed"][0] + 1) / 2 * self.max_speed * self.control_dt
            elif self.action_mode == "velocity":
                move = move * self.max_speed * self.control_dt
            else:
                move = move * self.max_step
            uv = np.clip(uv + move, -self._half, self._half)
        if "standoff" in parts:
            lo, hi = self.standoff_range
            standoff = lo + (parts["standoff"][0] + 1) / 2 * (hi - lo)
        if "tilt" in parts:
            tilt = parts["tilt"] * self.max_tilt_deg
        if "spray" in parts:
            spray = bool(parts["spray"][0] > 0)
        return {"uv": uv, "standoff": float(standoff), "tilt": np.asarray(tilt, dtype=np.float64), "spray": spray}

    def step(self, action: np.ndarray) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """Moves the nozzle as ``action`` says for ``control_dt`` seconds of simulation."""
        self._begin_step(action)
        assert self.sim is not None
        self.sim.step(self.steps_per_action)
        return self._end_step()

    def _begin_step(self, action: np.ndarray) -> None:
        """Checks ``action`` and sets the nozzle's path for the step it asks for; the simulation
        is then stepped ``steps_per_action`` steps, and :meth:`_end_step` ends the step."""
        if self.sim is None:
            raise RuntimeError("call reset() before step()")
        a = np.asarray(action, dtype=np.float64).reshape(-1)
        if a.shape != self.action_space.shape:
            raise ValueError(f"action: must hold {self.action_space.shape[0]} values ({', '.join(self.actions)}), got {a.shape[0]}")
        a = np.clip(np.nan_to_num(a), -1.0, 1.0)
        before, after = self._pose, self._next_pose(a)
        t0 = self.sim.time
        # Legs of at most 5 cm, so that the nozzle follows a curved surface.
        legs = max(1, min(20, math.ceil(float(np.linalg.norm(after["uv"] - before["uv"])) / 0.05)))
        waypoints = []
        for j in range(legs + 1):
            f = j / legs
            uv = before["uv"] + f * (after["uv"] - before["uv"])
            standoff = before["standoff"] + f * (after["standoff"] - before["standoff"])
            tilt = before["tilt"] + f * (after["tilt"] - before["tilt"])
            position, axis = self._world(uv, standoff, tilt)
            waypoints.append(
                {"time": t0 + f * self.control_dt, "position": position, "axis": axis, "spray": after["spray"]}
            )
        self.sim.set_nozzle_path(waypoints)
        self._next = after

    def _end_step(self) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """The step's observation, reward, end flags and info, once the simulation has stepped."""
        self._pose = self._next
        self._steps += 1
        values = self._map()
        info = self._measure(values)
        reward = info["score"] - self._score
        self._score = info["score"]
        truncated = self._steps >= self.episode_steps
        return self._observation(values), float(reward), False, truncated, info

    def render(self) -> Optional[np.ndarray]:
        """The target's map as an RGB heatmap of ``render_size`` pixels (uint8, top row up): see
        the module's documentation for the colours; a white cross marks the nozzle's footprint."""
        if self.render_mode != "rgb_array" or self.sim is None:
            return None
        values = self._map()
        mean, share = resample(values / self._ref, self.render_size)
        if self.task == "cleaning":
            anchors = [0.0, 1e-9, 1.0]
            colours = [(215, 215, 220), (170, 150, 120), (120, 70, 40)]
        else:
            lo = float(np.mean(self._low[self._mask])) / self._ref
            hi = float(np.mean(self._high[self._mask])) / self._ref
            anchors = [0.0, max(lo, 1e-9) * 0.999, lo, hi, max(2 * hi, hi + 1e-9)]
            colours = [(20, 20, 60), (60, 120, 230), (40, 190, 70), (40, 190, 70), (220, 40, 40)]
        img = np.stack([np.interp(mean, anchors, [c[i] for c in colours]) for i in range(3)], axis=-1)
        img[share < 0.5] = (128, 128, 128)
        rows, cols = self.render_size
        uv = self._pose["uv"] / self._half
        r = int(np.clip((uv[1] + 1) / 2 * rows, 0, rows - 1))
        c = int(np.clip((uv[0] + 1) / 2 * cols, 0, cols - 1))
        arm = max(2, min(rows, cols) // 40)
        img[max(0, r - arm) : r + arm + 1, c] = 255
        img[r, max(0, c - arm) : c + arm + 1] = 255
        return np.ascontiguousarray(img[::-1].astype(np.uint8))


class SprayVectorEnv(gymnasium.vector.VectorEnv):
    """``num_envs`` copies of :class:`SprayEnv` (each built with ``**kwargs``) stepped together:
    their simulations advance at once (:func:`spraysim.step_together`), on the GPU in shared
    dispatches (one dispatch for all) with ``backend="gpu"``, each on a thread of its own on the
    CPU otherwise. Observations, rewards and flags are stacked along a first axis of
    ``num_envs``; each environment's results equal :class:`SprayEnv`'s with the same seed and
    actions. An environment whose episode ended is reset by the next step, whose action for it
    is ignored (Gymnasium's next-step autoreset); ``reset(seed=s)`` seeds environment ``k`` with
    ``s + k``. Needs Gymnasium 1.0 or later.

    >>> from spraysim.gym import SprayVectorEnv
    >>> envs = SprayVectorEnv(4, process="painting", episode_steps=3)
    >>> obs, info = envs.reset(seed=1)
    >>> obs, rewards, terminations, truncations, info = envs.step(envs.action_space.sample())
    """

    def __init__(self, num_envs: int, **kwargs: Any) -> None:
        if not hasattr(gymnasium.vector, "AutoresetMode"):
            raise RuntimeError(f"SprayVectorEnv needs Gymnasium 1.0 or later, found {gymnasium.__version__}")
        if int(num_envs) != num_envs or num_envs < 1:
            raise ValueError(f"num_envs: must be a whole number ≥ 1, got {num_envs!r}")
        self.num_envs = int(num_envs)
        self.envs = [SprayEnv(**kwargs) for _ in range(self.num_envs)]
        first = self.envs[0]
        self.metadata = {
            **SprayEnv.metadata,
            "autoreset_mode": gymnasium.vector.AutoresetMode.NEXT_STEP,
        }
        self.render_mode = first.render_mode
        self.single_observation_space = first.observation_space
        self.single_action_space = first.action_space
        self.observation_space = gymnasium.vector.utils.batch_space(first.observation_space, self.num_envs)
        self.action_space = gymnasium.vector.utils.batch_space(first.action_space, self.num_envs)
        self._ended = np.zeros(self.num_envs, dtype=bool)

    def _stack(self, observations: list[dict[str, np.ndarray]]) -> dict[str, np.ndarray]:
        return {key: np.stack([o[key] for o in observations]) for key in observations[0]}

    def _merge(self, infos: list[dict[str, Any]]) -> dict[str, Any]:
        merged: dict[str, Any] = {}
        for k, info in enumerate(infos):
            merged = self._add_info(merged, info, k)
        return merged

    def reset(
        self, *, seed: Optional[Union[int, Sequence[Optional[int]]]] = None, options: Optional[dict[str, Any]] = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """Starts every environment's episode; ``seed`` is an int (environment ``k`` takes
        ``seed + k``), a list of seeds (one each, None for a drawn one) or None."""
        if seed is None or isinstance(seed, (int, np.integer)):
            seeds = [None if seed is None else int(seed) + k for k in range(self.num_envs)]
        else:
            seeds = list(seed)
            if len(seeds) != self.num_envs:
                raise ValueError(f"seed: must hold {self.num_envs} seeds, one per environment, got {len(seeds)}")
        results = [env.reset(seed=s, options=options) for env, s in zip(self.envs, seeds)]
        self._ended[:] = False
        return self._stack([r[0] for r in results]), self._merge([r[1] for r in results])

    def step(
        self, actions: np.ndarray
    ) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """Steps every environment by its row of ``actions``, together; an environment whose
        episode ended at the last step is reset instead (reward 0, not ended)."""
        a = np.asarray(actions, dtype=np.float64)
        if a.shape != self.action_space.shape:
            raise ValueError(f"actions: must have shape {self.action_space.shape}, got {a.shape}")
        stepping = [k for k in range(self.num_envs) if not self._ended[k]]
        for k in stepping:
            self.envs[k]._begin_step(a[k])
        sims = [self.envs[k].sim for k in stepping]
        if sims:
            step_together(sims, self.envs[0].steps_per_action)
        observations: list[dict[str, np.ndarray]] = []
        rewards = np.zeros(self.num_envs)
        terminations = np.zeros(self.num_envs, dtype=bool)
        truncations = np.zeros(self.num_envs, dtype=bool)
        infos: list[dict[str, Any]] = []
        for k, env in enumerate(self.envs):
            if self._ended[k]:
                obs, info = env.reset()
            else:
                obs, rewards[k], terminations[k], truncations[k], info = env._end_step()
            observations.append(obs)
            infos.append(info)
        self._ended = terminations | truncations
        return self._stack(observations), rewards, terminations, truncations, self._merge(infos)

    def render(self) -> Optional[tuple[np.ndarray, ...]]:
        """Each environment's :meth:`SprayEnv.render`, with ``render_mode="rgb_array"``."""
        if self.render_mode != "rgb_array":
            return None
        return tuple(env.render() for env in self.envs)


if ENV_ID not in gymnasium.envs.registry:
    gymnasium.register(id=ENV_ID, entry_point="spraysim.gym:SprayEnv")
