// Deterministic mutation fuzzing of mesh loading (ObjectModel::load, assimp behind the header
// bounds of meshes/src/mesh_bounds.cpp): 100 mutants of a box in each of OBJ, OFF, ASCII and
// binary PLY, ASCII and binary STL (bit flips, zeroed blocks, truncations, huge numbers; fixed
// seeds), each loaded in a child process with a time and address-space limit. Required: no
// crash, no hang, every refusal names the file, and peak memory within a small multiple of
// the file size plus the loader's fixed cost. The sanitizer build runs this too (label unit).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include "child_probe.hpp"
#include "mutator.hpp"
#include "seal_oracle.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMutantsPerFormat = 100;
constexpr std::uint64_t kSeed = 18;
constexpr double kSecondsPerCase = 30.0;
// Peak memory of a mutant's load may exceed the original's (the fixed cost of the importer,
// ~20 MiB for assimp's first OBJ import) by this margin plus this multiple of the file size.
constexpr long kMarginKib = 4096;  // allocator noise; hostile headers declare gigabytes
constexpr long kPerByte = 64;

test::ChildOutcome loadInChild(const std::string& path) {
  return test::runInChild(
      [&path] {
        try {
          ObjectModel::load(path);
          return std::string("accepted");
        } catch (const std::exception& e) {
          return std::string("refused ") + e.what();
        }
      },
      kSecondsPerCase, 2ull << 30);
}

TEST(MeshFuzzTest, MutantsOfEveryFormatAreLoadedOrRefusedWithinBounds) {
  const fs::path dir =
      fs::temp_directory_path() / ("taskmap_mesh_fuzz_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string data = std::string(TEST_DATA_DIR) + "/meshes/fuzz/";
  long worst_kib = 0;
  for (const char* name : {"box.obj", "box.off", "box_ascii.ply", "box_binary.ply", "box_ascii.stl",
                           "box_binary.stl"}) {
    const std::string original = test::fileBytes(data + name);
    ASSERT_FALSE(original.empty()) << name;
    std::map<std::string, int> outcomes;
    const test::ChildOutcome honest = loadInChild(data + name);
    ASSERT_EQ(honest.reply, "accepted") << name;
    const std::string path = (dir / name).string();
    for (std::size_t i = 0; i < kMutantsPerFormat; ++i) {
      const std::string bytes = test::mutate(original, kSeed, i);
      test::writeBytes(path, bytes);
      const std::string label = std::string(name) + " mutant " + std::to_string(i) + " (" +
                                test::toString(test::mutationOf(i)) + ")";
      const test::ChildOutcome out = loadInChild(path);
      if (out.kind == test::ChildOutcome::Kind::kCrashed) {
        ++outcomes["crash"];
        ADD_FAILURE() << label << ": crashed (signal " << out.signal << ")";
        continue;
      }
      if (out.kind == test::ChildOutcome::Kind::kTimedOut) {
        ++outcomes["hang"];
        ADD_FAILURE() << label << ": no answer within " << kSecondsPerCase << " s";
        continue;
      }
      ASSERT_EQ(out.kind, test::ChildOutcome::Kind::kReturned) << label;
      if (out.reply == "accepted") {
        ++outcomes["accepted"];
      } else {
        ++outcomes["refused"];
        EXPECT_NE(out.reply.find(path), std::string::npos) << label << ": " << out.reply;
        EXPECT_EQ(out.reply.find("bad_alloc"), std::string::npos) << label << ": " << out.reply;
      }
      // AddressSanitizer's quarantine and shadow memory make resident sizes noisier.
      const long margin = test::kAddressSanitizer ? 8 * kMarginKib : kMarginKib;
      const long limit =
          honest.peak_rss_delta_kib + margin + kPerByte * static_cast<long>(bytes.size()) / 1024;
      EXPECT_LE(out.peak_rss_delta_kib, limit) << label << ": " << out.reply;
      worst_kib = std::max(worst_kib, out.peak_rss_delta_kib - honest.peak_rss_delta_kib);
    }
    std::printf("[ mesh-fuzz ] %-15s %zu mutants:", name, kMutantsPerFormat);
    for (const auto& [outcome, n] : outcomes) std::printf("  %s %d", outcome.c_str(), n);
    std::printf("\n");
  }
  std::printf("[ mesh-fuzz ] worst peak memory of a mutant's load over the original's: %ld KiB\n",
              worst_kib);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace taskmap
