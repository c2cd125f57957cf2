// taskmap.export, taskmap.export_glb and taskmap.view: `taskmap export`, `taskmap export-glb`
// and `taskmap view` as calls, with the commands' option names as keywords.
#include "export_bindings.hpp"

#include "offline_docs.hpp"

#include "fs_path.hpp"

#include <filesystem>
#include <optional>
#include <string>

#include <pybind11/stl.h>

#include "inspect_bindings.hpp"
#include "taskmap/builder/map_export.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/inspect/glb_export.hpp"
#include "taskmap/inspect/map_hand.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/mapstore/trajectory_file.hpp"
#include "taskmap/viz/map_page.hpp"
#include "taskmap/viz/reach_page.hpp"

namespace py = pybind11;

namespace taskmap {
namespace {

/// The map's hand as the commands find it (`hand`: URDF or bundled name; "": the map's own, by
/// its SHA-256); a Python warning and no hand when there is none.
std::optional<HandModel> mapHandOrWarn(const TaskMapData& map, const std::string& hand,
                                       const std::string& without) {
  MapHandOptions options;
  if (!hand.empty()) options.hand = pythonHandUrdf(hand);
  options.hands_dir = pythonHandsDir();
  MapHandResult found = findMapHand(map, options);
  if (!found.hand) py::module_::import("warnings").attr("warn")(found.message + "; " + without);
  return std::move(found.hand);
}

/// The reach page of a trajectory with the map's hand (`hand`: URDF or bundled name; "": the
/// map's own); a Python warning and the planner's primitives when there is none. Writes it.
void writeTrajectoryPage(const TrajectoryRecord& r, const std::string& hand,
                         const std::string& output, const PageOptions& page) {
  MapHandOptions options;
  if (!hand.empty()) options.hand = pythonHandUrdf(hand);
  options.hands_dir = pythonHandsDir();
  const TrajectoryHand found = findTrajectoryHand(r, options);
  ReachPageInput input;
  input.trajectory = &r;
  if (found.found.hand) {
    input.hand = &*found.found.hand;
    input.grasp_joints = found.grasp_joints;
  } else {
    input.note = found.found.message;
    py::module_::import("warnings")
        .attr("warn")(found.found.message + "; drawing the hand as the planner's primitives");
  }
  writeReachPage(input, output, page);
}

std::string exportMap(const py::object& map_path, const std::string& format,
                      const py::object& output_path, double glyph_size, double density,
                      const std::string& object_file, std::optional<double> palm_offset,
                      const std::string& hand, bool force) {
  MapExportOptions o;
  o.map = fsPath(map_path);
  o.format = format;
  o.output = fsPath(output_path);
  o.glyph_size = glyph_size;
  o.density = density;
  o.object_file = object_file;
  o.palm_offset = palm_offset;
  o.hand = hand;
  o.force = force;
  o.output_option = "output";
  MapExportResult r;
  {
    py::gil_scoped_release release;
    r = exportMapFile(o);
  }
  if (r.hand_status != MapHandResult::Status::kLoaded)
    py::module_::import("warnings").attr("warn")(r.hand_message + "; drawing no hand");
  return o.output;
}

std::string exportGlb(const py::object& trajectory, const py::object& output_path, bool force) {
  const std::string input = fsPath(trajectory), output = fsPath(output_path);
  checkOutputPath(output, {input}, OutputKind::kGlb, force, "output");
  writeGlb(readTrajectory(input), output);
  return output;
}

std::string view(const py::object& file_path, const py::object& output_path,
                 const std::string& hand, int ghosts, const std::string& title) {
  const std::string file = fsPath(file_path);
  if (!std::filesystem::exists(file))
    throw Error("file '" + file + "' does not exist; give a task map or a trajectory (.h5)");
  PageOptions page;
  page.ghost_limit = ghosts;
  page.title = title;
  page.validate();
  const std::string output =
      output_path.is_none()
          ? std::filesystem::path(file).filename().replace_extension(".html").string()
          : fsPath(output_path);
  std::optional<TaskMapData> map;
  try {
    map = readMap(file);
  } catch (const Error& e) {
    if (std::string(e.what()).find("not a task map") == std::string::npos) throw;
  }
  if (!map) {
    writeTrajectoryPage(readTrajectory(file), hand, output, page);
    return output;
  }
  const std::optional<HandModel> model = mapHandOrWarn(*map, hand, "drawing palms only");
  MapPageInput input;
  input.map = &*map;
  input.hand = model ? &*model : nullptr;
  input.source = std::filesystem::path(file).filename().string();
  writeMapPage(input, output, page);
  return output;
}

}  // namespace

void bindExport(py::module_& m) {
  m.def("export", &exportMap, py::arg("map"), py::kw_only(), py::arg("format"), py::arg("output"),
        py::arg("glyph_size") = 0.0, py::arg("density") = 1000.0, py::arg("object_file") = "",
        py::arg("palm_offset") = py::none(), py::arg("hand") = "", py::arg("force") = false,
        pydoc::kExport);
  m.def("export_glb", &exportGlb, py::arg("trajectory"), py::kw_only(), py::arg("output"),
        py::arg("force") = false, pydoc::kExportGlb);
  m.def("view", &view, py::arg("file"), py::kw_only(), py::arg("output") = py::none(),
        py::arg("hand") = "", py::arg("ghosts") = PageOptions{}.ghost_limit, py::arg("title") = "",
        pydoc::kView);
}

}  // namespace taskmap
