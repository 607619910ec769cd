"""The Python sensor accessors (wait_magnetic_field, wait_nav_sat_fix, wait_dvl, wait_range,
wait_laser_scan, wait_image, wait_depth_image, wait_camera_info, wait_sonar_image, wait_sonar_detections,
wait_raw_sonar_image) against a real hadald over real DDS: the lockstep test scenario's AUV
(configs/vehicles/torpedo_auv.yaml) at 50 m depth, at rest, yawed 30 deg, world origin 43 N 5 E; the
profiler scenario (tests/integration/scenarios/profiler.yaml), the camera scenario
(tests/integration/scenarios/camera.yaml) and the sonar scenario (tests/integration/scenarios/sonar.yaml)."""

import math

import numpy as np
import pytest

import hadal

WAIT_S = 20.0  # generous bound on DDS events; not a speed assertion


def subscribed_client(domain_id, *subscribe):
    """A client whose sensor subscriptions (callables taking the client) are matched before any step,
    so the samples of the first request are not missed."""
    client = hadal.Client(domain_id=domain_id, name="pytest_sensors")
    assert client.wait_for_server(WAIT_S), "no status from hadald"
    for first_use in subscribe:
        assert first_use(client) is None  # lockstep: nothing is published before a step
    assert client.wait_for_subscriptions(WAIT_S)
    return client


def test_magnetic_field_is_earths_in_the_sensor_frame(lockstep_server):
    _, domain_id = lockstep_server
    client = subscribed_client(
        domain_id, lambda c: c.wait_magnetic_field("auv", "magnetometer", timeout_s=0.1))
    t = client.step(500)  # 1 s: 20 Hz, the last sample stamped t
    mag = client.wait_magnetic_field("auv", "magnetometer", min_stamp=t, timeout_s=WAIT_S)
    assert mag is not None and abs(mag.stamp - t) < 1e-9
    assert isinstance(mag, hadal.MagneticField)
    assert mag.frame_id == "auv/magnetometer"
    assert mag.magnetic_field.shape == (3,)
    assert mag.magnetic_field_covariance.shape == (3, 3)
    # WMM2025 at 43 N 5 E: F = 46.7 uT, 40..52 uT whatever the attitude, dipole and noise.
    assert 40e-6 < np.linalg.norm(mag.magnetic_field) < 52e-6
    # WMM2025 at 43 N 5 E, -0.05 km, 2026.0 (the scenario's default date; `hadal-geomag 43 5 -0.05 2026`):
    # north X, east Y, down Z. Heading 30 deg north of east: sensor x = (cos 30 east, sin 30 north), y =
    # (-sin 30 east, cos 30 north), z up; plus the motor's hard-iron dipole, 5.8 nT along x. Tolerance
    # 40 nT: 5 sigma of the 5 nT noise, 1 nT resolution, < 12 nT for the resting AUV's slight pitch.
    x_north, y_east, z_down = 24136.7e-9, 1116.0e-9, 39965.4e-9
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
    expected = [y_east * c + x_north * s + 5.8e-9, -y_east * s + x_north * c, -z_down]
    np.testing.assert_allclose(mag.magnetic_field, expected, rtol=0, atol=40e-9)
    # Configured noise: (5 nT)^2 + (1 nT resolution)^2 / 12 on the diagonal.
    np.testing.assert_allclose(mag.magnetic_field_covariance, np.eye(3) * (25.0 + 1.0 / 12.0) * 1e-18,
                               rtol=1e-9, atol=0)


def test_nav_sat_fix_under_water_has_no_fix(lockstep_server):
    _, domain_id = lockstep_server
    client = subscribed_client(domain_id, lambda c: c.wait_nav_sat_fix("auv", "gps", timeout_s=0.1))
    t = client.step(1000)  # 2 s at 1 Hz
    fix = client.wait_nav_sat_fix("auv", "gps", min_stamp=t, timeout_s=WAIT_S)
    assert fix is not None and abs(fix.stamp - t) < 1e-9
    assert isinstance(fix, hadal.NavSatFix)
    assert fix.frame_id == "auv/gps"
    assert fix.status == hadal.NavSatFix.STATUS_NO_FIX == -1
    assert not fix.has_fix()
    assert fix.service == hadal.NavSatFix.SERVICE_GPS
    assert math.isnan(fix.latitude) and math.isnan(fix.longitude) and math.isnan(fix.altitude)
    np.testing.assert_array_equal(fix.position_covariance, np.diag([2.25, 2.25, 9.0]))  # 1.5 m, 3 m
    assert fix.position_covariance_type == hadal.NavSatFix.COVARIANCE_TYPE_DIAGONAL_KNOWN


