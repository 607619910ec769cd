#!/usr/bin/env bash
# ROS 2 joints checked for real: hadal-ros2-joint-probe (Cyclone DDS, the independently written ROS 2 types
# of ros2_types.idl) commands the effort controller of tests/integration/scenarios/arm.yaml in a lockstep
# hadald and reads its sensor_msgs/JointState (ros2_joint_probe.c lists its checks).
#
# usage: run_joint_interop.sh HADALD PROBE REPO_ROOT
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/interop_lib.sh"
INTEROP_NAME="joint interop"
HADALD=$1
PROBE=$2
REPO_ROOT=$3
[[ -x "$HADALD" && -x "$PROBE" ]] || fail "hadald or the probe is missing"

reserve_interop_domain
make_work_dir hadal-joint-interop
isolate_discovery
"$HADALD" "$REPO_ROOT/tests/integration/scenarios/arm.yaml" --mode lockstep --domain-id "$DOMAIN" \
  --no-status-line >"$WORK/hadald.log" 2>&1 9>&- &
BACKGROUND_PID=$!

RC=0
"$PROBE" --domain-id "$DOMAIN" --vehicle arm --controller forearm_effort --joint 1 --joints 2 --effort 0.5 9>&- ||
  RC=$?
if [[ $RC -ne 0 ]]; then
  echo "--- hadald ---" >&2; cat "$WORK/hadald.log" >&2
  fail "the probe exited with $RC"
fi
kill -0 "$BACKGROUND_PID" 2>/dev/null || fail "hadald is not running any more"
echo "PASS: joint interop: a Cyclone DDS node commanded a joint controller and read JointState with ROS 2 types"
