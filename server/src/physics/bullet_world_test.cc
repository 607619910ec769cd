#include "hadal/physics/bullet_world.h"
#include "hadal/geometry/terrain.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hadal/physics/lumped_fluid.h"
#include "hadal/physics/test_models.h"

namespace hadal::physics {
namespace {

constexpr double kG = 9.80665;

using testing::at;

// Two boxes on a diagonal: the centre of mass is offset from B and the principal axes are rotated,
// so the X_WB <-> X_WP conversion is exercised.
std::vector<LinkSpec> two_box_links() {
  return {testing::box_link("a", 30.0, Eigen::Vector3d(0.4, 0.2, 0.2), 0.0,
                            at(Eigen::Vector3d(0.5, 0.3, 0.1))),
          testing::box_link("b", 10.0, Eigen::Vector3d(0.2, 0.2, 0.2), 0.0,
                            at(Eigen::Vector3d(-0.4, -0.2, 0.0)))};
}

VehicleSpec box_vehicle(double mass, const Eigen::Vector3d& size, double volume,
                        const Eigen::Vector3d& p_WB) {
  VehicleSpec vehicle;
  vehicle.name = "box";
  vehicle.links.push_back(testing::box_link("hull", mass, size, volume));
  vehicle.X_WB_initial = at(p_WB);
  return vehicle;
}

// One step of the physics composition the Simulation uses: fluid wrench at B's origin, then Bullet.
void step_with_fluid(BulletWorld& world, const LumpedFluid& fluid, double dt) {
  const RigidBodyState body = world.body_state(0);
  const LumpedFluidWrench w = fluid.wrench(body, Eigen::Vector3d::Zero());
  world.add_force_W(0, w.f_W(), body.X_WB.translation());
  world.add_torque_W(0, w.tau_W());
  world.step(dt);
}

TEST(BulletWorldTest, FreeFallMatchesSemiImplicitEulerClosedForm) {
  // Vacuum: water surface far below. The vehicle's centre of mass is offset from B and its
  // principal axes are rotated (two boxes on a diagonal), so the X_WB <-> X_WP conversion is
  // exercised.
  VehicleSpec vehicle;
  vehicle.links = two_box_links();
  const Eigen::Vector3d p0(5.0, -3.0, 50.0);
  vehicle.X_WB_initial =
      at(p0, Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  Model model = testing::water_model({vehicle});
  model.world.water.surface_z = -1000.0;
  model.world.seabed.z = -2000.0;
  BulletWorld world(model);
  ASSERT_FALSE(world.mass_properties(0).X_BP.linear().isIdentity(1e-6));

  const double dt = model.world.step_size();
  const int n = 1000;
  for (int k = 0; k < n; ++k) world.step(dt);
  const RigidBodyState s = world.body_state(0);

  // Semi-implicit Euler: v_k = -g k dt, z_N = z0 - g dt^2 N (N + 1) / 2. Bullet's arithmetic adds
  // ~N round-offs of the fall distance, i.e. ~1e-13 relative; 1e-9 relative is the stated bound.
  const double fall_discrete = kG * dt * dt * n * (n + 1) / 2.0;
  EXPECT_NEAR(s.X_WB.translation().z(), p0.z() - fall_discrete, 1e-9 * fall_discrete);
  EXPECT_NEAR(s.v_WB.z(), -kG * n * dt, 1e-9 * kG * n * dt);
  EXPECT_NEAR(s.X_WB.translation().x(), p0.x(), 1e-12);
  EXPECT_NEAR(s.X_WB.translation().y(), p0.y(), 1e-12);
  EXPECT_TRUE(s.X_WB.linear().isApprox(vehicle.X_WB_initial.linear(), 1e-12));
  // Continuous solution z0 - g t^2 / 2: the integrator's O(dt) error is exactly g t dt / 2.
  const double t = n * dt;
  const double bound = kG * t * dt / 2.0;
  EXPECT_LE(std::abs(s.X_WB.translation().z() - (p0.z() - kG * t * t / 2.0)), bound * (1.0 + 1e-9));
}

TEST(BulletWorldTest, NeutralBuoyancyStaysAtRest) {
  // rho V = m, fully submerged, centre of buoyancy straight above the centre of mass: no net force
  // and no moment. The residual is round-off in rho V g vs m g (~1e-16 relative), which in 2 s
  // integrates to ~1e-14 m/s; |v| < 1e-9 is the stated bound.
  VehicleSpec vehicle =
      box_vehicle(2.0, Eigen::Vector3d(0.2, 0.1, 0.1), 0.002, Eigen::Vector3d(0, 0, -10));
  vehicle.links[0].buoyancy.p_LCb = Eigen::Vector3d(0.0, 0.0, 0.1);
  const Model model = testing::water_model({vehicle});
  ASSERT_EQ(model.world.water.density * 0.002, 2.0);
  BulletWorld world(model);
  const LumpedFluid fluid(model.vehicles[0], model.world);
  for (int k = 0; k < 1000; ++k) step_with_fluid(world, fluid, model.world.step_size());
  const RigidBodyState s = world.body_state(0);
  EXPECT_LT(s.v_WB.norm(), 1e-9);
  EXPECT_LT(s.w_WB.norm(), 1e-9);
  EXPECT_LT((s.X_WB.translation() - Eigen::Vector3d(0, 0, -10)).norm(), 1e-9);
}

TEST(BulletWorldTest, PositiveBuoyancyAcceleratesAtNetOverMass) {
  // rho V = 1.25 m, no damping: a = (rho V - m) g / m = 0.25 g upward. After k steps of
  // semi-implicit Euler v = k a dt and dz = a dt^2 k (k + 1) / 2; round-off only (1e-12 relative).
  const double mass = 40.0;
  const Model model = testing::water_model({box_vehicle(
      mass, Eigen::Vector3d(0.5, 0.5, 0.2), 1.25 * mass / 1000.0, Eigen::Vector3d(0, 0, -30))});
  BulletWorld world(model);
  const LumpedFluid fluid(model.vehicles[0], model.world);
  const double dt = model.world.step_size();
  const double a = 0.25 * kG;
  step_with_fluid(world, fluid, dt);
  EXPECT_NEAR(world.body_state(0).v_WB.z(), a * dt, 1e-12 * a * dt);
  for (int k = 1; k < 10; ++k) step_with_fluid(world, fluid, dt);
  const RigidBodyState s = world.body_state(0);
  EXPECT_NEAR(s.v_WB.z(), 10 * a * dt, 1e-12 * 10 * a * dt);
  EXPECT_NEAR(s.X_WB.translation().z() + 30.0, a * dt * dt * 55.0, 1e-9 * a * dt * dt * 55.0);
}

TEST(BulletWorldTest, FloatingBoxSettlesAtDraughtOfMassOverDisplacement) {
  // Box 1 x 1 x 0.5 m, V = 0.5 m^3, rho V = 500 kg, m = 300 kg: equilibrium submerged fraction
  // s = m / (rho V) = 0.6, draught 0.3 m, so B (the box centre) floats at z = -0.3 + 0.25 = -0.05.
  // Heave: k = rho g A ~ 9.8 kN/m, m = 300 kg, damping 0.6 * 3000 N s/m -> zeta ~ 0.5, decay rate
  // ~3 /s; after 20 s the transient is ~e^-60 of the initial 0.25 m offset. The discrete fixed
  // point is exact (forces balance to round-off), so 1e-6 m only absorbs round-off and residual
  // motion.
  VehicleSpec vehicle =
      box_vehicle(300.0, Eigen::Vector3d(1.0, 1.0, 0.5), 0.5, Eigen::Vector3d(0, 0, 0.2));
  vehicle.fluid.linear_damping << 1000, 1000, 3000, 100, 100, 100;
  const Model model = testing::water_model({vehicle});
  BulletWorld world(model);
  const LumpedFluid fluid(model.vehicles[0], model.world);
  for (int k = 0; k < 10000; ++k) step_with_fluid(world, fluid, model.world.step_size());
  const RigidBodyState s = world.body_state(0);
  EXPECT_NEAR(s.X_WB.translation().z(), -0.05, 1e-6);
  EXPECT_NEAR(fluid.wrench(s, Eigen::Vector3d::Zero()).submerged_fraction, 0.6, 1e-6);
  EXPECT_LT(s.v_WB.norm(), 1e-6);
  EXPECT_TRUE(s.X_WB.linear().isIdentity(1e-9));
}

TEST(BulletWorldTest, TerminalVelocityIsRootOfLinearPlusQuadraticDamping) {
  // No gravity, so no buoyancy imbalance. A constant force F along the body x axis against
  // tau_u = -(a + b|u|) u: terminal speed u* = (-a + sqrt(a^2 + 4 b F)) / (2 b). The explicit force
  // evaluation has the same fixed point; the transient decays with time constant
  // m / (a + 2 b u*) ~ 0.5 s, so after 20 s it is e^-40 of u*: 1e-6 relative is met with margin.
  const double a = 50.0, b = 20.0, force = 100.0, mass = 50.0;
  const double u_terminal = (-a + std::sqrt(a * a + 4.0 * b * force)) / (2.0 * b);
  for (double yaw : {0.0, 0.6}) {
    VehicleSpec vehicle =
        box_vehicle(mass, Eigen::Vector3d(1.0, 0.3, 0.3), 0.09, Eigen::Vector3d(0, 0, -20));
    vehicle.X_WB_initial.linear() =
        Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    vehicle.fluid.linear_damping << a, 100, 100, 10, 10, 10;
    vehicle.fluid.quadratic_damping << b, 100, 100, 10, 10, 10;
    Model model = testing::water_model({vehicle});
    model.world.gravity_W.setZero();
    BulletWorld world(model);
    const LumpedFluid fluid(model.vehicles[0], model.world);
    const Eigen::Vector3d x_W = vehicle.X_WB_initial.linear() * Eigen::Vector3d::UnitX();
    for (int k = 0; k < 10000; ++k) {
      world.add_force_W(0, force * x_W, world.body_state(0).X_WB.translation());
      step_with_fluid(world, fluid, model.world.step_size());
    }
    const RigidBodyState s = world.body_state(0);
    const Eigen::Vector3d nu = s.X_WB.linear().transpose() * s.v_WB;
    EXPECT_NEAR(nu.x(), u_terminal, 1e-6 * u_terminal) << "yaw " << yaw;
    EXPECT_LT(nu.tail<2>().norm(), 1e-9) << "yaw " << yaw;
  }
}

TEST(BulletWorldTest, PrimitivesRestOnTheSeabedAtTheirHalfHeight) {
  // No water. Each vehicle drops 5 cm onto the seabed plane and rests with its lowest point on it:
  // box and upright cylinder at half their height, sphere and a lying capsule at their radius. The
  // contact solver may leave a residual penetration (split impulse; observed < 1e-9 m here) and the
  // shapes carry a collision margin <= 1 cm that Bullet keeps inside them; 1 mm bounds the former
  // and would catch a margin added outside the shape.
  Model model;
  model.world.water.surface_z = -1000.0;
  model.world.seabed.z = -50.0;
  auto one_shape = [](const std::string& name, CollisionShape shape, double x) {
    VehicleSpec vehicle;
    vehicle.name = name;
    LinkSpec link;
    link.mass = 20.0;
    link.I_LLcm_L = solid_sphere_inertia(20.0, 0.3);
    link.collisions.push_back(shape);
    vehicle.links.push_back(link);
    vehicle.X_WB_initial.translation() = Eigen::Vector3d(x, 0.0, 0.0);
    return vehicle;
  };
  CollisionShape box;
  box.type = CollisionShapeType::kBox;
  box.box_size = Eigen::Vector3d(0.6, 0.4, 0.3);
  CollisionShape sphere;
  sphere.type = CollisionShapeType::kSphere;
  sphere.radius = 0.25;
  CollisionShape cylinder;
  cylinder.type = CollisionShapeType::kCylinder;
  cylinder.radius = 0.2;
  cylinder.length = 0.5;
  CollisionShape capsule = cylinder;
  capsule.type = CollisionShapeType::kCapsule;
  capsule.X_LG.linear() =
      Eigen::AngleAxisd(EIGEN_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const double rest[] = {0.15, 0.25, 0.25, 0.2};
  model.vehicles = {one_shape("box", box, 0.0), one_shape("sphere", sphere, 3.0),
                    one_shape("cylinder", cylinder, 6.0), one_shape("capsule", capsule, 9.0)};
  for (int i = 0; i < 4; ++i)
    model.vehicles[i].X_WB_initial.translation().z() = -50.0 + rest[i] + 0.05;
  // A vehicle without collision shapes falls through.
  VehicleSpec ghost = model.vehicles[0];
  ghost.links[0].collisions.clear();
  ghost.X_WB_initial.translation().x() = 12.0;
  model.vehicles.push_back(ghost);

  BulletWorld world(model);
  for (int k = 0; k < 1000; ++k) world.step(model.world.step_size());
  for (int i = 0; i < 4; ++i) {
    const RigidBodyState s = world.body_state(i);
    EXPECT_NEAR(s.X_WB.translation().z(), -50.0 + rest[i], 1e-3) << model.vehicles[i].name;
    EXPECT_LT(s.v_WB.norm(), 1e-3) << model.vehicles[i].name;
    EXPECT_GT(world.num_contact_points(i), 0) << model.vehicles[i].name;
  }
  EXPECT_LT(world.body_state(4).X_WB.translation().z(), -60.0);
  EXPECT_EQ(world.num_contact_points(4), 0);
}

// A link's friction (LinkSpec::friction) times the seabed's 0.8 is the contact's Coulomb coefficient (Bullet
// multiplies the two). No water; a 20 kg box on the seabed pushed along x at its centre with 0.3 m g for 1 s:
// with friction 0.5 (mu = 0.4) it stays where it is; with 0.25 (mu = 0.2) it slides at (0.3 - 0.2) g, so
// 0.5 (0.1 g) t^2 = 0.490 m in 1 s. Bullet's iterative friction solve over the four contact points lands
// 2.9 % short (an effective mu of 0.203); 5 % bounds it, while the default friction (mu 0.4) would hold.
TEST(BulletWorldTest, ALinksFrictionTimesTheSeabedsHoldsOrSlidesABox) {
  Model model;
  model.world.water.surface_z = -1000.0;
  model.world.seabed.z = -50.0;
  const double m = 20.0, push = 0.3;
  for (const double friction : {0.5, 0.25}) {
    VehicleSpec vehicle = box_vehicle(m, Eigen::Vector3d(0.6, 0.4, 0.3), 0.0,
                                      Eigen::Vector3d(friction > 0.3 ? 0.0 : 3.0, 0.0, -50.0 + 0.15));
    vehicle.links[0].friction = friction;
    model.vehicles.push_back(vehicle);
  }
  BulletWorld world(model);
  const double dt = model.world.step_size();
  for (int k = 0; k < 100; ++k) world.step(dt);  // settle
  const double x0[] = {world.body_state(0).X_WB.translation().x(), world.body_state(1).X_WB.translation().x()};
  for (int k = 0; k < 500; ++k) {
    for (int i = 0; i < 2; ++i) {
      const RigidBodyState s = world.body_state(i);
      world.add_force_W(i, Eigen::Vector3d(push * m * kG, 0.0, 0.0), s.X_WB.translation());
    }
    world.step(dt);
  }
  ASSERT_EQ(model.world.physics_rate_hz, 500.0);
  EXPECT_LT(std::abs(world.body_state(0).X_WB.translation().x() - x0[0]), 1e-3);
  EXPECT_NEAR((world.body_state(1).X_WB.translation().x() - x0[1]) / (0.5 * (push - 0.2) * kG), 1.0, 0.05);
}

// A body clear of the flat seabed skips the narrow phase with it (bullet_world.cc, the seabed-aware near
// callback) and leaves no contact behind: a 20 kg box resting on the plane (contacts), pushed up with
// 2 m g for 0.3 s, rises 0.5 g t^2 = 0.44 m in free flight (within 5 mm: semi-implicit Euler adds
// g dt t / 2 = 3 mm) with no contact left; let go, it falls back
// and rests where it rested before (1e-3 m, the resting test's tolerance), with contacts again; moved 1 m
// up in one go, it keeps no stale contact (the skipped pair's manifold emptied).
TEST(BulletWorldTest, ABoxLiftedOffTheSeabedLeavesNoContactAndLandsAgain) {
  Model model;
  model.world.water.surface_z = -1000.0;
  model.world.seabed.z = -50.0;
  const double m = 20.0;
  model.vehicles.push_back(box_vehicle(m, Eigen::Vector3d(0.6, 0.4, 0.3), 0.0, Eigen::Vector3d(0, 0, -50.0 + 0.15)));
  BulletWorld world(model);
  const double dt = model.world.step_size();
  for (int k = 0; k < 200; ++k) world.step(dt);
  const double rest_z = world.body_state(0).X_WB.translation().z();
  ASSERT_GT(world.num_contact_points(0), 0);
  const int lift_steps = static_cast<int>(std::lround(0.3 / dt));
  for (int k = 0; k < lift_steps; ++k) {
    world.add_force_W(0, Eigen::Vector3d(0.0, 0.0, 2.0 * m * kG), world.body_state(0).X_WB.translation());
    world.step(dt);
  }
  EXPECT_EQ(world.num_contact_points(0), 0);
  EXPECT_NEAR(world.body_state(0).X_WB.translation().z() - rest_z, 0.5 * kG * 0.3 * 0.3, 5e-3);
  for (int k = 0; k < static_cast<int>(std::lround(3.0 / dt)); ++k) world.step(dt);
  EXPECT_NEAR(world.body_state(0).X_WB.translation().z(), rest_z, 1e-3);
  EXPECT_GT(world.num_contact_points(0), 0);
  // Moved 1 m up at once (a restored state, a reset), it keeps none of the contact it rested on.
  RigidBodyState up = world.body_state(0);
  up.X_WB.translation().z() += 1.0;
  world.set_body_state(0, up);
  world.step(dt);
  EXPECT_EQ(world.num_contact_points(0), 0);
}

TEST(BulletWorldTest, BoxesRestOnAMeshSeabedAtTheLocalHeight) {
  // A terrace: z = -50 for x <= -2, -48 for x >= 2, a ramp between. Boxes 0.3 m high dropped at
  // x = -6 and x = +6 rest with their bottoms on the local surface. The mesh carries a 1 mm collision
  // margin outside the surface (bullet_world.cc), so the rest height is surface + 0.15 m + 1 mm; 1 mm of
  // tolerance covers the solver's residual penetration.
  geometry::HeightField field;
  field.nx = 21;
  field.ny = 11;
  field.dx = field.dy = 1.0;
  field.x0 = -10.0;
  field.y0 = -5.0;
  for (int j = 0; j < field.ny; ++j) {
    for (int i = 0; i < field.nx; ++i) {
      const double x = field.x0 + i;
      field.heights.push_back(static_cast<float>(x <= -2.0 ? -50.0 : x >= 2.0 ? -48.0 : -49.0 + 0.5 * x));
    }
  }
  Model model;
  model.world.water.surface_z = -1000.0;
  model.world.seabed.type = SeabedType::kMesh;
  model.world.seabed.mesh = std::make_shared<const geometry::TriangleMesh>(geometry::heightfield_to_mesh(field));
  const double surface[] = {-50.0, -48.0};
  for (int k = 0; k < 2; ++k) {
    VehicleSpec vehicle;
    vehicle.name = k == 0 ? "low" : "high";
    vehicle.links = {testing::box_link("box", 20.0, Eigen::Vector3d(0.6, 0.4, 0.3), 0.0)};
    vehicle.X_WB_initial.translation() = Eigen::Vector3d(k == 0 ? -6.0 : 6.0, 0.3, surface[k] + 0.15 + 0.05);
    model.vehicles.push_back(vehicle);
  }
  BulletWorld world(model);
  for (int k = 0; k < 1000; ++k) world.step(model.world.step_size());
  for (int k = 0; k < 2; ++k) {
    const RigidBodyState s = world.body_state(k);
    EXPECT_NEAR(s.X_WB.translation().z(), surface[k] + 0.15 + 0.001, 1e-3) << model.vehicles[k].name;
    EXPECT_LT(s.v_WB.norm(), 1e-3) << model.vehicles[k].name;
    EXPECT_GT(world.num_contact_points(k), 0) << model.vehicles[k].name;
  }
}

TEST(BulletWorldTest, StateRoundTripsThroughPrincipalFrame) {
  // Writing a state and reading it back only costs the round-off of X_WB X_BP X_PB: 1e-12.
  VehicleSpec vehicle;
  vehicle.links = two_box_links();
  BulletWorld world(testing::water_model({vehicle}));
  RigidBodyState in;
  in.X_WB = at(Eigen::Vector3d(1, 2, -3),
               Eigen::Quaterniond(0.5, 0.1, -0.7, 0.2).normalized().toRotationMatrix());
  in.v_WB = Eigen::Vector3d(0.3, -0.2, 0.1);
  in.w_WB = Eigen::Vector3d(0.05, 0.4, -0.3);
  world.set_body_state(0, in);
  const RigidBodyState out = world.body_state(0);
  EXPECT_LT((out.X_WB.matrix() - in.X_WB.matrix()).norm(), 1e-12);
  EXPECT_LT((out.v_WB - in.v_WB).norm(), 1e-12);
  EXPECT_LT((out.w_WB - in.w_WB).norm(), 1e-12);
}

}  // namespace
}  // namespace hadal::physics
