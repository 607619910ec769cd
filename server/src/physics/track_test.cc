#include "hadal/physics/track.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hadal/core/units.h"

namespace hadal::physics {
namespace {

TrackActuator::Spec drive_spec() {
  TrackActuator::Spec spec;
  spec.sprocket_radius = 0.2;
  spec.max_speed_rad_s = 10.0;  // 2 m/s of belt at full setpoint
  spec.stall_torque = 400.0;
  spec.torque_constant = 2.0;
  spec.drive_inertia = 0.5;
  spec.speed_time_constant_s = 0.2;
  return spec;
}

TrackDrive prepared(const TrackActuator::Spec& spec, double dt = 0.002) {
  const Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();
  return TrackActuator::prepare(spec, ActuatorSetup{X_BL, 1025.0, dt, 3});
}

// Unloaded, the speed loop is first order: V_k = V_cmd (1 - (1 - dt / tau_s)^k) (explicit Euler, exact
// for the discrete loop up to rounding).
TEST(Track, UnloadedBeltFollowsTheCommandWithItsTimeConstant) {
  const TrackDrive drive = prepared(drive_spec());
  EXPECT_EQ(drive.link, 3u);
  TrackActuator::State state;
  const double setpoint = 0.5;
  TrackActuator::command(state, &setpoint);
  const double V_cmd = 0.5 * 10.0 * 0.2;
  for (int k = 1; k <= 500; ++k) {
    TrackActuator::actuate(drive, state);
    ASSERT_NEAR(state.belt_speed, V_cmd * (1.0 - std::pow(1.0 - 0.002 / 0.2, k)), 1e-12) << k;
  }
  EXPECT_NEAR(state.sprocket_speed, state.belt_speed / 0.2, 1e-15);
  EXPECT_EQ(TrackActuator::belt_velocity_B(drive, state), Eigen::Vector3d(-state.belt_speed, 0.0, 0.0));
}

// A load beyond what the motor gives slows the belt to where the torque-speed line meets it:
// F r = tau_stall (1 - omega / omega_0), i.e. omega = omega_0 (1 - F r / tau_stall); current = tau / k_t.
TEST(Track, OverloadedBeltSettlesOnTheMotorsTorqueSpeedLine) {
  const TrackDrive drive = prepared(drive_spec());
  TrackActuator::State state;
  const double setpoint = 1.0;
  TrackActuator::command(state, &setpoint);
  const double F = 1200.0;  // F r = 240 N m: 60 % of stall
  for (int k = 0; k < 20000; ++k) {
    TrackActuator::take_belt_force(drive, state, Eigen::Vector3d(F, 0.0, 0.0));
    TrackActuator::actuate(drive, state);
  }
  EXPECT_NEAR(state.sprocket_speed, 10.0 * (1.0 - 240.0 / 400.0), 1e-9);
  EXPECT_NEAR(state.motor_torque_Nm, 240.0, 1e-9);
  EXPECT_NEAR(state.current_A, 120.0, 1e-9);
  EXPECT_NEAR(state.power_W, 240.0 * 4.0, 1e-6);
  // Beyond stall the belt is pushed back.
  for (int k = 0; k < 2000; ++k) {
    TrackActuator::take_belt_force(drive, state, Eigen::Vector3d(2500.0, 0.0, 0.0));
    TrackActuator::actuate(drive, state);
  }
  EXPECT_LT(state.belt_speed, 0.0);
}

TEST(Track, ChecksItsSetpoint) {
  const TrackActuator::Spec spec = drive_spec();
  const double nan = NAN, big = 1.5, ok = -1.0;
  EXPECT_EQ(TrackActuator::check(spec, &nan, 2), "setpoint[2] is NaN");
  EXPECT_EQ(TrackActuator::check(spec, &big, 0), "setpoint[0] = 1.5 is outside [-1, 1]");
  EXPECT_EQ(TrackActuator::check(spec, &ok, 0), "");
}

}  // namespace
}  // namespace hadal::physics
