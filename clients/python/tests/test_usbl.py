"""The USBL and the LBL end to end: configs/scenarios/usbl_survey.yaml (a vessel's transceiver tracking two AUVs at
~1.7 and ~3.1 km slant range through a thermocline; the first AUV ranging to three seabed beacons) run by a real
hadald. In fast mode hadald records the fixes and the
vehicles' odometry; every fix must place its transponder where the AUV was when it replied, within the fix's
own covariance, and arrive two travel times plus the turnaround after its interrogation. In lockstep a live
client reads the same fixes over DDS."""

import math
import subprocess

import numpy as np
import pytest

import hadal
from hadal.bag import Bag
from hadal.frames import rotation_matrix
from hadal.server import find_hadald, reserve_domain, scenario_path

WAIT_S = 30.0
SCENARIO = "usbl_survey"  # configs/scenarios/usbl_survey.yaml
TURNAROUND_S = {"auv": 0.05, "deep_auv": 0.1}  # the scenario's transponders
P_BT = np.array([0.0, 0.0, 0.12])  # both transponders, in B
P_BS = np.array([0.0, 0.0, -0.6])  # the transceiver on the vessel


@pytest.fixture(scope="module")
def survey_bag(tmp_path_factory):
    """12 s of the survey in fast mode, recorded by hadald (bag time = sim time). With the default discovery wait
    (2 s in fast mode), so that the recorder has matched every writer before the first step: the test needs the
    odometry from t = 0 (on a loaded machine a recorder that joins late misses the first samples)."""
    bag = tmp_path_factory.mktemp("bag") / "usbl"
    domain, lock = reserve_domain(range(200, 230))
    try:
        done = subprocess.run([find_hadald(), scenario_path(SCENARIO), "--mode", "fast", "--duration", "12",
                               "--domain-id", str(domain), "--record", str(bag), "--no-status-line"],
                              capture_output=True, text=True, timeout=300)
    finally:
        lock.close()
    assert done.returncode == 0, done.stderr
    return bag


def pose_at(odometry, t):
    """(p_WB, R_WB) at sim time t, interpolated between the 10 Hz odometry samples around it (the AUVs move
    at ~1 m/s: linear interpolation is good to millimetres; the rotation of the nearer sample)."""
    times = np.array([s for s, _ in odometry])
    k = int(np.searchsorted(times, t))
    assert 0 < k < len(times), f"no odometry around t = {t}"
    (t0, a), (t1, b) = odometry[k - 1], odometry[k]
    s = (t - t0) / (t1 - t0)
    p = (1 - s) * np.asarray(a.p_WB) + s * np.asarray(b.p_WB)
    return p, rotation_matrix((a if s < 0.5 else b).q_WB)


def test_fixes_place_each_transponder_within_their_covariance(survey_bag):
    with Bag(survey_bag) as bag:
        assert bag.topics["/vessel/usbl"] == "hadal_msgs/msg/UsblFixes"
        messages = bag.messages("/vessel/usbl")
        odometry = {name: bag.messages(f"/{name}/odometry") for name in ("vessel", "auv", "deep_auv")}
    fixes = [fix for _, message in messages for fix in message.fixes]
    # Interrogations each second from t = 1 s (a sensor's first sample); replies back after ~2.25 s (auv) and
    # ~4.2 s (deep_auv): within 12 s, interrogations 0..8 and 0..6.
    by_target = {name: sorted(f.interrogation for f in fixes if f.target == name) for name in TURNAROUND_S}
    assert by_target["auv"] == list(range(9)), by_target
    assert by_target["deep_auv"] == list(range(7)), by_target
    for t, message in messages:
        assert message.frame_id == "vessel/usbl"
        # Published at the end of the 10 ms physics step in which the reply arrived, stamped with its arrival.
        assert t - 0.01 - 1e-9 < message.stamp <= t and message.fixes[-1].stamp == message.stamp
    worst = 0.0
    for fix in fixes:
        # The true latency: two travel times plus the turnaround; the interrogation on its 1 Hz tick.
        assert fix.interrogation_stamp == pytest.approx(fix.interrogation + 1.0, abs=1e-9)
        assert fix.stamp - fix.interrogation_stamp - fix.travel_time == pytest.approx(TURNAROUND_S[fix.target],
                                                                                    abs=1e-9)
        assert fix.range == pytest.approx(np.linalg.norm(fix.position), rel=1e-12)
        assert fix.snr_db > 20.0  # above the reference SNR: the configured errors
        # The truth: the range is the mean of the two legs (the interrogation from the transceiver at the
        # interrogation to the transponder when it heard it, the reply from where it replied to the transceiver
        # at the fix: both move, the vessel heaving on its waterline), along the direction of the reply. The
        # reply left half the two-way time before the fix (to within the ~1 ms the legs differ by).
        t_reply = fix.stamp - fix.travel_time / 2
        p_WB, R_WB = pose_at(odometry[fix.target], t_reply)
        p_WT = p_WB + R_WB @ P_BT
        p_WA, R_WA = pose_at(odometry[fix.target], t_reply - TURNAROUND_S[fix.target])
        p_WV, R_WV = pose_at(odometry["vessel"], fix.stamp)
        p_WS = p_WV + R_WV @ P_BS
        p_WI, R_WI = pose_at(odometry["vessel"], fix.interrogation_stamp)
        legs = np.linalg.norm(p_WA + R_WA @ P_BT - (p_WI + R_WI @ P_BS)) + np.linalg.norm(p_WT - p_WS)
        u_S = R_WV.T @ (p_WT - p_WS) / np.linalg.norm(p_WT - p_WS)
        error_S = np.asarray(fix.position) - legs / 2 * u_S
        covariance = np.asarray(fix.position_covariance).reshape(3, 3)
        d2 = error_S @ np.linalg.solve(covariance, error_S)
        worst = max(worst, d2)
        # The same in S: the position is the world position seen from the transceiver.
        np.testing.assert_allclose(R_WV @ np.asarray(fix.position) + p_WS, fix.position_world, atol=0.05)
        assert math.isclose(fix.bearing, math.atan2(fix.position[1], fix.position[0]), abs_tol=1e-12)
    # Mahalanobis distance squared of each 3-D error: chi-square with 3 degrees of freedom, P(> 30) = 1.4e-6
    # per fix (16 fixes, seeded). A fix placed at the wrong time (1 m/s x 1 s) or with the S axes swapped
    # is hundreds.
    assert worst < 30.0, worst


