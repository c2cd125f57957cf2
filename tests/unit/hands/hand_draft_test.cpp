// draftHandSidecar (taskmap hand-init): the drafts of the bundled hands against their
// hand-written sidecars, and of the real Franka and Allegro hands (tests/data/real), load.
#include "taskmap/hands/hand_draft.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"
#include "taskmap/hands/hand_model.hpp"

namespace taskmap {
namespace {

using json = nlohmann::json;

/// The approach axis of a hand in its URDF root frame.
Eigen::Vector3d approachInRoot(const HandModel& h) {
  return h.rootToPalm().linear() * h.approachAxis();
}

struct Loaded {
  SidecarDraft draft;
  json js;
  HandModel hand;
};

Loaded draftAndLoad(const std::string& urdf) {
  SidecarDraft d = draftHandSidecar(urdf);
  for (const auto& n : d.notes) std::cout << "  " << n << "\n";
  for (const auto& u : d.undecided) std::cout << "  undecided: " << u << "\n";
  EXPECT_TRUE(d.undecided.empty()) << urdf;
  const std::string tmp =
      ::testing::TempDir() + "/draft_" + std::filesystem::path(urdf).stem().string() + ".hand.json";
  std::ofstream(tmp) << d.json;
  json js = json::parse(d.json);
  return {d, js, HandModel::load(urdf, tmp)};
}

// The bundled hands' sidecars were written by hand: the draft finds the same palm link and
// fingers, and an approach axis within 35 degrees of theirs.
TEST(HandDraft, BundledHandsMatchTheirWrittenSidecars) {
  for (const char* name : {"panda", "barrett", "humanoid"}) {
    const std::string urdf = std::string(TASKMAP_HANDS_DIR) + "/" + name + "/" + name + ".urdf";
    const HandModel written = HandModel::load(urdf);
    std::cout << name << ":\n";
    const Loaded d = draftAndLoad(urdf);
    EXPECT_EQ(d.js["palm_link"], written.links()[written.palmLink()].name) << name;
    EXPECT_EQ(d.hand.fingerNames().size(), written.fingerNames().size()) << name;
    const double angle =
        std::acos(std::clamp(approachInRoot(d.hand).dot(approachInRoot(written)), -1.0, 1.0));
    EXPECT_LT(angle, 35.0 * M_PI / 180.0)
        << name << ": approach " << approachInRoot(d.hand).transpose() << " vs written "
        << approachInRoot(written).transpose();
    EXPECT_FALSE(d.hand.closing().empty()) << name;
  }
}

// The real hands (tests/data/real): the Franka hand's jaw closes toward its lower limit (0 m),
// opened at 0.04 m in the preshape, its second jaw following by <mimic>; the Allegro hand's
// palm faces +x of base_link (tests/data/real/README.md) and its fingers close.
TEST(HandDraft, RealFrankaAndAllegroHandsLoad) {
  const std::string real = std::string(TEST_DATA_DIR) + "/real/hands";
  const std::string franka = real + "/franka_hand/franka_hand.urdf";
  const std::string allegro = real + "/allegro_right/allegro_hand_description_right.urdf";
  if (!std::filesystem::exists(franka) || !std::filesystem::exists(allegro))
    GTEST_SKIP() << "real hands not in " << real;
  std::cout << "franka:\n";
  const Loaded f = draftAndLoad(franka);
  EXPECT_EQ(f.js["palm_link"], "panda_hand");
  ASSERT_EQ(f.js["closing"].size(), 1u);
  EXPECT_EQ(f.js["closing"][0]["joint"], "panda_finger_joint1");
  EXPECT_EQ(f.js["closing"][0]["toward"], "lower");
  EXPECT_DOUBLE_EQ(f.js["preshape"]["panda_finger_joint1"].get<double>(), 0.04);
  EXPECT_EQ(f.hand.fingerNames().size(), 2u);
  EXPECT_GT(approachInRoot(f.hand).z(), 0.99);  // the jaws point along the hand's z
  std::cout << "allegro:\n";
  const Loaded a = draftAndLoad(allegro);
  EXPECT_EQ(a.hand.fingerNames().size(), 4u);
  EXPECT_GE(a.js["closing"].size(), 8u);
  EXPECT_GT(approachInRoot(a.hand).x(), 0.5) << approachInRoot(a.hand).transpose();
}

// A URDF without collision geometry: the draft names the field it cannot decide.
TEST(HandDraft, UndecidedFieldIsNamed) {
  const std::string urdf = ::testing::TempDir() + "/no_geometry_hand.urdf";
  std::ofstream(urdf) << R"(<robot name="bare"><link name="base"/><link name="finger"/>
    <joint name="j" type="revolute"><parent link="base"/><child link="finger"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="1" effort="1" velocity="1"/></joint></robot>)";
  const SidecarDraft d = draftHandSidecar(urdf);
  ASSERT_EQ(d.undecided.size(), 1u);
  EXPECT_NE(d.undecided[0].find("palm_link"), std::string::npos) << d.undecided[0];
  EXPECT_TRUE(d.json.empty());
}

TEST(HandDraft, UnreadableUrdfIsAnError) {
  EXPECT_THROW(draftHandSidecar("/nonexistent/hand.urdf"), Error);
}

}  // namespace
}  // namespace taskmap
