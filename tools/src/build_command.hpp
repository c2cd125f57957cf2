#pragma once
/// @file build_command.hpp
/// What `taskmap build` and `taskmap-mpi build` share: the options (one definition, so both
/// accept the same command line), turning them into BuildOptions, the progress printer and
/// the summary.

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

#include "mesh_options.hpp"
#include "taskmap/builder/map_builder.hpp"

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
  bool force = false;         ///< replace an existing output that is not a task map
};

/// With --validate: labels the built map's grasps with the physics hold test (validate stage,
/// docs/VALIDATION.md) on args.threads threads and prints one line about it (unless quiet).
/// `label` starts the line, e.g. "taskmap build".
void validateIfAsked(const BuildArgs& args, const HandModel& hand, TaskMapData* map,
                     const std::string& label);

/// How to load the object: --scale and the repair options.
MeshLoadOptions meshLoadOptions(const BuildArgs& args);

/// Refuses --standoff when the grasp mode in force (--grasp, else the hand's) is not fingertip.
void checkGraspOptions(const BuildArgs& args, const BuildOptions& options, const HandModel& hand,
                       const std::string& hand_path);

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

/// A --hand argument as a URDF path: the path itself if it exists, else the bundled hand of
/// that name. Throws Error listing the bundled hands.
std::string resolveHandUrdf(const std::string& hand);

/// The sidecar a hand URDF is read with: <dir>/<stem>.hand.json.
std::string handSidecarPath(const std::string& urdf);

/// A build ready to run: validated options and the resolved hand URDF.
struct BuildPlan {
  BuildOptions options;   ///< validated
  std::string hand_urdf;  ///< --hand as a URDF path (bundled hand names resolved)
};

/// Validates the arguments (output directory exists, ranges) and resolves the hand. Throws
/// Error naming the option or file.
BuildPlan planBuild(const BuildArgs& args);

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

}  // namespace taskmap::cli
