// Force elements alone (no Bullet): the fluid models' wrenches on a submerged box against Archimedes,
// the current (and waves) they report for the added mass, the Earth-rotation Coriolis force's closed form, and the
// errors a vehicle without a hull gets.
#include "hadal/physics/fluid_forces.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hadal/physics/ocean.h"
#include "hadal/physics/test_models.h"

namespace hadal::physics {
namespace {

constexpr double kG = 9.80665;

// A 1 x 0.4 x 0.4 m box vehicle 20 m deep in still, constant-density water, centre of mass at B.
VehicleSpec box_vehicle(FluidModelType model) {
  VehicleSpec vehicle;
  vehicle.name = "box";
  const Eigen::Vector3d size(1.0, 0.4, 0.4);
  vehicle.links = {testing::box_link("hull", 100.0, size, size.prod())};
  vehicle.fluid.model = model;
  vehicle.fluid.added_mass.model = AddedMassModel::kNone;
  return vehicle;
}

StepWrench add(ForceElement& element, const RigidBodyState& body, const Eigen::Vector3d& p_WBcm,
               const Eigen::Vector3d& v_WBcm) {
  std::vector<ActuatorKindState> no_actuators;
  StepWrench out;
  element.add(ForceInput{0.0, body, p_WBcm, v_WBcm, no_actuators}, out);
  return out;
}

// Both models at rest, fully submerged: buoyancy rho g V straight up at the centroid (no moment about
// it), submerged fraction 1. The lumped model to rounding; the surface model integrates pressure over the
// box's faces in float (physics/surface_hydrodynamics.h: a few 1e-7 relative), hence 1e-6.
TEST(FluidForcesTest, SubmergedBoxFeelsArchimedes) {
  Model model = testing::water_model({});
  model.world.gravity_W = Eigen::Vector3d(0, 0, -kG);
  const Ocean ocean(model.world);
  RigidBodyState body;
  body.X_WB.translation() = Eigen::Vector3d(3.0, -1.0, -20.0);
  const Eigen::Vector3d p_WBcm = body.X_WB.translation();
  const double expected = 1000.0 * kG * 0.16;
  for (FluidModelType type : {FluidModelType::kLumped, FluidModelType::kSurface}) {
    const VehicleSpec vehicle = box_vehicle(type);
    VehicleFluid fluid = make_vehicle_fluid(vehicle, model.world, ocean, Eigen::Vector3d::Zero());
    EXPECT_EQ(fluid.faces > 0, type == FluidModelType::kSurface);
    EXPECT_TRUE(fluid.M_A0.isZero(0.0));
    const StepWrench w = add(*fluid.force, body, p_WBcm, Eigen::Vector3d::Zero());
    const double tolerance = (type == FluidModelType::kSurface ? 1e-6 : 1e-12) * expected;
    EXPECT_NEAR(w.f_W.z(), expected, tolerance) << static_cast<int>(type);
    EXPECT_NEAR(w.f_W.head<2>().norm(), 0.0, tolerance);
    EXPECT_NEAR(w.tau_W.norm(), 0.0, tolerance);
    EXPECT_NEAR(w.submerged_fraction, 1.0, 1e-6);
    EXPECT_EQ(w.v_water_W, Eigen::Vector3d::Zero());
  }
}

// The current at the centre of mass is reported for the added mass, and the lumped damping acts on the
// velocity through the water: a vehicle drifting with a uniform current feels no damping.
TEST(FluidForcesTest, CurrentIsReportedAndDampingActsThroughTheWater) {
  Model model = testing::water_model({});
  model.world.water.current.uniform_W = Eigen::Vector3d(0.4, -0.2, 0.0);
  const Ocean ocean(model.world);
  VehicleSpec vehicle = box_vehicle(FluidModelType::kLumped);
  vehicle.links[0].buoyancy.volume = 0.0;
  vehicle.fluid.linear_damping << 20, 50, 50, 5, 5, 5;
  VehicleFluid fluid = make_vehicle_fluid(vehicle, model.world, ocean, Eigen::Vector3d::Zero());
  RigidBodyState body;
  body.X_WB.translation() = Eigen::Vector3d(0, 0, -10.0);
  body.v_WB = model.world.water.current.uniform_W;
  StepWrench drifting = add(*fluid.force, body, body.X_WB.translation(), body.v_WB);
  EXPECT_EQ(drifting.v_water_W, model.world.water.current.uniform_W);
  EXPECT_NEAR(drifting.f_W.norm(), 0.0, 1e-12);
  body.v_WB.setZero();
  const StepWrench held = add(*fluid.force, body, body.X_WB.translation(), body.v_WB);
  EXPECT_NEAR(held.f_W.x(), 20.0 * 0.4, 1e-12);  // dragged along by the current: -D (v - u)
  EXPECT_NEAR(held.f_W.y(), 50.0 * -0.2, 1e-12);
}

// In waves the surface model reports the water at the centre of mass as the current plus the orbital velocity, and
// the orbital acceleration, for the added mass (physics/actuator_kind.h, StepWrench): linear theory's at the box 20 m
// down in 1 m, 10 s deep-water waves, to rounding. The lumped model does not see waves: the current alone.
TEST(FluidForcesTest, InWavesTheSurfaceModelReportsTheMovingWater) {
  Model model = testing::water_model({});
  model.world.water.current.uniform_W = Eigen::Vector3d(0.4, -0.2, 0.0);
  model.world.waves.spectrum = WaveSpectrum::kRegular;
  model.world.waves.regular = {{1.0, 10.0, 0.0, 0.3}};
  model.world.waves.ramp_time = 0.0;
  const Ocean ocean(model.world);
  RigidBodyState body;
  body.X_WB.translation() = Eigen::Vector3d(3.0, 0.0, -20.0);
  const double omega = 2.0 * M_PI / 10.0, k = omega * omega / kG;
  // eta = a cos(k x - omega t + phi) at t = 0; Wheeler's stretched depth z - eta (physics/waves.h).
  const double theta = k * 3.0 + 0.3, decay = std::exp(k * (-20.0 - std::cos(theta)));
  const Eigen::Vector3d v_orbital(omega * decay * std::cos(theta), 0.0, omega * decay * std::sin(theta));
  const Eigen::Vector3d a_orbital(omega * omega * decay * std::sin(theta), 0.0,
                                  -omega * omega * decay * std::cos(theta));
  const VehicleFluid surface =
      make_vehicle_fluid(box_vehicle(FluidModelType::kSurface), model.world, ocean, Eigen::Vector3d::Zero());
  const StepWrench w = add(*surface.force, body, body.X_WB.translation(), Eigen::Vector3d::Zero());
  EXPECT_LT((w.v_water_W - model.world.water.current.uniform_W - v_orbital).norm(), 1e-12);
  EXPECT_LT((w.a_water_W - a_orbital).norm(), 1e-12);
  EXPECT_GT(v_orbital.norm(), 0.1 * omega * decay);
  const VehicleFluid lumped =
      make_vehicle_fluid(box_vehicle(FluidModelType::kLumped), model.world, ocean, Eigen::Vector3d::Zero());
  const StepWrench l = add(*lumped.force, body, body.X_WB.translation(), Eigen::Vector3d::Zero());
  EXPECT_EQ(l.v_water_W, model.world.water.current.uniform_W);
  EXPECT_EQ(l.a_water_W, Eigen::Vector3d::Zero());
}

// F = -2 m Omega x v with Omega = Omega_E (0, cos lat, sin lat) in ENU. At 30 N (where cos and sin differ,
// so swapping them shows; at 45 N they are the same number) a 100 kg vehicle moving east at 1 m/s is pushed
// south (to its right) by 2 m Omega_E sin 30 and up by 2 m Omega_E cos 30; moving north at 1 m/s, east (to
// its right) by 2 m Omega_E sin 30. In the southern hemisphere (30 S) the sideways push turns left. 1e-15
// relative: a few roundings.
TEST(FluidForcesTest, EarthRotationCoriolisClosedForm) {
  for (const double latitude_deg : {30.0, -30.0}) {
    SCOPED_TRACE(latitude_deg);
    WorldSpec world;
    world.origin.latitude_rad = latitude_deg * kDegToRad;
    RigidBodyState body;
    std::vector<ActuatorKindState> none;
    EarthRotationForce element(world, 100.0);
    const double twice_m_omega = 2.0 * 100.0 * world.dynamics.earth_rotation_rate;
    const double sin_lat = latitude_deg > 0.0 ? 0.5 : -0.5, cos_lat = std::sqrt(3.0) / 2.0;
    StepWrench east;
    element.add(ForceInput{0.0, body, Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.0, 0.0), none}, east);
    EXPECT_NEAR(east.f_W.x(), 0.0, 1e-18);
    EXPECT_NEAR(east.f_W.y(), -twice_m_omega * sin_lat, 1e-15 * twice_m_omega);
    EXPECT_NEAR(east.f_W.z(), twice_m_omega * cos_lat, 1e-15 * twice_m_omega);
    EXPECT_EQ(east.tau_W, Eigen::Vector3d::Zero());
    StepWrench north;
    element.add(ForceInput{0.0, body, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 1.0, 0.0), none}, north);
    EXPECT_NEAR(north.f_W.x(), twice_m_omega * sin_lat, 1e-15 * twice_m_omega);
    EXPECT_NEAR(north.f_W.y(), 0.0, 1e-18);
    EXPECT_NEAR(north.f_W.z(), 0.0, 1e-18);
  }
}

// A surface model needs faces; an ellipsoid fitted to the hull needs a hull.
TEST(FluidForcesTest, VehiclesWithoutAHullAreClearErrors) {
  const Model model = testing::water_model({});
  const Ocean ocean(model.world);
  VehicleSpec vehicle = box_vehicle(FluidModelType::kSurface);
  vehicle.links[0].collisions.clear();
  EXPECT_THROW(make_vehicle_fluid(vehicle, model.world, ocean, Eigen::Vector3d::Zero()), std::invalid_argument);
  vehicle.fluid.model = FluidModelType::kLumped;
  vehicle.fluid.added_mass.model = AddedMassModel::kEllipsoid;
  try {
    make_vehicle_fluid(vehicle, model.world, ocean, Eigen::Vector3d::Zero());
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("vehicle 'box': fluid.added_mass"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hadal::physics
