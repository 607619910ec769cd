#include "hadal/physics/multibody.h"

#include "hadal/physics/articulated_dynamics.h"
#include "hadal/physics/joint_servo.h"

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

namespace hadal::physics {
namespace {

LinkSpec link(const std::string& name, double mass, const Eigen::Isometry3d& X_BL, const Eigen::Vector3d& p_LLcm,
              const Eigen::Vector3d& inertia) {
  LinkSpec l;
  l.name = name;
  l.mass = mass;
  l.I_LLcm_L = inertia.asDiagonal();
  l.p_LLcm = p_LLcm;
  l.X_BL = X_BL;
  return l;
}

Eigen::Isometry3d at(const Eigen::Vector3d& p, double angle = 0.0,
                     const Eigen::Vector3d& axis = Eigen::Vector3d::UnitZ()) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translate(p);
  X.rotate(Eigen::AngleAxisd(angle, axis.normalized()));
  return X;
}

JointSpec joint(JointType type, const Eigen::Vector3d& axis) {
  JointSpec j;
  j.type = type;
  j.axis_L = axis;
  return j;
}

// A Bullet world with gravity and nothing else, stepping one multibody.
struct World {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btMultiBodyConstraintSolver solver;
  btMultiBodyDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
  explicit World(double g) { world.setGravity(btVector3(0, 0, -g)); }
};

// A small sphere as a collider of the base and of every link, colliding with nothing (group 1, mask 0).
// Bullet solves a multibody's constraints (joint limits) only for bodies in a simulation island, and only
// bodies with collision objects are in one.
struct Colliders {
  btSphereShape sphere{0.05};
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders;
  btMultiBodyDynamicsWorld* world;
  Colliders(btMultiBodyDynamicsWorld& w, btMultiBody& mb) : world(&w) {
    for (int link = -1; link < mb.getNumLinks(); ++link) {
      colliders.push_back(std::make_unique<btMultiBodyLinkCollider>(&mb, link));
      colliders.back()->setCollisionShape(&sphere);
      if (link < 0) {
        mb.setBaseCollider(colliders.back().get());
      } else {
        mb.getLink(link).m_collider = colliders.back().get();
      }
      world->addCollisionObject(colliders.back().get(), 1, 0);
    }
  }
  ~Colliders() {
    for (auto& collider : colliders) world->removeCollisionObject(collider.get());
  }
};

// A compound pendulum on a fixed base: a 2 kg bob whose centre of mass hangs l = 0.8 m below a revolute
// joint about y, its own inertia about y 0.05 kg m^2 (0.03 and 0.02 about x and z: the wrong axis changes
// the period).
struct Pendulum {
  double m = 2.0, l = 0.8, I_yy = 0.05, g = 9.81, dt = 0.002;
  std::vector<LinkSpec> links = {link("frame", 10.0, at({0, 0, 0}), {0, 0, 0}, {1, 1, 1}),
                                 link("bob", m, at({0.2, -0.1, 1.0}), {0, 0, -l}, {0.03, I_yy, 0.02})};
  JointSpec joint_spec = joint(JointType::kRevolute, {0, 1, 0});
  double I_O() const { return I_yy + m * l * l; }
};

// Writes the state of a multibody with one joint at rest, the joint at q0, B at the identity.
void release_at(btMultiBody& mb, const Articulation& a, double q0) {
  Eigen::VectorXd q(1), zero(1);
  q << q0;
  zero << 0.0;
  set_multibody_state(mb, a, Eigen::Isometry3d::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), q,
                      zero);
}

// An arm whose bodies have off-axis principal frames (tilted links, off-centre centres of mass) and both
// joint kinds.
struct Arm {
  std::vector<LinkSpec> links = {
      link("base", 40.0, at({0, 0, 0}), {0.1, -0.05, -0.2}, {3.0, 4.0, 5.0}),
      link("shoulder", 3.0, at({0.3, 0.1, 0}, 0.4, {1, 0, 0}), {0.2, 0.03, 0.01}, {0.01, 0.05, 0.04}),
      link("fore", 2.0, at({0.9, 0.2, 0.1}, -0.3, {0, 1, 1}), {0.25, 0, -0.02}, {0.005, 0.03, 0.02}),
      link("tool", 0.5, at({1.3, 0.25, 0.1}, 0.2, {0, 0, 1}), {0.02, 0.01, 0}, {0.001, 0.002, 0.003}),
      link("slider", 0.4, at({1.4, 0.3, 0.0}, 0.6, {1, -1, 0}), {0, 0.01, 0.02}, {0.002, 0.001, 0.003})};
  std::vector<LinkJoint> joints = {{-1, {}},
                                   {0, joint(JointType::kRevolute, {0, 0, 1})},
                                   {1, joint(JointType::kRevolute, {0.2, 1, 0})},
                                   {2, {}},
                                   {3, joint(JointType::kPrismatic, {1, 0.3, -0.2})}};
};

