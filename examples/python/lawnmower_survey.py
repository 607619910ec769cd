#!/usr/bin/python3
"""A camera survey: the default scenario's torpedo AUV flies a lawn-mower pattern and saves camera frames.

The default scenario (configs/scenarios/default.yaml) WITH its forward camera (640 x 480 at 10 Hz, pitched
30 deg down, published 0.2 s after its snapshot) and its two LED spot lights, on a lockstep hadald this
script starts. The AUV starts at (0, 0, -96), 4 m above the sediment, heading +x; leg i runs along x
(+x on even legs, -x on odd ones) on the line y = i * --spacing, for --leg-length metres; the benthic lander
12 m ahead lies under the first leg. Guidance is line of sight: the heading to steer is that to a point
LOOKAHEAD_M ahead on the current line, so the end of one leg turns the AUV onto the next by itself (to port,
then to starboard, ...). The autopilot is a PD loop per axis on GROUND TRUTH (odometry: yaw, yaw rate, depth,
vertical speed), acceptable for an example about the camera, not a navigation system (see dead_reckoning.py
for one from the sensors): the sway thruster in the nose turns the AUV, the heave thruster holds the start's
depth, the main thruster drives at 0.6 (~1.07 m/s), at 0.1 while the heading is off by more than 0.3 rad
(slow turns are tight: at 0.3 the AUV needs ~9 m to turn round and overshoots a 5 m line spacing by 4 m; at
0.1 by under 1 m).

Every --every-th camera frame (frame k is the snapshot at k / 10 s, published at k / 10 + 0.2 s, so it is
read after the step that reaches that time) is written to --out as frame_<k>.png, and survey.png shows the
track with the frames' positions beside a contact sheet of up to 12 of them. The run ends with key=value
lines: frames_saved, legs, duration_s, distance_m (horizontal path), mean_brightness (mean 8-bit count of
the saved frames, all channels), min_frame_brightness, max_depth_excursion_m (from the start's depth) and
out (the directory):

    /usr/bin/python3 examples/python/lawnmower_survey.py --legs 3 --leg-length 20 --spacing 5 --out survey

Frames are rendered whether saved or not (~0.1 s each): that command (a 104 s survey) took 72 s on 2 cores.
(needs the Python client on PYTHONPATH: build/python, or the installed package; numpy, matplotlib).
"""

import argparse
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

try:
    import hadal
except ImportError:  # run from the source tree after a build
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "../../build/python"))
    import hadal

VEHICLE, CAMERA = "auv", "camera"
CONTROL_PERIOD_S = 0.1   # one camera period: a frame becomes due every step
CAMERA_RATE_HZ, CAMERA_LATENCY_S = 10.0, 0.2  # default.yaml
LOOKAHEAD_M = 3.0
CRUISE, TURN = 0.6, 0.1  # main thruster setpoints: straight (~1.07 m/s), and while the heading is off by
#                          more than 0.3 rad: the nose thruster turns the AUV tighter the slower it goes


yaw_of = hadal.frames.yaw


def wrap(angle):
    return math.atan2(math.sin(angle), math.cos(angle))


rotation = hadal.frames.rotation_matrix  # R_WB of a ROS quaternion (x, y, z, w)


def autopilot(odom, line_y, direction, depth):
    """[main, heave, sway] steering along the line y = line_y in direction +-1 (of x), holding z = depth."""
    _, y, z = odom.p_WB
    heading = math.atan2(line_y - y, direction * LOOKAHEAD_M)
    error = wrap(heading - yaw_of(odom.q_WB))
    w_z = odom.w_WB_B[2]
    v_z = (np.array(odom.v_WB_B) @ rotation(odom.q_WB)[2])  # vertical speed in W
    sway = np.clip(3.0 * error - 4.0 * w_z, -1.0, 1.0)      # fractions of full thrust
    heave = np.clip(0.5 * (depth - z) - 2.0 * v_z, -0.5, 0.5)
    main = CRUISE if abs(error) < 0.3 else TURN               # slower in the turns
    return [main] + [float(np.sign(f) * math.sqrt(abs(f))) for f in (heave, sway)]  # thrust ~ setpoint^2


