#pragma once
/// @file recorded_hand.hpp
/// The model file (URDF or MJCF) a task map's hand was built from, found once for every stage
/// (re-simulation, validation, pictures, scene files): the path the build recorded in the map's
/// parameters, or a bundled hand with the same content (SHA-256 of the file, /hand urdf_sha256).

#include <string>

#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap {

/// The hand URDF path the build recorded (params_json "hand", a string); "" when the map's
/// parameters are not a JSON object or record no hand path (imported or hand-made maps).
std::string recordedHandPath(const TaskMapData& map);

/// The model file of the map's hand: recordedHandPath(map) when that regular file's SHA-256 is
/// the map's (map.hand.urdf_sha256), else the first (by path) `<hands_dir>/<name>/<name>.urdf`
/// or `<name>/<name>.xml` (an MJCF hand) with that SHA-256 (hands_dir empty: only the recorded path
/// is tried). Throws Error "the map's hand '<name>' (URDF SHA-256 <12 digits>...) is neither at the
/// recorded path '<path>' nor a bundled hand under <hands_dir>" when none matches. Reads files
/// only; loads no hand.
std::string findMapHandUrdf(const TaskMapData& map, const std::string& hands_dir);

/// findMapHandUrdf with the bundled hands, `<dataDir()>/hands` (core/data_dir.hpp); only the
/// recorded path is tried when there is no data directory.
std::string findMapHandUrdf(const TaskMapData& map);

}  // namespace taskmap
