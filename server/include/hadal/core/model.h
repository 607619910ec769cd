// Model: everything loaded from a scenario. Immutable after load (docs/ARCHITECTURE.md, "Model and state").
// The aggregate of the subsystems' specs, each in a header of its own with its keys (core/world_spec.h,
// core/vehicle_spec.h and what they include; config/key_table.h says how keys are declared).
//
// Frames (docs/ARCHITECTURE.md, "Model and state"): W world, ENU, z up, water surface at z = water.surface_z; B vehicle body frame
// (x forward, y left, z up), the frame odometry reports; L link frame; G collision-geometry frame;
// T thruster. Poses are X_AB (pose of B in A), positions p_AB, rotations R_AB.
// Units: SI everywhere (m, kg, s, rad, N). Degrees exist only in YAML keys ending in `_deg` and are
// converted on load.
#pragma once

#include <string>
#include <vector>

#include "hadal/core/security_files.h"
#include "hadal/core/vehicle_spec.h"
#include "hadal/core/world_spec.h"
#include "hadal/physics/cable.h"

namespace hadal {

struct Model {
  std::string scenario_file;
  WorldSpec world;
  std::vector<VehicleSpec> vehicles;
  std::vector<physics::CableModel> cables;  // `cables:` (physics/cable.h), their ends resolved to vehicles and links
  // DDS Security of hadald's participant: the scenario's `security:` block or hadald --security FILE
  // (config/security_block.h); all empty: off.
  SecurityFiles security;

  // Index of the vehicle with this name, or -1.
  int vehicle_index(const std::string& name) const;
  // Index of the cable with this name, or -1.
  int cable_index(const std::string& name) const;
};

}  // namespace hadal
