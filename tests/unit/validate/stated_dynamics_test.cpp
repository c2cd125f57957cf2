// The hold test with a hand's own dynamics (issue 52 item 2, docs/VALIDATION.md "A hand's own
// dynamics"): the real LEAP hand's MJCF states its masses, servos, damping and contact
// parameters; the scene uses them where stated, the protocol's values where silent, and records
// which; with stated_dynamics off, and for a URDF hand, the scene is the protocol's.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "build_fixtures.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/validate/hold_test.hpp"

namespace taskmap {
namespace {

const HandModel& leap() {
  static const HandModel h =
      HandModel::load(std::string(TEST_DATA_DIR) + "/real/hands/leap_hand_mjcf/right_hand.xml");
  return h;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(StatedDynamics, TheLeapHandsOwnDynamicsAreInTheScene) {
  const HoldTester tester(leap(), testing::boxObject());
  const std::string& x = tester.mjcf();
  // Its servos: kp 3, kv 0.01 (MuJoCo 2.2.2 has no kv: a <general> affine servo).
  EXPECT_EQ(count(x, "<general name=\"act_"), 16u);
  EXPECT_EQ(count(x, "gainprm=\"3\" biasprm=\"0 -3 -0.01\""), 16u);
  EXPECT_EQ(count(x, "ctrlrange=\"-0.314 2.23\""), 3u);  // the mcp class's ctrlrange
  EXPECT_EQ(count(x, "damping=\"0.029999999999999999\" armature=\"0\" frictionloss=\"0.001\""),
            16u);
  EXPECT_EQ(count(x, "fullinertia="), 17u + 1u);            // the links and the object
  EXPECT_EQ(count(x, "mass=\"0.23699999999999999\""), 1u);  // the palm's 0.237 kg
  EXPECT_NE(x.find("balanceinertia=\"true\""), std::string::npos);
  // Its contacts: friction 0.2 (0.5 on the tips) with the protocol's torsional 0.02.
  EXPECT_EQ(count(x, "friction=\"0.5 0.02 0.0001\""), 4u);
  EXPECT_EQ(count(x, "solref=\"0.0001 1\""), 71u);
  const auto j = nlohmann::json::parse(tester.info().hand_dynamics);
  EXPECT_EQ(j["source"], "MJCF");
  EXPECT_EQ(j["kp"]["model"], 16);
  EXPECT_EQ(j["forcerange"]["model"], 0);
  EXPECT_EQ(j["mass_inertia"]["model"], 17);
  EXPECT_EQ(j["geom_friction"]["model"], 71);
  EXPECT_EQ(j["contact_excludes"]["model"], 18);
  // The record without a model (what a build stores in its /validation params).
  EXPECT_EQ(handDynamicsJson(leap(), HoldTestOptions{}), tester.info().hand_dynamics);
}

TEST(StatedDynamics, OffTheSceneIsTheProtocols) {
  HoldTestOptions o;
  o.stated_dynamics = false;
  const HoldTester tester(leap(), testing::boxObject(), o);
  const std::string& x = tester.mjcf();
  EXPECT_EQ(count(x, "<position name=\"act_"), 16u);
  EXPECT_EQ(count(x, "kp=\"5\""), 16u);
  EXPECT_EQ(x.find("frictionloss"), std::string::npos);
  EXPECT_EQ(count(x, "fullinertia"), 1u);  // the object only
  EXPECT_EQ(x.find("balanceinertia"), std::string::npos);
  const auto j = nlohmann::json::parse(tester.info().hand_dynamics);
  EXPECT_EQ(j["used"], "the protocol's");
  EXPECT_EQ(j["kp"]["model"], 0);
  EXPECT_EQ(handDynamicsJson(leap(), o), tester.info().hand_dynamics);
  // A URDF hand states nothing: no record, the protocol's scene.
  const HandModel barrett =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  const HoldTester urdf(barrett, testing::boxObject());
  EXPECT_TRUE(urdf.info().hand_dynamics.empty());
  EXPECT_TRUE(handDynamicsJson(barrett, o).empty());
  EXPECT_EQ(urdf.mjcf().find("frictionloss"), std::string::npos);
}

TEST(StatedDynamics, ALeapGraspIsTestedBothWays) {
  // The same grasp under both dynamics simulates (no instability) and reports a status.
  for (const bool stated : {true, false}) {
    HoldTestOptions o;
    o.stated_dynamics = stated;
    const HoldTester tester(leap(), testing::boxObject(), o);
    Pose palm;
    palm.position = Eigen::Vector3d(0, 0, -0.2);
    const HoldResult r = tester.test(palm, leap().preshape());
    EXPECT_NE(r.status, HoldStatus::kUnstable) << stated;
    EXPECT_GT(r.steps, 0) << stated;
  }
}

}  // namespace
}  // namespace taskmap
