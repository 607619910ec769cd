#!/usr/bin/env bash
# README's second command: set up (install + build), then run every test (unit, integration against a
# real hadald over real DDS, and the Cyclone DDS interop check). Tests keep DDS on this machine.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
tools/setup.sh -DHADAL_BUILD_TESTS=ON  # ON again after a demo's OFF (CMake keeps the last value)
export ROS_LOCALHOST_ONLY=1
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir build --output-on-failure -j"$jobs" "$@"
