// Mesh load time: a generated ~1M-triangle seabed as GLB and as glTF (+ .bin), and for each file,
// in the same process and interleaved run by run:
//   assimp_readfile      bare Assimp::Importer::ReadFile(path, 0) (the importer's construction and
//                        the scene's destruction are outside the timed region: the strictest
//                        baseline)
//   hadal_import_mesh    hadal::geometry::import_mesh to usable flat arrays (checks, ReadFile,
//                        conversion; assimp's scene is freed on the background thread, which is
//                        drained outside the timed region before the next measurement)
//   hadal_import_mesh_sync  the same with background_cleanup = false: freeing assimp's scene
//                        (one allocation per face) is inside the timed region
//   hadal_mesh_properties compute_mesh_properties on the imported mesh (face SoA, volume integrals,
//                        position welding + edge sort for closedness)
// Prints one JSON object per measurement (median of --repetitions runs after one warm-up run that
// brings the file into the page cache). Issue 3's targets: import < 0.2 s and <= 1.5x ReadFile.
//   build/bin/hadal_bench_mesh_load [--triangles N] [--repetitions R] [--keep DIR] [FILE ...]
// With FILE arguments, those files are measured instead of generated seabeds.
#include <assimp/scene.h>
#include <unistd.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "hadal/assets/mesh_generators.h"
#include "hadal/assets/scene_writer.h"
#include "hadal/geometry/mesh_import.h"
#include "hadal/geometry/mesh_properties.h"
#include "timing.h"

namespace {

using hadal::bench::Clock;
using hadal::bench::median;
using hadal::bench::seconds_since;

std::string runs_json(const std::vector<double>& v) {
  std::string out = "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%s%.4f", i ? ", " : "", v[i]);
    out += buf;
  }
  return out + "]";
}

std::string basename_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

int usage() {
  std::fprintf(
      stderr,
      "usage: hadal_bench_mesh_load [--triangles N] [--repetitions R] [--keep DIR] [FILE ...]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  long long triangles = 1000000;
  int repetitions = 5;
  std::string keep_dir;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--triangles" && i + 1 < argc)
      triangles = std::atoll(argv[++i]);
    else if (arg == "--repetitions" && i + 1 < argc)
      repetitions = std::atoi(argv[++i]);
    else if (arg == "--keep" && i + 1 < argc)
      keep_dir = argv[++i];
    else if (arg.rfind("--", 0) != 0)
      files.push_back(arg);
    else
      return usage();
  }
  if (triangles < 2 || repetitions < 1) return usage();

  std::string temp_dir;
  if (files.empty()) {
    std::string dir = keep_dir;
    if (dir.empty()) {
      char pattern[] = "/tmp/hadal_bench_mesh_load_XXXXXX";
      if (!mkdtemp(pattern)) {
        std::perror("mkdtemp");
        return 1;
      }
      dir = temp_dir = pattern;
    }
    const auto start = Clock::now();
    const auto spec = hadal::assets::single_mesh_scene(
        hadal::assets::make_seabed(hadal::assets::seabed_for_triangles(triangles, 1000.0, 7)));
    for (const char* ext : {".glb", ".gltf"}) {
      const std::string path = dir + "/seabed" + ext;
      if (const std::string error = hadal::assets::write_scene(spec, path); !error.empty()) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 1;
      }
      files.push_back(path);
    }
    std::fprintf(stderr, "generated %s in %.2f s\n", dir.c_str(), seconds_since(start));
  }

  for (const std::string& path : files) {
    // Warm-up: page cache, allocator, lazily loaded importer tables.
    hadal::geometry::ImportResult warm = hadal::geometry::import_mesh(path);
    if (!warm.ok()) {
      std::fprintf(stderr, "%s\n", warm.error.c_str());
      return 1;
    }
    const std::size_t tris = warm.mesh->num_triangles(), verts = warm.mesh->num_vertices();
    warm = {};
    std::vector<double> bare, import, import_sync, properties;
    bool closed = false;
    for (int r = 0; r < repetitions; ++r) {
      {
        Assimp::Importer importer;
        const auto start = Clock::now();
        const aiScene* scene = importer.ReadFile(path, 0);
        bare.push_back(seconds_since(start));
        if (!scene) {
          std::fprintf(stderr, "%s: %s\n", path.c_str(), importer.GetErrorString());
          return 1;
        }
      }
      auto start = Clock::now();
      hadal::geometry::ImportResult result = hadal::geometry::import_mesh(path);
      import.push_back(seconds_since(start));
      hadal::geometry::wait_for_background_cleanup();
      {
        hadal::geometry::ImportOptions sync;
        sync.background_cleanup = false;
        start = Clock::now();
        const hadal::geometry::ImportResult again = hadal::geometry::import_mesh(path, sync);
        import_sync.push_back(seconds_since(start));
      }
      start = Clock::now();
      const hadal::geometry::MeshProperties props =
          hadal::geometry::compute_mesh_properties(*result.mesh);
      properties.push_back(seconds_since(start));
      closed = props.closed;
    }
    const std::string name = basename_of(path);
    const std::string format = name.substr(name.find_last_of('.') + 1);
    const double bare_s = median(bare), import_s = median(import), sync_s = median(import_sync),
                 props_s = median(properties);
    const unsigned threads = std::thread::hardware_concurrency();
    std::printf(
        "{\"benchmark\": \"mesh_load\", \"measurement\": \"assimp_readfile\", \"file\": \"%s\", "
        "\"format\": \"%s\", \"triangles\": %zu, \"vertices\": %zu, \"median_s\": %.4f, "
        "\"runs_s\": %s}\n",
        name.c_str(), format.c_str(), tris, verts, bare_s, runs_json(bare).c_str());
    std::printf(
        "{\"benchmark\": \"mesh_load\", \"measurement\": \"hadal_import_mesh\", \"file\": \"%s\", "
        "\"format\": \"%s\", \"triangles\": %zu, \"vertices\": %zu, \"median_s\": %.4f, "
        "\"runs_s\": %s, "
        "\"ratio_to_readfile\": %.2f, \"target_s\": 0.2, \"target_ratio\": 1.5, \"threads\": %u}\n",
        name.c_str(), format.c_str(), tris, verts, import_s, runs_json(import).c_str(),
        import_s / bare_s, threads);
    std::printf(
        "{\"benchmark\": \"mesh_load\", \"measurement\": \"hadal_import_mesh_sync\", \"file\": "
        "\"%s\", "
        "\"format\": \"%s\", \"triangles\": %zu, \"vertices\": %zu, \"median_s\": %.4f, "
        "\"runs_s\": %s, "
        "\"ratio_to_readfile\": %.2f, \"threads\": %u}\n",
        name.c_str(), format.c_str(), tris, verts, sync_s, runs_json(import_sync).c_str(),
        sync_s / bare_s, threads);
    std::printf(
        "{\"benchmark\": \"mesh_load\", \"measurement\": \"hadal_mesh_properties\", \"file\": "
        "\"%s\", "
        "\"format\": \"%s\", \"triangles\": %zu, \"vertices\": %zu, \"median_s\": %.4f, "
        "\"runs_s\": %s, "
        "\"closed\": %s, \"threads\": %u}\n",
        name.c_str(), format.c_str(), tris, verts, props_s, runs_json(properties).c_str(),
        closed ? "true" : "false", threads);
    std::fflush(stdout);
  }
  if (!temp_dir.empty()) std::filesystem::remove_all(temp_dir);
  return 0;
}
