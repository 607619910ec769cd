#!/usr/bin/env bash
# README's first command: set up (install + build), then run the default scenario for one minute of
# simulated survey in real time and print the run summary. DDS discovery stays on this machine unless
# ROS_LOCALHOST_ONLY is already set to something else.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
tools/setup.sh
export ROS_LOCALHOST_ONLY="${ROS_LOCALHOST_ONLY:-1}"
exec build/bin/hadald configs/scenarios/default.yaml --duration 60 "$@"
