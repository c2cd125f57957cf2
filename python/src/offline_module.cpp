// taskmap._offline: the offline stages (map build, reaching planner, physics validation, map and
// hand reports, pictures), which load the simulators and the mesh and URDF libraries. `import
// taskmap` does not load it; the package imports it on first use of one of its names
// (python/taskmap/__init__.py).
#include <pybind11/pybind11.h>

#include "builder_bindings.hpp"
#include "export_bindings.hpp"
#include "inspect_bindings.hpp"
#include "picture_bindings.hpp"
#include "reaching_bindings.hpp"
#include "taskmap/core/error.hpp"
#include "validate_bindings.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_offline, m) {
  m.doc() =
      "taskmap's offline stages: build, dataset, import_acronym, recluster, Robot, reach, "
      "plan_grasp, validate, summary, hand_info, mesh_info, picture, export, export_glb, view "
      "(loaded on first use).";
  // taskmap::Error raised here is the package's one taskmap.Error (defined by taskmap._core).
  // A handle kept for the process's life: a static py::object would drop its reference at exit,
  // after the interpreter is gone.
  static const py::handle error =
      py::object(py::module_::import("taskmap._core").attr("Error")).release();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const taskmap::Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });
  taskmap::bindBuilder(m);
  taskmap::bindReaching(m);
  taskmap::bindValidate(m);
  taskmap::bindInspect(m);
  taskmap::bindPicture(m);
  taskmap::bindExport(m);
}
