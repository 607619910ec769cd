#!/usr/bin/python3
"""USBL-aided navigation over an acoustic modem: the classic loop, on configs/scenarios/usbl_survey.yaml.

The finned AUV flies a 600 m box 50 m above the 3000 m deep seabed, on its own sensors (as
examples/python/dead_reckoning.py does, whose dead reckoner this reuses):
  attitude   the gyro (HG1700, 50 Hz) integrated from the true initial attitude;
  x, y       the DVL's bottom-track velocity (5 Hz) rotated into W with that attitude;
  altitude   the DVL's, held by the elevators; heading by the rudders.
The vessel's USBL fixes the AUV once a second. Every --fix-every seconds the vessel side of this script sends the
latest fix down through the vessel's modem (WHOI Micro-Modem FH-FSK, 80 bit/s): a 20-byte packet (the time the
AUV replied, east, north, horizontal variance) that takes 2.3 s to send and ~2 s to travel, and may be lost. The AUV side reads
its modem and fuses each fix that arrives into a second estimate, with a simple delayed-measurement filter:
the dead-reckoning error is a random walk growing with distance (variance --q per metre); a fix stamped t_f
corrects the estimate by K (z - x_hat(t_f)), x_hat(t_f) the estimate's own history at the fix time (dead
reckoning adds no error between t_f and now that the fix could see), K = P / (P + R).

Then, in the same server, the packet success rate against range: the AUV's modem sends --packets packets of
20 bytes to the deep AUV's at each of several ranges (both 1000 m deep), against the rate the preset's error
curve gives at the SNR worked out by hand: SL - 20 log10 r - alpha r - NL, alpha and NL from hadal-ocean.

Writes a PNG (left: horizontal error against time, dead reckoning alone and aided, and each fix's own error;
right: packet success against range, measured and predicted) and key=value lines:

    /usr/bin/python3 examples/python/usbl_aided_navigation.py --duration 3600 --plot usbl_aided_navigation.png

(needs the Python client on PYTHONPATH: build/python, or the installed package; numpy, PyYAML, matplotlib.)
"""

import argparse
import contextlib
import json
import math
import os
import shutil
import struct
import subprocess
import sys

import numpy as np

try:
    import hadal
except ImportError:  # run from the source tree after a build
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "../../build/python"))
    import hadal
from hadal.server import find_hadald, scenario_path

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dead_reckoning import DeadReckoner, load_setup, rotation, wrap, yaw_of  # noqa: E402

AUV, VESSEL, FAR = "auv", "vessel", "deep_auv"
SEABED_Z = -3000.0
ALTITUDE = 50.0
FIX_FORMAT = "<dfff"  # reply time [s], east, north [m], horizontal variance [m^2]: 20 bytes
# The scenario's modems: configs/scenarios/usbl_survey.yaml, preset whoi_micromodem_fhfsk
# (server/src/sensors/modem_sensor.cc).
MODEM = {"frequency_hz": 25000.0, "bandwidth_hz": 4000.0, "bit_rate_bps": 80.0, "source_level_db": 185.0,
         "implementation_loss_db": 3.0, "preamble_s": 0.3}


def packet_success(snr_db, payload_bytes, m=MODEM):
    """The preset's error curve: non-coherent FSK, Eb/N0 = SNR + 10 log10(B / R) - loss, 8 bits a byte
    (sensors/modem_sensor.h, ModemSensor::packet_success)."""
    ebn0 = 10.0 ** ((snr_db + 10.0 * math.log10(m["bandwidth_hz"] / m["bit_rate_bps"]) -
                     m["implementation_loss_db"]) / 10.0)
    return (1.0 - 0.5 * math.exp(-0.5 * ebn0)) ** (8 * payload_bytes)


def packet_duration_s(payload_bytes, m=MODEM):
    return m["preamble_s"] + 8.0 * payload_bytes / m["bit_rate_bps"]


