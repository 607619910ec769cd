#!/usr/bin/env bash
# Regression recording (tests/regression/README.md): runs a lockstep hadald on a scenario, steps it with
# hadal-record-topics and writes one digest line per published topic, or compares them with a file.
#
# usage: record.sh BUILD_DIR CASE [--check | --write REASON]
#   CASE     default            configs/scenarios/default.yaml, 60 s (30 000 steps), its schedule only
#            two_vehicles       tests/regression/scenarios/two_vehicles_all_sensors.yaml, 20 s, with
#                               client commands and a watchdog timeout
#   --write  (re)writes tests/regression/digests/CASE/SIGNATURE.txt, this machine's file, and adds a line
#            to tests/regression/RECORDS.md: the date, case, signature, the topics whose digests changed
#            (or "new file") and REASON, why they changed (required; the same words go in the commit)
#   --check  (default) records and compares with tests/regression/digests/CASE/SIGNATURE.txt topic by
#            topic; skips (exit 77) when no digests were recorded on a machine of this floating-point
#            signature
#
# The digests are only comparable between builds on machines with the same signature: glibc picks its
# libm kernels and Embree its traversal kernels by CPU feature (FMA, AVX2, AVX-512), which can change the
# last bits of a result, and the vendors' approximate reciprocals differ (AMD's and Intel's AVX-512 camera
# depths differ in the last bits). The signature is the CPU vendor and the x86 feature flags among those
# that steer such choices; each signature has its own file, e.g.
# digests/default/x86_64-GenuineIntel-sse4_2-avx-fma-avx2-avx512f.txt.
# Completeness: every topic's recorded count must equal the count hadald reports having published.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
USAGE="usage: record.sh BUILD_DIR CASE [--check | --write REASON]"
BUILD=${1:?$USAGE}
CASE=${2:?$USAGE}
MODE=${3:---check}
REASON=${4:-}
case "$MODE" in
  --check) ;;
  --write) [[ -n "$REASON" ]] || { echo "record.sh: --write needs a REASON: why the digests change ($USAGE)" >&2; exit 2; } ;;
  *) echo "record.sh: $MODE? $USAGE" >&2; exit 2 ;;
esac
PYTHON=/usr/bin/python3
export ROS_LOCALHOST_ONLY=1

case "$CASE" in
  default)
    SCENARIO=configs/scenarios/default.yaml
    ARGS=(--steps 30000)
    ;;
  two_vehicles)
    SCENARIO=tests/regression/scenarios/two_vehicles_all_sensors.yaml
    # The buoy is commanded from 1 s on (client setpoints; its watchdog of 0.5 s fires between 6 s and
    # 7.5 s); the AUV leaves its schedule for client setpoints at 14 s.
    ARGS=(--steps 10000
          --command buoy@500=0.6,0.4 --command buoy@1500=0.8,-0.3 --command buoy@2750=0.2,0.9
          --command buoy@3750=-0.5,-0.5 --command buoy@5000=0.7,0.7
          --command auv@7000=0.9,-0.3,0.5 --command buoy@7000=0.3,0.6
          --command auv@7400=0.6,0.2,-0.2 --command buoy@7400=0.5,0.5
          --command auv@7800=0.6,0.0,0.0 --command buoy@7800=0.4,0.4)
    ;;
  *) echo "record.sh: unknown case $CASE (default, two_vehicles)" >&2; exit 2 ;;
esac

