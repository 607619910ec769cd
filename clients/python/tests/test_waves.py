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


def test_a_glider_surfacing_in_waves_gets_fixes_only_between_crests():
    """configs/scenarios/glider_surfacing.yaml: the glider climbs from 12 m into a swell (Hs 1 m, Tp 10 s) and lies at
    the surface, B a few decimetres under it, tossed by the waves. Its GPS antenna (0.26 m above B in the tail fin) is
    in the air only part of the time: from 160 s on, sampled each second, some samples are fixes and some are not, and
    every fix comes with B within 0.6 m of the surface over it (sea_state) and every sample with B deeper than 1 m is
    no fix."""
    with hadal.Server("glider_surfacing", mode="lockstep", domain_id="free") as server, server.client() as client:
        assert client.wait_sea_state("glider", timeout_s=0) is None
        assert client.wait_nav_sat_fix("glider", "gps", timeout_s=0) is None
        assert client.wait_for_subscriptions(WAIT_S)
        step_size = client.status().step_size
        t = client.step(round(160.0 / step_size))
        fixes, no_fixes = 0, 0
        for _ in range(140):
            t = client.step(round(1.0 / step_size))
            fix = client.wait_nav_sat_fix("glider", "gps", min_stamp=t - 1e-9, timeout_s=WAIT_S)
            sea = client.wait_sea_state("glider", min_stamp=t - 1e-9, timeout_s=WAIT_S)
            assert fix.stamp == t and sea.stamp == t
            assert sea.depth < 1.5, (t, sea.depth)  # at the surface
            if fix.has_fix():
                fixes += 1
                assert sea.depth < 0.6, (t, sea.depth)
            else:
                no_fixes += 1
    assert fixes >= 5 and no_fixes >= 5, (fixes, no_fixes)
