// The zoo's vehicles in-process (configs/scenarios/*.yaml), where the model's own forces can be read
// back: the glider's steady glide against the lift and drag its fluid model gives at that state.
#include "hadal/core/simulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hadal/config/scenario_loader.h"
#include "hadal/core/units.h"
#include "hadal/physics/actuators.h"
#include "hadal/physics/fluid_forces.h"
#include "hadal/physics/mass_properties.h"
#include "hadal/physics/ocean.h"

namespace hadal {
namespace {

struct Glide {
  double path_angle_deg;     // gamma from the velocity: below the horizontal when diving (> 0)
  double predicted_deg;      // atan(D / L) from the fluid model at the same state
  double hydrodynamic_N;     // |L + D|
  double net_buoyancy_N;     // what it must carry: (B - W) + the engine's
  double speed;              // [m/s]
};

// The glide at the current state of `sim`: the fluid model's force at the vehicle's velocity less its
// force at rest (the hydrostatic part) is lift and drag; D along -v, L across v.
Glide glide_of(const Simulation& sim, const Model& model) {
  const VehicleSpec& glider = model.vehicles[0];
  const VehicleState& vehicle = sim.state().vehicles[0];
  const physics::MassProperties mass = physics::composite_mass_properties(glider.links);
  const physics::Ocean ocean(model.world);
  const physics::VehicleFluid fluid = physics::make_vehicle_fluid(glider, model.world, ocean, mass.p_BBcm);
  std::vector<physics::ActuatorKindState> actuators = vehicle.actuators;
  const auto force_at = [&](const RigidBodyState& body) {
    const Eigen::Vector3d p_WBcm = body.X_WB * mass.p_BBcm;
    const Eigen::Vector3d v_WBcm = body.v_WB + body.w_WB.cross(p_WBcm - body.X_WB.translation());
    const physics::ForceInput in{sim.state().time, body, p_WBcm, v_WBcm, actuators};
    physics::StepWrench out;
    fluid.force->add(in, out);
    return out.f_W;
  };
  RigidBodyState at_rest = vehicle.body;
  at_rest.v_WB.setZero();
  at_rest.w_WB.setZero();
  const Eigen::Vector3d hydrostatic_W = force_at(at_rest);
  const Eigen::Vector3d dynamic_W = force_at(vehicle.body) - hydrostatic_W;
  const Eigen::Vector3d v_W = vehicle.body.v_WB;
  const Eigen::Vector3d along = v_W.normalized();
  const double D = -dynamic_W.dot(along);
  const double L = (dynamic_W + D * along).norm();
  const auto& engine = std::get<physics::BuoyancyEngineActuator::State>(vehicle.actuators[0]);
  Glide g;
  g.path_angle_deg = std::atan2(-v_W.z(), v_W.head<2>().norm()) / kDegToRad;
  g.predicted_deg = std::atan2(D, L) / kDegToRad;
  g.hydrodynamic_N = dynamic_W.norm();
  g.net_buoyancy_N = hydrostatic_W.z() - mass.mass * ocean.gravity() + engine.force_N;
  g.speed = v_W.norm();
  return g;
}

// configs/scenarios/glider.yaml: heavy by the engine's 250 cm^3 the glider dives, light it climbs. Once
// steady (150 s into each 200 s leg), its flight path is the one its own lift and drag give:
// tan(gamma) = D / L, to 0.1 deg (the residual of a state still settling), and the lift and drag carry
// exactly the net buoyancy (1 %). Measured: 24.320 deg down against 24.319 predicted, 24.006 deg up
// against 24.005, at 0.256 and 0.252 m/s, carrying 2.53 N and 2.49 N.
TEST(SimulationZoo, TheGliderGlidesAtTheAngleItsLiftAndDragGive) {
  const config::LoadResult loaded = config::load_scenario_file(HADAL_SOURCE_DIR "/configs/scenarios/glider.yaml");
  ASSERT_TRUE(loaded.model) << loaded.errors.front().format();
  const Model& model = *loaded.model;
  Simulation sim(model);
  const double dt = model.world.step_size();
  const auto run_to = [&](double t) {
    for (int k = static_cast<int>(std::lround((t - sim.state().time) / dt)); k > 0; --k) sim.step();
  };
  run_to(150.0);
  const Glide dive = glide_of(sim, model);
  run_to(350.0);
  const Glide climb = glide_of(sim, model);
  for (const Glide& g : {dive, climb}) {
    EXPECT_NEAR(std::abs(g.path_angle_deg), std::abs(g.predicted_deg), 0.1);
    EXPECT_NEAR(g.hydrodynamic_N, std::abs(g.net_buoyancy_N), 0.01 * std::abs(g.net_buoyancy_N));
    // A glider's glide: between 15 and 35 degrees, a few tenths of a metre per second.
    EXPECT_GT(std::abs(g.path_angle_deg), 15.0);
    EXPECT_LT(std::abs(g.path_angle_deg), 35.0);
    EXPECT_GT(g.speed, 0.15);
  }
  EXPECT_GT(dive.path_angle_deg, 0.0);   // down
  EXPECT_LT(climb.path_angle_deg, 0.0);  // up
  EXPECT_LT(dive.net_buoyancy_N, 0.0);
  EXPECT_GT(climb.net_buoyancy_N, 0.0);
  // Net buoyancy: the engine's 250 cm^3 of seawater, +-2.5 N, and the hull's trim (neutral within 0.3 N).
  EXPECT_NEAR(std::abs(dive.net_buoyancy_N), 1025.0 * 9.80665 * 2.5e-4, 0.3);
}

}  // namespace
}  // namespace hadal

