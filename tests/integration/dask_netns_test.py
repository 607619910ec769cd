"""hadal-campaign across machines without the machines (issue 41): a Dask scheduler in one network namespace,
two dask-workers in two others, joined by veth pairs on a bridge (real TCP between them, as between hosts).
Each case's hadald runs in its worker's namespace with discovery on that namespace's loopback alone.

- A 16-case campaign there gives the same table as on a LocalCluster (every column but where, how long and
  how often a case ran).
- kill -9 of a worker in the middle of the campaign: every case still completes, the interrupted case once
  more on the other worker, none lost and none twice, with the same metrics; the killed worker's hadald dies
  with it.

Needs root to make namespaces (ip netns, iproute2); skipped with that reason otherwise (CI runs as root)."""

import csv
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import threading
import time

import pytest

from hil_netns_test import WAIT_RUNNING, add_namespace_or_skip, ip

pytestmark = pytest.mark.skipif(os.geteuid() != 0 or shutil.which("ip") is None,
                                reason="needs root and iproute2's ip to make network namespaces (CI runs as root)")

SCHEDULER_ADDRESS = "10.78.0.1"
WORKER_ADDRESSES = ("10.78.0.2", "10.78.0.3")
PORT = 8786

# 16 cases of the ROV drifting for 4 s in a swept current from drawn start points; the metrics are where it
# ends (full precision in the CSV) and how many sim steps it took.
CAMPAIGN = textwrap.dedent("""\
    scenario: rov
    duration_s: 4.0
    seed: 41
    samples: 4
    grid:
      world.water.current.uniform: [[0.0, 0.0, 0.0], [0.2, 0.0, 0.0], [0.0, -0.2, 0.0], [0.3, 0.3, 0.0]]
    parameters:
      vehicles.rov.initial_pose.position: [{uniform: [-3.0, 3.0]}, {uniform: [-3.0, 3.0]}, {normal: [-80.0, 5.0]}]
    metrics: metrics.py:end_state
    retries: 2
""")
METRICS = textwrap.dedent("""
    def end_state(run):
        client = run.client
        client.wait_odometry("rov", timeout_s=0)
        client.wait_for_subscriptions()
        t = run.step_to(run.duration_s)
        odometry = client.wait_odometry("rov", min_stamp=t - 1e-6)
        return {"x_m": odometry.p_WB[0], "y_m": odometry.p_WB[1], "z_m": odometry.p_WB[2],
                "u_m_s": odometry.v_WB_B[0], "t_s": t}
""")
WHERE_AND_HOW_LONG = ("worker", "wall_s", "attempts")


@pytest.fixture
def cluster_namespaces():
    """A scheduler namespace with a bridge, and two worker namespaces on it by veth pairs; removed afterwards."""
    tag = str(os.getpid())
    scheduler_ns = f"hadal_dask_s{tag}"
    worker_ns = [f"hadal_dask_w{i}{tag}" for i in (1, 2)]
    add_namespace_or_skip(scheduler_ns)
    try:
        bridge = f"db{tag}"
        ip("-n", scheduler_ns, "link", "add", bridge, "type", "bridge")
        ip("-n", scheduler_ns, "addr", "add", SCHEDULER_ADDRESS + "/24", "dev", bridge)
        ip("-n", scheduler_ns, "link", "set", bridge, "up")
        ip("-n", scheduler_ns, "link", "set", "lo", "up")
        for i, (ns, address) in enumerate(zip(worker_ns, WORKER_ADDRESSES)):
            ip("netns", "add", ns)
            inner, outer = f"dw{i}{tag}", f"dp{i}{tag}"
            ip("link", "add", inner, "netns", ns, "type", "veth", "peer", "name", outer, "netns", scheduler_ns)
            ip("-n", scheduler_ns, "link", "set", outer, "master", bridge)
            ip("-n", scheduler_ns, "link", "set", outer, "up")
            ip("-n", ns, "addr", "add", address + "/24", "dev", inner)
            ip("-n", ns, "link", "set", inner, "up")
            ip("-n", ns, "link", "set", "lo", "up")
            subprocess.run(["ip", "netns", "exec", ns, sys.executable, "-c", WAIT_RUNNING, inner], check=True, timeout=30)
        subprocess.run(["ip", "netns", "exec", scheduler_ns, sys.executable, "-c", WAIT_RUNNING, bridge], check=True,
                       timeout=30)
        yield scheduler_ns, worker_ns
    finally:
        for ns in (*worker_ns, scheduler_ns):
            subprocess.run(["ip", "netns", "del", ns], capture_output=True, timeout=30)


