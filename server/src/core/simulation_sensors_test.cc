// Sensors sampled inside the simulation: the schedule, the mounting on a link, the motion at the start
// of the step handed to the IMU, determinism and state restore. Each kind's own model is tested in its
// module (sensors/<kind>_sensor_test.cc).
#include "hadal/core/simulation.h"
#include "hadal/geometry/raycast_service.h"
#include "hadal/sensors/camera_sensor.h"
#include "hadal/sensors/fls_sensor.h"
#include "hadal/sensors/multibeam_sensor.h"
#include "hadal/sensors/sidescan_sensor.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <atomic>
#include <future>
#include <thread>
#include <string>

#include "hadal/physics/ocean.h"
#include "hadal/physics/test_models.h"

namespace hadal {
namespace {

namespace testing = physics::testing;

// A vehicle that stays where it is put: no gravity, no buoyancy volume, no damping, no added mass.
// Its pressure sensor sits 0.5 m above and 0.3 m ahead of B's origin (link `mast` 0.2 m up, sensor
// 0.3 m up in it).
Model still_vehicle_with_pressure_sensor(double depth, const sensors::PressureSensor::Spec& pressure, double rate_hz,
                                         std::uint64_t seed = 1) {
  VehicleSpec vehicle;
  vehicle.name = "auv";
  vehicle.links = {testing::box_link("hull", 10.0, Eigen::Vector3d(1, 0.3, 0.3), 0.0),
                   testing::box_link("mast", 1.0, Eigen::Vector3d(0.1, 0.1, 0.1), 0.0,
                                     testing::at(Eigen::Vector3d(0.3, 0, 0.2)))};
  vehicle.fluid.model = FluidModelType::kLumped;
  vehicle.fluid.added_mass.model = AddedMassModel::kNone;
  vehicle.X_WB_initial = testing::at(Eigen::Vector3d(0, 0, -depth));
  SensorSpec sensor;
  sensor.name = "depth";
  sensor.link_index = 1;
  sensor.X_LS.translation() = Eigen::Vector3d(0, 0, 0.3);
  sensor.rate_hz = rate_hz;
  sensor.frame_id = "auv/depth";
  sensor.kind = pressure;
  vehicle.sensors = {sensor};
  Model model = testing::water_model({vehicle});
  model.world.gravity_W.setZero();
  model.world.seabed.z = -5000.0;
  model.world.physics_rate_hz = 1000.0;
  model.world.seed = seed;
  model.world.water.density_model = DensityModel::kRamp;
  return model;
}

double pressure_of(const Simulation& sim) {
  return state_of<sensors::PressureSensor>(sim.state().vehicles[0].sensors[0]).pressure;
}

// Without noise the sensor reads the ocean's absolute pressure at its own depth (0.5 m shallower than
// B), exactly; 200 Hz in a 1 kHz loop gives a sample every 5th step, stamped with its sim time.
TEST(SimulationSensorsTest, PressureSensorReadsTheOceanAtItsPositionOnSchedule) {
  const double depth = 1500.0;
  Simulation sim(still_vehicle_with_pressure_sensor(depth, sensors::PressureSensor::Spec{}, 200.0));
  const double expected = sim.ocean().pressure(depth - 0.5);
  std::uint64_t last = 0;
  for (int k = 1; k <= 1000; ++k) {
    sim.step();
    const SensorState& s = sim.state().vehicles[0].sensors[0];
    if (k % 5 == 0) {
      ASSERT_EQ(s.samples, last + 1) << k;
      EXPECT_EQ(s.stamp, sim.time());
      EXPECT_EQ(state_of<sensors::PressureSensor>(s).pressure, expected);
    } else {
      ASSERT_EQ(s.samples, last) << k;
    }
    last = s.samples;
  }
  EXPECT_EQ(last, 200u);
}

// Same seed: bit-identical streams; another seed: different; a restored state continues the stream
// exactly as the uninterrupted run does.
TEST(SimulationSensorsTest, SensorStreamsAreDeterministicAndRestorable) {
  sensors::PressureSensor::Spec pressure;
  pressure.noise_stddev = 50.0;
  auto stream = [&](std::uint64_t seed) {
    Simulation sim(still_vehicle_with_pressure_sensor(200.0, pressure, 100.0, seed));
    std::vector<double> values;
    for (int k = 0; k < 500; ++k) {
      sim.step();
      if (k % 10 == 9) values.push_back(pressure_of(sim));
    }
    return values;
  };
  EXPECT_EQ(stream(7), stream(7));
  EXPECT_NE(stream(7), stream(8));

  Simulation sim(still_vehicle_with_pressure_sensor(200.0, pressure, 100.0, 3));
  for (int k = 0; k < 237; ++k) sim.step();
  const SimState saved = sim.state();
  std::vector<double> first, second;
  for (int k = 0; k < 300; ++k) {
    sim.step();
    first.push_back(pressure_of(sim));
  }
  sim.set_state(saved);
  for (int k = 0; k < 300; ++k) {
    sim.step();
    second.push_back(pressure_of(sim));
  }
  EXPECT_EQ(first, second);
}

// One neutrally buoyant box (lumped model, rho V = m) with an IMU at lever arm r on it, the IMU frame
// turned by rpy_S; `gravity` on or off.
Model imu_vehicle(const Eigen::Vector3d& r_BS, const Eigen::Matrix3d& R_BS, bool gravity,
                  const sensors::ImuSensor::Spec& imu = sensors::ImuSensor::Spec{}) {
  VehicleSpec vehicle;
  vehicle.name = "auv";
  const Eigen::Vector3d size(1, 0.4, 0.4);
  vehicle.links = {testing::box_link("hull", 1000.0 * size.prod(), size, size.prod())};
  vehicle.fluid.model = FluidModelType::kLumped;
  vehicle.fluid.added_mass.model = AddedMassModel::kNone;
  vehicle.X_WB_initial = testing::at(Eigen::Vector3d(0, 0, -30));
  SensorSpec sensor;
  sensor.name = "imu";
  sensor.X_LS = testing::at(r_BS, R_BS);
  sensor.rate_hz = 100.0;
  sensor.frame_id = "auv/imu";
  sensor.kind = imu;
  vehicle.sensors = {sensor};
  Model model = testing::water_model({vehicle});
  if (!gravity) model.world.gravity_W.setZero();
  model.world.seabed.z = -5000.0;
  model.world.physics_rate_hz = 1000.0;
  return model;
}

// At rest in the water an ideal IMU reads no rotation and the specific force -g: "up", 9.80665 m/s^2,
// expressed in its own (here rolled and yawed) frame. Forces balance to rounding: 1e-9.
TEST(SimulationSensorsTest, ImuAtRestReadsGravityInItsFrame) {
  const Eigen::Matrix3d R_BS = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX())).toRotationMatrix();
  Simulation sim(imu_vehicle(Eigen::Vector3d(0.3, 0.1, 0.1), R_BS, true));
  for (int k = 0; k < 50; ++k) sim.step();
  const SensorState& s = sim.state().vehicles[0].sensors[0];
  ASSERT_EQ(s.samples, 5u);
  const Eigen::Vector3d expected = R_BS.transpose() * Eigen::Vector3d(0, 0, 9.80665);
  const sensors::ImuSensor::State& imu = state_of<sensors::ImuSensor>(s);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(imu.angular_velocity_S[c], 0.0, 1e-9);
    EXPECT_NEAR(imu.specific_force_S[c], expected[c], 1e-9);
  }
}

