"""The Gymnasium environment (runs when gymnasium is installed; CI installs it)."""

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

import spraysim  # noqa: E402
from spraysim.gym import ACTIONS, ENV_ID, PROCESSES, SprayEnv, default_scenario, resample  # noqa: E402

from test_targets import SHELL  # noqa: E402

ALL = tuple(ACTIONS)


@pytest.mark.parametrize("mode", ["velocity", "pose"])
def test_the_environment_passes_check_env(mode):
    check_env(gymnasium.make(ENV_ID, action_mode=mode, episode_steps=5).unwrapped, skip_render_check=False)


def test_every_action_and_process_passes_check_env():
    for process in PROCESSES:
        env = gymnasium.make(ENV_ID, process=process, actions=ALL, episode_steps=3, render_mode="rgb_array")
        check_env(env.unwrapped, skip_render_check=False)
        assert env.action_space.shape == (7,)


def test_an_episode_returns_its_final_score_gain_and_moves_the_nozzle():
    env = SprayEnv(episode_steps=10, obs_shape=(8, 4))
    obs, info = env.reset(seed=3)
    assert obs["thickness"].shape == (8, 4) and obs["thickness"].dtype == np.float32
    assert obs["mask"].shape == (8, 4) and (obs["mask"] == 1).all()
    np.testing.assert_allclose(obs["nozzle"][:2], [0.0, 0.0])
    # Shotcrete's default task: a 50 mm layer, 40 to 60 mm; bare, every cell is 40 mm short.
    assert env.process == "shotcrete" and env.task == "thickness"
    assert info["error"] == pytest.approx(0.8) and info["score"] == pytest.approx(-0.8)
    start = info["score"]
    total, truncated, steps = 0.0, False, 0
    while not truncated:
        obs, reward, terminated, truncated, info = env.step(np.array([1.0, 0.5], dtype=np.float32))
        assert not terminated
        total += reward
        steps += 1
    assert steps == 10
    assert total == pytest.approx(info["score"] - start, abs=1e-9)
    assert total > 0 and info["waste"] > 0.0 and info["mean_thickness"] > 0.0
    # 10 steps of 0.05 s at 0.5 m/s to the right and 0.25 m/s up, from the centre of a 2 m wall.
    np.testing.assert_allclose(obs["nozzle"][:2], [0.25, 0.125], atol=1e-6)
    # The deposit lies where the nozzle went: more on the right half than on the left.
    t = obs["thickness"]
    assert t[:, 2:].sum() > t[:, :2].sum()


def test_the_same_seed_gives_the_same_episode():
    a, b = SprayEnv(episode_steps=4), SprayEnv(episode_steps=4)
    a.reset(seed=5)
    b.reset(seed=5)
    for action in ([0.3, -0.2], [-1.0, 1.0], [0.0, 0.0], [1.0, 1.0]):
        ra = a.step(np.array(action, dtype=np.float32))
        rb = b.step(np.array(action, dtype=np.float32))
        assert ra[1] == rb[1]
        np.testing.assert_array_equal(ra[0]["thickness"], rb[0]["thickness"])


def test_standoff_tilt_speed_and_spray_actions_drive_the_nozzle():
    env = SprayEnv(process="painting", actions=ALL, episode_steps=3, max_tilt_deg=20.0)
    env.reset(seed=0)
    # move right, standoff at the top of its range, tilted 20° towards +u, full speed, no spray.
    obs, _, _, _, info = env.step(np.array([1, 0, 1, 1, 0, 1, -1], dtype=np.float32))
    lo, hi = env.standoff_range
    assert (lo, hi) == PROCESSES["painting"]["standoff_range"]
    np.testing.assert_allclose(obs["nozzle"][2:], [1.0, 1.0, 0.0, -1.0], atol=1e-6)
    # 0.05 s at the full 1 m/s along +u, out of a 1 m half width.
    assert obs["nozzle"][0] == pytest.approx(0.05, abs=1e-6)
    nozzle = env.sim.nozzle()
    assert not nozzle["spraying"]
    wall = env.sim.target_info("wall")
    frame = env.sim.surface_frame("wall", 0.05, 0.0, hi)
    np.testing.assert_allclose(nozzle["position"], frame["position"], atol=1e-9)
    # The axis leans 20° from the inward normal, towards the wall's right.
    axis = nozzle["axis"]
    assert np.degrees(np.arccos(axis @ -wall["normal"])) == pytest.approx(20.0, abs=1e-6)
    assert axis @ wall["right"] > 0
    assert env.sim.emitted()[0] == 0 and info["waste"] == 0.0  # nothing sprayed
    obs, *_ = env.step(np.array([0, 0, -1, 0, 0, 0, 1], dtype=np.float32))
    assert obs["nozzle"][2] == pytest.approx(-1.0) and env.sim.nozzle()["spraying"]
    assert obs["nozzle"][0] == pytest.approx(0.05, abs=1e-6)  # no direction: no travel


def test_each_process_has_a_realistic_default_task():
    paint = SprayEnv(process="painting")
    assert paint.task == "thickness" and paint._ref == pytest.approx(40e-6)
    assert paint.scenario.get("process.preset") == "painting"
    shotcrete = SprayEnv()
    assert shotcrete._ref == pytest.approx(0.05)
    blast = SprayEnv(process="blasting", episode_steps=2)
    assert blast.task == "cleaning"
    obs, info = blast.reset(seed=0)
    assert info["cleaned_fraction"] == 0.0 and info["score"] == 0.0
    np.testing.assert_allclose(obs["thickness"], 1.0)  # the whole coat left
    blast.step(np.zeros(2, dtype=np.float32))
    obs, _, _, _, info = blast.step(np.zeros(2, dtype=np.float32))
    assert obs["thickness"].min() < 1.0  # the coat wears where the grit strikes
    assert 0.0 <= info["cleaned_fraction"] <= 1.0
    # The process comes from a given scenario's preset.
    assert SprayEnv(scenario=default_scenario("painting")).process == "painting"


