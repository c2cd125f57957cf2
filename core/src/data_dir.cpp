#include "taskmap/core/data_dir.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <utility>
#include <vector>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

fs::path executableDir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  return exe.parent_path();
}

// The folder of the shared library holding this code (<prefix>/lib, or <build>/core), for a
// process that is not the taskmap tool (the Python interpreter, a user's program).
fs::path libraryDir() {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<const void*>(&libraryDir), &info) == 0 || info.dli_fname == nullptr)
    return {};
  std::error_code ec;
  const fs::path lib = fs::canonical(info.dli_fname, ec);
  return ec ? fs::path() : lib.parent_path();
}

std::vector<std::string> bundledHands(const fs::path& hands) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(hands, ec)) {
    const std::string name = entry.path().filename().string();
    if (fs::exists(entry.path() / (name + ".urdf")) || fs::exists(entry.path() / (name + ".xml")))
      names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

/// Regular files of `dir` (names), "" entries skipped; empty when it is not a folder.
std::vector<std::string> filesOf(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(dir.empty() ? fs::path(".") : dir, ec), end; !ec && it != end;
       it.increment(ec))
    if (it->is_regular_file(ec)) names.push_back(it->path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

std::vector<std::string> closestNames(const std::string& name,
                                      const std::vector<std::string>& candidates) {
  const std::string n = lower(name);
  const std::size_t limit = std::max<std::size_t>(1, n.size() / 3);
  std::vector<std::pair<std::size_t, std::string>> scored;
  for (const std::string& c : candidates) {
    const std::string l = lower(c);
    std::size_t d = editDistance(n, l);
    if (d > limit && !n.empty() && l.size() >= 3 &&
        (l.find(n) != std::string::npos || n.find(l) != std::string::npos))
      d = limit;  // one contains the other: "pand" and "panda_mimic"
    if (d <= limit) scored.emplace_back(d, c);
  }
  std::stable_sort(scored.begin(), scored.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::string> out;
  for (const auto& s : scored) out.push_back(s.second);
  return out;
}

std::string didYouMean(const std::string& name, const std::vector<std::string>& candidates) {
  const std::vector<std::string> close = closestNames(name, candidates);
  if (close.empty()) return "";
  std::string s = "; did you mean '" + close[0] + "'";
  if (close.size() > 1) s += " or '" + close[1] + "'";
  return s + "?";
}

std::vector<std::string> bundledObjectNames() {
  std::vector<std::string> names;
  try {
    for (const std::string& f : filesOf(fs::path(dataDir()) / "objects"))
      if (fs::path(f).extension() == ".obj") names.push_back(fs::path(f).stem().string());
  } catch (const Error&) {
    // No data directory: no bundled objects.
  }
  return names;
}

void requireObjectFile(const std::string& path) {
  std::error_code ec;
  if (fs::exists(path, ec)) return;
  const fs::path p(path);
  // Compared by file name (a path's length would loosen the edit distance's limit).
  std::vector<std::string> close;
  for (const std::string& f : closestNames(p.filename().string(), filesOf(p.parent_path())))
    close.push_back((p.parent_path() / f).string());
  // Bundled objects: a bare name ("baskt") is offered bundled names first ('basket'), a path
  // ("dir/mug.ob") the bundled files after its own folder's.
  const std::vector<std::string> bundled = bundledObjectNames();
  const bool bare = p.parent_path().empty();
  std::vector<std::string> offered;
  for (const std::string& key : {p.filename().string(), p.stem().string()})
    for (const std::string& name : closestNames(key, bundled)) {
      const std::string shown =
          bare ? name : (fs::path(dataDir()) / "objects" / (name + ".obj")).string();
      if (std::find(close.begin(), close.end(), shown) == close.end() &&
          std::find(offered.begin(), offered.end(), shown) == offered.end())
        offered.push_back(shown);
    }
  close.insert(bare ? close.begin() : close.end(), offered.begin(), offered.end());
  std::string hint;
  if (!close.empty()) hint = "; did you mean '" + close[0] + "'";
  if (close.size() > 1) hint += " or '" + close[1] + "'";
  if (!hint.empty()) hint += "?";
  throw Error("cannot open mesh file '" + path + "': no such file" + hint);
}

std::string objectFileOrBundled(const std::string& object) {
  std::error_code ec;
  if (fs::exists(object, ec)) return object;
  const fs::path p(object);
  if (!object.empty() && p.parent_path().empty() && !p.has_extension()) {
    const std::vector<std::string> names = bundledObjectNames();
    if (std::find(names.begin(), names.end(), object) != names.end())
      return (fs::path(dataDir()) / "objects" / (object + ".obj")).string();
  }
  return object;
}

std::string resolveObjectFile(const std::string& object) {
  const std::string path = objectFileOrBundled(object);
  requireObjectFile(path);
  return path;
}

std::string dataDir() {
  if (const char* env = std::getenv("TASKMAP_DATA_DIR"); env != nullptr && *env != '\0') {
    if (!fs::is_directory(env))
      throw Error(std::string("TASKMAP_DATA_DIR '") + env + "' is not a directory");
    return env;
  }
  const fs::path dir = executableDir() / ".." / "share" / "taskmap";
  const fs::path beside_library = libraryDir() / ".." / "share" / "taskmap";
  if (!fs::is_directory(dir) && !libraryDir().empty() && fs::is_directory(beside_library))
    return beside_library.lexically_normal().string();
  if (!fs::is_directory(dir))
    throw Error("taskmap's data directory " + dir.lexically_normal().string() +
                " is missing; reinstall taskmap or set TASKMAP_DATA_DIR to a folder holding "
                "hands/, objects/ and regression/");
  return dir.lexically_normal().string();
}

std::string resolveMapFile(const std::string& map) {
  if (fs::exists(map)) return map;
  const bool name = map.find('/') == std::string::npos && map.find('.') == std::string::npos;
  const std::string bundled = name ? dataDir() + "/maps/" + map + ".h5" : std::string();
  if (!bundled.empty() && fs::exists(bundled)) return bundled;
  throw Error("--map '" + map + "' is neither a map file nor a bundled map name" +
              (name ? " (no " + bundled + ")" : std::string()));
}

std::string handSidecarPath(const std::string& urdf) {
  const fs::path p(urdf);
  return (p.parent_path() / (p.stem().string() + ".hand.json")).string();
}

std::string resolveHandUrdf(const std::string& hand) {
  if (fs::exists(hand)) return hand;
  return bundledHandUrdf(hand);
}

std::string bundledHandUrdf(const std::string& name) {
  const fs::path hands = fs::path(dataDir()) / "hands";
  const fs::path urdf = hands / name / (name + ".urdf");
  if (name.find('/') == std::string::npos && fs::exists(urdf)) return urdf.string();
  const fs::path mjcf = hands / name / (name + ".xml");  // a bundled MJCF hand
  if (name.find('/') == std::string::npos && fs::exists(mjcf)) return mjcf.string();
  std::string list;
  const std::vector<std::string> names = bundledHands(hands);
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  std::string hint;
  const fs::path as_path(name);
  if (name.find('/') != std::string::npos) {
    std::vector<std::string> urdfs;
    for (const std::string& f : filesOf(as_path.parent_path()))
      if (fs::path(f).extension() == ".urdf" || fs::path(f).extension() == ".xacro" ||
          fs::path(f).extension() == ".xml")
        urdfs.push_back(f);
    const std::vector<std::string> close = closestNames(as_path.filename().string(), urdfs);
    if (!close.empty())
      hint = "; did you mean '" + (as_path.parent_path() / close[0]).string() + "'?";
    if (hint.empty()) hint = didYouMean(as_path.stem().string(), names);
  } else {
    hint = didYouMean(name, names);
  }
  throw Error(
      "hand '" + name + "' is neither a hand file (URDF or MJCF) nor a bundled hand name (" +
      (list.empty() ? std::string("none found") : list) + " under " + hands.string() + ")" + hint);
}

}  // namespace taskmap