// A body spinning at w about z (no gravity, no fluid): the IMU at r from the centre of mass reads w
// and the centripetal specific force -w^2 r in its frame (fixed to the body). The IMU uses the mean
// acceleration over the last step, whose direction lags the end-of-step radius by w dt / 2 (5e-4 rad
// here), hence 1e-3 relative.
TEST(SimulationSensorsTest, ImuOnASpinningBodyReadsTheCentripetalForce) {
  const double w = 1.0;
  const Eigen::Vector3d r(0.5, 0.0, 0.0);
  Model model = imu_vehicle(r, Eigen::Matrix3d::Identity(), false);
  model.vehicles[0].fluid.linear_damping.setZero();
  Simulation sim(model);
  SimState state = sim.state();
  state.vehicles[0].body.w_WB = Eigen::Vector3d(0, 0, w);
  sim.set_state(state);
  for (int k = 0; k < 1000; ++k) sim.step();
  const sensors::ImuSensor::State& imu = state_of<sensors::ImuSensor>(sim.state().vehicles[0].sensors[0]);
  EXPECT_NEAR(imu.angular_velocity_S.z(), w, 1e-9);
  EXPECT_NEAR(imu.specific_force_S.x(), -w * w * r.x(), 1e-3 * w * w * r.x());
  EXPECT_NEAR(imu.specific_force_S.y(), 0.0, 1e-3 * w * w * r.x());
  EXPECT_NEAR(imu.specific_force_S.z(), 0.0, 1e-9);
}

