#include "hadal/geometry/triangle_mesh.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace hadal::geometry {

void validate(const TriangleMesh& mesh, const std::string& prefix) {
  if (mesh.positions.size() % 3 != 0) {
    throw std::invalid_argument(prefix + "positions has " + std::to_string(mesh.positions.size()) +
                                " floats, not a multiple of 3");
  }
  if (mesh.indices.size() % 3 != 0) {
    throw std::invalid_argument(prefix + "indices has " + std::to_string(mesh.indices.size()) +
                                " entries, not a multiple of 3");
  }
  const std::size_t num_vertices = mesh.num_vertices();
  const std::size_t num_triangles = mesh.num_triangles();
  if (num_triangles == 0 || num_vertices == 0) {
    throw std::invalid_argument(prefix + "empty mesh (" + std::to_string(num_vertices) +
                                " vertices, " + std::to_string(num_triangles) + " triangles)");
  }
  if (num_vertices > std::numeric_limits<std::uint32_t>::max() ||
      num_triangles > std::numeric_limits<std::uint32_t>::max()) {
    throw std::invalid_argument(prefix + "more than 2^32 - 1 vertices or triangles");
  }
  for (std::size_t v = 0; v < num_vertices; ++v) {
    const float* p = &mesh.positions[3 * v];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      throw std::invalid_argument(prefix + "vertex " + std::to_string(v) + " is not finite");
    }
  }
  for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
    if (mesh.indices[i] >= num_vertices) {
      throw std::invalid_argument(prefix + "triangle " + std::to_string(i / 3) + " has vertex index " +
                                  std::to_string(mesh.indices[i]) + ", out of range (the mesh has " +
                                  std::to_string(num_vertices) + " vertices)");
    }
  }
  if (!mesh.uvs.empty() && mesh.uvs.size() != 2 * num_vertices) {
    throw std::invalid_argument(prefix + "uvs has " + std::to_string(mesh.uvs.size()) + " values for " +
                                std::to_string(num_vertices) + " vertices (2 each)");
  }
  if (!mesh.triangle_materials.empty()) {
    if (mesh.triangle_materials.size() != num_triangles) {
      throw std::invalid_argument(prefix + "triangle_materials has " +
                                  std::to_string(mesh.triangle_materials.size()) + " entries for " +
                                  std::to_string(num_triangles) + " triangles");
    }
    if (!mesh.materials.empty()) {
      for (std::size_t t = 0; t < num_triangles; ++t) {
        if (mesh.triangle_materials[t] >= mesh.materials.size()) {
          throw std::invalid_argument(prefix + "triangle " + std::to_string(t) + " has material " +
                                      std::to_string(mesh.triangle_materials[t]) +
                                      ", out of range (the mesh has " +
                                      std::to_string(mesh.materials.size()) + " materials)");
        }
      }
    }
  }
}

}  // namespace hadal::geometry
