// Writes the seed corpus of the mesh-import fuzzer: small generated assets in every format, each
// prefixed with the byte that selects its extension (see mesh_import_fuzz.cc). glTF seeds get
// their .bin inlined as a base64 data URI so that each seed is one self-contained file.
//   hadal_fuzz_make_corpus OUTPUT_DIR
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "hadal/assets/mesh_generators.h"
#include "hadal/assets/scene_writer.h"

namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 |
                       (unsigned char)bytes[i + 2];
    out += {table[v >> 18], table[(v >> 12) & 63], table[(v >> 6) & 63], table[v & 63]};
  }
  if (i + 1 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16;
    out += {table[v >> 18], table[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8;
    out += {table[v >> 18], table[(v >> 12) & 63], table[(v >> 6) & 63], '='};
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace hadal::assets;
  if (argc != 2) {
    std::fprintf(stderr, "usage: hadal_fuzz_make_corpus OUTPUT_DIR\n");
    return 2;
  }
  const fs::path out_dir = argv[1];
  const fs::path work = out_dir / "work";
  fs::create_directories(work);
  SeabedSpec seabed;
  seabed.cells_x = 5;
  seabed.cells_y = 4;
  const std::vector<std::pair<std::string, SceneSpec>> scenes = {
      {"box", single_mesh_scene(make_box(1, 2, 3, 0.5, 0, 0))},
      {"sphere", single_mesh_scene(make_uv_sphere(0.5, 6, 3))},
      {"frame", single_mesh_scene(make_grid_solid(box_frame_solid(1, 1, 1, 0.1), "frame"))},
      {"seabed", single_mesh_scene(make_seabed(seabed))},
      {"two_node", two_node_scene()},
      {"quad", textured_quad_scene(4, 2)},
  };
  struct Format {
    const char* ext;
    unsigned char selector;
    bool ascii;
  };
  const Format formats[] = {{".glb", 0, false},
                            {".gltf", 1, false},
                            {".obj", 2, false},
                            {".stl", 3, false},
                            {".stl", 3, true}};
  int written = 0;
  for (const auto& [name, spec] : scenes)
    for (const Format& format : formats) {
      const fs::path model = work / (name + (format.ascii ? "_ascii" : "") + format.ext);
      if (const std::string error = write_scene(spec, model.string(), format.ascii);
          !error.empty()) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 1;
      }
      std::string content = read_file(model);
      if (std::string(format.ext) == ".gltf") {  // inline every external buffer
        for (const auto& entry : fs::directory_iterator(work)) {
          if (entry.path().extension() != ".bin") continue;
          const std::string uri = "\"" + entry.path().filename().string() + "\"";
          const auto at = content.find(uri);
          if (at == std::string::npos) continue;
          content.replace(
              at, uri.size(),
              "\"data:application/octet-stream;base64," + base64(read_file(entry.path())) + "\"");
        }
      }
      std::ofstream seed(out_dir / ("seed_" + model.filename().string()), std::ios::binary);
      seed.put(static_cast<char>(format.selector));
      seed.write(content.data(), static_cast<std::streamsize>(content.size()));
      ++written;
    }
  fs::remove_all(work);
  std::printf("wrote %d seeds to %s\n", written, out_dir.c_str());
  return 0;
}
