// `taskmap validate` (and --robust) and `taskmap build` testing its grasps as a user runs them:
// labels in the map, the summary and its JSON, the same labels for one and two threads, clear
// refusals.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

class ValidateCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("validate_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// A small map of the panda jaws on the reference box, force-closure grasps untested.
  std::string buildBoxMap(const std::string& name, const std::string& extra = "") {
    const auto r = testing::runTaskmap("build --object " + std::string(TASKMAP_OBJECTS_DIR) +
                                       "/box.obj --hand panda --valid 8 --seed 4 --hold-test "
                                       "off -q -o " +
                                       path(name) + " " + extra);
    EXPECT_EQ(r.code, 0) << r.out;
    return path(name);
  }
  fs::path dir_;
};

TEST_F(ValidateCliTest, WritesLabelsAndTheSameForAnyThreadCount) {
  const std::string map = buildBoxMap("box.h5");
  const auto one = testing::runTaskmap("validate " + map + " --threads 1 -o " + path("one.h5"));
  ASSERT_EQ(one.code, 0) << one.out;
  EXPECT_NE(one.out.find("grasps hold"), std::string::npos) << one.out;
  EXPECT_NE(one.out.find("grasps per CPU-second"), std::string::npos) << one.out;
  const auto two =
      testing::runTaskmap("validate " + map + " --threads 2 --json -o " + path("two.h5"));
  ASSERT_EQ(two.code, 0) << two.out;
  const auto j = nlohmann::json::parse(two.out);
  EXPECT_EQ(j["tested"], 8);
  EXPECT_GE(j["holding"].get<int>(), 4);  // jaws at 70 N on a 0.1 kg box
  const TaskMapData a = readMap(path("one.h5")), b = readMap(path("two.h5"));
  ASSERT_TRUE(a.validation && b.validation);
  EXPECT_EQ(a.validation->hold, b.validation->hold);
  EXPECT_EQ(a.validation->translation, b.validation->translation);
  EXPECT_EQ(j["holding"].get<std::size_t>(), a.validation->holding());
  EXPECT_FALSE(readMap(map).validation.has_value());  // -o leaves the input alone
}

TEST_F(ValidateCliTest, BuildValidateLabelsAsItBuilds) {
  const std::string map = buildBoxMap("labelled.h5", "--validate");
  const TaskMapData m = readMap(map);
  ASSERT_TRUE(m.validation);
  EXPECT_EQ(m.validation->tested(), m.grasps.size());
}

