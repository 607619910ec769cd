#include "hadal/core/data_dir.h"

#include <cstdlib>
#include <system_error>

namespace hadal {

std::optional<DataDir> installed_data_dir() {
  namespace fs = std::filesystem;
  if (const char* dir = std::getenv("HADAL_DATA_DIR"); dir != nullptr && *dir != '\0') return DataDir{dir, true};
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return std::nullopt;
  const fs::path installed = exe.parent_path().parent_path() / "share" / "hadal";
  if (!fs::is_directory(installed, ec)) return std::nullopt;
  return DataDir{installed, false};
}

}  // namespace hadal
