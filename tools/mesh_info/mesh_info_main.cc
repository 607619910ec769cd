// hadal-mesh-info: imports a mesh the way hadald does and prints ONE JSON object on stdout:
//   triangles, vertices, bounds {min, max} [m], closed, boundary_edges, non_manifold_edges,
//   volume [m^3], centroid [m], inertia [m^5] (about the centroid, unit density, 3x3 row-major),
//   surface_area [m^2], degenerate_dropped, materials, textures, load_seconds (import only).
// volume, centroid and inertia are null when the mesh is not closed (the integrals are
// meaningless).
//   hadal-mesh-info FILE [--scale S] [--up-axis y|z]
// Exit status: 0 success; 1 the file cannot be imported (message on stderr, nothing on stdout);
// 2 usage error. Warnings (e.g. an OBJ's missing .mtl) go to stderr.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "cli_args.h"
#include "json_number.h"
#include "hadal/geometry/mesh_import.h"
#include "hadal/geometry/mesh_properties.h"

namespace {

using hadal::tools::json_number;

constexpr const char* kUsage =
    "usage: hadal-mesh-info FILE [--scale S] [--up-axis y|z]\n"
    "  FILE         .glb, .gltf, .obj or .stl\n"
    "  --scale S    file units -> metres (> 0, default 1)\n"
    "  --up-axis A  the file's up axis: z (default, no rotation) or y (glTF convention; rotated\n"
    "               +90 deg about x into Hadal's z-up frame)\n"
    "Prints one JSON object (SI units, Hadal's frame); inertia is about the centroid for unit "
    "density.\n";

// --scale S: "" when S is a finite number > 0 (into *scale), else the usage error.
std::string read_scale(const std::string& text, double* scale) {
  char* end = nullptr;
  *scale = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0') return "--scale: not a number: " + text;
  if (!(*scale > 0.0) || !std::isfinite(*scale)) return "--scale must be > 0 and finite (got " + text + ")";
  return "";
}

std::string read_up_axis(const std::string& text, hadal::geometry::UpAxis* up_axis) {
  if (text == "y" || text == "Y") {
    *up_axis = hadal::geometry::UpAxis::kY;
  } else if (text == "z" || text == "Z") {
    *up_axis = hadal::geometry::UpAxis::kZ;
  } else {
    return "--up-axis must be y or z (got " + text + ")";
  }
  return "";
}

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (unsigned char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\u%04x", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}


template <class Vector>
std::string json_vector(const Vector& v) {
  return "[" + json_number(v[0]) + ", " + json_number(v[1]) + ", " + json_number(v[2]) + "]";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace hadal::geometry;
  std::string file;
  ImportOptions options;
  hadal::tools::CommandLine command_line("hadal-mesh-info", kUsage);
  command_line.unknown_words("unknown option %s")
      .option_syntax(hadal::tools::OptionSyntax::kDoubleDash)
      .option("--scale", [&](const std::string& value) { return read_scale(value, &options.scale); })
      .option("--up-axis", [&](const std::string& value) { return read_up_axis(value, &options.up_axis); },
              "--up-axis needs y or z")
      .one_positional(&file, "more than one FILE");
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  if (file.empty()) return command_line.usage_error("missing FILE");

  const ImportResult result = import_mesh(file, options);
  for (const std::string& warning : result.warnings)
    std::fprintf(stderr, "hadal-mesh-info: warning: %s\n", warning.c_str());
  if (!result.ok()) {
    std::fprintf(stderr, "hadal-mesh-info: %s\n", result.error.c_str());
    return 1;
  }
  const TriangleMesh& mesh = *result.mesh;
  const MeshProperties props = compute_mesh_properties(mesh);

  std::string json = "{";
  json += "\"file\": " + json_string(file);
  json += ", \"triangles\": " + std::to_string(mesh.num_triangles());
  json += ", \"vertices\": " + std::to_string(mesh.num_vertices());
  json += ", \"bounds\": {\"min\": " + json_vector(props.bounds_min) +
          ", \"max\": " + json_vector(props.bounds_max) + "}";
  json += std::string(", \"closed\": ") + (props.closed ? "true" : "false");
  json += ", \"boundary_edges\": " + std::to_string(props.boundary_edges);
  json += ", \"non_manifold_edges\": " + std::to_string(props.non_manifold_edges);
  if (props.closed) {
    const auto& I = props.inertia_unit_density;
    json += ", \"volume\": " + json_number(props.volume);
    json += ", \"centroid\": " + json_vector(props.centroid);
    json += ", \"inertia\": [" + json_vector(I.row(0)) + ", " + json_vector(I.row(1)) + ", " +
            json_vector(I.row(2)) + "]";
  } else {
    json += ", \"volume\": null, \"centroid\": null, \"inertia\": null";
  }
  json += ", \"surface_area\": " + json_number(props.surface_area);
  json += ", \"degenerate_dropped\": " + std::to_string(result.degenerate_triangles_dropped);
  json += ", \"materials\": " + std::to_string(mesh.materials.size());
  json += ", \"textures\": " + std::to_string(mesh.textures.size());
  json += ", \"load_seconds\": " + json_number(result.load_seconds);
  json += "}\n";
  std::fputs(json.c_str(), stdout);
  return std::fflush(stdout) == 0 ? 0 : 1;
}
