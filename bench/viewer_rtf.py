#!/usr/bin/python3
"""What a viewer costs the server (docs/benchmarks.md, "Viewer"): the real-time factor of `hadald --mode fast` on the
default scenario (camera included) without a viewer, with hadal-viewer attached (it finds hadald and reads its
scene; with no page open it reads nothing more), and with hadal-viewer and a page (a WebSocket client taking everything it pushes: updates at 20 Hz,
camera frames at 5 Hz). The three configurations run in turn, --runs times, so drifts of the machine's speed
fall on all alike; each twice: sharing the machine's CPUs (hadald's threads on all of them, as it comes), and
split (hadald on CPU 0 alone, its world.threads then 1; viewer and page on CPU 1), which separates what the
server pays for one more subscriber from the CPU time the viewer takes from it. The viewer's CPU time per
wall second is reported, and hadald's own CPU time (user + system, all its threads) per simulated second,
which a virtual machine's drifting speed (other guests taking the host's time) moves far less than the RTF.
One JSON line per run, then per configuration the ratios to the no-viewer run of the same round (paired), then
the medians.

    /usr/bin/python3 bench/viewer_rtf.py [--build build] [--runs 5] [--seconds 30] [--nice-page]

Needs ROS_LOCALHOST_ONLY=1 (set here if absent) and python3-websocket.
"""

import argparse
import json
import os
import re
import resource
import signal
import statistics
import subprocess
import threading
import time

import websocket

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOMAIN = 87  # a benchmark runs alone, outside the test suite's 100..199


class Page(threading.Thread):
    """A WebSocket client that takes everything the viewer sends."""

    def __init__(self, url, cpus, nice):
        super().__init__(daemon=True)
        self.cpus = cpus
        self.nice = nice  # run at the viewer's niceness (10)
        self.socket = websocket.create_connection(url.replace("http", "ws").split("?")[0] + "ws", timeout=60)
        self.bytes = 0
        self.messages = 0
        self.running = True
        self.start()

    def run(self):
        if self.cpus:
            os.sched_setaffinity(0, self.cpus)  # this thread only
        if self.nice:
            os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), 10)  # this thread only, as the viewer
        try:
            while self.running:
                message = self.socket.recv()
                self.bytes += len(message)
                self.messages += 1
        except (websocket.WebSocketException, OSError):
            pass

    def close(self):
        self.running = False
        self.socket.close()


def cpu_seconds(pid):
    """User + system CPU time of a process [s] (/proc/PID/stat, clock ticks)."""
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def run_once(build, config, seconds, split, nice_page=False):
    env = dict(os.environ, ROS_LOCALHOST_ONLY="1", ROS_DOMAIN_ID=str(DOMAIN))
    viewer = page = None
    if config != "none":
        # Pinned before it starts: every thread it makes inherits the mask.
        viewer = subprocess.Popen([os.path.join(build, "bin/hadal-viewer"), "--port", "0"], env=env,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                  preexec_fn=(lambda: os.sched_setaffinity(0, {1})) if split else None)
        url = viewer.stdout.readline().split()[2]
        if config == "viewer+page":
            page = Page(url, {1} if split else None, nice_page)
    viewer_cpu0 = cpu_seconds(viewer.pid) if viewer else 0.0
    children0 = resource.getrusage(resource.RUSAGE_CHILDREN)  # the viewer is still running: not in it
    hadald = subprocess.run([os.path.join(build, "bin/hadald"), os.path.join(ROOT, "configs/scenarios/default.yaml"),
                             "--mode", "fast", "--duration", str(seconds), "--discovery-wait", "2",
                             "--no-status-line", *(["--cpus", "0"] if split else [])],
                            env=env, capture_output=True, text=True, timeout=600)
    summary = hadald.stdout + hadald.stderr
    match = re.search(r"sim time ([0-9.]+) s in ([0-9.]+) s wall, RTF ([0-9.]+)", summary)
    if hadald.returncode != 0 or not match:
        raise RuntimeError(f"hadald failed:\n{summary[-2000:]}")
    children1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu_s = (children1.ru_utime - children0.ru_utime) + (children1.ru_stime - children0.ru_stime)
    result = {"config": config, "split": split, "rtf": float(match.group(3)), "wall_s": float(match.group(2)),
              "hadald_cpu_ms_per_sim_s": round(1e3 * cpu_s / float(match.group(1)), 2)}
    if viewer:  # over hadald's whole run, discovery wait included (2 s)
        result["viewer_cpu_per_s"] = round((cpu_seconds(viewer.pid) - viewer_cpu0) / (float(match.group(2)) + 2.0), 3)
    if page:
        time.sleep(0.5)
        result.update(page_messages=page.messages, page_mbytes=round(page.bytes / 1e6, 1))
        page.close()
    if viewer:
        viewer.send_signal(signal.SIGINT)
        _, err = viewer.communicate(timeout=30)
        shown = re.search(r"([0-9]+) sample\(s\) shown", err)
        result["viewer_samples"] = int(shown.group(1)) if shown else None
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--seconds", type=float, default=30.0)
    parser.add_argument("--nice-page", action="store_true",
                        help="run the page client at niceness 10, like the viewer (a browser on this machine, niced)")
    args = parser.parse_args()
    if len(os.sched_getaffinity(0)) < 2:
        raise SystemExit("needs 2 CPUs (CPU 0 for hadald, CPU 1 for the viewer in the split runs)")
    configs = ["none", "viewer", "viewer+page"]
    rtf = {(config, split): [] for config in configs for split in (False, True)}
    cpu_ms = {(config, split): [] for config in configs for split in (False, True)}
    for run in range(args.runs):
        for config in configs[run % 3:] + configs[:run % 3]:
            for split in (False, True):
                result = run_once(args.build, config, args.seconds, split, args.nice_page)
                rtf[(config, split)].append(result["rtf"])
                cpu_ms[(config, split)].append(result["hadald_cpu_ms_per_sim_s"])
                print(json.dumps({"run": run, **result}), flush=True)
    def paired(values, config, split):
        """Per run, config's figure over the no-viewer figure of the same run (minutes apart at most, so a
        slow drift of the machine's speed falls on both): median, mean and its standard error."""
        ratios = [a / b for a, b in zip(values[(config, split)], values[("none", split)])]
        mean = statistics.fmean(ratios)
        error = statistics.stdev(ratios) / len(ratios) ** 0.5 if len(ratios) > 1 else float("nan")
        return {"median": round(statistics.median(ratios), 4), "mean": round(mean, 4), "stderr": round(error, 4)}

    for split in (False, True):
        print(json.dumps({"split": split, "paired_rtf_ratio": {c: paired(rtf, c, split) for c in configs[1:]},
                          "paired_cpu_ratio": {c: paired(cpu_ms, c, split) for c in configs[1:]}}), flush=True)
    for split in (False, True):
        medians = {config: statistics.median(rtf[(config, split)]) for config in configs}
        cpu = {config: statistics.median(cpu_ms[(config, split)]) for config in configs}
        none = rtf[("none", split)]
        print(json.dumps({"split": split, "median_rtf": medians,
                          "viewer_over_none": round(medians["viewer"] / medians["none"], 3),
                          "viewer_page_over_none": round(medians["viewer+page"] / medians["none"], 3),
                          "spread_none": [min(none), max(none)],
                          "median_hadald_cpu_ms_per_sim_s": cpu,
                          "spread_cpu_none": [min(cpu_ms[("none", split)]), max(cpu_ms[("none", split)])]}),
              flush=True)


if __name__ == "__main__":
    main()
