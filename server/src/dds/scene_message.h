// rt/hadal/scene (hadal_msgs/msg/Scene, idl/hadal_msgs.idl): what the world looks like, for viewers.
//
// The seabed's mesh in W: a plane is a square of side kPlaneSide around the vehicles' start (two
// triangles); a mesh of at most kMaxSeabedTriangles goes as it is; a larger one is resampled as a height
// field of at most kSeabedGrid x kSeabedGrid cells over its xy extent (its top surface, as the physics'
// geometry::SeabedHeight sees it; overhangs are lost, cells with no seabed left out). Each vehicle's
// mesh in B is what cameras see (geometry::vehicle_visual_B); an articulated vehicle's moving bodies add
// a mesh each in their frame K ("<vehicle>/<link>", geometry::links_visual_A) and a SceneLink with the
// kinematics to pose it from rt/<vehicle>/joint_states. Frames: every sensor's X_BS and every
// light's X_BF, with the reach a viewer draws (beams: the sensor's range limit; a camera: its far plane;
// a light: kLightReach) and a cone half angle (a light's outer one, a camera's horizontal). With waves, the sea
// state's components and build-up time, from which a viewer draws the moving surface at any sim time.
// Units: m, rad.
#pragma once

#include "hadal/core/model.h"

#include <hadal_msgs.h>

namespace hadal::dds {

inline constexpr double kPlaneSide = 400.0;             // [m]
inline constexpr std::size_t kMaxSeabedTriangles = 131072;
inline constexpr int kSeabedGrid = 256;                 // cells along the longer side
inline constexpr double kLightReach = 8.0;              // [m]

void fill_scene(const Model& model, double time_s, hadal_msgs::msg::Scene& msg);

}  // namespace hadal::dds
