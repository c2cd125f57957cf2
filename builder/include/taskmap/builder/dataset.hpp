#pragma once
/// @file dataset.hpp
/// A data set of task maps: one map per (object, hand), built by `taskmap dataset` and Python's
/// `taskmap.dataset` (jobs one after another, each on all threads, DatasetRun) and by
/// `taskmap-mpi dataset` (jobs handed out to ranks: planDataset, runDatasetJob,
/// DatasetManifest). Each job's seed derives from (seed, SHA-256 of the mesh file, SHA-256 of the
/// hand URDF), so no result depends on the list order or the number of ranks. DIR/manifest.json
/// records every job (sorted by object and hand) and is rewritten atomically as jobs finish; a
/// re-run skips maps whose file hash and build parameters match their entry.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "taskmap/builder/map_file_build.hpp"

namespace taskmap {

/// The options of a data set, named as `taskmap dataset`'s.
struct DatasetOptions {
  /// text file: one mesh path a line (relative to the file), optionally followed by the mesh's
  /// scale ("bunny.ply 0.01"); # comments
  std::string objects;
  std::string hands;   ///< comma-separated hand URDFs or bundled hand names
  std::string output;  ///< directory for the maps and manifest.json (created if missing)
  double scale = 1.0;  ///< mesh scale (file units -> m) of every object the list gives none
  /// valid, trials, seed (the data set's: each job's derives from it), threads, friction, ...
  /// as for a build; extra_params_json is set per job
  BuildOptions build;
  bool timestamp = false;                            ///< store the current time as created_utc
  HoldValidation validation = HoldValidation::kOff;  ///< label each map's grasps before writing
  bool force = false;  ///< replace map files (and manifest.json) that are not taskmap files
};

/// One map to build.
struct DatasetJob {
  std::string object;         ///< as written in the list
  std::string object_path;    ///< resolved path
  std::string hand;           ///< as given in hands
  std::string hand_urdf;      ///< resolved URDF
  std::string file;           ///< map file name in the output directory
  std::uintmax_t mesh_bytes;  ///< size of the mesh file (0 if unreadable); largest runs first
  double scale = 1.0;         ///< the list's scale for the mesh, else DatasetOptions::scale
};

/// The jobs of a data set, largest mesh first (ties by object, then hand).
struct DatasetPlan {
  DatasetOptions options;        ///< as given
  std::string dir;               ///< output directory
  std::vector<DatasetJob> jobs;  ///< in hand-out order
};

/// Reads the list, resolves the hands, creates the output directory. Throws Error naming the
/// file and line, the option, or two objects that would write the same map file.
DatasetPlan planDataset(const DatasetOptions& options);

/// Where a job stands in the manifest.
enum class DatasetJobStatus {
  kPending,               ///< not built (yet) in this run
  kComplete,              ///< map written, valid target reached
  kTrialBudgetExhausted,  ///< map written with fewer grasps than the valid target
  kFailed,                ///< no map: error says why (a bad mesh or hand, no grasp found)
};

/// "pending", "complete", "trial_budget_exhausted", "failed".
const char* toString(DatasetJobStatus status);

/// A job's entry in manifest.json (absent fields are left out of the file).
struct DatasetEntry {
  std::string object;                                    ///< as written in the list
  double scale = 1.0;                                    ///< mesh scale used
  std::string hand;                                      ///< as given
  std::string file;                                      ///< map file name in the directory
  DatasetJobStatus status = DatasetJobStatus::kPending;  ///< outcome
  std::optional<std::uint64_t> seed;                     ///< the job's derived seed
  std::optional<std::uint64_t> trials;                   ///< trials the map counts
  std::optional<std::uint64_t> valid;                    ///< force-closure grasps stored
  std::optional<std::string> file_sha256;                ///< SHA-256 of the written map file
  std::optional<std::string> build_sha256;  ///< SHA-256 of the build's identity (parameters)
  std::optional<std::string> error;         ///< "" when built; the error when failed
  /// What the hold test found (with HoldValidation); not stored in the manifest.
  std::optional<HoldLabels> validation;
};

/// The entry as a JSON object (the manifest's form; also what taskmap-mpi ranks send).
std::string datasetEntryJson(const DatasetEntry& entry);

/// An entry from datasetEntryJson. Throws Error when it is not one.
DatasetEntry datasetEntryFromJson(const std::string& json);

/// Runs one job: loads, builds and writes its map (atomically). Never throws for a bad mesh or
/// hand: the entry's status is then kFailed with the error. With control.stop raised during
/// the build the entry stays kPending and nothing is written.
DatasetEntry runDatasetJob(const DatasetPlan& plan, const DatasetJob& job,
                           const BuildControl& control = {});

/// DIR/manifest.json.
class DatasetManifest {
 public:
  /// Reads an existing manifest (a malformed one is ignored, note() says so); every job of the
  /// plan gets its entry from it or status kPending.
  explicit DatasetManifest(const DatasetPlan& plan);
  /// True when job i's earlier entry says finished and its map file and build parameters
  /// still match (the file's SHA-256 is recomputed).
  bool finishedEarlier(std::size_t i) const;
  /// Sets job i's entry.
  void set(std::size_t i, DatasetEntry entry);
  /// The jobs to build (not finishedEarlier), in plan order; their earlier entries become
  /// kPending and the manifest is written, so that it never pairs this run's parameters with
  /// a map of an earlier run's (another valid, say) while the jobs run.
  std::vector<std::size_t> startRun();
  /// Writes the manifest atomically. Throws Error naming the file.
  void write() const;
  /// Jobs with status kFailed.
  std::size_t failed() const;
  /// What reading found ("" if nothing to say).
  const std::string& note() const { return note_; }