def autopilot(nav, heading, altitude):
    """[main, rudder_top, rudder_bottom, elevator_port, elevator_starboard] (configs/vehicles/finned_auv.yaml):
    a positive rudder turns the nose to starboard, a positive elevator pitches it up."""
    R = rotation(nav.q)
    nose_up = math.asin(max(-1.0, min(1.0, R[2, 0])))
    rudder = np.clip(-(1.5 * wrap(heading - yaw_of(nav.q)) - 3.0 * nav.w_B[2]), -1.0, 1.0)
    nose_up_command = np.clip(0.02 * (ALTITUDE - altitude), -0.2, 0.2) if np.isfinite(altitude) else 0.0
    elevator = np.clip(4.0 * (nose_up_command - nose_up) + 2.0 * nav.w_B[1], -1.0, 1.0)
    return [0.6, float(rudder), float(rudder), float(elevator), float(elevator)]


class AidedEstimate:
    """Dead reckoning plus a correction from delayed position fixes (module docstring)."""

    def __init__(self, q_per_m, sigma0=1.0):
        self.offset = np.zeros(2)
        self.P = sigma0 ** 2
        self.q_per_m = q_per_m
        self.history_t, self.history_p = [], []  # dead reckoning's x, y at each DVL ping

    def predict(self, t, p_dr, distance):
        self.P += self.q_per_m * distance
        self.history_t.append(t)
        self.history_p.append(np.array(p_dr[:2]))

    def estimate(self, p_dr):
        return np.array(p_dr[:2]) + self.offset

    def fix(self, t_fix, z, variance):
        if not self.history_t or t_fix < self.history_t[0]:
            return False
        k = int(np.searchsorted(self.history_t, t_fix))
        k = min(max(k, 1), len(self.history_t) - 1)
        t0, t1 = self.history_t[k - 1], self.history_t[k]
        s = 0.0 if t1 == t0 else min(max((t_fix - t0) / (t1 - t0), 0.0), 1.0)
        p_then = (1 - s) * self.history_p[k - 1] + s * self.history_p[k] + self.offset
        innovation = np.asarray(z) - p_then
        if innovation @ innovation > 25.0 * (self.P + variance) * 2:  # a 5-sigma outlier: ignored
            return False
        gain = self.P / (self.P + variance)
        self.offset += gain * innovation
        self.P *= 1.0 - gain
        return True


