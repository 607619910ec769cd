// The ray-cast scene of a scenario: the seabed as static geometry and every link mesh as geometry of
// its vehicle's body (body index = vehicle index), for the sensors that cast rays (DVL beams,
// altimeters, cameras).
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
