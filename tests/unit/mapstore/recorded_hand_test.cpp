// The URDF of a map's hand, found once for every stage (recorded_hand.hpp): the recorded path
// when its bytes have the map's SHA-256, else the first bundled hand that has it; errors name
// the hand and what was tried.
#include "taskmap/mapstore/recorded_hand.hpp"

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "scratch_dir.hpp"
#include "seal_oracle.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

using testing::throwsError;

const testing::ScratchDir kDir("recorded_hand_test");

/// A file `<root>/<folder>/<name>` holding `text`; returns its path.
std::string writeFile(const std::string& folder, const std::string& name, const std::string& text) {
  std::filesystem::create_directories(kDir.root() / folder);
  const std::string path = (kDir.root() / folder / name).string();
  test::writeBytes(path, text);
  return path;
}

TaskMapData mapWithHand(const std::string& params_json, const std::string& urdf_text) {
  TaskMapData map;
  map.hand.name = "gripper";
  map.hand.urdf_sha256 = test::sha256Hex(urdf_text.data(), urdf_text.size());
  map.sampling.params_json = params_json;
  return map;
}

TEST(RecordedHand, RecordedPathIsTheHandParameterWhenItIsAString) {
  EXPECT_EQ(recordedHandPath(mapWithHand(R"({"hand": "/a/b.urdf", "seed": 1})", "")), "/a/b.urdf");
  EXPECT_EQ(recordedHandPath(mapWithHand(R"({"hand": 3})", "")), "");
  EXPECT_EQ(recordedHandPath(mapWithHand(R"({"seed": 1})", "")), "");
  EXPECT_EQ(recordedHandPath(mapWithHand("imported, not JSON", "")), "");
  EXPECT_EQ(recordedHandPath(mapWithHand(R"(["hand"])", "")), "");
}

TEST(RecordedHand, FindsTheRecordedFileOrABundledHandWithTheSameContent) {
  const std::string text = "<robot name=\"gripper\"/>\n";
  const std::string recorded = writeFile("built", "gripper.urdf", text);
  writeFile("hands/aa", "aa.urdf", "<robot name=\"other\"/>\n");
  const std::string bundled = writeFile("hands/gripper", "gripper.urdf", text);
  writeFile("hands/zz", "zz.urdf", text);  // same content, later by path
  const std::string hands = (kDir.root() / "hands").string();
  TaskMapData map = mapWithHand("{\"hand\": \"" + recorded + "\"}", text);
  EXPECT_EQ(findMapHandUrdf(map, hands), recorded);
  EXPECT_EQ(findMapHandUrdf(map, ""), recorded);
  // Moved or edited at the recorded path: the first bundled hand (by path) with that content.
  test::writeBytes(recorded, text + " ");
  EXPECT_EQ(findMapHandUrdf(map, hands), bundled);
  std::filesystem::remove(recorded);
  EXPECT_EQ(findMapHandUrdf(map, hands), bundled);
  map.sampling.params_json = "not JSON";
  EXPECT_EQ(findMapHandUrdf(map, hands), bundled);
}

TEST(RecordedHand, NoMatchNamesTheHandTheRecordedPathAndTheFolder) {
  const std::string hands = (kDir.root() / "nohands").string();
  const TaskMapData map = mapWithHand(R"({"hand": "/nonexistent/gripper.urdf"})", "content");
  EXPECT_TRUE(throwsError(
      [&] { findMapHandUrdf(map, hands); },
      {"the map's hand 'gripper' (URDF SHA-256 " + map.hand.urdf_sha256.substr(0, 12) + "...)",
       "is neither at the recorded path '/nonexistent/gripper.urdf' nor a "
       "bundled hand under " +
           hands}));
  EXPECT_TRUE(throwsError([&] { findMapHandUrdf(map, ""); },
                          {"recorded path '/nonexistent/gripper.urdf'"}));
  try {
    findMapHandUrdf(map, "");
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find("bundled"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace taskmap
