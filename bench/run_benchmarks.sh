#!/usr/bin/env bash
# Runs Hadal's benchmarks and prints one JSON object per measurement (results go to docs/benchmarks.md).
#   bench/run_benchmarks.sh [BUILD_DIR]     (default build/)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${1:-build}
export ROS_LOCALHOST_ONLY=1

# 1. Simulation core only (no DDS), default scenario.
"$build/bin/hadal_bench_step_rate" configs/scenarios/default.yaml --sim-seconds 60 --repetitions 3

# 2. The whole server in fast mode (simulation + DDS publishing of clock, odometry, thruster state,
#    status), default scenario, 3600 s of sim time, on a domain of its own.
# 3. Realtime mode holding a requested real-time factor (absolute schedule): 300 s of sim time at
#    --rtf 10 should take 30 s of wall time; the figure is the achieved RTF.
summarise() {  # NAME REQUESTED_RTF SUMMARY_TEXT [SCENARIO_LABEL]
  /usr/bin/python3 bench/summarise_hadald.py "$@"
}
for r in 1 2 3; do
  out=$("$build/bin/hadald" configs/scenarios/default.yaml --mode fast --duration 3600 --domain-id 231 \
        --discovery-wait 0 --no-status-line 2>/dev/null)
  summarise hadald_fast_mode - "$out"
done
out=$("$build/bin/hadald" configs/scenarios/default.yaml --mode realtime --rtf 10 --duration 300 \
      --domain-id 231 --no-status-line 2>/dev/null)
summarise hadald_realtime_mode 10 "$out"

# 4. The physics case: the default scenario's AUV alone (its own navigation sensors: IMU, DVL, altimeter, pressure,
#    GPS, magnetometer; no camera, sonar, lights or lander) with an 11 136-face torpedo hull mesh (generated) in place
#    of the tessellated capsule + fins: forces on every face every step at 500 Hz, the simulation core on one thread
#    (issue 45's anchor against Stonefish's Girona 500). Then the default scenario with that hull, its camera, sonar,
#    lights and lander: the simulation core and the whole server in fast mode (its figure is the camera's).
# 6 and 7 (at the end): memory over a 1M-triangle seabed; sensors: cost per sample of each of the
#    default AUV's sensors, their share of a core at the configured rates, and a captured sensor's scan
#    (bench/sensors.cc).
# 5. Two such physics-case AUVs, the second 20 m to port of the first (moved from wherever the first starts): their
#    fluid forces run on the worker pool, so with 2 cores the RTF stays close to the single-vehicle figure instead
#    of halving.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
/usr/bin/python3 bench/make_physics_case.py "$work" --build "$build"
"$build/bin/hadal_bench_step_rate" "$work/auv_surface.yaml" --sim-seconds 20 --repetitions 3 --threads 1
"$build/bin/hadal_bench_step_rate" "$work/default_surface.yaml" --sim-seconds 20 --repetitions 3
for r in 1 2 3; do
  out=$("$build/bin/hadald" "$work/default_surface.yaml" --mode fast --duration 60 --domain-id 231 \
        --discovery-wait 0 --no-status-line 2>/dev/null)
  summarise hadald_fast_mode_surface_model - "$out" "default.yaml + surface model, 11136-face hull"
done
"$build/bin/hadal_bench_step_rate" "$work/two_surface.yaml" --sim-seconds 20 --repetitions 3

# 6. Memory: hadald's peak resident set with the default AUV (DVL and altimeter: the world's ray-cast
#    scene is built) over a generated 1M-triangle seabed mesh, 10 s in fast mode; the figure is the
#    summary's "peak memory" (getrusage). One ray-cast world: the seabed's BVH and buffers exist once.
"$build/bin/hadal-make-asset" seabed "$work/seabed1m.glb" --triangles 1000000 --extent 1000 >/dev/null
/usr/bin/python3 - "$work" <<'PY'
import os, sys
work = sys.argv[1]
scenario = open("configs/scenarios/default.yaml").read()
start = scenario.index("  seabed:")
end = scenario.index("  # Calendar date")
scenario = (scenario[:start] + "  seabed:\n    type: mesh\n    file: seabed1m.glb\n"
            "    pose: {position: [0.0, 0.0, -150.0]}\n" + scenario[end:])
scenario = scenario.replace("include: ../vehicles/torpedo_auv.yaml",
                            "include: " + os.path.abspath("configs/vehicles/torpedo_auv.yaml"))
