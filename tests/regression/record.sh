#!/usr/bin/env bash
# Regression recording (tests/regression/README.md): runs a lockstep hadald on a scenario, steps it with
# hadal-record-topics and writes one digest line per published topic, or compares them with a file.
#
# usage: record.sh BUILD_DIR CASE [--check | --write REASON | --verify]
#   CASE     default            configs/scenarios/default.yaml, 60 s (30 000 steps), its schedule only
#            two_vehicles       tests/regression/scenarios/two_vehicles_all_sensors.yaml, 20 s, with
#                               client commands and a watchdog timeout
#   --write  (re)writes tests/regression/digests/CASE/LIBM.txt, the file of this machine's libm kind,
#            verified on this CPU only, and adds a line to tests/regression/RECORDS.md: the date, case,
#            CPU, the topics whose digests changed (or "new file") and REASON, why they changed (required;
#            the same words go in the commit)
#   --check  (default) records and compares with tests/regression/digests/CASE/LIBM.txt topic by topic;
#            skips (exit 77) when there is no file for this libm kind, or when the digests differ on a CPU
#            the file was not yet verified on (naming the topics); fails when they differ on a CPU it was
#   --verify records, compares, and when every digest matches adds this CPU to the file's verified list
#            (and a line to RECORDS.md)
#
# hadald runs with --ray-kernels portable (Embree's SSE4.2 kernels on every x86-64 CPU, hits recomputed in
# double precision: geometry/ray_kernels.h), which takes Embree's CPU-dependent arithmetic out of the
# results. What remains is glibc's libm, whose kernels for exp, log, pow, sin, cos... are chosen by CPU
# feature (FMA with AVX2, or not): LIBM is that kind (x86_64-fma-avx2 or x86_64), one file per kind. A
# file lists the CPUs (vendor and feature flags) it was verified on; a CPU not yet on the list that
# matches passes (and says how to add it), one that differs is reported as skipped, not failed.
# Completeness: every topic's recorded count must equal the count hadald reports having published.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
USAGE="usage: record.sh BUILD_DIR CASE [--check | --write REASON]"
BUILD=${1:?$USAGE}
CASE=${2:?$USAGE}
MODE=${3:---check}
REASON=${4:-}
case "$MODE" in
  --check|--verify) ;;
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
    # 7.5 s); the AUV leaves its schedule for client setpoints at 14 s. Modem packets: the buoy to the AUV,
    # a reply, a broadcast with a packet queued behind it, and two sent at once that neither modem hears
    # (half-duplex).
    ARGS=(--steps 10000
          --command buoy@500=0.6,0.4 --command buoy@1500=0.8,-0.3 --command buoy@2750=0.2,0.9
          --command buoy@3750=-0.5,-0.5 --command buoy@5000=0.7,0.7
          --command auv@7000=0.9,-0.3,0.5 --command buoy@7000=0.3,0.6
          --command auv@7400=0.6,0.2,-0.2 --command buoy@7400=0.5,0.5
          --command auv@7800=0.6,0.0,0.0 --command buoy@7800=0.4,0.4
          --packet "buoy/modem@1000=auv:fix 12.5 -3.0 -25.1" --packet "auv/modem@2200=buoy/modem:status ok"
          --packet "buoy/modem@3000=:to all" --packet "buoy/modem@3000=auv:queued behind it"
          --packet "buoy/modem@4500=auv:crossing" --packet "auv/modem@4500=buoy:crossing")
    ;;
  *) echo "record.sh: unknown case $CASE (default, two_vehicles)" >&2; exit 2 ;;
esac

