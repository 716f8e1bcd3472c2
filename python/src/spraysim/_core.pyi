"""Type stubs of the extension module ``spraysim._core`` (re-exported by ``spraysim``).

SI units throughout (m, s, kg); angles in degrees everywhere, the unit in every name
(``roll_deg``, ``angles_deg``); quaternions as (w, x, y, z); NaN in openings in every float map.
"""

import os
from typing import Any, Callable, Iterable, Literal, Mapping, Optional, Sequence, Tuple, TypedDict, Union, final, overload

import numpy as np
import numpy.typing as npt

__all__ = [
    "ALIVE",
    "HIT_SUBSTRATE",
    "RELEASED",
    "Scenario",
    "ScenarioError",
    "Simulation",
    "Snapshot",
    "presets",
    "presets_toml",
    "run_many",
    "step_together",
    "__version__",
]

__version__: str

ALIVE: int
"""Status bit of ``Simulation.particles()["state"]``: the particle is in flight."""
HIT_SUBSTRATE: int
"""Status bit: the particle has struck a substrate target at least once."""
RELEASED: int
"""Status bit: material released by a cohesive failure, not a particle from the nozzle."""

_ScenarioSource = Union["Scenario", Mapping[str, Any], str, "os.PathLike[str]", None]
"""A scenario, a dict shaped like the TOML file, a file path, or None (the default scene)."""

class ScenarioError(ValueError):
    """A scenario was refused: unknown key, wrong type, impossible value, a value nested deeper
    than 32 levels of dicts and lists or holding itself.

    The text is ``key: message (location)``, e.g. ``emitter.spawn_rate: must be greater than 0
    1/s, got -1 (Scenario.set('emitter.spawn_rate', -1.0))``; a syntax or read error, which has
    no key, reads ``location: message``. ``message`` holds the words the ``spraysim`` command
    prints for the same value.
    """

    key: Optional[str]
    """Dotted key refused (``"emitter.speed"``, ``"target[0].resolution"``); None for a syntax or
    read error."""
    location: Optional[str]
    """Where the value was given: ``file:line``, ``<dict>`` (or ``scenarios[i]`` in
    ``run_many``), or the Python call that set it, e.g. ``Scenario.set('emitter.speed', [30, 20])``."""
    message: str
    """What is wrong."""

@final
class Scenario:
    """A complete, validated, immutable scenario: every default filled in (``docs/scenario.md``
    lists every key with its unit and default).

    ``Scenario()`` is the built-in default scene (wet-mix shotcrete for 2 s onto a 2 m × 2 m
    wall from 1 m, with a floor collecting the rebound); ``Scenario(path)`` reads a TOML file,
    ``Scenario(dict)`` a dict shaped like the file. Equal when they resolve to the same values.

    Values from Python (dicts, ``set`` values) may nest dicts and lists at most 32 levels deep
    and must not contain themselves; both are refused with :class:`ScenarioError` naming the key.
    """

    def __new__(cls, source: _ScenarioSource = None) -> "Scenario": ...
    @staticmethod
    def default() -> "Scenario":
        """The built-in default scene."""
    @staticmethod
    def from_file(path: Union[str, "os.PathLike[str]"]) -> "Scenario":
        """Reads a TOML scenario file; paths it names are relative to its folder."""
    @staticmethod
    def from_toml(text: str, origin: str = "<string>") -> "Scenario":
        """Parses TOML scenario text; ``origin`` names it in errors."""
    @staticmethod
    def from_dict(data: Mapping[str, Any], origin: str = "<dict>") -> "Scenario":
        """Reads a dict shaped like the TOML file, with the same checks."""
    def set(self, key: str, value: Any) -> "Scenario":
        """A new scenario with the dotted ``key`` (``"emitter.spawn_rate"``,
        ``"target[0].resolution"``, ``"emitter.speed"``) set to ``value`` (number, bool, str,
        list, dict or numpy array, in the file's units: m, s, kg, degrees). Checked exactly as a
        file's value; raises :class:`ScenarioError` naming the key and this call."""
    def set_many(self, overrides: Union[Mapping[str, Any], Iterable[Tuple[str, Any]]]) -> "Scenario":
        """``set`` for several keys, applied in order."""
    def assign(self, assignment: str) -> "Scenario":
        """``set`` from ``"KEY=VALUE"`` text as the command's ``--set`` takes it (the value is
        TOML, or a bare word taken as a string)."""
    def get(self, key: str) -> Any:
        """The resolved value at a dotted key, e.g. ``get("emitter.speed") == [20.0, 30.0]``
        (m/s). Raises ``KeyError`` for a key the resolved scenario does not hold."""
    def to_toml(self) -> str:
        """The scenario as TOML with every value explicit (``scenario.resolved.toml``)."""
    def to_dict(self) -> dict[str, Any]:
        """The resolved scenario as a dict shaped like the file."""
    @property
    def origin(self) -> str:
        """Where it came from: a file name, ``"<default scene>"``, ``"<dict>"``, …"""
    @property
    def dt(self) -> float:
        """Time step Δt, s."""
    @property
    def duration(self) -> float:
        """Simulated duration, s."""
    @property
    def seed(self) -> int:
        """Seed of every random stream."""
    @property
    def spray_end(self) -> Optional[float]:
        """When the nozzle stops spraying for good, s, from its motion (waypoints, tool path,
        raster and its speed) without running; None when it sprays until the run ends."""
    @property
    def path_end(self) -> float:
        """When the nozzle's path reaches its last waypoint, s (0 for a static or circling
        nozzle), without running."""
    @property
    def target_names(self) -> list[str]:
        """The targets' names, in file order."""

