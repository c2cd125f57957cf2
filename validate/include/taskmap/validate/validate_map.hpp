#pragma once
/// @file validate_map.hpp
/// Labels a map's grasps with the physics hold test (hold_test.hpp) on all cores: per grasp,
/// whether it holds, the object's largest displacement and rotation, and the first push under
/// which it failed (MapValidation, mapstore/SCHEMA.md). Same labels for any thread count.

#include <array>
#include <atomic>
#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "taskmap/core/run_control.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/mapstore/task_map_data.hpp"
#include "taskmap/validate/hold_test.hpp"
#include "taskmap/validate/robust_hold.hpp"

namespace taskmap {

/// Which grasps to test and how.
struct ValidateOptions {
  HoldTestOptions hold;    ///< the protocol's numbers
  int threads = 0;         ///< worker threads, 0: all cores
  std::size_t grasps = 0;  ///< test the first this many grasps (0: all); the rest stay untested
  /// Also the robust label (`validate --robust`, robust_hold.hpp): every variant of every grasp
  /// (robust_variants.all_variants is set), the share held and the margin stored per grasp.
  bool robust = false;
  /// The variants and thresholds of the robust label; its `hold` is replaced by `hold` above.
  RobustHoldOptions robust_variants;
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
};

/// Progress of a validation: grasps done of the total to test.
struct ValidateProgress {
  std::size_t done = 0;     ///< grasps tested so far
  std::size_t total = 0;    ///< grasps to test
  std::size_t holding = 0;  ///< of those done, how many hold
};

/// Progress callback, interval and stop flag of a validation (run_control.hpp).
using ValidateControl = RunControl<ValidateProgress>;

/// What a validation found.
struct ValidationSummary {
  /// How the validation ended.
  enum class Status { kCompleted, kInterrupted };
  Status status = Status::kCompleted;  ///< kInterrupted: stop raised; no labels were written
  std::size_t tested = 0;              ///< grasps tested
  std::size_t holding = 0;             ///< grasps that hold
  /// Force-closure grasps tested and how many of them hold (for a map imported from ACRONYM:
  /// the grasps its own simulation labelled successful).
  std::size_t fc_tested = 0, fc_holding = 0;
  /// With ValidateOptions::robust: force-closure grasps that hold robustly.
  std::size_t fc_robust = 0;
  /// The jaws were closed from open (HoldTestOptions::close_from_open; mapClosesFromOpen).
  bool close_from_open = false;
  std::map<std::string, std::size_t> statuses;       ///< grasps per holdStatusName()
  std::array<std::size_t, 6> failed_by_direction{};  ///< slipped grasps per push direction
  /// With ValidateOptions::robust: grasps that hold robustly.
  std::size_t robust = 0;
  /// With ValidateOptions::robust: per variant (test order), its name and the grasps whose
  /// nominal variant held (within the margin) where it failed: what each variant adds.
  std::vector<std::pair<std::string, std::size_t>> variant_failures;
  HoldModelInfo model;        ///< the simulation model
  double cpu_seconds = 0.0;   ///< CPU time of the process during the tests, s
  double wall_seconds = 0.0;  ///< wall-clock time of the tests, s
  long long steps = 0;        ///< simulation steps taken
  std::string message;        ///< one line for people
};

/// True when the map's grasps are poses whose joint values are where parallel jaws touch when
/// they close from open at that pose (sampling params_json "hold_closing": "from_open", written
/// by `taskmap import --acronym ... --hand`, docs/ACRONYM.md): their hold test closes the jaws
/// from open (HoldTestOptions::close_from_open).
bool mapClosesFromOpen(const TaskMapData& map);

/// Throws Error saying what to do when the map's grasps have no joint values to test (a map
/// imported from ACRONYM without a hand: import it again with --hand).
void checkMapJoints(const TaskMapData& map);

/// Tests the grasps of `map` (its object mesh, hand joints and palm poses) with `hand`, which
/// must be the map's hand (same actuated joints; throws Error naming both otherwise, or when
/// the map has no joint values, checkMapJoints), and stores the labels in map->validation
/// (replacing earlier ones), with the protocol's parameters (close_from_open set when
/// mapClosesFromOpen). control.progress is called on the calling thread about every
/// control.interval_seconds; when control.stop becomes true the workers finish their current
/// grasp, the map is left unchanged and the status is kInterrupted. An exception from the
/// callback stops the workers and leaves validateMap with the map unchanged.
ValidationSummary validateMap(TaskMapData* map, const HandModel& hand,
                              const ValidateOptions& options, const ValidateControl& control = {});

/// The summary as a JSON object, the one form the CLI (`validate --json`) and Python
/// (`taskmap.validate`) report: tested, holding, hold_rate, force_closure_tested,
/// force_closure_holding, statuses, slipped_by_direction (by push direction name),
/// object_pieces, object_volume_error, object_note, close_from_open, cpu_seconds, wall_seconds
/// (s), grasps_per_cpu_second, steps; with robust labels also robust, robust_rate,
/// force_closure_robust and
/// variant_failures (by variant name: for "nominal" the protocol holds outside the margin, for
/// the others the failures where the nominal variant held within it).
std::string summaryJson(const ValidationSummary& summary);

/// The summary as `taskmap validate` prints it: the hold rate (all grasps and force-closure
/// grasps), outcomes, slips per push direction, the object's convex pieces and volume error
/// (with a warning beyond 10 %), grasps per CPU-second and where the labels were written
/// (`written_to`); lines end in '\n'.
std::string summaryText(const ValidationSummary& summary, const std::string& written_to);

/// Keeps only the grasps of `map` that hold (labels of validateMap; grasps not tested are
/// dropped too), with their contacts and labels, and re-clusters them with `clustering` (its
/// rotation_scale replaced by the map's rho) when the map was clustered and at least two remain;
/// fewer leave the map unclustered. Returns the grasps kept. Throws Error when the map has no
/// labels (validate it first).
std::size_t keepHoldingGrasps(TaskMapData* map, const ClusteringOptions& clustering = {});

/// The labels of grasps `keep` (indices into `labels`' grasps, in the order given): every
/// per-grasp vector of `labels` subset, the JSON attributes kept.
MapValidation subsetLabels(const MapValidation& labels, const std::vector<std::size_t>& keep);

/// The map labels of `results` (results[i] is grasp i's, null when it was not tested), the
/// protocol's label from each nominal; robust labels too when `robust` is given with the
/// `variants` the results ran (RobustHoldTester::options(), variants()).
MapValidation holdLabels(const std::vector<const RobustHoldResult*>& results,
                         const HoldTestOptions& protocol, const RobustHoldOptions* robust = nullptr,
                         const std::vector<HoldVariant>& variants = {});

/// The protocol's parameters as a JSON object (what /validation params_json stores).
std::string holdParamsJson(const HoldTestOptions& options);

/// Adds `hand_dynamics` (handDynamicsJson: which of an MJCF hand's own dynamics the hold test
/// used) to `validation`'s params; nothing when it is empty (a URDF hand).
void recordHandDynamics(const std::string& hand_dynamics, MapValidation* validation);

/// The map's object as a solid (its stored mesh, already closed and in metres).
ObjectModel mapObjectModel(const TaskMapData& map);

/// The hold test of grasp `grasp` of `map` with the object's path (HoldTester::trace): why a
/// grasp holds or fails (close_from_open set when mapClosesFromOpen). `hand` must be the map's
/// hand. Throws Error when `grasp` is not a grasp
/// index of the map or the hand does not match.
HoldTrace traceGrasp(const TaskMapData& map, const HandModel& hand, std::size_t grasp,
                     const HoldTestOptions& options = {});

/// A trace as a JSON object, the form `taskmap validate --trace --json` and Python
/// (`taskmap.trace_hold`) give: status, holds, max_translation (m), max_rotation (rad),
/// failed_direction (a push name or null), initial_penetration (m), approach (the hand's approach
/// axis in the palm frame) and samples, each with phase, step, translation, rotation, offset
/// (palm frame, m), along_approach (offset . approach, m) and contacts (link name: newtons).
std::string traceJson(const HoldTrace& trace, const HandModel& hand);

/// A trace as `taskmap validate --trace` prints it: one line per sample (phase, step, the
/// object's displacement, its part along the approach, rotation, links pressing it with their
/// forces), then the verdict; lines end in '\n'.
std::string traceText(const HoldTrace& trace, const HandModel& hand);

}  // namespace taskmap
