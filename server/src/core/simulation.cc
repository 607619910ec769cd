#include "hadal/core/simulation.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <charconv>
#include <cmath>
#include <limits>
#include <deque>
#include <future>
#include <iterator>
#include <stdexcept>
#include <thread>
#include <utility>

#include "hadal/core/rate_divider.h"
#include "hadal/geometry/raycast_service.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/geometry/scene_rays.h"
#include "hadal/geometry/seabed_height.h"
#include "hadal/geometry/world_scene.h"
#include "hadal/physics/actuators.h"
#include "hadal/physics/added_mass.h"
#include "hadal/physics/bullet_world.h"
#include "hadal/physics/fluid_forces.h"
#include "hadal/physics/mass_properties.h"
#include "hadal/physics/ocean.h"
#include "hadal/physics/terramechanics.h"
#include "hadal/sensors/sample_context.h"
#include "hadal/sensors/sensor_kinds.h"
#include "worker_pool.h"

namespace hadal {

// What the step needs per vehicle besides its state: constants derived from the model, and the step's
// scratch. Holds references into the model: made in place, never moved.
struct Simulation::VehicleRuntime {
  VehicleRuntime(const VehicleSpec& spec, const WorldSpec& world, const physics::MassProperties& mass_properties,
                 const physics::Ocean& ocean, const geometry::SeabedHeight* seabed)
      : actuators(spec, world, &ocean),
        seabed_below(physics::VehicleActuators::needs_seabed(spec) ? seabed : nullptr),
        p_BBcm(mass_properties.p_BBcm),
        mass(mass_properties.mass) {
    // The force elements, in the order they add up: actuators, fluid, Earth rotation, soil.
    forces.push_back(std::make_unique<physics::ActuatorForces>(actuators));
    physics::VehicleFluid fluid = physics::make_vehicle_fluid(spec, world, ocean, p_BBcm);
    forces.push_back(std::move(fluid.force));
    fluid_faces = fluid.faces;
    M_A0 = fluid.M_A0;
    if (world.dynamics.earth_rotation) forces.push_back(std::make_unique<physics::EarthRotationForce>(world, mass));
    if (spec.seabed_contact == SeabedContact::kSoil) {
      auto element = std::make_unique<physics::SoilForces>(geometry::vehicle_surface_B(spec), world.soil.layout(),
                                                           *seabed, mass, world.step_size());
      soil = element.get();
      forces.push_back(std::move(element));
    }
    if (!M_A0.isZero(0.0)) {
      added_mass = std::make_unique<physics::AddedMassDynamics>(
          physics::RigidBodyInertia{mass, mass_properties.I_BBcm_B}, M_A0, spec.fluid.added_mass.coriolis,
          world.dynamics.gyroscopic);
    }
    for (const SensorSpec& sensor : spec.sensors) {
      Sensor& mount = sensors.emplace_back();
      mount.X_BS = spec.links[static_cast<std::size_t>(sensor.link_index)].X_BL * sensor.X_LS;
      mount.period = 1.0 / sensor.rate_hz;
      mount.latency_steps = sensor.latency_steps(world.physics_rate_hz);
    }
  }

