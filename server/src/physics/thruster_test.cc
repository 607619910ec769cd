#include "hadal/physics/thruster.h"

#include <gtest/gtest.h>

#include <cmath>
#include <variant>

#include "hadal/physics/test_models.h"

namespace hadal::physics {
namespace {

constexpr double kRho = 1025.0;
constexpr double kDt = 0.002;

ThrusterActuator::Spec make_spec(double tau) {
  ThrusterActuator::Spec spec = std::get<ThrusterActuator::Spec>(
      testing::simple_thruster("main", Eigen::Vector3d(-0.5, 0.0, 0.1), Eigen::Vector3d::UnitX()).kind);
  spec.rotor_time_constant_s = tau;
  return spec;
}

// Runs `steps` rotor updates from rest with the setpoint held.
double spin_up(const Thruster& thruster, double setpoint, int steps) {
  double n = 0.0;
  for (int k = 0; k < steps; ++k) n = thruster.next_rotor_speed(n, setpoint);
  return n;
}

TEST(ThrusterTest, RotorReachesOneMinusInverseEAfterOneTimeConstant) {
  // Exact discretisation: after N steps with N dt = tau, n = n_cmd (1 - (e^{-dt/tau})^N) =
  // n_cmd (1 - e^-1). The only error is round-off in dt/tau and the N products: ~N eps = 2e-14.
  const double tau = 0.2;
  const Thruster thruster(make_spec(tau), Eigen::Isometry3d::Identity(), kRho, kDt);
  const int steps = static_cast<int>(std::lround(tau / kDt));
  const double n_cmd = 0.8 * 50.0;
  EXPECT_NEAR(spin_up(thruster, 0.8, steps), n_cmd * (1.0 - std::exp(-1.0)), 1e-12 * n_cmd);
}

TEST(ThrusterTest, ZeroTimeConstantFollowsImmediately) {
  const Thruster thruster(make_spec(0.0), Eigen::Isometry3d::Identity(), kRho, kDt);
  EXPECT_EQ(thruster.next_rotor_speed(12.0, -0.5), -25.0);
  EXPECT_EQ(thruster.next_rotor_speed(0.0, 1.0), 50.0);
}

TEST(ThrusterTest, SteadyStateThrustIsKtRhoD4NSquared) {
  // After 50 tau the lag is e^-50 ~ 2e-22 of n_cmd: below double resolution, so n = n_cmd up to
  // round-off and T = K_T rho D^4 n|n| to 1e-12 relative.
  const double tau = 0.05;
  const ThrusterActuator::Spec spec = make_spec(tau);
  const Thruster thruster(spec, Eigen::Isometry3d::Identity(), kRho, kDt);
  for (double setpoint : {0.6, -0.6}) {
    const double n = spin_up(thruster, setpoint, static_cast<int>(50 * tau / kDt));
    const double n_cmd = setpoint * spec.max_rotor_speed_rev_s;
    EXPECT_NEAR(n, n_cmd, 1e-12 * std::abs(n_cmd));
    const double expected = spec.thrust_coefficient * kRho * std::pow(spec.propeller_diameter, 4) *
                            n_cmd * std::abs(n_cmd);
    const double surface_z = 10.0;  // the vehicle at the origin is 10 m deep
    const ThrusterWrench w = thruster.wrench(n, Eigen::Isometry3d::Identity(), surface_z);
    EXPECT_NEAR(w.thrust, expected, 1e-12 * std::abs(expected));
    EXPECT_TRUE(w.f_W.isApprox(expected * Eigen::Vector3d::UnitX(), 1e-12));
  }
}

TEST(ThrusterTest, ReactionTorqueOpposesRightHandedRotation) {
  // Q = -handedness K_Q rho D^5 n|n| about the axis; the vehicle is yawed 90 deg and the link
  // pitched, so the axis in W is R_WB R_BL x. Same-expression arithmetic: 1e-12 relative.
  Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();
  X_BL.translation() = Eigen::Vector3d(0.0, 0.3, 0.0);
  X_BL.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.translation() = Eigen::Vector3d(10.0, -4.0, -20.0);
  X_WB.linear() = Eigen::AngleAxisd(EIGEN_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const double n = 30.0;
  for (int handedness : {1, -1}) {
    ThrusterActuator::Spec spec = make_spec(0.0);
    spec.handedness = handedness;
    const Thruster thruster(spec, X_BL, kRho, kDt);
    const double magnitude =
        spec.torque_coefficient * kRho * std::pow(spec.propeller_diameter, 5) * n * n;
    const ThrusterWrench w = thruster.wrench(n, X_WB, 0.0);
    EXPECT_NEAR(w.torque, -handedness * magnitude, 1e-12 * magnitude);
    const Eigen::Vector3d axis_W = X_WB.linear() * X_BL.linear() * Eigen::Vector3d::UnitX();
    EXPECT_TRUE(w.tau_W.isApprox(-handedness * magnitude * axis_W, 1e-12));
    EXPECT_TRUE(w.p_WT.isApprox(X_WB * (X_BL * spec.p_LT), 1e-12));
    // Reversing the rotor reverses both thrust and torque.
    EXPECT_NEAR(thruster.wrench(-n, X_WB, 0.0).torque, handedness * magnitude, 1e-12 * magnitude);
  }
}

TEST(ThrusterTest, NoThrustInAir) {
  const Thruster thruster(make_spec(0.0), Eigen::Isometry3d::Identity(), kRho, kDt);
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.translation() = Eigen::Vector3d(0.0, 0.0, -0.05);  // propeller at z = +0.05, above z = 0
  const ThrusterWrench w = thruster.wrench(40.0, X_WB, 0.0);
  EXPECT_EQ(w.thrust, 0.0);
  EXPECT_EQ(w.torque, 0.0);
  EXPECT_TRUE(w.f_W.isZero(0.0));
  EXPECT_TRUE(w.tau_W.isZero(0.0));
  // The rotor itself keeps following the command.
  EXPECT_EQ(thruster.next_rotor_speed(0.0, 1.0), 50.0);
  // Just below the surface it pushes.
  X_WB.translation().z() = -0.2;
  EXPECT_GT(thruster.wrench(40.0, X_WB, 0.0).thrust, 0.0);
}

// The actuator kind: its control is checked with the reason a client gets, held as the setpoint (a
// last-line guard clamps it), actuated through the rotor lag, and its wrench added about the centre of
// mass: f = T axis, tau = Q axis + (p_WT - p_WBcm) x f (closed form with the vehicle yawed, and the
// centre of mass off B's origin across the thrust axis, so that a moment about the origin would differ).
TEST(ThrusterTest, ActuatorKindChecksHoldsActuatesAndAddsItsWrench) {
  const ThrusterActuator::Spec spec = make_spec(0.0);
  const double good = 0.5, nan = std::nan(""), big = 1.5, neg_inf = -INFINITY;
  EXPECT_EQ(ThrusterActuator::check(spec, &good, 2), "");
  EXPECT_EQ(ThrusterActuator::check(spec, &nan, 2), "setpoint[2] is NaN");
  EXPECT_EQ(ThrusterActuator::check(spec, &big, 0), "setpoint[0] = 1.5 is outside [-1, 1]");
  EXPECT_EQ(ThrusterActuator::check(spec, &neg_inf, 1), "setpoint[1] is -inf");
  ThrusterActuator::State state;
  ThrusterActuator::command(state, &big);
  EXPECT_EQ(state.setpoint, 1.0);
  ThrusterActuator::command(state, &nan);
  EXPECT_EQ(state.setpoint, 0.0);
  ThrusterActuator::command(state, &good);
  const Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();
  const Thruster runtime = ThrusterActuator::prepare(spec, ActuatorSetup{X_BL, kRho, kDt});
  ThrusterActuator::actuate(runtime, state);
  EXPECT_EQ(state.rotor_speed_rev_s, 25.0);  // tau = 0: n = 0.5 x 50 rev/s at once

  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.linear() = Eigen::AngleAxisd(EIGEN_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X_WB.translation() = Eigen::Vector3d(1.0, 2.0, -30.0);
  const Eigen::Vector3d p_WBcm = X_WB * Eigen::Vector3d(0.1, 0.05, -0.2);
  StepWrench out;
  ThrusterActuator::add_wrench(runtime, state, ActuatorForceInput{X_WB, p_WBcm, 0.0}, out);
  const double T = spec.thrust_coefficient * kRho * std::pow(spec.propeller_diameter, 4) * 625.0;
  const double Q = -spec.torque_coefficient * kRho * std::pow(spec.propeller_diameter, 5) * 625.0;
  EXPECT_NEAR(state.thrust_N, T, 1e-12 * T);
  EXPECT_NEAR(state.torque_Nm, Q, 1e-12 * std::abs(Q));
  const Eigen::Vector3d axis_W(0.0, 1.0, 0.0);  // body x yawed 90 deg
  // p_WT - p_WBcm = R_WB ((-0.5, 0, 0.1) - (0.1, 0.05, -0.2)) = R_WB (-0.6, -0.05, 0.3) = (0.05, -0.6, 0.3),
  // so tau = Q y + r x T y = (-0.3 T, Q, 0.05 T) (about B's origin it would be (-0.1 T, Q, 0)).
  EXPECT_NEAR((out.f_W - T * axis_W).norm(), 0.0, 1e-12 * T);
  EXPECT_NEAR((out.tau_W - Eigen::Vector3d(-0.3 * T, Q, 0.05 * T)).norm(), 0.0, 1e-12 * T);

  ThrusterActuator::stop(state);
  EXPECT_EQ(state.rotor_speed_rev_s, 0.0);
  EXPECT_EQ(state.thrust_N, 0.0);
  EXPECT_TRUE(ThrusterActuator::is_finite(state));
  state.rotor_speed_rev_s = nan;
  EXPECT_FALSE(ThrusterActuator::is_finite(state));
}

}  // namespace
}  // namespace hadal::physics
