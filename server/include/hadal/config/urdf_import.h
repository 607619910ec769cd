// URDF import (YAML: a vehicle definition's `urdf`; docs/ARCHITECTURE.md, "URDF import"): the links,
// joints, inertials, collision shapes and meshes, visual meshes and colours of a URDF file, read with
// Debian's urdfdom, become the vehicle's LinkSpecs; the YAML adds what a URDF lacks (the fluid model,
// sensors, actuators, joint controllers).
//
// What each URDF element becomes:
//   <link>       a link of the same name; no <inertial>: a massless frame (it must ride on a body with mass)
//   <inertial>   mass, centre of mass (origin xyz) and inertia, turned from the inertial frame (origin rpy)
//                into L; checked like YAML's (positive definite, triangle inequality)
//   <collision>  box, cylinder (axis along z, as Hadal's), sphere: a collision shape at its origin; one mesh:
//                the link's surface (its `mesh`), with a uniform scale
//   <visual>     the first mesh: what ray casts see (the link's `visual`); the first material colour:
//                its albedo; primitives are not drawn (the collision shapes are seen instead)
//   <joint>      fixed, revolute, continuous, prismatic with origin (X_PL), axis, limits (lower, upper,
//                effort, velocity), dynamics (damping, friction). q starts at 0, or at the nearer limit
//                when 0 is outside them. floating and planar joints are refused; mimic is warned about
//                (the joint moves on its own)
// Mesh files: package://PKG/PATH is PATH in a directory named PKG above the URDF, else in an asset root
// (ROOT/PKG/PATH); file:///PATH as written; anything else relative to the URDF. Each must lie where the
// scenario's files may (docs/ARCHITECTURE.md, "Files a scenario may reach").
#pragma once

#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "hadal/config/key_table_fwd.h"
#include "hadal/geometry/link_spec.h"

namespace hadal::config {

class Value;
struct VehicleContext;

// A vehicle's `urdf` key.
struct UrdfMount {
  std::string file;    // resolved path
  std::string root;    // the URDF link the import starts at; empty: the URDF's root link
  std::string parent;  // the vehicle's link (from `links`) the root hangs on, by a fixed joint; empty: links[0]
  Eigen::Isometry3d X_PR = Eigen::Isometry3d::Identity();  // the root link's frame R in that link's (or B)
  // Where joints start (a URDF has no such element): by joint name, revolute and continuous joints from
  // `initial_deg` [rad here], prismatic ones from `initial` [m]; checked against the joints once imported.
  struct Initial {
    std::string joint;
    double value = 0.0;
    bool angle = true;  // from initial_deg
  };
  std::vector<Initial> initial;
};

const KeyTable<UrdfMount, VehicleContext>& urdf_keys();

// Appends the URDF's links under `root` to *links: with `links` empty the root becomes links[0], the base
// link, at X_BL = X_PR; otherwise it hangs on links[parent_index] by a fixed joint at X_PR. Problems are
// reported in the URDF file at the element's line (path `link "name"` / `joint "name"`), or at `where` (the
// YAML `urdf` value) when they concern the mount. False when any error was reported (*links then holds what
// was imported before it).
bool import_urdf(const Value& where, const UrdfMount& mount, int parent_index, std::vector<LinkSpec>* links);

}  // namespace hadal::config
