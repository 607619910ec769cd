#include "hadal/core/simulation.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <utility>

#include "hadal/geometry/primitive_mesh.h"
#include "hadal/physics/bullet_world.h"
#include "hadal/physics/lumped_fluid.h"
#include "hadal/physics/mass_properties.h"
#include "hadal/physics/ocean.h"
#include "hadal/physics/ocean_fluid.h"
#include "hadal/physics/surface_hydrodynamics.h"
#include "hadal/physics/thruster.h"

namespace hadal {

// Constants derived from the model that the step needs per vehicle; no evolving state.
struct Simulation::VehicleRuntime {
  std::vector<physics::Thruster> thrusters;
  physics::LumpedFluid fluid;
  // Surface fluid model only (null for the lumped model): the kernel over the vehicle's
  // hydrodynamic mesh in B, and the composite centre of mass p_BBcm it takes moments about.
  std::unique_ptr<physics::SurfaceHydrodynamics> surface;
  Eigen::Vector3d p_BBcm = Eigen::Vector3d::Zero();
};

namespace {

// Water at rest; currents will provide v_water_W at the vehicle.
const Eigen::Vector3d kWaterAtRest_W = Eigen::Vector3d::Zero();

std::string format_number(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);  // shortest round trip
  return std::string(buffer, result.ptr);
}

bool is_finite(const VehicleState& vehicle) {
  if (!vehicle.body.X_WB.matrix().allFinite() || !vehicle.body.v_WB.allFinite() ||
      !vehicle.body.w_WB.allFinite()) {
    return false;
  }
  for (const ThrusterState& thruster : vehicle.thrusters) {
    if (!std::isfinite(thruster.rotor_speed)) return false;
  }
  for (double setpoint : vehicle.client_setpoints) {
    if (!std::isfinite(setpoint)) return false;
  }
  return true;
}

// Last-line guard for schedule values (the config loader validates them): finite, within [-1, 1].
double sanitised(double setpoint) {
  return std::isfinite(setpoint) ? std::clamp(setpoint, -1.0, 1.0) : 0.0;
}

void apply_setpoints(const std::vector<double>& setpoints, VehicleState& vehicle) {
  for (std::size_t k = 0; k < vehicle.thrusters.size(); ++k) {
    vehicle.thrusters[k].setpoint = k < setpoints.size() ? sanitised(setpoints[k]) : 0.0;
  }
}

void apply_zero_setpoints(VehicleState& vehicle) {
  for (ThrusterState& thruster : vehicle.thrusters) thruster.setpoint = 0.0;
}

// Step (1): which setpoints drive the thrusters during the step of length dt that starts at sim
// time t.
void select_setpoints(const VehicleSpec& spec, double t, double dt, VehicleState& vehicle) {
  if (vehicle.command_source == CommandSource::kClient) {
    if (t - vehicle.last_command_time <= spec.command_timeout) {
      apply_setpoints(vehicle.client_setpoints, vehicle);
      vehicle.faults &= ~kFaultCommandTimeout;
    } else {
      apply_zero_setpoints(vehicle);
      vehicle.faults |= kFaultCommandTimeout;
    }
    return;
  }
  if (spec.schedule.empty()) {
    vehicle.command_source = CommandSource::kNone;
    apply_zero_setpoints(vehicle);
    return;
  }
  vehicle.command_source = CommandSource::kSchedule;
  // Zero-order hold: the last keyframe with time <= t (keyframes are sorted by time). A keyframe
  // within 1e-6 dt counts as reached, so round-off in t = step_count * dt (at 60 Hz, step 222
  // starts at 3.6999999999999997 for a keyframe at 3.7) cannot delay it by a step.
  const double t_reached = t + 1e-6 * dt;
  const auto after = std::upper_bound(
      spec.schedule.begin(), spec.schedule.end(), t_reached,
      [](double time, const SetpointKeyframe& keyframe) { return time < keyframe.time; });
  if (after == spec.schedule.begin()) {
    apply_zero_setpoints(vehicle);
  } else {
    apply_setpoints(std::prev(after)->setpoints, vehicle);
  }
}

VehicleState initial_vehicle_state(const VehicleSpec& spec) {
  VehicleState vehicle;
  vehicle.body.X_WB = spec.X_WB_initial;
  vehicle.body.v_WB = spec.v_WB_initial;
  vehicle.thrusters.resize(spec.thrusters.size());
  vehicle.command_source = spec.schedule.empty() ? CommandSource::kNone : CommandSource::kSchedule;
  return vehicle;
}

// Non-finite policy (DESIGN.md 7, MuJoCo mj_checkPos): back to the initial pose at rest, rotors
// stopped, client setpoints zeroed (the next accepted command takes over again), fault latched.
void reset_non_finite(const VehicleSpec& spec, VehicleState& vehicle) {
  vehicle.body = RigidBodyState{};
  vehicle.body.X_WB = spec.X_WB_initial;
  for (ThrusterState& thruster : vehicle.thrusters) {
    thruster.rotor_speed = 0.0;
    thruster.thrust = 0.0;
    thruster.torque = 0.0;
  }
  std::fill(vehicle.client_setpoints.begin(), vehicle.client_setpoints.end(), 0.0);
  vehicle.faults |= kFaultNonFiniteState;
  ++vehicle.fault_resets;
}

void validate(const Model& model) {
  if (!(model.world.physics_rate_hz > 0.0) || !std::isfinite(model.world.physics_rate_hz)) {
    throw std::invalid_argument("world.physics_rate_hz must be finite and > 0 (got " +
                                format_number(model.world.physics_rate_hz) + ")");
  }
  for (const VehicleSpec& vehicle : model.vehicles) {
    for (const ThrusterSpec& thruster : vehicle.thrusters) {
      if (thruster.link_index < 0 ||
          thruster.link_index >= static_cast<int>(vehicle.links.size())) {
        throw std::invalid_argument("vehicle '" + vehicle.name + "': thruster '" + thruster.name +
                                    "': link index " + std::to_string(thruster.link_index) +
                                    " out of range (" + std::to_string(vehicle.links.size()) +
                                    " links)");
      }
    }
  }
}

// The vehicle's hydrodynamic mesh in B: per link its mesh (in L) if it has one, else its collision
// primitives tessellated (geometry/primitive_mesh.h), moved by X_BL (and X_LG). Overlapping parts
// are not merged: each closed part displaces its own volume, so overlaps count twice.
geometry::TriangleMesh hydrodynamic_mesh_B(const VehicleSpec& spec) {
  geometry::TriangleMesh mesh_B;
  for (const LinkSpec& link : spec.links) {
    if (link.mesh && link.mesh->mesh) {
      geometry::append_transformed(*link.mesh->mesh, link.X_BL, &mesh_B);
      continue;
    }
    for (const CollisionShape& shape : link.collisions) {
      geometry::append_transformed(geometry::tessellate(shape), link.X_BL * shape.X_LG, &mesh_B);
    }
  }
  if (mesh_B.num_triangles() == 0) {
    throw std::invalid_argument("vehicle '" + spec.name +
                                "': fluid model 'surface' needs a hydrodynamic mesh: no link has a "
                                "mesh or collision shapes");
  }
  return mesh_B;
}

const Model& validated(const Model& model) {
  validate(model);
  return model;
}

}  // namespace

