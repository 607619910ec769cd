"""Faults a deployment meets, against real hadald processes over real DDS (issue 15):

- a client killed with SIGKILL never disturbs the server: it keeps stepping and other clients keep
  receiving;
- a server killed with SIGKILL is seen by its clients (the status heartbeat stops: server_alive() turns
  False and a pending step raises hadal.ServerLost within the heartbeat timeout), and a server restarted on
  the same domain is used by the same clients, which are never restarted;
- a subscriber that stops reading (SIGSTOP, with reliable readers on every topic, the camera's included) does
  not stop the physics loop, nor what the other clients receive;
- the shared-memory segments a killed server leaves in /dev/shm never break the next start, which removes
  them.

Packet loss on a link is in hil_netns_test.py. Nothing here measures speed (a test must not depend on the
machine's): "keeps stepping" is the server's sim time and a client's odometry advancing by a given amount of
sim time, within a timeout that only a stopped server misses. What the real-time loop costs is in
docs/benchmarks.md.
"""

import os
import signal
import subprocess
import sys
import time

import pytest

import hadal

WAIT_S = 30.0

# A client as its own process: subscribes to the AUV's odometry, IMU, depth and camera (the large samples
# that go through shared memory), commands the thrusters at 10 Hz, and says "ready" once a camera frame
# arrived. With "stall" it then stops itself (SIGSTOP) with its readers matched and their queues filling.
CLIENT = r"""
import os, signal, sys, time
import hadal
client = hadal.Client(domain_id=int(sys.argv[1]), name="fault_client")
assert client.wait_for_server(30.0)
client.subscribe("auv")
client.wait_imu("auv", "imu", timeout_s=0)
client.wait_fluid_pressure("auv", "depth", timeout_s=0)
client.wait_image("auv", "camera", timeout_s=0)
client.wait_depth_image("auv", "camera", timeout_s=0)
assert client.wait_for_subscriptions(30.0)
assert client.wait_image("auv", "camera", timeout_s=30.0) is not None
print("ready", flush=True)
if sys.argv[2] == "stall":
    os.kill(os.getpid(), signal.SIGSTOP)
while True:
    client.set_commands("auv", [0.5, 0.0, 0.0])
    time.sleep(0.1)
"""


