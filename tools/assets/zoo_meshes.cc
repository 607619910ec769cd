#include "hadal/assets/zoo_meshes.h"

#include <cmath>
#include <stdexcept>

namespace hadal::assets {

namespace {

// Rotations (row-major) taking a generator's z axis (cylinders) to x and to y.
constexpr double kZtoX[9] = {0, 0, 1, 0, 1, 0, -1, 0, 0};
constexpr double kZtoY[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0};
constexpr double kIdentity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

class Builder {
 public:
  // A material by base colour (linear RGB).
  unsigned material(const std::string& name, float r, float g, float b) {
    SceneMaterial m;
    m.name = name;
    m.base_color = {r, g, b, 1.0f};
    spec_.materials.push_back(m);
    return static_cast<unsigned>(spec_.materials.size() - 1);
  }
  void add(MeshData mesh, unsigned material, const double R[9] = kIdentity, double x = 0, double y = 0, double z = 0) {
    const double t[3] = {x, y, z};
    transform_mesh(mesh, R, t);
    spec_.meshes.push_back(std::move(mesh));
    spec_.mesh_materials.push_back(material);
    spec_.root.meshes.push_back(static_cast<unsigned>(spec_.meshes.size() - 1));
  }
  void box(double sx, double sy, double sz, double x, double y, double z, unsigned material) {
    add(make_box(sx, sy, sz, x, y, z), material);
  }
  // A cylinder of radius r and length l along `axis` ('x', 'y' or 'z'), centred at (x, y, z).
  void cylinder(double r, double l, char axis, double x, double y, double z, unsigned material) {
    add(make_cylinder(r, l, 24), material, axis == 'x' ? kZtoX : axis == 'y' ? kZtoY : kIdentity, x, y, z);
  }
  SceneSpec done() {
    spec_.root.name = "root";
    return std::move(spec_);
  }

