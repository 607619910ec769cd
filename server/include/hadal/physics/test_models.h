// Small scenario models built in code, for unit tests and benchmarks that must not depend on the
// YAML loader. Everything here is plain data; units SI.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

#include "hadal/core/model.h"
#include "hadal/physics/mass_properties.h"
#include "hadal/physics/thruster.h"

namespace hadal::physics::testing {

// The pose with rotation R and translation p.
inline Eigen::Isometry3d at(const Eigen::Vector3d& p,
                            const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R;
  X.translation() = p;
  return X;
}

// A homogeneous box link of full extents `size` whose centre of mass, centre of buoyancy and single
// box collision shape sit at the link origin; `volume` is its displaced volume (pass size.prod()
// for a closed hull).
inline LinkSpec box_link(std::string name, double mass, const Eigen::Vector3d& size, double volume,
                         const Eigen::Isometry3d& X_BL = Eigen::Isometry3d::Identity()) {
  LinkSpec link;
  link.name = std::move(name);
  link.mass = mass;
  link.I_LLcm_L = solid_box_inertia(mass, size);
  link.X_BL = X_BL;
  CollisionShape box;
  box.type = CollisionShapeType::kBox;
  box.box_size = size;
  link.collisions.push_back(box);
  link.buoyancy.volume = volume;
  return link;
}

// A thruster on links[0] at p_LT pushing along axis_L, with tau = 0, n_max = 50 rev/s and
// K_T rho D^4 ~ 0.5 N s^2 at rho = 1000 (T_max ~ 1.2 kN).
inline ActuatorSpec simple_thruster(std::string name, const Eigen::Vector3d& p_LT, const Eigen::Vector3d& axis_L) {
  ThrusterActuator::Spec thruster;
  thruster.p_LT = p_LT;
  thruster.axis_L = axis_L;
  thruster.propeller_diameter = 0.2;
  thruster.thrust_coefficient = 0.3;
  thruster.torque_coefficient = 0.05;
  thruster.rotor_time_constant_s = 0.0;
  thruster.max_rotor_speed_rev_s = 50.0;
  ActuatorSpec actuator;
  actuator.name = std::move(name);
  actuator.kind = thruster;
  return actuator;
}

// A world with the water surface at z = 0, the seabed at z = -100 m, rho = 1000 kg/m^3, 500 Hz, and
// the given vehicles.
inline Model water_model(std::vector<VehicleSpec> vehicles) {
  Model model;
  model.world.water.surface_z = 0.0;
  model.world.water.density = 1000.0;
  model.world.seabed.z = -100.0;
  model.world.physics_rate_hz = 500.0;
  model.vehicles = std::move(vehicles);
  return model;
}

// A vehicle "body" of one link "hull" with one collision shape (its hydrodynamic mesh), fluid model
// surface with coefficients `c`, at p_W.
inline VehicleSpec surface_vehicle(const CollisionShape& shape, double mass, const Eigen::Matrix3d& I,
                                   const HydrodynamicCoefficients& c, const Eigen::Vector3d& p_W) {
  VehicleSpec vehicle;
  vehicle.name = "body";
  LinkSpec link;
  link.name = "hull";
  link.mass = mass;
  link.I_LLcm_L = I;
  link.collisions.push_back(shape);
  vehicle.links.push_back(link);
  vehicle.fluid.model = FluidModelType::kSurface;
  vehicle.fluid.hydrodynamics = c;
  vehicle.X_WB_initial = at(p_W);
  return vehicle;
}

inline CollisionShape box_shape(const Eigen::Vector3d& size) {
  CollisionShape box;
  box.type = CollisionShapeType::kBox;
  box.box_size = size;
  return box;
}

// Surface-model coefficients with pressure drag only.
inline HydrodynamicCoefficients drag_only(double drag) {
  HydrodynamicCoefficients c;
  c.drag = drag;
  c.skin_friction = 0.0;
  c.lift = 0.0;
  c.magnus = 0.0;
  return c;
}

}  // namespace hadal::physics::testing
