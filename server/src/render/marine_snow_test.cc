// Marine snow against its contract: seeded and repeatable, none without lights or density, particles
// only in front of what the pixels see, and as many as the density puts in the visible volume.
#include "hadal/render/marine_snow.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "hadal/core/units.h"
#include "hadal/render/camera_rays.h"
#include "hadal/render/frame.h"
#include "render_test_support.h"

namespace hadal::render {
namespace {

using testing::plate;

Rgb white(const SurfacePoint&) { return Rgb::Ones(); }

// Camera at the origin looking along +x (90 deg), a light at the camera, clear water; a wall at `wall_m`.
RadianceFrame frame_with_snow(double density, std::uint64_t seed, float wall_m) {
  const Lens lens = make_lens(lens_from_horizontal_fov(200, 150, 90.0 * kDegToRad));
  geometry::EmbreeScene scene;
  scene.add_static_mesh(plate(wall_m, 0, 0, 50), 0, "wall");
  scene.build();
  FrameLighting lighting;
  lighting.water.absorption_per_m = Rgb::Constant(0.05);
  SpotLight light;
  light.inner_half_angle_rad = 1.0;
  light.outer_half_angle_rad = 1.2;
  lighting.lights = {light};
  lighting.marine_snow.density_per_m3 = density;
  lighting.marine_snow.seed = seed;
  lighting.marine_snow.max_range = 4.0;
  return render_radiance(scene, lens, X_SC(), 0.05f, 100.0f, geometry::kNoHit, lighting, white);
}

TEST(MarineSnowTest, SeededParticlesCatchTheLight) {
  const RadianceFrame none = frame_with_snow(0.0, 1, 50.0f);
  const RadianceFrame a = frame_with_snow(500.0, 1, 50.0f);
  const RadianceFrame b = frame_with_snow(500.0, 1, 50.0f);
  const RadianceFrame other = frame_with_snow(500.0, 2, 50.0f);
  EXPECT_EQ(none.snow_particles, 0u);
  // The visible volume within 4 m: a pyramid of 90 x 73.7 deg, 4 m deep, cut to the 4 m sphere; the
  // density's cells put ~500 particles in each m^3 of it: hundreds at least, fewer than in the cube.
  EXPECT_GT(a.snow_particles, 1000u);
  EXPECT_LT(a.snow_particles, static_cast<std::size_t>(500.0 * 8.0 * 8.0 * 8.0));
  EXPECT_EQ(a.snow_particles, b.snow_particles);
  std::size_t brighter = 0, differ = 0;
  for (std::size_t i = 0; i < a.radiance.size(); ++i) {
    ASSERT_TRUE((a.radiance[i] == b.radiance[i]).all());
    brighter += (a.radiance[i] > none.radiance[i]).any();
    differ += !(a.radiance[i] == other.radiance[i]).all();
  }
  EXPECT_GT(brighter, 500u);
  EXPECT_GT(differ, 500u);
}

// A wall 0.5 m ahead hides every particle behind it: only those in the 0.5 m in front are drawn.
TEST(MarineSnowTest, ParticlesBehindASurfaceAreHidden) {
  const RadianceFrame open = frame_with_snow(500.0, 1, 50.0f);
  const RadianceFrame walled = frame_with_snow(500.0, 1, 0.5f);
  EXPECT_GT(walled.snow_particles, 0u);
  EXPECT_LT(walled.snow_particles * 50, open.snow_particles);
}

TEST(MarineSnowTest, InvalidParametersAreRejected) {
  MarineSnow snow;
  snow.density_per_m3 = -1.0;
  EXPECT_THROW(validate(snow), std::invalid_argument);
  snow = MarineSnow{};
  snow.radius = 0.0;
  EXPECT_THROW(validate(snow), std::invalid_argument);
  snow = MarineSnow{};
  snow.albedo = 1.5;
  EXPECT_THROW(validate(snow), std::invalid_argument);
}

}  // namespace
}  // namespace hadal::render
