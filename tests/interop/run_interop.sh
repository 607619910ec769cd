#!/usr/bin/env bash
# ROS 2 wire-compatibility check: Cyclone DDS (hadal-ros2-probe) reads hadald's rt/clock,
# rt/<vehicle>/odometry and the default AUV's sensor topics (depth, imu, magnetometer, gps, dvl, altimeter)
# by their ROS 2 type names and commands rt/<vehicle>/actuators/commands. Decoded sensor values are
# checked against physics (the AUV starts level at 96 m depth, ~4 m above the sediment plain at
# z = -100 m, heading east, at 43 N 5 E), which also catches layout mistakes that a type-name match
# alone would not.
#
# usage: run_interop.sh HADALD PROBE REPO_ROOT [MODE] [DURATION_S]
#   MODE        fast (default) or realtime
#   DURATION_S  sim seconds hadald runs (default 5)
#
# Discovery stays on loopback (ROS_LOCALHOST_ONLY=1 for both processes). Each run takes its own DDS
# domain 100..199 by holding /tmp/hadal-dds-domain-<N>.lock, so concurrent tests never see each other.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/interop_lib.sh"

(( $# >= 3 )) || usage "HADALD PROBE REPO_ROOT [fast|realtime] [DURATION_S]"
HADALD=$1
PROBE=$2
REPO_ROOT=$3
MODE=${4:-fast}
DURATION=${5:-5}
SCENARIO="$REPO_ROOT/configs/scenarios/default.yaml"
VEHICLE=auv
SETPOINTS=0.5,0,0
PYTHON=/usr/bin/python3
INTEROP_NAME="interop ($MODE)"

require_executable "$HADALD" hadald
require_executable "$PROBE" probe
require_scenario "$SCENARIO"
case "$MODE" in fast | realtime) ;; *) fail "mode must be fast or realtime (got $MODE)" ;; esac

reserve_interop_domain
make_work_dir hadal-interop
isolate_discovery

echo "interop ($MODE): domain $DOMAIN, hadald $HADALD, probe $PROBE"

# The probe first, so hadald's discovery wait finds it: in fast mode hadald waits ~1 s for discovery and
# then runs the whole scenario in a fraction of a second. The probe stops by itself once the samples stop
# (--idle), or after --seconds at the latest.
start_probe --domain-id "$DOMAIN" --vehicle "$VEHICLE" --seconds 60 --idle 2 --publish-setpoints "$SETPOINTS"

# Discovery between the two vendors takes ~50-100 ms, but in roughly one start in four it takes ~1.05 s:
# Cyclone answers hadald's first SPDP announcement within ~0.2 ms, Fast DDS 2.9.1 apparently ignores
# that answer (seen on loopback captures: it never replies to it), and Cyclone repeats its SPDP to a
# new participant only 1 s later (Fast DDS's own repeated announcements get no answer, as Cyclone
# already knows the participant). hadald's default discovery wait in fast mode (2 s) covers that, so
# the fast run uses the exact acceptance command line (no --discovery-wait). Realtime mode does not
# wait; the first ~1 s of samples may then be missed, which the checks below tolerate.
EXTRA_ARGS=()
HADALD_START=$(date +%s.%N)

run_hadald "$SCENARIO" --duration "$DURATION" --mode "$MODE" --domain-id "$DOMAIN" --no-status-line \
  "${EXTRA_ARGS[@]}"
wait_for_probe
fail_unless_hadald_succeeded

echo "probe exit code: $PROBE_RC"
cat "$WORK/probe.json"

if ! "$PYTHON" - "$WORK/probe.json" "$SETPOINTS" "$HADALD_START" "$MODE" "$DURATION" <<'EOF'; then
import json
import math
import sys

path, setpoints, hadald_start = sys.argv[1], [float(x) for x in sys.argv[2].split(",")], float(sys.argv[3])
mode, duration = sys.argv[4], float(sys.argv[5])
try:
    with open(path) as f:
        r = json.load(f)
except (OSError, ValueError) as e:
    print(f"probe output is not one JSON object: {e}", file=sys.stderr)
    sys.exit(1)

