"""examples/python/rov_pick_and_place.py against a real lockstep hadald (configs/scenarios/rov_intervention.yaml):
the work-class ROV's Oberon 7 picks the push core up from the sediment by its fingers' contact and friction,
carries it, and drops it in its basket when the gripper opens. Run twice from the same seed, every position the
example reports is the same to the last bit (docs/ARCHITECTURE.md, "Noise and random streams": same seed,
same scenario, same lockstep commands, same output)."""

import math
import os
import sys

import hadal

SOURCE_DIR = os.environ.get("HADAL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "../.."))
sys.path.insert(0, os.path.join(SOURCE_DIR, "examples", "python"))

import rov_pick_and_place  # noqa: E402  (the example, from the source tree)


def run_once():
    with hadal.Server(os.path.join(SOURCE_DIR, "configs", "scenarios", "rov_intervention.yaml"), mode="lockstep",
                      cameras=False) as server, server.client("pick_and_place", timeout_s=30.0) as client:
        return rov_pick_and_place.pick_and_place(client, report=lambda line: print(line, flush=True))


def test_the_arm_picks_the_core_up_and_places_it_in_the_basket_identically_twice():
    first = run_once()
    # Standing on the sediment (its centre 0.15 m above it, the ROV's centre of mass 1.7 m above it) ...
    assert abs(first["start_B"][2] - (-1.55)) < 0.2
    # ... lifted with the gripper by 0.3 m (the arm's targets), minus a few centimetres of slip at most,
    assert first["lifted_B"][2] - first["start_B"][2] > 0.25
    # ... held above the basket (floor 1.09 m below B; the core's bottom 8 cm above it, its centre 0.23 m) ...
    assert first["held_B"][2] > -1.09 + 0.15
    # ... its wet weight felt by the wrist's force/torque sensor while held: (1.6 kg - rho V) g with V the
    # tube's and the handle's cylinders and rho ~1035 kg/m^3 at 1500 m, 6.5 N (the median of a second's
    # readings, empty and holding: a grasp's contacts slip and catch now and then, a reading 2-3 N off for a
    # step); 10 % for the sensor's noise, the tessellated volume and what is left of the arm's settling ...
    wet_weight = (1.6 - 1035.0 * math.pi * (0.03**2 * 0.3 + 0.0125**2 * 0.12)) * 9.80665
    assert abs(first["felt_N"][0] - wet_weight) < 0.1 * wet_weight, (first["felt_N"], wet_weight)
    # ... and dropped into it when the gripper opened.
    assert first["final_B"][2] < first["held_B"][2] - 0.01
    assert first["inside"], first
    second = run_once()
    for key in ("start_B", "lifted_B", "held_B", "final_B", "felt_N"):
        assert first[key].tobytes() == second[key].tobytes(), (key, first[key], second[key])
