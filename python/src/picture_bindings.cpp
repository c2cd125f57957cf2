// taskmap.picture: the picture of `taskmap inspect MAP --png PNG [--hand H] [--width W]
// [--height H]`, with the same keyword arguments.
#include "picture_bindings.hpp"

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
        py::arg("width") = d.width, py::arg("height") = d.height,
        R"(Draws a task map to a PNG, the picture of `taskmap inspect MAP --png PNG`; returns png.

map: the path of a task map file (.h5), or a TaskMap. The picture: three orthographic views
(top, front, side) of the object silhouette in the object frame with palm positions coloured by
cluster (outliers grey), each cluster representative with its approach axis (palm +z) and the
outline of the hand posed by it, and a histogram of epsilon per cluster. hand: the hand to
outline (URDF, or a bundled name under <data dir>/hands, core/data_dir.hpp); default: the map's hand, found
by its URDF SHA-256 at the recorded path or under <data dir>/hands (a warning, and no
hand, when none is found). width >= 800, height >= 600 pixels. The file is written atomically.
Raises taskmap.Error naming the file or option on bad input.)");
}

}  // namespace taskmap