problems = []
def check(cond, what):
    if not cond:
        problems.append(what)

clock, odom = r.get("clock", {}), r.get("odometry", {})
remote = {(p["topic"], p["type"]) for p in r.get("remote_publications", [])}
if not remote:
    problems.append("Cyclone discovered no hadald publication at all (discovery failed)")
check(clock.get("count", 0) > 0,
      "no rt/clock sample reached Cyclone (type rosgraph_msgs::msg::dds_::Clock_)")
check(odom.get("count", 0) > 0,
      "no reliable rt/auv/odometry sample reached Cyclone (type nav_msgs::msg::dds_::Odometry_)")
check(odom.get("best_effort_count", 0) > 0,
      "no rt/auv/odometry sample reached Cyclone's best-effort (sensor-data QoS) reader")
check(r.get("sane") is True, f"values not sane: {odom.get('insane_reason') or 'see JSON'}"
      f" (clock non-decreasing: {clock.get('non_decreasing')})")
last = odom.get("last") or {}
check(last.get("frame_id") == "world", f"odometry frame_id is {last.get('frame_id')!r}, expected 'world'")
check(last.get("child_frame_id") == "auv/base_link",
      f"odometry child_frame_id is {last.get('child_frame_id')!r}, expected 'auv/base_link'")
sp = r.get("setpoints", {})
check(sp.get("first_match_s") is not None,
      "hadald's reader on rt/auv/actuators/commands (std_msgs::msg::dds_::Float64MultiArray_) never "
      "matched Cyclone's writer")
ts = r.get("thruster_state", {})
check(ts.get("client_commanded", 0) > 0 and ts.get("setpoints_echoed") is True,
      f"setpoints {setpoints} written by Cyclone never showed up in rt/auv/thrusters/state as client "
      f"commands (client_commanded={ts.get('client_commanded')}, last={ts.get('last_setpoints')}, "
      f"rejected_commands={r.get('status', {}).get('rejected_commands')}, "
      f"last_error={r.get('status', {}).get('last_error')!r})")
expected_types = {"rt/clock": "rosgraph_msgs::msg::dds_::Clock_",
                  "rt/auv/odometry": "nav_msgs::msg::dds_::Odometry_",
                  "rt/auv/depth": "sensor_msgs::msg::dds_::FluidPressure_",
                  "rt/auv/imu": "sensor_msgs::msg::dds_::Imu_",
                  "rt/auv/magnetometer": "sensor_msgs::msg::dds_::MagneticField_",
                  "rt/auv/gps": "sensor_msgs::msg::dds_::NavSatFix_",
                  "rt/auv/dvl": "marine_acoustic_msgs::msg::dds_::Dvl_",
                  "rt/auv/altimeter": "sensor_msgs::msg::dds_::Range_"}
for topic, ty in remote:
    if topic in expected_types and ty != expected_types[topic]:
        problems.append(f"hadald publishes {topic} as type {ty!r}, ROS 2 expects {expected_types[topic]!r}")

# Sensor topics of the default AUV (configs/vehicles/torpedo_auv.yaml) and their rates [Hz].
SENSOR_RATES_HZ = {"depth": 10.0, "imu": 100.0, "magnetometer": 20.0, "gps": 1.0, "dvl": 5.0, "altimeter": 10.0}
sensors = r.get("sensors", {})

