#pragma once
/// @file trial_block.hpp
/// The two halves of a build that other executables (taskmap-mpi) share with buildMap: running
/// the trials [first, last) on threads, and assembling a map from the blocks of trials in index
/// order. Trial i depends only on (seed, i), so any split of [0, max_trials) into blocks run
/// anywhere gives the same outcomes; assembleMap applies the stop rule of buildMap (the first
/// valid_target force-closure grasps in trial order) and so gives the map buildMap gives.

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/builder/map_builder.hpp"
#include "taskmap/core/contact.hpp"
#include "taskmap/core/pose.hpp"

namespace taskmap {

/// The part of a simulated grasp a map stores.
struct TrialGrasp {
  Pose pose;                      ///< final palm pose in the object frame (metres)
  Eigen::VectorXd joints;         ///< final joint values, HandModel::jointNames() order (rad or m)
  std::vector<Contact> contacts;  ///< pressed contacts, object frame
  /// The build's physics hold test of the grasp (BuildOptions::hold_test), when it ran.
  std::optional<RobustHoldResult> hold;
};

/// One trial's outcome; the grasp only when a map may store it (status ok and force closure,
/// or status ok and BuildOptions::keep_invalid).
struct TrialOutcome {
  GraspStatus status = GraspStatus::kNoFingerContact;  ///< simulator outcome
  bool force_closure = false;                          ///< status ok and force closure
  bool unbalanced = false;  ///< status ok, refused by the hold filter (no quality computed)
  /// Status ok, refused by the squeeze-force test (BuildOptions::min_squeeze_force; no quality)
  bool weak_squeeze = false;
  /// Force closure by its contacts, refused by the closing check (the closing pushed the free
  /// object away); force_closure is then false and the trial does not count as valid.
  bool pushed = false;
  /// Force closure by its contacts, refused by the build's physics hold test
  /// (BuildOptions::hold_test); force_closure is then false.
  bool not_holding = false;
  double epsilon = 0.0;               ///< Ferrari-Canny epsilon (status ok)
  double volume = 0.0;                ///< GWS volume (status ok)
  std::unique_ptr<TrialGrasp> grasp;  ///< stored grasp, if any (a pointer: most trials have none)
};

/// The outcomes of the consecutive trials [first, first + trials.size()).
struct TrialBlock {
  std::uint64_t first = 0;                                     ///< index of trials[0]
  std::vector<TrialOutcome> trials;                            ///< in index order
  std::uint64_t valid() const;                                 ///< number of force-closure trials
  std::uint64_t end() const { return first + trials.size(); }  ///< one past the last index
};

/// Serialises a block to bytes (host byte order; for messages between ranks of one job and
/// for checkpoints read back by the same build of taskmap).
std::string encodeTrialBlock(const TrialBlock& block);

/// Inverse of encodeTrialBlock. Checks every length against the bytes and the joint count
/// against `joints`; throws Error("<what>: ...") on malformed input, never reads past the end.
TrialBlock decodeTrialBlock(const std::string& bytes, std::size_t joints, const std::string& what);

/// Runs blocks of trials of one (object, hand, options) on threads. Construction builds the
/// sampler and the simulator once (BuildTiming::setup_seconds).
class TrialRunner {
 public:
  /// Throws Error on invalid options. object and hand must outlive the runner. An unset sampler
  /// kind is chosen as buildMap chooses it (chooseSampler).
  TrialRunner(const ObjectModel& object, const HandModel& hand, const BuildOptions& options);
  ~TrialRunner();
  TrialRunner(const TrialRunner&) = delete;
  TrialRunner& operator=(const TrialRunner&) = delete;

  /// Runs every trial of [first, last) (last <= max_trials) on options.threads threads in
  /// sub-blocks of options.block_size. Returns false (and an unspecified block) when *stop
  /// rose before the end; rethrows a worker's exception after every thread joined.
  bool run(std::uint64_t first, std::uint64_t last, TrialBlock* block,
           const std::atomic<bool>* stop = nullptr);

  /// Stage times summed over every run() so far, setup and the sampler's pilot included.
  const BuildTiming& timing() const;

  /// The sampler the trials run and how it was chosen.
  const SamplerChoice& samplerChoice() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Builds the map from blocks that cover [0, n) in index order without gaps (n may be short
/// of max_trials when the stop rule was met earlier): takes the trials up to the valid_target-th
/// force-closure one, fills the grasps, clusters (unless interrupted) and sets the status.
/// `timing` is copied into the result (clustering_seconds filled in). Throws Error when the
/// blocks are not consecutive from 0.
BuildResult assembleMap(const ObjectModel& object, const HandModel& hand,
                        const BuildOptions& options, const std::vector<TrialBlock>& blocks,
                        bool interrupted, const BuildTiming& timing);

}  // namespace taskmap
