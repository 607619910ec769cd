"""hadal-viewer in a real browser (issue 14): Debian's headless Chromium, driven over its DevTools protocol,
loads the page against a running lockstep hadald and a recorded bag. The page shows the seabed and the
vehicle, the vehicle's pose in the 3-D view is the odometry's after steps, an articulated vehicle's arm is
drawn where its joints put it, the camera pane shows a frame that is not black, and a bag replays with
seeking. Screenshots go to HADAL_ARTIFACTS (build/test-artifacts/
viewer) for a person to look at."""

import contextlib
import glob
import math
import json
import os
import re
import signal
import sqlite3
import struct
import subprocess
import sys
import threading
import time
import urllib.request

import numpy as np
import pytest
import websocket

import hadal
from hadal.server import reserve_domain

sys.path.insert(0, os.path.join(os.environ["HADAL_SOURCE_DIR"], "tools/viewer"))
from cdp_browser import Browser, wait_until  # noqa: E402

VIEWER = os.environ["HADAL_VIEWER"]
HADALD = os.environ["HADALD"]
SOURCE_DIR = os.environ["HADAL_SOURCE_DIR"]
ARTIFACTS = os.environ.get("HADAL_ARTIFACTS", "test-artifacts/viewer")
CAMERA = "/auv/camera/preview"  # the camera's half-resolution preview (dds/image_preview.h)


def start_viewer(*args):
    viewer = subprocess.Popen([VIEWER, "--port", "0", *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True)
    line = viewer.stdout.readline()
    assert line.startswith("hadal-viewer: serving http://127.0.0.1:"), line + viewer.stderr.read()
    return viewer, line.split()[2]


def read_line(process, timeout_s):
    """The process's next stdout line, or None when none comes within timeout_s."""
    lines = []
    reader = threading.Thread(target=lambda: lines.append(process.stdout.readline()), daemon=True)
    reader.start()
    reader.join(timeout_s)
    return lines[0] if lines else None


def monitor_written(server):
    """How many monitor samples the stopped server wrote (its summary's count)."""
    with open(server.log_path) as log:
        return int(re.search(r"rt/hadal/monitor ([0-9]+)\n", log.read()).group(1))


def stop(process):
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=30)
    assert process.returncode == 0, err
    return err


@pytest.fixture
def browser(tmp_path):
    browser = Browser(str(tmp_path / "chromium"))
    yield browser
    assert not [c for c in browser.console if c and "Error" in c], browser.console
    browser.close()


def bag_odometry(bag, topic):
    """What the viewer shows of `topic` after a seek: (start, rows) with start the bag's first time [s] (the
    timeline's 0) and rows (bag time [s], stamp [s], p_WB, q_WB) of every nav_msgs/Odometry on the topic in
    the order the viewer feeds them (bag time, then id). Bag times are the sim time the recorder had seen
    on /clock when a sample came, which in a fast run can be a step or two past the sample's own stamp.
    Each decoded from its CDR (XCDR1, little endian: a 4-byte encapsulation header, then each field aligned
    to its size from there): the header's stamp (int32 sec, uint32 nanosec), two strings (uint32 length with
    the NUL, the bytes), then the pose's position and orientation as doubles."""
    (db_path,) = glob.glob(os.path.join(bag, "*.db3"))
    with contextlib.closing(sqlite3.connect(f"file:{db_path}?mode=ro", uri=True)) as db:
        (start,) = db.execute("SELECT MIN(timestamp) FROM messages").fetchone()
        rows = db.execute("SELECT messages.timestamp, data FROM messages JOIN topics ON topic_id = topics.id "
                          "WHERE name = ? ORDER BY messages.timestamp, messages.id", (topic,)).fetchall()
    poses = []
    for (bag_ns, data) in rows:
        assert data[:2] == b"\x00\x01", "not little-endian CDR"
        body = data[4:]
        sec, nanosec = struct.unpack_from("<iI", body, 0)
        at = 8
        for _ in range(2):  # frame_id, child_frame_id
            at = (at + 3) // 4 * 4
            (length,) = struct.unpack_from("<I", body, at)
            at += 4 + length
        at = (at + 7) // 8 * 8
        values = struct.unpack_from("<7d", body, at)
        poses.append((1e-9 * bag_ns, sec + 1e-9 * nanosec, list(values[:3]), list(values[3:])))
    return 1e-9 * start, poses