 private:
  SceneSpec spec_;
};

// Survey AUV (configs/vehicles/finned_auv.yaml): torpedo hull, four tail fins, propeller, DVL.
SceneSpec finned_auv() {
  Builder b;
  const unsigned hull = b.material("hull_yellow", 0.85f, 0.65f, 0.08f);
  const unsigned dark = b.material("fins_dark", 0.12f, 0.12f, 0.13f);
  b.add(make_torpedo(1.6, 0.0775, 32, 12), hull);
  for (const double s : {1.0, -1.0}) {
    b.box(0.15, 0.005, 0.16, -0.62, 0.0, s * 0.125, dark);  // rudders
    b.box(0.15, 0.16, 0.005, -0.62, s * 0.125, 0.0, dark);  // elevators
  }
  b.cylinder(0.06, 0.015, 'x', -0.815, 0.0, 0.0, dark);     // propeller disc
  b.cylinder(0.035, 0.02, 'z', 0.2, 0.0, -0.07, dark);      // DVL transducer head
  return b.done();
}

// Glider (configs/vehicles/underwater_glider.yaml): hull, straight wings, vertical tail, antenna.
SceneSpec underwater_glider() {
  Builder b;
  const unsigned hull = b.material("hull_yellow", 0.9f, 0.75f, 0.1f);
  const unsigned wing = b.material("wings_grey", 0.35f, 0.35f, 0.38f);
  const unsigned dark = b.material("antenna_black", 0.05f, 0.05f, 0.05f);
  b.add(make_torpedo(1.5, 0.11, 32, 12), hull);
  b.box(0.18, 0.5, 0.006, -0.1, 0.36, 0.0, wing);
  b.box(0.18, 0.5, 0.006, -0.1, -0.36, 0.0, wing);
  b.box(0.12, 0.004, 0.24, -0.62, 0.0, 0.14, wing);
  b.cylinder(0.008, 0.3, 'z', -0.64, 0.0, 0.4, dark);
  return b.done();
}

// Lander (configs/vehicles/freefall_lander.yaml): float, housing, base, legs and pads, weights.
SceneSpec freefall_lander() {
  Builder b;
  const unsigned foam = b.material("syntactic_foam", 0.9f, 0.45f, 0.08f);
  const unsigned frame = b.material("frame_grey", 0.5f, 0.5f, 0.52f);
  const unsigned steel = b.material("weights_steel", 0.2f, 0.2f, 0.22f);
  b.box(1.2, 1.2, 0.5, 0.0, 0.0, 0.25, foam);
  b.cylinder(0.12, 0.6, 'x', 0.0, 0.0, -0.12, frame);
  b.box(1.3, 1.3, 0.05, 0.0, 0.0, -0.265, frame);
  for (const double sx : {1.0, -1.0}) {
    for (const double sy : {1.0, -1.0}) {
      b.box(0.08, 0.08, 0.6, sx * 0.6, sy * 0.6, -0.59, frame);
      b.box(0.2, 0.2, 0.02, sx * 0.6, sy * 0.6, -0.88, frame);  // foot pad
    }
  }
  b.cylinder(0.1, 0.16, 'z', 0.0, 0.15, -0.37, steel);   // descent weight
  b.cylinder(0.1, 0.16, 'z', 0.0, -0.15, -0.37, steel);  // ascent weight
  return b.done();
}

// ROV (configs/vehicles/vectored_rov.yaml): open frame, foam block, eight thrusters, camera dome.
SceneSpec vectored_rov() {
  Builder b;
  const unsigned frame = b.material("frame_silver", 0.6f, 0.6f, 0.62f);
  const unsigned foam = b.material("foam_yellow", 0.9f, 0.7f, 0.05f);
  const unsigned black = b.material("thrusters_black", 0.06f, 0.06f, 0.06f);
  b.add(make_grid_solid(box_frame_solid(1.1, 0.8, 0.5, 0.04), "frame"), frame);
  b.box(1.0, 0.7, 0.16, 0.0, 0.0, 0.15, foam);
  // Horizontal thrusters along their directions (+-45 deg about z), vertical ones along z.
  for (const double sx : {1.0, -1.0}) {
    for (const double sy : {1.0, -1.0}) {
      const double yaw = (sx * sy > 0 ? -1.0 : 1.0) * 0.25 * 3.14159265358979323846;
      const double c = std::cos(yaw), s = std::sin(yaw);
      const double R[9] = {0, -s, c, 0, c, s, -1, 0, 0};  // Rz(yaw) * kZtoX
      b.add(make_cylinder(0.08, 0.12, 24), black, R, sx * 0.45, sy * 0.35, 0.0);
      b.cylinder(0.08, 0.12, 'z', sx * 0.35, sy * 0.3, 0.1, black);
    }
  }
  b.add(make_uv_sphere(0.09, 24, 12), black, kIdentity, 0.55, 0.0, -0.1);  // camera dome
  return b.done();
}

// Catamaran (configs/vehicles/catamaran_vessel.yaml): hulls, deck, thruster pods, mast and GPS dome.
SceneSpec catamaran_vessel() {
  Builder b;
  const unsigned white = b.material("hull_white", 0.85f, 0.85f, 0.85f);
  const unsigned grey = b.material("deck_grey", 0.3f, 0.3f, 0.32f);
  const unsigned red = b.material("antifouling_red", 0.6f, 0.1f, 0.08f);
  for (const double s : {1.0, -1.0}) {
    b.box(2.0, 0.3, 0.28, 0.0, s * 0.5, 0.06, white);  // topsides
    b.box(2.0, 0.3, 0.12, 0.0, s * 0.5, -0.14, red);   // below the waterline (draft 0.12 m)
    b.cylinder(0.05, 0.15, 'x', -1.0, s * 0.5, -0.16, grey);
  }
  b.box(1.2, 1.3, 0.05, 0.0, 0.0, 0.225, grey);
  b.cylinder(0.02, 0.75, 'z', 0.0, 0.0, 0.625, grey);
  b.add(make_uv_sphere(0.08, 24, 12), white, kIdentity, 0.0, 0.0, 1.0);
  return b.done();
}

// Crawler body (configs/vehicles/tracked_crawler.yaml, link hull = B): chassis, mast, lights.
SceneSpec tracked_crawler_hull() {
  Builder b;
  const unsigned body = b.material("chassis_orange", 0.85f, 0.35f, 0.05f);
  const unsigned grey = b.material("fittings_grey", 0.4f, 0.4f, 0.42f);
  b.box(1.6, 0.8, 0.5, 0.0, 0.0, 0.6, body);
  b.cylinder(0.03, 0.5, 'z', -0.5, 0.0, 1.1, grey);
  b.box(0.1, 0.5, 0.08, 0.8, 0.0, 0.75, grey);  // light bar
  return b.done();
}

// One crawler track (links track_port and track_starboard): a rubber belt around two sprockets.
SceneSpec tracked_crawler_track() {
  Builder b;
  const unsigned rubber = b.material("track_rubber", 0.08f, 0.08f, 0.08f);
  b.box(1.45, 0.3, 0.35, 0.0, 0.0, 0.0, rubber);
  b.cylinder(0.175, 0.3, 'y', 0.725, 0.0, 0.0, rubber);
  b.cylinder(0.175, 0.3, 'y', -0.725, 0.0, 0.0, rubber);
  return b.done();
}

// The hull of configs/vehicles/mesh_hull_auv.yaml (docs/own_vehicle.md), whose physics is this mesh: one
// closed torpedo, 1.8 m by 0.2 m, the geometry of `hadal-make-asset torpedo OUT --radius 0.1 --length 1.8
// --segments 48`, painted orange.
SceneSpec mesh_hull_auv() {
  Builder b;
  b.add(make_torpedo(1.8, 0.1, 48, 12), b.material("hull_orange", 0.9f, 0.45f, 0.1f));
  return b.done();
}

}  // namespace

const std::vector<std::string>& zoo_parts() {
  static const std::vector<std::string> parts = {"finned_auv",       "underwater_glider",    "freefall_lander",
                                                 "vectored_rov",     "catamaran_vessel",     "tracked_crawler_hull",
                                                 "tracked_crawler_track", "mesh_hull_auv"};
  return parts;
}

SceneSpec zoo_part_scene(const std::string& part) {
  if (part == "finned_auv") return finned_auv();
  if (part == "underwater_glider") return underwater_glider();
  if (part == "freefall_lander") return freefall_lander();
  if (part == "vectored_rov") return vectored_rov();
  if (part == "catamaran_vessel") return catamaran_vessel();
  if (part == "tracked_crawler_hull") return tracked_crawler_hull();
  if (part == "tracked_crawler_track") return tracked_crawler_track();
  if (part == "mesh_hull_auv") return mesh_hull_auv();
  throw std::invalid_argument("no zoo part '" + part + "'");
}

}  // namespace hadal::assets
