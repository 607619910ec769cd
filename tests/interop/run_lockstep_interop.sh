#!/usr/bin/env bash
# ROS 2 commanding checked for real: hadal-ros2-lockstep-probe (Cyclone DDS, the independently written ROS 2
# types of ros2_types.idl) commands a lockstep hadald on the default scenario with
# std_msgs/Float64MultiArray setpoints and hadal_msgs/StepRequest steps and resets (ros2_lockstep_probe.c
# lists its checks).
#
# usage: run_lockstep_interop.sh HADALD PROBE REPO_ROOT
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/interop_lib.sh"
INTEROP_NAME="lockstep interop"
HADALD=$1
PROBE=$2
REPO_ROOT=$3
[[ -x "$HADALD" && -x "$PROBE" ]] || fail "hadald or the probe is missing"

reserve_interop_domain
make_work_dir hadal-lockstep-interop
isolate_discovery
start_lockstep_hadald "$REPO_ROOT/configs/scenarios/default.yaml" --no-cameras

# The default AUV (configs/vehicles/torpedo_auv.yaml): 3 thrusters, 500 Hz physics. 20 requests of 50
# steps at 0.8 main thrust: 2 s from rest, ~0.8 m (hadal's own clients see the same); 0.3 m is a floor.
probe_lockstep_hadald --vehicle auv --setpoints 0.8,0,0 --requests 20 --steps 50 --step-size 0.002 --min-advance 0.3
echo "PASS: lockstep interop: a Cyclone DDS node stepped, commanded and reset hadald with ROS 2 types"
