#include "data_dir.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

#include "taskmap/core/error.hpp"

namespace taskmap::cli {
namespace {

namespace fs = std::filesystem;

fs::path executableDir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  return exe.parent_path();
}

std::vector<std::string> bundledHands(const fs::path& hands) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(hands, ec)) {
    const std::string name = entry.path().filename().string();
    if (fs::exists(entry.path() / (name + ".urdf"))) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

std::string dataDir() {
  if (const char* env = std::getenv("TASKMAP_DATA_DIR"); env != nullptr && *env != '\0') {
    if (!fs::is_directory(env))
      throw Error(std::string("TASKMAP_DATA_DIR '") + env + "' is not a directory");
    return env;
  }
  const fs::path dir = executableDir() / ".." / "share" / "taskmap";
  if (!fs::is_directory(dir))
    throw Error("taskmap's data directory " + dir.lexically_normal().string() +
                " is missing; reinstall taskmap or set TASKMAP_DATA_DIR to a folder holding "
                "hands/, objects/ and regression/");
  return dir.lexically_normal().string();
}

std::string bundledHandUrdf(const std::string& name) {
  const fs::path hands = fs::path(dataDir()) / "hands";
  const fs::path urdf = hands / name / (name + ".urdf");
  if (name.find('/') == std::string::npos && fs::exists(urdf)) return urdf.string();
  std::string list;
  for (const auto& n : bundledHands(hands)) list += (list.empty() ? "" : ", ") + n;
  throw Error("hand '" + name + "' is neither a URDF file nor a bundled hand name (" +
              (list.empty() ? std::string("none found") : list) + " under " + hands.string() + ")");
}

}  // namespace taskmap::cli
