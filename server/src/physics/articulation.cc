#include "hadal/physics/articulation.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace hadal::physics {

std::vector<LinkJoint> link_joints(const std::vector<LinkSpec>& links) {
  std::vector<LinkJoint> joints;
  joints.reserve(links.size());
  for (const LinkSpec& link : links) joints.push_back(LinkJoint{link.parent, link.joint});
  return joints;
}

namespace {

bool moves(JointType type) { return type != JointType::kFixed; }

}  // namespace

Articulation::Articulation(const std::vector<LinkSpec>& links, const std::vector<LinkJoint>& joints) {
  if (links.empty()) throw std::invalid_argument("articulation: no links");
  if (joints.size() != links.size()) {
    throw std::invalid_argument("articulation: " + std::to_string(joints.size()) + " joints for " +
                                std::to_string(links.size()) + " links");
  }
  const auto fail = [&](std::size_t i, const std::string& what) {
    throw std::invalid_argument("articulation: link '" + links[i].name + "': " + what);
  };
  if (joints[0].parent != -1 || moves(joints[0].joint.type)) {
    fail(0, "the base link (the first) cannot have a parent or a moving joint");
  }
  body_of_link_.assign(links.size(), -1);
  bodies_.push_back(Body{});  // the base body, frame B
  for (std::size_t i = 0; i < links.size(); ++i) {
    const LinkJoint& j = joints[i];
    if (j.parent < -1 || j.parent >= static_cast<int>(i)) {
      fail(i, "its parent must be an earlier link (got index " + std::to_string(j.parent) + ")");
    }
    const JointSpec& joint = j.joint;
    if (moves(joint.type)) {
      const double n = joint.axis_L.norm();
      if (!std::isfinite(n) || !(n > 0.0)) fail(i, "the joint axis must be finite and not zero");
      if (std::isnan(joint.lower) || std::isnan(joint.upper) || joint.lower > joint.upper) {
        fail(i, "the joint's lower limit must be <= its upper limit");
      }
      if (!(joint.damping >= 0.0) || !(joint.friction >= 0.0)) fail(i, "joint damping and friction must be >= 0");
    }
    const int parent_body = j.parent < 0 ? 0 : body_of_link_[static_cast<std::size_t>(j.parent)];
    if (!moves(joint.type)) {
      body_of_link_[i] = parent_body;  // rigidly on its parent's body
    } else {
      Body body;
      body.parent = parent_body;
      body.joint_link = static_cast<int>(i);
      body.joint = joint;
      body.axis_K = joint.axis_L.normalized();  // K is the joint link's frame
      body.X_BK0 = links[i].X_BL;
      body.X_PK0 = bodies_[static_cast<std::size_t>(parent_body)].X_BK0.inverse() * links[i].X_BL;
      body_of_link_[i] = static_cast<int>(bodies_.size());
      bodies_.push_back(body);
    }
    bodies_[static_cast<std::size_t>(body_of_link_[i])].links.push_back(static_cast<int>(i));
  }
  X_KL_.resize(links.size());
  for (std::size_t i = 0; i < links.size(); ++i) {
    X_KL_[i] = bodies_[static_cast<std::size_t>(body_of_link_[i])].X_BK0.inverse() * links[i].X_BL;
  }
  for (std::size_t k = 0; k < bodies_.size(); ++k) {
    Body& body = bodies_[k];
    std::vector<LinkSpec> in_K;
    for (int l : body.links) {
      LinkSpec link = links[static_cast<std::size_t>(l)];
      link.X_BL = X_KL_[static_cast<std::size_t>(l)];
      in_K.push_back(std::move(link));
    }
    try {
      body.mass_K = composite_mass_properties(in_K);
    } catch (const std::invalid_argument& e) {
      fail(static_cast<std::size_t>(body.links.front()), std::string("the body it starts: ") + e.what());
    }
    // A moving body turns (or is turned) about every axis: Featherstone's articulated inertia needs each
    // principal moment > 0 (a point mass on a joint through it would have none about the joint).
    if (k > 0 && !(body.mass_K.I_principal.minCoeff() > 0.0)) {
      std::ostringstream moments;
      moments << body.mass_K.I_principal.x() << ", " << body.mass_K.I_principal.y() << ", "
              << body.mass_K.I_principal.z();
      fail(static_cast<std::size_t>(body.links.front()),
           "the body it starts needs a positive moment of inertia about every axis (principal moments " +
               moments.str() + " kg m^2)");
    }
  }
}

