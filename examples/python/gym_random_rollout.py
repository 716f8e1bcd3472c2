"""A short random-policy rollout of the Gymnasium environment spraysim.gym.SprayEnv: the
agent moves the nozzle over the wall at random; the observation is the nozzle's place on the
wall and a 16 × 16 thickness map, the reward the gain in coverage less overspray and waste.

    pip install "./python[gym]"
    python examples/python/gym_random_rollout.py [--episodes 3] [--seed 0]

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
    a = parser.parse_args()

    env = gymnasium.make(ENV_ID, episode_steps=40, control_dt=0.05, target_thickness=0.5e-3)
    env.action_space.seed(a.seed)
    start = time.perf_counter()
    for episode in range(a.episodes):
        obs, info = env.reset(seed=a.seed + episode)
        total, done = 0.0, False
        while not done:
            obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
            total += reward
            done = terminated or truncated
        print(
            f"episode {episode}: return {total:+.4f}, coverage {info['coverage']:.3f}, "
            f"excess {info['excess']:.3f}, waste {info['waste']:.3f}, "
            f"nozzle at {np.round(obs['nozzle'].astype(float), 2).tolist()} after {info['time']:.2f} s"
        )
    print("last thickness observation (× target thickness, top row up):")
    for row in obs["thickness"][::-1]:
        print(" ".join(f"{v:4.1f}" for v in row))
    print(f"{a.episodes} episodes in {time.perf_counter() - start:.1f} s")
    env.close()


if __name__ == "__main__":
    main()
