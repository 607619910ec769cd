#!/usr/bin/python3
"""Scaling out on Dask (issue 41; docs/benchmarks.md, "Campaigns and learning on Dask"): one JSON line per
measurement. A dask-scheduler on 127.0.0.1 and dask-workers of one thread each, worker k pinned to CPU k
(taskset; its hadalds inherit the CPU), started and stopped here; real hadalds, real DDS, real TCP.

  campaign        hadal-campaign throughput (cases per wall second) with 1 and 2 workers, interleaved over
                  --rounds: CASES cases of the default scenario without its camera, --case-seconds of sim
                  time each in lockstep (the metrics function steps to the end and reads the odometry)
  vector_env      env steps per second of DaskVectorEnv(2k, envs_per_worker=k) on the two pinned workers
                  against VectorEnv(2k) in this process (its servers pinned to the same two CPUs), k = 1, 2,
                  4, 8, waypoint task (0.1 s = 50 physics steps per env step), random actions; and with
                  step_many (--batch steps per round trip) at k = 4
  round_trip      DaskVectorEnv.ping(): one empty actor call to each worker, with 1 and 2 workers: the per-step
                  cost of the network and Dask beyond the envs' own work, and its growth with the workers

    PYTHONPATH=build/python /usr/bin/python3 bench/dask_scaling.py [--rounds 3] [--seconds 10]
                                                                    [--only campaign,vector_env,round_trip]
"""

import argparse
import contextlib
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import textwrap
import time

import numpy as np

import hadal.env
from hadal import campaign as hadal_campaign

METRICS = textwrap.dedent("""
    def end_state(run):
        client = run.client
        client.wait_odometry("auv", timeout_s=0)
        client.wait_for_subscriptions()
        t = run.step_to(run.duration_s)
        odometry = client.wait_odometry("auv", min_stamp=t - 0.05)
        return {"x_m": odometry.p_WB[0], "z_m": odometry.p_WB[2], "t_s": t}
""")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextlib.contextmanager
def dask_cluster(cpus, work):
    """A scheduler and one single-threaded worker pinned to each CPU of cpus; yields the scheduler address."""
    from distributed import Client

    env = dict(os.environ, ROS_LOCALHOST_ONLY="1")
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    logs = open(os.path.join(work, f"dask-{port}.log"), "w")
    processes = [subprocess.Popen(["dask-scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard",
                                   "--no-show"], stdout=logs, stderr=subprocess.STDOUT, env=env)]
    try:
        for cpu in cpus:
            processes.append(subprocess.Popen(
                ["taskset", "-c", str(cpu), "dask-worker", address, "--nthreads", "1", "--no-nanny", "--no-dashboard",
                 "--host", "127.0.0.1", "--local-directory", os.path.join(work, f"w{port}-{cpu}")],
                stdout=logs, stderr=subprocess.STDOUT, env=env))
        with Client(address, timeout=60) as client:
            client.wait_for_workers(len(cpus), timeout=60)
        yield address
    finally:
        for process in reversed(processes):
            process.terminate()
        for process in processes:
            try:
                process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                process.kill()
        logs.close()


def campaign(rounds, cases, case_seconds, work):
    metrics = os.path.join(work, "metrics.py")
    with open(metrics, "w") as f:
        f.write(METRICS)
    path = os.path.join(work, "campaign.yaml")
    with open(path, "w") as f:
        f.write(textwrap.dedent(f"""\
            scenario: default
            duration_s: {case_seconds}
            seed: 1
            samples: {cases}
            parameters:
              world.water.current.uniform: [{{uniform: [-0.3, 0.3]}}, {{uniform: [-0.3, 0.3]}}, 0.0]
            metrics: metrics.py:end_state
            retries: 0
            """))
    plan = hadal_campaign.load(path)
    rates = {1: [], 2: []}
    for _ in range(rounds):
        for workers in (1, 2):
            with dask_cluster(list(range(workers)), work) as address:
                start = time.perf_counter()
                results = hadal_campaign.run(plan, scheduler=address, progress=None)
                wall = time.perf_counter() - start
            assert results.count("ok") == cases, [row["error"] for row in results.rows]
            rates[workers].append(cases / wall)
            yield {"benchmark": "campaign", "scenario": f"default --no-cameras, {case_seconds} s lockstep",
                   "workers": workers, "cases": cases, "wall_s": round(wall, 2),
                   "cases_per_s": round(cases / wall, 3)}
    ratios = [two / one for one, two in zip(rates[1], rates[2])]
    yield {"benchmark": "campaign_scaling", "two_over_one_worker": round(float(np.median(ratios)), 3),
           "per_round": [round(r, 3) for r in ratios]}


