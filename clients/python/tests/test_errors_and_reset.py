"""The client's typed errors, its lifecycle (nothing left behind, even by a failing block) and the lockstep
reset, against real hadald processes."""

import math
import os
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import hadal

WAIT_S = 20.0


def domain_ports(domain_id):
    """The UDP/shared-memory port numbers RTPS gives a domain: 7400 + 250 d + [0, 250) (RTPS 9.6.1.1,
    PB 7400, DG 250); Fast DDS names its shared-memory port segments after them."""
    first = 7400 + 250 * domain_id
    return range(first, first + 250)


def shm_files():
    """/dev/shm's entries: name -> inode, so that a file made since is told apart. Not the modification time:
    a participant writes its discovery into the port files of the others on its domain, those a killed process
    left too (a concurrent test's kill -9, on this domain before this block reserved it), which is no file
    this block left behind."""
    files = {}
    for entry in os.scandir("/dev/shm"):
        try:
            files[entry.name] = entry.stat().st_ino
        except FileNotFoundError:
            continue
    return files


def segments_of(domain_id):
    """/dev/shm entries of a domain's shared-memory ports (fastrtps_port<P>, its _el lock and semaphore)."""
    ports = {str(p) for p in domain_ports(domain_id)}
    left = []
    for name in os.listdir("/dev/shm"):
        for prefix in ("fastrtps_port", "sem.fastrtps_port"):
            if name.startswith(prefix) and name[len(prefix):].split("_")[0] in ports:
                left.append(name)
    return sorted(left)


def test_typed_errors_carry_the_servers_reason():
    with hadal.Server("default", mode="lockstep") as server, server.client("pytest") as client:
        client.set_commands("auv", [0.5, 0.0])  # the AUV has 3 thrusters
        with pytest.raises(hadal.CommandRejected) as rejected:
            client.step(1)
        assert rejected.value.reason == "auv: expected 3 setpoints (main, heave, sway), got 2"
        client.set_commands("auv", [math.nan, 0.0, 0.0])
        with pytest.raises(hadal.CommandRejected, match=r"setpoint\[0\] is NaN"):
            client.step(1)
        client.set_commands("ghost", [0.1])
        with pytest.raises(hadal.UnknownVehicle) as unknown:
            client.step(1)
        assert unknown.value.vehicle == "ghost"
        with pytest.raises(hadal.UnknownVehicle, match="reset: unknown vehicle 'ghost'") as unknown:
            client.reset(poses={"ghost": (0.0, 0.0, -50.0)})
        assert unknown.value.vehicle == "ghost"  # the reply's unknown_vehicle, not parsed from the text
        # Refused requests stepped nothing, and the server runs on.
        assert client.step(10) == pytest.approx(0.02)
        assert isinstance(rejected.value, hadal.ClientError)
    with hadal.Client(domain_id=server.domain_id, name="pytest") as client:  # the server is gone
        with pytest.raises(hadal.ServerNotFound):
            client.step(1, timeout_s=0.5)


def test_a_request_without_reply_is_a_timeout():
    with hadal.Server("default", mode="lockstep") as server, server.client("pytest") as client:
        # A request to a stopped (SIGSTOP) server: its reader is matched, but nothing answers. One answered step
        # first: the client's request writer is matched then (the status heartbeat may come before that match,
        # and a server stopped before it could never complete it: ServerNotFound, not the Timeout tested here).
        assert client.step(1) == pytest.approx(0.002)
        os.kill(server.process.pid, 19)
        try:
            with pytest.raises(hadal.Timeout) as timeout:
                client.step(1, timeout_s=0.5)
            assert isinstance(timeout.value, TimeoutError)
            # close() while another thread waits in a call: that call ends as it would have (a Timeout),
            # the client is gone only after it.
            errors = []
            waiting = threading.Thread(target=lambda: errors.append(pytest.raises(hadal.Timeout, client.step, 1, 1.0)))
            waiting.start()
            time.sleep(0.3)
            client.close()
            waiting.join(10)
            assert not waiting.is_alive() and len(errors) == 1 and client.closed
        finally:
            os.kill(server.process.pid, 18)


