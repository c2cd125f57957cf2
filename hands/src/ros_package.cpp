// package:// resolution and xacro detection (ros_package.hpp).
#include "taskmap/hands/ros_package.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

/// The <name> of dir/package.xml, "" when there is none.
std::string packageXmlName(const fs::path& dir) {
  std::error_code ec;
  const fs::path xml = dir / "package.xml";
  if (!fs::is_regular_file(xml, ec)) return "";
  std::ifstream in(xml);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  // The first <name>...</name>, trimmed; a name with blanks inside is none.
  const auto open = text.find("<name>");
  if (open == std::string::npos) return "";
  const auto begin = open + 6;
  const auto close = text.find("</name>", begin);
  if (close == std::string::npos) return "";
  const std::string blanks = " \t\r\n";
  const auto first = text.find_first_not_of(blanks, begin);
  if (first == std::string::npos || first >= close) return "";
  const auto last = text.find_last_not_of(blanks, close - 1);
  const std::string name = text.substr(first, last - first + 1);
  return name.find_first_of(blanks + "<") == std::string::npos ? name : "";
}

/// True when `dir` is package `pkg`: its package.xml names it, or it has no package.xml naming
/// another package and its folder name is pkg.
bool isPackage(const fs::path& dir, const std::string& pkg) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return false;
  const std::string name = packageXmlName(dir);
  if (!name.empty()) return name == pkg;
  return dir.filename() == pkg;
}

/// `pkg` at or below `root`, at most `depth` levels down ("" when not found).
std::string findBelow(const fs::path& root, const std::string& pkg, int depth) {
  if (isPackage(root, pkg)) return root.string();
  if (depth == 0) return "";
  std::error_code ec;
  if (isPackage(root / pkg, pkg)) return (root / pkg).string();
  for (fs::directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_directory(ec) || it->path().filename().string().rfind('.', 0) == 0) continue;
    const std::string found = findBelow(it->path(), pkg, depth - 1);
    if (!found.empty()) return found;
  }
  return "";
}

/// The package holding the URDF, walking up from its folder ("" when not found).
std::string findAbove(const std::string& urdf_path, const std::string& pkg) {
  std::error_code ec;
  fs::path dir = fs::absolute(urdf_path, ec).parent_path();
  for (int up = 0; up < 16 && !dir.empty(); ++up) {
    if (isPackage(dir, pkg)) return dir.string();
    if (isPackage(dir / pkg, pkg)) return (dir / pkg).string();
    if (dir == dir.root_path()) break;
    dir = dir.parent_path();
  }
  return "";
}

/// True when `xml` has a <xacro:...> element outside comments (an expanded URDF may keep the
/// xacro namespace and commented-out macros).
bool hasXacroElement(const std::string& xml) {
  std::size_t at = 0;
  while (at < xml.size()) {
    const std::size_t comment = xml.find("<!--", at);
    const std::size_t element = xml.find("<xacro:", at);
    if (element == std::string::npos) return false;
    if (comment == std::string::npos || element < comment) return true;
    const std::size_t end = xml.find("-->", comment + 4);
    if (end == std::string::npos) return false;
    at = end + 3;
  }
  return false;
}

}  // namespace

std::vector<std::string> rosPackagePath() {
  std::vector<std::string> out;
  const char* env = std::getenv("ROS_PACKAGE_PATH");
  if (env == nullptr) return out;
  std::stringstream ss(env);
  for (std::string item; std::getline(ss, item, ':');)
    if (!item.empty()) out.push_back(item);
  return out;
}

std::string resolvePackageUri(const std::string& uri, const std::string& urdf_path,
                              const std::string& what) {
  const std::string prefix = "package://";
  if (uri.rfind(prefix, 0) != 0) return uri;
  const std::string rest = uri.substr(prefix.size());
  const auto slash = rest.find('/');
  const std::string pkg = rest.substr(0, slash);
  const std::string rel = slash == std::string::npos ? "" : rest.substr(slash + 1);
  if (pkg.empty()) throw Error(what + "'" + uri + "' names no package (package://PKG/path)");
  const std::vector<std::string> paths = rosPackagePath();
  std::string root;
  for (const std::string& p : paths) {
    root = findBelow(p, pkg, 3);
    if (!root.empty()) break;
  }
  if (root.empty()) root = findAbove(urdf_path, pkg);
  if (root.empty()) {
    std::string searched;
    for (const std::string& p : paths) searched += (searched.empty() ? "" : ", ") + p;
    throw Error(what + "'" + uri + "': ROS package '" + pkg + "' not found (searched " +
                (searched.empty() ? std::string("ROS_PACKAGE_PATH: not set")
                                  : "ROS_PACKAGE_PATH: " + searched) +
                "; and the folders above the URDF: none is '" + pkg +
                "' or has a package.xml naming it); pass --package-path DIR with DIR the "
                "package's folder or a folder holding it, or set ROS_PACKAGE_PATH");
  }
  return (fs::path(root) / rel).string();
}

void refuseXacro(const std::string& path, const std::string& text, const std::string& what,
                 bool hand) {
  const bool named = path.size() >= 6 && path.compare(path.size() - 6, 6, ".xacro") == 0;
  if (!named && !hasXacroElement(text)) return;
  std::string stem = fs::path(path).filename().string();
  for (const char* ext : {".xacro", ".urdf"})
    if (stem.size() > std::string(ext).size() &&
        stem.compare(stem.size() - std::string(ext).size(), std::string::npos, ext) == 0)
      stem.resize(stem.size() - std::string(ext).size());
  throw Error(what + " '" + path +
              "' is a xacro file (ROS macros), not a URDF: expand it first, e.g. `xacro " + path +
              " -o " + stem +
              ".urdf` (xacro comes with ROS, or `pip install xacro`; give "
              "the macro's arguments as name:=value), then pass " +
              stem + ".urdf" +
              (hand ? " with its " + stem +
                          ".hand.json sidecar (meshes/hands/README.md); check `taskmap hand-info` "
                          "for self-collision geometry the expansion fixes to the palm"
                    : std::string()) +
              ". package:// mesh paths in it are found through --package-path DIR, "
              "ROS_PACKAGE_PATH or the package that holds the URDF");
}

}  // namespace taskmap
