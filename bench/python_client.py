#!/usr/bin/python3
"""Python client throughput (docs/benchmarks.md, "Lockstep round trip and the Python client"): one JSON
line per measurement.

  lockstep_calls     client.step(k) calls per second against a lockstep hadald on the default scenario
                     without its camera (hadald --no-cameras), k = 1 and 10 physics steps per call,
                     with the AUV's setpoints attached to every request (as a controller sends them), and
                     published on their topic too (set_commands) or not (publish=False); then
                     the same on bench/scenarios/lockstep_auv.yaml (the AUV alone: the round trip's share),
                     after a bare Fast DDS 1 KB round trip between two processes (hadal_bench_dds_round_trip,
                     from $HADAL_BUILD/bin, default build/bin)
  env_steps          hadal.env steps per second (waypoint task, random actions, 0.1 s = 50 physics steps
                     each) for one HadalEnv (as it comes, and pinned like a VectorEnv's servers) and
                     VectorEnv(n), n = 1, 2, 4 (n servers stepped concurrently; and 2 unpinned), measured
                     in interleaved slices of 0.02 s; then VectorEnv(2) over one env (vector_env_speedup)
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
import subprocess
import sys
import time

import numpy as np

import hadal
import hadal.env

HERE = os.path.dirname(os.path.abspath(__file__))


def lockstep_calls(seconds):
    """On the default scenario without its camera (its sonar and lander remain) and on bench/scenarios/lockstep_auv.yaml
    (the AUV alone, ~5 us of physics a step): the second shows the round trip's own cost."""
    here = os.path.dirname(os.path.abspath(__file__))
    bare = os.path.join(os.environ.get("HADAL_BUILD", os.path.join(os.path.dirname(here), "build")), "bin",
                        "hadal_bench_dds_round_trip")
    if os.path.exists(bare):  # the floor: a bare Fast DDS 1 KB round trip between two processes, in the same run
        out = subprocess.run([bare, "--seconds", str(seconds)], capture_output=True, text=True, check=True).stdout
        yield json.loads(out)
    lean = os.path.join(here, "scenarios", "lockstep_auv.yaml")
    for scenario, label in (("default", "default --no-cameras"), (lean, "lockstep_auv")):
        with hadal.Server(scenario, mode="lockstep", cameras=False) as server, server.client("bench") as client:
            client.step(1)
            # The command published on its topic and attached to the request (set_commands), or attached only
            # (publish=False: one DDS sample less a call, what hadal.env does).
            for steps, publish in ((1, True), (10, True), (1, False)):
                calls, start = 0, time.perf_counter()
                while time.perf_counter() - start < seconds:
                    client.set_commands("auv", [0.5, 0.0, 0.0], publish=publish)
                    client.step(steps)
                    calls += 1
                wall = time.perf_counter() - start
                yield {"benchmark": "lockstep_calls", "scenario": label, "steps_per_call": steps,
                       "published": publish, "calls": calls, "wall_s": round(wall, 3),
                       "calls_per_s": round(calls / wall, 1), "physics_steps_per_s": round(calls * steps / wall)}


def env_steps(seconds, slice_s=0.02, blocks=10):
    """All configurations live at once and are measured in turn, in slices of slice_s each (seconds of them in
    all per configuration), so that the machine's drift (+-20 % within a minute on this VM) hits each alike.
    A configuration's rate is its env steps over its time summed over the slices; each ratio is the ratio of
    two such rates, and min/max are those of the same ratio over `blocks` equal runs of consecutive rounds.

    Configurations: "single", a HadalEnv as it comes (the kernel places its server); "single_pinned", a
    HadalEnv whose server is pinned and batch-scheduled like a VectorEnv's (cpus=[first CPU], sched="batch");
    VectorEnv(n) for n = 1, 2, 4 as they come (pinned: hadal.env.VectorEnv); "2_unpinned", VectorEnv(2,
    pin_cpus=False)."""
    rounds = max(blocks, round(seconds / slice_s))
    first_cpu = min(os.sched_getaffinity(0))
    with contextlib.ExitStack() as stack:
        def env(**kwargs):
            made = stack.enter_context(hadal.env.HadalEnv(task="waypoint", **kwargs))
            made.reset()
            return made

        def vector(n, **kwargs):
            made = stack.enter_context(hadal.env.VectorEnv(n, task="waypoint", **kwargs))
            made.reset()
            return made

        configs = {"single": env(seed=1), "single_pinned": env(seed=2, cpus=[first_cpu], sched="batch"),
                   1: vector(1, seed=10), 2: vector(2, seed=20), 4: vector(4, seed=40),
                   "2_unpinned": vector(2, seed=30, pin_cpus=False)}

        def run(made):
            """(env steps, wall seconds) of one slice."""
            vector_env = isinstance(made, hadal.env.VectorEnv)
            steps, start = 0, time.perf_counter()
            while time.perf_counter() - start < slice_s:
                _, _, terminated, truncated, _ = made.step(made.action_space.sample())
                if vector_env:
                    steps += made.num_envs  # ended episodes reset in the same call
                else:
                    steps += 1
                    if terminated or truncated:
                        made.reset()
            return steps, time.perf_counter() - start

        for made in configs.values():  # warm-up
            run(made)
        slices = {key: [] for key in configs}
        for _ in range(rounds):
            for key, made in configs.items():
                slices[key].append(run(made))
        servers = {key: made.envs if isinstance(made, hadal.env.VectorEnv) else [made] for key, made in configs.items()}
        cpus = {key: [env.server.cpus for env in envs] for key, envs in servers.items()}

    def rate(key, part=slice(None)):
        return sum(n for n, _ in slices[key][part]) / sum(t for _, t in slices[key][part])

    parts = [slice(b * rounds // blocks, (b + 1) * rounds // blocks) for b in range(blocks)]
    for key in configs:
        per_block = [rate(key, part) for part in parts]
        yield {"benchmark": "env_steps", "task": "waypoint", "config": str(key), "envs": len(servers[key]),
               "server_cpus": cpus[key], "rounds": rounds, "slice_s": slice_s,
               "env_steps_per_s": round(rate(key), 1), "min": round(min(per_block), 1),
               "max": round(max(per_block), 1)}
    for two, over in ((2, "single"), (2, "single_pinned"), (2, 1), ("2_unpinned", "single")):
        per_block = [rate(two, part) / rate(over, part) for part in parts]
        yield {"benchmark": "vector_env_speedup", "config": str(two), "over": str(over),
               "ratio": round(rate(two) / rate(over), 3), "min": round(min(per_block), 2),
               "max": round(max(per_block), 2), "target": 1.6}


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
