#!/bin/bash
# How far headers reach: for each header given (paths below server/include, e.g. hadal/core/model.h),
# how many of a build's translation units include it, directly or not, read from the dependency files
# the compiler wrote (*.o.d) during the build; and the project headers core/model.h pulls in.
# Prints one "name value" line per figure (machine-readable).
#
#   bench/header_reach.sh <source dir> <build dir> [header ...]
#
# The build dir must hold a finished build (CMake's Makefile generator with GCC writes the .o.d files).
set -euo pipefail
src=$(cd "$1" && pwd)
build=$(cd "$2" && pwd)
shift 2
headers=("$@")
if [ ${#headers[@]} -eq 0 ]; then
  headers=(hadal/core/model.h hadal/physics/water_spec.h hadal/physics/soil_spec.h hadal/render/optics_spec.h
           hadal/sensors/dvl_spec.h hadal/geometry/mesh_import.h hadal/geometry/terrain.h hadal/render/optics.h
           hadal/physics/terramechanics.h hadal/sensors/dvl.h)
fi
mapfile -t depfiles < <(find "$build" -name '*.o.d')
[ ${#depfiles[@]} -gt 0 ] || { echo "header_reach.sh: no *.o.d files under $build (build first)" >&2; exit 1; }
echo "translation_units ${#depfiles[@]}"
for h in "${headers[@]}"; do
  if [ ! -f "$src/server/include/$h" ]; then echo "reach $h absent"; continue; fi
  echo "reach $h $(grep -l -F "server/include/$h" "${depfiles[@]}" | wc -l)"
done
model="$src/server/include/hadal/core/model.h"
echo "model_h_lines $(wc -l < "$model")"
closure=$(echo '#include "hadal/core/model.h"' | g++ -std=c++20 -x c++ -M -MG -I"$src/server/include" \
  -I/usr/include/eigen3 - 2>/dev/null | tr ' \\' '\n\n' | grep -F "$src/server/include/hadal/" | grep -v -F "$model" || true)
echo "model_h_project_headers $(printf '%s\n' "$closure" | grep -c . || true)"
printf '%s\n' "$closure" | sed "s|$src/server/include/||" | sort | sed 's/^/model_h_includes /'
