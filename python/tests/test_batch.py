"""run_many: many scenarios in parallel inside Rust, equal to sequential runs."""

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