def showing(browser, stamp):
    """The page's pose of the AUV when its stamp is `stamp` [s], else None."""
    pose = page_pose(browser, "auv")
    return pose if pose and abs(pose["stamp"] - stamp) < 1e-9 else None


def shown_after_seek(recorded, t):
    """The odometry the viewer shows after a seek to t [s] on its timeline: the last fed at or before it."""
    start, rows = recorded
    return [row for row in rows if row[0] <= start + t + 1e-12][-1]


def page_pose(browser, vehicle):
    return browser.evaluate(f"hadalViewer.vehiclePose('{vehicle}')")


def test_the_page_shows_a_lockstep_run_as_odometry_has_it(browser, tmp_path):
    with hadal.Server("default", mode="lockstep") as server:
        viewer, url = start_viewer("--domain-id", str(server.domain_id))
        try:
            browser.open(url)
            # The scene: the default scenario's procedural seabed (400 m at 2 m: 80 000 triangles) and both
            # vehicles with their meshes.
            wait_until(lambda: browser.evaluate("hadalViewer.seabedTriangles()") == 80000, 60, "the seabed")
            with server.client("viewer_test") as client:
                for _ in range(10):
                    client.step(50)  # 1 s of sim time in all
                odometry = client.wait_odometry("auv", min_stamp=1.0)
                assert odometry is not None and abs(odometry.stamp - 1.0) < 1e-9
                # The 3-D view's vehicle is where odometry says, to the last bit (JSON carries the shortest
                # exact decimal of each double).
                pose = wait_until(lambda: (p := page_pose(browser, "auv")) and p["stamp"] >= 1.0 and p, 30,
                                  "the page's pose at t = 1 s")
                assert pose["stamp"] == pytest.approx(1.0, abs=1e-9)
                np.testing.assert_array_equal(pose["p"], odometry.p_WB)
                np.testing.assert_array_equal(pose["q"], odometry.q_WB)
                assert pose["meshes"] >= 1 and pose["on_screen"], pose
                # The camera pane: a frame of the run, not black (the AUV's lights on the lander and seabed).
                camera = wait_until(lambda: browser.evaluate(f"hadalViewer.cameraMean('{CAMERA}')"), 30,
                                    "a camera frame in the page")
                assert camera["width"] == 320 and camera["height"] == 240
                assert camera["mean"] > 10.0, camera
                browser.screenshot(os.path.join(ARTIFACTS, "live_lockstep_t1.png"))
                trail_at_1s = browser.evaluate("hadalViewer.state.vehicles.auv.trailCount")
                for _ in range(20):
                    client.step(50)
                odometry = client.wait_odometry("auv", min_stamp=3.0)
                pose = wait_until(lambda: (p := page_pose(browser, "auv")) and p["stamp"] >= 3.0 and p, 30,
                                  "the page's pose at t = 3 s")
                np.testing.assert_array_equal(pose["p"], odometry.p_WB)
                # The status line's numbers (hadald's status is a 10 Hz wall-clock heartbeat: wait for it).
                status = wait_until(lambda: (s := browser.evaluate("hadalViewer.state.lastUpdate.status")) and
                                    s["steps"] == 1500 and s, 30, "the status at 1500 steps")
                assert status["mode"] == "lockstep"
                assert "1500 steps" in browser.evaluate("document.getElementById('status').textContent")
                # The trail grew (the viewer follows hadald's monitor, at most 20 samples per wall second: one
                # point per sample that moved 5 cm or more).
                assert browser.evaluate("hadalViewer.state.vehicles.auv.trailCount") > max(trail_at_1s, 1)
                browser.screenshot(os.path.join(ARTIFACTS, "live_lockstep_t3.png"))
        finally:
            err = stop(viewer)
    assert re.search(r", 0 undecodable$", err.strip()), err
    assert monitor_written(server) > 0  # the page's viewer read the monitor