// --- asynchronous capture ------------------------------------------------------------------------

// The still vehicle 40.2 m over a plane seabed with a downward profiler (10 Hz, latency `latency_s`),
// captured on the ray-cast workers.
Model profiler_vehicle(double latency_s, double noise_stddev = 0.0, std::uint64_t seed = 1) {
  Model model = still_vehicle_with_pressure_sensor(0.0, sensors::PressureSensor::Spec{}, 10.0, seed);
  model.world.seabed.z = -100.0;
  model.world.physics_rate_hz = 500.0;
  model.vehicles[0].X_WB_initial = testing::at(Eigen::Vector3d(0, 0, -59.8));
  SensorSpec profiler;
  profiler.name = "profiler";
  profiler.X_LS = testing::at(Eigen::Vector3d(0, 0, -0.2),
                              Eigen::AngleAxisd(EIGEN_PI / 2.0, Eigen::Vector3d::UnitY()).toRotationMatrix());
  profiler.rate_hz = 10.0;
  profiler.latency_s = latency_s;
  sensors::ProfilerSensor::Spec spec;
  spec.beams = 64;
  spec.noise_stddev = noise_stddev;
  spec.resolution = 0.0;
  profiler.kind = spec;
  model.vehicles[0].sensors = {profiler};
  return model;
}

const sensors::ProfilerSensor::State& scan_of(const Simulation& sim) {
  return state_of<sensors::ProfilerSensor>(sim.state().vehicles[0].sensors[0]);
}

// Captured at each sample time (every 50th step at 500 Hz), pending in the state for latency 0.05 s
// (25 steps), then delivered at the end of step 75, 125, ..., stamped with the capture's time; beam 31,
// next to the vertical, reads the plane 40 m down along its ray nearest the vertical (float: 4 ulp of
// 100 m).
TEST(SimulationSensorsTest, CapturesAreDeliveredAtCaptureTimePlusLatency) {
  Simulation sim(profiler_vehicle(0.05));
  for (int k = 1; k <= 300; ++k) {
    sim.step();
    const SensorState& s = sim.state().vehicles[0].sensors[0];
    const int delivered = k < 75 ? 0 : 1 + (k - 75) / 50;
    ASSERT_EQ(s.samples, static_cast<std::uint64_t>(delivered)) << k;
    const bool pending = k >= 50 && k % 50 < 25;
    ASSERT_EQ(s.captures.size(), pending ? 1u : 0u) << k;
    if (pending) {
      EXPECT_EQ(s.captures.front().time, static_cast<double>(50 * (k / 50)) * sim.model().world.step_size());
    }
    if (delivered > 0 && (k - 75) % 50 == 0) {
      EXPECT_EQ(s.stamp, static_cast<double>(k - 25) * sim.model().world.step_size()) << k;
      const auto& spec = std::get<sensors::ProfilerSensor::Spec>(sim.model().vehicles[0].sensors[0].kind);
      const double nearest = std::abs(sensors::ProfilerSensor::beam_angle(spec, 31)) -
                             spec.beam_width * (0.5 - 0.5 / spec.rays_per_beam);
      EXPECT_NEAR(scan_of(sim).ranges[31], 40.0 / std::cos(nearest), 4 * FLT_EPSILON * 100.0);
    }
  }
  EXPECT_EQ(sim.dropped_captures(), 0u);
  // Without latency the capture is delivered in the step that takes it.
  Simulation now(profiler_vehicle(0.0));
  for (int k = 0; k < 50; ++k) now.step();
  EXPECT_EQ(now.state().vehicles[0].sensors[0].samples, 1u);
  EXPECT_EQ(now.state().vehicles[0].sensors[0].stamp, now.time());
  EXPECT_TRUE(now.state().vehicles[0].sensors[0].captures.empty());
}

