# Sourced by the interop scripts beside it (run_*.sh): the set-up they share. Each run takes its own DDS
# domain 100..199 (../reserve_domain.sh) and keeps discovery on loopback, so concurrent tests never see
# each other; its files go to a scratch directory $WORK that is removed on exit, after the one process it
# started in the background ($BACKGROUND_PID: a probe, or a lockstep hadald) is stopped.
# Set INTEROP_NAME (what "FAIL: <name>: ..." says), HADALD and REPO_ROOT (and PROBE for start_probe) first.

source "$(dirname "${BASH_SOURCE[0]}")/../reserve_domain.sh"

BACKGROUND_PID=""

# "usage: <script> ARGUMENTS..." on stderr, exit 2.
usage() {
  echo "usage: $0 $*" >&2
  exit 2
}

fail() {
  echo "FAIL: $INTEROP_NAME: $*" >&2
  exit 1
}

# require_executable PATH WHAT
require_executable() {
  [[ -x "$1" ]] || fail "$2 not found or not executable: $1"
}

require_scenario() {
  [[ -f "$1" ]] || fail "scenario not found: $1"
}

# Sets DOMAIN, held on fd 9 for the life of the script: children that must not keep it get `9>&-`.
reserve_interop_domain() {
  reserve_domain 100 199 || fail "no free DDS domain in 100..199 (all /tmp/hadal-dds-domain-*.lock held)"
}

# Loopback discovery for every DDS vendor (ROS_LOCALHOST_ONLY is read by hadald and the Cyclone probes),
# and no user configuration that could widen it.
isolate_discovery() {
  export ROS_LOCALHOST_ONLY=1
  unset CYCLONEDDS_URI ROS_AUTOMATIC_DISCOVERY_RANGE
}

clean_up() {
  if [[ -n "$BACKGROUND_PID" ]] && kill -0 "$BACKGROUND_PID" 2>/dev/null; then
    kill "$BACKGROUND_PID" 2>/dev/null || true
    wait "$BACKGROUND_PID" 2>/dev/null || true
  fi
  rm -rf "$WORK"
}

# make_work_dir NAME: WORK=$TMPDIR/NAME.XXXXXX, removed on exit (clean_up).
make_work_dir() {
  WORK=$(mktemp -d "${TMPDIR:-/tmp}/$1.XXXXXX")
  trap clean_up EXIT
}

# start_probe ARGS...: $PROBE in the background (stdout $WORK/probe.json, stderr $WORK/probe.err); returns
# once it says "ready" on stderr (its readers and writers exist), so that hadald's discovery wait finds it.
start_probe() {
  "$PROBE" "$@" >"$WORK/probe.json" 2>"$WORK/probe.err" 9>&- &
  BACKGROUND_PID=$!
  for _ in $(seq 1 200); do
    grep -q "ready" "$WORK/probe.err" 2>/dev/null && break
    kill -0 "$BACKGROUND_PID" 2>/dev/null || break
    sleep 0.05
  done
  if ! grep -q "ready" "$WORK/probe.err" 2>/dev/null; then
    cat "$WORK/probe.err" >&2
    fail "the probe did not get ready within 10 s"
  fi
}

# Sets PROBE_RC once the probe has ended by itself.
wait_for_probe() {
  PROBE_RC=0
  wait "$BACKGROUND_PID" || PROBE_RC=$?
  BACKGROUND_PID=""
}

# run_hadald ARGS...: hadald in the foreground from REPO_ROOT (stdout $WORK/hadald.out, stderr
# $WORK/hadald.err); sets HADALD_RC.
run_hadald() {
  HADALD_RC=0
  (cd "$REPO_ROOT" && "$HADALD" "$@") >"$WORK/hadald.out" 2>"$WORK/hadald.err" 9>&- || HADALD_RC=$?
}

show_logs() {
  echo "--- hadald stdout ---" >&2; cat "$WORK/hadald.out" >&2
  echo "--- hadald stderr ---" >&2; cat "$WORK/hadald.err" >&2
  if [[ -f "$WORK/probe.json" ]]; then
    echo "--- probe stdout (JSON) ---" >&2; cat "$WORK/probe.json" >&2
    echo "--- probe stderr ---" >&2; cat "$WORK/probe.err" >&2
  fi
}

# start_lockstep_hadald SCENARIO ARGS...: hadald in lockstep on $DOMAIN in the background (its output in
# $WORK/hadald.log), stopped on exit.
start_lockstep_hadald() {
  local scenario=$1
  shift
  "$HADALD" "$scenario" --mode lockstep --domain-id "$DOMAIN" "$@" --no-status-line >"$WORK/hadald.log" 2>&1 9>&- &
  BACKGROUND_PID=$!
}

# probe_lockstep_hadald ARGS...: $PROBE in the foreground against the hadald start_lockstep_hadald started;
# fails (showing hadald's log) if the probe does, or if hadald did not outlive it.
probe_lockstep_hadald() {
  local rc=0
  "$PROBE" --domain-id "$DOMAIN" "$@" 9>&- || rc=$?
  if [[ $rc -ne 0 ]]; then
    echo "--- hadald ---" >&2; cat "$WORK/hadald.log" >&2
    fail "the probe exited with $rc"
  fi
  kill -0 "$BACKGROUND_PID" 2>/dev/null || fail "hadald is not running any more"
}

fail_unless_hadald_succeeded() {
  [[ $HADALD_RC -eq 0 ]] || { show_logs; fail "hadald exited with $HADALD_RC"; }
}
