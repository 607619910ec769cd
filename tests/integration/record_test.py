"""hadal-record against a real lockstep hadald: the bag it writes is rosbag2's (sqlite3 storage, metadata.yaml),
holds every sample the server published, and survives kill -9 as of its last flush (issue 14)."""

import contextlib
import os
import signal
import sqlite3
import subprocess
import time

import pytest
import yaml

import hadal

RECORD = os.environ["HADAL_RECORD"]
STEPS = 1000  # 2 s at the default scenario's 500 Hz


def counts(db_path):
    """{topic: message count} of a bag's database, by rosbag2's reader join."""
    with contextlib.closing(sqlite3.connect(f"file:{db_path}?mode=ro", uri=True)) as db:
        return dict(db.execute("SELECT topics.name, COUNT(*) FROM messages JOIN topics ON messages.topic_id = "
                               "topics.id GROUP BY topics.name"))


def metadata(bag):
    with open(os.path.join(bag, "metadata.yaml")) as f:
        return yaml.safe_load(f)["rosbag2_bagfile_information"]


def start_recorder(bag, domain_id, *extra):
    recorder = subprocess.Popen([RECORD, bag, "--domain-id", str(domain_id), "--use-sim-time", *extra],
                                stderr=subprocess.PIPE, text=True)
    line = recorder.stderr.readline()  # "recording N topic(s) ..." once its readers have matched
    assert "recording" in line, line
    return recorder


def wait_until(condition, timeout_s=30.0):
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.1)


@pytest.fixture
def server():
    with hadal.Server("default", mode="lockstep", cameras=False) as server:
        yield server


