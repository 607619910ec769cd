#include "hadal/physics/joint_trajectory.h"

#include <cmath>

namespace hadal::physics {
namespace {

std::string field_error(std::size_t point, const char* field, const std::string& what) {
  return "points[" + std::to_string(point) + "]." + field + ": " + what;
}

// "" or what is wrong with one field of a point: its size, or a value that is not finite.
std::string check_values(std::size_t point, const char* field, const std::vector<double>& values, std::size_t joints) {
  if (values.size() != joints) {
    return field_error(point, field, std::to_string(values.size()) + " values for " + std::to_string(joints) +
                                         " joints");
  }
  for (std::size_t j = 0; j < values.size(); ++j) {
    if (!std::isfinite(values[j])) return field_error(point, field, "value " + std::to_string(j) + " is not finite");
  }
  return {};
}

// One end of a segment: a joint's position, rate and acceleration at a time.
struct Knot {
  double t, p, v, a;
};

// The segment from `a` to `b` at time t in [a.t, b.t]: a line (order 1), Hermite's cubic (3) or the
// quintic through both ends' positions, rates and accelerations (5).
JointSetpoint segment(const Knot& a, const Knot& b, int order, double t) {
  const double T = b.t - a.t, s = t - a.t, dp = b.p - a.p;
  if (order == 1) return {a.p + dp * s / T, dp / T};
  double c2, c3, c4 = 0.0, c5 = 0.0;
  if (order == 3) {
    c2 = (3.0 * dp - (2.0 * a.v + b.v) * T) / (T * T);
    c3 = (-2.0 * dp + (a.v + b.v) * T) / (T * T * T);
  } else {
    const double T2 = T * T, T3 = T2 * T;
    c2 = 0.5 * a.a;
    c3 = (20.0 * dp - (8.0 * b.v + 12.0 * a.v) * T - (3.0 * a.a - b.a) * T2) / (2.0 * T3);
    c4 = (-30.0 * dp + (14.0 * b.v + 16.0 * a.v) * T + (3.0 * a.a - 2.0 * b.a) * T2) / (2.0 * T3 * T);
    c5 = (12.0 * dp - 6.0 * (b.v + a.v) * T - (a.a - b.a) * T2) / (2.0 * T3 * T2);
  }
  const double position = a.p + s * (a.v + s * (c2 + s * (c3 + s * (c4 + s * c5))));
  const double rate = a.v + s * (2.0 * c2 + s * (3.0 * c3 + s * (4.0 * c4 + s * 5.0 * c5)));
  return {position, rate};
}

Knot knot(const JointTrajectory& trajectory, std::size_t k, std::size_t j) {
  const JointTrajectoryPoint& point = trajectory.points[k];
  return {trajectory.start_time + point.time_from_start, point.positions[j],
          point.velocities.empty() ? 0.0 : point.velocities[j],
          point.accelerations.empty() ? 0.0 : point.accelerations[j]};
}

}  // namespace

std::string check_joint_trajectory(const std::vector<JointTrajectoryPoint>& points, std::size_t joints) {
  if (points.empty()) return "no points";
  const bool velocities = !points.front().velocities.empty();
  const bool accelerations = !points.front().accelerations.empty();
  if (accelerations && !velocities) return field_error(0, "accelerations", "given without velocities");
  for (std::size_t k = 0; k < points.size(); ++k) {
    const JointTrajectoryPoint& point = points[k];
    if (std::string e = check_values(k, "positions", point.positions, joints); !e.empty()) return e;
    if (point.velocities.empty() == velocities) {
      return field_error(k, "velocities", velocities ? "missing (points[0] has them: every point or none)"
                                                     : "given (points[0] has none: every point or none)");
    }
    if (point.accelerations.empty() == accelerations) {
      return field_error(k, "accelerations", accelerations ? "missing (points[0] has them: every point or none)"
                                                           : "given (points[0] has none: every point or none)");
    }
    if (velocities) {
      if (std::string e = check_values(k, "velocities", point.velocities, joints); !e.empty()) return e;
    }
    if (accelerations) {
      if (std::string e = check_values(k, "accelerations", point.accelerations, joints); !e.empty()) return e;
    }
    if (!std::isfinite(point.time_from_start) || point.time_from_start < 0.0) {
      return field_error(k, "time_from_start", "must be a time >= 0 s");
    }
    if (k > 0 && point.time_from_start <= points[k - 1].time_from_start) {
      return field_error(k, "time_from_start", "must come after points[" + std::to_string(k - 1) + "]'s");
    }
  }
  return {};
}

JointSetpoint sample_joint_trajectory(const JointTrajectory& trajectory, std::size_t j, double t) {
  const std::vector<JointTrajectoryPoint>& points = trajectory.points;
  const int order = !points.front().accelerations.empty() ? 5 : !points.front().velocities.empty() ? 3 : 1;
  if (t <= trajectory.started_at) return {trajectory.start_positions[j], trajectory.start_velocities[j]};
  std::size_t k = 0;
  while (k < points.size() && trajectory.start_time + points[k].time_from_start <= t) ++k;
  if (k == points.size()) return {points.back().positions[j], 0.0};
  const Knot b = knot(trajectory, k, j);
  if (k > 0) return segment(knot(trajectory, k - 1, j), b, order, t);
  // Before the first waypoint: from the joint's state when the trajectory started.
  const Knot a{trajectory.started_at, trajectory.start_positions[j], trajectory.start_velocities[j], 0.0};
  return segment(a, b, order, t);
}

}  // namespace hadal::physics
