#pragma once
/// @file block_ledger.hpp
/// Rank 0's book of a distributed build (taskmap-mpi build, tools/mpi/): the fixed blocks of
/// block_trials trials of [0, max_trials), which are finished, which to hand out next, and the stop
/// rule of buildMap (the completed prefix holds valid_target force-closure grasps). MPI-free.

#include <cstdint>
#include <optional>
#include <vector>

#include "taskmap/builder/trial_block.hpp"

namespace taskmap {

/// Blocks of one build by index; block b is the trials [b * block_trials, min(.., max_trials)).
class BlockLedger {
 public:
  /// @param block_trials trials per block (>= 1, else Error), independent of the rank count.
  BlockLedger(std::uint64_t max_trials, std::uint64_t block_trials, std::uint64_t valid_target);

  /// First trial of block b.
  std::uint64_t blockFirst(std::uint64_t b) const { return b * block_trials_; }
  /// One past the last trial of block b (the last block may be shorter).
  std::uint64_t blockLast(std::uint64_t b) const;
  /// Number of blocks of the build: ceil(max_trials / block_trials).
  std::uint64_t blockCount() const { return count_; }

  /// True when the block is one of this build's blocks (right start and length).
  bool fits(const TrialBlock& block) const;
  /// Records a finished block (ignored when already recorded). Returns false when it does not
  /// fit (nothing recorded).
  bool record(TrialBlock block);
  /// The next unfinished, not yet handed out block; false when the stop rule is met or every
  /// block was handed out.
  bool next(std::uint64_t* b);
  /// The stop rule is met or every block is finished.
  bool done() const;

  /// Moves out the finished prefix of blocks 0, 1, ... in order (call once, at the end).
  std::vector<TrialBlock> takePrefix();

  std::uint64_t blocksDone() const { return blocks_done_; }  ///< finished blocks
  std::uint64_t trialsDone() const { return trials_done_; }  ///< trials in finished blocks
  std::uint64_t validFound() const { return valid_found_; }  ///< force closure in them

 private:
  const std::uint64_t max_trials_, block_trials_, valid_target_, count_;
  std::vector<std::optional<TrialBlock>> blocks_;  // grows with the blocks recorded
  std::uint64_t next_ = 0, prefix_ = 0, prefix_valid_ = 0;
  std::uint64_t blocks_done_ = 0, trials_done_ = 0, valid_found_ = 0;
};

}  // namespace taskmap