def dask_env():
    env = dict(os.environ, ROS_LOCALHOST_ONLY="1", DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT="30s")
    return env


class DaskCluster:
    """dask-scheduler in one namespace, a dask-worker (no nanny: one process, one thread) in each other."""

    def __init__(self, scheduler_ns, worker_ns, log_dir):
        self.logs = []
        self.scheduler = self._start(scheduler_ns, log_dir / "scheduler.log", [
            "dask-scheduler", "--host", SCHEDULER_ADDRESS, "--port", str(PORT), "--no-dashboard",
            "--no-show"])
        self._wait_for_port()
        self.workers = [self._start(ns, log_dir / f"worker{i}.log", [
            "dask-worker", f"tcp://{SCHEDULER_ADDRESS}:{PORT}", "--host", address, "--nthreads", "1",
            "--no-nanny", "--no-dashboard", "--name", f"w{i}", "--local-directory", str(log_dir / f"w{i}")])
            for i, (ns, address) in enumerate(zip(worker_ns, WORKER_ADDRESSES), 1)]

    def _start(self, ns, log_path, command):
        log = open(log_path, "w")
        self.logs.append(log_path)
        return subprocess.Popen(["ip", "netns", "exec", ns, *command], stdout=log, stderr=subprocess.STDOUT,
                                env=dask_env(), start_new_session=True)

    def _wait_for_port(self):
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            if "Scheduler at:" in self.logs[0].read_text():
                return
            time.sleep(0.1)
        raise AssertionError("dask-scheduler did not start:\n" + self.logs[0].read_text())

    def log_text(self):
        return "\n".join(f"--- {path.name}\n{path.read_text()[-3000:]}" for path in self.logs)

    def stop(self):
        for process in (*self.workers, self.scheduler):
            if process.poll() is None:
                os.killpg(process.pid, signal.SIGTERM)
        for process in (*self.workers, self.scheduler):
            try:
                process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()


def campaign_command(path, out, *extra):
    return [sys.executable, "-m", "hadal.campaign", "run", str(path), "--out", str(out), "--figure", "none", *extra]


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def without(rows, columns):
    return [{k: v for k, v in row.items() if k not in columns} for row in rows]


@pytest.fixture
def campaign_file(tmp_path):
    (tmp_path / "metrics.py").write_text(METRICS)
    path = tmp_path / "campaign.yaml"
    path.write_text(CAMPAIGN)
    return path


@pytest.fixture
def local_rows(campaign_file, tmp_path):
    """The campaign on a LocalCluster of two workers in this namespace."""
    out = tmp_path / "local.csv"
    done = subprocess.run(campaign_command(campaign_file, out, "--workers", "2"), capture_output=True, text=True,
                          timeout=600, env=dask_env())
    assert done.returncode == 0, done.stdout + done.stderr
    rows = read_rows(out)
    assert len(rows) == 16 and all(row["status"] == "ok" for row in rows)
    return rows


def workers_of(rows):
    return {row["worker"].rsplit(":", 1)[0] for row in rows}


