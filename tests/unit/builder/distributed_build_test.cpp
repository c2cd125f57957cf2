// builder/distributed_build.hpp (`taskmap-mpi build` without MPI): blocks run by two ranks in
// any order, and a run stopped half-way then resumed from its checkpoint, write the same map bytes
// as the one-process file build (MapFileBuild); damaged or foreign block bytes are refused.
#include "taskmap/builder/distributed_build.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "error_matchers.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;
const std::string kData = std::string(TASKMAP_SOURCE_DIR) + "/meshes";

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class DistributedBuildTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("taskmap_distributed_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  FileBuildOptions request(const std::string& name) const {
    FileBuildOptions o;
    o.object = kData + "/objects/box.obj";
    o.hand = kData + "/hands/panda/panda.urdf";
    o.output = (dir_ / name).string();
    o.build.valid_target = 12;
    o.build.max_trials = 4000;
    o.build.seed = 4;
    o.build.threads = 1;
    return o;
  }
  std::string reference() const {
    MapFileBuild build(request("one.h5"));
    EXPECT_TRUE(build.run().written);
    return bytesOf((dir_ / "one.h5").string());
  }
  /// The real Allegro on the reference box: the default sampler is palm_enclose.
  FileBuildOptions encloseRequest(const std::string& name) const {
    FileBuildOptions o = request(name);
    o.hand = std::string(TEST_DATA_DIR) +
             "/real/hands/allegro_right/allegro_hand_description_right.urdf";
    o.build.valid_target = 6;
    return o;
  }
  fs::path dir_;
};

TEST_F(DistributedBuildTest, TwoRanksOutOfOrderWriteTheOneProcessMap) {
  const std::string expected = reference();
  const BuildRank coordinator(request("two.h5"), true);
  const BuildRank worker(request("two.h5"), false);
  DistributedBuild book(coordinator, 7);
  EXPECT_EQ(book.checkpointNote(), "");
  std::vector<std::uint64_t> out;
  for (std::uint64_t b; book.next(&b);) {
    out.push_back(b);
    if (out.size() == 2) {  // the second block comes back first, from the other rank
      book.accept(out[1], worker.runBlock(out[1], 7));
      book.accept(out[0], coordinator.runBlock(out[0], 7));
      out.clear();
    }
  }
  for (std::uint64_t b : out) book.accept(b, worker.runBlock(b, 7));
  EXPECT_GE(book.progress(1.0).valid_found, 12u);
  const FileBuildResult r = book.finish(coordinator.timing());
  ASSERT_TRUE(r.written) << r.build.message;
  EXPECT_EQ(bytesOf((dir_ / "two.h5").string()), expected);
  EXPECT_FALSE(fs::exists(dir_ / "two.h5.ckpt"));
}

TEST_F(DistributedBuildTest, TheDefaultSamplerGivesTheOneProcessMap) {
  MapFileBuild one(encloseRequest("one.h5"));
  const FileBuildResult single = one.run();
  ASSERT_TRUE(single.written) << single.build.message;
  EXPECT_EQ(single.build.sampler_choice.kind, SamplerKind::kPalmEnclose);
  const BuildRank coordinator(encloseRequest("two.h5"), true);
  const BuildRank worker(encloseRequest("two.h5"), false);
  EXPECT_EQ(worker.samplerChoice().kind, SamplerKind::kPalmEnclose);
  DistributedBuild book(coordinator, 5);
  for (std::uint64_t b; book.next(&b);) book.accept(b, worker.runBlock(b, 5));
  const FileBuildResult r = book.finish(coordinator.timing());
  ASSERT_TRUE(r.written) << r.build.message;
  EXPECT_FALSE(r.build.sampler_choice.enclose_refused);
  EXPECT_EQ(r.build.map.sampling.sampler, "palm_enclose");
  EXPECT_EQ(bytesOf((dir_ / "two.h5").string()), bytesOf((dir_ / "one.h5").string()));
}

TEST_F(DistributedBuildTest, AStoppedRunResumesFromItsCheckpoint) {
  const std::string expected = reference();
  std::uint64_t first_run = 0;
  {
    const BuildRank rank(request("resumed.h5"), true);
    DistributedBuild book(rank, 5);
    std::uint64_t b = 0;
    for (int k = 0; k < 3 && book.next(&b); ++k, ++first_run) book.accept(b, rank.runBlock(b, 5));
  }  // stopped: no map, the checkpoint stays
  ASSERT_TRUE(fs::exists(dir_ / "resumed.h5.ckpt"));
  EXPECT_FALSE(fs::exists(dir_ / "resumed.h5"));
  const BuildRank rank(request("resumed.h5"), true);
  DistributedBuild book(rank, 5);
  EXPECT_EQ(book.resumedBlocks(), first_run);
  EXPECT_NE(book.checkpointNote(), "");
  for (std::uint64_t b; book.next(&b);) book.accept(b, rank.runBlock(b, 5));
  ASSERT_TRUE(book.finish(rank.timing()).written);
  EXPECT_EQ(bytesOf((dir_ / "resumed.h5").string()), expected);
}

TEST_F(DistributedBuildTest, DamagedAndForeignBlocksAreRefused) {
  const BuildRank rank(request("refused.h5"), true);
  DistributedBuild book(rank, 5);
  std::uint64_t b = 0;
  ASSERT_TRUE(book.next(&b));
  const std::string bytes = rank.runBlock(b, 5);
  EXPECT_TRUE(testing::throwsError([&] { book.accept(b, bytes.substr(0, bytes.size() / 2)); },
                                   {"result of block"}));
  EXPECT_TRUE(testing::throwsError([&] { book.accept(b + 1, bytes); }, {"other trials"}));
  const BuildRank second(request("refused.h5"), false);  // a worker takes no lock
  EXPECT_TRUE(testing::throwsError([&] { const BuildRank other(request("refused.h5"), true); },
                                   {"refused.h5"}));
}

}  // namespace
}  // namespace taskmap
