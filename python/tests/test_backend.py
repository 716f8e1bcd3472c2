"""backend=: the particles flown on the GPU (Mesa's lavapipe will do) agree with the CPU engine
within statistics, repeat themselves to the bit, and a scenario the GPU cannot run is refused
by name (or run on the CPU with a warning for "auto")."""

import math
import os
import warnings

import pytest

import spraysim
from spraysim import Simulation


@pytest.fixture(scope="module")
def gpu_or_skip():
    """Skips where no GPU opens, unless SPRAYSIM_REQUIRE_GPU or CI is set (then it fails)."""
    try:
        sim = Simulation(spraysim.Scenario().set("simulation.duration", 0.01), backend="gpu")
    except RuntimeError as e:
        if os.environ.get("SPRAYSIM_REQUIRE_GPU") or os.environ.get("CI"):
            raise
        pytest.skip(f"no GPU: {e}")
    return sim.device


def run(scenario, backend, seed):
    sim = Simulation(scenario.set("simulation.seed", seed), backend=backend)
    sim.run()
    return sim.metrics()


def test_an_unknown_backend_is_refused_by_name(short):
    with pytest.raises(ValueError, match="backend.*\"cpu\", \"gpu\", \"auto\""):
        Simulation(short, backend="tpu")
    with pytest.raises(ValueError, match="backend"):
        spraysim.run_many([short], backend="cuda")
    sim = Simulation(short, backend="cpu")
    assert (sim.backend, sim.device) == ("cpu", "CPU")


def test_the_gpu_agrees_with_the_cpu_within_binomial_statistics(short, gpu_or_skip):
    sim = Simulation(short, backend="gpu")
    assert sim.backend == "gpu" and sim.device.startswith("GPU (")
    totals = {"cpu": [0, 0, 0], "gpu": [0, 0, 0]}
    for backend, seeds in (("cpu", (1, 2)), ("gpu", (11, 12))):
        for seed in seeds:
            m = run(short, backend, seed)
            fates = m["fates"]
            # Every particle has one fate, and the volume balance closes.
            assert m["emitted"]["count"] == sum(f["count"] for f in fates.values())
            assert abs(m["volume_balance"]["residual"]) <= 1e-12 * m["volume_balance"]["emitted"]
            t = totals[backend]
            t[0] += m["emitted"]["count"]
            t[1] += m["targets"]["wall"]["stuck"]["count"]
            t[2] += fates["in_flight"]["count"]
    for k, what in ((1, "stuck on the wall"), (2, "in flight at the end")):
        (n1, a), (n2, b) = (totals["cpu"][0], totals["cpu"][k]), (totals["gpu"][0], totals["gpu"][k])
        p = (a + b) / (n1 + n2)
        # 4.4 standard errors: about once in 10⁵ by chance, if both follow one law.
        tolerance = 4.4 * math.sqrt(p * (1 - p) * (1 / n1 + 1 / n2))
        assert abs(a / n1 - b / n2) <= tolerance, (what, a / n1, b / n2, tolerance)


def test_run_many_on_the_gpu_repeats_single_runs_to_the_bit(short, gpu_or_skip):
    # Three runs in one batch, their calls flown together, each equal to itself run alone.
    scenarios = [short.set("simulation.seed", s) for s in (3, 4, 5)]
    alone = []
    for scenario in scenarios:
        sim = Simulation(scenario, backend="gpu")
        sim.run()
        alone.append(sim.metrics())
    assert spraysim.run_many(scenarios, threads=2, backend="gpu") == alone
    assert alone[0] != alone[1], "another seed gives other results"


def test_a_scenario_outside_the_gpus_scope_is_refused_or_run_on_the_cpu(short):
    # The scope is checked before any adapter is looked for: this holds on any machine.
    # A paint gun's air: droplets carried in a jet, which only the CPU engine flies.
    gun = short.set("process.preset", "painting").set("process.gun", "hvlp")
    with pytest.raises(RuntimeError, match="gun's air"):
        Simulation(gun, backend="gpu")
    with pytest.raises(RuntimeError, match=r"scenarios\[1\].*gun's air"):
        spraysim.run_many([short, gun], backend="gpu")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sim = Simulation(gun, backend="auto")
    assert sim.backend == "cpu"
    assert any(issubclass(w.category, RuntimeWarning) and "gun's air" in str(w.message) for w in caught)


def test_the_gym_environment_sprays_on_the_gpu(gpu_or_skip):
    gym = pytest.importorskip("gymnasium")
    from spraysim.gym import SprayEnv

    env = SprayEnv(process="painting", episode_steps=3, backend="gpu")
    observation, _ = env.reset(seed=1)
    assert env.sim.backend == "gpu"
    total = 0.0
    for _ in range(3):
        observation, reward, terminated, truncated, info = env.step(env.action_space.sample())
        total += reward
        assert math.isfinite(reward)
    assert truncated and env.sim.metrics()["targets"][env.target]["stuck"]["count"] > 0
    assert isinstance(env.observation_space, gym.spaces.Space)


@pytest.mark.parametrize("backend", ["cpu", "gpu"])
def test_the_vector_env_steps_its_envs_together_as_each_alone(backend, request):
    gym = pytest.importorskip("gymnasium")
    if not hasattr(gym.vector, "AutoresetMode"):
        pytest.skip("SprayVectorEnv needs Gymnasium 1.0")
    if backend == "gpu":
        request.getfixturevalue("gpu_or_skip")
    import numpy as np
    from spraysim.gym import SprayEnv, SprayVectorEnv

    kwargs = dict(process="painting", actions=("move", "standoff"), episode_steps=3, backend=backend)
    envs = SprayVectorEnv(3, **kwargs)
    singles = [SprayEnv(**kwargs) for _ in range(3)]
    obs, _ = envs.reset(seed=5)
    alone = [env.reset(seed=5 + k)[0] for k, env in enumerate(singles)]
    for key in obs:
        assert np.array_equal(obs[key], np.stack([o[key] for o in alone]))
    rng = np.random.default_rng(0)
    ended, ends = [False] * 3, 0
    # Five steps: the episodes end at the third, and the fourth resets them (its actions unused).
    for step in range(5):
        actions = rng.uniform(-1, 1, size=envs.action_space.shape)
        obs, rewards, terminated, truncated, _ = envs.step(actions)
        for k, env in enumerate(singles):
            if ended[k]:
                o, r, done = env.reset()[0], 0.0, False
            else:
                o, r, te, tr, _ = env.step(actions[k])
                done = te or tr
            ended[k] = done
            ends += done
            assert rewards[k] == r and (terminated[k] or truncated[k]) == done, (step, k)
            for key in o:
                assert np.array_equal(obs[key][k], o[key]), (step, k, key)
    assert ends == 3 and envs.envs[0].sim.backend == backend
