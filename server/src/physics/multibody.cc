#include "hadal/physics/multibody.h"

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyLink.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace hadal::physics {
namespace {

// Bullet's clamps set out of reach: no joint rate or impulse of a real vehicle comes near them.
constexpr double kUnclamped = 1e30;

btVector3 bt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }

btQuaternion bt_rotation(const Eigen::Matrix3d& R) {
  const Eigen::Quaterniond q(R);
  return btQuaternion(q.x(), q.y(), q.z(), q.w());
}

btTransform bt(const Eigen::Isometry3d& X) { return btTransform(bt_rotation(X.linear()), bt(X.translation())); }

// The principal frame P of a body in its frame K.
const Eigen::Isometry3d& X_KP(const Articulation::Body& body) { return body.mass_K.X_BP; }

}  // namespace

void MultiBodyDeleter::operator()(btMultiBody* body) const { delete body; }

MultiBodyPtr make_multibody(const Articulation& articulation, bool fixed_base) {
  const Articulation::Body& base = articulation.body(0);
  MultiBodyPtr mb(new btMultiBody(articulation.num_dofs(), base.mass_K.mass, bt(base.mass_K.I_principal),
                                  fixed_base, /*canSleep=*/false));
  for (int k = 1; k < articulation.num_bodies(); ++k) {
    const Articulation::Body& body = articulation.body(k);
    const Articulation::Body& parent = articulation.body(body.parent);
    // At q = 0: K in the parent's principal frame, and this body's principal frame there.
    const Eigen::Isometry3d X_PpK = X_KP(parent).inverse() * body.X_PK0;
    const Eigen::Isometry3d X_PpP = X_PpK * X_KP(body);
    const btQuaternion parent_to_this = bt_rotation(X_PpP.linear().transpose());
    const Eigen::Matrix3d R_PK = X_KP(body).linear().transpose();
    const btVector3 axis_P = bt(R_PK * body.axis_K);
    // The pivot is K's origin: from the parent's centre of mass, in the parent's principal frame; to this
    // body's centre of mass, in its principal frame.
    const btVector3 parent_com_to_pivot = bt(X_PpK.translation());
    const btVector3 pivot_to_com = bt(R_PK * X_KP(body).translation());
    const btVector3 inertia = bt(body.mass_K.I_principal);
    switch (body.joint.type) {
      case JointType::kRevolute:
      case JointType::kContinuous:
        mb->setupRevolute(k - 1, body.mass_K.mass, inertia, body.parent - 1, parent_to_this, axis_P,
                          parent_com_to_pivot, pivot_to_com, /*disableParentCollision=*/true);
        break;
      case JointType::kPrismatic:
        mb->setupPrismatic(k - 1, body.mass_K.mass, inertia, body.parent - 1, parent_to_this, axis_P,
                           parent_com_to_pivot, pivot_to_com, /*disableParentCollision=*/true);
        break;
      case JointType::kFixed:
        throw std::logic_error("make_multibody: body " + std::to_string(k) + " has a fixed joint");
    }
  }
  mb->finalizeMultiDof();
  mb->setLinearDamping(0.0);
  mb->setAngularDamping(0.0);
  mb->setMaxCoordinateVelocity(kUnclamped);
  mb->setMaxAppliedImpulse(kUnclamped);
  mb->setUseGyroTerm(true);
  mb->setHasSelfCollision(false);
  set_multibody_state(*mb, articulation, Eigen::Isometry3d::Identity(), Eigen::Vector3d::Zero(),
                      Eigen::Vector3d::Zero(), Eigen::VectorXd::Zero(articulation.num_dofs()),
                      Eigen::VectorXd::Zero(articulation.num_dofs()));
  return mb;
}

void set_multibody_state(btMultiBody& mb, const Articulation& articulation, const Eigen::Isometry3d& X_WB,
                         const Eigen::Vector3d& v_WB, const Eigen::Vector3d& w_WB,
                         const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& qd) {
  if (q.size() != articulation.num_dofs() || qd.size() != articulation.num_dofs()) {
    throw std::invalid_argument("set_multibody_state: " + std::to_string(q.size()) + " coordinates and " +
                                std::to_string(qd.size()) + " rates for " + std::to_string(articulation.num_dofs()) +
                                " joints");
  }
  const Eigen::Isometry3d X_WP = X_WB * X_KP(articulation.body(0));
  mb.setBaseWorldTransform(bt(X_WP));
  mb.setBaseVel(bt(v_WB + w_WB.cross(X_WP.translation() - X_WB.translation())));
  mb.setBaseOmega(bt(w_WB));
  for (int i = 0; i < articulation.num_dofs(); ++i) {
    mb.setJointPos(i, q[i]);
    mb.setJointVel(i, qd[i]);
  }
  // Bullet's scratch for the tree's transforms, kept from call to call (this runs every step).
  thread_local btAlignedObjectArray<btQuaternion> world_to_local;
  thread_local btAlignedObjectArray<btVector3> local_origin;
  mb.forwardKinematics(world_to_local, local_origin);
}

