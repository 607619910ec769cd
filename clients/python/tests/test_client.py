"""The Python client against a real hadald over real DDS."""

import math
import signal

import numpy as np
import pytest

import hadal

WAIT_S = 20.0  # generous bound on DDS events; not a speed assertion


def connect(domain_id, vehicle="auv"):
    client = hadal.Client(domain_id=domain_id, name="pytest")
    client.subscribe(vehicle)
    assert client.wait_for_server(WAIT_S), "no status from hadald"
    assert client.wait_for_subscriptions(WAIT_S)
    return client


def test_drive_forward_in_lockstep(lockstep_server):
    _, domain_id = lockstep_server
    client = connect(domain_id)
    status = client.status()
    assert status.mode == hadal.ServerMode.LOCKSTEP
    assert status.vehicle_names == ["auv"]

    t = client.step(10)
    start = client.wait_odometry("auv", min_stamp=t, timeout_s=WAIT_S)
    assert start is not None
    for _ in range(6):  # 3 s, commands refreshed every 0.5 s (watchdog 1 s)
        client.set_commands("auv", [0.8, 0.0, 0.0])
        t = client.step(250)
    end = client.wait_odometry("auv", min_stamp=t, timeout_s=WAIT_S)
    assert end is not None and abs(end.stamp - t) < 1e-9

    assert isinstance(end.p_WB, np.ndarray) and end.p_WB.shape == (3,)
    assert abs(np.linalg.norm(end.q_WB) - 1.0) < 1e-9
    # The scenario yaws the AUV 30 deg: it moves along its body x axis, (cos 30, sin 30) in W, not along W's x
    # (which would make 30 deg with it) nor backwards. The main thruster pushes along x_B through the centre
    # line: what leaks sideways is the hull's trim, below 1 % of the way here (2 % allowed).
    body_x = np.array([math.cos(math.pi / 6), math.sin(math.pi / 6), 0.0])
    body_y = np.array([-math.sin(math.pi / 6), math.cos(math.pi / 6), 0.0])
    travelled = end.p_WB - start.p_WB
    assert travelled @ body_x > 1.5, travelled
    assert abs(travelled @ body_y) < 0.02 * (travelled @ body_x), travelled
    assert math.degrees(math.atan2(travelled[1], travelled[0])) == pytest.approx(30.0, abs=1.2), travelled
    assert end.v_WB_B[0] > 1.0 and abs(end.v_WB_B[1]) < 0.02 * end.v_WB_B[0], end.v_WB_B
    assert end.frame_id == "world" and end.child_frame_id == "auv/base_link"

    thrusters = client.wait_thruster_state("auv", min_stamp=t, timeout_s=WAIT_S)
    assert thrusters.names == ["main", "heave", "sway"]
    np.testing.assert_array_equal(thrusters.setpoint, [0.8, 0.0, 0.0])
    assert thrusters.command_source == 2
    assert thrusters.thrust[0] > 0.0


def test_bad_commands_raise_and_the_server_keeps_running(lockstep_server):
    process, domain_id = lockstep_server
    client = connect(domain_id)
    client.set_commands("auv", [float("nan"), 0.0, 0.0])
    with pytest.raises(hadal.ClientError, match=r"setpoint\[0\] is NaN"):
        client.step(10)
    client.set_commands("auv", [0.1, 0.2])
    with pytest.raises(hadal.ClientError, match="expected 3 setpoints"):
        client.step(10)
    client.set_commands("auv", [0.1, 0.0, 0.0])
    assert client.step(10) == pytest.approx(0.02, abs=1e-12)
    assert process.poll() is None


def test_the_old_command_name_is_refused_naming_the_new_one(lockstep_server):
    _, domain_id = lockstep_server
    client = connect(domain_id)
    with pytest.raises(AttributeError, match="set_thrusters was renamed set_commands"):
        client.set_thrusters("auv", [0.5, 0.0, 0.0])
    # Nothing was sent: the thrusters stay at rest.
    t = client.step(50)
    assert client.wait_thruster_state("auv", min_stamp=t, timeout_s=WAIT_S).setpoint.tolist() == [0.0, 0.0, 0.0]


