// Scenes built in code and written with assimp's Exporter (how every test asset is made; no model
// file is ever committed). Formats follow the file extension:
//   .glb -> "glb2" (binary glTF 2, textures embedded), .gltf -> "gltf2" (JSON + .bin beside it),
//   .obj -> "obj" (+ .mtl), .stl -> "stlb" (binary) or "stl" (ASCII, `stl_ascii`).
// STL carries neither materials nor a hierarchy (assimp pre-transforms the vertices); OBJ bakes
// node transforms into the vertices.
#pragma once

#include <assimp/scene.h>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hadal/assets/mesh_generators.h"

namespace hadal::assets {

struct SceneMaterial {
  std::string name = "material";
  std::array<float, 4> base_color{0.8f, 0.8f, 0.8f, 1.0f};  // linear RGBA
  // Base-colour texture as PNG bytes, or empty. Embedded in GLB/glTF ("*N" reference) unless
  // `texture_file` is set, in which case it is written beside the model under that relative name.
  std::vector<std::uint8_t> texture_png;
  std::string texture_file;
};

struct SceneNode {
  std::string name = "node";
  // Node-to-parent transform, row-major 4x4 acting on column vectors (assimp's convention).
  std::array<double, 16> transform{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::vector<unsigned> meshes;  // indices into SceneSpec::meshes
  std::vector<SceneNode> children;
};

struct SceneSpec {
  std::vector<MeshData> meshes;
  std::vector<unsigned> mesh_materials;  // one per mesh (default: material 0)
  std::vector<SceneMaterial> materials;  // default: one grey material
  SceneNode root;                        // default: root holding every mesh
};

// A scene holding one mesh in the root node with one material.
SceneSpec single_mesh_scene(MeshData mesh, SceneMaterial material = {});

// Row-major 4x4 of a rotation by `angle_rad` about a unit axis followed by a translation.
std::array<double, 16> rigid_transform(const double axis[3], double angle_rad, const double t[3]);

// Two-node scene for the node-transform test: the root holds a unit cube at the origin; its child
// node ("child", transform X_RC = translation (10, 0, 0) * rotation +90 deg about z) holds a
// 2 x 1 x 1 box centred at its own origin, so in the root frame the box spans x in [9.5, 10.5],
// y in [-1, 1], z in [-0.5, 0.5]. The root itself carries translation (0, 0, 5) so accumulation is
// exercised: every world z is shifted by +5.
SceneSpec two_node_scene();

// Test texture: width x height RGB, pixel (x, y) = test_texture_pixel(x, y) (row 0 at the top).
std::array<std::uint8_t, 3> test_texture_pixel(int x, int y);
std::vector<std::uint8_t> make_test_texture_png(int width, int height);

// A 1 m x 1 m quad in the xy-plane facing +z, UVs over [0, 1]^2, textured with the test texture.
// With `external_texture_file` set the PNG is written beside the model instead of being embedded.
SceneSpec textured_quad_scene(int texture_width, int texture_height,
                              const std::string& external_texture_file = "");

// Builds the aiScene in memory (what write_scene exports).
std::unique_ptr<aiScene> build_ai_scene(const SceneSpec& spec);

// Writes `spec` to `path` (format from the extension, see above). Returns "" on success, otherwise
// an error message naming the file.
std::string write_scene(const SceneSpec& spec, const std::string& path, bool stl_ascii = false);

}  // namespace hadal::assets
