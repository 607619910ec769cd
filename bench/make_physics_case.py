#!/usr/bin/python3
"""Writes the benchmarks' 11k-face scenarios into WORK (docs/benchmarks.md, "The physics case"):

  hull.glb              the generated torpedo hull: 1.6 m x 0.0775 m, 232 segments, 11,136 faces
  torpedo_surface.yaml  configs/vehicles/torpedo_auv.yaml with that hull as its link mesh
  default_surface.yaml  the camera scenario: configs/scenarios/default.yaml as it is, with that hull
  auv_surface.yaml      the physics case: the default AUV alone with its navigation sensors (IMU, DVL, altimeter,
                        pressure, GPS, magnetometer), no camera, sonar, lights or lander
  auv_one_thread.yaml   the physics case with world.threads and world.raycast_threads 1 (one stepping thread, as
                        a peer's single-threaded loop)
  two_surface.yaml      the physics case twice, the second AUV 20 m to port of wherever the first starts

    bench/make_physics_case.py WORK [--build build]    (run from anywhere; WORK must exist)
"""

import argparse
import copy
import os
import subprocess

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("work")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    args = parser.parse_args()
    work = os.path.abspath(args.work)
    subprocess.run([os.path.join(args.build, "bin", "hadal-make-asset"), "torpedo", os.path.join(work, "hull.glb"),
                    "--length", "1.6", "--radius", "0.0775", "--segments", "232"], check=True,
                   stdout=subprocess.DEVNULL)
    vehicle = open(os.path.join(ROOT, "configs", "vehicles", "torpedo_auv.yaml")).read()
    vehicle = vehicle.replace("  - name: hull\n", "  - name: hull\n    mesh: {file: hull.glb}\n", 1)
    open(os.path.join(work, "torpedo_surface.yaml"), "w").write(vehicle)
    scenario = open(os.path.join(ROOT, "configs", "scenarios", "default.yaml")).read()
    scenario = scenario.replace("include: ../vehicles/torpedo_auv.yaml", "include: torpedo_surface.yaml")
    open(os.path.join(work, "default_surface.yaml"), "w").write(scenario)
    physics = yaml.safe_load(scenario)
    auv = next(v for v in physics["vehicles"] if v["name"] == "auv")
    for key in ("sensors", "lights"):
        auv.pop(key, None)
    physics["vehicles"] = [auv]
    open(os.path.join(work, "auv_surface.yaml"), "w").write(yaml.safe_dump(physics, sort_keys=False))
    one_thread = copy.deepcopy(physics)
    one_thread["world"]["threads"] = 1
    one_thread["world"]["raycast_threads"] = 1
    open(os.path.join(work, "auv_one_thread.yaml"), "w").write(yaml.safe_dump(one_thread, sort_keys=False))
    second = copy.deepcopy(auv)
    second["name"] = "auv2"
    second["initial_pose"]["position"][1] += 20.0
    physics["vehicles"] = [auv, second]
    open(os.path.join(work, "two_surface.yaml"), "w").write(yaml.safe_dump(physics, sort_keys=False))


if __name__ == "__main__":
    main()
