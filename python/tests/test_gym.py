"""The Gymnasium environment (runs when gymnasium is installed; CI installs it)."""

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

from spraysim.gym import ENV_ID, SprayEnv  # noqa: E402


@pytest.mark.parametrize("mode", ["velocity", "pose"])
def test_the_environment_passes_check_env(mode):
    check_env(gymnasium.make(ENV_ID, action_mode=mode, episode_steps=5).unwrapped, skip_render_check=False)


def test_an_episode_returns_its_final_score_and_moves_the_nozzle():
    env = SprayEnv(episode_steps=10, obs_shape=(8, 4))
    obs, info = env.reset(seed=3)
    assert obs["thickness"].shape == (8, 4) and obs["thickness"].dtype == np.float32
    np.testing.assert_allclose(obs["nozzle"], [0.0, 0.0])
    assert info["score"] == 0.0
    total, truncated, steps = 0.0, False, 0
    while not truncated:
        obs, reward, terminated, truncated, info = env.step(np.array([1.0, 0.5], dtype=np.float32))
        assert not terminated
        total += reward
        steps += 1
    assert steps == 10
    assert total == pytest.approx(info["score"], abs=1e-9)
    assert info["coverage"] > 0.0 and info["waste"] > 0.0
    # 10 steps of 0.05 s at 1 m/s to the right and 0.5 m/s up, from the centre of a 2 m wall.
    np.testing.assert_allclose(obs["nozzle"], [0.5, 0.25], atol=1e-6)
    # The deposit lies where the nozzle went: more on the right half than on the left.
    t = obs["thickness"]
    assert t[:, 2:].sum() > t[:, :2].sum()
    image = SprayEnv(render_mode="rgb_array")
    image.reset(seed=0)
    assert image.render().shape == (16, 16, 3)


def test_the_same_seed_gives_the_same_episode():
    a, b = SprayEnv(episode_steps=4), SprayEnv(episode_steps=4)
    oa, _ = a.reset(seed=5)
    ob, _ = b.reset(seed=5)
    for action in ([0.3, -0.2], [-1.0, 1.0], [0.0, 0.0], [1.0, 1.0]):
        ra = a.step(np.array(action, dtype=np.float32))
        rb = b.step(np.array(action, dtype=np.float32))
        assert ra[1] == rb[1]
        np.testing.assert_array_equal(ra[0]["thickness"], rb[0]["thickness"])
