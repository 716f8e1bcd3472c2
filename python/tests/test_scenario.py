"""Scenarios from files, text, dicts and the default scene; overrides and their refusals."""

import pickle
import subprocess

import numpy as np
import pytest

import spraysim
from spraysim import Scenario, ScenarioError


def test_every_source_reads_the_same_scenario(tmp_path):
    default = Scenario()
    assert Scenario.default() == default
    assert default.origin == "<default scene>"
    assert Scenario.from_toml(default.to_toml()) == default
    assert Scenario.from_dict(default.to_dict()) == default
    path = tmp_path / "scene.toml"
    path.write_text(default.to_toml())
    assert Scenario.from_file(path) == default
    assert Scenario(str(path)) == default
    assert Scenario(path).origin == str(path)
    assert default.target_names == ["wall", "floor"]
    assert (default.dt, default.duration, default.seed) == (0.001, 2.0, 1)


def test_set_overrides_one_value_and_leaves_the_original_alone():
    base = Scenario()
    faster = base.set("emitter.spawn_rate", 2e4)
    assert faster.get("emitter.spawn_rate") == 2e4
    assert base.get("emitter.spawn_rate") == 1e4
    assert faster != base
    assert base.set("emitter.speed", [20, 28]).get("emitter.speed") == [20.0, 28.0]
    assert base.set("emitter.speed", np.array([20.0, 28.0])).get("emitter.speed") == [20.0, 28.0]
    assert base.set("target[0].resolution", (512, 256)).get("target[0].resolution") == [512, 256]
    assert base.set("simulation.seed", np.int64(3)).seed == 3
    many = base.set_many({"simulation.seed": 3, "emitter.speed": [20, 28]})
    assert many == base.set("simulation.seed", 3).set("emitter.speed", [20, 28])
    assert many == base.assign("simulation.seed=3").assign("emitter.speed=[20,28]")


@pytest.mark.parametrize(
    "key, value, assignment",
    [
        ("emitter.spawn_rate", -1.0, "emitter.spawn_rate=-1.0"),
        ("simulation.dt", 0.0, "simulation.dt=0.0"),
        ("emitter.speed", [30.0, 20.0], "emitter.speed=[30.0, 20.0]"),
        ("emitter.spawn_rat", 1.0, "emitter.spawn_rat=1.0"),
        ("target[0].resolution", [0, 10], "target[0].resolution=[0, 10]"),
    ],
)
def test_a_bad_override_raises_naming_the_key_with_the_commands_message(cli, tmp_path, key, value, assignment):
    with pytest.raises(ScenarioError) as refused:
        Scenario().set(key, value)
    e = refused.value
    assert e.key == key
    assert isinstance(e, ValueError)
    assert f"`{key}`" in str(e)
    assert e.location == f"--set {assignment}"
    # The command refuses the same override with the same words.
    scene = tmp_path / "scene.toml"
    scene.write_text(Scenario().to_toml())
    out = subprocess.run([cli, "check", str(scene), "--set", assignment], capture_output=True, text=True)
    assert out.returncode != 0
    assert out.stderr.strip() == f"error: {e}"


def test_values_without_a_toml_form_are_refused_naming_the_key():
    with pytest.raises(ScenarioError) as refused:
        Scenario().set("emitter.speed", [20.0, None])
    assert refused.value.key == "emitter.speed[1]"
    with pytest.raises(ScenarioError) as refused:
        Scenario().set("simulation.seed", object())
    assert refused.value.key == "simulation.seed"


def test_a_dict_is_checked_like_a_file():
    with pytest.raises(ScenarioError) as refused:
        Scenario({"simulation": {"dt": -0.001}})
    assert refused.value.key == "simulation.dt"
    assert str(refused.value) == "<dict>: `simulation.dt` must be greater than 0 s, got -0.001"
    with pytest.raises(ScenarioError) as refused:
        Scenario.from_dict({"target": [{"name": "wall", "center": [0, 0, 1]}]})
    assert refused.value.key.startswith("target[0].")


def test_a_file_error_names_file_line_and_key(tmp_path):
    path = tmp_path / "wall.toml"
    path.write_text("[simulation]\ndt = -0.001\n")
    with pytest.raises(ScenarioError) as refused:
        Scenario(path)
    assert str(refused.value) == f"{path}:2: `simulation.dt` must be greater than 0 s, got -0.001"
    assert refused.value.location == f"{path}:2"


def test_presets_are_the_commands_presets():
    presets = spraysim.presets()
    assert sorted(presets) == ["blasting", "painting", "shotcrete"]
    painting = Scenario().set("process.preset", "painting")
    assert painting.get("process.density") == presets["painting"]["process"]["density"]
    assert "# ---- painting ----" in spraysim.presets_toml()


def test_scenarios_pickle():
    scenario = Scenario().set("emitter.speed", [20, 28])
    assert pickle.loads(pickle.dumps(scenario)) == scenario