def check_sensor_stream(name, rate_hz):
    """Counts, stamps and frame of one sensor topic; returns its JSON entry, or None when no sample came."""
    m = sensors.get(name, {})
    topic = f"rt/auv/{name}"
    if m.get("count", 0) == 0:
        problems.append(f"no reliable {topic} sample reached Cyclone (probe's type {m.get('type')}, ROS 2's "
                        f"{expected_types[topic]}; hadald offers "
                        f"{sorted(f'{t} ({ty})' for t, ty in remote if t.startswith('rt/auv/'))})")
        return None
    check(m.get("type") == expected_types[topic], f"{topic}: probe read type {m.get('type')!r}")
    check(m.get("best_effort_count", 0) > 0,
          f"no {topic} sample reached Cyclone's best-effort (sensor-data QoS) reader")
    check(m.get("frame_id") == f"auv/{name}" and m.get("frame_id_changes") == 0,
          f"{topic} frame_id is {m.get('frame_id')!r} ({m.get('frame_id_changes')} changes), "
          f"expected 'auv/{name}' (a sensor's default frame_id is <vehicle>/<name>)")
    check(m.get("stamps_not_increasing") == 0,
          f"{topic}: {m.get('stamps_not_increasing')} stamps not after the one before (or nanosec >= 1e9)")
    check(m.get("non_finite_samples") == 0, f"{topic}: {m.get('non_finite_samples')} samples with NaN/Inf")
    # hadald samples a sensor at t = k / rate, k = 1 .. rate * duration (nothing at t = 0), so a complete
    # stream has rate * duration samples and ends at the last sim instant. At most that many arrive (a
    # duplicate or a doubled rate fails here). In fast mode hadald waits for discovery before t = 0, so
    # nothing is missed for discovery; 10 % slack covers UDP datagrams Cyclone loses when the CPU is
    # busy and hadald's KEEP_LAST(10) writer history can no longer repair (fast mode writes 100 IMU
    # samples per ~1-2 ms of wall time). In realtime mode hadald does not wait: up to ~1.05 s of samples
    # may precede discovery (see the comment above EXTRA_ARGS), so 1.2 s less is expected, with the same 10 %.
    expected = round(rate_hz * duration)
    discovery_slack_s = 0.0 if mode == "fast" else 1.2
    minimum = max(1, math.floor(0.9 * rate_hz * (duration - discovery_slack_s)))
    count = m["count"]
    check(minimum <= count <= expected,
          f"{topic}: {count} samples, expected {minimum}..{expected} at {rate_hz:g} Hz over {duration:g} s")
    first, last = m["first_stamp"]["s"], m["last_stamp"]["s"]
    check(abs(last - duration) < 0.5 / rate_hz,
          f"{topic}: last stamp {last:.6f} s, expected {duration:g} s (the stream stopped early?)")
    check(count <= round((last - first) * rate_hz) + 1,
          f"{topic}: {count} samples within stamps {first:.6f}..{last:.6f} s: more than {rate_hz:g} Hz allows")
    return m

def within(summary, lo, hi):
    """True when every sample's value lay in [lo, hi] (the summary's min and max do)."""
    return (summary or {}).get("n", 0) > 0 and summary.get("non_finite") == 0 and \
        lo <= summary["min"] and summary["max"] <= hi

def span(summary, unit=""):
    s = summary or {}
    return f"{s.get('min')}..{s.get('max')}{unit} over {s.get('n')} samples ({s.get('non_finite')} non-finite)"

# Depth (sensor_msgs/FluidPressure, absolute [Pa]): the sensor sits 0.05 m above the hull centre, which
# starts at 96 m depth; the AUV trims ~1.3 deg nose down and moves ~1 m/s, so it stays within a few cm
# of 95.95 m over a few seconds. p = p_atm + rho g d with p_atm 101325 Pa, rho 1025 kg/m^3, g 9.80665:
# 1.0658e6 Pa; +-2 m (+-20 kPa) bounds it far beyond motion and the 50 Pa noise, yet would catch a gauge
# pressure (no p_atm: 9.645e5), a bar/dbar scale or a misread double.
P_ATM, RHO, G = 101325.0, 1025.0, 9.80665
m = check_sensor_stream("depth", SENSOR_RATES_HZ["depth"])
if m:
    lo, hi = P_ATM + RHO * G * 93.95, P_ATM + RHO * G * 97.95
    check(within(m.get("fluid_pressure"), lo, hi),
          f"rt/auv/depth fluid_pressure {span(m.get('fluid_pressure'), ' Pa')}, expected {lo:.0f}..{hi:.0f} Pa "
          f"(p_atm + rho g (96 +- 2) m)")
    # variance 0 means "unknown" in ROS; hadald knows its noise (stddev^2 + resolution^2 / 12).
    check((m.get("variance") or 0) > 0, f"rt/auv/depth variance {m.get('variance')}, expected > 0")

