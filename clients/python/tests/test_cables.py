"""Cables end to end: configs/scenarios/lift_line.yaml (the free-fall lander hanging on 40 m of wire rope from a fixed
block) run by a real lockstep hadald. Once the lander has settled, the rope's forces on its two holders differ by the
rope's own wet weight (the lander's cancels: the block carries it, the lander feels it), and its shape runs from the
block to the lander's attachment point. The block's winch lowers the lander by what it pays out and stops at its
target; commands beyond its limits are refused naming the key, attached to a step or published."""

import math
import time

import numpy as np
import pytest

import hadal

WAIT_S = 30.0
SCENARIO = "lift_line"  # configs/scenarios/lift_line.yaml
ROPE = {"length": 40.0, "diameter": 0.016, "density": 4975.0, "segments": 20}
WATER_DENSITY, G = 1025.0, 9.80665
P_BA = np.array([0.0, 0.0, 0.5])  # the attachment point on the lander's frame, in B


def test_the_rope_carries_the_lander_and_shows_its_shape():
    with hadal.Server(SCENARIO, mode="lockstep", domain_id="free") as server, server.client() as client:
        assert client.wait_cable_force("lift_line", "from", timeout_s=0) is None  # subscribes
        assert client.wait_cable_force("lift_line", "to", timeout_s=0) is None
        assert client.wait_cable_shape("lift_line", timeout_s=0) is None
        assert client.wait_for_subscriptions(WAIT_S)
        t = client.step(round(60.0 / client.status().step_size))  # 60 s: the lander's bounce has died out
        block = client.wait_cable_force("lift_line", "from", min_stamp=t - 1e-9, timeout_s=WAIT_S)
        lander = client.wait_cable_force("lift_line", "to", min_stamp=t - 1e-9, timeout_s=WAIT_S)
        shape = client.wait_cable_shape("lift_line", min_stamp=t - 1e-9, timeout_s=WAIT_S)
        odometry = client.reply_odometry("lander")
    wet_rope = (ROPE["density"] - WATER_DENSITY) * math.pi * ROPE["diameter"] ** 2 / 4 * G * ROPE["length"]
    assert block.frame_id == "world" and block.stamp == t
    assert lander.force[2] > 300.0  # the rope holds the lander up by its wet weight (~630 N)
    assert block.force[2] < -lander.force[2]  # the block carries the lander and the rope
    # 2 %: what is left of the bounce after 60 s, and the water's density at depth (the rope's is that of 1025 kg/m^3).
    assert abs(-(block.force[2] + lander.force[2]) - wet_rope) < 0.02 * wet_rope, (block.force, lander.force, wet_rope)
    points = shape.points
    assert points.shape == (ROPE["segments"] + 1, 3)
    np.testing.assert_allclose(points[0], [0.0, 0.0, -5.0], atol=1e-9)
    R = hadal.frames.rotation_matrix(odometry.q_WB)
    # The end node follows the attachment point moved on at the step start's velocity: millimetres off a settled lander.
    np.testing.assert_allclose(points[-1], np.asarray(odometry.p_WB) + R @ P_BA, atol=1e-3)
    assert points[-1][2] < -5.0 - ROPE["length"]  # stretched


def test_the_winch_lowers_the_lander_and_refuses_what_it_cannot_do():
    with hadal.Server(SCENARIO, mode="lockstep", domain_id="free") as server, server.client() as client:
        assert client.wait_winch_state("lift_line", timeout_s=0) is None  # subscribes
        assert client.wait_for_subscriptions(WAIT_S)
        step_size = client.status().step_size
        t = client.step(round(30.0 / step_size))
        state = client.wait_winch_state("lift_line", min_stamp=t - 1e-9, timeout_s=WAIT_S)
        assert (state.length, state.speed, state.drum_length, state.min_length) == (40.0, 0.0, 200.0, 2.0)
        z0 = client.reply_odometry("lander").p_WB[2]
        # Refused in lockstep, each naming its key; the request changes nothing.
        for speed, target, reason in [(0.6, 0.0, "max_speed"), (0.3, 250.0, "drum_length"), (0.3, 1.0, "min_length"),
                                      (math.nan, 0.0, "speed is not finite")]:
            client.command_winch("lift_line", speed, target, publish=False)
            with pytest.raises(hadal.CommandRejected, match=reason):
                client.step(1)
        client.command_winch("no_such_cable", 0.1, publish=False)
        with pytest.raises(hadal.CommandRejected, match="unknown cable 'no_such_cable'"):
            client.step(1)
        # Lower the lander 10 m at 0.4 m/s: ramps up in 1.6 s, runs, brakes and stops at 50 m (about 27 s). Published
        # and attached to the next step (the attached copy applies it exactly there; the published one repeats it).
        client.command_winch("lift_line", 0.4, 50.0)
        t = client.step(round(35.0 / step_size))
        state = client.wait_winch_state("lift_line", min_stamp=t - 1e-9, timeout_s=WAIT_S)
        assert state.length == 50.0 and state.speed == 0.0 and not state.at_limit
        assert state.command_speed == 0.4 and state.target_length == 50.0
        block = client.wait_cable_force("lift_line", "from", min_stamp=t - 1e-9, timeout_s=WAIT_S)
        assert state.tension == pytest.approx(math.sqrt(sum(f * f for f in block.force)), rel=1e-12)
        # The lander hangs 10 m lower, and a little more for the longer rope's stretch and weight (millimetres), less
        # what is left of its bounce.
        assert client.reply_odometry("lander").p_WB[2] == pytest.approx(z0 - 10.0, abs=0.05)
        # Published (and attached to the next step, as set_commands is): the step is refused, and the published copy
        # (the topic's writer has long been matched: the first sample a new writer publishes may reach a reader that
        # has not matched it yet, docs/dds.md), refused when the server takes it at a step, lands in the status too;
        # the server steps on.
        time.sleep(0.5)
        before = client.status().rejected_commands
        client.command_winch("lift_line", 0.3, 500.0)
        with pytest.raises(hadal.CommandRejected, match="target_length 500 m is beyond the drum"):
            client.step(1)
        deadline = time.monotonic() + WAIT_S
        while client.status().rejected_commands < before + 2 and time.monotonic() < deadline:
            client.step(1)
            time.sleep(0.05)
        status = client.status()
        assert status.rejected_commands == before + 2
        assert "cable 'lift_line': winch: target_length 500 m is beyond the drum (drum_length 200 m)" in status.last_error
        assert client.wait_winch_state("lift_line", timeout_s=WAIT_S).length == 50.0  # unchanged
