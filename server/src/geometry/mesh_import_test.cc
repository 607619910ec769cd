#include "hadal/geometry/mesh_import.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "hadal/assets/mesh_generators.h"
#include "hadal/assets/scene_writer.h"
#include "hadal/geometry/mesh_properties.h"

namespace hadal::geometry {
namespace {

namespace fs = std::filesystem;

// Float positions: see mesh_properties_test.cc (relative 1e-6 on volumes and inertias).
constexpr double kFloatRel = 1e-6;

double rel_err(double value, double expected) {
  return std::abs(value - expected) / std::abs(expected);
}

std::vector<char> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const std::string& path, const std::vector<char>& bytes) {
  // A fresh file rather than O_TRUNC: ext4 flushes a truncated file's data on close (~3 ms each).
  fs::remove(path);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

void write_text(const std::string& path, const std::string& text) {
  write_bytes(path, {text.begin(), text.end()});
}

std::uint32_t u32_at(const std::vector<char>& b, std::size_t offset) {
  std::uint32_t v;
  std::memcpy(&v, b.data() + offset, 4);
  return v;
}

void set_u32(std::vector<char>& b, std::size_t offset, std::uint32_t v) {
  std::memcpy(b.data() + offset, &v, 4);
}

std::string base64(const std::vector<char>& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k)
      v = v << 8 | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? table[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

// Every test writes its generated assets into a fresh directory of its own.
class MeshImportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "hadal_mesh_import_XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return dir_ + "/" + name; }

  std::string write(const assets::SceneSpec& spec, const std::string& name,
                    bool stl_ascii = false) {
    const std::string file = path(name);
    const std::string error = assets::write_scene(spec, file, stl_ascii);
    EXPECT_EQ(error, "");
    return file;
  }

  static ImportResult import_ok(const std::string& file, const ImportOptions& options = {}) {
    ImportResult result = import_mesh(file, options);
    EXPECT_TRUE(result.ok()) << result.error;
    EXPECT_EQ(result.error, "");
    return result;
  }

  static void expect_error(const std::string& file, const std::string& expected,
                           const ImportOptions& options = {}) {
    const ImportResult result = import_mesh(file, options);
    EXPECT_FALSE(result.ok());
    EXPECT_EQ(result.error, expected);
  }

  std::string dir_;
};

// ---------------------------------------------------------------------------------------------
// Round trips and transforms

TEST_F(MeshImportTest, EveryFormatRoundTripsToTheSameProperties) {
  // A non-symmetric, closed, offset solid: the torpedo (curved, smooth normals) shifted off origin.
  assets::MeshData hull = assets::make_torpedo(2.0, 0.2, 24, 8);
  const double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, t[3] = {3.0, -1.0, 0.5};
  assets::transform_mesh(hull, R, t);
  TriangleMesh reference;
  reference.positions = hull.positions;
  reference.indices = hull.indices;
  const MeshProperties expected = compute_mesh_properties(reference);
  ASSERT_TRUE(expected.closed);
  const assets::SceneSpec spec = assets::single_mesh_scene(hull);
  struct Case {
    std::string name;
    bool ascii;
  };
  for (const Case& c : {Case{"hull.glb", false}, Case{"hull.gltf", false}, Case{"hull.obj", false},
                        Case{"hull.stl", false}, Case{"hull_ascii.stl", true}}) {
    SCOPED_TRACE(c.name);
    const ImportResult result = import_ok(write(spec, c.name, c.ascii));
    ASSERT_TRUE(result.ok());
    EXPECT_EQ(result.mesh->num_triangles(), hull.num_triangles());
    EXPECT_EQ(result.degenerate_triangles_dropped, 0u);
    const MeshProperties props = compute_mesh_properties(*result.mesh);
    EXPECT_TRUE(props.closed);
    // Text formats carry 9 significant digits, which round-trip floats exactly.
    EXPECT_LT(rel_err(props.volume, expected.volume), kFloatRel);
    EXPECT_LT((props.centroid - expected.centroid).norm(), kFloatRel);
    EXPECT_LT((props.inertia_unit_density - expected.inertia_unit_density).norm(),
              kFloatRel * expected.inertia_unit_density.norm());
    EXPECT_LT(rel_err(props.surface_area, expected.surface_area), kFloatRel);
    EXPECT_TRUE(props.bounds_min.isApprox(expected.bounds_min, 1e-7));
    EXPECT_TRUE(props.bounds_max.isApprox(expected.bounds_max, 1e-7));
  }
}

TEST_F(MeshImportTest, ChildNodeTransformShowsUpInWorldCoordinates) {
  // two_node_scene(): root (translated +5 in z) holds a unit cube at its origin; its child
  // (translation (10, 0, 0), +90 deg about z) holds a 2 x 1 x 1 box. In world coordinates the
  // child box spans x in [9.5, 10.5], y in [-1, 1], z in [4.5, 5.5].
  const assets::SceneSpec spec = assets::two_node_scene();
  for (const std::string name : {"nodes.glb", "nodes.gltf", "nodes.obj", "nodes.stl"}) {
    SCOPED_TRACE(name);
    const ImportResult result = import_ok(write(spec, name));
    ASSERT_TRUE(result.ok());
    const MeshProperties props = compute_mesh_properties(*result.mesh);
    EXPECT_TRUE(props.closed);
    EXPECT_TRUE(props.bounds_min.isApprox(Eigen::Vector3d(-0.5, -1.0, 4.5), 1e-6))
        << props.bounds_min.transpose();
    EXPECT_TRUE(props.bounds_max.isApprox(Eigen::Vector3d(10.5, 1.0, 5.5), 1e-6))
        << props.bounds_max.transpose();
    // Volumes 1 and 2 at x = 0 and x = 10: centroid x = 20/3; inertia = each box about its own
    // centre (the child's extents rotated to 1 x 2 x 1) plus m d d terms (parallel axes).
    EXPECT_LT(rel_err(props.volume, 3.0), kFloatRel);
    const Eigen::Vector3d c(20.0 / 3.0, 0.0, 5.0);
    EXPECT_LT((props.centroid - c).norm(), kFloatRel * c.norm());
    auto shifted = [&](double m, const Eigen::Matrix3d& I, const Eigen::Vector3d& p) {
      const Eigen::Vector3d d = p - c;
      return Eigen::Matrix3d(
          I + m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
    };
    const Eigen::Matrix3d I_cube = Eigen::Vector3d::Constant(1.0 / 6.0).asDiagonal();
    const Eigen::Matrix3d I_child = (2.0 / 12.0 * Eigen::Vector3d(5.0, 2.0, 5.0)).asDiagonal();
    const Eigen::Matrix3d I = shifted(1.0, I_cube, {0, 0, 5}) + shifted(2.0, I_child, {10, 0, 5});
    EXPECT_LT((props.inertia_unit_density - I).norm(), kFloatRel * I.norm());
  }
}

TEST_F(MeshImportTest, MirroringNodeKeepsNormalsOutward) {
  // A node with a reflection (x -> -x): det < 0 flips the winding, so the import reverses it.
  assets::SceneSpec spec = assets::single_mesh_scene(assets::make_box(1, 2, 3, 2.0, 0.0, 0.0));
  spec.root.transform = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const ImportResult result = import_ok(write(spec, "mirrored.glb"));
  ASSERT_TRUE(result.ok());
  const MeshProperties props = compute_mesh_properties(*result.mesh);
  EXPECT_TRUE(props.closed);
  EXPECT_LT(rel_err(props.volume, 6.0), kFloatRel);  // positive: outward
  EXPECT_LT((props.centroid - Eigen::Vector3d(-2, 0, 0)).norm(), kFloatRel);
  const auto& n = result.mesh->normals;
  const auto& p = result.mesh->positions;
  for (std::size_t v = 0; v < result.mesh->num_vertices(); ++v) {
    const Eigen::Vector3d nv(n[3 * v], n[3 * v + 1], n[3 * v + 2]),
        pv(p[3 * v], p[3 * v + 1], p[3 * v + 2]);
    EXPECT_GT(nv.dot(pv - props.centroid), 0.0);
  }
}

TEST_F(MeshImportTest, ScaleMultipliesVolumeByCubeAndInertiaByFifthPower) {
  const std::string file =
      write(assets::single_mesh_scene(assets::make_box(1, 2, 3, 1, 1, 1)), "box.glb");
  const MeshProperties unit = compute_mesh_properties(*import_ok(file).mesh);
  ImportOptions options;
  options.scale = 2.5;
  const MeshProperties scaled = compute_mesh_properties(*import_ok(file, options).mesh);
  EXPECT_LT(rel_err(scaled.volume, unit.volume * std::pow(2.5, 3)), kFloatRel);
  EXPECT_LT((scaled.centroid - 2.5 * unit.centroid).norm(), kFloatRel * scaled.centroid.norm());
  EXPECT_LT((scaled.inertia_unit_density - std::pow(2.5, 5) * unit.inertia_unit_density).norm(),
            kFloatRel * scaled.inertia_unit_density.norm());
  EXPECT_TRUE(scaled.bounds_max.isApprox(2.5 * unit.bounds_max, 1e-7));
}

TEST_F(MeshImportTest, YUpFileIsRotatedIntoZUp) {
  // (x, y, z)_file -> (x, -z, y)_Hadal: a box with extents (1, 2, 3) centred at (1, 2, 3) in the
  // file has extents (1, 3, 2) centred at (1, -3, 2); a +y face normal becomes +z.
  const std::string file =
      write(assets::single_mesh_scene(assets::make_box(1, 2, 3, 1, 2, 3)), "yup.gltf");
  ImportOptions options;
  options.up_axis = UpAxis::kY;
  const ImportResult result = import_ok(file, options);
  ASSERT_TRUE(result.ok());
  const MeshProperties props = compute_mesh_properties(*result.mesh);
  EXPECT_TRUE(props.bounds_min.isApprox(Eigen::Vector3d(0.5, -4.5, 1.0), 1e-7))
      << props.bounds_min.transpose();
  EXPECT_TRUE(props.bounds_max.isApprox(Eigen::Vector3d(1.5, -1.5, 3.0), 1e-7))
      << props.bounds_max.transpose();
  EXPECT_LT(rel_err(props.volume, 6.0), kFloatRel);
  // Flat faces: every vertex normal equals its triangle's normal from the converted positions,
  // so normals were rotated with the positions; and the file's +y face now faces +z.
  const TriangleMesh& m = *result.mesh;
  int up_faces = 0;
  for (std::size_t t = 0; t < m.num_triangles(); ++t) {
    const Eigen::Vector3d n_face(props.normal_x[t], props.normal_y[t], props.normal_z[t]);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = m.indices[3 * t + k];
      EXPECT_NEAR(
          Eigen::Vector3d(m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]).dot(n_face),
          1.0, 1e-6);
    }
    up_faces += n_face.z() > 0.5 && props.centroid_z[t] > 2.9;
  }
  EXPECT_EQ(up_faces, 2);
}

TEST_F(MeshImportTest, NormalsAreUnitAndOutward) {
  // From the file (GLB), and computed when the file has none (hand-written OBJ of a tetrahedron).
  const ImportResult sphere =
      import_ok(write(assets::single_mesh_scene(assets::make_uv_sphere(0.5, 24, 12)), "s.glb"));
  ASSERT_TRUE(sphere.ok());
  write_text(path("tetra.obj"),
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
  const ImportResult tetra = import_ok(path("tetra.obj"));
  ASSERT_TRUE(tetra.ok());
  for (const ImportResult* r : {&sphere, &tetra}) {
    const TriangleMesh& m = *r->mesh;
    const MeshProperties props = compute_mesh_properties(m);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (std::size_t v = 0; v < m.num_vertices(); ++v) {
      const Eigen::Vector3d n(m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]);
      const Eigen::Vector3d p(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
      EXPECT_NEAR(n.norm(), 1.0, 1e-6);  // float normal, renormalised in double
      EXPECT_GT(n.dot(p - props.centroid), 0.0);
    }
  }
}

TEST_F(MeshImportTest, ObjPolygonsAreTriangulated) {
  write_text(path("cube.obj"),
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
             "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");
  const ImportResult result = import_ok(path("cube.obj"));
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result.mesh->num_triangles(), 12u);
  const MeshProperties props = compute_mesh_properties(*result.mesh);
  EXPECT_TRUE(props.closed);
  EXPECT_LT(rel_err(props.volume, 1.0), kFloatRel);
}

TEST_F(MeshImportTest, MaterialsBecomePerTriangleIndices) {
  assets::SceneSpec spec;
  spec.meshes = {assets::make_box(1, 1, 1), assets::make_box(1, 1, 1, 3, 0, 0)};
  spec.materials.resize(2);
  spec.materials[0].name = "hull";
  spec.materials[0].base_color = {0.9f, 0.5f, 0.1f, 1.0f};
  spec.materials[1].name = "glass";
  spec.materials[1].base_color = {0.1f, 0.2f, 0.3f, 0.5f};
  spec.mesh_materials = {0, 1};
  const ImportResult result = import_ok(write(spec, "two.glb"));
  ASSERT_TRUE(result.ok());
  const TriangleMesh& m = *result.mesh;
  ASSERT_EQ(m.materials.size(), 2u);
  ASSERT_EQ(m.triangle_materials.size(), m.num_triangles());
  for (std::size_t t = 0; t < m.num_triangles(); ++t) {
    const Material& mat = m.materials[m.triangle_materials[t]];
    const float x = m.positions[3 * m.indices[3 * t]];
    EXPECT_EQ(mat.name, x > 1.0f ? "glass" : "hull");
  }
  for (const Material& mat : m.materials) {
    const std::array<float, 4> expected =
        mat.name == "glass" ? spec.materials[1].base_color : spec.materials[0].base_color;
    for (int k = 0; k < 4; ++k) EXPECT_FLOAT_EQ(mat.base_color[k], expected[k]);
    EXPECT_EQ(mat.base_color_texture, -1);
  }
}

// ---------------------------------------------------------------------------------------------
// Textures

void expect_test_texture(const ImportResult& result, int width, int height) {
  ASSERT_TRUE(result.ok()) << result.error;
  const TriangleMesh& m = *result.mesh;
  ASSERT_EQ(m.materials.size(), 1u);
  ASSERT_EQ(m.textures.size(), 1u);
  EXPECT_EQ(m.materials[0].base_color_texture, 0);
  EXPECT_FLOAT_EQ(m.materials[0].base_color[0], 1.0f);
  EXPECT_FLOAT_EQ(m.materials[0].base_color[1], 0.5f);
  EXPECT_FLOAT_EQ(m.materials[0].base_color[2], 0.25f);
  const Texture& t = m.textures[0];
  EXPECT_EQ(t.width, width);
  EXPECT_EQ(t.height, height);
  ASSERT_EQ(t.channels, 3);
  ASSERT_EQ(t.pixels.size(), std::size_t(width) * height * 3);
  for (auto [x, y] : {std::pair{0, 0}, std::pair{3, 5}, std::pair{width - 1, height - 1}}) {
    const auto rgb = assets::test_texture_pixel(x, y);
    const std::uint8_t* px = &t.pixels[3 * (std::size_t(y) * width + x)];
    EXPECT_EQ(px[0], rgb[0]);
    EXPECT_EQ(px[1], rgb[1]);
    EXPECT_EQ(px[2], rgb[2]);
  }
  // UVs keep assimp's convention (v up): the quad corner at (-0.5, -0.5) has uv (0, 0).
  ASSERT_EQ(m.uvs.size(), 2 * m.num_vertices());
  for (std::size_t v = 0; v < m.num_vertices(); ++v)
    if (m.positions[3 * v] < 0 && m.positions[3 * v + 1] < 0) {
      EXPECT_FLOAT_EQ(m.uvs[2 * v], 0.0f);
      EXPECT_FLOAT_EQ(m.uvs[2 * v + 1], 0.0f);
    }
}

TEST_F(MeshImportTest, EmbeddedGlbTextureIsDecoded) {
  expect_test_texture(import_ok(write(assets::textured_quad_scene(16, 8), "quad.glb")), 16, 8);
}

TEST_F(MeshImportTest, DataUriTextureInGltfIsDecoded) {
  expect_test_texture(import_ok(write(assets::textured_quad_scene(12, 10), "quad.gltf")), 12, 10);
}

TEST_F(MeshImportTest, ExternalTextureBesideObjIsDecoded) {
  expect_test_texture(
      import_ok(write(assets::textured_quad_scene(9, 7, "quad_texture.png"), "quad.obj")), 9, 7);
}

TEST_F(MeshImportTest, TexturesAreSkippedWhenNotWanted) {
  ImportOptions options;
  options.load_textures = false;
  const ImportResult result =
      import_ok(write(assets::textured_quad_scene(16, 8), "quad.glb"), options);
  ASSERT_TRUE(result.ok());
  EXPECT_TRUE(result.mesh->textures.empty());
  EXPECT_EQ(result.mesh->materials[0].base_color_texture, -1);
}

TEST_F(MeshImportTest, MissingOrCorruptTextureIsAnError) {
  const std::string obj = write(assets::textured_quad_scene(9, 7, "quad_texture.png"), "quad.obj");
  fs::remove(path("quad_texture.png"));
  expect_error(obj, obj + ": material 'textured': texture file '" + path("quad_texture.png") +
                        "' not found");

  const std::string glb = write(assets::textured_quad_scene(16, 8), "quad.glb");
  std::vector<char> bytes = read_bytes(glb);
  const std::string png_magic = "\x89PNG";
  const auto at = std::search(bytes.begin(), bytes.end(), png_magic.begin(), png_magic.end());
  ASSERT_NE(at, bytes.end());
  std::fill(at, at + 16, 'x');  // break the PNG signature and header
  write_bytes(glb, bytes);
  expect_error(glb, glb + ": material 'textured': embedded texture '*0' cannot be decoded");
}

// ---------------------------------------------------------------------------------------------
// Bad input: one clear error naming the file, never a crash

TEST_F(MeshImportTest, MissingFileUnsupportedExtensionEmptyFileAndBadScale) {
  expect_error(path("nothing.glb"), path("nothing.glb") + ": file not found");
  write_text(path("model.fbx"), "x");
  expect_error(
      path("model.fbx"),
      path("model.fbx") + ": unsupported extension '.fbx' (supported: .glb, .gltf, .obj, .stl)");
  write_text(path("model"), "x");
  expect_error(path("model"),
               path("model") + ": no file extension (supported: .glb, .gltf, .obj, .stl)");
  fs::create_directory(path("folder.obj"));
  expect_error(path("folder.obj"), path("folder.obj") + ": not a regular file");
  for (const std::string ext : {".glb", ".gltf", ".obj", ".stl"}) {
    write_text(path("empty" + ext), "");
    expect_error(path("empty" + ext), path("empty" + ext) + ": file is empty");
  }
  const std::string box = write(assets::single_mesh_scene(assets::make_box(1, 1, 1)), "box.glb");
  for (double scale : {0.0, -1.0, std::nan(""), HUGE_VAL}) {
    ImportOptions options;
    options.scale = scale;
    const ImportResult result = import_mesh(box, options);
    EXPECT_FALSE(result.ok());
    EXPECT_EQ(result.error.rfind(box + ": scale must be > 0 and finite (got ", 0), 0u)
        << result.error;
  }
  ImportOptions negative;
  negative.scale = -1.0;
  expect_error(box, box + ": scale must be > 0 and finite (got -1)", negative);
  // Upper-case extensions are accepted.
  fs::copy_file(box, path("BOX.GLB"));
  EXPECT_TRUE(import_mesh(path("BOX.GLB")).ok());
}

TEST_F(MeshImportTest, TruncatedGlbAtEveryLengthClass) {
  const std::string full = write(assets::single_mesh_scene(assets::make_box(1, 1, 1)), "box.glb");
  const std::vector<char> bytes = read_bytes(full);
  const std::size_t json_length = u32_at(bytes, 12), bin_start = 20 + json_length;
  ASSERT_EQ(u32_at(bytes, 8), bytes.size());
  // Inside the header, right after it, inside the JSON chunk header and body, at the BIN chunk
  // header, inside the BIN data, one byte short.
  for (std::size_t length : {std::size_t(1), std::size_t(11), std::size_t(12), std::size_t(16),
                             std::size_t(20), 20 + json_length / 2, bin_start, bin_start + 4,
                             bin_start + 8, bin_start + 100, bytes.size() - 1}) {
    SCOPED_TRACE(length);
    const std::string file = path("truncated.glb");
    write_bytes(file, {bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(length)});
    const std::string expected = length < 12 ? file + ": truncated GLB: " + std::to_string(length) +
                                                   " bytes, shorter than the 12-byte header"
                                             : file + ": truncated GLB: header declares " +
                                                   std::to_string(bytes.size()) +
                                                   " bytes, the file has " + std::to_string(length);
    expect_error(file, expected);
  }
  // A container whose header was patched to match the truncation: the chunk walk catches it.
  std::vector<char> cut(bytes.begin(),
                        bytes.begin() + static_cast<std::ptrdiff_t>(bin_start + 100));
  set_u32(cut, 8, static_cast<std::uint32_t>(cut.size()));
  write_bytes(path("patched.glb"), cut);
  expect_error(path("patched.glb"),
               path("patched.glb") + ": truncated GLB: chunk 1 (BIN) at byte " +
                   std::to_string(bin_start) + " declares " +
                   std::to_string(u32_at(bytes, bin_start)) + " bytes, only 92 remain");
  cut.resize(bin_start + 5);
  set_u32(cut, 8, static_cast<std::uint32_t>(cut.size()));
  write_bytes(path("patched.glb"), cut);
  expect_error(path("patched.glb"), path("patched.glb") +
                                        ": truncated GLB: chunk 1 header at byte " +
                                        std::to_string(bin_start) + " is cut off");
}

TEST_F(MeshImportTest, CorruptGlbContainers) {
  const std::string full = write(assets::single_mesh_scene(assets::make_box(1, 1, 1)), "box.glb");
  const std::vector<char> bytes = read_bytes(full);
  const std::size_t json_length = u32_at(bytes, 12);
  const std::string file = path("corrupt.glb");
  auto with = [&](auto&& edit) {
    std::vector<char> b = bytes;
    edit(b);
    write_bytes(file, b);
  };
  with([](std::vector<char>& b) { b[0] = 'x'; });
  expect_error(file, file + ": corrupt GLB: bad magic (expected 'glTF')");
  with([](std::vector<char>& b) { set_u32(b, 4, 1); });
  expect_error(file, file + ": unsupported GLB version 1 (only glTF 2.0 binary is supported)");
  with([](std::vector<char>& b) { b.push_back(0); });
  expect_error(file, file + ": corrupt GLB: header declares " + std::to_string(bytes.size()) +
                         " bytes, the file has " + std::to_string(bytes.size() + 1));
  with([](std::vector<char>& b) { set_u32(b, 16, 0x004E4942); });  // first chunk typed BIN
  expect_error(file, file + ": corrupt GLB: the first chunk is not JSON");
  with([&](std::vector<char>& b) {
    set_u32(b, 20 + json_length, u32_at(b, 20 + json_length) + 1000);
  });
  expect_error(file, file + ": truncated GLB: chunk 1 (BIN) at byte " +
                         std::to_string(20 + json_length) + " declares " +
                         std::to_string(u32_at(bytes, 20 + json_length) + 1000) + " bytes, only " +
                         std::to_string(u32_at(bytes, 20 + json_length)) + " remain");
  // Consistent container, broken content: assimp's reader reports it (its wording is assimp's, so
  // only Hadal's part of the message is pinned).
  with([](std::vector<char>& b) { std::fill(b.begin() + 20, b.begin() + 40, '@'); });
  expect_error(file, file + ": cannot read GLB: content not recognised as GLB");
  with([&](std::vector<char>& b) {  // drop the BIN chunk: buffer views point past the data
    b.resize(20 + json_length);
    set_u32(b, 8, static_cast<std::uint32_t>(b.size()));
  });
  const ImportResult no_bin = import_mesh(file);
  EXPECT_FALSE(no_bin.ok());
  EXPECT_EQ(no_bin.error.rfind(file + ": cannot read GLB: ", 0), 0u) << no_bin.error;
}

TEST_F(MeshImportTest, GltfWithItsBinDeletedNamesTheMissingFile) {
  const std::string file = write(assets::single_mesh_scene(assets::make_box(1, 1, 1)), "box.gltf");
  std::string bin;
  for (const auto& entry : fs::directory_iterator(dir_))
    if (entry.path().extension() == ".bin") bin = entry.path().string();
  ASSERT_FALSE(bin.empty());
  fs::remove(bin);
  expect_error(file, file + ": referenced file '" + bin + "' not found");
}

TEST_F(MeshImportTest, GltfWithBufferInADataUriNeedsNoBin) {
  const std::string file = write(assets::single_mesh_scene(assets::make_box(1, 2, 3)), "box.gltf");
  std::string bin;
  for (const auto& entry : fs::directory_iterator(dir_))
    if (entry.path().extension() == ".bin") bin = entry.path().string();
  ASSERT_FALSE(bin.empty());
  const std::vector<char> json_bytes = read_bytes(file);
  std::string json(json_bytes.begin(), json_bytes.end());
  const std::string uri = "\"" + fs::path(bin).filename().string() + "\"";
  const auto at = json.find(uri);
  ASSERT_NE(at, std::string::npos);
  json.replace(at, uri.size(),
               "\"data:application/octet-stream;base64," + base64(read_bytes(bin)) + "\"");
  fs::remove(bin);
  write_text(file, json);
  const ImportResult result = import_ok(file);
  ASSERT_TRUE(result.ok());
  const MeshProperties props = compute_mesh_properties(*result.mesh);
  EXPECT_TRUE(props.closed);
  EXPECT_LT(rel_err(props.volume, 6.0), kFloatRel);
}

TEST_F(MeshImportTest, ReferencedNamesThatCrashAssimpAreRejected) {
  // Fuzzer finding: assimp 5.2's FileSystemFilter::Cleanup runs past the end of a referenced name
  // ending in "://" (segfault). import_mesh rejects such names before assimp reads the file.
  const std::string obj = path("bad_mtllib.obj");
  write_bytes(obj,
              {'m', 't', 'l', 'l', 'i', 'b', ' ', 's', '4', ' ', ':', '/', '/', '\0', '\0', '\0'});
  expect_error(obj, obj + ": unusable material library name 's4 ://\\x00\\x00\\x00'");
  const std::string gltf = write(assets::single_mesh_scene(assets::make_box(1, 1, 1)), "box.gltf");
  const std::vector<char> bytes = read_bytes(gltf);
  std::string json(bytes.begin(), bytes.end());
  const auto at = json.find("\"uri\"");
  ASSERT_NE(at, std::string::npos);
  const auto open = json.find('"', json.find(':', at)), close = json.find('"', open + 1);
  for (const std::string uri :
       {"a://", "dir\\/x:\\/\\/", "b\\u003a//"}) {  // plain and JSON-escaped
    SCOPED_TRACE(uri);
    std::string edited = json;
    edited.replace(open + 1, close - open - 1, uri);
    write_text(gltf, edited);
    const ImportResult result = import_mesh(gltf);
    EXPECT_FALSE(result.ok());
    EXPECT_EQ(result.error.rfind(gltf + ": unusable file reference (uri) '", 0), 0u)
        << result.error;
  }
  // A .gltf that is not glTF goes to whichever assimp reader knows its content: OBJ lines with
  // such a material library name crashed it the same way (fuzzer finding); they are refused as in an OBJ.
  const std::string broken = path("broken.gltf");
  write_text(broken, "{ \"asset\": {\"version\": \"2.0\"\n# not JSON any more\nmtllib box.m://\n"
                     "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  expect_error(broken, broken + ": unusable material library name 'box.m://'");
  // A blank uri is safe (assimp is given a path with a directory) and reported as missing.
  std::string blank = json;
  blank.replace(open + 1, close - open - 1, " ");
  write_text(gltf, blank);
  expect_error(gltf, gltf + ": referenced file '" + dir_ + "/ ' not found");
}

TEST_F(MeshImportTest, NonFiniteVerticesAreRejected) {
  write_text(path("nan.obj"), "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n");
  expect_error(
      path("nan.obj"),
      path("nan.obj") + ": mesh 'defaultobject' vertex 2 has a non-finite coordinate (0, nan, 0)");
  write_text(path("inf.stl"),
             "solid probe\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
             "   vertex 0 1 inf\n  endloop\n endfacet\nendsolid probe\n");
  expect_error(path("inf.stl"),
               path("inf.stl") + ": mesh 'probe' vertex 2 has a non-finite coordinate (0, 1, inf)");
  // Finite in the file but not after scaling.
  write_text(path("big.obj"), "v 0 0 0\nv 3e38 0 0\nv 0 1 0\nf 1 2 3\n");
  ImportOptions options;
  options.scale = 10.0;
  expect_error(
      path("big.obj"),
      path("big.obj") + ": mesh 'defaultobject' vertex 1 has a non-finite coordinate (3e+38, 0, 0)",
      options);
}

TEST_F(MeshImportTest, DegenerateTrianglesAreDroppedAndCounted) {
  // A closed tetrahedron plus a triangle with a repeated vertex and one with collinear corners.
  write_text(path("tetra.obj"),
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 2 0 0\n"
             "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\nf 1 2 1\nf 1 2 5\n");
  const ImportResult result = import_ok(path("tetra.obj"));
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result.degenerate_triangles_dropped, 2u);
  EXPECT_EQ(result.mesh->num_triangles(), 4u);
  const MeshProperties props = compute_mesh_properties(*result.mesh);
  EXPECT_TRUE(props.closed);
  EXPECT_LT(rel_err(props.volume, 1.0 / 6.0), kFloatRel);
  // Repeated indices in an indexed format (GLB).
  assets::MeshData box = assets::make_box(1, 1, 1);
  box.indices.insert(box.indices.end(), {0, 0, 1, 2, 3, 2});
  const ImportResult glb = import_ok(write(assets::single_mesh_scene(box), "box.glb"));
  ASSERT_TRUE(glb.ok());
  EXPECT_EQ(glb.degenerate_triangles_dropped, 2u);
  EXPECT_EQ(glb.mesh->num_triangles(), 12u);
}

TEST_F(MeshImportTest, FilesWithoutTrianglesAreErrors) {
  write_text(path("points.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expect_error(path("points.obj"),
               path("points.obj") + ": no triangles (the file holds no triangle geometry)");
  write_text(path("lines.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
  expect_error(path("lines.obj"),
               path("lines.obj") + ": no triangles (the file holds no triangle geometry)");
  write_text(path("flat.obj"), "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 3 2 1\n");
  expect_error(path("flat.obj"),
               path("flat.obj") + ": no triangles (all 2 triangles are degenerate)");
}

TEST_F(MeshImportTest, OpenMeshImportsAndReportsBoundary) {
  assets::SeabedSpec spec;
  spec.cells_x = 12;
  spec.cells_y = 7;
  const ImportResult result =
      import_ok(write(assets::single_mesh_scene(assets::make_seabed(spec)), "seabed.glb"));
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result.mesh->num_triangles(), 2u * 12 * 7);
  const MeshProperties props = compute_mesh_properties(*result.mesh);
  EXPECT_FALSE(props.closed);
  EXPECT_EQ(props.boundary_edges, 2u * (12 + 7));
}

TEST_F(MeshImportTest, MissingMtlIsAWarningNotAnError) {
  write_text(
      path("tetra.obj"),
      "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
  const ImportResult result = import_ok(path("tetra.obj"));
  ASSERT_TRUE(result.ok());
  ASSERT_FALSE(result.warnings.empty());
  EXPECT_EQ(result.warnings[0].rfind(path("tetra.obj") + ": file '", 0), 0u) << result.warnings[0];
  EXPECT_NE(result.warnings[0].find("gone.mtl' not found"), std::string::npos)
      << result.warnings[0];
}

// Truncations of every format at every length, and seeded random byte corruption: the importer
// must return (ok or error), never crash, and an error must name the file.
TEST_F(MeshImportTest, TruncatedAndCorruptedFilesNeverCrash) {
  const assets::SceneSpec spec = assets::single_mesh_scene(assets::make_box(1, 1, 1));
  std::mt19937 rng(12345);
  for (const std::string name : {"b.glb", "b.gltf", "b.obj", "b.stl", "a.stl"}) {
    SCOPED_TRACE(name);
    const std::string original = write(spec, "src_" + name, name == "a.stl");
    const std::vector<char> bytes = read_bytes(original);
    const std::string file = path(name);
    // For glTF the JSON is the file (its .bin stays intact beside the source); step through it.
    const std::size_t step = std::max<std::size_t>(1, bytes.size() / 150);
    for (std::size_t length = 0; length < bytes.size(); length += step) {
      write_bytes(file, {bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(length)});
      const ImportResult r = import_mesh(file);
      if (!r.ok()) {
        EXPECT_EQ(r.error.rfind(file + ": ", 0), 0u) << r.error;
      }
      if (name == "b.glb") {
        EXPECT_FALSE(r.ok());
      }
    }
    for (int trial = 0; trial < 40; ++trial) {
      std::vector<char> corrupt = bytes;
      const int flips = 1 + static_cast<int>(rng() % 8);
      for (int k = 0; k < flips; ++k) corrupt[rng() % corrupt.size()] = static_cast<char>(rng());
      write_bytes(file, corrupt);
      const ImportResult r = import_mesh(file);
      if (!r.ok()) {
        EXPECT_EQ(r.error.rfind(file + ": ", 0), 0u) << r.error;
      }
      if (r.ok()) {  // whatever survived is well formed
        for (std::uint32_t i : r.mesh->indices) ASSERT_LT(i, r.mesh->num_vertices());
        for (float x : r.mesh->positions) ASSERT_TRUE(std::isfinite(x));
      }
    }
  }
}

TEST_F(MeshImportTest, LargeMeshUsesTheParallelPathAndMatchesTheSource) {
  // 2 * 260 * 260 = 135k triangles: several work chunks on each pass, and a scene large enough to
  // be freed on the background thread (default) -- or before returning (background_cleanup off).
  assets::SeabedSpec spec;
  spec.cells_x = spec.cells_y = 260;
  const assets::MeshData seabed = assets::make_seabed(spec);
  const std::string file = write(assets::single_mesh_scene(seabed), "big.glb");
  const ImportResult result = import_ok(file);
  ASSERT_TRUE(result.ok());
  // The exporter may renumber vertices but keeps the triangles in order: compare corner positions.
  const TriangleMesh& m = *result.mesh;
  ASSERT_EQ(m.indices.size(), seabed.indices.size());
  for (std::size_t c = 0; c < m.indices.size(); ++c)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(m.positions[3 * m.indices[c] + k], seabed.positions[3 * seabed.indices[c] + k])
          << c;
  EXPECT_GT(result.load_seconds, 0.0);
  wait_for_background_cleanup();
  ImportOptions sync;
  sync.background_cleanup = false;
  const ImportResult again = import_ok(file, sync);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again.mesh->positions, m.positions);
  EXPECT_EQ(again.mesh->normals, m.normals);
  EXPECT_EQ(again.mesh->uvs, m.uvs);
  EXPECT_EQ(again.mesh->indices, m.indices);
}

}  // namespace
}  // namespace hadal::geometry
