"""The examples under examples/python, run in a short form against real hadald processes."""

import importlib.util
import math
import os

import numpy as np

import hadal
from conftest import SOURCE_DIR

WAIT_S = 20.0


def load_example(name):
    path = os.path.join(SOURCE_DIR, "examples", "python", name + ".py")
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_rov_station_keeping_holds_against_the_current(rov_server):
    """The ROV drifts with the 0.3 m/s current when left alone; the example's station keeper brings it to
    a stop and holds it within 5 cm, its horizontal thrusters pushing against the water's drag."""
    example = load_example("rov_station_keeping")
    _, domain_id = rov_server
    client = hadal.Client(domain_id=domain_id, name="pytest")
    client.subscribe("rov")
    assert client.wait_for_server(WAIT_S)
    assert client.wait_for_subscriptions(WAIT_S)
    # 10 s adrift (100 Hz): carried downstream (+x), towards the current's speed.
    start = client.wait_odometry("rov", min_stamp=0.0, timeout_s=WAIT_S)
    t = client.step(1000)
    adrift = client.wait_odometry("rov", min_stamp=t - 1e-9, timeout_s=WAIT_S)
    assert adrift.p_WB[0] - start.p_WB[0] > 0.5
    # 60 s held where it is now (the keeper takes its station from the first odometry).
    track = example.hold_station(client, "rov", until_s=t + 60.0, report=None)
    first = track[0][0]
    # It had ~0.16 m/s of drift to brake: off by at most a few decimetres, then within 5 cm after 20 s.
    assert max(d for _, d in track) < 0.5
    assert max(d for s, d in track if s > first + 20.0) < 0.05
    thrusters = client.wait_thruster_state("rov", min_stamp=track[-1][0] - 1e-9, timeout_s=WAIT_S)
    # The horizontal four push upstream against ~18 N of drag (0.5 rho C_D A U^2 on the 0.8 m x 0.5 m
    # face at 0.3 m/s, C_D ~ 1): their thrusts' x-components sum to -(10 .. 40) N.
    upstream = sum(thrust * math.sqrt(0.5) for thrust in thrusters.thrust[:4])
    assert -40.0 < upstream < -10.0
    assert thrusters.command_source == 2
    np.testing.assert_array_less(np.abs(thrusters.setpoint), 1.0)


def test_auv_depth_change_on_its_fins(zoo_server):
    """The example autopilot takes the finned AUV from 20 m to 30 m on its elevators: nose down on the
    way, there within 0.3 m after 60 s, no deeper than 31 m."""
    example = load_example("auv_depth_change")
    client = hadal.Client(domain_id=zoo_server("auv"), name="pytest")
    client.subscribe("auv")
    assert client.wait_for_server(WAIT_S)
    assert client.wait_for_subscriptions(WAIT_S)
    track = example.fly(client, depth_m=30.0, until_s=70.0, report=None)
    assert min(pitch for _, _, pitch in track) < math.radians(-10.0)
    assert min(z for _, z, _ in track) > -31.0
    assert all(abs(z + 30.0) < 0.3 for t, z, _ in track if t > 60.0)