signature() {
  local flags vendor
  flags=$(grep -m1 '^flags' /proc/cpuinfo 2>/dev/null || true)
  vendor=$(sed -n 's/^vendor_id[[:space:]]*: *//p' /proc/cpuinfo 2>/dev/null | head -1)
  local out="$(uname -m)"
  [[ -n "$vendor" ]] && out+=" $vendor"
  for f in sse4_2 avx fma avx2 avx512f; do
    [[ " $flags " == *" $f "* ]] && out+=" $f"
  done
  echo "$out"
}
SIGNATURE=$(signature)
DIGESTS=tests/regression/digests/$CASE/${SIGNATURE// /-}.txt

if [[ "$MODE" == --check ]]; then
  if [[ ! -f "$DIGESTS" ]]; then
    echo "record.sh: SKIP: no digests of case $CASE recorded on a machine like this one ('$SIGNATURE');" \
         "recorded: $(cd "tests/regression/digests/$CASE" && ls -- *.txt | tr '\n' ' ')" >&2
    exit 77
  fi
  recorded=$(sed -n 's/^# signature: //p' "$DIGESTS")
  [[ "$recorded" == "$SIGNATURE" ]] || { echo "record.sh: $DIGESTS says signature '$recorded'" >&2; exit 1; }
fi

# A DDS domain of our own (the lock files the integration tests and interop script use), held on fd 9.
source tests/reserve_domain.sh
reserve_domain 200 231 || true
[[ -n "$DOMAIN" ]] || { echo "record.sh: no free DDS domain in 200..231" >&2; exit 1; }

WORK=$(mktemp -d "${TMPDIR:-/tmp}/hadal-regression.XXXXXX")
SERVER_PID=""
cleanup() {
  if [[ -n "$SERVER_PID" ]] && kill -0 "$SERVER_PID" 2>/dev/null; then kill -9 "$SERVER_PID" 2>/dev/null || true; fi
  rm -rf "$WORK"
}
trap cleanup EXIT

# --discovery-wait: the server publishes its first samples (t = 0) only after the recorder matched.
# Returns 0, 1 on any failure, 3 when the only failure was a sample the transport lost (a writer's
# sequence gap: DDS could not repair it in time on a loaded machine, not a difference in what hadald
# computed).
record_once() {
  "$BUILD/bin/hadald" "$SCENARIO" --mode lockstep --domain-id "$DOMAIN" --no-status-line --discovery-wait 5 \
    >"$WORK/summary.txt" 2>"$WORK/server.err" &
  SERVER_PID=$!
  if ! "$BUILD/bin/hadal-record-topics" --domain-id "$DOMAIN" --out "$WORK/digest.txt" "${ARGS[@]}" 2>"$WORK/recorder.err"; then
    cat "$WORK/recorder.err" >&2
    kill -9 "$SERVER_PID" 2>/dev/null || true
    wait "$SERVER_PID" 2>/dev/null || true
    SERVER_PID=""
    if grep -q '(a sample was lost)$' "$WORK/recorder.err" && ! grep -qv '(a sample was lost)$' "$WORK/recorder.err"; then
      return 3
    fi
    echo "record.sh: the recorder failed; hadald said:" >&2
    cat "$WORK/server.err" >&2
    return 1
  fi
  kill -TERM "$SERVER_PID"
  wait "$SERVER_PID" || { echo "record.sh: hadald exited with an error:" >&2; cat "$WORK/server.err" >&2; SERVER_PID=""; return 1; }
  SERVER_PID=""
}
# A lost sample makes the recording incomplete, so it is recorded once more (never a digest that
# differs: that is a failure at once).
status=0
record_once || status=$?
if [[ $status -eq 3 ]]; then
  echo "record.sh: DDS lost a sample (above); recording once more" >&2
  status=0
  record_once || status=$?
fi
[[ $status -eq 0 ]] || { echo "record.sh: recording failed" >&2; exit 1; }

"$PYTHON" - "$WORK/summary.txt" "$WORK/digest.txt" "$DIGESTS" "$MODE" "$CASE" "$SCENARIO" "$SIGNATURE" \
  "${ARGS[*]}" "$REASON" <<'PY'
import datetime
import os
import sys
summary, digest, digests, mode, case, scenario, signature, args, reason = sys.argv[1:]
published = {}
for line in open(summary):
    parts = line.split()
    if len(parts) == 2 and parts[0].startswith("rt/"):
        published[parts[0]] = int(parts[1])
rows = [line.split() for line in open(digest) if line.strip()]
problems = []
for topic, _type, count, _hash in rows:
    if published.get(topic) != int(count):
        problems.append(f"{topic}: recorded {count} samples, hadald published {published.get(topic)}")
if not rows:
    problems.append("nothing recorded")
if problems:
    sys.exit("record.sh: incomplete recording:\n  " + "\n  ".join(problems))
body = "".join(" ".join(r) + "\n" for r in rows)
if mode == "--write":
    before = {}
    if os.path.exists(digests):
        before = {l.split()[0]: l.split() for l in open(digests) if l.strip() and not l.startswith("#")}
    after = {r[0]: r for r in rows}
    changed = sorted(t for t in set(before) | set(after) if before.get(t) != after.get(t))
    if before and not changed:
        print(f"record.sh: {digests} unchanged ({len(rows)} topics): nothing written")
        sys.exit(0)
    what = ", ".join(changed) if before else "new file"
    log = "tests/regression/RECORDS.md"
    with open(log, "a") as f:
        f.write(f"| {datetime.date.today().isoformat()} | {case} | {signature} | {what} | {reason} |\n")
    print(f"record.sh: topics changed: {what}; logged in {log}")
    with open(digests, "w") as f:
        f.write(f"# Regression digests of case '{case}': {scenario}, hadal-record-topics {args}\n")
        f.write("# topic, DDS type, samples, FNV-1a 64 of the serialized samples (tests/regression/README.md)\n")
        f.write(f"# signature: {signature}\n")
        f.write(body)
    print(f"record.sh: wrote {digests} ({len(rows)} topics)")
    sys.exit(0)
expected = {l.split()[0]: l.split() for l in open(digests) if l.strip() and not l.startswith("#")}
got = {r[0]: r for r in rows}
diffs = []
for topic in sorted(set(expected) | set(got)):
    e, g = expected.get(topic), got.get(topic)
    if e != g:
        diffs.append(f"{topic}: expected {' '.join(e[1:]) if e else 'no topic'}, got {' '.join(g[1:]) if g else 'no topic'}")
if diffs:
    sys.exit(f"record.sh: case {case} differs from {digests}:\n  " + "\n  ".join(diffs))
print(f"record.sh: case {case}: {len(rows)} topics bit-identical to {digests}")
PY
