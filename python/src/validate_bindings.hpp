#pragma once
// taskmap.validate: the physics hold test of a map's grasps (validate stage).
#include <pybind11/pybind11.h>

namespace taskmap {

/// Adds taskmap.validate to the module.
void bindValidate(pybind11::module_& m);

}  // namespace taskmap