 private:
  const DatasetPlan& plan_;
  std::vector<DatasetEntry> entries_;  // by job index
  std::string note_;
};

/// The lock of a data-set directory (DIR/.taskmap-dataset.lock) for one run; a second run on the
/// same directory refuses with the holder's PID (run_lock.hpp).
std::string datasetLockPath(const DatasetPlan& plan);

/// A report after each finished job of DatasetRun::run.
struct DatasetProgress {
  std::size_t done = 0;          ///< jobs finished in this run
  std::size_t total = 0;         ///< jobs to build in this run (skipped ones not counted)
  double elapsed_seconds = 0.0;  ///< since the first job started
  DatasetEntry entry;            ///< the job just finished
};

/// Result of a data-set run.
struct DatasetResult {
  std::size_t jobs = 0;      ///< jobs of the data set
  std::size_t skipped = 0;   ///< finished earlier (map and parameters unchanged)
  std::size_t failed = 0;    ///< jobs with status kFailed (their errors are in the manifest)
  bool interrupted = false;  ///< control.stop was raised: the remaining jobs stay pending
  std::string dir;           ///< the output directory
};

/// A data set run in two steps (the CLI prints the manifest's note before the jobs): plan, lock
/// and manifest on construction, the jobs on run().
class DatasetRun {
 public:
  /// planDataset, the directory's lock, the manifest. Throws Error naming the file or option.
  explicit DatasetRun(const DatasetOptions& options);
  ~DatasetRun();
  DatasetRun(const DatasetRun&) = delete;
  DatasetRun& operator=(const DatasetRun&) = delete;

  const DatasetPlan& plan() const;  ///< the jobs
  const std::string& note() const;  ///< what reading the earlier manifest found, or ""

  /// Builds the jobs that did not finish earlier, largest first, each on all threads, writing
  /// the manifest after each; control.progress after each job (interval_seconds unused);
  /// control.stop ends the run after the current build stops (its map not written, its entry
  /// pending). `build` watches each job's trials (progress and interval; its stop is replaced
  /// by control.stop).
  DatasetResult run(const RunControl<DatasetProgress>& control = {},
                    const BuildControl& build = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace taskmap