  physics::VehicleActuators actuators;
  // The seabed, when an actuator reads its height under the vehicle (a drop weight's release altitude).
  const geometry::SeabedHeight* seabed_below;
  std::vector<std::unique_ptr<physics::ForceElement>> forces;
  Eigen::Vector3d p_BBcm;  // composite centre of mass in B
  double mass;             // [kg]
  Matrix6d M_A0 = Matrix6d::Zero();  // added mass at the surface, about Bcm, B axes
  std::unique_ptr<physics::AddedMassDynamics> added_mass;  // null without added mass
  std::size_t fluid_faces = 0;                             // surface-model faces per step
  const physics::SoilForces* soil = nullptr;               // in `forces`; null without soil contact
  std::vector<Eigen::Vector3d> belts;                      // per link, its surface's velocity in B (tracks)
  // A capture on the workers: a ray batch's hits, or a scene work's completion and what it fills (the
  // kind's Capture, kept alive by the work itself too, so that a dropped capture may finish safely).
  // A scene work dropped before a worker started it is skipped (`dropped`, read when it starts), so
  // that in real time one late frame does not make every frame queued behind it late as well.
  struct InFlight {
    std::future<geometry::RayHits> hits;
    std::future<void> done;
    std::shared_ptr<void> output;
    std::shared_ptr<std::atomic<bool>> dropped;
  };
  // Per sensor (same order as VehicleSpec::sensors): its pose in B, its sample period, and for a
  // captured kind its latency in steps and the captures in flight (one per pending capture, same order).
  struct Sensor {
    Eigen::Isometry3d X_BS = Eigen::Isometry3d::Identity();
    double period = 0.0;  // nominal sample period 1 / rate_hz [s]
    std::uint64_t latency_steps = 0;
    std::deque<InFlight> in_flight;
  };
  std::deque<Sensor> sensors;  // a deque: Sensor holds futures, which do not copy
  // Step scratch (not state). The centre of mass, its velocity and the angular velocity at the step
  // start, the wrench the force elements added up; then what Bullet was given at the centre of mass in
  // the B axes of the step start, and the velocity then, for the added-mass contact feedback.
  Eigen::Vector3d p_WBcm = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WBcm = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WB = Eigen::Vector3d::Zero();
  physics::StepWrench wrench;
  Vector6d tau_bullet_B = Vector6d::Zero();
  Vector6d nu0 = Vector6d::Zero();
  Eigen::Matrix3d R_WB0 = Eigen::Matrix3d::Identity();
};

namespace {

constexpr std::size_t kParallelFluidFaces = 4096;

// Finite, and within Simulation::kWorldBound_m of the world origin: a position of 1e300 m is finite, but
// a sensor's mount added to it, or the next step, is not.
bool within_world(const Eigen::Vector3d& p_W) { return (p_W.array().abs() <= Simulation::kWorldBound_m).all(); }

bool is_finite(const VehicleState& vehicle) {
  if (!within_world(vehicle.body.X_WB.translation())) return false;
  if (!vehicle.body.X_WB.matrix().allFinite() || !vehicle.body.v_WB.allFinite() ||
      !vehicle.body.w_WB.allFinite() || !vehicle.contact_wrench_B.allFinite()) {
    return false;
  }
  if (!physics::VehicleActuators::is_finite(vehicle.actuators)) return false;
  for (double control : vehicle.client_controls) {
    if (!std::isfinite(control)) return false;
  }
  return true;
}

// The control vector that drives the vehicle's actuators during the step of length dt that starts at
// sim time t: the client's while fresh (the watchdog zeroes it otherwise), else the schedule's
// zero-order hold, else nothing (zeros). Updates the command source and the timeout fault.
const std::vector<double>& select_controls(const VehicleSpec& spec, double t, double dt, VehicleState& vehicle) {
  static const std::vector<double> kZeros;  // VehicleActuators::command pads with zeros
  if (vehicle.command_source == CommandSource::kClient) {
    if (t - vehicle.last_command_time <= spec.command_timeout) {
      vehicle.faults &= ~kFaultCommandTimeout;
      return vehicle.client_controls;
    }
    vehicle.faults |= kFaultCommandTimeout;
    return kZeros;
  }
  if (spec.schedule.empty()) {
    vehicle.command_source = CommandSource::kNone;
    return kZeros;
  }
  vehicle.command_source = CommandSource::kSchedule;
  // Zero-order hold: the last keyframe with time <= t (keyframes are sorted by time). A keyframe
  // within 1e-6 dt counts as reached, so round-off in t = step_count * dt (at 60 Hz, step 222
  // starts at 3.6999999999999997 for a keyframe at 3.7) cannot delay it by a step.
  const double t_reached = t + 1e-6 * dt;
  const auto after = std::upper_bound(
      spec.schedule.begin(), spec.schedule.end(), t_reached,
      [](double time, const SetpointKeyframe& keyframe) { return time < keyframe.time; });
  return after == spec.schedule.begin() ? kZeros : std::prev(after)->setpoints;
}

VehicleState initial_vehicle_state(const VehicleSpec& spec) {
  VehicleState vehicle;
  vehicle.body.X_WB = spec.X_WB_initial;
  vehicle.body.v_WB = spec.v_WB_initial;
  vehicle.body.w_WB = spec.w_WB_initial;
  vehicle.actuators = physics::VehicleActuators::initial_states(spec);
  vehicle.command_source = spec.schedule.empty() ? CommandSource::kNone : CommandSource::kSchedule;
  return vehicle;
}

// Non-finite policy (docs/ARCHITECTURE.md, "Faults"; MuJoCo's mj_checkPos): back to the initial pose at
// rest, actuators stopped, client controls zeroed (the next accepted command takes over again), fault
// latched.
void reset_non_finite(const VehicleSpec& spec, VehicleState& vehicle) {
  vehicle.body = RigidBodyState{};
  vehicle.body.X_WB = spec.X_WB_initial;
  physics::VehicleActuators::stop(vehicle.actuators);
  std::fill(vehicle.client_controls.begin(), vehicle.client_controls.end(), 0.0);
  vehicle.contact_wrench_B.setZero();
  vehicle.soil_shear_W.clear();
  vehicle.faults |= kFaultNonFiniteState;
  ++vehicle.fault_resets;
}

std::string format_number(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);  // shortest round trip
  return std::string(buffer, result.ptr);
}

const Model& validated(const Model& model) {
  if (!(model.world.physics_rate_hz > 0.0) || !std::isfinite(model.world.physics_rate_hz)) {
    throw std::invalid_argument("world.physics_rate_hz must be finite and > 0 (got " +
                                format_number(model.world.physics_rate_hz) + ")");
  }
  for (const VehicleSpec& vehicle : model.vehicles) {
    if (!vehicle.X_WB_initial.matrix().allFinite() || !within_world(vehicle.X_WB_initial.translation())) {
      throw std::invalid_argument("vehicle '" + vehicle.name + "': initial pose not finite or beyond 1000 km of the "
                                  "world origin");
    }
    const auto check_link = [&](int link_index, const std::string& what) {
      if (link_index < 0 || link_index >= static_cast<int>(vehicle.links.size())) {
        throw std::invalid_argument("vehicle '" + vehicle.name + "': " + what + ": link index " +
                                    std::to_string(link_index) + " out of range (" +
                                    std::to_string(vehicle.links.size()) + " links)");
      }
    };
    for (const SensorSpec& sensor : vehicle.sensors) {
      check_link(sensor.link_index, "sensor '" + sensor.name + "'");
      if (!(sensor.rate_hz > 0.0) || !std::isfinite(sensor.rate_hz)) {
        throw std::invalid_argument("vehicle '" + vehicle.name + "': sensor '" + sensor.name +
                                    "': rate_hz must be finite and > 0");
      }
    }
    for (const ActuatorSpec& actuator : vehicle.actuators) {
      check_link(actuator.link_index, std::string(actuator.type()) + " '" + actuator.name + "'");
    }
  }
  return model;
}

}  // namespace