@final
class Snapshot:
    """A saved state of a :class:`Simulation`; ``Simulation.restore`` continues from it exactly
    as the original did. Immutable; restore it as often as you like."""

    @property
    def time(self) -> float:
        """Simulated time of the saved state, s."""
    @property
    def steps_done(self) -> int:
        """Steps taken up to the saved state."""

class _Particles(TypedDict):
    """The particles in flight, one row each (``Simulation.particles()``)."""

    position: npt.NDArray[np.float64]
    """(n, 3) positions, m."""
    velocity: npt.NDArray[np.float64]
    """(n, 3) velocities, m/s."""
    age: npt.NDArray[np.float64]
    """(n,) time since emission, s."""
    id: npt.NDArray[np.uint32]
    """(n,) emission index within the run."""
    impacts: npt.NDArray[np.uint16]
    """(n,) impacts so far."""
    state: npt.NDArray[np.uint8]
    """(n,) status bits: ``ALIVE | HIT_SUBSTRATE | RELEASED``."""

class _Nozzle(TypedDict):
    """The nozzle now (``Simulation.nozzle()``)."""

    position: npt.NDArray[np.float64]
    """(3,) position, m."""
    axis: npt.NDArray[np.float64]
    """(3,) unit spray axis."""
    quaternion: npt.NDArray[np.float64]
    """(4,) orientation (w, x, y, z): takes the tool's x, y, z axes to the aperture's width axis,
    its height axis and the spray axis."""
    matrix: npt.NDArray[np.float64]
    """(4, 4) homogeneous pose: columns width axis, height axis, spray axis, position."""
    roll_deg: float
    """Roll of the aperture about the spray axis, degrees."""
    velocity: npt.NDArray[np.float64]
    """(3,) velocity along its path, m/s."""
    spraying: bool

class _Circle(TypedDict):
    """A circle superposed on a nozzle path (``Simulation.nozzle_path()["circle"]``)."""

    radius: float
    """m."""
    frequency: float
    """Revolutions per second, Hz."""
    start: float
    """Time at which the offset is ``radius · first``, s."""
    first: npt.NDArray[np.float64]
    second: npt.NDArray[np.float64]
    """The offset's unit direction a quarter turn after ``first``."""
    axis: npt.NDArray[np.float64]
    """The spray axis the circle's plane is perpendicular to."""

class _NozzlePath(TypedDict):
    """A nozzle path exactly (``Simulation.nozzle_path()``)."""

    waypoints: list[dict[str, Any]]
    roll_deg: float
    circle: Optional[_Circle]

class _Samples(TypedDict):
    """The nozzle's poses at given times (``Simulation.nozzle_at``)."""

    position: npt.NDArray[np.float64]
    axis: npt.NDArray[np.float64]
    spraying: npt.NDArray[np.bool_]

class _SurfaceFrame(TypedDict):
    """A point of a surface and its frame (``Simulation.surface_frame``)."""

    position: npt.NDArray[np.float64]
    normal: npt.NDArray[np.float64]
    right: npt.NDArray[np.float64]
    up: npt.NDArray[np.float64]

class _Waypoint(TypedDict, total=False):
    """A waypoint of a nozzle path: ``time`` (s), ``position`` (m) and one orientation, ``axis``
    (a vector), ``quaternion`` (w, x, y, z) or ``matrix`` (4 × 4, holding the position instead
    of ``position``), and ``spray`` (spray from here to the next waypoint; default True)."""

    time: float
    position: npt.ArrayLike
    axis: npt.ArrayLike
    quaternion: npt.ArrayLike
    matrix: npt.ArrayLike
    spray: bool