LIFECYCLE = textwrap.dedent("""
    import sys, hadal
    with hadal.Server("default", mode="lockstep") as server:
        print(server.domain_id, server.process.pid, flush=True)
        with server.client("pytest") as client:
            client.step(5)
            if sys.argv[1] == "fail":
                assert False, "a failing test"
""")


@pytest.mark.parametrize("outcome", ["pass", "fail"])
def test_nothing_is_left_behind(outcome):
    """No hadald process and no shared-memory segment of the domain survive a block, even one that fails.
    Port files other processes left before (a server killed by faults_test.py or record_test.py on the same
    domain) are not this block's, even once it has written into them."""
    before = shm_files()
    run = subprocess.run([sys.executable, "-c", LIFECYCLE, outcome], capture_output=True, text=True, timeout=120)
    assert run.returncode == (0 if outcome == "pass" else 1), run.stderr
    if outcome == "fail":
        assert "AssertionError: a failing test" in run.stderr
    domain_id, pid = (int(x) for x in run.stdout.split())
    assert not os.path.exists(f"/proc/{pid}")
    after = shm_files()
    assert [name for name in segments_of(domain_id) if after.get(name) != before.get(name)] == []


def test_a_closed_client_says_so():
    client = hadal.Client(domain_id=231, name="pytest")
    client.close()
    assert client.closed
    with pytest.raises(hadal.ClientError, match="closed"):
        client.step(1)
    client.close()  # idempotent


def episode(client, seed, steps=40):
    """Reset with `seed`, then thrust: the IMU and depth samples of each step, and the poses."""
    client.reset(seed=seed)
    trace = []
    for _ in range(steps):
        client.set_commands("auv", [0.6, 0.1, -0.1])
        t = client.step(10)  # 20 ms: one odometry sample (50 Hz), the second of two IMU samples (100 Hz)
        imu = client.wait_imu("auv", "imu", min_stamp=t, timeout_s=WAIT_S)
        odom = client.wait_odometry("auv", min_stamp=t, timeout_s=WAIT_S)
        assert imu is not None and odom is not None
        trace.append(np.concatenate([[imu.stamp], imu.linear_acceleration, imu.angular_velocity, odom.p_WB]))
    return np.array(trace)


def test_reset_repeats_an_episode_without_a_restart():
    with hadal.Server("default", mode="lockstep") as server, server.client("pytest") as client:
        client.wait_imu("auv", "imu", timeout_s=0)
        client.wait_for_subscriptions(WAIT_S)
        first = episode(client, seed=11)
        again = episode(client, seed=11)
        other = episode(client, seed=12)
        pid = server.process.pid
        assert server.running and server.process.pid == pid
    assert first[0, 0] == pytest.approx(0.02)  # time starts over at 0
    np.testing.assert_array_equal(first, again)  # bit for bit, noise included
    assert np.array_equal(first[:, 7:], other[:, 7:])  # the physics has no randomness
    assert not np.array_equal(first[:, 1:7], other[:, 1:7])  # the IMU's noise does
    assert first[-1, 7] - first[0, 7] > 0.05  # and it moved


