#pragma once
// taskmap.summary and taskmap.hand_info: what `taskmap inspect` and `taskmap hand-info` report
// (inspect stage).
#include <pybind11/pybind11.h>

namespace taskmap {

/// Adds taskmap.summary and taskmap.hand_info to the module.
void bindInspect(pybind11::module_& m);

/// The URDF of `hand`: the path itself when it exists, else the bundled hand of that name under
/// dataDir()/hands (<name>/<name>.urdf; core/data_dir.hpp: $TASKMAP_DATA_DIR, else the
/// share/taskmap installed with the package); throws Error listing the bundled hands otherwise.
std::string pythonHandUrdf(const std::string& hand);

/// dataDir()/hands, or "" when there is no data directory.
std::string pythonHandsDir();

}  // namespace taskmap