def test_the_goal_may_be_a_band_or_a_map():
    band = SprayEnv(goal=(0.01, 0.02))
    _, info = band.reset(seed=0)
    assert info["error"] == pytest.approx(0.01 / 0.015)
    rows, cols = band._map_shape
    target = np.zeros((4, 4))
    target[:, 2:] = 0.02  # only the right half is to be sprayed
    mapped = SprayEnv(goal=target, tolerance=0.0)
    _, info = mapped.reset(seed=0)
    assert info["error"] == pytest.approx(0.5 * 0.02 / 0.01)
    with pytest.warns(DeprecationWarning, match="goal"):
        old = SprayEnv(target_thickness=0.5e-3)
    assert old._ref == pytest.approx(0.5e-3)
    with pytest.raises(ValueError, match="goal"):
        SprayEnv(goal=-1.0)
    with pytest.raises(ValueError, match="goal"):
        SprayEnv(goal=(0.02, 0.01))


def test_render_is_a_heatmap_of_the_map_at_a_useful_size():
    env = SprayEnv(render_mode="rgb_array", episode_steps=5)
    env.reset(seed=0)
    for _ in range(4):
        env.step(np.zeros(2, dtype=np.float32))
    image = env.render()
    assert image.shape == (256, 256, 3) and image.dtype == np.uint8
    # Sprayed cells differ from bare ones: more than a couple of colours.
    assert len(np.unique(image.reshape(-1, 3), axis=0)) > 5
    assert (image == 255).all(axis=2).any()  # the nozzle's cross
    assert SprayEnv(render_mode="rgb_array", render_size=(64, 96)).reset(seed=0) and True


def test_a_cylinder_shell_is_sprayed_on_its_unrolled_map():
    scenario = spraysim.Scenario.from_toml(SHELL).set("simulation.duration", 1.0)
    env = gymnasium.make(
        ENV_ID,
        scenario=scenario,
        process="shotcrete",
        actions=("move", "standoff"),
        standoff=0.5,
        standoff_range=(0.3, 0.7),
        obs_shape=(10, 18),
        episode_steps=4,
        render_mode="rgb_array",
    ).unwrapped
    assert env.target == "arch"
    check_env(env, skip_render_check=False)
    obs, _ = env.reset(seed=0)
    assert obs["thickness"].shape == (10, 18)
    # At the middle of the arch's unrolled map, 0.5 m inside a 1 m radius: 0.5 m from the axis.
    position = env.sim.nozzle()["position"]
    assert np.hypot(position[0], position[2]) == pytest.approx(0.5, abs=1e-9)
    for _ in range(3):
        obs, reward, *_ = env.step(np.array([0.5, 0.0, 0.0], dtype=np.float32))
    assert obs["thickness"].sum() > 0
    assert env.render().shape == (256, 256, 3)


def test_resampling_leaves_openings_out():
    values = np.array([[1.0, np.nan, 3.0, 3.0], [1.0, 1.0, 3.0, 3.0]])
    mean, share = resample(values, (1, 2))
    np.testing.assert_allclose(mean, [[1.0, 3.0]])
    np.testing.assert_allclose(share, [[0.75, 1.0]])
    up, whole = resample(np.array([[2.0]]), (2, 3))
    np.testing.assert_allclose(up, 2.0)
    np.testing.assert_allclose(whole, 1.0)


@pytest.mark.parametrize(
    "kwargs, named",
    [
        ({"actions": ("move", "fly")}, "actions"),
        ({"actions": ()}, "actions"),
        ({"process": "welding"}, "process"),
        ({"standoff_range": (1.0, 0.5)}, "standoff_range"),
        ({"max_tilt_deg": 95}, "max_tilt_deg"),
        ({"episode_steps": 0}, "episode_steps"),
        ({"obs_shape": (0, 4)}, "obs_shape"),
        ({"threads": -1}, "threads"),
        ({"target": "roof"}, "target"),
    ],
)
def test_bad_settings_raise_value_error_naming_them(kwargs, named):
    with pytest.raises(ValueError, match=named):
        SprayEnv(**kwargs)


def test_openings_are_neither_observed_nor_scored_as_bare():
    from test_conventions import window_wall

    env = SprayEnv(scenario=window_wall(duration=2.0), obs_shape=(25, 30), render_mode="rgb_array")
    obs, info = env.reset(seed=0)
    assert obs["mask"].min() == 0.0 and obs["mask"].max() == 1.0
    for _ in range(6):
        obs, _, _, _, info = env.step(np.array([0.2, 0.2], dtype=np.float32))
    assert np.isfinite(obs["thickness"]).all()
    # The error is the mean over the wall's surface only: the window and the door are left out.
    t = env.sim.thickness("wall")
    mask = env.sim.mask("wall")
    low, high = 0.04, 0.06
    expected = np.mean(np.maximum(low - t[mask], 0) + np.maximum(t[mask] - high, 0)) / 0.05
    assert info["error"] == pytest.approx(expected, rel=1e-12)
    assert info["mean_thickness"] == pytest.approx(np.nanmean(t), rel=1e-12)
    image = env.render()
    assert (image == 128).all(axis=2).mean() > 0.1  # the openings in grey
