// A camera's rays cast with real Embree: frame conventions, the depth image against the closed form, and
// points of the scene found where OpenCV projects them.
#include "hadal/render/camera_rays.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/geometry/embree_scene.h"
#include "render_test_support.h"

namespace hadal::render {
namespace {

using geometry::EmbreeScene;
using geometry::RayBatch;
using geometry::RayHits;

// A wall perpendicular to x_W at x = wall_x [m], 400 m square, facing -x (towards the camera).
EmbreeScene wall_at(float wall_x) {
  EmbreeScene scene;
  scene.add_static_mesh(testing::plate(wall_x, 0.0f, 0.0f, 200.0f), 0, "wall");
  scene.build();
  return scene;
}

RayHits cast(const EmbreeScene& scene, const RayBatch& batch) {
  RayHits hits;
  hits.resize(batch.size());
  scene.intersect(batch, 0, batch.size(), geometry::QueryPath::kAuto, hits);
  return hits;
}

using testing::barrel_lens;
using testing::fisheye_lens;

TEST(CameraRaysTest, OpticalFrameLooksAlongTheSensorsXAxis) {
  const Eigen::Isometry3d X = X_SC();
  EXPECT_TRUE((X.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX()));   // forward
  EXPECT_TRUE((X.linear() * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitY()));  // right
  EXPECT_TRUE((X.linear() * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitZ()));  // down
  EXPECT_NEAR(X.linear().determinant(), 1.0, 1e-15);
}

// A camera at the origin looking along x_W (X_WS = identity) at a wall 10 m ahead: every pixel's depth
// is 10 m (the wall is perpendicular to the optical axis). Tolerance 1e-4 m: Embree's hit distance and
// the product with the float ray's z are float arithmetic, a few ulps of 10 m (~1e-6 m each).
// Up-left in the world (y_W > 0, z_W > 0) is up-left in the image (u < cx, v < cy).
TEST(CameraRaysTest, DepthOfAWallIsItsDistanceAlongTheAxis) {
  const EmbreeScene scene = wall_at(10.0f);
  for (const LensSpec& spec : {barrel_lens(), fisheye_lens()}) {
    const Lens lens = make_lens(spec);
    RayBatch batch;
    add_camera_rays(lens, X_SC(), 0.1f, 1000.0f, geometry::kNoHit, batch);
    ASSERT_EQ(batch.size(), 640u * 480u);
    const RayHits hits = cast(scene, batch);
    const std::vector<float> depth = depth_image_m(lens, hits, 0);
    for (std::size_t i = 0; i < depth.size(); ++i) ASSERT_NEAR(depth[i], 10.0f, 1e-4f) << i;
    // The hit point of pixel (0, 0) lies up (z_W > 0) and left (y_W > 0) of the axis.
    const float t = hits.distance[0];
    EXPECT_GT(batch.d_W_y[0] * t, 1.0f);
    EXPECT_GT(batch.d_W_z[0] * t, 1.0f);
  }
}

// Nothing within the clip, or a fisheye's rays that leave behind the image plane: NaN depth.
TEST(CameraRaysTest, MissesAndClippedHitsHaveNoDepth) {
  const EmbreeScene scene = wall_at(10.0f);
  const Lens lens = make_lens(barrel_lens());
  RayBatch batch;
  add_camera_rays(lens, X_SC(), 0.1f, 9.0f, geometry::kNoHit, batch);  // the wall is beyond far
  const std::vector<float> depth = depth_image_m(lens, cast(scene, batch), 0);
  for (float d : depth) ASSERT_TRUE(std::isnan(d));
  EXPECT_THROW(add_camera_rays(lens, X_SC(), 2.0f, 1.0f, geometry::kNoHit, batch), std::invalid_argument);
}

// Points of the scene appear where cv::projectPoints puts them (issue 11's projection criterion,
// 0.1 px). The camera is tilted and displaced; for each of 35 points on the wall the sub-pixel position
// in the rendered hit map is found from the nearest pixel's hit and the local derivatives of the hit
// point over u and v (central differences; the map's curvature over half a pixel is ~1e-4 px), and
// compared with OpenCV's projection of the same point given in C.
TEST(CameraRaysTest, ScenePointsAppearWhereOpenCVProjectsThem) {
  const EmbreeScene scene = wall_at(12.0f);
  for (const LensSpec& spec : {LensSpec{}, barrel_lens(), fisheye_lens()}) {
    const Lens lens = make_lens(spec);
    Eigen::Isometry3d X_WS = Eigen::Isometry3d::Identity();
    X_WS.translate(Eigen::Vector3d(1.0, -0.5, 0.3));
    X_WS.rotate(Eigen::AngleAxisd(10.0 * kDegToRad, Eigen::Vector3d::UnitZ()));
    X_WS.rotate(Eigen::AngleAxisd(-5.0 * kDegToRad, Eigen::Vector3d::UnitY()));
    const Eigen::Isometry3d X_WC = X_WS * X_SC();
    RayBatch batch;
    add_camera_rays(lens, X_WC, 0.0f, std::numeric_limits<float>::infinity(), geometry::kNoHit, batch);
    const RayHits hits = cast(scene, batch);
    const int W = lens.width_px(), H = lens.height_px();
    const auto hit_W = [&](int u, int v) {
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      const double t = hits.distance[i];
      return Eigen::Vector3d(batch.p_WO_x[i] + t * batch.d_W_x[i], batch.p_WO_y[i] + t * batch.d_W_y[i],
                             batch.p_WO_z[i] + t * batch.d_W_z[i]);
    };
    std::vector<cv::Point3d> points_C;
    std::vector<Eigen::Vector2d> found;
    for (int a = -3; a <= 3; ++a) {
      for (int b = -2; b <= 2; ++b) {
        const Eigen::Vector3d q_W(12.0, 1.3 * a - 0.2, 1.1 * b + 0.4);
        // Nearest pixel by its hit point (coarse search, then every pixel nearby).
        int best_u = 1, best_v = 1;
        double best = std::numeric_limits<double>::infinity();
        for (int v = 1; v < H - 1; ++v) {
          for (int u = 1; u < W - 1; ++u) {
            const double d = (hit_W(u, v) - q_W).squaredNorm();
            if (d < best) best = d, best_u = u, best_v = v;
          }
        }
        const Eigen::Vector3d p0 = hit_W(best_u, best_v);
        Eigen::Matrix<double, 3, 2> J;
        J.col(0) = 0.5 * (hit_W(best_u + 1, best_v) - hit_W(best_u - 1, best_v));
        J.col(1) = 0.5 * (hit_W(best_u, best_v + 1) - hit_W(best_u, best_v - 1));
        const Eigen::Vector2d duv = J.colPivHouseholderQr().solve(q_W - p0);
        found.emplace_back(best_u + duv.x(), best_v + duv.y());
        const Eigen::Vector3d q_C = X_WC.inverse() * q_W;
        points_C.emplace_back(q_C.x(), q_C.y(), q_C.z());
      }
    }
    const std::vector<cv::Point2d> expected = testing::opencv_project(spec, points_C);
    double worst = 0.0;
    for (std::size_t i = 0; i < found.size(); ++i) {
      ASSERT_GT(expected[i].x, 1.0);
      ASSERT_LT(expected[i].x, W - 2.0);
      ASSERT_GT(expected[i].y, 1.0);
      ASSERT_LT(expected[i].y, H - 2.0);
      worst = std::max({worst, std::abs(found[i].x() - expected[i].x), std::abs(found[i].y() - expected[i].y)});
    }
    EXPECT_LT(worst, 0.1) << to_string(spec.model);
    RecordProperty("worst_px_" + std::string(to_string(spec.model)), std::to_string(worst));
    std::printf("%s: worst |found - cv::projectPoints| = %.2e px over %zu points\n",
                std::string(to_string(spec.model)).c_str(), worst, found.size());
  }
}

}  // namespace
}  // namespace hadal::render
