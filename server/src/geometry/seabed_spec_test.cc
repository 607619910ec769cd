// Loading the seabed's keys (world.seabed, geometry/seabed_spec.cc) through the scenario loader: values,
// defaults, conversions and the errors at file:line:col (config/scenario_test_support.h).
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "config/scenario_test_support.h"
#include "hadal/config/scenario_loader.h"
#include "hadal/geometry/triangle_mesh.h"

namespace hadal::config {
namespace {

namespace fs = std::filesystem;

TEST_F(ScenarioLoaderTest, SeabedTypesBuildTheirSurface) {
  // A 3 x 2 pixel 16-bit heightmap next to the scenario; 2 m per pixel.
  cv::Mat image(2, 3, CV_16UC1, cv::Scalar(0));
  image.at<std::uint16_t>(0, 2) = 65535;
  fs::create_directories(dir_ / "maps");
  ASSERT_TRUE(cv::imwrite((dir_ / "maps" / "h.png").string(), image));
  const std::string heightmap = write("scenarios/h.yaml", std::string(R"(world:
  seabed: {type: heightmap, file: ../maps/h.png, meters_per_pixel: 2, height_range: [-120, -100]}
vehicles:)") + kInlineVehicle);
  const LoadResult h = load_scenario_file(heightmap);
  for (const Diagnostic& d : h.errors) ADD_FAILURE() << d.format();
  ASSERT_TRUE(h.ok());
  const SeabedSpec& seabed = h.model->world.seabed;
  ASSERT_NE(seabed.mesh, nullptr);
  EXPECT_EQ(seabed.mesh->num_vertices(), 6u);
  EXPECT_EQ(seabed.mesh->num_triangles(), 4u);
  EXPECT_EQ(seabed.heightmap.height_min, -120.0);
  // Pixel (row 0, col 2) is the north-east corner: x = +2, y = +1, z = height_max.
  EXPECT_EQ(seabed.mesh->positions[3 * 5 + 0], 2.0f);
  EXPECT_EQ(seabed.mesh->positions[3 * 5 + 1], 1.0f);
  EXPECT_EQ(seabed.mesh->positions[3 * 5 + 2], -100.0f);

  const std::string procedural = write("p.yaml", std::string(R"(world:
  seed: 5
  seabed: {type: procedural, z: -80, size: [100, 50], resolution: 5, seed: 9}
vehicles:)") + kInlineVehicle);
  const LoadResult p = load_scenario_file(procedural);
  ASSERT_TRUE(p.ok());
  EXPECT_EQ(p.model->world.seabed.procedural.seed, 9u);  // its own seed wins over world.seed
  EXPECT_EQ(p.model->world.seabed.procedural.z_datum, -80.0);
  EXPECT_EQ(p.model->world.seabed.mesh->num_triangles(), 20u * 10u * 2u);

  const std::string plane = write("q.yaml", std::string("world: {seabed: {z: -30}}\nvehicles:") + kInlineVehicle);
  const LoadResult q = load_scenario_file(plane);
  ASSERT_TRUE(q.ok());
  EXPECT_EQ(q.model->world.seabed.mesh, nullptr);  // a plane needs no mesh
}

TEST_F(ScenarioLoaderTest, SeabedKeysAndFilesAreChecked) {
  const std::string keys = write("k.yaml", R"(world:
  seabed:
    type: procedural
    file: x.png
    size: [0, 10]
    slope_deg: 60
vehicles: [])");
  const std::vector<std::string> key_errors = errors_of(keys);
  ASSERT_GE(key_errors.size(), 3u);
  EXPECT_EQ(key_errors[0], keys + ":4:5: error: world.seabed.file: key 'file' is not used by seabed type 'procedural'");
  EXPECT_EQ(key_errors[1], keys + ":5:12: error: world.seabed.size[0]: must be in (0, 100000] (got 0)");
  EXPECT_EQ(key_errors[2], keys + ":6:16: error: world.seabed.slope_deg: must be in [0, 60) (got 60)");

  const std::string range = write("r.yaml", R"(world:
  seabed: {type: heightmap, file: h.png, meters_per_pixel: 1, height_range: [0, -5]}
vehicles: [])");
  EXPECT_EQ(errors_of(range)[0],
            range + ":2:77: error: world.seabed.height_range: must be [min, max] with max > min (got [0, -5])");

  const std::string missing = write("m.yaml", R"(world:
  seabed: {type: heightmap, file: nowhere.png, meters_per_pixel: 1, height_range: [-5, 0]}
vehicles: [])");
  EXPECT_EQ(errors_of(missing)[0], missing + ":2:35: error: world.seabed.file: " + (dir_ / "nowhere.png").string() +
                                       ": cannot open heightmap (file not found)");

  const std::string mesh = write("n.yaml", R"(world:
  seabed: {type: mesh, file: nowhere.glb, scale: 0.001, up_axis: y}
vehicles: [])");
  const std::vector<std::string> mesh_errors = errors_of(mesh);
  ASSERT_FALSE(mesh_errors.empty());
  // The importer's message names the file; the loader places it at the file key's value.
  EXPECT_EQ(mesh_errors[0].rfind(mesh + ":2:30: error: world.seabed.file: " + (dir_ / "nowhere.glb").string() + ": ", 0),
            0u)
      << mesh_errors[0];

  const std::string huge = write("g.yaml", R"(world:
  seabed: {type: procedural, size: [100000, 100000], resolution: 1}
vehicles: [])");
  EXPECT_EQ(errors_of(huge)[0], huge + ":2:11: error: world.seabed: size / resolution gives 1.00002e+10 height "
                                       "samples; at most 16777216 are allowed");
}

}  // namespace
}  // namespace hadal::config
