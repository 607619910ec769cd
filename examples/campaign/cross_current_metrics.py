"""Metrics of examples/campaign/cross_current.yaml: how far a cross current sets the AUV off its track.

hadal-campaign calls track_metrics(run) once per case on the worker that runs it, with a lockstep client
on that case's own hadald at t = 0 (hadal.campaign.Run); it returns the case's metrics by name (numbers).
"""

import math


def track_metrics(run):
    client = run.client
    client.wait_odometry("auv", timeout_s=0)  # subscribe, then wait until the reader has matched
    client.wait_for_subscriptions()
    start = client.wait_odometry("auv", min_stamp=0.0)
    heading0 = math.atan2(2.0 * (start.q_WB[3] * start.q_WB[2] + start.q_WB[0] * start.q_WB[1]),
                          1.0 - 2.0 * (start.q_WB[1] ** 2 + start.q_WB[2] ** 2))
    along = (math.cos(heading0), math.sin(heading0))
    cross_max, depth_min, depth_max = 0.0, -start.p_WB[2], -start.p_WB[2]
    for second in range(1, int(run.duration_s) + 1):  # a sample per sim second
        t = run.step_to(float(second))
        odometry = client.wait_odometry("auv", min_stamp=t - 1e-6)
        dx, dy = odometry.p_WB[0] - start.p_WB[0], odometry.p_WB[1] - start.p_WB[1]
        cross = -along[1] * dx + along[0] * dy  # to the left of the start heading
        cross_max = max(cross_max, abs(cross))
        depth_min, depth_max = min(depth_min, -odometry.p_WB[2]), max(depth_max, -odometry.p_WB[2])
    along_m = along[0] * dx + along[1] * dy
    return {"cross_track_m": cross, "max_cross_track_m": cross_max, "along_track_m": along_m,
            "speed_made_good_m_s": math.hypot(dx, dy) / odometry.stamp, "depth_band_m": depth_max - depth_min,
            "final_depth_m": -odometry.p_WB[2]}
