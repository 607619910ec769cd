"""Cables end to end: configs/scenarios/lift_line.yaml (the free-fall lander hanging on 40 m of wire rope from a fixed
block) run by a real lockstep hadald. Once the lander has settled, the rope's forces on its two holders differ by the
rope's own wet weight (the lander's cancels: the block carries it, the lander feels it), and its shape runs from the
block to the lander's attachment point."""

import math

import numpy as np

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