def test_reset_places_a_vehicle_at_rest():
    with hadal.Server("default", mode="lockstep") as server, server.client("pytest") as client:
        client.set_commands("auv", [0.8, 0.0, 0.0])
        client.step(200)
        half = math.sqrt(0.5)
        assert client.reset(seed=1, poses={"auv": (10.0, -5.0, -80.0, 0.0, 0.0, half, half)}) == 0.0
        odom = client.wait_odometry("auv", min_stamp=0.0, timeout_s=WAIT_S)
        assert odom.stamp == 0.0
        np.testing.assert_allclose(odom.p_WB, [10.0, -5.0, -80.0], atol=1e-12)
        np.testing.assert_allclose(odom.q_WB, [0.0, 0.0, half, half], atol=1e-12)
        np.testing.assert_allclose(odom.v_WB_B, 0.0, atol=1e-12)
        status = client.status()
        with pytest.raises(hadal.CommandRejected, match="quaternion norm"):
            client.reset(poses={"auv": (0.0, 0.0, -80.0, 0.0, 0.0, 0.0, 2.0)})
        with pytest.raises(hadal.CommandRejected, match="reset: vehicle 'auv': pose is not finite"):
            client.reset(poses={"auv": (math.nan, 0.0, -80.0)})
        with pytest.raises(ValueError):
            client.reset(poses={"auv": (0.0, 0.0)})
        assert status is not None and server.running


def test_replies_carry_every_vehicles_odometry():
    with hadal.Server("default", mode="lockstep") as server, server.client("pytest") as client:
        with pytest.raises(hadal.ClientError, match="no step reply"):
            client.reply_odometry("auv")
        client.wait_odometry("auv", timeout_s=0)
        client.wait_odometry("lander", timeout_s=0)
        client.wait_for_subscriptions(WAIT_S)
        client.set_commands("auv", [0.7, 0.2, -0.1])
        for _ in range(3):
            t = client.step(50)  # 0.1 s: both odometry streams (the AUV's 50 Hz, the lander's 10 Hz) have a sample at t
            for vehicle in ("auv", "lander"):
                published = client.wait_odometry(vehicle, min_stamp=t, timeout_s=WAIT_S)
                carried = client.reply_odometry(vehicle)
                assert carried.stamp == published.stamp == pytest.approx(t, abs=1e-9)
                assert carried.child_frame_id == published.child_frame_id == f"{vehicle}/base_link"
                for field in ("p_WB", "q_WB", "v_WB_B", "w_WB_B"):  # the same numbers, bit for bit
                    np.testing.assert_array_equal(getattr(carried, field), getattr(published, field))
        assert np.linalg.norm(client.reply_odometry("auv").v_WB_B) > 0.01  # it moves
        with pytest.raises(hadal.UnknownVehicle) as unknown:
            client.reply_odometry("ghost")
        assert unknown.value.vehicle == "ghost"
        assert client.reset(seed=1) == 0.0
        np.testing.assert_allclose(client.reply_odometry("auv").v_WB_B, 0.0, atol=1e-12)


def test_a_sensor_the_vehicle_does_not_have_raises_at_once():
    """A misspelt sensor, or a sensor read as another type (wait_imu on the DVL), raises UnknownSensor at once
    naming the vehicle's sensors and their types (from the server's scene), instead of returning None after
    the timeout (600 s: without the check the test would wait that long and then fail)."""
    sensors = r"\(its sensors: 'depth' \(pressure\), 'imu' \(imu\), 'magnetometer' \(magnetometer\), 'dvl' \(dvl\)\)"
    with hadal.Server("rov", mode="lockstep") as server, server.client("pytest") as client:
        assert client.wait_imu("rov", "imu", min_stamp=client.step(10), timeout_s=WAIT_S) is not None
        for call, name, message in (
                (lambda: client.wait_imu("rov", "imuu", timeout_s=600), "imuu", "no sensor 'imuu' on vehicle 'rov' "),
                (lambda: client.wait_dvl("rov", "dvll", timeout_s=600), "dvll", "no sensor 'dvll' on vehicle 'rov' "),
                (lambda: client.wait_image("rov", "camera", timeout_s=600), "camera",
                 "no sensor 'camera' on vehicle 'rov' "),
                (lambda: client.wait_imu("rov", "dvl", timeout_s=600), "dvl",
                 "sensor 'dvl' of vehicle 'rov' is of type dvl, not imu "),
                (lambda: client.wait_fluid_pressure("rov", "imu", timeout_s=600), "imu",
                 "sensor 'imu' of vehicle 'rov' is of type imu, not pressure ")):
            with pytest.raises(hadal.UnknownSensor, match=message + sensors) as unknown:
                call()
            assert (unknown.value.vehicle, unknown.value.sensor) == ("rov", name)
            assert isinstance(unknown.value, KeyError) and isinstance(unknown.value, hadal.ClientError)
        assert client.wait_dvl("rov", "dvl", min_stamp=client.step(10), timeout_s=WAIT_S) is not None  # still works


