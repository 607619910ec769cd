#!/usr/bin/env bash
# ROS 2 commanding checked for real: hadal-ros2-lockstep-probe (Cyclone DDS, the independently written ROS 2
# types of ros2_types.idl) commands a lockstep hadald on the default scenario with
# std_msgs/Float64MultiArray setpoints and hadal_msgs/StepRequest steps and resets (ros2_lockstep_probe.c
# lists its checks).
#
# usage: run_lockstep_interop.sh HADALD PROBE REPO_ROOT
set -euo pipefail
HADALD=$1
PROBE=$2
REPO_ROOT=$3
fail() { echo "FAIL: lockstep interop: $*" >&2; exit 1; }
[[ -x "$HADALD" && -x "$PROBE" ]] || fail "hadald or the probe is missing"

# A DDS domain of our own (fd 9), the same lock files as the other tests.
source "$(dirname "${BASH_SOURCE[0]}")/../reserve_domain.sh"
reserve_domain 100 199 || true
[[ -n "$DOMAIN" ]] || fail "no free DDS domain in 100..199"

export ROS_LOCALHOST_ONLY=1
unset CYCLONEDDS_URI ROS_AUTOMATIC_DISCOVERY_RANGE
LOG=$(mktemp "${TMPDIR:-/tmp}/hadal-lockstep-interop.XXXXXX")
"$HADALD" "$REPO_ROOT/configs/scenarios/default.yaml" --mode lockstep --no-cameras --domain-id "$DOMAIN" \
  --no-status-line >"$LOG" 2>&1 9>&- &
SERVER=$!
trap 'kill $SERVER 2>/dev/null || true; wait $SERVER 2>/dev/null || true; rm -f "$LOG"' EXIT

# The default AUV (configs/vehicles/torpedo_auv.yaml): 3 thrusters, 500 Hz physics. 20 requests of 50
# steps at 0.8 main thrust: 2 s from rest, ~0.8 m (hadal's own clients see the same); 0.3 m is a floor.
set +e
"$PROBE" --domain "$DOMAIN" --vehicle auv --setpoints 0.8,0,0 --requests 20 --steps 50 --step-size 0.002 \
  --min-advance 0.3 9>&-
RC=$?
set -e
if [[ $RC -ne 0 ]]; then
  echo "--- hadald ---" >&2; cat "$LOG" >&2
  fail "the probe exited with $RC"
fi
kill -0 $SERVER 2>/dev/null || fail "hadald is not running any more"
echo "PASS: lockstep interop: a Cyclone DDS node stepped, commanded and reset hadald with ROS 2 types"
