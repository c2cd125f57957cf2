#pragma once
/// @file map_file.hpp
/// Reading and writing task map files (HDF5, schema in mapstore/SCHEMA.md).

#include <string>

#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap {

/// Writes the map atomically: to a temporary file beside path, then renamed over it. A crash
/// or kill leaves either no file or the previous one. Throws Error naming the path.
void writeMap(const std::string& path, const TaskMapData& map);

/// Reads and validates a map; throws Error naming the file and the first violation (for a
/// newer schema: "written by a newer taskmap (schema N); upgrade").
TaskMapData readMap(const std::string& path);

}  // namespace taskmap