# IMU (sensor_msgs/Imu, body frame x forward, y left, z up): specific force f = a - g. The AUV starts from
# rest and accelerates at < 0.3 m/s^2 (~8 N of thrust on 30 kg plus ~1 kg added mass in surge), so |f| = 9.81 +- 0.5 m/s^2 on every
# sample (noise: 3.3e-3 m/s^2 per sample, vibration 1 mg); nearly level, so f points up: f_z > 9 m/s^2
# (a z-down or g-subtracted convention fails). Angular rates stay well below 0.3 rad/s (17 deg/s; seen
# <= 0.12 rad/s while the AUV trims after release); a deg/s value would exceed it. No orientation
# estimate: orientation_covariance[0] = -1 (REP 145) on every sample; noise covariances are known (> 0).
m = check_sensor_stream("imu", SENSOR_RATES_HZ["imu"])
if m:
    check(within(m.get("specific_force_norm"), G - 0.5, G + 0.5),
          f"rt/auv/imu |linear_acceleration| {span(m.get('specific_force_norm'), ' m/s^2')}, expected 9.81 +- 0.5")
    f = m.get("linear_acceleration") or [0, 0, 0]
    check(f[2] > 9.0, f"rt/auv/imu last linear_acceleration {f}: z should be ~ +9.8 m/s^2 (z up, at rest)")
    check(within(m.get("angular_rate_norm"), 0.0, 0.3),
          f"rt/auv/imu |angular_velocity| {span(m.get('angular_rate_norm'), ' rad/s')}, expected < 0.3 rad/s")
    check(m.get("orientation_reported") == 0,
          f"rt/auv/imu: {m.get('orientation_reported')} samples claim an orientation "
          f"(orientation_covariance[0] != -1)")
    check(all(v > 0 for v in (m.get("linear_acceleration_variance") or [0]) + (m.get("angular_velocity_variance") or [0])),
          f"rt/auv/imu covariance diagonals {m.get('linear_acceleration_variance')} / "
          f"{m.get('angular_velocity_variance')}, expected > 0")

# Magnetometer (sensor_msgs/MagneticField, tesla, body frame): WMM2025 at 43 N 5 E, 96 m below sea level,
# mid-2026: |B| ~ 46.7 uT, inclination ~ +59 deg (pointing down). The hard-iron
# dipole of the motor adds ~6 nT, noise 5 nT. |B| in 40..52 uT; with the AUV level and heading east
# (yaw 0 in ENU: x east, y north, z up) the field points north and down: B_y > 0, B_z < 0. A gauss or
# nanotesla scale, or a NED/ENU mix-up, fails.
m = check_sensor_stream("magnetometer", SENSOR_RATES_HZ["magnetometer"])
if m:
    check(within(m.get("field_norm_ut"), 40.0, 52.0),
          f"rt/auv/magnetometer |B| {span(m.get('field_norm_ut'), ' uT')}, expected 40..52 uT (WMM2025 ~46.7)")
    b = m.get("magnetic_field") or [0, 0, 0]
    check(b[1] > 0 and b[2] < 0, f"rt/auv/magnetometer last field {b} T: expected north (+y) and down (-z)")

# GPS (sensor_msgs/NavSatFix): the antenna is ~96 m under water, so no fix: status NO_FIX (-1) on every
# sample and no position (hadald sends NaN latitude/longitude/altitude). service = SERVICE_GPS (1) and
# position_covariance_type = COVARIANCE_TYPE_DIAGONAL_KNOWN (2) are what hadald writes; a uint16 after an
# int8 and a uint8 after a double array, they fail if the probe's XCDR1 alignment differed from hadald's.
m = check_sensor_stream("gps", SENSOR_RATES_HZ["gps"])
if m:
    st = m.get("status") or {}
    check(st.get("n", 0) > 0 and st.get("min") == -1 and st.get("max") == -1,
          f"rt/auv/gps status {span(st)}, expected NO_FIX (-1) under water")
    check(m.get("samples_with_position") == 0,
          f"rt/auv/gps: {m.get('samples_with_position')} samples carry a position without a fix")
    check(m.get("service") == 1, f"rt/auv/gps status.service {m.get('service')}, expected SERVICE_GPS (1)")
    check(m.get("position_covariance_type") == 2,
          f"rt/auv/gps position_covariance_type {m.get('position_covariance_type')}, expected DIAGONAL_KNOWN (2)")

