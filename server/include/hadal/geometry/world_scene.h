// The ray-cast scene of a scenario: the seabed as static geometry and every vehicle's surface as the
// geometry of its body (body index = vehicle index), for the sensors that cast rays (DVL beams,
// altimeters, cameras). A vehicle's surface is geometry::vehicle_surface_B: its links' meshes, and the
// tessellated collision primitives of links without a mesh (one scene mesh per vehicle, named after
// it); vehicles without either are invisible to rays. A sensor's rays start inside or on its own hull:
// they ignore their own body (RayBatch::ignore_body).
//
// A plane seabed becomes a 200 km x 200 km square centred on W's origin (Embree has no infinite
// planes); beyond ~100 km from the origin float vertices would lose centimetres anyway. Materials:
// kSeabedMaterial for the seabed, kVehicleMaterial for hulls.
#pragma once

#include "hadal/core/model.h"
#include "hadal/geometry/embree_scene.h"

namespace hadal::geometry {

inline constexpr std::uint32_t kSeabedMaterial = 0;
inline constexpr std::uint32_t kVehicleMaterial = 1;

// Adds the model's geometry to a new scene (not yet built). Throws std::invalid_argument (from
// EmbreeScene) if a mesh is unusable.
EmbreeScene build_world_scene(const Model& model, const std::string& device_config = "");

}  // namespace hadal::geometry
