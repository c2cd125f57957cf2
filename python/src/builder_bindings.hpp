#pragma once
// taskmap.build and taskmap.dataset (builder stage), part of taskmap._offline.

#include <pybind11/pybind11.h>

namespace taskmap {

/// Adds build and dataset to the module.
void bindBuilder(pybind11::module_& m);

}  // namespace taskmap
