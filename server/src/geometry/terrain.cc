#include "hadal/geometry/terrain.h"

namespace hadal::geometry {

TriangleMesh heightfield_to_mesh(const HeightField& field) {
  TriangleMesh mesh;
  const auto nx = static_cast<std::size_t>(field.nx);
  const auto ny = static_cast<std::size_t>(field.ny);
  mesh.positions.resize(nx * ny * 3);
  for (std::size_t j = 0; j < ny; ++j) {
    for (std::size_t i = 0; i < nx; ++i) {
      float* p = &mesh.positions[(j * nx + i) * 3];
      p[0] = static_cast<float>(field.x0 + static_cast<double>(i) * field.dx);
      p[1] = static_cast<float>(field.y0 + static_cast<double>(j) * field.dy);
      p[2] = field.heights[j * nx + i];
    }
  }
  mesh.indices.resize((nx - 1) * (ny - 1) * 6);
  std::uint32_t* index = mesh.indices.data();
  for (std::size_t j = 0; j + 1 < ny; ++j) {
    for (std::size_t i = 0; i + 1 < nx; ++i) {
      const auto a = static_cast<std::uint32_t>(j * nx + i);  // (i, j)
      const auto b = a + 1;                                   // (i+1, j)
      const auto c = static_cast<std::uint32_t>(a + nx);      // (i, j+1)
      const auto d = c + 1;                                   // (i+1, j+1)
      // Counter-clockwise seen from +z: (a, b, d) and (a, d, c).
      *index++ = a; *index++ = b; *index++ = d;
      *index++ = a; *index++ = d; *index++ = c;
    }
  }
  Material seabed;
  seabed.name = "seabed";
  mesh.materials.push_back(seabed);
  return mesh;
}

}  // namespace hadal::geometry
