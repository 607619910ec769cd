#!/usr/bin/python3
"""Load (docs/benchmarks.md, "Soak and load"): sixteen subscriber processes read every topic of a realtime hadald on
the default scenario (cameras included) with reliable keep-all readers, while the server must hold real time.

Each subscriber is bench/load_subscriber.cc (hadal::record::TopicTap: raw samples of every topic the server
writes). They start first; hadald then starts with a discovery wait, so that every reader has matched before
the first step, and runs --seconds of sim time in realtime mode. Reported:
- the server's real-time factor over the run (its summary: sim time / wall time after the discovery wait) and
  the lowest and highest of its once-per-wall-second status lines;
- per topic, what the server published (its summary) and, over the sixteen subscribers, the fewest samples
  received, the samples lost (gaps in the writer's sequence numbers), the readers that did not get the last
  sample, and the samples missed at the start (a first sequence number above 1: published before the reader
  matched, which only the server's own status and scene topics do, during the discovery wait).
One JSON line per run, then `"pass": true` when the RTF is within 1 % of 1.0 and no subscriber lost or missed a
sample of any topic.

    /usr/bin/python3 bench/load.py [--build build] [--subscribers 16] [--seconds 60] [--runs 1]

Needs ROS_LOCALHOST_ONLY=1 (set here if absent).
"""

import argparse
import json
import os
import re
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOMAIN = 86  # a benchmark runs alone, outside the test suite's 100..199


def published_counts(summary):
    """topic -> samples published, from hadald's summary ("    rt/auv/imu 1000")."""
    block = summary.split("samples published:", 1)[1]
    counts = {}
    for line in block.splitlines()[1:]:
        match = re.match(r"^    (rt/\S+) (\d+)$", line)
        if not match:
            break
        counts[match[1]] = int(match[2])
    return counts


def run(build, subscribers, seconds, scenario):
    env = dict(os.environ)
    env.setdefault("ROS_LOCALHOST_ONLY", "1")
    work = tempfile.mkdtemp(prefix="hadal-load-")
    readers = []
    for i in range(subscribers):
        ready = os.path.join(work, f"ready-{i}")
        process = subprocess.Popen([os.path.join(build, "bin/hadal_bench_load_subscriber"), "--domain-id", str(DOMAIN),
                                    "--quiet", "3", "--ready-file", ready],
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
        readers.append((process, ready))
    # The discovery wait covers the subscribers' discovery and matching (they find hadald's writers once it
    # has made them, then subscribe); 16 processes on 2 cores take a few seconds.
    server = subprocess.Popen([os.path.join(build, "bin/hadald"), scenario, "--mode", "realtime",
                               "--duration", str(seconds), "--domain-id", str(DOMAIN), "--discovery-wait", "20"],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    summary, log = server.communicate(timeout=seconds * 3 + 120)
    not_ready = [i for i, (_, ready) in enumerate(readers) if not os.path.exists(ready)]
    results = []
    for process, _ in readers:
        out, err = process.communicate(timeout=60)
        if process.returncode != 0:
            raise RuntimeError(f"a subscriber failed: {err}")
        results.append(json.loads(out))
    if server.returncode != 0:
        raise RuntimeError(f"hadald failed: {log[-2000:]}")
    match = re.search(r"sim time ([\d.]+) s in ([\d.]+) s wall", summary)
    sim_s, wall_s = float(match[1]), float(match[2])
    # The status lines of the run (not of the discovery wait, sim 0), less the first and last (partial seconds).
    line_rtfs = [float(rtf) for sim, rtf in re.findall(r"sim ([\d.]+) s  RTF ([\d.]+)  ", log) if float(sim) > 0]
    line_rtfs = line_rtfs[1:-1]
    published = published_counts(summary)
    topics = {}
    for topic, count in sorted(published.items()):
        got = [r["topics"].get(topic, {"samples": 0, "lost": 0, "first": 0, "last": 0}) for r in results]
        topics[topic] = {
            "published": count,
            "min_received": min(g["samples"] for g in got),
            "lost": sum(g["lost"] for g in got),  # gaps in the writer's sequence numbers
            "short_at_end": sum(1 for g in got if g["last"] != count),  # readers without the last sample
            "missed_at_start": sum(max(0, g["first"] - 1) for g in got if g["samples"] > 0),
        }
    rtf = sim_s / wall_s
    # Every reader matched before the first step, so it must have every sample of the simulation's topics;
    # the server's own topics (status, scene) also publish during the discovery wait, before it matched.
    before_matching = ("rt/hadal/status", "rt/hadal/scene", "rt/hadal/monitor")
    complete = all(t["lost"] == 0 and (topic in before_matching or (t["short_at_end"] == 0 and
                                                                     t["missed_at_start"] == 0))
                   for topic, t in topics.items() if t["published"] > 0)
    return {
        "benchmark": "load", "scenario": os.path.relpath(scenario, ROOT), "subscribers": subscribers,
        "sim_s": sim_s, "wall_s": wall_s, "rtf": round(rtf, 5),
        "rtf_per_second_min": min(line_rtfs, default=None), "rtf_per_second_max": max(line_rtfs, default=None),
        "subscribers_not_ready_at_end": len(not_ready),
        "samples_published": sum(published.values()),
        "samples_received": sum(sum(t["samples"] for t in r["topics"].values()) for r in results),
        "bytes_received": sum(sum(t["bytes"] for t in r["topics"].values()) for r in results),
        "topics": topics,
        "pass": abs(rtf - 1.0) <= 0.01 and complete and not not_ready,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--subscribers", type=int, default=16)
    parser.add_argument("--seconds", type=float, default=60.0, help="sim seconds of the realtime run")
    parser.add_argument("--runs", type=int, default=1)
    parser.add_argument("--scenario", default=os.path.join(ROOT, "configs/scenarios/default.yaml"))
    args = parser.parse_args()
    for _ in range(args.runs):
        print(json.dumps(run(args.build, args.subscribers, args.seconds, args.scenario)), flush=True)
        time.sleep(2)


if __name__ == "__main__":
    main()