// Bullet's pose of every body is the articulation's forward kinematics at B = X_WB and the joints at q:
// quaternion round trips and Bullet's chained transforms of terms ~ 40 m, 1e-12 m and 1e-13 rad.
void expect_bullets_poses(btMultiBody& mb, const Articulation& a, const Eigen::Isometry3d& X_WB,
                          const Eigen::VectorXd& q) {
  const std::vector<Eigen::Isometry3d> expected = a.poses_W(X_WB, q);
  const std::vector<Eigen::Isometry3d> bullet = multibody_poses_W(mb, a);
  for (int k = 0; k < a.num_bodies(); ++k) {
    SCOPED_TRACE("body " + std::to_string(k));
    const auto K = static_cast<std::size_t>(k);
    EXPECT_LT((bullet[K].translation() - expected[K].translation()).norm(), 1e-12);
    EXPECT_LT((bullet[K].linear() - expected[K].linear()).norm(), 1e-13);
  }
}

// The arm, after its state is written in: Bullet's poses of every body are the articulation's.
TEST(MultiBodyTest, BulletsBodyPosesAreTheArticulationsForwardKinematics) {
  const Arm arm;
  const Articulation a(arm.links, arm.joints);
  ASSERT_EQ(a.num_dofs(), 3);
  MultiBodyPtr mb = make_multibody(a, false);
  const Eigen::Isometry3d X_WB = at({2.0, -3.0, -40.0}, 0.7, {1, 2, -0.5});
  Eigen::VectorXd q(3), qd(3);
  q << 0.4, -1.1, 0.07;
  qd << 0.3, -0.2, 0.1;
  set_multibody_state(*mb, a, X_WB, Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0.01, -0.02, 0.03), q, qd);
  expect_bullets_poses(*mb, a, X_WB, q);
  EXPECT_EQ(multibody_joint_positions(*mb), q);
  EXPECT_EQ(multibody_joint_velocities(*mb), qd);
}

// The same arm with its first revolute joint and its prismatic joint locked (lower == upper, one at an
// angle and one at a distance that tell a flipped rotation or a lost offset apart; the shoulder's lock moves
// every link beyond it): lock_joints makes each a fixed joint at its lock, so the tree has one joint left,
// and every link is where the unlocked arm puts it with those joints at their locks (1e-12 m and 1e-13:
// the same chained products in another order). Bullet's multibody of it has that one degree of freedom and
// the same poses.
TEST(MultiBodyTest, ALockedJointIsFixedAtItsLock) {
  const Arm arm;
  std::vector<LinkSpec> links = arm.links;
  for (std::size_t l = 0; l < links.size(); ++l) {
    links[l].parent = arm.joints[l].parent;
    links[l].joint = arm.joints[l].joint;
  }
  links[1].joint.lower = links[1].joint.upper = 0.4;   // the shoulder
  links[4].joint.lower = links[4].joint.upper = 0.07;  // the slider
  lock_joints(links);
  EXPECT_EQ(links[1].joint.type, JointType::kFixed);
  EXPECT_EQ(links[1].joint.locked_type, JointType::kRevolute);
  EXPECT_EQ(links[4].joint.locked_type, JointType::kPrismatic);
  EXPECT_EQ(links[2].joint.locked_type, JointType::kFixed);  // free: as it was
  const Articulation locked(links);
  ASSERT_EQ(locked.num_dofs(), 1);
  const Articulation free(arm.links, arm.joints);
  const Eigen::Isometry3d X_WB = at({2.0, -3.0, -40.0}, 0.7, {1, 2, -0.5});
  Eigen::VectorXd q_free(3), q(1);
  q_free << 0.4, -1.1, 0.07;
  q << -1.1;
  const std::vector<Eigen::Isometry3d> X_WK_free = free.poses_W(X_WB, q_free), X_WK = locked.poses_W(X_WB, q);
  for (std::size_t l = 0; l < links.size(); ++l) {
    SCOPED_TRACE(links[l].name);
    const int il = static_cast<int>(l);
    const Eigen::Isometry3d expected = X_WK_free[static_cast<std::size_t>(free.body_of_link(il))] * free.X_KL(il);
    const Eigen::Isometry3d X_WL = X_WK[static_cast<std::size_t>(locked.body_of_link(il))] * locked.X_KL(il);
    EXPECT_LT((X_WL.translation() - expected.translation()).norm(), 1e-12);
    EXPECT_LT((X_WL.linear() - expected.linear()).norm(), 1e-13);
  }
  MultiBodyPtr mb = make_multibody(locked, false);
  EXPECT_EQ(mb->getNumDofs(), 1);
  set_multibody_state(*mb, locked, X_WB, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), q, Eigen::VectorXd::Zero(1));
  expect_bullets_poses(*mb, locked, X_WB, q);
  // A lock at zero leaves every pose as it was, to the bit.
  std::vector<LinkSpec> at_zero = links;
  at_zero[2].joint.lower = at_zero[2].joint.upper = 0.0;
  const std::vector<LinkSpec> before = at_zero;
  lock_joints(at_zero);
  for (std::size_t l = 0; l < links.size(); ++l) EXPECT_EQ(at_zero[l].X_BL.matrix(), before[l].X_BL.matrix());
}

