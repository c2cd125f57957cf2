// Deterministic mutation fuzzing of the formats and files beyond mesh_fuzz_test (issue 32): a
// box in 3MF, glTF (text, buffer inlined), GLB, COLLADA and DirectX .x (tests/data/meshes/fuzz/,
// written by assimp 5.2 from box.obj) through ObjectModel::load, and the Barrett hand's URDF and
// sidecar JSON and the LEAP hand's MJCF through HandModel::load. Few mutants per format (fixed
// seeds: bit flips, zeroed blocks, truncations, huge numbers), each loaded in a child process with
// a time and address-space limit. Required: no crash, no hang, every refusal names the file, peak
// memory within a margin of the original's. Prints the outcomes per format (refused / accepted /
// crash / hang / memory). Label fuzz: the release suite runs it, the sanitizer run does not.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include "child_probe.hpp"
#include "mutator.hpp"
#include "seal_oracle.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMeshMutants = 24;
constexpr std::size_t kHandMutants = 40;
constexpr std::uint64_t kSeed = 32;
constexpr double kSecondsPerCase = 30.0;
constexpr unsigned long long kAddressSpace = 2ull << 30;
// Peak memory of a mutant's load over the original's: this margin plus this multiple of the
// file size (a hostile header declares gigabytes; the parse child's limit must stop it).
constexpr long kMarginKib = 8192;
constexpr long kPerByte = 64;

/// Loads `path` with `load` in a child: "accepted" or "refused <message>".
test::ChildOutcome inChild(const std::function<void()>& load) {
  return test::runInChild(
      [&load] {
        try {
          load();
          return std::string("accepted");
        } catch (const std::exception& e) {
          return std::string("refused ") + e.what();
        }
      },
      kSecondsPerCase, kAddressSpace);
}

class FormatFuzz : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("taskmap_format_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Writes `count` mutants of `original` to `path`, loads each with `load` in a child, checks
  /// the outcome and prints the tally of `name`. `named` must appear in every refusal.
  void fuzz(const std::string& name, const std::string& original, const std::string& path,
            std::size_t count, const std::function<void()>& load, const std::string& named) {
    test::writeBytes(path, original);
    const test::ChildOutcome honest = inChild(load);
    ASSERT_EQ(honest.reply, "accepted") << name;
    std::map<std::string, int> tally{
        {"accepted", 0}, {"refused", 0}, {"crash", 0}, {"hang", 0}, {"memory", 0}};
    long worst = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::string bytes = test::mutate(original, kSeed, i);
      test::writeBytes(path, bytes);
      const std::string label =
          name + " mutant " + std::to_string(i) + " (" + test::toString(test::mutationOf(i)) + ")";
      const test::ChildOutcome out = inChild(load);
      if (out.kind == test::ChildOutcome::Kind::kCrashed) {
        ++tally["crash"];
        ADD_FAILURE() << label << ": crashed (signal " << out.signal << ")";
        continue;
      }
      if (out.kind == test::ChildOutcome::Kind::kTimedOut) {
        ++tally["hang"];
        ADD_FAILURE() << label << ": no answer within " << kSecondsPerCase << " s";
        continue;
      }
      ASSERT_EQ(out.kind, test::ChildOutcome::Kind::kReturned) << label;
      const long limit = honest.peak_rss_delta_kib + kMarginKib +
                         kPerByte * static_cast<long>(bytes.size()) / 1024;
      worst = std::max(worst, out.peak_rss_delta_kib - honest.peak_rss_delta_kib);
      if (out.peak_rss_delta_kib > limit) {
        ++tally["memory"];
        ADD_FAILURE() << label << ": peak memory grew by " << out.peak_rss_delta_kib
                      << " KiB (limit " << limit << " KiB): " << out.reply;
        continue;
      }
      if (out.reply == "accepted") {
        ++tally["accepted"];
        continue;
      }
      ++tally["refused"];
      EXPECT_NE(out.reply.find(named), std::string::npos) << label << ": " << out.reply;
      EXPECT_EQ(out.reply.find("bad_alloc"), std::string::npos) << label << ": " << out.reply;
    }
    std::printf("[ format-fuzz ] %-20s %zu mutants:", name.c_str(), count);
    for (const auto& [outcome, n] : tally) std::printf("  %s %d", outcome.c_str(), n);
    std::printf("  (worst peak memory over the original: %ld KiB)\n", worst);
  }

  fs::path dir_;
};

TEST_F(FormatFuzz, MeshContainerFormatsAreLoadedOrRefusedWithinBounds) {
  const std::string data = std::string(TEST_DATA_DIR) + "/meshes/fuzz/";
  for (const char* name : {"box.3mf", "box.gltf", "box.glb", "box.dae", "box.x"}) {
    const std::string path = (dir_ / name).string();
    fuzz(
        name, test::fileBytes(data + name), path, kMeshMutants,
        [&path] { ObjectModel::load(path); }, path);
  }
}

TEST_F(FormatFuzz, HandUrdfAndSidecarAreLoadedOrRefusedWithinBounds) {
  const std::string hands = std::string(TASKMAP_HANDS_DIR) + "/barrett/";
  const std::string urdf = test::fileBytes(hands + "barrett.urdf");
  const std::string sidecar = test::fileBytes(hands + "barrett.hand.json");
  ASSERT_FALSE(urdf.empty());
  ASSERT_FALSE(sidecar.empty());
  const std::string urdf_path = (dir_ / "hand.urdf").string();
  const std::string sidecar_path = (dir_ / "hand.hand.json").string();
  const auto load = [&urdf_path] { HandModel::load(urdf_path); };
  test::writeBytes(sidecar_path, sidecar);
  fuzz("barrett.urdf", urdf, urdf_path, kHandMutants, load, "hand.urdf");
  test::writeBytes(urdf_path, urdf);
  // A refusal of a damaged sidecar names the sidecar or the URDF it belongs to.
  fuzz("barrett.hand.json", sidecar, sidecar_path, kHandMutants, load, "hand.");
}

// Issue 52: the real LEAP hand's MJCF (MuJoCo Menagerie, with its two collision meshes and the
// sidecar) mutated like the URDF: loaded or refused naming the file, within time and memory.
TEST_F(FormatFuzz, HandMjcfIsLoadedOrRefusedWithinBounds) {
  const fs::path leap = fs::path(TEST_DATA_DIR) / "real/hands/leap_hand_mjcf";
  const std::string mjcf = test::fileBytes((leap / "right_hand.xml").string());
  ASSERT_FALSE(mjcf.empty());
  fs::create_directories(dir_ / "assets");
  for (const char* f : {"assets/tip.obj", "assets/thumb_tip.obj"})
    fs::copy_file(leap / f, dir_ / f);
  test::writeBytes((dir_ / "leap.hand.json").string(),
                   test::fileBytes((leap / "right_hand.hand.json").string()));
  const std::string path = (dir_ / "leap.xml").string();
  fuzz(
      "right_hand.xml (MJCF)", mjcf, path, kHandMutants, [&path] { HandModel::load(path); },
      "leap.");
}

}  // namespace
}  // namespace taskmap
