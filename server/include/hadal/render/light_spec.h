// An artificial light on a link as a scenario describes it (YAML: a vehicle definition's `lights`;
// docs/ARCHITECTURE.md, "Cameras"): a spot light (render/optics.h) whose beam points along x of its frame
// F, mounted at X_LF. Cameras of every vehicle see every light. The keys are declared once in
// render::light_keys() (server/src/render/light_spec.cc).
#pragma once

#include <Eigen/Geometry>

#include <string>

#include "hadal/config/key_table_fwd.h"
#include "hadal/core/units.h"

namespace hadal {

namespace config {
struct VehicleContext;
}

struct LightSpec {
  std::string name;    // unique within the vehicle
  int link_index = 0;  // index into VehicleSpec::links
  Eigen::Isometry3d X_LF = Eigen::Isometry3d::Identity();  // light frame in the link frame
  double inner_half_angle = 20.0 * kDegToRad;  // full intensity inside [rad]
  double outer_half_angle = 26.0 * kDegToRad;  // none beyond [rad]; a smooth edge between
  Eigen::Array3d intensity_W_per_sr = Eigen::Array3d::Constant(100.0);  // on the axis, per channel (R, G, B)
};

namespace render {
// The keys of one entry of `lights`.
const config::KeyTable<LightSpec, config::VehicleContext>& light_keys();
}  // namespace render

}  // namespace hadal