// Bullet's generalised velocity: the base's centre-of-mass velocity and angular velocity in W, the rates.
Eigen::VectorXd bullet_u(const btMultiBody& mb, bool fixed_base) {
  const Eigen::VectorXd qd = multibody_joint_velocities(mb);
  if (fixed_base) return qd;
  Eigen::VectorXd u(6 + qd.size());
  const btVector3 v = mb.getBaseVel(), w = mb.getBaseOmega();
  u << v.x(), v.y(), v.z(), w.x(), w.y(), w.z(), qd;
  return u;
}

// One Featherstone step of Bullet from a moving state (every rate non-zero, so every velocity-product
// term counts: a missing Coriolis 2 w x s qd or a centripetal term shifts the result by > 1e-3) with body
// wrenches, joint torques and gravity: Bullet's velocity change over dt is M^-1 (Q - c) of
// ArticulatedDynamics. Both evaluate the same equations at the same state in double precision:
// 1e-9 relative to the largest rate change.
TEST(MultiBodyTest, ArticulatedDynamicsPredictsBulletsStep) {
  const Arm arm;
  const Articulation a(arm.links, arm.joints);
  for (const bool fixed_base : {false, true}) {
    SCOPED_TRACE(fixed_base ? "fixed base" : "floating base");
    World world(9.81);
    MultiBodyPtr mb = make_multibody(a, fixed_base);
    world.world.addMultiBody(mb.get());
    const Eigen::Isometry3d X_WB = at({2.0, -3.0, -40.0}, 0.7, {1, 2, -0.5});
    const Eigen::Vector3d v_WB(0.4, -0.3, 0.2), w_WB = fixed_base ? Eigen::Vector3d::Zero()
                                                                  : Eigen::Vector3d(0.5, -0.8, 1.1);
    Eigen::VectorXd q(3), qd(3), tau(3);
    q << 0.4, -1.1, 0.07;
    qd << 1.3, -0.9, 0.4;
    tau << 2.0, -1.5, 0.7;
    set_multibody_state(*mb, a, X_WB, fixed_base ? Eigen::Vector3d::Zero() : v_WB, w_WB, q, qd);
    const std::vector<Eigen::Isometry3d> X_WK = a.poses_W(X_WB, q);
    ArticulatedDynamics dynamics(a, fixed_base);
    dynamics.update(X_WK, fixed_base ? Eigen::Vector3d::Zero() : v_WB, w_WB, qd);
    const Eigen::VectorXd u0 = bullet_u(*mb, fixed_base);
    ASSERT_LT((u0 - dynamics.u()).norm(), 1e-12);
    std::vector<ArticulatedDynamics::Wrench> wrenches(static_cast<std::size_t>(a.num_bodies()));
    for (int k = 0; k < a.num_bodies(); ++k) {
      ArticulatedDynamics::Wrench& W = wrenches[static_cast<std::size_t>(k)];
      W << 3.0 - k, 1.0 + 2.0 * k, -2.0 + k, 0.5 * k, -0.3, 0.2 + 0.1 * k;
      add_body_force_W(*mb, k, W.head<3>(), dynamics.p_Wcm(k));
      if (k == 0) {
        mb->addBaseTorque(btVector3(W[3], W[4], W[5]));
      } else {
        mb->addLinkTorque(k - 1, btVector3(W[3], W[4], W[5]));
      }
    }
    for (int j = 0; j < 3; ++j) mb->addJointTorque(j, tau[j]);
    const double dt = 1e-3;
    world.world.stepSimulation(dt, 0, dt);
    const Eigen::VectorXd u_dot_bullet = (bullet_u(*mb, fixed_base) - u0) / dt;
    const Eigen::VectorXd u_dot =
        dynamics.mass_matrix().ldlt().solve(dynamics.generalized_force(wrenches, {0, 0, -9.81}, tau) - dynamics.bias());
    EXPECT_LT((u_dot_bullet - u_dot).norm(), 1e-9 * u_dot.norm()) << "Bullet " << u_dot_bullet.transpose()
                                                                   << "\nours   " << u_dot.transpose();
  }
}

