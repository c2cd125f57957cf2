// taskmap.build and taskmap.dataset: the map build and data sets of maps (builder stage,
// taskmap/builder/map_file_build.hpp, dataset.hpp) with the keyword arguments of `taskmap build`
// and `taskmap dataset`. The GIL is released while the trials run; the progress hook takes it
// back on the calling thread, calls the user's callback and checks for signals, so Ctrl-C
// (KeyboardInterrupt) stops the build cleanly: the workers finish their trial, nothing is
// written, and the KeyboardInterrupt reaches the caller.
#include "builder_bindings.hpp"

#include <pybind11/stl.h>

#include <atomic>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "taskmap/builder/dataset.hpp"
#include "taskmap/builder/map_file_build.hpp"
#include "taskmap/core/error.hpp"

namespace py = pybind11;

namespace taskmap {
namespace {

/// The build knobs as named on the command line (`taskmap build --help`).
struct Knobs {
  std::string sampler = "mixed";
  std::uint64_t valid = 1000, trials = 200000, seed = 1;
  int threads = 0;
  double friction = 0.5;
  int cone_edges = 8;
  std::string grasp;  // "", "palm", "fingertip"
  std::optional<double> standoff;
  bool allow_size = false, keep_invalid = false, no_cluster = false, validate = false,
       keep_holding = false, hold_filter = false;
};

BuildOptions buildOptions(const Knobs& k) {
  BuildOptions o;
  o.sampler.kind = samplerKindFromString(k.sampler);
  o.valid_target = k.valid;
  o.max_trials = k.trials;
  o.seed = k.seed;
  o.threads = k.threads;
  o.quality.friction = k.friction;
  o.quality.cone_edges = k.cone_edges;
  o.keep_invalid = k.keep_invalid;
  o.cluster = !k.no_cluster;
  o.hold_filter.enabled = k.hold_filter;
  o.check_size = !k.allow_size;
  if (!k.grasp.empty() && k.grasp != "palm" && k.grasp != "fingertip")
    throw Error("grasp must be \"palm\" or \"fingertip\" (got \"" + k.grasp + "\")");
  if (!k.grasp.empty())
    o.simulation.grasp_mode = k.grasp == "palm" ? GraspMode::kPalm : GraspMode::kFingertip;
  o.simulation.standoff = k.standoff.value_or(-1.0);
  return o;
}

HoldValidation holdValidation(const Knobs& k) {
  if (k.keep_holding && !k.validate)
    throw Error("keep_holding needs validate (the hold labels decide what is kept)");
  if (!k.validate) return HoldValidation::kOff;
  return k.keep_holding ? HoldValidation::kKeepHolding : HoldValidation::kLabel;
}

MeshLoadOptions meshOptions(double scale, bool no_repair, const std::string& repair,
                            double wrap_alpha, double wrap_offset) {
  if (!repair.empty() && repair != "wrap") throw Error("repair must be \"wrap\" or empty");
  const bool wrap = repair == "wrap";
  if (wrap && no_repair) throw Error("repair=\"wrap\" and no_repair contradict each other");
  if (!wrap && (wrap_alpha > 0 || wrap_offset > 0))
    throw Error("wrap_alpha and wrap_offset need repair=\"wrap\"");
  MeshLoadOptions m;
  m.scale = scale;
  m.repair = !no_repair;
  m.wrap = wrap;
  m.wrap_alpha = wrap_alpha;
  m.wrap_offset = wrap_offset;
  return m;
}

/// The Python side of a run: the user's callback, the stop flag, and the first Python error
/// (KeyboardInterrupt from a signal, or the callback's exception) kept until the GIL is back.
class PythonRun {
 public:
  explicit PythonRun(py::object callback) : callback_(std::move(callback)) {}
  ~PythonRun() {
    if (!error_) return;
    py::gil_scoped_acquire acquire;
    error_.reset();
  }

  const std::atomic<bool>* stop() const { return &stop_; }

  /// Called with the GIL released: takes it, checks signals and, with a report maker, calls
  /// back with its report.
  template <class MakeReport>
  void report(MakeReport&& make) {
    if (stop_.load()) return;
    py::gil_scoped_acquire acquire;
    try {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if constexpr (!std::is_same_v<std::decay_t<MakeReport>, std::nullptr_t>)
        if (!callback_.is_none()) callback_(make());
    } catch (py::error_already_set& e) {
      error_.emplace(std::move(e));
      stop_.store(true);
    }
  }

