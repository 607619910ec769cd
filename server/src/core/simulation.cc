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
#include <variant>

#include "hadal/core/rate_divider.h"
#include "hadal/geometry/raycast_service.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/geometry/scene_rays.h"
#include "hadal/geometry/seabed_height.h"
#include "hadal/geometry/world_scene.h"
#include "hadal/physics/actuators.h"
#include "hadal/physics/added_mass.h"
#include "hadal/physics/articulated_dynamics.h"
#include "hadal/physics/articulation.h"
#include "hadal/physics/bullet_world.h"
#include "hadal/physics/fluid_forces.h"
#include "hadal/physics/joint_servo.h"
#include "hadal/physics/mass_properties.h"
#include "hadal/physics/ocean.h"
#include "hadal/physics/terramechanics.h"
#include "hadal/sensors/acoustic_channel.h"
#include "hadal/sensors/sample_context.h"
#include "hadal/sensors/sensor_kinds.h"
#include "worker_pool.h"

namespace hadal {
namespace {
bool on_joint(const SensorSpec& sensor);  // below
}  // namespace

// What the step needs per vehicle besides its state: constants derived from the model, and the step's
// scratch. Holds references into the model: made in place, never moved.
struct Simulation::VehicleRuntime {
  VehicleRuntime(const VehicleSpec& spec, const WorldSpec& world, const physics::MassProperties& mass_properties,
                 const physics::Ocean& ocean, const geometry::SeabedHeight* seabed,
                 const physics::Articulation* articulation_of)
      : actuators(spec, world, &ocean),
        seabed_below(physics::VehicleActuators::needs_seabed(spec) ? seabed : nullptr),
        p_BBcm(mass_properties.p_BBcm),
        mass(mass_properties.mass),
        articulation(articulation_of) {
    for (const SensorSpec& sensor : spec.sensors) {
      if (on_joint(sensor)) joint_sensor_rates_hz.push_back(sensor.rate_hz);
      Sensor& mount = sensors.emplace_back();
      mount.X_BS = spec.links[static_cast<std::size_t>(sensor.link_index)].X_BL * sensor.X_LS;
      mount.period = 1.0 / sensor.rate_hz;
      mount.latency_steps = sensor.latency_steps(world.physics_rate_hz);
      mount.by_event = std::visit(
          [](const auto& kind) { return sensors::SamplesByEvent<sensors::KindOf<std::decay_t<decltype(kind)>>>::value; },
          sensor.kind);
      // A sensor on a moving link follows its body K (its mounting in B is worked out at each sample).
      if (articulation) {
        mount.body = articulation->body_of_link(sensor.link_index);
        mount.X_KS = articulation->X_KL(sensor.link_index) * sensor.X_LS;
      }
    }
    if (articulation) {
      make_bodies(spec, world, ocean);
      return;
    }
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
  }

