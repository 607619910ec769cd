// Model: everything loaded from a scenario. Immutable after load (docs/ARCHITECTURE.md, "Model and state").
//
// Frames (docs/ARCHITECTURE.md, "Model and state"): W world, ENU, z up, water surface at z = water.surface_z; B vehicle body frame
// (x forward, y left, z up), the frame odometry reports; L link frame; G collision-geometry frame;
// T thruster. Poses are X_AB (pose of B in A), positions p_AB, rotations R_AB.
// Units: SI everywhere (m, kg, s, rad, N). Degrees exist only in YAML keys ending in `_deg` and are
// converted on load.
#pragma once

#include "hadal/core/security_files.h"
#include "hadal/core/units.h"
#include "hadal/geometry/mesh_import.h"
#include "hadal/geometry/terrain.h"
#include "hadal/geometry/triangle_mesh.h"
#include "hadal/physics/actuator_kinds.h"
#include "hadal/physics/surface_hydrodynamics.h"
#include "hadal/physics/terramechanics.h"
#include "hadal/render/marine_snow.h"
#include "hadal/render/sediment_pattern.h"
#include "hadal/render/optics.h"
#include "hadal/sensors/geodesy.h"
#include "hadal/sensors/magnetometer.h"
#include "hadal/sensors/sensor_kinds.h"

#include <Eigen/Geometry>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hadal {

using Vector6d = Eigen::Matrix<double, 6, 1>;

enum class VehicleType { kAuv, kRov, kLander, kSurfaceVessel, kGlider, kCrawler };

enum class CollisionShapeType { kBox, kSphere, kCylinder, kCapsule };

// A collision primitive attached to a link. Cylinders and capsules have their axis along G's z axis
// (as SDF/URDF); `length` is the length of the cylindrical part (a capsule's total length is
// length + 2 radius).
struct CollisionShape {
  CollisionShapeType type = CollisionShapeType::kBox;
  Eigen::Vector3d box_size = Eigen::Vector3d::Zero();  // full extents along G's x, y, z [m]
  double radius = 0.0;                                 // sphere, cylinder, capsule [m]
  double length = 0.0;                                 // cylinder, capsule [m]
  Eigen::Isometry3d X_LG = Eigen::Isometry3d::Identity();
};

// Lumped buoyancy of a link: the displaced volume of the fully submerged link and the centre of
// buoyancy (centroid of that volume).
struct BuoyancySpec {
  double volume = 0.0;                          // [m^3]
  Eigen::Vector3d p_LCb = Eigen::Vector3d::Zero();  // centre of buoyancy in L [m]
};

// The surface of a link from a mesh file (YAML link.mesh), with its vertices in L. Used for mass
// properties (with link.density), default buoyancy (closed meshes) and, later, ray casts and
// surface hydrodynamics.
struct LinkMesh {
  std::string file;  // resolved path
  geometry::ImportOptions import;
  Eigen::Isometry3d X_LM = Eigen::Isometry3d::Identity();  // pose of the file's frame in L
  std::shared_ptr<const geometry::TriangleMesh> mesh;      // vertices in L [m]
  bool closed = false;                                     // watertight and consistently oriented
  double volume = 0.0;                                     // enclosed volume (closed meshes) [m^3]
  Eigen::Vector3d p_LMc = Eigen::Vector3d::Zero();         // centroid of that volume in L [m]
};

// How cameras see a link's surface (render/frame.h): a uniform albedo, optionally painted with a
// checkerboard (a calibration target) in the x-y plane of a pattern frame P: squares of square_size
// along x_P (columns) and y_P (rows) from P's origin, square (0, 0) dark, then alternating; points
// outside the pattern keep `albedo` (the target's white border). The pattern is painted by (x_P, y_P)
// through the link's whole depth (a thin board shows it on both faces).
struct CheckerboardSpec {
  int columns = 0;           // squares along x_P
  int rows = 0;              // squares along y_P
  double square_size = 0.0;  // [m]
  Eigen::Isometry3d X_LP = Eigen::Isometry3d::Identity();
  Eigen::Array3d dark_albedo = Eigen::Array3d::Constant(0.03);
};
struct AppearanceSpec {
  std::optional<Eigen::Array3d> albedo;  // per channel (R, G, B); none: world.optics.vehicle_albedo
  // Lambert's backscatter parameter mu [dB] for sonars (render/sonar.h); none: world.acoustics.vehicle_backscatter_db
  std::optional<double> backscatter_db;
  std::optional<CheckerboardSpec> checkerboard;
};

