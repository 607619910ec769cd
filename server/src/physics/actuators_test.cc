// A vehicle's actuators as a set (physics/actuators.h): the control vector's checks and their reasons,
// commands padded with zeros, actuation, the wrenches summed in actuator order, and the fault policy.
#include "hadal/physics/actuators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hadal/physics/test_models.h"

namespace hadal::physics {
namespace {

VehicleSpec three_thrusters() {
  VehicleSpec vehicle;
  vehicle.name = "auv";
  vehicle.links = {testing::box_link("hull", 10.0, Eigen::Vector3d(1, 0.4, 0.4), 0.0)};
  vehicle.actuators = {testing::simple_thruster("main", Eigen::Vector3d(-0.6, 0, 0), Eigen::Vector3d::UnitX()),
                       testing::simple_thruster("heave", Eigen::Vector3d(0.3, 0, 0), Eigen::Vector3d::UnitZ()),
                       testing::simple_thruster("sway", Eigen::Vector3d(0.3, 0, 0), Eigen::Vector3d::UnitY())};
  return vehicle;
}

TEST(VehicleActuatorsTest, ChecksTheWholeControlVector) {
  const VehicleSpec vehicle = three_thrusters();
  const WorldSpec world;
  const VehicleActuators actuators(vehicle, world);
  EXPECT_EQ(actuators.num_controls(), 3u);
  EXPECT_EQ(actuators.check({0.1, 0.2, 0.3}), "");
  EXPECT_EQ(actuators.check({0.1, 0.2}), "expected 3 setpoints (main, heave, sway), got 2");
  EXPECT_EQ(actuators.check({0.1, std::nan(""), 2.0}), "setpoint[1] is NaN");  // the first problem
  EXPECT_EQ(actuators.check({0.1, 0.0, 2.0}), "setpoint[2] = 2 is outside [-1, 1]");
  VehicleSpec none = vehicle;
  none.actuators.clear();
  EXPECT_EQ(VehicleActuators(none, world).check({0.5}), "expected 0 setpoints, got 1");
}

// Commands shorter than the vector leave the rest at 0; actuation follows each rotor's lag (tau = 0 in
// the test thrusters: at once); the wrenches add up about the centre of mass in actuator order.
TEST(VehicleActuatorsTest, CommandActuateAndSumTheWrenches) {
  const VehicleSpec vehicle = three_thrusters();
  WorldSpec world;
  world.water.density = 1000.0;
  const VehicleActuators actuators(vehicle, world);
  std::vector<ActuatorKindState> states = VehicleActuators::initial_states(vehicle);
  ASSERT_EQ(states.size(), 3u);
  actuators.command(states, {0.5, -0.4});
  actuators.actuate(states);
  EXPECT_EQ(std::get<ThrusterActuator::State>(states[0]).rotor_speed_rev_s, 25.0);
  EXPECT_EQ(std::get<ThrusterActuator::State>(states[1]).rotor_speed_rev_s, -20.0);
  EXPECT_EQ(std::get<ThrusterActuator::State>(states[2]).setpoint, 0.0);
  RigidBodyState body;
  body.X_WB.translation() = Eigen::Vector3d(0, 0, -10);
  const Eigen::Vector3d p_WBcm = body.X_WB.translation();
  StepWrench out;
  ActuatorForces forces(actuators);
  forces.add(ForceInput{0.0, body, p_WBcm, Eigen::Vector3d::Zero(), states}, out);
  const double gain = 0.3 * 1000.0 * std::pow(0.2, 4);  // K_T rho D^4
  const double T_main = gain * 625.0, T_heave = -gain * 400.0;
  EXPECT_NEAR(out.f_W.x(), T_main, 1e-12 * T_main);
  EXPECT_NEAR(out.f_W.z(), T_heave, 1e-12 * T_main);
  // Heave thrust 0.3 m ahead of the centre of mass pitches: r x f = (0.3, 0, 0) x (0, 0, T) = (0, -0.3 T, 0);
  // the propellers' reaction torques act about their axes.
  const double Q_main = -0.05 * 1000.0 * std::pow(0.2, 5) * 625.0;
  const double Q_heave = 0.05 * 1000.0 * std::pow(0.2, 5) * 400.0;
  EXPECT_NEAR(out.tau_W.x(), Q_main, 1e-12 * std::abs(Q_main));
  EXPECT_NEAR(out.tau_W.y(), -0.3 * T_heave, 1e-12 * T_main);
  EXPECT_NEAR(out.tau_W.z(), Q_heave, 1e-12 * std::abs(Q_main));
  EXPECT_EQ(std::get<ThrusterActuator::State>(states[0]).thrust_N, out.f_W.x());

  EXPECT_TRUE(VehicleActuators::is_finite(states));
  std::get<ThrusterActuator::State>(states[2]).rotor_speed_rev_s = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(VehicleActuators::is_finite(states));
  VehicleActuators::stop(states);
  EXPECT_TRUE(VehicleActuators::is_finite(states));
  for (const ActuatorKindState& state : states) EXPECT_EQ(std::get<ThrusterActuator::State>(state).thrust_N, 0.0);
}

}  // namespace
}  // namespace hadal::physics
