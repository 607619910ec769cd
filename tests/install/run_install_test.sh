#!/usr/bin/env bash
# The install tree on its own (docs/server.md, "Installing"): `cmake --install BUILD --prefix P` into a temporary P,
# then, from a directory outside the source tree and with nothing pointing back into it (no HADALD,
# HADAL_SOURCE_DIR or HADAL_DATA_DIR): the Python package imports from P alone, hadal.Server("default")
# starts P/bin/hadald on P/share/hadal/configs, the magnetometer's World Magnetic Model is P's copy,
# hadal-viewer serves its page from P, and an outside CMake project finds the C++ client with
# find_package(hadal_client), builds and steps that server.
#
# usage: run_install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
BUILD=$(cd "$1" && pwd)
SOURCE=$(cd "$2" && pwd)
PYTHON=/usr/bin/python3
WORK=$(mktemp -d "${TMPDIR:-/tmp}/hadal-install.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
PREFIX=$WORK/prefix
fail() { echo "FAIL: install: $*" >&2; exit 1; }

cmake --install "$BUILD" --prefix "$PREFIX" >"$WORK/install.log" || { cat "$WORK/install.log" >&2; fail "cmake --install failed"; }
for f in bin/hadald bin/hadal-make-asset bin/hadal-geomag bin/hadal-viewer share/hadal/viewer/viewer.js \
         share/hadal/WMM2025.COF \
         share/hadal/configs/scenarios/default.yaml share/hadal/configs/meshes include/hadal_client/client.h \
         lib/python3/dist-packages/hadal/__init__.py lib/python3/dist-packages/hadal/env.py; do
  [[ -e "$PREFIX/$f" ]] || fail "$f is not in the install tree"
done
ls "$PREFIX"/lib*/cmake/hadal_client/hadal_clientConfig.cmake >/dev/null || fail "no CMake package config"
ls "$PREFIX"/lib/python3/dist-packages/hadal/_hadal*.so >/dev/null || fail "no Python extension module"

# Data found relative to the install.
"$PREFIX/bin/hadal-geomag" --help | grep -qF "$PREFIX/share/hadal/WMM2025.COF" ||
  fail "hadal-geomag does not default to the installed WMM2025.COF: $("$PREFIX/bin/hadal-geomag" --help | tail -1)"

# The installed viewer serves its page from the install tree (P/share/hadal/viewer), not the source tree.
"$PREFIX/bin/hadal-viewer" --port 0 --domain-id 232 >"$WORK/viewer.log" 2>&1 &
viewer_pid=$!
for _ in $(seq 50); do grep -q "serving" "$WORK/viewer.log" && break; sleep 0.1; done
kill -INT "$viewer_pid"; wait "$viewer_pid" || true
grep -qF "page from $PREFIX/share/hadal/viewer" "$WORK/viewer.log" ||
  fail "the installed hadal-viewer does not serve the installed page: $(cat "$WORK/viewer.log")"

# An outside project against the install prefix only.
cmake -S "$SOURCE/tests/install/consumer" -B "$WORK/consumer" -DCMAKE_PREFIX_PATH="$PREFIX" \
  -DCMAKE_BUILD_TYPE=Release >"$WORK/consumer.log" 2>&1 || { cat "$WORK/consumer.log" >&2; fail "consumer: configure"; }
cmake --build "$WORK/consumer" >>"$WORK/consumer.log" 2>&1 || { cat "$WORK/consumer.log" >&2; fail "consumer: build"; }

cd "$WORK"
env -u HADALD -u HADAL_SOURCE_DIR -u HADAL_DATA_DIR PYTHONPATH="$PREFIX/lib/python3/dist-packages" \
  ROS_LOCALHOST_ONLY=1 "$PYTHON" - "$PREFIX" "$WORK/consumer/consumer" <<'PYEOF' || fail "see above"
import math, os, subprocess, sys
prefix, consumer = sys.argv[1], sys.argv[2]
import hadal
import hadal.env
assert hadal.__file__.startswith(prefix), f"hadal imported from {hadal.__file__}, not from {prefix}"
with hadal.Server("default", mode="lockstep", cameras=False) as server:
    assert server.scenario == os.path.join(prefix, "share/hadal/configs/scenarios/default.yaml"), server.scenario
    assert server.process.args[0] == os.path.join(prefix, "bin/hadald"), server.process.args[0]
    with server.client("install_test") as client:
        client.wait_magnetic_field("auv", "magnetometer", timeout_s=0)
        client.wait_for_subscriptions(20)
        t = client.step(100)
        field = client.wait_magnetic_field("auv", "magnetometer", min_stamp=t, timeout_s=20)
        norm_uT = 1e6 * math.sqrt(sum(b * b for b in field.magnetic_field))
        assert 40.0 < norm_uT < 52.0, f"|B| = {norm_uT} uT: WMM2025 at 43 N 5 E is ~46.7 uT"
        client.reset()
    run = subprocess.run([consumer, str(server.domain_id)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stdout + run.stderr
    x = float(run.stdout.split("x=")[1])
    assert run.stdout.startswith("sim_time=1.000") and x > 0.02, run.stdout  # it moved forward
print(f"ok: installed package from {prefix}: |B| {norm_uT:.2f} uT; outside C++ project: {run.stdout.strip()}")
PYEOF
echo "PASS: install tree at $PREFIX works on its own"
