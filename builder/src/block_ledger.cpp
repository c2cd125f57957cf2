// Rank 0's book of a build in blocks (block_ledger.hpp).
#include "taskmap/builder/block_ledger.hpp"

#include <algorithm>
#include <utility>

#include "taskmap/core/error.hpp"

namespace taskmap {

BlockLedger::BlockLedger(std::uint64_t max_trials, std::uint64_t block_trials,
                         std::uint64_t valid_target)
    : max_trials_(max_trials),
      block_trials_(block_trials),
      valid_target_(valid_target),
      // Without wrap-around for any budget; the table itself grows with the work recorded.
      count_(block_trials == 0
                 ? 0
                 : max_trials / block_trials + (max_trials % block_trials != 0 ? 1 : 0)) {
  if (block_trials == 0) throw Error("block_trials must be >= 1 (--block-trials)");
}

std::uint64_t BlockLedger::blockLast(std::uint64_t b) const {
  return blockFirst(b) + std::min(block_trials_, max_trials_ - blockFirst(b));
}

bool BlockLedger::fits(const TrialBlock& block) const {
  if (block.first % block_trials_ != 0) return false;
  const std::uint64_t b = block.first / block_trials_;
  return b < count_ && block.end() == blockLast(b);
}

bool BlockLedger::record(TrialBlock block) {
  if (!fits(block)) return false;
  const std::uint64_t b = block.first / block_trials_;
  if (b >= blocks_.size()) blocks_.resize(b + 1);
  if (blocks_[b]) return true;
  ++blocks_done_;
  trials_done_ += block.trials.size();
  valid_found_ += block.valid();
  blocks_[b] = std::move(block);
  while (prefix_ < blocks_.size() && blocks_[prefix_]) prefix_valid_ += blocks_[prefix_++]->valid();
  return true;
}

bool BlockLedger::done() const {
  return prefix_valid_ >= valid_target_ || prefix_ == count_;
}

bool BlockLedger::next(std::uint64_t* b) {
  if (done()) return false;
  while (next_ < blocks_.size() && blocks_[next_]) ++next_;
  if (next_ >= count_) return false;
  *b = next_++;
  return true;
}

std::vector<TrialBlock> BlockLedger::takePrefix() {
  std::vector<TrialBlock> out;
  out.reserve(prefix_);
  for (std::uint64_t b = 0; b < prefix_; ++b) out.push_back(std::move(*blocks_[b]));
  return out;
}

}  // namespace taskmap