# DVL (marine_acoustic_msgs/Dvl; frame S: z down along the DVL axis, x forward, y starboard). The
# transducer is 0.0775 m below the hull centre, so ~3.9 m above the sediment plain (z = -100 m, 60 m
# around the start, tilted 1 deg): inside the Workhorse 600 preset's bottom-lock window (0.7-90 m) and,
# with no dropout configured, every ping is bottom track (velocity_mode 1) with all 4 beams, altitude
# 4 +- 1 m (the lander 12 m ahead stays outside the beams' footprint in these seconds).
# The AUV accelerates from rest to < 1.1 m/s (its cruise speed at 0.6 thrust): |velocity| < 2 m/s. The
# bottom-track velocity is the DVL's own over the ground, so it must agree with the odometry's body
# velocity at the same instant (both stream to the last sim instant), turned into S (y and z flipped):
# the DVL's bias (2 mm/s, 1 sigma), noise (~7 mm/s on x, y per ping from 5 mm/s per beam at 30 deg)
# and the lever arm (w x r with r ~0.21 m, |w| ~0.01 rad/s at the end of the run: ~2 mm/s) stay far below
# 0.05 m/s. Sound speed: the DVL measures it
# (no assumed value), seawater is 1400..1600 m/s. altitude = mean(range) cos(30 deg) for the last ping
# (the preset's beam tilt). sound_speed (a float32 after a uint8) and range (float64[4] after two
# booleans and a Vector3[4]) also check the probe's XCDR1 alignment against hadald's.
m = check_sensor_stream("dvl", SENSOR_RATES_HZ["dvl"])
if m:
    check(m.get("mode_bottom") == m["count"],
          f"rt/auv/dvl: {m.get('mode_bottom')} of {m['count']} pings in bottom track (water track "
          f"{m.get('mode_water')}, none {m.get('mode_other')}), expected all ~4 m above the seabed")
    nb = m.get("num_good_beams") or {}
    check(nb.get("n", 0) > 0 and nb.get("min") == 4 and nb.get("max") == 4,
          f"rt/auv/dvl num_good_beams {span(nb)}, expected 4 on every ping")
    check(within(m.get("altitude"), 3.0, 5.0),
          f"rt/auv/dvl altitude {span(m.get('altitude'), ' m')}, expected 4 +- 1 m")
    check(within(m.get("speed"), 0.0, 2.0), f"rt/auv/dvl |velocity| {span(m.get('speed'), ' m/s')}, expected < 2 m/s")
    v_dvl = m.get("velocity") or [math.nan] * 3
    v_odom = (odom.get("last") or {}).get("linear_velocity") or [math.nan] * 3
    v_odom_S = [v_odom[0], -v_odom[1], -v_odom[2]]
    same_instant = (odom.get("last") or {}).get("stamp") == m.get("last_stamp")
    check(same_instant and all(abs(a - b) < 0.05 for a, b in zip(v_dvl, v_odom_S)),
          f"rt/auv/dvl last velocity {v_dvl} m/s (stamp {m.get('last_stamp')}) vs odometry body velocity in S "
          f"{v_odom_S} (stamp {(odom.get('last') or {}).get('stamp')}): expected the same instant and within 0.05 m/s")
    check(1400.0 <= (m.get("sound_speed") or 0) <= 1600.0,
          f"rt/auv/dvl sound_speed {m.get('sound_speed')} m/s, expected 1400..1600 (seawater)")
    ranges = m.get("range") or []
    check(m.get("beam_ranges_valid") is True and len(ranges) == 4 and all(r is not None for r in ranges) and
          abs(sum(ranges) / 4 * math.cos(math.radians(30.0)) - (m.get("altitude") or {}).get("last", math.nan)) < 0.01,
          f"rt/auv/dvl last beam ranges {ranges} (valid {m.get('beam_ranges_valid')}): mean x cos 30 deg should be "
          f"the altitude {(m.get('altitude') or {}).get('last')} m")

