// Simulation tests of the rigid-body and added-mass dynamics (physics/added_mass.h, world.dynamics):
// closed forms for added mass at depth, the Munk moment, Earth-rotation Coriolis, the gyroscopic
// moment, drift with a current, and the contact load of a body resting on the seabed.
#include "hadal/core/simulation.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include "hadal/config/scenario_loader.h"
#include "hadal/geometry/mesh_properties.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/physics/mass_properties.h"
#include "hadal/physics/ocean.h"
#include "hadal/physics/test_models.h"

namespace hadal {
namespace {

namespace testing = physics::testing;

constexpr double kRho = 1000.0;  // testing::water_model
constexpr double kG = 9.80665;

void run(Simulation& sim, int steps) {
  for (int k = 0; k < steps; ++k) sim.step();
}

CollisionShape sphere_shape(double radius) {
  CollisionShape sphere;
  sphere.type = CollisionShapeType::kSphere;
  sphere.radius = radius;
  return sphere;
}

// A capsule of radius r along B's x axis (cylindrical part `length`).
CollisionShape capsule_along_x(double radius, double length) {
  CollisionShape capsule;
  capsule.type = CollisionShapeType::kCapsule;
  capsule.radius = radius;
  capsule.length = length;
  capsule.X_LG.linear() = Eigen::AngleAxisd(EIGEN_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return capsule;
}

double mesh_volume(const CollisionShape& shape) {
  return geometry::compute_mesh_properties(geometry::tessellate(shape)).volume;
}

// A sphere twice as dense as the water, released at rest with every fluid term but buoyancy off,
// accelerates at a = (m - rho V) g / (m + kappa(d) m_a): the effective added mass inferred from the
// measured acceleration is kappa(d) M_A0 at 10 m and at 3000 m. Semi-implicit Euler integrates a
// constant force exactly, and kappa changes by rho g dz / K ~ 1e-5 over the 1.6 m the sphere sinks in
// 1 s, so the inferred m_a matches to 1e-4 relative (kappa(3000 m) = 0.986 differs by 1.4e-2).
TEST(SimulationDynamicsTest, AddedMassAtDepthIsKappaTimesSurfaceAddedMass) {
  const double R = 0.2;
  const CollisionShape sphere = sphere_shape(R);
  const double volume = mesh_volume(sphere);
  const double mass = 2.0 * kRho * volume;
  for (double depth : {10.0, 3000.0}) {
    Model model = testing::water_model({testing::surface_vehicle(
        sphere, mass, physics::solid_sphere_inertia(mass, R), testing::drag_only(0.0),
        Eigen::Vector3d(0, 0, -depth))});
    model.world.seabed.z = -5000.0;
    Simulation sim(std::move(model));
    const Matrix6d& M_A0 = sim.added_mass(0);
    // The tessellated sphere's equivalent ellipsoid is a sphere to within the faceting (< 1 %).
    EXPECT_NEAR(M_A0(2, 2), 0.5 * kRho * volume, 0.01 * kRho * volume);
    const double kappa = sim.ocean().kappa(depth);
    const int steps = 500;
    run(sim, steps);
    const double a = sim.state().vehicles[0].body.v_WB.z() / (steps * sim.model().world.step_size());
    const double m_a_effective = -(mass - kRho * volume) * kG / a - mass;
    EXPECT_NEAR(m_a_effective / M_A0(2, 2), kappa, 1e-4) << "depth " << depth;
    // Sideways only the float kernel's rounding (~1e-7 of the buoyancy per face sum) pushes.
    EXPECT_NEAR(sim.state().vehicles[0].body.v_WB.head<2>().norm(), 0.0, 1e-6);
  }
}

// A neutrally buoyant slender capsule (no drag, no friction) moving forward with sideslip feels the
// Munk moment N = -(m_22 - m_11) u v about z: it yaws away from the flow, r_dot = N / (I_zz + m_66).
// Over the first 10 steps u, v change by < 1e-3 relative, hence 1 %. Without the added-mass
// Coriolis terms nothing turns it.
TEST(SimulationDynamicsTest, MunkMomentTurnsASlenderBodyAcrossTheFlow) {
  const double r = 0.1, length = 1.0;
  const CollisionShape capsule = capsule_along_x(r, length);
  const double mass = kRho * mesh_volume(capsule);
  const Eigen::Matrix3d I = physics::solid_cylinder_inertia(mass, r, length + 2 * r);
  const Eigen::Matrix3d I_B = capsule.X_LG.linear() * I * capsule.X_LG.linear().transpose();
  const double u = 1.0, v = 0.2;
  for (bool coriolis : {true, false}) {
    VehicleSpec vehicle = testing::surface_vehicle(capsule, mass, I_B, testing::drag_only(0.0),
                                                   Eigen::Vector3d(0, 0, -20));
    vehicle.fluid.added_mass.coriolis = coriolis;
    vehicle.v_WB_initial = Eigen::Vector3d(u, v, 0);
    Simulation sim(testing::water_model({vehicle}));
    const Matrix6d& M = sim.added_mass(0);
    ASSERT_GT(M(1, 1), 5.0 * M(0, 0));  // slender
    const int steps = 10;
    run(sim, steps);
    const double r_dot = sim.state().vehicles[0].body.w_WB.z() / (steps * sim.model().world.step_size());
    if (coriolis) {
      const double expected = -(M(1, 1) - M(0, 0)) * u * v / (I_B(2, 2) + M(5, 5));
      EXPECT_LT(r_dot, 0.0);
      EXPECT_NEAR(r_dot, expected, 0.01 * std::abs(expected));
      // Destabilising: the angle between the body axis and its velocity keeps growing.
      run(sim, 500);
      const RigidBodyState& body = sim.state().vehicles[0].body;
      const Eigen::Vector3d v_B = body.X_WB.linear().transpose() * body.v_WB;
      EXPECT_GT(std::atan2(v_B.y(), v_B.x()), std::atan2(v, u) + 0.05);
    } else {
      EXPECT_LT(std::abs(r_dot), 1e-4);
    }
  }
}

// Earth rotation in the inertial limit: a body in air (no fluid), no gravity, moving east at 10 m/s
// at 45 deg N. dv/dt = -2 Omega x v rotates v about Omega at rate 2 |Omega|, so with theta = 2 |Omega| t,
// k = Omega / |Omega| and v0 = v_par + v_perp (along and across k):
//   p(t) - p0 = v_par t + sin(theta) / (2 |Omega|) v_perp - (1 - cos(theta)) / (2 |Omega|) k x v_perp.
// The body veers south (right of its track, northern hemisphere) and up (Eotvos). Semi-implicit Euler
// errs by ~ |a| t dt / 2 = 3e-4 m after 200 s; tolerance 1e-3 m of a ~29 m deflection.
TEST(SimulationDynamicsTest, EarthRotationCoriolisMatchesTheInertialCircle) {
  const Eigen::Vector3d size(1.0, 0.5, 0.5), v0(10.0, 0.0, 0.0);
  const double mass = 100.0, latitude = EIGEN_PI / 4, seconds = 200.0;
  for (bool earth_rotation : {true, false}) {
    VehicleSpec vehicle = testing::surface_vehicle(testing::box_shape(size), mass,
                                                   physics::solid_box_inertia(mass, size),
                                                   testing::drag_only(1.0), Eigen::Vector3d(0, 0, 50));
    vehicle.v_WB_initial = v0;
    Model model = testing::water_model({vehicle});
    model.world.gravity_W.setZero();
    model.world.origin.latitude_rad = latitude;
    model.world.dynamics.earth_rotation = earth_rotation;
    Simulation sim(std::move(model));
    const int steps = static_cast<int>(seconds * sim.model().world.physics_rate_hz);
    run(sim, steps);
    const Eigen::Vector3d p = sim.state().vehicles[0].body.X_WB.translation() - Eigen::Vector3d(0, 0, 50);
    if (!earth_rotation) {
      // A straight line up to round-off: 1e5 position updates of ~2 km, eps 2.2e-16 each: 4.4e-8.
      EXPECT_LT((p - v0 * seconds).norm(), 1e-7);
      continue;
    }
    const double rate = sim.model().world.dynamics.earth_rotation_rate;
    const Eigen::Vector3d k(0.0, std::cos(latitude), std::sin(latitude));
    const Eigen::Vector3d v_par = v0.dot(k) * k, v_perp = v0 - v_par;
    const double theta = 2.0 * rate * seconds;
    const Eigen::Vector3d expected = v_par * seconds + std::sin(theta) / (2 * rate) * v_perp -
                                     (1 - std::cos(theta)) / (2 * rate) * k.cross(v_perp);
    EXPECT_LT((p - expected).norm(), 1e-3) << p.transpose() << " vs " << expected.transpose();
    EXPECT_LT(p.y(), -20.0);  // south
    EXPECT_GT(p.z(), 10.0);   // up
  }
}

// Torque-free rigid body spinning near its major axis, in air without gravity. With the gyroscopic
// moment (default) its angular momentum L_W = R I R^T w is conserved while w precesses; Bullet's
// implicit gyroscopic step is first order, so L drifts by O(dt) -- under 1 % in 10 s here. Without
// it, w_W stays constant (to round-off) and L does not.
TEST(SimulationDynamicsTest, GyroscopicMomentConservesAngularMomentum) {
  const Eigen::Vector3d size(1.0, 0.6, 0.2), w0(0.3, 0.2, 2.0);
  const double mass = 50.0;
  const Eigen::Matrix3d I_B = physics::solid_box_inertia(mass, size);
  for (bool gyroscopic : {true, false}) {
    VehicleSpec vehicle = testing::surface_vehicle(testing::box_shape(size), mass, I_B,
                                                   testing::drag_only(1.0), Eigen::Vector3d(0, 0, 50));
    vehicle.fluid.added_mass.model = AddedMassModel::kNone;
    Model model = testing::water_model({vehicle});
    model.world.gravity_W.setZero();
    model.world.dynamics.gyroscopic = gyroscopic;
    Simulation sim(std::move(model));
    SimState state = sim.state();
    state.vehicles[0].body.w_WB = w0;
    sim.set_state(state);
    const Eigen::Vector3d L0 = I_B * w0;
    run(sim, 5000);
    const RigidBodyState& body = sim.state().vehicles[0].body;
    const Eigen::Matrix3d R = body.X_WB.linear();
    const Eigen::Vector3d L = R * I_B * R.transpose() * body.w_WB;
    if (gyroscopic) {
      EXPECT_LT((L - L0).norm(), 0.01 * L0.norm());
      EXPECT_GT((body.w_WB - w0).norm(), 0.1);  // it precesses
    } else {
      EXPECT_LT((body.w_WB - w0).norm(), 1e-12);
      EXPECT_GT((L - L0).norm(), 0.05 * L0.norm());
    }
  }
}

// Lumped fluid model: a neutrally buoyant box in a uniform current drifts with it. Relative velocity
// decays with time constant (m + m_a) / D_l < 2 m / D_l = 3.2 s here, so after 30 s it is below
// e^-9 of the initial 0.32 m/s (quadratic damping only speeds this up).
TEST(SimulationDynamicsTest, LumpedModelBodyDriftsWithAUniformCurrent) {
  const Eigen::Vector3d size(1.0, 0.4, 0.4), current_W(0.3, 0.1, 0.0);
  const double mass = kRho * size.prod();
  VehicleSpec vehicle;
  vehicle.name = "box";
  vehicle.links = {testing::box_link("hull", mass, size, size.prod())};
  vehicle.fluid.model = FluidModelType::kLumped;
  vehicle.fluid.linear_damping << 100, 100, 100, 10, 10, 10;
  vehicle.fluid.quadratic_damping << 50, 50, 50, 5, 5, 5;
  vehicle.X_WB_initial = testing::at(Eigen::Vector3d(0, 0, -20));
  Model model = testing::water_model({vehicle});
  model.world.water.current.uniform_W = current_W;
  Simulation sim(std::move(model));
  run(sim, 15000);
  const RigidBodyState& body = sim.state().vehicles[0].body;
  EXPECT_LT((body.v_WB - current_W).norm(), 1e-3) << body.v_WB.transpose();
  EXPECT_NEAR(body.X_WB.translation().z(), -20.0, 0.01);
}

// A negatively buoyant box with added mass settles on the seabed and presses on it with its full
// submerged weight (m - rho V) g: the contact wrench of the previous step feeds the added-mass solve
// (without it the seabed would carry only m / (m + m_a) of it). Bullet's contact solver converges to
// ~1 % in a resting contact, hence 2 %.
TEST(SimulationDynamicsTest, BodyOnTheSeabedPressesWithItsSubmergedWeight) {
  const Eigen::Vector3d size(1.0, 1.0, 0.5);
  const double mass = 2.0 * kRho * size.prod();
  VehicleSpec vehicle = testing::surface_vehicle(
      testing::box_shape(size), mass, physics::solid_box_inertia(mass, size),
      testing::drag_only(5.0), Eigen::Vector3d(0, 0, -100.0 + 0.5 * size.z() + 0.2));
  Simulation sim(testing::water_model({vehicle}));
  ASSERT_GT(sim.added_mass(0)(2, 2), 0.5 * mass);
  run(sim, 2500);
  const VehicleState& state = sim.state().vehicles[0];
  const double submerged_weight = (mass - kRho * size.prod()) * kG;
  EXPECT_NEAR(state.contact_wrench_B.z(), submerged_weight, 0.02 * submerged_weight);
  EXPECT_LT(state.body.v_WB.norm(), 1e-3);
  EXPECT_NEAR(state.body.X_WB.translation().z(), -100.0 + 0.5 * size.z(), 0.02);
}

// The default AUV (configs/vehicles/torpedo_auv.yaml, surface fluid model with added mass) holds a
// straight course under thrust: its fins overcome the Munk moment. The default scenario's first
// schedule leg (main 0.6 for 25 s) ends near the steady speed; heading, roll and sideslip stay small
// (propeller torque heels it slightly; the slow rise from ~1 N of buoyancy is the only other
// disturbance). Printed figures are for the README/docs/benchmarks.md tables.
TEST(SimulationDynamicsTest, DefaultAuvHoldsItsCourseUnderThrust) {
  const config::LoadResult loaded =
      config::load_scenario_file(std::string(HADAL_SOURCE_DIR) + "/configs/scenarios/default.yaml");
  ASSERT_TRUE(loaded.model) << (loaded.errors.empty() ? "" : loaded.errors.front().format());
  Model model = *loaded.model;
  // Dynamics only: the camera's frames (rendered on the ray-cast workers) do not act on the vehicle.
  std::vector<SensorSpec>& sensors = model.vehicles[0].sensors;
  sensors.erase(std::remove_if(sensors.begin(), sensors.end(), [](const SensorSpec& s) { return s.type() == "camera"; }),
                sensors.end());
  Simulation sim(model);
  run(sim, 12000);  // 24 s
  const RigidBodyState& body = sim.state().vehicles[0].body;
  const Eigen::Matrix3d& R = body.X_WB.linear();
  const Eigen::Vector3d v_B = R.transpose() * body.v_WB;
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  const double roll = std::atan2(R(2, 1), R(2, 2));
  const double pitch = -std::asin(R(2, 0));
  constexpr double kDeg = 180.0 / 3.14159265358979323846;
  std::printf("default AUV after 24 s: p_W = [%.3f %.3f %.3f] m, v_B = [%.4f %.4f %.4f] m/s, roll %.2f, "
              "pitch %.2f, yaw %.3f deg\n", body.X_WB.translation().x(), body.X_WB.translation().y(),
              body.X_WB.translation().z(), v_B.x(), v_B.y(), v_B.z(), roll * kDeg, pitch * kDeg, yaw * kDeg);
  EXPECT_GT(v_B.x(), 0.9);
  EXPECT_LT(std::abs(v_B.y()), 0.02 * v_B.x());
  EXPECT_LT(std::abs(yaw) * kDeg, 1.0);
  EXPECT_LT(std::abs(roll) * kDeg, 5.0);
  EXPECT_LT(std::abs(pitch) * kDeg, 5.0);
  EXPECT_LT(std::abs(body.X_WB.translation().z() + 96.0), 1.0);  // its 4 m survey altitude
}

// Two vehicles with 4k+-face hulls: their fluid forces are computed on the worker pool, and each
// trajectory is bit-identical to the same vehicle simulated alone (serially).
TEST(SimulationDynamicsTest, ParallelFluidForcesEqualSerialBitForBit) {
  auto fine_sphere_vehicle = [](const std::string& name, const Eigen::Vector3d& p_W) {
    const double R = 0.3, mass = 0.8 * kRho * 4.0 / 3.0 * EIGEN_PI * R * R * R;
    VehicleSpec vehicle = testing::surface_vehicle(sphere_shape(R), mass,
                                                   physics::solid_sphere_inertia(mass, R),
                                                   physics::HydrodynamicCoefficients{}, p_W);
    vehicle.name = name;
    LinkMesh mesh;
    mesh.mesh = std::make_shared<geometry::TriangleMesh>(geometry::tessellate(sphere_shape(R), 72));
    mesh.closed = true;
    vehicle.links[0].mesh = mesh;
    vehicle.v_WB_initial = Eigen::Vector3d(0.5, -0.2, 0.1);
    return vehicle;
  };
  const VehicleSpec a = fine_sphere_vehicle("a", Eigen::Vector3d(0, 0, -20));
  VehicleSpec b = fine_sphere_vehicle("b", Eigen::Vector3d(5, 0, -0.1));  // crossing the surface
  b.v_WB_initial = Eigen::Vector3d(-0.3, 0.4, 0.0);
  Model both = testing::water_model({a, b});
  both.world.water.current.uniform_W = Eigen::Vector3d(0.2, 0.1, 0.0);
  Model only_a = both, only_b = both;
  only_a.vehicles = {a};
  only_b.vehicles = {b};
  Model serial = both;
  serial.world.threads = 1;  // world.threads caps the helpers: the stepping thread alone
  Model two = both;
  two.world.threads = 2;     // helpers however many cores this machine has
  Simulation sim(two), sim_a(only_a), sim_b(only_b), sim_serial(serial);
  ASSERT_EQ(sim.fluid_helper_threads(), 1u);
  ASSERT_EQ(sim_a.fluid_helper_threads(), 0u);
  ASSERT_EQ(sim_serial.fluid_helper_threads(), 0u);
  for (int k = 0; k < 300; ++k) {
    sim.step();
    sim_a.step();
    sim_b.step();
    sim_serial.step();
  }
  for (int i = 0; i < 2; ++i) {  // the same numbers on one thread as on two
    EXPECT_TRUE(sim.state().vehicles[i].body.X_WB.matrix() == sim_serial.state().vehicles[i].body.X_WB.matrix());
    EXPECT_TRUE(sim.state().vehicles[i].body.v_WB == sim_serial.state().vehicles[i].body.v_WB);
  }
  const RigidBodyState& pa = sim.state().vehicles[0].body;
  const RigidBodyState& pb = sim.state().vehicles[1].body;
  EXPECT_TRUE(pa.X_WB.matrix() == sim_a.state().vehicles[0].body.X_WB.matrix());
  EXPECT_TRUE(pa.v_WB == sim_a.state().vehicles[0].body.v_WB);
  EXPECT_TRUE(pb.X_WB.matrix() == sim_b.state().vehicles[0].body.X_WB.matrix());
  EXPECT_TRUE(pb.w_WB == sim_b.state().vehicles[0].body.w_WB);
  EXPECT_GT((pa.X_WB.translation() - Eigen::Vector3d(0, 0, -20)).norm(), 0.1);  // it moved
}

// A hull part that lies entirely inside another one changes nothing: the outer box alone and the
// outer box with a box inside it (the overlap counted once, the inner faces meeting no flow) follow
// the same path through a current, to float rounding of the kernel (~1e-6 relative).
TEST(SimulationDynamicsTest, HullPartInsideAnotherChangesNothing) {
  const Eigen::Vector3d outer(1.2, 0.5, 0.4), inner(0.6, 0.3, 0.2);
  const double mass = 0.9 * kRho * outer.prod();
  VehicleSpec alone = testing::surface_vehicle(testing::box_shape(outer), mass,
                                               physics::solid_box_inertia(mass, outer),
                                               physics::HydrodynamicCoefficients{}, Eigen::Vector3d(0, 0, -20));
  VehicleSpec nested = alone;
  CollisionShape inside = testing::box_shape(inner);
  inside.X_LG.translation() = Eigen::Vector3d(0.2, 0.05, -0.05);
  nested.links[0].collisions.push_back(inside);
  std::vector<Eigen::Vector3d> end;
  for (const VehicleSpec& vehicle : {alone, nested}) {
    Model model = testing::water_model({vehicle});
    model.world.water.current.uniform_W = Eigen::Vector3d(0.4, 0.2, 0.0);
    Simulation sim(std::move(model));
    run(sim, 2500);
    end.push_back(sim.state().vehicles[0].body.X_WB.translation());
  }
  EXPECT_GT((end[0] - Eigen::Vector3d(0, 0, -20)).norm(), 1.0);  // it moved (rose and drifted)
  EXPECT_LT((end[1] - end[0]).norm(), 1e-4) << end[0].transpose() << " vs " << end[1].transpose();
}

// Two overlapping spheres of a neutrally buoyant hull (mass = rho times the union's volume) stay at
// depth: the lens between them displaces water once.
TEST(SimulationDynamicsTest, OverlappingHullPartsDisplaceTheirUnionOnce) {
  const double R = 0.2, d = 0.2;
  CollisionShape fore = sphere_shape(R), aft = sphere_shape(R);
  fore.X_LG.translation() = Eigen::Vector3d(0.5 * d, 0, 0);
  aft.X_LG.translation() = Eigen::Vector3d(-0.5 * d, 0, 0);
  // The union of the tessellated spheres, minus the lens the simulator takes back: the smooth lens
  // pi (4R + d)(2R - d)^2 / 12 (geometry/shape_overlap.h estimates it to 1e-3).
  const double lens = EIGEN_PI * (4 * R + d) * (2 * R - d) * (2 * R - d) / 12.0;
  const double union_volume = 2.0 * mesh_volume(fore) - lens;
  const double mass = kRho * union_volume;
  VehicleSpec vehicle = testing::surface_vehicle(fore, mass, physics::solid_sphere_inertia(mass, R),
                                                 physics::HydrodynamicCoefficients{}, Eigen::Vector3d(0, 0, -20));
  vehicle.links[0].collisions.push_back(aft);
  Simulation sim(testing::water_model({vehicle}));
  run(sim, 2500);
  // Residual lift from the 1e-3 estimate: 1e-3 * lens * rho g ~ 0.1 N on ~57 kg (+ added mass) with
  // quadratic drag: well under a centimetre in 5 s. Without the correction it would rise metres.
  EXPECT_LT(std::abs(sim.state().vehicles[0].body.X_WB.translation().z() + 20.0), 0.02);
}

}  // namespace
}  // namespace hadal
