// TriangleMesh: geometry as flat, contiguous arrays (structure of arrays, no per-triangle objects),
// in Hadal's frame conventions after unit scaling and up-axis conversion (z up, metres).
//
// positions: x0 y0 z0 x1 y1 z1 ... (float, 3 per vertex) [m]
// normals:   3 per vertex, or empty                     [unit]
// uvs:       2 per vertex, or empty                     [texture coordinates, v up: texel row
//            (1 - v) * height, row 0 at the image top; assimp's and OpenGL's convention]
// indices:   3 per triangle, counter-clockwise seen from outside (outward normal by the right-hand rule)
// triangle_materials: one index into `materials` per triangle, or empty (all material 0)
// Positions are float (Embree's and the GPU's format); properties that need precision (volume,
// inertia) are accumulated in double.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace hadal::geometry {

// An 8-bit image, row-major, interleaved channels (RGB or RGBA), decoded with OpenCV at load.
struct Texture {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<std::uint8_t> pixels;  // width * height * channels
};

struct Material {
  std::string name;
  std::array<float, 4> base_color{1.0f, 1.0f, 1.0f, 1.0f};  // linear RGBA factor (glTF baseColorFactor)
  int base_color_texture = -1;  // index into TriangleMesh::textures, or -1
};

struct TriangleMesh {
  std::vector<float> positions;
  std::vector<float> normals;
  std::vector<float> uvs;
  std::vector<std::uint32_t> indices;
  std::vector<std::uint32_t> triangle_materials;
  std::vector<Material> materials;
  std::vector<Texture> textures;

  std::size_t num_vertices() const { return positions.size() / 3; }
  std::size_t num_triangles() const { return indices.size() / 3; }
};

// Throws std::invalid_argument, its message starting with `prefix`, unless the mesh is whole: triples of
// positions and indices, at least one triangle, at most 2^32 - 1 vertices and triangles, finite vertices,
// indices in range, two uvs per vertex if any, a material per triangle (in range) if any.
void validate(const TriangleMesh& mesh, const std::string& prefix);

}  // namespace hadal::geometry
