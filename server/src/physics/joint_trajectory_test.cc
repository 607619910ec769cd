#include "hadal/physics/joint_trajectory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace hadal::physics {
namespace {

// A polynomial joint motion and its first two derivatives, for waypoints and for the expected setpoints.
struct Motion {
  std::function<double(double)> p, v, a;
};

// A started trajectory of one joint with waypoints of `motion` at `times` (after start_time), giving
// velocities and accelerations as asked; it starts at started_at from the motion's state then.
JointTrajectory sampled(const Motion& motion, double start_time, double started_at, const std::vector<double>& times,
                        bool velocities, bool accelerations) {
  JointTrajectory trajectory;
  trajectory.start_time = start_time;
  for (double t : times) {
    JointTrajectoryPoint point;
    point.time_from_start = t;
    point.positions = {motion.p(start_time + t)};
    if (velocities) point.velocities = {motion.v(start_time + t)};
    if (accelerations) point.accelerations = {motion.a(start_time + t)};
    trajectory.points.push_back(point);
  }
  EXPECT_EQ(check_joint_trajectory(trajectory.points, 1), "");
  trajectory.started_at = started_at;
  trajectory.start_positions = {motion.p(started_at)};
  trajectory.start_velocities = {motion.v(started_at)};
  return trajectory;
}

// Positions alone: straight lines between waypoints (and from where the joint was to the first), then
// the last held at rate zero.
TEST(JointTrajectoryTest, PositionsAloneAreJoinedByLines) {
  JointTrajectory trajectory;
  trajectory.start_time = 10.0;
  trajectory.points = {{0.5, {1.0, -2.0}, {}, {}}, {1.5, {3.0, -1.0}, {}, {}}};
  ASSERT_EQ(check_joint_trajectory(trajectory.points, 2), "");
  trajectory.started_at = 10.1;
  trajectory.start_positions = {0.2, 0.0};
  trajectory.start_velocities = {5.0, 5.0};  // a line ignores rates
  // From (10.1 s, 0.2) to (10.5 s, 1.0): at 10.3 s, halfway, 0.6 at 2 rad/s.
  EXPECT_NEAR(sample_joint_trajectory(trajectory, 0, 10.3).position, 0.6, 1e-12);
  EXPECT_NEAR(sample_joint_trajectory(trajectory, 0, 10.3).rate, 2.0, 1e-12);
  // From (10.5, 1.0) to (11.5, 3.0) and (10.5, -2) to (11.5, -1): at 11.25 s, 2.5 and -1.25.
  EXPECT_NEAR(sample_joint_trajectory(trajectory, 0, 11.25).position, 2.5, 1e-12);
  EXPECT_NEAR(sample_joint_trajectory(trajectory, 0, 11.25).rate, 2.0, 1e-12);
  EXPECT_NEAR(sample_joint_trajectory(trajectory, 1, 11.25).position, -1.25, 1e-12);
  EXPECT_NEAR(sample_joint_trajectory(trajectory, 1, 11.25).rate, 1.0, 1e-12);
  EXPECT_EQ(trajectory.end_time(), 11.5);
  EXPECT_EQ(sample_joint_trajectory(trajectory, 1, 12.0).position, -1.0);
  EXPECT_EQ(sample_joint_trajectory(trajectory, 1, 12.0).rate, 0.0);
}

// Hermite's cubic reproduces any cubic from its positions and rates at the waypoints, the first segment
// from the joint's own state included; so does the quintic any quintic (whose acceleration is zero where
// the trajectory starts, as the first segment assumes).
TEST(JointTrajectoryTest, CubicsAndQuinticsReproduceTheirPolynomials) {
  const Motion cubic{[](double t) { return 1.0 + 2.0 * t - 0.5 * t * t + 0.25 * t * t * t; },
                     [](double t) { return 2.0 - t + 0.75 * t * t; }, [](double t) { return -1.0 + 1.5 * t; }};
  const JointTrajectory c = sampled(cubic, 2.0, 2.0, {0.4, 1.0, 2.5}, true, false);
  for (double t = 2.0; t < 4.5; t += 0.0625) {
    EXPECT_NEAR(sample_joint_trajectory(c, 0, t).position, cubic.p(t), 1e-12) << t;
    EXPECT_NEAR(sample_joint_trajectory(c, 0, t).rate, cubic.v(t), 1e-12) << t;
  }
  // t' = t - 1 so that the acceleration is zero at the start (1 s).
  const auto u = [](double t) { return t - 1.0; };
  const Motion quintic{
      [u](double t) { return 0.3 + 0.5 * u(t) + 0.2 * u(t) * u(t) * u(t) - 0.1 * std::pow(u(t), 4) +
                             0.03 * std::pow(u(t), 5); },
      [u](double t) { return 0.5 + 0.6 * u(t) * u(t) - 0.4 * std::pow(u(t), 3) + 0.15 * std::pow(u(t), 4); },
      [u](double t) { return 1.2 * u(t) - 1.2 * u(t) * u(t) + 0.6 * std::pow(u(t), 3); }};
  const JointTrajectory q = sampled(quintic, 0.5, 1.0, {0.9, 1.7, 3.0}, true, true);
  for (double t = 1.0; t < 3.5; t += 0.0625) {
    EXPECT_NEAR(sample_joint_trajectory(q, 0, t).position, quintic.p(t), 1e-12) << t;
    EXPECT_NEAR(sample_joint_trajectory(q, 0, t).rate, quintic.v(t), 1e-12) << t;
  }
  // The cubic alone cannot follow the quintic: the accelerations matter.
  const JointTrajectory q3 = sampled(quintic, 0.5, 1.0, {0.9, 1.7, 3.0}, true, false);
  EXPECT_GT(std::abs(sample_joint_trajectory(q3, 0, 2.85).position - quintic.p(2.85)), 1e-4);
}

TEST(JointTrajectoryTest, MalformedTrajectoriesAreRefusedNamingThePointAndField) {
  const auto check = [](std::vector<JointTrajectoryPoint> points) { return check_joint_trajectory(points, 2); };
  EXPECT_EQ(check({}), "no points");
  EXPECT_EQ(check({{0.5, {1.0}, {}, {}}}), "points[0].positions: 1 values for 2 joints");
  EXPECT_EQ(check({{0.5, {1.0, NAN}, {}, {}}}), "points[0].positions: value 1 is not finite");
  EXPECT_EQ(check({{0.5, {1.0, 2.0}, {}, {}}, {0.5, {1.0, 2.0}, {}, {}}}),
            "points[1].time_from_start: must come after points[0]'s");
  EXPECT_EQ(check({{-0.5, {1.0, 2.0}, {}, {}}}), "points[0].time_from_start: must be a time >= 0 s");
  EXPECT_EQ(check({{0.5, {1.0, 2.0}, {0.0, 0.0}, {}}, {1.0, {1.0, 2.0}, {}, {}}}),
            "points[1].velocities: missing (points[0] has them: every point or none)");
  EXPECT_EQ(check({{0.5, {1.0, 2.0}, {}, {}}, {1.0, {1.0, 2.0}, {0.0, 0.0}, {}}}),
            "points[1].velocities: given (points[0] has none: every point or none)");
  EXPECT_EQ(check({{0.5, {1.0, 2.0}, {}, {0.0, 0.0}}}), "points[0].accelerations: given without velocities");
  EXPECT_EQ(check({{0.5, {1.0, 2.0}, {0.0, INFINITY}, {}}}), "points[0].velocities: value 1 is not finite");
  EXPECT_EQ(check({{0.5, {1.0, 2.0}, {0.0, 0.0}, {0.0}}}), "points[0].accelerations: 1 values for 2 joints");
}

}  // namespace
}  // namespace hadal::physics
