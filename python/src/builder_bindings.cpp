// taskmap.build and taskmap.dataset: the map build and data sets of maps (builder stage,
// taskmap/builder/map_file_build.hpp, dataset.hpp) with the keyword arguments of `taskmap build`
// and `taskmap dataset`. The GIL is released while the trials run; the progress hook takes it
// back on the calling thread, calls the user's callback and checks for signals, so Ctrl-C
// (KeyboardInterrupt) stops the build cleanly: the workers finish their trial, nothing is
// written, and the KeyboardInterrupt reaches the caller.
#include "builder_bindings.hpp"

#include "fs_path.hpp"
#include "offline_docs.hpp"
#include "python_run.hpp"

#include <pybind11/stl.h>

#include <atomic>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "taskmap/builder/acronym_import.hpp"
#include "taskmap/builder/build_knobs.hpp"
#include "taskmap/builder/dataset.hpp"
#include "taskmap/builder/map_file_build.hpp"
#include "taskmap/builder/recluster.hpp"
#include "taskmap/builder/regression_suite.hpp"
#include "taskmap/clustering/clustering.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace py = pybind11;

namespace taskmap {

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

namespace {

/// The knobs of `kwargs` (named as visitBuildKnobs names them; None: the default). Raises
/// TypeError for a name that is not a knob or a value of the wrong type.
BuildKnobs knobsOf(const char* function, const py::kwargs& kwargs) {
  BuildKnobs k;
  for (const auto& item : kwargs) {
    const std::string key = py::cast<std::string>(item.first);
    const py::handle value = item.second;
    bool found = false;
    visitBuildKnobs(k, [&](const KnobInfo& info, auto& field) {
      if (key != info.name) return;
      found = true;
      if (value.is_none()) return;
      using T = std::decay_t<decltype(field)>;
      if constexpr (std::is_same_v<T, bool>) {
        if (!py::isinstance<py::bool_>(value))
          throw py::type_error(std::string(function) + "(): " + key + " must be True or False");
      }
      try {
        field = py::cast<T>(value);
      } catch (const py::cast_error&) {
        throw py::type_error(std::string(function) + "(): " + key + " must be " +
                             (std::is_same_v<T, std::string> ? "a str"
                              : std::is_floating_point_v<T>  ? "a number"
                              : std::is_unsigned_v<T>        ? "a non-negative int"
                                                             : "an int") +
                             ", not " +
                             py::str(value.get_type().attr("__name__")).cast<std::string>());
      }
    });
    if (!found)
      throw py::type_error(std::string(function) + "() got an unexpected keyword argument '" + key +
                           "' (the knobs are those of `taskmap build`: see help(taskmap." +
                           function + "))");
  }
  return k;
}

/// The knobs' part of a docstring: a napoleon "Other Parameters" section, one entry per knob
/// with its type, help and default.
std::string knobsDoc() {
  std::string doc = "Other Parameters:\n";
  BuildKnobs k;
  visitBuildKnobs(k, [&doc](const KnobInfo& info, const auto& field) {
    using T = std::decay_t<decltype(field)>;
    const char* type = std::is_same_v<T, bool>          ? "bool"
                       : std::is_same_v<T, std::string> ? "str"
                       : std::is_floating_point_v<T>    ? "float"
                                                        : "int";
    std::string d = py::repr(py::cast(field)).template cast<std::string>();
    if (!info.capture_default) d = "None (the hand's)";
    doc += std::string("    ") + info.name + " (" + type + "): " + info.help + ". Default: ``" + d +
           "``.\n";
  });
  return doc + "\n";
}

/// `doc` with the knobs' section inserted before its "Returns:" section.
std::string withKnobs(const char* doc) {
  std::string s = doc;
  const std::size_t at = s.find("Returns:");
  return at == std::string::npos ? s + "\n" + knobsDoc() : s.insert(at, knobsDoc());
}

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
                        const std::string& output, double scale, const BuildKnobs& knobs,
                        bool no_repair, const std::string& repair, double wrap_alpha,
                        double wrap_offset, bool force, py::object progress) {
  FileBuildOptions o;
  o.object = object;
  o.hand = hand;
  o.output = output;
  o.mesh = meshOptions(scale, no_repair, repair, wrap_alpha, wrap_offset);
  o.build = buildOptionsOf(knobs, KnobStyle::kPython);
  o.validation = holdValidationOf(knobs, KnobStyle::kPython);
  o.timestamp = knobs.timestamp;
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
                    double scale, const BuildKnobs& knobs, bool force, py::object progress) {
  DatasetOptions o;
  o.objects = objects;
  o.hands = hands;
  o.output = output;
  o.scale = scale;
  o.build = buildOptionsOf(knobs, KnobStyle::kPython);
  o.validation = holdValidationOf(knobs, KnobStyle::kPython);
  o.timestamp = knobs.timestamp;
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

/// taskmap.import_acronym: `taskmap import` as a call (its option names as keywords).
py::object importAcronym(const std::string& acronym, const std::string& object,
                         const std::string& output, double scale, bool successful_only,
                         bool no_cluster, const std::string& linkage, double rotation_scale,
                         std::optional<double> threshold, std::optional<int> clusters,
                         double min_size_fraction, std::optional<double> palm_offset,
                         const std::string& hand, bool timestamp, bool force) {
  AcronymFileImportOptions o;
  o.acronym = acronym;
  o.object = objectFileOrBundled(object);
  o.output = output;
  o.scale = scale;
  o.timestamp = timestamp;
  checkOutputPath(o.output, {o.acronym, o.object}, OutputKind::kTaskMap, force);
  if (o.scale < 0) throw Error("import_acronym: scale must be positive (0: the file's)");
  o.import.successful_only = successful_only;
  o.import.cluster = !no_cluster;
  o.import.clustering.method = linkageFromString(linkage);
  o.import.clustering.rotation_scale = rotation_scale;
  o.import.clustering.threshold = threshold;
  o.import.clustering.num_clusters = clusters;
  o.import.clustering.min_size_fraction = min_size_fraction;
  o.import.base_to_palm = acronymBaseToPalm(palm_offset, hand);
  o.hand = hand;
  {
    py::gil_scoped_release release;
    importAcronymFile(o);
  }
  return py::module_::import("taskmap._core").attr("load")(output);
}

/// taskmap.recluster: `taskmap cluster` as a call (its option names as keywords).
py::object recluster(const py::object& map, const ReclusterOptions& o, const std::string& output,
                     bool force) {
  const std::string path = fsPath(map);
  const std::string target = output.empty() ? path : output;
  if (!output.empty()) checkOutputPath(output, {path}, OutputKind::kTaskMap, force);
  {
    py::gil_scoped_release release;
    TaskMapData data = readMap(path);
    reclusterMap(&data, o);
    writeMap(target, data);
  }
  return py::module_::import("taskmap._core").attr("load")(target);
}

/// taskmap.regress: `taskmap regress` as a call; one dict per case.
py::dict regress(const RegressionSuiteOptions& options) {
  RegressionSuiteResult r;
  {
    py::gil_scoped_release release;
    r = runRegressionSuite(options);
  }
  py::list cases;
  for (const RegressionCaseRun& c : r.cases) {
    py::dict d;
    d["name"] = c.spec.name;
    d["object"] = c.object;
    d["hand"] = c.hand;
    d["golden"] = c.golden_path;
    d["outcome"] = c.outcome == RegressionCaseRun::Outcome::kCompared  ? "compared"
                   : c.outcome == RegressionCaseRun::Outcome::kUpdated ? "updated"
                                                                       : "no_golden";
    d["failures"] = c.failures;
    py::list rows;
    for (const ComparisonRow& row : c.comparison.rows)
      rows.append(py::dict(py::arg("statistic") = row.statistic, py::arg("golden") = row.golden,
                           py::arg("now") = row.now, py::arg("pass") = row.pass));
    d["rows"] = rows;
    d["text"] = regressionCaseText(c);
    cases.append(d);
  }
  py::dict out;
  out["cases"] = cases;
  out["failures"] = r.failures;
  out["golden_dir"] = r.golden_dir;
  return out;
}

}  // namespace

void bindBuilder(py::module_& m) {
  const ClusteringOptions clustering;
  m.def(
      "regress",
      [](const std::string& cases, const std::string& golden, const std::vector<std::string>& only,
         bool update, int threads, std::optional<double> friction) {
        RegressionSuiteOptions o;
        o.cases = cases;
        o.golden_dir = golden;
        o.only = only;
        o.update = update;
        o.threads = threads;
        o.friction = friction;
        return regress(o);
      },
      py::kw_only(), py::arg("cases") = "", py::arg("golden") = "",
      py::arg("only") = std::vector<std::string>{}, py::arg("update") = false,
      py::arg("threads") = 0, py::arg("friction") = py::none(), pydoc::kRegress);
  m.def(
      "recluster",
      [](const py::object& map, std::optional<double> threshold, std::optional<int> clusters,
         std::optional<int> min_size, std::optional<std::string> method,
         std::optional<double> outlier_budget, const std::string& output, bool force) {
        ReclusterOptions o;
        o.threshold = threshold;
        o.clusters = clusters;
        o.min_size = min_size;
        o.method = method;
        o.outlier_budget = outlier_budget;
        return recluster(map, o, output, force);
      },
      py::arg("map"), py::kw_only(), py::arg("threshold") = py::none(),
      py::arg("clusters") = py::none(), py::arg("min_size") = py::none(),
      py::arg("method") = py::none(), py::arg("outlier_budget") = py::none(),
      py::arg("output") = "", py::arg("force") = false, pydoc::kRecluster);
  m.def("import_acronym", &importAcronym, py::kw_only(), py::arg("acronym"), py::arg("object"),
        py::arg("output"), py::arg("scale") = 0.0, py::arg("successful_only") = false,
        py::arg("no_cluster") = false, py::arg("linkage") = toString(clustering.method),
        py::arg("rotation_scale") = kDefaultRotationScale, py::arg("threshold") = py::none(),
        py::arg("clusters") = py::none(), py::arg("min_size_fraction") = kDefaultMinSizeFraction,
        py::arg("palm_offset") = py::none(), py::arg("hand") = "", py::arg("timestamp") = false,
        py::arg("force") = false, pydoc::kImportAcronym);
  static const std::string build_doc = withKnobs(pydoc::kBuild);
  m.def(
      "build",
      [](const std::string& object, const std::string& hand, const std::string& output,
         double scale, bool no_repair, const std::string& repair, double wrap_alpha,
         double wrap_offset, bool force, py::object progress, const py::kwargs& knobs) {
        return buildMapFile(object, hand, output, scale, knobsOf("build", knobs), no_repair, repair,
                            wrap_alpha, wrap_offset, force, std::move(progress));
      },
      py::kw_only(), py::arg("object"), py::arg("hand"), py::arg("output"), py::arg("scale") = 1.0,
      py::arg("no_repair") = false, py::arg("repair") = "", py::arg("wrap_alpha") = 0.0,
      py::arg("wrap_offset") = 0.0, py::arg("force") = false, py::arg("progress") = py::none(),
      build_doc.c_str());
  static const std::string dataset_doc = withKnobs(pydoc::kDataset);
  m.def(
      "dataset",
      [](const std::string& objects, const std::vector<std::string>& hands,
         const std::string& output, double scale, bool force, py::object progress,
         const py::kwargs& knobs) {
        std::string joined;
        for (const std::string& h : hands) joined += (joined.empty() ? "" : ",") + h;
        return runDataset(objects, joined, output, scale, knobsOf("dataset", knobs), force,
                          std::move(progress));
      },
      py::kw_only(), py::arg("objects"), py::arg("hands"), py::arg("output"),
      py::arg("scale") = 1.0, py::arg("force") = false, py::arg("progress") = py::none(),
      dataset_doc.c_str());
}

}  // namespace taskmap
