"""Waves end to end: configs/scenarios/vessel_waves.yaml (the catamaran ASV in a JONSWAP sea, Hs 2 m, Tp 8 s, toward
45 deg, built up over 16 s) run by a real lockstep hadald. rt/vessel/sea_state carries the sea state's own figures
(its components hold Hs exactly; the build-up is half way at 8 s) and the sea at the vessel: the surface over B, with B
riding on it (B is 0.08 m above the waterline in calm
water). A scenario without waves has no sea_state topic."""

import math

import numpy as np

import hadal

WAIT_S = 30.0


def test_the_sea_state_at_the_vessel():
    with hadal.Server("vessel_waves", mode="lockstep", domain_id="free") as server, server.client() as client:
        assert client.wait_sea_state("vessel", timeout_s=0) is None  # subscribes
        assert client.wait_for_subscriptions(WAIT_S)
        step_size = client.status().step_size
        t = client.step(round(8.0 / step_size))
        half = client.wait_sea_state("vessel", min_stamp=t - 1e-9, timeout_s=WAIT_S)
        t = client.step(round(22.0 / step_size))  # 30 s: the full sea
        sea = client.wait_sea_state("vessel", min_stamp=t - 1e-9, timeout_s=WAIT_S)
        odometry = client.reply_odometry("vessel")
    assert half.stamp == 8.0 and abs(half.build_up - 0.5) < 1e-12
    assert sea.stamp == t and sea.build_up == 1.0 and sea.frame_id == "world"
    assert abs(sea.significant_height - 2.0) < 1e-9
    assert sea.peak_period == 8.0
    assert abs(sea.mean_direction - math.radians(45.0)) < 1e-12
    # The vessel rides the surface: B 0.08 m above its waterline, give or take its heave and pitch response.
    p = odometry.p_WB
    assert abs(sea.depth - (sea.surface_z - p[2])) < 1e-9
    assert -0.4 < sea.depth < 0.2, (sea.depth, sea.surface_z, p)
    assert np.linalg.norm(sea.surface_slope) < 0.5
    assert np.all(np.isfinite(sea.orbital_velocity))


def test_no_waves_no_sea_state():
    with hadal.Server("vessel", mode="lockstep", domain_id="free") as server, server.client() as client:
        assert client.wait_sea_state("vessel", timeout_s=0) is None
        t = client.step(50)
        assert client.wait_sea_state("vessel", min_stamp=t - 1e-9, timeout_s=2.0) is None
