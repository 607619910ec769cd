"""The README's snippets run as written with ROS_DOMAIN_ID set to a non-zero domain: the Python block (a
hadal.Server and its client), and with a real-time hadald started as the README's "Run the server" block
starts it, the ROS 2-typed probe line and the C++ drive_auv line. Each snippet is read from README.md
itself, so a README edit is what gets tested; only `build/` becomes the build directory under test."""

import json
import os
import re
import subprocess

import pytest

from conftest import HADALD, SESSION_DOMAINS, SOURCE_DIR
from hadal.server import reserve_domain

BUILD_DIR = os.path.dirname(os.path.dirname(os.path.abspath(HADALD)))


def readme_blocks():
    with open(os.path.join(SOURCE_DIR, "README.md")) as readme:
        return re.findall(r"```sh\n(.*?)```", readme.read(), re.S)


def block_with(text):
    found = [block for block in readme_blocks() if text in block]
    assert len(found) == 1, f"README.md has {len(found)} sh blocks with {text!r}"
    return found[0].replace("build/", BUILD_DIR + "/")


def line_with(text):
    lines = [line for line in block_with(text).splitlines() if text in line]
    assert len(lines) == 1, lines
    return lines[0]


@pytest.fixture
def readme_domain():
    """A non-zero domain no other test uses (conftest.SESSION_DOMAINS), its lock held: (id, lock handle)."""
    domain_id, handle = reserve_domain(SESSION_DOMAINS)
    yield domain_id, handle
    handle.close()


def reader_env(domain_id):
    """The environment a reader has after `export ROS_LOCALHOST_ONLY=1` and `export ROS_DOMAIN_ID=N`."""
    return dict(os.environ, ROS_LOCALHOST_ONLY="1", ROS_DOMAIN_ID=str(domain_id))


def run(command, env, timeout_s=120):
    return subprocess.run(["bash", "-c", command], cwd=SOURCE_DIR, env=env, capture_output=True, text=True,
                          timeout=timeout_s)


def test_the_python_snippet_runs_as_written(readme_domain):
    domain_id, handle = readme_domain
    handle.close()  # the snippet's hadal.Server takes the domain's lock itself
    done = run(block_with("import hadal"), reader_env(domain_id))
    assert done.returncode == 0, done.stderr
    position = [float(x) for x in re.findall(r"-?\d+\.\d*(?:e[-+]?\d+)?", done.stdout)]
    assert len(position) == 3, done.stdout  # the ROV's p_WB, drifting in the current


def test_the_probe_and_cpp_lines_read_and_drive_a_server_started_as_written(readme_domain):
    readme_env = reader_env(readme_domain[0])  # the lock stays held: this hadald is started by hand
    start = line_with("configs/scenarios/default.yaml  ").split("#")[0].strip()  # the real-time line
    server = subprocess.Popen(["bash", "-c", "exec " + start + " --no-status-line"], cwd=SOURCE_DIR, env=readme_env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        probe = run(line_with("hadal-ros2-probe").split("#")[0], readme_env)
        assert probe.returncode == 0, probe.stderr
        summary = json.loads(probe.stdout)
        assert summary["domain"] == int(readme_env["ROS_DOMAIN_ID"])
        assert summary["clock"]["count"] > 0 and summary["odometry"]["count"] > 0
        drive = run(re.search(r"`(build/bin/drive_auv[^`]*)`", open(os.path.join(SOURCE_DIR, "README.md")).read())
                    .group(1).replace("build/", BUILD_DIR + "/"), readme_env)
        assert drive.returncode == 0, drive.stderr
        assert server.poll() is None
    finally:
        server.terminate()
        out, err = server.communicate(timeout=30)
    assert server.returncode == 0, err
    assert f"DDS domain {readme_env['ROS_DOMAIN_ID']}" in err
