#!/usr/bin/env bash
# README's first command: set up what the demo runs (the packages hadald needs, not the tests' ones; hadald
# alone built), then run the default scenario for one minute of simulated survey in real time and print
# the run summary. DDS discovery stays on this machine unless ROS_LOCALHOST_ONLY is already set to
# something else. tools/test.sh afterwards builds the rest (it turns the tests back on).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
tools/setup.sh --only hadald -DHADAL_BUILD_TESTS=OFF
export ROS_LOCALHOST_ONLY="${ROS_LOCALHOST_ONLY:-1}"
exec build/bin/hadald configs/scenarios/default.yaml --duration 60 "$@"
