// Simulation tests of articulated vehicles (physics/articulation.h, physics/articulated_dynamics.h): a
// link on a joint in water against closed forms (the period from the wet weight and the added inertia,
// the effort that holds it), joint limits, momentum of a free-floating vehicle swinging its arm, restored
// states, and refused commands.
#include "hadal/core/simulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hadal/geometry/mesh_properties.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/physics/articulation.h"
#include "hadal/physics/mass_properties.h"
#include "hadal/physics/ocean.h"
#include "hadal/physics/test_models.h"
#include "hadal/render/camera_rays.h"
#include "hadal/render/lens.h"
#include "hadal/sensors/camera_sensor.h"
#include "hadal/sensors/force_torque_sensor.h"

namespace hadal {
namespace {

namespace testing = physics::testing;

constexpr double kPi = 3.14159265358979323846;

// A frame fixed in the water (a static vehicle's base link, without geometry) at 50 m, and an arm: a
// sphere of radius r and mass m on a revolute joint about y at the frame's origin, its centre l from the
// joint along `arm_L` (down: a pendulum; along x: horizontal at q = 0). Only buoyancy (pressure) and the
// sphere's added mass act (drag, skin friction, lift off).
struct Pendulum {
  double r = 0.1, m = 8.0, l = 0.5, depth = 50.0;
  Eigen::Vector3d arm_L = Eigen::Vector3d(0, 0, -1);
  double lower = -std::numeric_limits<double>::infinity(), upper = std::numeric_limits<double>::infinity();
  double initial = 0.0;