  /// With the GIL held: raises the kept error, if any.
  void raiseIfFailed() {
    if (!error_) return;
    py::error_already_set e = std::move(*error_);
    error_.reset();
    throw e;
  }

 private:
  py::object callback_;
  std::atomic<bool> stop_{false};
  std::optional<py::error_already_set> error_;
};

py::dict progressDict(const BuildProgress& p) {
  py::dict d;
  d["trials_done"] = p.trials_done;
  d["valid_found"] = p.valid_found;
  d["valid_target"] = p.valid_target;
  d["max_trials"] = p.max_trials;
  d["elapsed_seconds"] = p.elapsed_seconds;
  return d;
}

py::object buildMapFile(const std::string& object, const std::string& hand,
                        const std::string& output, double scale, const Knobs& knobs, bool no_repair,
                        const std::string& repair, double wrap_alpha, double wrap_offset,
                        bool timestamp, bool force, py::object progress) {
  FileBuildOptions o;
  o.object = object;
  o.hand = hand;
  o.output = output;
  o.mesh = meshOptions(scale, no_repair, repair, wrap_alpha, wrap_offset);
  o.build = buildOptions(knobs);
  o.validation = holdValidation(knobs);
  o.timestamp = timestamp;
  o.force = force;
  PythonRun run(std::move(progress));
  FileBuildResult r;
  {
    py::gil_scoped_release release;
    MapFileBuild build(o);
    BuildControl control;
    control.stop = run.stop();
    control.progress = [&run](const BuildProgress& p) {
      run.report([&p] { return progressDict(p); });
    };
    r = build.run(control);
  }
  run.raiseIfFailed();
  if (!r.written) throw Error(r.build.message + "; nothing written to '" + output + "'");
  return py::module_::import("taskmap._core").attr("load")(output);
}

py::dict datasetDict(const DatasetResult& r) {
  py::dict d;
  d["jobs"] = r.jobs;
  d["skipped"] = r.skipped;
  d["failed"] = r.failed;
  d["dir"] = r.dir;
  d["manifest"] = r.dir + "/manifest.json";
  return d;
}

py::dict runDataset(const std::string& objects, const std::string& hands, const std::string& output,
                    double scale, const Knobs& knobs, bool timestamp, bool force,
                    py::object progress) {
  DatasetOptions o;
  o.objects = objects;
  o.hands = hands;
  o.output = output;
  o.scale = scale;
  o.build = buildOptions(knobs);
  o.validation = holdValidation(knobs);
  o.timestamp = timestamp;
  o.force = force;
  PythonRun run(std::move(progress));
  DatasetResult r;
  {
    py::gil_scoped_release release;
    DatasetRun dataset(o);
    RunControl<DatasetProgress> control;
    control.stop = run.stop();
    control.progress = [&run](const DatasetProgress& p) {
      run.report([&p] {
        py::dict d;
        d["done"] = p.done;
        d["total"] = p.total;
        d["elapsed_seconds"] = p.elapsed_seconds;
        d["entry"] = py::module_::import("json").attr("loads")(datasetEntryJson(p.entry));
        return d;
      });
    };
    BuildControl trials;  // signals are checked during each map's trials too
    trials.progress = [&run](const BuildProgress&) { run.report(nullptr); };
    r = dataset.run(control, trials);
  }
  run.raiseIfFailed();
  return datasetDict(r);
}

}  // namespace

void bindBuilder(py::module_& m) {
  m.def(
      "build",
      [](const std::string& object, const std::string& hand, const std::string& output,
         double scale, const std::string& sampler, std::uint64_t valid, std::uint64_t trials,
         std::uint64_t seed, int threads, double friction, int cone_edges, const std::string& grasp,
         std::optional<double> standoff, bool allow_size, bool keep_invalid, bool no_cluster,
         bool validate, bool keep_holding, bool hold_filter, bool no_repair,
         const std::string& repair, double wrap_alpha, double wrap_offset, bool timestamp,
         bool force, py::object progress) {
        const Knobs k{sampler,      valid,      trials,   seed,         threads,
                      friction,     cone_edges, grasp,    standoff,     allow_size,
                      keep_invalid, no_cluster, validate, keep_holding, hold_filter};
        return buildMapFile(object, hand, output, scale, k, no_repair, repair, wrap_alpha,
                            wrap_offset, timestamp, force, std::move(progress));
      },
      py::kw_only(), py::arg("object"), py::arg("hand"), py::arg("output"), py::arg("scale") = 1.0,
      py::arg("sampler") = "mixed", py::arg("valid") = 1000, py::arg("trials") = 200000,
      py::arg("seed") = 1, py::arg("threads") = 0, py::arg("friction") = 0.5,
      py::arg("cone_edges") = 8, py::arg("grasp") = "", py::arg("standoff") = py::none(),
      py::arg("allow_size") = false, py::arg("keep_invalid") = false, py::arg("no_cluster") = false,
      py::arg("validate") = false, py::arg("keep_holding") = false, py::arg("hold_filter") = false,
      py::arg("no_repair") = false, py::arg("repair") = "", py::arg("wrap_alpha") = 0.0,
      py::arg("wrap_offset") = 0.0, py::arg("timestamp") = false, py::arg("force") = false,
      py::arg("progress") = py::none(),
      "Builds a task map as `taskmap build` does (the same options, the same map bytes for the "
      "same options: same seed same map for any thread count), writes it to `output` and "
      "returns it loaded (taskmap.load). object: mesh file, its coordinates times `scale` are "
      "metres in the object frame; hand: URDF (with its <stem>.hand.json sidecar) or a bundled "
      "hand name ('barrett', 'panda', ...). sampler: 'volume', 'surface' or 'mixed'; valid: "
      "stop after this many force-closure grasps; trials: trial budget; threads: 0 = all cores; "
      "friction: Coulomb mu; cone_edges: friction-cone edges; grasp: 'palm', 'fingertip' or '' "
      "(the hand's); standoff: fingertip grasps' palm-to-object distance in metres (None: the "
      "hand's); validate / keep_holding: label (keep) grasps by the physics hold test; "
      "hold_filter: the squeeze-balance filter; no_repair, repair='wrap', wrap_alpha, "
      "wrap_offset (metres): mesh repair; timestamp: store the current time; force: replace an "
      "output that is not a task map. progress(dict) is called about every 0.25 s with "
      "trials_done, valid_found, valid_target, max_trials, elapsed_seconds. Ctrl-C raises "
      "KeyboardInterrupt and writes nothing; so does an exception from `progress` (raised "
      "here). Errors in input raise taskmap.Error naming the file or option.");
  m.def(
      "dataset",
      [](const std::string& objects, const std::vector<std::string>& hands,
         const std::string& output, double scale, const std::string& sampler, std::uint64_t valid,
         std::uint64_t trials, std::uint64_t seed, int threads, double friction, int cone_edges,
         const std::string& grasp, std::optional<double> standoff, bool allow_size,
         bool keep_invalid, bool no_cluster, bool validate, bool keep_holding, bool hold_filter,
         bool timestamp, bool force, py::object progress) {
        const Knobs k{sampler,      valid,      trials,   seed,         threads,
                      friction,     cone_edges, grasp,    standoff,     allow_size,
                      keep_invalid, no_cluster, validate, keep_holding, hold_filter};
        std::string joined;
        for (const std::string& h : hands) joined += (joined.empty() ? "" : ",") + h;
        return runDataset(objects, joined, output, scale, k, timestamp, force, std::move(progress));
      },
      py::kw_only(), py::arg("objects"), py::arg("hands"), py::arg("output"),
      py::arg("scale") = 1.0, py::arg("sampler") = "mixed", py::arg("valid") = 1000,
      py::arg("trials") = 200000, py::arg("seed") = 1, py::arg("threads") = 0,
      py::arg("friction") = 0.5, py::arg("cone_edges") = 8, py::arg("grasp") = "",
      py::arg("standoff") = py::none(), py::arg("allow_size") = false,
      py::arg("keep_invalid") = false, py::arg("no_cluster") = false, py::arg("validate") = false,
      py::arg("keep_holding") = false, py::arg("hold_filter") = false, py::arg("timestamp") = false,
      py::arg("force") = false, py::arg("progress") = py::none(),
      "Builds one task map per (object, hand) into the directory `output` as `taskmap dataset` "
      "does (the same maps and manifest.json). objects: text file, one mesh path a line "
      "(relative to the file), optionally followed by its scale (file units to metres); hands: "
      "a list of hand URDFs or bundled hand names; scale: for meshes the list gives none; the "
      "other options as for taskmap.build (seed is the data set's: each job's derives from it "
      "and the mesh and hand contents). A re-run skips maps whose file and parameters match "
      "the manifest; a bad mesh is recorded there (status 'failed'), not raised. progress(dict) "
      "is called after each job with done, total, elapsed_seconds and entry (the job's manifest "
      "entry). Ctrl-C raises KeyboardInterrupt (the current map is not written, its entry stays "
      "'pending'). Returns {jobs, skipped, failed, dir, manifest}.");
}

}  // namespace taskmap
