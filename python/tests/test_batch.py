"""run_many: many scenarios in parallel inside Rust, equal to sequential runs."""

import pathlib
import subprocess
import sys

import numpy as np
import pytest

import spraysim
from spraysim import Scenario, Simulation


def variants(short):
    return [
        short,
        short.set("simulation.seed", 7),
        short.set("emitter.speed", [20, 28]),
        short.set_many({"process.preset": "painting", "emitter.spawn_rate": 2e4}),
        short.set("simulation.duration", 0.1),
    ]


def sequential(scenario):
    sim = Simulation(scenario, threads=1)
    sim.run()
    return sim


def test_run_many_equals_sequential_runs(short):
    scenarios = variants(short)
    expected = [sequential(s) for s in scenarios]
    for threads in (1, 2):
        assert spraysim.run_many(scenarios, threads=threads) == [s.metrics() for s in expected]
    with_maps = spraysim.run_many(scenarios, threads=2, maps=True)
    for (metrics, maps), sim in zip(with_maps, expected):
        assert metrics == sim.metrics()
        assert sorted(maps) == ["floor", "wall"]
        for name, array in maps.items():
            np.testing.assert_array_equal(array, sim.thickness(name))
        assert sorted(metrics["targets"]) == ["floor", "wall"]


def test_run_many_takes_dicts_and_paths(short, tmp_path):
    path = tmp_path / "short.toml"
    path.write_text(short.to_toml())
    results = spraysim.run_many([short, str(path), short.to_dict()], threads=2)
    assert results[0] == results[1] == results[2]


def test_run_many_refuses_a_bad_scenario_naming_the_key(short):
    with pytest.raises(spraysim.ScenarioError) as refused:
        spraysim.run_many([short, {"simulation": {"dt": 0}}])
    assert refused.value.key == "simulation.dt"
    assert spraysim.run_many([]) == []


def test_run_many_reads_a_generator_and_keeps_the_order(short):
    scenarios = [short.set("simulation.seed", seed) for seed in (5, 1, 3)]
    expected = spraysim.run_many(scenarios, threads=1)
    assert spraysim.run_many((s for s in scenarios), threads=2) == expected
    assert [m["emitted"]["count"] for m in expected] == [2000, 2000, 2000]
    assert expected[0] != expected[1]


def test_run_many_refuses_a_missing_scenario_naming_the_item(short):
    with pytest.raises(TypeError, match=r"`scenarios\[1\]` is None"):
        spraysim.run_many([short, None])
    with pytest.raises(TypeError, match=r"scenarios\[0\]"):
        spraysim.run_many([3.5])


@pytest.mark.parametrize(
    "single",
    ["abc", b"abc", pathlib.Path("scene.toml"), {"simulation": {"duration": 0.1}}, Scenario()],
    ids=["str", "bytes", "path", "dict", "Scenario"],
)
def test_run_many_refuses_one_scenario_given_as_the_whole_batch(single):
    with pytest.raises(TypeError, match="pass a list"):
        spraysim.run_many(single)


def test_run_many_names_the_item_of_a_refused_dict():
    with pytest.raises(spraysim.ScenarioError) as refused:
        spraysim.run_many([{}, {"simulation": {"dt": 0}}])
    assert str(refused.value) == "simulation.dt: must be greater than 0 s, got 0 (scenarios[1])"
    assert refused.value.location == "scenarios[1]"


def test_run_many_refuses_a_batch_whose_maps_exceed_the_memory_limit_before_running():
    # Each run is allowed 250 MB; its maps take 3.9 MB, so 100 runs' maps cannot be kept.
    big = Scenario().set_many(
        {"simulation.duration": 0.001, "simulation.max_memory": 2.5e8, "target[0].resolution": [700, 700]}
    )
    batch = [big.set("simulation.seed", seed) for seed in range(100)]
    with pytest.raises(MemoryError) as refused:
        spraysim.run_many(batch, threads=1, maps=True)
    message = str(refused.value)
    assert "Nothing was run" in message
    assert "maps=False" in message and "parts of at most" in message
    assert "250.0 MB" in message


TINY_BATCH = """
import spraysim

def peak_kib():
    # This process's own peak (getrusage would also count the parent's before exec).
    with open("/proc/self/status") as status:
        return next(int(line.split()[1]) for line in status if line.startswith("VmHWM:"))

tiny = spraysim.Scenario().set_many(
    {"simulation.duration": 0.002, "target[0].resolution": [8, 8], "target[1].resolution": [8, 8]}
)
start = peak_kib()
spraysim.run_many([tiny], threads=2)
one = peak_kib() - start
results = spraysim.run_many([tiny.set("simulation.seed", s) for s in range(60)], threads=2, maps=True)
assert len(results) == 60
print(one, peak_kib() - start)
"""


@pytest.mark.skipif(not pathlib.Path("/proc/self/status").exists(), reason="reads the peak memory in /proc")
def test_run_many_keeps_only_a_few_simulations_in_memory_at_once():
    # A child process measures its own peak memory: 60 runs at once would take about 60 times
    # what one run takes; two workers keep two or so alive.
    out = subprocess.run([sys.executable, "-c", TINY_BATCH], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    one, batch = (int(x) for x in out.stdout.split())
    assert batch < 15 * one, (one, batch)
