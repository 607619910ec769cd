"""hadal.bag.Bag over a bag that hadald --record wrote in fast mode: its topics, its messages decoded into the
client's values (the same numbers a live client reads), and clear errors for what it cannot read."""

import os
import subprocess

import pytest

import hadal
from hadal.bag import Bag
from hadal.server import find_hadald, reserve_domain, scenario_path

WAIT_S = 30.0


@pytest.fixture(scope="module")
def rov_bag(tmp_path_factory):
    """2 s of the ROV scenario in fast mode, recorded by hadald itself (bag time = sim time)."""
    bag = tmp_path_factory.mktemp("bag") / "rov"
    domain, lock = reserve_domain(range(200, 230))
    try:
        done = subprocess.run([find_hadald(), scenario_path("rov"), "--mode", "fast", "--duration", "2",
                               "--domain-id", str(domain), "--record", str(bag), "--no-status-line",
                               "--discovery-wait", "0", "--seed", "4"], capture_output=True, text=True, timeout=120)
    finally:
        lock.close()
    assert done.returncode == 0, done.stderr
    return bag


def test_a_recorded_bag_reads_as_the_clients_values(rov_bag):
    with Bag(rov_bag) as bag:
        assert bag.topics["/rov/odometry"] == "nav_msgs/msg/Odometry"
        assert bag.topics["/clock"] == "rosgraph_msgs/msg/Clock"
        odometry = bag.messages("/rov/odometry")
        assert all(isinstance(m, hadal.Odometry) for _, m in odometry)
        # Bag time is sim time, and each sample's stamp is its bag time.
        assert all(abs(t - m.stamp) < 1e-9 for t, m in odometry)
        assert odometry[-1][0] == pytest.approx(2.0, abs=1e-9)
        assert odometry[0][1].child_frame_id and odometry[0][1].frame_id == "world"
        clock = bag.messages("/clock")
        assert isinstance(clock[-1][1], float) and clock[-1][1] == pytest.approx(2.0, abs=1e-9)
        pressure_topics = [name for name, type_name in bag.topics.items() if type_name == "sensor_msgs/msg/FluidPressure"]
        assert pressure_topics
        t, pressure = bag.messages(pressure_topics[0])[-1]
        assert isinstance(pressure, hadal.FluidPressure) and pressure.pressure > 5e5  # ~90 m down: ~1 MPa


def test_the_bag_holds_what_a_live_client_reads_in_the_same_run(rov_bag):
    """The same scenario, seed and steps on a lockstep server: the odometry at t = 2 s a client reads is the
    bag's last sample, to the bit (the recording decodes to the same numbers)."""
    with hadal.Server("rov", mode="lockstep", domain_id="free", seed=4) as server, server.client() as client:
        client.wait_odometry("rov", timeout_s=0)
        assert client.wait_for_subscriptions(WAIT_S)
        t = client.step(round(2.0 / client.status().step_size))
        live = client.wait_odometry("rov", min_stamp=t - 1e-9, timeout_s=WAIT_S)
    with Bag(rov_bag) as bag:
        recorded = bag.messages("/rov/odometry")[-1][1]
    assert recorded.stamp == live.stamp
    assert list(recorded.p_WB) == list(live.p_WB) and list(recorded.q_WB) == list(live.q_WB)
    assert list(recorded.v_WB_B) == list(live.v_WB_B)


def test_what_the_bag_cannot_read_is_a_clear_error(rov_bag, tmp_path):
    with Bag(rov_bag) as bag:
        with pytest.raises(KeyError, match="no topic '/nope'"):
            bag.messages("/nope")
        data = bag.raw("/rov/odometry")[0][1]
    with pytest.raises(ValueError, match="do not decode as nav_msgs/msg/Odometry"):
        hadal.decode_message("nav_msgs/msg/Odometry", data[:20])
    with pytest.raises(ValueError, match="no decoder for message type 'std_msgs/msg/Nope'"):
        hadal.decode_message("std_msgs/msg/Nope", data)
    assert "nav_msgs/msg/Odometry" in hadal.decodable_message_types()
    with pytest.raises(FileNotFoundError, match="not a rosbag2 bag"):
        Bag(tmp_path)
