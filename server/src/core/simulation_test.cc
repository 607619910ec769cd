#include "hadal/core/simulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "hadal/geometry/mesh_properties.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/physics/mass_properties.h"
#include "hadal/physics/test_models.h"

namespace hadal {
namespace {

namespace testing = physics::testing;
using Thruster = physics::ThrusterActuator::State;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Eigen::Isometry3d at(const Eigen::Vector3d& p, double yaw = 0.0) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X.translation() = p;
  return X;
}

// A neutrally buoyant 1 x 0.4 x 0.4 m box AUV (rho V = m at rho = 1000) with a main thruster on the
// body x axis behind the centre of mass, a heave and a sway thruster, and diagonal damping.
VehicleSpec box_auv(const Eigen::Isometry3d& X_WB, double buoyancy_ratio = 1.0) {
  VehicleSpec vehicle;
  vehicle.name = "auv";
  const Eigen::Vector3d size(1.0, 0.4, 0.4);
  const double mass = 1000.0 * size.prod();
  vehicle.links.push_back(testing::box_link("hull", mass, size, buoyancy_ratio * size.prod()));
  vehicle.actuators = {
      testing::simple_thruster("main", Eigen::Vector3d(-0.6, 0, 0), Eigen::Vector3d::UnitX()),
      testing::simple_thruster("heave", Eigen::Vector3d(0, 0, 0), Eigen::Vector3d::UnitZ()),
      testing::simple_thruster("sway", Eigen::Vector3d(0, 0, 0), Eigen::Vector3d::UnitY())};
  vehicle.fluid.model = FluidModelType::kLumped;
  vehicle.fluid.linear_damping << 20, 50, 50, 5, 5, 5;
  vehicle.fluid.quadratic_damping << 40, 100, 100, 5, 5, 5;
  vehicle.X_WB_initial = X_WB;
  return vehicle;
}

Model one_auv_model(const Eigen::Isometry3d& X_WB = at(Eigen::Vector3d(0, 0, -20))) {
  return testing::water_model({box_auv(X_WB)});
}

// Bitwise equality of doubles (NaN-safe, distinguishes -0.0).
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

::testing::AssertionResult bit_identical(const SimState& a, const SimState& b) {
  if (!same_bits(a.time, b.time) || a.step_count != b.step_count) {
    return ::testing::AssertionFailure() << "time/step_count differ";
  }
  for (std::size_t i = 0; i < a.vehicles.size(); ++i) {
    const VehicleState& va = a.vehicles[i];
    const VehicleState& vb = b.vehicles[i];
    for (int k = 0; k < 16; ++k) {
      if (!same_bits(va.body.X_WB.matrix().data()[k], vb.body.X_WB.matrix().data()[k])) {
        return ::testing::AssertionFailure() << "X_WB differs at " << k;
      }
    }
    for (int k = 0; k < 3; ++k) {
      if (!same_bits(va.body.v_WB[k], vb.body.v_WB[k]) ||
          !same_bits(va.body.w_WB[k], vb.body.w_WB[k])) {
        return ::testing::AssertionFailure() << "velocity differs at " << k;
      }
    }
    for (std::size_t k = 0; k < va.actuators.size(); ++k) {
      const Thruster& ta = std::get<Thruster>(va.actuators[k]);
      const Thruster& tb = std::get<Thruster>(vb.actuators[k]);
      if (!same_bits(ta.setpoint, tb.setpoint) || !same_bits(ta.rotor_speed_rev_s, tb.rotor_speed_rev_s) ||
          !same_bits(ta.thrust_N, tb.thrust_N) || !same_bits(ta.torque_Nm, tb.torque_Nm)) {
        return ::testing::AssertionFailure() << "thruster " << k << " differs";
      }
    }
    if (va.faults != vb.faults || va.fault_resets != vb.fault_resets ||
        va.command_source != vb.command_source) {
      return ::testing::AssertionFailure() << "faults/command source differ";
    }
  }
  return ::testing::AssertionSuccess();
}

void run(Simulation& sim, int steps) {
  for (int k = 0; k < steps; ++k) sim.step();
}

TEST(SimulationTest, ForwardThrustMovesAlongBodyX) {
  // Main thruster on the body x axis (through the centre of mass) of a neutrally buoyant vehicle:
  // translation stays on the line through p0 along R_WB x. The propeller torque only rolls the
  // vehicle about that same axis. Direction error is round-off (1e-9 rad bound), depth change too.
  for (double yaw : {0.0, 1.0}) {
    const Eigen::Vector3d p0(3.0, -2.0, -20.0);
    Model model = one_auv_model(at(p0, yaw));
    model.vehicles[0].command_timeout = 10.0;  // one command for the whole 2 s run
    Simulation sim(std::move(model));
    ASSERT_EQ(sim.set_controls(0, {0.5, 0.0, 0.0}), "");
    run(sim, 1000);
    const RigidBodyState& body = sim.state().vehicles[0].body;
    const Eigen::Vector3d moved = body.X_WB.translation() - p0;
    const Eigen::Vector3d x_W(std::cos(yaw), std::sin(yaw), 0.0);
    EXPECT_GT(moved.dot(x_W), 1.0) << "yaw " << yaw;
    EXPECT_LT((moved - moved.dot(x_W) * x_W).norm(), 1e-9 * moved.norm()) << "yaw " << yaw;
    EXPECT_GT(std::get<Thruster>(sim.state().vehicles[0].actuators[0]).thrust_N, 0.0);
    EXPECT_LT(std::get<Thruster>(sim.state().vehicles[0].actuators[0]).torque_Nm, 0.0);  // right-handed, n > 0
  }
}

TEST(SimulationTest, PositivelyBuoyantVehicleRises) {
  Model model = testing::water_model({box_auv(at(Eigen::Vector3d(0, 0, -20)), 1.1)});
  Simulation sim(std::move(model));
  run(sim, 500);
  const RigidBodyState& body = sim.state().vehicles[0].body;
  EXPECT_GT(body.X_WB.translation().z(), -19.9);
  EXPECT_GT(body.v_WB.z(), 0.0);
  EXPECT_EQ(sim.state().vehicles[0].command_source, CommandSource::kNone);
}

// A static vehicle (VehicleSpec::is_static) never moves, even a heavy one that would sink, and a dynamic body
// falling on it comes to rest on top of it: the static box (0.4 m high) has its top at z = -19.8 m, so the
// falling box's centre rests 0.2 m higher, at -19.6 m, within Bullet's contact margin (0.04 m, its default).
TEST(SimulationTest, AStaticVehicleStaysPutAndADynamicOneRestsOnIt) {
  VehicleSpec prop = box_auv(at(Eigen::Vector3d(0.0, 0.0, -20.0)), 0.5);  // half buoyant: it would sink
  prop.name = "prop";
  prop.is_static = true;
  VehicleSpec falling = box_auv(at(Eigen::Vector3d(0.1, 0.0, -18.5)), 0.5);
  falling.name = "falling";
  Simulation sim(testing::water_model({prop, falling}));
  run(sim, 2500);  // 5 s at 500 Hz
  const RigidBodyState& fixed = sim.state().vehicles[0].body;
  EXPECT_TRUE(fixed.X_WB.isApprox(prop.X_WB_initial, 0.0)) << fixed.X_WB.matrix();
  EXPECT_EQ(fixed.v_WB, Eigen::Vector3d::Zero());
  EXPECT_EQ(fixed.w_WB, Eigen::Vector3d::Zero());
  const RigidBodyState& resting = sim.state().vehicles[1].body;
  EXPECT_EQ(sim.state().vehicles[0].faults, 0u);
  EXPECT_EQ(sim.state().vehicles[1].faults, 0u);
  EXPECT_NEAR(resting.X_WB.translation().z(), -19.6, 0.04);
  EXPECT_LT(resting.v_WB.norm(), 0.01);
}

TEST(SimulationTest, TimeIsStepCountTimesStepSize) {
  Simulation sim(one_auv_model());
  run(sim, 777);
  EXPECT_EQ(sim.state().step_count, 777u);
  EXPECT_EQ(sim.time(), 777 * sim.model().world.step_size());
}

TEST(SimulationTest, WatchdogZeroesStaleCommandsAndANewCommandClearsIt) {
  // 256 Hz makes dt = 2^-8 and every sim time exact, so the freshness boundary is tested exactly:
  // a command at t = 0 with timeout 0.5 s drives the step starting at t = 0.5 and not the next.
  Model model = one_auv_model();
  model.world.physics_rate_hz = 256.0;
  model.vehicles[0].command_timeout = 0.5;
  Simulation sim(std::move(model));
  ASSERT_EQ(sim.set_controls(0, {0.8, 0.0, -0.2}), "");
  run(sim, 129);  // the last step started at t = 128 / 256 = 0.5
  const VehicleState* vehicle = &sim.state().vehicles[0];
  EXPECT_EQ(std::get<Thruster>(vehicle->actuators[0]).setpoint, 0.8);
  EXPECT_EQ(std::get<Thruster>(vehicle->actuators[2]).setpoint, -0.2);
  EXPECT_EQ(vehicle->faults & kFaultCommandTimeout, 0u);
  EXPECT_EQ(vehicle->command_source, CommandSource::kClient);

  sim.step();  // started at t = 0.5 + 1/256: stale
  vehicle = &sim.state().vehicles[0];
  EXPECT_EQ(std::get<Thruster>(vehicle->actuators[0]).setpoint, 0.0);
  EXPECT_EQ(std::get<Thruster>(vehicle->actuators[2]).setpoint, 0.0);
  EXPECT_NE(vehicle->faults & kFaultCommandTimeout, 0u);
  const double n_before = std::get<Thruster>(vehicle->actuators[0]).rotor_speed_rev_s;
  run(sim, 10);
  EXPECT_EQ(std::get<Thruster>(sim.state().vehicles[0].actuators[0]).rotor_speed_rev_s, 0.0);  // tau = 0: stopped at once
  EXPECT_EQ(n_before, 0.0);

  ASSERT_EQ(sim.set_controls(0, {-0.3, 0.1, 0.0}), "");
  EXPECT_EQ(sim.state().vehicles[0].faults & kFaultCommandTimeout, 0u);
  EXPECT_EQ(sim.state().vehicles[0].last_command_time, sim.time());
  sim.step();
  EXPECT_EQ(std::get<Thruster>(sim.state().vehicles[0].actuators[0]).setpoint, -0.3);
  EXPECT_EQ(std::get<Thruster>(sim.state().vehicles[0].actuators[0]).rotor_speed_rev_s, -0.3 * 50.0);
  EXPECT_EQ(sim.state().vehicles[0].faults & kFaultCommandTimeout, 0u);
}

TEST(SimulationTest, ScheduleIsAZeroOrderHoldUntilAClientTakesOver) {
  // 256 Hz: keyframe times 0.25 and 0.5 s are exact step boundaries (64 and 128).
  Model model = one_auv_model();
  model.world.physics_rate_hz = 256.0;
  model.vehicles[0].schedule = {{0.25, {0.5, 0.0, 0.0}}, {0.5, {-0.5, 0.25, 0.0}}};
  Simulation sim(std::move(model));
  EXPECT_EQ(sim.state().vehicles[0].command_source, CommandSource::kSchedule);
  auto setpoint = [&](int k) { return std::get<Thruster>(sim.state().vehicles[0].actuators[k]).setpoint; };

  run(sim, 64);  // steps starting at 0 .. 63/256: before the first keyframe
  EXPECT_EQ(setpoint(0), 0.0);
  EXPECT_EQ(sim.state().vehicles[0].command_source, CommandSource::kSchedule);
  sim.step();  // started at 0.25
  EXPECT_EQ(setpoint(0), 0.5);
  run(sim, 63);  // last started at 127/256
  EXPECT_EQ(setpoint(0), 0.5);
  sim.step();  // started at 0.5
  EXPECT_EQ(setpoint(0), -0.5);
  EXPECT_EQ(setpoint(1), 0.25);
  run(sim, 100);
  EXPECT_EQ(setpoint(0), -0.5);  // held after the last keyframe

  // Hand-over: the client's command wins from now on, the schedule is never used again.
  ASSERT_EQ(sim.set_controls(0, {0.1, 0.2, 0.3}), "");
  EXPECT_EQ(sim.state().vehicles[0].command_source, CommandSource::kClient);
  sim.step();
  EXPECT_EQ(setpoint(0), 0.1);
  EXPECT_EQ(setpoint(2), 0.3);
  // After the watchdog expires the thrusters stop instead of falling back to the schedule.
  run(sim, 300);
  EXPECT_EQ(setpoint(0), 0.0);
  EXPECT_EQ(sim.state().vehicles[0].command_source, CommandSource::kClient);
  EXPECT_NE(sim.state().vehicles[0].faults & kFaultCommandTimeout, 0u);
}

TEST(SimulationTest, KeyframeIsNotDelayedByRoundOffOfSimTime) {
  // At 60 Hz, 222 * (1/60) = 3.6999999999999997 < 3.7: the keyframe must still apply to the step
  // that starts at step 222, not one step later.
  Model model = one_auv_model();
  model.world.physics_rate_hz = 60.0;
  model.vehicles[0].schedule = {{3.7, {1.0, 0.0, 0.0}}};
  Simulation sim(std::move(model));
  run(sim, 222);
  ASSERT_LT(sim.time(), 3.7);
  EXPECT_EQ(std::get<Thruster>(sim.state().vehicles[0].actuators[0]).setpoint, 0.0);
  sim.step();  // starts at step 222
  EXPECT_EQ(std::get<Thruster>(sim.state().vehicles[0].actuators[0]).setpoint, 1.0);
}

TEST(SimulationTest, RejectsInvalidCommandsWithAReason) {
  Simulation sim(one_auv_model());
  const SimState before = sim.state();
  EXPECT_EQ(sim.set_controls(7, {0, 0, 0}), "unknown vehicle index 7");
  EXPECT_EQ(sim.set_controls(-1, {0, 0, 0}), "unknown vehicle index -1");
  EXPECT_EQ(sim.set_controls(0, {0, 0}),
            "expected 3 setpoints (main, heave, sway), got 2");
  EXPECT_EQ(sim.set_controls(0, {0, kNaN, 0}), "setpoint[1] is NaN");
  EXPECT_EQ(sim.set_controls(0, {0, 0, -kInf}), "setpoint[2] is -inf");
  EXPECT_EQ(sim.set_controls(0, {1.5, 0, 0}), "setpoint[0] = 1.5 is outside [-1, 1]");
  EXPECT_EQ(sim.set_controls(0, {0, -1.0000001, 0}),
            "setpoint[1] = -1.0000001 is outside [-1, 1]");
  EXPECT_TRUE(bit_identical(sim.state(), before));
  EXPECT_TRUE(sim.state().vehicles[0].client_controls.empty());
  EXPECT_EQ(sim.state().vehicles[0].command_source, CommandSource::kNone);
  EXPECT_EQ(sim.set_controls(0, {1.0, -1.0, 0.0}), "");
}

TEST(SimulationTest, CheckingACommandValidatesWithoutApplying) {
  Simulation sim(one_auv_model());
  const SimState before = sim.state();
  EXPECT_EQ(sim.check_controls(0, {0, kNaN, 0}), "setpoint[1] is NaN");
  EXPECT_EQ(sim.check_controls(3, {0, 0, 0}), "unknown vehicle index 3");
  EXPECT_EQ(sim.check_controls(0, {0.5, 0.0, 0.0}), "");
  EXPECT_TRUE(bit_identical(sim.state(), before));  // a valid command is not applied either
  EXPECT_EQ(sim.state().vehicles[0].command_source, CommandSource::kNone);
}

TEST(SimulationTest, RestoredStateContinuesBitIdentically) {
  // A vehicle with an offset centre of mass and rotated principal axes, yawed, thrusters with rotor
  // lag, moving and turning: every conversion and every state variable is exercised.
  Model model = one_auv_model(at(Eigen::Vector3d(1, 2, -30), 0.4));
  VehicleSpec& vehicle = model.vehicles[0];
  Eigen::Isometry3d X_BL = at(Eigen::Vector3d(0.3, 0.1, 0.15), 0.5);
  vehicle.links.push_back(
      testing::box_link("pod", 20.0, Eigen::Vector3d(0.3, 0.2, 0.2), 0.004, X_BL));
  for (ActuatorSpec& thruster : vehicle.actuators) std::get<physics::ThrusterActuator::Spec>(thruster.kind).rotor_time_constant_s = 0.1;
  vehicle.v_WB_initial = Eigen::Vector3d(0.2, -0.1, 0.05);

  Simulation original(model);
  ASSERT_FALSE(original.mass_properties(0).X_BP.isApprox(Eigen::Isometry3d::Identity()));
  ASSERT_EQ(original.set_controls(0, {0.7, -0.3, 0.4}), "");
  run(original, 200);
  const SimState snapshot = original.state();
  run(original, 300);
  const SimState uninterrupted = original.state();

  Simulation fresh(model);
  fresh.set_state(snapshot);
  EXPECT_TRUE(bit_identical(fresh.state(), snapshot));
  run(fresh, 300);
  EXPECT_TRUE(bit_identical(fresh.state(), uninterrupted));

  original.set_state(snapshot);  // rewind the same instance
  run(original, 300);
  EXPECT_TRUE(bit_identical(original.state(), uninterrupted));
  EXPECT_GT(uninterrupted.vehicles[0].body.w_WB.norm(), 1e-3);  // it really turned
}

TEST(SimulationTest, RestoringAStateInContactIsDeterministic) {
  // Resting on the seabed, contact caches are not part of SimState; two restores of the same state
  // must still agree bit for bit.
  Model model = one_auv_model(at(Eigen::Vector3d(0, 0, -99.79), 0.2));
  model.vehicles[0].links[0].mass *= 2.0;  // sinks
  Simulation original(model);
  run(original, 500);
  const SimState snapshot = original.state();
  Simulation a(model), b(model);
  a.set_state(snapshot);
  b.set_state(snapshot);
  run(b, 50);  // history in b before restoring again
  b.set_state(snapshot);
  run(a, 300);
  run(b, 300);
  EXPECT_TRUE(bit_identical(a.state(), b.state()));
  EXPECT_NEAR(a.state().vehicles[0].body.X_WB.translation().z(), -99.8, 5e-3);  // resting
}

TEST(SimulationTest, NonFiniteStateFromSetStateIsResetAndFlagged) {
  const Model model = one_auv_model(at(Eigen::Vector3d(0, 0, -20), 0.3));
  Simulation sim(model);
  ASSERT_EQ(sim.set_controls(0, {0.5, 0.5, 0.5}), "");
  run(sim, 100);
  SimState bad = sim.state();
  bad.vehicles[0].body.v_WB.y() = kNaN;
  sim.set_state(bad);
  const VehicleState& vehicle = sim.state().vehicles[0];
  EXPECT_NE(vehicle.faults & kFaultNonFiniteState, 0u);
  EXPECT_EQ(vehicle.fault_resets, 1u);
  EXPECT_TRUE(vehicle.body.X_WB.isApprox(model.vehicles[0].X_WB_initial, 0.0));
  EXPECT_TRUE(vehicle.body.v_WB.isZero(0.0));
  EXPECT_EQ(std::get<Thruster>(vehicle.actuators[0]).rotor_speed_rev_s, 0.0);
  EXPECT_EQ(vehicle.client_controls, std::vector<double>({0.0, 0.0, 0.0}));

  // From then on it moves exactly like a vehicle that starts at rest at the initial pose.
  Simulation reference(model);
  ASSERT_EQ(reference.set_controls(0, {0.0, 0.0, 0.0}), "");
  run(sim, 50);
  run(reference, 50);
  EXPECT_EQ(sim.state().vehicles[0].body.X_WB.matrix(),
            reference.state().vehicles[0].body.X_WB.matrix());
  EXPECT_NE(sim.state().vehicles[0].faults & kFaultNonFiniteState, 0u);  // latched
  EXPECT_EQ(sim.state().vehicles[0].fault_resets, 1u);
}

// Found by the command fuzzer (tests/fuzz/command_fuzz.cc): a reset to a finite but absurd position (1e300 m)
// was accepted, and the altimeter's ray from there, its mount added, started at -inf: Embree's guard threw
// out of the step and ended the server. Beyond 1000 km of the origin a reset pose is refused, and a state
// that gets there is a fault like a non-finite one.
TEST(SimulationTest, PositionsBeyondTheWorldBoundAreRefusedOrReset) {
  const Model model = one_auv_model(at(Eigen::Vector3d(0, 0, -20), 0.3));
  Simulation sim(model);
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() = Eigen::Vector3d(0.0, -1e300, -50.0);
  EXPECT_EQ(sim.reset(1, {far}), "reset: vehicle 'auv': position beyond 1000 km of the world origin");
  far.translation().y() = -0.99e6;  // within the bound: fine
  EXPECT_EQ(sim.reset(1, {far}), "");
  SimState outside = sim.state();
  outside.vehicles[0].body.X_WB.translation().x() = 2e6;
  sim.set_state(outside);
  EXPECT_NE(sim.state().vehicles[0].faults & kFaultNonFiniteState, 0u);
  EXPECT_TRUE(sim.state().vehicles[0].body.X_WB.isApprox(model.vehicles[0].X_WB_initial, 0.0));
  run(sim, 10);
  Model beyond = model;
  beyond.vehicles[0].X_WB_initial.translation().x() = 1.5e6;
  EXPECT_THROW(Simulation{beyond}, std::invalid_argument);
}

TEST(SimulationTest, NonFiniteStateFromTheStepIsResetAndFlagged) {
  // 1e300 m/s against quadratic damping overflows the force to -inf inside the step; Bullet
  // integrates it to NaN (and disables the body when its bounding box overflows). The check after
  // the step resets the vehicle and it simulates normally afterwards.
  const Model model = one_auv_model();
  Simulation sim(model);
  SimState wild = sim.state();
  wild.vehicles[0].body.v_WB = Eigen::Vector3d(1e300, 0.0, 0.0);
  sim.set_state(wild);
  EXPECT_EQ(sim.state().vehicles[0].fault_resets, 0u);  // finite so far
  sim.step();
  const VehicleState& vehicle = sim.state().vehicles[0];
  EXPECT_NE(vehicle.faults & kFaultNonFiniteState, 0u);
  EXPECT_EQ(vehicle.fault_resets, 1u);
  EXPECT_TRUE(vehicle.body.X_WB.isApprox(model.vehicles[0].X_WB_initial, 0.0));
  EXPECT_EQ(sim.state().step_count, 1u);

  Simulation reference(model);
  ASSERT_EQ(sim.set_controls(0, {1.0, 0.0, 0.0}), "");
  ASSERT_EQ(reference.set_controls(0, {1.0, 0.0, 0.0}), "");
  run(sim, 100);
  run(reference, 100);
  EXPECT_EQ(sim.state().vehicles[0].body.X_WB.matrix(),
            reference.state().vehicles[0].body.X_WB.matrix());
  EXPECT_EQ(sim.state().vehicles[0].fault_resets, 1u);
}

TEST(SimulationTest, TwoLinkCompositeMassProperties) {
  // Two boxes 2 m apart on B-x (masses 3 and 1): com at x = 0.5, I_yy gains mu d^2 = 0.75 * 4 = 3.
  VehicleSpec vehicle;
  vehicle.links = {testing::box_link("fore", 3.0, Eigen::Vector3d(0.1, 0.1, 0.1), 0.0,
                                     at(Eigen::Vector3d(1, 0, 0))),
                   testing::box_link("aft", 1.0, Eigen::Vector3d(0.1, 0.1, 0.1), 0.0,
                                     at(Eigen::Vector3d(-1, 0, 0)))};
  vehicle.fluid.model = FluidModelType::kLumped;  // no volume, no damping: no fluid forces
  vehicle.fluid.added_mass.model = AddedMassModel::kNone;  // rigid-body kinematics only
  Model model = testing::water_model({vehicle});
  model.world.gravity_W.setZero();
  Simulation sim(model);
  const physics::MassProperties& props = sim.mass_properties(0);
  const double I_box = 4.0 * 0.02 / 12.0;  // sum of m (0.1^2 + 0.1^2) / 12
  EXPECT_DOUBLE_EQ(props.mass, 4.0);
  EXPECT_TRUE(props.p_BBcm.isApprox(Eigen::Vector3d(0.5, 0, 0)));
  EXPECT_NEAR(props.I_BBcm_B(0, 0), I_box, 1e-12);
  EXPECT_NEAR(props.I_BBcm_B(1, 1), I_box + 3.0, 1e-12);
  EXPECT_NEAR(props.I_BBcm_B(2, 2), I_box + 3.0, 1e-12);

  // Spinning about B-z at rate w with no forces: the centre of mass stays put while B's origin
  // circles it, v_WB = w x (p_WB - p_WBcm), and after a quarter turn the vehicle is yawed by pi/2.
  // Bullet's exponential-map rotation update is exact for a constant axis; round-off: 1e-9.
  SimState spin = sim.state();
  const double w = 0.5;
  spin.vehicles[0].body.w_WB = Eigen::Vector3d(0, 0, w);
  spin.vehicles[0].body.v_WB = Eigen::Vector3d(0, -0.5 * w, 0);  // w x (0 - (0.5, 0, 0))
  sim.set_state(spin);
  const double quarter_turn = EIGEN_PI / 2 / w;
  const int steps = static_cast<int>(std::lround(quarter_turn * sim.model().world.physics_rate_hz));
  run(sim, steps);
  const RigidBodyState& body = sim.state().vehicles[0].body;
  const double yaw = w * steps * sim.model().world.step_size();
  EXPECT_LT((body.X_WB * props.p_BBcm - Eigen::Vector3d(0.5, 0, 0)).norm(), 1e-9);
  EXPECT_NEAR(std::atan2(body.X_WB.linear()(1, 0), body.X_WB.linear()(0, 0)), yaw, 1e-9);
  const Eigen::Vector3d p_WBcm = body.X_WB * props.p_BBcm;
  EXPECT_LT((body.v_WB - body.w_WB.cross(body.X_WB.translation() - p_WBcm)).norm(), 1e-9);
}

TEST(SimulationTest, RejectsUnsimulatableModelsAndForeignStates) {
  Model model = one_auv_model();
  model.vehicles[0].actuators[1].link_index = 3;
  EXPECT_THROW(Simulation{model}, std::invalid_argument);
  Simulation sim(one_auv_model());
  SimState other = sim.state();
  other.vehicles[0].actuators.pop_back();
  EXPECT_THROW(sim.set_state(other), std::invalid_argument);
  other.vehicles.clear();
  EXPECT_THROW(sim.set_state(other), std::invalid_argument);
}

// --- surface fluid model ---------------------------------------------------------------------------

using testing::box_shape;
using testing::drag_only;
using testing::surface_vehicle;

// Wall-sided box floating at draft T = m / (rho A), A the waterplane area, whatever g (rho = 1000
// here). Released 2 cm above equilibrium; C_D = 20 damps the heave (period ~1 s with the heave
// added mass; quadratic damping shrinks the amplitude like 1/t) and does not move the equilibrium.
// After 30 s, the draft stays within 1 % of T over the next second (more than one heave period).
TEST(SimulationTest, SurfaceModelBoxFloatsAtDraftMOverRhoA) {
  const Eigen::Vector3d size(1.0, 0.6, 0.4);
  const double rho = 1000.0, mass = 0.3 * rho * size.prod();
  const double draft = mass / (rho * size.x() * size.y());  // 0.12 m
  const double z_eq = -draft + 0.5 * size.z();
  Simulation sim(testing::water_model({surface_vehicle(box_shape(size), mass,
                                                       physics::solid_box_inertia(mass, size),
                                                       drag_only(20.0), Eigen::Vector3d(0, 0, z_eq + 0.02))}));
  run(sim, 15000);
  double min_draft = 1.0, max_draft = 0.0;
  for (int k = 0; k < 500; ++k) {
    sim.step();
    const double draft_now = 0.5 * size.z() - sim.state().vehicles[0].body.X_WB.translation().z();
    min_draft = std::min(min_draft, draft_now);
    max_draft = std::max(max_draft, draft_now);
  }
  EXPECT_GT(min_draft, 0.99 * draft);
  EXPECT_LT(max_draft, 1.01 * draft);
  EXPECT_LT(sim.state().vehicles[0].body.w_WB.norm(), 1e-3);  // no heel or trim from a symmetric box
}

// A sphere twice as dense as the water falls at the terminal velocity of the kernel's drag law:
// (m - rho V) g = 1/2 rho C_D K v^2 with K = sum over the faces the flow hits (n_z < 0) of
// A |n_z|^3 and V the mesh's volume (buoyancy integrates the pressure over the same mesh). After
// 8 s (~15 time constants v_t / g') within 2 %; measured to O(dt) integration error.
TEST(SimulationTest, SurfaceModelSphereReachesTerminalVelocity) {
  const double rho = 1000.0, g = 9.80665, R = 0.2, C_D = 1.0;
  CollisionShape sphere;
  sphere.type = CollisionShapeType::kSphere;
  sphere.radius = R;
  const geometry::MeshProperties mesh = geometry::compute_mesh_properties(geometry::tessellate(sphere));
  double K = 0.0;
  for (std::size_t f = 0; f < mesh.face_area.size(); ++f) {
    if (mesh.normal_z[f] < 0.0) K -= mesh.face_area[f] * std::pow(mesh.normal_z[f], 3);
  }
  const double mass = 2.0 * rho * mesh.volume;
  const double v_t = std::sqrt((mass - rho * mesh.volume) * g / (0.5 * rho * C_D * K));
  Simulation sim(testing::water_model({surface_vehicle(sphere, mass, physics::solid_sphere_inertia(mass, R),
                                                       drag_only(C_D), Eigen::Vector3d(0, 0, -10))}));
  run(sim, 4000);
  const RigidBodyState& body = sim.state().vehicles[0].body;
  EXPECT_NEAR(-body.v_WB.z(), v_t, 0.02 * v_t);
  EXPECT_LT(body.v_WB.head<2>().norm(), 1e-3 * v_t);
}

// A neutrally buoyant box in a uniform current (world.water.current.uniform) drifts with it: the
// relative flow decays like 1 / (1 + t / tau), tau = (m + m_a) / (1/2 rho C_D A |u|) < 0.8 s with
// C_D = 20 (added mass m_a <= m for this box), so after 20 s the velocity is within 2 % of the
// current.
TEST(SimulationTest, SurfaceModelBodyDriftsWithAUniformCurrent) {
  const Eigen::Vector3d size(1.0, 0.4, 0.4), current_W(0.5, -0.2, 0.0);
  const double rho = 1000.0, mass = rho * size.prod();
  physics::HydrodynamicCoefficients c = drag_only(20.0);
  c.skin_friction = 0.004;
  Model model = testing::water_model({surface_vehicle(box_shape(size), mass,
                                                      physics::solid_box_inertia(mass, size), c,
                                                      Eigen::Vector3d(0, 0, -20))});
  model.world.water.current.uniform_W = current_W;
  Simulation sim(std::move(model));
  run(sim, 10000);
  const RigidBodyState& body = sim.state().vehicles[0].body;
  EXPECT_LT((body.v_WB - current_W).norm(), 0.02 * current_W.norm()) << body.v_WB.transpose();
  EXPECT_NEAR(body.X_WB.translation().z(), -20.0, 0.01);
}

TEST(SimulationTest, SurfaceModelVehicleWithoutFacesIsRejected) {
  VehicleSpec vehicle = surface_vehicle(box_shape(Eigen::Vector3d(1, 1, 1)), 1.0,
                                        Eigen::Matrix3d::Identity(), {}, Eigen::Vector3d(0, 0, -5));
  vehicle.links[0].collisions.clear();
  try {
    Simulation sim(testing::water_model({vehicle}));
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "vehicle 'body': fluid model 'surface' needs a hydrodynamic mesh: no link has a mesh or "
                 "collision shapes");
  }
}

}  // namespace
}  // namespace hadal