def survey(client, args):
    """Flies the legs; returns the track (t, x, y, z rows), the saved frames [(k, path, x, y, brightness)]."""
    status = client.status()
    steps = round(CONTROL_PERIOD_S / status.step_size)
    client.wait_image(VEHICLE, CAMERA, timeout_s=0)  # subscribe, then wait until the server has seen it
    client.wait_odometry(VEHICLE, timeout_s=0)
    client.wait_for_subscriptions()
    t = status.sim_time
    odom = client.wait_odometry(VEHICLE, min_stamp=t - 1e-9)
    x0, y0, depth = odom.p_WB
    track, frames, leg = [(t, x0, y0, depth)], [], 0
    max_time = args.legs * (args.leg_length + 3 * args.spacing) / 0.5 + 20.0  # a bound, should it go astray
    while leg < args.legs and t < max_time:
        direction = 1 if leg % 2 == 0 else -1
        leg_end_x = x0 + (args.leg_length if direction > 0 else 0.0)
        client.set_commands(VEHICLE, autopilot(odom, y0 + leg * args.spacing, direction, depth))
        t = client.step(steps)
        odom = client.wait_odometry(VEHICLE, min_stamp=t - 1e-9)
        if odom is None:
            raise hadal.Timeout(f"no odometry at t = {t:.2f} s")
        track.append((t, *odom.p_WB))
        if direction * (odom.p_WB[0] - leg_end_x) >= 0.0:
            leg += 1
        k = round((t - CAMERA_LATENCY_S) * CAMERA_RATE_HZ)  # the frame published in this step
        if k >= 1 and k % args.every == 0:
            image = client.wait_image(VEHICLE, CAMERA, min_stamp=k / CAMERA_RATE_HZ - 1e-6)
            if image is None or abs(image.stamp - k / CAMERA_RATE_HZ) > 1e-6:
                raise RuntimeError(f"frame {k} (stamp {k / CAMERA_RATE_HZ:.1f} s) not received at t = {t:.2f} s")
            path = os.path.join(args.out, f"frame_{k:05d}.png")
            plt.imsave(path, image.array)
            times = [p[0] for p in track]  # where the snapshot was taken, 0.2 s ago
            x, y = (np.interp(image.stamp, times, [p[i] for p in track]) for i in (1, 2))
            frames.append((k, path, x, y, float(image.array.mean())))
            print(f"frame {k}: t = {image.stamp:.1f} s at ({x:.1f}, {y:.1f}) brightness {frames[-1][4]:.1f}",
                  flush=True)
    return np.array(track), frames, leg


def summary(track, frames, path):
    """The track with the frames' positions, beside a contact sheet of up to 12 frames."""
    shown = [frames[i] for i in np.unique(np.linspace(0, len(frames) - 1, min(12, len(frames))).astype(int))]
    figure = plt.figure(figsize=(14, 6))
    axes = figure.add_gridspec(1, 1, left=0.05, right=0.33).subplots()
    axes.plot(track[:, 1], track[:, 2], "k-", label="track (ground truth)")
    axes.plot([f[2] for f in frames], [f[3] for f in frames], "r.", label="saved frames")
    axes.plot(12.0, 0.0, "bs", label="lander")
    axes.set(xlabel="x [m]", ylabel="y [m]", title="Lawn-mower track")
    axes.set_aspect("equal", adjustable="datalim")
    axes.legend(loc="best", fontsize=8)
    columns = 4
    rows = max(1, math.ceil(len(shown) / columns))
    grid = figure.add_gridspec(rows, columns, left=0.38, right=0.99, wspace=0.05, hspace=0.25)
    for i, (k, frame_path, *_) in enumerate(shown):
        cell = figure.add_subplot(grid[i // columns, i % columns])
        cell.imshow(plt.imread(frame_path))
        cell.set_title(f"t = {k / CAMERA_RATE_HZ:.1f} s", fontsize=8)
        cell.axis("off")
    figure.savefig(path, dpi=80)
    plt.close(figure)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--legs", type=int, default=3, help="survey lines")
    parser.add_argument("--leg-length", type=float, default=20.0, help="[m] along x")
    parser.add_argument("--spacing", type=float, default=5.0, help="[m] between lines, to port of the first")
    parser.add_argument("--every", type=int, default=10, help="save every N-th camera frame (10 Hz)")
    parser.add_argument("--out", default="survey", help="directory for the PNGs")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    with hadal.Server("default", mode="lockstep") as server, server.client() as client:
        track, frames, legs = survey(client, args)
    if not frames:
        raise RuntimeError("no frame saved: fly longer or lower --every")
    summary(track, frames, os.path.join(args.out, "survey.png"))
    brightness = np.array([f[4] for f in frames])
    figures = {"frames_saved": len(frames), "legs": legs, "duration_s": track[-1, 0],
               "distance_m": float(np.sum(np.linalg.norm(np.diff(track[:, 1:3], axis=0), axis=1))),
               "mean_brightness": brightness.mean(), "min_frame_brightness": brightness.min(),
               "max_depth_excursion_m": float(np.max(np.abs(track[:, 3] - track[0, 3])))}
    for key, value in figures.items():
        print(f"{key}={value}" if isinstance(value, int) else f"{key}={value:.4f}")
    print(f"out={os.path.abspath(args.out)}")


if __name__ == "__main__":
    main()
