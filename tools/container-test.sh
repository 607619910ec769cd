#!/usr/bin/env bash
# Builds Hadal's container images and runs its two compose stacks with podman (docs/containers.md), as root on
# a Debian 12 machine with no Docker daemon and no registry: outside the default test path (it takes ~20 min).
#
#   tools/container-test.sh [--keep]      (--keep: leave the images; default: remove them at the end)
#
# 1. Installs podman, runc, podman-compose and debootstrap if missing (apt).
# 2. A debian:12 base image from Debian's own mirror (debootstrap), unless one exists (podman image exists).
# 3. Builds docker/Dockerfile's server and client images, unchanged (the Dockerfile is Docker's).
# 4. The HIL stack (docker/compose.yaml): hadald in one container, the depth autopilot in another, over DDS
#    across the container network; the autopilot must take the AUV from 20 m to within 2 m of 30 m.
# 5. The Dask stack (docker/dask-compose.yaml): a scheduler and two workers as services; a 16-case campaign
#    submitted to the scheduler from a third container must come back with every case ok, from both workers.
# Prints one JSON line per figure (image sizes, build times, the runs' results) and exits non-zero on failure.
# Container settings for this machine's kernel (hybrid cgroups, which crun refuses: runc with cgroupfs; runc with
# cgroups disabled builds but cannot run a container) go in a containers.conf of
# this run's own (CONTAINERS_CONF), not in the user's (docs/containers.md, "With podman").
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
keep=0
[[ "${1:-}" == "--keep" ]] && keep=1
[[ $(id -u) -eq 0 ]] || { echo "container-test: error: run as root (podman builds as root here)" >&2; exit 2; }

need=()
for package in podman runc podman-compose debootstrap; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || need+=("$package")
done
if ((${#need[@]})); then
  echo "container-test: installing ${need[*]}" >&2
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" > /dev/null
fi

work=$(mktemp -d /tmp/hadal-container-test-XXXXXX)
trap 'rm -rf "$work"' EXIT
cat > "$work/containers.conf" <<'EOF'
[containers]
default_ulimits = []
[engine]
cgroup_manager = "cgroupfs"
runtime = "runc"
EOF
export CONTAINERS_CONF="$work/containers.conf"
ulimits=(--ulimit nofile=20000:20000 --ulimit nproc=4096:4096)
figure() { echo "{\"container_test\": \"$1\", $2}"; }

# 2. The base image.
if ! podman image exists docker.io/library/debian:12; then
  mirror=$(awk '/^URIs:/ {print $2; exit}' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)
  mirror=${mirror:-http://deb.debian.org/debian}
  start=$(date +%s)
  debootstrap --variant=minbase bookworm "$work/rootfs" "$mirror" > "$work/debootstrap.log" 2>&1 \
    || { tail -20 "$work/debootstrap.log" >&2; exit 1; }
  # As Docker's debian:12: no downloaded packages, no package lists (the images' apt-get update fetches them).
  rm -rf "$work"/rootfs/var/cache/apt/archives/*.deb "$work"/rootfs/var/lib/apt/lists/*
  tar -C "$work/rootfs" -c . | podman import - localhost/debian:12 > /dev/null
  podman tag localhost/debian:12 docker.io/library/debian:12
  rm -rf "$work/rootfs"
  figure base "\"debootstrap_s\": $(( $(date +%s) - start )), \"mirror\": \"$mirror\""
fi

# 3. The images.
for target in server client; do
  start=$(date +%s)
  podman build --pull=never "${ulimits[@]}" -f docker/Dockerfile --target "$target" -t "hadal-$target" . \
    > "$work/build-$target.log" 2>&1 || { tail -40 "$work/build-$target.log" >&2; exit 1; }
  size=$(podman image inspect --format '{{.Size}}' "hadal-$target")
  figure "image" "\"target\": \"$target\", \"build_s\": $(( $(date +%s) - start )), \"size_mb\": $(( size / 1000000 ))"
done

compose() { podman-compose --podman-run-args="${ulimits[*]}" "$@"; }

# 4. The HIL stack: the autopilot steps the lockstep server to t = 90 s, printing its depth every 10 s.
compose -f docker/compose.yaml up --no-build --abort-on-container-exit --exit-code-from autonomy \
  > "$work/hil.log" 2>&1 || { tail -60 "$work/hil.log" >&2; compose -f docker/compose.yaml down > /dev/null 2>&1; exit 1; }
compose -f docker/compose.yaml down > /dev/null 2>&1 || true
final=$(grep -o 'depth *[0-9.]* m' "$work/hil.log" | tail -1 | awk '{print $2}')
[[ -n "$final" ]] || { echo "container-test: error: the autopilot printed no depth:" >&2; tail -40 "$work/hil.log" >&2; exit 1; }
figure hil "\"final_depth_m\": $final, \"target_depth_m\": 30"
awk -v d="$final" 'BEGIN { exit !(d > 28 && d < 32) }' \
  || { echo "container-test: error: the AUV ended at $final m, not near 30 m" >&2; exit 1; }

# 5. The Dask stack: scheduler and two workers up, a campaign from a third container.
compose -f docker/dask-compose.yaml up -d --no-build scheduler worker1 worker2 > "$work/dask.log" 2>&1 \
  || { tail -40 "$work/dask.log" >&2; exit 1; }
status=0
start=$(date +%s)
compose -f docker/dask-compose.yaml run --rm campaign > "$work/campaign.log" 2>&1 || status=$?
compose -f docker/dask-compose.yaml down > /dev/null 2>&1 || true
summary=$(grep "hadal-campaign: cross_current:" "$work/campaign.log" || true)
if [[ $status -ne 0 || "$summary" != *"16 ok, 0 failed"* || "$summary" != *"on 2 worker(s)"* ]]; then
  echo "container-test: error: the campaign on the Dask stack failed (status $status):" >&2
  tail -40 "$work/campaign.log" >&2
  exit 1
fi
figure dask "\"campaign_s\": $(( $(date +%s) - start )), \"summary\": \"${summary//\"/}\""

if ((keep == 0)); then
  podman rmi hadal-server hadal-client > /dev/null
fi
echo "container-test: ok" >&2
