// Simulation::reset on the default scenario (configs/scenarios/default.yaml): an episode started over
// from the initial state with the same seed repeats the first one bit for bit, sensor noise included;
// another seed changes the noise and nothing else; a pose given to reset places the vehicle there at rest.
#include "hadal/core/simulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "hadal/config/scenario_loader.h"
#include "hadal/sensors/imu_sensor.h"

namespace hadal {
namespace {

Model default_model() {
  const config::LoadResult loaded = config::load_scenario_file(HADAL_SOURCE_DIR "/configs/scenarios/default.yaml");
  if (!loaded.model) throw std::runtime_error(loaded.errors.front().format());
  return *loaded.model;
}

int sensor_index(const Model& model, const std::string& name) {
  const auto& sensors = model.vehicles[0].sensors;
  for (std::size_t k = 0; k < sensors.size(); ++k) {
    if (sensors[k].name == name) return static_cast<int>(k);
  }
  throw std::runtime_error("no sensor " + name);
}

// One episode: thrust for `steps` steps; the pose and the IMU's sample after each step, as raw doubles.
std::vector<double> episode(Simulation& sim, int steps) {
  const int imu = sensor_index(sim.model(), "imu");
  std::vector<double> trace;
  EXPECT_EQ(sim.set_controls(0, {0.6, 0.2, -0.1}), "");
  for (int k = 0; k < steps; ++k) {
    sim.step();
    const VehicleState& v = sim.state().vehicles[0];
    const auto& sample = state_of<sensors::ImuSensor>(v.sensors[static_cast<std::size_t>(imu)]);
    trace.push_back(sim.state().time);
    for (int i = 0; i < 3; ++i) trace.push_back(v.body.X_WB.translation()[i]);
    for (int i = 0; i < 3; ++i) trace.push_back(sample.specific_force_S[i]);
    for (int i = 0; i < 3; ++i) trace.push_back(sample.angular_velocity_S[i]);
  }
  return trace;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(SimulationReset, TheSameSeedRepeatsAnEpisodeBitForBit) {
  const Model model = default_model();
  Simulation sim(model);
  const std::vector<double> first = episode(sim, 400);
  ASSERT_EQ(sim.reset(model.world.seed), "");
  EXPECT_EQ(sim.state().time, 0.0);
  EXPECT_EQ(sim.state().step_count, 0u);
  EXPECT_EQ(sim.state().vehicles[0].command_source, CommandSource::kSchedule);  // its schedule again, no client
  EXPECT_TRUE(sim.state().vehicles[0].client_controls.empty());
  const std::vector<double> second = episode(sim, 400);
  EXPECT_TRUE(same_bits(first, second));

  Simulation fresh(model);  // and a reset instance is a fresh one
  EXPECT_TRUE(same_bits(episode(fresh, 400), first));
}

TEST(SimulationReset, AnotherSeedChangesTheNoiseOnly) {
  const Model model = default_model();
  Simulation sim(model);
  const std::vector<double> first = episode(sim, 400);
  ASSERT_EQ(sim.reset(model.world.seed + 1), "");
  const std::vector<double> second = episode(sim, 400);
  ASSERT_EQ(first.size(), second.size());
  double max_pose_difference = 0.0, max_imu_difference = 0.0;
  for (std::size_t i = 0; i < first.size(); i += 10) {
    for (int k = 1; k < 4; ++k) max_pose_difference = std::max(max_pose_difference, std::abs(first[i + k] - second[i + k]));
    for (int k = 4; k < 10; ++k) max_imu_difference = std::max(max_imu_difference, std::abs(first[i + k] - second[i + k]));
  }
  EXPECT_EQ(max_pose_difference, 0.0);  // the physics has no randomness
  EXPECT_GT(max_imu_difference, 0.0);   // the IMU's noise does
}

TEST(SimulationReset, AGivenPoseIsWhereTheVehicleStartsAtRest) {
  const Model model = default_model();
  Simulation sim(model);
  episode(sim, 100);
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.translate(Eigen::Vector3d(5.0, -3.0, -90.0));
  X_WB.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  ASSERT_EQ(sim.reset(3, {X_WB}), "");
  const RigidBodyState& body = sim.state().vehicles[0].body;
  EXPECT_TRUE(body.X_WB.isApprox(X_WB, 1e-15));
  EXPECT_EQ(body.v_WB.norm(), 0.0);
  EXPECT_EQ(body.w_WB.norm(), 0.0);
  sim.step();  // Bullet starts from there too
  EXPECT_LT((sim.state().vehicles[0].body.X_WB.translation() - X_WB.translation()).norm(), 1e-3);

  Eigen::Isometry3d bad = X_WB;
  bad.translation().x() = std::nan("");
  const SimState before = sim.state();
  EXPECT_EQ(sim.reset(3, {bad}), "reset: vehicle 'auv': pose is not finite");
  EXPECT_EQ(sim.state().step_count, before.step_count);  // untouched
  const std::vector<std::optional<Eigen::Isometry3d>> too_many(model.vehicles.size() + 1, X_WB);
  EXPECT_EQ(sim.reset(3, too_many), "reset: " + std::to_string(too_many.size()) + " poses for " +
                                        std::to_string(model.vehicles.size()) + " vehicles");
}

}  // namespace
}  // namespace hadal
