#pragma once
// taskmap.picture: the PNG `taskmap inspect --png` draws of a map (picture stage).
#include <pybind11/pybind11.h>

namespace taskmap {

/// Adds taskmap.picture to the module.
void bindPicture(pybind11::module_& m);

}  // namespace taskmap