Simulation::Simulation(Model model)
    : model_(std::move(model)), world_(std::make_unique<physics::BulletWorld>(validated(model_))) {
  ocean_ = std::make_unique<physics::Ocean>(model_.world);
  for (const VehicleSpec& spec : model_.vehicles) {
    const bool needs_seabed =
        spec.seabed_contact == SeabedContact::kSoil || physics::VehicleActuators::needs_seabed(spec);
    if (!needs_seabed || seabed_height_) continue;
    const SeabedSpec& seabed = model_.world.seabed;
    seabed_height_ = std::make_unique<geometry::SeabedHeight>(
        seabed.mesh ? geometry::SeabedHeight(*seabed.mesh, /*height_field=*/seabed.type != SeabedType::kMesh)
                    : geometry::SeabedHeight::plane(seabed.z));
  }
  environment_ = std::make_unique<sensors::SensorEnvironment>(model_.world.origin);
  bool casts_rays = false, captures = false;
  runtime_.reserve(model_.vehicles.size());
  for (std::size_t i = 0; i < model_.vehicles.size(); ++i) {
    const VehicleSpec& spec = model_.vehicles[i];
    runtime_.push_back(std::make_unique<VehicleRuntime>(
        spec, model_.world, world_->mass_properties(static_cast<int>(i)), *ocean_, seabed_height_.get()));
    for (const SensorSpec& sensor : spec.sensors) {
      std::visit(
          [&](const auto& kind_spec) {
            using Kind = sensors::KindOf<std::decay_t<decltype(kind_spec)>>;
            casts_rays = casts_rays || Kind::kCastsRays;
            captures = captures || Kind::kCaptures;
          },
          sensor.kind);
    }
  }
  state_ = initial_state(model_.world.seed);
  // The one ray-cast world, built at start when some sensor needs it (else on the first request).
  if (captures) {
    raycast_service();
  } else if (casts_rays) {
    scene_rays();
  }
  // Force elements of several vehicles in parallel when it pays: a wake-up costs ~10 us, one face of
  // the surface model ~4.5 ns, so from ~2 x 4k faces on (the second-largest hull bounds the gain).
  std::vector<std::size_t> faces;
  for (const auto& runtime : runtime_) {
    if (runtime->fluid_faces > 0) faces.push_back(runtime->fluid_faces);
  }
  std::sort(faces.rbegin(), faces.rend());
  const auto threads = static_cast<std::size_t>(model_.world.effective_threads());
  if (faces.size() >= 2 && faces[1] >= kParallelFluidFaces && threads >= 2) {
    pool_ = std::make_unique<WorkerPool>(static_cast<unsigned>(std::min(threads - 1, faces.size() - 1)));
  }
}

