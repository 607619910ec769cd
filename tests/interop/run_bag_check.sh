#!/usr/bin/env bash
# A recorded bag of the default scenario, checked with the independent Cyclone types: hadald runs
# configs/scenarios/default.yaml for 2 s of sim time in fast mode with --record (docs/recording.md,
# "Recording inside the server"), then hadal-bag-check (bag_check.c) decodes every message of the bag with
# the ROS 2 types of ros2_types.idl through Cyclone DDS, and this script checks its JSON against the per-topic
# "samples published" counts hadald prints at exit (README.md, the summary under "Install, build, run"):
#   - every topic hadald published is in the bag under its ROS 2 name (rt/clock -> /clock), and the bag
#     has no other topic;
#   - each topic holds exactly as many messages as hadald published, and every one of them decoded;
#   - every topic but /hadal/step_reply has messages (see the comment at STEP_REPLY below);
#   - the bag's total is the "recorded N message(s)" hadald reports.
#
# usage: run_bag_check.sh HADALD BAG_CHECK REPO_ROOT [SCENARIO [DURATION [EMPTY,...]]]   (SCENARIO relative to
#        REPO_ROOT, default configs/scenarios/default.yaml; DURATION sim seconds, default 2; EMPTY: ROS 2 topic names
#        that may stay empty besides /hadal/step_reply, e.g. a modem's /<vehicle>/<modem>/rx when nobody sends)
#
# Discovery stays on loopback (ROS_LOCALHOST_ONLY=1); the run takes its own DDS domain 100..199 by holding
# /tmp/hadal-dds-domain-<N>.lock (../reserve_domain.sh), so concurrent tests never see each other.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/interop_lib.sh"
INTEROP_NAME="bag check"

(( $# >= 3 && $# <= 6 )) || usage "HADALD BAG_CHECK REPO_ROOT [SCENARIO [DURATION [EMPTY,...]]]"
HADALD=$1
BAG_CHECK=$2
REPO_ROOT=$3
SCENARIO=${4:-configs/scenarios/default.yaml}
DURATION=${5:-2}
export HADAL_BAG_MAY_BE_EMPTY=${6:-}
PYTHON=/usr/bin/python3

require_executable "$HADALD" hadald
require_executable "$BAG_CHECK" hadal-bag-check
require_scenario "$REPO_ROOT/$SCENARIO"

reserve_interop_domain
make_work_dir hadal-bag-check
isolate_discovery
export ROS_DOMAIN_ID=$DOMAIN

echo "bag check: domain $DOMAIN, hadald $HADALD, hadal-bag-check $BAG_CHECK"
run_hadald "$SCENARIO" --mode fast --duration "$DURATION" --record "$WORK/bag" --no-status-line
fail_unless_hadald_succeeded
[[ -f "$WORK/bag/metadata.yaml" ]] || { show_logs; fail "hadald wrote no bag (no $WORK/bag/metadata.yaml)"; }

set +e
"$BAG_CHECK" "$WORK/bag" >"$WORK/bag.json" 2>"$WORK/bag.err" 9>&-
CHECK_RC=$?
set -e
echo "hadal-bag-check exit code: $CHECK_RC"
if [[ $CHECK_RC -ne 0 ]]; then
  echo "--- hadal-bag-check stderr (first 60 lines) ---" >&2
  head -n 60 "$WORK/bag.err" >&2
fi

if ! "$PYTHON" - "$WORK/hadald.out" "$WORK/hadald.err" "$WORK/bag.json" "$CHECK_RC" "$DURATION" <<'EOF'; then
import json
import os
import re
import sys

out_path, err_path, json_path, check_rc, duration = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]), sys.argv[5]
problems = []

# hadald's summary on stdout: "  samples published:" then one "    rt/<topic> <count>" line per writer.
published = {}
with open(out_path) as f:
    lines = f.read().splitlines()
try:
    start = next(i for i, line in enumerate(lines) if line.strip() == "samples published:")
except StopIteration:
    print("hadald printed no 'samples published:' summary", file=sys.stderr)
    sys.exit(1)