class _TargetGeometry(TypedDict, total=False):
    """Keys of ``Simulation.target_info`` that depend on the target's shape."""

    rows: int
    """Rows of a rectangle's or a shell's map (a mesh has none)."""
    cols: int
    """Columns of a rectangle's or a shell's map."""
    cell_size: Tuple[float, float]
    """Cell (width along ``right`` or the arc, height along ``up`` or the axis), m."""
    size: Tuple[float, float]
    """A rectangle's (width, height), or a shell's unrolled (arc length, length), m."""
    center: npt.NDArray[np.float64]
    """A rectangle's centre, or the centre of a shell's axis, m."""
    normal: npt.NDArray[np.float64]
    """A rectangle's unit normal, towards the side that receives spray."""
    up: npt.NDArray[np.float64]
    """A rectangle's unit vector along which rows grow."""
    right: npt.NDArray[np.float64]
    """A rectangle's unit vector ``up × normal`` along which columns grow (the viewer's right,
    looking at the target from the spray side)."""
    axis: npt.NDArray[np.float64]
    """A shell's unit axis, along which rows grow."""
    radius: float
    """A shell's radius, m."""
    angles_deg: Tuple[float, float]
    """A shell's angular range, degrees."""
    side: Literal["inside", "outside"]
    """The side of a shell that receives spray."""

class _TargetInfo(_TargetGeometry):
    """A target's geometry (``Simulation.target_info``)."""

    name: str
    role: Literal["substrate", "collector"]
    shape: Literal["rectangle", "cylinder", "mesh"]
    cells: int
    """Cells of its maps (triangles on a mesh)."""
    solid_cells: int
    """Cells not cut away by openings."""

