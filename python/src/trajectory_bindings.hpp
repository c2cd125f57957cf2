#pragma once
// Python bindings of trajectory files (mapstore/TRAJECTORY.md), added to the `taskmap` module
// (taskmap_module.cpp).
#include <pybind11/pybind11.h>

namespace taskmap {

/// Adds taskmap.read_trajectory to the module.
void bindTrajectory(pybind11::module_& m);

}  // namespace taskmap