namespace hadal {
namespace {

// configs/scenarios/own_vehicle.yaml: the AUV whose hull is a GLB mesh (configs/vehicles/mesh_hull_auv.yaml)
// gets its physics from that mesh. Its displaced volume is the closed mesh's, 0.05185261 m^3 as
// hadal-mesh-info prints it; at rest the surface model's pressure integral over its 2304 faces is the
// buoyancy rho g V straight up (the divergence theorem is exact for a pressure linear in depth over planar
// faces). Tolerance 1e-7 relative: the mesh keeps its vertices in single precision (geometry/triangle_mesh.h)
// and ~3e5 Pa of absolute pressure over its 1.1 m^2 cancels down to 521 N (measured: 2.5e-9 vertically,
// 1e-8 across). Under thrust it drives forward.
TEST(SimulationZoo, TheMeshHulledAuvFloatsOnItsMeshVolumeAndDrives) {
  const config::LoadResult loaded = config::load_scenario_file(HADAL_SOURCE_DIR "/configs/scenarios/own_vehicle.yaml");
  ASSERT_TRUE(loaded.model) << loaded.errors.front().format();
  const Model& model = *loaded.model;
  const VehicleSpec& auv = model.vehicles[0];
  ASSERT_TRUE(auv.links[0].mesh.has_value());
  const double volume = auv.links[0].mesh->volume;
  EXPECT_NEAR(volume, 0.05185261244146982, 1e-12);
  const physics::MassProperties mass = physics::composite_mass_properties(auv.links);
  EXPECT_EQ(mass.mass, 53.0);
  const physics::Ocean ocean(model.world);
  const physics::VehicleFluid fluid = physics::make_vehicle_fluid(auv, model.world, ocean, mass.p_BBcm);
  RigidBodyState rest;
  rest.X_WB = auv.X_WB_initial;
  std::vector<physics::ActuatorKindState> actuators = physics::VehicleActuators::initial_states(auv);
  const Eigen::Vector3d p_WBcm = rest.X_WB * mass.p_BBcm;
  const physics::ForceInput in{0.0, rest, p_WBcm, Eigen::Vector3d::Zero(), actuators};
  physics::StepWrench out;
  fluid.force->add(in, out);
  const double buoyancy = 1025.0 * ocean.gravity() * volume;
  EXPECT_NEAR(out.f_W.z(), buoyancy, 1e-7 * buoyancy);
  EXPECT_NEAR(out.f_W.head<2>().norm(), 0.0, 1e-7 * buoyancy);

  Simulation sim(model);
  for (int k = 0; k < 10000; ++k) sim.step();  // 20 s at 500 Hz on 0.6 main thrust
  const Eigen::Vector3d p = sim.state().vehicles[0].body.X_WB.translation();
  EXPECT_GT(p.x(), 20.0);                     // over 1 m/s forward
  EXPECT_LT(std::abs(p.y()), 0.5);            // straight
  EXPECT_LT(std::abs(p.z() + 20.0), 3.0);     // near its depth
}

}  // namespace
}  // namespace hadal