  // An articulated vehicle's bodies, each with its own force elements in the order they add up (the base
  // body: the actuators first), the fluid model over its own links in its frame K (a body without
  // geometry meets no water) and its added mass: the base body's from fluid.added_mass as for a rigid
  // vehicle, a moving body's Lamb's ellipsoid fitted to its own hull unless the model is none.
  void make_bodies(const VehicleSpec& spec, const WorldSpec& world, const physics::Ocean& ocean) {
    const physics::Articulation& a = *articulation;
    dynamics = std::make_unique<physics::ArticulatedDynamics>(a, spec.is_static);
    bodies.resize(static_cast<std::size_t>(a.num_bodies()));
    for (int k = 0; k < a.num_bodies(); ++k) {
      Body& body = bodies[static_cast<std::size_t>(k)];
      const physics::Articulation::Body& tree = a.body(k);
      if (k == 0) body.forces.push_back(std::make_unique<physics::ActuatorForces>(actuators));
      VehicleSpec part;
      part.name = spec.name + "' link '" + spec.links[static_cast<std::size_t>(tree.links.front())].name;
      part.fluid = spec.fluid;
      for (int l : tree.links) {
        LinkSpec link = spec.links[static_cast<std::size_t>(l)];
        link.X_BL = a.X_KL(l);
        link.parent = -1;
        link.joint = JointSpec{};
        part.links.push_back(std::move(link));
      }
      if (k > 0 && part.fluid.added_mass.model != AddedMassModel::kNone) {
        part.fluid.added_mass = AddedMassSpec{};
        part.fluid.added_mass.model = AddedMassModel::kEllipsoid;  // fitted to this body's hull
      }
      if (geometry::has_surface_geometry(part.links)) {
        physics::VehicleFluid fluid = physics::make_vehicle_fluid(part, world, ocean, tree.mass_K.p_BBcm);
        body.forces.push_back(std::move(fluid.force));
        fluid_faces += fluid.faces;
        body.M_A0 = fluid.M_A0;
        has_added_mass = has_added_mass || !body.M_A0.isZero(0.0);
      }
      if (world.dynamics.earth_rotation) {
        body.forces.push_back(std::make_unique<physics::EarthRotationForce>(world, tree.mass_K.mass));
      }
    }
    M_A0 = bodies[0].M_A0;
    motors.resize(static_cast<std::size_t>(a.num_dofs()));
    for (int j = 0; j < a.num_dofs(); ++j) {
      const JointSpec& joint = a.body(j + 1).joint;
      motors[static_cast<std::size_t>(j)].servo.effort_limit = joint.effort_limit;
      motors[static_cast<std::size_t>(j)].servo.velocity_limit = joint.velocity_limit;
    }
    for (const physics::JointControllerSpec& controller : spec.joint_controllers) {
      for (std::size_t i = 0; i < controller.joints.size(); ++i) {
        JointMotor& motor = motors.at(static_cast<std::size_t>(controller.joints[i]));
        // A gripper's fingers run the position law (physics/joint_servo.h).
        motor.mode = controller.mode == physics::JointCommandMode::kGripper ? physics::JointCommandMode::kPosition
                                                                             : controller.mode;
        motor.servo.kp = i < controller.kp.size() ? controller.kp[i] : 0.0;
        motor.servo.kd = i < controller.kd.size() ? controller.kd[i] : 0.0;
      }
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
    // The mounting in B; for a sensor on a moving link (body > 0), at the last sample.
    Eigen::Isometry3d X_BS = Eigen::Isometry3d::Identity();
    int body = 0;  // an articulated vehicle's body the sensor's link is part of (0: the base, fixed in B)
    Eigen::Isometry3d X_KS = Eigen::Isometry3d::Identity();  // the mounting in that body's frame K
    double period = 0.0;  // nominal sample period 1 / rate_hz [s]
    std::uint64_t latency_steps = 0;
    bool by_event = false;  // its kind's samples are events (sensors::SamplesByEvent): advanced every step
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

  // An articulated vehicle (null for a rigid one): its tree (BulletWorld's), and per body its force
  // elements, added mass at the surface (about its centre of mass, K axes) and the step's wrench; the
  // equations of motion for the added mass; the step's body poses.
  const physics::Articulation* articulation = nullptr;
  struct Body {
    std::vector<std::unique_ptr<physics::ForceElement>> forces;
    Matrix6d M_A0 = Matrix6d::Zero();
    physics::StepWrench wrench;
  };
  std::vector<Body> bodies;
  // Per moving joint: its motor's law (its controller's mode and gains with the joint's limits; effort mode
  // for a joint in no controller).
  struct JointMotor {
    physics::JointCommandMode mode = physics::JointCommandMode::kEffort;
    physics::JointServoSpec servo;
  };
  std::vector<JointMotor> motors;
  std::unique_ptr<physics::ArticulatedDynamics> dynamics;
  // Each body's wrench handed to Bullet in the step (at its centre of mass, W; gravity and joint torques
  // apart), for the joints' wrenches (VehicleState::joint_wrenches_L).
  std::vector<physics::ArticulatedDynamics::Wrench> handed_W;
  // The rates of the sensors that read those wrenches (force_torque): they are worked out only for the
  // steps at whose end one of them samples (Simulation::measures_joint_wrenches).
  std::vector<double> joint_sensor_rates_hz;
  bool has_added_mass = false;
  std::vector<Eigen::Isometry3d> X_WK;
  // A floating articulated vehicle's momentum balance over the step (Simulation::keep_momentum): the
  // centre of mass, momentum and angular momentum about that centre the applied wrenches give.
  struct MomentumTarget {
    bool active = false;
    Eigen::Vector3d c_W = Eigen::Vector3d::Zero();
    Eigen::Vector3d P_W = Eigen::Vector3d::Zero();
    Eigen::Vector3d L_W = Eigen::Vector3d::Zero();
  } target;
  // For the constraint force (VehicleState::constraint_force): the step's generalised velocity, bias and
  // the generalised force Bullet was handed, at the step's start (`dynamics` keeps the mass matrix's state
  // until the next step's update()).
  Eigen::VectorXd u0, Q_given;
  Eigen::VectorXd c0;
  // What a step of an articulated vehicle works in, kept so that a step allocates nothing.
  struct Work {
    physics::ArticulatedDynamics::ImplicitJoints implicit;
    Eigen::VectorXd joint_torques, u1, u_dot, Q_c;
    std::vector<physics::ArticulatedDynamics::Wrench> wrenches;
    std::vector<physics::ArticulatedDynamics::AddedMassBody> added;
    physics::ArticulatedDynamics::Reactions reactions;
    std::vector<Eigen::Isometry3d> X_WK_after;  // the bodies' poses after the step (keep_momentum)
  } work;
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
  for (const auto& wrench : vehicle.joint_wrenches_L) {
    if (!wrench.allFinite()) return false;
  }
  for (const auto* joints : {&vehicle.joint_positions, &vehicle.joint_velocities, &vehicle.joint_efforts,
                             &vehicle.joint_targets, &vehicle.joint_target_rates, &vehicle.constraint_force}) {
    for (double value : *joints) {
      if (!std::isfinite(value)) return false;
    }
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

// Trait<K>::value of the sensor's kind K (sensors/sensor_kind.h's mounting traits).
template <template <class, class> class Trait>
bool kind_is(const SensorSpec& sensor) {
  return std::visit(
      [](const auto& spec) { return Trait<sensors::KindOf<std::decay_t<decltype(spec)>>, void>::value; },
      sensor.kind);
}
// A sensor whose kind measures its link's joint (the force/torque sensor).
bool on_joint(const SensorSpec& sensor) { return kind_is<sensors::OnJoint>(sensor); }
// A sensor whose kind may follow a moving link (not the IMU, not the DVL).
bool follows_moving_link(const SensorSpec& sensor) { return kind_is<sensors::OnMovingLink>(sensor); }
// A vehicle whose joints' wrenches are worked out (VehicleState::joint_wrenches_L): one with such a sensor.
bool measures_joints(const VehicleSpec& spec) {
  return std::any_of(spec.sensors.begin(), spec.sensors.end(), on_joint);
}

VehicleState initial_vehicle_state(const VehicleSpec& spec) {
  VehicleState vehicle;
  vehicle.body.X_WB = spec.X_WB_initial;
  vehicle.body.v_WB = spec.v_WB_initial;
  vehicle.body.w_WB = spec.w_WB_initial;
  vehicle.actuators = physics::VehicleActuators::initial_states(spec);
  vehicle.command_source = spec.schedule.empty() ? CommandSource::kNone : CommandSource::kSchedule;
  // A moving joint starts a body, in link order (physics/articulation.h). A position-controlled joint
  // holds where it starts; every other command starts at zero.
  for (const LinkSpec& link : spec.links) {
    if (link.joint.type == JointType::kFixed) continue;
    vehicle.joint_positions.push_back(link.joint.initial);
    vehicle.joint_velocities.push_back(0.0);
    vehicle.joint_efforts.push_back(0.0);
    vehicle.joint_targets.push_back(0.0);
    vehicle.joint_target_rates.push_back(0.0);
    vehicle.joint_effort_caps.push_back(std::numeric_limits<double>::infinity());
  }
  vehicle.joint_trajectories.assign(spec.joint_controllers.size(), nullptr);
  if (measures_joints(spec)) {
    vehicle.joint_wrenches_L.assign(spec.links.size(), Eigen::Matrix<double, 6, 1>::Zero());
  }
  for (const physics::JointControllerSpec& controller : spec.joint_controllers) {
    if (controller.mode != physics::JointCommandMode::kPosition &&
        controller.mode != physics::JointCommandMode::kGripper) {
      continue;
    }
    for (int joint : controller.joints) {
      const auto j = static_cast<std::size_t>(joint);
      vehicle.joint_targets.at(j) = vehicle.joint_positions.at(j);
    }
  }
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
  const VehicleState initial = initial_vehicle_state(spec);
  vehicle.joint_positions = initial.joint_positions;
  vehicle.joint_velocities = initial.joint_velocities;
  vehicle.joint_efforts = initial.joint_efforts;
  vehicle.joint_targets = initial.joint_targets;
  vehicle.joint_target_rates = initial.joint_target_rates;
  vehicle.joint_effort_caps = initial.joint_effort_caps;
  vehicle.joint_trajectories = initial.joint_trajectories;
  vehicle.joint_wrenches_L = initial.joint_wrenches_L;
  vehicle.constraint_force.clear();
  vehicle.faults |= kFaultNonFiniteState;
  ++vehicle.fault_resets;
}

std::string format_number(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);  // shortest round trip
  return std::string(buffer, result.ptr);
}

// What issue 40's first part does not simulate on an articulated vehicle yet, refused by name (the scenario
// reader refuses mounts on moving links with the key's position; this is the check for models built in code).
void validate_articulated(const VehicleSpec& vehicle, const WorldSpec& world) {
  for (const SensorSpec& sensor : vehicle.sensors) {
    if (!on_joint(sensor)) continue;
    const auto link = static_cast<std::size_t>(sensor.link_index);
    if (link >= vehicle.links.size() || vehicle.links[link].joint.type == JointType::kFixed) {
      throw std::invalid_argument("vehicle '" + vehicle.name + "': sensor '" + sensor.name + "' (" +
                                  std::string(sensor.type()) + ") must be on a link on a moving joint");
    }
  }
  if (!physics::is_articulated(vehicle.links)) return;
  const std::string prefix = "vehicle '" + vehicle.name + "': an articulated vehicle (a link on a joint) ";
  if (vehicle.fluid.model != FluidModelType::kSurface) {
    throw std::invalid_argument(prefix + "needs fluid.model surface");
  }
  if (vehicle.seabed_contact == SeabedContact::kSoil) {
    throw std::invalid_argument(prefix + "cannot have seabed_contact soil yet");
  }
  if (!world.dynamics.gyroscopic) throw std::invalid_argument(prefix + "needs world.dynamics.gyroscopic");
  const auto refuse_moving = [&](int link, const std::string& what) {
    if (link >= 0 && link < static_cast<int>(vehicle.links.size()) && link_moves(vehicle.links, link)) {
      throw std::invalid_argument(prefix + what + " is on link '" +
                                  vehicle.links[static_cast<std::size_t>(link)].name +
                                  "', which moves: sensors of this kind (they measure the base body's motion) and "
                                  "actuators are not supported on moving links");
    }
  };
  for (const SensorSpec& sensor : vehicle.sensors) {
    if (!on_joint(sensor) && !follows_moving_link(sensor)) {
      refuse_moving(sensor.link_index, "sensor '" + sensor.name + "'");
    }
  }
  for (const ActuatorSpec& actuator : vehicle.actuators) {
    refuse_moving(actuator.link_index, std::string(actuator.type()) + " '" + actuator.name + "'");
  }
}

// The model with each vehicle's locked joints fixed at their locks (geometry::lock_joints; the loader has done
// it for a loaded scenario, a model built in code may not have).
Model with_locked_joints(Model model) {
  for (VehicleSpec& vehicle : model.vehicles) lock_joints(vehicle.links);
  return model;
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
    validate_articulated(vehicle, model.world);
  }
  return model;
}

}  // namespace

void remove_cameras(Model& model) {
  for (VehicleSpec& vehicle : model.vehicles) {
    auto& sensors = vehicle.sensors;
    sensors.erase(std::remove_if(sensors.begin(), sensors.end(),
                                 [](const SensorSpec& s) {
                                   return std::visit(
                                       [](const auto& spec) {
                                         using Kind = sensors::KindOf<std::decay_t<decltype(spec)>>;
                                         return sensors::RendersImages<Kind>::value;
                                       },
                                       s.kind);
                                 }),
                  sensors.end());
  }
}

Simulation::Simulation(Model model)
    : model_(with_locked_joints(std::move(model))),
      world_(std::make_unique<physics::BulletWorld>(validated(model_))),
      ray_bodies_(model_) {
  ocean_ = std::make_unique<physics::Ocean>(model_.world);
  for (const VehicleSpec& spec : model_.vehicles) {
    const bool needs_seabed = spec.seabed_contact == SeabedContact::kSoil ||
                              physics::VehicleActuators::needs_seabed(spec) || !model_.cables.empty();
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
    const int index = static_cast<int>(i);
    runtime_.push_back(std::make_unique<VehicleRuntime>(spec, model_.world, world_->mass_properties(index), *ocean_,
                                                        seabed_height_.get(), world_->articulation(index)));
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
  if (state.cables.size() != model_.cables.size()) {
    throw std::invalid_argument("set_state: expected " + std::to_string(model_.cables.size()) + " cables, got " +
                                std::to_string(state.cables.size()));
  }
  for (std::size_t c = 0; c < model_.cables.size(); ++c) {
    const auto nodes = static_cast<std::size_t>(model_.cables[c].spec.segments + 1);
    if (state.cables[c].p_W.size() != nodes || state.cables[c].v_W.size() != nodes) {
      throw std::invalid_argument("set_state: cable '" + model_.cables[c].name + "': expected " +
                                  std::to_string(nodes) + " nodes");
    }
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
    const physics::Articulation* articulation = world_->articulation(static_cast<int>(i));
    const std::size_t joints = articulation ? static_cast<std::size_t>(articulation->num_dofs()) : 0;
    if (vehicle.joint_positions.size() != joints || vehicle.joint_velocities.size() != joints ||
        vehicle.joint_efforts.size() != joints || vehicle.joint_targets.size() != joints ||
        vehicle.joint_target_rates.size() != joints || vehicle.joint_effort_caps.size() != joints) {
      throw std::invalid_argument(prefix + "expected " + std::to_string(joints) + " joint positions, rates, " +
                                  "efforts, targets, target rates and effort caps, got " +
                                  std::to_string(vehicle.joint_positions.size()) + ", " +
                                  std::to_string(vehicle.joint_velocities.size()) + ", " +
                                  std::to_string(vehicle.joint_efforts.size()) + ", " +
                                  std::to_string(vehicle.joint_targets.size()) + ", " +
                                  std::to_string(vehicle.joint_target_rates.size()) + " and " +
                                  std::to_string(vehicle.joint_effort_caps.size()));
    }
    const std::size_t wrenches = measures_joints(spec) ? spec.links.size() : 0;
    if (vehicle.joint_wrenches_L.size() != wrenches) {
      throw std::invalid_argument(prefix + "expected " + std::to_string(wrenches) + " joint wrenches (one per link " +
                                  "with a force_torque sensor on the vehicle, else none), got " +
                                  std::to_string(vehicle.joint_wrenches_L.size()));
    }
    if (vehicle.joint_trajectories.size() != spec.joint_controllers.size()) {
      throw std::invalid_argument(prefix + "expected " + std::to_string(spec.joint_controllers.size()) +
                                  " joint trajectory slots (one per joint controller), got " +
                                  std::to_string(vehicle.joint_trajectories.size()));
    }
    const std::size_t generalised = articulation ? joints + (spec.is_static ? 0 : 6) : 0;
    if (!vehicle.constraint_force.empty() && vehicle.constraint_force.size() != generalised) {
      throw std::invalid_argument(prefix + "expected " + std::to_string(generalised) + " constraint forces (or none), "
                                  "got " + std::to_string(vehicle.constraint_force.size()));
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
    write_body(static_cast<int>(i), vehicle);
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
  lay_cables_straight(state);
  return state;
}

void Simulation::lay_cables_straight(SimState& state) const {
  state.cables.resize(model_.cables.size());
  for (std::size_t c = 0; c < model_.cables.size(); ++c) {
    const auto ends = cable_ends_W(c, state);
    state.cables[c] = physics::straight_cable(model_.cables[c].spec, ends[0], ends[1]);
  }
}

Simulation::HeldPoint Simulation::cable_end_point(const physics::CableEndSpec& end, const SimState& state) const {
  HeldPoint held;
  if (!end.on_vehicle()) {
    held.p_W = end.position + state.time * end.velocity_W;
    held.v_W = end.velocity_W;
    return held;
  }
  const auto v = static_cast<std::size_t>(end.vehicle_index);
  const VehicleState& vehicle = state.vehicles[v];
  const physics::Articulation* articulation = runtime_[v]->articulation;
  Eigen::Isometry3d X_WK = vehicle.body.X_WB;  // the frame of the body holding it
  Eigen::Vector3d v_WK = vehicle.body.v_WB, w_WK = vehicle.body.w_WB;
  Eigen::Vector3d p_K = model_.vehicles[v].links[static_cast<std::size_t>(end.link_index)].X_BL * end.position;
  if (articulation && articulation->body_of_link(end.link_index) != 0) {  // a link that moves on a joint
    held.body = articulation->body_of_link(end.link_index);
    const auto n = static_cast<Eigen::Index>(vehicle.joint_positions.size());
    const std::vector<Eigen::Isometry3d> poses = articulation->poses_W(
        vehicle.body.X_WB, Eigen::Map<const Eigen::VectorXd>(vehicle.joint_positions.data(), n));
    const std::vector<physics::Articulation::BodyVelocity> velocities = articulation->velocities_W(
        poses, vehicle.body.v_WB, vehicle.body.w_WB, Eigen::Map<const Eigen::VectorXd>(vehicle.joint_velocities.data(), n));
    const auto k = static_cast<std::size_t>(held.body);
    X_WK = poses[k];
    v_WK = velocities[k].v_WK;
    w_WK = velocities[k].w_WK;
    p_K = articulation->X_KL(end.link_index) * end.position;
  }
  held.p_W = X_WK * p_K;
  held.v_W = v_WK + w_WK.cross(held.p_W - X_WK.translation());
  return held;
}

std::array<Eigen::Vector3d, 2> Simulation::cable_ends_W(std::size_t c, const SimState& state) const {
  const physics::CableModel& cable = model_.cables[c];
  std::array<Eigen::Vector3d, 2> p_W;
  for (std::size_t e = 0; e < 2; ++e) p_W[e] = cable_end_point(cable.ends[e], state).p_W;
  const Eigen::Vector3d down(0.0, 0.0, -cable.spec.length);
  if (cable.ends[0].free) p_W[0] = p_W[1] + down;
  if (cable.ends[1].free) p_W[1] = p_W[0] + down;
  return p_W;
}

std::string Simulation::check_winch_command(int cable_index, double speed, double target_length) const {
  if (cable_index < 0 || static_cast<std::size_t>(cable_index) >= model_.cables.size()) return "unknown cable";
  const physics::CableModel& cable = model_.cables[static_cast<std::size_t>(cable_index)];
  const int e = cable.winch_end();
  if (e < 0) return "has no winch";
  const std::string reason = physics::check_winch_command(*cable.ends[static_cast<std::size_t>(e)].winch, speed, target_length);
  return reason.empty() ? "" : "winch: " + reason;
}

std::string Simulation::command_winch(int cable_index, double speed, double target_length) {
  std::string reason = check_winch_command(cable_index, speed, target_length);
  if (!reason.empty()) return reason;
  physics::WinchState& winch = state_.cables[static_cast<std::size_t>(cable_index)].winch;
  winch.command_speed = speed;
  winch.target_length = target_length;
  return "";
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
  lay_cables_straight(state);  // between where their ends now are
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

namespace {

// The vehicle's modem called `name` (its spec and its state in `state`), or the reason there is none.
struct ModemRef {
  int sensor = -1;
  const sensors::ModemSpec* spec = nullptr;
  std::string refusal;
};
ModemRef find_modem(const std::vector<VehicleSpec>& vehicles, int vehicle_index, const std::string& name) {
  if (vehicle_index < 0 || vehicle_index >= static_cast<int>(vehicles.size())) {
    return {-1, nullptr, "unknown vehicle index " + std::to_string(vehicle_index)};
  }
  const VehicleSpec& vehicle = vehicles[static_cast<std::size_t>(vehicle_index)];
  std::string modems;
  for (std::size_t k = 0; k < vehicle.sensors.size(); ++k) {
    const SensorSpec& sensor = vehicle.sensors[k];
    const auto* spec = std::get_if<sensors::ModemSpec>(&sensor.kind);
    if (sensor.name == name) {
      if (spec) return {static_cast<int>(k), spec, ""};
      return {-1, nullptr, "sensor '" + name + "' of '" + vehicle.name + "' is a " + std::string(sensor.type()) +
                               ", not a modem"};
    }
    if (spec) modems += (modems.empty() ? "'" : ", '") + sensor.name + "'";
  }
  return {-1, nullptr, "vehicle '" + vehicle.name + "' has no modem '" +
                           (name.size() <= 64 ? name : name.substr(0, 61) + "...") + "' (its modems: " +
                           (modems.empty() ? "none" : modems) + ")"};
}

}  // namespace

std::string Simulation::check_packet(int vehicle_index, const std::string& modem, const std::string& destination,
                                     std::size_t payload_bytes) const {
  const ModemRef ref = find_modem(model_.vehicles, vehicle_index, modem);
  if (!ref.spec) return ref.refusal;
  return sensors::ModemSensor::check_send(
      model_.vehicles, vehicle_index, ref.sensor, *ref.spec,
      state_of<sensors::ModemSensor>(state_.vehicles[static_cast<std::size_t>(vehicle_index)].sensors[static_cast<std::size_t>(ref.sensor)]),
      state_.time, destination, payload_bytes);
}

std::string Simulation::send_packet(int vehicle_index, const std::string& modem, const std::string& destination,
                                    std::vector<std::uint8_t> payload) {
  const ModemRef ref = find_modem(model_.vehicles, vehicle_index, modem);
  if (!ref.spec) return ref.refusal;
  auto& state = std::get<sensors::ModemSensor::State>(
      state_.vehicles[static_cast<std::size_t>(vehicle_index)].sensors[static_cast<std::size_t>(ref.sensor)].kind);
  return sensors::ModemSensor::send(model_.vehicles, vehicle_index, ref.sensor, *ref.spec, state, state_.time,
                                    destination, std::move(payload));
}

std::vector<sensors::AcousticLink> Simulation::acoustic_links() {
  std::vector<sensors::AcousticLink> links;
  const double dt = model_.world.step_size();
  for (std::size_t i = 0; i < runtime_.size(); ++i) {
    const VehicleSpec& spec = model_.vehicles[i];
    VehicleRuntime& runtime = *runtime_[i];
    for (std::size_t k = 0; k < spec.sensors.size(); ++k) {
      std::visit(
          [&](const auto& kind_spec) {
            using Kind = sensors::KindOf<std::decay_t<decltype(kind_spec)>>;
            if constexpr (sensors::HasAcousticLinks<Kind>::value) {
              const sensors::SampleContext context = sensor_context(i, k, runtime.sensors[k].X_BS, dt);
              Kind::acoustic_links(context, kind_spec,
                                   std::get<typename Kind::State>(state_.vehicles[i].sensors[k].kind), links);
            }
          },
          spec.sensors[k].kind);
    }
  }
  if (!links.empty()) {
    const sensors::AcousticChannel& channel = environment_->acoustic_channel(*ocean_, model_.world.acoustics);
    for (sensors::AcousticLink& link : links) link.sound_speed = channel.mean_sound_speed(link.p_Wemit, link.p_Wtarget);
  }
  return links;
}

std::string Simulation::set_joint_efforts(int vehicle_index, const std::vector<double>& efforts) {
  if (vehicle_index < 0 || vehicle_index >= static_cast<int>(model_.vehicles.size())) {
    return "unknown vehicle index " + std::to_string(vehicle_index);
  }
  const VehicleSpec& spec = model_.vehicles[static_cast<std::size_t>(vehicle_index)];
  const physics::Articulation* articulation = world_->articulation(vehicle_index);
  if (!articulation) return "vehicle '" + spec.name + "' has no moving joints";
  if (efforts.size() != static_cast<std::size_t>(articulation->num_dofs())) {
    return "vehicle '" + spec.name + "': " + std::to_string(efforts.size()) + " joint efforts for " +
           std::to_string(articulation->num_dofs()) + " joints";
  }
  for (const physics::JointControllerSpec& controller : spec.joint_controllers) {
    if (controller.mode != physics::JointCommandMode::kEffort) {
      return "vehicle '" + spec.name + "': joint controller '" + controller.name + "' commands its joints' " +
             physics::to_string(controller.mode) + ": efforts go to joints of effort controllers or of none";
    }
  }
  for (std::size_t j = 0; j < efforts.size(); ++j) {
    if (!std::isfinite(efforts[j])) {
      return "vehicle '" + spec.name + "': joint effort " + std::to_string(j) + " is not finite";
    }
  }
  state_.vehicles[static_cast<std::size_t>(vehicle_index)].joint_targets = efforts;
  return {};
}

std::string Simulation::set_joint_commands(int vehicle_index, const std::string& controller_name,
                                           const std::vector<double>& values) {
  const std::string reason = check_joint_commands(vehicle_index, controller_name, values);
  if (!reason.empty()) return reason;
  const VehicleSpec& spec = model_.vehicles[static_cast<std::size_t>(vehicle_index)];
  const physics::JointControllerSpec& controller = *find_joint_controller(vehicle_index, controller_name, nullptr);
  VehicleState& vehicle = state_.vehicles[static_cast<std::size_t>(vehicle_index)];
  const bool gripper = controller.mode == physics::JointCommandMode::kGripper;
  for (std::size_t k = 0; k < controller.joints.size(); ++k) {
    const auto j = static_cast<std::size_t>(controller.joints[k]);
    vehicle.joint_targets[j] = gripper ? controller.multipliers[k] * values[0] : values[k];
    vehicle.joint_target_rates[j] = 0.0;
    if (gripper) vehicle.joint_effort_caps[j] = values.size() > 1 ? values[1] : std::numeric_limits<double>::infinity();
  }
  // A command ends the group's trajectory.
  vehicle.joint_trajectories[static_cast<std::size_t>(&controller - spec.joint_controllers.data())].reset();
  return {};
}

const physics::JointControllerSpec* Simulation::find_joint_controller(int vehicle_index, const std::string& name,
                                                                      std::string* reason) const {
  if (vehicle_index < 0 || vehicle_index >= static_cast<int>(model_.vehicles.size())) {
    if (reason) *reason = "unknown vehicle index " + std::to_string(vehicle_index);
    return nullptr;
  }
  const VehicleSpec& spec = model_.vehicles[static_cast<std::size_t>(vehicle_index)];
  const auto found = std::find_if(spec.joint_controllers.begin(), spec.joint_controllers.end(),
                                  [&](const physics::JointControllerSpec& c) { return c.name == name; });
  if (found != spec.joint_controllers.end()) return &*found;
  if (reason) {
    std::string known;
    for (const auto& c : spec.joint_controllers) known += (known.empty() ? "" : ", ") + c.name;
    *reason = "vehicle '" + spec.name + "' has no joint controller '" + name + "' (" +
              (known.empty() ? std::string("it has none") : "it has " + known) + ")";
  }
  return nullptr;
}

std::string Simulation::check_joint_commands(int vehicle_index, const std::string& controller_name,
                                             const std::vector<double>& values) const {
  std::string reason;
  const physics::JointControllerSpec* found = find_joint_controller(vehicle_index, controller_name, &reason);
  if (!found) return reason;
  const VehicleSpec& spec = model_.vehicles[static_cast<std::size_t>(vehicle_index)];
  const physics::JointControllerSpec& controller = *found;
  const std::string prefix = "vehicle '" + spec.name + "': joint controller '" + controller.name + "': ";
  const physics::Articulation& a = *world_->articulation(vehicle_index);
  if (controller.mode == physics::JointCommandMode::kGripper) {
    if (values.empty() || values.size() > 2) {
      return prefix + std::to_string(values.size()) + " values: a gripper takes [position] or [position, max_effort]";
    }
    if (!std::isfinite(values[0])) return prefix + "the position is not finite";
    if (values.size() > 1 && !(values[1] > 0.0 && std::isfinite(values[1]))) {
      return prefix + "max_effort " + format_number(values[1]) + " must be finite and > 0";
    }
    for (std::size_t k = 0; k < controller.joints.size(); ++k) {
      const JointSpec& joint = a.body(controller.joints[k] + 1).joint;
      const std::string& link =
          joint_name(spec.links[static_cast<std::size_t>(a.body(controller.joints[k] + 1).joint_link)]);
      const double target = controller.multipliers[k] * values[0];
      if (target < joint.lower || target > joint.upper) {
        return prefix + "position " + format_number(values[0]) + " puts '" + link + "' at " + format_number(target) +
               ", outside its limits [" + format_number(joint.lower) + ", " + format_number(joint.upper) + "]";
      }
    }
    return {};
  }
  if (values.size() != controller.joints.size()) {
    return prefix + std::to_string(values.size()) + " values for " + std::to_string(controller.joints.size()) +
           " joints";
  }
  for (std::size_t k = 0; k < values.size(); ++k) {
    const JointSpec& joint = a.body(controller.joints[k] + 1).joint;
    const int joint_link = a.body(controller.joints[k] + 1).joint_link;
    const std::string& link = joint_name(spec.links[static_cast<std::size_t>(joint_link)]);
    if (!std::isfinite(values[k])) return prefix + "value " + std::to_string(k) + " (" + link + ") is not finite";
    const bool outside = values[k] < joint.lower || values[k] > joint.upper;
    if (controller.mode == physics::JointCommandMode::kPosition && outside) {
      return prefix + "position " + format_number(values[k]) + " for '" + link + "' is outside its limits [" +
             format_number(joint.lower) + ", " + format_number(joint.upper) + "]";
    }
  }
  return {};
}

std::string Simulation::set_joint_trajectory(int vehicle_index, const std::string& controller_name,
                                             const physics::JointTrajectoryCommand& command) {
  physics::JointTrajectory trajectory;
  const std::string reason = group_trajectory(vehicle_index, controller_name, command, &trajectory);
  if (!reason.empty()) return reason;
  trajectory.start_time = command.start_time.value_or(state_.time);
  const VehicleSpec& spec = model_.vehicles[static_cast<std::size_t>(vehicle_index)];
  const physics::JointControllerSpec& controller = *find_joint_controller(vehicle_index, controller_name, nullptr);
  state_.vehicles[static_cast<std::size_t>(vehicle_index)]
      .joint_trajectories[static_cast<std::size_t>(&controller - spec.joint_controllers.data())] =
      std::make_shared<const physics::JointTrajectory>(std::move(trajectory));
  return {};
}

std::string Simulation::check_joint_trajectory(int vehicle_index, const std::string& controller_name,
                                               const physics::JointTrajectoryCommand& command) const {
  return group_trajectory(vehicle_index, controller_name, command, nullptr);
}

std::string Simulation::group_trajectory(int vehicle_index, const std::string& controller_name,
                                         const physics::JointTrajectoryCommand& command,
                                         physics::JointTrajectory* out) const {
  std::string reason;
  const physics::JointControllerSpec* controller = find_joint_controller(vehicle_index, controller_name, &reason);
  if (!controller) return reason;
  const VehicleSpec& spec = model_.vehicles[static_cast<std::size_t>(vehicle_index)];
  const std::string prefix = "vehicle '" + spec.name + "': joint controller '" + controller->name + "': trajectory: ";
  if (controller->mode != physics::JointCommandMode::kPosition) {
    return prefix + "it is a " + physics::to_string(controller->mode) + " group; only position groups follow "
           "trajectories";
  }
  const physics::Articulation& a = *world_->articulation(vehicle_index);
  const auto name_of = [&](int joint) -> const std::string& {
    return joint_name(spec.links[static_cast<std::size_t>(a.body(joint + 1).joint_link)]);
  };
  const std::size_t n = controller->joints.size();
  std::string names;
  for (int joint : controller->joints) names += (names.empty() ? "" : ", ") + name_of(joint);
  if (command.joint_names.size() != n) {
    return prefix + std::to_string(command.joint_names.size()) + " joint names for the group's " + std::to_string(n) +
           " joints (" + names + ")";
  }
  // column[k]: where the group's k-th joint is in the command.
  std::vector<std::size_t> column(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::string& name = command.joint_names[i];
    std::size_t k = 0;
    while (k < n && name_of(controller->joints[k]) != name) ++k;
    if (k == n) {
      return prefix + "joint_names[" + std::to_string(i) + "] '" + name + "' is not a joint of the group (" + names +
             ")";
    }
    if (column[k] != n) return prefix + "joint_names[" + std::to_string(i) + "] '" + name + "' is named twice";
    column[k] = i;
  }
  if (std::string e = physics::check_joint_trajectory(command.points, n); !e.empty()) return prefix + e;
  if (command.start_time && !std::isfinite(*command.start_time)) return prefix + "its start time is not finite";
  for (std::size_t p = 0; p < command.points.size(); ++p) {
    for (std::size_t k = 0; k < n; ++k) {
      const JointSpec& joint = a.body(controller->joints[k] + 1).joint;
      const double value = command.points[p].positions[column[k]];
      if (value < joint.lower || value > joint.upper) {
        return prefix + "points[" + std::to_string(p) + "].positions: " + format_number(value) + " for '" +
               name_of(controller->joints[k]) + "' is outside its limits [" + format_number(joint.lower) + ", " +
               format_number(joint.upper) + "]";
      }
    }
  }
  if (out) {
    out->points.clear();
    const auto reorder = [&](const std::vector<double>& values) {
      std::vector<double> ordered;
      if (values.empty()) return ordered;
      for (std::size_t k = 0; k < n; ++k) ordered.push_back(values[column[k]]);
      return ordered;
    };
    for (const physics::JointTrajectoryPoint& point : command.points) {
      out->points.push_back({point.time_from_start, reorder(point.positions), reorder(point.velocities),
                             reorder(point.accelerations)});
    }
  }
  return {};
}

// Each group that follows a trajectory: its joints' position targets and their rates at t. A trajectory
// whose start has come starts from the joints' state now (the step's start); one whose last waypoint has
// passed leaves its targets there, at rest.
void Simulation::follow_joint_trajectories(std::size_t i, double t) {
  VehicleState& vehicle = state_.vehicles[i];
  const std::vector<physics::JointControllerSpec>& controllers = model_.vehicles[i].joint_controllers;
  for (std::size_t c = 0; c < vehicle.joint_trajectories.size(); ++c) {
    std::shared_ptr<const physics::JointTrajectory>& trajectory = vehicle.joint_trajectories[c];
    if (!trajectory || t < trajectory->start_time) continue;
    const std::vector<int>& joints = controllers[c].joints;
    if (!trajectory->started()) {
      auto started = std::make_shared<physics::JointTrajectory>(*trajectory);
      started->started_at = state_.time;
      for (int joint : joints) {
        started->start_positions.push_back(vehicle.joint_positions[static_cast<std::size_t>(joint)]);
        started->start_velocities.push_back(vehicle.joint_velocities[static_cast<std::size_t>(joint)]);
      }
      trajectory = std::move(started);
    }
    for (std::size_t k = 0; k < joints.size(); ++k) {
      const physics::JointSetpoint setpoint = physics::sample_joint_trajectory(*trajectory, k, t);
      vehicle.joint_targets[static_cast<std::size_t>(joints[k])] = setpoint.position;
      vehicle.joint_target_rates[static_cast<std::size_t>(joints[k])] = setpoint.rate;
    }
    if (t >= trajectory->end_time()) trajectory.reset();
  }
}

// The vehicle's state into Bullet: its body, and an articulated vehicle's joints.
void Simulation::write_body(int vehicle_index, const VehicleState& vehicle) {
  if (world_->articulation(vehicle_index)) {
    const auto n = static_cast<Eigen::Index>(vehicle.joint_positions.size());
    world_->set_articulated_state(vehicle_index, vehicle.body,
                                  Eigen::Map<const Eigen::VectorXd>(vehicle.joint_positions.data(), n),
                                  Eigen::Map<const Eigen::VectorXd>(vehicle.joint_velocities.data(), n));
  } else {
    world_->set_body_state(vehicle_index, vehicle.body);
  }
}

// One step, as the data flows (docs/ARCHITECTURE.md, "One step"): commands -> actuators -> force
// elements -> Bullet -> snapshot -> sensors due.
void Simulation::step() {
  const double t = state_.time;
  const double dt = model_.world.step_size();
  actuate(t, dt);
  step_cables(t, dt);
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

void Simulation::add_cable_loads(std::size_t vehicle, int body, const Eigen::Vector3d& p_Wcm,
                                 physics::StepWrench& wrench) const {
  if (vehicle >= cable_loads_.size()) return;
  for (const CableLoad& load : cable_loads_[vehicle]) {  // each cable pulls at its attachment point
    if (load.body != body) continue;
    wrench.f_W += load.f_W;
    wrench.tau_W += (load.p_W - p_Wcm).cross(load.f_W);
  }
}

void Simulation::step_cables(double t, double dt) {
  if (model_.cables.empty()) return;
  cable_loads_.assign(model_.vehicles.size(), {});
  physics::CableWorld world;
  world.ocean = ocean_.get();
  world.gravity_W = model_.world.gravity_W;
  world.time = t;
  if (seabed_height_) {
    world.seabed_z = [this](double x, double y) {
      geometry::SeabedHeight::Sample below;
      return seabed_height_->sample(x, y, &below) ? below.height : -std::numeric_limits<double>::infinity();
    };
  }
  for (std::size_t c = 0; c < model_.cables.size(); ++c) {
    const physics::CableModel& cable = model_.cables[c];
    std::array<HeldPoint, 2> held;
    std::array<physics::CableEnd, 2> ends;
    for (std::size_t e = 0; e < 2; ++e) {
      held[e] = cable_end_point(cable.ends[e], state_);
      ends[e].held = !cable.ends[e].free;
      ends[e].p_W0 = held[e].p_W;
      ends[e].p_W1 = held[e].p_W + dt * held[e].v_W;  // the point moves on with its body's velocity over the step
    }
    physics::CableState& state = state_.cables[c];
    const int winch = cable.winch_end();
    const double length_rate =
        winch < 0 ? 0.0 : physics::advance_winch(*cable.ends[static_cast<std::size_t>(winch)].winch, dt, state);
    const physics::CableStepResult result =
        physics::step_cable(cable.spec, world, ends[0], ends[1], dt, state, length_rate);
    state.f_W_ends = {result.f_W_end0, result.f_W_end1};
    for (std::size_t e = 0; e < 2; ++e) {
      if (!cable.ends[e].on_vehicle()) continue;
      cable_loads_[static_cast<std::size_t>(cable.ends[e].vehicle_index)].push_back(
          CableLoad{state.f_W_ends[e], held[e].p_W, held[e].body});
    }
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
    const VehicleState& vehicle = state_.vehicles[i];
    write_body(static_cast<int>(i), vehicle);
    runtime.p_WBcm = body.X_WB * runtime.p_BBcm;
    runtime.v_WBcm = body.v_WB + body.w_WB.cross(runtime.p_WBcm - body.X_WB.translation());
    runtime.w_WB = body.w_WB;
    if (runtime.articulation) {
      const auto n = static_cast<Eigen::Index>(vehicle.joint_positions.size());
      runtime.articulation->poses_W(body.X_WB, Eigen::Map<const Eigen::VectorXd>(vehicle.joint_positions.data(), n),
                                    runtime.X_WK);
      runtime.dynamics->update(runtime.X_WK, body.v_WB, body.w_WB,
                               Eigen::Map<const Eigen::VectorXd>(vehicle.joint_velocities.data(), n));
    }
  }
  const auto add_forces = [&](std::size_t i) {
    VehicleRuntime& runtime = *runtime_[i];
    VehicleState& vehicle = state_.vehicles[i];
    runtime.wrench = physics::StepWrench{};
    if (runtime.articulation) {
      apply_articulated_forces(i);
      for (std::size_t k = 0; k < runtime.bodies.size(); ++k) {  // cables hold any of its bodies
        const int body = static_cast<int>(k);
        add_cable_loads(i, body, runtime.dynamics->p_Wcm(body), runtime.bodies[k].wrench);
      }
      runtime.wrench = runtime.bodies[0].wrench;
      return;
    }
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
    VehicleRuntime& runtime = *runtime_[i];
    if (runtime.articulation) {
      hand_articulated_forces(i);
      continue;
    }
    if (model_.vehicles[i].is_static) continue;
    add_cable_loads(i, 0, runtime.p_WBcm, runtime.wrench);
    Eigen::Vector3d f_W = runtime.wrench.f_W;
    Eigen::Vector3d tau_W = runtime.wrench.tau_W;
    if (runtime.added_mass) convert_for_added_mass(runtime, state_.vehicles[i], f_W, tau_W);
    world_->add_force_W(static_cast<int>(i), f_W, runtime.p_WBcm);
    world_->add_torque_W(static_cast<int>(i), tau_W);
  }
}

// An articulated vehicle's force elements, body by body (a static vehicle's base body is fixed: its own
// elements are skipped), each at the body's centre of mass; the base body's wrench is also the vehicle's
// applied_wrench().
void Simulation::apply_articulated_forces(std::size_t i) {
  VehicleRuntime& runtime = *runtime_[i];
  VehicleState& vehicle = state_.vehicles[i];
  const physics::ArticulatedDynamics& dynamics = *runtime.dynamics;
  double seabed_z_below = -std::numeric_limits<double>::infinity();
  geometry::SeabedHeight::Sample below;
  const Eigen::Vector3d& p_WB = vehicle.body.X_WB.translation();
  if (runtime.seabed_below && runtime.seabed_below->sample(p_WB.x(), p_WB.y(), &below)) seabed_z_below = below.height;
  for (std::size_t k = 0; k < runtime.bodies.size(); ++k) {
    VehicleRuntime::Body& body = runtime.bodies[k];
    body.wrench = physics::StepWrench{};
    if (k == 0 && model_.vehicles[i].is_static) continue;
    const int index = static_cast<int>(k);
    const Vector6d& V = dynamics.velocity(index);
    const Eigen::Vector3d& p_Wcm = dynamics.p_Wcm(index);
    RigidBodyState motion;
    motion.X_WB = runtime.X_WK[k];
    motion.w_WB = V.tail<3>();
    motion.v_WB = V.head<3>() + motion.w_WB.cross(runtime.X_WK[k].translation() - p_Wcm);  // of K's origin
    const physics::ForceInput in{state_.time, motion,  p_Wcm,   V.head<3>(), vehicle.actuators,
                                 nullptr,     nullptr, seabed_z_below};
    for (const auto& element : body.forces) element->add(in, body.wrench);
  }
  runtime.wrench = runtime.bodies[0].wrench;
}

// An articulated vehicle's wrenches and joint torques into Bullet: each body's at its centre of mass, with
// its added-mass reaction (physics/articulated_dynamics.h; M_A0 scaled by kappa at its centre of mass and
// its submerged fraction, as for a rigid vehicle), and each joint's effort less its viscous damping.
void Simulation::hand_articulated_forces(std::size_t i) {
  VehicleRuntime& runtime = *runtime_[i];
  VehicleState& vehicle = state_.vehicles[i];
  const physics::ArticulatedDynamics& dynamics = *runtime.dynamics;
  const physics::Articulation& a = *runtime.articulation;
  const auto n = static_cast<std::size_t>(a.num_dofs());
  const double dt = model_.world.step_size();
  // Each joint's motor (its controller's law, or the effort it holds) and its viscous damping, taken
  // implicitly over the step with the added mass (physics/joint_servo.h).
  VehicleRuntime::Work& work = runtime.work;
  physics::ArticulatedDynamics::ImplicitJoints& implicit = work.implicit;
  const auto dofs = static_cast<Eigen::Index>(n);
  implicit.servo.resize(dofs);
  implicit.servo_D.resize(dofs);
  implicit.limit.resize(dofs);
  implicit.damping_D.resize(dofs);
  implicit.friction.resize(dofs);
  implicit.lower.resize(dofs);
  implicit.upper.resize(dofs);
  implicit.q = Eigen::Map<const Eigen::VectorXd>(vehicle.joint_positions.data(), dofs);
  implicit.dt = dt;
  Eigen::VectorXd& tau = work.joint_torques;  // the explicit part of the damping
  tau.resize(dofs);
  // Trajectories are sampled at the step's end, where the implicit law takes its error.
  follow_joint_trajectories(i, state_.time + dt);
  for (std::size_t j = 0; j < n; ++j) {
    const auto e = static_cast<Eigen::Index>(j);
    const VehicleRuntime::JointMotor& motor = runtime.motors[j];
    const physics::ServoStep step =
        physics::joint_servo_step(motor.servo, motor.mode, vehicle.joint_targets[j], vehicle.joint_positions[j],
                                  vehicle.joint_velocities[j], dt, vehicle.joint_target_rates[j]);
    const double limit = std::min(motor.servo.effort_limit, vehicle.joint_effort_caps[j]);  // a gripper's max_effort
    implicit.limit[e] = limit;
    // The law at the step's end decides whether it saturates (ArticulatedDynamics::reactions); a constant
    // torque (D = 0: an effort) is held within the limit here.
    implicit.servo[e] = step.D > 0.0 ? step.torque : std::clamp(step.torque, -limit, limit);
    implicit.servo_D[e] = step.D;
    const JointSpec& joint = a.body(static_cast<int>(j) + 1).joint;
    tau[e] = -joint.damping * vehicle.joint_velocities[j];
    implicit.damping_D[e] = joint.damping * dt;
    implicit.friction[e] = joint.friction;
    implicit.lower[e] = physics::lower_limit(joint);
    implicit.upper[e] = physics::upper_limit(joint);
  }
  std::vector<physics::ArticulatedDynamics::Wrench>& wrenches = work.wrenches;
  wrenches.resize(runtime.bodies.size());
  for (std::size_t k = 0; k < runtime.bodies.size(); ++k) {
    wrenches[k] << runtime.bodies[k].wrench.f_W, runtime.bodies[k].wrench.tau_W;
  }
  std::vector<physics::ArticulatedDynamics::AddedMassBody>& added = work.added;
  added.resize(runtime.bodies.size());
  if (runtime.has_added_mass) {
    for (std::size_t k = 0; k < runtime.bodies.size(); ++k) {
      const VehicleRuntime::Body& body = runtime.bodies[k];
      const double depth = std::max(ocean_->depth(dynamics.p_Wcm(static_cast<int>(k)).z()), 0.0);
      added[k].M_A = ocean_->kappa(depth) * body.wrench.submerged_fraction * body.M_A0;
      added[k].v_water_W = body.wrench.v_water_W;
      added[k].a_water_W = body.wrench.a_water_W;
    }
  }
  const auto n_c = static_cast<Eigen::Index>(vehicle.constraint_force.size());
  const Eigen::Map<const Eigen::VectorXd> Q_c(vehicle.constraint_force.data(), n_c);
  physics::ArticulatedDynamics::Reactions& reactions = work.reactions;
  dynamics.reactions(added, wrenches, model_.world.gravity_W, tau, Q_c, model_.vehicles[i].fluid.added_mass.coriolis,
                     &implicit, reactions);
  for (std::size_t k = 0; k < wrenches.size(); ++k) wrenches[k] += reactions.bodies[k];
  if (measures_joint_wrenches(i)) runtime.handed_W = wrenches;
  tau = reactions.joint_torques;
  for (std::size_t j = 0; j < n; ++j) vehicle.joint_efforts[j] = reactions.servo[static_cast<Eigen::Index>(j)];
  runtime.u0 = dynamics.u();
  runtime.c0 = dynamics.bias();
  dynamics.generalized_force(wrenches, model_.world.gravity_W, tau, runtime.Q_given);
  runtime.target.active = !model_.vehicles[i].is_static;
  if (runtime.target.active) {
    // The whole tree's momentum balance under the external wrenches (the joints' torques are internal).
    const physics::ArticulatedDynamics::Momentum now = dynamics.momentum(/*inertia=*/false);
    const Eigen::Vector3d& g_W = model_.world.gravity_W;
    Eigen::Vector3d F_W = now.mass * g_W, tau_W = Eigen::Vector3d::Zero();  // about the centre of mass
    for (std::size_t k = 0; k < wrenches.size(); ++k) {
      F_W += wrenches[k].head<3>();
      tau_W += (dynamics.p_Wcm(static_cast<int>(k)) - now.c_W).cross(wrenches[k].head<3>()) + wrenches[k].tail<3>();
    }
    VehicleRuntime::MomentumTarget& target = runtime.target;
    target.P_W = now.P_W + dt * F_W;
    target.c_W = now.c_W + dt * target.P_W / now.mass;
    // About the origin: L_O = L_c + c x P, and d/dt L_O = tau_c + c x F; then about the new centre.
    const Eigen::Vector3d L_O = now.L_W + now.c_W.cross(now.P_W) + dt * (tau_W + now.c_W.cross(F_W));
    target.L_W = L_O - target.c_W.cross(target.P_W);
  }
  const int v = static_cast<int>(i);
  for (std::size_t k = 0; k < wrenches.size(); ++k) {
    const int body = static_cast<int>(k);
    world_->add_body_wrench_W(v, body, wrenches[k].head<3>(), wrenches[k].tail<3>());
  }
  for (std::size_t j = 0; j < n; ++j) {
    world_->add_joint_torque(v, static_cast<int>(j), tau[static_cast<Eigen::Index>(j)]);
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
  if (!runtime.wrench.a_water_W.isZero(0.0)) {
    // Waves: the water's acceleration also accelerates the added mass (Morison's inertia term beyond Froude-Krylov).
    Vector6d a_water = Vector6d::Zero();
    a_water.head<3>() = R_BW * runtime.wrench.a_water_W;
    in.tau += in.kappa * (runtime.added_mass->added_mass_surface() * a_water);
  }
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
    if (runtime.articulation) {
      world_->joint_state(static_cast<int>(i), vehicle.joint_positions, vehicle.joint_velocities);
      const auto n_q = static_cast<Eigen::Index>(vehicle.joint_velocities.size());
      const Eigen::Map<const Eigen::VectorXd> qd(vehicle.joint_velocities.data(), n_q);
      // What Bullet's constraints added: M u_dot - (Q - c) over the step, at the step's start.
      const auto n_u = runtime.u0.size();
      VehicleRuntime::Work& work = runtime_[i]->work;
      Eigen::VectorXd& u1 = work.u1;
      u1.resize(n_u);
      u1.tail(qd.size()) = qd;
      if (n_u > qd.size()) {
        const Eigen::Vector3d p_Wcm = vehicle.body.X_WB * runtime.p_BBcm;
        u1.head<3>() = vehicle.body.v_WB + vehicle.body.w_WB.cross(p_Wcm - vehicle.body.X_WB.translation());
        u1.segment<3>(3) = vehicle.body.w_WB;
      }
      Eigen::VectorXd& u_dot = work.u_dot;
      u_dot = (u1 - runtime.u0) / dt;
      Eigen::VectorXd& Q_c = work.Q_c;
      runtime.dynamics->mass_times(u_dot, Q_c);
      Q_c -= runtime.Q_given - runtime.c0;
      vehicle.constraint_force.assign(Q_c.data(), Q_c.data() + Q_c.size());
      if (measures_joint_wrenches(i)) measure_joint_wrenches(i, u_dot, dt);
      if (runtime.target.active && world_->num_contact_points(static_cast<int>(i)) == 0) {
        keep_momentum(i);
      }
      continue;
    }
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

// Whether the step being taken works out vehicle i's joints' wrenches: one of its force_torque sensors
// samples at the step's end, step_count + 1 (take_snapshot counts the step only after reading them).
bool Simulation::measures_joint_wrenches(std::size_t i) const {
  if (state_.vehicles[i].joint_wrenches_L.empty()) return false;
  const double dt = model_.world.step_size();
  const std::vector<double>& rates_hz = runtime_[i]->joint_sensor_rates_hz;
  return std::any_of(rates_hz.begin(), rates_hz.end(),
                     [&](double rate_hz) { return sample_due(state_.step_count + 1, dt, rate_hz); });
}

// Each moving joint's wrench over the step just taken (physics/articulated_dynamics.h), from the
// acceleration Bullet gave (u_dot), the wrenches handed to it and its contacts, turned into each joint's
// link frame at the step's start.
void Simulation::measure_joint_wrenches(std::size_t i, const Eigen::VectorXd& u_dot, double dt) {
  const VehicleRuntime& runtime = *runtime_[i];
  const physics::ArticulatedDynamics& dynamics = *runtime.dynamics;
  const physics::Articulation& a = *runtime.articulation;
  std::vector<physics::ArticulatedDynamics::Wrench> external = runtime.handed_W;
  const std::vector<Eigen::Matrix<double, 6, 1>> contacts = world_->contact_wrenches_W(static_cast<int>(i), dt);
  for (std::size_t k = 0; k < external.size(); ++k) {
    // The contacts' moment about the world origin, moved to the centre of mass.
    const Eigen::Vector3d f_W = contacts[k].head<3>();
    external[k].head<3>() += f_W;
    external[k].tail<3>() += contacts[k].tail<3>() - dynamics.p_Wcm(static_cast<int>(k)).cross(f_W);
  }
  const std::vector<physics::ArticulatedDynamics::Wrench> joints =
      dynamics.joint_wrenches(u_dot, external, model_.world.gravity_W);
  VehicleState& vehicle = state_.vehicles[i];
  for (int k = 1; k < a.num_bodies(); ++k) {
    const auto b = static_cast<std::size_t>(k);
    const Eigen::Matrix3d R_KW = runtime.X_WK[b].linear().transpose();
    Eigen::Matrix<double, 6, 1>& out = vehicle.joint_wrenches_L[static_cast<std::size_t>(a.body(k).joint_link)];
    out.head<3>() = R_KW * joints[b].head<3>();
    out.tail<3>() = R_KW * joints[b].tail<3>();
  }
}

// Bullet's semi-implicit Euler in reduced coordinates keeps a free tree's momentum only to first order in
// the step (a vehicle swinging its arm drifts ~1e-3 m in 2 s at 500 Hz, half that at 1 kHz). Without
// contact (whose impulses Hadal does not know) the external wrenches are all known, so the step's
// momentum balance is exact: P' = P + dt F, c' = c + dt P' / m, L_O' = L_O + dt tau_O. Bullet's result is
// moved onto it by a rigid motion of the whole tree (a translation, and a uniform velocity and rotation
// rate about the centre of mass), a correction of the integrator's own order that leaves the joints as
// Bullet stepped them (docs/ARCHITECTURE.md, "Articulated vehicles").
void Simulation::keep_momentum(std::size_t i) {
  VehicleRuntime& runtime = *runtime_[i];
  VehicleState& vehicle = state_.vehicles[i];
  physics::ArticulatedDynamics& dynamics = *runtime.dynamics;
  const auto n = static_cast<Eigen::Index>(vehicle.joint_velocities.size());
  const Eigen::Map<const Eigen::VectorXd> qd(vehicle.joint_velocities.data(), n);
  // The next step's update() starts from this state again; its momentum needs the kinematics alone, at
  // the bodies' poses Bullet's step ended on.
  world_->body_poses_W(static_cast<int>(i), runtime.work.X_WK_after);
  dynamics.update_kinematics(runtime.work.X_WK_after, vehicle.body.v_WB, vehicle.body.w_WB, qd);
  const physics::ArticulatedDynamics::Momentum after = dynamics.momentum();
  const VehicleRuntime::MomentumTarget& target = runtime.target;
  vehicle.body.X_WB.translation() += target.c_W - after.c_W;
  const Eigen::Vector3d delta_w = after.I_W.ldlt().solve(target.L_W - after.L_W);
  const Eigen::Vector3d delta_v = (target.P_W - after.P_W) / after.mass;
  vehicle.body.w_WB += delta_w;
  vehicle.body.v_WB += delta_v + delta_w.cross(vehicle.body.X_WB.translation() - target.c_W);
}

// The non-finite policy for every vehicle whose state is no longer finite.
void Simulation::reset_non_finite_vehicles() {
  bool any_reset = false;
  for (std::size_t i = 0; i < runtime_.size(); ++i) {
    VehicleState& vehicle = state_.vehicles[i];
    if (is_finite(vehicle)) continue;
    reset_non_finite(model_.vehicles[i], vehicle);
    write_body(static_cast<int>(i), vehicle);
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
    std::vector<Eigen::Isometry3d> X_WK;  // the bodies' poses at this state, when a moving sensor needs them
    std::vector<Eigen::Isometry3d> X_Wb;  // every ray body's pose at this state, when a capture needs them
    for (std::size_t k = 0; k < spec.sensors.size(); ++k) {
      const bool due = sample_due(state_.step_count, dt, spec.sensors[k].rate_hz);
      SensorState& out = vehicle.sensors[k];
      if (!due && out.captures.empty() && !runtime.sensors[k].by_event) continue;
      VehicleRuntime::Sensor& mount = runtime.sensors[k];
      if (due && mount.body > 0) mount.X_BS = mounting_B(runtime, static_cast<int>(k), vehicle, X_WK);
      const auto context_at = [&](const Eigen::Isometry3d& X_BS) { return sensor_context(i, k, X_BS, dt); };
      const sensors::SampleContext context = context_at(mount.X_BS);
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
                capture.X_BS = mount.X_BS;
                if (X_Wb.empty()) X_Wb = ray_body_poses(state_);
                capture.X_WB = X_Wb;
                submit_capture<Kind>(i, k, kind_spec, capture);
              }
              while (!out.captures.empty() && out.captures.front().due_step <= state_.step_count) {
                VehicleRuntime::InFlight& flight = mount.in_flight.front();
                constexpr bool kByWork = sensors::CapturesByWork<Kind>::value;
                const bool ready = wait_for_captures_ ||
                                   (kByWork ? flight.done.wait_for(std::chrono::seconds(0))
                                            : flight.hits.wait_for(std::chrono::seconds(0))) == std::future_status::ready;
                if (ready) {
                  // Delivered with the mounting of its snapshot (a moving sensor's has changed since).
                  const sensors::SampleContext captured = context_at(out.captures.front().X_BS);
                  if constexpr (kByWork) {
                    flight.done.get();
                    Kind::deliver(captured, kind_spec, kind_state,
                                  std::move(*std::static_pointer_cast<typename Kind::Capture>(flight.output)));
                  } else {
                    geometry::RayHits hits = flight.hits.get();
                    Kind::deliver(captured, kind_spec, kind_state, hits);
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
            } else if constexpr (sensors::SamplesByEvent<Kind>::value) {
              if (const std::optional<double> stamp = Kind::advance(context, kind_spec, kind_state)) {
                out.stamp = *stamp;
                ++out.samples;
              }
              if (due) Kind::sample(context, kind_spec, kind_state);
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

sensors::SampleContext Simulation::sensor_context(std::size_t i, std::size_t k, const Eigen::Isometry3d& X_BS,
                                                  double dt) {
  VehicleRuntime& runtime = *runtime_[i];
  const VehicleRuntime::Sensor& mount = runtime.sensors[k];
  return sensors::SampleContext{state_.time,
                                mount.period,
                                dt,
                                model_.world,
                                *ocean_,
                                *environment_,
                                state_,
                                static_cast<int>(i),
                                X_BS,
                                runtime.p_BBcm,
                                runtime.v_WBcm,
                                runtime.w_WB,
                                rays_.get(),
                                &model_.vehicles[i].sensors[k],
                                ray_bodies_.of_body(static_cast<int>(i), mount.body),
                                &model_.vehicles};
}

template <class Kind>
void Simulation::submit_capture(std::size_t vehicle, std::size_t sensor, const typename Kind::Spec& spec,
                                const PendingCapture& capture) {
  VehicleRuntime::Sensor& mount = runtime_[vehicle]->sensors[sensor];
  const sensors::CaptureContext context{capture.time,  capture.step_count, capture.X_WB, static_cast<int>(vehicle),
                                        capture.X_BS,  &model_,            ocean_.get(),
                                        ray_bodies_.of_body(static_cast<int>(vehicle), mount.body)};
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

std::vector<Eigen::Isometry3d> Simulation::ray_body_poses(const SimState& state) const {
  std::vector<Eigen::Isometry3d> X_Wb;
  X_Wb.reserve(static_cast<std::size_t>(ray_bodies_.count()));
  for (const VehicleState& vehicle : state.vehicles) X_Wb.push_back(vehicle.body.X_WB);
  for (std::size_t i = 0; i < runtime_.size() && i < state.vehicles.size(); ++i) {
    const physics::Articulation* articulation = runtime_[i]->articulation;
    if (articulation == nullptr) continue;
    const VehicleState& vehicle = state.vehicles[i];
    const auto n = static_cast<Eigen::Index>(vehicle.joint_positions.size());
    const std::vector<Eigen::Isometry3d> X_WK =
        articulation->poses_W(vehicle.body.X_WB, Eigen::Map<const Eigen::VectorXd>(vehicle.joint_positions.data(), n));
    for (int k = 1; k < articulation->num_bodies(); ++k) {
      X_Wb.push_back(X_WK[static_cast<std::size_t>(k)] * articulation->body(k).X_BK0.inverse());
    }
  }
  return X_Wb;
}

Eigen::Isometry3d Simulation::mounting_B(const VehicleRuntime& runtime, int sensor, const VehicleState& vehicle,
                                         std::vector<Eigen::Isometry3d>& X_WK) const {
  const VehicleRuntime::Sensor& mount = runtime.sensors.at(static_cast<std::size_t>(sensor));
  if (mount.body == 0) return mount.X_BS;
  if (X_WK.empty()) {
    const auto n = static_cast<Eigen::Index>(vehicle.joint_positions.size());
    X_WK = runtime.articulation->poses_W(vehicle.body.X_WB,
                                         Eigen::Map<const Eigen::VectorXd>(vehicle.joint_positions.data(), n));
  }
  return vehicle.body.X_WB.inverse() * X_WK[static_cast<std::size_t>(mount.body)] * mount.X_KS;
}

Simulation::CaptureMount Simulation::capture_mount(int vehicle_index, int sensor_index) const {
  const auto v = static_cast<std::size_t>(vehicle_index);
  const VehicleRuntime& runtime = *runtime_.at(v);
  std::vector<Eigen::Isometry3d> X_WK;
  CaptureMount out;
  out.X_Wb = ray_body_poses(state_);
  out.X_BS = mounting_B(runtime, sensor_index, state_.vehicles.at(v), X_WK);
  out.ray_body = ray_bodies_.of_body(vehicle_index, runtime.sensors.at(static_cast<std::size_t>(sensor_index)).body);
  return out;
}

geometry::SceneRays& Simulation::scene_rays() {
  if (!rays_) {
    // Embree builds its BVHs on world.threads threads (its own default: all).
    const std::string device_config =
        model_.world.threads > 0 ? "threads=" + std::to_string(model_.world.threads) : std::string();
    rays_ = std::make_unique<geometry::SceneRays>(geometry::build_world_scene(model_, device_config),
                                                  [this](const SimState& state) { return ray_body_poses(state); });
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