std::vector<Eigen::Isometry3d> multibody_poses_W(btMultiBody& mb, const Articulation& articulation) {
  btAlignedObjectArray<btQuaternion> world_to_local;
  btAlignedObjectArray<btVector3> local_origin;
  mb.forwardKinematics(world_to_local, local_origin);
  return cached_poses_W(mb, articulation);
}

namespace {
// Body k's frame K in W from its principal frame P's as Bullet's transform holds it (its rotation matrix as
// it is): X_WP X_PK.
Eigen::Isometry3d pose_of(const btTransform& X_WP, const Articulation::Body& body) {
  const btMatrix3x3& basis = X_WP.getBasis();
  Eigen::Matrix3d R_WP;
  for (int r = 0; r < 3; ++r) R_WP.row(r) << basis[r].x(), basis[r].y(), basis[r].z();
  const Eigen::Isometry3d& X_KP_k = X_KP(body);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R_WP * X_KP_k.linear().transpose();
  const btVector3& o = X_WP.getOrigin();
  X.translation() = Eigen::Vector3d(o.x(), o.y(), o.z()) - X.linear() * X_KP_k.translation();
  return X;
}
}  // namespace

std::vector<Eigen::Isometry3d> cached_poses_W(const btMultiBody& mb, const Articulation& articulation) {
  std::vector<Eigen::Isometry3d> X_WK(static_cast<std::size_t>(articulation.num_bodies()));
  X_WK[0] = pose_of(mb.getBaseWorldTransform(), articulation.body(0));
  for (int k = 1; k < articulation.num_bodies(); ++k) {
    X_WK[static_cast<std::size_t>(k)] = pose_of(mb.getLink(k - 1).m_cachedWorldTransform, articulation.body(k));
  }
  return X_WK;
}

void collider_poses_W(const btMultiBody& mb, const Articulation& articulation, std::vector<Eigen::Isometry3d>& X_WK) {
  X_WK.resize(static_cast<std::size_t>(articulation.num_bodies()));
  for (int k = 0; k < articulation.num_bodies(); ++k) {
    const btMultiBodyLinkCollider* collider = k == 0 ? mb.getBaseCollider() : mb.getLink(k - 1).m_collider;
    if (collider == nullptr) {
      throw std::logic_error("collider_poses_W: body " + std::to_string(k) + " has no collider");
    }
    X_WK[static_cast<std::size_t>(k)] = pose_of(collider->getWorldTransform(), articulation.body(k));
  }
}

void place_colliders(btMultiBody& mb) {
  // btMultiBody::updateCollisionObjectWorldTransforms builds the same transforms again, by the same
  // arithmetic as forwardKinematics: the base's from its position and rotation, each link's its cached one.
  if (btMultiBodyLinkCollider* base = mb.getBaseCollider()) {
    const btTransform tr = mb.getBaseWorldTransform();
    base->setWorldTransform(tr);
    base->setInterpolationWorldTransform(tr);
  }
  for (int i = 0; i < mb.getNumLinks(); ++i) {
    if (btMultiBodyLinkCollider* collider = mb.getLink(i).m_collider) {
      collider->setWorldTransform(mb.getLink(i).m_cachedWorldTransform);
      collider->setInterpolationWorldTransform(mb.getLink(i).m_cachedWorldTransform);
    }
  }
}

void add_body_force_W(btMultiBody& mb, int k, const Eigen::Vector3d& f_W, const Eigen::Vector3d& p_W) {
  // Bullet's frame of body k is its principal frame, whose origin is the centre of mass (MassProperties).
  const btVector3 c =
      k == 0 ? mb.getBaseWorldTransform().getOrigin() : mb.getLink(k - 1).m_cachedWorldTransform.getOrigin();
  add_body_wrench_W(mb, k, f_W, (p_W - Eigen::Vector3d(c.x(), c.y(), c.z())).cross(f_W));
}

void add_body_wrench_W(btMultiBody& mb, int k, const Eigen::Vector3d& f_W, const Eigen::Vector3d& tau_W) {
  if (k == 0) {
    mb.addBaseForce(bt(f_W));
    mb.addBaseTorque(bt(tau_W));
  } else {
    mb.addLinkForce(k - 1, bt(f_W));
    mb.addLinkTorque(k - 1, bt(tau_W));
  }
}

Eigen::VectorXd multibody_joint_positions(const btMultiBody& mb) {
  Eigen::VectorXd q(mb.getNumLinks());
  for (int i = 0; i < mb.getNumLinks(); ++i) q[i] = mb.getJointPos(i);
  return q;
}

Eigen::VectorXd multibody_joint_velocities(const btMultiBody& mb) {
  Eigen::VectorXd qd(mb.getNumLinks());
  for (int i = 0; i < mb.getNumLinks(); ++i) qd[i] = mb.getJointVel(i);
  return qd;
}

void multibody_joint_state(const btMultiBody& mb, std::vector<double>& q, std::vector<double>& qd) {
  q.resize(static_cast<std::size_t>(mb.getNumLinks()));
  qd.resize(q.size());
  for (int i = 0; i < mb.getNumLinks(); ++i) {
    q[static_cast<std::size_t>(i)] = mb.getJointPos(i);
    qd[static_cast<std::size_t>(i)] = mb.getJointVel(i);
  }
}

}  // namespace hadal::physics
