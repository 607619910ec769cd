#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>

#include "hadal/config/key_table.h"
#include "hadal/core/world_spec.h"
#include "hadal/config/yaml_reader.h"
#include "hadal/sensors/geomagnetic.h"

namespace hadal::config {
namespace {


const KeyTable<DynamicsSpec>& dynamics_keys() {
  return declare_keys<DynamicsSpec>([](KeyTable<DynamicsSpec>& t) {
    t.describe("world.dynamics",
               "rigid-body inertial effects; Bullet integrates in W, so -m (w x v) and -(I w) x w are "
               "already in its equations");
    t.boolean("gyroscopic", &DynamicsSpec::gyroscopic)
        .doc("Bullet's rigid-body gyroscopic moment -(I w) x w (off: a torque-free body keeps w instead of its "
             "angular momentum)");
    t.boolean("earth_rotation", &DynamicsSpec::earth_rotation)
        .doc("Earth-rotation Coriolis force F = -2 m Omega x v at each centre of mass, Omega = 7.292115e-5 rad/s x "
             "(0, cos phi, sin phi) in ENU at origin.latitude_deg phi (hadal-validate-coriolis)");
  });
}

// "YYYY-MM-DD" within the geomagnetic model's validity (WMM2025: 2025-01-01 .. 2029-12-31).
bool read_date(const Value& date, WorldSpec& world, LoadContext&) {
  const std::optional<std::string> text = date.string();
  if (!text) return false;
  int year = 0, month = 0, day = 0;
  char extra = 0;
  const bool parsed = std::sscanf(text->c_str(), "%4d-%2d-%2d%c", &year, &month, &day, &extra) == 3 &&
                      text->size() == 10 && month >= 1 && month <= 12 && day >= 1 &&
                      day <= (month == 2 ? (year % 4 == 0 && (year % 100 != 0 || year % 400 == 0) ? 29 : 28)
                                         : (month == 4 || month == 6 || month == 9 || month == 11) ? 30 : 31);
  if (!parsed) {
    date.error("expected a date YYYY-MM-DD (got " + date.describe() + ")");
    return false;
  }
  if (year < 2025 || year > 2029) {
    date.error("must be within 2025-01-01 .. 2029-12-31, the World Magnetic Model 2025's validity (got " + *text + ")");
    return false;
  }
  world.start_decimal_year = sensors::decimal_year_from_date(year, month, day);
  return true;
}

WorldSpec default_world() {
  WorldSpec world;
  world.soil = physics::soil_keys().defaults();
  world.optics = render::optics_keys().defaults();
  return world;
}

// A plane seabed (or a procedural seabed's plain) deeper than any ocean is an error, one at or above the water
// surface a warning (the vehicles are on dry land): both are what z = +100 for "100 m down" gives (z is up in
// W). Said at world.seabed.z when given, else at world.water.surface_z, else at world.seabed.
void check_seabed_depth(const KeyReads& reads, const WorldSpec& world) {
  if (world.seabed.type != SeabedType::kPlane && world.seabed.type != SeabedType::kProcedural) return;
  const double depth = world.water.surface_z - world.seabed.z;
  if (depth > 0.0 && depth <= kDeepestOcean_m) return;
  // The value of world.<map>.<key> when the file gives it.
  const auto given = [&reads](const char* map, const char* key) -> std::optional<Value> {
    const std::optional<Value> parent = reads.map().optional(map);
    if (!parent || !parent->is_map() || !parent->node()[key]) return std::nullopt;
    const YAML::Node node = parent->node()[key];
    return parent->in_same_file(node, parent->path() + "." + key, node.Mark());
  };
  std::optional<Value> at = given("seabed", "z");
  if (!at) at = given("water", "surface_z");
  if (!at) at = reads.map().optional("seabed");
  if (!at) return;
  const std::string where = "the seabed at z = " + format_number(world.seabed.z) + " m and the water surface at z = " +
                            format_number(world.water.surface_z) + " m (world.water.surface_z; z is up in W)";
  if (depth > kDeepestOcean_m) {
    at->error(where + " put the seabed " + format_number(depth) + " m deep, deeper than any ocean (" +
              format_number(kDeepestOcean_m) + " m)");
  } else {
    at->warn(where + " put the seabed at or above the surface: the vehicles are on dry land (a seabed 100 m below "
             "the surface is z: " + format_number(world.water.surface_z - 100.0) + ")");
  }
}

}  // namespace

const KeyTable<WorldSpec, LoadContext>& world_keys() {
  return declare_keys<WorldSpec, LoadContext>(default_world(), [](KeyTable<WorldSpec, LoadContext>& t) {
    t.describe("world", "the world: physics rate, gravity, seed, water, seabed, soil, optics");
    // The rates below are bounded by the physics rate; an invalid one bounds nothing.
    t.before([](WorldSpec& world, LoadContext& context) {
      context.physics_rate_hz = world.physics_rate_hz;
      context.world_seed = world.seed;
    });
    t.number("physics_rate_hz", &WorldSpec::physics_rate_hz).unit("Hz").range(Range::closed(50.0, 100000.0))
        .on_read([](WorldSpec& world, LoadContext& context, bool ok) {
          context.physics_rate_hz = ok ? std::optional<double>(world.physics_rate_hz) : std::nullopt;
          // The clock cannot tick faster than physics: its default follows a slower physics rate.
          if (ok) world.clock_rate_hz = std::min(world.clock_rate_hz, world.physics_rate_hz);
        })
        .doc("the physics step rate; step size 1/rate");
    t.vector("gravity", &WorldSpec::gravity_W).unit("m/s²")
        .doc("in W. The water's hydrostatic pressure uses its magnitude g, or 9.80665 m/s² when it is zero (a "
             "weightless body under water still feels buoyancy)");
    t.unsigned_integer("seed", &WorldSpec::seed)
        .on_read([](WorldSpec& world, LoadContext& context, bool ok) {
          if (ok) context.world_seed = world.seed;
        })
        .doc("seeds every noise generator, the current, marine snow, the sediment pattern, a procedural seabed");
    t.string("frame_id", &WorldSpec::frame_id).doc("header.frame_id of world-frame messages");
    t.rate_hz("clock_rate_hz", &WorldSpec::clock_rate_hz).default_text("min(100, `physics_rate_hz`)")
        .doc("rate of rt/clock");
    t.rate_hz("status_rate_hz", &WorldSpec::status_rate_hz)
        .doc("rate of rt/hadal/status, in wall-clock time (a heartbeat, also while a lockstep server idles)");
    t.number("raycast_threads", &WorldSpec::raycast_threads).range(Range::closed(0.0, 256.0))
        .doc("worker threads that trace captured sensors and ray probes; 0: `threads`");
    t.choice("ray_kernels", &WorldSpec::ray_kernels,
             {{"native", geometry::RayKernels::kNative, "Embree's fastest kernels for this CPU"},
              {"portable", geometry::RayKernels::kPortable,
               "Embree's SSE4.2 kernels and every hit recomputed in double precision: the same bits on every "
               "x86-64 CPU of one libm kind, a camera frame ~40 % slower"}})
        .doc("which kernels trace rays (cameras, sonars, DVL, altimeters, probes). Ray-cast sensors give the same "
             "bits run after run either way; `native` ones can differ in their last bits between CPUs, `portable` "
             "ones do not (docs/ARCHITECTURE.md, \"One ray-cast world\"; tests/regression/README.md says on which "
             "CPUs that was checked)");
    t.number("threads", &WorldSpec::threads).range(Range::closed(0.0, 256.0))
        .doc("CPU threads the server computes on (stepping thread, fluid-force helpers, BVH builders, ray-cast "
             "workers); 0: one per CPU the process may run on; hadald --threads overrides it. Results do not "
             "depend on it");
    t.map("water", &WorldSpec::water, physics::water_keys()).doc("the water column");
    t.map("waves", &WorldSpec::waves, physics::wave_keys()).doc("the sea state; a flat surface by default");
    t.map("optics", &WorldSpec::optics, render::optics_keys()).doc("what cameras see");
    t.map("acoustics", &WorldSpec::acoustics, render::acoustics_keys())
        .doc("what sonars, acoustic positioning and modems hear");
    t.map("seabed", &WorldSpec::seabed, geometry::seabed_keys()).doc("the seabed; a plane at z = -100 m by default");
    t.map("soil", &WorldSpec::soil, physics::soil_keys())
        .doc("the seabed's soil under vehicles with seabed_contact: soil; the deep-sea ooze by default");
    t.custom("date", read_date, R"({"type": "string", "pattern": "^[0-9]{4}-[0-9]{2}-[0-9]{2}$"})", "string")
        .default_text("2026-01-01")
        .doc("calendar date at sim time 0, YYYY-MM-DD within 2025-01-01 .. 2029-12-31 (WMM2025's validity)");
    t.list("magnetic_dipoles", &WorldSpec::magnetic_dipoles_W, sensors::dipole_keys()).drop_invalid()
        .doc("static magnetic anomalies in W (wrecks, pipelines) that magnetometers see");
    t.map("dynamics", &WorldSpec::dynamics, dynamics_keys()).doc("rigid-body inertial effects");
    t.map("origin", &WorldSpec::origin, sensors::origin_keys()).doc("geodetic position of W's origin");
    t.check([](const KeyReads& reads, WorldSpec& world, LoadContext& context) {
      context.water_surface_z = world.water.surface_z;
      if (reads.ok("seabed") && reads.ok("water")) check_seabed_depth(reads, world);
      world.optics.daylight.surface_z_m = world.water.surface_z;
      world.optics.marine_snow.seed = world.seed;
      world.optics.seabed_pattern.seed = world.seed;
      return true;
    });
  });
}

}  // namespace hadal::config
