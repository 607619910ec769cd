"""Acoustic modems end to end: configs/scenarios/usbl_survey.yaml (a vessel and two AUVs 1.7 and 3.1 km away,
each with a WHOI Micro-Modem FH-FSK modem) run by a real lockstep hadald. A packet attached to a step request
leaves the vessel's modem at that request's first step and reaches the AUV's rx topic the travel time plus its
duration later; one published on the tx topic gets there too; bad packets are refused with their reason and the
server goes on; the same seed gives the same packets."""

import time

import pytest

import hadal

WAIT_S = 30.0
SCENARIO = "usbl_survey"  # configs/scenarios/usbl_survey.yaml
SOUND_SPEED_BOUNDS = (1470.0, 1530.0)  # the scenario's CTD cast: 1482-1521 m/s


def duration_s(payload_bytes):
    """The Micro-Modem FH-FSK packet: 0.3 s of probe, then 80 bit/s (sensors/modem_spec.h)."""
    return 0.3 + 8.0 * payload_bytes / 80.0


def test_a_packet_reaches_the_addressed_auv_after_the_travel_time_and_its_duration():
    with hadal.Server(SCENARIO, mode="lockstep", domain_id="free") as server, server.client() as client:
        assert client.receive_packets("auv", "modem") == []  # subscribes
        assert client.receive_packets("deep_auv", "modem") == []
        assert client.wait_for_subscriptions(WAIT_S)
        step_size = client.status().step_size
        t0 = client.step(10)
        client.send_packet("vessel", "modem", b"goto 600 300", destination="auv", publish=False)
        client.step(round(4.0 / step_size))
        packets = client.receive_packets("auv", "modem", timeout_s=WAIT_S)
        assert len(packets) == 1, packets
        packet = packets[0]
        assert packet.payload == b"goto 600 300"
        assert packet.source == "vessel/modem" and packet.destination == "auv" and packet.sequence_number == 0
        assert packet.transmit_stamp == pytest.approx(t0, abs=1e-9)
        # The AUV is ~1.7 km from the vessel's modem.
        slant = packet.travel_time * SOUND_SPEED_BOUNDS[0], packet.travel_time * SOUND_SPEED_BOUNDS[1]
        assert 1500.0 < slant[0] and slant[1] < 1900.0, slant
        assert packet.stamp == pytest.approx(packet.transmit_stamp + packet.travel_time + duration_s(12), abs=1e-9)
        assert packet.snr_db > 0.0
        assert client.receive_packets("deep_auv", "modem") == []  # not addressed to it

        # Published on the tx topic (no step request attached): sent when the server takes it at a step.
        client.send_packet("auv", "modem", b"ack", destination="vessel")
        time.sleep(0.5)
        client.step(round(4.0 / step_size))
        assert client.receive_packets("vessel", "modem", timeout_s=WAIT_S)[0].payload == b"ack"


def test_bad_packets_are_refused_with_their_reason_and_the_server_goes_on():
    with hadal.Server(SCENARIO, mode="lockstep", domain_id="free") as server, server.client() as client:
        assert client.wait_for_server(WAIT_S)
        refusals = [(("vessel", "modem", b"x" * 33, "auv"), "max_payload_bytes (32)"),
                    (("vessel", "modem", b"", "auv"), "empty payload"),
                    (("vessel", "modem", b"hi", "glider"), "unknown destination 'glider'"),
                    (("vessel", "modem", b"hi", "vessel"), "the sending modem itself"),
                    (("vessel", "usbl", b"hi", "auv"), "is a usbl, not a modem"),
                    (("vessel", "sonar", b"hi", "auv"), "has no modem 'sonar'")]
        for args, reason in refusals:
            client.send_packet(*args, publish=False)
            with pytest.raises(hadal.CommandRejected, match=reason.replace("(", r"\(").replace(")", r"\)")):
                client.step(1)
        with pytest.raises(hadal.UnknownVehicle):
            client.send_packet("glider", "modem", b"hi", publish=False)
            client.step(1)
        # A refused request changes nothing; the server steps on. Four packets fill the queue behind the one
        # being sent; a sixth is refused.
        for k in range(5):
            client.send_packet("vessel", "modem", bytes([k]), destination="auv", publish=False)
        client.step(1)
        client.send_packet("vessel", "modem", b"sixth", destination="auv", publish=False)
        with pytest.raises(hadal.CommandRejected, match="queue_length 4"):
            client.step(1)
        # Published on the tx topic, a refusal is counted in the status with its reason (the status comes at 10 Hz
        # of wall time: let it catch up with the refusals above first).
        time.sleep(0.5)
        before = client.status().rejected_commands
        assert before == 8
        client.send_packet("vessel", "modem", b"y" * 40, destination="auv")
        deadline = time.monotonic() + WAIT_S
        while client.status().rejected_commands == before and time.monotonic() < deadline:
            client.step(1)
            time.sleep(0.05)
        status = client.status()
        assert status.rejected_commands == before + 1
        assert "max_payload_bytes" in status.last_error


def test_same_seed_same_packets():
    with hadal.Server(SCENARIO, mode="lockstep", domain_id="free") as server, server.client() as client:
        client.receive_packets("deep_auv", "modem")
        assert client.wait_for_subscriptions(WAIT_S)
        step_size = client.status().step_size
        runs = []
        for _ in range(2):
            client.reset(seed=11)
            for k in range(3):
                client.send_packet("vessel", "modem", bytes([k]) * 20, destination="", publish=False)
            client.step(round(25.0 / step_size))
            time.sleep(0.5)
            got = client.receive_packets("deep_auv", "modem", timeout_s=WAIT_S)
            runs.append([(p.sequence_number, p.payload, p.transmit_stamp, p.stamp, p.snr_db) for p in got])
        assert len(runs[0]) == 3 and runs[0] == runs[1]
        # Back to back: each packet starts when the one before ends.
        assert runs[0][1][2] - runs[0][0][2] == pytest.approx(duration_s(20), abs=1e-9)
