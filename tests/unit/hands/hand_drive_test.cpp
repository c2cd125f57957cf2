// How the physics models drive a hand's joints (hands' hand_drive.hpp): the knuckle jaw's
// closed form per actuator and per URDF joint, coupled parallel jaws, a dexterous hand, the
// revolute gripper option off.
#include "taskmap/hands/hand_drive.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace taskmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

HandModel knuckleJaw() {
  return HandModel::load(std::string(TEST_DATA_DIR) + "/hands/knuckle_jaw/knuckle_jaw.urdf");
}

/// Index into HandModel::joints() of the URDF joint `name`.
std::size_t joint(const HandModel& hand, const std::string& name) {
  for (std::size_t k = 0; k < hand.joints().size(); ++k)
    if (hand.joints()[k].name == name) return k;
  ADD_FAILURE() << "no joint " << name;
  return 0;
}

TEST(HandDrive, TheKnuckleJawsTipsPressWithTheJawForceInBothModels) {
  // tests/data/hands/knuckle_jaw: each pad rides on a 0.04 m knuckle leaning 20 degrees outward
  // at q = 0 (the pad joint at the knuckle's tip, the finger's deepest link's origin), so at
  // mid-range (0.4 rad) a tip closes at s = 0.04 cos(0.4 rad - 20 deg) m per radian of its
  // knuckle toward the other tip. Relative 1e-5: the URDF gives the lean to 7 digits.
  const HandModel hand = knuckleJaw();
  const DriveOptions o;
  const double s = 0.04 * std::cos(0.4 - 20.0 * M_PI / 180.0), tol = 1e-5;
  const RevoluteGripper g = revoluteGripper(hand, o);
  EXPECT_NEAR(g.lever, 2.0 * s, tol * s);
  // One actuator with the mimics rigid (MuJoCo): both tips through it.
  const std::vector<JointDrive> act = actuatorDrives(hand, o);
  ASSERT_EQ(act.size(), 1u);
  EXPECT_NEAR(act[0].kp, o.kp_prismatic * 2.0 * s * s, tol * o.kp_prismatic * s * s);
  EXPECT_NEAR(act[0].limit, o.jaw_force * 2.0 * s, tol * o.jaw_force * s);
  // A servo per joint (Bullet): each knuckle presses its own tip with jaw_force; the pads'
  // joints, whose turning does not move the tips, hold the linkage with the actuator's drive.
  const std::vector<JointDrive> per = jointDrives(hand, o);
  ASSERT_EQ(per.size(), hand.joints().size());
  for (const char* knuckle : {"finger_joint", "right_knuckle_joint"}) {
    SCOPED_TRACE(knuckle);
    const JointDrive& d = per[joint(hand, knuckle)];
    EXPECT_NEAR(d.kp, o.kp_prismatic * s * s, tol * o.kp_prismatic * s * s);
    EXPECT_NEAR(d.limit, o.jaw_force * s, tol * o.jaw_force * s);
  }
  for (const char* pad : {"left_pad_joint", "right_pad_joint"}) {
    SCOPED_TRACE(pad);
    EXPECT_EQ(per[joint(hand, pad)].kp, g.kp);
    EXPECT_EQ(per[joint(hand, pad)].limit, g.torque);
  }
}

TEST(HandDrive, OffTheRevoluteGripperIsADexterousHand) {
  const HandModel hand = knuckleJaw();
  DriveOptions o;
  o.revolute_gripper_force = false;
  EXPECT_EQ(revoluteGripper(hand, o).lever, 0.0);
  EXPECT_EQ(actuatorDrives(hand, o)[0].kp, o.kp_revolute);
  EXPECT_EQ(actuatorDrives(hand, o)[0].limit, kInf);
  for (const JointDrive& d : jointDrives(hand, o)) {
    EXPECT_EQ(d.kp, o.kp_revolute);
    EXPECT_EQ(d.limit, kInf);
  }
}

TEST(HandDrive, CoupledJawsAndADexterousHandKeepTheProtocolsDrives) {
  // The real Franka hand: finger_joint2 mimics finger_joint1. The one actuator drags the second
  // jaw along (twice the jaw force through the equality); each joint's own servo presses with
  // the jaw force.
  const HandModel franka =
      HandModel::load(std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/franka_hand.urdf");
  const DriveOptions o;
  const std::vector<JointDrive> act = actuatorDrives(franka, o);
  ASSERT_EQ(act.size(), 1u);
  EXPECT_EQ(act[0].kp, o.kp_prismatic);
  EXPECT_EQ(act[0].limit, 2.0 * o.jaw_force);
  const std::vector<JointDrive> per = jointDrives(franka, o);
  int jaws = 0;
  for (std::size_t k = 0; k < per.size(); ++k) {
    if (franka.joints()[k].type != JointType::kPrismatic) continue;
    ++jaws;
    EXPECT_EQ(per[k].kp, o.kp_prismatic);
    EXPECT_EQ(per[k].limit, o.jaw_force);
  }
  EXPECT_EQ(jaws, 2);
  // The barrett (revolute fingers, several actuated joints): kp_revolute, no limit.
  const HandModel barrett =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  EXPECT_EQ(revoluteGripper(barrett, o).lever, 0.0);
  for (const JointDrive& d : actuatorDrives(barrett, o)) {
    EXPECT_EQ(d.kp, o.kp_revolute);
    EXPECT_EQ(d.limit, kInf);
  }
  const std::vector<JointDrive> joints = jointDrives(barrett, o);
  for (std::size_t k = 0; k < joints.size(); ++k)
    EXPECT_EQ(joints[k].kp, barrett.joints()[k].type == JointType::kFixed ? 0.0 : o.kp_revolute);
}

}  // namespace
}  // namespace taskmap
