// Loading the soil's keys (world.soil, physics/soil_spec.cc) through the scenario loader: values, defaults,
// conversions and the errors at file:line:col (config/scenario_test_support.h).
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "config/scenario_test_support.h"
#include "hadal/config/scenario_loader.h"
#include "hadal/physics/soil_presets.h"

namespace hadal::config {
namespace {

namespace fs = std::filesystem;

// The soil presets as an unknown one's error lists them (physics/soil_presets.cc).
const std::string kSoilPresets =
    "'deep_sea_ooze', 'dry_sand', 'sandy_loam', 'clayey_soil', 'lete_sand', 'lunar_soil', 'hit_lss1', "
    "'heavy_clay_25', 'heavy_clay_40', 'lean_clay_22', 'lean_clay_32', 'clayey_soil_55'";

TEST_F(ScenarioLoaderTest, SoilPresetOverridesAndSeabedContact) {
  // No soil block: the deep-sea ooze preset; a vehicle meets the seabed rigidly unless it says soil.
  const auto plain = load_scenario_file(write("plain.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle));
  ASSERT_TRUE(plain.model) << plain.errors.front().format();
  EXPECT_EQ(plain.model->world.soil.preset, "deep_sea_ooze");
  EXPECT_EQ(plain.model->world.soil.parameters.k_phi, config::find_preset(physics::soil_presets(), "deep_sea_ooze")->figures.k_phi);
  EXPECT_EQ(plain.model->vehicles[0].seabed_contact, SeabedContact::kRigid);

  const std::string path = write("s.yaml", R"(world:
  soil:
    preset: dry_sand
    cohesion: 1500
    friction_angle_deg: 30
    damping: 5000
vehicles:
  - name: crawler
    type: crawler
    seabed_contact: soil
    links:
      - name: body
        mass: 300.0
        inertia: {ixx: 50, iyy: 80, izz: 100}
        collisions: [{shape: box, size: [2.0, 1.2, 0.6]}]
)");
  const auto result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << result.errors.front().format();
  const SoilSpec& soil = result.model->world.soil;
  const physics::SoilParameters& sand = config::find_preset(physics::soil_presets(), "dry_sand")->figures;
  EXPECT_EQ(soil.preset, "dry_sand");
  EXPECT_EQ(soil.parameters.sinkage_exponent, sand.sinkage_exponent);
  EXPECT_EQ(soil.parameters.k_c, sand.k_c);
  EXPECT_EQ(soil.parameters.k_phi, sand.k_phi);
  EXPECT_EQ(soil.parameters.cohesion, 1500.0);
  EXPECT_NEAR(soil.parameters.friction_angle, 30.0 * kDegToRad, kTol);
  EXPECT_EQ(soil.parameters.shear_deformation_modulus, sand.shear_deformation_modulus);
  EXPECT_EQ(soil.parameters.damping, 5000.0);
  EXPECT_EQ(result.model->vehicles[0].seabed_contact, SeabedContact::kSoil);
}

TEST_F(ScenarioLoaderTest, SoilErrors) {
  const std::string path = write("s.yaml", R"(world:
  soil:
    preset: quicksand
    sinkage_exponent: 0
    k_c: 0
    k_phi: 0
    friction_angle_deg: 75
    shear_deformation_modulus: -0.01
    porosity: 0.4
vehicles:
  - name: crawler
    type: crawler
    seabed_contact: sticky
    links:
      - name: body
        mass: 300.0
        inertia: {ixx: 50, iyy: 80, izz: 100}
  - name: sled
    type: crawler
    seabed_contact: soil
    links:
      - name: body
        mass: 300.0
        inertia: {ixx: 50, iyy: 80, izz: 100}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":3:13: error: world.soil.preset: unknown soil preset 'quicksand' (presets: " +
                       kSoilPresets + ")",
                   path + ":4:23: error: world.soil.sinkage_exponent: must be in (0, 3] (got 0)",
                   path + ":6:5: error: world.soil.k_phi: k_c and k_phi are both 0: the soil would bear nothing",
                   path + ":7:25: error: world.soil.friction_angle_deg: must be in [0, 60] (got 75)",
                   path + ":8:32: error: world.soil.shear_deformation_modulus: must be in (0, 1] (got -0.01)",
                   path + ":9:5: error: world.soil.porosity: unknown key 'porosity'",
                   path + ":13:21: error: vehicles[0].seabed_contact: must be one of 'rigid', 'soil' (got 'sticky')",
                   path + ":20:5: error: vehicles[1].seabed_contact: soil contact presses on the vehicle's "
                          "surface, and no link has a mesh or collision shapes"}));
}

TEST_F(ScenarioLoaderTest, SoilRegionsByMap) {
  // 2 x 3 pixels, 5 m each, centred on (10, 0): row 0 (north) is [0, 1, 2], row 1 [2, 2, 0].
  cv::Mat image(2, 3, CV_8UC1, cv::Scalar(0));
  image.at<std::uint8_t>(0, 1) = 1;
  image.at<std::uint8_t>(0, 2) = 2;
  image.at<std::uint8_t>(1, 0) = 2;
  image.at<std::uint8_t>(1, 1) = 2;
  fs::create_directories(dir_ / "maps");
  ASSERT_TRUE(cv::imwrite((dir_ / "maps" / "soil.png").string(), image));
  const std::string path = write("scenarios/s.yaml", std::string(R"(world:
  soil:
    preset: deep_sea_ooze
    regions:
      - {preset: dry_sand}
      - {preset: clayey_soil, cohesion: 5000}
    map: {file: ../maps/soil.png, meters_per_pixel: 5, center: [10, 0]}
vehicles:)") + kInlineVehicle);
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& d : result.errors) ADD_FAILURE() << d.format();
  ASSERT_TRUE(result.ok());
  const SoilSpec& soil = result.model->world.soil;
  ASSERT_EQ(soil.regions.size(), 2u);
  EXPECT_EQ(soil.regions[0].preset, "dry_sand");
  EXPECT_EQ(soil.regions[1].parameters.cohesion, 5000.0);
  EXPECT_EQ(soil.regions[1].parameters.k_phi, config::find_preset(physics::soil_presets(), "clayey_soil")->figures.k_phi);
  ASSERT_NE(soil.map, nullptr);
  const physics::SoilLayout layout = soil.layout();
  ASSERT_EQ(layout.soils.size(), 3u);
  // Cells: x in [-5, 0), [0, 5), [5, 10) ... from the west edge at 10 - 7.5 = 2.5; y north half [0, 5).
  EXPECT_EQ(layout.region_at(3.0, 2.0), 0u);    // row 0, column 0
  EXPECT_EQ(layout.region_at(9.0, 2.0), 1u);    // row 0, column 1
  EXPECT_EQ(layout.region_at(16.0, 4.9), 2u);   // row 0, column 2
  EXPECT_EQ(layout.region_at(3.0, -2.0), 2u);   // row 1, column 0
  EXPECT_EQ(layout.region_at(16.0, -2.0), 0u);  // row 1, column 2
  EXPECT_EQ(layout.region_at(2.4, 0.0), 0u);    // off the map: the world's soil
  EXPECT_EQ(layout.region_at(9.0, 5.1), 0u);
}

TEST_F(ScenarioLoaderTest, SoilMapErrors) {
  cv::Mat image(2, 2, CV_8UC1, cv::Scalar(0));
  image.at<std::uint8_t>(1, 0) = 3;
  ASSERT_TRUE(cv::imwrite((dir_ / "three.png").string(), image));
  ASSERT_TRUE(cv::imwrite((dir_ / "colour.png").string(), cv::Mat(2, 2, CV_8UC3, cv::Scalar(0, 0, 0))));
  const std::string beyond = write("a.yaml", std::string(R"(world:
  soil:
    regions: [{preset: dry_sand}, {preset: lunar_soil}]
    map: {file: three.png, meters_per_pixel: 1}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(beyond),
            (Lines{beyond + ":4:17: error: world.soil.map.file: " + (dir_ / "three.png").string() +
                   ": pixel (row 1, column 0) names region 3, but there are 2 regions (0 is the world's soil)"}));
  const std::string colour = write("b.yaml", std::string(R"(world:
  soil:
    regions: [{preset: dry_sand}]
    map: {file: colour.png, meters_per_pixel: 0}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(colour),
            (Lines{colour + ":4:47: error: world.soil.map.meters_per_pixel: must be in (0, 1000000] (got 0)"}));
  const std::string colour2 = write("c.yaml", std::string(R"(world:
  soil:
    regions: [{preset: dry_sand}]
    map: {file: colour.png, meters_per_pixel: 2}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(colour2),
            (Lines{colour2 + ":4:17: error: world.soil.map.file: " + (dir_ / "colour.png").string() +
                   ": a soil map is an 8-bit single-channel image of region numbers (this one has 3 channel(s) of "
                   "8 bits)"}));
  const std::string unplaced = write("d.yaml", std::string(R"(world:
  soil:
    regions: [{preset: dry_sand, porosity: 1}, {preset: basalt}]
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(unplaced),
            (Lines{unplaced + ":3:5: error: world.soil.regions: regions need a `map` that says where each one is",
                   unplaced + ":3:34: error: world.soil.regions[0].porosity: unknown key 'porosity'",
                   unplaced + ":3:57: error: world.soil.regions[1].preset: unknown soil preset 'basalt' (presets: " +
                       kSoilPresets + ")"}));
  const std::string no_regions = write("e.yaml", std::string(R"(world:
  soil:
    map: {file: three.png, meters_per_pixel: 1}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(no_regions),
            (Lines{no_regions + ":3:5: error: world.soil.map: a soil map places `regions`, and there are none"}));
}

}  // namespace
}  // namespace hadal::config
