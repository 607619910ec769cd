// libFuzzer target for the scenario loader (hadal::config::load_scenario_file, with the strict YAML
// reader under it). Each input is a scenario file, written to <tmp>/scenarios/fuzz.yaml in a per-process
// tree whose vehicles/ and meshes/ are links to the repository's configs (so includes and meshes of the
// seeds, configs/scenarios/*.yaml, resolve as they do in configs/). Any crash, sanitizer report, leak or
// hang is a finding; errors are the expected outcome for most inputs, and each must be a diagnostic
// naming a file, a line and a column, never an exception.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "hadal/config/scenario_loader.h"

namespace {

namespace fs = std::filesystem;

// <tmp>/hadal_fuzz_scenario_<pid>/{scenarios/,vehicles -> configs/vehicles, meshes -> configs/meshes}.
const fs::path& scenario_path() {
  static const fs::path path = [] {
    const char* tmp = std::getenv("TMPDIR");
    const fs::path root = fs::path(tmp && *tmp ? tmp : "/tmp") / ("hadal_fuzz_scenario_" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root / "scenarios");
    for (const char* dir : {"vehicles", "meshes"}) {
      fs::create_directory_symlink(fs::path(HADAL_SOURCE_CONFIGS_DIR) / dir, root / dir);
    }
    return root / "scenarios" / "fuzz.yaml";
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = scenario_path().string();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  const hadal::config::LoadResult result = hadal::config::load_scenario_file(path);
  if (result.ok()) return 0;
  if (result.errors.empty()) std::abort();  // no model and no reason
  for (const auto& error : result.errors) {
    if (error.format().find(": error: ") == std::string::npos) std::abort();  // file:line:col: error: ...
  }
  return 0;
}
