// The IMU kind alone (no Bullet): specific force and rate at a lever arm from the given motion (closed
// forms), its frame, noise, temperature drift, thruster vibration, the data-sheet presets and its message.
#include "hadal/sensors/imu_sensor.h"

#include <gtest/gtest.h>
#include <sensor_msgs.h>

#include <cfloat>
#include <cmath>

#include "config/reference_csv_test_support.h"
#include "sensor_test_support.h"
#include "hadal/core/units.h"

namespace hadal::sensors {
namespace {

using testing::pose;
using testing::rpy;
using testing::SensorTestWorld;

constexpr double kG = 9.80665;

SensorTestWorld world_at(const Eigen::Vector3d& p_W) {
  Model model = testing::one_vehicle_world(p_W, -5000.0);
  model.world.gravity_W = Eigen::Vector3d(0, 0, -kG);
  return SensorTestWorld(model);
}

// At rest an ideal IMU reads no rotation and the specific force -g: "up", g_n, expressed in its own
// (here rolled and yawed) frame, on a rolled vehicle. 4 eps of g for the rotations.
TEST(ImuSensorTest, AtRestReadsGravityInItsFrame) {
  SensorTestWorld world = world_at(Eigen::Vector3d(0, 0, -30));
  const Eigen::Matrix3d R_WB = rpy(0.2, -0.1, 1.0);
  world.body().X_WB = pose(Eigen::Vector3d(0, 0, -30), R_WB);
  const Eigen::Matrix3d R_BS = rpy(0.4, 0.0, 0.7);
  const ImuSensor::Spec spec;
  ImuSensor::State state = world.initial_state<ImuSensor>(spec, 100.0);
  world.sample<ImuSensor>(spec, state, pose(Eigen::Vector3d(0.3, 0.1, 0.1), R_BS), 100.0);
  const Eigen::Vector3d expected = (R_WB * R_BS).transpose() * Eigen::Vector3d(0, 0, kG);
  EXPECT_EQ(state.angular_velocity_S, Eigen::Vector3d::Zero());
  EXPECT_NEAR((state.specific_force_S - expected).norm(), 0.0, 4 * DBL_EPSILON * kG);
}

// The lever arm r = p_WS - p_WBcm: a body that turns at w about z, gains dv along x and dw about z
// over the step dt, with its centre of mass at p_BBcm, reads at the end of the step
//   f = dv / dt + (dw / dt) x r + w x (w x r) - g,   rate w,
// in S. Here w = (0, 0, 2) rad/s, dv / dt = (3, 0, 0) m/s^2, dw / dt = 5 rad/s^2 about z,
// r = (0.5, 0.2, 0) m: f = (3 - 5 * 0.2 - 4 * 0.5, 5 * 0.5 - 4 * 0.2, g) = (0, 1.7, g) m/s^2.
// 1e-12: the velocities of the centre of mass are formed from B's origin and differenced over dt.
TEST(ImuSensorTest, LeverArmSpecificForceIsTheClosedForm) {
  SensorTestWorld world = world_at(Eigen::Vector3d::Zero());
  world.model.world.water.surface_z = -100.0;  // in air, at the origin
  const double dt = 0.002;
  world.step_size = dt;
  world.p_BBcm = Eigen::Vector3d(-0.1, 0.0, 0.0);  // the centre of mass 0.1 m behind B's origin
  const Eigen::Vector3d p_BS(0.4, 0.2, 0.0);         // r = p_BS - p_BBcm = (0.5, 0.2, 0)
  const Eigen::Vector3d w_end(0, 0, 2.0), w_start = w_end - Eigen::Vector3d(0, 0, 5.0 * dt);
  const Eigen::Vector3d v_cm_end(0.7, 0.0, 0.0), v_cm_start = v_cm_end - Eigen::Vector3d(3.0 * dt, 0, 0);
  RigidBodyState& body = world.body();
  body.X_WB = Eigen::Isometry3d::Identity();
  body.w_WB = w_end;
  body.v_WB = v_cm_end + w_end.cross(-world.p_BBcm);  // B's origin is 0.1 m ahead of the centre of mass
  world.v_WBcm_step_start = v_cm_start;
  world.w_WB_step_start = w_start;
  const ImuSensor::Spec spec;
  ImuSensor::State state = world.initial_state<ImuSensor>(spec, 100.0);
  world.sample<ImuSensor>(spec, state, pose(p_BS), 100.0);
  EXPECT_NEAR((state.specific_force_S - Eigen::Vector3d(0.0, 1.7, kG)).norm(), 0.0, 1e-12);
  EXPECT_EQ(state.angular_velocity_S, w_end);
  // Seen from a sensor frame yawed 90 deg: x_S = y_B, y_S = -x_B.
  world.sample<ImuSensor>(spec, state, pose(p_BS, rpy(0, 0, EIGEN_PI / 2.0)), 100.0);
  EXPECT_NEAR((state.specific_force_S - Eigen::Vector3d(1.7, 0.0, kG)).norm(), 0.0, 1e-12);
}

// White gyro noise from an ARW figure: sample stddev N sqrt(rate) within 4 sigma / sqrt(2 n) (n =
// 20 000 samples of one axis, fixed seed); temperature drift (T - T_ref) k_T shifts the reading by the
// ocean's temperature at the sensor.
TEST(ImuSensorTest, NoiseAndTemperatureDrift) {
  SensorTestWorld world = world_at(Eigen::Vector3d(0, 0, -30));
  ImuSensor::Spec spec;
  const double N = arw_to_noise_density(0.125);
  for (auto& axis : spec.gyro.axes) axis.white_noise_density = N;
  spec.temperature_reference = 20.0;
  spec.accel_temperature_coefficient = 1e-3;  // [m/s^2 per K]; water at 4 degC: -0.016 m/s^2
  ImuSensor::State state = world.initial_state<ImuSensor>(spec, 100.0);
  const int n = 20000;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    world.sample<ImuSensor>(spec, state, Eigen::Isometry3d::Identity(), 100.0);
    sum += state.angular_velocity_S.z();
    sum2 += state.angular_velocity_S.z() * state.angular_velocity_S.z();
  }
  const double sigma = N * std::sqrt(100.0);
  const double stddev = std::sqrt(sum2 / n - (sum / n) * (sum / n));
  EXPECT_NEAR(stddev, sigma, 4.0 * sigma / std::sqrt(2.0 * n));
  EXPECT_NEAR(state.specific_force_S.z(), kG + (world.ocean.temperature(30.0) - 20.0) * 1e-3, 1e-12);
}

// Thruster vibration: A sin(2 pi f t) on every axis with f = blades x |rotor speed| of the named
// thruster; none while it stands still.
TEST(ImuSensorTest, ThrusterVibrationAtTheBladePassFrequency) {
  Model model = testing::one_vehicle_world(Eigen::Vector3d(0, 0, -30), -5000.0);
  model.world.gravity_W.setZero();
  model.vehicles[0].actuators = {ActuatorSpec{"port", 0, physics::ThrusterActuator::Spec{}},
                                 ActuatorSpec{"starboard", 0, physics::ThrusterActuator::Spec{}}};
  SensorTestWorld world(model);
  ImuSensor::Spec spec;
  spec.vibration_thruster = 1;
  spec.vibration_blades = 4;
  spec.accel_vibration_amplitude = 0.01;
  spec.gyro_vibration_amplitude = 0.002;
  ImuSensor::State state = world.initial_state<ImuSensor>(spec, 100.0);
  world.state.time = 0.0123;
  world.sample<ImuSensor>(spec, state, Eigen::Isometry3d::Identity(), 100.0);
  EXPECT_EQ(state.specific_force_S, Eigen::Vector3d::Zero());
  std::get<physics::ThrusterActuator::State>(world.state.vehicles[0].actuators[1]).rotor_speed_rev_s = -12.5;  // 50 Hz
  world.sample<ImuSensor>(spec, state, Eigen::Isometry3d::Identity(), 100.0);
  const double phase = std::sin(2.0 * kPi * 50.0 * 0.0123);
  EXPECT_NEAR((state.specific_force_S - Eigen::Vector3d::Constant(0.01 * phase)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((state.angular_velocity_S - Eigen::Vector3d::Constant(0.002 * phase)).norm(), 0.0, 1e-15);
}

// sensor_msgs/Imu: rates and specific force, no orientation (covariance[0] = -1), diagonal covariances
// N^2 rate_hz per axis.
TEST(ImuSensorTest, Message) {
  ImuSensor::Spec spec;
  for (auto& axis : spec.gyro.axes) axis.white_noise_density = 1e-4;
  for (auto& axis : spec.accel.axes) axis.white_noise_density = 2e-3;
  ImuSensor::State state;
  state.angular_velocity_S = Eigen::Vector3d(0.1, 0.2, 0.3);
  state.specific_force_S = Eigen::Vector3d(0.0, 0.1, 9.8);
  sensor_msgs::msg::Imu msg;
  const std::string frame = "auv/imu";
  ImuSensor::fill_message(spec, state, MessageHeader{1.25, frame, 100.0}, msg);
  EXPECT_EQ(msg.angular_velocity().y(), 0.2);
  EXPECT_EQ(msg.linear_acceleration().z(), 9.8);
  EXPECT_EQ(msg.orientation_covariance()[0], -1.0);
  EXPECT_EQ(msg.angular_velocity_covariance()[4], 1e-8 * 100.0);
  EXPECT_EQ(msg.linear_acceleration_covariance()[8], 4e-6 * 100.0);
  EXPECT_EQ(msg.linear_acceleration_covariance()[1], 0.0);
  EXPECT_EQ(msg.header().frame_id(), "auv/imu");
}

// The presets carry the figures of docs/reference/sensors/imu_datasheet_figures.csv: the gyroscopes' as
// the CSV's rows give them (read from the file), the accelerometers' converted to SI (checked by hand).
TEST(ImuSensorTest, PresetsCarryTheDataSheetFigures) {
  ASSERT_EQ(imu_presets().size(), 5u);
  const auto rows = reference_tables::csv_rows(std::string(HADAL_SENSOR_REFERENCE_DIR) + "/imu_datasheet_figures.csv",
                                      "imu,class,gyro_ARW_deg_per_sqrt_h,gyro_bias_instability_deg_per_h", 7);
  for (const config::Preset<ImuDatasheet>& preset : imu_presets()) {
    SCOPED_TRACE(std::string(preset.id));
    const auto row = rows.find(std::string(preset.product));
    ASSERT_NE(row, rows.end()) << "no row '" << preset.product << "'";
    EXPECT_EQ(row->second[1].find("unverified"), std::string::npos);  // the ARW is verified
    EXPECT_EQ(preset.figures.gyro_arw_deg_per_sqrt_h, reference_tables::cell_figures(row->second[1]).at(0));
    const bool bias_verified = row->second[2].find("unverified") == std::string::npos;
    EXPECT_EQ(preset.figures.gyro_bias_instability_deg_per_h,
              bias_verified ? reference_tables::cell_figures(row->second[2]).at(0) : 0.0);
    EXPECT_NE(preset.source.find("imu_datasheet_figures.csv"), std::string::npos);
  }
  const auto figures = [](std::string_view id) { return config::find_preset(imu_presets(), id)->figures; };
  EXPECT_NEAR(figures("honeywell_hg1700").accel_noise_density, 3.302e-4, 1e-18);  // 0.065 ft/s/sqrt(h)
  EXPECT_NEAR(figures("honeywell_hg1700").accel_bias_instability_mps2, 9.80665e-3, 1e-18);
  EXPECT_EQ(figures("honeywell_hg9900").accel_noise_density, 0.0);  // "none listed"
  EXPECT_NEAR(figures("honeywell_hg9900").accel_bias_instability_mps2, 2.4516625e-4, 1e-19);
  EXPECT_NEAR(figures("safran_primus_200").accel_noise_density, 5.88399e-4, 1e-18);
  EXPECT_NEAR(figures("sensonor_stim300").accel_noise_density, 1e-3, 1e-18);
  EXPECT_NEAR(figures("sensonor_stim300").accel_bias_instability_mps2, 4.903325e-4, 1e-18);
  EXPECT_EQ(figures("sensonor_stim300").gyro_misalignment_rad, 1e-3);
  // Rows marked unverified are not presets.
  EXPECT_EQ(config::find_preset(imu_presets(), "kvh_1750"), nullptr);
  EXPECT_EQ(config::find_preset(imu_presets(), "ixblue_phins"), nullptr);
}

TEST(ImuSensorTest, PresetAsTriadParams) {
  const ImuNoiseParams p = imu_noise_params(config::find_preset(imu_presets(), "sensonor_stim300")->figures);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(p.gyro.axes[i].white_noise_density, arw_to_noise_density(0.15));
    EXPECT_EQ(p.gyro.axes[i].gauss_markov, bias_instability_to_gauss_markov_bank(deg_per_h_to_rad_per_s(0.5), 1.0, 1e5));
    EXPECT_EQ(p.accel.axes[i].white_noise_density, vrw_to_noise_density(0.06));
    EXPECT_EQ(p.accel.axes[i].gauss_markov.size(), 8u);
  }
  EXPECT_EQ(p.gyro.misalignment_sigma, 1e-3);
  EXPECT_EQ(p.accel.max, 10.0 * kStandardGravity);
  EXPECT_EQ(p.accel.min, -10.0 * kStandardGravity);
  const ImuNoiseParams hg = imu_noise_params(config::find_preset(imu_presets(), "honeywell_hg1700")->figures);
  EXPECT_DOUBLE_EQ(hg.gyro.scale_factor_sigma, 150e-6);
  EXPECT_DOUBLE_EQ(hg.accel.scale_factor_sigma, 300e-6);
  EXPECT_TRUE(std::isinf(hg.accel.max));
  for (const config::Preset<ImuDatasheet>& preset : imu_presets()) {
    const ImuNoiseParams q = imu_noise_params(preset.figures);
    EXPECT_NO_THROW(make_noise_state(q.gyro, 1)) << preset.id;
    EXPECT_NO_THROW(make_noise_state(q.accel, 1)) << preset.id;
  }
}

}  // namespace
}  // namespace hadal::sensors
