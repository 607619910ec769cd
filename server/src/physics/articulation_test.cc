#include "hadal/physics/articulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace hadal::physics {
namespace {

LinkSpec link(const std::string& name, double mass, const Eigen::Vector3d& p_BL, const Eigen::Vector3d& p_LLcm) {
  LinkSpec l;
  l.name = name;
  l.mass = mass;
  l.I_LLcm_L = Eigen::Vector3d(0.01, 0.02, 0.03).asDiagonal();
  l.p_LLcm = p_LLcm;
  l.X_BL = Eigen::Isometry3d::Identity();
  l.X_BL.translation() = p_BL;
  return l;
}

JointSpec revolute(const Eigen::Vector3d& axis) {
  JointSpec j;
  j.type = JointType::kRevolute;
  j.axis_L = axis;
  return j;
}

// A base pose off every axis, so that nothing below passes by lying in W's planes.
Eigen::Isometry3d base_pose() {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translate(Eigen::Vector3d(2.0, -3.0, -40.0));
  X.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, -0.5).normalized()));
  return X;
}

// A planar arm on the base: shoulder (revolute about z at x = 0.3 m), elbow (revolute about z, 0.7 m
// further), and a tool fixed 0.4 m beyond the elbow and 0.05 m up. With joint angles (q1, q2) the tool's
// origin is at (0.3 + 0.7 cos q1 + 0.4 cos(q1 + q2), 0.7 sin q1 + 0.4 sin(q1 + q2), 0.05) in B.
struct PlanarArm {
  std::vector<LinkSpec> links = {link("base", 50.0, {0, 0, 0}, {0, 0, -0.1}),
                                 link("upper", 3.0, {0.3, 0, 0}, {0.35, 0, 0}),
                                 link("fore", 2.0, {1.0, 0, 0}, {0.2, 0, 0}),
                                 link("tool", 0.5, {1.4, 0, 0.05}, {0.02, 0.01, 0})};
  std::vector<LinkJoint> joints = {{-1, {}}, {0, revolute({0, 0, 1})}, {1, revolute({0, 0, 2})}, {2, {}}};
};

TEST(ArticulationTest, FixedLinksJoinTheirParentsBody) {
  const PlanarArm arm;
  const Articulation a(arm.links, arm.joints);
  ASSERT_EQ(a.num_bodies(), 3);
  EXPECT_EQ(a.num_dofs(), 2);
  EXPECT_EQ(a.body(0).links, std::vector<int>{0});
  EXPECT_EQ(a.body(1).links, std::vector<int>{1});
  EXPECT_EQ(a.body(2).links, (std::vector<int>{2, 3}));
  EXPECT_EQ(a.body(2).parent, 1);
  EXPECT_EQ(a.body_of_link(3), 2);
  // The forearm body's mass properties in its frame K (the fore link's): 2 kg at (0.2, 0, 0) and 0.5 kg
  // at (0.4 + 0.02, 0.01, 0.05): the composite centre of mass by hand.
  EXPECT_DOUBLE_EQ(a.body(2).mass_K.mass, 2.5);
  const Eigen::Vector3d p_KKcm = (2.0 * Eigen::Vector3d(0.2, 0, 0) + 0.5 * Eigen::Vector3d(0.42, 0.01, 0.05)) / 2.5;
  EXPECT_LT((a.body(2).mass_K.p_BBcm - p_KKcm).norm(), 1e-15);
  // The elbow's axis (0, 0, 2) in its link frame, normalised.
  EXPECT_EQ(a.body(2).axis_K, Eigen::Vector3d(0, 0, 1));
}

// geometry's link_bodies (what the ray-cast scene's bodies are made of) numbers a branched tree's bodies as
// the articulation does: base; a on it (revolute); b fixed on the base; c on a (revolute); d fixed on c;
// e on b (revolute): bodies 0, 1, 0, 2, 2, 3.
TEST(ArticulationTest, LinkBodiesNumberTheBodiesAsTheArticulationDoes) {
  std::vector<LinkSpec> links;
  const std::vector<std::pair<int, bool>> tree = {{-1, false}, {0, true}, {0, false}, {1, true}, {3, false}, {2, true}};
  for (std::size_t i = 0; i < tree.size(); ++i) {
    LinkSpec l = link("l" + std::to_string(i), 1.0, {0.1 * static_cast<double>(i), 0, 0}, {0, 0, 0});
    l.parent = tree[i].first;
    if (tree[i].second) l.joint = revolute({0, 1, 0});
    links.push_back(l);
  }
  const Articulation a(links);
  const std::vector<int> bodies = link_bodies(links);
  EXPECT_EQ(bodies, (std::vector<int>{0, 1, 0, 2, 2, 3}));
  for (std::size_t i = 0; i < links.size(); ++i) EXPECT_EQ(bodies[i], a.body_of_link(static_cast<int>(i))) << i;
}