def test_waits_time_out_with_none(lockstep_server):
    _, domain_id = lockstep_server
    client = subscribed_client(domain_id)
    t = client.step(10)
    # A stamp the server has not reached (it only steps on request): None after the timeout.
    assert client.wait_magnetic_field("auv", "magnetometer", min_stamp=t + 1.0, timeout_s=0.2) is None
    assert client.wait_range("auv", "altimeter", min_stamp=t + 1.0, timeout_s=0.2) is None
    # Sensors it does not have raise at once (test_errors_and_reset.py).
    for wait in (client.wait_dvl, client.wait_range):
        with pytest.raises(hadal.UnknownSensor):
            wait("auv", "no_such_sensor", timeout_s=0.2)


def test_constants_are_the_messages():
    assert (hadal.Dvl.VELOCITY_MODE_NONE, hadal.Dvl.VELOCITY_MODE_BOTTOM_TRACK,
            hadal.Dvl.VELOCITY_MODE_WATER_TRACK) == (0, 1, 2)
    assert (hadal.Dvl.DVL_TYPE_PISTON, hadal.Dvl.DVL_TYPE_PHASED_ARRAY) == (0, 1)
    assert (hadal.Range.ULTRASOUND, hadal.Range.INFRARED) == (0, 1)
    assert (hadal.NavSatFix.STATUS_NO_FIX, hadal.NavSatFix.STATUS_FIX, hadal.NavSatFix.STATUS_SBAS_FIX,
            hadal.NavSatFix.STATUS_GBAS_FIX) == (-1, 0, 1, 2)


# DVL and altimeter of the default AUV: rt/auv/dvl at 5 Hz, rt/auv/altimeter at 10 Hz.


def test_dvl_bottom_tracks_50_m_above_the_seabed(lockstep_server):
    _, domain_id = lockstep_server
    client = subscribed_client(domain_id, lambda c: c.wait_dvl("auv", "dvl", timeout_s=0.1))
    t = client.step(500)  # 1 s at 5 Hz
    dvl = client.wait_dvl("auv", "dvl", min_stamp=t, timeout_s=WAIT_S)
    assert dvl is not None and abs(dvl.stamp - t) < 1e-9
    assert isinstance(dvl, hadal.Dvl)
    assert dvl.frame_id == "auv/dvl"
    assert dvl.velocity_mode == hadal.Dvl.VELOCITY_MODE_BOTTOM_TRACK
    assert dvl.num_good_beams == 4 and dvl.beam_ranges_valid and dvl.beam_velocities_valid
    assert dvl.velocity.shape == (3,) and dvl.velocity_covariance.shape == (3, 3)
    assert dvl.beam_unit_vec.shape == (4, 3)
    for array in (dvl.ranges, dvl.range_covariance, dvl.beam_quality, dvl.beam_velocity,
                  dvl.beam_velocity_covariance):
        assert array.shape == (4,)
    np.testing.assert_allclose(np.linalg.norm(dvl.beam_unit_vec, axis=1), 1.0, atol=1e-6)
    # Plane seabed at z = -100 m, AUV at rest at -50 m (rising ~1 cm/s): altitude 50 m within the
    # transducer's offset from the centre (< 0.1 m) and the range noise of four averaged beams.
    assert abs(dvl.altitude - 50.0) < 0.5
    assert np.linalg.norm(dvl.velocity) < 0.05  # at rest; single-ping noise of a few mm/s
    assert dvl.speed_gnd == pytest.approx(math.hypot(dvl.velocity[0], dvl.velocity[1]), abs=1e-9)


