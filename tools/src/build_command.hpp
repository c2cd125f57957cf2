#pragma once
/// @file build_command.hpp
/// What the build and dataset commands of `taskmap` and `taskmap-mpi` share: the options (one
/// definition, so both accept the same command line), turning them into the library's
/// FileBuildOptions and DatasetOptions (taskmap/builder/map_file_build.hpp, dataset.hpp), the
/// progress printer and the summaries.

#include <cstdint>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "mesh_options.hpp"
#include "taskmap/builder/build_knobs.hpp"
#include "taskmap/builder/build_report.hpp"
#include "taskmap/builder/dataset.hpp"
#include "taskmap/builder/map_file_build.hpp"

namespace taskmap::cli {

/// The command line of a build, as parsed: the knobs (taskmap/builder/build_knobs.hpp, the one
/// list the command line and Python share), the files, the mesh options and the printing.
struct BuildArgs : BuildKnobs {
  std::string object, hand, output;
  double scale = 1.0;
  MeshRepairArgs repair;  ///< --no-repair, --repair wrap, --wrap-alpha, --wrap-offset
  bool quiet = false, progress = false;
  bool force = false;  ///< replace an existing output that is not a task map
};

/// The library's options of a build command line: the knobs, the mesh options and the hold
/// validation. Throws Error on contradicting options (--keep-holding without --validate).
FileBuildOptions fileBuildOptions(const BuildArgs& args);

/// --validate and --keep-holding as the library's mode. Throws Error("--keep-holding needs
/// --validate ...") for --keep-holding alone.
HoldValidation holdValidation(const BuildArgs& args);

/// How to load the object: --scale and the repair options.
MeshLoadOptions meshLoadOptions(const BuildArgs& args);

/// The physics validation's line(s) on stderr ("<label>: physics validation: ..."), unless
/// quiet; nothing without labels.
void printHoldLabels(const std::string& label, const std::optional<HoldLabels>& labels,
                     bool keep_holding, bool quiet);

/// Prints hand-info's warnings about the hand (hand_check.hpp) on stderr, one line each as
/// "<label>: warning: hand '<name>': ...", before the trials (also with --quiet). Returns true
/// when it printed any.
bool printHandWarnings(const std::string& label, const HandModel& hand);

/// Adds the build options (--object, --hand, -o, --scale and the knobs) to a subcommand.
void addBuildOptions(CLI::App& cmd, BuildArgs& args);

/// Adds the knobs of a build (every knob of visitBuildKnobs, --package-path, -q, --progress) to
/// a subcommand.
void addBuildKnobs(CLI::App& cmd, BuildArgs& args);

/// The BuildOptions of the knobs (not validated; no extra_params_json).
BuildOptions knobOptions(const BuildArgs& args);

/// Progress: a bar on a terminal (or with --progress), a log line every 10 s otherwise.
class ProgressPrinter {
 public:
  /// @param label start of each log line, e.g. "taskmap build".
  ProgressPrinter(std::string label, bool terminal, bool quiet);
  /// Draws one report.
  void operator()(const BuildProgress& p);
  /// Ends the bar's line.
  void finish();

 private:
  std::string label_;
  bool terminal_, quiet_, drawn_ = false;
  double next_log_ = 10.0;
};

/// Prints buildSummaryText on stdout (unless quiet) and buildBudgetWarning on stderr. @param how
/// one line after "threads", e.g. "2 (not stored: ...)".
void printBuildSummary(const std::string& label, const BuildArgs& args, const BuildResult& result,
                       double write_seconds, const std::string& how);

/// The command line of a data set.
struct DatasetArgs {
  /// text file: one mesh path a line (relative to the file), optionally followed by the mesh's
  /// scale ("bunny.ply 0.01"); # comments
  std::string objects;
  std::string hands;   ///< comma-separated hand URDFs or bundled hand names
  std::string output;  ///< directory for the maps and manifest.json (created if missing)
  double scale = 1.0;  ///< mesh scale of every object the list gives none
  BuildArgs knobs;     ///< --valid, --trials, --seed, --threads, ... as for `taskmap build`
};

/// Adds the data-set options to a subcommand.
void addDatasetOptions(CLI::App& cmd, DatasetArgs& args);

/// The library's options of a data-set command line.
DatasetOptions datasetOptions(const DatasetArgs& args);

}  // namespace taskmap::cli
