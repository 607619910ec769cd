#!/usr/bin/python3
"""Where a viewer's cost to the server lies (docs/benchmarks.md, "Viewer"): hadald --mode fast on the default scenario
(camera included), alone on CPU 0, profiled with `perf record -e cpu-clock` (a sample every 250 us of its CPU
time), without a viewer and with hadal-viewer and a page (viewer_rtf.Page) on CPU 1, in turn, --runs times. Per
run it counts hadald's samples in all, in the code that only a reader of the monitor or a preview runs
(dds::half_resolution, the monitor's fill and serialization), in Fast DDS (libfastrtps, libfastcdr) and in
the kernel. The same simulated time is the same work, so a configuration's extra samples are what it costs;
those outside the viewer's code paths are spread over all of hadald's code (a virtual machine's drifting speed,
or the other CPU's load slowing this one), and the viewer-only code is the server's own price for a page.
One JSON line per run, then the medians of the per-round differences as a share of the no-viewer run's samples.

    ROS_LOCALHOST_ONLY=1 /usr/bin/python3 bench/viewer_profile.py [--build build] [--runs 3] [--seconds 100]

Needs perf (Debian's linux-perf; not installed by tools/setup.sh), python3-websocket and 2 CPUs.
"""

import argparse
import json
import os
import re
import shutil
import signal
import statistics
import subprocess
import tempfile

from viewer_rtf import DOMAIN, ROOT, Page

# Code that runs only for a reader of the monitor (dds/monitor.h) or of a camera's preview (dds/image_preview.h).
VIEWER_ONLY = re.compile(r"half_resolution|MonitorContent::fill|MonitorPubSubType|MonitorSample")
CATEGORIES = {"viewer_only": lambda dso, sym: bool(VIEWER_ONLY.search(sym)),
              "fast_dds": lambda dso, sym: dso.startswith(("libfastrtps", "libfastcdr")),
              "kernel": lambda dso, sym: dso == "[kernel.kallsyms]"}


def profile_once(build, page, seconds, workdir):
    env = dict(os.environ, ROS_LOCALHOST_ONLY="1", ROS_DOMAIN_ID=str(DOMAIN))
    viewer = client = None
    if page:
        viewer = subprocess.Popen([os.path.join(build, "bin/hadal-viewer"), "--port", "0"], env=env,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                  preexec_fn=lambda: os.sched_setaffinity(0, {1}))
        client = Page(viewer.stdout.readline().split()[2], {1}, False)
    data = os.path.join(workdir, "perf.data")
    try:
        run = subprocess.run(["perf", "record", "-q", "-e", "cpu-clock", "-o", data, "--",
                              os.path.join(build, "bin/hadald"), os.path.join(ROOT, "configs/scenarios/default.yaml"),
                              "--mode", "fast", "--duration", str(seconds), "--discovery-wait", "2",
                              "--no-status-line", "--cpus", "0"], env=env, capture_output=True, text=True, timeout=900)
    finally:
        if client:
            client.close()
        if viewer:
            viewer.send_signal(signal.SIGINT)
            viewer.communicate(timeout=30)
    summary = run.stdout + run.stderr
    match = re.search(r"RTF ([0-9.]+)", summary)
    if run.returncode != 0 or not match:
        raise RuntimeError(f"hadald under perf failed:\n{summary[-2000:]}")
    report = subprocess.run(["perf", "report", "-i", data, "--no-children", "-g", "none", "--stdio",
                             "--sort", "dso,sym", "-F", "sample,dso,sym"], capture_output=True, text=True, check=True)
    counts = {"all": 0, **{name: 0 for name in CATEGORIES}}
    for line in report.stdout.splitlines():
        fields = line.split(None, 2)
        if len(fields) < 3 or line.startswith("#") or not fields[0].isdigit():
            continue
        samples, dso, sym = int(fields[0]), fields[1], fields[2]
        counts["all"] += samples
        for name, belongs in CATEGORIES.items():
            counts[name] += samples if belongs(dso, sym) else 0
    monitors = re.search(r"rt/hadal/monitor ([0-9]+)", summary)
    previews = re.search(r"rt/auv/camera/preview ([0-9]+)", summary)
    return {"page": page, "rtf": float(match.group(1)), "samples": counts,
            "monitors_written": int(monitors.group(1)) if monitors else None,
            "previews_written": int(previews.group(1)) if previews else None}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=100.0)
    args = parser.parse_args()
    if shutil.which("perf") is None:
        raise SystemExit("needs perf: apt-get install linux-perf")
    if len(os.sched_getaffinity(0)) < 2:
        raise SystemExit("needs 2 CPUs (CPU 0 for hadald, CPU 1 for the viewer and its page)")
    shares = {name: [] for name in ["all", *CATEGORIES]}
    with tempfile.TemporaryDirectory(prefix="hadal-viewer-profile-") as workdir:
        for run in range(args.runs):
            results = {}
            for page in ((False, True) if run % 2 == 0 else (True, False)):
                results[page] = profile_once(args.build, page, args.seconds, workdir)
                print(json.dumps({"run": run, **results[page]}), flush=True)
            base = results[False]["samples"]["all"]
            for name in shares:
                extra = results[True]["samples"][name] - results[False]["samples"][name]
                shares[name].append(extra / base)
    print(json.dumps({"extra_samples_with_a_page_over_none": {
        name: {"median": round(statistics.median(values), 4), "runs": [round(v, 4) for v in values]}
        for name, values in shares.items()}}), flush=True)


if __name__ == "__main__":
    main()
