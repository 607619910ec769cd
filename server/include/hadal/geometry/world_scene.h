// The ray-cast scene of a scenario: the seabed as static geometry and every vehicle's surface as the
// geometry of its bodies, for the sensors that cast rays (DVL beams, altimeters, cameras, sonars). A
// vehicle's surface is geometry::vehicle_visual_B: its links' visual meshes, else their meshes, else their
// tessellated collision primitives; vehicles without any are invisible to rays. A sensor's rays start
// inside or on its own hull: they ignore the body it is mounted on (RayBatch::ignore_body), and meet the
// vehicle's other bodies (a camera on an ROV's frame sees its arm; one on the wrist sees the fingers).
//
// Ray bodies (EmbreeScene's body indices, RayBodies below): body v < V (the number of vehicles) is vehicle
// v's base body, its links rigidly on B; after them come the articulated vehicles' moving bodies, vehicle
// by vehicle, in physics::Articulation's order (link_bodies). Every ray body's mesh is given in B with the
// joints at q = 0 (each link at its LinkSpec::X_BL), and its pose is "B as the body carries it": X_WB for
// a base body, X_WK X_BK0^-1 for a moving body K (X_BK0: K in B at q = 0). So a link L on ray body b is at
// X_W(b) X_BL whatever the joints, and whatever looks a link up by its X_BL (a checkerboard's frame, a
// light's) works on every body alike. The poses are the simulation's (Simulation::ray_body_poses).
//
// A plane seabed becomes a 200 km x 200 km square centred on W's origin (Embree has no infinite
// planes); beyond ~100 km from the origin float vertices would lose centimetres anyway. Materials:
// kSeabedMaterial for the seabed, kVehicleMaterial for hulls.
#pragma once

#include <vector>

#include "hadal/core/model.h"
#include "hadal/geometry/embree_scene.h"

namespace hadal::geometry {

inline constexpr std::uint32_t kSeabedMaterial = 0;
inline constexpr std::uint32_t kVehicleMaterial = 1;

// Which vehicle and which of its bodies each ray body is (see above).
class RayBodies {
 public:
  explicit RayBodies(const Model& model);
  // The number of ray bodies: one per vehicle, plus the moving bodies.
  int count() const { return static_cast<int>(vehicle_.size()); }
  // The vehicle ray body b belongs to.
  int vehicle(int b) const { return vehicle_.at(static_cast<std::size_t>(b)); }
  // The ray body of a vehicle's body (Articulation's numbering: 0 the base body, = the vehicle's index).
  int of_body(int vehicle, int body) const {
    return body == 0 ? vehicle : first_moving_.at(static_cast<std::size_t>(vehicle)) + body - 1;
  }
  // The ray body a vehicle's link is on.
  int of_link(int vehicle, int link) const {
    return of_body(vehicle, link_body_.at(static_cast<std::size_t>(vehicle)).at(static_cast<std::size_t>(link)));
  }
  // Whether a vehicle's link moves relative to B (it is on a moving body).
  bool link_moves(int vehicle, int link) const { return of_link(vehicle, link) != vehicle; }

 private:
  std::vector<int> vehicle_;                 // per ray body
  std::vector<int> first_moving_;            // per vehicle: the ray body of its body 1
  std::vector<std::vector<int>> link_body_;  // per vehicle, per link: its body (link_bodies)
};

// Adds the model's geometry to a new scene (not yet built). Throws std::invalid_argument (from
// EmbreeScene) if a mesh is unusable.
EmbreeScene build_world_scene(const Model& model, const std::string& device_config = "");

}  // namespace hadal::geometry
