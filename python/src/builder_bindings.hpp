#pragma once
// taskmap.build and taskmap.dataset (builder stage), part of taskmap._offline.

#include <string>

#include <pybind11/pybind11.h>

#include "taskmap/meshes/object_model.hpp"

namespace taskmap {

/// How to load an object mesh from the keyword arguments scale, no_repair, repair ("" or
/// "wrap"), wrap_alpha and wrap_offset (metres; the CLI's --scale, --no-repair, --repair,
/// --wrap-alpha, --wrap-offset). Throws Error naming the keyword on contradicting arguments.
MeshLoadOptions meshOptions(double scale, bool no_repair, const std::string& repair,
                            double wrap_alpha, double wrap_offset);

/// Adds build and dataset to the module.
void bindBuilder(pybind11::module_& m);

}  // namespace taskmap
