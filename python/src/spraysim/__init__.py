"""spraysim: a particle-system simulator of construction spraying (shotcrete, spray painting,
abrasive blasting), the same Rust engine as the ``spraysim`` command.

SI units throughout (m, s, kg), z up, gravity -9.81 m/s² along z; angles in degrees in
scenario files and radians in code.

>>> import spraysim
>>> scenario = spraysim.Scenario().set("simulation.duration", 0.2)   # the default scene, 0.2 s
>>> sim = spraysim.Simulation(scenario, threads=2)
>>> sim.run()
>>> wall = sim.thickness("wall")          # (rows, cols) float64, m; row 0 at the bottom
>>> sim.metrics()["transfer_efficiency"]  # what metrics.json holds  # doctest: +SKIP

- :class:`Scenario`: a validated, immutable scenario from a file, TOML text, a dict or the
  default scene; ``set("emitter.spawn_rate", 2e4)`` overrides a value by its dotted key, with
  the checks and messages of the ``spraysim`` command (:class:`ScenarioError` names the key).
- :class:`Simulation`: steps, runs (releasing the interpreter; Ctrl-C works), numpy arrays of
  particles and deposits, metrics, outputs, nozzle control between steps, snapshots.
- :func:`run_many`: many scenarios in parallel inside Rust.
- :mod:`spraysim.gym`: a Gymnasium environment (needs ``pip install gymnasium``).
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
]
