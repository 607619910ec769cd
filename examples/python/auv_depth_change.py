#!/usr/bin/python3
"""Depth and heading autopilot for the finned AUV (configs/vehicles/finned_auv.yaml), on its fins alone.

The propeller holds 0.6 of full speed (~1.1 m/s); a depth loop asks for a pitch (at most 20 deg, damped
by the climb rate), a pitch loop turns both elevators (positive: nose up), and a heading loop turns both
rudders (positive: nose to starboard). It reads ground-truth odometry -- an example of the control loop,
not of navigation -- and steps a lockstep hadald at 10 Hz:

    hadald configs/scenarios/auv.yaml --mode lockstep &
    /usr/bin/python3 examples/python/auv_depth_change.py --depth 30 --until 90

(needs the Python client on PYTHONPATH: build/python, or the installed package). Prints depth, pitch
and elevator every 10 s.
"""

import argparse
import math
import os
import sys

try:
    import hadal
except ImportError:  # run from the source tree after a build
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "../../build/python"))
    import hadal


def attitude(q):
    """Nose-up pitch and yaw (heading from x, to the left) [rad] of a ROS quaternion (x, y, z, w)."""
    x, y, z, w = q
    pitch = -math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x))))
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return pitch, yaw


def clamp(value, limit):
    return max(-limit, min(limit, value))


class Autopilot:
    """Cascaded depth -> pitch -> elevator loop and a heading -> rudder loop (gains for ~1 m/s)."""

    def __init__(self, depth_m, heading_rad=0.0, throttle=0.6):
        self.target_z = -depth_m
        self.heading = heading_rad
        self.throttle = throttle

    def setpoints(self, odometry):
        pitch, yaw = attitude(odometry.q_WB)
        u, _, w = odometry.v_WB_B
        climb_rate = w * math.cos(pitch) + u * math.sin(pitch)
        pitch_cmd = clamp(0.08 * (self.target_z - odometry.p_WB[2]) - 0.4 * climb_rate, 0.35)
        elevator = clamp(2.0 * (pitch_cmd - pitch) - 1.0 * (-odometry.w_WB_B[1]), 1.0)
        heading_error = math.atan2(math.sin(yaw - self.heading), math.cos(yaw - self.heading))
        rudder = clamp(2.0 * heading_error + 1.0 * odometry.w_WB_B[2], 1.0)
        # [main, rudder_top, rudder_bottom, elevator_port, elevator_starboard]
        return [self.throttle, rudder, rudder, elevator, elevator]


def fly(client, depth_m, until_s, vehicle="auv", report=print):
    """Flies the autopilot against a lockstep hadald until sim time until_s; returns [(t, z, pitch)]."""
    status = client.status()
    steps = max(1, round(0.1 / status.step_size))
    client.wait_odometry(vehicle, timeout_s=0)
    client.wait_for_subscriptions()
    pilot = Autopilot(depth_m)
    t = client.step(steps)
    track = []
    while t < until_s:
        odometry = client.wait_odometry(vehicle, min_stamp=t - 1e-9)
        client.set_commands(vehicle, pilot.setpoints(odometry))
        t = client.step(steps)
        pitch, _ = attitude(odometry.q_WB)
        track.append((odometry.stamp, odometry.p_WB[2], pitch))
        if report and abs(odometry.stamp / 10.0 - round(odometry.stamp / 10.0)) < 1e-6:
            report(f"t = {odometry.stamp:5.1f} s  depth {-odometry.p_WB[2]:6.2f} m  "
                   f"pitch {math.degrees(pitch):6.1f} deg")
    return track


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--domain-id", type=int, help="DDS domain (default: $ROS_DOMAIN_ID, else 0)")
    parser.add_argument("--depth", type=float, default=30.0, help="target depth [m]")
    parser.add_argument("--until", type=float, default=90.0, help="sim time to stop at [s]")
    parser.add_argument("--security-file", default=None,
                        help="DDS Security: a YAML file with this client's security: block (docs/dds.md, 'DDS Security')")
    args = parser.parse_args()
    client = hadal.Client(domain_id=args.domain_id, security_file=args.security_file)
    client.wait_for_server()
    fly(client, args.depth, args.until)


if __name__ == "__main__":
    main()
