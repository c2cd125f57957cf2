#pragma once
// Python bindings of the reaching stage, added to the `taskmap` module (taskmap_module.cpp).
#include <pybind11/pybind11.h>

namespace taskmap {

/// Adds taskmap.Robot and taskmap.reach to the module.
void bindReaching(pybind11::module_& m);

}  // namespace taskmap
