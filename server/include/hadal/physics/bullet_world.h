// BulletWorld: the rigid-body world of a scenario in double-precision Bullet.
//
// Each vehicle is ONE Bullet rigid body: all links are rigidly attached to the body frame B, so the
// vehicle's mass properties are the composite of its links (physics/mass_properties). Bullet places
// a body's origin at its centre of mass with principal axes, so Bullet holds the pose of the
// principal frame P and this class converts at the boundary:
//   X_WP = X_WB * X_BP,   v_WP = v_WB + w_WB x (p_WP - p_WB),   w_WP = w_WB.
// Collision primitives of all links go into one btCompoundShape with child poses
// X_PG = X_BP^-1 X_BL X_LG (cylinder/capsule along G-z: btCylinderShapeZ / btCapsuleShapeZ); a
// vehicle without shapes gets an empty compound and collides with nothing. The seabed is a static
// plane z = seabed.z with normal +z, or the seabed's mesh; a vehicle with seabed_contact soil does not
// collide with it (its soil forces do, physics/terramechanics.h), only with other vehicles. Gravity (WorldSpec::gravity_W) is applied by Bullet at each
// centre of mass.
//
// Gyroscopic moment: with world.dynamics.gyroscopic (default) Bullet integrates the rigid-body
// term -(I w) x w implicitly (BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY); without it a torque-free
// body keeps w_WB constant instead of its angular momentum.
// Integration: one fixed step per call, stepSimulation(dt, 0, dt) -- semi-implicit Euler
// (v += a dt, then p += v dt), no sub-stepping, no interpolation. Sleeping is disabled.
//
// State: the pose and velocity of every body are written in with set_body_state() and read back
// with body_state(). Bullet's only other persistent state is its contact cache (persistent
// manifolds, used for warm starting, and the broadphase pair cache). clear_contacts() rebuilds the
// world's collision bookkeeping from scratch, so that restoring the same SimState twice gives
// bit-identical continuations; a run restored while a vehicle is in contact can differ from the
// uninterrupted run in the last bits (the contact cache is not part of SimState).
//
// Articulated vehicles (a link on a joint that is not fixed; physics/articulation.h) are one btMultiBody
// each (physics/multibody.h: Featherstone's reduced coordinates, so joints are exact): body 0 is the base
// body (frame B), its base fixed in W for a static vehicle; each body's shapes are one compound on its own
// btMultiBodyLinkCollider (a body without shapes gets a small sphere that collides with nothing, since
// Bullet solves joint limits and friction only for bodies with colliders); links do not collide with each
// other. Joint limits and Coulomb friction are Bullet constraints; everything else (damping, efforts,
// fluid) comes in as forces. The world is a btMultiBodyDynamicsWorld only when the model has an articulated
// vehicle, so rigid-only scenes step exactly as before. The state adds the joint coordinates and rates.
//
// Contact parameters: friction 0.5 (vehicle) x 0.8 (seabed) = 0.4 combined (Bullet multiplies
// them), restitution 0 -- a vehicle settling on sediment does not bounce. Collision margin:
// Bullet's 0.04 m default is meant for metre-scale game objects; boxes and cylinders use
// min(0.01 m, 20 % of their smallest half extent), kept inside the shape, so small parts keep
// their size.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "hadal/core/model.h"
#include "hadal/core/state.h"
#include "hadal/physics/mass_properties.h"

namespace hadal::physics {

class Articulation;

class BulletWorld {
 public:
  // Builds the seabed and one body per model vehicle at X_WB_initial / v_WB_initial. Throws
  // std::invalid_argument if a vehicle has no positive, finite mass.
  explicit BulletWorld(const Model& model);
  ~BulletWorld();
  BulletWorld(const BulletWorld&) = delete;
  BulletWorld& operator=(const BulletWorld&) = delete;

  int num_vehicles() const;
  // The vehicle's; an articulated vehicle's base body's (Articulation::Body::mass_K, K = B).
  const MassProperties& mass_properties(int vehicle) const;
  // The articulated vehicle's tree of bodies; null for a rigid vehicle.
  const Articulation* articulation(int vehicle) const;

  // Pose and velocity of the vehicle's body frame B.
  RigidBodyState body_state(int vehicle) const;

  // Writes pose and velocity of B into Bullet and discards forces accumulated for the next step.
  // `body` must be finite (a NaN bounding box would poison the broadphase tree); re-enables a body
  // Bullet disabled after its bounding box overflowed.
  void set_body_state(int vehicle, const RigidBodyState& body);

  // An articulated vehicle's state: B's pose and velocity and the joint coordinates and rates
  // (Articulation::num_dofs() each); like set_body_state otherwise.
  void set_articulated_state(int vehicle, const RigidBodyState& body, const Eigen::Ref<const Eigen::VectorXd>& q,
                             const Eigen::Ref<const Eigen::VectorXd>& qd);
  // Each body's frame K in W (Articulation's order) where Bullet holds it: after a step, the step's result;
  // after set_articulated_state, the state written. Empty for a rigid vehicle.
  void body_poses_W(int vehicle, std::vector<Eigen::Isometry3d>& X_WK) const;
  // Its joint coordinates and rates as Bullet holds them.
  Eigen::VectorXd joint_positions(int vehicle) const;
  Eigen::VectorXd joint_velocities(int vehicle) const;
  // Both into `q` and `qd` (resized; empty for a rigid vehicle), without allocating once they have the size.
  void joint_state(int vehicle, std::vector<double>& q, std::vector<double>& qd) const;

  // Drops all contact manifolds and broadphase pairs and re-inserts the bodies in model order, so
  // collision bookkeeping no longer depends on history. Allocates; not for the per-step path.
  void clear_contacts();

  // Accumulate for the next step() only (Bullet clears forces after each step).
  // Force f_W applied at the world point p_WQ [N, m].
  void add_force_W(int vehicle, const Eigen::Vector3d& f_W, const Eigen::Vector3d& p_WQ);
  // Pure moment [N m], expressed in W.
  void add_torque_W(int vehicle, const Eigen::Vector3d& tau_W);

  // For an articulated vehicle's body k (Articulation's numbering; 0 is the base body): a force f_W at
  // the world point p_WQ, a pure moment tau_W, and a torque (force) on moving joint j [N m or N]. The
  // force's moment is taken about the body's centre of mass where set_articulated_state put it: write the
  // state before adding forces, as the simulation does every step.
  void add_body_force_W(int vehicle, int body, const Eigen::Vector3d& f_W, const Eigen::Vector3d& p_WQ);
  void add_body_torque_W(int vehicle, int body, const Eigen::Vector3d& tau_W);
  void add_joint_torque(int vehicle, int joint, double tau);
  // Body k's force f_W acting at its centre of mass and a moment tau_W (both in W): what the simulation
  // hands each body every step, with no moment to take.
  void add_body_wrench_W(int vehicle, int body, const Eigen::Vector3d& f_W, const Eigen::Vector3d& tau_W);

  // Advances by exactly one step of dt seconds.
  void step(double dt);

  // Number of contact points of the vehicle's body (any of its bodies) in the current contact manifolds.
  int num_contact_points(int vehicle) const;
  // A vehicle's contacts in the last step of dt: per body (Articulation's numbering; a rigid vehicle: one), the
  // force and the moment about the world origin its contact points' impulses (normal and friction, as the
  // solver applied them) give over the step, in W [N; N m].
  std::vector<Eigen::Matrix<double, 6, 1>> contact_wrenches_W(int vehicle, double dt) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hadal::physics