struct LinkSpec {
  std::string name;
  double mass = 0.0;                                      // [kg], > 0
  Eigen::Matrix3d I_LLcm_L = Eigen::Matrix3d::Identity();  // L about its centre of mass Lcm, L axes [kg m^2]
  Eigen::Vector3d p_LLcm = Eigen::Vector3d::Zero();       // centre of mass in L [m]
  Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();  // link frame in the vehicle body frame
  std::vector<CollisionShape> collisions;
  BuoyancySpec buoyancy;
  std::optional<LinkMesh> mesh;
  // How the link looks to ray casts (cameras, DVL and altimeter beams, geometry/world_scene.h), in place
  // of its surface there (YAML link.visual): a detailed model over simple physics. The physics --
  // fluid forces, soil, Bullet -- keeps `mesh` or `collisions`.
  std::optional<LinkMesh> visual;
  AppearanceSpec appearance;

  // The mesh ray casts see: `visual`, else `mesh` (null: the collision shapes, or nothing).
  const LinkMesh* seen_mesh() const {
    if (visual && visual->mesh) return &*visual;
    return mesh && mesh->mesh ? &*mesh : nullptr;
  }
};

// An actuator (YAML: a list of the vehicle definition per kind, e.g. `thrusters`), mounted on a link. Its
// kind (physics/actuator_kinds.h) says what it is, what it takes from the vehicle's control vector and
// what force it adds (physics/actuator_kind.h).
struct ActuatorSpec {
  std::string name;    // unique within the vehicle
  int link_index = 0;  // index into VehicleSpec::links
  physics::ActuatorKindSpec kind;

  // The kind's name ("thruster", ...).
  std::string_view type() const;
  // Entries of the vehicle's control vector this actuator takes.
  std::size_t num_controls() const;
};

// The kind spec of an actuator as kind K's Spec (K must be the actuator's kind).
template <class K>
const typename K::Spec& spec_of(const ActuatorSpec& actuator) {
  return std::get<typename K::Spec>(actuator.kind);
}

enum class FluidModelType { kLumped, kSurface };

// kSurface (default): per-face forces on the links' hydrodynamic meshes
// (physics/surface_hydrodynamics.h) in the scenario's Ocean; buoyancy comes from pressure integration, so links' buoyancy volumes are not
// used. Coefficients in `hydrodynamics` (its `buoyancy` flag is always true from YAML).
// kLumped: Fossen-style lumped fluid model: buoyancy rho g V at the centre of buoyancy, and
// damping in the body frame, tau = -(D_l + D_q |nu|) nu with nu = [u v w p q r] relative to the water.
// Coefficients are magnitudes (>= 0): linear [N s/m x3, N m s/rad x3], quadratic [N s^2/m^2 x3,
// N m s^2/rad^2 x3].

// Added mass and inertia (physics/added_mass.h). The fluid accelerated with the body adds the 6x6
// matrix M_A to its inertia; at depth d it is scaled by kappa(d) = 1 - p(d)/K (paper; K from
// world.water.bulk_modulus), and its Coriolis-centripetal terms C_A(nu_r) nu_r (Fossen 2011, eq.
// 6.43; they contain the Munk moment) act with it.
//   kNone       no added mass.
//   kEllipsoid  Lamb's ellipsoid coefficients (rho0 V k-factors, rho0 from world.water) of
//               - the given semi-axes, ellipsoid frame E at X_BE (semi_axes_E set), or
//               - the hydrodynamic mesh's inertia-equivalent ellipsoid (same volume, same principal
//                 second moments, centred at the enclosed volume's centroid) otherwise.
//   kMatrix     a given 6x6 M_A0 [kg, kg m, kg m^2] at the surface, about the point p_BR, in B axes.
enum class AddedMassModel { kNone, kEllipsoid, kMatrix };

using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct AddedMassSpec {
  AddedMassModel model = AddedMassModel::kEllipsoid;
  std::optional<Eigen::Vector3d> semi_axes_E;              // [m]; empty: fit to the hull
  Eigen::Isometry3d X_BE = Eigen::Isometry3d::Identity();  // ellipsoid centre and axes in B
  Matrix6d M_A0 = Matrix6d::Zero();                        // kMatrix, symmetric positive semidefinite
  Eigen::Vector3d p_BR = Eigen::Vector3d::Zero();          // kMatrix reference point in B [m]
  bool coriolis = true;                                    // C_A(nu_r) nu_r on/off
};

