// taskmap.summary and taskmap.hand_info: the numbers `taskmap inspect` prints about a map and
// what `taskmap hand-info` reports about a hand, as dicts (the CLI's --json, parsed), with the
// keyword arguments of the commands.
#include "inspect_bindings.hpp"

#include "offline_docs.hpp"

#include "fs_path.hpp"

#include "builder_bindings.hpp"

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/hands/hand_draft.hpp"
#include "taskmap/inspect/hand_info.hpp"
#include "taskmap/inspect/map_summary.hpp"
#include "taskmap/inspect/mesh_info.hpp"
#include "taskmap/integration/task_map.hpp"
#include "taskmap/picture/hand_picture.hpp"
#include "taskmap/viz/hand_page.hpp"

namespace py = pybind11;

namespace taskmap {
namespace {

py::dict jsonDict(const std::string& text) {
  return py::module_::import("json").attr("loads")(text).cast<py::dict>();
}

/// Sets ROS_PACKAGE_PATH to `dirs` before its old value for the object's life (the CLI's
/// --package-path), and restores it after.
class PackagePath {
 public:
  explicit PackagePath(const std::vector<std::string>& dirs) {
    if (dirs.empty()) return;
    const char* old = std::getenv("ROS_PACKAGE_PATH");
    if (old != nullptr) old_ = old;
    std::string value;
    for (const std::string& d : dirs) value += (value.empty() ? "" : ":") + d;
    if (old_ && !old_->empty()) value += ":" + *old_;
    ::setenv("ROS_PACKAGE_PATH", value.c_str(), 1);
    set_ = true;
  }
  PackagePath(const PackagePath&) = delete;
  PackagePath& operator=(const PackagePath&) = delete;
  ~PackagePath() {
    if (!set_) return;
    if (old_)
      ::setenv("ROS_PACKAGE_PATH", old_->c_str(), 1);
    else
      ::unsetenv("ROS_PACKAGE_PATH");
  }

 private:
  std::optional<std::string> old_;
  bool set_ = false;
};

py::dict summary(const py::object& map) {
  std::string text;
  if (py::isinstance<TaskMap>(map)) {
    text = summaryJson(summarizeMap(map.cast<const TaskMap&>().data(), ""));
  } else {
    InspectOptions options;
    options.map = fsPath(map);
    text = summaryJson(inspectMap(options).summary);
  }
  return jsonDict(text);
}

py::dict handInfoDict(const std::string& hand, const std::string& png, const std::string& html,
                      const std::vector<std::string>& package_path) {
  const PackagePath scope(package_path);
  HandInfoOptions options;
  options.hand = pythonHandUrdf(hand);
  options.validate();
  const HandModel model = HandModel::load(options.hand);
  const HandInfo info = handInfo(model);
  if (!png.empty()) writeHandPicture(model, png);
  if (!html.empty()) writeHandPage(model, html);
  return jsonDict(info.json);
}

py::dict meshInfoDict(const py::object& file, double scale, bool no_repair,
                      const std::string& repair, double wrap_alpha, double wrap_offset) {
  const std::string path = fsPath(file);
  if (!(scale > 0.0)) throw Error("mesh_info: scale must be positive");
  const MeshLoadOptions options = meshOptions(scale, no_repair, repair, wrap_alpha, wrap_offset);
  return jsonDict(meshInfo(ObjectModel::load(resolveObjectFile(path), options)).json);
}

py::dict handInitDict(const py::object& urdf_path, const py::object& output_path, bool force,
                      const std::vector<std::string>& package_path) {
  const PackagePath scope(package_path);
  const std::string urdf = fsPath(urdf_path);
  const std::string output = output_path.is_none() ? "" : fsPath(output_path);
  if (!std::filesystem::exists(urdf)) throw Error("hand_init: no URDF file '" + urdf + "'");
  if (!output.empty() && std::filesystem::exists(output) && !force)
    throw Error("hand_init: '" + output + "' exists; pass force=True to replace it");
  const SidecarDraft d = draftHandSidecar(urdf);
  if (!d.undecided.empty()) {
    std::string what;
    for (const std::string& u : d.undecided) what += "; " + u;
    throw Error("hand_init: could not draft a sidecar for '" + urdf +
                "': write the undecided fields by hand (meshes/hands/README.md)" + what);
  }
  if (!output.empty()) writeFileAtomically(output, d.json, "cannot write sidecar '" + output + "'");
  py::dict r;
  r["sidecar"] = jsonDict(d.json);
  r["json"] = d.json;
  r["notes"] = d.notes;
  return r;
}

}  // namespace

std::string pythonHandsDir() {
  try {
    return (std::filesystem::path(dataDir()) / "hands").string();
  } catch (const Error&) {
    return "";  // no data directory: hands by path only
  }
}

std::string pythonHandUrdf(const std::string& hand) {
  if (hand.empty()) throw Error("hand is empty; give a hand URDF or a bundled hand name");
  return resolveHandUrdf(hand);
}

void bindInspect(py::module_& m) {
  m.def("summary", &summary, py::arg("map"), pydoc::kSummary);
  m.def("hand_init", &handInitDict, py::arg("urdf"), py::kw_only(), py::arg("output") = py::none(),
        py::arg("force") = false, py::arg("package_path") = std::vector<std::string>{},
        pydoc::kHandInit);
  m.def("mesh_info", &meshInfoDict, py::arg("file"), py::kw_only(), py::arg("scale") = 1.0,
        py::arg("no_repair") = false, py::arg("repair") = "", py::arg("wrap_alpha") = 0.0,
        py::arg("wrap_offset") = 0.0, pydoc::kMeshInfo);
  m.def("hand_info", &handInfoDict, py::arg("hand"), py::kw_only(), py::arg("png") = "",
        py::arg("html") = "", py::arg("package_path") = std::vector<std::string>{},
        pydoc::kHandInfo);
}

}  // namespace taskmap