def test_the_page_draws_an_arm_where_its_joints_put_it(browser):
    """The work-class ROV's arm, commanded away from its stowed pose: the page draws every moving body where
    the scene's links and the joints' positions put it (X_WK = X_WB X_parent_K(q) down the tree, worked out
    here from the odometry, the scene's kinematics and the joint states as the client reads them). Within
    1e-4 m and 1e-5 in the rotation: three.js's matrices are float32, 1500 m down (1e-4 m there)."""
    scenario = os.path.join(SOURCE_DIR, "configs", "scenarios", "rov_intervention.yaml")
    with hadal.Server(scenario, mode="lockstep", cameras=False) as server:
        viewer, url = start_viewer("--domain-id", str(server.domain_id))
        try:
            browser.open(url)
            links = wait_until(lambda: browser.evaluate("hadalViewer.state.scene && hadalViewer.state.scene.links"),
                               60, "the scene's links")
            # Eight moving bodies: the Oberon 7's finger tips are locked, part of their fingers' bodies.
            assert len(links) == 8 and links[0]["parent"] == "base_link", links
            with server.client("viewer_arm_test") as client:
                client.set_joint_commands("rov", "arm", [0.6, 0.4, -0.5, 0.3, 0.5, 0.2])
                client.step(500)  # 1 s
                odometry = client.wait_odometry("rov", min_stamp=1.0)
                joints = client.wait_joint_state("rov", min_stamp=1.0)
                positions = dict(zip(joints.names, joints.position))
                assert abs(positions["azimuth"]) > 0.05  # moving towards its command
                page = wait_until(lambda: (v := browser.evaluate("hadalViewer.state.lastUpdate.vehicles.rov")) and
                                  v["stamp"] >= 1.0 and v.get("joints") == positions and v, 30,
                                  "the page's pose and joints at t = 1 s")
                np.testing.assert_array_equal(page["p"], odometry.p_WB)
                posed = {"base_link": (hadal.frames.rotation_matrix(odometry.q_WB), np.asarray(odometry.p_WB))}
                drawn = 0
                for link in links:
                    R_P, p_P = posed[link["parent"]]
                    R = R_P @ hadal.frames.rotation_matrix(link["q"])
                    p = p_P + R_P @ np.asarray(link["p"])
                    axis, q = np.asarray(link["axis"]), positions[link["joint"]]
                    if link["joint_type"] == "prismatic":
                        p = p + R @ axis * q
                    else:
                        K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
                        R = R @ (np.eye(3) + np.sin(q) * K + (1 - np.cos(q)) * K @ K)
                    posed[link["name"]] = (R, p)
                    shown = browser.evaluate(f"hadalViewer.linkPose('rov', '{link['name']}')")
                    np.testing.assert_allclose(shown["p"], p, rtol=0, atol=1e-4, err_msg=link["name"])
                    np.testing.assert_allclose(hadal.frames.rotation_matrix(shown["q"]), R, rtol=0, atol=1e-5,
                                               err_msg=link["name"])
                    drawn += shown["vertices"] > 0
                assert drawn >= 6, drawn  # the arm's bodies with a mesh
                # The wrist's force/torque frame rides on its body.
                frame = browser.evaluate("(() => { const f = hadalViewer.state.frames['rov/wrist_ft']; "
                                         "f.object.updateMatrixWorld(true); const p = f.object.getWorldPosition("
                                         "f.object.position.clone()); return {frame: f.frame, p: [p.x, p.y, p.z]}; })()")
                R, p = posed[frame["frame"]["link"]]
                np.testing.assert_allclose(frame["p"], p + R @ np.asarray(frame["frame"]["link_p"]), rtol=0,
                                           atol=1e-4)
                browser.screenshot(os.path.join(ARTIFACTS, "rov_arm.png"))
        finally:
            stop(viewer)


