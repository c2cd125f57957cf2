#pragma once
/// @file map_file.hpp
/// Reading and writing task map files (sealed HDF5, schema in mapstore/SCHEMA.md).

#include <cstddef>
#include <string>

#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap {

/// Largest file sealMap() reads (bytes).
constexpr std::size_t kMaxSealBytes = std::size_t{16} << 30;

/// Writes the map atomically: to a temporary file beside path, then renamed over it. A crash
/// or kill leaves either no file or the previous one. The file is sealed: its first 512 bytes
/// (the HDF5 user block) hold the SHA-256 and length of the rest. Same map, same bytes.
/// Throws Error naming the path.
void writeMap(const std::string& path, const TaskMapData& map);

/// Reads and validates a map: checks the seal (length, SHA-256) before HDF5 parses anything,
/// then hands HDF5 the verified bytes from memory. Throws Error naming the file and what is
/// wrong (no seal, truncated, content not matching the seal, the first schema violation, for
/// a newer schema "written by a newer taskmap (schema N); upgrade"). Every reader of maps
/// (TaskMap::load, the Python module, the taskmap tool) goes through this function.
TaskMapData readMap(const std::string& path);

/// Re-seals the map at path on purpose (after an edit with another HDF5 tool, or a schema-1
/// map from before seals): validates it as a task map, then replaces it atomically by the
/// same content with a fresh seal (prepending the 512-byte user block if it has none). HDF5
/// parses the unverified file here; run it in a process you can afford to lose (the taskmap
/// tool does). Throws Error naming the file.
void sealMap(const std::string& path);

/// Creation time to store in a new map (ISO 8601 UTC): SOURCE_DATE_EPOCH when set (throws
/// Error when it is not a number of seconds), else the current time when wall_clock, else ""
/// (so the same arguments give the same bytes).
std::string mapCreationTime(bool wall_clock = false);

}  // namespace taskmap
