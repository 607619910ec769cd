// Articulation: a vehicle's links as a tree of rigid bodies joined by joints (issue 40, the first part:
// the tree and its kinematics; docs/ARCHITECTURE.md, "Articulated vehicles").
//
// Links joined by fixed joints (and every link without a parent: rigidly on the base) make one rigid
// body; each revolute, continuous or prismatic joint starts a new body. A body's frame K is the frame of
// the link whose joint starts it (URDF's convention: the joint at the child link's origin, its axis in
// the child link's frame); the base body's frame is the vehicle's B. Every link's LinkSpec::X_BL is its
// pose in B with every joint at q = 0. A joint's coordinate q is an angle about the axis [rad]
// (revolute, continuous) or a distance along it [m] (prismatic), zero at X_BL, positive by the right-
// hand rule / along the axis.
//
// Pure functions of the spec and the state: forward kinematics (each body's pose in W) and each body's
// velocity from the base's and the joint rates. The dynamics (Bullet's btMultiBody) builds on this.
#pragma once

#include <Eigen/Geometry>

#include <limits>
#include <vector>

#include "hadal/geometry/link_spec.h"
#include "hadal/physics/mass_properties.h"

namespace hadal::physics {

// Where a link hangs: its parent link (an index into the vehicle's links, lower than its own; -1: on the
// base, links[0]'s body) and the joint between them.
struct LinkJoint {
  int parent = -1;
  JointSpec joint;
};

// The link-joint pairs of a vehicle's links (LinkSpec::parent and ::joint).
std::vector<LinkJoint> link_joints(const std::vector<LinkSpec>& links);

// Whether a vehicle with these links is articulated: some link moves on a joint (link_moves).
bool is_articulated(const std::vector<LinkSpec>& links);

// A joint's limits as the joint solve takes them: -+infinity for a continuous joint.
double lower_limit(const JointSpec& joint);
double upper_limit(const JointSpec& joint);

class Articulation {
 public:
  struct Body {
    std::vector<int> links;         // the links it is made of (ascending)
    int parent = -1;                // parent body; -1 for the base body (body 0)
    int joint_link = -1;            // the link whose joint starts it; -1 for the base body
    JointSpec joint;                // that joint (kFixed for the base body)
    Eigen::Vector3d axis_K = Eigen::Vector3d::UnitZ();  // the joint's unit axis in K
    Eigen::Isometry3d X_BK0 = Eigen::Isometry3d::Identity();  // K in B at q = 0
    Eigen::Isometry3d X_PK0 = Eigen::Isometry3d::Identity();  // K in its parent body's frame at q = 0
    MassProperties mass_K;          // its links' composite mass properties in K (MassProperties' B is K)
  };
  struct BodyVelocity {
    Eigen::Vector3d v_WK = Eigen::Vector3d::Zero();  // of K's origin, in W [m/s]
    Eigen::Vector3d w_WK = Eigen::Vector3d::Zero();  // in W [rad/s]
  };

  // joints[i] for links[i]; links[0] must have no parent and a fixed joint. Throws std::invalid_argument
  // naming the link for: sizes that differ, a parent that is not an earlier link, links[0] with a parent
  // or a moving joint, an axis that is zero or not finite, lower > upper, a negative damping or friction,
  // a body without positive mass.
  Articulation(const std::vector<LinkSpec>& links, const std::vector<LinkJoint>& joints);
  // From the links' own parent and joint.
  explicit Articulation(const std::vector<LinkSpec>& links) : Articulation(links, link_joints(links)) {}

  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  // One coordinate per moving joint, in body order: body k > 0 has coordinate k - 1.
  int num_dofs() const { return num_bodies() - 1; }
  const Body& body(int k) const { return bodies_.at(static_cast<std::size_t>(k)); }
  int body_of_link(int link) const { return body_of_link_.at(static_cast<std::size_t>(link)); }
  // A link's pose in its body's frame K.
  const Eigen::Isometry3d& X_KL(int link) const { return X_KL_.at(static_cast<std::size_t>(link)); }

  // Each body's frame K in W, given B's pose in W and the joint coordinates (num_dofs()).
  std::vector<Eigen::Isometry3d> poses_W(const Eigen::Isometry3d& X_WB, const Eigen::Ref<const Eigen::VectorXd>& q) const;
  // The same into `X_WK` (resized; a step's calls then allocate nothing).
  void poses_W(const Eigen::Isometry3d& X_WB, const Eigen::Ref<const Eigen::VectorXd>& q, std::vector<Eigen::Isometry3d>& X_WK) const;
  // Each body's velocity, given B's (v_WB of B's origin) and the joint rates; poses from poses_W.
  std::vector<BodyVelocity> velocities_W(const std::vector<Eigen::Isometry3d>& X_WK, const Eigen::Vector3d& v_WB,
                                         const Eigen::Vector3d& w_WB, const Eigen::Ref<const Eigen::VectorXd>& qd) const;
  void velocities_W(const std::vector<Eigen::Isometry3d>& X_WK, const Eigen::Vector3d& v_WB, const Eigen::Vector3d& w_WB,
                    const Eigen::Ref<const Eigen::VectorXd>& qd, std::vector<BodyVelocity>& out) const;

 private:
  std::vector<Body> bodies_;
  std::vector<int> body_of_link_;
  std::vector<Eigen::Isometry3d> X_KL_;
};

}  // namespace hadal::physics
