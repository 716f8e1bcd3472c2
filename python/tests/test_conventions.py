"""The package's conventions: angles in degrees, poses as axes, quaternions or matrices, maps
with NaN in openings and a mask, metrics keyed by target, the spraying's end without a run,
the nozzle's circle, and Python-shaped errors."""

import math
import warnings

import numpy as np
import pytest

import spraysim
from spraysim import Scenario, ScenarioError, Simulation

from conftest import REPO

from test_targets import SHELL


def window_wall(duration=0.3):
    """The wall with a window and a door, short and coarse, the nozzle aimed at the window's
    edge."""
    return Scenario.from_file(REPO / "examples" / "wall_with_window.toml").set_many(
        {
            "simulation.duration": duration,
            "target[0].resolution": [150, 125],
            "nozzle": {"position": [-1.2, -0.1, 1.45], "axis": [1.0, 0.0, 0.0]},
        }
    )


# ---- angles: degrees everywhere, the unit in the name ----


def test_angles_are_degrees_with_the_unit_in_the_name():
    assert "degrees" in spraysim.__doc__ and "_deg" in spraysim.__doc__
    scenario = Scenario().set_many({"simulation.duration": 0.01, "nozzle.roll": 30.0})
    assert scenario.get("nozzle.roll") == 30.0  # the file's degrees
    sim = Simulation(scenario)
    assert sim.nozzle()["roll_deg"] == pytest.approx(30.0)
    assert sim.nozzle_path()["roll_deg"] == pytest.approx(30.0)
    here = sim.nozzle()
    sim.set_nozzle_path([{"time": 0.0, "position": here["position"], "axis": here["axis"]}], roll_deg=90.0)
    assert sim.nozzle()["roll_deg"] == pytest.approx(90.0)
    shell = Simulation(Scenario.from_toml(SHELL))
    info = shell.target_info("arch")
    assert info["angles_deg"] == pytest.approx((0.0, 180.0)) and "angles" not in info


def test_the_old_radian_roll_still_works_with_a_deprecation_warning():
    sim = Simulation(Scenario().set("simulation.duration", 0.01))
    here = sim.nozzle()
    waypoints = [{"time": 0.0, "position": here["position"], "axis": here["axis"]}]
    with pytest.warns(DeprecationWarning, match="roll_deg"):
        sim.set_nozzle_path(waypoints, roll=math.pi / 2)
    assert sim.nozzle()["roll_deg"] == pytest.approx(90.0)
    with pytest.raises(ValueError, match="`roll_deg` and `roll`"):
        sim.set_nozzle_path(waypoints, roll_deg=10.0, roll=0.1)
    with pytest.raises(ValueError, match="`roll_deg` must be finite"):
        sim.set_nozzle_path(waypoints, roll_deg=float("inf"))


# ---- poses: axis, quaternion (w, x, y, z) or 4 × 4 matrix ----


