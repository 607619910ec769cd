// Buoyancy engine: the bladder's volume follows the command at the pump's rate, its buoyancy and moment,
// and the pump's energy against the closed form (p - p_atm) Delta V / eta; the valve costs nothing.
#include "hadal/physics/buoyancy_engine.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hadal/core/model.h"
#include "hadal/physics/ocean.h"

namespace hadal::physics {
namespace {

constexpr double kDt = 0.01;

BuoyancyEngineActuator::Spec pump() {
  BuoyancyEngineActuator::Spec spec;
  spec.p_LE = Eigen::Vector3d(0.7, 0.0, 0.0);
  spec.max_volume_change = 2.5e-4;  // 250 cm^3 each way
  spec.pump_rate = 1e-5;            // 10 cm^3/s
  spec.efficiency = 0.4;
  return spec;
}

TEST(BuoyancyEngine, PumpsAtItsRateAndPaysForDepth) {
  const WorldSpec world;  // constant density 1025 kg/m^3
  const Ocean ocean(world);
  const BuoyancyEngineActuator::Spec spec = pump();
  const Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();
  const auto runtime = BuoyancyEngineActuator::prepare(spec, ActuatorSetup{X_BL, 1025.0, kDt, 0});
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.translation() = Eigen::Vector3d(0.0, 0.0, -200.0);
  const Eigen::Vector3d p_WBcm = X_WB.translation();
  ActuatorForceInput in{X_WB, p_WBcm, 0.0};
  in.ocean = &ocean;

  BuoyancyEngineActuator::State state;
  double setpoint = 1.0;  // out to +250 cm^3: 25 s
  BuoyancyEngineActuator::command(state, &setpoint);
  StepWrench out;
  for (int k = 1; k <= 3000; ++k) {
    BuoyancyEngineActuator::actuate(runtime, state);
    out = StepWrench{};
    BuoyancyEngineActuator::add_wrench(runtime, state, in, out);
    ASSERT_NEAR(state.volume_change, std::min(k * 1e-7, 2.5e-4), 1e-15) << k;
  }
  // Buoyancy at the bladder, 0.7 m ahead of the centre of mass: rho g Delta V up, a nose-up moment.
  const double F = 1025.0 * ocean.gravity() * 2.5e-4;
  EXPECT_NEAR(out.f_W.z(), F, 1e-9);
  EXPECT_NEAR(out.tau_W.y(), -0.7 * F, 1e-9);
  EXPECT_NEAR(state.volume_rate, 0.0, 1e-15);
  // Energy: the gauge pressure at the bladder (200 m down) times the volume pumped, over the efficiency.
  const double gauge = ocean.pressure(200.0) - world.water.atmospheric_pressure;
  EXPECT_NEAR(state.energy_J / (gauge * 2.5e-4 / 0.4), 1.0, 1e-9);
  EXPECT_GT(state.energy_J, 1000.0);  // ~1.3 kJ

  // Back in to -250 cm^3 through the valve: the energy stays.
  const double spent = state.energy_J;
  setpoint = -1.0;
  BuoyancyEngineActuator::command(state, &setpoint);
  for (int k = 0; k < 6000; ++k) {
    BuoyancyEngineActuator::actuate(runtime, state);
    BuoyancyEngineActuator::add_wrench(runtime, state, in, out);
  }
  EXPECT_NEAR(state.volume_change, -2.5e-4, 1e-15);
  EXPECT_EQ(state.energy_J, spent);
  EXPECT_EQ(state.power_W, 0.0);
}

TEST(BuoyancyEngine, NoBuoyancyInAirAndSetpointsChecked) {
  const WorldSpec world;
  const Ocean ocean(world);
  const BuoyancyEngineActuator::Spec spec = pump();
  const Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();
  const auto runtime = BuoyancyEngineActuator::prepare(spec, ActuatorSetup{X_BL, 1025.0, kDt, 0});
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.translation() = Eigen::Vector3d(0.0, 0.0, 0.5);
  ActuatorForceInput in{X_WB, X_WB.translation(), 0.0};
  in.ocean = &ocean;
  BuoyancyEngineActuator::State state;
  state.volume_change = 1e-4;
  StepWrench out;
  BuoyancyEngineActuator::add_wrench(runtime, state, in, out);
  EXPECT_EQ(out.f_W.norm(), 0.0);
  const double nan = std::nan("");
  EXPECT_EQ(BuoyancyEngineActuator::check(spec, &nan, 0), "setpoint[0] is NaN");
}

}  // namespace
}  // namespace hadal::physics
