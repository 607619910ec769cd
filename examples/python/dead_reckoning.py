#!/usr/bin/python3
"""Dead reckoning of the torpedo AUV (configs/vehicles/torpedo_auv.yaml) from its IMU, DVL and depth sensor.

The AUV flies a box: legs of 30 s at 0.6 of full main thrust (~1.07 m/s), each 90 deg to port of the last,
turned by the sway thruster in the nose, its depth held by the heave thruster. Navigation and autopilot use
the sensors alone, never ground truth after t = 0:
  attitude   the gyro's rate integrated as a quaternion (trapezoidal rate, 100 Hz), starting from the TRUE
             initial orientation (and velocity), taken once from odometry at t = 0, as if aligned;
  x, y       the DVL's bottom-track velocity (5 Hz) turned from its frame S (z down: roll 180 deg) into B,
             less the lever arm's w x r, rotated into W with that attitude, integrated between pings;
  z          the depth sensor: d = (p - p_atm) / (rho g) with the scenario's constants (its water of
             constant density), less the sensor's offset from B rotated with that attitude.
Each ping is compared with ground-truth odometry; the run ends with key=value lines (final and largest
horizontal error, distance travelled, drift as a percentage of it, heading error) and a PNG: the
trajectory, truth vs dead reckoning, and the horizontal error against time. It starts its own lockstep
hadald on --scenario (default: configs/scenarios/default.yaml; any with the torpedo AUV as `auv`) on
--domain-id ($ROS_DOMAIN_ID, else 0, as every Hadal tool), or with --attach steps the freshly started lockstep
one already running that scenario there:

    /usr/bin/python3 examples/python/dead_reckoning.py --duration 300 --plot dead_reckoning.png

(needs the Python client on PYTHONPATH: build/python, or the installed package; numpy, PyYAML, matplotlib).
"""

import argparse
import contextlib
import math
import os
import sys

import numpy as np
import yaml

try:
    import hadal
except ImportError:  # run from the source tree after a build
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "../../build/python"))
    import hadal
from hadal.server import scenario_path

VEHICLE = "auv"


rotation = hadal.frames.rotation_matrix  # R_WB of a ROS quaternion (x, y, z, w)
yaw_of = hadal.frames.yaw


def rotate_by_rate(q, w_B, dt):
    """q_WB followed by the body rotation w_B dt (the exact quaternion of that rotation vector)."""
    angle = float(np.linalg.norm(w_B)) * dt
    if angle == 0.0:
        return q
    bx, by, bz = np.asarray(w_B) / np.linalg.norm(w_B) * math.sin(angle / 2.0)
    bw = math.cos(angle / 2.0)
    x, y, z, w = q
    q = np.array([w * bx + x * bw + y * bz - z * by, w * by - x * bz + y * bw + z * bx,
                  w * bz + x * by - y * bx + z * bw, w * bw - x * bx - y * by - z * bz])
    return q / np.linalg.norm(q)


def wrap(angle):
    return math.atan2(math.sin(angle), math.cos(angle))


def load_setup(scenario_file, vehicle=VEHICLE):
    """The scenario's water constants and the vehicle's sensor mounts {name: (rate_hz, p_BS, R_BS)}."""
    with open(scenario_file) as f:
        scenario = yaml.safe_load(f)
    world = scenario.get("world", {})
    water = world.get("water", {})  # defaults: configs/REFERENCE.md; a constant-density ocean assumed
    constants = {"surface_z": water.get("surface_z", 0.0), "rho": water.get("density", 1025.0),
                 "p_atm": water.get("atmospheric_pressure", 101325.0),
                 "g": float(np.linalg.norm(world.get("gravity", [0.0, 0.0, -9.80665])))}
    entry = next(v for v in scenario["vehicles"] if v["name"] == vehicle)
    sensors = entry.get("sensors", [])
    if "include" in entry:
        with open(os.path.join(os.path.dirname(scenario_file), entry["include"])) as f:
            sensors = yaml.safe_load(f).get("sensors", []) + sensors
    mounts = {}
    for sensor in sensors:
        pose = sensor.get("pose", {})
        q_BS = np.array([0.0, 0.0, 0.0, 1.0])
        for axis, angle in zip((2, 1, 0), np.radians(pose.get("rpy_deg", [0.0] * 3))[::-1]):
            q_BS = rotate_by_rate(q_BS, np.eye(3)[axis] * angle, 1.0)  # Rz(yaw) Ry(pitch) Rx(roll)
        mounts[sensor["name"]] = (sensor.get("rate_hz"), np.array(pose.get("position", [0.0] * 3), float),
                                  rotation(q_BS))
    return constants, mounts


