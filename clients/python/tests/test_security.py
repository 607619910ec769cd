"""DDS Security (docs/dds.md, "DDS Security"): a hadald started with --security talks to authenticated clients
only. A client without security, and one whose certificates another CA signed, see no server, receive
nothing and command nothing, while the authenticated client steps it, reads its sensors (a camera frame
too) and drives the AUV. The demo set-up comes from tools/make-security-demo.sh (openssl)."""

import contextlib
import os
import shutil
import signal
import sqlite3
import subprocess
import time

import pytest

import hadal
from conftest import SOURCE_DIR

# Secure discovery adds an authentication handshake (Fast DDS retries it every 0.5 s).
WAIT_S = 20.0
# How long the outsiders keep writing and listening while the authenticated client runs the server.
OUTSIDER_S = 3.0

pytestmark = pytest.mark.skipif(shutil.which("openssl") is None, reason="openssl is needed to make certificates")


def make_demo(directory, *clients):
    subprocess.run([os.path.join(SOURCE_DIR, "tools/make-security-demo.sh"), str(directory), *clients],
                   check=True, capture_output=True)
    return directory


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    return make_demo(tmp_path_factory.mktemp("security") / "demo", "alice")


@pytest.fixture(scope="module")
def rogue(tmp_path_factory):
    """A set-up of the same shape made by other CAs: certificates and grants the server never trusted."""
    return make_demo(tmp_path_factory.mktemp("security") / "rogue", "alice")


def test_the_demo_script_writes_what_the_readme_says(demo):
    for name in ("identity_ca.pem", "permissions_ca.pem", "governance.p7s", "permissions.p7s", "hadald.yaml",
                 "alice.yaml", "hadald/cert.pem", "alice/key.pem"):
        assert (demo / name).is_file(), name
    assert oct((demo / "alice/key.pem").stat().st_mode & 0o777) == "0o600"
    assert oct((demo / "ca").stat().st_mode & 0o777) == "0o700"
    grants = (demo / "permissions.xml").read_text()
    assert "<subject_name>CN=hadald,O=Hadal demo</subject_name>" in grants
    assert "<subject_name>CN=alice,O=Hadal demo</subject_name>" in grants
    # Both documents verify against the permissions CA as Fast DDS checks them (PKCS7_TEXT).
    for document in ("governance.p7s", "permissions.p7s"):
        subprocess.run(["openssl", "smime", "-verify", "-text", "-in", str(demo / document), "-CAfile",
                        str(demo / "permissions_ca.pem"), "-out", os.devnull], check=True, capture_output=True)
    again = subprocess.run([os.path.join(SOURCE_DIR, "tools/make-security-demo.sh"), str(demo)],
                           capture_output=True, text=True)
    assert again.returncode == 2 and "exists" in again.stderr


def test_only_the_authenticated_client_reads_and_commands_a_secure_server(demo, rogue):
    with hadal.Server(os.path.join(SOURCE_DIR, "configs/scenarios/default.yaml"), mode="lockstep",
                      security_file=demo / "hadald.yaml", client_security_file=demo / "alice.yaml") as server, \
            hadal.Client(server.domain_id, "alice", security_file=demo / "alice.yaml") as alice, \
            hadal.Client(server.domain_id, "outsider") as plain, \
            hadal.Client(server.domain_id, "rogue", security_file=rogue / "alice.yaml") as impostor:
        with open(server.log_path) as log:
            assert "DDS Security on" in log.read()
        assert alice.wait_for_server(WAIT_S)
        # The outsiders subscribe (a first call does) to what they would read, and command full thrust all along.
        for outsider in (plain, impostor):
            outsider.wait_odometry("auv", timeout_s=0.01)
            outsider.wait_image("auv", "camera", timeout_s=0.01)
        stamp = 0.0
        for _ in range(int(OUTSIDER_S / 0.2)):
            for outsider in (plain, impostor):
                outsider.set_commands("auv", [1.0, 1.0, 1.0])
            stamp = alice.step(100)  # 0.2 s at 500 Hz
        # The scenario's schedule (0.6 ahead) still drives the AUV: no client command ever arrived.
        state = alice.wait_thruster_state("auv", min_stamp=stamp, timeout_s=WAIT_S)
        assert state is not None
        assert list(state.setpoint) == [0.6, 0.0, 0.0], "an outsider's setpoints reached the AUV"
        assert state.command_source == 1  # the scenario schedule, not a client
        idle = alice.wait_odometry("auv", min_stamp=stamp, timeout_s=WAIT_S)
        image = alice.wait_image("auv", "camera", timeout_s=WAIT_S)  # large frames pass encrypted too
        assert image is not None and image.array.max() > 0

        # The authenticated client's own command reaches the AUV: the outsiders' did not for want of access.
        for _ in range(10):
            alice.set_commands("auv", [1.0, 0.0, 0.0])
            stamp = alice.step(100)
        state = alice.wait_thruster_state("auv", min_stamp=stamp, timeout_s=WAIT_S)
        assert list(state.setpoint) == [1.0, 0.0, 0.0] and state.command_source == 2
        driven = alice.wait_odometry("auv", min_stamp=stamp, timeout_s=WAIT_S)
        assert driven.v_WB_B[0] > idle.v_WB_B[0] + 0.05  # full ahead beats the schedule's 0.6
        assert alice.status().rejected_commands == 0

        for outsider in (plain, impostor):
            assert not outsider.server_alive()
            assert outsider.status() is None
            assert outsider.wait_odometry("auv", timeout_s=0.01) is None
            assert outsider.wait_image("auv", "camera", timeout_s=0.01) is None
            assert outsider.thruster_state("auv") is None


