#include "hadal/config/scenario_loader.h"
#include "hadal/config/security_block.h"
#include "hadal/core/data_dir.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <utility>

#include "hadal/geometry/mesh_import.h"
#include "hadal/geometry/mesh_properties.h"
#include "hadal/geometry/mesh_transform.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/geometry/terrain.h"
#include "hadal/core/units.h"
#include "hadal/physics/seawater.h"
#include "hadal/physics/control_vector.h"
#include "hadal/physics/soil_map.h"
#include "hadal/physics/soil_presets.h"
#include "hadal/render/water_presets.h"
#include "hadal/sensors/geomagnetic.h"
#include "hadal/sensors/noise.h"
#include "hadal/sensors/sensor_kinds.h"
#include "hadal/config/yaml_reader.h"

namespace hadal::config {


namespace {

// Inertia tensors typed by hand are rounded to 3-4 digits; a 0.1 % tolerance on the triangle inequality
// still admits the limiting cases (thin rod, flat plate) written that way.
constexpr double kTriangleRelativeTolerance = 1e-3;

// Keys of a vehicle definition: an included file's root, or inline in the scenario's vehicle entry.
// the actuator kinds' lists, e.g. "thrusters" (physics/actuator_kinds.h), between links and sensors.
const std::vector<std::string>& definition_keys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> list = {"type", "seabed_contact", "links"};
    physics::ActuatorKinds::for_each(
        [&](auto tag) { list.emplace_back(decltype(tag)::type::kListKey); });
    list.insert(list.end(), {"sensors", "lights", "fluid"});
    return list;
  }();
  return keys;
}
const std::vector<std::string>& vehicle_entry_keys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> list = {"name", "include", "initial_pose", "initial_velocity",
                                     "initial_angular_velocity", "command_timeout_s",
                                     "odometry_rate_hz", "thruster_state_rate_hz", "schedule"};
    list.insert(list.end(), definition_keys().begin(), definition_keys().end());
    return list;
  }();
  return keys;
}

std::vector<std::pair<std::string, VehicleType>> vehicle_type_choices() {
  std::vector<std::pair<std::string, VehicleType>> choices;
  for (VehicleType type : {VehicleType::kAuv, VehicleType::kRov, VehicleType::kLander,
                           VehicleType::kSurfaceVessel, VehicleType::kGlider, VehicleType::kCrawler}) {
    choices.emplace_back(to_string(type), type);
  }
  return choices;
}

