#include "hadal/physics/multibody.h"

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <gtest/gtest.h>

#include <cmath>
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

// An arm whose bodies have off-axis principal frames (tilted links, off-centre centres of mass) and both
// joint kinds: Bullet's poses of every body, after the state is written in, are the articulation's.
TEST(MultiBodyTest, BulletsBodyPosesAreTheArticulationsForwardKinematics) {
  const std::vector<LinkSpec> links = {
      link("base", 40.0, at({0, 0, 0}), {0.1, -0.05, -0.2}, {3.0, 4.0, 5.0}),
      link("shoulder", 3.0, at({0.3, 0.1, 0}, 0.4, {1, 0, 0}), {0.2, 0.03, 0.01}, {0.01, 0.05, 0.04}),
      link("fore", 2.0, at({0.9, 0.2, 0.1}, -0.3, {0, 1, 1}), {0.25, 0, -0.02}, {0.005, 0.03, 0.02}),
      link("tool", 0.5, at({1.3, 0.25, 0.1}, 0.2, {0, 0, 1}), {0.02, 0.01, 0}, {0.001, 0.002, 0.003}),
      link("slider", 0.4, at({1.4, 0.3, 0.0}, 0.6, {1, -1, 0}), {0, 0.01, 0.02}, {0.002, 0.001, 0.003})};
  const std::vector<LinkJoint> joints = {{-1, {}},
                                         {0, joint(JointType::kRevolute, {0, 0, 1})},
                                         {1, joint(JointType::kRevolute, {0.2, 1, 0})},
                                         {2, {}},
                                         {3, joint(JointType::kPrismatic, {1, 0.3, -0.2})}};
  const Articulation a(links, joints);
  ASSERT_EQ(a.num_dofs(), 3);
  MultiBodyPtr mb = make_multibody(a, false);
  const Eigen::Isometry3d X_WB = at({2.0, -3.0, -40.0}, 0.7, {1, 2, -0.5});
  Eigen::VectorXd q(3), qd(3);
  q << 0.4, -1.1, 0.07;
  qd << 0.3, -0.2, 0.1;
  set_multibody_state(*mb, a, X_WB, Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0.01, -0.02, 0.03), q, qd);
  const std::vector<Eigen::Isometry3d> expected = a.poses_W(X_WB, q);
  const std::vector<Eigen::Isometry3d> bullet = multibody_poses_W(*mb, a);
  for (int k = 0; k < a.num_bodies(); ++k) {
    SCOPED_TRACE("body " + std::to_string(k));
    const auto K = static_cast<std::size_t>(k);
    // Quaternion round trips and Bullet's chained transforms of terms ~ 40 m: 1e-12 m, 1e-13 rad.
    EXPECT_LT((bullet[K].translation() - expected[K].translation()).norm(), 1e-12);
    EXPECT_LT((bullet[K].linear() - expected[K].linear()).norm(), 1e-13);
  }
  EXPECT_EQ(multibody_joint_positions(*mb), q);
  EXPECT_EQ(multibody_joint_velocities(*mb), qd);
}

// A compound pendulum in vacuum on a fixed base: a 2 kg bob whose centre of mass hangs l = 0.8 m below a
// revolute joint about y, its own inertia about y 0.05 kg m^2 (0.03 and 0.02 about x and z: the wrong axis
// changes the period). Small swings (0.05 rad) have the period T = 2 pi sqrt((I_yy + m l^2) / (m g l)).
// Tolerance 5e-4 relative: the amplitude's lengthening theta0^2 / 16 = 1.6e-4, semi-implicit Euler at
// 500 Hz (omega dt)^2 / 24 ~ 2e-6, the zero crossings interpolated linearly (~1e-7). Without damping the
// swing keeps its amplitude (within 1 % after five periods; Bullet's default damping of 0.04 loses ~30 %).
TEST(MultiBodyTest, CompoundPendulumSwingsWithTheClosedFormPeriod) {
  const double m = 2.0, l = 0.8, I_yy = 0.05, g = 9.81, dt = 0.002;
  const std::vector<LinkSpec> links = {link("frame", 10.0, at({0, 0, 0}), {0, 0, 0}, {1, 1, 1}),
                                       link("bob", m, at({0.2, -0.1, 1.0}), {0, 0, -l}, {0.03, I_yy, 0.02})};
  const Articulation a(links, {{-1, {}}, {0, joint(JointType::kRevolute, {0, 1, 0})}});
  MultiBodyPtr mb = make_multibody(a, /*fixed_base=*/true);
  World world(g);
  world.world.addMultiBody(mb.get());
  Eigen::VectorXd q0(1), zero(1);
  q0 << 0.05;
  zero << 0.0;
  set_multibody_state(*mb, a, Eigen::Isometry3d::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), q0,
                      zero);
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

}  // namespace
}  // namespace hadal::physics