def test_lbl_ranges_are_the_mean_of_the_two_legs_to_each_beacon(survey_bag):
    with Bag(survey_bag) as bag:
        assert bag.topics["/auv/lbl"] == "hadal_msgs/msg/LblRanges"
        messages = bag.messages("/auv/lbl")
        odometry = bag.messages("/auv/odometry")
    ranges = [r for _, m in messages for r in m.ranges]
    # One interrogation at t = 5 s (0.2 Hz); the beacons 2.0-2.3 km away answer within ~3.2 s.
    assert sorted(r.beacon for r in ranges) == ["north", "southeast", "southwest"]
    beacons = {"north": ([0.0, 2000.0, -2980.0], 0.05), "southeast": ([1800.0, -1000.0, -2980.0], 0.1),
               "southwest": ([-1800.0, -1000.0, -2980.0], 0.15)}
    p_BS = np.array([0.0, 0.0, -0.12])
    for r in ranges:
        position, turnaround = beacons[r.beacon]
        assert list(r.beacon_position) == position
        assert r.interrogation == 0 and r.interrogation_stamp == pytest.approx(5.0, abs=1e-9)
        assert r.stamp - r.interrogation_stamp - r.travel_time == pytest.approx(turnaround, abs=1e-9)
        assert r.range_variance == pytest.approx(0.01, rel=1e-12) and r.snr_db > 20.0
        # The AUV moves ~1 m/s: the mean of the leg out (from the interrogation) and the leg back (to the fix).
        legs = 0.0
        for t in (r.interrogation_stamp, r.stamp):
            p_WB, R_WB = pose_at(odometry, t)
            legs += np.linalg.norm(np.asarray(position) - (p_WB + R_WB @ p_BS))
        assert abs(r.range - legs / 2) < 5 * 0.1, (r.beacon, r.range - legs / 2)


def test_a_live_client_reads_the_fixes():
    with hadal.Server(SCENARIO, mode="lockstep", domain_id="free") as server, server.client() as client:
        assert client.wait_usbl_fixes("vessel", "usbl", timeout_s=0) is None
        assert client.wait_for_subscriptions(WAIT_S)
        step_size = client.status().step_size
        # The first interrogation at 1 s: auv's reply is back at ~3.25 s, deep_auv's (~5.2 s) not yet.
        t = client.step(round(3.5 / step_size))
        message = client.wait_usbl_fixes("vessel", "usbl", min_stamp=3.0, timeout_s=WAIT_S)
        assert message is not None and message.stamp <= t
        assert [f.target for f in message.fixes] == ["auv"]
        fix = message.fixes[0]
        assert 1500.0 < fix.range < 1900.0 and fix.elevation < 0.0
        assert -90.0 < fix.latitude < 90.0 and fix.altitude < -1000.0
        with pytest.raises(hadal.UnknownSensor):
            client.wait_usbl_fixes("auv", "usbl", timeout_s=0)


def test_the_acoustic_signals_in_flight_are_published_while_read(survey_bag):
    """rt/hadal/acoustic_links (what hadal-viewer draws): written while read, here by hadald's own recorder, paced
    in wall time, so its count depends on the machine; at least the first list is there."""
    with Bag(survey_bag) as bag:
        assert bag.topics["/hadal/acoustic_links"] == "hadal_msgs/msg/AcousticLinks"
        assert bag.count("/hadal/acoustic_links") >= 1