// Vehicle names become DDS/ROS topic segments (rt/<name>/...).
bool is_valid_vehicle_name(const std::string& name) {
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  return std::all_of(name.begin(), name.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

// R = Rz(yaw) Ry(pitch) Rx(roll), angles in radians.
Eigen::Matrix3d rotation_from_rpy(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// {position: [x, y, z], rpy_deg: [roll, pitch, yaw]}, both optional.
bool read_pose(const Value& value, Eigen::Isometry3d* X) {
  const MapReader map(value, {"position", "rpy_deg"});
  if (!map.ok()) return false;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d rpy_deg = Eigen::Vector3d::Zero();
  const bool ok = map.read_vector3("position", Need::kOptional, Range::finite(), &position) &
                  map.read_vector3("rpy_deg", Need::kOptional, Range::finite(), &rpy_deg);
  if (!ok) return false;
  X->setIdentity();
  X->linear() = rotation_from_rpy(rpy_deg * kDegToRad);
  X->translation() = position;
  return true;
}

// Reads a publication rate [Hz]: > 0 and, when the physics rate is known, at most the physics rate.
bool read_rate(const MapReader& map, const std::string& key, std::optional<double> physics_rate_hz,
               double* out) {
  const std::optional<Value> value = map.optional(key);
  if (!value) return true;
  const std::optional<double> rate = value->number(Range::positive());
  if (!rate) return false;
  if (physics_rate_hz && *rate > *physics_rate_hz) {
    value->error("must be <= world.physics_rate_hz (" + format_number(*physics_rate_hz) + ") (got " +
                 value->node().Scalar() + ")");
    return false;
  }
  *out = *rate;
  return true;
}

// Rejects names used twice in one list; `names` maps each name to the path that used it first.
bool check_unique(const Value& name_value, const std::string& name, const std::string& what,
                  const std::string& owner_path, std::map<std::string, std::string>* names) {
  const auto [it, inserted] = names->emplace(name, owner_path);
  if (!inserted) {
    name_value.error("duplicate " + what + " name " + quoted(name) + " (first used by " + it->second + ")");
  }
  return inserted;
}

// --- vehicle definition ------------------------------------------------------------------------------

// What a vehicle definition (inline or included) yields, plus what cross-checks need to know about it.
struct VehicleDefinition {
  std::string source_file;
  VehicleType type = VehicleType::kAuv;
  SeabedContact seabed_contact = SeabedContact::kRigid;
  std::vector<LinkSpec> links;
  std::vector<ActuatorSpec> actuators;
  std::vector<SensorSpec> sensors;
  std::vector<LightSpec> lights;
  FluidSpec fluid;
  // Length and names of the control vector, or nullopt when an actuator list itself is unusable (not a
  // list, an actuator without a valid name): the schedule's setpoint count is then not checked.
  std::optional<std::size_t> control_count;
  std::optional<std::vector<std::string>> control_names;
  // Names and kinds of the actuators (for sensors that refer to one); empty when a name is unusable.
  std::vector<std::string> actuator_names;
  std::vector<std::string> actuator_types;
  // The links' names (nullopt when some link has no usable name), for entries that extend an included
  // definition with sensors and lights.
  std::optional<std::vector<std::string>> link_names;
};

// ixx, iyy, izz > 0 and products (default 0) form I_LLcm_L = [[ixx ixy ixz] [ixy iyy iyz] [ixz iyz izz]]
// (tensor entries, as URDF/SDF). A physical body has a positive-definite I whose principal moments
// satisfy the triangle inequalities A + B >= C (because A + B - C = 2 * integral of z^2 dm).
bool read_inertia(const Value& value, Eigen::Matrix3d* I_out) {
  const MapReader map(value, {"ixx", "iyy", "izz", "ixy", "ixz", "iyz"});
  if (!map.ok()) return false;
  double ixx = 0.0, iyy = 0.0, izz = 0.0, ixy = 0.0, ixz = 0.0, iyz = 0.0;
  const bool ok = map.read_number("ixx", Need::kRequired, Range::positive(), &ixx) &
                  map.read_number("iyy", Need::kRequired, Range::positive(), &iyy) &
                  map.read_number("izz", Need::kRequired, Range::positive(), &izz) &
                  map.read_number("ixy", Need::kOptional, Range::finite(), &ixy) &
                  map.read_number("ixz", Need::kOptional, Range::finite(), &ixz) &
                  map.read_number("iyz", Need::kOptional, Range::finite(), &iyz);
  if (!ok) return false;

  Eigen::Matrix3d I;
  I << ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz;
  const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues();
  if (!(moments.minCoeff() > 0.0)) {
    value.error("must be positive definite (principal moments " + format_approximate(moments[0]) + ", " +
                format_approximate(moments[1]) + ", " + format_approximate(moments[2]) + ")");
    return false;
  }
  const double tolerance = kTriangleRelativeTolerance * moments.maxCoeff();
  // Diagonal entries obey the inequalities in any axes, so check them first for a readable message.
  const struct {
    double a, b, c;
    const char* text;
  } diagonal_checks[] = {{ixx, iyy, izz, "ixx + iyy >= izz"},
                         {iyy, izz, ixx, "iyy + izz >= ixx"},
                         {izz, ixx, iyy, "izz + ixx >= iyy"}};
  for (const auto& check : diagonal_checks) {
    if (check.a + check.b < check.c - tolerance) {
      value.error(std::string("violates the triangle inequality ") + check.text + " (" +
                  format_number(check.a) + " + " + format_number(check.b) + " < " + format_number(check.c) +
                  ")");
      return false;
    }
  }
  // Eigenvalues are sorted ascending: the binding inequality is m0 + m1 >= m2.
  if (moments[0] + moments[1] < moments[2] - tolerance) {
    value.error("violates the triangle inequality for principal moments (" + format_approximate(moments[0]) +
                " + " + format_approximate(moments[1]) + " < " + format_approximate(moments[2]) + ")");
    return false;
  }
  *I_out = I;
  return true;
}

bool read_collision(const Value& value, CollisionShape* shape) {
  const MapReader map(value, {"shape", "size", "radius", "length", "pose"});
  if (!map.ok()) return false;
  static const std::vector<std::pair<std::string, CollisionShapeType>> kShapes = {
      {"box", CollisionShapeType::kBox},
      {"sphere", CollisionShapeType::kSphere},
      {"cylinder", CollisionShapeType::kCylinder},
      {"capsule", CollisionShapeType::kCapsule}};
  const bool shape_ok = map.read_choice("shape", Need::kRequired, kShapes, &shape->type);
  // Values are checked whatever the shape; which of them the shape needs is checked below.
  bool ok = shape_ok;
  ok &= map.read_vector3("size", Need::kOptional, Range::positive(), &shape->box_size);
  ok &= map.read_number("radius", Need::kOptional, Range::positive(), &shape->radius);
  ok &= map.read_number("length", Need::kOptional, Range::positive(), &shape->length);
  if (const auto pose = map.optional("pose")) ok &= read_pose(*pose, &shape->X_LG);
  if (!shape_ok) return false;

  const std::string shape_name = map.optional("shape")->node().Scalar();
  const bool is_box = shape->type == CollisionShapeType::kBox;
  const bool is_round = !is_box;
  const bool has_length =
      shape->type == CollisionShapeType::kCylinder || shape->type == CollisionShapeType::kCapsule;
  const std::pair<const char*, bool> keys[] = {
      {"size", is_box}, {"radius", is_round}, {"length", has_length}};
  for (const auto& [key, needed] : keys) {
    if (needed && !map.has(key)) {
      map.required(key, "needed by shape " + quoted(shape_name));
      ok = false;
    } else if (!needed && map.has(key)) {
      map.error_at_key(key, "key " + quoted(key) + " is not used by shape " + quoted(shape_name));
      ok = false;
    }
  }
  return ok;
}

// Samples a procedural or heightmap seabed may have (16 M: 64 MB of float heights, ~32 M triangles).
constexpr double kMaxSeabedSamples = 16777216.0;

// Builds the seabed surface of `seabed` (already validated keys); reports load problems at `file_value`
// (the file key's value) or at the map.
void build_seabed_mesh(const MapReader& map, SeabedSpec* seabed) {
  using geometry::TriangleMesh;
  switch (seabed->type) {
    case SeabedType::kPlane:
      return;
    case SeabedType::kProcedural: {
      seabed->procedural.z_datum = seabed->z;
      const double samples = (seabed->procedural.size_x / seabed->procedural.resolution + 1.0) *
                             (seabed->procedural.size_y / seabed->procedural.resolution + 1.0);
      if (samples > kMaxSeabedSamples) {
        map.value().error("size / resolution gives " + format_approximate(samples) +
                          " height samples; at most 16777216 are allowed");
        return;
      }
      seabed->mesh = std::make_shared<const TriangleMesh>(
          geometry::heightfield_to_mesh(geometry::procedural_seabed(seabed->procedural)));
      return;
    }
    case SeabedType::kHeightmap: {
      const geometry::HeightmapLoad load = geometry::load_heightmap(seabed->heightmap);
      if (!load.field) {
        map.optional("file")->error(load.error);
        return;
      }
      seabed->mesh = std::make_shared<const TriangleMesh>(geometry::heightfield_to_mesh(*load.field));
      return;
    }
    case SeabedType::kMesh: {
      geometry::ImportResult imported = geometry::import_mesh(seabed->file, seabed->import);
      if (!imported.mesh) {
        map.optional("file")->error(imported.error);
        return;
      }
      geometry::transform_mesh(seabed->X_WM, &*imported.mesh);
      seabed->mesh = std::make_shared<const TriangleMesh>(std::move(*imported.mesh));
      return;
    }
  }
}

// world.water.current: uniform + exponentially decaying shear + Gauss-Markov (hadal/physics/ocean.h).
void read_current(const Value& value, CurrentSpec* current) {
  const MapReader map(value, {"uniform", "shear", "gauss_markov"});
  if (!map.ok()) return;
  map.read_vector3("uniform", Need::kOptional, Range::finite(), &current->uniform_W);
  if (const auto shear_value = map.optional("shear")) {
    const MapReader shear(*shear_value, {"surface", "decay_depth"});
    if (shear.ok()) {
      shear.read_vector3("surface", Need::kRequired, Range::finite(), &current->shear_surface_W);
      shear.read_number("decay_depth", Need::kRequired, Range::positive(), &current->shear_decay_depth);
    }
  }
  if (const auto gm_value = map.optional("gauss_markov")) {
    const MapReader gm(*gm_value, {"sigma", "time_constant_s"});
    if (gm.ok()) {
      gm.read_vector3("sigma", Need::kRequired, Range::non_negative(), &current->gauss_markov_sigma_W);
      // A slowly varying current: below 1 s it would be turbulence, and the lazily generated record
      // (64 samples per time constant) would grow large.
      gm.read_number("time_constant_s", Need::kRequired, Range::closed(1.0, 1e7),
                     &current->gauss_markov_time_constant);
    }
  }
}

// world.water: surface, density model (constant | ramp | ctd) with its own keys, pressure, current.
void read_water(const Value& value, WaterSpec* water) {
  const MapReader map(value, {"surface_z", "density", "density_model", "rho0", "pycnocline_depth",
                              "pycnocline_density_increase", "ctd", "temperature_degc", "salinity",
                              "atmospheric_pressure", "bulk_modulus", "ph", "current"});
  if (!map.ok()) return;
  map.read_number("surface_z", Need::kOptional, Range::finite(), &water->surface_z);
  map.read_number("atmospheric_pressure", Need::kOptional, Range::closed(0.0, 1e7), &water->atmospheric_pressure);
  map.read_number("bulk_modulus", Need::kOptional, Range::positive(), &water->bulk_modulus);
  map.read_number("ph", Need::kOptional, Range::closed(6.0, 9.0), &water->ph);
  if (const auto current = map.optional("current")) read_current(*current, &water->current);

  static const std::vector<std::pair<std::string, DensityModel>> kModels = {
      {"constant", DensityModel::kConstant}, {"ramp", DensityModel::kRamp}, {"ctd", DensityModel::kCtd}};
  if (!map.read_choice("density_model", Need::kOptional, kModels, &water->density_model)) return;
  const std::string model_name = map.has("density_model") ? map.optional("density_model")->node().Scalar()
                                                          : "constant";
  const DensityModel model = water->density_model;
  const bool is_constant = model == DensityModel::kConstant, is_ramp = model == DensityModel::kRamp,
             is_ctd = model == DensityModel::kCtd;
  const std::pair<const char*, bool> used[] = {{"density", is_constant},
                                               {"rho0", is_ramp},
                                               {"pycnocline_depth", is_ramp},
                                               {"pycnocline_density_increase", is_ramp},
                                               {"ctd", is_ctd},
                                               {"temperature_degc", !is_ctd},
                                               {"salinity", !is_ctd}};
  for (const auto& [key, needed] : used) {
    if (!needed && map.has(key)) {
      map.error_at_key(key, "key " + quoted(key) + " is not used by density_model " + quoted(model_name));
    }
  }

  const Range kTemperature = Range::closed(-2.5, 40.0), kSalinity = Range::closed(0.0, 42.0);
  if (is_constant) {
    map.read_number("density", Need::kOptional, Range::left_open(0.0, 2000.0), &water->density);
  }
  if (!is_ctd) {
    map.read_number("temperature_degc", Need::kOptional, kTemperature, &water->temperature);
    map.read_number("salinity", Need::kOptional, kSalinity, &water->salinity);
  }
  if (is_ramp) {
    map.read_number("rho0", Need::kOptional, Range::left_open(0.0, 2000.0), &water->rho0);
    map.read_number("pycnocline_depth", Need::kOptional, Range::positive(), &water->pycnocline_depth);
    map.read_number("pycnocline_density_increase", Need::kOptional, Range::closed(0.0, 100.0),
                    &water->pycnocline_density_increase);
    water->density = water->rho0;  // the lumped fluid model sees the surface density
  }
  if (is_ctd) {
    const auto ctd = map.required("ctd", "needed by density_model 'ctd'");
    if (!ctd) return;
    const auto rows = ctd->list();
    if (!rows) return;
    if (rows->size() < 2) {
      ctd->error("needs at least 2 rows (got " + std::to_string(rows->size()) + ")");
      return;
    }
    bool ok = true;
    // Depth of the previous row, when that row's depth was valid.
    bool has_previous = false;
    double previous_depth = 0.0;
    for (std::size_t i = 0; i < rows->size(); ++i) {
      const MapReader row((*rows)[i], {"depth", "temperature_degc", "salinity"});
      if (!row.ok()) {
        ok = false;
        has_previous = false;
        continue;
      }
      CtdSample sample;
      const bool depth_ok = row.read_number("depth", Need::kRequired, Range::closed(0.0, 11000.0), &sample.depth);
      ok &= depth_ok;
      ok &= row.read_number("temperature_degc", Need::kRequired, kTemperature, &sample.temperature);
      ok &= row.read_number("salinity", Need::kRequired, kSalinity, &sample.salinity);
      if (depth_ok && has_previous && !(sample.depth > previous_depth)) {
        row.optional("depth")->error("must be greater than the previous row's depth (" +
                                     format_number(previous_depth) + ")");
        ok = false;
      }
      has_previous = depth_ok;
      previous_depth = sample.depth;
      water->ctd.push_back(sample);
    }
    if (!ok) {
      water->ctd.clear();
      return;
    }
    // The lumped fluid model sees the surface density of the cast (EOS-80 at zero sea pressure).
    const CtdSample& top = water->ctd.front();
    water->density = physics::density_eos80(top.salinity, physics::its90_to_ipts68(top.temperature), 0.0);
  }
}

// world.seabed: type plane | mesh | heightmap | procedural, each with its own keys.
void read_seabed(const Value& value, std::uint64_t world_seed, SeabedSpec* seabed) {
  const MapReader map(value, {"type", "z", "file", "scale", "up_axis", "pose", "meters_per_pixel", "height_range",
                              "size", "resolution", "relief", "ridge_height", "slope_deg", "plain_radius", "seed"});
  if (!map.ok()) return;
  static const std::vector<std::pair<std::string, SeabedType>> kTypes = {{"plane", SeabedType::kPlane},
                                                                         {"mesh", SeabedType::kMesh},
                                                                         {"heightmap", SeabedType::kHeightmap},
                                                                         {"procedural", SeabedType::kProcedural}};
  if (!map.read_choice("type", Need::kOptional, kTypes, &seabed->type)) return;
  const std::string type_name = map.has("type") ? map.optional("type")->node().Scalar() : "plane";

  // Which keys each type takes; the rest are errors naming the type.
  const SeabedType type = seabed->type;
  const bool is_mesh = type == SeabedType::kMesh, is_heightmap = type == SeabedType::kHeightmap,
             is_procedural = type == SeabedType::kProcedural, is_plane = type == SeabedType::kPlane;
  const std::pair<const char*, bool> used[] = {
      {"z", is_plane || is_procedural}, {"file", is_mesh || is_heightmap}, {"scale", is_mesh},
      {"up_axis", is_mesh},           {"pose", is_mesh},                  {"meters_per_pixel", is_heightmap},
      {"height_range", is_heightmap}, {"size", is_procedural},            {"resolution", is_procedural},
      {"relief", is_procedural},      {"ridge_height", is_procedural},    {"slope_deg", is_procedural},
      {"plain_radius", is_procedural}, {"seed", is_procedural}};
  bool ok = true;
  for (const auto& [key, needed] : used) {
    if (!needed && map.has(key)) {
      map.error_at_key(key, "key " + quoted(key) + " is not used by seabed type " + quoted(type_name));
      ok = false;
    }
  }

  ok &= map.read_number("z", Need::kOptional, Range::finite(), &seabed->z);
  if (is_mesh || is_heightmap) {
    std::string file;
    if (map.read_string("file", Need::kRequired, &file) && map.optional("file")->file_path(file, &seabed->file)) {
      seabed->heightmap.file = seabed->file;
    } else {
      ok = false;
    }
  }
  if (is_mesh) {
    ok &= map.read_number("scale", Need::kOptional, Range::positive(), &seabed->import.scale);
    static const std::vector<std::pair<std::string, geometry::UpAxis>> kAxes = {{"z", geometry::UpAxis::kZ},
                                                                                 {"y", geometry::UpAxis::kY}};
    ok &= map.read_choice("up_axis", Need::kOptional, kAxes, &seabed->import.up_axis);
    if (const auto pose = map.optional("pose")) ok &= read_pose(*pose, &seabed->X_WM);
  }
  if (is_heightmap) {
    ok &= map.read_number("meters_per_pixel", Need::kRequired, Range::positive(), &seabed->heightmap.meters_per_pixel);
    if (const auto range = map.required("height_range")) {
      if (const auto values = range->numbers(2)) {
        if ((*values)[1] > (*values)[0]) {
          seabed->heightmap.height_min = (*values)[0];
          seabed->heightmap.height_max = (*values)[1];
        } else {
          range->error("must be [min, max] with max > min (got [" + format_number((*values)[0]) + ", " +
                       format_number((*values)[1]) + "])");
          ok = false;
        }
      } else {
        ok = false;
      }
    } else {
      ok = false;
    }
  }
  if (is_procedural) {
    geometry::ProceduralSeabedSpec& p = seabed->procedural;
    p.seed = world_seed;
    if (const auto size = map.optional("size")) {
      if (const auto values = size->numbers(2, Range::left_open(0.0, 100000.0))) {
        p.size_x = (*values)[0];
        p.size_y = (*values)[1];
      } else {
        ok = false;
      }
    }
    ok &= map.read_number("resolution", Need::kOptional, Range::positive(), &p.resolution);
    ok &= map.read_number("relief", Need::kOptional, Range::non_negative(), &p.relief);
    ok &= map.read_number("ridge_height", Need::kOptional, Range::non_negative(), &p.ridge_height);
    double slope_deg = p.slope / kDegToRad;
    if (map.read_number("slope_deg", Need::kOptional, Range::right_open(0.0, 60.0), &slope_deg)) {
      p.slope = slope_deg * kDegToRad;
    } else {
      ok = false;
    }
    ok &= map.read_number("plain_radius", Need::kOptional, Range::non_negative(), &p.plain_radius);
    if (const auto seed = map.optional("seed")) {
      if (const auto s = seed->non_negative_integer()) p.seed = *s; else ok = false;
    }
  }
  if (ok) build_seabed_mesh(map, seabed);
}

bool read_buoyancy(const Value& value, BuoyancySpec* buoyancy) {
  const MapReader map(value, {"volume", "center"});
  if (!map.ok()) return false;
  return map.read_number("volume", Need::kRequired, Range::non_negative(), &buoyancy->volume) &
         map.read_vector3("center", Need::kOptional, Range::finite(), &buoyancy->p_LCb);
}

// Reads a required `name` and reports it if already in `seen` (name -> path of its first user). False
// only when there is no usable name: a duplicate still names something that references can match.
bool read_unique_name(const MapReader& map, const std::string& what, std::map<std::string, std::string>* seen,
                      std::string* name) {
  const auto value = map.required("name");
  if (!value) return false;
  const auto text = value->string();
  if (!text) return false;
  *name = *text;
  check_unique(*value, *text, what, map.value().path(), seen);
  return true;
}

// Returns the link's name when it has a valid one (nullopt otherwise).
// link.mesh: {file, scale, up_axis, pose}. Imports the file into L and computes its volume properties;
// the returned properties are those of the mesh in L.
std::optional<geometry::MeshProperties> read_link_mesh(const Value& value, LinkMesh* link_mesh,
                                                       bool volume_matters = true) {
  const MapReader map(value, {"file", "scale", "up_axis", "pose"});
  if (!map.ok()) return std::nullopt;
  bool ok = true;
  std::string file;
  if (!map.read_string("file", Need::kRequired, &file) || !map.optional("file")->file_path(file, &link_mesh->file)) {
    ok = false;
  }
  ok &= map.read_number("scale", Need::kOptional, Range::positive(), &link_mesh->import.scale);
  static const std::vector<std::pair<std::string, geometry::UpAxis>> kAxes = {{"z", geometry::UpAxis::kZ},
                                                                               {"y", geometry::UpAxis::kY}};
  ok &= map.read_choice("up_axis", Need::kOptional, kAxes, &link_mesh->import.up_axis);
  if (const auto pose = map.optional("pose")) ok &= read_pose(*pose, &link_mesh->X_LM);
  if (!ok) return std::nullopt;

  geometry::ImportResult imported = geometry::import_mesh(link_mesh->file, link_mesh->import);
  if (!imported.mesh) {
    map.optional("file")->error(imported.error);
    return std::nullopt;
  }
  geometry::TriangleMesh& mesh = *imported.mesh;
  geometry::transform_mesh(link_mesh->X_LM, &mesh);
  geometry::MeshProperties properties = geometry::compute_mesh_properties(mesh);
  link_mesh->closed = properties.closed;
  link_mesh->volume = properties.volume;
  link_mesh->p_LMc = properties.centroid;
  link_mesh->mesh = std::make_shared<const geometry::TriangleMesh>(std::move(mesh));
  if (volume_matters && properties.closed && !(properties.volume > 0.0)) {
    value.error("mesh '" + file + "' encloses a volume of " + format_approximate(properties.volume) +
                " m^3 (faces oriented inward?)");
    return std::nullopt;
  }
  return properties;
}

// A link's `appearance` (AppearanceSpec): albedo, a checkerboard {squares: [columns, rows],
// square_size, dark_albedo, pose}, and the sonars' backscatter_db.
void read_appearance(const Value& value, AppearanceSpec* appearance) {
  const MapReader map(value, {"albedo", "checkerboard", "backscatter_db"});
  if (!map.ok()) return;
  double backscatter_db = 0.0;
  if (map.has("backscatter_db") &&
      map.read_number("backscatter_db", Need::kOptional, Range::closed(-80.0, 0.0), &backscatter_db)) {
    appearance->backscatter_db = backscatter_db;
  }
  Eigen::Vector3d albedo;
  if (map.has("albedo") && map.read_vector3("albedo", Need::kOptional, Range::closed(0.0, 1.0), &albedo)) {
    appearance->albedo = albedo.array();
  }
  if (const auto board_value = map.optional("checkerboard")) {
    const MapReader board(*board_value, {"squares", "square_size", "dark_albedo", "pose"});
    if (!board.ok()) return;
    CheckerboardSpec spec;
    bool ok = true;
    if (const auto squares = board.required("squares")) {
      if (const auto counts = squares->numbers(2, Range::closed(2.0, 1000.0))) {
        if ((*counts)[0] != std::floor((*counts)[0]) || (*counts)[1] != std::floor((*counts)[1])) {
          squares->error("must be two whole numbers [columns, rows] (got [" + format_number((*counts)[0]) + ", " +
                         format_number((*counts)[1]) + "])");
          ok = false;
        }
        spec.columns = static_cast<int>((*counts)[0]);
        spec.rows = static_cast<int>((*counts)[1]);
      } else {
        ok = false;
      }
    } else {
      ok = false;
    }
    ok &= board.read_number("square_size", Need::kRequired, Range::positive(), &spec.square_size);
    Eigen::Vector3d dark = spec.dark_albedo.matrix();
    if (board.read_vector3("dark_albedo", Need::kOptional, Range::closed(0.0, 1.0), &dark)) spec.dark_albedo = dark.array();
    if (const auto pose = board.optional("pose")) ok &= read_pose(*pose, &spec.X_LP);
    if (ok) appearance->checkerboard = spec;
  }
}

std::optional<std::string> read_link(const Value& value, std::map<std::string, std::string>* seen_names,
                                     LinkSpec* link) {
  const MapReader map(value, {"name", "pose", "mass", "center_of_mass", "inertia", "collisions", "buoyancy",
                              "mesh", "visual", "density", "appearance"});
  if (!map.ok()) return std::nullopt;
  const bool name_ok = read_unique_name(map, "link", seen_names, &link->name);
  if (const auto pose = map.optional("pose")) read_pose(*pose, &link->X_BL);

  std::optional<geometry::MeshProperties> mesh_properties;
  if (const auto mesh = map.optional("mesh")) {
    LinkMesh link_mesh;
    mesh_properties = read_link_mesh(*mesh, &link_mesh);
    if (mesh_properties) link->mesh = std::move(link_mesh);
  }

  double density = 0.0;
  const bool has_density = map.has("density");
  if (has_density && map.read_number("density", Need::kOptional, Range::positive(), &density)) {
    if (!map.has("mesh")) {
      map.error_at_key("density", "key 'density' needs 'mesh' (mass properties from the mesh's volume)");
    } else if (mesh_properties && !link->mesh->closed) {
      map.optional("mesh")->error("mesh is open (" + std::to_string(mesh_properties->boundary_edges) +
                                  " boundary edges): mass from 'density' needs a closed mesh");
    } else if (mesh_properties) {
      // Mass properties of the homogeneous solid the mesh encloses, already in L.
      link->mass = density * mesh_properties->volume;
      link->p_LLcm = mesh_properties->centroid;
      link->I_LLcm_L = density * mesh_properties->inertia_unit_density;
    }
    for (const char* key : {"mass", "center_of_mass", "inertia"}) {
      if (map.has(key)) {
        map.error_at_key(key, std::string("key '") + key + "' cannot be combined with 'density' (the mesh and " +
                                  "density give it)");
      }
    }
  } else if (!has_density) {
    map.read_number("mass", Need::kRequired, Range::positive(), &link->mass);
    map.read_vector3("center_of_mass", Need::kOptional, Range::finite(), &link->p_LLcm);
    if (const auto inertia = map.required("inertia")) read_inertia(*inertia, &link->I_LLcm_L);
  }

  if (const auto collisions = map.optional("collisions")) {
    if (const auto items = collisions->list()) {
      for (const Value& item : *items) {
        CollisionShape shape;
        read_collision(item, &shape);
        link->collisions.push_back(shape);
      }
    }
  }
  if (const auto buoyancy = map.optional("buoyancy")) {
    read_buoyancy(*buoyancy, &link->buoyancy);
  } else if (link->mesh) {
    // A hull mesh displaces the volume it encloses, centred on its centroid.
    if (link->mesh->closed) {
      link->buoyancy.volume = link->mesh->volume;
      link->buoyancy.p_LCb = link->mesh->p_LMc;
    } else {
      map.optional("mesh")->warn("mesh is open (" + std::to_string(mesh_properties->boundary_edges) +
                                 " boundary edges): its volume is undefined, so the link gets no buoyancy; "
                                 "give buoyancy: {volume, center} or close the mesh");
    }
  }
  if (const auto visual = map.optional("visual")) {
    // How the link looks (open meshes welcome: their volume is never used).
    LinkMesh visual_mesh;
    if (read_link_mesh(*visual, &visual_mesh, /*volume_matters=*/false)) link->visual = std::move(visual_mesh);
  }
  if (const auto appearance = map.optional("appearance")) read_appearance(*appearance, &link->appearance);
  if (!name_ok) return std::nullopt;
  return link->name;
}

// A `link` value naming one of the vehicle's links: its index into `link_names`, or nullopt (reported
// unless `link_names` itself is unknown, nullopt, when a bad link list was reported already).
std::optional<int> read_link_reference(const Value& link, const std::optional<std::vector<std::string>>& link_names) {
  const auto link_name = link.string();
  if (!link_name) return std::nullopt;
  const auto& names = link_names.value_or(std::vector<std::string>());
  const auto it = std::find(names.begin(), names.end(), *link_name);
  if (it != names.end()) return static_cast<int>(it - names.begin());
  if (link_names) {
    link.error("no link named " + quoted(*link_name) + " in this vehicle (links: " + join_names(names) + ")");
  }
  return std::nullopt;
}

// The actuator kinds' YAML readers, one row per kind of physics/actuator_kinds.h, in its order: each
// kind has a list of its own in the vehicle definition.
struct ActuatorKindReader {
  std::string list_key;                   // e.g. "thrusters"
  std::string type;                       // e.g. "thruster"
  const std::vector<std::string>* keys;  // the kind's keys besides name and link
  std::size_t controls;                   // its entries of the control vector
  physics::ActuatorKindSpec (*read)(const physics::ActuatorReader&);
};

const std::vector<ActuatorKindReader>& actuator_kind_readers() {
  static const std::vector<ActuatorKindReader> readers = [] {
    std::vector<ActuatorKindReader> list;
    physics::ActuatorKinds::for_each([&](auto tag) {
      using Kind = typename decltype(tag)::type;
      list.push_back({std::string(Kind::kListKey), std::string(Kind::kType), &Kind::keys(), Kind::kControls,
                      [](const physics::ActuatorReader& reader) -> physics::ActuatorKindSpec {
                        return Kind::read(reader);
                      }});
    });
    return list;
  }();
  return readers;
}

// One entry of an actuator list: name, link, then the kind's keys. `link_names` is nullopt when some
// link has no valid name: an unmatched link is then not reported (it may name that link).
std::optional<std::string> read_actuator(const Value& value, const ActuatorKindReader& kind,
                                         const std::optional<std::vector<std::string>>& link_names,
                                         std::map<std::string, std::string>* seen_names, ActuatorSpec* actuator) {
  std::vector<std::string> keys = {"name", "link"};
  keys.insert(keys.end(), kind.keys->begin(), kind.keys->end());
  const MapReader map(value, keys);
  if (!map.ok()) return std::nullopt;
  const bool name_ok = read_unique_name(map, kind.type, seen_names, &actuator->name);
  if (const auto link = map.required("link")) {
    if (const auto index = read_link_reference(*link, link_names)) actuator->link_index = *index;
  }
  actuator->kind = kind.read(physics::ActuatorReader{map});
  if (!name_ok) return std::nullopt;
  return actuator->name;
}

// The sensor kinds' YAML readers, one row per kind of sensors/sensor_kinds.h, in its order.
struct SensorKindReader {
  std::string type;                       // `type:` value
  const std::vector<std::string>* keys;  // the keys only this kind takes
  bool captures;                          // captured asynchronously: takes latency_s
  sensors::SensorKindSpec (*read)(const sensors::SensorReader&);
};

const std::vector<SensorKindReader>& sensor_kind_readers() {
  static const std::vector<SensorKindReader> readers = [] {
    std::vector<SensorKindReader> list;
    sensors::SensorKinds::for_each([&](auto tag) {
      using Kind = typename decltype(tag)::type;
      list.push_back({std::string(Kind::kType), &Kind::keys(), Kind::kCaptures,
                      [](const sensors::SensorReader& reader) -> sensors::SensorKindSpec { return Kind::read(reader); }});
    });
    return list;
  }();
  return readers;
}

// One entry of a vehicle definition's `sensors` list: the common keys, then the kind's own through its
// reader. `link_names` as for actuators (nullopt: unknown, then a `link` is not checked);
// `physics_rate_hz` bounds rate_hz when known. Keys of another sensor kind are errors.
void read_sensor(const Value& value, const std::optional<std::vector<std::string>>& link_names,
                 const std::vector<std::string>& actuator_names, const std::vector<std::string>& actuator_types,
                 std::optional<double> physics_rate_hz,
                 std::map<std::string, std::string>* seen_names, SensorSpec* sensor) {
  const std::vector<SensorKindReader>& readers = sensor_kind_readers();
  std::vector<std::pair<std::string, std::size_t>> types;
  std::vector<std::string> keys = {"name", "type", "link", "pose", "rate_hz", "frame_id", "latency_s"};
  for (std::size_t k = 0; k < readers.size(); ++k) {
    types.emplace_back(readers[k].type, k);
    for (const std::string& key : *readers[k].keys) {
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
    }
  }
  const MapReader map(value, keys);
  if (!map.ok()) return;
  read_unique_name(map, "sensor", seen_names, &sensor->name);
  std::size_t kind = 0;
  if (!map.read_choice("type", Need::kRequired, types, &kind)) return;
  if (const auto link = map.optional("link")) {
    if (const auto index = read_link_reference(*link, link_names)) sensor->link_index = *index;
  }
  if (const auto pose = map.optional("pose")) read_pose(*pose, &sensor->X_LS);
  read_rate(map, "rate_hz", physics_rate_hz, &sensor->rate_hz);
  map.read_string("frame_id", Need::kOptional, &sensor->frame_id);
  const SensorKindReader& reader = readers[kind];
  if (map.has("latency_s") && !reader.captures) {
    map.error_at_key("latency_s", "key 'latency_s' is not used by sensor type " + quoted(reader.type) +
                                      " (it samples on the stepping thread, without latency)");
  } else {
    map.read_number("latency_s", Need::kOptional, Range::closed(0.0, 10.0), &sensor->latency_s);
  }
  std::vector<std::string> reported;  // a key of several other kinds (preset) is reported once
  for (const SensorKindReader& other : readers) {
    if (&other == &reader) continue;
    for (const std::string& key : *other.keys) {
      if (map.has(key) && std::find(reader.keys->begin(), reader.keys->end(), key) == reader.keys->end() &&
          std::find(reported.begin(), reported.end(), key) == reported.end()) {
        reported.push_back(key);
        map.error_at_key(key, "key " + quoted(key) + " is not used by sensor type " + quoted(reader.type));
      }
    }
  }
  sensor->kind = reader.read(
      sensors::SensorReader{map, actuator_names, actuator_types, map.has("rate_hz"), sensor->rate_hz});
}

// One entry of a vehicle's `lights` list (LightSpec): name, link, pose, beam half angles, intensity.
void read_light(const Value& value, const std::optional<std::vector<std::string>>& link_names,
                std::map<std::string, std::string>* seen_names, LightSpec* light) {
  const MapReader map(value, {"name", "link", "pose", "inner_half_angle_deg", "outer_half_angle_deg",
                              "intensity_w_per_sr"});
  if (!map.ok()) return;
  read_unique_name(map, "light", seen_names, &light->name);
  if (const auto link = map.required("link")) {
    if (const auto index = read_link_reference(*link, link_names)) light->link_index = *index;
  }
  if (const auto pose = map.optional("pose")) read_pose(*pose, &light->X_LF);
  double inner_deg = light->inner_half_angle / kDegToRad, outer_deg = light->outer_half_angle / kDegToRad;
  const bool inner_ok = map.read_number("inner_half_angle_deg", Need::kOptional, Range::right_open(0.0, 180.0), &inner_deg);
  const bool outer_ok = map.read_number("outer_half_angle_deg", Need::kOptional, Range::left_open(0.0, 180.0), &outer_deg);
  if (inner_ok && outer_ok && !(inner_deg < outer_deg)) {
    map.error_at_key(map.has("outer_half_angle_deg") ? "outer_half_angle_deg" : "inner_half_angle_deg",
                     "the beam's outer half angle (" + format_number(outer_deg) +
                         " deg) must exceed its inner half angle (" + format_number(inner_deg) + " deg)");
  }
  light->inner_half_angle = inner_deg * kDegToRad;
  light->outer_half_angle = outer_deg * kDegToRad;
  Eigen::Vector3d intensity = light->intensity_W_per_sr.matrix();
  if (map.read_vector3("intensity_w_per_sr", Need::kOptional, Range::closed(0.0, 1e7), &intensity)) {
    light->intensity_W_per_sr = intensity.array();
  }
}

void read_hydrodynamics(const Value& value, physics::HydrodynamicCoefficients* coefficients) {
  const MapReader map(value, {"drag", "skin_friction", "lift", "magnus"});
  if (!map.ok()) return;
  map.read_number("drag", Need::kOptional, Range::non_negative(), &coefficients->drag);
  map.read_number("skin_friction", Need::kOptional, Range::non_negative(), &coefficients->skin_friction);
  map.read_number("lift", Need::kOptional, Range::non_negative(), &coefficients->lift);
  map.read_number("magnus", Need::kOptional, Range::non_negative(), &coefficients->magnus);
}

// fluid.added_mass: {model: none|ellipsoid|matrix, semi_axes, pose, matrix, reference_point, coriolis}.
void read_added_mass(const Value& value, AddedMassSpec* added) {
  const MapReader map(value, {"model", "semi_axes", "pose", "matrix", "reference_point", "coriolis"});
  if (!map.ok()) return;
  static const std::vector<std::pair<std::string, AddedMassModel>> kModels = {
      {"none", AddedMassModel::kNone}, {"ellipsoid", AddedMassModel::kEllipsoid},
      {"matrix", AddedMassModel::kMatrix}};
  if (!map.read_choice("model", Need::kOptional, kModels, &added->model)) return;
  const bool is_ellipsoid = added->model == AddedMassModel::kEllipsoid;
  const bool is_matrix = added->model == AddedMassModel::kMatrix;
  const std::string model_name = is_ellipsoid ? "ellipsoid" : is_matrix ? "matrix" : "none";
  const std::pair<const char*, bool> used[] = {{"semi_axes", is_ellipsoid},
                                               {"pose", is_ellipsoid},
                                               {"matrix", is_matrix},
                                               {"reference_point", is_matrix},
                                               {"coriolis", is_ellipsoid || is_matrix}};
  bool ok = true;
  for (const auto& [key, needed] : used) {
    if (!needed && map.has(key)) {
      map.error_at_key(key, "key " + quoted(key) + " is not used by added_mass model " + quoted(model_name));
      ok = false;
    }
  }
  if (!ok) return;
  map.read_bool("coriolis", Need::kOptional, &added->coriolis);
  if (is_ellipsoid) {
    Eigen::Vector3d semi_axes = Eigen::Vector3d::Zero();
    if (map.has("semi_axes") && map.read_vector3("semi_axes", Need::kRequired, Range::positive(), &semi_axes)) {
      added->semi_axes_E = semi_axes;
    }
    if (const auto pose = map.optional("pose")) {
      if (!map.has("semi_axes")) {
        map.error_at_key("pose", "key 'pose' needs 'semi_axes' (without them the ellipsoid is fitted to the "
                                 "hull, centre and axes included)");
      } else {
        read_pose(*pose, &added->X_BE);
      }
    }
  }
  if (is_matrix) {
    map.read_vector3("reference_point", Need::kOptional, Range::finite(), &added->p_BR);
    if (const auto matrix = map.required("matrix", "model 'matrix' needs the 6x6 added-mass matrix")) {
      if (const auto values = matrix->numbers(36)) {
        const Matrix6d M = Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(values->data());
        const double scale = M.cwiseAbs().maxCoeff();
        const double asymmetry = (M - M.transpose()).cwiseAbs().maxCoeff();
        if (asymmetry > 1e-9 * scale) {
          matrix->error("must be symmetric (largest |M_ij - M_ji| = " + format_approximate(asymmetry) + ")");
        } else if (Eigen::SelfAdjointEigenSolver<Matrix6d>(M).eigenvalues().minCoeff() < -1e-9 * scale) {
          matrix->error("must be positive semidefinite (an added mass cannot lower the kinetic energy)");
        } else {
          added->M_A0 = M;
        }
      }
    }
  }
}

// `links` are the vehicle's links as read. The default model is 'surface' when some link has faces
// (a mesh or collision shapes), else 'lumped' (buoyancy volumes and damping need no geometry).
// `value` is the `fluid` map, or nullopt when the definition has none.
void read_fluid(const std::optional<Value>& value, const std::vector<LinkSpec>& links, FluidSpec* fluid) {
  const bool has_faces = geometry::has_surface_geometry(links);
  fluid->model = has_faces ? FluidModelType::kSurface : FluidModelType::kLumped;
  // Added mass is fitted to the hull by default; a vehicle without geometry has none unless given.
  fluid->added_mass.model = has_faces ? AddedMassModel::kEllipsoid : AddedMassModel::kNone;
  std::optional<MapReader> map;
  if (value) {
    map.emplace(*value, std::vector<std::string>{"model", "linear_damping", "quadratic_damping",
                                                 "hydrodynamics", "added_mass"});
    if (!map->ok()) return;
    static const std::vector<std::pair<std::string, FluidModelType>> kModels = {
        {"lumped", FluidModelType::kLumped}, {"surface", FluidModelType::kSurface}};
    if (!map->read_choice("model", Need::kOptional, kModels, &fluid->model)) return;
  }
  const bool is_lumped = fluid->model == FluidModelType::kLumped;
  const std::string model_name = is_lumped ? "lumped" : "surface";
  if (map) {
    const std::pair<const char*, bool> used[] = {
        {"linear_damping", is_lumped}, {"quadratic_damping", is_lumped}, {"hydrodynamics", !is_lumped}};
    for (const auto& [key, needed] : used) {
      if (!needed && map->has(key)) {
        const char* why_default = is_lumped ? " (the default for a vehicle without a mesh or collision shapes)"
                                            : " (the default for a vehicle with a mesh or collision shapes; "
                                              "set model: lumped for damping coefficients)";
        map->error_at_key(key, "key " + quoted(key) + " is not used by fluid model " + quoted(model_name) +
                                   (map->has("model") ? "" : why_default));
      }
    }
    if (const auto added_mass = map->optional("added_mass")) read_added_mass(*added_mass, &fluid->added_mass);
  }
  if (is_lumped) {
    if (!map) return;
    const std::pair<const char*, Vector6d*> dampings[] = {{"linear_damping", &fluid->linear_damping},
                                                          {"quadratic_damping", &fluid->quadratic_damping}};
    for (const auto& [key, out] : dampings) {
      if (const auto damping = map->optional(key)) {
        if (const auto values = damping->numbers(6, Range::non_negative())) {
          *out = Eigen::Map<const Vector6d>(values->data());
        }
      }
    }
    return;
  }
  if (map) {
    if (const auto hydrodynamics = map->optional("hydrodynamics")) {
      read_hydrodynamics(*hydrodynamics, &fluid->hydrodynamics);
    }
  }
  if (has_faces || links.empty()) return;  // no links: already reported
  map->optional("model")->error(
      "fluid model 'surface' needs a hydrodynamic mesh: no link has a 'mesh' or 'collisions'");
}

// Appends the `sensors` and `lights` lists of `map` to the definition (names unique within each list,
// those already in the definition included): a definition's own lists, or a scenario's vehicle entry
// extending an included definition.
void read_sensors_and_lights(const MapReader& map, std::optional<double> physics_rate_hz, VehicleDefinition* definition) {
  if (const auto sensors = map.optional("sensors")) {
    if (const auto items = sensors->list()) {
      std::map<std::string, std::string> seen;
      for (const SensorSpec& sensor : definition->sensors) seen.emplace(sensor.name, definition->source_file);
      for (std::size_t i = 0; i < items->size(); ++i) {
        SensorSpec sensor;
        read_sensor((*items)[i], definition->link_names, definition->actuator_names, definition->actuator_types,
                    physics_rate_hz, &seen, &sensor);
        definition->sensors.push_back(std::move(sensor));
      }
    }
  }
  if (const auto lights = map.optional("lights")) {
    if (const auto items = lights->list()) {
      std::map<std::string, std::string> seen;
      for (const LightSpec& light : definition->lights) seen.emplace(light.name, definition->source_file);
      for (const Value& item : *items) read_light(item, definition->link_names, &seen, &definition->lights.emplace_back());
    }
  }
}

// Reads the definition keys (type, links, the actuator lists, sensors, fluid) of `map`: the included file's root, or the
// scenario's vehicle entry for an inline definition.
VehicleDefinition read_definition(const MapReader& map, std::optional<double> physics_rate_hz) {
  VehicleDefinition definition;
  definition.source_file = map.value().file();
  map.read_choice("type", Need::kRequired, vehicle_type_choices(), &definition.type);
  map.read_choice<SeabedContact>("seabed_contact", Need::kOptional,
                                 {{"rigid", SeabedContact::kRigid}, {"soil", SeabedContact::kSoil}},
                                 &definition.seabed_contact);

  std::optional<std::vector<std::string>> link_names;  // nullopt: not all links have a usable name
  if (const auto links = map.required("links")) {
    if (const auto items = links->list()) {
      if (items->empty()) links->error("must not be empty (links[0] is the base link)");
      link_names.emplace();
      std::map<std::string, std::string> seen;
      for (std::size_t i = 0; i < items->size(); ++i) {
        LinkSpec link;
        const auto name = read_link((*items)[i], &seen, &link);
        if (name && link_names) {
          link_names->push_back(*name);
        } else {
          link_names.reset();
        }
        definition.links.push_back(std::move(link));
      }
    }
  }

  definition.control_count = 0;
  definition.control_names.emplace();
  std::map<std::string, std::string> actuator_names_seen;  // unique across every actuator list
  for (const ActuatorKindReader& kind : actuator_kind_readers()) {
    const auto list = map.optional(kind.list_key);
    if (!list) continue;
    const auto items = list->list();
    if (!items) {
      definition.control_count.reset();
      definition.control_names.reset();
      continue;
    }
    if (definition.control_count) *definition.control_count += items->size() * kind.controls;
    for (std::size_t i = 0; i < items->size(); ++i) {
      ActuatorSpec actuator;
      const auto name = read_actuator((*items)[i], kind, link_names, &actuator_names_seen, &actuator);
      if (name && definition.control_names) {
        for (std::size_t c = 0; c < kind.controls; ++c) {
          definition.control_names->push_back(kind.controls == 1 ? *name : *name + "[" + std::to_string(c) + "]");
        }
        definition.actuator_names.push_back(*name);
        definition.actuator_types.push_back(kind.type);
      } else {
        definition.control_names.reset();
      }
      definition.actuators.push_back(std::move(actuator));
    }
  }
  if (!definition.control_names) {
    definition.actuator_names.clear();
    definition.actuator_types.clear();
  }

  definition.link_names = link_names;
  if (definition.seabed_contact == SeabedContact::kSoil && !definition.links.empty() &&
      !geometry::has_surface_geometry(definition.links)) {
    map.error_at_key("seabed_contact", "soil contact presses on the vehicle's surface, and no link has a mesh or "
                                       "collision shapes");
  }
  read_sensors_and_lights(map, physics_rate_hz, &definition);

  read_fluid(map.optional("fluid"), definition.links, &definition.fluid);
  return definition;
}

// world.acoustics (AcousticsSpec): Lambert's backscatter parameter of the seabed and of hulls [dB].
void read_acoustics(const Value& value, AcousticsSpec* acoustics) {
  const MapReader map(value, {"seabed_backscatter_db", "vehicle_backscatter_db"});
  if (!map.ok()) return;
  map.read_number("seabed_backscatter_db", Need::kOptional, Range::closed(-80.0, 0.0), &acoustics->seabed_backscatter_db);
  map.read_number("vehicle_backscatter_db", Need::kOptional, Range::closed(-80.0, 0.0), &acoustics->vehicle_backscatter_db);
}

// world.optics (OpticsSpec), its defaults filled whether or not the block is given: water absorption
// = pure water (Pope & Fry 1997, render/water_presets.h) unless given, scattering 0.037 /m per channel
// (Petzold's clear ocean at 530 nm, b = 0.037 /m: Mobley, Light and Water (1994), Table 3.10), the
// Henyey-Greenstein g 0.924, forward scatter within 10 deg (render/forward_scatter.h); daylight E0 [W/m^2 per channel] at the water surface decaying by a Jerlov
// type's Kd (type I by default).
void read_optics(const std::optional<Value>& value, double surface_z, OpticsSpec* optics) {
  optics->water.absorption_per_m = render::pure_water_absorption_per_m();
  optics->water.scattering_per_m = render::Rgb::Constant(0.037);
  optics->water.forward_scatter_max_angle_rad = 10.0 * kDegToRad;
  optics->daylight.surface_irradiance_W_per_m2 = render::Rgb(150.0, 170.0, 160.0);
  optics->daylight.Kd_per_m = render::jerlov_Kd_per_m(render::JerlovType::kI);
  optics->daylight.surface_z_m = surface_z;
  if (!value) return;
  const MapReader map(*value, {"absorption", "scattering", "phase_g", "forward_scatter_max_angle_deg", "daylight",
                               "seabed_albedo", "vehicle_albedo", "marine_snow", "seabed_pattern"});
  if (!map.ok()) return;
  const auto read_rgb = [](const MapReader& from, const std::string& key, const Range& range, Eigen::Array3d* out) {
    Eigen::Vector3d v = out->matrix();
    if (from.read_vector3(key, Need::kOptional, range, &v)) *out = v.array();
  };
  read_rgb(map, "absorption", Range::closed(0.0, 100.0), &optics->water.absorption_per_m);
  read_rgb(map, "scattering", Range::closed(0.0, 100.0), &optics->water.scattering_per_m);
  map.read_number("phase_g", Need::kOptional, Range{-1.0, 1.0, false, false}, &optics->water.phase_g);
  double forward_deg = optics->water.forward_scatter_max_angle_rad / kDegToRad;
  if (map.read_number("forward_scatter_max_angle_deg", Need::kOptional, Range::closed(0.0, 30.0), &forward_deg)) {
    optics->water.forward_scatter_max_angle_rad = forward_deg * kDegToRad;
  }
  read_rgb(map, "seabed_albedo", Range::closed(0.0, 1.0), &optics->seabed_albedo);
  read_rgb(map, "vehicle_albedo", Range::closed(0.0, 1.0), &optics->vehicle_albedo);
  if (const auto pattern_value = map.optional("seabed_pattern")) {
    const MapReader pattern(*pattern_value, {"amplitude", "scale", "octaves"});
    if (pattern.ok()) {
      render::SedimentPattern& out = optics->seabed_pattern;
      pattern.read_number("amplitude", Need::kRequired, Range::closed(0.0, 1.0), &out.amplitude);
      pattern.read_number("scale", Need::kOptional, Range::left_open(0.0, 1e4), &out.scale_m);
      pattern.read_whole_number("octaves", Need::kOptional, Range::closed(1.0, 8.0), &out.octaves);
    }
  }
  if (const auto snow_value = map.optional("marine_snow")) {
    const MapReader snow(*snow_value, {"density", "radius", "max_range", "albedo"});
    if (snow.ok()) {
      render::MarineSnow& out = optics->marine_snow;
      snow.read_number("density", Need::kRequired, Range::closed(0.0, 1e5), &out.density_per_m3);
      snow.read_number("radius", Need::kOptional, Range::left_open(0.0, 0.1), &out.radius_m);
      snow.read_number("max_range", Need::kOptional, Range::left_open(0.0, 50.0), &out.max_range_m);
      snow.read_number("albedo", Need::kOptional, Range::closed(0.0, 1.0), &out.albedo);
    }
  }
  if (const auto daylight_value = map.optional("daylight")) {
    const MapReader daylight(*daylight_value, {"surface_irradiance", "jerlov_type"});
    if (!daylight.ok()) return;
    read_rgb(daylight, "surface_irradiance", Range::closed(0.0, 1e5), &optics->daylight.surface_irradiance_W_per_m2);
    if (const auto type = daylight.optional("jerlov_type")) {
      if (const auto name = type->string()) {
        render::JerlovType jerlov = render::JerlovType::kI;
        if (render::jerlov_type_from_string(*name, &jerlov)) {
          optics->daylight.Kd_per_m = render::jerlov_Kd_per_m(jerlov);
        } else {
          type->error("unknown Jerlov water type " + quoted(*name) +
                      " (one of I, IA, IB, II, III, 1C, 3C, 5C, 7C, 9C)");
        }
      }
    }
  }
}

// A soil's parameters: a preset (physics/soil_presets.h) with any of them overridden, in SI; `preset_name`
// and `p` hold the starting soil on entry.
const std::vector<std::string> kSoilParameterKeys = {"preset",   "sinkage_exponent", "k_c",
                                                     "k_phi",    "cohesion",         "friction_angle_deg",
                                                     "shear_deformation_modulus", "damping", "shear_damping_time"};

void read_soil_parameters(const MapReader& map, std::string* preset_name, physics::SoilParameters* p) {
  if (const auto preset = map.optional("preset")) {
    if (const auto name = preset->string()) {
      if (const physics::SoilPreset* found = physics::find_soil_preset(*name)) {
        *preset_name = *name;
        *p = found->soil;
      } else {
        preset->error("unknown soil preset " + quoted(*name) + " (one of " + physics::soil_preset_names() + ")");
      }
    }
  }
  map.read_number("sinkage_exponent", Need::kOptional, Range::left_open(0.0, 3.0), &p->sinkage_exponent);
  map.read_number("k_c", Need::kOptional, Range::closed(0.0, 1e9), &p->k_c);
  map.read_number("k_phi", Need::kOptional, Range::closed(0.0, 1e10), &p->k_phi);
  map.read_number("cohesion", Need::kOptional, Range::closed(0.0, 1e7), &p->cohesion);
  double friction_angle_deg = p->friction_angle / kDegToRad;
  if (map.read_number("friction_angle_deg", Need::kOptional, Range::closed(0.0, 60.0), &friction_angle_deg)) {
    p->friction_angle = friction_angle_deg * kDegToRad;
  }
  map.read_number("shear_deformation_modulus", Need::kOptional, Range::left_open(0.0, 1.0),
                  &p->shear_deformation_modulus);
  map.read_number("damping", Need::kOptional, Range::closed(0.0, 1e9), &p->damping);
  map.read_number("shear_damping_time", Need::kOptional, Range::closed(0.0, 1.0), &p->shear_damping_time);
  if (p->k_c == 0.0 && p->k_phi == 0.0 && (map.has("k_c") || map.has("k_phi"))) {
    map.error_at_key(map.has("k_phi") ? "k_phi" : "k_c", "k_c and k_phi are both 0: the soil would bear nothing");
  }
}

// world.soil (SoilSpec): the world's soil (the deep-sea ooze when neither the block nor its preset is
// given), and optionally soils by region: `regions` (each a soil like the world's, starting from the
// ooze) placed by the image `map`.
void read_soil(const std::optional<Value>& value, SoilSpec* soil) {
  soil->preset = "deep_sea_ooze";
  soil->parameters = physics::find_soil_preset(soil->preset)->soil;
  if (!value) return;
  std::vector<std::string> keys = kSoilParameterKeys;
  keys.insert(keys.end(), {"regions", "map"});
  const MapReader map(*value, keys);
  if (!map.ok()) return;
  read_soil_parameters(map, &soil->preset, &soil->parameters);
  if (const auto regions = map.optional("regions")) {
    if (const auto list = regions->list()) {
      if (list->empty()) regions->error("must list at least one soil (or leave regions out)");
      if (list->size() > 255) regions->error("at most 255 regions (a map pixel is 8 bits; 0 is the world's soil)");
      for (const Value& entry : *list) {
        const MapReader region_map(entry, kSoilParameterKeys);
        SoilSpec::Region region{"deep_sea_ooze", physics::find_soil_preset("deep_sea_ooze")->soil};
        // A malformed entry (reported) still holds its place, so the map's numbers keep their meaning.
        if (region_map.ok()) read_soil_parameters(region_map, &region.preset, &region.parameters);
        soil->regions.push_back(region);
      }
    }
  }
  const auto map_value = map.optional("map");
  if (map.has("regions") && !map_value) {
    map.error_at_key("regions", "regions need a `map` that says where each one is");
  }
  if (!map_value) return;
  if (!map.has("regions")) {
    map.error_at_key("map", "a soil map places `regions`, and there are none");
    return;
  }
  const MapReader image(*map_value, {"file", "meters_per_pixel", "center"});
  if (!image.ok()) return;
  std::string file;
  double meters_per_pixel = 0.0;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  bool ok = image.read_string("file", Need::kRequired, &file);
  ok &= image.read_number("meters_per_pixel", Need::kRequired, Range::left_open(0.0, 1e6), &meters_per_pixel);
  if (const auto center_value = image.optional("center")) {
    if (const auto xy = center_value->numbers(2)) {
      center.head<2>() = Eigen::Vector2d((*xy)[0], (*xy)[1]);
    } else {
      ok = false;
    }
  }
  if (!ok || soil->regions.empty()) return;
  const auto file_value = image.optional("file");
  std::string path;
  if (!file_value->file_path(file, &path)) return;
  const physics::SoilMapLoad load =
      physics::load_soil_region_map(path, meters_per_pixel, center.head<2>(), soil->regions.size());
  if (!load.map) {
    file_value->error(load.error);
    return;
  }
  soil->map = load.map;
}

// --- scenario ------------------------------------------------------------------------------------------

class ScenarioLoader {
 public:
  LoadResult load(const std::string& path, const LoadOptions& options);

 private:
  void read_world(const Value& value, WorldSpec* world);
  void read_vehicle(const Value& value, VehicleSpec* vehicle);
  // The definition in `include` (a path relative to the including file), loaded once per resolved path.
  // nullopt when the file cannot be opened (reported at `include`) or does not parse.
  const std::optional<VehicleDefinition>& included_definition(const Value& include, const std::string& path);
  void read_schedule(const Value& value, const VehicleDefinition* definition,
                     std::vector<SetpointKeyframe>* schedule);

  DiagnosticSink sink_;
  std::optional<double> physics_rate_hz_;  // nullopt when world.physics_rate_hz is invalid
  struct IncludedFile {
    std::string open_error;                       // set when the file cannot be opened
    std::optional<VehicleDefinition> definition;  // nullopt when it cannot be opened or parsed
  };
  std::map<std::string, IncludedFile> includes_;      // by resolved path
  std::shared_ptr<const std::vector<std::filesystem::path>> roots_;  // where the files named may lie
  std::map<std::string, std::string> vehicle_names_;  // name -> path of the entry that used it first
};

LoadResult ScenarioLoader::load(const std::string& path, const LoadOptions& options) {
  Model model;
  model.scenario_file = path;
  std::vector<std::filesystem::path> roots;
  for (const AssetRoot& root : asset_roots(path, options)) {
    if (root.error.empty()) {
      roots.push_back(root.path);
    } else {
      sink_.report(path, YAML::Mark::null_mark(), "", "asset root " + quoted(root.path) + " (" + root.origin +
                                                          ") " + root.error);
    }
  }
  roots_ = std::make_shared<const std::vector<std::filesystem::path>>(std::move(roots));
  std::string open_error;
  const std::optional<YAML::Node> root = parse_yaml_file(path, &sink_, &open_error);
  if (!root && !open_error.empty()) {
    sink_.report(path, YAML::Mark::null_mark(), "", "cannot open scenario file (" + open_error + ")");
  }
  if (root) {
    const auto source = std::make_shared<const Source>(Source{path, &sink_, roots_});
    const MapReader map(Value::root(*root, source), {"world", "vehicles", "security"});
    if (const auto world = map.required("world")) read_world(*world, &model.world);
    if (const auto security = map.optional("security")) {
      if (auto files = read_security_block(*security)) model.security = std::move(*files);
    }
    if (const auto vehicles = map.required("vehicles")) {
      if (const auto items = vehicles->list()) {
        if (items->empty()) vehicles->error("must not be empty");
        for (std::size_t i = 0; i < items->size(); ++i) {
          VehicleSpec vehicle;
          read_vehicle((*items)[i], &vehicle);
          model.vehicles.push_back(std::move(vehicle));
        }
      }
    }
  }

  LoadResult result;
  for (Diagnostic& diagnostic : sink_.sorted()) {
    (diagnostic.warning ? result.warnings : result.errors).push_back(std::move(diagnostic));
  }
  if (result.errors.empty()) result.model = std::move(model);
  return result;
}

void ScenarioLoader::read_world(const Value& value, WorldSpec* world) {
  const MapReader map(value, {"physics_rate_hz", "gravity", "seed", "frame_id", "clock_rate_hz",
                              "status_rate_hz", "water", "seabed", "origin", "raycast_threads", "threads", "dynamics",
                              "date", "magnetic_dipoles", "optics", "acoustics", "soil"});
  if (!map.ok()) return;
  if (map.read_number("physics_rate_hz", Need::kOptional, Range::closed(50.0, 100000.0),
                      &world->physics_rate_hz)) {
    physics_rate_hz_ = world->physics_rate_hz;
  }
  map.read_vector3("gravity", Need::kOptional, Range::finite(), &world->gravity_W);
  if (const auto seed = map.optional("seed")) {
    if (const auto value = seed->non_negative_integer()) world->seed = *value;
  }
  map.read_string("frame_id", Need::kOptional, &world->frame_id);
  // The clock cannot tick faster than physics: the default follows a slower physics rate.
  world->clock_rate_hz = std::min(world->clock_rate_hz, world->physics_rate_hz);
  read_rate(map, "clock_rate_hz", physics_rate_hz_, &world->clock_rate_hz);
  read_rate(map, "status_rate_hz", physics_rate_hz_, &world->status_rate_hz);
  map.read_whole_number("raycast_threads", Need::kOptional, Range::closed(0.0, 256.0), &world->raycast_threads);
  map.read_whole_number("threads", Need::kOptional, Range::closed(0.0, 256.0), &world->threads);

  if (const auto water_value = map.optional("water")) read_water(*water_value, &world->water);
  read_optics(map.optional("optics"), world->water.surface_z, &world->optics);
  if (const auto acoustics = map.optional("acoustics")) read_acoustics(*acoustics, &world->acoustics);
  world->optics.marine_snow.seed = world->seed;
  world->optics.seabed_pattern.seed = world->seed;
  if (const auto seabed_value = map.optional("seabed")) read_seabed(*seabed_value, world->seed, &world->seabed);
  read_soil(map.optional("soil"), &world->soil);
  if (const auto date = map.optional("date")) {
    // "YYYY-MM-DD" within the geomagnetic model's validity (WMM2025: 2025-01-01 .. 2029-12-31).
    if (const auto text = date->string()) {
      int year = 0, month = 0, day = 0;
      char extra = 0;
      const bool parsed = std::sscanf(text->c_str(), "%4d-%2d-%2d%c", &year, &month, &day, &extra) == 3 &&
                          text->size() == 10 && month >= 1 && month <= 12 && day >= 1 &&
                          day <= (month == 2 ? (year % 4 == 0 && (year % 100 != 0 || year % 400 == 0) ? 29 : 28)
                                             : (month == 4 || month == 6 || month == 9 || month == 11) ? 30 : 31);
      if (!parsed) {
        date->error("expected a date YYYY-MM-DD (got " + date->describe() + ")");
      } else if (year < 2025 || year > 2029) {
        date->error("must be within 2025-01-01 .. 2029-12-31, the World Magnetic Model 2025's validity (got " +
                    *text + ")");
      } else {
        world->start_decimal_year = sensors::decimal_year_from_date(year, month, day);
      }
    }
  }
  if (const auto dipoles = map.optional("magnetic_dipoles")) {
    world->magnetic_dipoles_W = sensors::read_dipoles(*dipoles);
  }
  if (const auto dynamics_value = map.optional("dynamics")) {
    const MapReader dynamics(*dynamics_value, {"gyroscopic", "earth_rotation"});
    if (dynamics.ok()) {
      dynamics.read_bool("gyroscopic", Need::kOptional, &world->dynamics.gyroscopic);
      dynamics.read_bool("earth_rotation", Need::kOptional, &world->dynamics.earth_rotation);
    }
  }
  if (const auto origin_value = map.optional("origin")) {
    const MapReader origin(*origin_value, {"latitude_deg", "longitude_deg", "altitude"});
    if (origin.ok()) {
      double latitude_deg = 0.0, longitude_deg = 0.0;
      if (origin.read_number("latitude_deg", Need::kOptional, Range::closed(-90.0, 90.0), &latitude_deg)) {
        world->origin.latitude_rad = latitude_deg * kDegToRad;
      }
      if (origin.read_number("longitude_deg", Need::kOptional, Range::closed(-180.0, 180.0),
                             &longitude_deg)) {
        world->origin.longitude_rad = longitude_deg * kDegToRad;
      }
      origin.read_number("altitude", Need::kOptional, Range::finite(), &world->origin.height_m);
    }
  }
}

void ScenarioLoader::read_vehicle(const Value& value, VehicleSpec* vehicle) {
  const MapReader map(value, vehicle_entry_keys());
  if (!map.ok()) return;

  if (const auto name = map.required("name")) {
    if (const auto text = name->string()) {
      vehicle->name = *text;
      if (!is_valid_vehicle_name(*text)) {
        name->error("must match [A-Za-z][A-Za-z0-9_]* (got " + quoted(*text) + ")");
      } else {
        check_unique(*name, *text, "vehicle", value.path(), &vehicle_names_);
      }
    }
  }

  // The definition: either `include` (which the entry may extend with more `sensors` and `lights`) or
  // inline keys, never both.
  std::vector<std::string> inline_keys;
  for (const std::string& key : definition_keys()) {
    if (map.has(key) && key != "sensors" && key != "lights") inline_keys.push_back(quoted(key));
  }
  std::optional<VehicleDefinition> inline_definition;
  const VehicleDefinition* definition = nullptr;
  if (const auto include = map.optional("include")) {
    if (!inline_keys.empty()) {
      map.error_at_key("include", "cannot be combined with an inline definition (found " + join_names(inline_keys) +
                                      "; an entry with 'include' may only add 'sensors' and 'lights')");
    } else if (const auto include_path = include->string()) {
      const auto& included = included_definition(*include, *include_path);
      if (included && (map.has("sensors") || map.has("lights"))) {
        inline_definition = *included;  // extended by the entry's own lists
        read_sensors_and_lights(map, physics_rate_hz_, &*inline_definition);
        definition = &*inline_definition;
      } else if (included) {
        definition = &*included;
      }
    }
  } else if (!inline_keys.empty() || map.has("sensors") || map.has("lights")) {
    inline_definition = read_definition(map, physics_rate_hz_);
    definition = &*inline_definition;
  } else {
    value.error("needs either 'include' or an inline definition ('type', 'links', ...)");
  }
  if (definition) {
    vehicle->source_file = definition->source_file;
    vehicle->type = definition->type;
    vehicle->seabed_contact = definition->seabed_contact;
    vehicle->links = definition->links;
    vehicle->actuators = definition->actuators;
    vehicle->sensors = definition->sensors;
    vehicle->lights = definition->lights;
    vehicle->fluid = definition->fluid;
    for (SensorSpec& sensor : vehicle->sensors) {
      if (sensor.frame_id.empty()) sensor.frame_id = vehicle->name + "/" + sensor.name;
    }
  }

  if (const auto pose = map.optional("initial_pose")) read_pose(*pose, &vehicle->X_WB_initial);
  map.read_vector3("initial_velocity", Need::kOptional, Range::finite(), &vehicle->v_WB_initial);
  map.read_vector3("initial_angular_velocity", Need::kOptional, Range::closed(-100.0, 100.0), &vehicle->w_WB_initial);
  map.read_number("command_timeout_s", Need::kOptional, Range::positive(), &vehicle->command_timeout);
  read_rate(map, "odometry_rate_hz", physics_rate_hz_, &vehicle->odometry_rate_hz);
  read_rate(map, "thruster_state_rate_hz", physics_rate_hz_, &vehicle->thruster_state_rate_hz);
  if (const auto schedule = map.optional("schedule")) {
    read_schedule(*schedule, definition, &vehicle->schedule);
  }
}

const std::optional<VehicleDefinition>& ScenarioLoader::included_definition(const Value& include,
                                                                            const std::string& path) {
  static const std::optional<VehicleDefinition> kRefused;
  std::string resolved;
  if (!include.file_path(path, &resolved)) return kRefused;
  auto [it, first_use] = includes_.try_emplace(resolved);
  IncludedFile& included = it->second;
  if (first_use) {
    const std::optional<YAML::Node> root = parse_yaml_file(resolved, &sink_, &included.open_error);
    if (root) {
      const auto source = std::make_shared<const Source>(Source{resolved, &sink_, roots_});
      const MapReader map(Value::root(*root, source), definition_keys());
      if (map.ok()) included.definition = read_definition(map, physics_rate_hz_);
    }
  }
  // Errors inside the file are reported once; a file that cannot be opened at every include naming it.
  if (!included.open_error.empty()) {
    include.error("cannot open " + config::quoted(resolved) + " (" + included.open_error + ")");
  }
  return included.definition;
}

void ScenarioLoader::read_schedule(const Value& value, const VehicleDefinition* definition,
                                   std::vector<SetpointKeyframe>* schedule) {
  const auto items = value.list();
  if (!items) return;
  std::optional<double> previous_time;
  for (const Value& item : *items) {
    const MapReader map(item, {"time_s", "setpoints"});
    if (!map.ok()) continue;
    SetpointKeyframe keyframe;
    if (const auto time = map.required("time_s")) {
      const auto t = time->number(Range::non_negative());
      if (t && previous_time && *t <= *previous_time) {
        time->error("must be greater than the previous time_s (" + format_number(*previous_time) + ") (got " +
                    time->node().Scalar() + ")");
      }
      if (t) {
        keyframe.time = *t;
        previous_time = t;  // compare the next entry with this one, so one misplaced entry is one error
      }
    }
    if (const auto setpoints = map.required("setpoints")) {
      if (const auto values = setpoints->numbers(std::nullopt, Range::closed(-1.0, 1.0))) {
        keyframe.setpoints = *values;
      }
      // Cross-file check: the count comes from the (possibly included) vehicle definition.
      const std::size_t count = setpoints->node().size();
      if (setpoints->node().IsSequence() && definition && definition->control_count &&
          count != *definition->control_count) {
        const std::string names =
            definition->control_names ? " (" + join_names(*definition->control_names) + ")" : "";
        setpoints->error("expected " + std::to_string(*definition->control_count) +
                         " setpoints, one per actuator" + names + " (got " + std::to_string(count) + ")");
      } else if (!keyframe.setpoints.empty() && definition && definition->control_count &&
                 keyframe.setpoints.size() == *definition->control_count) {
        // Each actuator's own check (a drop weight's 0 or 1), as for a command at run time.
        std::size_t failed = 0;
        const std::string reason = physics::check_actuator_controls(definition->actuators, keyframe.setpoints, &failed);
        if (!reason.empty()) setpoints->error(reason + " (" + definition->actuators[failed].name + ")");
      }
    }
    schedule->push_back(std::move(keyframe));
  }
}

}  // namespace

std::vector<AssetRoot> asset_roots(const std::string& scenario_path, const LoadOptions& options) {
  namespace fs = std::filesystem;
  std::vector<AssetRoot> roots;
  // A configured root that is not a directory is an error; a default one that is not is left out.
  auto add = [&](const fs::path& dir, const std::string& origin, bool configured) {
    AssetRoot root{dir.string(), origin, ""};
    std::error_code ec;
    const fs::path real = fs::canonical(fs::absolute(dir, ec), ec);
    if (ec || !fs::is_directory(real, ec)) {
      if (!configured) return;
      root.error = "is not a directory";
    } else {
      root.path = real.string();
    }
    roots.push_back(std::move(root));
  };
  // The scenario's tree: its directory, or, in the layout of configs/ (scenarios/, vehicles/, meshes/ side by
  // side), the directory holding scenarios/.
  std::error_code ec;
  fs::path tree = fs::weakly_canonical(fs::absolute(scenario_path, ec), ec).parent_path();
  if (tree.filename() == "scenarios") tree = tree.parent_path();
  add(tree, "the scenario's tree", false);
  // hadal's own configs: installed (or $HADAL_DATA_DIR's), else the source tree's.
  const std::optional<DataDir> data = installed_data_dir();
  if (data && (data->from_environment || fs::is_directory(data->path / "configs", ec))) {
    add(data->path / "configs", data->from_environment ? "hadal's configs, $HADAL_DATA_DIR/configs" : "hadal's configs",
        false);
  } else {
    add(fs::path(HADAL_SOURCE_CONFIGS_DIR), "hadal's configs", false);
  }
  for (const std::string& dir : options.asset_roots) add(dir, "--asset-root", true);
  if (const char* list = std::getenv("HADAL_ASSET_ROOTS"); list != nullptr) {
    std::string text = list;
    for (std::size_t start = 0; start <= text.size();) {
      const std::size_t end = std::min(text.find(':', start), text.size());
      if (end > start) add(text.substr(start, end - start), "$HADAL_ASSET_ROOTS", true);
      start = end + 1;
    }
  }
  return roots;
}

LoadResult load_scenario_file(const std::string& path, const LoadOptions& options) {
  ScenarioLoader loader;
  return loader.load(path, options);
}

}  // namespace hadal::config