  Model model() const {
    CollisionShape sphere;
    sphere.type = CollisionShapeType::kSphere;
    sphere.radius = r;
    sphere.X_LG.translation() = l * arm_L;
    VehicleSpec vehicle = testing::surface_vehicle(sphere, 1.0, Eigen::Matrix3d::Identity(), testing::drag_only(0.0),
                                                   Eigen::Vector3d(0, 0, -depth));
    vehicle.name = "frame";
    vehicle.is_static = true;
    LinkSpec arm = vehicle.links[0];
    arm.name = "arm";
    arm.mass = m;
    arm.I_LLcm_L = physics::solid_sphere_inertia(m, r);
    arm.p_LLcm = l * arm_L;
    arm.joint.type = JointType::kRevolute;
    arm.joint.axis_L = Eigen::Vector3d::UnitY();
    arm.joint.lower = lower;
    arm.joint.upper = upper;
    arm.joint.initial = initial;
    LinkSpec& frame = vehicle.links[0];
    frame.name = "frame";
    frame.mass = 10.0;
    frame.collisions.clear();
    vehicle.links.push_back(arm);
    Model model = testing::water_model({vehicle});
    model.world.seabed.z = -500.0;
    return model;
  }
  // The tessellated sphere's volume (the surface model's buoyancy is exactly rho g of it).
  double volume() const {
    CollisionShape sphere;
    sphere.type = CollisionShapeType::kSphere;
    sphere.radius = r;
    return geometry::compute_mesh_properties(geometry::tessellate(sphere)).volume;
  }
  // The wet weight's torque about the joint with the arm horizontal [N m], in `sim`'s water at the depth.
  double gravity_torque(const Simulation& sim) const {
    return (m - sim.ocean().density(depth) * volume()) * 9.80665 * l;
  }
};

// A position controller `name` on the one joint, with gains kp and kd.
physics::JointControllerSpec position_controller(const std::string& name, double kp, double kd) {
  physics::JointControllerSpec position;
  position.name = name;
  position.mode = physics::JointCommandMode::kPosition;
  position.joints = {0};
  position.kp = {kp};
  position.kd = {kd};
  return position;
}

double joint_q(const Simulation& sim) { return sim.state().vehicles[0].joint_positions.at(0); }

// Where a position controller of stiffness kp holds the horizontal arm commanded to `target`: at rest
// kp (q* - q) balances the wet weight's torque tau_g cos q, so q = q* + tau_g cos(q) / kp (by iteration).
double held_at(double target, double tau_g, double kp) {
  double q = target;
  for (int k = 0; k < 20; ++k) q = target + tau_g * std::cos(q) / kp;
  return q;
}

// The pendulum's arm horizontal (along x at q = 0), within +-1 rad, and its position controller
// "arm_position" (kp 2000, kd 200).
Model held_arm(Pendulum& p) {
  p.arm_L = Eigen::Vector3d::UnitX();
  p.lower = -1.0;
  p.upper = 1.0;
  Model model = p.model();
  model.vehicles[0].joint_controllers.push_back(position_controller("arm_position", 2000.0, 200.0));
  return model;
}

// A 1 m box of 80 kg with a two-link arm (a shoulder turning about a tilted axis, a forearm about y) at
// height z (in the water below 0).
VehicleSpec arm_vehicle(double z) {
  VehicleSpec vehicle = testing::surface_vehicle(testing::box_shape({1.0, 0.6, 0.4}), 80.0,
                                                 physics::solid_box_inertia(80.0, {1.0, 0.6, 0.4}),
                                                 testing::drag_only(0.0), Eigen::Vector3d(0, 0, z));
  vehicle.fluid.added_mass.model = AddedMassModel::kNone;
  LinkSpec shoulder = testing::box_link("shoulder", 6.0, {0.5, 0.1, 0.1}, 0.0, testing::at({0.6, 0.1, 0.0}));
  shoulder.p_LLcm = Eigen::Vector3d(0.25, 0, 0);
  shoulder.collisions[0].X_LG.translation() = shoulder.p_LLcm;
  shoulder.joint.type = JointType::kRevolute;
  shoulder.joint.axis_L = Eigen::Vector3d(0, 0.3, 1).normalized();
  LinkSpec fore = testing::box_link("fore", 3.0, {0.4, 0.08, 0.08}, 0.0, testing::at({0.5, 0.0, 0.0}));
  fore.parent = 1;
  fore.X_BL = shoulder.X_BL * fore.X_BL;
  fore.p_LLcm = Eigen::Vector3d(0.2, 0, 0);
  fore.collisions[0].X_LG.translation() = fore.p_LLcm;
  fore.joint.type = JointType::kRevolute;
  fore.joint.axis_L = Eigen::Vector3d::UnitY();
  vehicle.links.push_back(shoulder);
  vehicle.links.push_back(fore);
  return vehicle;
}

// Small swings of the pendulum in water: T = 2 pi sqrt((I_cm + m l^2 + m_A l^2) / ((m - rho V) g l)), with
// m_A = kappa(50 m) rho V / 2 the sphere's added mass (Lamb; the fitted ellipsoid of the tessellated sphere)
// and V the tessellated volume. Released at 2 degrees, the period over 5 swings from interpolated zero
// crossings matches within 1 % (the bound; the amplitude's lengthening theta0^2 / 16 = 8e-5 and
// the step's (omega dt)^2 ~ 3e-5 are far below). Without the added inertia the period is 11 % shorter.
TEST(SimulationArticulatedTest, PendulumInWaterSwingsWithItsWetWeightAndAddedInertia) {
  Pendulum p;
  p.initial = 2.0 * kPi / 180.0;
  Simulation sim(p.model());
  const physics::Ocean& ocean = sim.ocean();
  const double rho = ocean.density(p.depth + p.l);
  const double V = p.volume();
  const double m_A = ocean.kappa(p.depth + p.l) * 0.5 * rho * V;
  const double g = 9.80665;
  const double I = 0.4 * p.m * p.r * p.r + (p.m + m_A) * p.l * p.l;
  const double expected = 2.0 * kPi * std::sqrt(I / ((p.m - rho * V) * g * p.l));
  std::vector<double> crossings;
  const double dt = sim.model().world.step_size();
  double q_prev = joint_q(sim);
  while (crossings.size() < 6 && sim.time() < 20.0) {
    sim.step();
    const double q = joint_q(sim);
    if (q_prev < 0.0 && q >= 0.0) crossings.push_back(sim.time() - dt * q / (q - q_prev));
    q_prev = q;
  }
  ASSERT_EQ(crossings.size(), 6u);
  const double period = (crossings.back() - crossings.front()) / 5.0;
  EXPECT_NEAR(period / expected, 1.0, 0.01) << "period " << period << " s, closed form " << expected << " s";
}

// The effort that holds the horizontal arm still is its wet weight times its lever arm,
// tau = -(m - rho V) g l about +y (gravity turns +x towards -z: positive q). With it the arm stays within
// 1e-5 rad for 0.5 s; 0.5 % more or less effort turns it by > 1e-3 rad either way (0.5 % of 18.7 N m over
// the inertia 2.55 kg m^2: 4.6e-3 rad in 0.5 s).
TEST(SimulationArticulatedTest, TheEffortHoldingAHorizontalArmIsItsWetWeightTimesItsLeverArm) {
  Pendulum p;
  p.arm_L = Eigen::Vector3d::UnitX();
  const double rho_V = [&] {
    Simulation sim(p.model());
    return sim.ocean().density(p.depth) * p.volume();
  }();
  const double hold = -(p.m - rho_V) * 9.80665 * p.l;
  const auto q_after = [&](double effort) {
    Simulation sim(p.model());
    EXPECT_EQ(sim.set_joint_efforts(0, {effort}), "");
    for (int k = 0; k < 250; ++k) sim.step();
    return joint_q(sim);
  };
  EXPECT_LT(std::abs(q_after(hold)), 1e-5);
  EXPECT_LT(q_after(hold * 1.005), -1e-3);
  EXPECT_GT(q_after(hold * 0.995), 1e-3);
}

// Coulomb friction at the joint: the horizontal arm's wet weight turns it with 18.7 N m. Friction of
// 25 N m holds it (within 1e-6 rad for 0.5 s); friction of 10 N m lets it go with the closed-form
// acceleration (tau_g - F) / (I_cm + (m + m_A) l^2): q(0.2 s) = alpha t^2 / 2 within 2 % (the gravity
// torque falls with cos q, 3e-4 at 0.03 rad; one step's start-up, 1 %; measured 0.5 %). The friction is a
// Bullet constraint, whose impulse sees the rigid inertia only: without the constraint force fed back into
// the added-mass solve (VehicleState::constraint_force) q is 27 % short.
TEST(SimulationArticulatedTest, JointFrictionHoldsBelowItsTorqueAndOpposesMotionAboveIt) {
  Pendulum p;
  p.arm_L = Eigen::Vector3d::UnitX();
  const auto q_after = [&](double friction, int steps, double* alpha) {
    Model model = p.model();
    model.vehicles[0].links[1].joint.friction = friction;
    Simulation sim(std::move(model));
    const physics::Ocean& ocean = sim.ocean();
    const double rho = ocean.density(p.depth);
    const double m_A = ocean.kappa(p.depth) * 0.5 * rho * p.volume();
    const double tau_g = (p.m - rho * p.volume()) * 9.80665 * p.l;
    *alpha = (tau_g - friction) / (0.4 * p.m * p.r * p.r + (p.m + m_A) * p.l * p.l);
    for (int k = 0; k < steps; ++k) sim.step();
    return joint_q(sim);
  };
  double alpha = 0.0;
  EXPECT_LT(std::abs(q_after(25.0, 250, &alpha)), 1e-6);
  const double q = q_after(10.0, 100, &alpha);
  EXPECT_NEAR(q / (0.5 * alpha * 0.2 * 0.2), 1.0, 0.02) << "q " << q;
}

// A position controller (kp, kd) holds the horizontal arm at its target less the gravity sag: at rest
// kp (q* - q) balances the wet weight's torque tau_g cos q, so q = q* + tau_g cos(q) / kp (solved by
// iteration); after 4 s (the slow mode's time constant kd / kp = 0.1 s) within 1e-6 rad. An effort
// controller's command is held within the joint's effort_limit, and bad commands are refused by name.
TEST(SimulationArticulatedTest, JointControllersHoldTheirCommandsWithinTheJointsLimits) {
  Pendulum p;
  Model model = held_arm(p);
  const physics::JointControllerSpec position = model.vehicles[0].joint_controllers[0];
  Simulation sim(std::move(model));
  const double tau_g = p.gravity_torque(sim);
  EXPECT_EQ(sim.state().vehicles[0].joint_targets, std::vector<double>{0.0});  // holds where it starts
  ASSERT_EQ(sim.set_joint_commands(0, "arm_position", {0.3}), "");
  for (int k = 0; k < 2000; ++k) sim.step();
  const double expected = held_at(0.3, tau_g, position.kp[0]);
  EXPECT_NEAR(joint_q(sim), expected, 1e-6) << "sag " << expected - 0.3;
  EXPECT_NEAR(sim.state().vehicles[0].joint_efforts[0], -tau_g * std::cos(expected), 1e-3);

  EXPECT_NE(sim.set_joint_commands(0, "arm_position", {1.5}).find("outside its limits [-1, 1]"), std::string::npos);
  EXPECT_NE(sim.set_joint_commands(0, "arm_position", {0.1, 0.2}).find("2 values for 1 joints"), std::string::npos);
  EXPECT_NE(sim.set_joint_commands(0, "arm_position", {std::nan("")}).find("not finite"), std::string::npos);
  EXPECT_NE(sim.set_joint_commands(0, "gripper", {0.0}).find("no joint controller 'gripper' (it has arm_position)"),
            std::string::npos);
  EXPECT_NE(sim.set_joint_efforts(0, {1.0}).find("commands its joints' position"), std::string::npos);
  EXPECT_EQ(sim.state().vehicles[0].joint_targets, std::vector<double>{0.3});

  Model limited = p.model();
  limited.vehicles[0].links[1].joint.effort_limit = 5.0;
  Simulation weak(std::move(limited));
  ASSERT_EQ(weak.set_joint_efforts(0, {-50.0}), "");
  weak.step();
  EXPECT_EQ(weak.state().vehicles[0].joint_efforts, std::vector<double>{-5.0});
  EXPECT_EQ(weak.state().vehicles[0].joint_targets, std::vector<double>{-50.0});
}

// A gripper (physics/joint_servo.h) moves its fingers together: two horizontal arms (the pendulum's, 0.5 m
// apart in y), the second on a joint about -y and so with multiplier -1: the command [0.3] holds both at
// the same physical angle, q1 = held_at(0.3) and q2 = -q1 (the position law's gravity sag, as a position
// group's; within 1e-6 rad after 4 s). With [0.3, max_effort] and max_effort half the wet weight's torque,
// neither finger can hold its arm up: each sags onto its limit (q1 = 1, q2 = -1) pushing back with exactly
// max_effort (its joint effort, to the bit), and a plain [0.3] lifts them back. Bad commands are refused
// by name and change nothing.
TEST(SimulationArticulatedTest, AGripperMovesItsFingersTogetherWithinItsMaxEffort) {
  Pendulum p;
  Model model = held_arm(p);
  VehicleSpec& vehicle = model.vehicles[0];
  LinkSpec mirrored = vehicle.links[1];
  mirrored.name = "arm_mirrored";
  mirrored.X_BL.translation() = Eigen::Vector3d(0.0, 0.5, 0.0);
  mirrored.joint.axis_L = -Eigen::Vector3d::UnitY();
  vehicle.links.push_back(mirrored);
  physics::JointControllerSpec gripper = position_controller("gripper", 2000.0, 200.0);
  gripper.mode = physics::JointCommandMode::kGripper;
  gripper.joints = {0, 1};
  gripper.kp = {2000.0, 2000.0};
  gripper.kd = {200.0, 200.0};
  gripper.multipliers = {1.0, -1.0};
  vehicle.joint_controllers = {gripper};
  Simulation sim(std::move(model));
  const double tau_g = p.gravity_torque(sim);
  const auto q = [&](std::size_t j) { return sim.state().vehicles[0].joint_positions.at(j); };
  ASSERT_EQ(sim.set_joint_commands(0, "gripper", {0.3}), "");
  for (int k = 0; k < 2000; ++k) sim.step();
  const double held = held_at(0.3, tau_g, 2000.0);
  EXPECT_NEAR(q(0), held, 1e-6);
  EXPECT_NEAR(q(1), -held, 1e-6);

  const double max_effort = 0.5 * tau_g;
  ASSERT_EQ(sim.set_joint_commands(0, "gripper", {0.3, max_effort}), "");
  for (int k = 0; k < 2000; ++k) sim.step();
  EXPECT_NEAR(q(0), 1.0, 1e-3);
  EXPECT_NEAR(q(1), -1.0, 1e-3);
  EXPECT_EQ(std::abs(sim.state().vehicles[0].joint_efforts[0]), max_effort);
  EXPECT_EQ(std::abs(sim.state().vehicles[0].joint_efforts[1]), max_effort);

  ASSERT_EQ(sim.set_joint_commands(0, "gripper", {0.3}), "");
  for (int k = 0; k < 2000; ++k) sim.step();
  EXPECT_NEAR(q(0), held, 1e-6);

  const auto refused = [&](const std::vector<double>& values, const std::string& why) {
    const std::string reason = sim.set_joint_commands(0, "gripper", values);
    EXPECT_NE(reason.find(why), std::string::npos) << reason;
  };
  refused({}, "0 values: a gripper takes [position] or [position, max_effort]");
  refused({0.1, 1.0, 2.0}, "3 values");
  refused({std::nan("")}, "the position is not finite");
  refused({1.5}, "position 1.5 puts 'arm' at 1.5, outside its limits [-1, 1]");
  refused({0.1, 0.0}, "max_effort 0 must be finite and > 0");
  refused({0.1, std::numeric_limits<double>::infinity()}, "max_effort inf must be finite and > 0");
  const std::vector<double> targets = sim.state().vehicles[0].joint_targets;
  EXPECT_EQ(targets, (std::vector<double>{0.3, -0.3}));
  EXPECT_NE(sim.set_joint_trajectory(0, "gripper", {}).find("only position groups follow trajectories"),
            std::string::npos);
}

// A position group follows a trajectory (physics/joint_trajectory.h): nothing changes before its start;
// then each step's target is the line from where the joint was at the start to the waypoint, sampled at
// the step's end, and its rate is fed forward, so on the ramp the arm runs at the target less the same
// gravity sag as at rest (the steady ramp needs no torque beyond gravity's). Without the feed-forward it
// would also lag kd / kp times the rate (0.1 s * 0.3 rad/s = 0.03 rad); the bound, 1e-3 rad, is the
// start's transient, decayed over seven time constants kd / kp. After the last waypoint the group holds
// it; a command cancels a trajectory; malformed trajectories are refused by name.
TEST(SimulationArticulatedTest, APositionGroupFollowsATrajectoryWithItsRateFedForward) {
  Pendulum p;
  Model model = held_arm(p);
  const physics::JointControllerSpec position = model.vehicles[0].joint_controllers[0];
  physics::JointControllerSpec velocity = position_controller("arm_velocity", 0.0, 10.0);
  velocity.mode = physics::JointCommandMode::kVelocity;
  Simulation sim(std::move(model));
  const double dt = sim.model().world.step_size();
  const double tau_g = p.gravity_torque(sim);
  const auto sag = [&](double target) { return held_at(target, tau_g, position.kp[0]) - target; };
  // Settled at 0 first.
  for (int k = 0; k < 1000; ++k) sim.step();
  const double q0 = joint_q(sim), t_start = sim.state().time + 0.1, t_end = t_start + 1.0;
  physics::JointTrajectoryCommand command;
  command.start_time = t_start;
  command.joint_names = {"arm"};
  command.points = {{1.0, {0.3}, {}, {}}};
  ASSERT_EQ(sim.set_joint_trajectory(0, "arm_position", command), "");
  while (sim.state().time + dt < t_start) {
    sim.step();
    ASSERT_EQ(sim.state().vehicles[0].joint_targets[0], 0.0);
  }
  const double started_at = sim.state().time, q_started = joint_q(sim);
  const double rate = (0.3 - q_started) / (t_end - started_at);
  double worst = 0.0;
  while (sim.state().time + dt < t_end) {
    sim.step();
    const double t = sim.state().time;  // the end of the step just taken: where its target was sampled
    ASSERT_NEAR(sim.state().vehicles[0].joint_targets[0], q_started + rate * (t - started_at), 1e-12) << t;
    ASSERT_NEAR(sim.state().vehicles[0].joint_target_rates[0], rate, 1e-12) << t;
    if (t > started_at + 0.7) {
      const double target = sim.state().vehicles[0].joint_targets[0];
      worst = std::max(worst, std::abs(joint_q(sim) - target - sag(target)));
    }
  }
  EXPECT_LT(worst, 1e-3) << "q0 " << q0;
  sim.step();
  EXPECT_EQ(sim.state().vehicles[0].joint_targets[0], 0.3);
  EXPECT_EQ(sim.state().vehicles[0].joint_target_rates[0], 0.0);
  EXPECT_EQ(sim.state().vehicles[0].joint_trajectories[0], nullptr);
  for (int k = 0; k < 2000; ++k) sim.step();
  EXPECT_NEAR(joint_q(sim), 0.3 + sag(0.3), 1e-6);

  // A command cancels a trajectory that has not ended.
  command.start_time.reset();
  command.points = {{2.0, {-0.5}, {}, {}}};
  ASSERT_EQ(sim.set_joint_trajectory(0, "arm_position", command), "");
  for (int k = 0; k < 100; ++k) sim.step();  // 0.2 s at -0.4 rad/s
  EXPECT_NEAR(sim.state().vehicles[0].joint_targets[0], 0.3 + sag(0.3) - 0.08, 1e-3);
  ASSERT_EQ(sim.set_joint_commands(0, "arm_position", {0.2}), "");
  for (int k = 0; k < 10; ++k) sim.step();
  EXPECT_EQ(sim.state().vehicles[0].joint_targets[0], 0.2);
  EXPECT_EQ(sim.state().vehicles[0].joint_target_rates[0], 0.0);

  const auto refused = [&](const std::string& controller, physics::JointTrajectoryCommand bad) {
    return sim.set_joint_trajectory(0, controller, bad);
  };
  command.points = {{1.0, {1.5}, {}, {}}};
  EXPECT_EQ(refused("arm_position", command),
            "vehicle 'frame': joint controller 'arm_position': trajectory: points[0].positions: 1.5 for 'arm' is "
            "outside its limits [-1, 1]");
  command.points = {{1.0, {0.5}, {}, {}}, {0.5, {0.5}, {}, {}}};
  EXPECT_EQ(refused("arm_position", command),
            "vehicle 'frame': joint controller 'arm_position': trajectory: points[1].time_from_start: must come "
            "after points[0]'s");
  command.points = {{1.0, {0.5}, {}, {}}};
  command.joint_names = {"elbow"};
  EXPECT_EQ(refused("arm_position", command),
            "vehicle 'frame': joint controller 'arm_position': trajectory: joint_names[0] 'elbow' is not a joint "
            "of the group (arm)");
  command.joint_names = {"arm", "arm"};
  EXPECT_EQ(refused("arm_position", command),
            "vehicle 'frame': joint controller 'arm_position': trajectory: 2 joint names for the group's 1 joints "
            "(arm)");
  command.joint_names = {"arm"};
  EXPECT_NE(refused("gripper", command).find("no joint controller 'gripper'"), std::string::npos);
  EXPECT_EQ(sim.state().vehicles[0].joint_targets[0], 0.2);

  Model with_velocity = p.model();
  with_velocity.vehicles[0].joint_controllers.push_back(velocity);
  Simulation rates(std::move(with_velocity));
  EXPECT_EQ(rates.set_joint_trajectory(0, "arm_velocity", command),
            "vehicle 'frame': joint controller 'arm_velocity': trajectory: it is a velocity group; only position "
            "groups follow trajectories");
}

// A force_torque sensor on the arm's link (its joint), sampled every step; `pose` its mounting in the link.
SensorSpec force_torque_sensor(const Eigen::Isometry3d& X_LS) {
  SensorSpec sensor;
  sensor.name = "wrist_ft";
  sensor.link_index = 1;
  sensor.X_LS = X_LS;
  sensor.rate_hz = 500.0;
  sensor.frame_id = "frame/wrist_ft";
  sensor.kind = sensors::ForceTorqueSpec{};
  return sensor;
}

const sensors::ForceTorqueSensor::State& force_torque(const Simulation& sim) {
  return state_of<sensors::ForceTorqueSensor>(sim.state().vehicles[0].sensors.at(0));
}

// The horizontal arm held by its position controller: at rest, what it puts on the frame across its joint
// (child_to_parent) is its wet weight W straight down and the moment W l cos q about +y, which is minus
// its motor's effort. The sensor sits 0.1 m along the arm, turned 90 degrees about x: the force reads in
// its axes, and the moment about its own origin is the joint's less the lever 0.1 m x F. At rest the
// Newton-Euler sum is exact but for the servo's residual motion (< 1e-9 rad/s after 4 s), hence 1e-6 of W.
TEST(SimulationArticulatedTest, AForceTorqueSensorReadsTheWetWeightAndTheEffortHoldingAnArm) {
  Pendulum p;
  Model model = held_arm(p);
  Eigen::Isometry3d X_LS = Eigen::Isometry3d::Identity();
  X_LS.translation() = Eigen::Vector3d(0.1, 0.0, 0.0);
  X_LS.linear() = Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  model.vehicles[0].sensors.push_back(force_torque_sensor(X_LS));
  Simulation sim(std::move(model));
  const double W = p.gravity_torque(sim) / p.l;  // the wet weight [N]
  for (int k = 0; k < 2000; ++k) sim.step();
  const double q = joint_q(sim);
  // The link frame L is the arm's, turned by q about y; F in W is (0, 0, -W).
  const Eigen::Matrix3d R_WL = Eigen::AngleAxisd(q, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d F_L = R_WL.transpose() * Eigen::Vector3d(0, 0, -W);
  const Eigen::Vector3d N_L(0.0, W * p.l * std::cos(q), 0.0);
  EXPECT_NEAR(N_L.y(), -sim.state().vehicles[0].joint_efforts[0], 1e-6 * W * p.l);
  const Eigen::Matrix3d R_SL = X_LS.linear().transpose();
  const Eigen::Vector3d F_S = R_SL * F_L;
  const Eigen::Vector3d N_S = R_SL * (N_L - X_LS.translation().cross(F_L));
  EXPECT_LT((force_torque(sim).force_S - F_S).norm(), 1e-6 * W) << force_torque(sim).force_S.transpose();
  EXPECT_LT((force_torque(sim).torque_S - N_S).norm(), 1e-6 * W * p.l) << force_torque(sim).torque_S.transpose();
}

// The pendulum swinging freely in water: across its joint it pulls on the frame along the arm with its
// wet weight's share and its centripetal force,
//   (m - rho V) g cos(theta) + m omega^2 l   (without added mass),
// and passes no moment about the joint's axis (no motor, no damping). With added mass the moment about
// the axis stays zero only if the added mass's reaction is counted: it alone decelerates the arm's m_A
// share (m_A l alpha, 4 N m at the swing's ends, would be left over). Each step's reading against the
// state the step started from, to 1e-6 of the wet weight (the sums are exact for the discrete step).
TEST(SimulationArticulatedTest, ASwingingPendulumPullsWithItsWetWeightAndItsCentripetalForce) {
  Pendulum p;
  p.initial = 40.0 * kPi / 180.0;
  for (const bool added_mass : {false, true}) {
    Model model = p.model();
    if (!added_mass) model.vehicles[0].fluid.added_mass.model = AddedMassModel::kNone;
    model.vehicles[0].sensors.push_back(force_torque_sensor(Eigen::Isometry3d::Identity()));
    Simulation sim(std::move(model));
    const double rho = sim.ocean().density(p.depth + p.l), V = p.volume(), g = 9.80665;
    const double W = (p.m - rho * V) * g;
    double worst_radial = 0.0, worst_axis = 0.0, fastest = 0.0;
    for (int k = 0; k < 1000; ++k) {
      const double theta = joint_q(sim), omega = sim.state().vehicles[0].joint_velocities[0];
      sim.step();
      fastest = std::max(fastest, std::abs(omega));
      // In L (the arm's frame) the arm points along -z: the pull on the frame is along -z.
      const double pull = W * std::cos(theta) + p.m * omega * omega * p.l;
      worst_radial = std::max(worst_radial, std::abs(-force_torque(sim).force_S.z() - pull));
      worst_axis = std::max(worst_axis, std::abs(force_torque(sim).torque_S.y()));
    }
    EXPECT_GT(fastest, 1.0) << added_mass;  // it swings: m omega^2 l is a tenth of W or more
    if (!added_mass) {
      EXPECT_LT(worst_radial, 1e-6 * W) << worst_radial;
    }
    EXPECT_LT(worst_axis, 1e-6 * W * p.l) << added_mass << " " << worst_axis;
  }
}

// The joints' wrenches are worked out only for the steps at whose end a force/torque sensor samples
// (VehicleState::joint_wrenches_L): a sensor at a fifth of the physics rate reads, at each of its samples,
// exactly what one sampled every step reads at that step (the same noise-free swing, to the bit).
TEST(SimulationArticulatedTest, AForceTorqueSensorBelowThePhysicsRateReadsTheStepItSamples) {
  Pendulum p;
  p.initial = 40.0 * kPi / 180.0;
  const auto swinging = [&](double rate_hz) {
    Model model = p.model();
    SensorSpec sensor = force_torque_sensor(Eigen::Isometry3d::Identity());
    sensor.rate_hz = rate_hz;
    model.vehicles[0].sensors.push_back(sensor);
    return std::make_unique<Simulation>(std::move(model));
  };
  const std::unique_ptr<Simulation> every = swinging(500.0), fifth = swinging(100.0);
  std::uint64_t seen = 0;
  int compared = 0;
  for (int k = 0; k < 500; ++k) {
    every->step();
    fifth->step();
    const SensorState& slow = fifth->state().vehicles[0].sensors.at(0);
    if (slow.samples == seen) continue;
    seen = slow.samples;
    ++compared;
    const auto& reading = state_of<sensors::ForceTorqueSensor>(slow);
    EXPECT_EQ(reading.force_S, force_torque(*every).force_S) << "step " << k;
    EXPECT_EQ(reading.torque_S, force_torque(*every).torque_S) << "step " << k;
  }
  EXPECT_EQ(compared, 100);
  EXPECT_GT(force_torque(*every).force_S.norm(), 1.0);  // it pulls
}

// A load resting on a tray: the contact carries its wet weight to the tray, and the tray's joint carries
// both. The tray (a 0.6 x 0.3 x 0.04 m box of 10 kg centred 0.4 m out) hangs on the frame's joint about y,
// held level by its position controller; a 0.12 m cube of 4 kg rests on it 0.55 m out. Settled (2 s), the
// sensor reads both wet weights straight down and their moments about the joint, each taken at where its
// body is; 1e-4 of the total for what is left of the settling. Without the contacts' impulses it would
// read the tray alone: the load is 45 % of the total.
TEST(SimulationArticulatedTest, AForceTorqueSensorFeelsALoadThroughItsContacts) {
  // Either order of the vehicles, so that the tray is either body of Bullet's contact manifold.
  for (const bool load_first : {false, true}) {
    Pendulum p;
    Model model = p.model();
    VehicleSpec frame = model.vehicles[0];
    LinkSpec& tray = frame.links[1];
    const Eigen::Vector3d size(0.6, 0.3, 0.04);
    tray.name = "tray";
    tray.mass = 10.0;
    tray.I_LLcm_L = physics::solid_box_inertia(10.0, size);
    tray.p_LLcm = Eigen::Vector3d(0.4, 0.0, 0.0);
    tray.collisions = {testing::box_shape(size)};
    tray.collisions[0].X_LG.translation() = tray.p_LLcm;
    frame.joint_controllers.push_back(position_controller("tray_position", 20000.0, 2000.0));
    frame.sensors.push_back(force_torque_sensor(Eigen::Isometry3d::Identity()));
    const double edge = 0.12;
    VehicleSpec load = testing::surface_vehicle(testing::box_shape(Eigen::Vector3d::Constant(edge)), 4.0,
                                                physics::solid_box_inertia(4.0, Eigen::Vector3d::Constant(edge)),
                                                testing::drag_only(0.0), Eigen::Vector3d(0.55, 0.0, -p.depth + 0.0805));
    load.name = "load";
    model.vehicles = load_first ? std::vector<VehicleSpec>{load, frame} : std::vector<VehicleSpec>{frame, load};
    const std::size_t f = load_first ? 1 : 0, l = 1 - f;
    Simulation sim(std::move(model));
    for (int k = 0; k < 1000; ++k) sim.step();
    const double rho = sim.ocean().density(p.depth), g = 9.80665;
    const double W_tray = (10.0 - rho * size.prod()) * g, W_load = (4.0 - rho * edge * edge * edge) * g;
    const double q = sim.state().vehicles[f].joint_positions[0];
    const Eigen::Matrix3d R_WL = Eigen::AngleAxisd(q, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Vector3d o_W(0.0, 0.0, -p.depth);
    const Eigen::Vector3d r_tray = R_WL * Eigen::Vector3d(0.4, 0.0, 0.0);
    const Eigen::Vector3d r_load = sim.state().vehicles[l].body.X_WB.translation() - o_W;
    ASSERT_NEAR(r_load.x(), 0.55, 0.01);  // still where it was put
    const Eigen::Vector3d F_W(0.0, 0.0, -(W_tray + W_load));
    const Eigen::Vector3d N_W =
        r_tray.cross(Eigen::Vector3d(0, 0, -W_tray)) + r_load.cross(Eigen::Vector3d(0, 0, -W_load));
    const double total = W_tray + W_load;
    const auto& reading = state_of<sensors::ForceTorqueSensor>(sim.state().vehicles[f].sensors.at(0));
    EXPECT_LT((reading.force_S - R_WL.transpose() * F_W).norm(), 1e-4 * total)
        << load_first << ": " << reading.force_S.transpose() << " vs " << (R_WL.transpose() * F_W).transpose();
    EXPECT_LT((reading.torque_S - R_WL.transpose() * N_W).norm(), 1e-4 * total * 0.5)
        << load_first << ": " << reading.torque_S.transpose() << " vs " << (R_WL.transpose() * N_W).transpose();
  }
}

// A profiler "profiler" on link `link` at p_LS looking straight down its link's -z (x_S down), with one
// exact, narrow beam (1 mrad, one ray, no noise, ranges from 0.1 m) at 50 Hz.
SensorSpec down_beam(int link, const Eigen::Vector3d& p_LS) {
  SensorSpec profiler;
  profiler.name = "profiler";
  profiler.link_index = link;
  profiler.X_LS = testing::at(p_LS, Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitY()).toRotationMatrix());
  profiler.rate_hz = 50.0;
  sensors::ProfilerSensor::Spec beam;
  beam.beams = 1;
  beam.fov = 1e-3;
  beam.beam_width = 1e-4;
  beam.rays_per_beam = 1;
  beam.noise_stddev = 0.0;
  beam.resolution = 0.0;
  beam.min_range = 0.1;
  profiler.kind = beam;
  return profiler;
}

// Sensors follow their moving link: a pressure sensor and a downward profiler 0.6 m down the swinging
// pendulum's arm read where the arm has taken them. The pressure is the ocean's at the sensor's depth,
// 50 m + 0.6 cos(theta) (1e-9 relative: the same arithmetic); the profiler's single narrow beam, along the
// arm, meets the seabed 10 m under the joint at (10 - 0.6 cos theta) / cos theta with theta at the scan's
// capture, though the scan is delivered a period later, the arm elsewhere (float hits: 4 ulp of 100 m).
// Were the sensors fixed in B where the arm hangs at rest, both would miss by up to 9 cm and 3 m.
TEST(SimulationArticulatedTest, SensorsOnAMovingLinkFollowIt) {
  Pendulum p;
  p.initial = 40.0 * kPi / 180.0;
  Model model = p.model();
  model.world.seabed.z = -p.depth - 10.0;
  const double arm = 0.6;
  SensorSpec pressure;
  pressure.name = "depth";
  pressure.link_index = 1;
  pressure.X_LS.translation() = Eigen::Vector3d(0.0, 0.0, -arm);
  pressure.rate_hz = 500.0;
  sensors::PressureSensor::Spec exact;
  exact.resolution = 0.0;
  pressure.kind = exact;
  SensorSpec profiler = down_beam(1, pressure.X_LS.translation());
  profiler.latency_s = 0.02;
  model.vehicles[0].sensors = {pressure, profiler};
  Simulation sim(std::move(model));
  std::map<std::uint64_t, double> theta_at;  // by step count
  std::uint64_t scans = 0;
  int checked = 0;
  for (int k = 0; k < 500; ++k) {
    sim.step();
    const double theta = joint_q(sim);
    theta_at[sim.state().step_count] = theta;
    const double expected = sim.ocean().pressure(p.depth + arm * std::cos(theta));
    const double measured = state_of<sensors::PressureSensor>(sim.state().vehicles[0].sensors[0]).pressure;
    ASSERT_NEAR(measured / expected, 1.0, 1e-9) << k;
    const SensorState& scan = sim.state().vehicles[0].sensors[1];
    if (scan.samples == scans) continue;
    scans = scan.samples;
    const auto step = static_cast<std::uint64_t>(std::llround(scan.stamp / sim.model().world.step_size()));
    const double at = theta_at.at(step);
    const double range = state_of<sensors::ProfilerSensor>(scan).ranges.at(0);
    EXPECT_NEAR(range, (10.0 - arm * std::cos(at)) / std::cos(at), 4 * FLT_EPSILON * 100.0) << k;
    EXPECT_GT(std::abs(joint_q(sim) - at), 1e-3);  // the arm has moved since
    ++checked;
  }
  EXPECT_GE(checked, 15);
}

// The ray-cast world has the moving links where their joints put them (geometry/world_scene.h): a profiler
// on the static frame, at the joint and looking straight down, meets the pendulum's bob, a 0.2 m cube
// whose centre hangs l = 0.5 m below the joint, on the face nearest the joint: at (l - h) / cos(theta)
// for a swing angle theta (h = 0.1 m, the half side; the beam stays on that face while tan(theta) (l - h)
// < h). Swinging within +-10 deg, that is 0.400-0.406 m; a bob left at q = 0 would read 0.400 m
// throughout. Tolerance: Embree's float32 distances, a few ulp of the 50 m coordinates (4e-6 m each).
TEST(SimulationArticulatedTest, RaysMeetAMovingLinkWhereItsJointPutsIt) {
  Pendulum p;
  p.initial = 10.0 * kPi / 180.0;
  Model model = p.model();
  const double h = 0.1;
  model.vehicles[0].links[1].collisions[0] = testing::box_shape({2 * h, 2 * h, 2 * h});
  model.vehicles[0].links[1].collisions[0].X_LG.translation() = p.l * p.arm_L;
  model.vehicles[0].sensors = {down_beam(0, Eigen::Vector3d::Zero())};  // on the frame, at the joint
  Simulation sim(std::move(model));
  std::map<std::uint64_t, double> theta_at;  // by step count
  std::uint64_t scans = 0;
  int checked = 0;
  double widest = 0.0;
  for (int k = 0; k < 1000; ++k) {
    sim.step();
    theta_at[sim.state().step_count] = joint_q(sim);
    const SensorState& scan = sim.state().vehicles[0].sensors[0];
    if (scan.samples == scans) continue;
    scans = scan.samples;
    const auto step = static_cast<std::uint64_t>(std::llround(scan.stamp / sim.model().world.step_size()));
    const double theta = theta_at.at(step);
    const double range = state_of<sensors::ProfilerSensor>(scan).ranges.at(0);
    EXPECT_NEAR(range, (p.l - h) / std::cos(theta), 2e-5) << k;
    widest = std::max(widest, std::abs(theta));
    ++checked;
  }
  EXPECT_GE(checked, 30);
  EXPECT_GT(widest, 8.0 * kPi / 180.0);  // the bob swung, and the beam saw it where it was
}

// A light on a moving link follows it: a narrow lamp (2-3 deg) on the pendulum's arm, 0.25 m to its side
// and pointing along it, held at theta = 0.3 rad (its wet weight presses it on its lower limit there), lights
// the seabed 10 m below the joint where its axis meets it, (-10 tan(theta), 0.25, -60) in W; a camera on the frame looking straight
// down sees the spot's centroid (pixels above half its peak) at that point's projection (render::project)
// within 1 px: the spot is some 8 px across, its brightness varies over it by the inverse square and the
// incidence by a few %, which moves the centroid by a fraction of a pixel. A lamp left at q = 0 would
// light (0, 0.25, -60), 21 px away.
TEST(SimulationArticulatedTest, ALightOnAMovingLinkLightsWhereItsJointPointsIt) {
  Pendulum p;
  p.initial = p.lower = 0.3;
  p.upper = 0.6;
  Model model = p.model();
  model.world.seabed.z = -p.depth - 10.0;
  SensorSpec camera;
  camera.name = "camera";
  camera.link_index = 0;
  camera.X_LS = testing::at(Eigen::Vector3d(0, -0.3, 0),
                            Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitY()).toRotationMatrix());
  camera.rate_hz = 10.0;
  sensors::CameraSensor::Spec spec;
  const render::LensSpec lens = render::lens_from_horizontal_fov(96, 72, 70.0 * kDegToRad);
  sensors::CameraSensor::set_lens(spec, lens);
  spec.sensor.exposure_s = 0.5;
  camera.kind = spec;
  model.vehicles[0].sensors = {camera};
  LightSpec lamp;
  lamp.name = "lamp";
  lamp.link_index = 1;  // the arm
  const Eigen::Matrix3d x_along_arm = Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  lamp.X_LF = testing::at(Eigen::Vector3d(0, 0.25, 0), x_along_arm);
  lamp.inner_half_angle = 2.0 * kDegToRad;
  lamp.outer_half_angle = 3.0 * kDegToRad;
  lamp.intensity_W_per_sr = Eigen::Array3d::Constant(2e4);
  model.vehicles[0].lights = {lamp};
  const Eigen::Isometry3d X_WC = model.vehicles[0].X_WB_initial * camera.X_LS * render::X_SC();
  Simulation sim(std::move(model));
  for (int k = 0; k < 60; ++k) sim.step();
  ASSERT_NEAR(joint_q(sim), 0.3, 1e-3);
  const auto& image = state_of<sensors::CameraSensor>(sim.state().vehicles[0].sensors[0]).image;
  ASSERT_EQ(image.size(), 96u * 72u * 3u);
  std::vector<double> luma(96 * 72);
  for (std::size_t i = 0; i < luma.size(); ++i) luma[i] = image[3 * i] + image[3 * i + 1] + image[3 * i + 2];
  const double peak = *std::max_element(luma.begin(), luma.end());
  const double floor = *std::min_element(luma.begin(), luma.end());
  ASSERT_GT(peak - floor, 100.0);
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double n = 0.0;
  for (int v = 0; v < 72; ++v) {
    for (int u = 0; u < 96; ++u) {
      if (luma[static_cast<std::size_t>(v * 96 + u)] <= 0.5 * (peak + floor)) continue;
      sum += Eigen::Vector2d(u, v);
      n += 1.0;
    }
  }
  const Eigen::Vector3d spot_W(-10.0 * std::tan(0.3), 0.25, -p.depth - 10.0);
  Eigen::Vector2d expected;
  ASSERT_TRUE(render::project(lens, X_WC.inverse() * spot_W, &expected));
  EXPECT_LT((sum / n - expected).norm(), 1.0) << (sum / n).transpose() << " vs " << expected.transpose() << ", " << n
                                             << " px";
}

// What a frame rendered outside the step takes (Simulation::capture_mount, hadal-render's): for a sensor on
// the pendulum's arm swung to theta about y at the frame's origin, its mounting in B is R_y(theta) X_LS
// (closed form, 1e-12), it is on the arm's ray body (1: after the one vehicle's base body), and the ray bodies'
// poses are the frame's and the arm's "B as it carries it" (R_y(theta) here).
TEST(SimulationArticulatedTest, ACaptureMountIsWhereTheJointsHoldTheSensor) {
  Pendulum p;
  p.initial = 0.4;
  Model model = p.model();
  SensorSpec profiler = down_beam(1, Eigen::Vector3d(0.1, 0.2, -0.3));
  model.vehicles[0].sensors = {down_beam(0, Eigen::Vector3d::Zero()), profiler};
  model.vehicles[0].sensors[0].name = "frame_profiler";
  Simulation sim(std::move(model));
  for (int k = 0; k < 37; ++k) sim.step();
  const double theta = joint_q(sim);
  ASSERT_GT(std::abs(theta - 0.4), 1e-3);  // it has swung
  const Eigen::Matrix3d R = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Simulation::CaptureMount on_arm = sim.capture_mount(0, 1);
  const Eigen::Isometry3d X_BS = testing::at(R * profiler.X_LS.translation(), R * profiler.X_LS.linear());
  EXPECT_LT((on_arm.X_BS.matrix() - X_BS.matrix()).norm(), 1e-12);
  EXPECT_EQ(on_arm.ray_body, 1);
  ASSERT_EQ(on_arm.X_Wb.size(), 2u);
  const Eigen::Isometry3d& X_WB = sim.state().vehicles[0].body.X_WB;
  EXPECT_LT((on_arm.X_Wb[0].matrix() - X_WB.matrix()).norm(), 1e-12);
  EXPECT_LT((on_arm.X_Wb[1].matrix() - (X_WB * testing::at(Eigen::Vector3d::Zero(), R)).matrix()).norm(), 1e-12);
  const Simulation::CaptureMount on_frame = sim.capture_mount(0, 0);
  EXPECT_EQ(on_frame.ray_body, 0);
  EXPECT_TRUE(on_frame.X_BS.isApprox(sim.model().vehicles[0].sensors[0].X_LS, 1e-15));
  EXPECT_THROW(sim.capture_mount(0, 2), std::out_of_range);
  EXPECT_THROW(sim.capture_mount(1, 0), std::out_of_range);
}

// The servo is taken implicitly over the step (physics/joint_servo.h), so gains far past the explicit
// bound hold a light link: a 50 g sphere 0.5 m out (I = m l^2 + its added inertia, about 0.013 kg m^2)
// under kd = 100 has kd dt / I = 15 at 500 Hz, where an explicit law multiplies every rate error by
// |1 - 15| each step. It settles where kp (q* - q) balances the wet weight's torque, as the slow law does.
TEST(SimulationArticulatedTest, AStiffServoOnALightLinkIsStable) {
  Pendulum p;
  p.r = 0.02;
  p.m = 0.05;
  p.arm_L = Eigen::Vector3d::UnitX();
  Model model = p.model();
  ASSERT_EQ(model.world.physics_rate_hz, 500.0);
  const physics::JointControllerSpec position = position_controller("wrist", 5000.0, 100.0);
  model.vehicles[0].joint_controllers.push_back(position);
  Simulation sim(std::move(model));
  const double tau_g = p.gravity_torque(sim);
  ASSERT_EQ(sim.set_joint_commands(0, "wrist", {0.5}), "");
  double fastest = 0.0;
  for (int k = 0; k < 1000; ++k) {
    sim.step();
    fastest = std::max(fastest, std::abs(sim.state().vehicles[0].joint_velocities[0]));
  }
  const double expected = held_at(0.5, tau_g, position.kp[0]);
  EXPECT_NEAR(joint_q(sim), expected, 1e-9);
  // The rate the law asks for is kp / kd (q* - q) = 25 rad/s at the start: never more.
  EXPECT_LE(fastest, 25.0);
}

// A servo at its rate limit against Coulomb friction runs at the limit less friction's share: the
// position law asks for 0.15 rad/s (velocity_limit) of a light link (the stiff-servo test's 50 g sphere,
// no gravity), so its torque kd (0.15 - qd) balances the friction F and what the water takes (about
// 0.16 N m, measured) at a steady rate F / kd = 5 mrad/s below the frictionless one (to 1e-6 rad/s, kd
// times which, 2e-4 N m, bounds how much the water's share may differ between the two rates). The joint
// solve first tries every
// frictional joint stuck, where stopping the moving link within one step would take kd qd more torque than
// the law has and pass its effort limit (20 N m): once it slides, the law is back within the limit and
// must drive it again. A servo left saturated at 20 N m throws the link far past 0.15 rad/s.
TEST(SimulationArticulatedTest, AServoAgainstFrictionRunsAtItsRateLimitLessFrictionsShare) {
  const double kd = 200.0;
  const auto run = [&](double friction, double* fastest) {
    Pendulum p;
    p.r = 0.02;
    p.m = 0.05;
    p.arm_L = Eigen::Vector3d::UnitX();
    p.lower = -1.0;
    p.upper = 1.0;
    Model model = p.model();
    model.world.gravity_W.setZero();
    LinkSpec& arm = model.vehicles[0].links[1];
    arm.joint.friction = friction;    // [N m]
    arm.joint.effort_limit = 20.0;    // [N m]
    arm.joint.velocity_limit = 0.15;  // [rad/s]
    model.vehicles[0].joint_controllers.push_back(position_controller("wrist", 100.0, kd));
    Simulation sim(std::move(model));
    EXPECT_EQ(sim.set_joint_commands(0, "wrist", {0.9}), "");
    *fastest = 0.0;
    for (int k = 0; k < 500; ++k) {  // 1 s: 0.145 rad, far from the target
      sim.step();
      *fastest = std::max(*fastest, std::abs(sim.state().vehicles[0].joint_velocities[0]));
    }
    return sim.state().vehicles[0].joint_velocities[0];
  };
  double fastest = 0.0, fastest_free = 0.0;
  const double rate = run(1.0, &fastest);
  const double free_rate = run(0.0, &fastest_free);
  EXPECT_LE(fastest, 0.15);
  EXPECT_LE(fastest_free, 0.15);
  EXPECT_NEAR(free_rate - rate, 1.0 / kd, 1e-6) << "rates " << free_rate << ", " << rate;
}

// Joint limits are hard stops at the position level: under ten times the effort gravity needs, the arm
// pressed against its limit of +-10 degrees for 1 s never passes it and rests on it. The implicit joint
// solve ends a step that would pass the bound on it, and Bullet's step follows the solve's motion (the
// same equations; ArticulatedDynamicsPredictsBulletsStep: 1e-9), so the bound holds to 1e-9 rad, where
// Bullet's own limit constraint (a soft stop corrected by a fraction per step) overshot by 7-8 mrad.
TEST(SimulationArticulatedTest, JointLimitsHoldUnderFullEffort) {
  constexpr double kTolerance = 1e-9;  // [rad]
  Pendulum p;
  p.lower = -10.0 * kPi / 180.0;
  p.upper = 10.0 * kPi / 180.0;
  for (const double effort : {200.0, -200.0}) {
    Simulation sim(p.model());
    ASSERT_EQ(sim.set_joint_efforts(0, {effort}), "");
    double extreme = 0.0;
    for (int k = 0; k < 500; ++k) {
      sim.step();
      extreme = effort > 0 ? std::max(extreme, joint_q(sim)) : std::min(extreme, joint_q(sim));
    }
    const double limit = effort > 0 ? p.upper : p.lower;
    EXPECT_NEAR(extreme, limit, kTolerance) << "effort " << effort;
    EXPECT_NEAR(joint_q(sim), limit, kTolerance) << "effort " << effort;
  }
}

// A locked joint (lower = upper = 0.2 rad) is a fixed joint at its lock (geometry::lock_joints; the simulation
// locks a model built in code as the loader does a scenario's): the pendulum is one rigid body with the sphere
// turned 0.2 rad about y, so its centre of mass is at m l (-sin 0.2, 0, -cos 0.2) / (m + 10 kg) in B (to
// rounding, 1e-15 m), and no joint is left to command.
TEST(SimulationArticulatedTest, ALockedJointIsFixedAtItsLock) {
  Pendulum locked;
  locked.lower = locked.upper = locked.initial = 0.2;
  Simulation sim(locked.model());
  EXPECT_TRUE(sim.state().vehicles[0].joint_positions.empty());
  EXPECT_NE(sim.set_joint_efforts(0, {200.0}), "");
  const double share = locked.m * locked.l / (locked.m + 10.0);
  const Eigen::Vector3d expected(-share * std::sin(0.2), 0.0, -share * std::cos(0.2));
  EXPECT_LT((sim.mass_properties(0).p_BBcm - expected).norm(), 1e-15) << sim.mass_properties(0).p_BBcm.transpose();
  const JointSpec& joint = sim.model().vehicles[0].links[1].joint;
  EXPECT_EQ(joint.type, JointType::kFixed);
  EXPECT_EQ(joint.locked_type, JointType::kRevolute);  // JointState reports it (SceneMessageTest)
}

// A free-floating vehicle (no gravity; in air above the water, so no fluid forces) swinging a two-joint arm
// with its joint motors: internal torques only, so its centre of mass stays where it was (within 1e-6 m over 2 s) and its
// angular momentum stays zero, while the base moves and turns in reaction by centimetres and degrees.
// (Bullet's step alone drifts by 9e-4 m here, first order in dt: Simulation::keep_momentum's correction.)
TEST(SimulationArticulatedTest, AFreeFloatingVehicleSwingingItsArmKeepsItsCentreOfMass) {
  Model model = testing::water_model({arm_vehicle(20.0)});  // in air
  model.world.gravity_W.setZero();
  Simulation sim(std::move(model));
  struct Momentum {
    Eigen::Vector3d c = Eigen::Vector3d::Zero(), L = Eigen::Vector3d::Zero();  // L about c
  };
  const auto momentum = [&]() {
    // From the state through the articulation's own kinematics.
    const VehicleState& v = sim.state().vehicles[0];
    const physics::Articulation articulation(sim.model().vehicles[0].links);
    const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(v.joint_positions.data(), 2);
    const Eigen::VectorXd qd = Eigen::Map<const Eigen::VectorXd>(v.joint_velocities.data(), 2);
    const std::vector<Eigen::Isometry3d> X_WK = articulation.poses_W(v.body.X_WB, q);
    const auto velocity = articulation.velocities_W(X_WK, v.body.v_WB, v.body.w_WB, qd);
    Momentum out;
    double mass = 0.0;
    for (int k = 0; k < articulation.num_bodies(); ++k) {
      const physics::MassProperties& body = articulation.body(k).mass_K;
      out.c += body.mass * (X_WK[static_cast<std::size_t>(k)] * body.p_BBcm);
      mass += body.mass;
    }
    out.c /= mass;
    for (int k = 0; k < articulation.num_bodies(); ++k) {
      const auto i = static_cast<std::size_t>(k);
      const physics::MassProperties& body = articulation.body(k).mass_K;
      const Eigen::Vector3d c_k = X_WK[i] * body.p_BBcm;
      const Eigen::Vector3d v_k = velocity[i].v_WK + velocity[i].w_WK.cross(c_k - X_WK[i].translation());
      const Eigen::Matrix3d R = X_WK[i].linear();
      out.L += (c_k - out.c).cross(body.mass * v_k) + R * body.I_BBcm_B * R.transpose() * velocity[i].w_WK;
    }
    return out;
  };
  const Eigen::Vector3d c0 = momentum().c;
  const Eigen::Isometry3d X_WB0 = sim.state().vehicles[0].body.X_WB;
  double max_drift = 0.0, max_L = 0.0;
  for (int k = 0; k < 1000; ++k) {
    // A swing out and back: +-effort each half second.
    const double sign = (k / 250) % 2 == 0 ? 1.0 : -1.0;
    ASSERT_EQ(sim.set_joint_efforts(0, {4.0 * sign, -2.0 * sign}), "");
    sim.step();
    const Momentum now = momentum();
    max_drift = std::max(max_drift, (now.c - c0).norm());
    max_L = std::max(max_L, now.L.norm());
  }
  const Eigen::Isometry3d& X_WB = sim.state().vehicles[0].body.X_WB;
  EXPECT_LT(max_drift, 1e-6);
  EXPECT_LT(max_L, 1e-9);  // [kg m^2/s]; the arm's own is ~1 (a 0.5 kg m^2 link at ~2 rad/s)
  EXPECT_GT((X_WB.translation() - X_WB0.translation()).norm(), 0.01) << "the base moves in reaction";
  EXPECT_GT(Eigen::AngleAxisd(X_WB.linear() * X_WB0.linear().transpose()).angle(), 1.0 * kPi / 180.0);
}

// A restored state continues bit for bit: the joints are part of the state. Joint efforts are refused
// when they do not fit (the state untouched), and reset puts the joints back at their initial positions.
// Waves reach an articulated vehicle's added mass too: two neutrally buoyant spheres (the base, and one on an arm
// held by a stiff position controller), 10 m down in long regular waves (0.5 m, 12 s: 225 m long), drift with the
// water. Froude-Krylov gives each sphere m a_water and the added mass's share m_A a_water comes on top (Morison's
// inertia), so their horizontal velocity swings with the water's orbital velocity a omega e^(k z) within 5 % (the
// surface's swing modulates e^(k (z - eta)) by 1.4 %); without the water's acceleration in the added mass it would be
// m / (m + m_A) = 2/3 of it. Drag, friction and lift off.
TEST(SimulationArticulatedTest, InWavesItsBodiesDriftWithTheWater) {
  CollisionShape sphere;
  sphere.type = CollisionShapeType::kSphere;
  sphere.radius = 0.3;
  const double volume = geometry::compute_mesh_properties(geometry::tessellate(sphere)).volume;
  Model probe = testing::water_model({});
  const double rho = physics::Ocean(probe.world).density(10.0), m = rho * volume;
  VehicleSpec vehicle = testing::surface_vehicle(sphere, m, physics::solid_sphere_inertia(m, 0.3),
                                                 testing::drag_only(0.0), Eigen::Vector3d(0, 0, -10.0));
  LinkSpec arm = vehicle.links[0];
  arm.name = "arm";
  arm.collisions[0].X_LG.translation() = Eigen::Vector3d(1.0, 0.0, 0.0);
  arm.p_LLcm = Eigen::Vector3d(1.0, 0.0, 0.0);
  arm.joint.type = JointType::kRevolute;
  arm.joint.axis_L = Eigen::Vector3d::UnitY();
  vehicle.links.push_back(arm);
  vehicle.joint_controllers.push_back(position_controller("arm_position", 2000.0, 200.0));
  Model model = testing::water_model({vehicle});
  model.world.seabed.z = -500.0;
  model.world.physics_rate_hz = 200.0;
  model.world.waves.spectrum = physics::WaveSpectrum::kRegular;
  model.world.waves.regular = {{0.5, 12.0, 0.0, 0.0}};
  Simulation sim(model);
  const double omega = 2.0 * kPi / 12.0, k = omega * omega / 9.80665;
  double lo = 1e9, hi = -1e9;
  for (int step = 1; step <= 200 * 60; ++step) {  // the sea built up over 24 s; the last two periods measured
    sim.step();
    if (step <= 200 * 36) continue;
    const double v = sim.state().vehicles[0].body.v_WB.x();
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  const double orbital = 0.5 * omega * std::exp(k * -10.0);
  std::printf("horizontal velocity amplitude %.5f m/s, the water's %.5f m/s\n", 0.5 * (hi - lo), orbital);
  EXPECT_NEAR(0.5 * (hi - lo) / orbital, 1.0, 0.05) << 0.5 * (hi - lo) << " vs " << orbital;
}

TEST(SimulationArticulatedTest, RestoredStatesContinueIdenticallyAndBadEffortsAreRefused) {
  Pendulum p;
  p.initial = 0.3;
  Simulation sim(p.model());
  EXPECT_EQ(sim.state().vehicles[0].joint_positions, std::vector<double>{0.3});
  ASSERT_EQ(sim.set_joint_efforts(0, {1.5}), "");
  for (int k = 0; k < 100; ++k) sim.step();
  const SimState saved = sim.state();
  for (int k = 0; k < 200; ++k) sim.step();
  const SimState first = sim.state();
  sim.set_state(saved);
  for (int k = 0; k < 200; ++k) sim.step();
  EXPECT_EQ(sim.state().vehicles[0].joint_positions, first.vehicles[0].joint_positions);
  EXPECT_EQ(sim.state().vehicles[0].joint_velocities, first.vehicles[0].joint_velocities);
  EXPECT_NE(first.vehicles[0].joint_positions, saved.vehicles[0].joint_positions);

  EXPECT_NE(sim.set_joint_efforts(0, {1.0, 2.0}).find("2 joint efforts for 1 joints"), std::string::npos);
  EXPECT_NE(sim.set_joint_efforts(0, {std::nan("")}).find("not finite"), std::string::npos);
  EXPECT_NE(sim.set_joint_efforts(3, {1.0}).find("unknown vehicle"), std::string::npos);
  EXPECT_EQ(sim.state().vehicles[0].joint_efforts, std::vector<double>{1.5});
  SimState wrong = saved;
  wrong.vehicles[0].joint_positions.push_back(0.0);
  EXPECT_THROW(sim.set_state(wrong), std::invalid_argument);

  ASSERT_EQ(sim.reset(7), "");
  EXPECT_EQ(sim.state().vehicles[0].joint_positions, std::vector<double>{0.3});
  EXPECT_EQ(sim.state().vehicles[0].joint_efforts, std::vector<double>{0.0});

  // A floating vehicle in water, with added mass (constraint forces and momentum balance in the state).
  VehicleSpec floating = arm_vehicle(-30.0);
  floating.fluid.added_mass.model = AddedMassModel::kEllipsoid;
  floating.links[2].joint.friction = 0.5;
  Simulation swim(testing::water_model({floating}));
  ASSERT_EQ(swim.set_joint_efforts(0, {3.0, -1.0}), "");
  for (int k = 0; k < 100; ++k) swim.step();
  const SimState start = swim.state();
  EXPECT_EQ(start.vehicles[0].constraint_force.size(), 8u);
  for (int k = 0; k < 200; ++k) swim.step();
  const SimState once = swim.state();
  swim.set_state(start);
  for (int k = 0; k < 200; ++k) swim.step();
  EXPECT_EQ(swim.state().vehicles[0].joint_positions, once.vehicles[0].joint_positions);
  EXPECT_EQ(swim.state().vehicles[0].body.X_WB.matrix(), once.vehicles[0].body.X_WB.matrix());
  EXPECT_EQ(swim.state().vehicles[0].body.v_WB, once.vehicles[0].body.v_WB);
}

}  // namespace
}  // namespace hadal
