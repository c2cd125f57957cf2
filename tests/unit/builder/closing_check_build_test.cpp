// The closing check in a build (BuildOptions::closing_check): refused trials are counted as
// `pushed`, every stored grasp passes the check again, the map is the same for any thread
// count, the parameters are recorded only when the check is on, and `pushed` trials round-trip
// through the blocks of taskmap-mpi.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "build_fixtures.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/builder/trial_block.hpp"
#include "taskmap/grasp_sim/closing_check.hpp"
#include "taskmap/validate/hold_test.hpp"

namespace taskmap {
namespace {

TEST(ClosingCheckBuild, StoresOnlyGraspsThatPassAndCountsTheOthers) {
  // The humanoid's closing pushes most of its force-closure grasps of the box away.
  const HandModel hand =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf");
  BuildOptions o;
  o.seed = 5;
  o.valid_target = 4;
  o.threads = 1;
  o.closing_check.mode = ClosingCheckMode::kClosing;
  o.sampler.kind = SamplerKind::kMixed;  // mixed grasps: most are pushed
  const BuildResult one = buildMap(testing::boxObject(), hand, o);
  ASSERT_EQ(one.status, BuildStatus::kComplete) << one.message;
  EXPECT_GT(one.map.sampling.outcomes.at("pushed"), 0u);
  EXPECT_GT(one.timing.closing_checks, 0u);
  EXPECT_GT(one.timing.closing_check_seconds, 0.0);
  const ClosingChecker checker(testing::boxObject(), hand, o.closing_check);
  for (std::size_t i = 0; i < one.map.grasps.size(); ++i) {
    const Eigen::VectorXd q = one.map.grasps.joints.row(static_cast<Eigen::Index>(i)).transpose();
    EXPECT_TRUE(checker.check(one.map.grasps.poseAt(i), q).holds) << "grasp " << i;
  }
  EXPECT_NE(one.map.sampling.params_json.find("\"closing_check\":\"closing\""), std::string::npos);
  o.threads = 2;
  const BuildResult two = buildMap(testing::boxObject(), hand, o);
  EXPECT_EQ(one.map.grasps.pose, two.map.grasps.pose);
  EXPECT_EQ(one.map.grasps.joints, two.map.grasps.joints);
  EXPECT_EQ(one.map.sampling.outcomes, two.map.sampling.outcomes);
  // Off (the default), the map records no check and no trial is pushed.
  o.closing_check.mode = ClosingCheckMode::kOff;
  const BuildResult off = buildMap(testing::boxObject(), hand, o);
  EXPECT_EQ(off.map.sampling.outcomes.count("pushed"), 0u);
  EXPECT_EQ(off.map.sampling.params_json.find("\"closing_"), std::string::npos);
  EXPECT_EQ(off.timing.closing_checks, 0u);
}

// The early verdict's jaw settings (ClosingCheckOptions::jaws: 20 solver iterations, torsional
// friction 0.02 m, warm-started drives) on the grasps of a default build of the panda's jaws on
// the box, labelled by the physics hold test (MuJoCo): nearly all hold, and with the reference
// settings (4 iterations, no torsional friction) the early verdict refuses most of those (the
// solver's grip stays too light: a 1 N push slides or turns the box past a threshold; on the
// 100 grasps of the VALIDATION.md maps 14 of 96 holding ones passed). With the jaws' settings
// it passes most of them (92 of 96 there). The price is precision: on this box it also passes
// most grasps the hold test drops (there 3 of 4; over the jaws' 500 labelled grasps precision
// 0.94 -> 0.86, docs/VALIDATION.md, second round).
TEST(ClosingCheckBuild, JawSettingsPassJawGraspsThatHoldInPhysics) {
  const HandModel hand = HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/panda/panda.urdf");
  BuildOptions o;
  o.seed = 1;
  o.valid_target = 10;
  o.threads = 1;
  o.cluster = false;
  o.sampler.kind = SamplerKind::kMixed;  // the sampler of the grasps the settings were chosen on
  const BuildResult built = buildMap(testing::boxObject(), hand, o);
  ASSERT_EQ(built.status, BuildStatus::kComplete) << built.message;
  const ClosingCheckOptions early = ClosingCheckOptions::earlyVerdict();
  ClosingCheckOptions plain = early;
  plain.jaws = ClosingCheckOptions::Jaws();
  const ClosingChecker light(testing::boxObject(), hand, plain);
  const ClosingChecker firm(testing::boxObject(), hand, early);
  const HoldTester validator(hand, testing::boxObject());
  int holding = 0, light_pass = 0, firm_pass = 0, light_false = 0, firm_false = 0;
  for (std::size_t i = 0; i < built.map.grasps.size(); ++i) {
    const Pose pose = built.map.grasps.poseAt(i);
    const Eigen::VectorXd q = built.map.grasps.joints.row(static_cast<Eigen::Index>(i)).transpose();
    const bool holds = validator.test(pose, q).holds;
    const bool a = light.check(pose, q).holds, b = firm.check(pose, q).holds;
    holding += holds ? 1 : 0;
    light_pass += holds && a ? 1 : 0;
    firm_pass += holds && b ? 1 : 0;
    light_false += !holds && a ? 1 : 0;
    firm_false += !holds && b ? 1 : 0;
  }
  std::printf(
      "holding %d of %zu; passed among them: reference %d, jaws %d; among the others: %d, %d\n",
      holding, built.map.grasps.size(), light_pass, firm_pass, light_false, firm_false);
  EXPECT_GE(holding, 7);
  EXPECT_LE(light_pass, holding / 2);
  EXPECT_GE(firm_pass, holding - 1);
  EXPECT_GE(firm_false, light_false);  // more passes also of those: the settings' price
}

TEST(ClosingCheckBuild, PushedTrialsRoundTripThroughBlocks) {
  TrialBlock block;
  block.first = 3;
  block.trials.resize(2);
  block.trials[0].status = GraspStatus::kOk;
  block.trials[0].pushed = true;
  block.trials[1].status = GraspStatus::kOk;
  block.trials[1].force_closure = true;
  const TrialBlock back = decodeTrialBlock(encodeTrialBlock(block), 2, "block");
  EXPECT_TRUE(back.trials[0].pushed);
  EXPECT_FALSE(back.trials[1].pushed);
  EXPECT_EQ(back.valid(), 1u);
  // A pushed trial that claims force closure is malformed.
  block.trials[0].force_closure = true;
  EXPECT_THROW(decodeTrialBlock(encodeTrialBlock(block), 2, "block"), Error);
}

}  // namespace
}  // namespace taskmap