struct FluidSpec {
  FluidModelType model = FluidModelType::kSurface;
  AddedMassSpec added_mass;
  Vector6d linear_damping = Vector6d::Zero();
  Vector6d quadratic_damping = Vector6d::Zero();
  physics::HydrodynamicCoefficients hydrodynamics;
};

// A sensor (YAML: the vehicle definition's `sensors` list). Each is mounted on a link at X_LS (sensor
// frame S), samples at rate_hz in sim time (sample n at the first physics step whose time reaches
// n / rate_hz: no drift for rates that do not divide the physics rate), computes the ideal value from
// the state, then applies its noise (its kind's module, sensors/<kind>_sensor.h), and is published on
// rt/<vehicle>/<name> with header.frame_id `frame_id` and the sample's sim time as stamp.
struct SensorSpec {
  std::string name;      // unique within the vehicle; topic rt/<vehicle>/<name>
  int link_index = 0;    // index into VehicleSpec::links
  Eigen::Isometry3d X_LS = Eigen::Isometry3d::Identity();  // mounting pose in the link frame
  double rate_hz = 10.0;
  std::string frame_id;  // header.frame_id; default "<vehicle>/<name>"
  double latency_s = 0.0;  // captured kinds (sensors/sensor_kind.h): from capture to delivery [s]
  sensors::SensorKindSpec kind;  // the kind (sensors/sensor_kinds.h) and its parameters

  // The kind's YAML type name ("pressure", "imu", ...).
  std::string_view type() const;
};

// The kind spec of a sensor as kind K's Spec (K must be the sensor's kind; std::bad_variant_access
// otherwise).
template <class K>
const typename K::Spec& spec_of(const SensorSpec& sensor) {
  return std::get<typename K::Spec>(sensor.kind);
}

// An artificial light on a link (docs/ARCHITECTURE.md, "Cameras"): a spot light (render/optics.h) whose
// beam points along x of its frame F, mounted at X_LF. Cameras of every vehicle see every light.
struct LightSpec {
  std::string name;    // unique within the vehicle
  int link_index = 0;  // index into VehicleSpec::links
  Eigen::Isometry3d X_LF = Eigen::Isometry3d::Identity();  // light frame in the link frame
  double inner_half_angle = 20.0 * kDegToRad;  // full intensity inside [rad]
  double outer_half_angle = 26.0 * kDegToRad;  // none beyond [rad]; a smooth edge between
  Eigen::Array3d intensity_W_per_sr = Eigen::Array3d::Constant(100.0);  // on the axis, per channel (R, G, B)
};

// Zero-order-hold keyframe of a scenario schedule: from time (sim time, s) on, the vehicle's actuators
// take this control vector (one normalised setpoint per thruster, in [-1, 1]).
struct SetpointKeyframe {
  double time = 0.0;  // [s]
  std::vector<double> setpoints;
};

// How a vehicle meets the seabed (YAML: the vehicle definition's `seabed_contact`).
//   kRigid  Bullet's rigid contact of its collision shapes with the seabed (friction 0.4, no bounce).
//   kSoil   the soil's Bekker pressure and Janosi-Hanamoto shear under every face of its surface
//           (physics/terramechanics.h, world.soil) instead; Bullet leaves it and the seabed apart.
enum class SeabedContact { kRigid, kSoil };

struct VehicleSpec {
  std::string name;                 // DDS topics are rt/<name>/...
  VehicleType type = VehicleType::kAuv;
  SeabedContact seabed_contact = SeabedContact::kRigid;
  std::string source_file;          // file the vehicle definition came from (scenario or include)
  std::vector<LinkSpec> links;      // links[0] is the base link; links are rigidly attached to B
  std::vector<ActuatorSpec> actuators;  // their controls form the vehicle's control vector, in order
  std::vector<SensorSpec> sensors;
  std::vector<LightSpec> lights;
  FluidSpec fluid;
  Eigen::Isometry3d X_WB_initial = Eigen::Isometry3d::Identity();
  Eigen::Vector3d v_WB_initial = Eigen::Vector3d::Zero();  // initial linear velocity in W [m/s]
  Eigen::Vector3d w_WB_initial = Eigen::Vector3d::Zero();  // initial angular velocity in W [rad/s]
  std::vector<SetpointKeyframe> schedule;   // used until a client first commands the vehicle
  double command_timeout = 1.0;             // watchdog [s of sim time]
  double odometry_rate_hz = 50.0;
  double thruster_state_rate_hz = 20.0;

  int link_index(const std::string& link_name) const;
  // Length of the control vector: the actuators' controls summed.
  std::size_t num_controls() const;
};

enum class SeabedType { kPlane, kMesh, kHeightmap, kProcedural };

