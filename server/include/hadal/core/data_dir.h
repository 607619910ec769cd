// Where hadal's installed data lies (scenarios and vehicles, the World Magnetic Model, the viewer's page):
// one answer for every module that looks.
#pragma once

#include <filesystem>
#include <optional>

namespace hadal {

struct DataDir {
  std::filesystem::path path;
  bool from_environment = false;  // $HADAL_DATA_DIR: use what it names even if a file is missing (an error then)
};
// $HADAL_DATA_DIR when set (an override), else <exe>/../share/hadal when that directory exists (an install
// tree: P/bin/hadald -> P/share/hadal), else nothing: a build tree, whose callers fall back to the source
// tree's files.
std::optional<DataDir> installed_data_dir();

}  // namespace hadal