# Altimeter (sensor_msgs/Range, one acoustic beam straight down): 0.0775 m below the hull centre, ~3.9 m
# above the seabed, so range 4 +- 1 m on every sample, finite and inside [min_range, max_range]. The
# limits, radiation type and beam width are the default AUV's configuration as hadald writes it (0.3 m,
# 100 m, ULTRASOUND = 0, 6 deg); as float32s after a uint8 they also check the XCDR1 alignment.
m = check_sensor_stream("altimeter", SENSOR_RATES_HZ["altimeter"])
if m:
    check(within(m.get("range"), 3.0, 5.0), f"rt/auv/altimeter range {span(m.get('range'), ' m')}, expected 4 +- 1 m")
    check(m.get("range_outside_limits") == 0,
          f"rt/auv/altimeter: {m.get('range_outside_limits')} ranges outside [min_range, max_range]")
    check(abs((m.get("min_range") or 0) - 0.3) < 1e-6 and m.get("max_range") == 100.0,
          f"rt/auv/altimeter limits [{m.get('min_range')}, {m.get('max_range')}] m, expected [0.3, 100]")
    check(m.get("radiation_type") == 0, f"rt/auv/altimeter radiation_type {m.get('radiation_type')}, expected ULTRASOUND (0)")
    check(abs((m.get("field_of_view") or 0) - math.radians(6.0)) < 1e-6,
          f"rt/auv/altimeter field_of_view {m.get('field_of_view')} rad, expected 6 deg (0.1047 rad)")

def after_start(t):
    return "never" if t is None else f"{r['start_unix_s'] + t - hadald_start:.3f} s"
if "start_unix_s" in r:
    print(f"discovery: Cyclone matched hadald's rt/clock writer {after_start(clock.get('first_match_s'))} and "
          f"its setpoints reader {after_start(sp.get('first_match_s'))} after hadald was started; first "
          f"clock sample {after_start(clock.get('first_sample_s'))}")

if problems:
    for p in problems:
        print(f"  - {p}", file=sys.stderr)
    sys.exit(1)
print(f"ok: {clock['count']} clock samples (sim {clock['first']['s']:.3f} .. {clock['last']['s']:.3f} s), "
      f"{odom['count']} odometry samples ({odom['best_effort_count']} best effort), "
      f"{ts['client_commanded']} thruster states commanded by Cyclone")
s = sensors
print(f"ok: sensors: depth {s['depth']['count']} ({s['depth']['best_effort_count']} best effort), "
      f"p {s['depth']['fluid_pressure']['mean']:.0f} Pa; "
      f"imu {s['imu']['count']} ({s['imu']['best_effort_count']}), "
      f"|f| {s['imu']['specific_force_norm']['min']:.3f}..{s['imu']['specific_force_norm']['max']:.3f} m/s^2; "
      f"magnetometer {s['magnetometer']['count']} ({s['magnetometer']['best_effort_count']}), "
      f"|B| {s['magnetometer']['field_norm_ut']['mean']:.2f} uT; "
      f"gps {s['gps']['count']} ({s['gps']['best_effort_count']}), status {s['gps']['status']['last']:.0f}; "
      f"dvl {s['dvl']['count']} ({s['dvl']['best_effort_count']}), bottom track {s['dvl']['mode_bottom']}, "
      f"altitude {s['dvl']['altitude']['mean']:.2f} m, |v| last {s['dvl']['speed']['last']:.3f} m/s; "
      f"altimeter {s['altimeter']['count']} ({s['altimeter']['best_effort_count']}), "
      f"range {s['altimeter']['range']['mean']:.2f} m")
EOF
  show_logs
  fail "the probe's report does not show ROS 2 compatible topics (see above)"
fi
[[ $PROBE_RC -eq 0 ]] || { show_logs; fail "probe exited with $PROBE_RC"; }
echo "PASS: interop ($MODE): Cyclone DDS read hadald's ROS 2 topics (clock, odometry, sensors) and commanded its thrusters"
