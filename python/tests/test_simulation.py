"""Simulations: outputs against the command, arrays, metrics, nozzle control, snapshots."""

import filecmp
import json
import os
import re
import subprocess

import numpy as np
import pytest

import spraysim
from spraysim import Scenario, Simulation


def test_outputs_are_byte_identical_to_the_commands(cli, tmp_path, monkeypatch):
    scene = tmp_path / "scene.toml"
    scene.write_text(Scenario().set_many({"simulation.duration": 0.25, "process.cohesion.interval": 0.1}).to_toml())
    sets = ["simulation.seed=3", "emitter.speed=[20,28]"]
    by_cli, by_python = tmp_path / "cli", tmp_path / "python"
    by_cli.mkdir()
    by_python.mkdir()
    # Both write to `out` relative to their own folder, so the resolved scenarios name the same one.
    args = [cli, "run", str(scene), "-o", "out", "-q", "-j", "2"]
    subprocess.run(args + [a for s in sets for a in ("--set", s)], cwd=by_cli, check=True)
    scenario = Scenario(scene)
    for s in sets:
        scenario = scenario.assign(s)
    assert scenario == Scenario(scene).set("simulation.seed", 3).set("emitter.speed", [20, 28])
    sim = Simulation(scenario, threads=2)
    sim.run()
    monkeypatch.chdir(by_python)
    written = sim.write_outputs("out")
    # The writer's own bookkeeping (hidden files) is not part of the set.
    names = sorted(n for n in os.listdir(by_cli / "out") if not n.startswith("."))
    assert names == sorted(os.path.basename(p) for p in written)
    assert {"metrics.json", "wall_thickness.npy", "wall_thickness.png", "scenario.resolved.toml"} <= set(names)
    match, mismatch, errors = filecmp.cmpfiles(by_cli / "out", by_python / "out", names, shallow=False)
    assert (mismatch, errors) == ([], [])
    assert sorted(match) == names


def test_metrics_are_what_metrics_json_holds(short, tmp_path):
    sim = Simulation(short)
    sim.run()
    sim.write_outputs(tmp_path)
    written = json.loads((tmp_path / "metrics.json").read_text())
    # A written set's metrics.json also lists the set's other files (name, size, SHA-256).
    manifest = written.pop("files")
    assert sorted(f["name"] for f in manifest) == sorted(
        p.name for p in tmp_path.iterdir() if p.name != "metrics.json" and not p.name.startswith(".")
    )
    assert json.loads(sim.metrics_json()) == written
    # metrics() keys the targets by name; the file lists them in scenario order.
    by_name = sim.metrics()
    assert list(by_name["targets"]) == ["wall", "floor"] == [t["name"] for t in written["targets"]]
    assert list(by_name["targets"].values()) == written["targets"]
    assert {**by_name, "targets": written["targets"]} == written
    m = sim.metrics()
    assert m["emitted"]["count"] == sim.emitted()[0] == 2000
    assert m["time"] == pytest.approx(0.2)


def test_thickness_has_the_documented_shape_units_and_orientation():
    # Aim at the point 0.5 m to the viewer's right of and 0.5 m above the wall's centre.
    # The wall's normal is -x and up +z, so right = up × normal = -y.
    scenario = Scenario().set_many(
        {
            "simulation.duration": 0.3,
            "target[0].resolution": [200, 100],  # [cols, rows]
            "nozzle.position": [-1.0, -0.5, 1.5],
        }
    )
    sim = Simulation(scenario)
    sim.run()
    wall = sim.thickness("wall")
    info = sim.target_info("wall")
    assert wall.shape == (100, 200) == (info["rows"], info["cols"])
    assert wall.dtype == np.float64
    np.testing.assert_allclose(info["right"], [0.0, -1.0, 0.0], atol=1e-12)
    assert info["cell_size"] == pytest.approx((0.01, 0.02))
    # Centroid of the deposit: row 0 at the bottom edge, columns towards the viewer's right.
    rows, cols = np.indices(wall.shape)
    centroid = np.array([(rows * wall).sum(), (cols * wall).sum()]) / wall.sum()
    expected = np.array([(0.5 + 1.0) / 2.0 * 100 - 0.5, (0.5 + 1.0) / 2.0 * 200 - 0.5])
    assert np.abs(centroid - expected).max() < 3.0, centroid
    # Metres: thickness × cell area adds up to the layer's volume in m³.
    target = sim.metrics()["targets"]["wall"]
    cell_area = info["cell_size"][0] * info["cell_size"][1]
    assert wall.sum() * cell_area == pytest.approx(target["layer_volume"], rel=1e-9)
    assert wall.max() == pytest.approx(target["thickness"]["max"], rel=1e-12)
    hits = sim.hits(0)
    assert hits.shape == wall.shape and hits.dtype == np.uint32
    assert int(hits.sum()) == target["hits"]
    assert sim.erosion("wall") is None