def test_a_campaign_across_namespaces_is_the_local_clusters_to_the_bit(cluster_namespaces, campaign_file, tmp_path,
                                                                       local_rows):
    scheduler_ns, worker_ns = cluster_namespaces
    cluster = DaskCluster(scheduler_ns, worker_ns, tmp_path)
    try:
        out = tmp_path / "cluster.csv"
        done = subprocess.run(["ip", "netns", "exec", scheduler_ns, *campaign_command(
            campaign_file, out, "--scheduler", f"tcp://{SCHEDULER_ADDRESS}:{PORT}", "--connect-timeout", "30")],
            capture_output=True, text=True, timeout=600, env=dask_env())
    finally:
        cluster.stop()
    assert done.returncode == 0, done.stdout + done.stderr + cluster.log_text()
    assert "16 cases on 2 worker(s)" in done.stdout
    rows = read_rows(out)
    # Both workers ran cases, over TCP to their namespaces' addresses.
    assert workers_of(rows) == {f"tcp://{address}" for address in WORKER_ADDRESSES}, rows
    assert all(row["attempts"] == "1" for row in rows)
    assert without(rows, WHERE_AND_HOW_LONG) == without(local_rows, WHERE_AND_HOW_LONG)


def hadald_children(pid):
    """The pids of hadald processes whose parent is pid."""
    out = subprocess.run(["ps", "-o", "pid=,ppid=,comm=", "-e"], capture_output=True, text=True, check=True).stdout
    return [int(p) for p, parent, command in (line.split(None, 2) for line in out.splitlines())
            if int(parent) == pid and command.strip() == "hadald"]


def test_a_worker_killed_mid_campaign_loses_no_case_and_counts_none_twice(cluster_namespaces, campaign_file,
                                                                          tmp_path, local_rows):
    scheduler_ns, worker_ns = cluster_namespaces
    cluster = DaskCluster(scheduler_ns, worker_ns, tmp_path)
    out = tmp_path / "cluster.csv"
    killed_server = None
    try:
        campaign = subprocess.Popen(["ip", "netns", "exec", scheduler_ns, *campaign_command(
            campaign_file, out, "--scheduler", f"tcp://{SCHEDULER_ADDRESS}:{PORT}", "--connect-timeout", "30")],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=dask_env())
        # Kill worker 1 (ip netns exec has exec'ed dask-worker: the same pid) while a case of it is running
        # its hadald, once the campaign is under way (a case has completed: the progress bar has moved).
        lines = []
        reader = threading.Thread(target=lambda: lines.extend(campaign.stderr), daemon=True)
        reader.start()
        victim = cluster.workers[0]
        deadline = time.monotonic() + 300
        while time.monotonic() < deadline and campaign.poll() is None:
            if any(" cases: " in line and not line.startswith("[" + "." * 30) for line in list(lines)):
                children = hadald_children(victim.pid)
                if children:
                    killed_server = children[0]
                    os.kill(victim.pid, signal.SIGKILL)
                    break
            time.sleep(0.02)
        assert killed_server is not None, "never caught worker 1 running a case"
        stdout = campaign.stdout.read()
        campaign.wait(timeout=600)
        reader.join(timeout=30)
        stderr = "".join(lines)
    finally:
        cluster.stop()
    assert campaign.returncode == 0, stdout + stderr + cluster.log_text()
    rows = read_rows(out)
    assert [int(row["case"]) for row in rows] == list(range(16))  # every case, once
    assert all(row["status"] == "ok" for row in rows)
    retried = [row for row in rows if row["attempts"] == "2"]
    assert len(retried) == 1 and all(row["attempts"] in ("1", "2") for row in rows), rows
    assert retried[0]["worker"] == f"tcp://{WORKER_ADDRESSES[1]}:" + retried[0]["worker"].rsplit(":", 1)[1]
    assert "1 retried" in stdout
    # The same metrics as on the LocalCluster, the retried case's too.
    assert without(rows, WHERE_AND_HOW_LONG) == without(local_rows, WHERE_AND_HOW_LONG)
    # The killed worker's hadald died with it (setpriv --pdeathsig), not left stepping nothing.
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and os.path.exists(f"/proc/{killed_server}"):
        time.sleep(0.1)
    assert not os.path.exists(f"/proc/{killed_server}"), "the killed worker's hadald is still running"
