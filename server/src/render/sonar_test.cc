#include "hadal/render/sonar.h"

#include <gtest/gtest.h>

#include <atomic>
#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/geometry/embree_scene.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/geometry/ray_batch.h"
#include "render_test_support.h"

namespace hadal::render {
namespace {

using geometry::EmbreeScene;
using geometry::TriangleMesh;

constexpr float kMu = 0.01f;  // Lambert's mu of every surface here (-20 dB)

const BackscatterOfHits kUniformMu = [](const geometry::RayHits& hits, std::size_t count, float* mu) {
  for (std::size_t i = 0; i < count; ++i) mu[i] = hits.hit(i) ? kMu : 0.0f;
};

TriangleMesh sphere(const Eigen::Vector3d& centre, double radius) {
  CollisionShape shape;
  shape.type = CollisionShapeType::kSphere;
  shape.radius = radius;
  TriangleMesh out;
  geometry::append_transformed(geometry::tessellate(shape, 128), Eigen::Isometry3d(Eigen::Translation3d(centre)), &out);
  return out;
}

TriangleMesh box(const Eigen::Vector3d& centre, const Eigen::Vector3d& size) {
  CollisionShape shape;
  shape.type = CollisionShapeType::kBox;
  shape.box_size = size;
  TriangleMesh out;
  geometry::append_transformed(geometry::tessellate(shape), Eigen::Isometry3d(Eigen::Translation3d(centre)), &out);
  return out;
}

// The plane z = z0 (a 1 km square), facing up.
TriangleMesh floor_at(float z0) {
  TriangleMesh m;
  m.positions = {-500.0f, -500.0f, z0, 500.0f, -500.0f, z0, 500.0f, 500.0f, z0, -500.0f, 500.0f, z0};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

EmbreeScene scene_of(const std::vector<TriangleMesh>& meshes) {
  EmbreeScene scene;
  for (const TriangleMesh& mesh : meshes) scene.add_static_mesh(mesh);
  scene.build();
  return scene;
}

// A fan of `count` beams over `fov` about z_S from x_S, each w_u wide in the fan and w_v across it,
// the fan tilted down about y_S by `tilt` [rad].
std::vector<SonarBeam> fan(int count, double fov, double w_u, double w_v, double tilt = 0.0) {
  std::vector<SonarBeam> beams = fan_beams(count, fov, w_u, w_v);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (SonarBeam& b : beams) {
    b.axis_S = R * b.axis_S;
    b.u_S = R * b.u_S;
  }
  return beams;
}

// Noise-free: no speckle, no receiver noise, so intensities are the sonar equation's.
SonarPingSpec quiet(SonarPingSpec spec) {
  spec.speckle = false;
  spec.receiver_noise = false;
  return spec;
}

struct Image {
  int beams = 0, bins = 0;
  std::vector<float> intensity, mean_a;
  float at(int k, int b) const { return intensity[static_cast<std::size_t>(k * bins + b)]; }
};

Image ping_image(const EmbreeScene& scene, const SonarPingSpec& spec, const Eigen::Isometry3d& X_WS,
                 const SonarWater& water = {}, std::uint64_t ping_index = 0, const ParallelFor& parallel = serial_for) {
  Image image;
  image.beams = static_cast<int>(spec.beams.size());
  image.bins = spec.bins;
  image.intensity.assign(static_cast<std::size_t>(image.beams * image.bins), -1.0f);
  image.mean_a.assign(image.intensity.size(), 0.0f);
  ping(scene, spec, X_WS, geometry::kNoHit, water, kUniformMu, 7, ping_index, parallel, [&](const BeamEcho& echo) {
    for (int b = 0; b < echo.bins; ++b) {
      image.intensity[static_cast<std::size_t>(echo.beam * echo.bins + b)] = echo.intensity[b];
      image.mean_a[static_cast<std::size_t>(echo.beam * echo.bins + b)] = echo.mean_offset_u_rad[b];
    }
  });
  return image;
}

TEST(SonarTest, RaysSpanTheBeamAndThePatternIsMinus3DbAtItsEdges) {
  SonarBeam beam = fan(1, 0.0, 0.02, 0.3, 0.2)[0];
  EXPECT_NEAR(beam.direction_S(0.0, 0.0).dot(beam.axis_S), 1.0, 1e-12);
  EXPECT_NEAR(std::acos(beam.direction_S(0.01, 0.0).dot(beam.axis_S)), 0.01, 1e-12);
  EXPECT_NEAR(std::acos(beam.direction_S(0.0, -0.15).dot(beam.axis_S)), 0.15, 1e-12);
  EXPECT_NEAR(beam.direction_S(0.3, 0.4).norm(), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(beam.pattern(0.0, 0.0), 1.0);
  EXPECT_NEAR(10.0 * std::log10(beam.pattern(0.01, 0.0)), -3.0103, 1e-4);
  EXPECT_NEAR(10.0 * std::log10(beam.pattern(0.0, 0.15)), -3.0103, 1e-4);
}

TEST(SonarTest, InvalidSpecsAreRefusedWithTheReason) {
  SonarPingSpec spec;
  EXPECT_THROW(spec.validate(), std::invalid_argument);  // no beams
  spec.beams = fan(4, 1.0, 0.01, 0.2);
  EXPECT_NO_THROW(spec.validate());
  spec.beams[2].u_S = spec.beams[2].axis_S;
  try {
    spec.validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("beam 2"), std::string::npos) << e.what();
  }
  spec.beams = fan(4, 1.0, 0.01, 0.2);
  spec.max_range = spec.min_range;
  EXPECT_THROW(spec.validate(), std::invalid_argument);
}

// A sphere at known range and bearing is brightest in the beam that contains its bearing, and its echo
// starts in the bin of its front surface's range (geometry alone: the ray on the centre line returns first).
TEST(SonarTest, SphereAppearsAtItsRangeAndBearingBin) {
  SonarPingSpec spec;
  spec.beams = fan(128, 90.0 * kDegToRad, 90.0 / 128.0 * kDegToRad, 20.0 * kDegToRad);
  spec.min_range = 1.0;
  spec.max_range = 30.0;
  spec.bins = 580;  // 5 cm
  spec.rays_u = 4;
  spec.rays_v = 64;
  const double bearing = 17.3 * kDegToRad, range = 12.34, radius = 0.15;
  const Eigen::Vector3d centre = range * Eigen::Vector3d(std::cos(bearing), std::sin(bearing), 0.0);
  const EmbreeScene scene = scene_of({sphere(centre, radius)});
  const Image image = ping_image(scene, quiet(spec), Eigen::Isometry3d::Identity());
  int best_k = 0, best_b = 0;
  for (int k = 0; k < image.beams; ++k) {
    for (int b = 0; b < image.bins; ++b) {
      if (image.at(k, b) > image.at(best_k, best_b)) {
        best_k = k;
        best_b = b;
      }
    }
  }
  const int expected_beam = static_cast<int>(std::floor((bearing + 45.0 * kDegToRad) / (90.0 * kDegToRad) * 128));
  EXPECT_EQ(best_k, expected_beam);
  // The echo starts in the bin of the front surface's range; it peaks there or in the next bin (a spherical
  // zone's area grows with its depth into the sphere, 2 pi rho dh, while cos theta falls slowly).
  int leading = 0;
  while (image.at(best_k, leading) == 0.0f) ++leading;
  EXPECT_EQ(leading, spec.bin_of(range - radius));
  EXPECT_GE(best_b, leading);
  EXPECT_LE(best_b, leading + 1);
  EXPECT_GT(image.at(best_k, best_b), 0.0f);
  // Nothing else is there: every cell more than a beam and 5 bins away is empty.
  for (int k = 0; k < image.beams; ++k) {
    for (int b = 0; b < image.bins; ++b) {
      if (std::abs(k - best_k) > 1 || std::abs(b - best_b) > 5) {
        ASSERT_EQ(image.at(k, b), 0.0f) << k << " " << b;
      }
    }
  }
}

// The sphere's echo summed over its cells, with the TVG removed, against the closed form: the integral over
// the sphere's front of SL W mu cos(theta) 10^(-2 TL(r) / 10) r^2 dOmega, taken by quadrature over the angle
// psi off the beam's axis (r(psi) and theta(psi) exact; W = 2^(-4 psi^2 / w^2), the beam being round,
// w_u = w_v). Tolerance 1 dB (the issue's); the sampling of the sphere's disk by a 256 x 256 grid over
// the beam (>= 250 rays on it at 40 m: a few per cent), its 128-segment tessellation (< 1 %) and the loss's
// interpolation within a 2 cm bin (< 0.01 %) stay well inside it.
TEST(SonarTest, EchoFallsWithRangeAsSpreadingAndAbsorptionAfterTvgRemoval) {
  const double width = 10.0 * kDegToRad, radius = 0.25;
  SonarPingSpec spec;
  spec.beams = fan(1, 0.0, width, width);
  spec.min_range = 1.0;
  spec.max_range = 61.0;
  spec.bins = 3000;
  spec.rays_u = 256;
  spec.rays_v = 256;
  spec.source_level_db = 200.0;
  SonarWater water;
  water.absorption_db_per_m = 0.08;  // ~300 kHz
  for (double spreading : {20.0, 10.0}) {
    spec.spreading_db_per_decade = spreading;
    for (double range : {5.0, 10.0, 20.0, 40.0}) {
      SCOPED_TRACE(::testing::Message() << "N " << spreading << ", range " << range);
      const EmbreeScene scene = scene_of({sphere(Eigen::Vector3d(range, 0.0, 0.0), radius)});
      const Image image = ping_image(scene, quiet(spec), Eigen::Isometry3d::Identity(), water);
      double measured = 0.0;
      for (int b = 0; b < spec.bins; ++b) {
        measured += image.at(0, b) / std::pow(10.0, tvg_db(spec, water, spec.bin_centre_m(b)) / 10.0);
      }
      const double psi_max = std::asin(radius / range);
      const int n = 20000;
      double expected = 0.0;
      for (int i = 0; i < n; ++i) {
        const double psi = (i + 0.5) * psi_max / n;
        const double root = std::sqrt(std::max(0.0, radius * radius - range * range * std::sin(psi) * std::sin(psi)));
        const double r = range * std::cos(psi) - root, cos_theta = root / radius;
        const double loss = std::pow(10.0, (spec.source_level_db - 2.0 * transmission_loss_db(spec, water, r)) / 10.0);
        expected += std::exp2(-4.0 * psi * psi / (width * width)) * kMu * cos_theta * loss * r * r * 2.0 * kPi *
                    std::sin(psi) * psi_max / n;
      }
      EXPECT_NEAR(10.0 * std::log10(measured / expected), 0.0, 1.0);
    }
  }
}

// A box on a flat seabed: the seabed behind it, as seen from the sonar, returns nothing (noise off), while
// the seabed before and beyond the shadow does. Geometry: sonar 10 m above the seabed, box 2 m high from
// x = 15 to 16 m; rays over its top edge (16, 0, -8) meet the seabed at x = 20, so the shadow in the centre
// beam runs from the box's base at range 18.03 m (front face bottom) to 22.36 m.
TEST(SonarTest, ShadowBehindABoxIsEmptyOfReturns) {
  SonarPingSpec spec;
  spec.beams = fan(33, 40.0 * kDegToRad, 40.0 / 33.0 * kDegToRad, 30.0 * kDegToRad, 30.0 * kDegToRad);
  spec.min_range = 1.0;
  spec.max_range = 41.0;
  spec.bins = 800;  // 5 cm
  spec.rays_u = 4;
  spec.rays_v = 400;
  const EmbreeScene scene =
      scene_of({floor_at(-10.0f), box(Eigen::Vector3d(15.5, 0.0, -9.0), Eigen::Vector3d(1.0, 2.0, 2.0))});
  const Image image = ping_image(scene, quiet(spec), Eigen::Isometry3d::Identity());
  const int centre = 16;
  // The box's echo: ranges 17.0 (top front edge) to 18.03 m.
  double box_echo = 0.0;
  for (int b = spec.bin_of(17.0); b <= spec.bin_of(18.03); ++b) box_echo += image.at(centre, b);
  EXPECT_GT(box_echo, 0.0);
  for (int b = spec.bin_of(18.03) + 2; b < spec.bin_of(22.36) - 1; ++b) {
    EXPECT_EQ(image.at(centre, b), 0.0f) << "range " << spec.bin_centre_m(b);
  }
  // The seabed lit before the box and beyond the shadow (the beam reaches it from 14.1 to 38.6 m).
  for (double r : {15.0, 16.5, 24.0, 30.0, 36.0}) EXPECT_GT(image.at(centre, spec.bin_of(r)), 0.0f) << r;
  // A beam well off the box sees no shadow there.
  for (int b = spec.bin_of(18.5); b < spec.bin_of(22.0); ++b) EXPECT_GT(image.at(2, b), 0.0f);
}

// Rays sparse in range (a low, grazing fan: 64 rays across a 10 deg aperture for 2000 bins of 5 cm; beyond
// 60 m the rays meet the seabed more than a metre apart) still fill every bin between the ranges where the
// aperture's edges meet the seabed: each ray's echo is shared among the bins its patch spans. Sonar 3 m above the seabed, fan 7 deg down: 3 / sin 12 deg = 14.43 m to
// 3 / sin 2 deg = 85.96 m.
TEST(SonarTest, SparseRaysStillFillTheBinsTheirPatchesSpan) {
  SonarPingSpec spec;
  spec.beams = fan(9, 9.0 * kDegToRad, 1.0 * kDegToRad, 10.0 * kDegToRad, 7.0 * kDegToRad);
  spec.min_range = 1.0;
  spec.max_range = 101.0;
  spec.bins = 2000;
  spec.rays_u = 2;
  spec.rays_v = 64;
  const EmbreeScene scene = scene_of({floor_at(-3.0f)});
  const Image image = ping_image(scene, quiet(spec), Eigen::Isometry3d::Identity());
  const int near = spec.bin_of(3.0 / std::sin(12.0 * kDegToRad)), far = spec.bin_of(3.0 / std::sin(2.0 * kDegToRad));
  // Filled from the near edge (as sharp as one ray cell: the first cell spans 0.18 m, 4 bins, of range, its
  // patch centred on its ray, which jitter places within it) to 40 m, where neighbouring rays (jittered lines:
  // up to two cells apart) meet the seabed up to 2 r^2 / h dv = 2.9 m apart, within kMaxFootprintBins (3.2 m);
  // without the sharing the bins would be empty from 7.4 m on, where that spacing exceeds a bin.
  for (int b = near + 4; b < spec.bin_of(40.0); ++b) ASSERT_GT(image.at(4, b), 0.0f) << "range " << spec.bin_centre_m(b);
  for (int b = 0; b < near - 3; ++b) ASSERT_EQ(image.at(4, b), 0.0f) << "range " << spec.bin_centre_m(b);
  for (int b = far + 40; b < spec.bins; ++b) ASSERT_EQ(image.at(4, b), 0.0f) << "range " << spec.bin_centre_m(b);
}

// A multibeam over a flat seabed at altitude h, rolled by rho: every beam's detection within one range bin
// of h / cos(angle off nadir) (the beam axis meeting the plane), by phase on the oblique beams and by
// amplitude near nadir.
TEST(SonarTest, MultibeamRangesOverAFlatSeabedMatchTheGeometry) {
  SonarPingSpec spec;
  spec.beams = fan(128, 120.0 * kDegToRad, 1.0 * kDegToRad, 2.0 * kDegToRad);
  spec.min_range = 0.5;
  spec.max_range = 100.5;
  spec.bins = 4000;  // 2.5 cm
  // Enough rays across each beam that its footprint's bins all get some: 1 deg at 60 deg off nadir and 40 m
  // spans ~1.2 m of range, 48 bins.
  spec.rays_u = 96;
  spec.rays_v = 4;
  const double h = 20.0;
  // S: x_S down, y_S to port (W's y), z_S forward (W's x).
  Eigen::Matrix3d R_down;
  R_down.col(0) = -Eigen::Vector3d::UnitZ();
  R_down.col(1) = Eigen::Vector3d::UnitY();
  R_down.col(2) = Eigen::Vector3d::UnitX();
  const EmbreeScene scene = scene_of({floor_at(0.0f)});
  for (double roll_deg : {0.0, 10.0, -15.0}) {
    SCOPED_TRACE(roll_deg);
    Eigen::Isometry3d X_WS = Eigen::Isometry3d::Identity();
    X_WS.translation() = Eigen::Vector3d(0.0, 0.0, h);
    X_WS.linear() = Eigen::AngleAxisd(roll_deg * kDegToRad, Eigen::Vector3d::UnitX()).toRotationMatrix() * R_down;
    int by_phase = 0, by_amplitude = 0;
    ping(scene, quiet(spec), X_WS, geometry::kNoHit, SonarWater{}, kUniformMu, 1, 0, serial_for, [&](const BeamEcho& echo) {
      const double down = -(X_WS.linear() * spec.beams[static_cast<std::size_t>(echo.beam)].axis_S).z();
      const double expected = h / down;
      if (!(expected < spec.max_range - 2.0)) return;
      const BottomDetection detection = detect_bottom(spec, SonarWater{}, echo);
      ASSERT_TRUE(detection.valid) << "beam " << echo.beam;
      EXPECT_NEAR(detection.range_m, expected, spec.bin_size_m()) << "beam " << echo.beam << (detection.by_phase ? " phase" : " amplitude");
      ++(detection.by_phase ? by_phase : by_amplitude);
    });
    EXPECT_GT(by_phase, 50);
    EXPECT_GE(by_amplitude, 2);  // at least the beams either side of nadir
  }
}

// The sea surface as a reflector (SonarWater.surface): a multibeam looking up from 20 m under a flat surface, with
// nothing in the scene within range, detects the surface at h / cos(beam) in each beam (within a bin), and its echoes
// are those of the same multibeam looking down at an Embree floor 20 m below with the same mu, the mirror image
// (1e-4 relative: the floor's hit distances are Embree's floats). Without the surface the upward ping is empty.
TEST(SonarTest, LookingUpItHearsTheSeaSurface) {
  SonarPingSpec spec;
  spec.beams = fan(64, 120.0 * kDegToRad, 1.0 * kDegToRad, 2.0 * kDegToRad);
  spec.min_range = 0.5;
  spec.max_range = 100.5;
  spec.bins = 4000;
  spec.rays_u = 96;
  spec.rays_v = 4;
  const double h = 20.0;
  Eigen::Matrix3d R_down, R_up;  // S: x_S down (up), y_S to port, z_S forward (x_S x y_S)
  R_down.col(0) = -Eigen::Vector3d::UnitZ();
  R_down.col(1) = Eigen::Vector3d::UnitY();
  R_down.col(2) = Eigen::Vector3d::UnitX();
  R_up.col(0) = Eigen::Vector3d::UnitZ();
  R_up.col(1) = Eigen::Vector3d::UnitY();
  R_up.col(2) = -Eigen::Vector3d::UnitX();
  Eigen::Isometry3d X_down = Eigen::Isometry3d::Identity(), X_up = Eigen::Isometry3d::Identity();
  X_down.linear() = R_down;
  X_down.translation() = Eigen::Vector3d(0.0, 0.0, h);
  X_up.linear() = R_up;
  X_up.translation() = Eigen::Vector3d(0.0, 0.0, -h);
  const EmbreeScene floor = scene_of({floor_at(0.0f)}), deep = scene_of({floor_at(-500.0f)});
  SonarWater sea;
  sea.surface = true;
  sea.surface_mu = kMu;
  const Image up = ping_image(deep, quiet(spec), X_up, sea), down = ping_image(floor, quiet(spec), X_down);
  double up_sum = 0.0, down_sum = 0.0, empty_sum = 0.0;
  for (std::size_t i = 0; i < up.intensity.size(); ++i) {
    up_sum += up.intensity[i];
    down_sum += down.intensity[i];
  }
  EXPECT_GT(up_sum, 0.0);
  EXPECT_NEAR(up_sum / down_sum, 1.0, 1e-4);
  for (int k = 0; k < up.beams; ++k) {
    double peak = 0.0, peak_r = 0.0;
    for (int b = 0; b < up.bins; ++b) {
      if (up.at(k, b) > peak) peak = up.at(k, b), peak_r = spec.bin_centre_m(b);
    }
    const double cos_beam = (R_up * spec.beams[static_cast<std::size_t>(k)].axis_S).z();
    if (h / cos_beam > spec.max_range - 2.0) continue;
    EXPECT_NEAR(peak_r, h / cos_beam, 0.02 * h / cos_beam) << "beam " << k;  // the footprint's spread
  }
  const Image calm = ping_image(deep, quiet(spec), X_up);
  for (float v : calm.intensity) empty_sum += v;
  EXPECT_EQ(empty_sum, 0.0);
}

// Speckle and noise from seeded streams: the same ping twice and on two threads is bit-identical; the next
// ping differs.
TEST(SonarTest, SameSeedSameEchoWhateverTheThreads) {
  SonarPingSpec spec;
  spec.beams = fan(32, 60.0 * kDegToRad, 60.0 / 32.0 * kDegToRad, 20.0 * kDegToRad, 25.0 * kDegToRad);
  spec.bins = 300;
  spec.rays_v = 128;
  const EmbreeScene scene = scene_of({floor_at(-8.0f), sphere(Eigen::Vector3d(15.0, 1.0, -7.5), 0.5)});
  const ParallelFor two_threads = testing::two_threads;
  const Image a = ping_image(scene, spec, Eigen::Isometry3d::Identity(), {}, 3);
  const Image b = ping_image(scene, spec, Eigen::Isometry3d::Identity(), {}, 3, two_threads);
  const Image c = ping_image(scene, spec, Eigen::Isometry3d::Identity(), {}, 4);
  EXPECT_EQ(a.intensity, b.intensity);
  EXPECT_NE(a.intensity, c.intensity);
  for (float v : a.intensity) ASSERT_GE(v, 0.0f);
}

// Open water (nothing to hit): each bin is receiver noise times the TVG, exponential with mean
// 10^(NL / 10) under speckle. Mean over 64 beams x 400 bins = 25 600 draws: relative standard error
// 1 / sqrt(25600) = 0.6 %; tolerance 4 % (6.5 sigma, seeded).
TEST(SonarTest, OpenWaterIsReceiverNoise) {
  SonarPingSpec spec;
  spec.beams = fan(64, 60.0 * kDegToRad, 60.0 / 64.0 * kDegToRad, 20.0 * kDegToRad);
  spec.bins = 400;
  spec.rays_v = 8;
  spec.noise_level_db = 75.0;
  const EmbreeScene scene = scene_of({floor_at(-100.0f)});  // out of the 50 m window
  SonarWater water;
  water.absorption_db_per_m = 0.05;
  const Image image = ping_image(scene, spec, Eigen::Isometry3d::Identity(), water);
  double sum = 0.0;
  for (int k = 0; k < image.beams; ++k) {
    for (int b = 0; b < image.bins; ++b) sum += image.at(k, b) / std::pow(10.0, tvg_db(spec, water, spec.bin_centre_m(b)) / 10.0);
  }
  EXPECT_NEAR(sum / (image.beams * image.bins) / std::pow(10.0, 7.5), 1.0, 0.04);
}

// A jittered grid line's cos and sin from its centre's (cos_sin_near) against std::cos and std::sin, over centres
// across a fan's vertical aperture and offsets up to the series' limit: within 4 ulps of 1 (the identities' few
// roundings; the series' remainders are below 3e-21).
TEST(SonarTest, GridLineTrigonometryFromTheCentreIsExactToRounding) {
  double worst = 0.0;
  for (double c = -0.6; c <= 0.6; c += 0.0137) {
    for (double delta = -kSmallAngleRad; delta <= kSmallAngleRad; delta += kSmallAngleRad / 97.0) {
      double cos_e = 0.0, sin_e = 0.0;
      cos_sin_near(std::cos(c), std::sin(c), delta, cos_e, sin_e);
      worst = std::max({worst, std::abs(cos_e - std::cos(c + delta)), std::abs(sin_e - std::sin(c + delta))});
    }
  }
  EXPECT_LT(worst, 4.0 * 2.2e-16) << worst;
  double cos_e = 0.0, sin_e = 0.0;
  cos_sin_near(std::cos(0.3), std::sin(0.3), 0.0, cos_e, sin_e);  // no jitter: the centre's values, bit for bit
  EXPECT_EQ(cos_e, std::cos(0.3));
  EXPECT_EQ(sin_e, std::sin(0.3));
}

}  // namespace
}  // namespace hadal::render