class DeadReckoner:
    """Pose of B in W from the gyro, the DVL and the depth sensor."""

    def __init__(self, q_WB, p_WB, v_W, constants, mounts):
        self.q, self.p, self.v_W = np.array(q_WB, float), np.array(p_WB, float), np.array(v_W, float)
        self.w_B, self.constants, self.mounts = None, constants, mounts

    def gyro(self, w_S, dt):
        w_B = self.mounts["imu"][2] @ w_S
        self.q = rotate_by_rate(self.q, w_B if self.w_B is None else 0.5 * (self.w_B + w_B), dt)
        self.w_B = w_B

    def dvl(self, v_S, dt):
        _, r_BS, R_BS = self.mounts["dvl"]
        v_W = rotation(self.q) @ (R_BS @ v_S - np.cross(self.w_B, r_BS))  # at B's origin, not the transducer
        self.p[:2] += 0.5 * (self.v_W[:2] + v_W[:2]) * dt
        self.v_W = v_W

    def depth(self, pressure):
        c = self.constants
        z_S = c["surface_z"] - (pressure - c["p_atm"]) / (c["rho"] * c["g"])
        self.p[2] = z_S - (rotation(self.q) @ self.mounts["depth"][1])[2]


def autopilot(t, nav, start_yaw, start_z, leg_s=30.0):
    """[main, heave, sway] for the box: heading 90 deg more to port each leg, the start's depth held."""
    heading_error = wrap(start_yaw + math.pi / 2 * int(t // leg_s) - yaw_of(nav.q))
    sway = np.clip(3.0 * heading_error - 4.0 * nav.w_B[2], -1.0, 1.0)  # fractions of full thrust
    heave = np.clip(0.5 * (start_z - nav.p[2]) - 2.0 * nav.v_W[2], -0.5, 0.5)
    main = 0.6 if abs(heading_error) < 0.2 else 0.3  # slower in the turns: the nose's thruster turns it faster
    return [main] + [float(np.sign(f) * math.sqrt(abs(f))) for f in (heave, sway)]  # thrust ~ setpoint^2


def need(sample, what):
    if sample is None:
        raise RuntimeError(f"no {what} from the server (is it a lockstep hadald with the torpedo AUV?)")
    return sample


def navigate(client, duration_s, constants, mounts, report=print):
    """Flies the box for duration_s on a lockstep server; returns arrays t, p_WB true and dead-reckoned
    (at t = 0, then one row per DVL ping), and the final heading error [rad]."""
    status = need(client.status(), "status")
    imu_dt = 1.0 / mounts["imu"][0]
    steps = round(imu_dt / status.step_size)
    per_ping = round(mounts["imu"][0] / mounts["dvl"][0])  # the DVL's period: a whole number of IMU periods
    client.wait_imu(VEHICLE, "imu", timeout_s=0)
    client.wait_dvl(VEHICLE, "dvl", timeout_s=0)
    client.wait_fluid_pressure(VEHICLE, "depth", timeout_s=0)
    client.wait_odometry(VEHICLE, timeout_s=0)
    client.wait_for_subscriptions()
    t0 = status.sim_time
    truth = need(client.wait_odometry(VEHICLE, min_stamp=t0 - 1e-9), "odometry")
    # The initial state, the only use of ground truth in navigation: pose and velocity at t = 0.
    nav = DeadReckoner(truth.q_WB, truth.p_WB, rotation(truth.q_WB) @ truth.v_WB_B, constants, mounts)
    start_yaw, start_z = yaw_of(truth.q_WB), truth.p_WB[2]
    log, count, t, lost = [(0.0, truth.p_WB, nav.p.copy())], 0, t0, 0
    while t < t0 + duration_s - 1e-6:
        t = client.step(steps)
        count += 1
        nav.gyro(need(client.wait_imu(VEHICLE, "imu", min_stamp=t - 1e-9), "IMU").angular_velocity, imu_dt)
        if count % per_ping:
            continue
        ping = need(client.wait_dvl(VEHICLE, "dvl", min_stamp=t - 1e-9), "DVL ping")
        if ping.velocity_mode == ping.VELOCITY_MODE_BOTTOM_TRACK and np.all(np.isfinite(ping.velocity)):
            nav.dvl(ping.velocity, per_ping * imu_dt)
        else:  # no bottom lock: carry on at the last velocity
            lost += 1
            nav.p[:2] += nav.v_W[:2] * per_ping * imu_dt
        nav.depth(need(client.wait_fluid_pressure(VEHICLE, "depth", min_stamp=t - 1e-9), "pressure").pressure)
        client.set_commands(VEHICLE, autopilot(t - t0, nav, start_yaw, start_z))
        truth = need(client.wait_odometry(VEHICLE, min_stamp=t - 1e-9), "odometry")
        log.append((t - t0, truth.p_WB, nav.p.copy()))
        if report and count % round(60.0 / imu_dt) == 0:
            report(f"t = {t - t0:5.0f} s  horizontal error {np.linalg.norm(truth.p_WB[:2] - nav.p[:2]):.3f} m")
    if lost and report:
        report(f"{lost} DVL pings without bottom lock")
    times, true_p, dead_reckoned_p = (np.array(column) for column in zip(*log))
    return times, true_p, dead_reckoned_p, wrap(yaw_of(nav.q) - yaw_of(truth.q_WB))


def plot(times, truth, estimate, error, title, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, (trajectory, drift) = plt.subplots(1, 2, figsize=(12, 5.5))
    trajectory.plot(truth[:, 0], truth[:, 1], "k-", label="ground truth")
    trajectory.plot(estimate[:, 0], estimate[:, 1], "r--", label="dead reckoning (IMU + DVL + depth)")
    trajectory.plot(truth[0, 0], truth[0, 1], "go", label="start")
    trajectory.set(xlabel="x (east) [m]", ylabel="y (north) [m]", title="Trajectory")
    trajectory.set_aspect("equal", adjustable="datalim")
    trajectory.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3)
    drift.plot(times, error, "r-")
    drift.set(xlabel="time [s]", ylabel="horizontal error [m]", title="Dead-reckoning drift")
    for axes in (trajectory, drift):
        axes.grid(True)
    figure.suptitle(title)
    figure.tight_layout()
    figure.savefig(path, dpi=100)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=300.0, help="sim time to fly [s]")
    parser.add_argument("--plot", default="dead_reckoning.png", help="PNG to write")
    parser.add_argument("--scenario", default="default", help="name in configs/scenarios, or a file")
    parser.add_argument("--domain-id", type=int, help="DDS domain (default: $ROS_DOMAIN_ID, else 0)")
    parser.add_argument("--attach", action="store_true",
                        help="step the lockstep hadald running on the domain instead of starting one")
    args = parser.parse_args()
    scenario = scenario_path(args.scenario)
    constants, mounts = load_setup(scenario)
    domain_id = hadal.default_domain_id() if args.domain_id is None else args.domain_id
    with (contextlib.nullcontext() if args.attach else
          hadal.Server(scenario, cameras=False, domain_id=domain_id)) as server:
        with hadal.Client(domain_id=domain_id) as client:
            if not client.wait_for_server():
                raise hadal.ServerNotFound(f"no hadald on DDS domain {domain_id}")
            times, truth, estimate, heading_error = navigate(client, args.duration, constants, mounts)
    error = np.linalg.norm(truth[:, :2] - estimate[:, :2], axis=1)
    distance = float(np.sum(np.linalg.norm(np.diff(truth[:, :2], axis=0), axis=1)))
    figures = {"duration_s": times[-1], "distance_travelled_m": distance, "final_horizontal_error_m": error[-1],
               "max_horizontal_error_m": error.max(), "drift_percent_of_distance": 100.0 * error[-1] / distance,
               "heading_error_deg": math.degrees(heading_error),
               "final_depth_error_m": estimate[-1, 2] - truth[-1, 2]}
    for key, value in figures.items():
        print(f"{key}={value:.4f}")
    plot(times, truth, estimate, error, f"{distance:.0f} m travelled in {times[-1]:.0f} s: final horizontal error "
         f"{error[-1]:.2f} m ({figures['drift_percent_of_distance']:.2f} % of the distance)", args.plot)
    print(f"plot={os.path.abspath(args.plot)}")


if __name__ == "__main__":
    main()
