// taskmap.validate: labels a map's grasps with the physics hold test (docs/VALIDATION.md) and
// writes them into the map, with the keyword arguments of `taskmap validate`.
#include "validate_bindings.hpp"

#include "offline_docs.hpp"
#include "python_run.hpp"

#include <pybind11/stl.h>

#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/mapstore/recorded_hand.hpp"
#include "taskmap/validate/validate_map.hpp"

namespace py = pybind11;

namespace taskmap {
namespace {

py::dict summaryDict(const ValidationSummary& s) {
  return py::module_::import("json").attr("loads")(summaryJson(s)).cast<py::dict>();
}

/// `hand`, or the URDF the map was built with (refused with what to pass when not found).
std::string handUrdf(const TaskMapData& map, const std::string& hand, const std::string& map_path,
                     const char* who) {
  try {
    checkMapJoints(map);
  } catch (const Error& e) {
    throw Error(std::string(who) + ": map '" + map_path + "': " + e.what());
  }
  if (!hand.empty()) return hand;
  try {
    return findMapHandUrdf(map);
  } catch (const Error& e) {
    throw Error(std::string(who) + ": map '" + map_path + "': " + e.what() + "; pass hand=PATH");
  }
}

py::dict validatePath(const std::string& map_path, const std::string& hand,
                      const std::string& output, int threads, std::size_t grasps,
                      double object_mass, double friction, double jaw_force, double contact_patch,
                      bool robust, bool full, bool stated_dynamics, const std::string& integrator,
                      py::object progress) {
  TaskMapData map = readMap(map_path);
  const std::string urdf = handUrdf(map, hand, map_path, "validate");
  ValidateOptions o;
  o.threads = threads;
  o.grasps = grasps;
  o.hold.object_mass = object_mass;
  o.hold.sliding_friction = friction;
  o.hold.jaw_force = jaw_force;
  o.hold.contact_patch = contact_patch;
  o.hold.settle_stop = !full;
  o.hold.integrator = integratorFromName(integrator);
  o.robust = robust;
  o.hold.stated_dynamics = stated_dynamics;
  PythonRun run(std::move(progress));
  ValidationSummary s;
  {
    py::gil_scoped_release release;
    ValidateControl control;
    control.stop = run.stop();
    control.progress = [&run](const ValidateProgress& p) {
      run.report([&p] {
        py::dict d;
        d["done"] = p.done;
        d["total"] = p.total;
        d["holding"] = p.holding;
        return d;
      });
    };
    s = validateMap(&map, HandModel::load(urdf), o, control);
  }
  run.raiseIfFailed();  // Ctrl-C or the callback's exception: nothing written
  {
    py::gil_scoped_release release;
    writeMap(output.empty() ? map_path : output, map);
  }
  return summaryDict(s);
}

py::dict tracePath(const std::string& map_path, std::size_t grasp, const std::string& hand,
                   double object_mass, double friction, double jaw_force, double contact_patch) {
  std::string trace_json;
  {
    py::gil_scoped_release release;
    const TaskMapData map = readMap(map_path);
    const std::string urdf = handUrdf(map, hand, map_path, "trace_hold");
    HoldTestOptions o;
    o.object_mass = object_mass;
    o.sliding_friction = friction;
    o.jaw_force = jaw_force;
    o.contact_patch = contact_patch;
    const HandModel h = HandModel::load(urdf);
    trace_json = traceJson(traceGrasp(map, h, grasp, o), h);
  }
  return py::module_::import("json").attr("loads")(trace_json).cast<py::dict>();
}

}  // namespace

void bindValidate(py::module_& m) {
  const HoldTestOptions d;
  m.def("validate", &validatePath, py::arg("map"), py::arg("hand") = "", py::arg("output") = "",
        py::arg("threads") = 0, py::arg("grasps") = 0, py::arg("object_mass") = d.object_mass,
        py::arg("friction") = d.sliding_friction, py::arg("jaw_force") = d.jaw_force,
        py::arg("contact_patch") = d.contact_patch, py::arg("robust") = false,
        py::arg("full") = false, py::arg("stated_dynamics") = d.stated_dynamics,
        py::arg("integrator") = integratorName(d.integrator), py::arg("progress") = py::none(),
        pydoc::kValidate);
  m.def("trace_hold", &tracePath, py::arg("map"), py::arg("grasp"), py::arg("hand") = "",
        py::arg("object_mass") = d.object_mass, py::arg("friction") = d.sliding_friction,
        py::arg("jaw_force") = d.jaw_force, py::arg("contact_patch") = d.contact_patch,
        pydoc::kTraceHold);
}

}  // namespace taskmap
