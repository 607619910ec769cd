// Integration test of the two asset CLIs as users run them: hadal-make-asset writes a file,
// hadal-mesh-info prints one JSON object about it (parsed here), or fails with the documented exit
// codes and nothing on stdout.
#include <gtest/gtest.h>

#include "cli_test_support.h"
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using hadal::test::Json;
using hadal::test::JsonParser;
using hadal::test::RunResult;

class MeshInfoCliTest : public hadal::test::CliTest {
 protected:
  RunResult make_asset(const std::string& args) const {
    return run(std::string(HADAL_MAKE_ASSET) + " " + args);
  }
  RunResult mesh_info(const std::string& args) const {
    return run(std::string(HADAL_MESH_INFO) + " " + args);
  }

  static Json parse_one_line(const std::string& out) {
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;  // exactly one JSON object
    return parse(out);
  }
};

TEST_F(MeshInfoCliTest, ReportsAGeneratedOffsetBox) {
  const std::string file = dir_ + "/box.glb";
  const RunResult made = make_asset("box " + file + " --size 1 2 3 --center 4 0 -2");
  ASSERT_EQ(made.exit_code, 0) << made.err;
  const RunResult info = mesh_info(file);
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_EQ(info.err, "");
  const Json j = parse_one_line(info.out);
  EXPECT_EQ(j["file"].string, file);
  EXPECT_EQ(j["triangles"].number, 12);
  EXPECT_EQ(j["vertices"].number, 24);
  EXPECT_TRUE(j["closed"].boolean);
  EXPECT_EQ(j["boundary_edges"].number, 0);
  EXPECT_EQ(j["degenerate_dropped"].number, 0);
  // Exactly representable corners: the closed forms hold to double round-off.
  EXPECT_NEAR(j["volume"].number, 6.0, 1e-12);
  EXPECT_NEAR(j["surface_area"].number, 22.0, 1e-12);
  const double centroid[3] = {4, 0, -2}, lo[3] = {3.5, -1, -3.5}, hi[3] = {4.5, 1, -0.5};
  const double I[3] = {6.0 / 12 * (4 + 9), 6.0 / 12 * (1 + 9), 6.0 / 12 * (1 + 4)};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(j["centroid"][k].number, centroid[k], 1e-12);
    EXPECT_NEAR(j["bounds"]["min"][k].number, lo[k], 1e-12);
    EXPECT_NEAR(j["bounds"]["max"][k].number, hi[k], 1e-12);
    for (std::size_t l = 0; l < 3; ++l)
      EXPECT_NEAR(j["inertia"][k][l].number, k == l ? I[k] : 0.0, 1e-12);
  }
  EXPECT_GT(j["load_seconds"].number, 0.0);
  EXPECT_EQ(j["load_seconds"].type, Json::Type::kNumber);
}

TEST_F(MeshInfoCliTest, ScaleAndUpAxisOptions) {
  // File y-up box 1 x 2 x 3 at the origin; --up-axis y maps (x, y, z) -> (x, -z, y), --scale 2.
  const std::string file = dir_ + "/box.gltf";
  ASSERT_EQ(make_asset("box " + file + " --size 1 2 3").exit_code, 0);
  const RunResult info = mesh_info(file + " --scale 2 --up-axis y");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const Json j = parse_one_line(info.out);
  EXPECT_NEAR(j["volume"].number, 6.0 * 8.0, 1e-12);
  const double hi[3] = {1, 3, 2};
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(j["bounds"]["max"][k].number, hi[k], 1e-12);
}