def test_a_lockstep_run_is_recorded_whole_as_a_rosbag2_bag(server, tmp_path):
    bag = str(tmp_path / "run")
    recorder = start_recorder(bag, server.domain_id)
    with server.client("record_test") as client:
        for _ in range(STEPS // 50):
            client.step(50)
    db_path = os.path.join(bag, "run_0.db3")
    # Published in 2 s of sim time, t = 0 included: /clock at 100 Hz, odometry at 50 Hz
    # (configs/scenarios/default.yaml).
    wait_until(lambda: counts(db_path).get("/auv/odometry") == 101 and counts(db_path).get("/clock") == 201)
    recorder.send_signal(signal.SIGINT)
    _, err = recorder.communicate(timeout=30)
    assert recorder.returncode == 0, err
    recorded = counts(db_path)
    assert recorded["/clock"] == 201 and recorded["/lander/odometry"] == 101
    assert recorded["/auv/imu"] == 200  # 100 Hz, first sample at 0.01 s
    info = metadata(bag)
    assert info["version"] == 9 and info["storage_identifier"] == "sqlite3"
    assert info["relative_file_paths"] == ["run_0.db3"] and info["files"][0]["path"] == "run_0.db3"
    by_name = {t["topic_metadata"]["name"]: t for t in info["topics_with_message_count"]}
    assert {name: t["message_count"] for name, t in by_name.items() if t["message_count"]} == recorded
    assert info["message_count"] == sum(recorded.values())
    assert by_name["/auv/odometry"]["topic_metadata"]["type"] == "nav_msgs/msg/Odometry"
    assert by_name["/auv/imu"]["topic_metadata"]["type"] == "sensor_msgs/msg/Imu"
    assert by_name["/clock"]["topic_metadata"]["offered_qos_profiles"][0]["reliability"] == "reliable"
    # --use-sim-time: bag time is sim time, 0 .. 2 s.
    assert info["starting_time"]["nanoseconds_since_epoch"] == 0
    assert info["duration"]["nanoseconds"] == 2_000_000_000
    assert not os.path.exists(db_path + "-wal")  # closed: one file, as rosbag2 leaves it
    with contextlib.closing(sqlite3.connect(f"file:{db_path}?mode=ro", uri=True)) as db:
        (data,) = db.execute("SELECT data FROM messages JOIN topics ON topic_id = topics.id WHERE name = '/clock' "
                             "ORDER BY timestamp DESC LIMIT 1").fetchone()
        (row,) = db.execute("SELECT metadata_version FROM metadata").fetchone()
    assert data[:2] == b"\x00\x01"  # CDR little endian, as on the wire
    assert int.from_bytes(data[4:8], "little") == 2 and int.from_bytes(data[8:12], "little") == 0  # 2.000 s
    assert row == 9
    # Every topic holds what hadald says it published over its life, but for what is paced in wall time: its
    # heartbeat (/hadal/status, published before the recorder joined and after it left) and the camera
    # preview (none here: the fixture's server runs without cameras).
    assert server.stop() == 0
    wall_paced = {"/hadal/status", "/auv/camera/preview"}
    assert {topic: n for topic, n in published_counts(server.log_path).items() if topic not in wall_paced} == \
        {topic: n for topic, n in recorded.items() if topic not in wall_paced}
    assert recorded["/hadal/scene"] == 1 and recorded["/hadal/step_reply"] == STEPS // 50
    # The monitor carries the other topics' samples again: not recorded unless named, so never read, so never
    # written (absent from the published counts, which list topics with samples).
    assert "/hadal/monitor" not in recorded and "/hadal/monitor" not in published_counts(server.log_path)


def published_counts(log_path):
    """{ROS topic: samples} of the topics hadald's run summary lists as published with at least one sample."""
    counts, listing = {}, False
    with open(log_path) as log:
        for line in log:
            if line.strip() == "samples published:":
                listing = True
            elif listing and line.startswith("    rt/"):
                topic, n = line.split()
                if int(n):
                    counts[topic[2:]] = int(n)
            else:
                listing = False
    assert counts, "no 'samples published' in hadald's summary"
    return counts


def remove_port_segments(domain_id):
    """A killed process leaves Fast DDS's shared-memory port segments of its domain behind, and the ports it
    had open stay referenced after their owners exit (issue 15's subject): remove the domain's, once nothing
    runs on it, so that the next user of the domain id starts clean. Ports: 7400 + 250 * domain + offsets."""
    ports = range(7400 + 250 * domain_id, 7400 + 250 * (domain_id + 1))
    for name in os.listdir("/dev/shm"):
        for prefix in ("fastrtps_port", "sem.fastrtps_port"):
            number = name[len(prefix):].split("_")[0]
            if name.startswith(prefix) and number.isdigit() and int(number) in ports:
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(os.path.join("/dev/shm", name))


def test_kill_9_leaves_a_readable_bag_as_of_the_last_flush(tmp_path):
    with hadal.Server("default", mode="lockstep", cameras=False) as server:
        domain_id = server.domain_id
        try:
            killed_recorder_run(server, tmp_path)
        finally:  # hadald stopped, the domain's segments removed, and only then its domain id let go
            server.process.terminate()
            server.process.wait(timeout=30)
            remove_port_segments(domain_id)
            server.stop()


def killed_recorder_run(server, tmp_path):
    bag = str(tmp_path / "killed")
    recorder = start_recorder(bag, server.domain_id)
    with server.client("record_test") as client:
        client.step(STEPS)
    # The recorder flushes once per wall second: once metadata.yaml shows every /clock sample, kill it.
    wait_until(lambda: {t["topic_metadata"]["name"]: t["message_count"]
                        for t in metadata(bag)["topics_with_message_count"]}.get("/clock") == 201)
    recorder.kill()
    recorder.wait()
    assert recorder.returncode == -signal.SIGKILL
    recorded = counts(os.path.join(bag, "killed_0.db3"))
    info = metadata(bag)
    assert recorded["/clock"] == 201
    for entry in info["topics_with_message_count"]:  # the metadata never claims more than the database holds
        assert entry["message_count"] <= recorded.get(entry["topic_metadata"]["name"], 0)


def test_bad_use_is_a_clear_error(tmp_path):
    existing = tmp_path / "exists"
    existing.mkdir()
    result = subprocess.run([RECORD, str(existing)], capture_output=True, text=True)
    assert result.returncode == 2
    assert f"bag directory {existing} already exists" in result.stderr
    result = subprocess.run([RECORD, str(tmp_path / "b"), "--domain-id", "231", "--wait", "1"], capture_output=True,
                            text=True)
    assert result.returncode == 1 and "no hadald on DDS domain 231 within 1 s" in result.stderr
    assert not (tmp_path / "b").exists()  # nothing written
    result = subprocess.run([RECORD, str(tmp_path / "c"), "--topics", "auv/imu"], capture_output=True, text=True)
    assert result.returncode == 2 and "--topics takes ROS 2 names" in result.stderr


def test_hadald_record_writes_the_run_from_t_0(tmp_path):
    """hadald --record: the same recorder in the server's process, matched before the first step."""
    bag = str(tmp_path / "fast")
    domain_id, lock = hadal.server.reserve_domain(range(100, 200))
    try:
        scenario = hadal.server.scenario_path("default")
        result = subprocess.run([os.environ["HADALD"], scenario, "--mode", "fast", "--no-cameras", "--duration", "2",
                                 "--discovery-wait", "0", "--domain-id", str(domain_id), "--no-status-line",
                                 "--record", bag], capture_output=True, text=True, timeout=120)
        assert result.returncode == 0, result.stderr
        recorded = counts(os.path.join(bag, "fast_0.db3"))
        assert recorded["/clock"] == 201 and recorded["/auv/odometry"] == 101 and recorded["/auv/imu"] == 200
        assert f"recorded {sum(recorded.values())} message(s) into {bag}" in result.stderr
        assert metadata(bag)["message_count"] == sum(recorded.values())
        again = subprocess.run([os.environ["HADALD"], scenario, "--record", bag], capture_output=True, text=True)
        assert again.returncode == 2 and f"--record: bag directory {bag} already exists" in again.stderr
    finally:
        lock.close()
