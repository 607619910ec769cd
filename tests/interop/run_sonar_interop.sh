#!/usr/bin/env bash
# ROS 2 wire compatibility of the sonars: Cyclone DDS (hadal-ros2-probe --sonars) reads the three sonars of
# configs/scenarios/sonar_survey.yaml by their ROS 2 type names (marine_acoustic_msgs ProjectedSonarImage,
# SonarDetections, RawSonarImage) while hadald runs it in fast mode, and the decoded messages are checked
# against the scenario: beam and bin counts, array lengths that agree, the products' frequencies, a
# seawater sound speed, multibeam ranges that reach a seabed ~10 m below, side-scan sample rates and angles.
#
# usage: run_sonar_interop.sh HADALD PROBE REPO_ROOT [DURATION_S]   (default 3 sim seconds)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/interop_lib.sh"
INTEROP_NAME="sonar interop"

(( $# >= 3 )) || usage "HADALD PROBE REPO_ROOT [DURATION_S]"
HADALD=$1
PROBE=$2
REPO_ROOT=$3
DURATION=${4:-3}
SCENARIO="$REPO_ROOT/configs/scenarios/sonar_survey.yaml"
PYTHON=/usr/bin/python3

require_executable "$HADALD" hadald
require_executable "$PROBE" probe
require_scenario "$SCENARIO"

reserve_interop_domain
make_work_dir hadal-sonar-interop
isolate_discovery
echo "sonar interop: domain $DOMAIN, hadald $HADALD, probe $PROBE"

start_probe --domain-id "$DOMAIN" --vehicle auv --sonars --seconds 90 --idle 3

# Fast mode: hadald waits for discovery (2 s by default) before t = 0 and waits for every ping.
run_hadald "$SCENARIO" --duration "$DURATION" --mode fast --domain-id "$DOMAIN" --no-status-line
wait_for_probe
fail_unless_hadald_succeeded
cat "$WORK/probe.json"

"$PYTHON" - "$WORK/probe.json" "$DURATION" <<'EOF' || fail "see above"
import json
import math
import sys

r = json.load(open(sys.argv[1]))
duration = float(sys.argv[2])
sensors = r.get("sensors", {})
problems = []

def check(cond, what):
    if not cond:
        problems.append(what)

TYPES = {"fls": "marine_acoustic_msgs::msg::dds_::ProjectedSonarImage_",
         "multibeam": "marine_acoustic_msgs::msg::dds_::SonarDetections_",
         "sidescan/port": "marine_acoustic_msgs::msg::dds_::RawSonarImage_",
         "sidescan/starboard": "marine_acoustic_msgs::msg::dds_::RawSonarImage_"}
remote = {p["topic"]: p["type"] for p in r.get("remote_publications", [])}
RATE_HZ = 5.0  # every sonar of the scenario
for name, ros_type in TYPES.items():
    topic = f"rt/auv/{name}"
    m = sensors.get(name, {})
    check(remote.get(topic) == ros_type, f"hadald offers {topic} as {remote.get(topic)!r}, ROS 2 expects {ros_type!r}")
    expected = round(RATE_HZ * duration)
    check(math.floor(0.9 * expected) <= m.get("count", 0) <= expected,
          f"{topic}: {m.get('count', 0)} samples on the reliable reader, expected ~{expected}")
    check(m.get("best_effort_count", 0) > 0, f"{topic}: nothing on the best-effort (sensor-data QoS) reader")
    if m.get("count", 0) == 0:
        continue
    check(m.get("frame_id") == "auv/sidescan" if name.startswith("sidescan") else m.get("frame_id") == f"auv/{name}",
          f"{topic}: frame_id {m.get('frame_id')!r}")
    check(m.get("stamps_not_increasing") == 0 and m.get("non_finite_samples") == 0,
          f"{topic}: stamps not increasing or non-finite numbers")
    check(m.get("mismatched_lengths") == 0, f"{topic}: array lengths that disagree")
    check(1400.0 < (m.get("sound_speed") or 0) < 1600.0, f"{topic}: sound speed {m.get('sound_speed')}")

fls = sensors.get("fls", {})
if fls.get("count"):
    # oculus_m750d with 256 beams: 750 kHz, 512 bins, uint8 samples, the seabed in view.
    check(fls.get("beams") == 256 and fls.get("bins") == 512 and fls.get("dtype") == 0 and
          fls.get("image_bytes") == 256 * 512, f"fls: {fls.get('beams')} beams x {fls.get('bins')} bins, dtype "
          f"{fls.get('dtype')}, {fls.get('image_bytes')} bytes")
    check(fls.get("frequency") == 750000.0, f"fls: frequency {fls.get('frequency')}")
    check(fls.get("nonzero_samples", 0) > 5000, f"fls: only {fls.get('nonzero_samples')} non-zero samples")
mb = sensors.get("multibeam", {})
if mb.get("count"):
    # r2sonic_2024: 256 beams over 130 deg, 10 m above a plain: nadir ~10 m, the outer beams (65 deg) ~24 m.
    det, rng = mb.get("detected_beams") or {}, mb.get("detected_range") or {}
    check(mb.get("beams") == 256 and mb.get("frequency") == 400000.0,
          f"multibeam: {mb.get('beams')} beams at {mb.get('frequency')} Hz")
    check((det.get("min") or 0) > 200, f"multibeam: as few as {det.get('min')} of 256 beams detected the seabed")
    check(8.5 < (rng.get("min") or 0) and (rng.get("max") or 1e9) < 40.0,
          f"multibeam: ranges {rng.get('min')}..{rng.get('max')} m, expected ~10 m at nadir to ~24 m")
for side, sign in (("sidescan/port", -1.0), ("sidescan/starboard", 1.0)):
    m = sensors.get(side, {})
    if not m.get("count"):
        continue
    # edgetech_2205_850khz: 3000 samples over 0..75 m, rx angle -+(90 - 25) deg.
    check(m.get("beams") == 1 and m.get("bins") == 3000 and m.get("image_bytes") == 3000,
          f"{side}: {m.get('beams')} beam(s), {m.get('bins')} samples, {m.get('image_bytes')} bytes")
    bin_m = 75.0 / 3000
    check(abs(m.get("sample_rate", 0) - m.get("sound_speed", 0) / (2 * bin_m)) < 1.0,
          f"{side}: sample rate {m.get('sample_rate')} Hz, expected c / (2 bin)")
    check(abs((m.get("rx_angle") or 0) - sign * math.radians(65.0)) < 1e-5, f"{side}: rx angle {m.get('rx_angle')}")
    check(m.get("sample0") == 0, f"{side}: sample0 {m.get('sample0')} (the window starts at 0 m)")
    check(m.get("nonzero_samples", 0) > 500, f"{side}: only {m.get('nonzero_samples')} non-zero samples")
for p in problems:
    print("FAIL:", p, file=sys.stderr)
sys.exit(1 if problems else 0)
EOF
echo "PASS: sonar interop"
