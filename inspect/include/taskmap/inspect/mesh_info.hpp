#pragma once
/// @file mesh_info.hpp
/// What `taskmap mesh-info` reports about an object mesh loaded as a solid: the file, what was
/// repaired, the size (with the graspable-size check), the volume and mass properties; as JSON
/// text and as the printed text.

#include <string>

#include "taskmap/meshes/object_model.hpp"

namespace taskmap {

/// The report of one loaded object.
struct MeshInfo {
  /// JSON text indented by 2 (what `mesh-info --json` prints, without the final newline): path,
  /// format, sha256, scale, input_vertices, input_faces, vertices, faces, repairs, warnings,
  /// size (m), graspable_size, closed, volume (m^3), bounds_min, bounds_max, center_of_mass (m,
  /// object frame), inertia (3 rows; density 1 kg/m^3, about the centre of mass, kg m^2),
  /// torque_scale (m).
  std::string json;
  std::string text;  ///< the text `mesh-info` prints (lines ending in newlines)
};

/// Reports on a loaded object (no further loading: microseconds).
MeshInfo meshInfo(const ObjectModel& object);

/// The JSON `mesh-info --json` prints for a file that does not load: {"path", "closed": false,
/// "error"} (indented by 2, no final newline).
std::string meshInfoErrorJson(const std::string& path, const std::string& error);

}  // namespace taskmap
