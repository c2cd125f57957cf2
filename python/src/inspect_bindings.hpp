#pragma once
// taskmap.summary and taskmap.hand_info: what `taskmap inspect` and `taskmap hand-info` report
// (inspect stage).
#include <pybind11/pybind11.h>

namespace taskmap {

/// Adds taskmap.summary and taskmap.hand_info to the module.
void bindInspect(pybind11::module_& m);

/// The URDF of `hand`: the path itself when it exists, else the bundled hand of that name under
/// $TASKMAP_DATA_DIR/hands (<name>/<name>.urdf); throws Error saying what to give otherwise.
std::string pythonHandUrdf(const std::string& hand);

/// $TASKMAP_DATA_DIR/hands, or "" when TASKMAP_DATA_DIR is not set.
std::string pythonHandsDir();

}  // namespace taskmap
