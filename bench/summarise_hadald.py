#!/usr/bin/python3
"""One JSON row from hadald's end-of-run summary ("sim time S s in W s wall, RTF R, N steps"), for the shell drivers
(bench/run_benchmarks.sh, bench/side_by_side.sh):

    bench/summarise_hadald.py NAME REQUESTED_RTF SUMMARY_TEXT [SCENARIO_LABEL]

REQUESTED_RTF is "-" outside realtime mode; SCENARIO_LABEL defaults to configs/scenarios/default.yaml.
"""

import json
import re
import sys


def main():
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    name, requested, text = sys.argv[1:4]
    scenario = sys.argv[4] if len(sys.argv) == 5 else "configs/scenarios/default.yaml"
    m = re.search(r"sim time ([\d.]+) s in ([\d.]+) s wall, RTF ([\d.]+), (\d+) steps", text)
    if not m:
        sys.exit(f"summarise_hadald.py: no hadald summary in:\n{text[-2000:]}")
    sim, wall, steps = float(m[1]), float(m[2]), int(m[4])
    row = {"benchmark": name, "scenario": scenario, "sim_s": sim, "wall_s": wall,
           "steps": steps, "steps_per_s": round(steps / wall), "rtf": round(sim / wall, 3)}
    if requested != "-":
        row["requested_rtf"] = float(requested)
    print(json.dumps(row))


if __name__ == "__main__":
    main()