def test_range_of_the_altimeter_is_the_height_above_the_seabed(lockstep_server):
    _, domain_id = lockstep_server
    client = subscribed_client(domain_id, lambda c: c.wait_range("auv", "altimeter", timeout_s=0.1))
    t = client.step(500)  # 1 s at 10 Hz
    rng = client.wait_range("auv", "altimeter", min_stamp=t, timeout_s=WAIT_S)
    assert rng is not None and abs(rng.stamp - t) < 1e-9
    assert isinstance(rng, hadal.Range)
    assert rng.frame_id == "auv/altimeter"
    assert rng.radiation_type == hadal.Range.ULTRASOUND  # acoustic: the closest ROS radiation type
    assert 0.0 < rng.field_of_view < math.pi
    assert rng.min_range <= rng.range <= rng.max_range
    assert abs(rng.range - 50.0) < 0.5  # plane seabed 50 m below; mount offset and noise as the DVL's


def test_laser_scan_of_the_profiler(profiler_server):
    """A scan taken at 0.1 s arrives 0.05 s later (in the request that covers 0.15 s), stamped 0.1 s,
    as a float32 numpy array of 64 beams; the beams nearest the vertical read the 40 m to the plane."""
    _, domain_id = profiler_server
    client = subscribed_client(domain_id, lambda c: c.wait_laser_scan("auv", "profiler", timeout_s=0.1))
    assert abs(client.step(74) - 0.148) < 1e-12
    assert client.wait_laser_scan("auv", "profiler", timeout_s=0.0) is None  # due at 0.15 s
    client.step(1)
    scan = client.wait_laser_scan("auv", "profiler", min_stamp=0.1, timeout_s=WAIT_S)
    assert scan is not None and isinstance(scan, hadal.LaserScan)
    assert abs(scan.stamp - 0.1) < 1e-9
    assert scan.frame_id == "auv/profiler"
    assert scan.ranges.dtype == np.float32 and scan.ranges.shape == (64,)
    np.testing.assert_allclose(scan.ranges[31:33], [40.0, 40.0], rtol=0, atol=1e-3)
    assert scan.intensities.shape == (0,)
    assert abs(scan.angle_increment - math.radians(90.0) / 64) < 1e-6


def test_camera_images_are_numpy_views(camera_server):
    """The camera 10 m above the seabed looking down, light at the camera, noise off: a frame taken at
    0.1 s arrives 0.05 s later as an (H, W, 3) uint8 array viewing the message's bytes (no copy), the
    pixels beside the centre at the Lambertian closed form (117, 140, 128); depth an (H, W) float32 array
    of 10 m; the calibration as configured."""
    _, domain_id = camera_server
    client = subscribed_client(domain_id, lambda c: c.wait_image("auv", "camera", timeout_s=0.1),
                               lambda c: c.wait_depth_image("auv", "camera", timeout_s=0.1),
                               lambda c: c.wait_camera_info("auv", "camera", timeout_s=0.1))
    client.step(75)
    image = client.wait_image("auv", "camera", min_stamp=0.1, timeout_s=WAIT_S)
    assert image is not None and isinstance(image, hadal.Image)
    assert abs(image.stamp - 0.1) < 1e-9
    assert image.frame_id == "auv/camera_optical" and image.encoding == "rgb8"
    pixels = image.array
    assert pixels.dtype == np.uint8 and pixels.shape == (120, 160, 3)
    assert not pixels.flags.owndata and pixels.base is not None  # a view of the message's bytes
    assert image.array.__array_interface__["data"][0] == pixels.__array_interface__["data"][0]
    albedo, c = np.array([0.5, 0.4, 0.3]), np.array([0.05, 0.03, 0.02])
    expected = np.round(100.0 * albedo / math.pi * 2000.0 / 100.0 * np.exp(-2.0 * c * 10.0))
    np.testing.assert_array_equal(pixels[59, 79], expected.astype(np.uint8))
    depth = client.wait_depth_image("auv", "camera", min_stamp=0.1, timeout_s=WAIT_S)
    assert depth.encoding == "32FC1"
    assert depth.array.dtype == np.float32 and depth.array.shape == (120, 160)
    np.testing.assert_allclose(depth.array, 10.0, rtol=0, atol=1e-4)
    info = client.wait_camera_info("auv", "camera", min_stamp=0.1, timeout_s=WAIT_S)
    assert isinstance(info, hadal.CameraInfo) and info.distortion_model == "plumb_bob"
    assert info.k.shape == (3, 3) and info.p.shape == (3, 4)
    assert abs(info.k[0, 0] - 80.0 / math.tan(math.radians(30.0))) < 1e-9
    assert info.k[0, 2] == 79.5 and info.k[1, 2] == 59.5
    np.testing.assert_array_equal(info.d, np.zeros(5))


