#!/usr/bin/env bash
# README's second command: set up (install + build), then run every test (unit, integration against a
# real hadald over real DDS, and the Cyclone DDS interop check), then list what skipped and why. Tests keep
# DDS on this machine.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
tools/setup.sh -DHADAL_BUILD_TESTS=ON  # ON again after a demo's OFF (CMake keeps the last value)
export ROS_LOCALHOST_ONLY=1
jobs=$(nproc 2>/dev/null || echo 2)
# The JUnit report keeps each test's output (the last 64 KiB of a passed one's, where pytest lists its
# skips): tools/test_report.py lists every skipped test with its reason at the end, pass or fail.
status=0
ctest --test-dir build --output-on-failure -j"$jobs" --output-junit "$PWD/build/test-results.xml" \
  --test-output-size-passed 65536 --test-output-truncation head "$@" || status=$?
/usr/bin/python3 tools/test_report.py build/test-results.xml || true
exit "$status"
