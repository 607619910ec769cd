#!/usr/bin/python3
"""Soak (docs/benchmarks.md, "Soak and load"): hadald runs a scenario (the default one, cameras included) for 24
simulated hours in fast mode while this driver records, once per wall second, its sim time and real-time factor
(its status line), its resident memory (RSS, /proc/<pid>/status), and counts NaN events (hadald's "non-finite
state" lines and, from a client subscribed to rt/hadal/status all along, the vehicles' fault counts). A client
stays connected for the whole run, reading the status heartbeat.

Written to --out (default BUILD/soak/): samples.csv (wall_s, sim_h, rss_mib, rtf), soak.png (RSS and RTF over
sim time), summary.json; the summary is also printed, one JSON line:
  rss_after_first_hour_mib  RSS when the first simulated hour ends
  rss_max_later_mib         the largest RSS after that
  rss_growth_pct            (rss_max_later - rss_after_first_hour) / rss_after_first_hour, in %
  nan_events                non-finite states reported (log lines; status fault counts as a check)
  rtf_by_hour               mean RTF of each simulated hour
  pass                      zero NaN events and RSS growth under 5 %

    /usr/bin/python3 bench/soak.py [--build build] [--sim-hours 24] [--scenario FILE] [--no-cameras] [--out DIR]

Needs ROS_LOCALHOST_ONLY=1 (set here if absent), python3-matplotlib for the figure.
"""

import argparse
import csv
import json
import os
import re
import subprocess
import sys
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOMAIN = 85  # a benchmark runs alone, outside the test suite's 100..199
STATUS_LINE = re.compile(r"^hadald: sim ([\d.]+) s  RTF ([\d.]+)  ")


def rss_mib(pid):
    with open(f"/proc/{pid}/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def plot(samples, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    hours = [s["sim_h"] for s in samples]
    figure, (rss_axis, rtf_axis) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    rss_axis.plot(hours, [s["rss_mib"] for s in samples], color="tab:blue")
    rss_axis.set_ylabel("hadald RSS [MiB]")
    rss_axis.axvline(1.0, color="grey", linestyle=":", label="end of the first simulated hour")
    rss_axis.legend(loc="lower right")
    rss_axis.grid(alpha=0.3)
    rss_axis.set_ylim(0, 1.25 * max(s["rss_mib"] for s in samples))
    rtf_axis.plot(hours, [s["rtf"] for s in samples], color="tab:orange", linewidth=0.6)
    rtf_axis.set_ylabel("real-time factor (per wall second)")
    rtf_axis.set_xlabel("simulated time [h]")
    rtf_axis.grid(alpha=0.3)
    rtf_axis.set_ylim(bottom=0)
    figure.suptitle(title)
    figure.tight_layout()
    figure.savefig(path, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--sim-hours", type=float, default=24.0)
    parser.add_argument("--scenario", default=os.path.join(ROOT, "configs/scenarios/default.yaml"))
    parser.add_argument("--no-cameras", action="store_true", help="leave the cameras out (hadald --no-cameras)")
    parser.add_argument("--out", default=None, help="default: BUILD/soak")
    args = parser.parse_args()
    args.out = args.out or os.path.join(args.build, "soak")
    os.makedirs(args.out, exist_ok=True)
    os.environ.setdefault("ROS_LOCALHOST_ONLY", "1")
    sys.path.insert(0, os.path.join(args.build, "python"))
    import hadal

    command = [os.path.join(args.build, "bin/hadald"), args.scenario, "--mode", "fast", "--domain-id", str(DOMAIN),
               "--duration", str(args.sim_hours * 3600.0)]
    if args.no_cameras:
        command.append("--no-cameras")
    server = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    samples = []
    nan_lines = []
    log_tail = []

    def read_log():
        for line in server.stderr:
            log_tail.append(line)
            del log_tail[:-50]
            if "non-finite state" in line:
                nan_lines.append(line.strip())
            match = STATUS_LINE.match(line)
            if match and float(match[1]) > 0:
                try:
                    rss = rss_mib(server.pid)
                except OSError:
                    continue
                samples.append({"wall_s": round(time.monotonic() - start, 1), "sim_h": float(match[1]) / 3600.0,
                                "rss_mib": round(rss, 2), "rtf": float(match[2])})

    start = time.monotonic()
    reader = threading.Thread(target=read_log, daemon=True)
    reader.start()
    max_faults = 0
    status_seen = 0
    with hadal.Client(DOMAIN, "hadal_soak") as client:
        while server.poll() is None:
            time.sleep(1.0)
            status = client.status()
            if status is not None:
                status_seen += 1
                max_faults = max(max_faults, sum(status.vehicle_faults))
    summary_text = server.stdout.read()
    reader.join(timeout=10)
    if server.returncode != 0:
        sys.exit("hadald failed:\n" + "".join(log_tail))

    with open(os.path.join(args.out, "samples.csv"), "w", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=["wall_s", "sim_h", "rss_mib", "rtf"])
        writer.writeheader()
        writer.writerows(samples)
    first_hour = [s for s in samples if s["sim_h"] <= 1.0]
    later = [s for s in samples if s["sim_h"] > 1.0]
    rss_first = first_hour[-1]["rss_mib"] if first_hour else float("nan")
    rss_later = max((s["rss_mib"] for s in later), default=float("nan"))
    growth = (rss_later - rss_first) / rss_first * 100.0
    rtf_by_hour = []
    for hour in range(int(args.sim_hours + 0.999)):
        in_hour = [s["rtf"] for s in samples if hour < s["sim_h"] <= hour + 1]
        rtf_by_hour.append(round(sum(in_hour) / len(in_hour), 2) if in_hour else None)
    match = re.search(r"sim time ([\d.]+) s in ([\d.]+) s wall, RTF ([\d.]+)", summary_text)
    peak = re.search(r"peak memory: ([\d.]+) MiB", summary_text)
    summary = {
        "benchmark": "soak", "scenario": os.path.relpath(args.scenario, ROOT), "cameras": not args.no_cameras,
        "sim_hours": float(match[1]) / 3600.0, "wall_s": float(match[2]), "rtf": float(match[3]),
        "rss_after_first_hour_mib": rss_first, "rss_max_later_mib": rss_later,
        "rss_final_mib": samples[-1]["rss_mib"], "rss_growth_pct": round(growth, 2),
        "peak_memory_mib": float(peak[1]) if peak else None,
        "nan_events": len(nan_lines), "status_fault_count_max": max_faults, "status_samples_read": status_seen,
        "rtf_by_hour": rtf_by_hour, "samples": len(samples),
        "pass": len(nan_lines) == 0 and max_faults == 0 and growth < 5.0,
    }
    with open(os.path.join(args.out, "summary.json"), "w") as out:
        json.dump(summary, out, indent=1)
    plot(samples, os.path.join(args.out, "soak.png"),
         f"hadald --mode fast, {summary['scenario']}{'' if summary['cameras'] else ' (no cameras)'}: "
         f"{summary['sim_hours']:.1f} simulated h in {summary['wall_s'] / 60:.0f} min")
    print(json.dumps(summary), flush=True)


if __name__ == "__main__":
    main()
