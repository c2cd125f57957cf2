#pragma once
/// @file map_builder.hpp
/// The map-building pipeline (paper 1.6.1): sample -> simulate -> score -> cluster, on all
/// cores, deterministic for a seed whatever the thread count.
///
/// Determinism: trial i draws from Rng(seed, i) alone. Trials are processed in fixed blocks of
/// block_size indices claimed by worker threads; results are stored by index. The map holds
/// the first valid_target force-closure grasps in trial-index order, `trials` counts the
/// trials up to and including the one that gave the last of them, and work past it is
/// discarded. So 1, 2 or 8 threads give identical datasets.

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "taskmap/builder/hold_filter.hpp"
#include "taskmap/clustering/clustering.hpp"
#include "taskmap/core/run_control.hpp"
#include "taskmap/grasp_sim/closing_check.hpp"
#include "taskmap/grasp_sim/grasp_simulator.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/mapstore/task_map_data.hpp"
#include "taskmap/meshes/object_model.hpp"
#include "taskmap/quality/grasp_quality.hpp"
#include "taskmap/sampler/sampler.hpp"
#include "taskmap/validate/robust_hold.hpp"

namespace taskmap {

/// Options of a build. The sampler's approach axis is taken from the hand.
/// Largest trial budget and valid target validate() accepts (10^15: three thousand CPU-years at
/// 100 us a trial); larger numbers are typing errors or wrapped negatives.
constexpr std::uint64_t kMaxBuildCount = 1000000000000000ULL;

/// The quality options of a build by default: QualityOptions' defaults with volume
/// VolumeMode::kNever (force closure and epsilon exactly as before; /grasps/volume 0 and
/// params "volume": "never"; docs/PERFORMANCE.md, "The quality stage").
QualityOptions buildQualityDefaults();

/// The physics hold test a build runs on each force-closure grasp (the validate stage in
/// MuJoCo, docs/VALIDATION.md): a grasp is stored, and counts towards valid_target, only when it
/// holds; its labels are stored with it (/grasps/hold, and for kRobust /grasps/robust ...).
enum class BuildHoldTest {
  kOff,      ///< none: the map stores force-closure grasps (the paper's map)
  kNominal,  ///< DexGraspBench's protocol at the grasp's pose
  kRobust,   ///< the robust label (robust_hold.hpp): every variant, within the margin
};

/// "off", "nominal", "robust".
const char* toString(BuildHoldTest test);

/// The BuildHoldTest named `name` ("off", "nominal", "robust"); throws Error naming the choices.
BuildHoldTest buildHoldTestFromString(const std::string& name);

/// Which simulated grasps a build stores.
enum class StoredGrasps {
  kForceClosure,  ///< the force-closure grasps (the paper's map; valid_target counts them)
  kAllCompleted,  ///< every completed trial (status ok), force closure or not (`--keep-invalid`)
};

struct BuildOptions {
  SamplerOptions sampler;      ///< sampler kind and standoff (approach_axis is overridden)
  GraspSimOptions simulation;  ///< simulator knobs
  /// Friction, cone edges, contact model; by default a build computes force closure and
  /// epsilon only (buildQualityDefaults: the wrench-space volume, which needs the whole 6-D hull,
  /// took 90-99 % of the quality stage on fine meshes and nothing downstream reads it;
  /// VolumeMode::kForceClosure stores it as before).
  QualityOptions quality = buildQualityDefaults();
  /// The hold filter run before quality (off by default): grasps whose squeeze cannot hold the
  /// free object are not stored (outcome `unbalanced`); hold_filter.hpp, docs/METHOD.md §4b.
  HoldFilterOptions hold_filter;
  /// N, >= 0: a simulated grasp whose squeeze presses no contact with at least this force
  /// (graspSqueezeForce: the hold test's drive) is not stored (outcome `weak_squeeze`): the
  /// fingers stopped so close to their preshape that the hold test's squeeze cannot press.
  /// 0: off (maps built before 2026-11-27, whose params lack the key). docs/METHOD.md §4e.
  double min_squeeze_force = kDefaultMinSqueezeForce;
  /// The closing check run on force-closure grasps (off by default): grasps whose closing, with
  /// the object free to move, pushes it away are not stored (outcome `pushed`);
  /// grasp_sim/closing_check.hpp, docs/METHOD.md §4d.
  ClosingCheckOptions closing_check;
  /// The physics hold test of each force-closure grasp: off by default here; the file builds
  /// (`taskmap build`, `dataset`, `taskmap-mpi`, Python `taskmap.build`) default to kRobust
  /// (build_knobs.hpp). With it on, valid_target counts grasps that hold.
  BuildHoldTest hold_test = BuildHoldTest::kOff;
  /// The protocol, variants and margin of hold_test (kNominal: the protocol alone). A build
  /// stops at a grasp's first failing variant (all_variants and protocol_label are ignored).
  RobustHoldOptions hold_test_options;
  ClusteringOptions clustering;       ///< rotation_scale is overridden by the hand's
  std::uint64_t seed = 1;             ///< run seed
  std::uint64_t valid_target = 1000;  ///< stop after this many force-closure grasps (>= 1)
  std::uint64_t max_trials = 200000;  ///< trial budget (>= 1, <= kMaxBuildCount)
  int threads = 0;                    ///< worker threads; 0 = all cores
  /// Which grasps are stored (params_json "keep_invalid": true for kAllCompleted).
  StoredGrasps stored = StoredGrasps::kForceClosure;
  bool cluster = true;  ///< cluster the stored grasps (needs >= 2 of them)
  /// Refuse an object whose size is implausible for the hand (size_check.hpp) before any
  /// trial; false (`--allow-size`) builds it anyway. Not stored: it does not change a map.
  bool check_size = true;
  /// Trials per work block (>= 1): a worker simulates a block, then scores it; with the hold
  /// test at most 4 (a thread's block past the valid target is work thrown away, and a tested
  /// grasp costs the time of thousands of trials). Does not change results.
  std::uint64_t block_size = 64;
  /// Extra entries for /sampling params_json (a JSON object, e.g. file paths), merged in.
  std::string extra_params_json = "{}";
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
};

/// How a build ended.
enum class BuildStatus {
  kComplete,              ///< valid_target force-closure grasps found
  kTrialBudgetExhausted,  ///< max_trials spent with fewer found; the map holds what was found
  kInterrupted,           ///< the stop flag was raised; the map holds a partial prefix
  /// max_trials spent and no grasp stored: the message names the dominant trial outcome and
  /// what to check (units, approach axis, preshape); the map holds no grasp and must not be
  /// written as a result.
  kNoGrasps,
};

/// "complete", "trial_budget_exhausted", "interrupted", "no_grasps".
const char* toString(BuildStatus status);

/// Where the time went. Stage times are CPU seconds of the worker threads, summed over threads,
/// so their shares of their sum are the shares of the work even on a loaded machine.
struct BuildTiming {
  double wall_seconds = 0.0;        ///< whole buildMap call
  double sampling_seconds = 0.0;    ///< Sampler::sample, CPU seconds summed over threads
  double simulation_seconds = 0.0;  ///< GraspSimulator::simulate, CPU seconds summed over threads
  /// evaluateGrasp and (when on) the hold filter and the closing check, CPU seconds summed over
  /// threads
  double quality_seconds = 0.0;
  /// The closing check's part of quality_seconds (0 when it is off)
  double closing_check_seconds = 0.0;
  std::uint64_t closing_checks = 0;  ///< force-closure grasps the closing check simulated
  /// The physics hold test (BuildOptions::hold_test), CPU seconds summed over threads; not part
  /// of quality_seconds
  double hold_test_seconds = 0.0;
  std::uint64_t hold_tests = 0;        ///< force-closure grasps the hold test simulated
  long long hold_test_steps = 0;       ///< MuJoCo steps of those tests
  double clustering_seconds = 0.0;     ///< clusterGrasps, wall seconds (one thread)
  double setup_seconds = 0.0;          ///< building sampler and simulator before the trials, wall
  std::uint64_t trials_simulated = 0;  ///< trials actually run, including discarded ones
  /// Simulated grasps (status ok) whose quality was computed: none past the trial that
  /// completes the valid target once every earlier block has finished
  std::uint64_t grasps_scored = 0;
};

/// Progress report, delivered on the calling thread about every progress_interval.
struct BuildProgress {
  std::uint64_t trials_done = 0;   ///< trials finished so far (any order)
  std::uint64_t valid_found = 0;   ///< force-closure grasps among them
  std::uint64_t valid_target = 0;  ///< BuildOptions::valid_target
  std::uint64_t max_trials = 0;    ///< BuildOptions::max_trials
  double elapsed_seconds = 0.0;    ///< since the trials started
  std::uint64_t blocks_done = 0;   ///< work blocks finished (0 when not counted)
  std::uint64_t blocks_total = 0;  ///< work blocks of the trial budget (0 when not counted)
};

/// Receives progress reports (on the thread that called buildMap).
using ProgressCallback = std::function<void(const BuildProgress&)>;

/// Progress callback, interval and stop flag of a build (run_control.hpp).
using BuildControl = RunControl<BuildProgress>;

/// How a build's sampler was chosen (chooseSampler, sampler_choice.hpp).
struct SamplerChoice {
  SamplerKind kind = SamplerKind::kMixed;  ///< the sampler the build runs
  /// The hand's default is palm_enclose, whose probe found that it cannot place the hand on
  /// this object: the build runs mixed (sampler_choice.hpp)
  bool enclose_refused = false;
};

/// Result of a build.
struct BuildResult {
  BuildStatus status = BuildStatus::kComplete;
  std::string message;           ///< one line for the user
  TaskMapData map;               ///< ready for writeMap (generator, created_utc filled in)
  BuildTiming timing;            ///< wall and CPU seconds of the stages
  SamplerChoice sampler_choice;  ///< the sampler the build ran and how it was chosen
};

/// Runs the pipeline. Throws Error on invalid options and, unless options.check_size is false,
/// on an object whose size is implausible for the hand (size_check.hpp: over kMaxReachRatio
/// times its reach, or thinner than its thinnest finger link), naming the scale that fixes a
/// file in other units. control.progress gets a report about every control.interval_seconds;
/// returns kInterrupted soon after *control.stop becomes true (workers finish their current
/// trial); an exception from the callback leaves buildMap after the workers are joined.
BuildResult buildMap(const ObjectModel& object, const HandModel& hand, const BuildOptions& options,
                     const BuildControl& control = {});

/// The worker threads BuildOptions::threads means: itself when positive, else the cores this
/// process may run on (its CPU affinity mask, so taskset or `mpirun --bind-to` are respected).
int buildThreadCount(int threads);

/// The map's /object record of a loaded object: name, source SHA-256, scale, volume, centre of
/// mass and torque scale, and its mesh (metres, object frame). Used by builds and imports.
MapObject mapObjectOf(const ObjectModel& object);

/// Current UTC time as ISO 8601 ("2026-11-21T12:00:00Z").
std::string utcNow();

}  // namespace taskmap
