#!/usr/bin/python3
"""Pick and place: the work-class ROV takes a push core from the sediment and puts it in its basket.

configs/scenarios/rov_intervention.yaml: the SF 30k (configs/vehicles/work_class_rov.yaml) with its Oberon 7
arm hovers over a push core lying on the sediment. This example, a lockstep client at 10 Hz:
  - holds the ROV on station (a PID on position and heading, a PD on roll and pitch, the wrench allocated
    over the eight thrusters by least squares);
  - plans the arm's moves with its own kinematics, read from the arm's URDF (configs/urdf/oberon7_arm.urdf)
    and its mount in the vehicle file: forward kinematics, and inverse kinematics by damped least squares
    for the gripper's centre pointing down with its fingers closing across the core;
  - sends each move as joint positions interpolated in time to the `arm` position controller (its joints
    also keep their own rate limits), and opens and shuts the parallel gripper with its `gripper` controller
    (one position for both fingers; shut on an object, each finger presses like a spring): the core is held
    by the fingers' contact and friction alone.
It reads ground truth (the ROV's and the core's odometry): an example of manipulation, not of perception.

    hadald configs/scenarios/rov_intervention.yaml --mode lockstep &
    /usr/bin/python3 examples/python/rov_pick_and_place.py

(add --no-cameras to hadald to skip rendering the ROV's two cameras: about 6 times faster, same motion).

(needs the Python client on PYTHONPATH: build/python, or the installed package). Prints each phase and where
the core ends up; exits 1 if it is not in the basket.
"""

import argparse
import math
import os
import sys
import xml.etree.ElementTree as ElementTree

import numpy as np
import yaml

try:
    import hadal
except ImportError:  # run from the source tree after a build
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "../../build/python"))
    import hadal

CONFIGS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../configs")
VEHICLE_FILE = os.path.join(CONFIGS, "vehicles/work_class_rov.yaml")
ARM_JOINTS = ["azimuth", "shoulder", "elbow", "roll", "pitch", "wrist"]
# The gripper's centre in the end effector's frame: between the finger tips, along its x axis [m].
TCP_EE = np.array([0.16, 0.0, 0.0])
GRIPPER_OPEN, GRIPPER_SHUT = 1.0, 0.0  # finger positions [rad] (the URDF's limits: 0 .. 1.047)
# The gripper's centre above the core's when it shuts: on its handle (configs/objects/push_core.yaml), a
# 25 mm bar the jaws close on nearly shut, where their faces squeeze it neither in nor out.
GRASP_ABOVE_CENTRE = 0.21  # [m]