def test_sonars_over_a_plane(sonar_server):
    """The three sonars 20 m above a plane seabed, noise off (tests/integration/scenarios/sonar.yaml): the
    pings of 0.2 s arrive 0.05 s later as numpy arrays whose echoes lie where the geometry puts them, each
    within one range bin: the forward-looking sonar's centre beams (fan 30 deg down, 20 deg aperture) from
    20 / sin 40 deg to 20 / sin 20 deg, every multibeam beam at 20 / cos(its angle), and each side-scan
    channel from its first bottom return, straight below at 20 m, on."""
    _, domain_id = sonar_server
    client = subscribed_client(domain_id, lambda c: c.wait_sonar_image("auv", "fls", timeout_s=0.1),
                               lambda c: c.wait_sonar_detections("auv", "multibeam", timeout_s=0.1),
                               lambda c: c.wait_raw_sonar_image("auv", "sidescan", "port", timeout_s=0.1),
                               lambda c: c.wait_raw_sonar_image("auv", "sidescan", "starboard", timeout_s=0.1))
    client.step(125)  # 0.25 s
    fls = client.wait_sonar_image("auv", "fls", min_stamp=0.2, timeout_s=WAIT_S)
    assert fls is not None and isinstance(fls, hadal.SonarImage)
    assert abs(fls.stamp - 0.2) < 1e-9 and fls.frame_id == "auv/fls"
    assert fls.frequency_hz == 400e3 and 1400.0 < fls.sound_speed < 1600.0
    image = fls.array
    assert image.dtype == np.float32 and image.shape == (200, 64)
    bin_m = (60.0 - 0.5) / 200
    np.testing.assert_allclose(fls.ranges, 0.5 + (np.arange(200) + 0.5) * bin_m, rtol=0, atol=1e-4)
    np.testing.assert_allclose(fls.beam_azimuths, math.radians(-30.0) + (np.arange(64) + 0.5) * math.radians(60.0) / 64,
                               rtol=0, atol=1e-6)
    np.testing.assert_allclose(fls.vertical_apertures, math.radians(20.0), rtol=1e-6)
    for beam in (31, 32):
        lit = np.nonzero(image[:, beam] > 0)[0]
        assert abs(fls.ranges[lit[0]] - 20.0 / math.sin(math.radians(40.0))) <= bin_m
        assert abs(fls.ranges[lit[-1]] - 20.0 / math.sin(math.radians(20.0))) <= bin_m
    detections = client.wait_sonar_detections("auv", "multibeam", min_stamp=0.2, timeout_s=WAIT_S)
    assert detections is not None and isinstance(detections, hadal.SonarDetections)
    assert detections.ranges.shape == (64,) and (detections.flags == 0).all()
    np.testing.assert_allclose(detections.ranges, 20.0 / np.cos(detections.rx_angles), rtol=0,
                               atol=(60.0 - 0.5) / 2380 + 1e-4)
    for channel, sign in (("port", -1.0), ("starboard", 1.0)):
        side = client.wait_raw_sonar_image("auv", "sidescan", channel, min_stamp=0.2, timeout_s=WAIT_S)
        assert side is not None and isinstance(side, hadal.RawSonarImage)
        assert side.samples.dtype == np.float32 and side.samples.shape == (500,)
        assert abs(side.rx_angle - sign * math.radians(70.0)) < 1e-6
        side_bin = 60.0 / 500  # the side-scan's window starts at 0 m
        assert side.sample0 == 0 and abs(side.sample_rate - side.sound_speed / (2.0 * side_bin)) < 1e-2
        first = np.nonzero(side.samples > 0)[0][0]
        # ranges: where each sample starts, (sample0 + i) bin.
        np.testing.assert_allclose(side.ranges[:3], [0.0, side_bin, 2.0 * side_bin], rtol=0, atol=1e-5)
        assert abs(side.ranges[first] + 0.5 * side_bin - 20.0) <= side_bin
