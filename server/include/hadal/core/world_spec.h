// The world a scenario describes (YAML `world`): the physics rate, gravity, the seed, threads, the
// calendar date and geodetic origin, and the subsystems each with a spec of its own (water, seabed, soil,
// optics, acoustics, dynamics, magnetic dipoles). Its keys are declared once in config::world_keys()
// (server/src/config/world_keys.cc); configs/REFERENCE.md shows them.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

#include "hadal/config/key_table_fwd.h"
#include "hadal/geometry/ray_kernels.h"
#include "hadal/geometry/seabed_spec.h"
#include "hadal/physics/soil_spec.h"
#include "hadal/physics/waves.h"
#include "hadal/physics/water_spec.h"
#include "hadal/render/acoustics_spec.h"
#include "hadal/render/optics_spec.h"
#include "hadal/sensors/geodetic_position.h"
#include "hadal/sensors/magnetic_dipole.h"

namespace hadal {

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

struct WorldSpec {
  Eigen::Vector3d gravity_W = Eigen::Vector3d(0.0, 0.0, -9.80665);  // [m/s^2]
  // Calendar date at sim time 0 as a decimal year (YAML world.date: "YYYY-MM-DD"); the sim time adds
  // t / (365.25 d). Geomagnetic field and (later) celestial quantities use it.
  double start_decimal_year = 2026.0;  // 2026-01-01
  std::vector<sensors::MagneticDipole> magnetic_dipoles_W;  // static magnetic anomalies (wrecks, pipes)
  double physics_rate_hz = 500.0;
  std::uint64_t seed = 0;
  WaterSpec water;
  physics::WaveSpec waves;  // world.waves: a flat surface by default
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
  geometry::RayKernels ray_kernels = geometry::RayKernels::kNative;  // which Embree kernels trace rays
  // CPU threads the server computes on: the stepping thread and the fluid-force helpers (threads - 1),
  // Embree's BVH builders, and the ray-cast workers unless raycast_threads says otherwise; 0: one per CPU
  // the process may run on. 1 suits several servers sharing a machine (hadal.env.VectorEnv).
  int threads = 0;

  // threads, or when it is 0 the number of CPUs the process may run on (sched_getaffinity: hadald --cpus,
  // taskset, a container's cpuset), at least 1.
  int effective_threads() const;

  double step_size() const { return 1.0 / physics_rate_hz; }
};

namespace config {
struct LoadContext;
// The keys of `world`. Its defaults (world_keys().defaults()) are those a scenario gets: the deep-sea
// ooze, clear water's optics; a default-constructed WorldSpec has neither.
const KeyTable<WorldSpec, LoadContext>& world_keys();
}  // namespace config

}  // namespace hadal
