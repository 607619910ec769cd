"""hadal.Server: a hadald process launched, awaited and stopped from Python."""

import os

import pytest

import hadal
from conftest import SESSION_DOMAINS, SOURCE_DIR
from hadal.server import reserve_domain

WAIT_S = 20.0


def test_server_lifecycle():
    """By name, on a free domain, ready when it returns; stopped on leaving the block, its log kept."""
    with hadal.Server("rov", mode="lockstep", seed=3, domain_id="free") as server:
        assert server.running
        assert 100 <= server.domain_id < 200
        assert os.path.samefile(server.scenario, os.path.join(SOURCE_DIR, "configs/scenarios/rov.yaml"))
        client = hadal.Client(domain_id=server.domain_id, name="pytest")
        assert client.wait_for_server(WAIT_S)
        assert client.step(10) == pytest.approx(0.1)
        pid = server.process.pid
    assert not server.running
    assert server.process.returncode == 0  # SIGTERM: a clean stop
    assert not os.path.exists(f"/proc/{pid}")
    assert "hadald" in open(server.log_path).read()
    assert server.stop() == 0  # idempotent


def test_logs_are_kept_in_one_folder_that_keeps_the_newest(tmp_path, monkeypatch):
    """Logs go under hadal.server.LOG_ROOT, which keeps the LOGS_KEPT newest of stopped servers and never
    deletes a running server's: one running server, then three started and stopped in turn with two kept."""
    monkeypatch.setattr(hadal.server, "LOG_ROOT", str(tmp_path / "logs"))
    monkeypatch.setattr(hadal.server, "LOGS_KEPT", 2)
    with hadal.Server("lander", mode="lockstep", domain_id="free") as running:
        logs = []
        for _ in range(3):
            with hadal.Server("lander", mode="lockstep", domain_id="free") as server:
                logs.append(server.log_path)
            assert "hadald summary" in open(server.log_path).read()  # readable after stop
        assert os.path.dirname(os.path.dirname(running.log_path)) == str(tmp_path / "logs")
        assert os.path.exists(running.log_path)  # running: never pruned
        assert not os.path.exists(logs[0])  # beyond the two newest
        assert os.path.exists(logs[1]) and os.path.exists(logs[2])
        assert sorted(os.listdir(tmp_path / "logs")) == sorted(
            os.path.basename(os.path.dirname(p)) for p in (running.log_path, logs[1], logs[2]))


def test_server_is_stopped_when_the_block_raises():
    with pytest.raises(KeyError):
        with hadal.Server("lander", mode="lockstep") as server:
            raise KeyError("a user's bug")
    assert not server.running


def test_the_domain_is_ros_domain_id_as_for_every_tool_and_free_picks_an_unused_one(monkeypatch):
    """domain_id None: $ROS_DOMAIN_ID (else 0), where hadal.Client() and ros2 look too; a domain another
    hadal.Server holds is refused naming its pid; "free" gives each server its own; a bad id is a ValueError."""
    candidate, handle = reserve_domain(SESSION_DOMAINS)  # a domain no other test uses, free now
    handle.close()
    monkeypatch.setenv("ROS_DOMAIN_ID", str(candidate))
    assert hadal.default_domain_id() == candidate
    with hadal.Server("rov") as a:
        assert a.domain_id == candidate
        with hadal.Client(name="pytest") as client:  # the same rule: the same domain
            assert client.wait_for_server(WAIT_S)
        with pytest.raises(hadal.ServerNotFound, match=rf"DDS domain {candidate} is held by another hadal.Server "
                                                        rf"\(pid {os.getpid()}\): .*domain_id='free'"):
            hadal.Server("rov")
        with hadal.Server("rov", domain_id="free") as b, hadal.Server("rov", domain_id="free") as c:
            assert len({a.domain_id, b.domain_id, c.domain_id}) == 3
            assert 100 <= b.domain_id < 200 and 100 <= c.domain_id < 200
            assert a.running and b.running and c.running
    monkeypatch.delenv("ROS_DOMAIN_ID")
    assert hadal.default_domain_id() == 0
    monkeypatch.setenv("ROS_DOMAIN_ID", "300")
    with pytest.raises(ValueError, match=r"ROS_DOMAIN_ID must be an integer in 0..232 \(got '300'\)"):
        hadal.Server("rov")
    for bad in (233, -1, "any", 1.5, True):
        with pytest.raises(ValueError, match="domain_id must be an integer in 0..232, None"):
            hadal.Server("rov", domain_id=bad)