def test_a_vehicle_the_server_does_not_have_raises_at_once():
    """subscribe, wait_odometry, a sensor's or an actuator's wait on a misspelt vehicle raise UnknownVehicle
    naming the vehicles there are, instead of returning None after the timeout (600 s here: without the
    check the test would wait that long and then fail)."""
    with hadal.Server("rov", mode="lockstep") as server, server.client("pytest") as client:
        for call in (lambda: client.subscribe("rvo"),
                     lambda: client.wait_odometry("rvo", timeout_s=600),
                     lambda: client.wait_thruster_state("rvo", timeout_s=600),
                     lambda: client.wait_imu("rvo", "imu", timeout_s=600),
                     lambda: client.wait_fin_state("rvo", timeout_s=600)):
            with pytest.raises(hadal.UnknownVehicle, match=r"no vehicle 'rvo' on this server \(vehicles: 'rov'\)") \
                    as unknown:
                call()
            assert unknown.value.vehicle == "rvo"
        assert client.wait_odometry("rov", min_stamp=client.step(10), timeout_s=WAIT_S) is not None  # still works


def test_the_client_takes_its_domain_from_ros_domain_id(monkeypatch):
    """As hadald and every Hadal tool: domain_id, else $ROS_DOMAIN_ID, else 0; out of 0..232 a ValueError."""
    with hadal.Server("rov", mode="lockstep", domain_id="free") as server:
        monkeypatch.setenv("ROS_DOMAIN_ID", str(server.domain_id))  # 100..199: not the default 0
        with hadal.Client(name="pytest") as client:
            assert client.wait_for_server(WAIT_S)
        monkeypatch.setenv("ROS_DOMAIN_ID", "233")
        with pytest.raises(ValueError, match=r"ROS_DOMAIN_ID must be an integer in 0..232 \(got '233'\)"):
            hadal.Client()
        with pytest.raises(ValueError, match=r"domain_id must be in 0..232 \(got -1\)"):
            hadal.Client(domain_id=-1)
        with hadal.Client(domain_id=server.domain_id, name="pytest") as client:  # given: the variable is not read
            assert client.wait_for_server(WAIT_S)


def test_requests_sent_without_waiting_are_answered_in_any_order():
    with hadal.Server("default", mode="lockstep", domain_id="free") as first_server, \
            hadal.Server("default", mode="lockstep", domain_id="free") as second_server:
        with first_server.client("pytest") as first, second_server.client("pytest") as second:
            # Two servers stepping at once, waited for in the other order; then one server, two requests.
            a, b = first.send_step(10), second.send_step(20)
            assert second.wait_reply(b) == pytest.approx(0.04)
            assert first.wait_reply(a) == pytest.approx(0.02)
            r1 = first.send_step(5)
            r2 = first.send_reset(seed=3, steps=5)
            assert first.wait_reply(r2) == pytest.approx(0.01)  # the reset came second
            assert first.wait_reply(r1) == pytest.approx(0.03)
            with pytest.raises(hadal.ClientError, match="is waiting"):
                first.wait_reply(r1)  # each reply is waited for once
            first.set_commands("auv", [0.5, 0.0], publish=False)
            refused = first.send_step(1)
            with pytest.raises(hadal.CommandRejected, match="expected 3 setpoints"):
                first.wait_reply(refused)
            assert first.step(1) == pytest.approx(0.012)