def test_the_page_draws_the_moving_sea(browser):
    """vessel_waves.yaml (a JONSWAP sea): the scene carries the sea state's components, from which the page draws
    the surface around the followed vehicle at the latest sim time. Its middle vertex is eta(x, y, t) = r(t) sum a
    cos(k (x cos b + y sin b) - w t + phi) worked out here from the scene's components (1e-5 m: three.js's float32
    positions), and the same components give the surface rt/vessel/sea_state reports over the vessel (1e-9 m)."""
    with hadal.Server("vessel_waves", mode="lockstep", cameras=False) as server:
        viewer, url = start_viewer("--domain-id", str(server.domain_id))
        try:
            browser.open(url)
            waves = wait_until(lambda: browser.evaluate("hadalViewer.state.scene && hadalViewer.state.scene.waves"),
                               60, "the scene's waves")
            assert len(waves["components"]) == 128 and waves["ramp_time"] == 16.0
            z0 = browser.evaluate("hadalViewer.state.scene.water_surface_z")

            def eta(x, y, t):
                r = 1.0 if t >= waves["ramp_time"] else 0.5 * (1.0 - math.cos(math.pi * t / waves["ramp_time"]))
                return z0 + r * sum(a * math.cos(k * (x * math.cos(b) + y * math.sin(b)) - w * t + phi)
                                    for a, w, k, b, phi in waves["components"])

            with server.client("viewer_waves_test") as client:
                assert client.wait_sea_state("vessel", timeout_s=0) is None
                assert client.wait_for_subscriptions(30.0)
                t = client.step(1000)  # 10 s at 100 Hz: the sea building up
                sea = client.wait_sea_state("vessel", min_stamp=t - 1e-9, timeout_s=30.0)
                odometry = client.reply_odometry("vessel")
                assert abs(eta(odometry.p_WB[0], odometry.p_WB[1], t) - sea.surface_z) < 1e-9
                drawn = wait_until(lambda: (s := browser.evaluate("hadalViewer.seaSurface()")) and
                                   abs(s["time"] - t) < 1e-9 and s, 30, "the surface at the last step")
            x, y, z = drawn["p"]
            assert abs(x - odometry.p_WB[0]) < 2.5 and abs(y - odometry.p_WB[1]) < 2.5  # snapped to the 2.5 m grid
            assert abs(z - eta(x, y, t)) < 1e-5, (z, eta(x, y, t))
            assert abs(eta(x, y, t) - z0) > 1e-3  # a sea, not the mean level
            browser.screenshot(os.path.join(ARTIFACTS, "vessel_waves.png"))
        finally:
            stop(viewer)


def test_ten_loads_in_a_row_each_show_the_run_at_their_load_event(browser):
    """What a one-shot screenshot (chromium --headless --screenshot) shows: the page at its load event. Each of ten
    loads of a real-time run shows, then, the seabed drawn, both vehicles posed, the camera and sonar panes with a
    frame and the status line (hadal-viewer serves the page's first state, /first.js, once it has them); the
    WebSocket then carries the run on without sending the scene again."""
    with hadal.Server("default", mode="realtime") as server:
        viewer, url = start_viewer("--domain-id", str(server.domain_id))
        try:
            # Loads of a run the viewer found (finding hadald on a loaded machine can take longer than the first
            # state waits for a hadald that is not there).
            line = read_line(viewer, 60)
            assert line and line.startswith("hadal-viewer: watching hadald ("), line
            for load in range(10):
                browser.load(url)
                at_load = browser.evaluate("hadalViewer.atLoad")
                shown = {k: v for k, v in at_load.items() if k != "poses"}
                assert at_load["seabed_triangles"] == 80000, (load, shown)
                # The 3-D view is drawn: the seabed fills most of it (0.85 of the pixels here; the background
                # only above the horizon).
                assert at_load["drawn"] > 0.5, (load, shown)
                for vehicle in ("auv", "lander"):
                    assert at_load["poses"][vehicle] and at_load["poses"][vehicle]["stamp"] > 0, (load, at_load)
                assert at_load["poses"]["auv"]["on_screen"], (load, at_load)
                for topic in (CAMERA, "/auv/fls/preview"):
                    pane = at_load["cameras"].get(topic)
                    assert pane and pane["mean"] > 10.0, (load, topic, shown)
                assert at_load["status"].startswith("sim ") and " realtime " in at_load["status"], (load, shown)
            # After the load the WebSocket carries the run on, and its join did not send the scene again.
            stamp = at_load["poses"]["auv"]["stamp"]
            wait_until(lambda: page_pose(browser, "auv")["stamp"] > stamp + 0.5, 30, "the page following the run")
            assert browser.evaluate("hadalViewer.state.scenes") == 1
            browser.screenshot(os.path.join(ARTIFACTS, "live_realtime_tenth_load.png"))
        finally:
            err = stop(viewer)
    assert re.search(r", 0 undecodable$", err.strip()), err