def test_a_thickness_view_is_live_and_read_only_and_a_copy_is_not(short):
    sim = Simulation(short)
    sim.step(50)
    view, copy = sim.thickness("wall"), sim.thickness("wall", copy=True)
    before = view.sum()
    assert copy.sum() == before
    sim.step(50)
    assert view.sum() > before  # the view shows the simulation as it goes
    assert copy.sum() == before
    with pytest.raises(ValueError):
        view[0, 0] = 1.0
    copy[0, 0] = 1.0
    with pytest.raises(KeyError, match="wall, floor"):
        sim.thickness("roof")
    with pytest.raises(IndexError):
        sim.thickness(5)


def test_a_view_outlives_its_simulation_and_restores(short):
    sim = Simulation(short)
    snap = sim.snapshot()
    sim.step(100)
    view = sim.thickness("wall")
    frozen = view.copy()
    sim.restore(snap)  # the state the view shows is replaced…
    assert sim.thickness("wall").sum() == 0.0
    sim.step(20)
    np.testing.assert_array_equal(view, frozen)  # …and kept while the view lives
    del sim
    np.testing.assert_array_equal(view, frozen)


def test_maps_cannot_be_taken_while_the_simulation_runs(short):
    sim = Simulation(short)
    refusals = []

    def progress(t, end):
        # Called between two slices of the run, which holds the simulation.
        try:
            sim.thickness("wall")
        except RuntimeError as e:
            refusals.append(str(e))

    sim.run(progress=progress)
    assert refusals and "busy in this same thread" in refusals[0]


def test_particles_are_the_ones_in_flight(short):
    sim = Simulation(short)
    sim.step(100)
    p = sim.particles()
    n = sim.metrics()["fates"]["in_flight"]["count"]
    assert p["position"].shape == (n, 3) and p["velocity"].shape == (n, 3)
    assert p["age"].shape == p["id"].shape == p["impacts"].shape == p["state"].shape == (n,)
    assert (p["state"] & spraysim.ALIVE).all()
    # Ages are single precision, summed step by step: within 1e-6 s of the time.
    assert ((p["age"] > 0) & (p["age"] <= sim.time + 1e-6)).all()
    assert len(np.unique(p["id"])) == n
    # Between the nozzle (x = -1 m) and the wall (x = 0) or falling from it onto the floor.
    assert ((p["position"][:, 0] > -3.0) & (p["position"][:, 0] <= 1e-6)).all()
    fresh = p["impacts"] == 0
    assert (p["velocity"][fresh, 0] > 15.0).all()  # still flying at the wall at 20–30 m/s


def test_step_and_run_until(short):
    sim = Simulation(short)
    assert (sim.time, sim.steps_done, sim.total_steps) == (0.0, 0, 200)
    sim.step()
    sim.step(4)
    assert sim.steps_done == 5
    sim.run(until=0.05)
    assert sim.steps_done == 50 and sim.time == pytest.approx(0.05)
    seen = []
    sim.run(progress=lambda t, end: seen.append((t, end)))
    assert sim.is_finished and sim.steps_done == 200
    assert seen and seen[-1] == (pytest.approx(0.2), pytest.approx(0.2))
    sim.step(3)  # past the duration
    assert sim.steps_done == 203
    with pytest.raises(ValueError):
        sim.run(until=-1.0)


