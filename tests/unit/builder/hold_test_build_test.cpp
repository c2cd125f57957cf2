// Builds that test each force-closure grasp in physics (BuildOptions::hold_test): the map holds
// only grasps that hold robustly, each with its labels, as many as asked for; the refused ones
// are counted; the result does not depend on the thread count; the labels travel through the
// trial blocks of a distributed build; the parameters record the test.
#include <gtest/gtest.h>

#include <string>

#include "build_fixtures.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/builder/trial_block.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/validate/robust_hold.hpp"

namespace taskmap {
namespace {

const HandModel& barrett() {
  static const HandModel hand =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  return hand;
}

/// A robust build of few grasps; the turns of the palm left out to keep the test short (the
/// variants' own tests are robust_hold_test.cpp's).
BuildOptions robustBuild(int threads) {
  BuildOptions o;
  o.seed = 1;
  o.valid_target = 3;
  o.threads = threads;
  o.hold_test = BuildHoldTest::kRobust;
  o.hold_test_options.palm_turn = 0.0;
  return o;
}

TEST(HoldTestBuild, StoresOnlyRobustGraspsWithTheirLabels) {
  const BuildResult one = buildMap(testing::boxObject(), barrett(), robustBuild(1));
  ASSERT_EQ(one.status, BuildStatus::kComplete) << one.message;
  const TaskMapData& map = one.map;
  ASSERT_EQ(map.grasps.size(), 3u);
  ASSERT_TRUE(map.validation.has_value());
  const MapValidation& v = *map.validation;
  EXPECT_EQ(v.holding(), 3u);
  EXPECT_EQ(v.robustCount(), 3u);
  EXPECT_NO_THROW(map.validate());
  EXPECT_EQ(v.variantCount(), 8u);  // nominal, friction, six shifts
  EXPECT_NE(v.robust_json.find("\"shift+z\""), std::string::npos);
  EXPECT_NE(map.sampling.params_json.find("\"hold_test\":\"robust\""), std::string::npos);
  EXPECT_NE(one.message.find("hold robustly"), std::string::npos) << one.message;
  EXPECT_GE(one.timing.hold_tests, 3u);
  EXPECT_GT(one.timing.hold_test_seconds, 0.0);
  // A stored grasp holds robustly when tested again on its own (the label is the test's).
  RobustHoldOptions o = robustBuild(1).hold_test_options;
  o.all_variants = true;
  const RobustHoldTester tester(barrett(), testing::boxObject(), o);
  const RobustHoldResult r =
      tester.test(map.grasps.poseAt(2), map.grasps.joints.row(2).transpose());
  EXPECT_TRUE(r.robust);
  EXPECT_EQ(r.push_translation, v.push_translation[2]);
  // Two threads: the same grasps, labels and outcome counts.
  const BuildResult two = buildMap(testing::boxObject(), barrett(), robustBuild(2));
  EXPECT_EQ(one.map.grasps.pose, two.map.grasps.pose);
  EXPECT_EQ(one.map.sampling.outcomes, two.map.sampling.outcomes);
  EXPECT_EQ(v.push_translation, two.map.validation->push_translation);
  EXPECT_EQ(v.variant_held, two.map.validation->variant_held);
}

// The grasps a robust build refuses are force closure by their contacts (outcome not_holding);
// without the test the same trials store them.
TEST(HoldTestBuild, RefusedGraspsAreCountedAndTheRawBuildStoresThem) {
  BuildOptions o = robustBuild(1);
  o.seed = 3;
  o.valid_target = 6;
  o.sampler.kind = SamplerKind::kMixed;  // mixed trials: some force closure fails physics
  const BuildResult robust = buildMap(testing::boxObject(), barrett(), o);
  ASSERT_EQ(robust.status, BuildStatus::kComplete) << robust.message;
  const auto refused = robust.map.sampling.outcomes.at("not_holding");
  EXPECT_GT(refused, 0u);
  o.hold_test = BuildHoldTest::kOff;
  o.max_trials = robust.map.sampling.trials;
  o.valid_target = 1000;
  const BuildResult raw = buildMap(testing::boxObject(), barrett(), o);
  EXPECT_EQ(raw.map.grasps.size(), 6u + refused);
  EXPECT_FALSE(raw.map.validation.has_value());
  EXPECT_EQ(raw.map.sampling.params_json.find("hold_test"), std::string::npos);
  // The nominal test keeps what holds under the protocol: at least the robust grasps.
  o.hold_test = BuildHoldTest::kNominal;
  const BuildResult nominal = buildMap(testing::boxObject(), barrett(), o);
  EXPECT_GE(nominal.map.grasps.size(), 6u);
  EXPECT_EQ(nominal.map.validation->holding(), nominal.map.grasps.size());
  EXPECT_TRUE(nominal.map.validation->robust_json.empty());
}

TEST(HoldTestBuild, LabelsRoundTripThroughBlocks) {
  TrialBlock block;
  block.first = 0;
  block.trials.resize(2);
  block.trials[0].status = GraspStatus::kOk;
  block.trials[0].not_holding = true;
  TrialOutcome& kept = block.trials[1];
  kept.status = GraspStatus::kOk;
  kept.force_closure = true;
  kept.grasp = std::make_unique<TrialGrasp>();
  kept.grasp->joints = Eigen::VectorXd::Zero(2);
  RobustHoldResult r;
  r.nominal.status = HoldStatus::kHolds;
  r.nominal.holds = true;
  r.nominal.push_translation = 0.002;
  r.robust = true;
  r.tested = r.held = 3;
  r.variant_held = {1, 1, 1};
  r.push_translation = 0.004;
  r.steps = 1234;
  kept.grasp->hold = r;
  const TrialBlock back = decodeTrialBlock(encodeTrialBlock(block), 2, "block");
  EXPECT_TRUE(back.trials[0].not_holding);
  EXPECT_EQ(back.valid(), 1u);
  ASSERT_TRUE(back.trials[1].grasp->hold.has_value());
  const RobustHoldResult& b = *back.trials[1].grasp->hold;
  EXPECT_TRUE(b.robust);
  EXPECT_EQ(b.variant_held, r.variant_held);
  EXPECT_EQ(b.push_translation, 0.004);
  EXPECT_EQ(b.nominal.push_translation, 0.002);
  EXPECT_EQ(b.steps, 1234);
  // A robust result that lost a variant, or a refused trial that claims force closure, is
  // malformed.
  kept.grasp->hold->variant_held = {1, 0, 1};
  EXPECT_THROW(decodeTrialBlock(encodeTrialBlock(block), 2, "block"), Error);
  kept.grasp->hold->variant_held = {1, 1, 1};
  block.trials[0].force_closure = true;
  EXPECT_THROW(decodeTrialBlock(encodeTrialBlock(block), 2, "block"), Error);
}

}  // namespace
}  // namespace taskmap