def test_a_viewer_without_a_page_costs_the_server_no_writes():
    """With no page open, a live viewer reads only the scene, which the server wrote once before anyone joined:
    the monitor and the camera previews, written only while read, stay unwritten however long the run."""
    with hadal.Server("default", mode="lockstep") as server:
        viewer, _ = start_viewer("--domain-id", str(server.domain_id))
        try:
            line = read_line(viewer, 60)
            assert line and line.startswith("hadal-viewer: watching hadald ("), line
            with server.client("viewer_test") as client:
                for _ in range(20):
                    client.step(50)  # 2 s of sim time
                assert client.wait_odometry("auv", min_stamp=2.0) is not None
            # The monitor's pace is wall time (at most every 50 ms): let several of its chances pass.
            time.sleep(1.0)
        finally:
            err = stop(viewer)
    with open(server.log_path) as log:
        summary = log.read()
    assert "rt/hadal/monitor 0\n" in summary and "rt/auv/camera/preview 0\n" in summary, summary
    assert re.search(r"^hadal-viewer: 1 sample\(s\) shown, 0 undecodable$", err.strip(), re.M), err  # the scene


def test_a_recorded_bag_replays_and_seeks(browser, tmp_path):
    bag = str(tmp_path / "bag")
    reserved = reserve_domain(range(100, 200))  # the run's own DDS domain, as every test's
    assert reserved, "no free DDS domain in 100..199"
    domain_id, lock = reserved
    with lock:
        run = subprocess.run([HADALD, os.path.join(SOURCE_DIR, "configs/scenarios/default.yaml"), "--mode", "fast",
                              "--duration", "4", "--record", bag, "--no-status-line", "--domain-id", str(domain_id)],
                             env=dict(os.environ, ROS_LOCALHOST_ONLY="1"), capture_output=True, text=True,
                             timeout=120)
    assert run.returncode == 0, run.stderr
    viewer, url = start_viewer("--bag", bag)
    try:
        # At its load event the page shows the bag: the seabed and the camera's first frame.
        browser.load(url)
        at_load = browser.evaluate("hadalViewer.atLoad")
        assert at_load["seabed_triangles"] == 80000 and at_load["drawn"] > 0.5, at_load
        assert at_load["cameras"].get(CAMERA) and at_load["cameras"][CAMERA]["mean"] > 10.0, at_load
        source = wait_until(lambda: browser.evaluate("hadalViewer.state.source"), 30, "the bag's controls")
        assert source["kind"] == "bag" and source["duration"] == pytest.approx(4.0, abs=0.011)
        assert browser.evaluate("document.getElementById('bagbar').hidden") is False
        # Seek to 2 s: the vehicle is where the bag's last odometry fed by then had it, to the last bit. Bag
        # times are the sim time the recorder had seen on /clock when a sample came, so under load in a fast
        # run that sample can be stamped before 2 s.
        browser.evaluate("send({cmd: 'pause'})")  # the page's own command (the play button toggles)
        wait_until(lambda: not browser.evaluate("hadalViewer.state.source.playing"), 10, "pause")
        browser.evaluate("(() => { const t = document.getElementById('timeline'); t.value = 2;"
                         " t.dispatchEvent(new Event('input')); })()")
        recorded = bag_odometry(bag, "/auv/odometry")
        _, stamp_2s, p_2s, q_2s = shown_after_seek(recorded, 2.0)
        # Stamped 2 s, or earlier when its sample came after /clock had passed it (seen: 1.78 s under load), or
        # later when /clock came late (seen: 2.4 s with the test suite running beside it).
        assert 1.0 < stamp_2s < 3.0, stamp_2s
        pose2 = wait_until(lambda: showing(browser, stamp_2s), 30,
                           "the pose at 2 s")
        np.testing.assert_array_equal(pose2["p"], p_2s)
        np.testing.assert_array_equal(pose2["q"], q_2s)
        browser.screenshot(os.path.join(ARTIFACTS, "bag_seek_2s.png"))
        trail2 = browser.evaluate("hadalViewer.state.vehicles.auv.trailCount")
        # Back to 1 s: the state starts over from the bag's beginning and lands on the 1 s pose; the trail
        # is shorter; forward again to 2 s gives the same pose as before.
        browser.evaluate("(() => { const t = document.getElementById('timeline'); t.value = 1;"
                         " t.dispatchEvent(new Event('input')); })()")
        _, stamp_1s, p_1s, _ = shown_after_seek(recorded, 1.0)
        assert stamp_1s < stamp_2s, (stamp_1s, stamp_2s)
        pose1 = wait_until(lambda: showing(browser, stamp_1s), 30,
                           "the pose at 1 s")
        np.testing.assert_array_equal(pose1["p"], p_1s)
        assert pose1["p"] != pose2["p"]
        assert 0 < wait_until(lambda: browser.evaluate("hadalViewer.state.vehicles.auv.trailCount") < trail2, 10,
                              f"a trail shorter than the {trail2} points at {stamp_2s} s (stamp {stamp_1s} s)")
        browser.evaluate("(() => { const t = document.getElementById('timeline'); t.value = 2;"
                         " t.dispatchEvent(new Event('input')); })()")
        again = wait_until(lambda: showing(browser, stamp_2s), 30,
                           "the pose at 2 s again")
        assert again["p"] == pose2["p"] and again["q"] == pose2["q"]
        camera = wait_until(lambda: browser.evaluate(f"hadalViewer.cameraMean('{CAMERA}')"), 30, "a camera frame")
        assert camera["mean"] > 10.0, camera
    finally:
        err = stop(viewer)
    assert re.search(r", 0 undecodable$", err.strip()), err


