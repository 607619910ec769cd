// The vehicle zoo's visual models (configs/vehicles/*.yaml, link `visual`): each vehicle's look built
// from the generators in mesh_generators.h, in its link frame L (x forward, y left, z up, metres),
// with glTF base colours. `hadal-make-asset zoo DIR` writes them as DIR/<part>.glb; the committed copies
// in configs/meshes/ are checked against a fresh generation by the test suite (tools/assets/CMakeLists.txt).
// The physics of every zoo vehicle is its collision shapes; these meshes are only what ray casts see.
#pragma once

#include <string>
#include <vector>

#include "hadal/assets/scene_writer.h"

namespace hadal::assets {

// The parts, one GLB each: finned_auv, underwater_glider, freefall_lander, vectored_rov,
// catamaran_vessel, tracked_crawler_hull, tracked_crawler_track.
const std::vector<std::string>& zoo_parts();
// Throws std::invalid_argument for a name not in zoo_parts().
SceneSpec zoo_part_scene(const std::string& part);

}  // namespace hadal::assets
