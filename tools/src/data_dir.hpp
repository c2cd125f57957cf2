#pragma once
/// @file data_dir.hpp
/// Where the `taskmap` tool finds its bundled data: the reference hands (hands/<name>/),
/// objects (objects/), robots (robots/<name>/<name>.urdf) and the regression suite
/// (regression/cases.json, regression/golden/).

#include <string>

namespace taskmap::cli {

/// The data directory: $TASKMAP_DATA_DIR if set, else `<directory of the
/// executable>/../share/taskmap` (the install tree's share/taskmap; the build tree stages the same
/// layout in <build>/share). Throws Error saying how to set TASKMAP_DATA_DIR when neither exists.
std::string dataDir();

/// The URDF of a bundled hand: `<dataDir()>/hands/<name>/<name>.urdf`. Throws Error listing the
/// bundled hands when there is none of that name.
std::string bundledHandUrdf(const std::string& name);

}  // namespace taskmap::cli
