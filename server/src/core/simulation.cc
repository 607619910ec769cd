#include "hadal/core/simulation.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>
#include <thread>
#include <utility>

#include "hadal/geometry/embree_scene.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/geometry/ray_batch.h"
#include "hadal/geometry/world_scene.h"
#include "hadal/geometry/shape_overlap.h"
#include "hadal/geometry/mesh_properties.h"
#include "hadal/physics/added_mass.h"
#include "hadal/physics/bullet_world.h"
#include "hadal/physics/lumped_fluid.h"
#include "hadal/physics/mass_properties.h"
#include "hadal/physics/ocean.h"
#include "hadal/physics/ocean_fluid.h"
#include "hadal/physics/surface_hydrodynamics.h"
#include "hadal/physics/thruster.h"
#include "hadal/core/rate_divider.h"

#include "hadal/geometry/scene_rays.h"
#include "hadal/sensors/sample_context.h"
#include "hadal/sensors/sensor_kinds.h"
#include "hadal/core/units.h"
#include "worker_pool.h"

namespace hadal {

// Constants derived from the model that the step needs per vehicle; no evolving state.
struct Simulation::VehicleRuntime {
  std::vector<physics::Thruster> thrusters;
  physics::LumpedFluid fluid;
  // Surface fluid model only (null for the lumped model): the kernel over the vehicle's
  // hydrodynamic mesh in B.
  std::unique_ptr<physics::SurfaceHydrodynamics> surface;
  Eigen::Vector3d p_BBcm = Eigen::Vector3d::Zero();  // composite centre of mass in B
  double mass = 0.0;
  Matrix6d M_A0 = Matrix6d::Zero();                  // added mass at the surface, about Bcm, B axes
  std::unique_ptr<physics::AddedMassDynamics> added_mass;  // null without added mass
  // Per sensor (same order as VehicleSpec::sensors): its pose in B and its sample period.
  struct Sensor {
    Eigen::Isometry3d X_BS = Eigen::Isometry3d::Identity();
    double period = 0.0;  // nominal sample period 1 / rate_hz [s]
  };
  std::vector<Sensor> sensors = {};
  // Surface model: volume displaced twice where hull parts overlap, its centroid in B, and the
  // height over which it goes from dry to wet (diameter of the sphere of that volume).
  double excess_volume = 0.0;
  Eigen::Vector3d p_BE = Eigen::Vector3d::Zero();
  double excess_height = 0.0;
  // Step scratch (not state). The centre of mass and its velocity at the step start, every applied
  // wrench of the step collected at the centre of mass in W, the submerged fraction; then what Bullet
  // was given at the centre of mass in the B axes of the step start, and the velocity then, for the
  // added-mass contact feedback after the step.
  Eigen::Vector3d p_WBcm = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WBcm = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WB = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_water_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d f_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d tau_W = Eigen::Vector3d::Zero();  // about p_WBcm
  double submerged_fraction = 0.0;
  Vector6d tau_bullet_B = Vector6d::Zero();
  Vector6d nu0 = Vector6d::Zero();
  Eigen::Matrix3d R_WB0 = Eigen::Matrix3d::Identity();
};

namespace {

constexpr std::size_t kParallelFluidFaces = 4096;

std::string format_number(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);  // shortest round trip
  return std::string(buffer, result.ptr);
}

bool is_finite(const VehicleState& vehicle) {
  if (!vehicle.body.X_WB.matrix().allFinite() || !vehicle.body.v_WB.allFinite() ||
      !vehicle.body.w_WB.allFinite() || !vehicle.contact_wrench_B.allFinite()) {
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
  vehicle.contact_wrench_B.setZero();
  vehicle.faults |= kFaultNonFiniteState;
  ++vehicle.fault_resets;
}

void validate(const Model& model) {
  if (!(model.world.physics_rate_hz > 0.0) || !std::isfinite(model.world.physics_rate_hz)) {
    throw std::invalid_argument("world.physics_rate_hz must be finite and > 0 (got " +
                                format_number(model.world.physics_rate_hz) + ")");
  }
  for (const VehicleSpec& vehicle : model.vehicles) {
    for (const SensorSpec& sensor : vehicle.sensors) {
      if (sensor.link_index < 0 || sensor.link_index >= static_cast<int>(vehicle.links.size())) {
        throw std::invalid_argument("vehicle '" + vehicle.name + "': sensor '" + sensor.name +
                                    "': link index " + std::to_string(sensor.link_index) + " out of range");
      }
      if (!(sensor.rate_hz > 0.0) || !std::isfinite(sensor.rate_hz)) {
        throw std::invalid_argument("vehicle '" + vehicle.name + "': sensor '" + sensor.name +
                                    "': rate_hz must be finite and > 0");
      }
    }
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

// The vehicle's hydrodynamic mesh in B (geometry::vehicle_surface_B).
geometry::TriangleMesh hydrodynamic_mesh_B(const VehicleSpec& spec) {
  geometry::TriangleMesh mesh_B = geometry::vehicle_surface_B(spec);
  if (mesh_B.num_triangles() == 0) {
    throw std::invalid_argument("vehicle '" + spec.name +
                                "': fluid model 'surface' needs a hydrodynamic mesh: no link has a "
                                "mesh or collision shapes");
  }
  return mesh_B;
}

// Parts of a hull built from primitives may overlap. Each tessellated part is closed and integrates
// its own pressure, so the overlap displaces water twice; and faces of one part that lie inside
// another meet no flow. The hull keeps every face for buoyancy, turns the flow terms off on faces
// whose centroid lies inside another primitive (exposed = false), and the doubly counted volume
// (geometry/shape_overlap.h: excess volume E and its centroid, from the smooth primitives; the
// inscribed tessellation overlaps slightly less, so E over-corrects by ~2 % of itself) is taken
// back each step as a downward force rho g E at its centroid.
struct HydrodynamicHull {
  geometry::TriangleMesh mesh_B;
  std::vector<bool> exposed;  // one per triangle
  double excess_volume = 0.0;                                 // E [m^3]
  Eigen::Vector3d p_BE = Eigen::Vector3d::Zero();             // its centroid in B
  Eigen::Matrix3d C_E = Eigen::Matrix3d::Zero();              // its second moment about p_BE [m^5]
};

HydrodynamicHull hydrodynamic_hull(const VehicleSpec& spec) {
  HydrodynamicHull hull;
  hull.mesh_B = hydrodynamic_mesh_B(spec);
  hull.exposed.assign(hull.mesh_B.num_triangles(), true);
  // The primitives that became faces, in B, with the index of their first triangle.
  std::vector<std::pair<CollisionShape, Eigen::Isometry3d>> shapes_B;
  std::vector<std::size_t> first_triangle;
  std::size_t triangle = 0;
  for (const LinkSpec& link : spec.links) {
    if (link.mesh && link.mesh->mesh) {
      triangle += link.mesh->mesh->num_triangles();
      continue;
    }
    for (const CollisionShape& shape : link.collisions) {
      shapes_B.emplace_back(shape, link.X_BL * shape.X_LG);
      first_triangle.push_back(triangle);
      triangle += geometry::tessellate(shape).num_triangles();
    }
  }
  first_triangle.push_back(triangle);
  if (shapes_B.size() < 2) return hull;
  double volume = 0.0;
  for (const auto& shape : shapes_B) {
    volume += std::abs(geometry::compute_mesh_properties(geometry::tessellate(shape.first)).volume);
  }
  geometry::OverlapExcessOptions options;
  options.absolute_tolerance = 1e-4 * volume;
  const geometry::OverlapExcess excess = geometry::overlap_excess(shapes_B, options);
  if (excess.overlapping_pairs.empty()) return hull;
  hull.excess_volume = excess.volume;
  hull.p_BE = excess.centroid_B;
  hull.C_E = excess.second_moment_B;
  const geometry::TriangleMesh& mesh = hull.mesh_B;
  for (std::size_t part = 0; part < shapes_B.size(); ++part) {
    for (std::size_t t = first_triangle[part]; t < first_triangle[part + 1]; ++t) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = mesh.indices[3 * t + k];
        c += Eigen::Vector3d(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
      }
      c /= 3.0;
      for (std::size_t other = 0; other < shapes_B.size(); ++other) {
        if (other != part && geometry::contains(shapes_B[other].first, shapes_B[other].second, c)) {
          hull.exposed[t] = false;
          break;
        }
      }
    }
  }
  return hull;
}

// Volume properties of the hull's union: the parts' (each closed part integrated by the divergence
// theorem) less the doubly counted overlap E with centroid p_BE and second moment C_E about it.
geometry::MeshProperties union_properties(const HydrodynamicHull& hull) {
  geometry::MeshProperties props = geometry::compute_mesh_properties(hull.mesh_B);
  const double E = hull.excess_volume;
  if (!(E > 0.0) || !props.closed || !(props.volume > E)) return props;
  const auto second_moment = [](const Eigen::Matrix3d& I) {  // I = tr(C) 1 - C  =>  C = tr(I)/2 1 - I
    return Eigen::Matrix3d(0.5 * I.trace() * Eigen::Matrix3d::Identity() - I);
  };
  const double V = props.volume - E;
  const Eigen::Vector3d c = (props.volume * props.centroid - E * hull.p_BE) / V;
  const Eigen::Vector3d dp = props.centroid - c, de = hull.p_BE - c;
  const Eigen::Matrix3d C = second_moment(props.inertia_unit_density) +
                            props.volume * dp * dp.transpose() - hull.C_E -
                            E * de * de.transpose();
  props.volume = V;
  props.centroid = c;
  props.inertia_unit_density = C.trace() * Eigen::Matrix3d::Identity() - C;
  return props;
}

// M_A0 about the centre of mass p_BBcm in B axes (physics/added_mass.h, AddedMassSpec). `hull` is
// the vehicle's hydrodynamic hull (needed by an ellipsoid fitted to it).
Matrix6d surface_added_mass(const VehicleSpec& spec, const HydrodynamicHull* hull,
                            const Eigen::Vector3d& p_BBcm, double surface_density) {
  const AddedMassSpec& added = spec.fluid.added_mass;
  switch (added.model) {
    case AddedMassModel::kNone:
      return Matrix6d::Zero();
    case AddedMassModel::kMatrix:
      return physics::shift_added_mass(added.M_A0, Eigen::Matrix3d::Identity(), added.p_BR, p_BBcm);
    case AddedMassModel::kEllipsoid:
      break;
  }
  physics::Ellipsoid ellipsoid;
  if (added.semi_axes_E) {
    ellipsoid.semi_axes = *added.semi_axes_E;
    ellipsoid.X_BE = added.X_BE;
  } else {
    try {
      if (!hull) throw std::invalid_argument("no link has a mesh or collision shapes");
      ellipsoid = physics::equivalent_ellipsoid(union_properties(*hull));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("vehicle '" + spec.name + "': fluid.added_mass: " + e.what() +
                                  "; give fluid.added_mass.semi_axes or a matrix, or model: none");
    }
  }
  return physics::shift_added_mass(
      physics::ellipsoid_added_mass(ellipsoid.semi_axes, surface_density),
      ellipsoid.X_BE.linear(), ellipsoid.X_BE.translation(), p_BBcm);
}

// Earth's angular velocity in W (ENU) at geodetic latitude `latitude` [rad/s].
Eigen::Vector3d earth_rotation_W(const DynamicsSpec& dynamics, double latitude) {
  return dynamics.earth_rotation_rate *
         Eigen::Vector3d(0.0, std::cos(latitude), std::sin(latitude));
}

const Model& validated(const Model& model) {
  validate(model);
  return model;
}

}  // namespace

Simulation::Simulation(Model model)
    : model_(std::move(model)), world_(std::make_unique<physics::BulletWorld>(validated(model_))) {
  const double dt = model_.world.step_size();
  ocean_ = std::make_unique<physics::Ocean>(model_.world);
  const GeodeticOrigin& origin = model_.world.origin;
  environment_ = std::make_unique<sensors::SensorEnvironment>(origin.latitude, origin.longitude, origin.altitude);
  bool casts_rays = false;
  runtime_.reserve(model_.vehicles.size());
  for (const VehicleSpec& spec : model_.vehicles) {
    const int index = static_cast<int>(runtime_.size());
    std::vector<physics::Thruster> thrusters;
    thrusters.reserve(spec.thrusters.size());
    for (const ThrusterSpec& thruster : spec.thrusters) {
      thrusters.emplace_back(thruster, spec.links[thruster.link_index].X_BL,
                             model_.world.water.density, dt);
    }
    VehicleRuntime runtime{std::move(thrusters), physics::LumpedFluid(spec, model_.world), nullptr,
                           Eigen::Vector3d::Zero(), 0.0, Matrix6d::Zero(), nullptr};
    const physics::MassProperties& mass = world_->mass_properties(index);
    runtime.p_BBcm = mass.p_BBcm;
    runtime.mass = mass.mass;
    std::optional<HydrodynamicHull> hull;
    if (spec.fluid.model == FluidModelType::kSurface || geometry::has_surface_geometry(spec.links)) {
      hull = hydrodynamic_hull(spec);  // throws for a surface-model vehicle without faces
    }
    if (spec.fluid.model == FluidModelType::kSurface) {
      runtime.surface = std::make_unique<physics::SurfaceHydrodynamics>(
          hull->mesh_B, spec.fluid.hydrodynamics, hull->exposed);
      runtime.excess_volume = hull->excess_volume;
      runtime.p_BE = hull->p_BE;
      runtime.excess_height = 2.0 * std::cbrt(3.0 * hull->excess_volume / (4.0 * kPi));
    }
    runtime.M_A0 = surface_added_mass(spec, hull ? &*hull : nullptr, mass.p_BBcm, ocean_->density(0.0));
    if (!runtime.M_A0.isZero(0.0)) {
      runtime.added_mass = std::make_unique<physics::AddedMassDynamics>(
          physics::RigidBodyInertia{mass.mass, mass.I_BBcm_B}, runtime.M_A0,
          spec.fluid.added_mass.coriolis, model_.world.dynamics.gyroscopic);
    }
    VehicleState vehicle = initial_vehicle_state(spec);
    for (const SensorSpec& sensor : spec.sensors) {
      const VehicleRuntime::Sensor& mount =
          runtime.sensors.emplace_back(VehicleRuntime::Sensor{spec.links[sensor.link_index].X_BL * sensor.X_LS,
                                                              1.0 / sensor.rate_hz});
      SensorState& sensor_state = vehicle.sensors.emplace_back();
      std::visit(
          [&](const auto& kind_spec) {
            using Kind = sensors::KindOf<std::decay_t<decltype(kind_spec)>>;
            const sensors::SensorSetup setup{model_.world.seed, spec.name, sensor.name, mount.period, *environment_};
            sensor_state.kind = Kind::initial_state(kind_spec, setup);
            casts_rays = casts_rays || Kind::kCastsRays;
          },
          sensor.kind);
    }
    runtime_.push_back(std::move(runtime));
    state_.vehicles.push_back(std::move(vehicle));
  }
  if (casts_rays) {
    rays_ = std::make_unique<geometry::SceneRays>(geometry::build_world_scene(model_, "threads=1"));
  }
  // Fluid forces of several vehicles in parallel when it pays: a wake-up costs ~10 us, one face
  // ~4.5 ns, so from ~2 x 4k faces on (the second-largest hull bounds the gain).
  std::vector<std::size_t> faces;
  for (const VehicleRuntime& runtime : runtime_) {
    if (runtime.surface) faces.push_back(runtime.surface->num_faces());
  }
  std::sort(faces.rbegin(), faces.rend());
  const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
  if (faces.size() >= 2 && faces[1] >= kParallelFluidFaces && hardware >= 2) {
    pool_ = std::make_unique<WorkerPool>(
        static_cast<unsigned>(std::min<std::size_t>(hardware - 1, faces.size() - 1)));
  }
}

Simulation::~Simulation() = default;

const physics::MassProperties& Simulation::mass_properties(int vehicle_index) const {
  return world_->mass_properties(vehicle_index);
}

unsigned Simulation::fluid_helper_threads() const { return pool_ ? pool_->helpers() : 0; }

const Matrix6d& Simulation::added_mass(int vehicle_index) const {
  return runtime_.at(vehicle_index).M_A0;
}

void Simulation::set_state(const SimState& state) {
  if (state.vehicles.size() != model_.vehicles.size()) {
    throw std::invalid_argument("set_state: expected " + std::to_string(model_.vehicles.size()) +
                                " vehicles, got " + std::to_string(state.vehicles.size()));
  }
  for (std::size_t i = 0; i < model_.vehicles.size(); ++i) {
    if (state.vehicles[i].sensors.size() != model_.vehicles[i].sensors.size()) {
      throw std::invalid_argument("set_state: vehicle '" + model_.vehicles[i].name + "': expected " +
                                  std::to_string(model_.vehicles[i].sensors.size()) + " sensors, got " +
                                  std::to_string(state.vehicles[i].sensors.size()));
    }
    for (std::size_t k = 0; k < model_.vehicles[i].sensors.size(); ++k) {
      const SensorSpec& sensor = model_.vehicles[i].sensors[k];
      if (state.vehicles[i].sensors[k].kind.index() != sensor.kind.index()) {
        throw std::invalid_argument("set_state: vehicle '" + model_.vehicles[i].name + "': sensor '" + sensor.name +
                                    "' is a " + std::string(sensor.type()) + ", its state is of another kind");
      }
    }
    if (state.vehicles[i].thrusters.size() != model_.vehicles[i].thrusters.size()) {
      throw std::invalid_argument(
          "set_state: vehicle '" + model_.vehicles[i].name + "': expected " +
          std::to_string(model_.vehicles[i].thrusters.size()) + " thrusters, got " +
          std::to_string(state.vehicles[i].thrusters.size()));
    }
  }
  state_ = state;
  if (rays_) rays_->invalidate();  // the restored poses, even at the same step count
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
  const Eigen::Vector3d& g_W = model_.world.gravity_W;
  const Eigen::Vector3d Omega_W =
      model_.world.dynamics.earth_rotation
          ? earth_rotation_W(model_.world.dynamics, model_.world.origin.latitude)
          : Eigen::Vector3d::Zero();

  // (1)-(3) per vehicle: setpoints, rotor dynamics and thruster forces.
  for (int i = 0; i < num_vehicles; ++i) {
    const VehicleSpec& spec = model_.vehicles[i];
    VehicleRuntime& runtime = runtime_[i];
    VehicleState& vehicle = state_.vehicles[i];

    select_setpoints(spec, t, dt, vehicle);

    // Bullet is re-seeded from the state every step, so a restored SimState and the uninterrupted
    // run drive Bullet from identical numbers (X_WB -> X_WP is not exactly invertible).
    world_->set_body_state(i, vehicle.body);

    const Eigen::Isometry3d& X_WB = vehicle.body.X_WB;
    runtime.p_WBcm = X_WB * runtime.p_BBcm;
    runtime.v_WBcm = vehicle.body.v_WB + vehicle.body.w_WB.cross(runtime.p_WBcm - X_WB.translation());
    runtime.w_WB = vehicle.body.w_WB;
    runtime.f_W.setZero();
    runtime.tau_W.setZero();
    for (std::size_t k = 0; k < vehicle.thrusters.size(); ++k) {
      const physics::Thruster& thruster = runtime.thrusters[k];
      ThrusterState& thruster_state = vehicle.thrusters[k];
      thruster_state.rotor_speed =
          thruster.next_rotor_speed(thruster_state.rotor_speed, thruster_state.setpoint);
      const physics::ThrusterWrench wrench =
          thruster.wrench(thruster_state.rotor_speed, X_WB, surface_z);
      thruster_state.thrust = wrench.thrust;
      thruster_state.torque = wrench.torque;
      runtime.f_W += wrench.f_W;
      runtime.tau_W += wrench.tau_W + (wrench.p_WT - runtime.p_WBcm).cross(wrench.f_W);
    }
  }

  // (3) fluid, per vehicle independent (each writes only its own runtime), so in parallel when
  // several large hulls make it pay (pool_); gravity is Bullet's.
  auto fluid_forces = [&](std::size_t index) {
    VehicleRuntime& runtime = runtime_[index];
    const RigidBodyState& body = state_.vehicles[index].body;
    runtime.v_water_W = ocean_->current_W(runtime.p_WBcm, t);
    if (runtime.surface) {
      // Surface model: buoyancy, drag, friction, lift and Magnus from the faces, in the Ocean at the
      // step's start time; f_W acts at the centre of mass and tau_W is about it.
      physics::BodyMotion motion;
      motion.X_WB = body.X_WB;
      motion.p_WBcm = runtime.p_WBcm;
      motion.v_WBcm = runtime.v_WBcm;
      motion.w_WB = body.w_WB;
      const physics::HydrodynamicWrench fluid =
          runtime.surface->compute(motion, physics::OceanFluid(*ocean_, t));
      runtime.f_W += fluid.f_W;
      runtime.tau_W += fluid.tau_W;
      runtime.submerged_fraction = fluid.wetted_area / runtime.surface->surface_area();
      if (runtime.excess_volume > 0.0) {
        // Overlapping parts: take back the doubly counted buoyancy, -rho g E, at the overlap's
        // centroid, ramped from dry to wet over its height (exact when it is fully submerged).
        const Eigen::Vector3d p_WE = body.X_WB * runtime.p_BE;
        const double depth = ocean_->depth(p_WE.z());
        const double wet = std::clamp(0.5 + depth / runtime.excess_height, 0.0, 1.0);
        // Buoyancy acts along +z of W with the Ocean's g, like the kernel's pressure.
        const Eigen::Vector3d f_E(0.0, 0.0, -wet * ocean_->density(std::max(depth, 0.0)) *
                                                runtime.excess_volume * ocean_->gravity());
        runtime.f_W += f_E;
        runtime.tau_W += (p_WE - runtime.p_WBcm).cross(f_E);
      }
    } else {
      // Lumped model: buoyancy and damping relative to the current at the centre of mass.
      const physics::LumpedFluidWrench fluid = runtime.fluid.wrench(body, runtime.v_water_W);
      runtime.f_W += fluid.f_W();
      runtime.tau_W += fluid.tau_W() + (body.X_WB.translation() - runtime.p_WBcm).cross(fluid.f_W());
      runtime.submerged_fraction = fluid.submerged_fraction;
    }
  };
  if (pool_) {
    pool_->run(runtime_.size(), fluid_forces);
  } else {
    for (std::size_t i = 0; i < runtime_.size(); ++i) fluid_forces(i);
  }

  for (int i = 0; i < num_vehicles; ++i) {
    VehicleRuntime& runtime = runtime_[i];
    VehicleState& vehicle = state_.vehicles[i];
    Eigen::Vector3d f_W = runtime.f_W;
    Eigen::Vector3d tau_W = runtime.tau_W;

    // (3) Earth-rotation Coriolis.
    if (model_.world.dynamics.earth_rotation) f_W += -2.0 * runtime.mass * Omega_W.cross(runtime.v_WBcm);

    // (4) added mass: the wrench Bullet needs so that its rigid-body step follows
    // (M_RB + M_A) nu_dot + C_RB nu + C_A nu_r = tau + g + tau_contact.
    if (runtime.added_mass) {
      const Eigen::Matrix3d R_WB = vehicle.body.X_WB.linear();
      const Eigen::Matrix3d R_BW = R_WB.transpose();
      physics::AddedMassInput in;
      in.kappa = ocean_->kappa(std::max(ocean_->depth(runtime.p_WBcm.z()), 0.0)) *
                 runtime.submerged_fraction;
      in.nu.head<3>() = R_BW * runtime.v_WBcm;
      in.nu.tail<3>() = R_BW * vehicle.body.w_WB;
      in.nu_r = in.nu;
      in.nu_r.head<3>() -= R_BW * runtime.v_water_W;
      in.tau.head<3>() = R_BW * f_W;
      in.tau.tail<3>() = R_BW * tau_W;
      in.gravity_B = R_BW * g_W;
      in.tau_contact = vehicle.contact_wrench_B;
      runtime.tau_bullet_B = runtime.added_mass->bullet_wrench(in);
      runtime.nu0 = in.nu;
      runtime.R_WB0 = R_WB;
      f_W = R_WB * runtime.tau_bullet_B.head<3>();
      tau_W = R_WB * runtime.tau_bullet_B.tail<3>();
    }
    world_->add_force_W(i, f_W, runtime.p_WBcm);
    world_->add_torque_W(i, tau_W);
  }

  // (5) Bullet.
  world_->step(dt);

  // (6) snapshot; time from the step count so it does not drift.
  for (int i = 0; i < num_vehicles; ++i) {
    VehicleState& vehicle = state_.vehicles[i];
    vehicle.body = world_->body_state(i);
    const VehicleRuntime& runtime = runtime_[i];
    if (!runtime.added_mass) continue;
    // Contact wrench of this step, for the next one (zero without contact points).
    if (world_->num_contact_points(i) == 0) {
      vehicle.contact_wrench_B.setZero();
      continue;
    }
    const Eigen::Isometry3d& X_WB = vehicle.body.X_WB;
    const Eigen::Vector3d p_WBcm = X_WB * runtime.p_BBcm;
    const Eigen::Matrix3d R_B0W = runtime.R_WB0.transpose();
    Vector6d nu1_B0;
    nu1_B0.head<3>() =
        R_B0W * (vehicle.body.v_WB + vehicle.body.w_WB.cross(p_WBcm - X_WB.translation()));
    nu1_B0.tail<3>() = R_B0W * vehicle.body.w_WB;
    vehicle.contact_wrench_B = runtime.added_mass->contact_wrench(
        runtime.nu0, nu1_B0, dt, runtime.tau_bullet_B, R_B0W * g_W);
  }
  ++state_.step_count;
  state_.time = static_cast<double>(state_.step_count) * dt;

  // (7) non-finite check.
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

  // (8) sensors due at the new time sample the new state.
  for (int i = 0; i < num_vehicles; ++i) {
    const VehicleSpec& spec = model_.vehicles[i];
    const VehicleRuntime& runtime = runtime_[i];
    VehicleState& vehicle = state_.vehicles[i];
    for (std::size_t k = 0; k < spec.sensors.size(); ++k) {
      if (!sample_due(state_.step_count, dt, spec.sensors[k].rate_hz)) continue;
      const VehicleRuntime::Sensor& mount = runtime.sensors[k];
      const sensors::SampleContext context{state_.time, mount.period, dt, model_.world, *ocean_, *environment_,
                                           state_, i, mount.X_BS, runtime.p_BBcm, runtime.v_WBcm, runtime.w_WB,
                                           rays_.get()};
      SensorState& out = vehicle.sensors[k];
      std::visit(
          [&](const auto& kind_spec) {
            using Kind = sensors::KindOf<std::decay_t<decltype(kind_spec)>>;
            Kind::sample(context, kind_spec, std::get<typename Kind::State>(out.kind));
          },
          spec.sensors[k].kind);
      out.stamp = state_.time;
      ++out.samples;
    }
  }
}

}  // namespace hadal
