// A vehicle's link as a scenario describes it (YAML: a vehicle definition's `links`): mass properties,
// collision shapes, buoyancy, the surface from a mesh file, how it looks and sounds. Links are rigidly
// attached to the vehicle's body frame B. The keys are declared once in geometry::link_keys()
// (server/src/geometry/link_spec.cc); configs/REFERENCE.md shows them.
//
// Frames: B vehicle body, L link, G collision geometry, M a mesh file's frame, P a checkerboard's.
#pragma once

#include <Eigen/Geometry>

#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hadal/config/key_table_fwd.h"
#include "hadal/geometry/mesh_import_options.h"

namespace hadal {

namespace config {
struct VehicleContext;
}

enum class CollisionShapeType { kBox, kSphere, kCylinder, kCapsule };

// A collision primitive attached to a link. Cylinders and capsules have their axis along G's z axis
// (as SDF/URDF); `length` is the length of the cylindrical part (a capsule's total length is
// length + 2 radius).
struct CollisionShape {
  CollisionShapeType type = CollisionShapeType::kBox;
  Eigen::Vector3d box_size = Eigen::Vector3d::Zero();  // full extents along G's x, y, z [m]
  double radius = 0.0;                                 // sphere, cylinder, capsule [m]
  double length = 0.0;                                 // cylinder, capsule [m]
  Eigen::Isometry3d X_LG = Eigen::Isometry3d::Identity();
};

// Lumped buoyancy of a link: the displaced volume of the fully submerged link and the centre of
// buoyancy (centroid of that volume).
struct BuoyancySpec {
  double volume = 0.0;                          // [m^3]
  Eigen::Vector3d p_LCb = Eigen::Vector3d::Zero();  // centre of buoyancy in L [m]
};

// The surface of a link from a mesh file (YAML link.mesh), with its vertices in L. Used for mass
// properties (with link.density), default buoyancy (closed meshes) and, later, ray casts and
// surface hydrodynamics.
struct LinkMesh {
  std::string file;  // resolved path
  geometry::ImportOptions import;
  Eigen::Isometry3d X_LM = Eigen::Isometry3d::Identity();  // pose of the file's frame in L
  std::shared_ptr<const geometry::TriangleMesh> mesh;      // vertices in L [m]
  bool closed = false;                                     // watertight and consistently oriented
  double volume = 0.0;                                     // enclosed volume (closed meshes) [m^3]
  Eigen::Vector3d p_LMc = Eigen::Vector3d::Zero();         // centroid of that volume in L [m]
  Eigen::Matrix3d I_unit_density = Eigen::Matrix3d::Zero();  // of that volume about p_LMc, density 1 [m^5]
  std::size_t boundary_edges = 0;                            // edges of one triangle only (0: closed)
};

// How cameras see a link's surface (render/frame.h): a uniform albedo, optionally painted with a
// checkerboard (a calibration target) in the x-y plane of a pattern frame P: squares of square_size
// along x_P (columns) and y_P (rows) from P's origin, square (0, 0) dark, then alternating; points
// outside the pattern keep `albedo` (the target's white border). The pattern is painted by (x_P, y_P)
// through the link's whole depth (a thin board shows it on both faces).
struct CheckerboardSpec {
  int columns = 0;           // squares along x_P
  int rows = 0;              // squares along y_P
  double square_size = 0.0;  // [m]
  Eigen::Isometry3d X_LP = Eigen::Isometry3d::Identity();
  Eigen::Array3d dark_albedo = Eigen::Array3d::Constant(0.03);
};
struct AppearanceSpec {
  std::optional<Eigen::Array3d> albedo;  // per channel (R, G, B); none: world.optics.vehicle_albedo
  // Lambert's backscatter parameter mu [dB] for sonars (render/sonar.h); none: world.acoustics.vehicle_backscatter_db
  std::optional<double> backscatter_db;
  std::optional<CheckerboardSpec> checkerboard;
};

// The joint between a link and its parent (YAML link.joint; physics/articulation.h builds the tree): URDF's
// convention, the joint at the child link's origin, its axis in the child link's frame L. A joint's
// coordinate q is an angle about the axis [rad] (revolute, continuous) or a distance along it [m]
// (prismatic), zero at the link's `pose`, positive by the right-hand rule / along the axis.
enum class JointType { kFixed, kRevolute, kContinuous, kPrismatic };

const char* to_string(JointType type);

struct JointSpec {
  std::string name;  // as ROS names it (JointState, joint_controllers); empty: the child link's name
  JointType type = JointType::kFixed;
  Eigen::Vector3d axis_L = Eigen::Vector3d::UnitZ();  // in the child link's frame; normalised on use
  double lower = -std::numeric_limits<double>::infinity();  // [rad] or [m]
  double upper = std::numeric_limits<double>::infinity();   // [rad] or [m]
  double damping = 0.0;   // viscous [N m s/rad] or [N s/m]
  double friction = 0.0;  // Coulomb [N m] or [N]
  double initial = 0.0;   // q at the start and after a reset [rad] or [m]
  // Its motor's limits (URDF's <limit effort velocity>): every torque (force) it applies, and the rate a
  // position or velocity command may ask for. > 0 from YAML; 0 from a URDF means no motor (no joint
  // controller may drive it).
  double effort_limit = std::numeric_limits<double>::infinity();    // [N m] or [N]
  double velocity_limit = std::numeric_limits<double>::infinity();  // [rad/s] or [m/s]
  // A revolute or prismatic joint whose limits meet (a URDF's zero-range joint: the Oberon 7's finger tips)
  // is loaded as a fixed joint at its lock (lock_joints): `type` is then kFixed and this is its own type.
  // Nothing moves it, so its links are part of the parent's rigid body; JointState still reports it, at
  // `lower`, rate and effort zero. kFixed: not a locked joint.
  JointType locked_type = JointType::kFixed;
};

struct LinkSpec {
  std::string name;
  double mass = 0.0;                                      // [kg], > 0
  double density = 0.0;  // [kg/m^3] the mass properties are the closed mesh's at this density; 0: given
  Eigen::Matrix3d I_LLcm_L = Eigen::Matrix3d::Identity();  // L about its centre of mass Lcm, L axes [kg m^2]
  Eigen::Vector3d p_LLcm = Eigen::Vector3d::Zero();       // centre of mass in L [m]
  // The link frame in the vehicle body frame B, with every joint at q = 0 (YAML `pose` is X_PL, in the
  // parent link's frame, for a link with a `parent`; the reader composes X_BL = X_BP X_PL).
  Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();
  int parent = -1;   // index of the parent link (an earlier one); -1: on the base link's body
  JointSpec joint;   // to the parent (or to B): fixed unless given
  std::vector<CollisionShape> collisions;
  // Coulomb friction coefficient of the link's surface in rigid contact: a contact's is the product of its
  // two surfaces' (Bullet's rule; the seabed's is 0.8). A rigid body's is its first link's: the base link's
  // for a vehicle, that of the link whose joint starts it for an arm's body.
  double friction = 0.5;
  BuoyancySpec buoyancy;
  std::optional<LinkMesh> mesh;
  // How the link looks to ray casts (cameras, DVL and altimeter beams, geometry/world_scene.h), in place
  // of its surface there (YAML link.visual): a detailed model over simple physics. The physics --
  // fluid forces, soil, Bullet -- keeps `mesh` or `collisions`.
  std::optional<LinkMesh> visual;
  AppearanceSpec appearance;

