// hadal-make-asset: writes a generated test mesh (assimp Exporter; format from the extension).
//   hadal-make-asset SHAPE OUTPUT.{glb,gltf,obj,stl} [options]
// Exit status: 0 written, 1 generation/export error, 2 usage error.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "hadal/assets/mesh_generators.h"
#include "hadal/assets/scene_writer.h"
#include "hadal/assets/zoo_meshes.h"
#include "cli_args.h"

namespace {

constexpr const char* kUsage =
    "usage: hadal-make-asset SHAPE OUTPUT.{glb,gltf,obj,stl} [options]\n"
    "shapes:\n"
    "  box            closed box                      --size X Y Z [1 1 1] --center X Y Z [0 0 0]\n"
    "  sphere         UV sphere                       --radius R [0.5] --segments N [32] --rings N "
    "[N/2]\n"
    "  cylinder       closed cylinder along z         --radius R [0.5] --length L [2] --segments N "
    "[32]\n"
    "  torpedo        AUV hull along x                --radius R [0.15] --length L [2] --segments "
    "N [32]\n"
    "  frame          ROV-like frame of square bars   --size X Y Z [1.5 1 1] --bar B [0.05]\n"
    "  lander         frame on four legs              --size X Y Z [2 2 1.5] --bar B [0.08] "
    "--leg-length L [0.6]\n"
    "  seabed         seeded height field             --triangles N [10000] --extent E [100] "
    "--seed S [1]\n"
    "  two-node       root cube + child box with a known node transform\n"
    "  textured-quad  quad with a generated PNG base-colour texture\n"
    "                                                 --texture-size W H [16 8] --external-texture "
    "NAME\n"
    "  zoo            the vehicle zoo's visual models: OUTPUT is a directory, one <part>.glb each\n"
    "                 (configs/meshes/ holds the committed copies)\n"
    "options: --stl-ascii (ASCII STL instead of binary)\n"
    "All lengths in metres; Hadal's frame (z up, x forward).\n";

bool parse_double(const char* text, double& out) {
  char* end = nullptr;
  out = std::strtod(text, &end);
  return end != text && *end == '\0';
}

}  // namespace

int main(int argc, char** argv) {
  using namespace hadal::assets;
  // Its usage errors only: SHAPE and OUTPUT come first, options take one to three numbers, --help stands alone.
  const hadal::tools::CommandLine command_line("hadal-make-asset", kUsage);
  if (argc == 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (argc < 3) return command_line.usage_error("need SHAPE and OUTPUT");
  const std::string shape = argv[1], output = argv[2];
  std::vector<double> size, center{0, 0, 0}, texture_size{16, 8};
  double radius = -1, length = -1, bar = -1, leg_length = 0.6, triangles = 10000, extent = 100,
         seed = 1, segments = 32, rings = -1;
  std::string external_texture;
  bool stl_ascii = false;
  for (int i = 3; i < argc; ++i) {
    const std::string arg = argv[i];
    auto values = [&](std::size_t n, std::vector<double>& out) {
      if (i + static_cast<int>(n) >= argc) return false;
      out.assign(n, 0.0);
      for (std::size_t k = 0; k < n; ++k)
        if (!parse_double(argv[++i], out[k])) return false;
      return true;
    };
    auto value = [&](double& out) { return i + 1 < argc && parse_double(argv[++i], out); };
    bool ok = true;
    if (arg == "--size")
      ok = values(3, size);
    else if (arg == "--center")
      ok = values(3, center);
    else if (arg == "--texture-size")
      ok = values(2, texture_size);
    else if (arg == "--radius")
      ok = value(radius);
    else if (arg == "--length")
      ok = value(length);
    else if (arg == "--segments")
      ok = value(segments);
    else if (arg == "--rings")
      ok = value(rings);
    else if (arg == "--bar")
      ok = value(bar);
    else if (arg == "--leg-length")
      ok = value(leg_length);
    else if (arg == "--triangles")
      ok = value(triangles);
    else if (arg == "--extent")
      ok = value(extent);
    else if (arg == "--seed")
      ok = value(seed);
    else if (arg == "--external-texture" && i + 1 < argc)
      external_texture = argv[++i];
    else if (arg == "--stl-ascii")
      stl_ascii = true;
    else
      return command_line.usage_error("unknown option '" + arg + "'");
    if (!ok) return command_line.usage_error("bad or missing value for " + arg);
  }

  if (shape == "zoo") {
    for (const std::string& part : zoo_parts()) {
      const std::string path = output + "/" + part + ".glb";
      const std::string error = write_scene(zoo_part_scene(part), path);
      if (!error.empty()) {
        std::fprintf(stderr, "hadal-make-asset: %s\n", error.c_str());
        return 1;
      }
      std::printf("wrote %s\n", path.c_str());
    }
    return 0;
  }
  SceneSpec spec;
  try {
    const int n = static_cast<int>(segments);
    if (shape == "box") {
      if (size.empty()) size = {1, 1, 1};
      spec =
          single_mesh_scene(make_box(size[0], size[1], size[2], center[0], center[1], center[2]));
    } else if (shape == "sphere") {
      spec = single_mesh_scene(
          make_uv_sphere(radius > 0 ? radius : 0.5, n, rings > 0 ? int(rings) : n / 2));
    } else if (shape == "cylinder") {
      spec =
          single_mesh_scene(make_cylinder(radius > 0 ? radius : 0.5, length > 0 ? length : 2.0, n));
    } else if (shape == "torpedo") {
      spec = single_mesh_scene(
          make_torpedo(length > 0 ? length : 2.0, radius > 0 ? radius : 0.15, n, 12));
    } else if (shape == "frame") {
      if (size.empty()) size = {1.5, 1.0, 1.0};
      spec = single_mesh_scene(make_grid_solid(
          box_frame_solid(size[0], size[1], size[2], bar > 0 ? bar : 0.05), "frame"));
    } else if (shape == "lander") {
      if (size.empty()) size = {2.0, 2.0, 1.5};
      spec = single_mesh_scene(make_grid_solid(
          lander_solid(size[0], size[1], size[2], bar > 0 ? bar : 0.08, leg_length), "lander"));
    } else if (shape == "seabed") {
      if (!(triangles >= 2 && triangles <= 2.0e7))
        return command_line.usage_error("--triangles must be in [2, 2e7]");
      spec = single_mesh_scene(make_seabed(seabed_for_triangles(
          static_cast<std::int64_t>(triangles), extent, static_cast<std::uint64_t>(seed))));
    } else if (shape == "two-node") {
      spec = two_node_scene();
    } else if (shape == "textured-quad") {
      spec = textured_quad_scene(int(texture_size[0]), int(texture_size[1]), external_texture);
    } else {
      return command_line.usage_error("unknown shape '" + shape + "'");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hadal-make-asset: %s\n", e.what());
    return 1;
  }
  const std::string error = write_scene(spec, output, stl_ascii);
  if (!error.empty()) {
    std::fprintf(stderr, "hadal-make-asset: %s\n", error.c_str());
    return 1;
  }
  std::size_t tris = 0, verts = 0;
  for (const auto& m : spec.meshes) {
    tris += m.num_triangles();
    verts += m.num_vertices();
  }
  std::printf("wrote %s: %s, %zu triangles, %zu vertices\n", output.c_str(), shape.c_str(), tris,
              verts);
  return 0;
}
