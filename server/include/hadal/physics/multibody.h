// An Articulation (physics/articulation.h) as Bullet's reduced-coordinate multibody (btMultiBody,
// Featherstone's algorithm): issue 40's dynamics, built here and tested against the articulation's own
// kinematics and closed forms before the simulation steps vehicles with it (docs/ARCHITECTURE.md,
// "Articulated vehicles").
//
// Bullet's base is body 0 and its link i is body i + 1. Bullet holds every body in its principal frame P
// (origin at the centre of mass, principal axes: MassProperties::X_BP of the body's mass_K, K the body's
// frame), so a body's frame is X_WK = X_WP X_KP^-1 at the boundary, as BulletWorld does for rigid bodies.
// Bullet's silent defaults are switched off: no linear or angular damping (0.04 each by default),
// coordinate velocities and applied impulses unclamped (100 rad/s and 1000 N s), the gyroscopic term on.
#pragma once

#include <Eigen/Geometry>

#include <memory>
#include <vector>

#include "hadal/physics/articulation.h"

class btMultiBody;

namespace hadal::physics {

struct MultiBodyDeleter {
  void operator()(btMultiBody* body) const;
};
using MultiBodyPtr = std::unique_ptr<btMultiBody, MultiBodyDeleter>;

// The articulation's bodies as a btMultiBody (the base fixed in W when fixed_base), at rest with every
// joint at zero and B at the identity. A loaded vehicle has no locked joint (geometry::lock_joints made it a
// fixed one, its links part of the parent's body). The joints' limits and friction are joint torques of the
// simulation's implicit joint solve (physics/articulated_dynamics.h), not Bullet's.
MultiBodyPtr make_multibody(const Articulation& articulation, bool fixed_base);

// Writes B's pose and velocity (of B's origin, in W) and the joint coordinates and rates into Bullet and
// updates its cached link transforms.
void set_multibody_state(btMultiBody& body, const Articulation& articulation, const Eigen::Isometry3d& X_WB,
                         const Eigen::Vector3d& v_WB, const Eigen::Vector3d& w_WB, const Eigen::Ref<const Eigen::VectorXd>& q,
                         const Eigen::Ref<const Eigen::VectorXd>& qd);

// Each body's frame K in W as Bullet holds it (after set_multibody_state or a step; refreshes Bullet's
// cached link transforms from its state).
std::vector<Eigen::Isometry3d> multibody_poses_W(btMultiBody& body, const Articulation& articulation);
// The same from Bullet's cached link transforms as they are (set_multibody_state leaves them current).
std::vector<Eigen::Isometry3d> cached_poses_W(const btMultiBody& body, const Articulation& articulation);
// The same from the bodies' colliders (every body must have one), which Bullet's step leaves at the step's
// result (btMultiBody::updateCollisionObjectWorldTransforms; the cached link transforms stay at its start).
void collider_poses_W(const btMultiBody& body, const Articulation& articulation, std::vector<Eigen::Isometry3d>& X_WK);

// Moves the base's and the links' colliders to the cached transforms (Bullet moves them only within a
// step; btMultiBody::updateCollisionObjectWorldTransforms gives the same, computing them again).
void place_colliders(btMultiBody& body);

// A force f_W [N] acting at the point p_W [m] of body k (both in W), for the next step: Bullet takes a
// body's force at its centre of mass (where its cached transforms put it: set_multibody_state's, or the
// last step's start), so the moment (p_W - c_W) x f_W goes in as a torque.
void add_body_force_W(btMultiBody& body, int k, const Eigen::Vector3d& f_W, const Eigen::Vector3d& p_W);
// Body k's force f_W at its centre of mass and a moment tau_W (both in W), for the next step.
void add_body_wrench_W(btMultiBody& body, int k, const Eigen::Vector3d& f_W, const Eigen::Vector3d& tau_W);

// The joint coordinates and rates Bullet holds.
Eigen::VectorXd multibody_joint_positions(const btMultiBody& body);
Eigen::VectorXd multibody_joint_velocities(const btMultiBody& body);
// Both into `q` and `qd` (resized to the joints' number).
void multibody_joint_state(const btMultiBody& body, std::vector<double>& q, std::vector<double>& qd);

}  // namespace hadal::physics
