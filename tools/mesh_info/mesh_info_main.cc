// hadal-mesh-info: imports a mesh the way hadald does and prints ONE JSON object on stdout:
//   triangles, vertices, bounds {min, max} [m], closed, boundary_edges, non_manifold_edges,
//   volume [m^3], centroid [m], inertia [m^5] (about the centroid, unit density, 3x3 row-major),
//   surface_area [m^2], degenerate_dropped, materials, textures, load_seconds (import only).
// volume, centroid and inertia are null when the mesh is not closed (the integrals are
// meaningless).
//   hadal-mesh-info FILE [--scale S] [--up-axis y|z]
// With --mass M it prints instead a link's mass block, YAML to paste under a link whose mesh sits at the
// link's origin: the homogeneous solid of mass M (density M / volume), centre of mass its centroid,
// inertia about it in the mesh's axes (after --scale and --up-axis), as configs/REFERENCE.md's
// links[].inertia; an open or inward-oriented mesh has none (exit 1).
//   hadal-mesh-info FILE [--scale S] [--up-axis y|z] [--mass M]
// Exit status: 0 success; 1 the file cannot be imported (message on stderr, nothing on stdout);
// 2 usage error. Warnings (e.g. an OBJ's missing .mtl) go to stderr.
#include <cstdio>
#include <optional>
#include <string>

#include "cli_args.h"
#include "json_number.h"
#include "hadal/geometry/mesh_import.h"
#include "hadal/geometry/mesh_properties.h"

namespace {

using hadal::tools::json_number;

constexpr const char* kUsage =
    "usage: hadal-mesh-info FILE [--scale S] [--up-axis y|z] [--mass M]\n"
    "  FILE         .glb, .gltf, .obj or .stl\n"
    "  --scale S    file units -> metres (> 0, default 1)\n"
    "  --up-axis A  the file's up axis: z (default, no rotation) or y (glTF convention; rotated\n"
    "               +90 deg about x into Hadal's z-up frame)\n"
    "  --mass M     print instead a link's mass, center_of_mass and inertia (YAML) for the closed\n"
    "               mesh as a homogeneous solid of M kg (> 0)\n"
    "Prints one JSON object (SI units, Hadal's frame); inertia is about the centroid for unit "
    "density.\n";

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

// The --mass block (header comment). I = inertia_unit_density * density; an inward-oriented mesh has a
// negative volume, and is refused as hadald refuses it for a link.
int print_mass_block(const std::string& file, const hadal::geometry::MeshProperties& props, double mass) {
  if (!props.closed || !(props.volume > 0.0)) {
    std::fprintf(stderr, "hadal-mesh-info: %s: %s, so it has no volume to spread %s kg over\n", file.c_str(),
                 props.closed ? "the mesh is oriented inward" : "the mesh is not closed", json_number(mass).c_str());
    return 1;
  }
  const double density = mass / props.volume;
  const Eigen::Matrix3d I = props.inertia_unit_density * density;
  std::printf("# %s as a homogeneous solid: volume %s m^3, density %s kg/m^3; for a link whose `mesh` has\n"
              "# this scale and up_axis and no pose (configs/REFERENCE.md, links[])\n",
              file.c_str(), json_number(props.volume).c_str(), json_number(density).c_str());
  std::printf("mass: %s\n", json_number(mass).c_str());
  std::printf("center_of_mass: %s\n", json_vector(props.centroid).c_str());
  std::printf("inertia: {ixx: %s, iyy: %s, izz: %s, ixy: %s, ixz: %s, iyz: %s}\n", json_number(I(0, 0)).c_str(),
              json_number(I(1, 1)).c_str(), json_number(I(2, 2)).c_str(), json_number(I(0, 1)).c_str(),
              json_number(I(0, 2)).c_str(), json_number(I(1, 2)).c_str());
  return std::fflush(stdout) == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace hadal::geometry;
  std::string file;
  ImportOptions options;
  double mass = 0.0;  // [kg]; 0: the JSON report
  hadal::tools::CommandLine command_line("hadal-mesh-info", kUsage);
  command_line.unknown_words("unknown option %s")
      .option_syntax(hadal::tools::OptionSyntax::kDoubleDash)
      .number("--scale", &options.scale, hadal::tools::NumberRange::greater_than(0.0))
      .number("--mass", &mass, hadal::tools::NumberRange::greater_than(0.0))
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
  if (mass > 0.0) return print_mass_block(file, props, mass);

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
