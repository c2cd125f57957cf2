// Blocks of trials: TrialRunner blocks assembled by assembleMap equal buildMap for any split,
// the byte encoding round-trips bit for bit and refuses malformed bytes, the checkpoint keeps
// intact records and drops a torn or corrupted tail, and ignores another build's file.
#include "taskmap/builder/trial_block.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "build_fixtures.hpp"
#include "taskmap/builder/build_checkpoint.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

constexpr auto box = &testing::boxObject;
constexpr auto panda = &testing::pandaHand;

BuildOptions smallBuild(int threads) {
  BuildOptions o;
  o.seed = 5;
  o.valid_target = 4;
  o.max_trials = 600;
  o.threads = threads;
  o.block_size = 4;
  return o;
}

// Blocks of `size` trials covering [0, n) run by one runner.
std::vector<TrialBlock> runBlocks(const BuildOptions& options, std::uint64_t size,
                                  std::uint64_t n) {
  TrialRunner runner(box(), panda(), options);
  std::vector<TrialBlock> blocks;
  for (std::uint64_t first = 0; first < n; first += size) {
    blocks.emplace_back();
    EXPECT_TRUE(runner.run(first, std::min(first + size, n), &blocks.back()));
  }
  return blocks;
}

void expectSameOutcome(const TrialOutcome& a, const TrialOutcome& b) {
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.force_closure, b.force_closure);
  EXPECT_EQ(a.epsilon, b.epsilon);
  EXPECT_EQ(a.volume, b.volume);
  ASSERT_EQ(a.grasp != nullptr, b.grasp != nullptr);
  if (!a.grasp) return;
  EXPECT_EQ(a.grasp->pose.position, b.grasp->pose.position);
  EXPECT_EQ(a.grasp->pose.orientation.coeffs(), b.grasp->pose.orientation.coeffs());
  EXPECT_EQ(a.grasp->joints, b.grasp->joints);
  ASSERT_EQ(a.grasp->contacts.size(), b.grasp->contacts.size());
  for (std::size_t c = 0; c < a.grasp->contacts.size(); ++c) {
    EXPECT_EQ(a.grasp->contacts[c].point, b.grasp->contacts[c].point);
    EXPECT_EQ(a.grasp->contacts[c].normal, b.grasp->contacts[c].normal);
    EXPECT_EQ(a.grasp->contacts[c].depth, b.grasp->contacts[c].depth);
    EXPECT_EQ(a.grasp->contacts[c].link, b.grasp->contacts[c].link);
  }
}

TEST(TrialBlockTest, AssembledBlocksEqualBuildMapForAnySplitAndThreads) {
  const BuildResult direct = buildMap(box(), panda(), smallBuild(1));
  ASSERT_EQ(direct.status, BuildStatus::kComplete);
  const std::uint64_t n = direct.map.sampling.trials;
  for (const auto& [size, threads] : {std::pair<std::uint64_t, int>{7, 2}, {50, 1}, {n, 2}}) {
    SCOPED_TRACE("blocks of " + std::to_string(size));
    const BuildOptions o = smallBuild(threads);
    const BuildResult r =
        assembleMap(box(), panda(), o, runBlocks(o, size, n), false, BuildTiming{});
    EXPECT_EQ(r.status, BuildStatus::kComplete);
    EXPECT_EQ(r.map.sampling.trials, direct.map.sampling.trials);
    EXPECT_EQ(r.map.sampling.outcomes, direct.map.sampling.outcomes);
    EXPECT_EQ(r.map.sampling.params_json, direct.map.sampling.params_json);
    EXPECT_EQ(r.map.grasps.pose, direct.map.grasps.pose);
    EXPECT_EQ(r.map.grasps.joints, direct.map.grasps.joints);
    EXPECT_EQ(r.map.grasps.contact_points, direct.map.grasps.contact_points);
    ASSERT_TRUE(r.map.clustering && direct.map.clustering);
    EXPECT_EQ(r.map.clustering->labels, direct.map.clustering->labels);
  }
}

TEST(TrialBlockTest, BlocksMustBeConsecutiveFromZero) {
  const BuildOptions o = smallBuild(1);
  std::vector<TrialBlock> blocks = runBlocks(o, 10, 30);
  blocks.erase(blocks.begin() + 1);
  EXPECT_THROW(assembleMap(box(), panda(), o, blocks, false, BuildTiming{}), Error);
  TrialRunner runner(box(), panda(), o);
  TrialBlock b;
  EXPECT_THROW(runner.run(5, 5, &b), Error);
  EXPECT_THROW(runner.run(0, o.max_trials + 1, &b), Error);
}