Simulation::Simulation(Model model)
    : model_(std::move(model)), world_(std::make_unique<physics::BulletWorld>(validated(model_))) {
  const double dt = model_.world.step_size();
  runtime_.reserve(model_.vehicles.size());
  for (const VehicleSpec& spec : model_.vehicles) {
    std::vector<physics::Thruster> thrusters;
    thrusters.reserve(spec.thrusters.size());
    for (const ThrusterSpec& thruster : spec.thrusters) {
      thrusters.emplace_back(thruster, spec.links[thruster.link_index].X_BL,
                             model_.world.water.density, dt);
    }
    VehicleRuntime runtime{std::move(thrusters), physics::LumpedFluid(spec, model_.world), nullptr,
                           Eigen::Vector3d::Zero()};
    if (spec.fluid.model == FluidModelType::kSurface) {
      runtime.surface = std::make_unique<physics::SurfaceHydrodynamics>(hydrodynamic_mesh_B(spec),
                                                                        spec.fluid.hydrodynamics);
      runtime.p_BBcm = world_->mass_properties(static_cast<int>(runtime_.size())).p_BBcm;
      if (!ocean_) ocean_ = std::make_unique<physics::Ocean>(model_.world);
    }
    runtime_.push_back(std::move(runtime));
    state_.vehicles.push_back(initial_vehicle_state(spec));
  }
}