def test_the_viewer_loads_no_blas_and_little_static_tls():
    """civetweb (Debian's build) runs each request on a worker thread with a 100 KiB stack, and glibc places every
    loaded library's static TLS at the top of each thread's stack. OpenCV's core loads libblas.so.3, which on a
    machine whose BLAS alternative is OpenBLAS (a fresh Debian 12 with the project's packages: seen in a
    container) brings 60 KiB of it: the viewer then died (SIGSEGV, stack overflow in its first page request's
    printf). So: no OpenCV and no BLAS in what it loads, and the static TLS of everything it loads well below
    the stack (16 KiB; ~4 KiB here)."""
    run = subprocess.run(["ldd", VIEWER], capture_output=True, text=True, check=True)
    libraries = [line.split("=>")[1].split("(")[0].strip() for line in run.stdout.splitlines()
                 if "=>" in line and "/" in line.split("=>")[1]]
    assert libraries, run.stdout
    assert not [lib for lib in libraries if re.search(r"libopencv|libblas|libopenblas|liblapack", lib)], run.stdout
    tls = 0
    for library in libraries:
        headers = subprocess.run(["readelf", "-lW", library], capture_output=True, text=True, check=True).stdout
        for line in headers.splitlines():
            fields = line.split()
            if fields and fields[0] == "TLS":
                tls += int(fields[5], 16)  # MemSiz
    assert tls < 16 * 1024, tls