def test_server_stops_cleanly_on_sigterm(lockstep_server):
    process, domain_id = lockstep_server
    connect(domain_id)
    process.send_signal(signal.SIGTERM)
    assert process.wait(timeout=WAIT_S) == 0


def test_sensor_samples_arrive_as_numpy(lockstep_server):
    _, domain_id = lockstep_server
    client = connect(domain_id)
    # Subscribe before stepping so the samples of this request are not missed.
    assert client.wait_imu("auv", "imu", timeout_s=0.1) is None
    assert client.wait_fluid_pressure("auv", "depth", timeout_s=0.1) is None
    assert client.wait_for_subscriptions(WAIT_S)
    t = client.step(500)  # 1 s: IMU at 100 Hz, depth at 10 Hz
    imu = client.wait_imu("auv", "imu", min_stamp=t, timeout_s=WAIT_S)
    assert imu is not None and abs(imu.stamp - t) < 1e-9
    assert imu.frame_id == "auv/imu"
    assert imu.linear_acceleration.shape == (3,)
    assert abs(imu.linear_acceleration[2] - 9.80665) < 0.2  # at rest: specific force +g, HG1700 noise
    depth = client.wait_fluid_pressure("auv", "depth", min_stamp=t, timeout_s=WAIT_S)
    assert depth is not None and depth.frame_id == "auv/depth"
    # ~50 m of water: p_atm + rho g d within a metre.
    assert abs((depth.pressure - 101325.0) / (1025.0 * 9.80665) - 49.95) < 1.0


def test_crawler_tracks_drive_and_report_their_state(crawler_server):
    """The crawler's control vector is its two belt speeds; its tracks' state comes back as numpy arrays."""
    _, domain_id = crawler_server
    client = connect(domain_id, "crawler")
    t = client.step(400)  # 2 s at 200 Hz: settled into the sediment
    start = client.wait_odometry("crawler", min_stamp=t, timeout_s=WAIT_S)
    for _ in range(8):  # 4 s at 0.6 of full belt speed, commands refreshed every 0.5 s
        client.set_commands("crawler", [0.6, 0.6])
        t = client.step(100)
    end = client.wait_odometry("crawler", min_stamp=t, timeout_s=WAIT_S)
    belt = 0.6 * 32.0 * 2.0 * math.pi / 60.0 * 0.15  # setpoint x max_rpm x sprocket radius [m/s]
    assert abs((end.p_WB[0] - start.p_WB[0]) - belt * (4.0 - 0.3)) < 0.02 * belt * 4.0
    tracks = client.wait_track_state("crawler", min_stamp=t, timeout_s=WAIT_S)
    assert tracks.names == ["track_port", "track_starboard"]
    assert isinstance(tracks.belt_speed, np.ndarray)
    np.testing.assert_allclose(tracks.belt_speed, [belt, belt], rtol=1e-3)
    assert tracks.command_source == 2
    assert np.all(tracks.load > 0.0)


def test_drop_weight_state(zoo_server):
    """The lander's drop weights report on rt/lander/drop_weights/state, read as numpy arrays."""
    client = connect(zoo_server("lander"), "lander")
    client.wait_drop_weight_state("lander", timeout_s=0)  # subscribe, then step
    assert client.wait_for_subscriptions(WAIT_S)
    client.set_commands("lander", [0.0, 1.0])  # release the ascent weight at once
    t = client.step(100)
    weights = client.wait_drop_weight_state("lander", min_stamp=t, timeout_s=WAIT_S)
    assert weights.names == ["descent_weight", "ascent_weight"]
    assert weights.attached.dtype == np.bool_
    np.testing.assert_array_equal(weights.attached, [True, False])
    np.testing.assert_array_equal(weights.reason, [0, 1])  # attached; released on command
    assert math.isnan(weights.release_time[0]) and weights.release_time[1] == 0.0
    assert weights.force[0] < -400.0 and weights.force[1] == 0.0  # 50 kg of steel in water: -426 N