// The step never forms M: the constraint force Bullet's contacts added is M u_dot - (Q - c) with M u_dot
// by the tree (mass_times). It is M (mass_matrix(), the matrix the test above checks against Bullet) times
// u_dot, for an acceleration with every entry distinct, at a state 40 m from W's origin (where a twist about
// the origin and one about the centre of mass differ most): 1e-12 of the product's size (rounding).
TEST(MultiBodyTest, MassTimesIsTheMassMatrixTimesTheAcceleration) {
  const Arm arm;
  const Articulation a(arm.links, arm.joints);
  for (const bool fixed_base : {false, true}) {
    SCOPED_TRACE(fixed_base ? "fixed base" : "floating base");
    const Eigen::Isometry3d X_WB = at({2.0, -3.0, -40.0}, 0.7, {1, 2, -0.5});
    Eigen::VectorXd q(3), qd(3);
    q << 0.4, -1.1, 0.07;
    qd << 1.3, -0.9, 0.4;
    ArticulatedDynamics dynamics(a, fixed_base);
    dynamics.update(a.poses_W(X_WB, q), Eigen::Vector3d(0.4, -0.3, 0.2), Eigen::Vector3d(0.5, -0.8, 1.1), qd);
    Eigen::VectorXd u_dot(dynamics.size());
    for (Eigen::Index i = 0; i < u_dot.size(); ++i) {
      u_dot[i] = 0.3 * static_cast<double>(i) - 1.1 + 0.07 * static_cast<double>(i * i);
    }
    Eigen::VectorXd product;
    dynamics.mass_times(u_dot, product);
    const Eigen::VectorXd expected = dynamics.mass_matrix() * u_dot;
    EXPECT_LT((product - expected).norm(), 1e-12 * expected.norm())
        << product.transpose() << "\nvs " << expected.transpose();
  }
}

