"""examples/python/dead_reckoning.py, run in a short form as a subprocess that starts its own lockstep hadald."""

import os

from conftest import SOURCE_DIR, run_example

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def test_dead_reckoning_drifts_less_than_one_percent_of_distance(tmp_path):
    """30 s of the first straight leg from rest (the first turn is at 30 s): ~29 m at up to 1.07 m/s.

    The error budget over 30 s (configs/vehicles/torpedo_auv.yaml): the DVL's turn-on bias, 2 mm/s (1 sigma)
    per axis, is the largest term: its horizontal magnitude is Rayleigh-distributed, below 3.7 sigma =
    7.4 mm/s with 99.9 % probability, which is 0.22 m after 30 s. Its ping noise (5 mm/s per beam, ~7 mm/s
    per horizontal axis at 30 deg beams) integrated over 150 pings of 0.2 s adds ~0.02 m; the HG1700 gyro
    (1 deg/h bias, 0.125 deg/sqrt(h) random walk) turns the heading by ~0.02 deg at most, under 0.01 m at
    30 m. So the final horizontal error stays under 1 % of the distance (~0.3 m) and the heading error
    under 0.1 deg. Depth comes from the pressure sensor (50 Pa of noise = 5 mm of water): within 5 cm."""
    plot = tmp_path / "dead_reckoning.png"
    figures = run_example("dead_reckoning.py", ["--duration", "30", "--plot", str(plot), "--scenario",
                                                os.path.join(SOURCE_DIR, "configs", "scenarios", "default.yaml")],
                          timeout=180)
    assert plot.read_bytes()[:8] == PNG_SIGNATURE
    assert figures["duration_s"] == 30.0
    assert figures["distance_travelled_m"] > 20.0  # it moved: ~29 m
    assert figures["final_horizontal_error_m"] < 0.01 * figures["distance_travelled_m"]
    assert figures["drift_percent_of_distance"] < 1.0
    assert abs(figures["heading_error_deg"]) < 0.1
    assert abs(figures["final_depth_error_m"]) < 0.05
