// Cables in the simulation (physics/cable.h, Simulation::step_cables): a heavy box hanging on a cable from a fixed
// point settles where the cable, stretched by the box's and its own weight, puts it, and the fixed point carries
// both wet weights; a cable on an arm's link holds it about its joint; a winch hauls the box up; a reset lays the cable straight between its ends where they now are; a restored state
// continues bit for bit.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>

#include "hadal/config/scenario_loader.h"
#include "hadal/core/simulation.h"
#include "hadal/physics/test_models.h"

namespace hadal {
namespace {

using physics::testing::at;

constexpr double kG = 9.80665;

// A 1 x 0.4 x 0.4 m box of 160 kg displacing 0.08 m^3 (wet weight 80 kg g in water of 1000 kg/m^3), damped, hung
// from (0, 0, -10) by 20 m of 20 mm rope (3000 kg/m^3, EA 1e6 N) attached 0.2 m above its centre.
Model hanging_box() {
  VehicleSpec box;
  box.name = "box";
  const Eigen::Vector3d size(1.0, 0.4, 0.4);
  box.links.push_back(physics::testing::box_link("hull", 160.0, size, 0.08));
  box.fluid.model = FluidModelType::kLumped;
  box.fluid.linear_damping << 200, 200, 200, 50, 50, 50;
  box.X_WB_initial = at(Eigen::Vector3d(0.0, 0.0, -30.2));
  Model model = physics::testing::water_model({box});
  physics::CableModel cable;
  cable.name = "rope";
  cable.spec.length = 20.0;
  cable.spec.segments = 20;
  cable.spec.diameter = 0.02;
  cable.spec.density = 3000.0;
  cable.spec.axial_stiffness = 1.0e6;
  cable.spec.damping_s = 0.01;
  cable.ends[0].position = Eigen::Vector3d(0.0, 0.0, -10.0);
  cable.ends[1].vehicle = "box";
  cable.ends[1].vehicle_index = 0;
  cable.ends[1].position = Eigen::Vector3d(0.0, 0.0, 0.2);
  model.cables = {cable};
  return model;
}

// A scenario written to a temporary file and loaded (its errors fail the test).
std::optional<Model> load_yaml(const std::string& name, const std::string& yaml) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << yaml;
  const config::LoadResult loaded = config::load_scenario_file(path.string());
  std::filesystem::remove(path);
  EXPECT_TRUE(loaded.model) << (loaded.errors.empty() ? "" : loaded.errors.front().format());
  return loaded.model;
}

// Steps the simulation 10000 times and returns the mean z force of cable 0 on its `from` end over the last 2000
// (several periods of whatever still bounces).
double mean_fixed_end_fz(Simulation& sim) {
  double mean_fz = 0.0;
  for (int k = 0; k < 10000; ++k) {
    sim.step();
    if (k >= 8000) mean_fz += sim.state().cables[0].f_W_ends[0].z() / 2000.0;
  }
  return mean_fz;
}

// At rest the fixed point carries the box's and the cable's wet weight, and the box hangs the stretched length
// below it: each segment stretched by the weight below its middle, (W + w (L - s)) / EA per metre. 1 % of the
// weight, 1 cm of position: what is left of the settling after 20 s.
TEST(SimulationCableTest, ABoxHangsOnItsCableAndTheFixedPointCarriesBoth) {
  Simulation sim(hanging_box());
  for (int k = 0; k < 10000; ++k) sim.step();
  const physics::CableSpec& spec = sim.model().cables[0].spec;
  const double box = (160.0 - 1000.0 * 0.08) * kG;
  const double rope = (spec.density - 1000.0) * spec.area() * kG;  // per metre
  const physics::CableState& cable = sim.state().cables[0];
  EXPECT_NEAR(cable.f_W_ends[0].z(), -(box + rope * spec.length), 0.01 * box);
  EXPECT_NEAR(cable.f_W_ends[1].z(), box, 0.01 * box);  // the cable holds the box up
  const double stretch = (box * spec.length + rope * spec.length * spec.length / 2.0) / spec.axial_stiffness;
  const Eigen::Vector3d p_WB = sim.state().vehicles[0].body.X_WB.translation();
  EXPECT_NEAR(p_WB.z(), -10.0 - spec.length - stretch - 0.2, 0.01) << "stretch " << stretch << " m";
  EXPECT_NEAR(p_WB.x(), 0.0, 1e-6);
  EXPECT_TRUE(cable.p_W.back().isApprox(sim.state().vehicles[0].body.X_WB * Eigen::Vector3d(0.0, 0.0, 0.2), 1e-9));
}

// A reset with a pose lays the cable straight from its fixed end to the box's point where the box now is.
TEST(SimulationCableTest, AResetLaysTheCableBetweenItsEnds) {
  Simulation sim(hanging_box());
  for (int k = 0; k < 500; ++k) sim.step();
  ASSERT_EQ(sim.reset(1, {at(Eigen::Vector3d(5.0, 0.0, -25.0))}), "");
  const physics::CableState& cable = sim.state().cables[0];
  EXPECT_TRUE(cable.p_W.front().isApprox(Eigen::Vector3d(0.0, 0.0, -10.0)));
  EXPECT_TRUE(cable.p_W.back().isApprox(Eigen::Vector3d(5.0, 0.0, -24.8)));
  EXPECT_TRUE(cable.p_W[10].isApprox(Eigen::Vector3d(2.5, 0.0, -17.4)));
  for (const Eigen::Vector3d& v : cable.v_W) EXPECT_TRUE(v.isZero());
}

// A state taken mid-swing and restored continues bit for bit, cable included.
TEST(SimulationCableTest, ARestoredStateContinuesBitIdentically) {
  Model model = hanging_box();
  model.vehicles[0].X_WB_initial = at(Eigen::Vector3d(6.0, 0.0, -28.0));  // it swings
  Simulation a(model), b(model);
  for (int k = 0; k < 300; ++k) a.step();
  b.set_state(a.state());
  for (int k = 0; k < 300; ++k) a.step(), b.step();
  const auto& ca = a.state().cables[0];
  const auto& cb = b.state().cables[0];
  for (std::size_t i = 0; i < ca.p_W.size(); ++i) {
    EXPECT_EQ(std::memcmp(ca.p_W[i].data(), cb.p_W[i].data(), 3 * sizeof(double)), 0) << i;
    EXPECT_EQ(std::memcmp(ca.v_W[i].data(), cb.v_W[i].data(), 3 * sizeof(double)), 0) << i;
  }
  EXPECT_EQ(std::memcmp(a.state().vehicles[0].body.X_WB.data(), b.state().vehicles[0].body.X_WB.data(),
                        16 * sizeof(double)),
            0);
}

// An articulated vehicle (a frame with an arm on a revolute joint, the surface fluid model) hangs on a cable tied to its
// base: the fixed point carries the frame's, the arm's and the rope's wet weight (1 %, on average over the
// vehicle's bounce), and the arm hangs on.
TEST(SimulationCableTest, AnArticulatedVehicleHangsFromItsBase) {
  const std::optional<Model> model = load_yaml("hadal_cable_articulated.yaml", R"(world:
  water: {density: 1000.0}
  seabed: {type: plane, z: -200.0}
vehicles:
  - name: rov
    type: rov
    initial_pose: {position: [0, 0, -30.5]}
    links:
      - {name: frame, mass: 600, inertia: {ixx: 60, iyy: 60, izz: 60}, collisions: [{shape: box, size: [1.0, 0.8, 0.6]}]}
      - {name: arm, pose: {position: [0.6, 0, -0.2]}, mass: 20, inertia: {ixx: 0.5, iyy: 0.5, izz: 0.5},
         collisions: [{shape: box, size: [0.4, 0.1, 0.1]}],
         joint: {type: revolute, axis: [0, 1, 0], lower_deg: -90, upper_deg: 90, damping: 20}}
    fluid: {model: surface}
cables:
  - {name: rope, length: 20, segments: 20, diameter: 0.02, density: 3000, axial_stiffness: 1.0e6, damping_s: 0.01,
     from: {position: [0, 0, -10]}, to: {vehicle: rov, link: frame, position: [0, 0, 0.5]}}
)");
  ASSERT_TRUE(model);
  Simulation sim(*model);
  // The vehicle bounces on the rope's stretch (~7 rad/s), damped only by its quadratic drag: the force on the
  // fixed point is averaged over the last 4 s (several periods).
  const double mean_fz = mean_fixed_end_fz(sim);
  const physics::CableSpec& spec = sim.model().cables[0].spec;
  const double vehicle = (600.0 - 1000.0 * 0.48 + 20.0 - 1000.0 * 0.004) * kG;  // the boxes' displacement
  const double rope = (spec.density - 1000.0) * spec.area() * kG * spec.length;
  EXPECT_NEAR(mean_fz, -(vehicle + rope), 0.01 * vehicle);
  const Eigen::Vector3d p_WB = sim.state().vehicles[0].body.X_WB.translation();
  EXPECT_LT(p_WB.z(), -30.0);
  EXPECT_GT(p_WB.z(), -31.0);
  EXPECT_TRUE(std::isfinite(sim.state().vehicles[0].joint_positions[0]));
}

// A boom on a revolute joint (about y) of a fixed crane, held level by a cable from a point above its tip: the cable
// on the moving link takes the boom's wet weight about the joint, T = W_wet x_cm / x_tip (0.5 m and 0.8 m apart, so a
// cable acting at the wrong point, or on the base body, or not at all lets the boom fall), and the neutrally buoyant
// rope passes it to the fixed point whole (1 %, averaged over the last 4 s).
TEST(SimulationCableTest, ACableHoldsABoomOnAJointAtItsTip) {
  const std::optional<Model> model = load_yaml("hadal_cable_boom.yaml", R"(world:
  water: {density: 1000.0}
  seabed: {type: plane, z: -200.0}
vehicles:
  - name: crane
    type: lander
    static: true
    initial_pose: {position: [0, 0, -20]}
    links:
      - {name: post, mass: 100, inertia: {ixx: 10, iyy: 10, izz: 10}, collisions: [{shape: box, size: [0.2, 0.2, 0.2]}]}
      - {name: boom, pose: {position: [0.2, 0, 0]}, mass: 30, center_of_mass: [0.5, 0, 0],
         inertia: {ixx: 0.1, iyy: 2.5, izz: 2.5},
         collisions: [{shape: box, size: [1.0, 0.1, 0.1], pose: {position: [0.5, 0, 0]}}],
         joint: {type: revolute, axis: [0, 1, 0], lower_deg: -90, upper_deg: 90, damping: 50}}
    fluid: {model: surface}
cables:
  - {name: stay, length: 5, segments: 10, diameter: 0.01, density: 1000, axial_stiffness: 1.0e5, damping_s: 0.01,
     from: {position: [1.0, 0, -15]}, to: {vehicle: crane, link: boom, position: [0.8, 0, 0]}}
)");
  ASSERT_TRUE(model);
  Simulation sim(*model);
  const double mean_fz = mean_fixed_end_fz(sim);
  const double boom = (30.0 - 1000.0 * 0.01) * kG;  // its weight and buoyancy both act 0.5 m out
  const double tension = boom * 0.5 / 0.8;
  EXPECT_NEAR(mean_fz, -tension, 0.01 * tension);
  EXPECT_NEAR(sim.state().cables[0].f_W_ends[1].z(), tension, 0.01 * tension);  // it holds the boom up
  // Level but for the rope's stretch (T L / EA = 6 mm at 0.8 m): a few milliradians down (positive about y).
  const double q = sim.state().vehicles[0].joint_positions[0];
  EXPECT_GT(q, 0.0);
  EXPECT_LT(q, 0.02);
  const Eigen::Vector3d tip = sim.state().cables[0].p_W.back();
  EXPECT_NEAR(tip.x(), 1.0, 1e-3);
  EXPECT_NEAR(tip.z(), -20.0 - 0.8 * std::sin(q), 1e-6);
}

// A winch at the fixed point hauls the hanging box up from 20 m to 10 m of rope and stops there: the box then hangs
// 10 m and the stretch below the point (1 cm), the winch at rest. Commands it cannot follow are refused, naming the
// key, with its state untouched.
TEST(SimulationCableTest, AWinchHaulsTheBoxUpAndStopsAtItsTarget) {
  Model model = hanging_box();
  model.cables[0].ends[0].winch = physics::WinchSpec{50.0, 2.0, 1.0, 0.5};
  Simulation sim(model);
  EXPECT_EQ(sim.command_winch(0, 2.0, 0.0), "winch: speed 2 m/s is beyond the winch's max_speed (1 m/s)");
  EXPECT_EQ(sim.command_winch(0, 0.5, 60.0), "winch: target_length 60 m is beyond the drum (drum_length 50 m)");
  EXPECT_EQ(sim.command_winch(1, 0.5, 10.0), "unknown cable");
  EXPECT_EQ(sim.state().cables[0].winch.command_speed, 0.0);
  ASSERT_EQ(sim.command_winch(sim.model().cable_index("rope"), 0.5, 10.0), "");
  for (int k = 0; k < 20000; ++k) sim.step();  // 40 s: ~21 s of hauling, then settling
  const physics::CableState& cable = sim.state().cables[0];
  EXPECT_EQ(cable.length, 10.0);
  EXPECT_EQ(cable.winch.speed, 0.0);
  const physics::CableSpec& spec = sim.model().cables[0].spec;
  const double box = (160.0 - 1000.0 * 0.08) * kG;
  const double rope = (spec.density - 1000.0) * spec.area() * kG;
  const double stretch = (box * 10.0 + rope * 10.0 * 10.0 / 2.0) / spec.axial_stiffness;
  EXPECT_NEAR(sim.state().vehicles[0].body.X_WB.translation().z(), -10.0 - 10.0 - stretch - 0.2, 0.01);
  EXPECT_NEAR(cable.f_W_ends[0].z(), -(box + rope * 10.0), 0.01 * box);
}

}  // namespace
}  // namespace hadal
