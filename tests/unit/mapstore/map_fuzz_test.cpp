// Deterministic mutation fuzzing of the map reader (readMap): 240 mutants of a real map (bit
// flips, zeroed blocks, truncations, huge numbers; fixed seeds), each read in a child process
// with a time limit. Required: no crash, no hang, every refusal names the file and says what
// is wrong, and no accepted file whose grasps differ from the original. A second round
// re-seals each mutant of the HDF5 content (as a user re-sealing a damaged file on purpose
// would): then HDF5's own checksums (metadata, Fletcher-32 on the data) must refuse it.
// The sanitizer build runs this too (label unit).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include "child_probe.hpp"
#include "mutator.hpp"
#include "seal_oracle.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMutants = 240;
constexpr std::uint64_t kSeed = 18;
constexpr double kSecondsPerCase = 20.0;

std::string fixture() {
  return std::string(TEST_DATA_DIR) + "/maps/box_barrett.h5";
}

// "same" when the map read equals the original in every grasp, else "differs: <what>".
std::string compareGrasps(const TaskMapData& a, const TaskMapData& b) {
  const MapGrasps &g = a.grasps, &h = b.grasps;
  if (g.pose != h.pose) return "differs: pose";
  if (g.joints != h.joints) return "differs: joints";
  if (g.epsilon != h.epsilon || g.volume != h.volume) return "differs: quality";
  if (g.force_closure != h.force_closure) return "differs: force_closure";
  if (g.contact_offsets != h.contact_offsets || g.contact_points != h.contact_points ||
      g.contact_normals != h.contact_normals)
    return "differs: contacts";
  if (a.clustering.has_value() != b.clustering.has_value() ||
      (a.clustering && a.clustering->labels != b.clustering->labels))
    return "differs: clusters";
  return "same";
}

struct Tally {
  std::map<std::string, int> by_outcome;
  int cases = 0;
};

// Reads path in a child; records the outcome; fails the test on crash, hang, a refusal that
// does not name the file, or an accepted map whose grasps differ.
void probe(const std::string& path, const TaskMapData& original, const std::string& label,
           Tally& tally) {
  const test::ChildOutcome out = test::runInChild(
      [&] {
        try {
          return "accepted " + compareGrasps(readMap(path), original);
        } catch (const std::exception& e) {
          return std::string("refused ") + e.what();
        }
      },
      kSecondsPerCase, 2ull << 30);
  ++tally.cases;
  switch (out.kind) {
    case test::ChildOutcome::Kind::kCrashed:
      ++tally.by_outcome["crash"];
      ADD_FAILURE() << label << ": crashed (signal " << out.signal << ")";
      return;
    case test::ChildOutcome::Kind::kTimedOut:
      ++tally.by_outcome["hang"];
      ADD_FAILURE() << label << ": no answer within " << kSecondsPerCase << " s";
      return;
    case test::ChildOutcome::Kind::kFailed:
      ADD_FAILURE() << label << ": could not start a child process";
      return;
    case test::ChildOutcome::Kind::kReturned:
      break;
  }
  const std::string& r = out.reply;
  if (r.rfind("accepted same", 0) == 0) {
    ++tally.by_outcome["accepted, grasps identical"];
  } else if (r.rfind("accepted", 0) == 0) {
    ++tally.by_outcome["accepted, grasps DIFFER"];
    ADD_FAILURE() << label << ": " << r;
  } else {
    // "refused task map '<path>': <reason>": bucket by the first words of the reason.
    const std::string reason = r.substr(r.find("': ") == std::string::npos ? 0 : r.find("': ") + 3);
    ++tally.by_outcome["refused: " + reason.substr(0, reason.find_first_of(":(,;/'"))];
    EXPECT_NE(r.find(path), std::string::npos)
        << label << ": refusal does not name the file: " << r;
    EXPECT_GT(reason.size(), 10u) << label << ": refusal says nothing: " << r;
  }
}

void report(const std::string& title, const Tally& t) {
  std::printf("[ map-fuzz ] %s: %d mutants\n", title.c_str(), t.cases);
  for (const auto& [outcome, n] : t.by_outcome)
    std::printf("[ map-fuzz ]   %4d  %s\n", n, outcome.c_str());
}

class MapFuzzTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("taskmap_map_fuzz_" + std::to_string(getpid()));
    fs::create_directories(dir_);
    original_bytes_ = test::fileBytes(fixture());
    ASSERT_GT(original_bytes_.size(), 4096u);
    original_ = readMap(fixture());
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  std::string original_bytes_;
  TaskMapData original_;
};

TEST_F(MapFuzzTest, MutantsOfASealedMapAreRefusedOrIdentical) {
  Tally tally;
  const std::string path = (dir_ / "mutant.h5").string();
  for (std::size_t i = 0; i < kMutants; ++i) {
    test::writeBytes(path, test::mutate(original_bytes_, kSeed, i));
    probe(path, original_,
          "mutant " + std::to_string(i) + " (" + test::toString(test::mutationOf(i)) + ")", tally);
  }
  report("sealed map, mutated anywhere", tally);
}

TEST_F(MapFuzzTest, ResealedMutantsAreCaughtByHdf5ChecksumsOrIdentical) {
  Tally tally;
  const std::string path = (dir_ / "resealed.h5").string();
  for (std::size_t i = 0; i < kMutants; ++i) {
    std::string bytes = test::mutate(original_bytes_, kSeed + 1, i, 512);
    if (bytes.size() < 512) continue;
    bytes.replace(0, 512, test::sealBlock(bytes.substr(512)));
    test::writeBytes(path, bytes);
    probe(path, original_,
          "resealed mutant " + std::to_string(i) + " (" + test::toString(test::mutationOf(i)) + ")",
          tally);
  }
  report("HDF5 content mutated, then re-sealed", tally);
}

}  // namespace
}  // namespace taskmap
