#!/usr/bin/env bash
# Installs every Hadal dependency from Debian 12 packages (idempotent: only missing packages are
# installed; apt-get as root, sudo otherwise) and builds everything into build/ (hadald lands in
# build/bin/hadald). Extra arguments are passed to CMake's configure step; with -DHADAL_BUILD_TESTS=OFF among
# them (the container images, the demo) the packages only the tests use are left out. A first argument
# `--only TARGET` builds that target alone (the demo: hadald).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

target=()
if [[ "${1:-}" == "--only" ]]; then
  target=(--target "${2:?setup: --only needs a target}")
  shift 2
fi

PACKAGES=(
  build-essential cmake pkg-config
  libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libsqlite3-dev libbullet-dev
  libassimp-dev libembree-dev libopencv-dev libgeographiclib-dev liburdfdom-dev
  libfastrtps-dev libfastcdr-dev fastddsgen fastdds-tools libssl-dev openssl
  libcivetweb-dev libjs-three libjpeg62-turbo-dev
  python3 python3-dev pybind11-dev python3-numpy python3-yaml python3-matplotlib python3-distributed
)
# Used by the tests alone: fuzzing (clang), Cyclone DDS interop, GoogleTest, the browser test, the network
# namespace test, pytest, an independent JSON Schema validator.
TEST_PACKAGES=(
  clang libclang-rt-14-dev
  cyclonedds-dev cyclonedds-tools
  libgtest-dev libgmock-dev chromium python3-websocket iproute2 nftables python3-pytest python3-jsonschema
)
tests=1
for arg in "$@"; do
  [[ "$arg" == "-DHADAL_BUILD_TESTS=OFF" ]] && tests=0
done
((tests)) && PACKAGES+=("${TEST_PACKAGES[@]}")

missing=()
for package in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  if [[ $(id -u) -eq 0 ]]; then SUDO=(); else SUDO=(sudo); fi
  "${SUDO[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${SUDO[@]}" apt-get install -y -qq "${missing[@]}"
fi

jobs=$(nproc 2>/dev/null || echo 2)
# Debian's interpreter for the Python client, whatever python3 comes first on PATH.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 "$@"
cmake --build build -j"$jobs" "${target[@]}"