// Added mass handed to Bullet as each body's reaction -M_A nu_r_dot - C_A(nu_r) nu_r at the solved
// acceleration. Kirchhoff's equations: in an ideal fluid at rest the bodies' momentum plus each body's fluid
// impulse (R_WK [p; h] with [p; h] = M_A nu about its centre of mass) is conserved, since the fluid's force
// on a body is minus that impulse's rate; internal joint torques change neither. The arm tumbles freely for
// 1 s with torques on its joints, a tilted, anisotropic, coupled M_A on every body and no gravity: the total
// linear and angular impulse changes only by the integrator's first-order error, as a rigid arm's momentum
// does (1.2e-3 and 1.9e-3 of their sizes at 1 ms, a quarter of that at 0.25 ms). Without C_A (the Munk
// terms) it drifts by ~0.2.
TEST(MultiBodyTest, AddedMassReactionsConserveTheImpulseOfBodiesAndFluid) {
  const Arm arm;
  const Articulation a(arm.links, arm.joints);
  const auto bodies = static_cast<std::size_t>(a.num_bodies());
  std::vector<ArticulatedDynamics::AddedMassBody> added(bodies);
  for (std::size_t k = 0; k < bodies; ++k) {
    const double scale = a.body(static_cast<int>(k)).mass_K.mass;
    added[k].M_A.diagonal() << 0.3 * scale, 0.8 * scale, 1.1 * scale, 0.02 * scale, 0.05 * scale, 0.04 * scale;
    added[k].M_A(0, 4) = added[k].M_A(4, 0) = 0.05 * scale;  // a coupling term
  }
  struct Impulse {
    Eigen::Vector3d P = Eigen::Vector3d::Zero(), L = Eigen::Vector3d::Zero();
  };
  const auto run = [&](bool coriolis, bool with_added_mass, int refine = 1) {
    World world(0.0);
    MultiBodyPtr mb = make_multibody(a, false);
    world.world.addMultiBody(mb.get());
    Eigen::VectorXd q(3), qd(3), tau(3);
    q << 0.4, -1.1, 0.07;
    qd << 1.3, -0.9, 0.4;
    tau << 2.0, -1.5, 0.7;
    set_multibody_state(*mb, a, at({2.0, -3.0, -40.0}, 0.7, {1, 2, -0.5}), {0.4, -0.3, 0.2}, {0.5, -0.8, 1.1}, q,
                        qd);
    ArticulatedDynamics dynamics(a, false);
    const std::vector<ArticulatedDynamics::Wrench> none(bodies, ArticulatedDynamics::Wrench::Zero());
    const auto impulse = [&]() {
      Impulse out;
      for (std::size_t k = 0; k < bodies; ++k) {
        const int body = static_cast<int>(k);
        const Vector6d& V = dynamics.velocity(body);
        const Eigen::Isometry3d X_WK = multibody_poses_W(*mb, a)[k];
        const Eigen::Matrix3d R_WK = X_WK.linear();
        Vector6d nu;
        nu << R_WK.transpose() * V.head<3>(), R_WK.transpose() * V.tail<3>();
        const Vector6d fluid = with_added_mass ? Vector6d(added[k].M_A * nu) : Vector6d::Zero();
        const double m = a.body(body).mass_K.mass;
        const Eigen::Matrix3d I_W = R_WK * a.body(body).mass_K.I_BBcm_B * R_WK.transpose();
        const Eigen::Vector3d& c = dynamics.p_Wcm(body);
        out.P += m * V.head<3>() + R_WK * fluid.head<3>();
        out.L += c.cross(m * V.head<3>()) + I_W * V.tail<3>() + R_WK * fluid.tail<3>() +
                 c.cross(R_WK * fluid.head<3>());
      }
      return out;
    };
    std::vector<Impulse> history;
    const double dt = 1e-3 / refine;
    const int steps = 1000 * refine;
    for (int step = 0; step <= steps; ++step) {
      const std::vector<Eigen::Isometry3d> X_WK = multibody_poses_W(*mb, a);
      const btVector3 v_c = mb->getBaseVel(), w = mb->getBaseOmega();
      const Eigen::Vector3d w_WB(w.x(), w.y(), w.z());
      const Eigen::Vector3d v_WB = Eigen::Vector3d(v_c.x(), v_c.y(), v_c.z()) +
                                   w_WB.cross(X_WK[0].translation() - X_WK[0] * a.body(0).mass_K.p_BBcm);
      dynamics.update(X_WK, v_WB, w_WB, multibody_joint_velocities(*mb));
      if (step == 0 || step == steps) history.push_back(impulse());
      if (step == steps) break;
      if (with_added_mass) {
        const auto reactions =
            dynamics.added_mass_reactions(added, none, Eigen::Vector3d::Zero(), tau, Eigen::VectorXd(), coriolis);
        for (std::size_t k = 0; k < bodies; ++k) {
          const ArticulatedDynamics::Wrench& W = reactions[k];
          add_body_force_W(*mb, static_cast<int>(k), W.head<3>(), dynamics.p_Wcm(static_cast<int>(k)));
          if (k == 0) {
            mb->addBaseTorque(btVector3(W[3], W[4], W[5]));
          } else {
            mb->addLinkTorque(static_cast<int>(k) - 1, btVector3(W[3], W[4], W[5]));
          }
        }
      }
      for (int j = 0; j < 3; ++j) mb->addJointTorque(j, tau[j]);
      world.world.stepSimulation(dt, 0, dt);
    }
    const double dP = (history[1].P - history[0].P).norm() / history[0].P.norm();
    const double dL = (history[1].L - history[0].L).norm() / history[0].L.norm();
    return std::max(dP, dL);
  };
  const double rigid = run(true, false), rigid_fine = run(true, false, 4);
  const double drift = run(true, true), drift_fine = run(true, true, 4);
  const double without_coriolis = run(false, true);
  // Semi-implicit Euler's first-order error: a quarter of the step, a quarter of the drift (within 25 %).
  EXPECT_LT(rigid, 3e-3) << "the rigid arm's own momentum";
  EXPECT_LT(rigid_fine, rigid / 3.0);
  EXPECT_LT(drift, 3e-3);
  EXPECT_LT(drift_fine, drift / 3.0);
  EXPECT_GT(without_coriolis, 0.05);
}