def start_client(domain_id, behaviour):
    process = subprocess.Popen([sys.executable, "-c", CLIENT, str(domain_id), behaviour], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    line = process.stdout.readline()
    if line.strip() != "ready":
        process.kill()
        raise AssertionError("client did not get ready: " + line + process.stderr.read())
    return process


def wait_stopped(process):
    """Until the process is stopped (SIGSTOP): its state in /proc is T."""
    deadline = time.monotonic() + WAIT_S
    while time.monotonic() < deadline:
        with open(f"/proc/{process.pid}/stat") as stat:
            if stat.read().rsplit(")", 1)[1].split()[0] == "T":
                return
        time.sleep(0.01)
    raise AssertionError("the client did not stop itself")


def assert_keeps_stepping(client, sim_s):
    """The server advances by sim_s seconds of sim time (its status) and this client receives odometry that far
    on, within WAIT_S: a server blocked by a reader, or a client no longer served, fails it."""
    first = client.status()
    first_odometry = client.wait_odometry("auv", timeout_s=WAIT_S)
    assert first_odometry is not None
    odometry = client.wait_odometry("auv", min_stamp=first_odometry.stamp + sim_s, timeout_s=WAIT_S)
    assert odometry is not None, f"no odometry {sim_s} s of sim time after {first_odometry.stamp}"
    # The status is a 10 Hz wall-clock heartbeat: it may trail the odometry by a period or so.
    deadline = time.monotonic() + WAIT_S
    while client.status().sim_time < first.sim_time + sim_s:
        assert time.monotonic() < deadline, f"the status stayed below {first.sim_time + sim_s} s of sim time"
        time.sleep(0.05)


def test_a_killed_client_never_disturbs_the_server_or_other_clients():
    with hadal.Server("default", mode="realtime") as server, server.client("observer", timeout_s=WAIT_S) as observer:
        observer.subscribe("auv")
        assert observer.wait_for_subscriptions(WAIT_S)
        victims = [start_client(server.domain_id, "run") for _ in range(2)]
        try:
            victims[0].kill()  # SIGKILL: no goodbye, its readers and shared-memory ports just vanish
            victims[0].wait()
            assert_keeps_stepping(observer, 3.0)
            assert server.running
            # The other client is still served: its process is alive and a new client gets everything too.
            assert victims[1].poll() is None
            with server.client("late", timeout_s=WAIT_S) as late:
                assert late.wait_image("auv", "camera", timeout_s=WAIT_S) is not None
        finally:
            for victim in victims:
                victim.kill()
                victim.wait()
        assert server.stop() == 0, server.log_tail()


def test_a_stalled_subscriber_does_not_slow_the_physics_loop():
    with hadal.Server("default", mode="realtime") as server, server.client("observer", timeout_s=WAIT_S) as observer:
        observer.subscribe("auv")
        assert observer.wait_for_subscriptions(WAIT_S)
        stalled = start_client(server.domain_id, "stall")
        try:
            wait_stopped(stalled)
            # Its reliable readers acknowledge nothing now, for the camera's 10 Hz frames too; the writers'
            # histories are KEEP_LAST, so the server drops the oldest for it instead of waiting.
            assert_keeps_stepping(observer, 3.0)
            stalled.send_signal(signal.SIGCONT)
            assert_keeps_stepping(observer, 1.0)
        finally:
            stalled.kill()
            stalled.wait()
        assert server.stop() == 0, server.log_tail()


def test_a_killed_server_is_seen_lost_and_its_restart_serves_the_same_client():
    server = hadal.Server("default", mode="lockstep", cameras=False)
    domain = server.domain_id
    with pytest.raises(ValueError, match="server_timeout_s must be a positive number"):
        hadal.Client(domain_id=domain, server_timeout_s=0.0)
    client = hadal.Client(domain_id=domain, name="survivor", server_timeout_s=1.0)
    try:
        assert client.wait_for_server(WAIT_S)
        assert client.step(10) == pytest.approx(0.02, abs=1e-12)
        # A long request in progress when the server dies: its reply never comes. The heartbeat (10 Hz, also
        # during a request) stops, and the wait ends with ServerLost (after ~1 s), not with the timeout of
        # its 120 s (hadal.Timeout "no step reply from the server within 120 s").
        request = client.send_step(500 * 3600, timeout_s=120.0)
        time.sleep(0.5)
        server.process.kill()
        server.process.wait()
        with pytest.raises(hadal.ServerLost, match="went silent"):
            client.wait_reply(request, timeout_s=120.0)
        assert not client.server_alive()
        assert client.seconds_since_status() > 1.0
        server.stop()  # releases the domain
        # The same domain, a new server; the same client, never restarted.
        server = hadal.Server("default", mode="lockstep", cameras=False, domain_id=domain)
        assert client.wait_for_server(WAIT_S)
        assert client.server_alive()
        assert client.step(10) == pytest.approx(0.02, abs=1e-12)  # the new run, from t = 0
        client.set_commands("auv", [1.0, 0.0, 0.0])
        t = client.step(50)
        assert client.wait_thruster_state("auv", min_stamp=t - 0.1, timeout_s=WAIT_S).setpoint[0] == 1.0
    finally:
        client.close()
        server.stop()


def shm_segments():
    """The Fast DDS shared-memory segments in /dev/shm (fastrtps_<16 hex digits>)."""
    return {name for name in os.listdir("/dev/shm")
            if name.startswith("fastrtps_") and len(name) == len("fastrtps_") + 16 and "port" not in name}


def test_the_shared_memory_of_a_killed_server_never_breaks_the_next_start():
    before = shm_segments()
    server = hadal.Server("default", mode="lockstep")  # its camera: frames published 0.2 s after their stamp
    domain = server.domain_id
    try:
        with server.client("first", timeout_s=WAIT_S) as client:
            client.wait_image("auv", "camera", timeout_s=0)
            assert client.wait_for_subscriptions(WAIT_S)
            assert client.wait_image("auv", "camera", min_stamp=client.step(250) - 0.3, timeout_s=WAIT_S) is not None
        own = shm_segments() - before
        assert own, "hadald made no shared-memory segment"
        server.process.kill()
        server.process.wait()
        server.stop()
        left = own & shm_segments()
        assert left, "the killed server left no segment behind (nothing to test)"
        # The lock files are older than the cleaner's 10 s grace period only later: age them, as time would.
        for name in left:
            os.utime(f"/dev/shm/{name}_el", (time.time() - 60, time.time() - 60))
        server = hadal.Server("default", mode="lockstep", domain_id=domain)
        with server.client("second", timeout_s=WAIT_S) as client:
            client.wait_image("auv", "camera", timeout_s=0)
            assert client.wait_for_subscriptions(WAIT_S)
            frame = client.wait_image("auv", "camera", min_stamp=client.step(250) - 0.3, timeout_s=WAIT_S)
            assert frame is not None and frame.array.shape == (480, 640, 3)
        assert not left & shm_segments(), "the restart did not remove the dead server's segments"
        assert "stale shared-memory segment(s)" in open(server.log_path).read()
    finally:
        server.stop()
