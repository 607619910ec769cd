#!/usr/bin/env bash
# Every tool takes the DDS domain as --domain-id (docs/ros2.md): the probes refuse the old --domain with a
# message naming the new flag, and exit non-zero before touching DDS.
#   run_domain_flag_check.sh PROBE...
set -uo pipefail
status=0
for probe in "$@"; do
  out=$("$probe" --domain 3 2>&1)
  rc=$?
  if [ "$rc" -eq 0 ] || [[ "$out" != *"--domain is now --domain-id"* ]]; then
    echo "$probe --domain 3: exit $rc, output: $out"
    status=1
  fi
done
exit $status