Simulation::~Simulation() = default;

const physics::MassProperties& Simulation::mass_properties(int vehicle_index) const {
  return world_->mass_properties(vehicle_index);
}

void Simulation::set_state(const SimState& state) {
  if (state.vehicles.size() != model_.vehicles.size()) {
    throw std::invalid_argument("set_state: expected " + std::to_string(model_.vehicles.size()) +
                                " vehicles, got " + std::to_string(state.vehicles.size()));
  }
  for (std::size_t i = 0; i < model_.vehicles.size(); ++i) {
    if (state.vehicles[i].thrusters.size() != model_.vehicles[i].thrusters.size()) {
      throw std::invalid_argument(
          "set_state: vehicle '" + model_.vehicles[i].name + "': expected " +
          std::to_string(model_.vehicles[i].thrusters.size()) + " thrusters, got " +
          std::to_string(state.vehicles[i].thrusters.size()));
    }
  }
  state_ = state;
  for (std::size_t i = 0; i < model_.vehicles.size(); ++i) {
    VehicleState& vehicle = state_.vehicles[i];
    if (!is_finite(vehicle)) reset_non_finite(model_.vehicles[i], vehicle);
    world_->set_body_state(static_cast<int>(i), vehicle.body);
  }
  world_->clear_contacts();
}

std::string Simulation::check_thruster_setpoints(int vehicle_index,
                                                 const std::vector<double>& setpoints) const {
  if (vehicle_index < 0 || vehicle_index >= static_cast<int>(model_.vehicles.size())) {
    return "unknown vehicle index " + std::to_string(vehicle_index);
  }
  const VehicleSpec& spec = model_.vehicles[vehicle_index];
  if (setpoints.size() != spec.thrusters.size()) {
    std::string reason = "expected " + std::to_string(spec.thrusters.size()) +
                         (spec.thrusters.size() == 1 ? " setpoint" : " setpoints");
    if (!spec.thrusters.empty()) {
      reason += " (";
      for (std::size_t k = 0; k < spec.thrusters.size(); ++k) {
        reason += (k > 0 ? ", " : "") + spec.thrusters[k].name;
      }
      reason += ")";
    }
    return reason + ", got " + std::to_string(setpoints.size());
  }
  for (std::size_t k = 0; k < setpoints.size(); ++k) {
    const double value = setpoints[k];
    const std::string label = "setpoint[" + std::to_string(k) + "]";
    if (std::isnan(value)) return label + " is NaN";
    if (std::isinf(value)) return label + " is " + (value > 0 ? "+inf" : "-inf");
    if (value < -1.0 || value > 1.0)
      return label + " = " + format_number(value) + " is outside [-1, 1]";
  }
  return {};
}

std::string Simulation::set_thruster_setpoints(int vehicle_index,
                                               const std::vector<double>& setpoints) {
  std::string reason = check_thruster_setpoints(vehicle_index, setpoints);
  if (!reason.empty()) return reason;
  VehicleState& vehicle = state_.vehicles[vehicle_index];
  vehicle.client_setpoints.assign(setpoints.begin(), setpoints.end());
  vehicle.last_command_time = state_.time;
  vehicle.command_source = CommandSource::kClient;
  vehicle.faults &= ~kFaultCommandTimeout;
  return {};
}