// The seabed: an infinite plane, or a triangle-mesh surface built at load time from a mesh file, a
// heightmap image or seeded procedural bathymetry (hadal/geometry/terrain.h). YAML: world.seabed.
struct SeabedSpec {
  SeabedType type = SeabedType::kPlane;
  double z = -100.0;  // plane: its height in W; procedural: height of the sediment plain [m]
  // kMesh: the file (resolved relative to the scenario), its units and up axis, and the pose X_WM of
  // the file's frame in W.
  std::string file;
  geometry::ImportOptions import;
  Eigen::Isometry3d X_WM = Eigen::Isometry3d::Identity();
  geometry::HeightmapSpec heightmap;          // kHeightmap (file in heightmap.file)
  geometry::ProceduralSeabedSpec procedural;  // kProcedural (z_datum = z)
  // The surface in W for every type but kPlane, built by the loader; shared, never modified.
  std::shared_ptr<const geometry::TriangleMesh> mesh;
};

// The seabed's soil (YAML world.soil, physics/terramechanics.h): a preset of published parameters
// (physics/soil_presets.h) with any parameter overridden; the deep-sea ooze preset when not given. Used
// by vehicles with seabed_contact soil.
struct SoilSpec {
  std::string preset = "deep_sea_ooze";  // the preset the parameters started from ("" if none)
  physics::SoilParameters parameters;    // SI, filled by the loader
  // Soils by region (world.soil.regions and map): the map's region k >= 1 is regions[k - 1]; region 0
  // and everywhere off the map is `parameters`.
  struct Region {
    std::string preset;
    physics::SoilParameters parameters;
  };
  std::vector<Region> regions;
  std::shared_ptr<const physics::SoilRegionMap> map;  // null: `parameters` everywhere

  physics::SoilLayout layout() const {
    physics::SoilLayout layout{{parameters}, map};
    for (const Region& region : regions) layout.soils.push_back(region.parameters);
    return layout;
  }
};

// The water column (YAML `world.water`; see configs/REFERENCE.md and hadal/physics/ocean.h for the model).
enum class DensityModel { kConstant, kRamp, kCtd };

// One row of a CTD cast: temperature (ITS-90) and practical salinity at a depth below the surface.
struct CtdSample {
  double depth = 0.0;        // [m] below the surface
  double temperature = 4.0;  // [degC] (YAML: temperature_degc)
  double salinity = 35.0;    // practical salinity [PSS-78, dimensionless]
};

// Water current: uniform + exponentially decaying shear + a first-order Gauss-Markov term, all in W.
struct CurrentSpec {
  Eigen::Vector3d uniform_W = Eigen::Vector3d::Zero();        // [m/s]
  Eigen::Vector3d shear_surface_W = Eigen::Vector3d::Zero();  // shear at the surface [m/s]
  double shear_decay_depth = 50.0;                            // e-folding depth of the shear [m]
  Eigen::Vector3d gauss_markov_sigma_W = Eigen::Vector3d::Zero();  // stationary std per axis [m/s]
  double gauss_markov_time_constant = 600.0;                       // [s]
};

struct WaterSpec {
  double surface_z = 0.0;  // water surface height in W [m]
  // Constant-model density [kg/m^3]. The lumped fluid model uses this one value whatever density_model
  // is; the loader sets it to rho0 (ramp) or the EOS-80 surface density of the first CTD row (ctd).
  double density = 1025.0;
  DensityModel density_model = DensityModel::kConstant;
  // Ramp model rho(d) = rho0 + pycnocline_density_increase * min(d, pycnocline_depth) / pycnocline_depth.
  double rho0 = 1025.0;                          // [kg/m^3]
  double pycnocline_depth = 1000.0;              // [m]
  double pycnocline_density_increase = 3.075;    // [kg/m^3] (+0.3 % of 1025)
  std::vector<CtdSample> ctd;                    // CTD model: >= 2 rows, depths strictly increasing
  double temperature = 4.0;                      // non-CTD water [degC]
  double salinity = 35.0;                        // non-CTD water (practical salinity)
  double atmospheric_pressure = 101325.0;        // at the surface [Pa]
  double bulk_modulus = 2.2e9;                   // K in kappa(d) = 1 - p(d)/K [Pa]
  double ph = 8.0;                               // sound absorption's boric acid term (physics/seawater.h)
  CurrentSpec current;
};

