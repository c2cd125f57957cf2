#pragma once
/// @file distributed_build.hpp
/// A map build spread over processes (`taskmap-mpi build`), without the transport: every
/// process holds a BuildRank that runs numbered blocks of trials and returns them as bytes; one
/// coordinator (DistributedBuild) hands the blocks out, keeps the finished ones in a checkpoint
/// beside the output (a stopped run resumes from it), applies buildMap's stop rule and writes
/// the map: the same bytes as `taskmap build` for any number of processes and block size.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "taskmap/builder/block_ledger.hpp"
#include "taskmap/builder/build_checkpoint.hpp"
#include "taskmap/builder/map_file_build.hpp"
#include "taskmap/builder/trial_block.hpp"
#include "taskmap/core/run_lock.hpp"

namespace taskmap {

/// One process's part of a distributed build: the plan, the object, the hand and the trial
/// runner (options.build.threads threads).
class BuildRank {
 public:
  /// planFileBuild(options), the output's run lock when `coordinator` (a second build of the
  /// same output refuses with the holder's PID), the object (options.mesh) and the hand, and
  /// checkGraspOptions. Throws Error naming the file or option.
  BuildRank(const FileBuildOptions& options, bool coordinator);

  /// Runs block b (trials [b * block_trials, min(.., max_trials))) and returns its
  /// encodeTrialBlock bytes.
  std::string runBlock(std::uint64_t b, std::uint64_t block_trials) const;

  const FileBuildOptions& request() const { return request_; }  ///< as given
  const FileBuildPlan& plan() const { return plan_; }           ///< validated options, hand URDF
  const ObjectModel& object() const { return *object_; }        ///< the loaded object
  const HandModel& hand() const { return *hand_; }              ///< the loaded hand
  /// Stage CPU seconds and trials simulated by this process so far (setup and the sampler's
  /// pilot included).
  const BuildTiming& timing() const { return runner_->timing(); }
  /// The sampler the trials run and how it was chosen (TrialRunner::samplerChoice).
  const SamplerChoice& samplerChoice() const { return runner_->samplerChoice(); }

 private:
  FileBuildOptions request_;
  FileBuildPlan plan_;
  std::optional<RunLock> lock_;
  std::unique_ptr<ObjectModel> object_;
  std::unique_ptr<HandModel> hand_;
  std::unique_ptr<TrialRunner> runner_;
};

/// The coordinator's book: blocks to hand out, results into the checkpoint
/// (`<output>.ckpt`, blocks of an earlier run of the same build resumed), progress, and at the
/// end the map assembled from the finished prefix, labelled when asked, and written.
class DistributedBuild {
 public:
  /// Opens the checkpoint of this build (rank's object, hand, options and block_trials) and
  /// records the blocks it holds. @param block_trials trials per block (>= 1, else Error).
  DistributedBuild(const BuildRank& rank, std::uint64_t block_trials);

  const std::string& checkpointNote() const { return checkpoint_.loadNote(); }  ///< "" if new
  std::uint64_t resumedBlocks() const { return resumed_; }  ///< blocks taken from the checkpoint
  std::uint64_t trialsSimulated() const { return simulated_; }  ///< trials accepted in this run

  /// The next block to hand out; false when the stop rule is met or every block is out.
  bool next(std::uint64_t* b) { return ledger_.next(b); }
  /// A finished block's bytes (BuildRank::runBlock): checked, appended to the checkpoint and
  /// recorded. Throws Error when the bytes are damaged or are not block b.
  void accept(std::uint64_t b, const std::string& bytes);
  /// Progress so far (blocks, trials, valid grasps); elapsed_seconds as given.
  BuildProgress progress(double elapsed_seconds) const;

  /// Assembles the map from the finished blocks with `timing` (stage CPU seconds summed over
  /// the processes, wall time of the run), labels the grasps when the request asks, writes the
  /// output atomically and removes the checkpoint. A build without grasps (kNoGrasps) writes
  /// nothing and removes the checkpoint (written is false).
  FileBuildResult finish(const BuildTiming& timing);

 private:
  const BuildRank& rank_;
  BlockLedger ledger_;
  BuildCheckpoint checkpoint_;
  std::uint64_t resumed_ = 0, simulated_ = 0;
};

}  // namespace taskmap