def test_buoyancy_engine_state(zoo_server):
    """The glider's buoyancy engine (rt/glider/buoyancy_engines/state): heavy from the start at 10 cm^3/s."""
    client = connect(zoo_server("glider"), "glider")
    client.wait_buoyancy_engine_state("glider", timeout_s=0)
    assert client.wait_for_subscriptions(WAIT_S)
    t = client.step(500)  # 10 s at 50 Hz
    engine = client.wait_buoyancy_engine_state("glider", min_stamp=t, timeout_s=WAIT_S)
    assert engine.names == ["pump"]
    np.testing.assert_allclose(engine.volume_change, [-1e-4], rtol=1e-9)
    np.testing.assert_allclose(engine.volume_rate, [-1e-5], rtol=1e-9)
    assert engine.energy[0] == 0.0  # the valve lets oil in for free
    assert engine.force[0] < 0.0


def test_fin_state(zoo_server):
    """The AUV's fins (rt/auv/fins/state): commanded elevators turn at the servo's 60 deg/s."""
    client = connect(zoo_server("auv"), "auv")
    client.wait_fin_state("auv", timeout_s=0)
    assert client.wait_for_subscriptions(WAIT_S)
    client.set_commands("auv", [0.6, 0.0, 0.0, 0.4, 0.4])  # elevators to 10 deg
    t = client.step(10)  # 0.1 s at 100 Hz: 6 deg
    fins = client.wait_fin_state("auv", min_stamp=t, timeout_s=WAIT_S)
    assert fins.names == ["rudder_top", "rudder_bottom", "elevator_port", "elevator_starboard"]
    np.testing.assert_allclose(np.degrees(fins.angle), [0.0, 0.0, 6.0, 6.0], atol=1e-9)
    assert fins.lift.shape == (4,) and fins.command_source == 2


def test_joint_state(arm_server):
    """An articulated vehicle's joints on rt/arm/joint_states (sensor_msgs/JointState), read as numpy arrays,
    commanded through its joint controllers: the shoulder's position controller holds it where it starts
    (30 deg) less its sag; the forearm, released at -20 deg with no effort, falls under its wet weight
    (positive q turns +x towards -z). A command for the position controller then moves the shoulder; a bad
    one is refused by the lockstep step with its reason."""
    _, domain_id = arm_server
    client = connect(domain_id, "arm")
    client.wait_joint_state("arm", timeout_s=0)  # subscribe, then step
    assert client.wait_for_subscriptions(WAIT_S)
    t = client.step(100)  # 0.2 s
    joints = client.wait_joint_state("arm", min_stamp=t, timeout_s=WAIT_S)
    assert joints.names == ["shoulder", "forearm"]
    assert joints.frame_id == "arm/base_link"
    assert joints.position.dtype == np.float64 and joints.position.shape == (2,)
    assert abs(joints.position[0] - math.radians(30.0)) < math.radians(3.0)
    assert joints.position[1] > math.radians(-20.0) and joints.velocity[1] > 0.0
    assert joints.effort[1] == 0.0 and joints.effort[0] != 0.0

    client.set_joint_commands("arm", "shoulder_position", [math.radians(-10.0)])
    client.set_joint_commands("arm", "forearm_effort", [0.5])
    t = client.step(1000)  # 2 s
    joints = client.wait_joint_state("arm", min_stamp=t, timeout_s=WAIT_S)
    assert abs(joints.position[0] - math.radians(-10.0)) < math.radians(3.0)
    assert joints.effort[1] == 0.5

    client.set_joint_commands("arm", "shoulder_position", [math.radians(150.0)])  # beyond its 120 deg limit
    with pytest.raises(hadal.CommandRejected, match="outside its limits"):
        client.step(1)