// Rigid-body inertial effects (YAML world.dynamics). Bullet integrates in the inertial world frame,
// where the paper's body-frame terms -m (w x v) and -(I w) x w are implicit: translation needs
// nothing, and the gyroscopic moment -(I w) x w is Bullet's gyroscopic term (on by default, implicit
// integration). Earth rotation is not in Bullet: with it on, each vehicle gets F = -2 m Omega_W x v_WBcm
// at its centre of mass, Omega_W = Omega_E (0, cos(lat), sin(lat)) in ENU at world.origin's latitude
// (the centrifugal part is inside g).
struct DynamicsSpec {
  bool gyroscopic = true;        // Bullet's rigid-body gyroscopic moment
  bool earth_rotation = false;   // Earth-rotation Coriolis force
  double earth_rotation_rate = 7.2921150e-5;  // Omega_E [rad/s] (WGS84)
};

// What sonars hear (render/sonar.h, docs/ARCHITECTURE.md "Sonars"): Lambert's backscatter parameter mu
// [dB] of the world's surfaces, sigma = mu cos^2(incidence) per unit area and steradian. YAML
// world.acoustics. The seabed's default is Mackenzie's (1961) deep-sea value, -27 dB; hulls (metal, GRP) are
// strong scatterers, -10 dB; a link's appearance.backscatter_db overrides the hulls' value.
struct AcousticsSpec {
  double seabed_backscatter_db = -27.0;
  double vehicle_backscatter_db = -10.0;
};

// What cameras see (render/optics.h, docs/ARCHITECTURE.md "Cameras"): the water's absorption and
// scattering per channel, daylight from the surface, and the albedo of the world's surfaces. YAML
// world.optics; the loader fills the defaults (pure water plus a little scattering, Jerlov type I
// daylight at the water surface).
struct OpticsSpec {
  render::WaterOptics water;
  render::Daylight daylight;
  render::MarineSnow marine_snow;  // none by default; its seed is world.seed
  Eigen::Array3d seabed_albedo = Eigen::Array3d(0.30, 0.28, 0.22);   // sediment, per channel (R, G, B)
  render::SedimentPattern seabed_pattern;  // none by default (amplitude 0); its seed is world.seed
  Eigen::Array3d vehicle_albedo = Eigen::Array3d(0.85, 0.70, 0.15);  // hulls (survey-yellow)
};

struct WorldSpec {
  Eigen::Vector3d gravity_W = Eigen::Vector3d(0.0, 0.0, -9.80665);  // [m/s^2]
  // Calendar date at sim time 0 as a decimal year (YAML world.date: "YYYY-MM-DD"); the sim time adds
  // t / (365.25 d). Geomagnetic field and (later) celestial quantities use it.
  double start_decimal_year = 2026.0;  // 2026-01-01
  std::vector<sensors::MagneticDipole> magnetic_dipoles_W;  // static magnetic anomalies (wrecks, pipes)
  double physics_rate_hz = 500.0;
  std::uint64_t seed = 0;
  WaterSpec water;
  SeabedSpec seabed;
  SoilSpec soil;
  sensors::GeodeticPosition origin;  // of W's origin, WGS84 (YAML: latitude_deg, longitude_deg, altitude)
  DynamicsSpec dynamics;
  OpticsSpec optics;
  AcousticsSpec acoustics;
  std::string frame_id = "world";  // header.frame_id of world-frame messages
  double clock_rate_hz = 100.0;    // rt/clock
  double status_rate_hz = 10.0;    // rt/hadal/status
  int raycast_threads = 0;         // ray-cast worker threads; 0: `threads`
  // CPU threads the server computes on: the stepping thread and the fluid-force helpers (threads - 1),
  // Embree's BVH builders, and the ray-cast workers unless raycast_threads says otherwise; 0: one per CPU
  // the process may run on. 1 suits several servers sharing a machine (hadal.env.VectorEnv).
  int threads = 0;

  // threads, or when it is 0 the number of CPUs the process may run on (sched_getaffinity: hadald --cpus,
  // taskset, a container's cpuset), at least 1.
  int effective_threads() const;

  double step_size() const { return 1.0 / physics_rate_hz; }
};

struct Model {
  std::string scenario_file;
  WorldSpec world;
  std::vector<VehicleSpec> vehicles;
  // DDS Security of hadald's participant: the scenario's `security:` block or hadald --security FILE
  // (config/security_block.h); all empty: off.
  SecurityFiles security;

  // Index of the vehicle with this name, or -1.
  int vehicle_index(const std::string& name) const;
};

const char* to_string(VehicleType type);
std::optional<VehicleType> vehicle_type_from_string(const std::string& text);

}  // namespace hadal