// A pending capture is part of the state: restoring a state saved while a capture was in flight (and
// while the vehicle moves) re-casts it from its snapshot, and the scans, noise included, continue
// bit-identically; the same seed gives the same scans, another seed others.
TEST(SimulationSensorsTest, PendingCapturesRestoreAndReplayExactly) {
  auto moving = [](std::uint64_t seed) {
    Model model = profiler_vehicle(0.07, 0.02, seed);
    model.vehicles[0].v_WB_initial = Eigen::Vector3d(0.5, 0.2, 0.3);  // rising: every scan differs
    return model;
  };
  auto record = [](Simulation& sim, int steps) {
    std::vector<double> out;
    std::uint64_t seen = sim.state().vehicles[0].sensors[0].samples;
    for (int k = 0; k < steps; ++k) {
      sim.step();
      const SensorState& s = sim.state().vehicles[0].sensors[0];
      if (s.samples == seen) continue;
      seen = s.samples;
      out.push_back(s.stamp);
      const auto& ranges = state_of<sensors::ProfilerSensor>(s).ranges;
      out.insert(out.end(), ranges.begin(), ranges.end());
    }
    return out;
  };
  Simulation a(moving(3)), b(moving(3)), c(moving(4));
  EXPECT_EQ(record(a, 600), record(b, 600));
  record(c, 600);
  for (int k = 0; k < 60; ++k) {  // into a capture's flight: taken at 1.3 s (step 650), due at 1.37 s
    a.step();
    c.step();
  }
  ASSERT_EQ(a.state().vehicles[0].sensors[0].captures.size(), 1u);
  EXPECT_NE(state_of<sensors::ProfilerSensor>(a.state().vehicles[0].sensors[0]).ranges,
            state_of<sensors::ProfilerSensor>(c.state().vehicles[0].sensors[0]).ranges);
  const SimState saved = a.state();
  const std::vector<double> first = record(a, 400);
  ASSERT_GE(first.size(), 4u * 65u);
  a.set_state(saved);
  EXPECT_EQ(record(a, 400), first);
}

// When the step must not wait (real time), a capture whose rays are not traced by its due step is
// dropped and counted. 4096 beams x 64 rays = 262 144 rays over the plane with no latency: the step
// checks a few nanoseconds after handing them to the workers, long before any CPU has traced them.
TEST(SimulationSensorsTest, LateCapturesAreDroppedWhenTheStepMustNotWait) {
  Model model = profiler_vehicle(0.0);
  auto& spec = std::get<sensors::ProfilerSensor::Spec>(model.vehicles[0].sensors[0].kind);
  spec.beams = 4096;
  spec.rays_per_beam = 64;
  Simulation sim(std::move(model));
  sim.set_wait_for_captures(false);
  for (int k = 0; k < 50; ++k) sim.step();
  EXPECT_EQ(sim.dropped_captures(), 1u);
  EXPECT_EQ(sim.state().vehicles[0].sensors[0].samples, 0u);
  EXPECT_TRUE(sim.state().vehicles[0].sensors[0].captures.empty());
}

// The moving vehicle of the profiler tests with a camera looking down at the seabed (96 x 72 px, 10 Hz,
// latency 0.07 s, the image sensor's noise on) and a light beside it, in slightly turbid water.
Model camera_vehicle(std::uint64_t seed) {
  Model model = profiler_vehicle(0.07, 0.0, seed);
  model.vehicles[0].v_WB_initial = Eigen::Vector3d(0.5, 0.2, 0.3);
  model.world.optics.water.scattering_per_m = render::Rgb::Constant(0.05);
  SensorSpec camera;
  camera.name = "camera";
  camera.X_LS = testing::at(Eigen::Vector3d(0, 0, -0.2),
                            Eigen::AngleAxisd(EIGEN_PI / 2.0, Eigen::Vector3d::UnitY()).toRotationMatrix());
  camera.rate_hz = 10.0;
  camera.latency_s = 0.07;
  sensors::CameraSensor::Spec spec;
  sensors::CameraSensor::set_lens(spec, render::lens_from_horizontal_fov(96, 72, 70.0 * kDegToRad));
  spec.sensor.exposure_s = 0.5;  // bright enough at 40 m to make counts
  camera.kind = spec;
  model.vehicles[0].sensors = {camera};
  LightSpec light;
  light.name = "lamp";
  light.X_LF = testing::at(Eigen::Vector3d(0.3, 0, -0.2), camera.X_LS.linear());
  light.intensity_W_per_sr = Eigen::Array3d::Constant(5e4);
  model.vehicles[0].lights = {light};
  return model;
}

