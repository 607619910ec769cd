#!/usr/bin/python3
"""Validates every scenario, vehicle and object file shipped in the repository against `hadald --schema` with an
independent JSON Schema validator (Debian's python3-jsonschema), and shows that the schema refuses what
hadald refuses: a misspelled key, a wrong type, a key another type does not use.

usage: validate_shipped_files.py HADALD SOURCE_DIR
"""
import copy
import json
import os
import re
import subprocess
import sys

import jsonschema
import yaml


class Yaml12Loader(yaml.SafeLoader):
    """YAML 1.2 core schema, as hadald and the YAML language server read it: `1e-3` is a number (PyYAML's
    YAML 1.1 resolver wants a dot), a date stays a string, and only true/false are booleans."""


Yaml12Loader.yaml_implicit_resolvers = {
    first: [(tag, regexp) for tag, regexp in resolvers
            if tag not in ("tag:yaml.org,2002:timestamp", "tag:yaml.org,2002:bool", "tag:yaml.org,2002:float",
                           "tag:yaml.org,2002:int")]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()}
Yaml12Loader.add_implicit_resolver("tag:yaml.org,2002:bool", re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$"),
                                   list("tTfF"))
Yaml12Loader.add_implicit_resolver("tag:yaml.org,2002:int", re.compile(r"^[-+]?[0-9]+$"), list("-+0123456789"))
Yaml12Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^(?:[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$"),
    list("-+0123456789."))


def load(path):
    with open(path, encoding="utf-8") as f:
        return yaml.load(f, Loader=Yaml12Loader)


def schema(hadald, which):
    out = subprocess.run([hadald, "--schema", which], check=True, capture_output=True, text=True).stdout
    document = json.loads(out)
    jsonschema.Draft7Validator.check_schema(document)
    return jsonschema.Draft7Validator(document)


def errors(validator, document):
    return sorted(validator.iter_errors(document), key=lambda e: list(e.absolute_path))


def main():
    hadald, source = sys.argv[1], sys.argv[2]
    scenario, vehicle, thing = schema(hadald, "scenario"), schema(hadald, "vehicle"), schema(hadald, "object")
    counts = {"scenario": 0, "vehicle": 0, "object": 0}
    failures = []
    for root, dirs, files in os.walk(source):
        dirs[:] = [d for d in dirs if d not in (".git", "build") and not d.startswith("build")]
        for name in sorted(files):
            if not name.endswith(".yaml"):
                continue
            path = os.path.join(root, name)
            document = load(path)
            if not isinstance(document, dict):
                continue
            if "world" in document and "vehicles" in document:
                kind, validator = "scenario", scenario
            elif "links" in document and "type" in document:
                kind, validator = "vehicle", vehicle
            elif "links" in document and os.path.basename(root) == "objects":
                kind, validator = "object", thing  # an object file has no type
            else:
                continue  # not a scenario, vehicle or object file (compose files, security blocks)
            counts[kind] += 1
            for error in errors(validator, document):
                failures.append("%s: %s: %s" % (os.path.relpath(path, source), "/".join(map(str, error.absolute_path)),
                                                error.message))
    print("validated %d scenario files, %d vehicle files and %d object files" %
          (counts["scenario"], counts["vehicle"], counts["object"]))
    for failure in failures:
        print("FAIL " + failure)
    # Every shipped scenario and vehicle was seen (a walk that found none would pass vacuously).
    assert counts["scenario"] >= 15 and counts["vehicle"] >= 7 and counts["object"] >= 1, counts
    assert not failures, "%d shipped files do not validate" % len(failures)

    # What hadald refuses, the schema refuses too.
    default = load(os.path.join(source, "configs", "scenarios", "default.yaml"))
    torpedo = load(os.path.join(source, "configs", "vehicles", "torpedo_auv.yaml"))
    assert not errors(scenario, default) and not errors(vehicle, torpedo)

    def refused(validator, document, change, why):
        broken = copy.deepcopy(document)
        change(broken)
        found = errors(validator, broken)
        assert found, "the schema accepts " + why
        print("refused (%s): %s" % (why, found[0].message))

    refused(scenario, default, lambda d: d["world"].__setitem__("physics_rate", 500), "a misspelled world key")
    refused(scenario, default, lambda d: d["world"].setdefault("water", {}).__setitem__("surface_zz", 0.0),
            "a misspelled water key")
    refused(scenario, default, lambda d: d["vehicles"][0]["sensors"][0].__setitem__("rate_hzz", 5),
            "a misspelled sensor key")
    refused(scenario, default, lambda d: d["world"].__setitem__("physics_rate_hz", "fast"), "a string for a number")
    refused(scenario, default, lambda d: d["world"].__setitem__("physics_rate_hz", 10), "a number out of range")
    refused(scenario, default, lambda d: d["vehicles"][0].__setitem__("type", "auv"),
            "an inline definition key beside include")
    refused(vehicle, torpedo, lambda d: d["links"][0].__setitem__("masss", 1.0), "a misspelled link key")
    imu = next(s for s in torpedo["sensors"] if s["type"] == "imu")
    refused(vehicle, torpedo, lambda d: next(s for s in d["sensors"] if s["type"] == "imu").__setitem__(
        "beam_tilt_deg", 30), "a DVL key on an IMU")
    refused(vehicle, torpedo, lambda d: next(s for s in d["sensors"] if s["type"] == "imu").__setitem__(
        "latency_s", 0.1), "latency_s on a kind sampled on the stepping thread")
    refused(vehicle, torpedo, lambda d: d["thrusters"][0].pop("max_rpm"), "a missing required key")
    refused(vehicle, torpedo, lambda d: d["sensors"].append({"name": "x", "type": "sonar"}), "an unknown sensor type")
    core = load(os.path.join(source, "configs", "objects", "push_core.yaml"))
    assert not errors(thing, core)
    refused(thing, core, lambda d: d.__setitem__("thrusters", []), "an actuator list on an object")
    assert imu["type"] == "imu"
    print("ok")


if __name__ == "__main__":
    main()
