#!/usr/bin/python3
"""Station keeping for the vectored ROV (configs/vehicles/vectored_rov.yaml) against a current.

A PID on the position error in the world frame (the integral takes up the current's steady drag), a PD
on heading, a PD on roll and pitch, then a thrust allocation over the eight thrusters: the horizontal
four by the pseudo-inverse of their (surge, sway, yaw) map, the vertical four of their (heave, roll,
pitch) map, and each thrust turned into a setpoint (thrust grows with the square of the rotor speed,
T = T_max s|s|). It reads ground-truth odometry -- an example of the control loop, not of navigation.

    hadald configs/scenarios/rov.yaml --mode lockstep &
    /usr/bin/python3 examples/python/rov_station_keeping.py --until 120

(needs the Python client on PYTHONPATH: build/python, or the installed package). Prints the distance
from the station every 10 s.
"""

import argparse
import math
import os
import sys

import numpy as np

try:
    import hadal
except ImportError:  # run from the source tree after a build
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "../../build/python"))
    import hadal

# The vehicle file's thrusters: position in B [m], unit direction in B, in command order.
S = math.sqrt(0.5)
HORIZONTAL = [((0.45, 0.35, 0.0), (S, -S, 0.0)), ((0.45, -0.35, 0.0), (S, S, 0.0)),
              ((-0.45, 0.35, 0.0), (S, S, 0.0)), ((-0.45, -0.35, 0.0), (S, -S, 0.0))]
VERTICAL = [((0.35, 0.3, 0.1), (0.0, 0.0, 1.0)), ((0.35, -0.3, 0.1), (0.0, 0.0, 1.0)),
            ((-0.35, 0.3, 0.1), (0.0, 0.0, 1.0)), ((-0.35, -0.3, 0.1), (0.0, 0.0, 1.0))]
T_MAX = 0.4 * 1025.0 * 0.15 ** 4 * 25.0 ** 2  # K_T rho D^4 n_max^2 [N]
CENTER_OF_MASS_B = np.array([0.0, 0.0, -0.05])


def wrench_map(thrusters, rows):
    """Columns: each thruster's unit-thrust wrench (force, moment about the centre of mass) in B, rows picked."""
    columns = []
    for position, direction in thrusters:
        d = np.array(direction)
        moment = np.cross(np.array(position) - CENTER_OF_MASS_B, d)
        columns.append(np.concatenate([d, moment])[rows])
    return np.array(columns).T


# (Fx, Fy, Mz) from the horizontal four, (Fz, Mx, My) from the vertical four.
ALLOCATE_HORIZONTAL = np.linalg.pinv(wrench_map(HORIZONTAL, [0, 1, 5]))
ALLOCATE_VERTICAL = np.linalg.pinv(wrench_map(VERTICAL, [2, 3, 4]))


rotation = hadal.frames.rotation_matrix  # R_WB of a ROS quaternion (x, y, z, w)


class StationKeeper:
    """Holds p_W and heading psi [rad]; gains for ~750 kg with added mass, 0.5 rad/s, critically damped."""

    def __init__(self, station_W, heading=0.0, dt=0.1):
        self.station_W = np.asarray(station_W, dtype=float)
        self.heading = heading
        self.dt = dt
        self.integral_W = np.zeros(3)
        self.kp, self.kd, self.ki = 190.0, 750.0, 25.0              # N/m, N s/m, N/(m s)
        self.kp_yaw, self.kd_yaw = 60.0, 150.0                       # N m/rad, N m s/rad
        self.kp_tilt, self.kd_tilt = 100.0, 60.0                     # roll and pitch

    def setpoints(self, odometry):
        R_WB = rotation(odometry.q_WB)
        v_W = R_WB @ odometry.v_WB_B
        error_W = self.station_W - odometry.p_WB
        self.integral_W = np.clip(self.integral_W + error_W * self.dt, -20.0, 20.0)
        force_W = self.kp * error_W - self.kd * v_W + self.ki * self.integral_W
        force_B = R_WB.T @ force_W
        yaw = math.atan2(R_WB[1, 0], R_WB[0, 0])
        yaw_error = math.atan2(math.sin(self.heading - yaw), math.cos(self.heading - yaw))
        w_B = odometry.w_WB_B
        moment_z = self.kp_yaw * yaw_error - self.kd_yaw * w_B[2]
        roll = math.atan2(R_WB[2, 1], R_WB[2, 2])
        pitch = -math.asin(max(-1.0, min(1.0, R_WB[2, 0])))
        moment_x = -self.kp_tilt * roll - self.kd_tilt * w_B[0]
        moment_y = -self.kp_tilt * pitch - self.kd_tilt * w_B[1]
        thrust = np.concatenate([ALLOCATE_HORIZONTAL @ np.array([force_B[0], force_B[1], moment_z]),
                                 ALLOCATE_VERTICAL @ np.array([force_B[2], moment_x, moment_y])])
        setpoints = np.sign(thrust) * np.sqrt(np.abs(thrust) / T_MAX)
        return np.clip(setpoints, -1.0, 1.0)


def hold_station(client, vehicle="rov", until_s=120.0, period_s=0.1, report=print):
    """Runs the station keeper against a lockstep hadald until sim time until_s; returns [(t, distance)].

    period_s must be a multiple of the vehicle's odometry period."""
    status = client.status()
    steps = max(1, round(period_s / status.step_size))
    client.wait_odometry(vehicle, timeout_s=0)
    client.wait_for_subscriptions()
    t = client.step(steps)  # a period: odometry (20 Hz in configs/scenarios/rov.yaml) is due at its end
    odometry = client.wait_odometry(vehicle, min_stamp=t - 1e-9)
    keeper = StationKeeper(odometry.p_WB.copy(), dt=steps * status.step_size)
    track = []
    while t < until_s:
        client.set_commands(vehicle, keeper.setpoints(odometry).tolist())
        t = client.step(steps)
        odometry = client.wait_odometry(vehicle, min_stamp=t - 1e-9)
        distance = float(np.linalg.norm(odometry.p_WB - keeper.station_W))
        track.append((t, distance))
        if report and abs(t / 10.0 - round(t / 10.0)) < 1e-6:
            report(f"t = {t:6.1f} s  off station {distance:6.3f} m")
    return track


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--domain-id", type=int, help="DDS domain (default: $ROS_DOMAIN_ID, else 0)")
    parser.add_argument("--vehicle", default="rov")
    parser.add_argument("--until", type=float, default=120.0, help="sim time to stop at [s]")
    args = parser.parse_args()
    client = hadal.Client(domain_id=args.domain_id)
    client.wait_for_server()
    hold_station(client, args.vehicle, args.until)


if __name__ == "__main__":
    main()
