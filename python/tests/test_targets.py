"""Curved and meshed targets from Python: the maps' shapes and the mass they hold."""

import numpy as np

import spraysim

from conftest import REPO

SHELL = """
[simulation]
duration = 0.05
gravity = [0.0, 0.0, 0.0]
[process.impact]
rebound_model = "never"
[process.slump]
interval = 0.0
[emitter]
shape = "point"
cone_angle = 60.0
spawn_rate = 20000.0
[nozzle]
position = [0.0, 0.0, 0.0]
axis = [0.0, 0.0, 1.0]
[[target]]
name = "arch"
shape = "cylinder"
center = [0.0, 0.0, 0.0]
axis = [0.0, 1.0, 0.0]
radius = 1.0
length = 2.0
angles = [0.0, 180.0]
resolution = [90, 40]
"""


def test_a_shell_map_is_unrolled_and_holds_what_stuck() -> None:
    sim = spraysim.Simulation(spraysim.Scenario.from_toml(SHELL))
    sim.run()
    info = sim.target_info("arch")
    assert info["shape"] == "cylinder" and info["side"] == "inside"
    t = sim.thickness("arch", copy=True)
    assert t.shape == (40, 90) == (info["rows"], info["cols"])
    arc, length = info["size"]
    assert abs(arc - np.pi) < 1e-12 and abs(length - 2.0) < 1e-12
    # Equal cells: the map's volume is the mean thickness times the area, and every particle
    # that stuck (no rebound, no gravity, a cone inside the arch) is in it.
    stuck = sim.metrics()["targets"]["arch"]["stuck"]
    assert stuck["count"] > 100
    assert abs(t.mean() * arc * length / stuck["volume"] - 1.0) < 1e-6
    # The spray is straight up: the crown (the middle columns) is thicker than the springlines.
    assert t[:, 40:50].mean() > 10 * t[:, :5].mean()


def test_a_mesh_map_has_one_value_per_triangle() -> None:
    sc = spraysim.Scenario.from_file(REPO / "examples" / "door_panel.toml").set("simulation.duration", 0.3)
    sim = spraysim.Simulation(sc)
    sim.run()
    info = sim.target_info("door")
    assert info["shape"] == "mesh" and "rows" not in info
    t = sim.thickness("door")
    assert t.shape == (info["cells"],) and t.shape == sim.hits("door").shape
    assert t.max() > 0.0


PAINTED = """
[simulation]
duration = 0.3
[process]
preset = "painting"
gun = "hvlp"
volume_solids = 0.4
[emitter]
spawn_rate = 5000.0
[nozzle]
position = [-0.15, 0.0, 1.0]
axis = [1.0, 0.0, 0.0]
[[target]]
name = "panel"
center = [0.0, 0.0, 1.0]
normal = [-1.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
size = [1.0, 1.0]
resolution = [64, 64]
"""


def test_a_paint_gun_gives_a_dry_film_and_overspray() -> None:
    sim = spraysim.Simulation(spraysim.Scenario.from_toml(PAINTED), threads=1)
    sim.run()
    wet, dry = sim.thickness("panel"), sim.dry_thickness("panel")
    assert dry is not None and dry.shape == wet.shape
    np.testing.assert_allclose(dry, 0.4 * wet, rtol=1e-12)
    m = sim.metrics()
    fates = m["fates"]
    assert fates["overspray"]["count"] > 0
    assert sum(f["count"] for f in fates.values()) == m["emitted"]["count"]
    assert m["targets"]["panel"]["dry_thickness"]["mean"] > 0.0
    plain = spraysim.Simulation(spraysim.Scenario.from_toml(PAINTED.replace("volume_solids = 0.4", "")))
    assert plain.dry_thickness("panel") is None