def navigate(client, duration_s, mounts, fix_every_s, q_per_m, report=print):
    """Flies the box; returns rows (t, true x, y, dead-reckoned x, y, aided x, y), the fixes' own errors
    [(t, error)], and the packet counts (sent, received)."""
    status = client.status()
    imu_dt = 1.0 / mounts["imu"][0]
    steps = round(imu_dt / status.step_size)
    per_ping = round(mounts["imu"][0] / mounts["dvl"][0])
    for wait in (lambda: client.wait_imu(AUV, "imu", timeout_s=0), lambda: client.wait_dvl(AUV, "dvl", timeout_s=0),
                 lambda: client.wait_usbl_fixes(VESSEL, "usbl", timeout_s=0)):
        wait()
    client.receive_packets(AUV, "modem")
    client.wait_for_subscriptions()
    x0, y0 = 600.0, 300.0
    t0 = client.reset(poses={AUV: (x0, y0, SEABED_Z + ALTITUDE)})
    truth = client.reply_odometry(AUV)
    nav = DeadReckoner(truth.q_WB, truth.p_WB, np.zeros(3), {}, mounts)
    aided = AidedEstimate(q_per_m)
    start_yaw = yaw_of(truth.q_WB)
    rows, fixes, count, t = [], [], 0, t0
    last_fix, pending_fix, next_send, sent, received, altitude = -1.0, None, fix_every_s, 0, 0, ALTITUDE
    leg_s = 600.0
    while t < t0 + duration_s - 1e-6:
        t = client.step(steps)
        count += 1
        nav.gyro(client.wait_imu(AUV, "imu", min_stamp=t - 1e-9, timeout_s=30).angular_velocity, imu_dt)
        if count % per_ping:
            continue
        ping = client.wait_dvl(AUV, "dvl", min_stamp=t - 1e-9, timeout_s=30)
        p_before = nav.p.copy()
        if ping.velocity_mode == ping.VELOCITY_MODE_BOTTOM_TRACK and np.all(np.isfinite(ping.velocity)):
            nav.dvl(ping.velocity, per_ping * imu_dt)
            altitude = ping.altitude if np.isfinite(ping.altitude) else altitude
        else:
            nav.p[:2] += nav.v_W[:2] * per_ping * imu_dt
        aided.predict(t, nav.p, float(np.linalg.norm(nav.p[:2] - p_before[:2])))
        heading = start_yaw + math.pi / 2 * int((t - t0) // leg_s)
        client.set_commands(AUV, autopilot(nav, heading, altitude), publish=False)
        truth = client.reply_odometry(AUV)

        # The vessel: keep the latest fix of the AUV; send one down every fix_every_s seconds.
        message = client.wait_usbl_fixes(VESSEL, "usbl", min_stamp=last_fix + 1e-6, timeout_s=0)
        if message is not None:
            last_fix = message.stamp
            for fix in message.fixes:
                if fix.target != AUV:
                    continue
                covariance = np.asarray(fix.position_covariance).reshape(3, 3)
                variance = 0.5 * (covariance[0, 0] + covariance[1, 1])  # horizontal, the vessel about level
                # The position is where the transponder replied: half the two-way time before the fix's stamp.
                t_reply = fix.stamp - fix.travel_time / 2
                pending_fix = (t_reply, fix.position_world[0], fix.position_world[1], variance)
                fixes.append((t_reply - t0, fix.position_world[0], fix.position_world[1]))
        if pending_fix is not None and t - t0 >= next_send:
            client.send_packet(VESSEL, "modem", struct.pack(FIX_FORMAT, *pending_fix), destination=AUV, publish=False)
            sent += 1
            pending_fix = None
            next_send += fix_every_s

        # The AUV: fuse every fix its modem decoded.
        for packet in client.receive_packets(AUV, "modem"):
            received += 1
            t_fix, east, north, variance = struct.unpack(FIX_FORMAT, packet.payload)
            aided.fix(t_fix, (east, north), variance)
        estimate = aided.estimate(nav.p)
        rows.append((t - t0, truth.p_WB[0], truth.p_WB[1], nav.p[0], nav.p[1], estimate[0], estimate[1]))
        if report and count % round(300.0 / imu_dt) == 0:
            dr = math.hypot(truth.p_WB[0] - nav.p[0], truth.p_WB[1] - nav.p[1])
            fused = math.hypot(truth.p_WB[0] - estimate[0], truth.p_WB[1] - estimate[1])
            report(f"t = {t - t0:5.0f} s  dead reckoning {dr:7.2f} m, aided {fused:6.2f} m, "
                   f"fixes {received}/{sent}, altitude {altitude:5.1f} m")
    rows = np.array(rows)
    # Each fix's own error: against the true position at its reply time (the 5 Hz truth, interpolated).
    fix_errors = np.array([(tf, math.hypot(east - np.interp(tf, rows[:, 0], rows[:, 1]),
                                           north - np.interp(tf, rows[:, 0], rows[:, 2])))
                           for tf, east, north in fixes if rows[0, 0] <= tf <= rows[-1, 0]])
    return rows, fix_errors, sent, received


def water_figures(scenario, depth):
    """Absorption at the modems' frequency and the noise in their band at `depth` (hadal-ocean)."""
    ocean = shutil.which("hadal-ocean") or os.path.join(os.path.dirname(find_hadald()), "hadal-ocean")
    out = subprocess.run([ocean, scenario, "--depths", str(depth), "--frequency", str(MODEM["frequency_hz"]),
                          "--bandwidth", str(MODEM["bandwidth_hz"])], capture_output=True, text=True, check=True)
    line = json.loads(out.stdout.splitlines()[0])
    return line["absorption_db_per_m"], line["noise_level_db"]


def success_against_range(client, scenario, packets, payload_bytes=20, depth=1000.0):
    """(ranges, hand SNRs, measured success rates) for the AUV's modem sending to the deep AUV's."""
    alpha, noise = water_figures(scenario, depth)

    def hand_snr(r):
        return MODEM["source_level_db"] - 20.0 * math.log10(r) - alpha * r - noise

    def range_for(snr):
        lo, hi = 10.0, 100000.0
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if hand_snr(mid) > snr else (lo, mid)
        return 0.5 * (lo + hi)

    client.receive_packets(FAR, "modem")
    client.wait_for_subscriptions()
    step_size = client.status().step_size
    gap = packet_duration_s(payload_bytes) + 0.2
    ranges, snrs, rates = [], [], []
    for snr in np.arange(-8.0, 0.5, 1.0):
        r = range_for(snr)
        z = -depth + 0.12  # the modems 0.12 m above B
        client.reset(poses={AUV: (0.0, 0.0, z), FAR: (r, 0.0, z)})
        for k in range(packets):
            client.send_packet(AUV, "modem", bytes([k % 256]) * payload_bytes, destination=FAR, publish=False)
            client.step(round(gap / step_size))
        client.step(round((r / 1400.0 + 1.0) / step_size))
        got = len(client.receive_packets(FAR, "modem", timeout_s=2.0))
        ranges.append(r)
        snrs.append(snr)
        rates.append(got / packets)
        print(f"range {r:7.0f} m  hand SNR {snr:5.1f} dB  success {got}/{packets}", file=sys.stderr)
    return np.array(ranges), np.array(snrs), np.array(rates), payload_bytes, packets


def plot(rows, fix_errors, sweep, title, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, (drift, comms) = plt.subplots(1, 2, figsize=(13, 5.5))
    t = rows[:, 0]
    dr = np.hypot(rows[:, 1] - rows[:, 3], rows[:, 2] - rows[:, 4])
    fused = np.hypot(rows[:, 1] - rows[:, 5], rows[:, 2] - rows[:, 6])
    if len(fix_errors):
        drift.plot(fix_errors[:, 0], fix_errors[:, 1], ".", color="0.7", markersize=3, label="USBL fix error (at the vessel)")
    drift.plot(t, dr, "r-", label="dead reckoning (gyro + DVL)")
    drift.plot(t, fused, "b-", label="dead reckoning + fixes via the modem")
    drift.set(xlabel="time [s]", ylabel="horizontal error [m]", title="Navigation error")
    drift.legend(loc="upper left")
    ranges, snrs, rates, payload, packets = sweep
    order = np.argsort(ranges)
    ranges, snrs, rates = ranges[order], snrs[order], rates[order]
    fine = np.linspace(ranges.min(), ranges.max(), 200)
    predicted = [packet_success(np.interp(r, ranges, snrs), payload) for r in fine]  # SNR is linear in r here
    comms.plot(fine / 1000.0, predicted, "k-", label="error curve at the hand SNR")
    errors = np.sqrt(np.maximum(rates * (1 - rates), 0.25 / packets) / packets)  # binomial standard error
    comms.errorbar(ranges / 1000.0, rates, yerr=errors, fmt="o", color="tab:orange", capsize=3,
                   label=f"measured ({packets} packets per range)")
    comms.set(xlabel="range [km] (both modems 1000 m deep)", ylabel="packet success",
              title=f"Micro-Modem FH-FSK, {payload}-byte packets")
    for r, snr in zip(ranges, snrs):
        comms.annotate(f"{snr:.0f} dB", (r / 1000.0, 1.04), ha="center", fontsize=8, color="0.4")
    comms.set_ylim(-0.05, 1.1)
    comms.legend(loc="lower left", title="hand SNR above the points")
    for axes in (drift, comms):
        axes.grid(True)
    figure.suptitle(title)
    figure.tight_layout()
    figure.savefig(path, dpi=100)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=3600.0, help="sim time to fly [s]")
    parser.add_argument("--fix-every", type=float, default=20.0, help="seconds between fixes sent down [s]")
    parser.add_argument("--q", type=float, default=0.02, help="dead-reckoning variance growth [m^2 per m]")
    parser.add_argument("--packets", type=int, default=100, help="packets per range in the success sweep")
    parser.add_argument("--plot", default="usbl_aided_navigation.png", help="PNG to write")
    parser.add_argument("--scenario", default="usbl_survey", help="name in configs/scenarios, or a file")
    parser.add_argument("--domain-id", type=int, help="DDS domain (default: $ROS_DOMAIN_ID, else 0)")
    parser.add_argument("--attach", action="store_true",
                        help="step the lockstep hadald running on the domain instead of starting one")
    args = parser.parse_args()
    scenario = scenario_path(args.scenario)
    _, mounts = load_setup(scenario, AUV)
    domain_id = hadal.default_domain_id() if args.domain_id is None else args.domain_id
    with (contextlib.nullcontext() if args.attach else hadal.Server(scenario, domain_id=domain_id)):
        with hadal.Client(domain_id=domain_id) as client:
            if not client.wait_for_server():
                raise hadal.ServerNotFound(f"no hadald on DDS domain {domain_id}")
            rows, fix_errors, sent, received = navigate(client, args.duration, mounts, args.fix_every, args.q,
                                                        report=lambda line: print(line, file=sys.stderr))
            sweep = success_against_range(client, scenario, args.packets)
    dr = np.hypot(rows[:, 1] - rows[:, 3], rows[:, 2] - rows[:, 4])
    fused = np.hypot(rows[:, 1] - rows[:, 5], rows[:, 2] - rows[:, 6])
    distance = float(np.sum(np.hypot(np.diff(rows[:, 1]), np.diff(rows[:, 2]))))
    ranges, snrs, rates, payload, _ = sweep
    # Where the measured rate is neither 0 nor 1, the SNR it implies through the error curve against the hand SNR.
    offsets = [abs(inverse_success(rate, payload) - snr) for snr, rate in zip(snrs, rates) if 0.05 < rate < 0.95]
    worst_db = max(offsets) if offsets else float("nan")
    figures = {"duration_s": rows[-1, 0], "distance_travelled_m": distance, "fixes_sent": sent,
               "fixes_received": received, "final_error_dead_reckoning_m": dr[-1], "final_error_aided_m": fused[-1],
               "max_error_dead_reckoning_m": dr.max(), "max_error_aided_m": fused.max(),
               "median_fix_error_m": float(np.median(fix_errors[:, 1])) if len(fix_errors) else float("nan"),
               "worst_success_snr_offset_db": worst_db}
    for key, value in figures.items():
        print(f"{key}={value:.4f}" if isinstance(value, float) else f"{key}={value}")
    plot(rows, fix_errors, sweep, f"{distance:.0f} m in {rows[-1, 0]:.0f} s: dead reckoning {dr[-1]:.1f} m off, "
         f"aided {fused[-1]:.1f} m ({received} of {sent} fixes through the modem)", args.plot)
    print(f"plot={os.path.abspath(args.plot)}")


def inverse_success(rate, payload_bytes):
    """The SNR at which the error curve gives `rate` (bisection; it rises with SNR)."""
    lo, hi = -40.0, 40.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if packet_success(mid, payload_bytes) < rate else (lo, mid)
    return 0.5 * (lo + hi)


if __name__ == "__main__":
    main()