def rpy_matrix(roll, pitch, yaw):
    """URDF's fixed-axis roll, pitch, yaw: Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr, cp, sp, cy, sy = (math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch),
                              math.cos(yaw), math.sin(yaw))
    return (np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]]) @ np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
            @ np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]]))


def transform(R, p):
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


def axis_rotation(axis, angle):
    """Rodrigues: the rotation by `angle` about the unit `axis`."""
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


rotation = hadal.frames.rotation_matrix  # R_WB of a ROS quaternion (x, y, z, w)


class ArmKinematics:
    """The arm's chain from the vehicle body frame B to the end effector, from the URDF and its mount."""

    def __init__(self, vehicle_file=VEHICLE_FILE):
        with open(vehicle_file) as f:
            vehicle = yaml.safe_load(f)
        mount = vehicle["urdf"]
        pose = mount.get("pose", {})
        self.X_B_base = transform(rpy_matrix(*[math.radians(a) for a in pose.get("rpy_deg", [0, 0, 0])]),
                                  pose.get("position", [0, 0, 0]))
        urdf = os.path.join(os.path.dirname(vehicle_file), mount["file"])
        joints = {j.get("name"): j for j in ElementTree.parse(urdf).getroot().findall("joint")}
        self.origins, self.axes, lower, upper = [], [], [], []
        for name in ARM_JOINTS:
            joint = joints[name]
            origin = joint.find("origin")
            xyz = [float(v) for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
            rpy = [float(v) for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
            self.origins.append(transform(rpy_matrix(*rpy), xyz))
            self.axes.append([float(v) for v in joint.find("axis").get("xyz").split()])
            limit = joint.find("limit")
            has_limits = joint.get("type") != "continuous" and limit is not None
            lower.append(float(limit.get("lower")) if has_limits else -math.pi)
            upper.append(float(limit.get("upper")) if has_limits else math.pi)
        self.lower, self.upper = np.array(lower), np.array(upper)

    def end_effector(self, q):
        """X_B_ee: the end effector's frame in B at joint positions q."""
        X = self.X_B_base.copy()
        for origin, axis, angle in zip(self.origins, self.axes, q):
            X = X @ origin @ transform(axis_rotation(axis, angle), np.zeros(3))
        return X

    def _error(self, q, tcp_B, close_B):
        X = self.end_effector(q)
        tcp = X[:3, :3] @ TCP_EE + X[:3, 3]
        # The gripper points down (its x along -z of B) and closes along close_B (its y).
        return np.concatenate([tcp - tcp_B, 0.3 * (X[:3, 0] - np.array([0.0, 0.0, -1.0])),
                               0.3 * (X[:3, 1] - close_B)])

    def inverse(self, tcp_B, close_B, q0):
        """Joint positions that put the gripper's centre at tcp_B pointing down, closing along close_B:
        damped least squares from q0 within the joint limits. Raises if it does not converge."""
        q = np.array(q0, dtype=float)
        close_B = np.asarray(close_B, dtype=float) / np.linalg.norm(close_B)
        for _ in range(200):
            e = self._error(q, tcp_B, close_B)
            if np.linalg.norm(e) < 1e-7:
                return q
            J = np.empty((e.size, q.size))
            for i in range(q.size):
                dq = np.zeros(q.size)
                dq[i] = 1e-7
                J[:, i] = (self._error(q + dq, tcp_B, close_B) - e) / 1e-7
            q = np.clip(q - J.T @ np.linalg.solve(J @ J.T + 1e-4 * np.eye(e.size), e), self.lower, self.upper)
        raise RuntimeError(f"no joint positions reach {tcp_B} (residual {np.linalg.norm(e):.3g})")


class StationKeeper:
    """Holds the ROV's position, heading and level trim (the arm and basket ahead of the centre of mass
    pitch it down by a few degrees against the foam's righting moment). Gains for ~1900 kg plus its added
    mass (Berg 2012) at ~0.5 rad/s, critically damped."""

    def __init__(self, station_W, heading, dt, vehicle_file=VEHICLE_FILE):
        with open(vehicle_file) as f:
            thrusters = yaml.safe_load(f)["thrusters"]
        columns = []
        for t in thrusters:
            d = np.array(t["direction"], dtype=float)
            d /= np.linalg.norm(d)
            columns.append(np.concatenate([d, np.cross(np.array(t["position"], dtype=float), d)]))
        self.allocate = np.linalg.pinv(np.array(columns).T)  # wrench in B (about B's origin) -> thrusts
        t = thrusters[0]
        self.t_max = (t["thrust_coefficient"] * 1025.0 * t["propeller_diameter"] ** 4 * (t["max_rpm"] / 60.0) ** 2)
        self.station_W, self.heading, self.dt = np.asarray(station_W, dtype=float), heading, dt
        self.integral_W = np.zeros(3)
        self.kp, self.kd, self.ki = np.array([700.0, 800.0, 1400.0]), np.array([2600.0, 3000.0, 5500.0]), 60.0
        self.kp_yaw, self.kd_yaw, self.kp_tilt, self.kd_tilt = 230.0, 900.0, 3000.0, 2000.0

    def setpoints(self, odometry):
        R_WB = rotation(odometry.q_WB)
        v_W = R_WB @ odometry.v_WB_B
        error_W = self.station_W - odometry.p_WB
        self.integral_W = np.clip(self.integral_W + error_W * self.dt, -50.0, 50.0)
        force_W = self.kp * error_W - self.kd * v_W + self.ki * self.integral_W
        yaw = math.atan2(R_WB[1, 0], R_WB[0, 0])
        yaw_error = math.atan2(math.sin(self.heading - yaw), math.cos(self.heading - yaw))
        roll = math.atan2(R_WB[2, 1], R_WB[2, 2])
        pitch = -math.asin(max(-1.0, min(1.0, R_WB[2, 0])))
        w_B = odometry.w_WB_B
        moment_B = np.array([-self.kp_tilt * roll - self.kd_tilt * w_B[0], -self.kp_tilt * pitch - self.kd_tilt * w_B[1],
                             self.kp_yaw * yaw_error - self.kd_yaw * w_B[2]])
        thrust = self.allocate @ np.concatenate([R_WB.T @ force_W, moment_B])
        return np.clip(np.sign(thrust) * np.sqrt(np.abs(thrust) / self.t_max), -1.0, 1.0)


class Intervention:
    """The lockstep loop: station keeping every period, and the arm's and gripper's commands."""

    def __init__(self, client, vehicle="rov", target="core", period_s=0.1, report=print):
        self.client, self.vehicle, self.target, self.report = client, vehicle, target, report
        status = client.status()
        self.steps = max(1, round(period_s / status.step_size))
        self.period = self.steps * status.step_size
        self.arm = ArmKinematics()
        client.wait_odometry(vehicle, timeout_s=0)
        client.wait_odometry(target, timeout_s=0)
        client.wait_joint_state(vehicle, timeout_s=0)
        client.wait_wrench(vehicle, "wrist_ft", timeout_s=0)
        client.wait_for_subscriptions()
        self.t = client.step(self.steps)
        self.odometry = client.wait_odometry(vehicle, min_stamp=self.t - 1e-9)
        R_WB = rotation(self.odometry.q_WB)
        self.keeper = StationKeeper(self.odometry.p_WB.copy(), math.atan2(R_WB[1, 0], R_WB[0, 0]), self.period)
        joints = client.wait_joint_state(vehicle, min_stamp=self.t - 1e-9)
        self.q = np.array([joints.position[joints.names.index(name)] for name in ARM_JOINTS])
        self.grip = 0.0

    def tick(self):
        """One period: the thrusters' setpoints, then the step."""
        self.client.set_commands(self.vehicle, self.keeper.setpoints(self.odometry).tolist())
        self.t = self.client.step(self.steps)
        self.odometry = self.client.wait_odometry(self.vehicle, min_stamp=self.t - 1e-9)

    def wait(self, seconds):
        for _ in range(round(seconds / self.period)):
            self.tick()

    def move(self, q_goal, speed=0.12):
        """The arm from its commanded position to q_goal along a straight line in joint space, starting and
        stopping smoothly (a half-cosine profile: a held core is not shaken loose), the fastest joint at
        `speed` [rad/s] at most (under every joint's limit), then 1.5 s to settle."""
        q_goal = np.asarray(q_goal, dtype=float)
        duration = max(0.5 * math.pi * float(np.max(np.abs(q_goal - self.q))) / speed, self.period)
        start, steps = self.q.copy(), round(duration / self.period)
        for k in range(1, steps + 1):
            s = 0.5 * (1.0 - math.cos(math.pi * k / steps))
            self.client.set_joint_commands(self.vehicle, "arm", (start + (q_goal - start) * s).tolist())
            self.tick()
        self.q = q_goal
        self.wait(1.5)

    def gripper(self, position, timeout_s=10.0):
        """Opens or shuts the fingers (both to `position`) and waits until both have stopped: at the position,
        or on an object (they move at 0.15 rad/s at most)."""
        self.grip = position
        self.client.set_joint_commands(self.vehicle, "gripper", [position])  # a gripper: both fingers there
        start = self.t
        while self.t - start < timeout_s:
            self.tick()
            joints = self.client.wait_joint_state(self.vehicle, min_stamp=self.t - 1e-9)
            rates = [joints.velocity[joints.names.index(f)] for f in ("finger_left_joint", "finger_right_joint")]
            if self.t - start > 1.0 and max(abs(r) for r in rates) < 0.01:
                break
        self.wait(0.5)

    def wrist_force_W(self):
        """The wrist force/torque sensor's force [N] in W: what the end effector and what it holds put on the
        wrist (the sensor sits at the end effector's frame)."""
        wrench = self.client.wait_wrench(self.vehicle, "wrist_ft", min_stamp=self.t - 1e-9)
        R_WS = rotation(self.odometry.q_WB) @ self.arm.end_effector(self.q)[:3, :3]
        return R_WS @ wrench.force

    def steady_wrist_force_W(self, seconds=1.0):
        """The wrist's force [N] in W over the next `seconds` of holding still: the median of one reading per
        period, per axis. A grasp's contacts slip and catch now and then (a reading 2-3 N off for a step);
        the median leaves those out where one reading or a mean would take them in."""
        readings = []
        for _ in range(max(1, round(seconds / self.period))):
            self.tick()
            readings.append(self.wrist_force_W())
        return np.median(readings, axis=0)

    def to_body(self, p_W):
        """A world point in B, at the ROV's present pose."""
        return rotation(self.odometry.q_WB).T @ (np.asarray(p_W) - self.odometry.p_WB)

    def target_position_W(self):
        return self.client.wait_odometry(self.target, min_stamp=self.t - 1e-9).p_WB.copy()

    def reach(self, tcp_B, close_B=(1.0, 0.0, 0.0)):
        self.move(self.arm.inverse(np.asarray(tcp_B, dtype=float), close_B, self.q))


def pick_and_place(client, vehicle="rov", target="core", report=print):
    """Runs the whole intervention. Returns the core's positions in B [m] where it started, lifted, just
    before the gripper let go and at the end, with whether it ended in the basket: a dict."""
    job = Intervention(client, vehicle, target, report=report)
    report(f"t = {job.t:5.1f} s  station kept at {np.round(job.keeper.station_W, 2).tolist()}")
    job.wait(2.0)
    job.gripper(GRIPPER_OPEN)
    core_B = job.to_body(job.target_position_W())
    report(f"t = {job.t:5.1f} s  gripper open; core at {np.round(core_B, 3).tolist()} in B")
    grasp_B = core_B + [0.0, 0.0, GRASP_ABOVE_CENTRE]
    # Out of the stowed pose high over the core (a straight line in joint space from the stowed pose to
    # just above it would sweep the gripper through it), then down onto it.
    job.reach(grasp_B + [0.0, 0.0, 0.5])
    job.reach(grasp_B + [0.0, 0.0, 0.25])
    # The arm's weight moved forward and the ROV's trim with it: where the core is in B now, then down
    # onto it (a slender core standing on the sediment tips over at the first push of a finger).
    grasp_B = job.to_body(job.target_position_W()) + [0.0, 0.0, GRASP_ABOVE_CENTRE]
    job.reach(grasp_B + [0.0, 0.0, 0.25])
    empty_W = job.steady_wrist_force_W()
    job.reach(grasp_B)
    report(f"t = {job.t:5.1f} s  gripper around the core")
    job.gripper(GRIPPER_SHUT)
    job.reach(grasp_B + [0.0, 0.0, 0.3])
    lifted = job.to_body(job.target_position_W())
    # What the wrist feels of the core: the downward pull it gained since the gripper hung empty.
    felt = float(empty_W[2] - job.steady_wrist_force_W()[2])
    report(f"t = {job.t:5.1f} s  core lifted to {np.round(lifted, 3).tolist()} in B; the wrist feels {felt:.2f} N")
    # Over the basket (configs/vehicles/work_class_rov.yaml: its floor's top 1.09 m below B), then down
    # until the core's bottom is 8 cm above the floor (below the walls' top), and let go.
    basket_B = np.array([1.75, 0.0, -1.09])
    release_B = basket_B + [0.0, 0.0, 0.08 + 0.15 + GRASP_ABOVE_CENTRE]
    job.reach(release_B + [0.0, 0.0, 0.15])
    job.reach(release_B)
    held = job.to_body(job.target_position_W())
    job.gripper(GRIPPER_OPEN)
    job.reach(release_B + [0.0, 0.0, 0.15])
    job.wait(3.0)
    final_B = job.to_body(job.target_position_W())
    # Inside the walls, upright or tipped over (its centre at most half its length above the floor).
    inside = bool(abs(final_B[0] - basket_B[0]) < 0.17 and abs(final_B[1] - basket_B[1]) < 0.22
                  and basket_B[2] < final_B[2] < basket_B[2] + 0.16)
    report(f"t = {job.t:5.1f} s  core at {np.round(final_B, 3).tolist()} in B: "
           f"{'in the basket' if inside else 'NOT in the basket'}")
    return {"start_B": core_B, "lifted_B": lifted, "held_B": held, "final_B": final_B, "inside": inside,
            "felt_N": np.array([felt])}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--domain-id", type=int, help="DDS domain (default: $ROS_DOMAIN_ID, else 0)")
    args = parser.parse_args()
    client = hadal.Client(domain_id=args.domain_id)
    client.wait_for_server()
    sys.exit(0 if pick_and_place(client)["inside"] else 1)


if __name__ == "__main__":
    main()
