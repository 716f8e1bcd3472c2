"""spraysim: a particle-system simulator of construction spraying (shotcrete, spray painting,
abrasive blasting), the same Rust engine as the ``spraysim`` command.

Conventions:

- SI units throughout (m, s, kg), z up, gravity -9.81 m/s² along z.
- Angles are in degrees everywhere, in scenario files and in code, and every angle the
  package takes or gives carries the unit in its name: ``roll_deg``, ``angles_deg``,
  ``max_tilt_deg``. (``Simulation.set_nozzle_path(roll=…)``, in radians, still works with a
  ``DeprecationWarning``.) Scenario keys keep the file's names and units (``nozzle.roll`` is in
  degrees).
- A nozzle pose is a position (m) with an orientation: a spray ``axis``, a unit
  ``quaternion`` given as ``(w, x, y, z)`` (scalar first; the spray axis is the tool's z axis
  rotated by it, as in ``nozzle.path_csv``), or a 4 × 4 homogeneous ``matrix`` (rotation and
  position; the spray axis is its third column).
- Maps (``thickness``, ``erosion``, ``coating``, ``run_many``'s maps) hold NaN in cells cut
  away by openings, as the ``.npy`` files do; ``Simulation.mask(target)`` is False there. Use
  ``np.nanmean`` and the like.
- ``Simulation.metrics()["targets"]`` is a dict keyed by target name (``metrics.json`` lists
  the targets in scenario order).
- Errors are Python exceptions whose text begins with the key or argument they are about:
  ``emitter.speed: must be … (Scenario.set('emitter.speed', …))``; bad argument values raise
  ``ValueError`` with the reason.

>>> import spraysim
>>> scenario = spraysim.Scenario().set("simulation.duration", 0.2)   # the default scene, 0.2 s
>>> sim = spraysim.Simulation(scenario, threads=2)
>>> sim.run()
>>> wall = sim.thickness("wall")          # (rows, cols) float64, m; row 0 at the bottom; NaN in openings
>>> sim.metrics()["transfer_efficiency"]  # what metrics.json holds  # doctest: +SKIP

- :class:`Scenario`: a validated, immutable scenario from a file, TOML text, a dict or the
  default scene; ``set("emitter.spawn_rate", 2e4)`` overrides a value by its dotted key, with
  the checks and messages of the ``spraysim`` command (:class:`ScenarioError` names the key);
  ``spray_end`` says when spraying ends, without a run.
- :class:`Simulation`: steps, runs (releasing the interpreter; Ctrl-C works), numpy arrays of
  particles and deposits, metrics, outputs, nozzle control between steps, snapshots.
- :func:`run_many`: many scenarios in parallel inside Rust.
- :func:`step_together`: simulations stepped together (on the GPU, in shared dispatches).
- :mod:`spraysim.gym`: a Gymnasium environment, and its vectorised form (needs ``pip install
  gymnasium``).
"""

from ._core import (
    ALIVE,
    HIT_SUBSTRATE,
    RELEASED,
    Scenario,
    ScenarioError,
    Simulation,
    Snapshot,
    __version__,
    presets,
    presets_toml,
    run_many,
    step_together,
)

__all__ = [
    "ALIVE",
    "HIT_SUBSTRATE",
    "RELEASED",
    "Scenario",
    "ScenarioError",
    "Simulation",
    "Snapshot",
    "__version__",
    "presets",
    "presets_toml",
    "run_many",
    "step_together",
]
