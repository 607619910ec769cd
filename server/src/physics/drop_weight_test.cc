// Drop weight: its wet weight and moment while attached, and each trigger (command, altitude, time)
// releasing it for good with the time and the reason kept.
#include "hadal/physics/drop_weight.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hadal/core/model.h"
#include "hadal/physics/ocean.h"

namespace hadal::physics {
namespace {

using Release = DropWeightActuator::Release;

DropWeightActuator::Spec weight() {
  DropWeightActuator::Spec spec;
  spec.p_LW = Eigen::Vector3d(0.4, -0.3, -0.5);
  spec.mass = 25.0;
  spec.volume = 25.0 / DropWeightActuator::kSteelDensity;
  return spec;
}

struct Lander {
  WorldSpec world;
  Ocean ocean{world};
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  Eigen::Vector3d p_WBcm = Eigen::Vector3d::Zero();
  DropWeightActuator::Runtime runtime;
  DropWeightActuator::State state;

  explicit Lander(const DropWeightActuator::Spec& spec) {
    const Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();
    runtime = DropWeightActuator::prepare(spec, ActuatorSetup{X_BL, 1025.0, 0.01, 0});
    X_WB.translation() = Eigen::Vector3d(0.0, 0.0, -80.0);
    p_WBcm = X_WB.translation();
  }
  StepWrench step(double time, double seabed_z = -std::numeric_limits<double>::infinity(), double command = 0.0) {
    DropWeightActuator::command(state, &command);
    ActuatorForceInput in{X_WB, p_WBcm, 0.0};
    in.time = time;
    in.ocean = &ocean;
    in.seabed_z_below = seabed_z;
    StepWrench out;
    DropWeightActuator::add_wrench(runtime, state, in, out);
    return out;
  }
};

TEST(DropWeight, AttachedItPullsWithItsWetWeight) {
  Lander lander(weight());
  const StepWrench out = lander.step(0.0);
  const double g = lander.ocean.gravity();
  const double wet = (1025.0 * 25.0 / 7850.0 - 25.0) * g;  // -212.4 N
  EXPECT_NEAR(out.f_W.z(), wet, 1e-9);
  EXPECT_NEAR(out.f_W.head<2>().norm(), 0.0, 1e-15);
  EXPECT_TRUE(out.tau_W.isApprox(Eigen::Vector3d(0.4, -0.3, -0.5).cross(Eigen::Vector3d(0, 0, wet)), 1e-12));
  EXPECT_TRUE(lander.state.attached());
  EXPECT_TRUE(std::isnan(lander.state.release_time));
}

TEST(DropWeight, CommandReleasesForGood) {
  Lander lander(weight());
  lander.step(0.0);
  const StepWrench released = lander.step(12.5, -100.0, 1.0);
  EXPECT_EQ(released.f_W.norm(), 0.0);
  EXPECT_EQ(lander.state.reason, Release::kCommand);
  EXPECT_EQ(lander.state.release_time, 12.5);
  // A later 0 does not bring it back.
  EXPECT_EQ(lander.step(13.0, -100.0, 0.0).f_W.norm(), 0.0);
  EXPECT_EQ(lander.state.release_time, 12.5);
  const double half = 0.5, one = 1.0, nan = std::nan("");
  EXPECT_EQ(DropWeightActuator::check(weight(), &half, 2), "setpoint[2] = 0.5 is not 0 (hold) or 1 (release)");
  EXPECT_EQ(DropWeightActuator::check(weight(), &nan, 2), "setpoint[2] is NaN, not 0 (hold) or 1 (release)");
  EXPECT_EQ(DropWeightActuator::check(weight(), &one, 2), "");
}

TEST(DropWeight, AltitudeAndTimeTriggers) {
  DropWeightActuator::Spec spec = weight();
  spec.release_altitude = 5.0;
  spec.release_time_s = 600.0;
  EXPECT_TRUE(DropWeightActuator::needs_seabed(spec));
  EXPECT_FALSE(DropWeightActuator::needs_seabed(weight()));
  {
    Lander lander(spec);
    lander.step(1.0, -90.0);  // 10 m up: attached
    EXPECT_TRUE(lander.state.attached());
    lander.step(2.0, -84.0);  // 4 m up
    EXPECT_EQ(lander.state.reason, Release::kAltitude);
    EXPECT_EQ(lander.state.release_time, 2.0);
  }
  {
    Lander lander(spec);
    lander.step(599.0);  // no seabed under it: only the timer
    EXPECT_TRUE(lander.state.attached());
    lander.step(600.0);
    EXPECT_EQ(lander.state.reason, Release::kTime);
  }
}

}  // namespace
}  // namespace hadal::physics