// The implicit joint solve (servos, damping) ends on a motion the plain added-mass solve agrees with: handed
// the joint torques it returns (servo, less the implicit damping at the solved rates, plus the explicit
// torques), ArticulatedDynamics::added_mass_reactions (an LDLT of the same matrix) gives every body the same
// reaction. The arm floats, moves, carries an anisotropic coupled M_A on every body, gravity and applied
// wrenches; two servos with a stiffness D and one without. Within 1e-12 of the reactions' size: the two
// factorisations round differently (seen: 7e-16 of it at most), over a mass matrix whose entries span 1e-3
// to 1e2.
TEST(MultiBodyTest, TheImplicitJointSolveEndsOnTheExplicitSolvesMotion) {
  const Arm arm;
  const Articulation a(arm.links, arm.joints);
  const auto bodies = static_cast<std::size_t>(a.num_bodies());
  ArticulatedDynamics dynamics(a, false);
  Eigen::VectorXd q(3), qd(3), tau(3);
  q << 0.4, -1.1, 0.07;
  qd << 1.3, -0.9, 0.4;
  tau << 2.0, -1.5, 0.7;
  const Eigen::Isometry3d X_WB = at({2.0, -3.0, -40.0}, 0.7, {1, 2, -0.5});
  dynamics.update(a.poses_W(X_WB, q), Eigen::Vector3d(0.4, -0.3, 0.2), Eigen::Vector3d(0.5, -0.8, 1.1), qd);
  std::vector<ArticulatedDynamics::AddedMassBody> added(bodies);
  std::vector<ArticulatedDynamics::Wrench> wrenches(bodies);
  for (std::size_t k = 0; k < bodies; ++k) {
    const double scale = a.body(static_cast<int>(k)).mass_K.mass;
    added[k].M_A.diagonal() << 0.3 * scale, 0.8 * scale, 1.1 * scale, 0.02 * scale, 0.05 * scale, 0.04 * scale;
    added[k].M_A(0, 4) = added[k].M_A(4, 0) = 0.05 * scale;
    added[k].v_water_W = Eigen::Vector3d(0.1, -0.05, 0.0);
    wrenches[k] << 3.0 - k, 1.0 + 0.5 * k, -2.0, 0.3, -0.1 * k, 0.2;
  }
  const Eigen::Vector3d g_W(0.0, 0.0, -9.81);
  ArticulatedDynamics::ImplicitJoints implicit;
  implicit.servo = Eigen::Vector3d(5.0, -3.0, 1.0);
  implicit.servo_D = Eigen::Vector3d(40.0, 0.0, 15.0);
  implicit.limit = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  implicit.damping_D = Eigen::Vector3d(0.5, 0.2, 0.0);
  implicit.q = q;
  implicit.dt = 1e-3;
  ArticulatedDynamics::Reactions out;
  dynamics.reactions(added, wrenches, g_W, tau, Eigen::VectorXd(), true, &implicit, out);
  EXPECT_EQ(out.servo[1], -3.0);  // no stiffness: its torque as given
  const std::vector<ArticulatedDynamics::Wrench> plain =
      dynamics.added_mass_reactions(added, wrenches, g_W, out.joint_torques, Eigen::VectorXd(), true);
  double size = 0.0;
  for (std::size_t k = 0; k < bodies; ++k) size = std::max(size, plain[k].norm());
  ASSERT_GT(size, 1.0);
  for (std::size_t k = 0; k < bodies; ++k) {
    EXPECT_LT((out.bodies[k] - plain[k]).norm(), 1e-12 * size) << "body " << k << ": " << out.bodies[k].transpose()
                                                             << " vs " << plain[k].transpose();
  }
}

// The pendulum in vacuum: small swings (0.05 rad) have the period T = 2 pi sqrt((I_yy + m l^2) / (m g l)).
// Tolerance 5e-4 relative: the amplitude's lengthening theta0^2 / 16 = 1.6e-4, semi-implicit Euler at
// 500 Hz (omega dt)^2 / 24 ~ 2e-6, the zero crossings interpolated linearly (~1e-7). Without damping the
// swing keeps its amplitude (within 1 % after five periods; Bullet's default damping of 0.04 loses ~30 %).
TEST(MultiBodyTest, CompoundPendulumSwingsWithTheClosedFormPeriod) {
  const Pendulum p;
  const double m = p.m, l = p.l, I_yy = p.I_yy, g = p.g, dt = p.dt;
  const Articulation a(p.links, {{-1, {}}, {0, p.joint_spec}});
  MultiBodyPtr mb = make_multibody(a, /*fixed_base=*/true);
  World world(g);
  world.world.addMultiBody(mb.get());
  release_at(*mb, a, 0.05);
  const double expected_T = 2.0 * M_PI * std::sqrt((I_yy + m * l * l) / (m * g * l));
  std::vector<double> crossings;  // downward zero crossings of q
  double previous = mb->getJointPos(0), peak = 0.0;
  for (int step = 1; step <= static_cast<int>(6 * expected_T / dt); ++step) {
    world.world.stepSimulation(dt, 0, dt);
    const double now = mb->getJointPos(0);
    if (previous > 0.0 && now <= 0.0) crossings.push_back((step - 1 + previous / (previous - now)) * dt);
    if (crossings.size() >= 5) peak = std::max(peak, std::abs(now));
    previous = now;
  }
  world.world.removeMultiBody(mb.get());
  ASSERT_GE(crossings.size(), 6u);
  const double T = (crossings[5] - crossings[0]) / 5.0;
  EXPECT_NEAR(T / expected_T, 1.0, 5e-4) << "T = " << T << " s, closed form " << expected_T << " s";
  EXPECT_NEAR(peak / 0.05, 1.0, 0.01);
}