// --mass M: the link block of a homogeneous solid, ready to paste. The 1 x 2 x 3 box centred at (4, 0, -2)
// with 12 kg (density 2 kg/m^3): moments m/12 (b^2 + c^2) = 13, 10, 5 kg m^2 (distinct on each axis), no
// products, the centre of mass at the box's centre; to double round-off (exact corners). An open mesh has
// no volume to spread the mass over: exit 1, nothing on stdout; a mass <= 0 is a usage error.
TEST_F(MeshInfoCliTest, MassPrintsTheLinkBlockOfAHomogeneousSolid) {
  const std::string file = dir_ + "/box.glb";
  ASSERT_EQ(make_asset("box " + file + " --size 1 2 3 --center 4 0 -2").exit_code, 0);
  const RunResult info = mesh_info(file + " --mass 12");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  std::istringstream lines(info.out);
  std::string line;
  std::vector<std::string> yaml;
  while (std::getline(lines, line)) {
    if (line.rfind("#", 0) != 0) yaml.push_back(line);
  }
  ASSERT_EQ(yaml.size(), 3u) << info.out;
  EXPECT_EQ(yaml[0], "mass: 12");
  double c[3] = {};
  ASSERT_EQ(std::sscanf(yaml[1].c_str(), "center_of_mass: [%lf, %lf, %lf]", &c[0], &c[1], &c[2]), 3) << yaml[1];
  double I[6] = {};
  ASSERT_EQ(std::sscanf(yaml[2].c_str(), "inertia: {ixx: %lf, iyy: %lf, izz: %lf, ixy: %lf, ixz: %lf, iyz: %lf}",
                        &I[0], &I[1], &I[2], &I[3], &I[4], &I[5]),
            6)
      << yaml[2];
  const double expected_c[3] = {4, 0, -2}, expected_I[6] = {13, 10, 5, 0, 0, 0};
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], expected_c[k], 1e-12);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(I[k], expected_I[k], 1e-12) << k;
  EXPECT_NE(info.out.find("density 2 kg/m^3"), std::string::npos) << info.out;

  const std::string open = dir_ + "/seabed.obj";
  ASSERT_EQ(make_asset("seabed " + open + " --triangles 200 --extent 10").exit_code, 0);
  const RunResult refused = mesh_info(open + " --mass 12");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_EQ(refused.out, "");
  EXPECT_NE(refused.err.find("the mesh is not closed, so it has no volume to spread 12 kg over"), std::string::npos)
      << refused.err;
  EXPECT_EQ(mesh_info(file + " --mass 0").exit_code, 2);
  EXPECT_EQ(mesh_info(file + " --mass heavy").exit_code, 2);
}

TEST_F(MeshInfoCliTest, OpenSeabedHasNullVolume) {
  const std::string file = dir_ + "/seabed.obj";
  ASSERT_EQ(make_asset("seabed " + file + " --triangles 2000 --extent 50").exit_code, 0);
  const RunResult info = mesh_info(file);
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const Json j = parse_one_line(info.out);
  EXPECT_FALSE(j["closed"].boolean);
  EXPECT_EQ(j["closed"].type, Json::Type::kBool);
  EXPECT_EQ(j["triangles"].number, 2 * 32 * 32);  // round(sqrt(2000 / 2)) = 32 cells a side
  EXPECT_EQ(j["boundary_edges"].number, 4 * 32);
  EXPECT_EQ(j["volume"].type, Json::Type::kNull);
  EXPECT_EQ(j["inertia"].type, Json::Type::kNull);
}

TEST_F(MeshInfoCliTest, EveryGeneratorShapeWritesALoadableFile) {
  for (const std::string shape : {"box", "sphere", "cylinder", "torpedo", "frame", "lander",
                                  "seabed", "two-node", "textured-quad"}) {
    SCOPED_TRACE(shape);
    const std::string file = dir_ + "/" + shape + ".glb";
    const RunResult made = make_asset(shape + " " + file);
    ASSERT_EQ(made.exit_code, 0) << made.err;
    const RunResult info = mesh_info(file);
    ASSERT_EQ(info.exit_code, 0) << info.err;
    const Json j = parse_one_line(info.out);
    const bool open = shape == "seabed" || shape == "textured-quad";
    EXPECT_EQ(j["closed"].boolean, !open);
    EXPECT_EQ(j["textures"].number, shape == "textured-quad" ? 1 : 0);
  }
}

TEST_F(MeshInfoCliTest, ErrorsGoToStderrWithExitCodes) {
  const RunResult missing = mesh_info(dir_ + "/nothing.glb");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_EQ(missing.out, "");
  EXPECT_EQ(missing.err, "hadal-mesh-info: " + dir_ + "/nothing.glb: file not found\n");

  const RunResult unsupported = mesh_info(dir_ + "/model.3ds");
  EXPECT_EQ(unsupported.exit_code, 1);
  EXPECT_EQ(unsupported.out, "");

  for (const std::string args : {"", "a.glb b.glb", "a.glb --up-axis x", "a.glb --scale -2",
                                 "a.glb --scale", "a.glb --bogus"}) {
    SCOPED_TRACE(args);
    const RunResult usage = mesh_info(args);
    EXPECT_EQ(usage.exit_code, 2);
    EXPECT_EQ(usage.out, "");
    EXPECT_NE(usage.err.find("usage: hadal-mesh-info FILE"), std::string::npos);
  }
  const RunResult bad_shape = make_asset("pyramid " + dir_ + "/x.glb");
  EXPECT_EQ(bad_shape.exit_code, 2);
  const RunResult bad_format = make_asset("box " + dir_ + "/x.fbx");
  EXPECT_EQ(bad_format.exit_code, 1);
  EXPECT_NE(bad_format.err.find("unsupported extension '.fbx'"), std::string::npos)
      << bad_format.err;
}

}  // namespace