Simulation::~Simulation() = default;

const physics::MassProperties& Simulation::mass_properties(int vehicle_index) const {
  return world_->mass_properties(vehicle_index);
}

const physics::SoilWrench* Simulation::soil_wrench(int vehicle_index) const {
  const VehicleRuntime& runtime = *runtime_.at(static_cast<std::size_t>(vehicle_index));
  return runtime.soil ? &runtime.soil->last() : nullptr;
}

const physics::StepWrench& Simulation::applied_wrench(int vehicle_index) const {
  return runtime_.at(static_cast<std::size_t>(vehicle_index))->wrench;
}

unsigned Simulation::fluid_helper_threads() const { return pool_ ? pool_->helpers() : 0; }

const Matrix6d& Simulation::added_mass(int vehicle_index) const { return runtime_.at(vehicle_index)->M_A0; }

void Simulation::set_state(const SimState& state) {
  if (state.vehicles.size() != model_.vehicles.size()) {
    throw std::invalid_argument("set_state: expected " + std::to_string(model_.vehicles.size()) +
                                " vehicles, got " + std::to_string(state.vehicles.size()));
  }
  for (std::size_t i = 0; i < model_.vehicles.size(); ++i) {
    const VehicleSpec& spec = model_.vehicles[i];
    const VehicleState& vehicle = state.vehicles[i];
    const std::string prefix = "set_state: vehicle '" + spec.name + "': ";
    if (vehicle.sensors.size() != spec.sensors.size()) {
      throw std::invalid_argument(prefix + "expected " + std::to_string(spec.sensors.size()) + " sensors, got " +
                                  std::to_string(vehicle.sensors.size()));
    }
    for (std::size_t k = 0; k < spec.sensors.size(); ++k) {
      if (vehicle.sensors[k].kind.index() != spec.sensors[k].kind.index()) {
        throw std::invalid_argument(prefix + "sensor '" + spec.sensors[k].name + "' is a " +
                                    std::string(spec.sensors[k].type()) + ", its state is of another kind");
      }
    }
    if (vehicle.actuators.size() != spec.actuators.size()) {
      throw std::invalid_argument(prefix + "expected " + std::to_string(spec.actuators.size()) + " actuators, got " +
                                  std::to_string(vehicle.actuators.size()));
    }
    for (std::size_t k = 0; k < spec.actuators.size(); ++k) {
      if (vehicle.actuators[k].index() != spec.actuators[k].kind.index()) {
        throw std::invalid_argument(prefix + "actuator '" + spec.actuators[k].name + "' is a " +
                                    std::string(spec.actuators[k].type()) + ", its state is of another kind");
      }
    }
  }
  state_ = state;
  if (rays_) rays_->invalidate();  // the restored poses, even at the same step count
  restart_captures();
  for (std::size_t i = 0; i < model_.vehicles.size(); ++i) {
    VehicleState& vehicle = state_.vehicles[i];
    if (!is_finite(vehicle)) reset_non_finite(model_.vehicles[i], vehicle);
    world_->set_body_state(static_cast<int>(i), vehicle.body);
  }
  world_->clear_contacts();
}

