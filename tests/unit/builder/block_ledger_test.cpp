// BlockLedger (block_ledger.hpp): the blocks of a distributed build, handed out once each, the
// stop rule on the finished prefix in index order (blocks finishing out of order), duplicates and
// foreign blocks refused.
#include "taskmap/builder/block_ledger.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "error_matchers.hpp"

namespace taskmap {
namespace {

using taskmap::testing::errorMessage;

// Block [first, last) whose trials with index in `valid` have force closure.
TrialBlock block(std::uint64_t first, std::uint64_t last, const std::vector<std::uint64_t>& valid) {
  TrialBlock b;
  b.first = first;
  b.trials.resize(last - first);
  for (std::uint64_t i : valid) b.trials[i - first].force_closure = true;
  return b;
}

TEST(BlockLedger, BlocksCoverTheBudgetAndAreHandedOutOnce) {
  BlockLedger ledger(25, 10, 1000);
  EXPECT_EQ(ledger.blockCount(), 3u);
  EXPECT_EQ(ledger.blockFirst(2), 20u);
  EXPECT_EQ(ledger.blockLast(2), 25u);  // the last block is shorter
  std::vector<std::uint64_t> handed;
  for (std::uint64_t b; ledger.next(&b);) handed.push_back(b);
  EXPECT_EQ(handed, (std::vector<std::uint64_t>{0, 1, 2}));
  EXPECT_FALSE(ledger.done());
  EXPECT_TRUE(ledger.record(block(20, 25, {})));
  EXPECT_TRUE(ledger.record(block(0, 10, {3})));
  EXPECT_TRUE(ledger.record(block(10, 20, {})));
  EXPECT_TRUE(ledger.done());  // every block finished
  EXPECT_EQ(ledger.trialsDone(), 25u);
  EXPECT_EQ(ledger.validFound(), 1u);
  const std::vector<TrialBlock> prefix = ledger.takePrefix();
  ASSERT_EQ(prefix.size(), 3u);
  for (std::size_t i = 0; i < prefix.size(); ++i) EXPECT_EQ(prefix[i].first, 10 * i);
}

TEST(BlockLedger, StopRuleCountsTheFinishedPrefixOnly) {
  BlockLedger ledger(100, 10, 3);
  // Block 1 finishes first with enough valid grasps, but block 0 is missing: not done.
  EXPECT_TRUE(ledger.record(block(10, 20, {11, 12, 13})));
  EXPECT_FALSE(ledger.done());
  EXPECT_EQ(ledger.validFound(), 3u);
  std::uint64_t b = 99;
  ASSERT_TRUE(ledger.next(&b));
  EXPECT_EQ(b, 0u);  // block 1 is finished: not handed out again
  ASSERT_TRUE(ledger.next(&b));
  EXPECT_EQ(b, 2u);
  EXPECT_TRUE(ledger.record(block(0, 10, {})));
  EXPECT_TRUE(ledger.done());
  EXPECT_FALSE(ledger.next(&b));
  EXPECT_EQ(ledger.takePrefix().size(), 2u);
}

TEST(BlockLedger, DuplicatesAreIgnoredAndForeignBlocksRefused) {
  BlockLedger ledger(30, 10, 5);
  EXPECT_TRUE(ledger.record(block(0, 10, {1})));
  EXPECT_TRUE(ledger.record(block(0, 10, {1, 2})));  // a resumed duplicate: ignored
  EXPECT_EQ(ledger.blocksDone(), 1u);
  EXPECT_EQ(ledger.validFound(), 1u);
  EXPECT_FALSE(ledger.record(block(5, 15, {})));   // wrong start
  EXPECT_FALSE(ledger.record(block(10, 15, {})));  // wrong length
  EXPECT_FALSE(ledger.record(block(30, 40, {})));  // past the budget
  EXPECT_FALSE(ledger.fits(block(20, 29, {})));
  EXPECT_TRUE(ledger.fits(block(20, 30, {})));
  EXPECT_EQ(ledger.blocksDone(), 1u);
  EXPECT_EQ(errorMessage([] { BlockLedger(10, 0, 1); }),
            "block_trials must be >= 1 (--block-trials)");
}

}  // namespace
}  // namespace taskmap