  // The mesh ray casts see: `visual`, else `mesh` (null: the collision shapes, or nothing).
  const LinkMesh* seen_mesh() const {
    if (visual && visual->mesh) return &*visual;
    return mesh && mesh->mesh ? &*mesh : nullptr;
  }
};

// A link's joint's name: JointSpec::name, else the link's own.
inline const std::string& joint_name(const LinkSpec& link) {
  return link.joint.name.empty() ? link.name : link.joint.name;
}

// A joint's motion at coordinate q, in its link's frame at q = 0 (URDF's convention): a rotation by q about the
// unit `axis` (revolute, continuous), a translation by q along it (prismatic), none (fixed).
Eigen::Isometry3d joint_motion(JointType type, const Eigen::Vector3d& axis, double q);

// A revolute or prismatic joint (not yet locked) whose limits meet: lower == upper, finite.
bool limits_meet(const JointSpec& joint);

// Each joint whose limits meet becomes a fixed joint at its lock (JointSpec::locked_type): its link, and every
// link beyond it, moved to where the joint at `lower` puts them (X_BL is at q = 0). Loaders call it on the
// whole link list, before anything reads the tree (a lock at 0 leaves every pose as it was, to the bit).
void lock_joints(std::vector<LinkSpec>& links);

// Whether a link's joint is one JointState reports: it moves, or it is locked.
inline bool reports_joint(const LinkSpec& link) {
  return link.joint.type != JointType::kFixed || link.joint.locked_type != JointType::kFixed;
}

// Whether links[index] moves relative to B: it or a link it hangs on has a joint that is not fixed.
bool link_moves(const std::vector<LinkSpec>& links, int index);

// Each link's rigid body, numbered as physics::Articulation numbers them (physics/articulation.h): 0 for
// the base body (the links rigidly on B), k for the body that the k-th moving joint in link order starts;
// a link on a fixed joint is on its parent's body. Links whose parent is not an earlier link are on the base.
std::vector<int> link_bodies(const std::vector<LinkSpec>& links);

namespace geometry {
// Why I (about the centre of mass) cannot be a body's inertia, or "": it must be positive definite, its
// principal moments obeying A + B >= C (0.1 % of the largest moment of slack for rounded hand-typed values).
std::string inertia_error(const Eigen::Matrix3d& I);

// A link's mesh file imported into L (its `import` options, X_LM), with its volume properties. `written`
// names the file in messages. `volume_matters`: a hull's (a closed mesh oriented inward is an error), not
// a visual's (open meshes welcome).
struct MeshLoad {
  std::optional<LinkMesh> mesh;  // nullopt: `error` says why
  std::string error;
  bool at_file = false;  // the file itself could not be imported (else its volume is wrong)
};
MeshLoad load_link_mesh(LinkMesh link_mesh, bool volume_matters, const std::string& written);

// The keys of one entry of `links`. Reading imports the link's meshes and computes what they give (mass
// properties with `density`, buoyancy of a closed mesh).
const config::KeyTable<LinkSpec, config::VehicleContext>& link_keys();
}  // namespace geometry

}  // namespace hadal
