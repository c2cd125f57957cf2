#pragma once
/// @file dataset.hpp
/// A data set of task maps: one map per (object, hand), shared by `taskmap dataset` (jobs one
/// after another, each on all threads) and `taskmap-mpi dataset` (jobs handed out to ranks).
/// Each job's seed derives from (--seed, SHA-256 of the mesh file, SHA-256 of the hand URDF),
/// so no result depends on the list order or the number of ranks. DIR/manifest.json records
/// every job (sorted by object and hand) and is rewritten atomically as jobs finish; a re-run
/// skips maps whose file hash and build parameters match their entry.

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "build_command.hpp"

namespace taskmap::cli {

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

/// One map to build.
struct DatasetJob {
  std::string object;         ///< as written in the list
  std::string object_path;    ///< resolved path
  std::string hand;           ///< as given in --hands
  std::string hand_urdf;      ///< resolved URDF
  std::string file;           ///< map file name in the output directory
  std::uintmax_t mesh_bytes;  ///< size of the mesh file (0 if unreadable); largest runs first
  double scale = 1.0;         ///< the list's scale for the mesh, else --scale
};

/// The jobs of a data set, largest mesh first (ties by object, then hand).
struct DatasetPlan {
  DatasetArgs args;
  std::string dir;               ///< output directory
  std::vector<DatasetJob> jobs;  ///< in hand-out order
};

/// Reads the list, resolves the hands, creates the output directory. Throws Error naming the
/// file and line, the option, or two objects that would write the same map file.
DatasetPlan planDataset(const DatasetArgs& args);

/// Runs one job: loads, builds and writes its map (atomically). Never throws for a bad mesh or
/// hand: the entry's status is then "failed" with the error. Entry fields: object, scale, hand,
/// seed, status (complete, trial_budget_exhausted, failed), trials, valid, file, file_sha256,
/// build_sha256, error.
nlohmann::json runDatasetJob(const DatasetPlan& plan, const DatasetJob& job);

/// DIR/manifest.json.
class DatasetManifest {
 public:
  /// Reads an existing manifest (a malformed one is ignored, note() says so); every job of the
  /// plan gets its entry from it or status "pending".
  explicit DatasetManifest(const DatasetPlan& plan);
  /// True when job i's earlier entry says finished and its map file and build parameters
  /// still match (the file's SHA-256 is recomputed).
  bool finishedEarlier(std::size_t i) const;
  /// Sets job i's entry.
  void set(std::size_t i, nlohmann::json entry);
  /// The jobs to build (not finishedEarlier), in plan order; their earlier entries become
  /// "pending" and the manifest is written, so that it never pairs this run's parameters with
  /// a map of an earlier run's (another --valid, say) while the jobs run.
  std::vector<std::size_t> startRun();
  /// Writes the manifest atomically. Throws Error naming the file.
  void write() const;
  /// Jobs with status "failed".
  std::size_t failed() const;
  /// What reading found ("" if nothing to say).
  const std::string& note() const { return note_; }

 private:
  const DatasetPlan& plan_;
  std::vector<nlohmann::json> entries_;  // by job index
  std::string note_;
};

/// The lock of a data-set directory (DIR/.taskmap-dataset.lock) for one run; a second run on the
/// same directory refuses with the holder's PID (run_lock.hpp).
std::string datasetLockPath(const DatasetPlan& plan);

/// One line for a finished job: "[done/total, ETA hh:mm:ss] object x hand: status, V valid in
/// T trials -> file" (or the error). @param elapsed_seconds since the first job started.
std::string datasetProgressLine(std::size_t done, std::size_t total, double elapsed_seconds,
                                const nlohmann::json& entry);

}  // namespace taskmap::cli