// Each joint's viscous damping, -damping * qd, as a joint torque for the next step (Bullet clears applied
// torques after a step: call before every step). Explicit, as Bullet sees it; the simulation takes it
// implicitly with the added mass (physics/articulated_dynamics.h).
void add_joint_damping(btMultiBody& mb, const Articulation& articulation) {
  const Eigen::VectorXd qd = multibody_joint_velocities(mb);
  for (int k = 1; k < articulation.num_bodies(); ++k) {
    const double damping = articulation.body(k).joint.damping;
    if (damping > 0.0) mb.addJointTorque(k - 1, -damping * qd[k - 1]);
  }
}

// Joint damping c: released from 0.05 rad at rest, the linearised pendulum's peaks are
// theta0 exp(-c t / (2 I_O)) at t = n pi / omega_d. The peak after five periods against that envelope at
// its own time: within 0.5 % (the peak sampled at 500 Hz, (omega dt)^2 / 2 ~ 3e-5; the swing's
// nonlinearity at 0.05 rad, ~2e-4; the integrator's own damping, none without Bullet's defaults).
TEST(MultiBodyTest, JointDampingDecaysTheSwingAtTheClosedFormRate) {
  Pendulum p;
  p.joint_spec.damping = 0.05;  // N m s/rad: about 20 % of the amplitude lost in five periods
  const Articulation a(p.links, {{-1, {}}, {0, p.joint_spec}});
  MultiBodyPtr mb = make_multibody(a, true);
  World world(p.g);
  world.world.addMultiBody(mb.get());
  release_at(*mb, a, 0.05);
  const double T = 2.0 * M_PI * std::sqrt(p.I_O() / (p.m * p.g * p.l));
  double peak = 0.0, peak_time = 0.0;
  for (int step = 1; step <= static_cast<int>(5.3 * T / p.dt); ++step) {
    add_joint_damping(*mb, a);
    world.world.stepSimulation(p.dt, 0, p.dt);
    const double t = step * p.dt;
    if (t > 4.7 * T && mb->getJointPos(0) > peak) {
      peak = mb->getJointPos(0);
      peak_time = t;
    }
  }
  world.world.removeMultiBody(mb.get());
  const double expected = 0.05 * std::exp(-p.joint_spec.damping * peak_time / (2.0 * p.I_O()));
  EXPECT_NEAR(peak / expected, 1.0, 5e-3) << "peak " << peak << " at " << peak_time << " s, envelope " << expected;
  EXPECT_LT(peak, 0.05 * 0.85);  // it did decay
}

// A force at a point of a link, held by the joint: with gravity off, a horizontal arm (revolute about y,
// the bob's centre of mass 0.8 m out along x) carries a force F = (0.3, -0.4, -20) N at the point
// (1.1, 0.15, 0.05) m of the bob, off its centre of mass. The joint torque that holds it is the moment of F
// about the joint axis, tau = -((p - o) x F) . y: the arm stays within 1e-9 rad for 1 s (it starts at rest
// and the net torque is zero to rounding), and 0.5 % more or less torque turns it the opposite ways by more
// than 1e-3 rad (the holding effort's tolerance in issue 40, shown to tell).
TEST(MultiBodyTest, AForceAtAPointOfALinkIsHeldByItsMomentAboutTheJoint) {
  Pendulum p;
  p.links[1].X_BL = at({0.0, 0.0, 0.0});
  p.links[1].p_LLcm = Eigen::Vector3d(0.8, 0.0, 0.0);  // the arm along x: horizontal
  const Articulation a(p.links, {{-1, {}}, {0, p.joint_spec}});
  const Eigen::Vector3d F(0.3, -0.4, -20.0), point(1.1, 0.15, 0.05);
  const double holding = -point.cross(F).dot(Eigen::Vector3d::UnitY());  // the joint is at W's origin
  const auto swing = [&](double torque) {
    MultiBodyPtr mb = make_multibody(a, true);
    World world(0.0);
    world.world.addMultiBody(mb.get());
    for (int step = 0; step < static_cast<int>(1.0 / p.dt); ++step) {
      const std::vector<Eigen::Isometry3d> X_WK = multibody_poses_W(*mb, a);
      // The point moves with the bob: its place in the bob's frame K at q = 0 is `point` (K = B = W here).
      add_body_force_W(*mb, 1, F, X_WK[1] * point);
      mb->addJointTorque(0, torque);
      world.world.stepSimulation(p.dt, 0, p.dt);
    }
    const double q = mb->getJointPos(0);
    world.world.removeMultiBody(mb.get());
    return q;
  };
  EXPECT_LT(std::abs(swing(holding)), 1e-9);
  const double more = swing(1.005 * holding), less = swing(0.995 * holding);
  EXPECT_GT(std::abs(more), 1e-3);
  EXPECT_GT(std::abs(less), 1e-3);
  EXPECT_LT(more * less, 0.0);
}

