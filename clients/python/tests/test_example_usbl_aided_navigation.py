"""examples/python/usbl_aided_navigation.py, run in a short form as a subprocess that starts its own lockstep hadald:
two minutes of the AUV's box with USBL fixes sent down through the modems, then the packet-success sweep."""

from conftest import run_example

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def test_fixes_reach_the_auv_and_packet_success_follows_the_hand_snr(tmp_path):
    """120 s: a fix sent every 20 s (6), each 20 bytes at 80 bit/s over ~3 km with an SNR near 30 dB, so all arrive;
    the aided estimate stays within a few fix errors (USBL at ~3 km: ~5 m per axis). The sweep (60 packets at hand
    SNRs -8..0 dB) inverted through the error curve lands within 1 dB of the hand SNR wherever the rate is neither
    0 nor 1 (a lockstep run with the scenario's seed: the same numbers every time)."""
    plot = tmp_path / "usbl_aided_navigation.png"
    figures = run_example("usbl_aided_navigation.py", ["--duration", "120", "--packets", "60", "--plot", str(plot)])
    assert plot.read_bytes()[:8] == PNG_SIGNATURE
    assert figures["duration_s"] == 120.0
    # Every fix arrives, but the one sent at the last step, still in the water when the run ends.
    assert figures["fixes_sent"] == 6 and figures["fixes_received"] == 5
    assert figures["distance_travelled_m"] > 80.0
    assert figures["final_error_aided_m"] < 10.0
    assert figures["worst_success_snr_offset_db"] < 1.0
