#!/usr/bin/python3
"""Learn the waypoint task with numpy alone: the cross-entropy method over a linear policy a = tanh(W x + b).

The policy maps the task's 12 observations, scaled to order one (x = obs * OBS_SCALE: the waypoint in B per
4 m, velocity in m/s, angular velocity per 0.5 rad/s, W's up axis in B), to the 3 thruster setpoints [main,
heave, sway]: 39 parameters. The cross-entropy method keeps a Gaussian over them (mean mu, per-parameter
sigma, starting at mu = 0, sigma = --init-std); each iteration samples --population candidates, scores each
on the same --episodes episode seeds (common random numbers: every candidate meets the same starts and
waypoints, so their returns differ by the policy alone), and refits mu and sigma to the best --elite of them
(sigma floored by --min-std). The candidates' episodes run on a VectorEnv of --envs lockstep servers, one
(candidate, seed) pair per server at a time. The mean policy mu is scored each iteration on --eval-episodes
held-out seeds never used for training. Everything follows from --seed: a rerun prints the same returns,
whatever --envs (a lockstep episode depends on its seed and actions alone).

What to expect (defaults, ~3.5 min on 2 cores): the held-out return goes from 1.6 (thrusters off: the AUV
floats up towards the waypoint) to ~9 (a random policy: ~-2; the waypoint is 11-21 m away, +10 on reaching
it). A hand-tuned linear policy that slows down near the waypoint scores ~21: the nose's tunnel thrusters
lose authority at speed, so turning needs low speed, which this small budget seldom finds.

Each iteration prints the population's best and mean return, the elites' mean and the mean policy's
held-out return; the run ends with key=value lines (initial_mean_return: mu = 0, i.e. all thrusters off, on
the held-out seeds; final_mean_return: the last mu there; improvement: their difference; success rates)
and --save writes the policy (W, b, obs_scale) and the learning curve to an .npz:

    /usr/bin/python3 examples/python/train_waypoint.py --iterations 10 --population 16 --save policy.npz

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

OBS_SCALE = np.array([0.25] * 3 + [1.0] * 3 + [2.0] * 3 + [1.0] * 3)  # goal_B, v_B, w_B, up_B
N_OBS, N_ACT = 12, 3
N_PARAMS = N_ACT * N_OBS + N_ACT


def policy(theta, obs):
    """Actions (n, 3) of parameter rows theta (n, 39) for observations (n, 12)."""
    W = theta[:, :N_ACT * N_OBS].reshape(-1, N_ACT, N_OBS)
    return np.tanh(np.einsum("nij,nj->ni", W, obs * OBS_SCALE) + theta[:, N_ACT * N_OBS:])


def evaluate(envs, thetas, seeds):
    """Returns and successes (len(thetas), len(seeds)) of every candidate on every seed, and the env steps."""
    jobs = [(k, j) for k in range(len(thetas)) for j in range(len(seeds))]
    returns, successes = np.zeros((len(thetas), len(seeds))), np.zeros((len(thetas), len(seeds)), bool)
    n, steps = envs.num_envs, 0
    for first in range(0, len(jobs), n):
        batch = jobs[first:first + n]
        rows = np.zeros((n, N_PARAMS))
        jobs_now = [batch[i] if i < len(batch) else batch[0] for i in range(n)]  # idle envs (last round) too:
        obs = envs.reset(seed=[int(seeds[j]) for _, j in jobs_now])[0]           # never-reset envs can't step
        for i, (k, _) in enumerate(jobs_now):
            rows[i] = thetas[k]
        done = np.arange(n) >= len(batch)  # idle servers step with zero thrust, ignored
        total = np.zeros(n)
        while not done.all():
            actions = np.where(done[:, None], 0.0, policy(rows, obs))
            obs, rewards, terminated, truncated, infos = envs.step(actions)
            steps += n
            total += np.where(done, 0.0, rewards)
            for i in np.flatnonzero(~done & (terminated | truncated)):  # the VectorEnv reset it: ignored
                done[i] = True
                k, j = batch[i]
                successes[k, j] = infos[i]["final_info"]["is_success"]
        for i, (k, j) in enumerate(batch):
            returns[k, j] = total[i]
    return returns, successes, steps


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--iterations", type=int, default=10)
    parser.add_argument("--population", type=int, default=16, help="candidates per iteration")
    parser.add_argument("--elite", type=int, default=4, help="candidates the distribution is refitted to")
    parser.add_argument("--episodes", type=int, default=2, help="episode seeds per iteration (all candidates)")
    parser.add_argument("--eval-episodes", type=int, default=4, help="held-out seeds scoring the mean policy")
    parser.add_argument("--episode-steps", type=int, default=200, help="steps of 0.1 s per episode at most")
    parser.add_argument("--init-std", type=float, default=1.0)
    parser.add_argument("--min-std", type=float, default=0.05)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--envs", type=int, default=2, help="lockstep servers evaluating in parallel")
    parser.add_argument("--save", help="write the policy and the learning curve to this .npz")
    args = parser.parse_args()

    rng = np.random.default_rng(args.seed)
    eval_seeds = rng.integers(0, 2**31, args.eval_episodes)  # held out: never trained on
    mu, sigma = np.zeros(N_PARAMS), np.full(N_PARAMS, args.init_std)
    curve = []  # per iteration: population best, population mean, elite mean, mean policy (held out)
    with hadal.env.VectorEnv(args.envs, task="waypoint", seed=args.seed,
                             max_episode_steps=args.episode_steps) as envs:
        start = time.monotonic()
        initial, initial_success, steps = evaluate(envs, mu[None], eval_seeds)
        final, final_success = initial, initial_success
        print(f"iteration 0: mean policy (all thrusters off) held-out return {initial.mean():.3f}", flush=True)
        for iteration in range(1, args.iterations + 1):
            seeds = rng.integers(2**31, 2**32, args.episodes)  # this iteration's, the same for every candidate
            thetas = mu + sigma * rng.standard_normal((args.population, N_PARAMS))
            returns, _, n = evaluate(envs, thetas, seeds)
            scores = returns.mean(axis=1)
            elite = thetas[np.argsort(scores)[::-1][:args.elite]]
            mu, sigma = elite.mean(axis=0), np.maximum(elite.std(axis=0), args.min_std)
            final, final_success, m = evaluate(envs, mu[None], eval_seeds)
            steps += n + m
            curve.append((scores.max(), scores.mean(), np.sort(scores)[::-1][:args.elite].mean(), final.mean()))
            print(f"iteration {iteration}: best {scores.max():.3f} mean {scores.mean():.3f} elite mean "
                  f"{curve[-1][2]:.3f} | mean policy held-out {final.mean():.3f} success {final_success.mean():.2f} "
                  f"| sigma {sigma.mean():.3f} ({time.monotonic() - start:.0f} s)", flush=True)
        elapsed = time.monotonic() - start
    curve = np.array(curve).reshape(-1, 4)
    figures = {"iterations": args.iterations, "initial_mean_return": initial.mean(),
               "initial_population_mean_return": curve[0, 1] if len(curve) else float("nan"),
               "final_mean_return": final.mean(), "improvement": final.mean() - initial.mean(),
               "initial_success_rate": initial_success.mean(), "final_success_rate": final_success.mean(),
               "env_steps": steps, "wall_s": elapsed, "env_steps_per_s": steps / elapsed}
    for key, value in figures.items():
        print(f"{key}={value}" if isinstance(value, int) else f"{key}={value:.4f}")
    if args.save:
        np.savez(args.save, W=mu[:N_ACT * N_OBS].reshape(N_ACT, N_OBS), b=mu[N_ACT * N_OBS:], obs_scale=OBS_SCALE,
                 sigma=sigma, curve=curve, eval_seeds=eval_seeds)
        print(f"policy={os.path.abspath(args.save)}")


if __name__ == "__main__":
    main()