// Forward kinematics against the planar closed form, at angles that tell the joints and the signs apart.
TEST(ArticulationTest, PlanarArmForwardKinematicsIsTheClosedForm) {
  const PlanarArm arm;
  const Articulation a(arm.links, arm.joints);
  const Eigen::Isometry3d X_WB = base_pose();
  for (const Eigen::Vector2d& q : {Eigen::Vector2d(0.4, -1.1), Eigen::Vector2d(-2.5, 0.3), Eigen::Vector2d(0, 0)}) {
    const std::vector<Eigen::Isometry3d> X_WK = a.poses_W(X_WB, q);
    const Eigen::Isometry3d X_W_tool = X_WK[2] * a.X_KL(3);
    const Eigen::Vector3d p_B_tool(0.3 + 0.7 * std::cos(q[0]) + 0.4 * std::cos(q[0] + q[1]),
                                   0.7 * std::sin(q[0]) + 0.4 * std::sin(q[0] + q[1]), 0.05);
    // Double rounding of a few products of terms ~ 40 m: 1e-12 m.
    EXPECT_LT((X_W_tool.translation() - X_WB * p_B_tool).norm(), 1e-12) << q.transpose();
    const Eigen::Matrix3d R_B_tool = Eigen::AngleAxisd(q[0] + q[1], Eigen::Vector3d::UnitZ()).toRotationMatrix();
    EXPECT_LT((X_W_tool.linear() - X_WB.linear() * R_B_tool).norm(), 1e-14);
    // The elbow's origin is 0.7 m from the shoulder's, at angle q1.
    const Eigen::Vector3d p_B_elbow(0.3 + 0.7 * std::cos(q[0]), 0.7 * std::sin(q[0]), 0.0);
    EXPECT_LT((X_WK[2].translation() - X_WB * p_B_elbow).norm(), 1e-12);
  }
}

// A prismatic joint along a tilted axis of a rotated link: the link slides along R_BL axis by q.
TEST(ArticulationTest, PrismaticJointSlidesAlongItsAxisInTheLinkFrame) {
  std::vector<LinkSpec> links = {link("base", 10.0, {0, 0, 0}, {0, 0, 0}),
                                 link("slider", 1.0, {0.1, 0.2, 0.3}, {0, 0, 0})};
  links[1].X_BL.rotate(Eigen::AngleAxisd(0.9, Eigen::Vector3d(0.3, -1.0, 0.4).normalized()));
  JointSpec slide;
  slide.type = JointType::kPrismatic;
  slide.axis_L = Eigen::Vector3d(0.0, 1.0, 1.0);
  const Articulation a(links, {{-1, {}}, {0, slide}});
  const Eigen::Isometry3d X_WB = base_pose();
  Eigen::VectorXd q(1);
  q << 0.25;
  const std::vector<Eigen::Isometry3d> X_WK = a.poses_W(X_WB, q);
  const Eigen::Vector3d expected =
      X_WB * (links[1].X_BL.translation() + 0.25 * links[1].X_BL.linear() * Eigen::Vector3d(0, 1, 1).normalized());
  EXPECT_LT((X_WK[1].translation() - expected).norm(), 1e-12);
  EXPECT_LT((X_WK[1].linear() - X_WB.linear() * links[1].X_BL.linear()).norm(), 1e-14);  // no turning
}

