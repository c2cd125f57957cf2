#pragma once
// taskmap.export, taskmap.export_glb and taskmap.view (inspect, mapstore and viz stages), part of
// taskmap._offline.

#include <pybind11/pybind11.h>

namespace taskmap {

/// Adds export, export_glb and view to the module.
void bindExport(pybind11::module_& m);

}  // namespace taskmap