# This CPU: architecture, vendor and the x86 flags that steer glibc's and Embree's kernel choices.
cpu() {
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
# The libm kind: glibc's x86_64 libm takes its FMA kernels where the CPU has FMA and AVX2.
libm_kind() {
  local flags
  flags=$(grep -m1 '^flags' /proc/cpuinfo 2>/dev/null || true)
  if [[ "$(uname -m)" == x86_64 && " $flags " == *" fma "* && " $flags " == *" avx2 "* ]]; then
    echo "x86_64-fma-avx2"
  else
    uname -m
  fi
}
CPU=$(cpu)
DIGESTS=tests/regression/digests/$CASE/$(libm_kind).txt

if [[ "$MODE" != --write && ! -f "$DIGESTS" ]]; then
  echo "record.sh: SKIP: no digests of case $CASE for this machine's libm kind ($DIGESTS);" \
       "recorded: $(cd "tests/regression/digests/$CASE" && ls -- *.txt | tr '\n' ' ')" >&2
  exit 77
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
    --ray-kernels portable \
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

"$PYTHON" - "$WORK/summary.txt" "$WORK/digest.txt" "$DIGESTS" "$MODE" "$CASE" "$SCENARIO" "$CPU" \
  "${ARGS[*]}" "$REASON" <<'PY'
import datetime
import os
import sys
summary, digest, digests, mode, case, scenario, cpu, args, reason = sys.argv[1:]
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
LOG = "tests/regression/RECORDS.md"


def read(path):
    """The digest rows by topic and the CPUs the file was verified on."""
    rows, verified = {}, []
    for line in open(path):
        if line.startswith("# verified on: "):
            verified.append(line[len("# verified on: "):].strip())
        elif line.strip() and not line.startswith("#"):
            rows[line.split()[0]] = line.split()
    return rows, verified


def write(path, rows, verified):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(f"# Regression digests of case '{case}': {scenario}, hadal-record-topics {args}, "
                "hadald --ray-kernels portable\n")
        f.write("# topic, DDS type, samples, FNV-1a 64 of the serialized samples (tests/regression/README.md)\n")
        for v in verified:
            f.write(f"# verified on: {v}\n")
        f.write("".join(" ".join(r) + "\n" for r in rows))


def log(what, why):
    with open(LOG, "a") as f:
        f.write(f"| {datetime.date.today().isoformat()} | {case} | {cpu} | {what} | {why} |\n")


if mode == "--write":
    before = read(digests)[0] if os.path.exists(digests) else {}
    after = {r[0]: r for r in rows}
    changed = sorted(t for t in set(before) | set(after) if before.get(t) != after.get(t))
    if before and not changed:
        print(f"record.sh: {digests} unchanged ({len(rows)} topics): nothing written")
        sys.exit(0)
    what = ", ".join(changed) if before else "new file"
    write(digests, rows, [cpu])
    log(what, reason)
    print(f"record.sh: topics changed: {what}; logged in {LOG}")
    print(f"record.sh: wrote {digests} ({len(rows)} topics), verified on {cpu} only")
    sys.exit(0)
expected, verified = read(digests)
got = {r[0]: r for r in rows}
diffs = []
for topic in sorted(set(expected) | set(got)):
    e, g = expected.get(topic), got.get(topic)
    if e != g:
        diffs.append(f"{topic}: expected {' '.join(e[1:]) if e else 'no topic'}, got {' '.join(g[1:]) if g else 'no topic'}")
if diffs and cpu not in verified:
    print(f"record.sh: SKIP: case {case} differs from {digests} on this CPU ({cpu}), which it was not verified on "
          f"(verified on: {'; '.join(verified)}):\n  " + "\n  ".join(diffs), file=sys.stderr)
    sys.exit(77)
if diffs:
    sys.exit(f"record.sh: case {case} differs from {digests}:\n  " + "\n  ".join(diffs))
if cpu in verified:
    print(f"record.sh: case {case}: {len(rows)} topics bit-identical to {digests}")
elif mode == "--verify":
    write(digests, [expected[t] for t in expected], verified + [cpu])
    log("none (verified)", "the digests match on this CPU too")
    print(f"record.sh: case {case}: {len(rows)} topics bit-identical to {digests}; added {cpu} to its verified list")
else:
    print(f"record.sh: case {case}: {len(rows)} topics bit-identical to {digests}, on a CPU it was not yet verified "
          f"on ({cpu}): `tests/regression/record.sh BUILD {case} --verify` adds it")
PY