def test_snapshot_run_restore_run_gives_identical_results_twice(short):
    sim = Simulation(short, threads=2)
    sim.run(until=0.1)
    snap = sim.snapshot()
    assert snap.time == pytest.approx(0.1)
    sim.run()
    first = (sim.metrics_json(), sim.thickness("wall", copy=True), sim.particles())
    for _ in range(2):
        sim.restore(snap)
        assert sim.time == pytest.approx(0.1)
        sim.run()
        assert sim.metrics_json() == first[0]
        np.testing.assert_array_equal(sim.thickness("wall"), first[1])
        for k, v in sim.particles().items():
            np.testing.assert_array_equal(v, first[2][k])
    # And it is the run that was never interrupted.
    straight = Simulation(short, threads=1)
    straight.run()
    assert straight.metrics_json() == first[0]
    twin = sim.copy()
    assert twin.metrics_json() == sim.metrics_json()


def test_the_nozzle_can_be_moved_between_steps(short):
    sim = Simulation(short)
    sim.run(until=0.1)  # sprays at the wall's centre
    np.testing.assert_allclose(sim.nozzle()["position"], [-1.0, 0.0, 1.0])
    sim.set_nozzle([-1.0, 0.0, 1.6])  # then 0.6 m higher, same axis
    sim.run()
    wall = sim.thickness("wall")
    rows = wall.sum(axis=1)
    centre_row, high_row = int(1.0 / 2.0 * 256), int(1.6 / 2.0 * 256)
    assert rows[centre_row] > 0 and rows[high_row] > 0
    assert rows[(centre_row + high_row) // 2] < 0.05 * min(rows[centre_row], rows[high_row])
    # A path: from the centre to the right in 0.1 s, then off.
    sim2 = Simulation(short)
    sim2.set_nozzle_path(
        [
            {"time": 0.0, "position": [-1, 0, 1], "axis": [1, 0, 0]},
            (0.1, [-1, -0.5, 1], [1, 0, 0], False),
        ]
    )
    sim2.run(until=0.05)
    n = sim2.nozzle()
    np.testing.assert_allclose(n["position"], [-1.0, -0.25, 1.0], atol=1e-12)
    np.testing.assert_allclose(n["velocity"], [0.0, -5.0, 0.0], atol=1e-9)
    assert n["spraying"]
    sim2.run()
    assert not sim2.nozzle()["spraying"]
    assert sim2.emitted()[0] == 1000  # 10⁴ particles/s for the 0.1 s of spraying
    assert [w["spray"] for w in sim2.nozzle_waypoints()] == [True, False]


def test_bad_nozzle_paths_are_refused_naming_the_field(short):
    sim = Simulation(short)
    with pytest.raises(ValueError, match=r"waypoints\[1\]\.time"):
        sim.set_nozzle_path([(0.1, [0, 0, 1], [1, 0, 0]), (0.1, [0, 0, 1], [1, 0, 0])])
    with pytest.raises(ValueError, match=r"waypoints\[0\]\.axis"):
        sim.set_nozzle_path([{"time": 0.0, "position": [0, 0, 1], "axis": [0, 0, 0]}])
    with pytest.raises(ValueError, match="position"):
        sim.set_nozzle([0, 0])
    with pytest.raises(ValueError, match="at least one"):
        sim.set_nozzle_path([])


def test_threads_do_not_change_results(short):
    runs = []
    for threads in (1, 2):
        sim = Simulation(short, threads=threads)
        sim.run()
        runs.append(sim.metrics_json())
    assert runs[0] == runs[1]


def test_a_target_index_out_of_range_raises_index_error_listing_the_targets(short):
    sim = Simulation(short)
    for accessor in (sim.thickness, sim.hits, sim.erosion, sim.target_info):
        with pytest.raises(IndexError, match=r"negative.*0 to 1.*wall, floor"):
            accessor(-1)
        with pytest.raises(IndexError, match=r"no target 2.*0 to 1.*wall, floor"):
            accessor(2)
        with pytest.raises(IndexError, match="wall, floor"):
            accessor(10**30)
        with pytest.raises(TypeError, match=r"name \(str\) or index \(int\), got float"):
            accessor(0.5)
    assert sim.target_info(np.int64(1))["name"] == "floor"
    assert sim.thickness(1).shape == sim.thickness("floor").shape


def test_unknown_waypoint_keys_are_refused_naming_the_key(short):
    sim = Simulation(short)
    before = sim.nozzle_waypoints()
    with pytest.raises(ValueError, match=r"`waypoints\[1\]` has an unknown key 'spary'.*time, position, axis, quaternion, matrix, spray"):
        sim.set_nozzle_path(
            [
                {"time": 0.0, "position": [-1, 0, 1], "axis": [1, 0, 0]},
                {"time": 0.1, "position": [-1, 0, 1], "axis": [1, 0, 0], "spary": False},
            ]
        )
    with pytest.raises(ValueError, match=r"`waypoints\[0\]` .* got 5 items"):
        sim.set_nozzle_path([(0.0, [-1, 0, 1], [1, 0, 0], True, "extra")])
    assert len(sim.nozzle_waypoints()) == len(before)  # the path is left as it was


@pytest.mark.parametrize(
    "position, axis, refused",
    [
        ([0, 0, 1], [float("nan"), 0, 0], "`axis` must be three finite numbers"),
        ([0, 0, 1], [0, 0, 0], "`axis` must be a non-zero direction"),
        ([0, 0, 1], [float("inf"), 0, 0], "`axis` must be three finite numbers"),
        ([0, float("nan"), 1], None, "`position` must be three finite numbers"),
        ([2e4, 0, 1], None, "`position` must lie within ±10000 m"),
        ([0, 0, -1e5], [1, 0, 0], "`position` must lie within ±10000 m"),
    ],
)
def test_nozzle_poses_beyond_reach_or_without_direction_are_refused(short, position, axis, refused):
    sim = Simulation(short)
    before = sim.nozzle()
    with pytest.raises(ValueError, match=refused):
        sim.set_nozzle(position, axis)
    with pytest.raises(ValueError, match=refused.replace("`", r"`waypoints\[0\]\.", 1)):
        sim.set_nozzle_path([{"time": 0.0, "position": position, "axis": axis if axis else [1, 0, 0]}])
    np.testing.assert_array_equal(sim.nozzle()["position"], before["position"])


def test_a_very_long_or_short_axis_is_normalised(short):
    sim = Simulation(short)
    sim.set_nozzle([-1, 0, 1], [1e308, 1e308, 0])
    np.testing.assert_allclose(sim.nozzle()["axis"], [2**-0.5, 2**-0.5, 0.0])
    sim.set_nozzle([-1, 0, 1], [1e-300, 0, 0])
    np.testing.assert_allclose(sim.nozzle()["axis"], [1.0, 0.0, 0.0])


@pytest.mark.parametrize("threads", [-1, -(10**30)])
def test_a_negative_thread_count_is_refused(short, threads):
    with pytest.raises(ValueError, match="`threads` must be 0 .* or a positive count"):
        Simulation(short, threads=threads)
    with pytest.raises(ValueError, match="`threads` must be 0"):
        spraysim.run_many([short], threads=threads)
    sim = Simulation(short, threads=1)
    with pytest.raises(ValueError, match="`threads` must be 0"):
        sim.threads = threads
    assert sim.threads == 1


@pytest.mark.parametrize("threads", [10**5, 10**30])
def test_a_thread_count_above_the_cap_is_refused_naming_the_cap(short, threads):
    # Refused before any thread starts, naming the most this machine allows (8 per core, at
    # least 64).
    cap = r"at most (\d+) worker threads .*8 per core"
    with pytest.raises(ValueError, match=cap) as refused:
        Simulation(short, threads=threads)
    assert 64 <= int(re.search(cap, str(refused.value)).group(1)) < threads
    with pytest.raises(ValueError, match=cap):
        spraysim.run_many([short], threads=threads)
    with pytest.raises(ValueError, match=cap):
        Simulation(short).threads = threads
    with pytest.raises(TypeError, match="`threads` must be a whole number"):
        Simulation(short, threads=2.0)