// Runs the pendulum under a joint servo for `seconds`, from rest at q0; returns (q, qd) at the end and,
// through rate_at, qd at time `at`.
std::pair<double, double> servo_run(const Pendulum& p, double g, const JointServoSpec& spec, JointCommandMode mode,
                                    double target, double seconds, double at = -1.0, double* rate_at = nullptr) {
  const Articulation a(p.links, {{-1, {}}, {0, p.joint_spec}});
  MultiBodyPtr mb = make_multibody(a, true);
  World world(g);
  world.world.addMultiBody(mb.get());
  release_at(*mb, a, 0.0);
  for (int step = 0; step < static_cast<int>(std::lround(seconds / p.dt)); ++step) {
    mb->addJointTorque(0, joint_servo_torque(spec, mode, target, mb->getJointPos(0), mb->getJointVel(0)));
    add_joint_damping(*mb, a);
    world.world.stepSimulation(p.dt, 0, p.dt);
    if (rate_at != nullptr && std::abs((step + 1) * p.dt - at) < 0.5 * p.dt) *rate_at = mb->getJointVel(0);
  }
  const std::pair<double, double> end{mb->getJointPos(0), mb->getJointVel(0)};
  world.world.removeMultiBody(mb.get());
  return end;
}

// Position control against gravity: the pendulum settles where the servo's torque balances gravity's,
// kp (q* - q) = m g l sin q (solved by Newton here), within 1e-6 rad after 6 s (the closed loop's slowest
// mode decays as exp(-t kd / (2 I_O)) = exp(-45) by then). With the effort limited to 5 N m below what
// holding needs, it sags to where m g l sin q = 5 N m: a saturated servo's torque is constant and damps
// nothing, so the joint's own damping (3 N m s/rad, exp(-t c / (2 I_O)) = exp(-22) in 20 s) settles it.
TEST(MultiBodyTest, APositionServoSettlesWhereItsTorqueBalancesGravity) {
  const Pendulum p;
  const double mgl = p.m * p.g * p.l;
  JointServoSpec spec;
  spec.kp = 200.0;
  spec.kd = 20.0;
  const double target = 0.6;
  double q = target;
  for (int i = 0; i < 50; ++i) q -= (spec.kp * (target - q) - mgl * std::sin(q)) / (-spec.kp - mgl * std::cos(q));
  const auto [q_end, qd_end] = servo_run(p, p.g, spec, JointCommandMode::kPosition, target, 6.0);
  EXPECT_NEAR(q_end, q, 1e-6);
  EXPECT_NEAR(qd_end, 0.0, 1e-6);
  EXPECT_GT(target - q_end, 0.03);  // gravity's share (0.042 rad) is visible: the law, not a rigid hold
  spec.effort_limit = 5.0;
  Pendulum damped = p;
  damped.joint_spec.damping = 3.0;
  const auto [q_sag, qd_sag] = servo_run(damped, p.g, spec, JointCommandMode::kPosition, M_PI / 2, 20.0);
  EXPECT_NEAR(q_sag, std::asin(5.0 / mgl), 1e-6);
  EXPECT_NEAR(qd_sag, 0.0, 1e-6);
}

// Velocity control without gravity: the rate approaches the command, held to the velocity limit, as
// 2 (1 - exp(-t kd / I_O)): at t = I_O / kd (0.66 s) 1 - 1/e of it within 1 % (explicit Euler's dt kd / I_O
// = 0.3 %), at 6 s (9 time constants) within 1e-3.
TEST(MultiBodyTest, AVelocityServoReachesItsLimitedRateWithItsTimeConstant) {
  const Pendulum p;
  JointServoSpec spec;
  spec.kd = 2.0;
  spec.velocity_limit = 2.0;
  const double tau = p.I_O() / spec.kd;
  double rate_at_tau = 0.0;
  const auto [q_end, qd_end] =
      servo_run(p, 0.0, spec, JointCommandMode::kVelocity, 3.0, 6.0, std::round(tau / p.dt) * p.dt, &rate_at_tau);
  EXPECT_NEAR(qd_end, 2.0, 1e-3);
  EXPECT_NEAR(rate_at_tau / (2.0 * (1.0 - std::exp(-std::round(tau / p.dt) * p.dt / tau))), 1.0, 0.01);
  EXPECT_GT(q_end, 0.0);
}

}  // namespace
}  // namespace hadal::physics