// Real time (the step never waits): frames dropped before any worker started them are skipped, never
// rendered. The test holds both ray-cast workers in a job of its own (every task of its parallel loop
// waits for a latch) while the simulation steps past three frames' due steps (taken at 0.1, 0.2 and
// 0.3 s, due 0.07 s later): all three are dropped, and when the workers are let go each is skipped.
// Then, waiting again, the frame taken at 0.4 s renders and is delivered as usual.
TEST(SimulationSensorsTest, CameraFramesDroppedBeforeTheyStartAreSkipped) {
  Model model = camera_vehicle(3);
  model.world.raycast_threads = 2;
  Simulation sim(std::move(model));
  sim.set_wait_for_captures(false);
  geometry::RaycastService& service = sim.raycast_service();
  ASSERT_EQ(service.num_threads(), 2);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<int> holding{0};
  const std::vector<Eigen::Isometry3d> X_WB = {sim.state().vehicles[0].body.X_WB};
  std::future<void> blocker = service.submit(X_WB, [&](const geometry::EmbreeScene&, const ParallelFor& parallel) {
    parallel(64, [&](std::size_t) {
      ++holding;
      released.wait();
    });
  });
  while (holding.load() < 2) std::this_thread::yield();  // both workers are in the test's job
  for (int k = 0; k < 190; ++k) sim.step();             // to 0.38 s: frames of 0.1, 0.2, 0.3 s due and dropped
  EXPECT_EQ(sim.dropped_captures(), 3u);
  EXPECT_EQ(sim.state().vehicles[0].sensors[0].samples, 0u);
  release.set_value();
  blocker.get();
  // A job submitted now finishes after every job before it: the three dropped frames have been reached.
  service.submit(X_WB, [](const geometry::EmbreeScene&, const ParallelFor&) {}).get();
  EXPECT_EQ(sim.skipped_captures(), 3u);
  sim.set_wait_for_captures(true);
  for (int k = 0; k < 60; ++k) sim.step();  // to 0.5 s: the 0.4 s frame is due at 0.47 s
  EXPECT_EQ(sim.state().vehicles[0].sensors[0].samples, 1u);
  EXPECT_EQ(sim.dropped_captures(), 3u);
  EXPECT_EQ(sim.skipped_captures(), 3u);
}

// A camera's frames are captures like the profiler's scans: restoring a state saved with a frame in
// flight re-renders it from its snapshot and the images, noise included, continue bit-identically; the
// same seed gives the same images, another seed other noise.
TEST(SimulationSensorsTest, CameraFramesRestoreAndReplayExactly) {
  auto record = [](Simulation& sim, int steps) {
    std::vector<std::vector<std::uint8_t>> out;
    std::uint64_t seen = sim.state().vehicles[0].sensors[0].samples;
    for (int k = 0; k < steps; ++k) {
      sim.step();
      const SensorState& s = sim.state().vehicles[0].sensors[0];
      if (s.samples == seen) continue;
      seen = s.samples;
      out.push_back(state_of<sensors::CameraSensor>(s).image);
    }
    return out;
  };
  Simulation a(camera_vehicle(3)), b(camera_vehicle(3)), c(camera_vehicle(4));
  const auto frames = record(a, 200);
  ASSERT_EQ(frames.size(), 3u);  // taken at 0.1, 0.2, 0.3 s, out 0.07 s later
  std::size_t lit = 0;
  for (std::uint8_t count : frames.back()) lit += count > 0;
  EXPECT_GT(lit, frames.back().size() / 10);  // the light's footprint on the seabed
  EXPECT_EQ(record(b, 200), frames);
  EXPECT_NE(record(c, 200), frames);
  for (int k = 0; k < 10; ++k) a.step();  // taken at 0.4 s (step 200), due at step 235
  ASSERT_EQ(a.state().vehicles[0].sensors[0].captures.size(), 1u);
  const SimState saved = a.state();
  const auto next = record(a, 100);
  ASSERT_EQ(next.size(), 2u);
  a.set_state(saved);
  EXPECT_EQ(record(a, 100), next);
}

