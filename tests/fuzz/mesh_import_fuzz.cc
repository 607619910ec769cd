// libFuzzer target for hadal::geometry::import_mesh (and compute_mesh_properties on what loads).
// Input layout: byte 0 selects the extension (byte % 4: .glb, .gltf, .obj, .stl), the rest is the
// file's content, written to a per-process temporary file and imported from there (assimp reads
// files, and a glTF's references resolve relative to it). Any crash, sanitizer report, leak or hang
// is a finding; an import error is the expected outcome for most inputs.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "hadal/geometry/mesh_import.h"
#include "hadal/geometry/mesh_properties.h"

namespace {

const std::string& input_stem() {
  static const std::string stem = [] {
    const char* tmp = std::getenv("TMPDIR");
    return std::string(tmp && *tmp ? tmp : "/tmp") + "/hadal_fuzz_mesh_import_" +
           std::to_string(::getpid());
  }();
  return stem;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const kExtensions[4] = {".glb", ".gltf", ".obj", ".stl"};
  const std::string path = input_stem() + kExtensions[data[0] % 4];
  std::remove(path.c_str());  // a fresh file: ext4 flushes data of a truncated one on close
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size > 1 && std::fwrite(data + 1, 1, size - 1, f) != size - 1) std::abort();
  std::fclose(f);

  hadal::geometry::ImportOptions options;
  options.background_cleanup = false;  // every allocation freed within the run (leak detection)
  const hadal::geometry::ImportResult result = hadal::geometry::import_mesh(path, options);
  if (result.ok()) {
    const auto& mesh = *result.mesh;
    for (std::uint32_t i : mesh.indices)
      if (i >= mesh.num_vertices()) std::abort();  // the importer promises valid indices
    (void)hadal::geometry::compute_mesh_properties(mesh);
  } else if (result.error.rfind(path + ": ", 0) != 0) {
    std::abort();  // every error names the file
  }
  std::remove(path.c_str());
  return 0;
}
