"""pytest fixtures: a real hadald process on a DDS domain reserved for the test."""

import os
import subprocess
import sys

import pytest

from hadal.server import reserve_domain

HADALD = os.environ.get("HADALD", os.path.join(os.path.dirname(__file__), "../../../build/bin/hadald"))
SOURCE_DIR = os.environ.get("HADAL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "../../.."))
os.environ.setdefault("ROS_LOCALHOST_ONLY", "1")


# Domains only this (serial) test session uses: other tests reserve 20..99 (C++), 100..199 (interop,
# hadal.Server's "free"), 200..231 (pytest fixtures, the regression recorder). A test that picks one of these,
# releases it and lets a hadal.Server take it again cannot meet another test's server there.
SESSION_DOMAINS = range(10, 20)


def _session_domain():
    """A domain of SESSION_DOMAINS no one holds now: the session's ROS_DOMAIN_ID, where hadal.Server and
    hadal.Client go when given no domain_id (never a user's domain 0, nor the ids other tests reserve)."""
    reserved = reserve_domain(SESSION_DOMAINS)
    if reserved is None:
        return str(SESSION_DOMAINS[-1])
    candidate, handle = reserved
    handle.close()  # a hadal.Server of the session takes the lock
    return str(candidate)


os.environ["ROS_DOMAIN_ID"] = _session_domain()


def run_example(script, args, timeout=300):
    """examples/python/<script> run as a user runs it, in a subprocess (it starts its own hadald): its key=value
    lines as floats (but plot=), after asserting that it exited 0."""
    env = dict(os.environ)
    env.setdefault("ROS_LOCALHOST_ONLY", "1")
    result = subprocess.run([sys.executable, os.path.join(SOURCE_DIR, "examples", "python", script), *args], env=env,
                            capture_output=True, text=True, timeout=timeout)
    assert result.returncode == 0, result.stdout + result.stderr
    figures = {}
    for line in result.stdout.splitlines():
        key, _, value = line.partition("=")
        if value and key != "plot":
            figures[key] = float(value)
    return figures


def scenario(relative):
    return os.path.join(SOURCE_DIR, relative)


@pytest.fixture
def domain_id():
    """A DDS domain id in 200..229 no other test holds (flock, as the C++ tests' DomainLease)."""
    reserved = reserve_domain(range(200, 230))
    if reserved is None:
        pytest.fail("no free DDS domain id")
    candidate, handle = reserved
    yield candidate
    handle.close()


def _lockstep(relative_scenario, domain_id):
    """hadald in lockstep mode on a scenario of the source tree; yields (process, domain_id)."""
    process = subprocess.Popen(
        [HADALD, scenario(relative_scenario), "--mode", "lockstep", "--domain-id", str(domain_id),
         "--no-status-line"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    yield process, domain_id
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            process.kill()
    out, err = process.communicate()
    sys.stderr.write(err)


@pytest.fixture
def lockstep_server(domain_id):
    """hadald in lockstep mode on the AUV test scenario; yields (process, domain_id)."""
    yield from _lockstep("tests/integration/scenarios/auv_client.yaml", domain_id)


@pytest.fixture
def profiler_server(domain_id):
    """hadald in lockstep mode on the profiler test scenario (a captured sensor kind)."""
    yield from _lockstep("tests/integration/scenarios/profiler.yaml", domain_id)


@pytest.fixture
def camera_server(domain_id):
    """hadald in lockstep mode on the camera test scenario (tests/integration/scenarios/camera.yaml)."""
    yield from _lockstep("tests/integration/scenarios/camera.yaml", domain_id)


@pytest.fixture
def sonar_server(domain_id):
    """hadald in lockstep mode on the sonar test scenario (tests/integration/scenarios/sonar.yaml)."""
    yield from _lockstep("tests/integration/scenarios/sonar.yaml", domain_id)


@pytest.fixture
def arm_server(domain_id):
    """hadald in lockstep mode on the articulated test scenario (tests/integration/scenarios/arm.yaml)."""
    yield from _lockstep("tests/integration/scenarios/arm.yaml", domain_id)


@pytest.fixture
def crawler_server(domain_id):
    """hadald in lockstep mode on the crawler zoo scenario (configs/scenarios/crawler.yaml)."""
    yield from _lockstep("configs/scenarios/crawler.yaml", domain_id)


@pytest.fixture
def zoo_server(domain_id):
    """A function starting hadald in lockstep on configs/scenarios/<name>.yaml; yields its domain id."""
    started = []

    def start(name):
        generator = _lockstep(f"configs/scenarios/{name}.yaml", domain_id)
        started.append(generator)
        next(generator)
        return domain_id

    yield start
    for generator in started:
        next(generator, None)


@pytest.fixture
def rov_server(domain_id):
    """hadald in lockstep mode on the ROV zoo scenario (configs/scenarios/rov.yaml: a 0.3 m/s current)."""
    yield from _lockstep("configs/scenarios/rov.yaml", domain_id)