def test_usage_errors_and_the_token(tmp_path):
    run = subprocess.run([VIEWER, "--bind", "0.0.0.0"], capture_output=True, text=True, timeout=30)
    assert run.returncode == 2 and "give --token" in run.stderr, run.stderr
    run = subprocess.run([VIEWER, "--port", "70000"], capture_output=True, text=True, timeout=30)
    assert run.returncode == 2 and "--port must be" in run.stderr, run.stderr
    run = subprocess.run([VIEWER, "--bag", str(tmp_path / "none")], capture_output=True, text=True, timeout=30)
    assert run.returncode == 1 and "no bag directory" in run.stderr, run.stderr
    run = subprocess.run([VIEWER], capture_output=True, text=True, timeout=30,
                         env=dict(os.environ, ROS_DOMAIN_ID="300"))
    assert run.returncode == 2 and "ROS_DOMAIN_ID must be an integer in 0..232" in run.stderr, run.stderr
    run = subprocess.run([VIEWER, "--nice", "20"], capture_output=True, text=True, timeout=30)
    assert run.returncode == 2 and "--nice takes an integer in 0..19" in run.stderr, run.stderr
    viewer, url = start_viewer("--token", "s3cret", "--domain-id", "231")
    try:
        assert url.endswith("/?token=s3cret")
        # It runs below the server's priority (--nice 10 by default; field 19 of /proc/PID/stat).
        with open(f"/proc/{viewer.pid}/stat") as stat:
            assert int(stat.read().rsplit(")", 1)[1].split()[16]) == 10
        base = url.split("?")[0]
        with pytest.raises(urllib.error.HTTPError) as refused:
            urllib.request.urlopen(base)
        assert refused.value.code == 403
        with urllib.request.urlopen(url) as page:
            assert page.status == 200 and "hadal_token=s3cret" in page.headers["Set-Cookie"]
        # The page's first state, with no hadald on the domain: served all the same (without a scene; the
        # WebSocket brings one when a hadald comes), and only with the token.
        with urllib.request.urlopen(base + "first.js?token=s3cret") as first:
            text = first.read().decode()
        assert text.startswith('window.hadalFirst = {"scene_id":null,"scene":null,"meshes":[],'), text[:200]
        assert '"source":{"kind":"live","domain":231,"connected":false}' in text, text[-300:]
        with pytest.raises(urllib.error.HTTPError) as refused:
            urllib.request.urlopen(base + "first.js")
        assert refused.value.code == 403
        with pytest.raises((websocket.WebSocketBadStatusException, websocket.WebSocketConnectionClosedException)):
            websocket.create_connection(base.replace("http", "ws") + "ws", timeout=10)
        socket = websocket.create_connection(base.replace("http", "ws") + "ws", timeout=10,
                                             cookie="hadal_token=s3cret")
        assert json.loads(socket.recv())["type"] in ("history", "update")
        socket.close()
        for path in ("../etc/passwd", "%2e%2e/%2e%2e/etc/passwd", "viewer.js/../../viewer_main.cc"):
            with pytest.raises(urllib.error.HTTPError) as missing:
                urllib.request.urlopen(base + path + "?token=s3cret")
            assert missing.value.code in (400, 404), path
    finally:
        stop(viewer)
    # Without a token (loopback): another site's page in the same browser cannot open the WebSocket, nor can
    # a request that names another host (DNS rebinding).
    viewer, url = start_viewer("--domain-id", "231")
    try:
        ws_url = url.replace("http", "ws") + "ws"
        with pytest.raises((websocket.WebSocketBadStatusException, websocket.WebSocketConnectionClosedException)):
            websocket.create_connection(ws_url, timeout=10, origin="http://evil.example")
        with pytest.raises(urllib.error.HTTPError) as refused:
            urllib.request.urlopen(urllib.request.Request(url, headers={"Host": "evil.example"}))
        assert refused.value.code == 403
        socket = websocket.create_connection(ws_url, timeout=10)  # the page's own origin
        assert json.loads(socket.recv())["type"] in ("history", "update")
        socket.close()
    finally:
        stop(viewer)