// The integrator (docs/VALIDATION.md, "The integrator"): `implicit` by default, implicitfast one
// option away in validate and build, recorded with the labels; another name refused with the
// choices.
TEST_F(ValidateCliTest, TheIntegratorIsAChoiceAndIsRecorded) {
  const std::string map = buildBoxMap("box.h5");
  const auto integratorOf = [](const std::string& file) {
    const TaskMapData m = readMap(file);
    EXPECT_TRUE(m.validation.has_value()) << file;
    return m.validation ? nlohmann::json::parse(m.validation->params_json)["integrator"]
                        : nlohmann::json();
  };
  auto r = testing::runTaskmap("validate " + map + " -q -o " + path("implicit.h5"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(integratorOf(path("implicit.h5")), "implicit");
  r = testing::runTaskmap("validate " + map + " --integrator implicitfast -q -o " +
                          path("fast.h5"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(integratorOf(path("fast.h5")), "implicitfast");
  const std::string built = buildBoxMap("built.h5", "--validate --integrator implicitfast");
  EXPECT_EQ(integratorOf(built), "implicitfast");
  r = testing::runTaskmap("validate " + map + " --integrator rk4 -o " + path("rk4.h5"));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("implicitfast"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(path("rk4.h5")));
}

// The default build tests each force-closure grasp as it is found and stores N that hold
// robustly, with their labels; the summary says how many were tested and kept, and what the
// test cost. Validating that map again (robustly) finds every grasp robust.
TEST_F(ValidateCliTest, TheDefaultBuildStoresGraspsThatHoldRobustly) {
  const auto r =
      testing::runTaskmap("build --object " + std::string(TASKMAP_OBJECTS_DIR) +
                          "/box.obj --hand barrett --valid 4 --seed 4 -o " + path("robust.h5"));
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* part : {"found 4 grasps that hold robustly", "tested in physics", "kept",
                           "hold test", "tested in MuJoCo"})
    EXPECT_NE(r.out.find(part), std::string::npos) << part << "\n" << r.out;
  const TaskMapData m = readMap(path("robust.h5"));
  ASSERT_EQ(m.grasps.size(), 4u);
  ASSERT_TRUE(m.validation);
  EXPECT_EQ(m.validation->robustCount(), 4u);
  const auto again = testing::runTaskmap("validate " + path("robust.h5") + " --robust --json -o " +
                                         path("again.h5"));
  ASSERT_EQ(again.code, 0) << again.out;
  const auto j = nlohmann::json::parse(again.out);
  EXPECT_EQ(j["robust"], 4);
  EXPECT_EQ(j["variant_failures"]["shift+z"], 0);
  // --validate would label what the build labelled already: refused, saying why.
  const auto twice = testing::runTaskmap("build --object " + std::string(TASKMAP_OBJECTS_DIR) +
                                         "/box.obj --hand barrett --valid 4 -o " +
                                         path("twice.h5") + " --validate");
  EXPECT_NE(twice.code, 0);
  EXPECT_NE(twice.out.find("--hold-test off"), std::string::npos) << twice.out;
  EXPECT_FALSE(fs::exists(path("twice.h5")));
}

// validate --robust: every variant of every grasp, the share held and the margin stored per
// grasp, the variants and thresholds in /validation; a robust grasp holds under the protocol.
TEST_F(ValidateCliTest, RobustLabelsEveryVariantOfEveryGrasp) {
  const std::string map = buildBoxMap("variants.h5");
  const auto r = testing::runTaskmap("validate " + map + " --robust");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("robust (every variant holds within the margin)"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("variants failing where the nominal held: nominal"), std::string::npos)
      << r.out;
  const TaskMapData m = readMap(map);
  ASSERT_TRUE(m.validation);
  const MapValidation& v = *m.validation;
  ASSERT_EQ(v.robust.size(), 8u);
  EXPECT_EQ(v.variantCount(), 14u);  // the box is convex: no second decomposition
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_NE(v.robust[i], MapValidation::kNotTested);
    if (v.robust[i] == 1) {
      EXPECT_EQ(v.hold[i], 1);
    }
    EXPECT_GE(v.robust_share[i], 0.0);
    for (std::size_t k = 0; k < 14; ++k) EXPECT_NE(v.variant_held[i * 14 + k], 255);
  }
}

TEST_F(ValidateCliTest, BuildKeepHoldingStoresOnlyGraspsThatHold) {
  // Barrett on the box: about a third of its force-closure grasps hold (docs/VALIDATION.md).
  const std::string args = "build --object " + std::string(TASKMAP_OBJECTS_DIR) +
                           "/box.obj --hand barrett --valid 8 --seed 4 --threads 1 "
                           "--hold-test off -o ";
  const auto r = testing::runTaskmap(args + path("kept.h5") + " --validate --keep-holding");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("--keep-holding: kept"), std::string::npos) << r.out;
  const TaskMapData m = readMap(path("kept.h5"));
  ASSERT_TRUE(m.validation);
  EXPECT_GT(m.grasps.size(), 0u);
  EXPECT_LT(m.grasps.size(), 8u) << "every grasp held: the test no longer tells";
  for (std::size_t i = 0; i < m.grasps.size(); ++i) EXPECT_EQ(m.validation->hold[i], 1);
  const auto refused = testing::runTaskmap(args + path("never.h5") + " --keep-holding");
  EXPECT_NE(refused.code, 0);
  EXPECT_NE(refused.out.find("--keep-holding needs --validate"), std::string::npos) << refused.out;
  EXPECT_FALSE(fs::exists(path("never.h5")));
}

// --trace: one grasp's test stage by stage, as text and as JSON, the map left as it was; its
// verdict is the grasp's label; an index past the grasps and -o are refused.
TEST_F(ValidateCliTest, TraceShowsOneGraspStageByStage) {
  const std::string map = buildBoxMap("traced.h5");
  const auto bytes = [](const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  const std::string before = bytes(map);
  const auto text = testing::runTaskmap("validate " + map + " --trace 0");
  ASSERT_EQ(text.code, 0) << text.out;
  for (const char* part : {"grasp 0 of", "along approach mm", "closing", "squeeze", "-x"})
    EXPECT_NE(text.out.find(part), std::string::npos) << part << "\n" << text.out;
  const auto json = testing::runTaskmap("validate " + map + " --trace 0 --json");
  ASSERT_EQ(json.code, 0) << json.out;
  const auto j = nlohmann::json::parse(json.out);
  EXPECT_EQ(bytes(map), before);  // nothing written
  ASSERT_TRUE(j["samples"].is_array());
  EXPECT_EQ(j["samples"][0]["phase"], "closing");
  EXPECT_TRUE(j["samples"][0].contains("along_approach"));
  const auto labelled =
      testing::runTaskmap("validate " + map + " --threads 1 -o " + path("labels.h5"));
  ASSERT_EQ(labelled.code, 0) << labelled.out;
  EXPECT_EQ(j["holds"].get<bool>(), readMap(path("labels.h5")).validation->hold[0] == 1);
  const auto past = testing::runTaskmap("validate " + map + " --trace 8");
  EXPECT_NE(past.code, 0);
  EXPECT_NE(past.out.find("grasp 8 is not in the map (it has 8 grasps"), std::string::npos)
      << past.out;
  const auto out = testing::runTaskmap("validate " + map + " --trace 0 -o " + path("x.h5"));
  EXPECT_NE(out.code, 0);
  EXPECT_NE(out.out.find("--trace writes nothing"), std::string::npos) << out.out;
}

TEST_F(ValidateCliTest, RefusesWhatIsNotAMapAndAnotherHand) {
  std::ofstream(path("junk.h5")) << "not a map";
  const auto junk = testing::runTaskmap("validate " + path("junk.h5"));
  EXPECT_NE(junk.code, 0);
  EXPECT_NE(junk.out.find("junk.h5"), std::string::npos) << junk.out;
  const std::string map = buildBoxMap("box2.h5");
  const auto hand = testing::runTaskmap("validate " + map + " --hand " +
                                        std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  EXPECT_NE(hand.code, 0);
  EXPECT_NE(hand.out.find("actuated joints"), std::string::npos) << hand.out;
  // A map whose hand is neither at its recorded path nor bundled (no URDF has its SHA-256):
  // the refusal names the map and the hand and says what to pass.
  TaskMapData lost = readMap(map);
  lost.hand.urdf_sha256 = std::string(64, '0');
  writeMap(path("lost_hand.h5"), lost);
  const auto no_hand = testing::runTaskmap("validate " + path("lost_hand.h5"));
  EXPECT_NE(no_hand.code, 0);
  for (const std::string& part :
       {"validate: map '" + path("lost_hand.h5") + "': the map's hand 'panda_hand'",
        std::string("is neither at the recorded path"), std::string("; pass --hand URDF")})
    EXPECT_NE(no_hand.out.find(part), std::string::npos) << no_hand.out;
  // -o never replaces a file that is not a task map (nor the hand) without --force.
  std::ofstream(path("notes.txt")) << "my notes";
  const auto guard = testing::runTaskmap("validate " + map + " -o " + path("notes.txt"));
  EXPECT_NE(guard.code, 0);
  EXPECT_NE(guard.out.find("notes.txt"), std::string::npos) << guard.out;
  std::ifstream in(path("notes.txt"));
  std::string text;
  std::getline(in, text);
  EXPECT_EQ(text, "my notes");
}

}  // namespace
}  // namespace taskmap