@final
class Simulation:
    """A running simulation of a scenario.

    ``threads`` is the number of worker threads (0: one per core, at most 8 per core or 64,
    whichever is more; more raises ``ValueError``); results do not depend on it. ``step`` and
    ``run`` release the interpreter while they work, in slices of about 10 ms (on the GPU, at
    least one call of up to 128 layer epochs): other Python threads run meanwhile, and Ctrl-C
    raises ``KeyboardInterrupt`` within a slice, leaving the simulation valid at the step it
    reached.

    Thread-safe: calls from several threads take turns in the order they came, each waiting
    (with the interpreter released, Ctrl-C still working) until the call before it has returned.
    A callback of a call (``run``'s ``progress``) cannot use its own simulation: that raises
    ``RuntimeError``.

    ``backend`` is what flies the particles: ``"cpu"``, ``"gpu"`` (the GPU's kernels, on a
    Vulkan adapter or Mesa's lavapipe; results equal the CPU's within statistics, not to the
    bit; ``RuntimeError`` where it cannot run, saying why) or ``"auto"`` (the GPU where it can,
    else the CPU with a ``RuntimeWarning``); None takes the scenario's ``simulation.backend``.
    """

    def __new__(
        cls, scenario: _ScenarioSource = None, threads: int = 0, backend: Optional[str] = None
    ) -> "Simulation": ...
    def step(self, n: int = 1) -> None:
        """Advances by ``n`` time steps Δt (also past the configured duration); a negative ``n``
        raises ``ValueError``."""
    def run(
        self,
        until: Optional[float] = None,
        progress: Union[bool, Callable[[float, float], Any], None] = None,
    ) -> None:
        """Runs until simulated time reaches ``until`` (s; the configured duration when None).
        ``progress=True`` prints the simulated time to stderr; a callable is called as
        ``progress(time_s, until_s)`` about every 10 ms (it cannot use this simulation, which
        is busy with the run)."""
    @property
    def time(self) -> float:
        """Simulated time, s."""
    @property
    def steps_done(self) -> int: ...
    @property
    def total_steps(self) -> int:
        """Steps the configured duration takes."""
    @property
    def dt(self) -> float:
        """Time step Δt, s."""
    @property
    def duration(self) -> float:
        """Configured duration, s."""
    @property
    def is_finished(self) -> bool:
        """True once the configured duration has been simulated."""
    threads: int
    """Worker threads (0: one per core, at most 8 per core or 64); results do not depend on it."""
    @property
    def backend(self) -> Literal["cpu", "gpu"]:
        """What flies the particles."""
    @property
    def device(self) -> str:
        """What flies the particles, in words: ``"CPU"``, or ``"GPU (adapter, driver, API)"``."""
    @property
    def scenario(self) -> Scenario: ...
    @property
    def target_names(self) -> list[str]: ...
    def emitted(self) -> Tuple[int, float]:
        """Particles emitted so far: ``(count, volume in m³)``."""
    def metrics(self) -> dict[str, Any]:
        """The results so far: what ``metrics.json`` holds (less its ``files`` manifest), with
        ``targets`` a dict keyed by target name (the file lists them in scenario order)."""
    def metrics_json(self) -> str:
        """The text ``metrics.json`` would hold now, without the ``files`` manifest that only a
        written set of outputs has."""
    def write_outputs(self, directory: Union[str, "os.PathLike[str]", None] = None) -> list[str]:
        """Writes every output into ``directory`` (the scenario's ``output.directory`` when
        None) as ``spraysim run -o DIRECTORY`` does, all or nothing; returns the paths."""
    def snapshot(self) -> Snapshot:
        """Saves the present state."""
    def restore(self, snapshot: Snapshot) -> None:
        """Returns to a saved state; arrays taken earlier with ``copy=False`` keep showing the
        state they were taken from."""
    def copy(self) -> "Simulation":
        """An independent copy that continues exactly as this one would."""
    def __copy__(self) -> "Simulation": ...
    def __deepcopy__(self, memo: Any) -> "Simulation": ...
    def particles(self) -> _Particles:
        """The particles in flight now, as numpy arrays."""
    def thickness(self, target: Union[str, int], copy: bool = False) -> npt.NDArray[np.float64]:
        """Deposited thickness, m. On a rectangle, a (rows, cols) array: row 0 is the target's
        bottom edge (rows grow along ``up``), columns grow along ``right`` = ``up × normal`` (the
        viewer's right looking from the spray side): plot with ``origin="lower"``; cells in
        openings hold NaN, as in the ``.npy`` files (``mask`` is False there; use
        ``np.nanmean``). On a cylinder shell, the unrolled (rows along the axis, cols around it)
        map. On a mesh, one value per triangle, in the file's order. ``copy=False``: a read-only
        view of the simulation's memory (no copy) that shows later steps, on a target without
        openings; a target with openings, or ``copy=True``, gives an independent array.
        ``target`` is a name or an index from 0: an unknown name raises ``KeyError``, a negative
        or too large index ``IndexError``, both listing the targets."""
    def mask(self, target: Union[str, int]) -> npt.NDArray[np.bool_]:
        """Where the target's surface is, laid out as ``thickness``: False in cells cut away by
        openings (NaN in ``thickness``)."""
    def hits(self, target: Union[str, int], copy: bool = False) -> npt.NDArray[np.uint32]:
        """Impacts per cell (stuck or rebounded), laid out as ``thickness`` (0 in openings)."""
    def erosion(self, target: Union[str, int]) -> Optional[npt.NDArray[np.float64]]:
        """Depth eroded per cell, coating and substrate together, m (a copy, NaN in openings), or
        None without erosion."""
    def coating(self, target: Union[str, int]) -> Optional[npt.NDArray[np.float64]]:
        """Coating left per cell, m (a copy, NaN in openings; 0 where cleaned to bare
        substrate), or None without erosion."""
    def dry_thickness(self, target: Union[str, int]) -> Optional[npt.NDArray[np.float64]]:
        """Dry film per cell, m: the wet ``thickness`` times ``process.volume_solids`` (a copy,
        NaN in openings), or None without volume solids."""
    def target_info(self, target: Union[str, int]) -> _TargetInfo:
        """A target's geometry."""
    def surface_frame(self, target: Union[str, int], u: float, v: float, height: float = 0.0) -> _SurfaceFrame:
        """A rectangle's or cylinder shell's surface at unrolled ``(u, v)`` (m from the middle of
        its map; ``u`` along the columns, ``v`` along the rows) raised by ``height`` (m) on the
        receiving side: its ``position``, receiving ``normal``, ``right`` (growing ``u``) and
        ``up`` (growing ``v``). A mesh raises ``ValueError``."""
    def nozzle(self) -> _Nozzle:
        """The nozzle's pose (position, axis, quaternion, matrix, roll_deg), velocity and spray
        state now."""
    def set_nozzle(
        self,
        position: Optional[npt.ArrayLike] = None,
        axis: Optional[npt.ArrayLike] = None,
        spray: bool = True,
        *,
        quaternion: Optional[npt.ArrayLike] = None,
        matrix: Optional[npt.ArrayLike] = None,
    ) -> None:
        """Holds the nozzle at a pose from the next step on (closed-loop control): ``position``
        (m, finite, within ±10⁴ m of the origin as in scenario files) with ``axis`` (finite,
        non-zero, normalised), ``quaternion`` (w, x, y, z; the spray axis is the tool's z axis
        rotated by it) or neither (the present axis); or a 4 × 4 ``matrix`` alone (rotation and
        position; the spray axis is its third column). Anything else raises ``ValueError``
        naming the argument."""
    def set_nozzle_path(
        self,
        waypoints: Iterable[Union[_Waypoint, Mapping[str, Any], Tuple[Any, ...]]],
        roll_deg: Optional[float] = None,
        *,
        roll: Optional[float] = None,
    ) -> None:
        """Replaces the nozzle's path from the next step on: waypoints in absolute simulated
        time (s, strictly increasing), position interpolated linearly and axis spherically;
        ``roll_deg`` (degrees) turns the aperture about the axis (``roll``, in radians, is
        deprecated). A waypoint dict takes the keys ``time``, ``position``, ``axis``,
        ``quaternion``, ``matrix`` and ``spray`` only; poses are checked as by ``set_nozzle``."""
    def nozzle_waypoints(self, samples_per_turn: int = 16) -> list[dict[str, Any]]:
        """The nozzle's path as flown, as waypoint dicts that ``set_nozzle_path`` takes back: its
        own waypoints without a circle; with one, the path sampled ``samples_per_turn`` times per
        revolution (and at its own waypoints), circle included, up to its last waypoint or the
        configured duration, whichever is later."""
    def nozzle_path(self) -> _NozzlePath:
        """The nozzle's path exactly: its own waypoints, ``roll_deg`` and its ``circle``."""
    def nozzle_at(self, times: Iterable[float]) -> _Samples:
        """The nozzle's pose at each of ``times`` (s), circle included, without running."""

