#pragma once
// taskmap.TaskMap's stored data as numpy arrays (python/src/map_arrays.cpp).

#include <pybind11/pybind11.h>

#include "taskmap/integration/task_map.hpp"

namespace taskmap {

/// Adds the read-only array properties of a map (joints, force closure, contacts with their
/// link names, physics hold labels) and contacts(i) to the TaskMap class.
void bindTaskMapArrays(pybind11::class_<TaskMap>& cls);

}  // namespace taskmap
