// Parallel jaws closed from open at a fixed pose (grasp_sim/jaw_closing.hpp): closed-form
// outcomes on boxes between the jaws of the real Franka hand (tests/data/real) and the bundled
// panda with a mimic jaw; jaws that miss or intersect the object are reported; hands that are
// not parallel jaws are refused.
#include "taskmap/grasp_sim/jaw_closing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "error_matchers.hpp"
#include "grasp_fixtures.hpp"
#include "taskmap/core/error.hpp"
#include "test_meshes.hpp"

namespace taskmap {
namespace {

using taskmap::testing::errorMessage;
using taskmap::testing::fromAbove;

HandModel frankaHand() {
  return HandModel::load(std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/franka_hand.urdf");
}

// The inner face of the Franka hand's fingertip pad lies 0.02 mm past its joint's origin
// (box at y = 7.58 mm, 15.2 mm thick): a jaw at q touches a face at q - 2e-5.
constexpr double kPadInset = 7.6e-3 - 7.58e-3;

ObjectModel box(double width, const Eigen::Vector3d& centre = Eigen::Vector3d::Zero()) {
  return ObjectModel::fromMesh(testing::makeBox(width, 0.03, 0.10, centre), "box");
}

// The palm 6 cm above the box's centre, approach down: the fingertip pads (36 to 54.5 mm
// along the approach) are level with the box's upper half; the jaws close along object x.
const Pose kAbove = fromAbove(Eigen::Vector3d(0.0, 0.0, 0.06));

TEST(JawClosing, ABoxBetweenOpenJawsClosesThemToHalfItsWidth) {
  const HandModel hand = frankaHand();
  for (const double w : {0.02, 0.04, 0.07}) {
    SCOPED_TRACE(w);
    const JawCloser closer(hand, box(w));
    ASSERT_EQ(closer.jawNames().size(), 2u);
    const JawClosing c = closer.close(kAbove);
    EXPECT_EQ(c.status, JawClosingStatus::kClosed) << toString(c.status);
    ASSERT_EQ(c.joints.size(), 1);
    EXPECT_NEAR(c.joints[0], w / 2 + kPadInset, 1e-12);
    EXPECT_NEAR(c.joints[0], w / 2, 1e-4);
    // Each jaw travels from the open 4 cm to the face.
    ASSERT_EQ(c.sweep.size(), 2u);
    for (double s : c.sweep) EXPECT_NEAR(s, 0.04 - w / 2 - kPadInset, 1e-12);
    EXPECT_NEAR(c.object_shift, 0.0, 1e-12);
  }
}

TEST(JawClosing, AnOffCentreBoxSlidesBetweenTheJaws) {
  // 8 mm off centre along the closing axis: one jaw touches 8 mm early and pushes the box over
  // until the other touches; the jaws still close to half its width.
  const double w = 0.04, off = 0.008;
  const JawCloser closer(frankaHand(), box(w, Eigen::Vector3d(off, 0.0, 0.0)));
  const JawClosing c = closer.close(kAbove);
  ASSERT_EQ(c.status, JawClosingStatus::kClosed) << toString(c.status);
  EXPECT_NEAR(c.joints[0], w / 2 + kPadInset, 1e-12);
  EXPECT_NEAR(std::abs(c.sweep[0] - c.sweep[1]), 2 * off, 1e-12);
  EXPECT_NEAR(c.object_shift, off, 1e-12);
}

TEST(JawClosing, TurnedPosesAndTheBundledMimicPandaGiveTheSameWidth) {
  // The box turned about the approach axis by 30 degrees: the jaws meet its edges, not its
  // faces. Palm-frame geometry: the pads close along palm y, 2 cm pads.
  const double w = 0.03;
  Pose turned = kAbove;
  turned.orientation =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * kAbove.orientation;  // about object z
  const JawCloser franka(frankaHand(), box(w));
  const JawClosing c = franka.close(turned);
  ASSERT_EQ(c.status, JawClosingStatus::kClosed);
  // The 3 cm x 3 cm section's extent across the jaws' line through its centre, turned 0.3 rad:
  // the pads (17.5 mm across) span the corner; at least half the width, at most the diagonal.
  EXPECT_GT(c.joints[0], w / 2);
  EXPECT_LT(c.joints[0], w / std::sqrt(2.0) + 1e-3);
  const HandModel mimic = HandModel::load(testing::testHandPath("panda_mimic"));
  const JawClosing m = JawCloser(mimic, box(w)).close(kAbove);
  ASSERT_EQ(m.status, JawClosingStatus::kClosed);
  EXPECT_NEAR(m.joints[0], w / 2, 1e-3);
}

TEST(JawClosing, JawsThatMissOrIntersectTheObjectAreReported) {
  const HandModel hand = frankaHand();
  // The box 20 cm beside the hand: both jaws sweep past it and close on nothing.
  JawClosing c = JawCloser(hand, box(0.04, Eigen::Vector3d(0.0, 0.2, 0.0))).close(kAbove);
  EXPECT_EQ(c.status, JawClosingStatus::kMissed);
  EXPECT_TRUE(std::isinf(c.sweep[0]) && std::isinf(c.sweep[1]));
  EXPECT_EQ(c.joints[0], 0.0);  // the closed limit
  // The palm 20 cm above: the fingertips end above the box.
  c = JawCloser(hand, box(0.04)).close(fromAbove(Eigen::Vector3d(0.0, 0.0, 0.25)));
  EXPECT_EQ(c.status, JawClosingStatus::kMissed);
  // A 9 cm box is wider than the open jaws (8 cm): both intersect it before closing.
  c = JawCloser(hand, box(0.09)).close(kAbove);
  EXPECT_EQ(c.status, JawClosingStatus::kOverlaps);
  EXPECT_EQ(c.sweep, (std::vector<double>{0.0, 0.0}));
  EXPECT_EQ(c.joints[0], 0.04);  // open
  // A 4 cm box 3.5 cm off centre (x from 15 to 55 mm): one pad is inside it, the other sweeps
  // from -40 mm to its face at 15 mm; the joint closes by that sweep over both jaws' speed.
  c = JawCloser(hand, box(0.04, Eigen::Vector3d(0.035, 0.0, 0.0))).close(kAbove);
  EXPECT_EQ(c.status, JawClosingStatus::kOverlaps);
  ASSERT_EQ(c.sweep.size(), 2u);
  EXPECT_EQ(std::min(c.sweep[0], c.sweep[1]), 0.0);
  EXPECT_NEAR(std::max(c.sweep[0], c.sweep[1]), 0.055 - kPadInset, 1e-12);
  EXPECT_NEAR(c.joints[0], 0.04 - (0.055 - kPadInset) / 2, 1e-12);
  // A jaw inside the object: the box wraps the whole hand.
  c = JawCloser(hand, ObjectModel::fromMesh(testing::makeBox(0.5, 0.5, 0.5), "big")).close(kAbove);
  EXPECT_EQ(c.status, JawClosingStatus::kOverlaps);
  EXPECT_STREQ(toString(JawClosingStatus::kMissed), "missed");
}

TEST(JawClosing, HandsThatAreNotParallelJawsAreRefused) {
  // The bundled panda closes its two fingers with two joints; the Barrett hand turns fingers.
  for (const char* name : {"panda", "barrett"}) {
    const std::string m = errorMessage([&] { JawCloser(testing::referenceHand(name), box(0.04)); });
    EXPECT_NE(m.find("is not a parallel-jaw gripper"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace taskmap