bool is_articulated(const std::vector<LinkSpec>& links) {
  for (std::size_t i = 0; i < links.size(); ++i) {
    if (link_moves(links, static_cast<int>(i))) return true;
  }
  return false;
}

double lower_limit(const JointSpec& joint) {
  return joint.type == JointType::kContinuous ? -std::numeric_limits<double>::infinity() : joint.lower;
}

double upper_limit(const JointSpec& joint) {
  return joint.type == JointType::kContinuous ? std::numeric_limits<double>::infinity() : joint.upper;
}

std::vector<Eigen::Isometry3d> Articulation::poses_W(const Eigen::Isometry3d& X_WB, const Eigen::Ref<const Eigen::VectorXd>& q) const {
  std::vector<Eigen::Isometry3d> X_WK;
  poses_W(X_WB, q, X_WK);
  return X_WK;
}

void Articulation::poses_W(const Eigen::Isometry3d& X_WB, const Eigen::Ref<const Eigen::VectorXd>& q,
                           std::vector<Eigen::Isometry3d>& X_WK) const {
  if (q.size() != num_dofs()) {
    throw std::invalid_argument("articulation: " + std::to_string(q.size()) + " joint coordinates for " +
                                std::to_string(num_dofs()) + " joints");
  }
  X_WK.resize(bodies_.size());
  X_WK[0] = X_WB;
  for (std::size_t k = 1; k < bodies_.size(); ++k) {
    const Body& body = bodies_[k];
    // X_WP X_PK0 M(q) by 3 x 3 blocks, as Eigen's isometry products take them (the same sums in the same
    // order), without their general path: A = X_WP X_PK0, then A M(q).
    const Eigen::Isometry3d& X_WP = X_WK[static_cast<std::size_t>(body.parent)];
    const Eigen::Matrix3d R_A = X_WP.linear() * body.X_PK0.linear();
    const Eigen::Vector3d p_A = X_WP.linear() * body.X_PK0.translation() + X_WP.translation();
    const Eigen::Isometry3d M = joint_motion(body.joint.type, body.axis_K, q[static_cast<Eigen::Index>(k - 1)]);
    Eigen::Isometry3d& X = X_WK[k];
    X.linear() = R_A * M.linear();
    X.translation() = R_A * M.translation() + p_A;
    X.makeAffine();
  }
}

std::vector<Articulation::BodyVelocity> Articulation::velocities_W(const std::vector<Eigen::Isometry3d>& X_WK,
                                                                   const Eigen::Vector3d& v_WB,
                                                                   const Eigen::Vector3d& w_WB,
                                                                   const Eigen::Ref<const Eigen::VectorXd>& qd) const {
  std::vector<BodyVelocity> out;
  velocities_W(X_WK, v_WB, w_WB, qd, out);
  return out;
}

void Articulation::velocities_W(const std::vector<Eigen::Isometry3d>& X_WK, const Eigen::Vector3d& v_WB,
                                const Eigen::Vector3d& w_WB, const Eigen::Ref<const Eigen::VectorXd>& qd,
                                std::vector<BodyVelocity>& out) const {
  if (qd.size() != num_dofs() || X_WK.size() != bodies_.size()) {
    throw std::invalid_argument("articulation: " + std::to_string(qd.size()) + " joint rates and " +
                                std::to_string(X_WK.size()) + " poses for " + std::to_string(num_dofs()) +
                                " joints");
  }
  out.resize(bodies_.size());
  out[0] = BodyVelocity{v_WB, w_WB};
  for (std::size_t k = 1; k < bodies_.size(); ++k) {
    const Body& body = bodies_[k];
    const auto p = static_cast<std::size_t>(body.parent);
    const Eigen::Vector3d axis_W = X_WK[k].linear() * body.axis_K;
    const double rate = qd[static_cast<Eigen::Index>(k - 1)];
    // K's origin moves with the parent body (a point of it), plus the joint's own motion.
    out[k].w_WK = out[p].w_WK;
    out[k].v_WK = out[p].v_WK + out[p].w_WK.cross(X_WK[k].translation() - X_WK[p].translation());
    if (body.joint.type == JointType::kPrismatic) {
      out[k].v_WK += rate * axis_W;
    } else {
      out[k].w_WK += rate * axis_W;
    }
  }
}

}  // namespace hadal::physics