// The moving vehicle of the profiler tests (its sensors 40 m above the seabed) with the three sonars (small: 32 beams
// each), speckle and receiver noise on, 10 Hz, latency 0.05 s: an FLS pitched 30 deg down, a multibeam looking
// down and a side-scan.
Model sonar_vehicle(std::uint64_t seed) {
  Model model = profiler_vehicle(0.05, 0.0, seed);
  model.vehicles[0].v_WB_initial = Eigen::Vector3d(0.5, 0.2, 0.3);
  const auto mount = [](const std::string& name, const Eigen::Matrix3d& R_LS, sensors::SensorKindSpec kind) {
    SensorSpec sensor;
    sensor.name = name;
    sensor.X_LS = testing::at(Eigen::Vector3d(0, 0, -0.2), R_LS);
    sensor.rate_hz = 10.0;
    sensor.latency_s = 0.05;
    sensor.kind = std::move(kind);
    return sensor;
  };
  sensors::FlsSensor::Spec fls;
  fls.beams = 32;
  fls.acoustics.max_range = 120.0;  // the seabed 40 m below: 62 to 117 m along the fan (no loader, no rate check)
  fls.acoustics.bins = 128;
  sensors::FlsSensor::make_ping(fls);
  sensors::MultibeamSensor::Spec multibeam;
  multibeam.beams = 32;
  multibeam.acoustics.max_range = 70.0;
  multibeam.acoustics.bins = 1000;
  sensors::MultibeamSensor::make_ping(multibeam);
  sensors::SidescanSensor::Spec sidescan;
  sidescan.acoustics.max_range = 70.0;
  sidescan.acoustics.bins = 300;
  sensors::SidescanSensor::make_ping(sidescan);
  const Eigen::Matrix3d down = Eigen::AngleAxisd(EIGEN_PI / 2.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  model.vehicles[0].sensors = {
      mount("fls", Eigen::AngleAxisd(EIGEN_PI / 6.0, Eigen::Vector3d::UnitY()).toRotationMatrix(), fls),
      mount("multibeam", down, multibeam), mount("sidescan", Eigen::Matrix3d::Identity(), sidescan)};
  return model;
}

// The sonars' pings are captures like the camera's frames: the same seed gives the same images and
// detections (speckle and noise included), another seed others; restoring a state saved with pings in flight
// re-pings them from their snapshots and everything continues bit-identically.
TEST(SimulationSensorsTest, SonarPingsRestoreAndReplayExactly) {
  using Record = std::vector<std::vector<std::uint8_t>>;
  auto record = [](Simulation& sim, int steps) {
    Record out;
    std::vector<std::uint64_t> seen(3);
    for (std::size_t k = 0; k < 3; ++k) seen[k] = sim.state().vehicles[0].sensors[k].samples;
    for (int n = 0; n < steps; ++n) {
      sim.step();
      const auto& sensors = sim.state().vehicles[0].sensors;
      for (std::size_t k = 0; k < 3; ++k) {
        if (sensors[k].samples == seen[k]) continue;
        seen[k] = sensors[k].samples;
        if (k == 0) out.push_back(state_of<sensors::FlsSensor>(sensors[k]).image);
        if (k == 1) {
          const auto& ranges = state_of<sensors::MultibeamSensor>(sensors[k]).last.range_m;
          std::vector<std::uint8_t> bytes(ranges.size() * sizeof(double));
          std::memcpy(bytes.data(), ranges.data(), bytes.size());
          out.push_back(std::move(bytes));
        }
        if (k == 2) out.push_back(state_of<sensors::SidescanSensor>(sensors[k]).port);
      }
    }
    return out;
  };
  Simulation a(sonar_vehicle(3)), b(sonar_vehicle(3)), c(sonar_vehicle(4));
  const Record pings = record(a, 200);
  ASSERT_EQ(pings.size(), 9u);  // 0.1, 0.2, 0.3 s for each sonar, out 0.05 s later
  // The multibeam's first ping (0.1 s) reads the seabed 40 m below the sonar along beam 16's axis, 2.0 deg
  // off nadir: 40.03 / cos(2.0 deg) = 40.06 m (the vehicle rose 3 cm), within 15 cm (speckle and noise on).
  double near_nadir = 0.0;
  std::memcpy(&near_nadir, pings[1].data() + 16 * sizeof(double), sizeof near_nadir);
  EXPECT_NEAR(near_nadir, 40.06, 0.15);
  EXPECT_EQ(record(b, 200), pings);
  EXPECT_NE(record(c, 200), pings);
  for (int k = 0; k < 10; ++k) a.step();  // pinged at 0.4 s (step 200), due at step 225
  ASSERT_EQ(a.state().vehicles[0].sensors[0].captures.size(), 1u);
  const SimState saved = a.state();
  const Record next = record(a, 100);
  ASSERT_EQ(next.size(), 6u);
  a.set_state(saved);
  EXPECT_EQ(record(a, 100), next);
}

}  // namespace
}  // namespace hadal