SimState Simulation::initial_state(std::uint64_t seed) const {
  SimState state;
  for (std::size_t i = 0; i < model_.vehicles.size(); ++i) {
    const VehicleSpec& spec = model_.vehicles[i];
    VehicleState vehicle = initial_vehicle_state(spec);
    for (std::size_t k = 0; k < spec.sensors.size(); ++k) {
      SensorState& sensor_state = vehicle.sensors.emplace_back();
      std::visit(
          [&](const auto& kind_spec) {
            using Kind = sensors::KindOf<std::decay_t<decltype(kind_spec)>>;
            const sensors::SensorSetup setup{seed, spec.name, spec.sensors[k].name, runtime_[i]->sensors[k].period,
                                             *environment_};
            sensor_state.kind = Kind::initial_state(kind_spec, setup);
          },
          spec.sensors[k].kind);
    }
    state.vehicles.push_back(std::move(vehicle));
  }
  return state;
}

std::string Simulation::reset(std::uint64_t seed, const std::vector<std::optional<Eigen::Isometry3d>>& X_WB) {
  if (X_WB.size() > model_.vehicles.size()) {
    return "reset: " + std::to_string(X_WB.size()) + " poses for " + std::to_string(model_.vehicles.size()) +
           " vehicles";
  }
  for (std::size_t i = 0; i < X_WB.size(); ++i) {
    if (X_WB[i] && !X_WB[i]->matrix().allFinite()) {
      return "reset: vehicle '" + model_.vehicles[i].name + "': pose is not finite";
    }
    if (X_WB[i] && !within_world(X_WB[i]->translation())) {
      return "reset: vehicle '" + model_.vehicles[i].name + "': position beyond 1000 km of the world origin";
    }
  }
  SimState state = initial_state(seed);
  for (std::size_t i = 0; i < X_WB.size(); ++i) {
    if (X_WB[i]) state.vehicles[i].body = RigidBodyState{*X_WB[i], Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  }
  set_state(state);
  return "";
}

std::string Simulation::check_controls(int vehicle_index, const std::vector<double>& controls) const {
  if (vehicle_index < 0 || vehicle_index >= static_cast<int>(model_.vehicles.size())) {
    return "unknown vehicle index " + std::to_string(vehicle_index);
  }
  return runtime_[static_cast<std::size_t>(vehicle_index)]->actuators.check(controls);
}

std::string Simulation::set_controls(int vehicle_index, const std::vector<double>& controls) {
  std::string reason = check_controls(vehicle_index, controls);
  if (!reason.empty()) return reason;
  VehicleState& vehicle = state_.vehicles[static_cast<std::size_t>(vehicle_index)];
  vehicle.client_controls.assign(controls.begin(), controls.end());
  vehicle.last_command_time = state_.time;
  vehicle.command_source = CommandSource::kClient;
  vehicle.faults &= ~kFaultCommandTimeout;
  return {};
}

// One step, as the data flows (docs/ARCHITECTURE.md, "One step"): commands -> actuators -> force
// elements -> Bullet -> snapshot -> sensors due.
void Simulation::step() {
  const double t = state_.time;
  const double dt = model_.world.step_size();
  actuate(t, dt);
  apply_forces(t);
  world_->step(dt);
  take_snapshot(dt);
  reset_non_finite_vehicles();
  sample_sensors(dt);
}

// Commands -> actuators: each vehicle's control vector for this step, held by its actuators, which
// then advance their own dynamics (a thruster's rotor lag).
void Simulation::actuate(double t, double dt) {
  for (std::size_t i = 0; i < runtime_.size(); ++i) {
    VehicleState& vehicle = state_.vehicles[i];
    const physics::VehicleActuators& actuators = runtime_[i]->actuators;
    actuators.command(vehicle.actuators, select_controls(model_.vehicles[i], t, dt, vehicle));
    actuators.actuate(vehicle.actuators);
  }
}

// Force elements -> Bullet: each vehicle's elements add their wrenches at its centre of mass (vehicles
// are independent, so in parallel when several large hulls make it pay); the added mass converts the
// sum into the wrench Bullet's rigid-body step needs. Gravity is Bullet's.
void Simulation::apply_forces(double t) {
  for (std::size_t i = 0; i < runtime_.size(); ++i) {
    VehicleRuntime& runtime = *runtime_[i];
    const RigidBodyState& body = state_.vehicles[i].body;
    // Bullet is re-seeded from the state every step, so a restored SimState and the uninterrupted
    // run drive Bullet from identical numbers (X_WB -> X_WP is not exactly invertible).
    world_->set_body_state(static_cast<int>(i), body);
    runtime.p_WBcm = body.X_WB * runtime.p_BBcm;
    runtime.v_WBcm = body.v_WB + body.w_WB.cross(runtime.p_WBcm - body.X_WB.translation());
    runtime.w_WB = body.w_WB;
  }
  const auto add_forces = [&](std::size_t i) {
    VehicleRuntime& runtime = *runtime_[i];
    VehicleState& vehicle = state_.vehicles[i];
    runtime.wrench = physics::StepWrench{};
    if (model_.vehicles[i].is_static) return;  // nothing moves it
    const bool belts = runtime.soil && runtime.actuators.drives_surfaces();
    if (belts) runtime.actuators.belt_velocities(vehicle.actuators, runtime.belts);
    double seabed_z_below = -std::numeric_limits<double>::infinity();
    geometry::SeabedHeight::Sample below;
    const Eigen::Vector3d& p_WB = vehicle.body.X_WB.translation();
    if (runtime.seabed_below && runtime.seabed_below->sample(p_WB.x(), p_WB.y(), &below)) {
      seabed_z_below = below.height;
    }
    const physics::ForceInput in{t, vehicle.body, runtime.p_WBcm, runtime.v_WBcm, vehicle.actuators,
                                 &vehicle.soil_shear_W, belts ? &runtime.belts : nullptr, seabed_z_below};
    for (const auto& element : runtime.forces) element->add(in, runtime.wrench);
    // The soil's shear on each driven surface is its drive's load in the next step.
    if (belts) {
      runtime.actuators.take_belt_forces(vehicle.actuators, runtime.soil->last().link_shear_force_W,
                                         vehicle.body.X_WB.linear());
    }
  };
  if (pool_) {
    pool_->run(runtime_.size(), add_forces);
  } else {
    for (std::size_t i = 0; i < runtime_.size(); ++i) add_forces(i);
  }
  for (std::size_t i = 0; i < runtime_.size(); ++i) {
    if (model_.vehicles[i].is_static) continue;
    VehicleRuntime& runtime = *runtime_[i];
    Eigen::Vector3d f_W = runtime.wrench.f_W;
    Eigen::Vector3d tau_W = runtime.wrench.tau_W;
    if (runtime.added_mass) convert_for_added_mass(runtime, state_.vehicles[i], f_W, tau_W);
    world_->add_force_W(static_cast<int>(i), f_W, runtime.p_WBcm);
    world_->add_torque_W(static_cast<int>(i), tau_W);
  }
}

// The wrench Bullet needs so that its rigid-body step follows
// (M_RB + M_A) nu_dot + C_RB nu + C_A nu_r = tau + g + tau_contact (physics/added_mass.h), with M_A0
// scaled by kappa(d) at the centre of mass times the submerged fraction, nu_r relative to the current.
void Simulation::convert_for_added_mass(VehicleRuntime& runtime, const VehicleState& vehicle, Eigen::Vector3d& f_W,
                                        Eigen::Vector3d& tau_W) const {
  const Eigen::Matrix3d R_WB = vehicle.body.X_WB.linear();
  const Eigen::Matrix3d R_BW = R_WB.transpose();
  physics::AddedMassInput in;
  in.kappa = ocean_->kappa(std::max(ocean_->depth(runtime.p_WBcm.z()), 0.0)) * runtime.wrench.submerged_fraction;
  in.nu.head<3>() = R_BW * runtime.v_WBcm;
  in.nu.tail<3>() = R_BW * vehicle.body.w_WB;
  in.nu_r = in.nu;
  in.nu_r.head<3>() -= R_BW * runtime.wrench.v_water_W;
  in.tau.head<3>() = R_BW * f_W;
  in.tau.tail<3>() = R_BW * tau_W;
  in.gravity_B = R_BW * model_.world.gravity_W;
  in.tau_contact = vehicle.contact_wrench_B;
  runtime.tau_bullet_B = runtime.added_mass->bullet_wrench(in);
  runtime.nu0 = in.nu;
  runtime.R_WB0 = R_WB;
  f_W = R_WB * runtime.tau_bullet_B.head<3>();
  tau_W = R_WB * runtime.tau_bullet_B.tail<3>();
}

// Snapshot of the bodies after Bullet's step, the contact wrench of added-mass vehicles for the next
// step, and the time from the step count so it does not drift.
void Simulation::take_snapshot(double dt) {
  const Eigen::Vector3d& g_W = model_.world.gravity_W;
  for (std::size_t i = 0; i < runtime_.size(); ++i) {
    VehicleState& vehicle = state_.vehicles[i];
    vehicle.body = world_->body_state(static_cast<int>(i));
    const VehicleRuntime& runtime = *runtime_[i];
    if (!runtime.added_mass || model_.vehicles[i].is_static) continue;
    if (world_->num_contact_points(static_cast<int>(i)) == 0) {
      vehicle.contact_wrench_B.setZero();
      continue;
    }
    const Eigen::Isometry3d& X_WB = vehicle.body.X_WB;
    const Eigen::Vector3d p_WBcm = X_WB * runtime.p_BBcm;
    const Eigen::Matrix3d R_B0W = runtime.R_WB0.transpose();
    Vector6d nu1_B0;
    nu1_B0.head<3>() = R_B0W * (vehicle.body.v_WB + vehicle.body.w_WB.cross(p_WBcm - X_WB.translation()));
    nu1_B0.tail<3>() = R_B0W * vehicle.body.w_WB;
    vehicle.contact_wrench_B =
        runtime.added_mass->contact_wrench(runtime.nu0, nu1_B0, dt, runtime.tau_bullet_B, R_B0W * g_W);
  }
  ++state_.step_count;
  state_.time = static_cast<double>(state_.step_count) * dt;
}

// The non-finite policy for every vehicle whose state is no longer finite.
void Simulation::reset_non_finite_vehicles() {
  bool any_reset = false;
  for (std::size_t i = 0; i < runtime_.size(); ++i) {
    VehicleState& vehicle = state_.vehicles[i];
    if (is_finite(vehicle)) continue;
    reset_non_finite(model_.vehicles[i], vehicle);
    world_->set_body_state(static_cast<int>(i), vehicle.body);
    any_reset = true;
  }
  // Contact impulses cached from the failed step may be NaN; they would poison the warm start.
  if (any_reset) world_->clear_contacts();
}

// The sensors due at the new time sample the new state, each through its kind (sensors/sensor_kinds.h):
// sampled here, or, for a captured kind, its snapshot handed to the ray-cast workers; then the
// captures due at this step are delivered.
void Simulation::sample_sensors(double dt) {
  for (std::size_t i = 0; i < runtime_.size(); ++i) {
    const VehicleSpec& spec = model_.vehicles[i];
    VehicleRuntime& runtime = *runtime_[i];
    VehicleState& vehicle = state_.vehicles[i];
    for (std::size_t k = 0; k < spec.sensors.size(); ++k) {
      const bool due = sample_due(state_.step_count, dt, spec.sensors[k].rate_hz);
      SensorState& out = vehicle.sensors[k];
      if (!due && out.captures.empty()) continue;
      VehicleRuntime::Sensor& mount = runtime.sensors[k];
      const sensors::SampleContext context{state_.time,  mount.period,   dt,           model_.world,
                                           *ocean_,      *environment_, state_,       static_cast<int>(i),
                                           mount.X_BS,   runtime.p_BBcm, runtime.v_WBcm, runtime.w_WB,
                                           rays_.get()};
      std::visit(
          [&](const auto& kind_spec) {
            using Kind = sensors::KindOf<std::decay_t<decltype(kind_spec)>>;
            auto& kind_state = std::get<typename Kind::State>(out.kind);
            if constexpr (Kind::kCaptures) {
              if (due) {
                PendingCapture& capture = out.captures.emplace_back();
                capture.time = state_.time;
                capture.step_count = state_.step_count;
                capture.due_step = state_.step_count + mount.latency_steps;
                for (const VehicleState& v : state_.vehicles) capture.X_WB.push_back(v.body.X_WB);
                submit_capture<Kind>(i, k, kind_spec, capture);
              }
              while (!out.captures.empty() && out.captures.front().due_step <= state_.step_count) {
                VehicleRuntime::InFlight& flight = mount.in_flight.front();
                constexpr bool kByWork = sensors::CapturesByWork<Kind>::value;
                const bool ready = wait_for_captures_ ||
                                   (kByWork ? flight.done.wait_for(std::chrono::seconds(0))
                                            : flight.hits.wait_for(std::chrono::seconds(0))) == std::future_status::ready;
                if (ready) {
                  if constexpr (kByWork) {
                    flight.done.get();
                    Kind::deliver(context, kind_spec, kind_state,
                                  std::move(*std::static_pointer_cast<typename Kind::Capture>(flight.output)));
                  } else {
                    geometry::RayHits hits = flight.hits.get();
                    Kind::deliver(context, kind_spec, kind_state, hits);
                    service_->recycle(std::move(hits));
                  }
                  out.stamp = out.captures.front().time;
                  ++out.samples;
                } else {
                  ++dropped_captures_;  // late in real time: dropped, never waited for
                  if (flight.dropped) flight.dropped->store(true);  // skipped if not started yet
                }
                mount.in_flight.pop_front();
                out.captures.erase(out.captures.begin());
              }
            } else if (due) {
              Kind::sample(context, kind_spec, kind_state);
              out.stamp = state_.time;
              ++out.samples;
            }
          },
          spec.sensors[k].kind);
    }
  }
}

template <class Kind>
void Simulation::submit_capture(std::size_t vehicle, std::size_t sensor, const typename Kind::Spec& spec,
                                const PendingCapture& capture) {
  VehicleRuntime::Sensor& mount = runtime_[vehicle]->sensors[sensor];
  const sensors::CaptureContext context{capture.time,  capture.step_count, capture.X_WB, static_cast<int>(vehicle),
                                        mount.X_BS,    &model_,            ocean_.get()};
  VehicleRuntime::InFlight flight;
  if constexpr (sensors::CapturesByWork<Kind>::value) {
    auto output = std::make_shared<typename Kind::Capture>();
    const auto& state = std::get<typename Kind::State>(state_.vehicles[vehicle].sensors[sensor].kind);
    sensors::CaptureWork work = Kind::capture(context, spec, state, *output);
    flight.dropped = std::make_shared<std::atomic<bool>>(false);
    flight.done = raycast_service().submit(
        capture.X_WB, [work = std::move(work), output, dropped = flight.dropped, skipped = skipped_captures_](
                          const geometry::EmbreeScene& scene, const ParallelFor& parallel) {
          if (dropped->load()) {
            skipped->fetch_add(1);
            return;
          }
          work(scene, parallel);
        });
    flight.output = std::move(output);
  } else {
    flight.hits = raycast_service().submit(Kind::capture_rays(context, spec));
  }
  mount.in_flight.push_back(std::move(flight));
}

// After a restore: the captures in flight belong to another history; the restored state's pending
// captures are cast again from their snapshots.
void Simulation::restart_captures() {
  for (std::size_t i = 0; i < runtime_.size(); ++i) {
    for (std::size_t k = 0; k < runtime_[i]->sensors.size(); ++k) {
      VehicleRuntime::Sensor& mount = runtime_[i]->sensors[k];
      mount.in_flight.clear();
      for (const PendingCapture& capture : state_.vehicles[i].sensors[k].captures) {
        std::visit(
            [&](const auto& kind_spec) {
              using Kind = sensors::KindOf<std::decay_t<decltype(kind_spec)>>;
              if constexpr (Kind::kCaptures) submit_capture<Kind>(i, k, kind_spec, capture);
            },
            model_.vehicles[i].sensors[k].kind);
      }
    }
  }
}

geometry::SceneRays& Simulation::scene_rays() {
  if (!rays_) {
    // Embree builds its BVHs on world.threads threads (its own default: all).
    const std::string device_config =
        model_.world.threads > 0 ? "threads=" + std::to_string(model_.world.threads) : std::string();
    rays_ = std::make_unique<geometry::SceneRays>(geometry::build_world_scene(model_, device_config));
  }
  return *rays_;
}

geometry::RaycastService& Simulation::raycast_service() {
  if (!service_) {
    geometry::RaycastServiceOptions options;
    const WorldSpec& world = model_.world;
    options.num_threads = world.raycast_threads > 0 ? world.raycast_threads : world.effective_threads();
    service_ = std::make_unique<geometry::RaycastService>(scene_rays().scene().view(), options);
  }
  return *service_;
}

}  // namespace hadal