def presets() -> dict[str, dict[str, dict[str, Any]]]:
    """Each process preset's ``process`` and ``emitter`` sections, by name (``"shotcrete"``,
    ``"painting"``, ``"blasting"``), in the file's units."""

def presets_toml() -> str:
    """The presets as TOML with units and sources (``spraysim presets``)."""

@overload
def run_many(
    scenarios: Iterable[_ScenarioSource],
    threads: int = 0,
    maps: Literal[False] = False,
    backend: Optional[str] = None,
) -> list[dict[str, Any]]:
    """Runs every scenario to its end in parallel inside Rust on ``threads`` threads (0: one
    per core), releasing the interpreter. ``scenarios`` is a list or any iterable (a generator
    too) of scenarios; a single ``str``, path, ``dict`` or ``Scenario`` raises ``TypeError``
    (pass a list), as does a None item. Returns each run's metrics (its ``metrics.json``, with
    ``targets`` keyed by name as ``Simulation.metrics`` gives them), in order; with
    ``maps=True``, ``(metrics, {target: thickness})`` pairs (thickness in m, laid out as
    ``Simulation.thickness``, NaN in openings). Results equal those of sequential runs.

    The scenarios are all read and checked first (no simulation is built then). At most
    ``threads`` simulations (one per core for 0) are alive at a time, fewer when the memory
    limit needs it; each is built when a worker frees and dropped once its result is taken. Before anything runs, the batch is checked against the memory limit (the largest
    ``simulation.max_memory`` of its scenarios, by default half of the machine's memory): a
    batch whose results cannot all be kept raises ``MemoryError`` saying what to change
    (``maps=False``, or smaller parts).

    ``backend`` is as for ``Simulation``, for every run (None: each scenario's own); with
    ``"gpu"`` the runs go in batches of up to 64 (fewer where memory needs it; ``threads`` does
    not bound them), each run on a thread of its own and the batch's calls flown together in
    one dispatch; each run's results equal its run alone on the GPU."""
@overload
def run_many(
    scenarios: Iterable[_ScenarioSource],
    threads: int = 0,
    maps: Literal[True] = ...,
    backend: Optional[str] = None,
) -> list[Tuple[dict[str, Any], dict[str, npt.NDArray[np.float64]]]]: ...
def step_together(sims: Sequence[Simulation], n: Optional[int] = None) -> None:
    """Advances each simulation of ``sims`` by ``n`` steps (1 when None; fewer where its run
    ends), together: each on a thread of its own, the calls of those on the GPU flown in shared
    dispatches (one dispatch for all of a batch), the others on the CPU. Each one's results
    equal stepping it alone. The simulations must be distinct; each is busy until all are done.
    Those on the GPU stay in their batch until the next call, which finds its storage and its
    copy of their layers again (only the cells changed since then are uploaded), as long as it
    is handed the same simulations or some of them. A new one among them (an environment reset
    into a new ``Simulation``) takes the place of one that is gone (no longer referenced) whose
    grids it fits, and only its own layers are uploaded; where there is none, all of them go in
    new batches. Ctrl-C raises
    ``KeyboardInterrupt`` once the calls under way end."""