void Simulation::step() {
  const double dt = model_.world.step_size();
  const double t = state_.time;
  const double surface_z = model_.world.water.surface_z;
  const int num_vehicles = static_cast<int>(model_.vehicles.size());

  for (int i = 0; i < num_vehicles; ++i) {
    const VehicleSpec& spec = model_.vehicles[i];
    VehicleRuntime& runtime = runtime_[i];
    VehicleState& vehicle = state_.vehicles[i];

    // (1) setpoints.
    select_setpoints(spec, t, dt, vehicle);

    // Bullet is re-seeded from the state every step, so a restored SimState and the uninterrupted
    // run drive Bullet from identical numbers (X_WB -> X_WP is not exactly invertible).
    world_->set_body_state(i, vehicle.body);

    // (2) rotor dynamics and (3) thruster forces.
    for (std::size_t k = 0; k < vehicle.thrusters.size(); ++k) {
      const physics::Thruster& thruster = runtime.thrusters[k];
      ThrusterState& thruster_state = vehicle.thrusters[k];
      thruster_state.rotor_speed =
          thruster.next_rotor_speed(thruster_state.rotor_speed, thruster_state.setpoint);
      const physics::ThrusterWrench wrench =
          thruster.wrench(thruster_state.rotor_speed, vehicle.body.X_WB, surface_z);
      thruster_state.thrust = wrench.thrust;
      thruster_state.torque = wrench.torque;
      world_->add_force_W(i, wrench.f_W, wrench.p_WT);
      world_->add_torque_W(i, wrench.tau_W);
    }

    // (3) fluid (gravity is Bullet's).
    if (runtime.surface) {
      // Surface model: buoyancy, drag, friction, lift and Magnus from the faces, in the Ocean at the
      // step's start time; f_W acts at the centre of mass and tau_W is about it.
      physics::BodyMotion motion;
      motion.X_WB = vehicle.body.X_WB;
      motion.p_WBcm = vehicle.body.X_WB * runtime.p_BBcm;
      motion.v_WBcm =
          vehicle.body.v_WB + vehicle.body.w_WB.cross(motion.p_WBcm - vehicle.body.X_WB.translation());
      motion.w_WB = vehicle.body.w_WB;
      const physics::HydrodynamicWrench fluid =
          runtime.surface->compute(motion, physics::OceanFluid(*ocean_, t));
      world_->add_force_W(i, fluid.f_W, motion.p_WBcm);
      world_->add_torque_W(i, fluid.tau_W);
    } else {
      // Lumped model: buoyancy and damping.
      const physics::LumpedFluidWrench fluid = runtime.fluid.wrench(vehicle.body, kWaterAtRest_W);
      world_->add_force_W(i, fluid.f_W(), vehicle.body.X_WB.translation());
      world_->add_torque_W(i, fluid.tau_W());
    }
  }

  // (4) Bullet.
  world_->step(dt);

  // (5) snapshot; time from the step count so it does not drift.
  for (int i = 0; i < num_vehicles; ++i) state_.vehicles[i].body = world_->body_state(i);
  ++state_.step_count;
  state_.time = static_cast<double>(state_.step_count) * dt;

  // (6) non-finite check.
  bool any_reset = false;
  for (int i = 0; i < num_vehicles; ++i) {
    VehicleState& vehicle = state_.vehicles[i];
    if (is_finite(vehicle)) continue;
    reset_non_finite(model_.vehicles[i], vehicle);
    world_->set_body_state(i, vehicle.body);
    any_reset = true;
  }
  // Contact impulses cached from the failed step may be NaN; they would poison the warm start.
  if (any_reset) world_->clear_contacts();
}

}  // namespace hadal