open(f"{work}/seabed1m.yaml", "w").write(scenario)
PY
for r in 1 2 3; do
  out=$("$build/bin/hadald" "$work/seabed1m.yaml" --mode fast --duration 10 --domain-id 231 \
        --discovery-wait 0 --no-status-line 2>/dev/null)
  /usr/bin/python3 - "$out" <<'PY'
import json, re, sys
m = re.search(r"peak memory: ([\d.]+) MiB", sys.argv[1])
print(json.dumps({"benchmark": "hadald_peak_memory", "scenario": "default.yaml over a 999698-triangle seabed mesh",
                  "peak_rss_mib": float(m[1])}))
PY
done

# 7. Sensors (bench/sensors.cc).
"$build/bin/hadal_bench_sensors"

# 8. Cameras (bench/render.cc): one 640 x 480 deep-sea frame (radiance, depth, counts) over a 1M-triangle
#    seabed on one and two threads, with and without the seabed declared a height field, next to its
#    primary rays alone; then the default scenario's camera frame as the simulation renders it
#    (bench/camera_frame.cc).
"$build/bin/hadal_bench_render" --repetitions 3
"$build/bin/hadal_bench_camera_frame" --repetitions 10

# 9. Sonars (bench/sonar.cc): a forward-looking sonar ping (256 beams x 512 bins, 10 rays per cell) and a
#    multibeam ping (256 beams) over the 1M-triangle seabed on one and two threads.
"$build/bin/hadal_bench_sonar" --repetitions 10

# 10. Articulated vehicles (issue 40): the work-class ROV with its Oberon 7 arm over the push core, and the
#     two-joint arm on a fixed frame, 500 Hz, every body's fluid model every step, one thread, no cameras
#     (the physics step's figure). Interleaved, so that the two see the same machine; the arm's step is the
#     yardstick of how busy the machine was.
for r in 1 2 3; do
  for scenario in configs/scenarios/rov_intervention.yaml tests/integration/scenarios/arm.yaml; do
    "$build/bin/hadal_bench_step_rate" "$scenario" --sim-seconds 10 --repetitions 8 --threads 1 --no-cameras
  done
done

# 11. Scaling out on Dask (issue 41, bench/dask_scaling.py): campaign throughput with 1 and 2 workers of one
#     core each, DaskVectorEnv against VectorEnv with 1-8 envs per worker, and the bare round trip.
PYTHONPATH="$build/python" /usr/bin/python3 bench/dask_scaling.py

# 12. Acoustic positioning and modems (issue 42, bench/acoustics.cc): a USBL at 1 Hz, an LBL ranging to four
#     beacons at 1 Hz and four modems with traffic, against the default scenario's step without its camera and sonar.
"$build/bin/hadal_bench_acoustics"

# 13. Cables (issue 43, bench/cables.cc): a 300 m, 100-segment tow cable at 500 Hz on one thread; then the
#     work-class ROV with its arm on its tether under the TMS's umbilical (rov_tether.yaml, 100 Hz) and the towed
#     side-scan survey (towfish.yaml, 500 Hz, its side-scan included), one thread, no cameras (the physics step's
#     figure, as in section 10).
"$build/bin/hadal_bench_cables"
for scenario in configs/scenarios/rov_tether.yaml configs/scenarios/towfish.yaml; do
  "$build/bin/hadal_bench_step_rate" "$scenario" --sim-seconds 60 --repetitions 3 --threads 1 --no-cameras
done

# 14. Waves (issue 44): the catamaran ASV drifting and driving in a JONSWAP sea (vessel_waves.yaml, Hs 2 m, Tp 8 s,
#     128 components, 100 Hz), the physics step on one thread and the whole server in fast mode, each next to the
#     same vessel on a calm sea (vessel.yaml); the per-body cost of the waves on the 11k-face hull is section 4's
#     hadal_bench_hydrodynamics, case partial_waves.
for scenario in configs/scenarios/vessel_waves.yaml configs/scenarios/vessel.yaml; do
  "$build/bin/hadal_bench_step_rate" "$scenario" --sim-seconds 60 --repetitions 3 --threads 1 --no-cameras
  out=$("$build/bin/hadald" "$scenario" --mode fast --duration 600 --domain-id 231 --discovery-wait 0 \
        --no-status-line 2>/dev/null)
  summarise hadald_fast_mode - "$out" "$scenario"
done

