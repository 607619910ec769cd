"""hadal-campaign (clients/python/hadal/campaign.py) on a real Dask LocalCluster of real worker processes, each
case a real lockstep hadald: the cases a file makes, its errors, the results table, retries and failures,
and the same metrics for the same case wherever it runs.

The campaigns here are small (a few cases, seconds of sim time) and nothing is timed."""

import csv
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from hadal import campaign
from hadal.errors import ScenarioError

SOURCE_DIR = os.environ.get("HADAL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "../.."))
CAMPAIGN_CLI = [sys.executable, "-m", "hadal.campaign"]

# The ROV holds still in its current; the metrics are where it is after duration_s, and (for the failure
# test) a case that raises.
METRICS = textwrap.dedent("""
    def final_pose(run):
        client = run.client
        client.wait_odometry("rov", timeout_s=0)
        client.wait_for_subscriptions()
        t = run.step_to(run.duration_s)
        odometry = client.wait_odometry("rov", min_stamp=t - 1e-6)
        return {"x_m": odometry.p_WB[0], "y_m": odometry.p_WB[1], "z_m": odometry.p_WB[2], "t_s": t,
                "current_x_m_s": run.parameters.get("world.water.current.uniform", [0.0])[0]}

    def from_bag(run):
        from hadal.bag import Bag
        with Bag(run.bag) as bag:
            t, odometry = bag.messages("/rov/odometry")[-1]
        return {"x_m": odometry.p_WB[0], "y_m": odometry.p_WB[1], "z_m": odometry.p_WB[2], "t_s": t}

    def fails_on_case_two(run):
        if run.case == 2:
            raise RuntimeError("case two always fails")
        return final_pose(run)
""")


def write_campaign(tmp_path, body, metrics=METRICS):
    (tmp_path / "metrics.py").write_text(metrics)
    path = tmp_path / "campaign.yaml"
    path.write_text(textwrap.dedent(body))
    return str(path)


SMALL = textwrap.dedent("""\
    scenario: rov
    duration_s: 2.0
    seed: 11
    samples: 2
    grid:
      world.water.current.uniform: [[0.0, 0.0, 0.0], [0.3, 0.0, 0.0]]
    parameters:
      vehicles.rov.initial_pose.position: [{uniform: [-2.0, 2.0]}, 0.0, {normal: [-60.0, 1.0]}]
    metrics: metrics.py:final_pose
""")


def test_cases_are_the_grid_times_the_draws_and_each_depends_on_seed_and_index_alone(tmp_path):
    c = campaign.load(write_campaign(tmp_path, SMALL))
    cases = c.cases()
    assert [case.parameters["world.water.current.uniform"] for case in cases] == \
        [[0.0, 0.0, 0.0]] * 2 + [[0.3, 0.0, 0.0]] * 2  # the grid's order, `samples` draws at each point
    positions = np.array([case.parameters["vehicles.rov.initial_pose.position"] for case in cases])
    assert np.all(np.abs(positions[:, 0]) <= 2.0) and np.all(positions[:, 1] == 0.0)
    assert len({case.seed for case in cases}) == 4  # a world seed per case
    # Same file, same cases; a case's draws depend on (seed, index): case 1 of a 3-sample campaign draws what
    # case 1 of the 2-sample one drew.
    assert [(k.seed, k.parameters) for k in campaign.load(c.path).cases()] == [(k.seed, k.parameters) for k in cases]
    three = campaign.load(write_campaign(tmp_path, SMALL.replace("samples: 2", "samples: 3"))).cases()
    assert (three[1].seed, three[1].parameters) == (cases[1].seed, cases[1].parameters)
    other = campaign.load(write_campaign(tmp_path, SMALL.replace("seed: 11", "seed: 12"))).cases()
    assert other[0].parameters != cases[0].parameters and other[0].seed != cases[0].seed
    # world.seed among the overrides fixes every case's world seed.
    fixed = campaign.load(write_campaign(tmp_path, SMALL + "overrides: {world.seed: 5}\n")).cases()
    assert {case.seed for case in fixed} == {5}


def test_the_distributions_draw_what_they_say(tmp_path):
    draws = campaign.load(write_campaign(tmp_path, """\
        scenario: rov
        duration_s: 1
        samples: 4000
        parameters:
          a: {uniform: [2.0, 4.0]}
          b: {normal: [10.0, 0.5]}
          c: {loguniform: [0.01, 100.0]}
          d: {integers: [1, 3]}
          e: {choice: [red, green]}
        metrics: metrics.py:final_pose
        """)).cases()
    values = {key: [case.parameters[key] for case in draws] for key in "abcde"}
    assert min(values["a"]) >= 2.0 and max(values["a"]) < 4.0
    # 4000 draws: the sample mean's standard error is 0.5/sqrt(4000) = 0.008; 5 of them is 0.04.
    assert abs(np.mean(values["b"]) - 10.0) < 0.04 and abs(np.std(values["b"]) - 0.5) < 0.03
    # log-uniform over four decades: the median is at 1 (10^0); half the draws below it, within 5 sigma of a
    # binomial count (sigma = sqrt(4000)/2 = 32).
    assert abs(sum(v < 1.0 for v in values["c"]) - 2000) < 160
    assert set(values["d"]) == {1, 2, 3} and set(values["e"]) == {"red", "green"}


@pytest.mark.parametrize("body,message", [
    ("scenario: rov\nduration_s: 1\nmetrics: metrics.py:final_pose\nsampels: 3\n",
     ":4:1: error: sampels: unknown key 'sampels'; did you mean 'samples'?"),
    ("scenario: rov\nduration_s: 1\nmetrics: metrics.py:final_pose\nparameters:\n  world.seed: {uniform: [4, 1]}\n",
     ":5:25: error: parameters.world.seed.uniform: needs [low, high] with low < high (got [4, 1])"),
    ("scenario: rov\nduration_s: 1\nmetrics: metrics.py:final_pose\nparameters:\n  x: [0, {normal: [0, -1]}]\n",
     ":5:19: error: parameters.x[1].normal: needs [mean, std] with std > 0 (got [0, -1])"),
    ("scenario: rov\nduration_s: 1\nmetrics: metrics.py:final_pose\nparameters:\n  x: {uniform: [0, 1], seed: 3}\n",
     ":5:6: error: parameters.x: a distribution is a map of one key"),
    ("scenario: rov\nduration_s: 1\nmetrics: metrics.py:final_pose\ngrid:\n  x: [{choice: [1, 2]}]\n",
     ":5:7: error: grid.x[0]: a grid's values are constants; distributions go under parameters"),
    ("scenario: rov\nduration_s: 0\nmetrics: metrics.py:final_pose\n", ":2:13: error: duration_s: must be > 0 (got 0)"),
    ("scenario: no_such_scenario\nduration_s: 1\nmetrics: metrics.py:final_pose\n",
     ":1:11: error: scenario: no scenario 'no_such_scenario'"),
    ("scenario: rov\nduration_s: 1\nmetrics: metrics.py:no_such_function\n",
     ":3:10: error: metrics: "),
    ("scenario: rov\nduration_s: 1\nmetrics: metrics.py:final_pose\nkeep_bags: true\n",
     ":4:12: error: keep_bags: bags are recorded in mode: fast only"),
    ("scenario: rov\nmetrics: metrics.py:final_pose\n", ":1:1: error: duration_s: missing (required)"),
])
def test_a_bad_campaign_file_is_an_error_at_its_line_and_column_and_nothing_runs(tmp_path, body, message):
    path = write_campaign(tmp_path, body)
    with pytest.raises(campaign.CampaignError) as error:
        campaign.load(path)
    assert any(line.startswith(path + message) for line in error.value.errors), error.value.errors
    out = tmp_path / "results.csv"
    done = subprocess.run([*CAMPAIGN_CLI, "run", path, "--out", str(out)], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 1 and path + message in done.stderr and "nothing run" in done.stderr
    assert not out.exists() and not (tmp_path / "results.png").exists()


def test_an_unknown_override_key_is_hadalds_own_error_before_anything_runs(tmp_path):
    path = write_campaign(tmp_path, SMALL.replace("world.water.current.uniform:", "world.water.current.unifrm:"))
    out = tmp_path / "results.csv"
    done = subprocess.run([*CAMPAIGN_CLI, "run", path, "--out", str(out)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 1, done.stderr
    assert "error: world.water.current.unifrm: unknown key 'unifrm'; did you mean 'uniform'?" in done.stderr
    assert "nothing run" in done.stderr and not out.exists()
    with pytest.raises(ScenarioError):
        campaign.check_cases(campaign.load(path), campaign.load(path).cases())


def test_an_unreachable_scheduler_is_a_clear_error_and_nothing_is_written(tmp_path):
    path = write_campaign(tmp_path, SMALL)
    out = tmp_path / "results.csv"
    done = subprocess.run([*CAMPAIGN_CLI, "run", path, "--out", str(out), "--scheduler", "tcp://127.0.0.1:9",
                           "--connect-timeout", "2"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert "hadal-campaign: error: no Dask scheduler answered at tcp://127.0.0.1:9 within 2 s" in done.stderr
    assert not out.exists() and not (tmp_path / "results.png").exists()


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_a_campaign_on_a_local_cluster_gives_each_case_the_metrics_it_gives_anywhere(tmp_path):
    """Four cases on two worker processes: every case ok once, in case order, with its parameters; the 0.3 m/s
    current carries the ROV downstream; a case run again in this process gives the same metrics, bit for bit."""
    path = write_campaign(tmp_path, SMALL)
    out = tmp_path / "results.csv"
    done = subprocess.run([*CAMPAIGN_CLI, "run", path, "--out", str(out), "--workers", "2"], capture_output=True,
                          text=True, timeout=240)
    assert done.returncode == 0, done.stderr
    assert "4 cases on 2 worker(s)" in done.stdout and "4 ok, 0 failed, 0 invalid, 0 retried" in done.stdout
    rows = read_rows(out)
    assert [row["case"] for row in rows] == ["0", "1", "2", "3"]
    assert all(row["status"] == "ok" and row["attempts"] == "1" and row["error"] == "" for row in rows)
    assert len({row["worker"] for row in rows}) == 2  # both workers ran cases
    c = campaign.load(path)
    cases = c.cases()
    for row, case in zip(rows, cases):
        assert int(row["seed"]) == case.seed
        assert float(row["t_s"]) == pytest.approx(2.0, abs=1e-9)
    # Drifting in 0.3 m/s for 2 s moves the ROV (its 0.06 m in the first 2 s, as its mass and added mass
    # pick up the current) downstream, +x, by more than 0.03 m; in still water it stays where its case put it.
    for row, case in zip(rows, cases):
        moved = float(row["x_m"]) - case.parameters["vehicles.rov.initial_pose.position"][0]
        assert (moved > 0.03) if case.parameters["world.water.current.uniform"][0] > 0 else (abs(moved) < 1e-6)
    # The same case here, not on a worker: the same metrics to the last bit (the CSV keeps repr's 17 digits).
    again = campaign.run_case(c.task_spec(), 3, cases[3].parameters, cases[3].seed)
    assert again["status"] == "ok"
    assert {k: repr(v) for k, v in again["metrics"].items()} == {k: rows[3][k] for k in again["metrics"]}
    assert (tmp_path / "results.png").stat().st_size > 10_000  # the summary figure


def test_a_case_that_raises_is_retried_then_reported_failed_never_dropped(tmp_path):
    path = write_campaign(tmp_path, SMALL.replace("final_pose", "fails_on_case_two") + "retries: 1\n")
    out = tmp_path / "results.csv"
    done = subprocess.run([*CAMPAIGN_CLI, "run", path, "--out", str(out), "--workers", "2", "--figure", "none"],
                          capture_output=True, text=True, timeout=240)
    assert done.returncode == 3, done.stderr
    rows = read_rows(out)
    assert [row["status"] for row in rows] == ["ok", "ok", "failed", "ok"]
    assert rows[2]["attempts"] == "2" and [row["attempts"] for row in rows if row["case"] != "2"] == ["1"] * 3
    assert rows[2]["error"].startswith("RuntimeError: case two always fails (at ") and "metrics.py:" in rows[2]["error"]
    assert "hadal-campaign: case 2 failed: RuntimeError: case two always fails" in done.stderr
    assert not (tmp_path / "results.png").exists()


def test_a_drawn_value_the_scenario_refuses_is_an_invalid_case_not_a_retry(tmp_path):
    """A case whose draw hadald refuses (a negative watchdog) is `invalid` with hadald's error, run once; the
    others run."""
    path = write_campaign(tmp_path, """\
        scenario: rov
        duration_s: 0.5
        seed: 3
        samples: 6
        parameters:
          vehicles.rov.command_timeout_s: {choice: [1.0, -1.0]}
        metrics: metrics.py:final_pose
        """)
    c = campaign.load(path)
    refused = [case.index for case in c.cases() if case.parameters["vehicles.rov.command_timeout_s"] < 0]
    assert 0 < len(refused) < 6
    results = campaign.run(c, workers=2, progress=None)
    for row in results.rows:
        if row["case"] in refused:
            assert row["status"] == "invalid" and row["attempts"] == 1
            assert "command_timeout_s: must be > 0 (got -1" in row["error"]
        else:
            assert row["status"] == "ok" and row["metrics"]["t_s"] == pytest.approx(0.5)


def test_fast_mode_scores_each_case_from_its_recorded_bag_as_lockstep_scores_it_live(tmp_path):
    """mode: fast runs hadald --mode fast --record for duration_s and hands the metrics function the bag: the
    ROV's last recorded odometry is, to the bit, what the lockstep client reads for the same cases; keep_bags
    keeps each case's bag beside the table."""
    path = write_campaign(tmp_path, SMALL.replace("metrics.py:final_pose", "metrics.py:from_bag")
                          + "mode: fast\nkeep_bags: true\n")
    out = tmp_path / "fast.csv"
    done = subprocess.run([*CAMPAIGN_CLI, "run", path, "--out", str(out), "--workers", "2", "--figure", "none"],
                          capture_output=True, text=True, timeout=240)
    assert done.returncode == 0, done.stderr
    assert f"bags {tmp_path / 'fast.bags'}" in done.stdout
    fast = read_rows(out)
    lockstep = campaign.run(campaign.load(write_campaign(tmp_path, SMALL)), workers=2, progress=None)
    for row, live in zip(fast, lockstep.rows):
        assert row["status"] == "ok" and live["status"] == "ok"
        assert [row[k] for k in ("x_m", "y_m", "z_m", "t_s")] == [repr(live["metrics"][k]) for k in ("x_m", "y_m", "z_m", "t_s")]
    from hadal.bag import Bag
    with Bag(tmp_path / "fast.bags" / "case-00003") as bag:
        assert bag.messages("/rov/odometry")[-1][1].p_WB[0] == float(fast[3]["x_m"])
