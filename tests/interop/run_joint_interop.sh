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
start_lockstep_hadald "$REPO_ROOT/tests/integration/scenarios/arm.yaml"
probe_lockstep_hadald --vehicle arm --controller forearm_effort --joint 1 --joints 2 --effort 0.5
echo "PASS: joint interop: a Cyclone DDS node commanded a joint controller and read JointState with ROS 2 types"
