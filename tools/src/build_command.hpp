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
#include "taskmap/builder/dataset.hpp"
#include "taskmap/builder/map_file_build.hpp"

namespace taskmap::cli {

/// The command line of a build, as parsed.
struct BuildArgs {
  std::string object, hand, output, sampler = "mixed";
  double scale = 1.0;
  std::uint64_t valid = 1000, trials = 200000, seed = 1;
  int threads = 0;
  double friction = 0.5;
  int cone_edges = 8;
  std::string volume = "never";  ///< which stored grasps get the wrench-space volume

  int contacts_per_link = 0;  ///< per-link contact reduction before the hull (0 = none)
  std::string grasp;          ///< "", "palm" or "fingertip" ("" = the hand sidecar's)
  double standoff = -1.0;     ///< metres; negative = the hand sidecar's
  MeshRepairArgs repair;      ///< --no-repair, --repair wrap, --wrap-alpha, --wrap-offset
  bool keep_invalid = false, no_cluster = false, quiet = false, progress = false;
  bool timestamp = false;     ///< store the current time as created_utc
  bool allow_size = false;    ///< build an object whose size is implausible for the hand
  bool validate = false;      ///< label the grasps with the physics hold test before writing
  bool keep_holding = false;  ///< with validate: store only the grasps that hold
  bool hold_filter = false;   ///< refuse grasps the squeeze-balance filter finds unbalanced
  /// --closing-check: "off", "closing" or "pushes" (ClosingCheckMode)
  std::string closing_check = "off";
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

/// Adds the knobs of a build (--sampler, --valid, --trials, --seed, --threads, --friction,
/// --cone-edges, --grasp, --standoff, --allow-size, --keep-invalid, --no-cluster, --timestamp,
/// -q, --progress) to a subcommand.
void addBuildKnobs(CLI::App& cmd, BuildArgs& args);

/// The BuildOptions of the knobs (not validated; no extra_params_json).
BuildOptions knobOptions(const BuildArgs& args);

/// "hh:mm:ss" of a duration in seconds, "--:--:--" when unknown.
std::string clockString(double seconds);

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

/// Prints the summary of a written map on stdout (unless quiet) and the budget warning on
/// stderr. @param how one line after "threads", e.g. "2 (not stored: ...)".
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

/// One line for a finished job: "[done/total, ETA hh:mm:ss] object x hand: status, V valid in
/// T trials -> file" (or the error). @param elapsed_seconds since the first job started.
std::string datasetProgressLine(std::size_t done, std::size_t total, double elapsed_seconds,
                                const DatasetEntry& entry);

}  // namespace taskmap::cli