def measure(step, seconds):
    """Env steps per second of step() (returning the env steps it made) over `seconds` after 5 warm-up calls."""
    for _ in range(5):
        step()
    made, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        made += step()
    return made / (time.perf_counter() - start)


def vector_env(rounds, seconds, batch, work):
    rng = np.random.default_rng(0)
    with dask_cluster([0, 1], work) as address:
        for per_worker in (1, 2, 4, 8):
            n = 2 * per_worker
            remote = hadal.env.DaskVectorEnv(n, envs_per_worker=per_worker, scheduler=address, task="waypoint",
                                             seed=1, pin_cpus=True)
            local = hadal.env.VectorEnv(n, task="waypoint", seed=1)
            try:
                remote.reset(seed=1)
                local.reset(seed=1)
                rows = {"dask": [], "local": [], "dask_step_many": []}
                def stepped(envs):
                    def step():
                        envs.step(rng.uniform(-1, 1, (n, 3)))
                        return n
                    return step

                def stepped_many():
                    remote.step_many(rng.uniform(-1, 1, (batch, n, 3)))
                    return batch * n

                for _ in range(rounds):
                    rows["dask"].append(measure(stepped(remote), seconds))
                    rows["local"].append(measure(stepped(local), seconds))
                    if per_worker == 4:
                        rows["dask_step_many"].append(measure(stepped_many, seconds))
            finally:
                remote.close()
                local.close()
            record = {"benchmark": "vector_env", "task": "waypoint", "envs_per_worker": per_worker, "workers": 2,
                      "envs": n, "dask_steps_per_s": round(float(np.median(rows["dask"])), 1),
                      "local_steps_per_s": round(float(np.median(rows["local"])), 1),
                      "dask_over_local": round(float(np.median(np.array(rows["dask"]) / np.array(rows["local"]))), 3)}
            if rows["dask_step_many"]:
                record.update(step_many_batch=batch,
                              dask_step_many_steps_per_s=round(float(np.median(rows["dask_step_many"])), 1),
                              step_many_over_local=round(float(np.median(
                                  np.array(rows["dask_step_many"]) / np.array(rows["local"]))), 3))
            yield record


def round_trip(seconds, work):
    """The bare round trip to 1 and to 2 workers: its growth with the workers is the client's own cost per
    worker per step, which bounds how far one client scales out."""
    for workers in (1, 2):
        with dask_cluster(list(range(workers)), work) as address:
            remote = hadal.env.DaskVectorEnv(workers, envs_per_worker=1, scheduler=address, task="waypoint", seed=1,
                                             pin_cpus=True)
            try:
                for _ in range(20):
                    remote.ping()
                times = []
                start = time.perf_counter()
                while time.perf_counter() - start < seconds:
                    t = time.perf_counter()
                    remote.ping()
                    times.append(time.perf_counter() - t)
            finally:
                remote.close()
        yield {"benchmark": "round_trip", "what": f"DaskVectorEnv.ping(), {workers} worker(s)", "workers": workers,
               "calls": len(times), "median_ms": round(float(np.median(times)) * 1e3, 3),
               "p90_ms": round(float(np.quantile(times, 0.9)) * 1e3, 3)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=10.0, help="per vector-env measurement")
    parser.add_argument("--cases", type=int, default=8)
    parser.add_argument("--case-seconds", type=float, default=30.0)
    parser.add_argument("--batch", type=int, default=10, help="steps per step_many call")
    parser.add_argument("--only", default="campaign,vector_env,round_trip")
    args = parser.parse_args()
    if len(os.sched_getaffinity(0)) < 2 or shutil.which("dask-worker") is None or shutil.which("taskset") is None:
        sys.exit("dask_scaling: needs 2 CPUs, dask-worker (python3-distributed) and taskset")
    os.environ.setdefault("ROS_LOCALHOST_ONLY", "1")
    package = os.path.dirname(os.path.dirname(os.path.abspath(hadal.env.__file__)))
    os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (package, os.environ.get("PYTHONPATH")) if p)
    only = args.only.split(",")
    with tempfile.TemporaryDirectory(prefix="hadal-dask-bench-") as work:
        runs = []
        if "round_trip" in only:
            runs.append(round_trip(min(args.seconds, 5.0), work))
        if "campaign" in only:
            runs.append(campaign(args.rounds, args.cases, args.case_seconds, work))
        if "vector_env" in only:
            runs.append(vector_env(args.rounds, args.seconds, args.batch, work))
        for run in runs:
            for record in run:
                print(json.dumps(record), flush=True)


if __name__ == "__main__":
    main()