def test_joint_trajectory(arm_server):
    """A trajectory for the shoulder's position group (trajectory_msgs/JointTrajectory, attached to the step
    request and published on rt/arm/shoulder_position/joint_trajectory), stamped 0.1 s ahead in sim time:
    the shoulder keeps its command until then, passes the first waypoint (10 deg at 1 s) and holds the
    last (40 deg at 2 s), each within 3 deg (the gravity sag of kp = 400 on the arm's wet weight). A
    trajectory naming a joint outside the group, or sent to an effort group, is refused with its reason."""
    _, domain_id = arm_server
    client = connect(domain_id, "arm")
    client.wait_joint_state("arm", timeout_s=0)
    assert client.wait_for_subscriptions(WAIT_S)
    client.set_joint_commands("arm", "shoulder_position", [math.radians(-30.0)])
    t0 = client.step(1000)  # 2 s at 500 Hz: settled at -30 deg
    client.set_joint_trajectory("arm", "shoulder_position", ["shoulder"], times=[1.0, 2.0],
                                positions=np.radians([[10.0], [40.0]]), start_time=t0 + 0.1)
    t = client.step(50)  # 0.1 s: not started
    joints = client.wait_joint_state("arm", min_stamp=t, timeout_s=WAIT_S)
    assert abs(joints.position[0] - math.radians(-30.0)) < math.radians(3.0)
    t = client.step(500)  # to t0 + 1.1 s: at the first waypoint
    joints = client.wait_joint_state("arm", min_stamp=t, timeout_s=WAIT_S)
    assert abs(joints.position[0] - math.radians(10.0)) < math.radians(3.0)
    t = client.step(1500)  # to t0 + 4.1 s: holding the last
    joints = client.wait_joint_state("arm", min_stamp=t, timeout_s=WAIT_S)
    assert abs(joints.position[0] - math.radians(40.0)) < math.radians(3.0)

    client.set_joint_trajectory("arm", "shoulder_position", ["forearm"], times=[1.0], positions=[[0.0]])
    with pytest.raises(hadal.CommandRejected, match="'forearm' is not a joint of the group"):
        client.step(1)
    client.set_joint_trajectory("arm", "forearm_effort", ["forearm"], times=[1.0], positions=[[0.0]])
    with pytest.raises(hadal.CommandRejected, match="only position groups follow trajectories"):
        client.step(1)
    with pytest.raises(ValueError, match=r"positions: shape \(2, 1\) expected"):
        client.set_joint_trajectory("arm", "shoulder_position", ["shoulder"], times=[1.0, 2.0], positions=[[0.0]])


def test_force_torque_wrench(arm_server):
    """The elbow's force_torque sensor (geometry_msgs/WrenchStamped on rt/arm/elbow_ft) as numpy arrays: at
    the reply's sim time, in the sensor's frame, the forearm's pull finite and between its wet weight's
    order (1 N) and ten times it."""
    _, domain_id = arm_server
    client = connect(domain_id, "arm")
    client.wait_wrench("arm", "elbow_ft", timeout_s=0)  # subscribe, then step
    assert client.wait_for_subscriptions(WAIT_S)
    t = client.step(50)  # 0.1 s: a 50 Hz sample at t
    wrench = client.wait_wrench("arm", "elbow_ft", min_stamp=t, timeout_s=WAIT_S)
    assert wrench.stamp == pytest.approx(t, abs=1e-9)
    assert wrench.frame_id == "arm/elbow_ft"
    assert wrench.force.shape == (3,) and wrench.torque.shape == (3,) and wrench.force.dtype == np.float64
    assert np.all(np.isfinite(wrench.force)) and np.all(np.isfinite(wrench.torque))
    assert 1.0 < np.linalg.norm(wrench.force) < 100.0
