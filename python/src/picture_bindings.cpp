// taskmap.picture: the picture of `taskmap inspect MAP --png PNG [--hand H] [--width W]
// [--height H]`, with the same keyword arguments.
#include "picture_bindings.hpp"

#include "offline_docs.hpp"

#include "fs_path.hpp"

#include <optional>
#include <string>

#include "inspect_bindings.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/inspect/map_hand.hpp"
#include "taskmap/inspect/map_summary.hpp"
#include "taskmap/integration/task_map.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/picture/map_picture.hpp"

namespace py = pybind11;

namespace taskmap {
namespace {

std::string picture(const py::object& map, const std::string& png, const std::string& hand,
                    int width, int height) {
  PictureOptions options;
  options.width = width;
  options.height = height;
  options.validate();
  if (png.empty()) throw Error("png is empty; give the PNG file to write");
  std::optional<TaskMapData> read;
  std::string path;
  if (!py::isinstance<TaskMap>(map)) {
    InspectOptions inspect;
    inspect.map = fsPath(map);
    inspect.validate();
    path = inspect.map;
    read = readMap(path);
  }
  const TaskMapData& data = read ? *read : map.cast<const TaskMap&>().data();
  const MapSummary summary = summarizeMap(data, path);
  MapHandOptions hand_options;
  if (!hand.empty()) hand_options.hand = pythonHandUrdf(hand);
  hand_options.hands_dir = pythonHandsDir();
  const MapHandResult found = findMapHand(data, hand_options);
  if (!found.hand) {
    py::module_::import("warnings")
        .attr("warn")(found.message + "; drawing no hand" +
                      (found.status == MapHandResult::Status::kNotFound ? " (give hand=)" : ""));
  }
  {
    py::gil_scoped_release release;
    writeMapPicture(data, summary, png, options, found.hand ? &*found.hand : nullptr);
  }
  return png;
}

}  // namespace

void bindPicture(py::module_& m) {
  const PictureOptions d;
  m.def("picture", &picture, py::arg("map"), py::kw_only(), py::arg("png"), py::arg("hand") = "",
        py::arg("width") = d.width, py::arg("height") = d.height, pydoc::kPicture);
}

}  // namespace taskmap