def test_a_malformed_scenario_is_a_clear_error(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("world:\n  physics_rate_hz: -5\nvehicles: []\n")
    with pytest.raises(hadal.ScenarioError) as error:
        hadal.Server(str(bad))
    assert error.value.errors == [f"{bad}:2:20: error: world.physics_rate_hz: must be in [50, 100000] (got -5)",
                                  f"{bad}:3:11: error: vehicles: must not be empty"]
    assert error.value.scenario == str(bad)
    assert str(error.value) == f"{bad}: 2 error(s) in the scenario:\n" + "\n".join(error.value.errors)
    assert isinstance(error.value, ValueError) and isinstance(error.value, hadal.ClientError)
    with pytest.raises(FileNotFoundError):
        hadal.Server("no_such_scenario")
    with pytest.raises(ValueError):
        hadal.Server("rov", mode="turbo")


def test_overrides_set_keys_as_the_file_would_and_are_checked_like_it():
    """Server(overrides=...) passes each as hadald --set: the ROV starts where the override puts it (the file
    says 90 m down); a misspelt key is the file's own error, reported at the override."""
    moved = {"vehicles.rov.initial_pose": {"position": [5.0, -2.0, -40.0]}, "world.water.current.uniform": [0.2, 0, 0]}
    with hadal.Server("rov", mode="lockstep", domain_id="free", overrides=moved) as server:
        client = hadal.Client(domain_id=server.domain_id, name="pytest")
        assert client.wait_for_server(WAIT_S)
        t = client.step(10)
        odometry = client.wait_odometry("rov", min_stamp=t, timeout_s=WAIT_S)
        assert odometry is not None
        # Within 0.05 m after a few steps of drifting in its trim and the 0.2 m/s current.
        assert abs(odometry.p_WB[0] - 5.0) < 0.05 and abs(odometry.p_WB[1] + 2.0) < 0.05
        assert abs(odometry.p_WB[2] + 40.0) < 0.05
    with pytest.raises(hadal.ScenarioError) as error:
        hadal.Server("rov", domain_id="free", overrides=["world.water.current.unifrm=[0.2, 0, 0]"])
    assert error.value.errors == ["--set world.water.current.unifrm=[0.2, 0, 0]:1:21: error: "
                                  "world.water.current.unifrm: unknown key 'unifrm'; did you mean 'uniform'?"]
    with pytest.raises(ValueError, match="not one string"):
        hadal.Server("rov", overrides="world.seed=3")
    # The same check without starting anything (hadald --check): what a campaign does before its first case.
    assert hadal.server.check_scenario("rov", overrides=moved).endswith("configs/scenarios/rov.yaml")
    with pytest.raises(hadal.ScenarioError) as error:
        hadal.server.check_scenario("rov", overrides={"vehicles.rov.command_timeout_s": -1})
    assert len(error.value.errors) == 1 and "vehicles.rov.command_timeout_s=-1:1:" in error.value.errors[0]


def test_lockstep_spin_goes_to_hadald_and_is_checked_there():
    """Server(lockstep_spin_us=...) is hadald --lockstep-spin-us; hadald refuses a value out of range."""
    with hadal.Server("rov", mode="lockstep", domain_id="free", lockstep_spin_us=0) as server:
        with open(f"/proc/{server.process.pid}/cmdline") as cmdline:
            args = cmdline.read().split("\0")
        assert args[args.index("--lockstep-spin-us") + 1] == "0"
        client = hadal.Client(domain_id=server.domain_id, name="pytest")
        assert client.wait_for_server(WAIT_S)
        assert abs(client.step(5) - 0.05) < 1e-9  # rov.yaml steps at 100 Hz
    with pytest.raises(hadal.ServerNotFound, match=r"--lockstep-spin-us must be an integer in 0\.\.100000"):
        hadal.Server("rov", lockstep_spin_us=100001)


def test_a_cpu_the_process_may_not_run_on_is_a_clear_error():
    """hadald --cpus refuses a CPU outside the launching process's set before anything starts."""
    missing = max(os.sched_getaffinity(0)) + 1
    with pytest.raises(hadal.ServerNotFound) as error:
        hadal.Server("rov", cpus=[missing], sched="batch")
    assert f"--cpus {missing}: CPU {missing} is not one this process may run on" in str(error.value)
    with pytest.raises(hadal.ServerNotFound, match="--sched must be batch or other"):
        hadal.Server("rov", sched="fifo")
