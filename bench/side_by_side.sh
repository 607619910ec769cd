#!/usr/bin/env bash
# Issue 45's figures side by side in one run, each against its anchor (docs/benchmarks.md, "Side by side"):
#   1. the face kernel per face (hadal_bench_hydrodynamics; anchor <= 2.5 ns in constant water, the physics case's);
#   2. the physics case (bench/make_physics_case.py: the 11,136-face hull at 500 Hz, every face every step, one
#      thread), alternating with Stonefish's Girona 500 at its default prescaler 10 and at 1 when STONEFISH_G500
#      names its harness (../shared/peer-bench/stonefish/ builds it), 3 rounds of 60 s; anchors >= 60x and >= 1x
#      Stonefish's prescaled default;
#   3. Python lockstep step(1) with a thruster command each call, after the bare Fast DDS 1 KB round trip
#      (bench/python_client.py lockstep_calls); anchor >= 8,000 calls/s;
#   4. hadald configs/scenarios/default.yaml --mode fast with its camera, 3 runs of 60 s; anchor >= 5x.
# Prints one JSON object per measurement, then a summary table.
#   bench/side_by_side.sh [BUILD_DIR]      (default build/; STONEFISH_G500=/path/to/g500_bench optional)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${1:-build}
export ROS_LOCALHOST_ONLY=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out="$work/figures.jsonl"
/usr/bin/python3 bench/make_physics_case.py "$work" --build "$build"

"$build/bin/hadal_bench_hydrodynamics" --repetitions 5 | grep '"surface_hydrodynamics"' | tee -a "$out"
for round in 1 2 3; do
  "$build/bin/hadal_bench_step_rate" "$work/auv_one_thread.yaml" --sim-seconds 60 --repetitions 1 --threads 1 \
    | tee -a "$out"
  if [[ -n "${STONEFISH_G500:-}" ]]; then
    for prescaler in 10 1; do
      "$STONEFISH_G500" "$prescaler" 30000 2>/dev/null | grep '^{' \
        | /usr/bin/python3 -c 'import json, sys; d = json.loads(sys.stdin.read()); d["benchmark"] = "stonefish_g500"; d["prescaler"] = int(sys.argv[1]); print(json.dumps(d))' "$prescaler" \
        | tee -a "$out"
    done
  fi
done
PYTHONPATH="$build/python" HADAL_BUILD="$build" HADALD="$build/bin/hadald" \
  /usr/bin/python3 bench/python_client.py --only lockstep_calls --seconds 5 | tee -a "$out"
for round in 1 2 3; do
  summary=$("$build/bin/hadald" configs/scenarios/default.yaml --mode fast --duration 60 --domain-id 231 \
            --discovery-wait 0 --no-status-line 2>/dev/null)
  /usr/bin/python3 bench/summarise_hadald.py hadald_fast_mode - "$summary" | tee -a "$out"
done
/usr/bin/python3 - "$out" <<'PY'
import json, sys
rows = [json.loads(line) for line in open(sys.argv[1])]
def span(values, fmt="{:.4g}"):
    return fmt.format(min(values)) + ("" if len(values) == 1 else "-" + fmt.format(max(values)))
kernel = {(r["case"], r["fluid"], r.get("kernel", "vector")): r["ns_per_face"] for r in rows
          if r["benchmark"] == "surface_hydrodynamics" and "ns_per_face" in r}
hadal = [r["rtf"] for r in rows if r["benchmark"] == "sim_step_rate"]
sf10 = [r for r in rows if r["benchmark"] == "stonefish_g500" and r["prescaler"] == 10]
sf1 = [r for r in rows if r["benchmark"] == "stonefish_g500" and r["prescaler"] == 1]
print("\n| figure | measured | anchor |\n|---|---|---|")
print(f"| face kernel, submerged, constant water | {kernel[('submerged', 'constant', 'vector')]:.2f} ns/face "
      f"(unvectorised {kernel[('submerged', 'constant', 'scalar')]:.1f}) | <= 2.5 ns |")
print(f"| face kernel, submerged, pycnocline ramp (sampled per face) | {kernel[('submerged', 'ramp', 'vector')]:.2f} ns/face | - |")
print(f"| physics case, one thread | {span(hadal)}x | >= 60x |")
if sf10:
    rtf = lambda r: r.get("rtf", r.get("real_time_factor"))
    ratios = [h / rtf(s) for h, s in zip(hadal, sf10)]
    print(f"| Stonefish Girona 500, prescaler 10 | {span([rtf(r) for r in sf10])}x | - |")
    print(f"| Stonefish Girona 500, prescaler 1 | {span([rtf(r) for r in sf1])}x | - |")
    print(f"| physics case / Stonefish prescaler 10, per round | {span(ratios)} | >= 1 |")
bare = [r["round_trips_per_s"] for r in rows if r["benchmark"] == "dds_round_trip"]
print(f"| bare Fast DDS 1 KB round trip | {span(bare, '{:.0f}')}/s | - |")
for r in rows:
    if r["benchmark"] == "lockstep_calls" and r["steps_per_call"] == 1:
        print(f"| step(1) with a command, {r['scenario']}{', published too' if r.get('published') else ', attached only'} | "
              f"{r['calls_per_s']:.0f}/s | >= 8,000/s |")
fast = [r["rtf"] for r in rows if r["benchmark"] == "hadald_fast_mode"]
print(f"| hadald default.yaml --mode fast, with its camera | {span(fast)}x | >= 5x |")
PY