def test_a_pose_is_an_axis_a_quaternion_or_a_matrix():
    sim = Simulation(Scenario().set("simulation.duration", 0.05))
    # A quarter turn about +y takes the tool's z axis to +x.
    half = math.pi / 4
    sim.set_nozzle([-1.0, 0.1, 1.0], quaternion=[math.cos(half), 0.0, math.sin(half), 0.0])
    sim.step()
    np.testing.assert_allclose(sim.nozzle()["axis"], [1.0, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(sim.nozzle()["position"], [-1.0, 0.1, 1.0])
    # A matrix holds the position (last column) and the axis (third column).
    m = np.eye(4)
    m[:3, :3] = [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]
    m[:3, 3] = [-0.9, 0.2, 1.1]
    sim.set_nozzle(matrix=m)
    sim.step()
    np.testing.assert_allclose(sim.nozzle()["position"], [-0.9, 0.2, 1.1])
    np.testing.assert_allclose(sim.nozzle()["axis"], [1.0, 0.0, 0.0], atol=1e-12)
    # The pose now, as a quaternion and a matrix, gives the same pose back.
    now = sim.nozzle()
    w, x, y, z = now["quaternion"]
    assert w * w + x * x + y * y + z * z == pytest.approx(1.0)
    np.testing.assert_allclose(now["matrix"][:3, 2], now["axis"], atol=1e-12)
    np.testing.assert_allclose(now["matrix"][:3, 3], now["position"])
    np.testing.assert_allclose(now["matrix"][3], [0, 0, 0, 1])
    tilted = [-1.0, 0.0, 1.0], [1.0, 0.3, -0.2]
    sim.set_nozzle(*tilted)
    sim.step()
    pose = sim.nozzle()
    sim.set_nozzle(matrix=pose["matrix"])
    sim.step()
    np.testing.assert_allclose(sim.nozzle()["axis"], pose["axis"], atol=1e-12)
    sim.set_nozzle(pose["position"], quaternion=pose["quaternion"])
    sim.step()
    np.testing.assert_allclose(sim.nozzle()["axis"], pose["axis"], atol=1e-12)
    # Waypoints take them too.
    sim.set_nozzle_path(
        [
            {"time": sim.time, "position": [-1, 0, 1], "quaternion": [1, 0, 0, 0]},
            {"time": sim.time + 0.1, "matrix": m},
        ]
    )
    waypoints = sim.nozzle_waypoints()
    np.testing.assert_allclose(waypoints[0]["axis"], [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(waypoints[1]["position"], [-0.9, 0.2, 1.1])


@pytest.mark.parametrize(
    "kwargs, refused",
    [
        ({"position": [0, 0, 1], "quaternion": [0, 0, 0, 0]}, "`quaternion` must be a non-zero quaternion"),
        ({"position": [0, 0, 1], "quaternion": [1, 0, 0]}, r"`quaternion` must be four numbers \(w, x, y, z\)"),
        ({"position": [0, 0, 1], "axis": [1, 0, 0], "quaternion": [1, 0, 0, 0]}, "give one orientation"),
        ({"position": [0, 0, 1], "matrix": np.eye(4)}, "`position` and `matrix` were both given"),
        ({"matrix": np.eye(3)}, "`matrix` must be a 4 × 4 matrix"),
        ({"matrix": 2 * np.eye(4)}, "must be a rotation"),
        ({"matrix": np.diag([1.0, 1.0, -1.0, 1.0])}, "must be a rotation"),
        ({"matrix": np.vstack([np.eye(4)[:3], [1, 0, 0, 1]])}, r"last row must be \[0, 0, 0, 1\]"),
        ({"axis": [1, 0, 0]}, "`position` is missing"),
    ],
)
def test_bad_poses_are_refused_naming_the_argument(kwargs, refused):
    sim = Simulation(Scenario().set("simulation.duration", 0.01))
    with pytest.raises(ValueError, match=refused):
        sim.set_nozzle(**kwargs)


# ---- maps: NaN in openings, as in the files, and a mask ----


def test_maps_hold_nan_in_openings_as_the_files_do_and_come_with_a_mask(tmp_path):
    sim = Simulation(window_wall())
    sim.run()
    wall = sim.thickness("wall")
    mask = sim.mask("wall")
    info = sim.target_info("wall")
    assert mask.dtype == bool and mask.shape == wall.shape
    assert 0 < info["solid_cells"] == mask.sum() < info["cells"]
    assert np.isnan(wall[~mask]).all() and np.isfinite(wall[mask]).all()
    assert np.nanmax(wall) > 0
    # nan-aware sums and means leave the openings out: the layer's volume adds up.
    cell_area = info["cell_size"][0] * info["cell_size"][1]
    layer = sim.metrics()["targets"]["wall"]["layer_volume"]
    assert np.nansum(wall) * cell_area == pytest.approx(layer, rel=1e-9)
    assert np.isnan(wall.mean()) and np.nanmean(wall) == pytest.approx(wall[mask].mean())
    assert (sim.hits("wall")[~mask] == 0).all()
    sim.write_outputs(tmp_path)
    written = np.load(tmp_path / "wall_thickness.npy")
    np.testing.assert_array_equal(np.isnan(written), ~mask)
    np.testing.assert_allclose(written[mask], wall[mask], rtol=1e-6)
    # run_many's maps too.
    (_, maps), = spraysim.run_many([window_wall()], maps=True)
    np.testing.assert_array_equal(maps["wall"], wall)
    # A target without openings keeps its live view, and a full mask.
    assert sim.mask("floor").all() and not sim.thickness("floor").flags.writeable


# ---- metrics keyed by target name ----


def test_metrics_targets_are_keyed_by_name(short):
    sim = Simulation(short)
    sim.run()
    targets = sim.metrics()["targets"]
    assert isinstance(targets, dict) and list(targets) == ["wall", "floor"]
    assert targets["wall"]["name"] == "wall" and targets["floor"]["role"] == "collector"
    assert spraysim.run_many([short])[0]["targets"].keys() == targets.keys()


# ---- when spraying ends, without a run ----


def test_spray_end_comes_from_the_path_without_running():
    assert Scenario().spray_end is None  # a static nozzle sprays throughout
    assert Scenario().path_end == 0.0
    raster = Scenario.from_file(REPO / "examples" / "figure4b_shotcrete.toml")
    end = raster.spray_end
    assert end is not None and 0 < end <= raster.path_end
    sim = Simulation(raster.set("simulation.duration", 0.01))
    last = sim.nozzle_path()["waypoints"][-1]
    assert end == pytest.approx(last["time"]) and not last["spray"]
    # The raster's length and speed give it: passes of 1.2 m + 2 × 0.1 m lead at 0.6 m/s, 0.1 m apart.
    passes = int(0.6 / 0.1 + 1e-9) + 1
    assert end == pytest.approx((passes * 1.4 + (passes - 1) * 0.1) / 0.6, rel=1e-9)
    short = Scenario().set_many(
        {
            "simulation.duration": 0.2,
            "nozzle": {
                "waypoints": [
                    {"time": 0.0, "position": [-1.0, 0.0, 1.0], "axis": [1.0, 0.0, 0.0]},
                    {"time": 0.05, "position": [-1.0, 0.1, 1.0], "axis": [1.0, 0.0, 0.0], "spray": False},
                ]
            },
        }
    )
    assert short.spray_end == pytest.approx(0.05)
    sim = Simulation(short)
    sim.run(until=0.06)
    emitted = sim.emitted()[0]
    sim.run()
    assert sim.emitted()[0] == emitted  # nothing more after spray_end


# ---- the nozzle's circle ----


def test_nozzle_waypoints_include_the_circle():
    radius, frequency = 0.1, 2.0
    scenario = Scenario().set_many(
        {
            "simulation.duration": 0.5,
            "nozzle": {
                "position": [-1.0, 0.0, 1.0],
                "axis": [1.0, 0.0, 0.0],
                "circle_radius": radius,
                "circle_frequency": frequency,
            },
        }
    )
    sim = Simulation(scenario)
    path = sim.nozzle_path()
    assert path["circle"]["radius"] == radius and path["circle"]["frequency"] == frequency
    assert len(path["waypoints"]) == 1
    sampled = sim.nozzle_waypoints(samples_per_turn=16)
    # One revolution every 0.5 s, 16 samples each: 17 poses over the 0.5 s run.
    assert len(sampled) == 17
    offsets = np.array([w["position"] for w in sampled]) - [-1.0, 0.0, 1.0]
    np.testing.assert_allclose(np.linalg.norm(offsets, axis=1), radius, rtol=1e-12)
    np.testing.assert_allclose(offsets[:, 0], 0.0, atol=1e-12)  # in the plane across the axis
    assert np.ptp(offsets[:, 1]) == pytest.approx(2 * radius)
    # The pose at any time, circle included, without running.
    at = sim.nozzle_at([0.0, 0.125, 0.25])
    assert at["position"].shape == (3, 3)
    np.testing.assert_allclose(at["position"][0], sampled[0]["position"])
    np.testing.assert_allclose(at["position"][2], sampled[8]["position"])
    sim.run(until=0.125)
    np.testing.assert_allclose(sim.nozzle()["position"], at["position"][1], atol=1e-12)
    with pytest.raises(ValueError, match="`samples_per_turn` must be from 3"):
        sim.nozzle_waypoints(samples_per_turn=0)


# ---- Python-shaped errors ----


def test_errors_begin_with_the_key_not_the_commands_syntax():
    with pytest.raises(ScenarioError) as refused:
        Scenario().set("emitter.speed", [-3.0, 20.0])
    text = str(refused.value)
    assert text.startswith("emitter.speed: ") and "--set" not in text and "`emitter.speed`" not in text
    with pytest.raises(ValueError, match=r"^emitter\.spawn_rate: must be greater than 0"):
        Scenario().assign("emitter.spawn_rate=-3")
    with pytest.raises(ValueError, match=r"^simulation\.dt: "):
        Scenario({"simulation": {"dt": -1.0}})


@pytest.mark.parametrize("n, error", [(-1, ValueError), (-(10**30), ValueError), (10**30, ValueError), (1.5, TypeError)])
def test_absurd_step_counts_raise_with_the_reason(short, n, error):
    sim = Simulation(short)
    with pytest.raises(error, match="`n`"):
        sim.step(n)
    assert sim.steps_done == 0
    sim.step()
    sim.step(np.int64(2))
    assert sim.steps_done == 3


def test_absurd_arguments_raise_value_error_not_overflow_error(short):
    with pytest.raises(ValueError, match="`threads` must be 0"):
        Simulation(short, threads=-1)
    sim = Simulation(short)
    with pytest.raises(ValueError, match="`until`"):
        sim.run(until=-1.0)
    with pytest.raises(ValueError, match="`times` must be finite"):
        sim.nozzle_at([float("nan")])
    with pytest.raises(ValueError, match="`u` must be finite"):
        sim.surface_frame("wall", float("inf"), 0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match="`samples_per_turn`"):
            sim.nozzle_waypoints(samples_per_turn=-1)
