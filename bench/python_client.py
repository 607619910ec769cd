#!/usr/bin/python3
"""Python client throughput (BENCHMARKS.md, "Python: lockstep, environments, camera frames"): one JSON line
per measurement.

  lockstep_calls     client.step(k) calls per second against a lockstep hadald on the default scenario
                     without its camera (hadald --no-cameras), k = 1 and 10 physics steps per call,
                     with the AUV's setpoints attached to every request (as a controller sends them)
  env_steps          hadal.env steps per second (waypoint task, random actions, 0.1 s = 50 physics steps
                     each) for one HadalEnv and VectorEnv(n), n = 1, 2, 4 (n servers stepped concurrently),
                     measured in interleaved rounds; then VectorEnv(2) over one env (vector_env_speedup)
  camera_frames      640 x 480 rgb8 frames per second delivered into numpy (frame.array copied) from
                     bench/scenarios/camera_stream.yaml (30 Hz camera, plane seabed, one lamp): lockstep
                     requests of one frame period each, waiting for that frame

    /usr/bin/python3 bench/python_client.py [--seconds 10] [--only lockstep_calls,env_steps,camera_frames]

Needs PYTHONPATH=build/python (or the installed package) and ROS_LOCALHOST_ONLY=1.
"""

import argparse
import contextlib
import json
import os
import statistics
import sys
import time

import numpy as np

import hadal
import hadal.env

HERE = os.path.dirname(os.path.abspath(__file__))


def lockstep_calls(seconds):
    with hadal.Server("default", mode="lockstep", cameras=False) as server, server.client("bench") as client:
        client.step(1)
        for steps in (1, 10):
            calls, start = 0, time.perf_counter()
            while time.perf_counter() - start < seconds:
                client.set_thrusters("auv", [0.5, 0.0, 0.0])
                client.step(steps)
                calls += 1
            wall = time.perf_counter() - start
            yield {"benchmark": "lockstep_calls", "scenario": "default --no-cameras", "steps_per_call": steps,
                   "calls": calls, "wall_s": round(wall, 3), "calls_per_s": round(calls / wall, 1),
                   "physics_steps_per_s": round(calls * steps / wall)}


def env_steps(seconds, rounds=8):
    """All envs live at once and are measured in turn, `rounds` slices of seconds / rounds each, so that the
    machine's drift (+-20 % over minutes on this VM) hits every configuration alike; each row gives the
    median of its slices, and the ratios are medians of the per-round ratios."""
    slice_s = seconds / rounds
    with contextlib.ExitStack() as stack:
        single = stack.enter_context(hadal.env.HadalEnv(task="waypoint", seed=1))  # the baseline, in this process
        vectors = {n: stack.enter_context(hadal.env.VectorEnv(n, task="waypoint", seed=10 * n)) for n in (1, 2, 4)}
        single.reset()
        for envs in vectors.values():
            envs.reset()

        def run_single():
            steps, start = 0, time.perf_counter()
            while time.perf_counter() - start < slice_s:
                _, _, terminated, truncated, _ = single.step(single.action_space.sample())
                steps += 1
                if terminated or truncated:
                    single.reset()
            return steps / (time.perf_counter() - start)

        def run_vector(n):
            envs, steps, start = vectors[n], 0, time.perf_counter()
            while time.perf_counter() - start < slice_s:
                envs.step(envs.action_space.sample())  # ended episodes reset in the same call
                steps += n
            return steps / (time.perf_counter() - start)

        runs = {"single": run_single, 1: lambda: run_vector(1), 2: lambda: run_vector(2), 4: lambda: run_vector(4)}
        for run in runs.values():  # warm-up
            run()
        rates = {key: [] for key in runs}
        for _ in range(rounds):
            for key, run in runs.items():
                rates[key].append(run())
        threads = {n: vectors[n].envs[0].server.threads for n in vectors}
    for key, values in rates.items():
        yield {"benchmark": "env_steps", "task": "waypoint", "envs": 1 if key == "single" else key,
               "vector": key != "single", "server_threads": threads.get(key), "rounds": rounds,
               "slice_s": slice_s, "env_steps_per_s": round(statistics.median(values), 1),
               "min": round(min(values), 1), "max": round(max(values), 1)}
    for baseline in ("single", 1):
        ratios = [two / one for two, one in zip(rates[2], rates[baseline])]
        over = "HadalEnv" if baseline == "single" else "VectorEnv(1)"
        yield {"benchmark": "vector_env_speedup", "two_envs_over": over,
               "median": round(statistics.median(ratios), 2), "min": round(min(ratios), 2),
               "max": round(max(ratios), 2), "target": 1.6}


def camera_frames(seconds):
    scenario = os.path.join(HERE, "scenarios", "camera_stream.yaml")
    with hadal.Server(scenario, mode="lockstep") as server, server.client("bench") as client:
        client.wait_image("probe", "camera", timeout_s=0)
        client.wait_for_subscriptions(20)
        period_steps = 10  # 300 Hz physics, 30 Hz camera
        t = client.step(period_steps)
        client.wait_image("probe", "camera", min_stamp=t, timeout_s=20)
        frames, start, checksum = 0, time.perf_counter(), 0
        while time.perf_counter() - start < seconds:
            t = client.step(period_steps)
            frame = client.wait_image("probe", "camera", min_stamp=t, timeout_s=20)
            pixels = np.array(frame.array)  # a copy the caller owns
            checksum += int(pixels[240, 320, 1])
            frames += 1
        wall = time.perf_counter() - start
        yield {"benchmark": "camera_frames", "width": frame.width, "height": frame.height,
               "encoding": frame.encoding, "frames": frames, "wall_s": round(wall, 3),
               "fps": round(frames / wall, 1), "centre_green_mean": round(checksum / frames, 1)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0, help="wall time per measurement")
    parser.add_argument("--only", default="lockstep_calls,env_steps,camera_frames")
    args = parser.parse_args()
    for name in args.only.split(","):
        for row in globals()[name](args.seconds):
            print(json.dumps(row), flush=True)


if __name__ == "__main__":
    sys.exit(main())
