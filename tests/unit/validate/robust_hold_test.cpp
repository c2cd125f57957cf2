// The robust hold test: its variants (names, the poses they test, the second decomposition only
// where it differs), a squeezing grasp that holds under every variant, a margin that fails a
// grasp the protocol passes, the stop at the first failure, and the settled-push stop against
// the full protocol.
#include "taskmap/validate/robust_hold.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "build_fixtures.hpp"
#include "error_matchers.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

/// Palm above the 4 x 5 x 12 cm box, approach down (-z), jaws closing along object x.
Pose topGrasp(double height) {
  return testing::topBoxGrasp(height);
}

const Eigen::Vector2d kSqueeze(0.02, 0.02);  // jaws where the box's faces are

const RobustHoldTester& pandaOnBox() {
  static const RobustHoldTester tester(testing::pandaHand(), testing::boxObject());
  return tester;
}

TEST(RobustHold, VariantsAreNamedAndMoveThePalmInItsOwnFrame) {
  const auto& v = pandaOnBox().variants();
  std::vector<std::string> names;
  for (const HoldVariant& x : v) names.push_back(x.name());
  // The box is convex: its second decomposition is its hull again, so there is no such variant.
  // Test order: the variants that fail most often first (robust_hold.cpp).
  const std::vector<std::string> expected = {"nominal", "turn+y",  "turn-y",  "turn+x",  "friction",
                                             "turn-x",  "turn-z",  "turn+z",  "shift+z", "shift-z",
                                             "shift-y", "shift+y", "shift-x", "shift+x"};
  EXPECT_EQ(names, expected);
  EXPECT_EQ(robustVariants(RobustHoldOptions{}, true).back().name(), "decomposition");
  const Pose palm = topGrasp(0.061);
  const Pose shifted = v[8].apply(palm);  // shift+z: 1 mm along the palm's z (object -z)
  EXPECT_NEAR((shifted.position - palm.position - Eigen::Vector3d(0, 0, -0.001)).norm(), 0.0,
              1e-12);
  const Pose turned = v[7].apply(palm);  // turn+z: 2 degrees about the palm's z, in place
  EXPECT_NEAR((turned.position - palm.position).norm(), 0.0, 1e-12);
  EXPECT_NEAR(rotationAngle(turned.orientation, palm.orientation), 2.0 * M_PI / 180.0, 1e-9);
  EXPECT_EQ(v[4].apply(palm).position, palm.position);  // friction: the same pose
}

TEST(RobustHold, JawsSqueezingTheBoxHoldUnderEveryVariant) {
  const RobustHoldResult r = pandaOnBox().test(topGrasp(0.061), kSqueeze);
  EXPECT_TRUE(r.nominal.holds);
  EXPECT_TRUE(r.robust);
  EXPECT_EQ(r.tested, static_cast<int>(pandaOnBox().variants().size()));
  EXPECT_EQ(r.held, r.tested);
  EXPECT_DOUBLE_EQ(r.share(), 1.0);
  for (auto h : r.variant_held) EXPECT_EQ(h, 1);
  EXPECT_LT(r.push_translation, pandaOnBox().options().margin_translation);
  EXPECT_LT(r.push_rotation, pandaOnBox().options().margin_rotation);
  EXPECT_GT(r.steps, r.nominal.steps);
}

// A margin of 10 micrometres: the protocol holds, the margin does not. With the protocol's label
// asked for, the nominal result is the protocol's; a build's tester stops at that first failure.
TEST(RobustHold, AMarginTheGraspExceedsFailsItWhereTheProtocolHolds) {
  RobustHoldOptions o;
  o.margin_translation = 1e-5;
  o.all_variants = true;
  const RobustHoldTester all(testing::pandaHand(), testing::boxObject(), o);
  const RobustHoldResult r = all.test(topGrasp(0.061), kSqueeze);
  EXPECT_TRUE(r.nominal.holds) << holdStatusName(r.nominal.status);
  EXPECT_FALSE(r.robust);
  EXPECT_EQ(r.variant_held[0], 0);
  EXPECT_EQ(r.tested, static_cast<int>(all.variants().size()));
  EXPECT_LT(r.share(), 1.0);
  o.all_variants = false;
  o.protocol_label = false;
  const RobustHoldTester first(testing::pandaHand(), testing::boxObject(), o);
  const RobustHoldResult f = first.test(topGrasp(0.061), kSqueeze);
  EXPECT_FALSE(f.robust);
  EXPECT_EQ(f.tested, 1);
  EXPECT_TRUE(f.nominal.margin_exceeded);
  EXPECT_FALSE(f.nominal.holds);
  EXPECT_EQ(f.variant_held[1], 255);
}

TEST(RobustHold, AGraspThatDoesNotHoldIsNotRobust) {
  const RobustHoldResult r = pandaOnBox().test(topGrasp(0.5), Eigen::Vector2d(0.04, 0.04));
  EXPECT_FALSE(r.nominal.holds);
  EXPECT_FALSE(r.robust);
  EXPECT_EQ(r.tested, 1);
}

// The settled stop ends a holding grasp's pushes early and gives the protocol's verdict and
// (within the settled drift) its displacement; a grasp that slips fails as in the full protocol.
TEST(RobustHold, SettledPushesEndEarlyWithTheFullProtocolsVerdict) {
  HoldTestOptions full;
  full.settle_stop = false;
  const HoldTester slow(testing::pandaHand(), testing::boxObject(), full);
  const HoldTester& fast = pandaOnBox().nominal();
  ASSERT_TRUE(fast.options().settle_stop);
  const HoldResult a = slow.test(topGrasp(0.061), kSqueeze);
  const HoldResult b = fast.test(topGrasp(0.061), kSqueeze);
  EXPECT_TRUE(a.holds);
  EXPECT_TRUE(b.holds);
  EXPECT_LT(b.steps, a.steps / 2);
  EXPECT_NEAR(b.max_translation, a.max_translation, 1e-3);
  const HoldResult c = slow.test(topGrasp(0.5), Eigen::Vector2d(0.04, 0.04));
  const HoldResult d = fast.test(topGrasp(0.5), Eigen::Vector2d(0.04, 0.04));
  EXPECT_EQ(c.status, d.status);
  EXPECT_EQ(c.failed_direction, d.failed_direction);
}

TEST(RobustHold, OptionsOutOfRangeAreRefusedByName) {
  RobustHoldOptions o;
  o.palm_shift = -0.001;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"palm_shift"}));
  o = {};
  o.margin_rotation = 0.0;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"margin_rotation"}));
  o = {};
  o.decomposition_pieces = 65;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"decomposition_pieces"}));
  o = {};
  o.hold.settle_window = 0;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"settle_window"}));
}

TEST(RobustHold, ParamsJsonNamesTheVariantsAndThresholds) {
  const std::string j = robustParamsJson(pandaOnBox().options(), pandaOnBox().variants());
  for (const char* key : {"\"variants\"", "\"shift+z\"", "\"margin_translation\":0.01",
                          "\"friction\":0.5", "\"palm_turn\""})
    EXPECT_NE(j.find(key), std::string::npos) << key << " in " << j;
}

}  // namespace
}  // namespace taskmap
