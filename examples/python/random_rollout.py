#!/usr/bin/python3
"""Random policy on a hadal.env task: the baseline any learned policy must beat, and a throughput figure.

Each step samples the action space (uniform in [-1, 1] per actuator, seeded from --seed) and applies it for
the task's control period (0.1 s of sim time for "waypoint", 0.2 s for "station_keeping"). With --envs 1 a
HadalEnv runs the episodes one after another; with --envs N a VectorEnv steps N servers concurrently (one
hadald each, on its own DDS domain) and its same-call autoreset starts the next episode of an env whose
episode ended. Each finished episode prints its return, length and success (the waypoint reached; the
station-keeping task has no success, only "lost" beyond 10 m); the run ends with key=value lines: episodes,
mean_return, std_return, success_rate, env_steps (all steps taken, those of unfinished episodes included)
and env_steps_per_s (wall clock, server start excluded). --steps caps an episode's length (the tasks' own
caps: 600 steps):

    /usr/bin/python3 examples/python/random_rollout.py --task waypoint --episodes 3 --steps 200 --seed 0

(needs the Python client on PYTHONPATH: build/python, or the installed package; numpy).
"""

import argparse
import os
import sys
import time

import numpy as np

try:
    import hadal.env
except ImportError:  # run from the source tree after a build
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "../../build/python"))
    import hadal.env


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--task", default="waypoint", choices=sorted(hadal.env.TASKS), help="hadal.env task")
    parser.add_argument("--episodes", type=int, default=3, help="episodes to finish")
    parser.add_argument("--steps", type=int, default=200, help="steps per episode at most (truncation)")
    parser.add_argument("--seed", type=int, default=0, help="seeds the episodes and the actions")
    parser.add_argument("--envs", type=int, default=1, help="> 1: a VectorEnv of that many servers")
    args = parser.parse_args()

    returns, lengths, successes = [], [], []

    def finished(reward_sum, length, info):
        returns.append(reward_sum)
        lengths.append(length)
        successes.append(bool(info.get("is_success", False)))
        extra = "".join(f" {k}={info[k]:.2f}" for k in ("distance_m", "offset_m") if k in info)
        print(f"episode {len(returns)}: return={reward_sum:.3f} length={length} "
              f"success={successes[-1]}{extra}", flush=True)

    steps = 0
    if args.envs <= 1:
        with hadal.env.HadalEnv(task=args.task, seed=args.seed, max_episode_steps=args.steps) as env:
            start = time.monotonic()
            for _ in range(args.episodes):
                env.reset()
                reward_sum, length, done = 0.0, 0, False
                while not done:
                    _, reward, terminated, truncated, info = env.step(env.action_space.sample())
                    reward_sum, length, steps = reward_sum + reward, length + 1, steps + 1
                    done = terminated or truncated
                finished(reward_sum, length, info)
            elapsed = time.monotonic() - start
    else:
        with hadal.env.VectorEnv(args.envs, task=args.task, seed=args.seed, max_episode_steps=args.steps) as envs:
            start = time.monotonic()
            envs.reset(seed=args.seed)  # env i: seed + i
            reward_sums, lengths_now = np.zeros(args.envs), np.zeros(args.envs, dtype=int)
            while len(returns) < args.episodes:
                _, rewards, terminated, truncated, infos = envs.step(envs.action_space.sample())
                steps += args.envs
                reward_sums += rewards
                lengths_now += 1
                for i in np.flatnonzero(terminated | truncated):  # already reset by the VectorEnv
                    if len(returns) < args.episodes:
                        finished(float(reward_sums[i]), int(lengths_now[i]), infos[i]["final_info"])
                    reward_sums[i], lengths_now[i] = 0.0, 0
            elapsed = time.monotonic() - start

    figures = {"episodes": len(returns), "mean_return": float(np.mean(returns)), "std_return": float(np.std(returns)),
               "mean_length": float(np.mean(lengths)), "success_rate": float(np.mean(successes)),
               "env_steps": steps, "wall_s": elapsed, "env_steps_per_s": steps / elapsed}
    for key, value in figures.items():
        print(f"{key}={value}" if isinstance(value, int) else f"{key}={value:.4f}")


if __name__ == "__main__":
    main()