for line in lines[start + 1:]:
    m = re.fullmatch(r"\s+(rt/\S+) (\d+)", line)
    if not m:
        break
    published["/" + m.group(1)[len("rt/"):]] = int(m.group(2))  # DDS rt/<name> is ROS 2's /<name>
if not published:
    problems.append("hadald's summary lists no published topic")
with open(err_path) as f:
    recorded = re.search(r"recorded (\d+) message\(s\)", f.read())

try:
    with open(json_path) as f:
        bag = json.load(f)
except (OSError, ValueError) as e:
    print(f"hadal-bag-check's output is not one JSON object: {e}", file=sys.stderr)
    sys.exit(1)
topics = bag.get("topics", {})

if check_rc != 0 or bag.get("ok") is not True:
    problems.append(f"hadal-bag-check failed (exit {check_rc}, {bag.get('failures')} failures; first: "
                    f"{(bag.get('errors') or ['?'])[0]})")
if bag.get("decoded") != bag.get("message_count"):
    problems.append(f"{bag.get('decoded')} of the bag's {bag.get('message_count')} messages decoded")

# STEP_REPLY: /hadal/step_reply answers lockstep step requests; a fast run gets none, so hadald publishes 0
# replies and the bag holds the topic with 0 messages. That is the only topic allowed to be empty (its
# count must still equal hadald's 0); every other topic of the default scenario publishes from t = 0 on.
MAY_BE_EMPTY = {"/hadal/step_reply"} | {t for t in os.environ.get("HADAL_BAG_MAY_BE_EMPTY", "").split(",") if t}
# NOT_RECORDED: the monitor carries the other topics' samples again; recorders leave it out unless it is named,
# so nobody reads it and hadald never writes it (server/src/dds/monitor.h): 0 published, not in the bag.
NOT_RECORDED = {"/hadal/monitor"}
for name in sorted(NOT_RECORDED):
    if published.pop(name, None) != 0 or name in topics:
        problems.append(f"{name}: expected unread, unwritten (0 in hadald's summary) and unrecorded")
for name, count in sorted(published.items()):
    t = topics.get(name)
    if t is None:
        problems.append(f"{name}: hadald published {count} messages, the bag has no such topic")
        continue
    if t.get("count") != count:
        problems.append(f"{name} ({t.get('type')}): hadald published {count} messages, the bag holds {t.get('count')}")
    if t.get("decoded") != t.get("count"):
        problems.append(f"{name} ({t.get('type')}): {t.get('decoded')} of {t.get('count')} messages decoded")
    if count == 0 and name not in MAY_BE_EMPTY:
        problems.append(f"{name}: hadald published nothing on it in {duration} s")
for name in sorted(set(topics) - set(published)):
    problems.append(f"the bag has topic {name!r} ({topics[name].get('type')!r}, {topics[name].get('count')} "
                    f"messages) that hadald's summary does not list")
total = sum(published.values())
if recorded is None:
    problems.append("hadald did not report how many messages it recorded")
elif int(recorded.group(1)) != total or bag.get("message_count") != total:
    problems.append(f"hadald published {total} messages, recorded {recorded.group(1)}, the bag holds "
                    f"{bag.get('message_count')}")

if problems:
    for p in problems:
        print(f"  - {p}", file=sys.stderr)
    sys.exit(1)
cam = topics.get("/auv/camera/image_raw", {}).get("last", {})
print(f"ok: {len(published)} topics, {total} messages, all decoded with ros2_types.idl and counted as published "
      f"(camera {cam.get('width')}x{cam.get('height')} {cam.get('encoding')}, "
      f"{topics.get('/auv/camera/image_raw', {}).get('count')} frames)")
EOF
  show_logs
  echo "--- hadal-bag-check stdout (JSON) ---" >&2; cat "$WORK/bag.json" >&2
  fail "the recorded bag does not decode as ROS 2 types, or does not hold what hadald published (see above)"
fi
echo "PASS: bag check: every message of a recorded bag of $SCENARIO decodes with Cyclone and ros2_types.idl"