TEST(TrialBlockTest, EncodingRoundTripsBitForBit) {
  BuildOptions o = smallBuild(2);
  o.stored = StoredGrasps::kAllCompleted;
  const TrialBlock block = std::move(runBlocks(o, 120, 120).front());
  ASSERT_GT(block.valid(), 0u);
  const std::size_t joints = panda().jointNames().size();
  const TrialBlock back = decodeTrialBlock(encodeTrialBlock(block), joints, "test");
  EXPECT_EQ(back.first, block.first);
  ASSERT_EQ(back.trials.size(), block.trials.size());
  for (std::size_t i = 0; i < block.trials.size(); ++i)
    expectSameOutcome(back.trials[i], block.trials[i]);
}

TEST(TrialBlockTest, MalformedBytesAreRefused) {
  const TrialBlock block = std::move(runBlocks(smallBuild(1), 60, 60).front());
  const std::size_t joints = panda().jointNames().size();
  const std::string bytes = encodeTrialBlock(block);
  for (std::size_t cut : {std::size_t{0}, std::size_t{7}, bytes.size() / 2, bytes.size() - 1}) {
    try {
      decodeTrialBlock(bytes.substr(0, cut), joints, "block from rank 3");
      ADD_FAILURE() << "accepted a block cut at " << cut;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("block from rank 3: malformed trial block"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_THROW(decodeTrialBlock(bytes + "x", joints, "t"), Error);
  EXPECT_THROW(decodeTrialBlock(bytes, joints + 1, "t"), Error);  // grasps have other joints
  std::string bad_status = bytes;
  bad_status[16] = static_cast<char>(200);  // status byte of the first trial
  EXPECT_THROW(decodeTrialBlock(bad_status, joints, "t"), Error);
  std::string huge_count = bytes;
  huge_count[15] = static_cast<char>(0x7f);  // trial count beyond the data
  EXPECT_THROW(decodeTrialBlock(huge_count, joints, "t"), Error);
}

class CheckpointTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (std::filesystem::temp_directory_path() /
             ("taskmap_ckpt_" + std::to_string(::getpid()) + ".ckpt"))
                .string();
    blocks_ = runBlocks(smallBuild(2), 20, 60);
    identity_ = buildIdentity(box(), panda(), smallBuild(2), 20);
  }
  void TearDown() override { std::filesystem::remove(path_); }
  std::size_t joints() const { return panda().jointNames().size(); }
  void writeThree() {
    BuildCheckpoint c(path_, identity_, joints());
    EXPECT_EQ(c.loadNote(), "");
    for (const TrialBlock& b : blocks_) c.append(b);
  }
  std::string path_, identity_;
  std::vector<TrialBlock> blocks_;
};

TEST_F(CheckpointTest, IntactRecordsAreReadBack) {
  writeThree();
  BuildCheckpoint c(path_, identity_, joints());
  const std::vector<TrialBlock> loaded = c.takeLoaded();
  ASSERT_EQ(loaded.size(), 3u);
  for (std::size_t b = 0; b < 3; ++b) {
    EXPECT_EQ(loaded[b].first, blocks_[b].first);
    for (std::size_t i = 0; i < loaded[b].trials.size(); ++i)
      expectSameOutcome(loaded[b].trials[i], blocks_[b].trials[i]);
  }
  EXPECT_NE(c.loadNote().find("3 blocks (60 trials)"), std::string::npos) << c.loadNote();
  c.remove();
  EXPECT_FALSE(std::filesystem::exists(path_));
}

TEST_F(CheckpointTest, TornOrCorruptedTailIsDropped) {
  writeThree();
  const auto size = std::filesystem::file_size(path_);
  std::filesystem::resize_file(path_, size - 5);  // killed while writing the last record
  {
    BuildCheckpoint c(path_, identity_, joints());
    EXPECT_EQ(c.takeLoaded().size(), 2u);
    EXPECT_NE(c.loadNote().find("dropped a damaged tail"), std::string::npos) << c.loadNote();
    c.append(blocks_[2]);  // appended after the intact records, not after the torn one
  }
  {
    std::fstream f(path_, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-10, std::ios::end);
    f.put('\x55');  // a flipped byte in the last payload
  }
  BuildCheckpoint c(path_, identity_, joints());
  EXPECT_EQ(c.takeLoaded().size(), 2u);
}

TEST_F(CheckpointTest, AnotherBuildsCheckpointIsReplaced) {
  writeThree();
  BuildOptions other = smallBuild(2);
  other.seed = 6;
  BuildCheckpoint c(path_, buildIdentity(box(), panda(), other, 20), joints());
  EXPECT_TRUE(c.takeLoaded().empty());
  EXPECT_NE(c.loadNote().find("belongs to another build"), std::string::npos) << c.loadNote();
  // Threads do not change the trials, so they are not part of the identity.
  EXPECT_EQ(identity_, buildIdentity(box(), panda(), smallBuild(1), 20));
  EXPECT_NE(identity_, buildIdentity(box(), panda(), smallBuild(1), 21));
}

}  // namespace
}  // namespace taskmap