def test_security_files_that_do_not_fit_are_clear_errors(demo, rogue, domain_id):
    # A file missing from the block names the key and the file.
    broken = demo / "broken.yaml"  # beside the others: paths are relative to the file
    broken.write_text((demo / "alice.yaml").read_text().replace("alice/key.pem", str(demo / "alice/nokey.pem")))
    with pytest.raises(RuntimeError, match=r"broken.yaml:\d+:\d+: error: security.private_key: cannot read"):
        hadal.Client(domain_id, "alice", security_file=broken)
    # A key that is not the certificate's: Fast DDS refuses, and the error says what to check.
    mixed = demo / "mixed.yaml"
    mixed.write_text((demo / "alice.yaml").read_text().replace("alice/key.pem", str(rogue / "alice/key.pem")))
    with pytest.raises(RuntimeError, match="with DDS Security: Fast DDS refused the security files"):
        hadal.Client(domain_id, "alice", security_file=mixed)
    # hadald refuses to start on a bad --security file, before anything runs.
    hadald = hadal.server.find_hadald()
    result = subprocess.run([hadald, os.path.join(SOURCE_DIR, "configs/scenarios/default.yaml"), "--domain-id",
                             str(domain_id), "--security", str(broken), "--duration", "1"],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 1
    assert "security.private_key: cannot read" in result.stderr
    assert "nothing started" in result.stderr


def bag_counts(bag):
    """{topic: message count} of a rosbag2 bag directory's database."""
    (database,) = [name for name in os.listdir(bag) if name.endswith(".db3")]
    with contextlib.closing(sqlite3.connect(f"file:{os.path.join(bag, database)}?mode=ro", uri=True)) as db:
        return dict(db.execute("SELECT topics.name, COUNT(*) FROM messages JOIN topics ON messages.topic_id = "
                               "topics.id GROUP BY topics.name"))


def wait_until(condition, timeout_s=30.0):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.1)
    return condition()


def test_a_secure_run_is_recorded_by_hadald_and_by_hadal_record(demo, tmp_path):
    """Secure participants never take Fast DDS's in-process shortcut (their GUIDs come from their
    certificates), so hadald --record reads over shared memory like any recorder; stepped in requests of 50
    steps, no writer's history of 10 overflows, and both bags must be whole, without a lost-sample warning."""
    scenario = os.path.join(SOURCE_DIR, "configs/scenarios/default.yaml")
    inside, beside = str(tmp_path / "inside"), str(tmp_path / "beside")
    record = os.path.join(os.path.dirname(hadal.server.find_hadald()), "hadal-record")
    with hadal.Server(scenario, mode="lockstep", cameras=False, security_file=demo / "hadald.yaml",
                      client_security_file=demo / "alice.yaml", extra_args=["--record", inside]) as server, \
            server.client("alice") as alice:
        recorder = subprocess.Popen([record, beside, "--domain-id", str(server.domain_id), "--use-sim-time",
                                     "--security", str(demo / "alice.yaml")], stderr=subprocess.PIPE, text=True)
        line = recorder.stderr.readline()  # once its readers have matched
        assert "recording" in line, line + recorder.stderr.read()
        # The other direction: hadald's writers match the recorder's readers on their own, later with security
        # (the crypto tokens go first); a sample written before that is missing from the bag, not lost (no gap
        # in the sequence). Once the status heartbeat arrives in the bag, hadald has matched it.
        assert wait_until(lambda: bag_counts(beside).get("/hadal/status", 0) > 0)
        for _ in range(10):
            alice.step(50)  # 1 s in all: /clock at 100 Hz and odometry at 50 Hz, t = 0 included
        assert wait_until(lambda: bag_counts(beside).get("/clock") == 101 and
                          bag_counts(beside).get("/auv/odometry") == 51), bag_counts(beside)
        recorder.send_signal(signal.SIGINT)
        _, err = recorder.communicate(timeout=30)
        assert recorder.returncode == 0, err
        assert "lost" not in err, err
        server.stop()
        with open(server.log_path) as log:
            text = log.read()
        assert "recorded" in text and "samples lost" not in text, text
    for bag in (inside, beside):
        recorded = bag_counts(bag)
        assert recorded["/clock"] == 101 and recorded["/auv/odometry"] == 51, (bag, recorded)
