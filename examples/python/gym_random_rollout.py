"""A short random-policy rollout of the Gymnasium environment spraysim.gym.SprayEnv: the
agent moves the nozzle over the wall at random, and sets its standoff, tilt and spraying; the
observation is the nozzle's pose and a 32 × 32 thickness map, the reward the step's gain in the
score (the layer's error against the process's thickness band, less waste; for blasting, the
share cleaned).

    pip install "./python[gym]"
    python examples/python/gym_random_rollout.py [--process painting] [--episodes 3] [--seed 0]

About 1 s on 2 cores with the defaults. A learning agent plugs in the same way, e.g. with
stable-baselines3: `PPO("MultiInputPolicy", gymnasium.make("spraysim/Spray-v0")).learn(...)`.
"""

import argparse
import time

import gymnasium
import numpy as np

from spraysim.gym import ENV_ID


def main():
    parser = argparse.ArgumentParser(description="random rollout of the spraysim Gymnasium environment")
    parser.add_argument("--episodes", type=int, default=3)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--process", choices=["shotcrete", "painting", "blasting"], default="painting")
    a = parser.parse_args()

    env = gymnasium.make(
        ENV_ID,
        process=a.process,
        actions=("move", "standoff", "tilt", "spray"),
        episode_steps=40,
        control_dt=0.05,
    )
    env.action_space.seed(a.seed)
    start = time.perf_counter()
    for episode in range(a.episodes):
        obs, info = env.reset(seed=a.seed + episode)
        total, done = 0.0, False
        while not done:
            obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
            total += reward
            done = terminated or truncated
        measures = ", ".join(f"{k} {v:.3f}" for k, v in info.items() if k not in ("time", "score"))
        print(
            f"episode {episode}: return {total:+.4f}, score {info['score']:+.4f}, {measures}, "
            f"nozzle (u, v, standoff, tilts, spray) {np.round(obs['nozzle'].astype(float), 2).tolist()} "
            f"after {info['time']:.2f} s"
        )
    print("last thickness observation, every other cell (× goal thickness, top row up):")
    for row in obs["thickness"][::-2, ::2]:
        print(" ".join(f"{v:4.1f}" for v in row))
    print(f"{a.episodes} episodes in {time.perf_counter() - start:.1f} s")
    env.close()


if __name__ == "__main__":
    main()
