#include "hadal/geometry/shape_overlap.h"
#include "hadal/core/units.h"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

namespace hadal::geometry {
namespace {

// Sums over up to ~1e5 cells: rounding well below 1e-10 of the total.
constexpr double kSumRel = 1e-10;
// Results that come from a handful of whole cells (regions equal to the overlap): a few roundings
// plus the corner tests' allowance (32 eps of the coordinates times a cell's surface area).
constexpr double kExactRel = 1e-12;
// The allowance enters the second moment's bound times the search diameter squared, some 10-100
// times |S| / E here, and the centroid's times the diameter over E.
constexpr double kExactSecondMomentRel = 100 * kExactRel;
constexpr double kExactCentroidRel = 10 * kExactRel;
// The centroid's bound at relative_tolerance t is at most this times t times the excess's RMS radius
// sqrt(tr S / E) (0.10-0.19 in these tests, flat faces oblique to B's axes included).
constexpr double kCentroidBoundPerTolerance = 2.5;

using ShapeList = std::vector<std::pair<CollisionShape, Eigen::Isometry3d>>;

CollisionShape box(double x, double y, double z) {
  CollisionShape s;
  s.type = CollisionShapeType::kBox;
  s.box_size = Eigen::Vector3d(x, y, z);
  return s;
}

CollisionShape round_shape(CollisionShapeType type, double radius, double length = 0.0) {
  CollisionShape s;
  s.type = type;
  s.radius = radius;
  s.length = length;
  return s;
}

Eigen::Isometry3d pose(const Eigen::Vector3d& p, const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R;
  X.translation() = p;
  return X;
}

// A rotation with no special alignment, so cell faces meet no shape face by accident.
Eigen::Matrix3d tilted() {
  return Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
}

// Moves every shape by X_AB (the excess is invariant; its centroid moves with it).
ShapeList moved(const ShapeList& shapes, const Eigen::Isometry3d& X_AB) {
  ShapeList out;
  for (const auto& [shape, X_BG] : shapes) out.emplace_back(shape, X_AB * X_BG);
  return out;
}

// Second moments (integral of (x - p)(x - p)^T dV about the centroid p) of solids, in their own
// axes: a box of sides s, V / 12 diag(s_i^2); a ball of radius r, 4 pi r^5 / 15 I; a cylinder of
// radius r and length l along z, V diag(r^2 / 4, r^2 / 4, l^2 / 12).
Eigen::Matrix3d box_second_moment(const Eigen::Vector3d& size) {
  return (size.prod() / 12.0) * size.cwiseAbs2().asDiagonal().toDenseMatrix();
}

Eigen::Matrix3d ball_second_moment(double r) {
  return 4.0 * kPi * std::pow(r, 5) / 15.0 * Eigen::Matrix3d::Identity();
}

Eigen::Matrix3d cylinder_second_moment(double r, double l) {
  return kPi * r * r * l * Eigen::Vector3d(r * r / 4.0, r * r / 4.0, l * l / 12.0).asDiagonal().toDenseMatrix();
}

// S expressed in A when its axes are R_AB.
Eigen::Matrix3d rotated(const Eigen::Matrix3d& R_AB, const Eigen::Matrix3d& S_B) {
  return R_AB * S_B * R_AB.transpose();
}

// The closed-form second moment S (about the exact centroid) taken about r.centroid_B instead:
// S + E dp dp^T, dp = centroid_B - centroid. second_moment_B and its bound are about centroid_B,
// which is off the centroid by at most centroid_error_bound.
Eigen::Matrix3d about_estimate(const OverlapExcess& r, double volume, const Eigen::Vector3d& centroid,
                               const Eigen::Matrix3d& second_moment) {
  const Eigen::Vector3d dp = r.centroid_B - centroid;
  return second_moment + volume * dp * dp.transpose();
}

// The estimate is within its rigorous bound of the closed form, and the bound met the tolerance.
// The centroid's and the second moment's bounds are not refinement targets: the centroid's is
// checked to stay within kCentroidBoundPerTolerance * relative_tolerance of the excess's RMS radius
// (0.25 % at the default 1e-3; it shrinks with the tolerance, h^2), the second moment's below 1 % of
// |S|, the accuracy the hull's inertia-equivalent ellipsoid needs.
void expect_within_bound(const OverlapExcess& r, double volume, const Eigen::Vector3d& centroid,
                         const Eigen::Matrix3d& second_moment,
                         double relative_tolerance = OverlapExcessOptions{}.relative_tolerance) {
  EXPECT_LE(std::abs(r.volume - volume), r.volume_error_bound + kSumRel * volume)
      << "volume " << r.volume << " exact " << volume;
  EXPECT_TRUE(r.converged);
  EXPECT_LE(r.volume_error_bound, relative_tolerance * r.volume * (1 + kSumRel));
  const double rms_radius = std::sqrt(second_moment.trace() / volume);
  EXPECT_LE((r.centroid_B - centroid).norm(), r.centroid_error_bound + kSumRel * rms_radius)
      << "centroid " << r.centroid_B.transpose() << " exact " << centroid.transpose();
  EXPECT_LE(r.centroid_error_bound, kCentroidBoundPerTolerance * relative_tolerance * rms_radius);
  const Eigen::Matrix3d exact = about_estimate(r, volume, centroid, second_moment);
  const double norm = second_moment.norm();
  EXPECT_LE((r.second_moment_B - exact).norm(), r.second_moment_error_bound + kSumRel * norm)
      << "second moment\n" << r.second_moment_B << "\nexact\n" << exact;
  EXPECT_LE(r.second_moment_error_bound, 1e-2 * norm);
  EXPECT_EQ(r.second_moment_B, r.second_moment_B.transpose());
}

// Centroid and second moment from whole cells: exact up to rounding and the corner tests'
// allowance.
void expect_exact_moments(const OverlapExcess& r, double volume, const Eigen::Vector3d& centroid,
                          const Eigen::Matrix3d& second_moment) {
  const double rms_radius = std::sqrt(second_moment.trace() / volume);
  EXPECT_LE((r.centroid_B - centroid).norm(), kExactCentroidRel * rms_radius)
      << "centroid " << r.centroid_B.transpose() << " exact " << centroid.transpose();
  EXPECT_LE(r.centroid_error_bound, kExactCentroidRel * rms_radius);
  const double norm = second_moment.norm();
  EXPECT_LE((r.second_moment_B - second_moment).norm(), kExactSecondMomentRel * norm)
      << "second moment\n" << r.second_moment_B << "\nexact\n" << second_moment;
  EXPECT_LE(r.second_moment_error_bound, kExactSecondMomentRel * norm);
}

TEST(ShapeOverlapTest, ContainsIsExactForEachPrimitive) {
  // Boundaries are inside (closed solids).
  const Eigen::Isometry3d X_BG = pose(Eigen::Vector3d(1.0, 0.0, 0.0));
  const CollisionShape b = box(0.4, 0.2, 0.1);
  EXPECT_TRUE(contains(b, X_BG, Eigen::Vector3d(1.2, 0.1, 0.05)));
  EXPECT_FALSE(contains(b, X_BG, Eigen::Vector3d(1.2, 0.1, 0.0500001)));
  const CollisionShape sphere = round_shape(CollisionShapeType::kSphere, 0.5);
  EXPECT_TRUE(contains(sphere, X_BG, Eigen::Vector3d(1.0, 0.5, 0.0)));
  EXPECT_FALSE(contains(sphere, X_BG, Eigen::Vector3d(1.0, 0.5, 0.001)));

  // Axis along B's x: z_G = x_B after a quarter turn about y.
  const Eigen::Isometry3d X_BA =
      pose(Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix());
  const CollisionShape cylinder = round_shape(CollisionShapeType::kCylinder, 0.2, 1.0);
  EXPECT_TRUE(contains(cylinder, X_BA, Eigen::Vector3d(1.45, 0.1, 0.1)));
  EXPECT_FALSE(contains(cylinder, X_BA, Eigen::Vector3d(1.55, 0.0, 0.0)));    // beyond the cap
  EXPECT_FALSE(contains(cylinder, X_BA, Eigen::Vector3d(1.0, 0.15, 0.15)));   // rho = 0.212
  EXPECT_TRUE(contains(cylinder, X_BA, Eigen::Vector3d(0.55, 0.0, 0.199)));
  const CollisionShape capsule = round_shape(CollisionShapeType::kCapsule, 0.2, 1.0);
  EXPECT_TRUE(contains(capsule, X_BA, Eigen::Vector3d(1.69, 0.0, 0.0)));      // in the hemisphere
  EXPECT_FALSE(contains(capsule, X_BA, Eigen::Vector3d(1.71, 0.0, 0.0)));
  EXPECT_TRUE(contains(capsule, X_BA, Eigen::Vector3d(1.65, 0.1, 0.0)));      // 0.180 from the end
  EXPECT_FALSE(contains(capsule, X_BA, Eigen::Vector3d(1.65, 0.15, 0.0)));    // 0.212 from the end
  EXPECT_TRUE(contains(capsule, X_BA, Eigen::Vector3d(0.31, 0.0, 0.0)));
  EXPECT_FALSE(contains(capsule, X_BA, Eigen::Vector3d(1.0, 0.15, 0.15)));

  // Signed distances: box corner region, cylinder rim, inside a capsule.
  EXPECT_NEAR(signed_distance(b, X_BG, Eigen::Vector3d(1.5, 0.4, 0.05)), std::hypot(0.3, 0.3), 1e-15);
  EXPECT_NEAR(signed_distance(cylinder, X_BA, Eigen::Vector3d(1.8, 0.6, 0.0)), std::hypot(0.3, 0.4), 1e-15);
  EXPECT_NEAR(signed_distance(capsule, X_BA, Eigen::Vector3d(0.9, 0.0, 0.05)), -0.15, 1e-15);
}

TEST(ShapeOverlapTest, BoundingBoxesAreTight) {
  // Cylinder and capsule tilted by theta about y: x extent h sin(theta) + r cos(theta) (the
  // rectangle's / stadium's shadow), y extent r.
  const double r = 0.2, h = 0.5, theta = 0.3;
  const Eigen::Isometry3d X_BG =
      pose(Eigen::Vector3d(1.0, 2.0, 3.0), Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()).toRotationMatrix());
  const Eigen::AlignedBox3d cylinder = bounding_box(round_shape(CollisionShapeType::kCylinder, r, 2 * h), X_BG);
  EXPECT_NEAR(0.5 * cylinder.sizes().x(), h * std::sin(theta) + r * std::cos(theta), 1e-15);
  EXPECT_NEAR(0.5 * cylinder.sizes().y(), r, 1e-15);
  EXPECT_NEAR(0.5 * cylinder.sizes().z(), h * std::cos(theta) + r * std::sin(theta), 1e-15);
  const Eigen::AlignedBox3d capsule = bounding_box(round_shape(CollisionShapeType::kCapsule, r, 2 * h), X_BG);
  EXPECT_NEAR(0.5 * capsule.sizes().x(), h * std::sin(theta) + r, 1e-15);
  EXPECT_NEAR(0.5 * capsule.sizes().z(), h * std::cos(theta) + r, 1e-15);
  EXPECT_TRUE(capsule.center().isApprox(Eigen::Vector3d(1.0, 2.0, 3.0), 1e-15));
}

// Equal spheres of radius R at centre distance d overlap in a lens of volume
// pi (4R + d)(2R - d)^2 / 12, centroid at the midpoint. The lens is a solid of revolution about
// the line of centres: at distance t from the midplane its disc has radius^2 R^2 - s^2, s = |t| + d/2,
// so (closed form, polynomial antiderivatives over s in [d/2, R])
//   along the axis     2 pi integral (s - d/2)^2 (R^2 - s^2) ds,
//   across the axis    2 integral pi (R^2 - s^2)^2 / 4 ds    (a disc's integral x^2 dA is pi rho^4 / 4).
Eigen::Matrix3d lens_second_moment(double R, double d, const Eigen::Vector3d& axis) {
  const double c = 0.5 * d;
  auto along = [&](double s) {  // antiderivative of (s - c)^2 (R^2 - s^2)
    return R * R * std::pow(s, 3) / 3 - std::pow(s, 5) / 5 - c * R * R * s * s + c * std::pow(s, 4) / 2 +
           c * c * R * R * s - c * c * std::pow(s, 3) / 3;
  };
  auto across = [&](double s) {  // antiderivative of (R^2 - s^2)^2
    return std::pow(R, 4) * s - 2 * R * R * std::pow(s, 3) / 3 + std::pow(s, 5) / 5;
  };
  const double s_axis = 2 * kPi * (along(R) - along(c));
  const double s_across = 0.5 * kPi * (across(R) - across(c));
  const Eigen::Matrix3d aa = axis * axis.transpose();
  return s_axis * aa + s_across * (Eigen::Matrix3d::Identity() - aa);
}

TEST(ShapeOverlapTest, TwoSpheresOverlapInTheLens) {
  const double R = 0.1;
  const CollisionShape sphere = round_shape(CollisionShapeType::kSphere, R);
  const Eigen::Vector3d p_BA(0.3, -0.2, 0.05), axis = Eigen::Vector3d(1.0, 2.0, 3.0).normalized();
  // The closed form at d = 0 is the whole ball.
  EXPECT_TRUE(lens_second_moment(R, 0.0, axis).isApprox(ball_second_moment(R), 1e-14));
  for (double d : {0.02, 0.1, 0.17}) {
    SCOPED_TRACE(d);
    const OverlapExcess r = overlap_excess({{sphere, pose(p_BA)}, {sphere, pose(p_BA + d * axis)}});
    expect_within_bound(r, kPi * (4 * R + d) * (2 * R - d) * (2 * R - d) / 12, p_BA + 0.5 * d * axis,
                        lens_second_moment(R, d, axis));
    EXPECT_EQ(r.overlapping_pairs, (std::vector<std::pair<int, int>>{{0, 1}}));
  }
}

TEST(ShapeOverlapTest, SphereInsideSphereExcessIsTheInnerBall) {
  const Eigen::Vector3d p_BI(0.25, -0.1, 0.3);
  const ShapeList shapes = {{round_shape(CollisionShapeType::kSphere, 0.3), pose(Eigen::Vector3d(0.3, 0.0, 0.2))},
                            {round_shape(CollisionShapeType::kSphere, 0.12), pose(p_BI)}};
  expect_within_bound(overlap_excess(shapes), 4 * kPi * std::pow(0.12, 3) / 3, p_BI, ball_second_moment(0.12));
}

TEST(ShapeOverlapTest, BoxInsideBoxExcessIsTheInnerVolume) {
  const CollisionShape outer = box(1.0, 0.8, 0.6), inner = box(0.3, 0.2, 0.1);
  const Eigen::Vector3d p_BI(0.1, -0.2, 0.05);
  // Aligned: the search region is the inner box itself, one cell inside both.
  const OverlapExcess aligned =
      overlap_excess({{outer, pose(Eigen::Vector3d::Zero())}, {inner, pose(p_BI)}});
  EXPECT_NEAR(aligned.volume, 0.006, kExactRel * 0.006);
  EXPECT_LE(aligned.volume_error_bound, kExactRel * 0.006);
  expect_exact_moments(aligned, 0.006, p_BI, box_second_moment(inner.box_size));
  EXPECT_EQ(aligned.overlapping_pairs, (std::vector<std::pair<int, int>>{{0, 1}}));
  // Tilted inner box, still inside (its half-diagonal 0.187 < 0.2, its centre's distance to the
  // nearest outer face).
  const OverlapExcess tilted_inner =
      overlap_excess({{outer, pose(Eigen::Vector3d::Zero())}, {inner, pose(p_BI, tilted())}});
  expect_within_bound(tilted_inner, 0.006, p_BI, rotated(tilted(), box_second_moment(inner.box_size)));
}

// Aligned boxes overlapping in a slab: x [0.45, 0.5], y [-0.3, 0.3], z [-0.1, 0.2].
TEST(ShapeOverlapTest, AlignedBoxesOverlapInAnExactSlab) {
  const ShapeList shapes = {{box(1.0, 0.6, 0.4), pose(Eigen::Vector3d::Zero())},
                            {box(0.5, 0.8, 0.3), pose(Eigen::Vector3d(0.7, 0.1, 0.05))}};
  const double volume = 0.05 * 0.6 * 0.3;
  const Eigen::Vector3d centroid(0.475, 0.0, 0.05);
  const Eigen::Matrix3d second_moment = box_second_moment(Eigen::Vector3d(0.05, 0.6, 0.3));
  const OverlapExcess r = overlap_excess(shapes);
  EXPECT_NEAR(r.volume, volume, kExactRel * volume);
  EXPECT_LE(r.volume_error_bound, kExactRel * volume);
  expect_exact_moments(r, volume, centroid, second_moment);
  // The same pair turned and moved: faces no longer align with the cells. The cells cut by one face
  // alone are never refined; their moments are exact (clipped), so the centroid is as good as
  // elsewhere.
  const Eigen::Isometry3d X_AB = pose(Eigen::Vector3d(-2.0, 1.0, 0.5), tilted());
  expect_within_bound(overlap_excess(moved(shapes, X_AB)), volume, X_AB * centroid,
                      rotated(X_AB.linear(), second_moment));
}

// Boxes 0.2 x 0.1 x 0.1 at x = 0 and x = 0.15 share four face planes along the overlap
// [0.05, 0.1] x 0.1 x 0.1: cells there are cut by two coplanar faces and contain neither box, and
// their moments come from a cell clipped twice by the same plane (the second cut once left the first
// one's face broken: 0.18 % off in S against a bound of 0.033 % at this tolerance).
TEST(ShapeOverlapTest, TiltedBoxesWithCoplanarFaces) {
  const CollisionShape b = box(0.2, 0.1, 0.1);
  const ShapeList shapes = {{b, pose(Eigen::Vector3d::Zero())}, {b, pose(Eigen::Vector3d(0.15, 0.0, 0.0))}};
  const double volume = 0.05 * 0.1 * 0.1;
  const Eigen::Vector3d centroid(0.075, 0.0, 0.0);
  const Eigen::Matrix3d second_moment = box_second_moment(Eigen::Vector3d(0.05, 0.1, 0.1));
  const OverlapExcess aligned = overlap_excess(shapes);
  EXPECT_NEAR(aligned.volume, volume, kExactRel * volume);
  expect_exact_moments(aligned, volume, centroid, second_moment);
  const Eigen::Isometry3d X_AB = pose(Eigen::Vector3d(1.0, 2.0, 3.0), tilted());
  OverlapExcessOptions options;
  options.relative_tolerance = 1e-4;
  expect_within_bound(overlap_excess(moved(shapes, X_AB), options), volume, X_AB * centroid,
                      rotated(X_AB.linear(), second_moment), options.relative_tolerance);
}

TEST(ShapeOverlapTest, DisjointShapesGiveExactlyZero) {
  const CollisionShape sphere = round_shape(CollisionShapeType::kSphere, 1.0);
  // Bounding boxes apart: nothing is searched.
  const OverlapExcess apart = overlap_excess({{sphere, pose(Eigen::Vector3d::Zero())},
                                              {box(1.0, 1.0, 1.0), pose(Eigen::Vector3d(1.6, 0.0, 0.0))}});
  EXPECT_EQ(apart.volume, 0.0);
  EXPECT_EQ(apart.volume_error_bound, 0.0);
  EXPECT_EQ(apart.second_moment_B, Eigen::Matrix3d::Zero());
  EXPECT_EQ(apart.second_moment_error_bound, 0.0);
  EXPECT_EQ(apart.cells_evaluated, 0u);
  EXPECT_TRUE(apart.overlapping_pairs.empty());
  // Bounding boxes overlap ([0.5, 1]^3) but the spheres are 0.6 apart along the diagonal: every
  // cell is eventually shown to miss one of them.
  const OverlapExcess diagonal = overlap_excess({{sphere, pose(Eigen::Vector3d::Zero())},
                                                 {sphere, pose(Eigen::Vector3d::Constant(1.5))}});
  EXPECT_EQ(diagonal.volume, 0.0);
  EXPECT_EQ(diagonal.volume_error_bound, 0.0);
  EXPECT_EQ(diagonal.second_moment_B, Eigen::Matrix3d::Zero());
  EXPECT_EQ(diagonal.second_moment_error_bound, 0.0);
  EXPECT_TRUE(diagonal.converged);
  EXPECT_GT(diagonal.cells_evaluated, 0u);
  EXPECT_TRUE(diagonal.overlapping_pairs.empty());
  EXPECT_EQ(overlap_excess({}).volume, 0.0);
  EXPECT_EQ(overlap_excess({{sphere, pose(Eigen::Vector3d::Zero())}}).volume, 0.0);
}

TEST(ShapeOverlapTest, CylinderAndCapsuleOverlaps) {
  const double R = 0.1;
  const Eigen::Isometry3d X_AB = pose(Eigen::Vector3d(0.4, -0.3, -1.0), tilted());
  const Eigen::Matrix3d z_to_x = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Matrix3d z_to_y = Eigen::AngleAxisd(-kPi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Matrix3d R_AB = X_AB.linear();
  {
    // Perpendicular cylinders of radius R along x and y: 16 R^3 / 3. The section at height z is a
    // square of half side w = sqrt(R^2 - z^2), so integral z^2 dV = integral 4 w^2 z^2 dz =
    // 16 R^5 / 15 and integral x^2 dV = integral 4 w^4 / 3 dz = 64 R^5 / 45.
    SCOPED_TRACE("Steinmetz solid");
    const CollisionShape cylinder = round_shape(CollisionShapeType::kCylinder, R, 0.5);
    const ShapeList shapes = {{cylinder, pose(Eigen::Vector3d::Zero(), z_to_x)},
                              {cylinder, pose(Eigen::Vector3d::Zero(), z_to_y)}};
    const Eigen::Matrix3d second_moment =
        std::pow(R, 5) * Eigen::Vector3d(64.0 / 45, 64.0 / 45, 16.0 / 15).asDiagonal().toDenseMatrix();
    expect_within_bound(overlap_excess(moved(shapes, X_AB)), 16 * R * R * R / 3, X_AB.translation(),
                        rotated(R_AB, second_moment));
  }
  {
    // Vertical capsule (centre z = 0.15, length 0.4) through the top face z = 0 of a large box:
    // below it the lower hemisphere (centroid 3R/8 below its centre z = -0.05) and the cylinder
    // z in [-0.05, 0]. The face is oblique to B's axes; the centroid is checked to 0.25 % of the
    // RMS radius (0.19 mm) like the others.
    SCOPED_TRACE("capsule through a box face");
    const ShapeList shapes = {{round_shape(CollisionShapeType::kCapsule, R, 0.4), pose(Eigen::Vector3d(0.0, 0.0, 0.15))},
                              {box(1.0, 1.0, 1.0), pose(Eigen::Vector3d(0.0, 0.0, -0.5))}};
    const double hemisphere = 2 * kPi * R * R * R / 3, band = kPi * R * R * 0.05;
    const double z = (hemisphere * (-0.05 - 3 * R / 8) + band * (-0.025)) / (hemisphere + band);
    // Second moments: a hemisphere has integral w^2 dV = integral x^2 dV = 2 pi R^5 / 15 about its
    // flat face's centre (half the ball's), and integral w dV = -3 R / 8 times its volume.
    const double z0 = -0.05;
    const double zz = 2 * kPi * std::pow(R, 5) / 15 - 2 * z0 * (3 * R / 8) * hemisphere + z0 * z0 * hemisphere +
                      kPi * R * R * std::pow(0.05, 3) / 3 - (hemisphere + band) * z * z;
    const double xx = 2 * kPi * std::pow(R, 5) / 15 + band * R * R / 4;
    expect_within_bound(overlap_excess(moved(shapes, X_AB)), hemisphere + band, X_AB * Eigen::Vector3d(0.0, 0.0, z),
                        rotated(R_AB, Eigen::Vector3d(xx, xx, zz).asDiagonal().toDenseMatrix()));
  }
  {
    SCOPED_TRACE("sphere inside a capsule's end");
    const ShapeList shapes = {{round_shape(CollisionShapeType::kCapsule, R, 0.4), pose(Eigen::Vector3d::Zero(), z_to_x)},
                              {round_shape(CollisionShapeType::kSphere, R), pose(Eigen::Vector3d(0.2, 0.0, 0.0))}};
    expect_within_bound(overlap_excess(moved(shapes, X_AB)), 4 * kPi * R * R * R / 3,
                        X_AB * Eigen::Vector3d(0.2, 0.0, 0.0), ball_second_moment(R));
  }
  {
    SCOPED_TRACE("cylinder inside a box");
    const ShapeList shapes = {{box(0.6, 0.3, 0.3), pose(Eigen::Vector3d::Zero())},
                              {round_shape(CollisionShapeType::kCylinder, R, 0.5), pose(Eigen::Vector3d(0.02, 0.01, 0.0), z_to_x)}};
    expect_within_bound(overlap_excess(moved(shapes, X_AB)), kPi * R * R * 0.5, X_AB * Eigen::Vector3d(0.02, 0.01, 0.0),
                        rotated(R_AB * z_to_x, cylinder_second_moment(R, 0.5)));
  }
}

// Integral of (x - o)(x - o)^T dV over the box [lo, hi].
Eigen::Matrix3d box_raw_second_moment(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                      const Eigen::Vector3d& o) {
  const Eigen::Vector3d c = 0.5 * (lo + hi) - o;
  return (hi - lo).prod() * (c * c.transpose()) + box_second_moment(hi - lo);
}

// Where three shapes overlap the integrand is 2. For three sets max(count - 1, 0) =
// sum over pairs of 1_i 1_j - 1_1 1_2 1_3, so E = sum V_ij - V_123 (and the same for moments).
TEST(ShapeOverlapTest, TripleOverlapCountsTwice) {
  {
    SCOPED_TRACE("concentric spheres");  // count 3 inside r = 0.1, 2 out to r = 0.2
    const Eigen::Vector3d c(0.1, 0.2, -0.3);
    const ShapeList shapes = {{round_shape(CollisionShapeType::kSphere, 0.3), pose(c)},
                              {round_shape(CollisionShapeType::kSphere, 0.2), pose(c)},
                              {round_shape(CollisionShapeType::kSphere, 0.1), pose(c)}};
    const OverlapExcess r = overlap_excess(shapes);
    expect_within_bound(r, 4 * kPi / 3 * (0.2 * 0.2 * 0.2 + 0.1 * 0.1 * 0.1), c,
                        ball_second_moment(0.2) + ball_second_moment(0.1));
    EXPECT_EQ(r.overlapping_pairs, (std::vector<std::pair<int, int>>{{0, 1}, {0, 2}, {1, 2}}));
  }
  // Boxes A = [0,2]x[0,2]x[0,2], B = [1,3]x[0,2]x[0,2], C = [0.5,1.5]x[0.5,1.5]x[1,3] (scaled by
  // 0.1): AB = [1,2]x[0,2]x[0,2], AC = [0.5,1.5]x[0.5,1.5]x[1,2], BC = ABC = [1,1.5]x[0.5,1.5]x[1,2].
  // Their search regions overlap, so this also checks that no region is counted twice.
  const double s = 0.1;
  const ShapeList shapes = {{box(2 * s, 2 * s, 2 * s), pose(s * Eigen::Vector3d(1.0, 1.0, 1.0))},
                            {box(2 * s, 2 * s, 2 * s), pose(s * Eigen::Vector3d(2.0, 1.0, 1.0))},
                            {box(1 * s, 1 * s, 2 * s), pose(s * Eigen::Vector3d(1.0, 1.0, 2.0))}};
  const double v_ab = 4, v_ac = 1, v_bc = 0.5, v_abc = 0.5;
  const Eigen::Vector3d c_ab(1.5, 1.0, 1.0), c_ac(1.0, 1.0, 1.5), c_bc(1.25, 1.0, 1.5);
  const double volume = (v_ab + v_ac + v_bc - v_abc) * s * s * s;
  const Eigen::Vector3d centroid = s * (v_ab * c_ab + v_ac * c_ac + v_bc * c_bc - v_abc * c_bc) /
                                   (v_ab + v_ac + v_bc - v_abc);
  const Eigen::Matrix3d second_moment =  // about the centroid: AB + AC (BC and ABC cancel)
      box_raw_second_moment(s * Eigen::Vector3d(1.0, 0.0, 0.0), s * Eigen::Vector3d(2.0, 2.0, 2.0), centroid) +
      box_raw_second_moment(s * Eigen::Vector3d(0.5, 0.5, 1.0), s * Eigen::Vector3d(1.5, 1.5, 2.0), centroid);
  const OverlapExcess r = overlap_excess(shapes);
  EXPECT_NEAR(r.volume, volume, kExactRel * volume);
  EXPECT_LE(r.volume_error_bound, kExactRel * volume);
  expect_exact_moments(r, volume, centroid, second_moment);
  EXPECT_EQ(r.overlapping_pairs, (std::vector<std::pair<int, int>>{{0, 1}, {0, 2}, {1, 2}}));
  // Turned: every face oblique to the cells (A and B also share four face planes).
  const Eigen::Isometry3d X_AB = pose(Eigen::Vector3d(1.0, 2.0, 3.0), tilted());
  expect_within_bound(overlap_excess(moved(shapes, X_AB)), volume, X_AB * centroid,
                      rotated(X_AB.linear(), second_moment));
}

TEST(ShapeOverlapTest, OverlappingPairsNameOnlyShapesThatOverlap) {
  // 0-1 and 1-2 overlap; 3's bounding box overlaps 0's but the spheres are 0.012 apart (and it
  // only touches 1's box).
  const ShapeList shapes = {{round_shape(CollisionShapeType::kSphere, 0.1), pose(Eigen::Vector3d::Zero())},
                            {box(0.2, 0.1, 0.1), pose(Eigen::Vector3d(0.15, 0.0, 0.0))},
                            {round_shape(CollisionShapeType::kCylinder, 0.05, 0.2), pose(Eigen::Vector3d(0.28, 0.0, 0.0))},
                            {round_shape(CollisionShapeType::kSphere, 0.1), pose(Eigen::Vector3d(0.0, 0.15, 0.15))}};
  const OverlapExcess r = overlap_excess(shapes);
  EXPECT_EQ(r.overlapping_pairs, (std::vector<std::pair<int, int>>{{0, 1}, {1, 2}}));
  EXPECT_GT(r.volume, 0.0);
}

TEST(ShapeOverlapTest, CellBudgetKeepsTheBoundValid) {
  const double R = 0.1, d = 0.1;
  const CollisionShape sphere = round_shape(CollisionShapeType::kSphere, R);
  const ShapeList shapes = {{sphere, pose(Eigen::Vector3d::Zero(), tilted())}, {sphere, pose(Eigen::Vector3d(d, 0.0, 0.0))}};
  const double volume = kPi * (4 * R + d) * (2 * R - d) * (2 * R - d) / 12;
  OverlapExcessOptions options;
  options.max_cells = 500;
  const OverlapExcess coarse = overlap_excess(shapes, options);
  EXPECT_FALSE(coarse.converged);
  EXPECT_LE(coarse.cells_evaluated, options.max_cells);
  EXPECT_LE(std::abs(coarse.volume - volume), coarse.volume_error_bound);
  EXPECT_LE((coarse.centroid_B - Eigen::Vector3d(0.5 * d, 0.0, 0.0)).norm(), coarse.centroid_error_bound);
  const Eigen::Matrix3d second_moment = lens_second_moment(R, d, Eigen::Vector3d::UnitX());
  const Eigen::Vector3d centroid(0.5 * d, 0.0, 0.0);
  EXPECT_LE((coarse.second_moment_B - about_estimate(coarse, volume, centroid, second_moment)).norm(),
            coarse.second_moment_error_bound);
  // Tighter tolerance, more cells, smaller bound; same inputs, bit-identical output.
  options.max_cells = 1000000;
  options.relative_tolerance = 1e-4;
  const OverlapExcess fine = overlap_excess(shapes, options);
  EXPECT_TRUE(fine.converged);
  EXPECT_LE(std::abs(fine.volume - volume), fine.volume_error_bound);
  EXPECT_LE(fine.volume_error_bound, 1e-4 * fine.volume);
  EXPECT_LE((fine.second_moment_B - about_estimate(fine, volume, centroid, second_moment)).norm(),
            fine.second_moment_error_bound);
  EXPECT_LE(fine.second_moment_error_bound, 1e-3 * second_moment.norm());
  EXPECT_LT(fine.second_moment_error_bound, coarse.second_moment_error_bound);
  EXPECT_LE((fine.centroid_B - centroid).norm(), fine.centroid_error_bound);
  EXPECT_LE(fine.centroid_error_bound, kCentroidBoundPerTolerance * 1e-4 * std::sqrt(second_moment.trace() / volume));
  EXPECT_LT(fine.centroid_error_bound, coarse.centroid_error_bound);
  const OverlapExcess again = overlap_excess(shapes, options);
  EXPECT_EQ(again.volume, fine.volume);
  EXPECT_EQ(again.centroid_B, fine.centroid_B);
  EXPECT_EQ(again.second_moment_B, fine.second_moment_B);
}

}  // namespace
}  // namespace hadal::geometry
