// Sidecar keys "coupled" and "grasp" (hands/src/hand_model_grasping.cpp).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "error_matchers.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/hands/hand_model.hpp"

namespace taskmap {
namespace {

const std::string kPandaUrdf = std::string(TASKMAP_HANDS_DIR) + "/panda/panda.urdf";

// The bundled panda's sidecar with `extra` JSON members added (written to a temporary file).
std::string pandaSidecar(const std::string& name, const std::string& extra) {
  const std::string path =
      (std::filesystem::temp_directory_path() /
       ("taskmap_grasping_keys_" + std::to_string(::getpid()) + "_" + name + ".hand.json"))
          .string();
  std::ofstream f(path);
  f << R"({"palm_link": "panda_hand", "palm_frame": {"xyz": [0, 0, 0.0584]},
    "approach_axis": [0, 0, 1], "squeeze": 0.001,
    "preshape": {"panda_finger_joint1": 0.04, "panda_finger_joint2": 0.04},
    "closing": [{"joint": "panda_finger_joint1", "toward": "lower"},
                {"joint": "panda_finger_joint2", "toward": "lower"}],
    "fingers": {"left": ["panda_leftfinger"], "right": ["panda_rightfinger"]})"
    << (extra.empty() ? "" : ", " + extra) << "}";
  return path;
}

void expectError(const std::string& name, const std::string& extra,
                 std::initializer_list<std::string> fragments) {
  const std::string sidecar = pandaSidecar(name, extra);
  EXPECT_TRUE(testing::throwsError([&] { HandModel::load(kPandaUrdf, sidecar); }, fragments))
      << extra;
  std::filesystem::remove(sidecar);
}

TEST(HandGraspingKeys, DefaultsArePalmGraspsWithoutCoupling) {
  const HandModel h = HandModel::load(kPandaUrdf);
  EXPECT_EQ(h.graspMode(), GraspMode::kPalm);
  EXPECT_EQ(h.standoff(), 0.0);
  EXPECT_TRUE(h.coupledClosing().empty());
}

TEST(HandGraspingKeys, CoupledGroupAndFingertipMode) {
  const std::string sidecar =
      pandaSidecar("ok", R"("coupled": [["panda_finger_joint2", "panda_finger_joint1"]],
                            "grasp": {"mode": "fingertip", "standoff": 0.015})");
  const HandModel h = HandModel::load(kPandaUrdf, sidecar);
  std::filesystem::remove(sidecar);
  ASSERT_EQ(h.coupledClosing().size(), 1u);
  EXPECT_EQ(h.coupledClosing()[0], (std::vector<int>{1, 0}));  // indexes into closing()
  EXPECT_EQ(h.graspMode(), GraspMode::kFingertip);
  EXPECT_DOUBLE_EQ(h.standoff(), 0.015);
  // The test hands of tests/data/hands.
  const HandModel r = HandModel::load(std::string(TEST_DATA_DIR) +
                                      "/hands/robotiq_2f85_style/robotiq_2f85_style.urdf");
  EXPECT_EQ(r.graspMode(), GraspMode::kFingertip);
  EXPECT_DOUBLE_EQ(r.standoff(), 0.02);
  EXPECT_NEAR(r.upperLimits()[0] * 2.0, 0.085, 1e-12);  // the 85 mm stroke
}

TEST(HandGraspingKeys, BadValuesNameTheKey) {
  expectError("not_array", R"("coupled": "panda_finger_joint1")", {"coupled must be an array"});
  expectError("single", R"("coupled": [["panda_finger_joint1"]])", {"coupled[0]", "at least two"});
  expectError("unknown", R"("coupled": [["panda_finger_joint1", "nope"]])",
              {"coupled[0][1]", "'nope'", "not listed in \"closing\""});
  expectError("twice", R"("coupled": [["panda_finger_joint1", "panda_finger_joint1"]])",
              {"coupled[0]", "second time"});
  expectError("mode", R"("grasp": {"mode": "pinch"})", {"grasp.mode", "\"fingertip\""});
  expectError("key", R"("grasp": {"mode": "fingertip", "stand_off": 0.01})",
              {"grasp: unknown key 'stand_off'"});
  expectError("range", R"("grasp": {"mode": "fingertip", "standoff": -0.01})",
              {"grasp.standoff", "[0, 0.5]"});
  expectError("palm", R"("grasp": {"standoff": 0.01})",
              {"grasp.standoff applies to fingertip grasps"});
}

}  // namespace
}  // namespace taskmap
