// Loading the world's own keys (config/world_keys.cc) through the scenario loader: values, defaults,
// conversions and the errors at file:line:col (config/scenario_test_support.h).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "config/scenario_test_support.h"
#include "hadal/config/scenario_loader.h"

namespace hadal::config {
namespace {

TEST_F(ScenarioLoaderTest, ClockRateDefaultFollowsASlowPhysicsRate) {
  const std::string path =
      write("s.yaml", std::string("world: {physics_rate_hz: 60}\nvehicles:") + kInlineVehicle);
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result.model->world.clock_rate_hz, 60.0);
}

TEST_F(ScenarioLoaderTest, WorldDateErrors) {
  const std::string bad_form = write("a.yaml", "world: {date: 2026-13-01}\nvehicles: []\n");
  const std::string out_of_model = write("b.yaml", "world: {date: \"2031-01-01\"}\nvehicles: []\n");
  const std::vector<std::string> a = errors_of(bad_form), b = errors_of(out_of_model);
  ASSERT_FALSE(a.empty());
  EXPECT_NE(a[0].find(":1:15: error: world.date: expected a date YYYY-MM-DD (got '2026-13-01')"), std::string::npos)
      << a[0];
  ASSERT_FALSE(b.empty());
  EXPECT_NE(b[0].find(":1:15: error: world.date: must be within 2025-01-01 .. 2029-12-31, the World Magnetic "
                      "Model 2025's validity (got 2031-01-01)"),
            std::string::npos) << b[0];
}

// Plausible units (configs/REFERENCE.md): a water density in g/cm³ is out of range; a seabed deeper than any
// ocean is an error and one above the surface a warning, at world.seabed.z, each with file:line:col.
TEST_F(ScenarioLoaderTest, ImplausibleWaterAndSeabedAreSaidWithTheirKey) {
  const std::string grams = write("g.yaml", "world:\n  water: {density: 1.025}\nvehicles: []\n");
  EXPECT_EQ(errors_of(grams)[0], grams + ":2:20: error: world.water.density: must be in [900, 1300] (got 1.025)");
  const std::string ramp = write("r.yaml", "world:\n  water: {density_model: ramp, rho0: 1.02, pycnocline_depth: 20000}\n"
                                           "vehicles: []\n");
  const std::vector<std::string> r = errors_of(ramp);
  ASSERT_EQ(r.size(), 3u);  // the two keys, and the empty vehicle list
  EXPECT_EQ(r[0], ramp + ":2:38: error: world.water.rho0: must be in [900, 1300] (got 1.02)");
  EXPECT_EQ(r[1], ramp + ":2:62: error: world.water.pycnocline_depth: must be in (0, 11000] (got 20000)");
  const std::string deep = write("d.yaml", "world:\n  water: {surface_z: 10}\n  seabed: {type: plane, z: -11500}\n"
                                           "vehicles:" + std::string(kInlineVehicle));
  EXPECT_EQ(errors_of(deep),
            std::vector<std::string>({deep + ":3:28: error: world.seabed.z: the seabed at z = -11500 m and the water "
                                             "surface at z = 10 m (world.water.surface_z; z is up in W) put the seabed "
                                             "11510 m deep, deeper than any ocean (11000 m)"}));
  const std::string up = write("u.yaml", "world:\n  seabed: {type: plane, z: 100}\nvehicles:" + std::string(kInlineVehicle));
  const LoadResult dry = load_scenario_file(up);
  ASSERT_TRUE(dry.ok());
  ASSERT_EQ(dry.warnings.size(), 1u);
  EXPECT_EQ(dry.warnings[0].format(),
            up + ":2:28: warning: world.seabed.z: the seabed at z = 100 m and the water surface at z = 0 m "
                 "(world.water.surface_z; z is up in W) put the seabed at or above the surface: the vehicles are on "
                 "dry land (a seabed 100 m below the surface is z: -100)");
  // At the surface's key when the seabed keeps its default plane (z = -100).
  const std::string low = write("l.yaml", "world:\n  water: {surface_z: -150}\nvehicles:" + std::string(kInlineVehicle));
  const LoadResult below = load_scenario_file(low);
  ASSERT_EQ(below.warnings.size(), 1u);
  EXPECT_NE(below.warnings[0].format().find(low + ":2:22: warning: world.water.surface_z: the seabed at z = -100 m"),
            std::string::npos)
      << below.warnings[0].format();
  const std::string fine = write("f.yaml", "world:\n  water: {density: 1000}\n  seabed: {type: plane, z: -10900}\n"
                                           "vehicles:" + std::string(kInlineVehicle));
  const LoadResult ok = load_scenario_file(fine);
  EXPECT_TRUE(ok.ok());
  EXPECT_TRUE(ok.warnings.empty());
}

// world.waves: a JONSWAP sea, its defaults, degrees to radians; regular components; and what is refused at its key:
// a negative Hs, a zero Tp, Hs 0 (a spectrum without energy), too many components, components that all have no
// amplitude, a spectrum's key given to regular waves, a negative build-up time.
TEST_F(ScenarioLoaderTest, WavesAndTheirBadValues) {
  const std::string good = write("good.yaml", R"(world:
  waves: {spectrum: jonswap, significant_height: 2.0, peak_period: 8.0, direction_deg: 90, spreading: 6}
vehicles:)" + std::string(kInlineVehicle));
  const LoadResult loaded = load_scenario_file(good);
  ASSERT_TRUE(loaded.ok()) << (loaded.errors.empty() ? "" : loaded.errors.front().format());
  const physics::WaveSpec& waves = loaded.model->world.waves;
  EXPECT_EQ(waves.spectrum, physics::WaveSpectrum::kJonswap);
  EXPECT_DOUBLE_EQ(waves.direction, 0.5 * std::numbers::pi);
  EXPECT_EQ(waves.spreading, 6.0);
  EXPECT_EQ(waves.components, 128);  // the defaults
  EXPECT_DOUBLE_EQ(waves.gamma, 3.3);
  EXPECT_TRUE(std::isinf(waves.depth));
  EXPECT_FALSE(waves.ramp_time);  // two peak periods (physics/waves.h)
  const std::string regular = write("regular.yaml", R"(world:
  waves:
    spectrum: regular
    depth: 40
    ramp_time: 30
    regular:
      - {amplitude: 0.5, period: 6, direction_deg: 180}
vehicles:)" + std::string(kInlineVehicle));
  const LoadResult two = load_scenario_file(regular);
  ASSERT_TRUE(two.ok());
  ASSERT_EQ(two.model->world.waves.regular.size(), 1u);
  EXPECT_DOUBLE_EQ(two.model->world.waves.regular[0].direction, std::numbers::pi);
  EXPECT_DOUBLE_EQ(two.model->world.waves.depth, 40.0);
  EXPECT_EQ(two.model->world.waves.ramp_time, 30.0);
  EXPECT_FALSE(load_scenario_file(write("none.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle)).model->world.waves.enabled());
  const auto first_error = [&](const std::string& name, const std::string& waves_yaml) {
    const std::vector<std::string> errors = errors_of(write(name, "world:\n  waves: " + waves_yaml + "\nvehicles: []\n"));
    return errors.empty() ? std::string("(no error)") : errors.front().substr(errors.front().find(':') + 1);
  };
  EXPECT_EQ(first_error("a.yaml", "{spectrum: jonswap, significant_height: -1, peak_period: 8}"),
            "2:50: error: world.waves.significant_height: must be in (0, 30] (got -1)");
  EXPECT_EQ(first_error("b.yaml", "{spectrum: jonswap, significant_height: 1, peak_period: 0}"),
            "2:66: error: world.waves.peak_period: must be in (0, 60] (got 0)");
  EXPECT_EQ(first_error("c.yaml", "{spectrum: pierson_moskowitz, significant_height: 0, peak_period: 8}"),
            "2:60: error: world.waves.significant_height: must be in (0, 30] (got 0)");
  EXPECT_EQ(first_error("d.yaml", "{spectrum: jonswap, significant_height: 1, peak_period: 8, components: 5000}"),
            "2:81: error: world.waves.components: must be in [1, 2048] (got 5000)");
  EXPECT_EQ(first_error("e.yaml", "{spectrum: regular, regular: [{amplitude: 0, period: 5}]}"),
            "2:30: error: world.waves.regular: the components have no energy (every amplitude is 0)");
  EXPECT_EQ(first_error("f.yaml", "{spectrum: regular, peak_period: 8, regular: [{amplitude: 1, period: 5}]}"),
            "2:30: error: world.waves.peak_period: key 'peak_period' is not used by wave spectrum 'regular'");
  EXPECT_EQ(first_error("g.yaml", "{spectrum: jonswap, significant_height: 1, peak_period: 8, components: 2.5}"),
            "2:81: error: world.waves.components: must be a whole number (got 2.5)");
  EXPECT_EQ(first_error("h.yaml", "{spectrum: jonswap, significant_height: 1, peak_period: 8, ramp_time: -5}"),
            "2:80: error: world.waves.ramp_time: must be in [0, 3600] (got -5)");
}

TEST_F(ScenarioLoaderTest, RaycastThreadsIsAWholeNumberInRange) {
  const std::string good = write("g.yaml", std::string("world: {raycast_threads: 3}\nvehicles:") + kInlineVehicle);
  const LoadResult g = load_scenario_file(good);
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(g.model->world.raycast_threads, 3);
  EXPECT_EQ(g.model->world.threads, 0);  // default: one per hardware thread
  EXPECT_GE(g.model->world.effective_threads(), 1);
  const std::string one = write("one.yaml", std::string("world: {threads: 1}\nvehicles:") + kInlineVehicle);
  EXPECT_EQ(load_scenario_file(one).model->world.threads, 1);
  EXPECT_EQ(load_scenario_file(one).model->world.effective_threads(), 1);
  const std::string many = write("many.yaml", "world:\n  threads: 300\nvehicles: []\n");
  EXPECT_EQ(errors_of(many)[0], many + ":2:12: error: world.threads: must be in [0, 256] (got 300)");
  const std::string bad = write("b.yaml", "world:\n  raycast_threads: 1.5\nvehicles: []\n");
  EXPECT_EQ(errors_of(bad)[0], bad + ":2:20: error: world.raycast_threads: must be a whole number (got 1.5)");
  const std::string negative = write("n.yaml", "world:\n  raycast_threads: -1\nvehicles: []\n");
  EXPECT_EQ(errors_of(negative)[0], negative + ":2:20: error: world.raycast_threads: must be in [0, 256] (got -1)");
}

// world.acoustics: beacons with their defaults, ambient noise; a repeated beacon name, a missing position and
// a shipping figure out of [0, 1] are errors at their keys.
TEST_F(ScenarioLoaderTest, AcousticBeaconsAndAmbientNoise) {
  const std::string good = write("g.yaml", std::string(R"(world:
  acoustics:
    spreading_exponent: 1.5
    ambient_noise: {shipping: 0.2, wind_speed: 12}
    beacons:
      - {name: a, position: [1, 2, -90]}
      - {name: b, position: [-4, 5, -95], turnaround_s: 0.2, source_level_db: 180}
vehicles:)") + kInlineVehicle);
  const LoadResult g = load_scenario_file(good);
  ASSERT_TRUE(g.ok()) << g.errors.front().format();
  const AcousticsSpec& acoustics = g.model->world.acoustics;
  EXPECT_EQ(acoustics.spreading_exponent, 1.5);
  EXPECT_EQ(acoustics.ambient_noise.shipping, 0.2);
  EXPECT_EQ(acoustics.ambient_noise.wind_speed, 12.0);
  ASSERT_EQ(acoustics.beacons.size(), 2u);
  EXPECT_EQ(acoustics.beacons[0].p_W, Eigen::Vector3d(1, 2, -90));
  EXPECT_EQ(acoustics.beacons[0].turnaround_s, 0.05);
  EXPECT_EQ(acoustics.beacons[1].source_level_db, 180.0);
  const std::string bad = write("b.yaml", std::string(R"(world:
  acoustics:
    ambient_noise: {shipping: 2}
    beacons:
      - {name: a, position: [1, 2, -90]}
      - {name: a, position: [1, 2, -80]}
      - {name: c}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":3:31: error: world.acoustics.ambient_noise.shipping: must be in [0, 1] (got 2)",
                   bad + ":4:5: error: world.acoustics.beacons: duplicate beacon name 'a' (beacons[0] and beacons[1])",
                   bad + ":7:9: error: world.acoustics.beacons[2]: missing required key 'position'"}));
}

TEST_F(ScenarioLoaderTest, RatesAboveThePhysicsRate) {
  const std::string path = write("s.yaml", std::string(R"(world:
  physics_rate_hz: 100
  clock_rate_hz: 200
vehicles:)") + kInlineVehicle + "    actuator_state_rate_hz: 1000\n");
  EXPECT_EQ(
      errors_of(path),
      (Lines{path + ":3:18: error: world.clock_rate_hz: must be <= world.physics_rate_hz (100) (got 200)",
             path + ":19:29: error: vehicles[0].actuator_state_rate_hz: must be <= world.physics_rate_hz "
                    "(100) (got 1000)"}));
}

}  // namespace
}  // namespace hadal::config
