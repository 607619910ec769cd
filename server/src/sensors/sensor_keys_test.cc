// Loading the sensor kinds' keys (each kind's keys()) through the scenario loader: values, defaults,
// conversions and the errors at file:line:col (config/scenario_test_support.h).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "config/scenario_test_support.h"
#include "hadal/config/scenario_loader.h"
#include "hadal/render/water_presets.h"
#include "hadal/sensors/geomagnetic.h"
#include "hadal/sensors/noise.h"

namespace hadal::config {
namespace {

TEST_F(ScenarioLoaderTest, SensorsLoadWithDefaults) {
  const std::string path = write("s.yaml", R"(world: {physics_rate_hz: 1000}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
      - {name: mast, mass: 1.0, inertia: {ixx: 1, iyy: 1, izz: 1}, pose: {position: [0, 0, 0.5]}}
    sensors:
      - {name: depth, type: pressure}
      - name: depth_aft
        type: pressure
        link: mast
        pose: {position: [-0.7, 0, 0.1]}
        rate_hz: 200
        frame_id: auv/aft_pressure
        noise_stddev: 50
        resolution: 10
        range_pa: 7.0e7
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const std::vector<SensorSpec>& sensors = result.model->vehicles[0].sensors;
  ASSERT_EQ(sensors.size(), 2u);
  EXPECT_EQ(sensors[0].name, "depth");
  EXPECT_EQ(sensors[0].type(), "pressure");
  EXPECT_EQ(sensors[0].link_index, 0);
  EXPECT_EQ(sensors[0].rate_hz, 10.0);
  EXPECT_EQ(sensors[0].frame_id, "auv/depth");
  EXPECT_EQ(spec_of<sensors::PressureSensor>(sensors[0]).noise_stddev, 0.0);
  EXPECT_EQ(sensors[1].link_index, 1);
  EXPECT_EQ(sensors[1].X_LS.translation(), Eigen::Vector3d(-0.7, 0, 0.1));
  EXPECT_EQ(sensors[1].rate_hz, 200.0);
  EXPECT_EQ(sensors[1].frame_id, "auv/aft_pressure");
  EXPECT_EQ(spec_of<sensors::PressureSensor>(sensors[1]).noise_stddev, 50.0);
  EXPECT_EQ(spec_of<sensors::PressureSensor>(sensors[1]).resolution, 10.0);
  EXPECT_EQ(spec_of<sensors::PressureSensor>(sensors[1]).range_pa, 7.0e7);
}

TEST_F(ScenarioLoaderTest, SensorErrors) {
  const std::string path = write("s.yaml", std::string(R"(world: {physics_rate_hz: 500}
)") + kSensorVehicle + R"(      - {name: depth, type: barometer}
      - {name: depth, type: pressure, link: fin}
      - {name: fast, type: pressure, rate_hz: 1000, noise_stddev: -1}
      - {type: pressure, colour: red}
      - {name: old, type: pressure, range_max: 7.0e7}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":8:29: error: vehicles[0].sensors[0].type: must be one of 'pressure', 'imu', "
                          "'magnetometer', 'gps', 'dvl', 'altimeter', 'profiler', 'camera', 'fls', 'multibeam', "
                          "'sidescan', 'force_torque', 'usbl', 'lbl', 'modem' (got 'barometer')",
                   path + ":9:16: error: vehicles[0].sensors[1].name: duplicate sensor name 'depth' (first "
                          "used by vehicles[0].sensors[0])",
                   path + ":9:45: error: vehicles[0].sensors[1].link: no link named 'fin' in this vehicle "
                          "(links: hull)",
                   path + ":10:47: error: vehicles[0].sensors[2].rate_hz: must be <= world.physics_rate_hz "
                          "(500) (got 1000)",
                   path + ":10:67: error: vehicles[0].sensors[2].noise_stddev: must be >= 0 (got -1)",
                   path + ":11:9: error: vehicles[0].sensors[3]: missing required key 'name'",
                   path + ":11:26: error: vehicles[0].sensors[3].colour: unknown key 'colour'",
                   path + ":12:37: error: vehicles[0].sensors[4].range_max: key 'range_max' was renamed 'range_pa' "
                          "(a channel's full scale is range_<unit>, as range_g and range_ut)"}));
}

// The profiler (a captured kind): its keys and the common latency_s, which only captured kinds take.
TEST_F(ScenarioLoaderTest, ProfilerKeysAndLatency) {
  const std::string path = write("s.yaml", std::string(R"(world: {physics_rate_hz: 500}
)") + kSensorVehicle + R"(      - {name: scan, type: profiler, rate_hz: 5, latency_s: 0.08, beams: 128, fov_deg: 60, beam_width_deg: 2,
         rays_per_beam: 4, min_range: 1, max_range: 30, noise_stddev: 0.02, resolution: 0.01}
      - {name: plain, type: profiler}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const auto& sensors = result.model->vehicles[0].sensors;
  EXPECT_EQ(sensors[0].type(), "profiler");
  EXPECT_EQ(sensors[0].latency_s, 0.08);
  const sensors::ProfilerSensor::Spec& scan = spec_of<sensors::ProfilerSensor>(sensors[0]);
  EXPECT_EQ(scan.beams, 128);
  EXPECT_DOUBLE_EQ(scan.fov, 60.0 * kDegToRad);
  EXPECT_DOUBLE_EQ(scan.beam_width, 2.0 * kDegToRad);
  EXPECT_EQ(scan.rays_per_beam, 4);
  EXPECT_EQ(scan.min_range, 1.0);
  EXPECT_EQ(scan.max_range, 30.0);
  EXPECT_EQ(scan.noise_stddev, 0.02);
  EXPECT_EQ(scan.resolution, 0.01);
  // Not given: one sample period (configs/REFERENCE.md, "Captured sensors"), so real time publishes it.
  EXPECT_DOUBLE_EQ(sensors[1].latency_s, 1.0 / sensors[1].rate_hz);
  EXPECT_GT(sensors[1].latency_steps(500.0), 0u);
  EXPECT_EQ(spec_of<sensors::ProfilerSensor>(sensors[1]).beams, sensors::ProfilerSensor::Spec{}.beams);

  const std::string bad = write("bad.yaml", std::string(R"(world: {physics_rate_hz: 500}
)") + kSensorVehicle + R"(      - {name: scan, type: profiler, beams: 12.5, rays_per_beam: 0, latency_s: -1, max_range: 0.2}
      - {name: depth, type: pressure, latency_s: 0.1}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":8:45: error: vehicles[0].sensors[0].beams: must be a whole number (got 12.5)",
                   bad + ":8:66: error: vehicles[0].sensors[0].rays_per_beam: must be in [1, 64] (got 0)",
                   bad + ":8:80: error: vehicles[0].sensors[0].latency_s: must be in [0, 10] (got -1)",
                   bad + ":8:84: error: vehicles[0].sensors[0].max_range: max_range (0.2 m) must exceed min_range "
                         "(0.5 m)",
                   bad + ":9:39: error: vehicles[0].sensors[1].latency_s: key 'latency_s' is not used by sensor "
                         "type 'pressure' (it samples on the stepping thread, without latency)"}));
}

// A camera (calibration, lens model, clip, sensor figures), a vehicle's lights and world.optics; then
// their errors.
TEST_F(ScenarioLoaderTest, CameraLightsAndOptics) {
  const std::string path = write("s.yaml", std::string(R"(world:
  physics_rate_hz: 500
  optics: {absorption: [0.4, 0.07, 0.03], scattering: [0.1, 0.1, 0.1], phase_g: 0.9, forward_scatter_max_angle_deg: 5,
           daylight: {surface_irradiance: [100, 120, 110], jerlov_type: II}, seabed_albedo: [0.2, 0.2, 0.1],
           marine_snow: {density: 50, radius: 0.002}, seabed_pattern: {amplitude: 0.3, scale: 0.5, octaves: 3}}
)") + kSensorVehicle + R"(      - {name: cam, type: camera, rate_hz: 5, latency_s: 0.05, width: 320, height: 240, fx: 300, fy: 301,
         cx: 160.5, cy: 119, lens_model: plumb_bob, distortion: [-0.1, 0.02, 0.001, 0, 0], near_clip: 0.2,
         far_clip: 30, encoding: mono8, exposure_s: 0.02, read_noise_e: 2, shot_noise: false}
      - {name: wide, type: camera}
    lights:
      - {name: lamp, link: hull, pose: {position: [0.5, 0.3, 0], rpy_deg: [0, 10, 0]}, inner_half_angle_deg: 30,
         outer_half_angle_deg: 35, intensity_w_per_sr: [300, 310, 320]}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const auto& sensors = result.model->vehicles[0].sensors;
  const sensors::CameraSensor::Spec& cam = spec_of<sensors::CameraSensor>(sensors[0]);
  EXPECT_EQ(sensors[0].latency_s, 0.05);
  EXPECT_EQ(cam.lens->width_px(), 320);
  EXPECT_EQ(cam.lens->spec().fy, 301.0);
  EXPECT_EQ(cam.lens->spec().cx, 160.5);
  EXPECT_EQ(cam.lens->distortion_model(), "plumb_bob");
  EXPECT_EQ(cam.lens->D(), (std::vector<double>{-0.1, 0.02, 0.001, 0.0, 0.0}));
  EXPECT_EQ(cam.near_clip, 0.2);
  EXPECT_EQ(cam.far_clip, 30.0);
  EXPECT_TRUE(cam.mono);
  EXPECT_EQ(cam.sensor.exposure_s, 0.02);
  EXPECT_FALSE(cam.sensor.shot_noise);
  const sensors::CameraSensor::Spec& wide = spec_of<sensors::CameraSensor>(sensors[1]);
  EXPECT_EQ(wide.lens->width_px(), 640);
  EXPECT_NEAR(2.0 * std::atan(320.0 / wide.lens->spec().fx), 90.0 * kDegToRad, 1e-12);
  EXPECT_EQ(wide.lens->spec().cx, 319.5);
  const LightSpec& lamp = result.model->vehicles[0].lights.at(0);
  EXPECT_EQ(lamp.X_LF.translation(), Eigen::Vector3d(0.5, 0.3, 0.0));
  EXPECT_DOUBLE_EQ(lamp.outer_half_angle, 35.0 * kDegToRad);
  EXPECT_EQ(lamp.intensity_W_per_sr[2], 320.0);
  const OpticsSpec& optics = result.model->world.optics;
  EXPECT_EQ(optics.water.absorption_per_m[1], 0.07);
  EXPECT_EQ(optics.water.phase_g, 0.9);
  EXPECT_DOUBLE_EQ(optics.water.forward_scatter_max_angle_rad, 5.0 * kDegToRad);
  EXPECT_EQ(optics.daylight.surface_irradiance_W_per_m2[0], 100.0);
  EXPECT_EQ(optics.daylight.Kd_per_m[2], render::jerlov_Kd_per_m(render::JerlovType::kII)[2]);
  EXPECT_EQ(optics.seabed_albedo[2], 0.1);
  EXPECT_EQ(optics.marine_snow.density_per_m3, 50.0);
  EXPECT_EQ(optics.marine_snow.radius, 0.002);
  EXPECT_EQ(optics.seabed_pattern.amplitude, 0.3);
  EXPECT_EQ(optics.seabed_pattern.scale_m, 0.5);
  EXPECT_EQ(optics.seabed_pattern.octaves, 3);
  EXPECT_EQ(optics.seabed_pattern.seed, result.model->world.seed);
  EXPECT_EQ(optics.marine_snow.max_range, render::MarineSnow{}.max_range);

  const std::string bad = write("bad.yaml", std::string(R"(world:
  optics: {scattering: [0.1, -1, 0], daylight: {jerlov_type: XI}, seabed_pattern: {amplitude: 2, octaves: 0},
           forward_scatter_max_angle_deg: 40}
)") + kSensorVehicle + R"(      - {name: a, type: camera, hfov_deg: 60, fx: 300, fy: 300}
      - {name: b, type: camera, distortion: [0.1, 0, 0, 0, 0], near_clip: 3, far_clip: 2}
      - {name: c, type: camera, lens_model: fisheye, width: 0}
      - {name: d, type: camera, lens_model: plumb_bob, distortion: [-0.9, 0, 0, 0, 0]}
    lights:
      - {name: lamp, link: mast, inner_half_angle_deg: 40, outer_half_angle_deg: 30}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":2:30: error: world.optics.scattering[1]: must be in [0, 100] (got -1)",
                   bad + ":2:62: error: world.optics.daylight.jerlov_type: unknown Jerlov water type 'XI' (one of I, "
                         "IA, IB, II, III, 1C, 3C, 5C, 7C, 9C)",
                   bad + ":2:95: error: world.optics.seabed_pattern.amplitude: must be in [0, 1] (got 2)",
                   bad + ":2:107: error: world.optics.seabed_pattern.octaves: must be in [1, 8] (got 0)",
                   bad + ":3:43: error: world.optics.forward_scatter_max_angle_deg: must be in [0, 30] (got 40)",
                   bad + ":10:33: error: vehicles[0].sensors[0].hfov_deg: give either hfov_deg or the calibration fx, "
                         "fy, not both",
                   bad + ":11:33: error: vehicles[0].sensors[1].distortion: a pinhole lens has no distortion (set "
                         "lens_model: plumb_bob or equidistant)",
                   bad + ":11:78: error: vehicles[0].sensors[1].far_clip: far_clip (2 m) must exceed near_clip (3 m)",
                   bad + ":12:45: error: vehicles[0].sensors[2].lens_model: must be one of 'pinhole', 'plumb_bob', "
                         "'radial_tangential', 'equidistant' (got 'fisheye')",
                   bad + ":12:61: error: vehicles[0].sensors[2].width: must be in [1, 8192] (got 0)",
                   bad + ":13:56: error: vehicles[0].sensors[3].distortion: unusable lens: distortion: the "
                         "radial_tangential distortion has no inverse at pixel (0, 0): the lens folds over inside the "
                         "image (monotone up to r = 0.6085806195); check the coefficients' signs and the image size",
                   bad + ":15:28: error: vehicles[0].lights[0].link: no link named 'mast' in this vehicle (links: hull)",
                   bad + ":15:60: error: vehicles[0].lights[0].outer_half_angle_deg: the beam's outer half angle (30 "
                         "deg) must exceed its inner half angle (40 deg)"}));
}

// A camera from a preset (render/camera_presets.h), downscaled; then the preset's errors.
TEST_F(ScenarioLoaderTest, CameraPresetAndDownscale) {
  const std::string path = write("s.yaml", std::string(R"(world: {}
)") + kSensorVehicle + R"(      - {name: cam, type: camera, preset: svin2_stereo_rig_v2_left, downscale: 2.5}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const render::Lens& lens = *spec_of<sensors::CameraSensor>(result.model->vehicles[0].sensors[0]).lens;
  EXPECT_EQ(lens.width_px(), 640);
  EXPECT_EQ(lens.height_px(), 480);
  EXPECT_DOUBLE_EQ(lens.spec().fx, 1156.5188534683703 / 2.5);
  EXPECT_DOUBLE_EQ(lens.spec().cy, (617.2779853849335 + 0.5) / 2.5 - 0.5);
  EXPECT_EQ(lens.D()[0], -0.17473019446863114);

  const std::string bad = write("bad.yaml", std::string(R"(world: {}
)") + kSensorVehicle + R"(      - {name: a, type: camera, preset: gopro}
      - {name: b, type: camera, preset: subpipe_gopro_hero10, fx: 300}
      - {name: c, type: camera, preset: subpipe_gopro_hero10, downscale: 3}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":8:41: error: vehicles[0].sensors[0].preset: unknown camera preset 'gopro' (presets: "
                         "'svin2_stereo_rig_v2_left', 'subpipe_gopro_hero10')",
                   bad + ":9:63: error: vehicles[0].sensors[1].fx: the preset sets the calibration; give either 'fx' "
                         "or 'preset' (use 'downscale' for a smaller image)",
                   bad + ":10:63: error: vehicles[0].sensors[2].downscale: downscale 3 does not divide the "
                         "2704 x 1520 image into whole pixels"}));
}

// The three sonars from presets and keys, world.acoustics, a link's backscatter_db and the water's pH; then
// their errors: an unknown preset, a window, a ping rate beyond the two-way travel limit, a display window.
TEST_F(ScenarioLoaderTest, SonarsFromPresetsAndKeys) {
  const std::string path = write("s.yaml", R"(world:
  physics_rate_hz: 500
  water: {ph: 7.8}
  acoustics: {seabed_backscatter_db: -30, vehicle_backscatter_db: -12}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, appearance: {backscatter_db: -5}}
    sensors:
      - {name: fls, type: fls, preset: oculus_m750d, beams: 256, latency_s: 0.05}
      - {name: mbes, type: multibeam, preset: r2sonic_2024, rate_hz: 5, speckle: false}
      - {name: sss, type: sidescan, depression_deg: 15, max_range: 100, bins: 1000, image_dtype: float32, rate_hz: 4}
      - {name: plain, type: fls}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const WorldSpec& world = result.model->world;
  EXPECT_EQ(world.water.ph, 7.8);
  EXPECT_EQ(world.acoustics.seabed_backscatter_db, -30.0);
  EXPECT_EQ(world.acoustics.vehicle_backscatter_db, -12.0);
  EXPECT_EQ(*result.model->vehicles[0].links[0].appearance.backscatter_db, -5.0);
  const auto& sensors = result.model->vehicles[0].sensors;
  const sensors::FlsSensor::Spec& fls = spec_of<sensors::FlsSensor>(sensors[0]);
  EXPECT_EQ(fls.beams, 256);  // the file's, over the preset's 512
  EXPECT_EQ(fls.acoustics.frequency_hz, 750e3);
  EXPECT_NEAR(fls.fov, 130.0 * kDegToRad, kTol);
  EXPECT_NEAR(fls.vertical_aperture, 20.0 * kDegToRad, kTol);
  EXPECT_EQ(fls.acoustics.max_range, 40.0);
  EXPECT_EQ(sensors[0].rate_hz, 10.0);  // the preset's
  EXPECT_EQ(sensors[0].latency_s, 0.05);
  ASSERT_TRUE(fls.ping);
  EXPECT_EQ(fls.ping->beams.size(), 256u);
  EXPECT_EQ(fls.ping->rays_u * fls.ping->rays_v, 4 * 512);  // rays_per_cell x bins
  const sensors::MultibeamSensor::Spec& mbes = spec_of<sensors::MultibeamSensor>(sensors[1]);
  EXPECT_EQ(mbes.beams, 256);
  EXPECT_NEAR(mbes.across_beam_width, 0.5 * kDegToRad, kTol);
  EXPECT_EQ(sensors[1].rate_hz, 5.0);  // the file's
  EXPECT_FALSE(mbes.acoustics.speckle);
  const sensors::SidescanSensor::Spec& sss = spec_of<sensors::SidescanSensor>(sensors[2]);
  EXPECT_NEAR(sss.depression, 15.0 * kDegToRad, kTol);
  EXPECT_EQ(sss.acoustics.bins, 1000);
  EXPECT_TRUE(sss.encoding.float32);
  EXPECT_EQ(sss.ping->beams.size(), 2u);
  EXPECT_EQ(spec_of<sensors::FlsSensor>(sensors[3]).beams, sensors::FlsSensor::Spec{}.beams);

  const std::string bad = write("bad.yaml", std::string(R"(world: {physics_rate_hz: 500, acoustics: {seabed_backscatter_db: 3}}
)") + kSensorVehicle + R"(      - {name: a, type: fls, preset: blueview}
      - {name: b, type: multibeam, rate_hz: 20, max_range: 100}
      - {name: c, type: sidescan, min_range: 30, max_range: 20, display_min_db: 150, display_max_db: 120}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":1:66: error: world.acoustics.seabed_backscatter_db: must be in [-80, 0] (got 3)",
                   bad + ":8:38: error: vehicles[0].sensors[0].preset: unknown forward-looking sonar preset 'blueview' "
                         "(presets: 'oculus_m750d', 'oculus_m750d_1200khz', 'gemini_720is', 'aris_explorer_3000')",
                   bad + ":9:36: error: vehicles[0].sensors[1].rate_hz: a ping every 0.05 s (rate_hz 20) is shorter "
                         "than the echoes' two-way travel time over max_range 100 m: rate_hz must be <= 8 "
                         "(1600 m/s / (2 max_range))",
                   bad + ":10:50: error: vehicles[0].sensors[2].max_range: max_range (20 m) must exceed min_range "
                         "(30 m)",
                   bad + ":10:86: error: vehicles[0].sensors[2].display_max_db: display_max_db (120) must exceed "
                         "display_min_db (150)"}));
}

TEST_F(ScenarioLoaderTest, DvlAndAltimeterFromPresetAndKeys) {
  const std::string path = write("s.yaml", std::string(R"(world: {physics_rate_hz: 500}
)") + kSensorVehicle + R"(      - {name: dvl, type: dvl, preset: nortek_dvl1000_4000m}
      - name: dvl2
        type: dvl
        rate_hz: 4
        preset: teledyne_workhorse_navigator_600
        beam_tilt_deg: 20
        first_beam_azimuth_deg: 0
        max_altitude: 60
        dropout_probability: 0.05
        assumed_sound_speed: 1480
        water_track: false
        water_track_layer_near: 1
        water_track_layer_far: 9
        beam_velocity_noise_stddev: 0.01
        range_noise_stddev: 0.05
        velocity_resolution: 0.001
        bias: {initial: [0.001, 0, 0], initial_stddev: 0.002, drift_rate: [0, 1.0e-7, 0], random_walk: 1.0e-5}
      - {name: alt, type: altimeter, min_range: 0.5, max_range: 50, noise_stddev: 0.02, resolution: 0.01,
         field_of_view_deg: 10}
      - {name: alt2, type: altimeter}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const std::vector<SensorSpec>& sensors = result.model->vehicles[0].sensors;
  ASSERT_EQ(sensors.size(), 4u);
  // The preset sets the rate (8 Hz), the window and the per-ping noise at that rate.
  EXPECT_EQ(sensors[0].type(), "dvl");
  EXPECT_EQ(sensors[0].rate_hz, 8.0);
  const sensors::DvlParams& nortek = spec_of<sensors::DvlSensor>(sensors[0]).params;
  EXPECT_DOUBLE_EQ(nortek.beam_tilt, 25.0 * M_PI / 180.0);
  EXPECT_EQ(nortek.min_altitude, 0.2);
  EXPECT_EQ(nortek.max_altitude, 75.0);
  EXPECT_DOUBLE_EQ(nortek.beam_velocity_noise.noise.white_noise_density, 0.005 * std::sqrt(1.0 / 8.0));
  EXPECT_DOUBLE_EQ(nortek.water_track_velocity_noise.noise.white_noise_density, 0.015 * std::sqrt(1.0 / 8.0));
  // Keys override the preset; noise per ping at the given 4 Hz.
  EXPECT_EQ(sensors[1].rate_hz, 4.0);
  const sensors::DvlParams& p = spec_of<sensors::DvlSensor>(sensors[1]).params;
  EXPECT_DOUBLE_EQ(p.beam_tilt, 20.0 * M_PI / 180.0);
  EXPECT_EQ(p.first_beam_azimuth, 0.0);
  EXPECT_EQ(p.min_altitude, 0.7);
  EXPECT_EQ(p.max_altitude, 60.0);
  EXPECT_EQ(p.dropout_probability, 0.05);
  EXPECT_EQ(p.assumed_sound_speed, 1480.0);
  EXPECT_FALSE(p.water_track);
  EXPECT_EQ(p.water_track_layer_near, 1.0);
  EXPECT_EQ(p.water_track_layer_far, 9.0);
  EXPECT_DOUBLE_EQ(p.beam_velocity_noise.noise.white_noise_density, 0.01 * 0.5);
  EXPECT_DOUBLE_EQ(p.range_noise.noise.white_noise_density, 0.05 * 0.5);
  EXPECT_EQ(p.beam_velocity_noise.lsb, 0.001);
  EXPECT_EQ(p.bias.initial, Eigen::Vector3d(0.001, 0, 0));
  EXPECT_EQ(p.bias.initial_sigma, 0.002);
  EXPECT_EQ(p.bias.drift_rate, Eigen::Vector3d(0, 1e-7, 0));
  EXPECT_EQ(p.bias.random_walk_density, 1e-5);
  const sensors::AltimeterSensor::Spec& alt = spec_of<sensors::AltimeterSensor>(sensors[2]);
  EXPECT_EQ(sensors[2].type(), "altimeter");
  EXPECT_EQ(alt.min_range, 0.5);
  EXPECT_EQ(alt.max_range, 50.0);
  EXPECT_EQ(alt.noise_stddev, 0.02);
  EXPECT_EQ(alt.resolution, 0.01);
  EXPECT_DOUBLE_EQ(alt.field_of_view, 10.0 * M_PI / 180.0);
  EXPECT_EQ(spec_of<sensors::AltimeterSensor>(sensors[3]).max_range, sensors::AltimeterSensor::Spec{}.max_range);
  EXPECT_EQ(sensors[3].rate_hz, 10.0);
}

TEST_F(ScenarioLoaderTest, DvlAndAltimeterErrors) {
  const std::string path = write("s.yaml", std::string(R"(world: {physics_rate_hz: 500}
)") + kSensorVehicle + R"(      - {name: a, type: dvl, preset: rdi_600}
      - {name: b, type: dvl, min_altitude: 100, beam_tilt_deg: 75}
      - {name: c, type: dvl, assumed_sound_speed: 340, water_track_layer_near: 8, water_track_layer_far: 4}
      - {name: d, type: dvl, bias: {drift: 1}, dropout_probability: 1.5}
      - {name: e, type: altimeter, min_range: 10, max_range: 5, gyro: {}}
      - {name: f, type: pressure, max_altitude: 3}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":8:38: error: vehicles[0].sensors[0].preset: unknown DVL preset 'rdi_600' (presets: "
                          "'teledyne_workhorse_navigator_600', 'teledyne_explorer_1000', 'nortek_dvl1000_4000m', "
                          "'nortek_dvl500_300m', 'sonardyne_syrinx_600', 'water_linked_a50')",
                   path + ":9:30: error: vehicles[0].sensors[1].min_altitude: max_altitude (90 m) must exceed "
                          "min_altitude (100 m)",
                   path + ":9:64: error: vehicles[0].sensors[1].beam_tilt_deg: must be in [1, 60] (got 75)",
                   path + ":10:30: error: vehicles[0].sensors[2].assumed_sound_speed: assumed_sound_speed must be "
                          "0 (measured) or in [1300, 1700] m/s, got 340",
                   path + ":10:83: error: vehicles[0].sensors[2].water_track_layer_far: the water-track layer "
                          "must have near < far (got 8 m to 4 m)",
                   path + ":11:37: error: vehicles[0].sensors[3].bias.drift: unknown key 'drift'",
                   path + ":11:69: error: vehicles[0].sensors[3].dropout_probability: must be in [0, 1] (got 1.5)",
                   path + ":12:51: error: vehicles[0].sensors[4].max_range: max_range (5 m) must exceed min_range "
                          "(10 m)",
                   path + ":12:65: error: vehicles[0].sensors[4].gyro: key 'gyro' is not used by sensor type "
                          "'altimeter'",
                   path + ":13:35: error: vehicles[0].sensors[5].max_altitude: key 'max_altitude' is not used by "
                          "sensor type 'pressure'"}));
}

TEST_F(ScenarioLoaderTest, ImuFromPresetAndFigures) {
  const std::string path = write("s.yaml", R"(world: {physics_rate_hz: 500}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    thrusters:
      - {name: main, link: hull, position: [-0.8, 0, 0], direction: [1, 0, 0], propeller_diameter: 0.1,
         thrust_coefficient: 0.4, max_rpm: 1500}
    sensors:
      - name: imu
        type: imu
        rate_hz: 100
        preset: honeywell_hg1700
        gyro: {arw_deg_per_sqrt_h: 0.2, range_deg_per_s: 400}
        accel: {range_g: 10, resolution_mg: 0.1}
        temperature: {reference_degc: 15, accel_mg_per_degc: 0.05}
        vibration: {thruster: main, blades: 4, accel_mg: 2}
      - {name: plain, type: imu, white_noise_only: true, preset: honeywell_hg1700}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const sensors::ImuSensor::Spec& imu = spec_of<sensors::ImuSensor>(result.model->vehicles[0].sensors[0]);
  EXPECT_EQ(result.model->vehicles[0].sensors[0].type(), "imu");
  EXPECT_DOUBLE_EQ(imu.gyro.axes[0].white_noise_density, sensors::arw_to_noise_density(0.2));  // override
  EXPECT_FALSE(imu.gyro.axes[0].gauss_markov.empty());  // the preset's bias instability
  EXPECT_DOUBLE_EQ(imu.gyro.max, 400.0 * M_PI / 180.0);
  EXPECT_DOUBLE_EQ(imu.gyro.min, -400.0 * M_PI / 180.0);
  EXPECT_DOUBLE_EQ(imu.accel.max, 10.0 * 9.80665);
  EXPECT_DOUBLE_EQ(imu.accel.lsb, 1e-4 * 9.80665);
  EXPECT_EQ(imu.temperature_reference, 15.0);
  EXPECT_DOUBLE_EQ(imu.accel_temperature_coefficient, 0.05e-3 * 9.80665);
  EXPECT_EQ(imu.vibration_thruster, 0);
  EXPECT_EQ(imu.vibration_blades, 4);
  EXPECT_DOUBLE_EQ(imu.accel_vibration_amplitude, 2e-3 * 9.80665);
  const sensors::ImuSensor::Spec& plain = spec_of<sensors::ImuSensor>(result.model->vehicles[0].sensors[1]);
  EXPECT_TRUE(plain.gyro.axes[0].gauss_markov.empty());
  EXPECT_GT(plain.gyro.axes[0].white_noise_density, 0.0);
  EXPECT_EQ(plain.gyro.scale_factor_sigma, 0.0);
}

TEST_F(ScenarioLoaderTest, ImuErrors) {
  const std::string path = write("s.yaml", std::string(R"(world: {physics_rate_hz: 500}
)") + kSensorVehicle + R"(      - {name: a, type: imu, preset: stim999, noise_stddev: 3}
      - {name: b, type: imu, gyro: {arw: 1}, vibration: {thruster: main}}
      - {name: c, type: pressure, preset: honeywell_hg1700}
)");
  const std::vector<std::string> errors = errors_of(path);
  ASSERT_EQ(errors.size(), 5u);
  EXPECT_NE(errors[0].find(":8:38: error: vehicles[0].sensors[0].preset: unknown IMU preset 'stim999' (presets: "),
            std::string::npos) << errors[0];
  EXPECT_NE(errors[1].find(":8:47: error: vehicles[0].sensors[0].noise_stddev: key 'noise_stddev' is not used by "
                           "sensor type 'imu'"), std::string::npos) << errors[1];
  EXPECT_NE(errors[2].find(":9:37: error: vehicles[0].sensors[1].gyro.arw: unknown key 'arw'"), std::string::npos)
      << errors[2];
  EXPECT_NE(errors[3].find(":9:68: error: vehicles[0].sensors[1].vibration.thruster: no thruster named 'main' in this "
                           "vehicle (it has none)"),
            std::string::npos) << errors[3];
  EXPECT_NE(errors[4].find(":10:35: error: vehicles[0].sensors[2].preset: key 'preset' is not used by sensor "
                           "type 'pressure'"), std::string::npos) << errors[4];
}

TEST_F(ScenarioLoaderTest, MagnetometerDateAndDipoles) {
  const std::string path = write("s.yaml", std::string(R"(world:
  date: "2027-07-02"
  magnetic_dipoles: [{position: [100, 0, -90], moment: [0, 5000, 0], radius: 5}]
)") + kSensorVehicle + R"(      - name: mag
        type: magnetometer
        rate_hz: 20
        noise_stddev_nt: 40
        resolution_nt: 5
        range_ut: 800
        hard_iron: [{position: [-0.7, 0, 0], moment: [0.1, 0, 0]}]
        soft_iron: [1.02, 0.01, 0, 0.01, 0.98, 0, 0, 0, 1]
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  EXPECT_DOUBLE_EQ(result.model->world.start_decimal_year, sensors::decimal_year_from_date(2027, 7, 2));
  ASSERT_EQ(result.model->world.magnetic_dipoles_W.size(), 1u);
  EXPECT_EQ(result.model->world.magnetic_dipoles_W[0].radius, 5.0);
  const sensors::MagnetometerParams& p = spec_of<sensors::MagnetometerSensor>(result.model->vehicles[0].sensors[0]).params;
  EXPECT_TRUE(p.dipoles_W.empty());  // the world's dipoles stay the world's
  ASSERT_EQ(p.dipoles_B.size(), 1u);
  EXPECT_EQ(p.dipoles_B[0].p_FD, Eigen::Vector3d(-0.7, 0, 0));
  EXPECT_EQ(p.soft_iron_S(0, 1), 0.01);
  EXPECT_DOUBLE_EQ(p.noise.axes[0].white_noise_density, 40e-9 / std::sqrt(20.0));
  EXPECT_DOUBLE_EQ(p.noise.lsb, 5e-9);
  EXPECT_DOUBLE_EQ(p.noise.max, 800e-6);
}

}  // namespace
}  // namespace hadal::config
