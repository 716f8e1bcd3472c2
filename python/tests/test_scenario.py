"""Scenarios from files, text, dicts and the default scene; overrides and their refusals."""

import json
import pickle
import subprocess
import sys

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


def test_a_whole_table_of_another_kind_replaces_the_nozzle_and_overrides_go_in_any_order():
    base = Scenario()
    raster = base.set("nozzle", {"raster": {"target": "wall", "standoff": 1.0, "speed": 0.5}})
    # The static nozzle's keys are gone with the table it replaced; the raster's are read.
    assert raster.get("nozzle.raster.target") == "wall"
    assert raster.spray_end is not None and raster.spray_end > 0.0
    with pytest.raises(ScenarioError) as refused:
        base.set("nozzle.raster", {"target": "wall"})
    assert "nozzle={raster" in str(refused.value)
    # A circle's radius before or after its frequency: checked together, either order.
    one = base.set_many({"nozzle.circle_radius": 0.05, "nozzle.circle_frequency": 2.0})
    other = base.set_many({"nozzle.circle_frequency": 2.0, "nozzle.circle_radius": 0.05})
    assert one == other and one.get("nozzle.circle_radius") == 0.05


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
    # Located at the Python call, with the value as given, not at the command's `--set`; the
    # text begins with the key, Python-shaped.
    assert e.location == f"Scenario.set({key!r}, {value!r})"
    assert str(e) == f"{key}: {e.message} ({e.location})"
    assert "--set" not in str(e)
    # The command refuses the same override with the same words.
    scene = tmp_path / "scene.toml"
    scene.write_text(Scenario().to_toml())
    out = subprocess.run([cli, "check", str(scene), "--set", assignment], capture_output=True, text=True)
    assert out.returncode != 0
    assert out.stderr.strip() == f"error: --set {assignment}: `{key}` {e.message}"


def test_override_errors_name_the_python_call_that_gave_the_value():
    with pytest.raises(ScenarioError) as refused:
        Scenario().set_many({"simulation.seed": 3, "emitter.speed": [30, 20]})
    assert refused.value.location == "Scenario.set_many({'emitter.speed': [30, 20]})"
    assert str(refused.value).startswith("emitter.speed: must be [min, max] with min ≤ max")
    assert str(refused.value).endswith("(Scenario.set_many({'emitter.speed': [30, 20]}))")
    with pytest.raises(ScenarioError) as refused:
        Scenario().assign("emitter.spawn_rate=-1")
    assert refused.value.location == "Scenario.assign('emitter.spawn_rate=-1')"
    with pytest.raises(ScenarioError) as refused:
        Scenario().set("emitter.speed", [20.0, None])
    assert refused.value.location == "Scenario.set('emitter.speed', [20.0, None])"
    # An override made by an earlier call, which a later one made impossible, is named too.
    with pytest.raises(ScenarioError) as refused:
        Scenario().set("target[0].resolution", [1024, 1024]).set("simulation.max_memory", 1.5e8)
    assert refused.value.key == "target[0].resolution"
    assert refused.value.location == "Scenario.set('target[0].resolution', [1024, 1024])"


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
    assert str(refused.value) == "simulation.dt: must be greater than 0 s, got -0.001 (<dict>)"
    with pytest.raises(ScenarioError) as refused:
        Scenario.from_dict({"target": [{"name": "wall", "center": [0, 0, 1]}]})
    assert refused.value.key.startswith("target[0].")


def test_a_file_error_names_file_line_and_key(tmp_path):
    path = tmp_path / "wall.toml"
    path.write_text("[simulation]\ndt = -0.001\n")
    with pytest.raises(ScenarioError) as refused:
        Scenario(path)
    assert str(refused.value) == f"simulation.dt: must be greater than 0 s, got -0.001 ({path}:2)"
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


def nested_dict(depth):
    """{"a": {"a": ... {} ...}} with `depth` dicts inside the outermost one."""
    value = {}
    for _ in range(depth):
        value = {"a": value}
    return value


def refusal_in_a_child(build):
    """Runs `build` (code that makes a scenario) in a child process, so that a crash fails the
    test instead of ending the test run; returns the ScenarioError's key and message."""
    code = (
        "import json, spraysim\n"
        "try:\n"
        f"    exec({build!r})\n"
        "except spraysim.ScenarioError as e:\n"
        "    print(json.dumps([e.key, e.message, str(e)]))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout, "not refused"
    return json.loads(out.stdout)


def test_a_value_that_contains_itself_is_refused_naming_the_key():
    key, message, _ = refusal_in_a_child("d = {}\nd['self'] = d\nspraysim.Scenario({'output': d})")
    assert key == "output.self"
    assert "`output`" in message and "contain itself" in message
    key, message, _ = refusal_in_a_child("v = [1.0]\nv.append(v)\nspraysim.Scenario().set('emitter.speed', v)")
    assert key == "emitter.speed[1]"
    assert "`emitter.speed`" in message and "contain itself" in message


@pytest.mark.parametrize("depth", [33, 100, 1000])
def test_values_nested_deeper_than_the_cap_are_refused_naming_the_key_path(depth):
    with pytest.raises(ScenarioError) as refused:
        Scenario({"output": nested_dict(depth)})
    # The cap is hit at the 32nd level: `output` and 31 levels of `a` below it.
    assert refused.value.key == "output" + ".a" * 31
    assert "32 levels" in refused.value.message
    assert str(refused.value).startswith("output.a.a.")
    assert str(refused.value).endswith("(<dict>)")


def test_values_within_the_nesting_cap_reach_the_scenarios_own_checks():
    with pytest.raises(ScenarioError) as refused:
        Scenario({"output": nested_dict(30)})
    assert refused.value.key == "output.a"
    assert "levels" not in refused.value.message


@pytest.mark.parametrize(
    "build, key",
    [
        ("value = {}\nfor _ in range(10_000): value = {'a': value}\nspraysim.Scenario(value)", "a" + ".a" * 31),
        (
            "value = []\nfor _ in range(100_000): value = [value]\nspraysim.Scenario().set('emitter.speed', value)",
            "emitter.speed" + "[0]" * 32,
        ),
    ],
    ids=["dict-10k-deep", "list-100k-deep"],
)
def test_runaway_nesting_raises_instead_of_crashing_the_interpreter(build, key):
    refused_key, message, _ = refusal_in_a_child(build)
    assert refused_key == key
    assert "32 levels" in message
