// Sensors sampled inside the simulation: schedule, ideal values from the state and the ocean, noise
// from the shared noise module, determinism and state restore.
#include "hadal/core/simulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "hadal/physics/ocean.h"
#include "hadal/physics/test_models.h"
#include "hadal/sensors/geomagnetic.h"
#include "hadal/sensors/magnetometer.h"
#include "hadal/sensors/noise.h"

namespace hadal {
namespace {

namespace testing = physics::testing;

// A vehicle that stays where it is put: no gravity, no buoyancy volume, no damping, no added mass.
// Its pressure sensor sits 0.5 m above and 0.3 m ahead of B's origin (link `mast` 0.2 m up, sensor
// 0.3 m up in it).
Model still_vehicle_with_pressure_sensor(double depth, const PressureSensorSpec& pressure, double rate_hz,
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
  sensor.pressure = pressure;
  vehicle.sensors = {sensor};
  Model model = testing::water_model({vehicle});
  model.world.gravity_W.setZero();
  model.world.seabed.z = -5000.0;
  model.world.physics_rate_hz = 1000.0;
  model.world.seed = seed;
  model.world.water.density_model = DensityModel::kRamp;
  return model;
}

// Without noise the sensor reads the ocean's absolute pressure at its own depth (0.5 m shallower than
// B), exactly; 200 Hz in a 1 kHz loop gives a sample every 5th step, stamped with its sim time.
TEST(SimulationSensorsTest, PressureSensorReadsTheOceanAtItsPositionOnSchedule) {
  const double depth = 1500.0;
  Simulation sim(still_vehicle_with_pressure_sensor(depth, PressureSensorSpec{}, 200.0));
  const double expected = sim.ocean().pressure(depth - 0.5);
  std::uint64_t last = 0;
  for (int k = 1; k <= 1000; ++k) {
    sim.step();
    const SensorState& s = sim.state().vehicles[0].sensors[0];
    if (k % 5 == 0) {
      ASSERT_EQ(s.samples, last + 1) << k;
      EXPECT_EQ(s.stamp, sim.time());
      EXPECT_EQ(s.value[0], expected);
    } else {
      ASSERT_EQ(s.samples, last) << k;
    }
    last = s.samples;
  }
  EXPECT_EQ(last, 200u);
}

// White noise of 100 Pa: over 20 000 samples the mean is within 4 sigma / sqrt(n) = 2.8 Pa of the
// ideal value and the standard deviation within 4 sigma / sqrt(2 n) = 2 % of 100 Pa (fixed seed).
TEST(SimulationSensorsTest, PressureNoiseHasTheConfiguredSpread) {
  PressureSensorSpec pressure;
  pressure.noise_stddev = 100.0;
  Simulation sim(still_vehicle_with_pressure_sensor(100.0, pressure, 1000.0));
  const double ideal = sim.ocean().pressure(99.5);
  double sum = 0.0, sum2 = 0.0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    sim.step();
    const double e = sim.state().vehicles[0].sensors[0].value[0] - ideal;
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / n, stddev = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 4.0 * 100.0 / std::sqrt(n));
  EXPECT_NEAR(stddev, 100.0, 4.0 * 100.0 / std::sqrt(2.0 * n));
}

// Quantisation to the resolution and clipping to [0, range_max]; above the water the sensor reads the
// atmosphere.
TEST(SimulationSensorsTest, PressureResolutionRangeAndAir) {
  PressureSensorSpec pressure;
  pressure.resolution = 1000.0;
  pressure.noise_stddev = 300.0;
  Simulation sim(still_vehicle_with_pressure_sensor(50.0, pressure, 100.0));
  for (int k = 0; k < 100; ++k) {
    sim.step();
    const double p = sim.state().vehicles[0].sensors[0].value[0];
    EXPECT_EQ(std::fmod(p, 1000.0), 0.0) << p;
  }
  PressureSensorSpec small_range;
  small_range.range_max = 2.0e5;
  Simulation deep(still_vehicle_with_pressure_sensor(1000.0, small_range, 100.0));
  deep.step();
  for (int k = 0; k < 10; ++k) deep.step();
  EXPECT_EQ(deep.state().vehicles[0].sensors[0].value[0], 2.0e5);
  Simulation dry(still_vehicle_with_pressure_sensor(-10.0, PressureSensorSpec{}, 100.0));
  for (int k = 0; k < 10; ++k) dry.step();
  EXPECT_EQ(dry.state().vehicles[0].sensors[0].value[0], dry.ocean().atmospheric_pressure());
}

// Same seed: bit-identical streams; another seed: different; a restored state continues the stream
// exactly as the uninterrupted run does.
TEST(SimulationSensorsTest, SensorStreamsAreDeterministicAndRestorable) {
  PressureSensorSpec pressure;
  pressure.noise_stddev = 50.0;
  auto stream = [&](std::uint64_t seed) {
    Simulation sim(still_vehicle_with_pressure_sensor(200.0, pressure, 100.0, seed));
    std::vector<double> values;
    for (int k = 0; k < 500; ++k) {
      sim.step();
      if (k % 10 == 9) values.push_back(sim.state().vehicles[0].sensors[0].value[0]);
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
    first.push_back(sim.state().vehicles[0].sensors[0].value[0]);
  }
  sim.set_state(saved);
  for (int k = 0; k < 300; ++k) {
    sim.step();
    second.push_back(sim.state().vehicles[0].sensors[0].value[0]);
  }
  EXPECT_EQ(first, second);
}

// One neutrally buoyant box (lumped model, rho V = m) with an IMU at lever arm r on it, the IMU frame
// turned by rpy_S; `gravity` on or off.
Model imu_vehicle(const Eigen::Vector3d& r_BS, const Eigen::Matrix3d& R_BS, bool gravity,
                  const ImuSensorSpec& imu = ImuSensorSpec{}) {
  VehicleSpec vehicle;
  vehicle.name = "auv";
  const Eigen::Vector3d size(1, 0.4, 0.4);
  vehicle.links = {testing::box_link("hull", 1000.0 * size.prod(), size, size.prod())};
  vehicle.fluid.model = FluidModelType::kLumped;
  vehicle.fluid.added_mass.model = AddedMassModel::kNone;
  vehicle.X_WB_initial = testing::at(Eigen::Vector3d(0, 0, -30));
  SensorSpec sensor;
  sensor.name = "imu";
  sensor.type = SensorType::kImu;
  sensor.X_LS = testing::at(r_BS, R_BS);
  sensor.rate_hz = 100.0;
  sensor.frame_id = "auv/imu";
  sensor.imu = imu;
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
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(s.value[c], 0.0, 1e-9);
    EXPECT_NEAR(s.value[3 + c], expected[c], 1e-9);
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
  const SensorState& s = sim.state().vehicles[0].sensors[0];
  EXPECT_NEAR(s.value[2], w, 1e-9);
  EXPECT_NEAR(s.value[3], -w * w * r.x(), 1e-3 * w * w * r.x());
  EXPECT_NEAR(s.value[4], 0.0, 1e-3 * w * w * r.x());
  EXPECT_NEAR(s.value[5], 0.0, 1e-9);
}

// White gyro noise from an ARW figure: sample stddev N sqrt(rate) within 4 sigma / sqrt(2 n) (n =
// 20 000 samples of one axis, fixed seed); temperature drift (T - T_ref) k_T shifts the mean.
TEST(SimulationSensorsTest, ImuNoiseAndTemperatureDrift) {
  ImuSensorSpec imu;
  const double N = sensors::arw_to_noise_density(0.125);
  for (auto& axis : imu.gyro.axes) axis.white_noise_density = N;
  imu.temperature_reference = 20.0;
  imu.accel_temperature_coefficient = 1e-3;  // [m/s^2 per K]; water at 4 degC: -0.016 m/s^2
  Model model = imu_vehicle(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), true, imu);
  Simulation sim(model);
  const int n = 20000;
  double sum = 0.0, sum2 = 0.0, accel_z = 0.0;
  for (int k = 0; k < n * 10; ++k) {
    sim.step();
    if ((k + 1) % 10 != 0) continue;
    const SensorState& s = sim.state().vehicles[0].sensors[0];
    sum += s.value[2];
    sum2 += s.value[2] * s.value[2];
    accel_z = s.value[5];
  }
  const double sigma = N * std::sqrt(100.0);
  const double stddev = std::sqrt(sum2 / n - (sum / n) * (sum / n));
  EXPECT_NEAR(stddev, sigma, 4.0 * sigma / std::sqrt(2.0 * n));
  EXPECT_NEAR(accel_z, 9.80665 + (sim.ocean().temperature(30.0) - 20.0) * 1e-3, 1e-9);
}

// A magnetometer on the still vehicle 30 m below W's origin (43 N 5 E, 2026-06-01), B aligned with W:
// without noise it reads WMM2025 at the sensor's geodetic position (height -30 m on the origin's
// normal), in ENU = S axes, to 1e-12 T (0.001 nT; the model's own synthesis is exact to rounding);
// a hard-iron dipole m = 1 A m^2 along z, 0.5 m ahead of the sensor, adds its equatorial closed form
// -mu0 m / (4 pi r^3) = -0.8 uT along z.
TEST(SimulationSensorsTest, MagnetometerReadsWmmPlusHardIron) {
  Model model = still_vehicle_with_pressure_sensor(30.0, PressureSensorSpec{}, 10.0);
  model.world.origin.latitude = 43.0 * EIGEN_PI / 180.0;
  model.world.origin.longitude = 5.0 * EIGEN_PI / 180.0;
  model.world.start_decimal_year = sensors::decimal_year_from_date(2026, 6, 1);
  SensorSpec magnetometer;
  magnetometer.name = "mag";
  magnetometer.type = SensorType::kMagnetometer;
  magnetometer.rate_hz = 10.0;
  model.vehicles[0].sensors = {magnetometer};
  Simulation plain(model);
  sensors::MagneticDipole hard_iron;
  hard_iron.p_FD = Eigen::Vector3d(0.5, 0.0, 0.0);
  hard_iron.m_F = Eigen::Vector3d(0.0, 0.0, 1.0);
  model.vehicles[0].sensors[0].magnetometer.params.dipoles_B = {hard_iron};
  Simulation with_iron(model);
  for (int k = 0; k < 100; ++k) {
    plain.step();
    with_iron.step();
  }
  const sensors::GeomagneticModel wmm =
      sensors::GeomagneticModel::load_cof(std::string(HADAL_SOURCE_DIR) + "/server/data/WMM2025.COF");
  const double year = model.world.start_decimal_year + 0.1 / (365.25 * 86400.0);
  const Eigen::Vector3d expected =
      wmm.field(model.world.origin.latitude, model.world.origin.longitude, -30.0, year).B_ENU_T();
  const std::vector<double>& B = plain.state().vehicles[0].sensors[0].value;
  ASSERT_EQ(plain.state().vehicles[0].sensors[0].samples, 1u);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(B[c], expected[c], 1e-12) << c;
  const std::vector<double>& B_iron = with_iron.state().vehicles[0].sensors[0].value;
  EXPECT_NEAR(B_iron[2] - B[2], -1e-7 / 0.125, 1e-15);
  EXPECT_NEAR(B_iron[0] - B[0], 0.0, 1e-15);
}

// GPS: with the antenna above the water a fix at GeographicLib's LocalCartesian inverse of the antenna
// position (W = the local ENU frame at world.origin), agreeing with the magnetometer's own exact ECEF
// geodesy to 1e-12 deg; under water NO_FIX with NaN. Horizontal noise of 2 m per axis: sample stddev of
// the east offset over 4000 fixes within 4 sigma / sqrt(2 n) = 4.5 %.
TEST(SimulationSensorsTest, GpsFixesOnlyAboveTheWater) {
  auto gps_model = [](double z, double horizontal) {
    Model model = still_vehicle_with_pressure_sensor(-z, PressureSensorSpec{}, 10.0);
    model.world.origin.latitude = 43.0 * EIGEN_PI / 180.0;
    model.world.origin.longitude = 5.0 * EIGEN_PI / 180.0;
    model.vehicles[0].X_WB_initial.translation() = Eigen::Vector3d(120.0, -40.0, z);
    SensorSpec gps;
    gps.name = "gps";
    gps.type = SensorType::kGps;
    gps.rate_hz = 10.0;
    gps.gps.horizontal_stddev = horizontal;
    gps.gps.vertical_stddev = 0.0;
    model.vehicles[0].sensors = {gps};
    return model;
  };
  Simulation surfaced(gps_model(1.0, 0.0));
  for (int k = 0; k < 100; ++k) surfaced.step();
  const std::vector<double>& fix = surfaced.state().vehicles[0].sensors[0].value;
  ASSERT_EQ(fix[3], 1.0);
  const sensors::LocalEnuFrame frame({43.0 * EIGEN_PI / 180.0, 5.0 * EIGEN_PI / 180.0, 0.0});
  const sensors::GeodeticPosition expected = frame.to_geodetic(Eigen::Vector3d(120.0, -40.0, 1.0));
  EXPECT_NEAR(fix[0], expected.latitude_rad * 180.0 / EIGEN_PI, 1e-12);
  EXPECT_NEAR(fix[1], expected.longitude_rad * 180.0 / EIGEN_PI, 1e-12);
  EXPECT_NEAR(fix[2], expected.height_m, 1e-6);

  Simulation dived(gps_model(-1.0, 0.0));
  for (int k = 0; k < 100; ++k) dived.step();
  const std::vector<double>& none = dived.state().vehicles[0].sensors[0].value;
  EXPECT_EQ(none[3], 0.0);
  EXPECT_TRUE(std::isnan(none[0]));

  Simulation noisy(gps_model(1.0, 2.0));
  const int n = 4000;
  const double metres_per_deg_lon = 111319.49 * std::cos(43.0 * EIGEN_PI / 180.0);  // ~, scale only
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n * 100; ++k) {
    noisy.step();
    if ((k + 1) % 100 != 0) continue;
    const double east = (noisy.state().vehicles[0].sensors[0].value[1] - fix[1]) * metres_per_deg_lon;
    sum += east;
    sum2 += east * east;
  }
  const double stddev = std::sqrt(sum2 / n - (sum / n) * (sum / n));
  EXPECT_NEAR(stddev, 2.0, 4.0 * 2.0 / std::sqrt(2.0 * n) + 0.01);  // + 0.5 % for the metre scale
}

}  // namespace
}  // namespace hadal
