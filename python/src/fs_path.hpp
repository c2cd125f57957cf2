#pragma once
// A path argument of the Python calls: str, bytes or any os.PathLike, as os.fspath gives it.

#include <pybind11/pybind11.h>

#include <string>

namespace taskmap {

/// `path` through os.fspath, as a string (raises TypeError for what is not a path).
inline std::string fsPath(const pybind11::object& path) {
  return pybind11::str(pybind11::module_::import("os").attr("fspath")(path));
}

}  // namespace taskmap