// Each body's velocity is the time derivative of its pose: against central differences of poses_W along
// a path q(t) = q0 + qd t, with the base moving too. Tolerance 1e-6: the difference's truncation error
// (h^2 / 6 times the third derivative, h = 1e-5 s, derivatives ~ 10) and rounding (1e-16 x 40 m / h).
TEST(ArticulationTest, BodyVelocitiesAreTheDerivativesOfThePoses) {
  PlanarArm arm;
  JointSpec slide;
  slide.type = JointType::kPrismatic;
  slide.axis_L = Eigen::Vector3d(1.0, -0.5, 0.2);
  arm.links.push_back(link("probe", 0.3, {1.5, 0.1, 0.0}, {0, 0, 0}));
  arm.joints.push_back({3, slide});
  const Articulation a(arm.links, arm.joints);
  ASSERT_EQ(a.num_dofs(), 3);
  const Eigen::Vector3d v_WB(0.4, -0.2, 0.1), w_WB(0.3, -0.5, 0.8);
  const Eigen::Vector3d q0(0.4, -1.1, 0.05), qd(0.7, -1.3, 0.2);
  const auto pose_at = [&](double t) {
    Eigen::Isometry3d X_WB = base_pose();
    X_WB.translation() += v_WB * t;
    X_WB.linear() = Eigen::AngleAxisd(w_WB.norm() * t, w_WB.normalized()).toRotationMatrix() * X_WB.linear();
    return a.poses_W(X_WB, q0 + qd * t);
  };
  const std::vector<Eigen::Isometry3d> X_WK = pose_at(0.0);
  const std::vector<Articulation::BodyVelocity> v = a.velocities_W(X_WK, v_WB, w_WB, qd);
  const double h = 1e-5;
  const std::vector<Eigen::Isometry3d> ahead = pose_at(h), behind = pose_at(-h);
  for (int k = 0; k < a.num_bodies(); ++k) {
    SCOPED_TRACE("body " + std::to_string(k));
    const auto K = static_cast<std::size_t>(k);
    const Eigen::Vector3d v_fd = (ahead[K].translation() - behind[K].translation()) / (2 * h);
    EXPECT_LT((v[K].v_WK - v_fd).norm(), 1e-6);
    // w from dR/dt R^T (skew-symmetric).
    const Eigen::Matrix3d W = (ahead[K].linear() - behind[K].linear()) / (2 * h) * X_WK[K].linear().transpose();
    const Eigen::Vector3d w_fd(W(2, 1), W(0, 2), W(1, 0));
    EXPECT_LT((v[K].w_WK - w_fd).norm(), 1e-6);
  }
  // The prismatic body turns with its parent (the forearm): its angular velocity is the forearm's.
  EXPECT_LT((v[3].w_WK - v[2].w_WK).norm(), 1e-15);
}

TEST(ArticulationTest, BadTreesAreClearErrors) {
  const PlanarArm arm;
  const auto error_of = [](const std::vector<LinkSpec>& links, const std::vector<LinkJoint>& joints) {
    try {
      Articulation a(links, joints);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  std::vector<LinkJoint> joints = arm.joints;
  joints[1].parent = 2;  // a later link: also how a cycle would show
  EXPECT_EQ(error_of(arm.links, joints),
            "articulation: link 'upper': its parent must be an earlier link (got index 2)");
  joints = arm.joints;
  joints[2].joint.axis_L = Eigen::Vector3d::Zero();
  EXPECT_EQ(error_of(arm.links, joints), "articulation: link 'fore': the joint axis must be finite and not zero");
  joints = arm.joints;
  joints[0].joint = revolute({0, 0, 1});
  EXPECT_EQ(error_of(arm.links, joints),
            "articulation: link 'base': the base link (the first) cannot have a parent or a moving joint");
  joints = arm.joints;
  joints[1].joint.lower = 1.0;
  joints[1].joint.upper = -1.0;
  EXPECT_EQ(error_of(arm.links, joints),
            "articulation: link 'upper': the joint's lower limit must be <= its upper limit");
  std::vector<LinkSpec> links = arm.links;
  links[1].mass = 0.0;
  EXPECT_EQ(error_of(links, arm.joints).rfind("articulation: link 'upper': the body it starts: composite mass", 0), 0u)
      << error_of(links, arm.joints);
  links = arm.links;
  links[1].I_LLcm_L = Eigen::Vector3d(0.0, 0.2, 0.2).asDiagonal();  // no moment about x
  EXPECT_EQ(error_of(links, arm.joints).rfind("articulation: link 'upper': the body it starts needs a positive "
                                              "moment of inertia about every axis", 0),
            0u)
      << error_of(links, arm.joints);
}

}  // namespace
}  // namespace hadal::physics
