// The build's hold filter: contact Jacobians against finite differences of the hand's
// kinematics (revolute chains and mimic couplings), efforts from the squeeze target, and a
// build with the filter on stores only grasps it passes, counts the others as `unbalanced`, and
// gives the same map for any thread count. The squeeze-force test (on by default): its formula on
// a hand-made drive, against finite differences of the hand's kinematics on real grasps, and a
// build that refuses weak squeezes as `weak_squeeze` and records its threshold.
#include "taskmap/builder/hold_filter.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include <Eigen/Geometry>

#include "build_fixtures.hpp"
#include "error_matchers.hpp"
#include "taskmap/builder/build_params.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/builder/trial_block.hpp"
#include "taskmap/hands/hand_drive.hpp"
#include "taskmap/mapstore/grasp_contacts.hpp"

namespace taskmap {
namespace {

/// A grasp pose off the identity (rotation and translation) so frames matter.
Pose somePalm() {
  Pose p;
  p.position = Eigen::Vector3d(0.01, -0.02, 0.15);
  p.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  return p;
}

void checkJacobianByFiniteDifferences(const HandModel& hand) {
  const Pose palm = somePalm();
  const Eigen::Isometry3d to_object = palm.toIsometry();
  const Eigen::VectorXd q = 0.5 * (hand.lowerLimits() + hand.upperLimits());
  const std::vector<Eigen::Isometry3d> poses = hand.linkPoses(q);
  std::vector<Contact> contacts;
  std::vector<Eigen::Vector3d> local;  // contact point in its link frame
  for (std::size_t l = 0; l < hand.links().size(); ++l) {
    Contact c;
    c.link = static_cast<int>(l);
    local.emplace_back(0.01, 0.02, 0.03);
    c.point = to_object * poses[l] * local.back();
    contacts.push_back(c);
  }
  const SqueezeDrive drive = squeezeDrive(hand, palm, q, contacts, HoldFilterOptions{});
  ASSERT_EQ(drive.jacobians.size(), contacts.size());
  const double h = 1e-6;
  for (Eigen::Index j = 0; j < q.size(); ++j) {
    Eigen::VectorXd qp = q, qm = q;
    qp(j) += h;
    qm(j) -= h;
    const auto pp = hand.linkPoses(qp), pm = hand.linkPoses(qm);
    for (std::size_t l = 0; l < contacts.size(); ++l) {
      const Eigen::Vector3d dp =
          (to_object * pp[l] * local[l] - to_object * pm[l] * local[l]) / (2.0 * h);
      EXPECT_LT((drive.jacobians[l].row(j).transpose() - dp).norm(), 1e-6)
          << hand.name() << " link " << hand.links()[l].name << " joint " << j;
    }
  }
}

TEST(HoldFilter, JacobiansMatchFiniteDifferences) {
  checkJacobianByFiniteDifferences(testing::pandaHand());  // prismatic jaws, one mimic
  checkJacobianByFiniteDifferences(
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf"));  // mimic
  checkJacobianByFiniteDifferences(
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf"));
}

TEST(HoldFilter, EffortsPushTowardsTheClampedSqueezeTarget) {
  const HandModel hand = HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  const Eigen::VectorXd q0 = hand.preshape();
  Eigen::VectorXd q = q0;
  q(1) = q0(1) + 0.5;            // a proximal joint closed by 0.5 rad
  q(3) = hand.upperLimits()(3);  // another at its limit: the squeeze target is clamped there
  HoldFilterOptions o;
  const SqueezeDrive d = squeezeDrive(hand, Pose{}, q, {}, o);
  EXPECT_NEAR(d.effort(1), o.kp_revolute * 0.1 * 0.5, 1e-12);  // kp (q0 + 1.1 (q - q0) - q)
  EXPECT_EQ(d.effort(3), 0.0);
  EXPECT_TRUE(
      testing::throwsError([&] { squeezeDrive(hand, Pose{}, Eigen::VectorXd::Zero(2), {}, o); },
                           {"2 joint values", "actuated joints"}));
  o.squeeze_fraction = 0.5;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"squeeze_fraction", "[1, 2]"}));
}

// With revolute_gripper_force, a one-joint revolute gripper (tests/data/hands/knuckle_jaw)
// presses with the validator's drive of it (hands' actuatorDrives): gain kp_prismatic x the
// tips' squared speeds, at most the jaw force at each tip; off (the default), kp_revolute
// without a limit.
TEST(HoldFilter, ARevoluteGripperPressesWithItsDrive) {
  const HandModel hand =
      HandModel::load(std::string(TEST_DATA_DIR) + "/hands/knuckle_jaw/knuckle_jaw.urdf");
  HoldFilterOptions o;
  EXPECT_FALSE(o.revolute_gripper_force);
  o.revolute_gripper_force = true;
  const RevoluteGripper g =
      revoluteGripper(hand, {o.kp_revolute, o.kp_prismatic, o.jaw_force, true});
  ASSERT_GT(g.lever, 0.0);
  o.squeeze_fraction = 1.5;  // far enough past the grasp to reach the drive's limit
  for (const double closed : {0.002, 0.5}) {  // a small squeeze below the limit, a large one at it
    SCOPED_TRACE(closed);
    const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, closed);
    const double squeeze = 0.5 * closed;  // q0 = 0: target 1.5 q, within the 0.8 rad limit
    const double expected = std::min(g.kp * squeeze, g.torque);
    EXPECT_NEAR(squeezeDrive(hand, Pose{}, q, {}, o).effort(0), expected, 1e-9 * g.torque);
    o.revolute_gripper_force = false;
    EXPECT_NEAR(squeezeDrive(hand, Pose{}, q, {}, o).effort(0), o.kp_revolute * squeeze, 1e-12);
    o.revolute_gripper_force = true;
  }
  EXPECT_LT(g.kp * 0.5 * 0.002, g.torque);
  EXPECT_GT(g.kp * 0.5 * 0.5, g.torque);
}

TEST(HoldFilter, ABuildStoresOnlyGraspsThatPassAndCountsTheOthers) {
  const HandModel barrett =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  BuildOptions o;
  o.seed = 5;
  o.valid_target = 6;
  o.threads = 1;
  o.hold_filter.enabled = true;
  const BuildResult one = buildMap(testing::boxObject(), barrett, o);
  ASSERT_EQ(one.status, BuildStatus::kComplete) << one.message;
  EXPECT_GT(one.map.sampling.outcomes.at("unbalanced"), 0u);
  const auto& mp = testing::boxObject().massProperties();
  for (std::size_t i = 0; i < one.map.grasps.size(); ++i) {
    const MapGrasps& g = one.map.grasps;
    const std::vector<Contact> contacts = graspContacts(g, i);
    const Eigen::VectorXd q = g.joints.row(static_cast<Eigen::Index>(i)).transpose();
    const SqueezeDrive d = squeezeDrive(barrett, g.poseAt(i), q, contacts, o.hold_filter);
    EXPECT_TRUE(
        squeezeBalance(contacts, d, mp.center_of_mass, mp.torque_scale, o.hold_filter.balance)
            .balanced)
        << "grasp " << i;
  }
  EXPECT_NE(one.map.sampling.params_json.find("\"hold_filter\":\"squeeze_balance\""),
            std::string::npos);
  o.threads = 2;
  const BuildResult two = buildMap(testing::boxObject(), barrett, o);
  EXPECT_EQ(one.map.grasps.pose, two.map.grasps.pose);
  EXPECT_EQ(one.map.sampling.outcomes, two.map.sampling.outcomes);
  // Off (the default), the map records no filter.
  o.hold_filter.enabled = false;
  const BuildResult off = buildMap(testing::boxObject(), barrett, o);
  EXPECT_EQ(off.map.sampling.outcomes.count("unbalanced"), 0u);
  EXPECT_EQ(off.map.sampling.params_json.find("hold_filter"), std::string::npos);
}

TEST(HoldFilter, UnbalancedTrialsRoundTripThroughBlocks) {
  TrialBlock block;
  block.first = 3;
  block.trials.resize(2);
  block.trials[0].status = GraspStatus::kOk;
  block.trials[0].unbalanced = true;
  block.trials[1].status = GraspStatus::kOk;
  const TrialBlock back = decodeTrialBlock(encodeTrialBlock(block), 2, "block");
  EXPECT_TRUE(back.trials[0].unbalanced);
  EXPECT_FALSE(back.trials[1].unbalanced);
  EXPECT_EQ(back.valid(), 0u);
}

TEST(HoldFilter, SqueezeForceIsTheEffortOverTheLeverOfAPressingJoint) {
  Contact c;
  c.normal = Eigen::Vector3d::UnitZ();  // outward: pressing is along -z
  SqueezeDrive d;
  d.effort = Eigen::Vector3d(0.2, 1.0, 3.0);
  Eigen::Matrix<double, Eigen::Dynamic, 3> jac(3, 3);
  jac << 0.0, 0.0, -0.05,  // presses: 0.2 N m over 0.05 m
      0.0, 0.0, 0.1,       // pulls the contact out of the object: no force
      0.1, 0.0, 0.0;       // slides it along the surface: no force
  d.jacobians = {jac};
  EXPECT_NEAR(squeezeForce({c}, d), 4.0, 1e-12);
  d.effort(1) = -1.0;  // now the second joint presses, 1 N m over 0.1 m
  EXPECT_NEAR(squeezeForce({c}, d), 10.0, 1e-12);
  d.effort.setZero();
  EXPECT_EQ(squeezeForce({c}, d), 0.0);
  EXPECT_TRUE(testing::throwsError(
      [&] {
        squeezeForce({c, c}, d);
      },
      {"squeeze force", "1 Jacobians for 2 contacts"}));
}

// An independent oracle on real grasps: the lever of each contact about each actuated joint from
// finite differences of the hand's forward kinematics, the effort from the squeeze target.
double squeezeForceByFiniteDifferences(const HandModel& hand, const Pose& palm,
                                       const Eigen::VectorXd& q,
                                       const std::vector<Contact>& contacts) {
  const Eigen::Isometry3d to_object = palm.toIsometry();
  const std::vector<Eigen::Isometry3d> poses = hand.linkPoses(q);
  const Eigen::VectorXd q0 = hand.preshape();
  const double h = 1e-6;
  double force = 0.0;
  for (Eigen::Index a = 0; a < q.size(); ++a) {
    // The hold test's servo at the grasp: kp (q0 + 1.1 (q - q0) - q), clamped target.
    const double target =
        std::clamp(q0(a) + 1.1 * (q(a) - q0(a)), hand.lowerLimits()(a), hand.upperLimits()(a));
    const double effort = 5.0 * (target - q(a));
    Eigen::VectorXd qp = q, qm = q;
    qp(a) += h;
    qm(a) -= h;
    const auto pp = hand.linkPoses(qp), pm = hand.linkPoses(qm);
    for (const Contact& c : contacts) {
      const auto l = static_cast<std::size_t>(c.link);
      const Eigen::Vector3d local = (to_object * poses[l]).inverse() * c.point;
      const Eigen::Vector3d v = (to_object * pp[l] * local - to_object * pm[l] * local) / (2 * h);
      if (v.norm() < 1e-9 || effort * v.dot(c.normal) >= 0.0) continue;
      force = std::max(force, std::abs(effort) / v.norm());
    }
  }
  return force;
}

TEST(HoldFilter, ABuildRefusesWeakSqueezesAndRecordsTheThreshold) {
  // The barrett on the reference cylinder with palm_enclose: its proximal links often touch at
  // once, 0.04-0.13 rad from the preshape (docs/METHOD.md §4e).
  const HandModel barrett =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  const ObjectModel cylinder =
      ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/cylinder.obj");
  BuildOptions o;
  o.sampler.kind = SamplerKind::kPalmEnclose;
  o.seed = 1;
  o.valid_target = 12;
  o.threads = 1;
  o.cluster = false;
  EXPECT_NEAR(o.min_squeeze_force, 1.0 / 1.2, 1e-15);
  const BuildResult on = buildMap(cylinder, barrett, o);
  ASSERT_EQ(on.status, BuildStatus::kComplete) << on.message;
  EXPECT_GT(on.map.sampling.outcomes.at("weak_squeeze"), 0u);
  o.min_squeeze_force = 0.0;
  const BuildResult off = buildMap(cylinder, barrett, o);
  EXPECT_EQ(off.map.sampling.outcomes.count("weak_squeeze"), 0u);
  int weak = 0;
  for (const BuildResult* r : {&on, &off}) {
    const MapGrasps& g = r->map.grasps;
    for (std::size_t i = 0; i < g.size(); ++i) {
      const std::vector<Contact> contacts = graspContacts(g, i);
      const Eigen::VectorXd q = g.joints.row(static_cast<Eigen::Index>(i)).transpose();
      const double f = graspSqueezeForce(barrett, g.poseAt(i), q, contacts);
      EXPECT_NEAR(f, squeezeForceByFiniteDifferences(barrett, g.poseAt(i), q, contacts),
                  1e-6 * std::max(1.0, f))
          << "grasp " << i;
      if (r == &on) {
        EXPECT_GE(f, 1.0 / 1.2) << "a stored grasp of the default build";
      }
      weak += f < 1.0 / 1.2 ? 1 : 0;
    }
  }
  EXPECT_GT(weak, 0) << "without the test the build stores weak squeezes";
  // The threshold is in the map's parameters; a map without it was built without the test.
  EXPECT_NEAR(buildParamsFromJson(on.map.sampling.params_json).options.min_squeeze_force, 1.0 / 1.2,
              1e-15);
  EXPECT_EQ(buildParamsFromJson("{}").options.min_squeeze_force, 0.0);
  // A threshold no grasp meets: nothing is stored, and the message names the option.
  o.min_squeeze_force = 1e6;
  o.max_trials = 40;
  const BuildResult none = buildMap(cylinder, barrett, o);
  EXPECT_EQ(none.status, BuildStatus::kNoGrasps);
  EXPECT_NE(none.message.find("--min-squeeze-force"), std::string::npos) << none.message;
  o.min_squeeze_force = -1.0;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"min_squeeze_force", ">= 0"}));
}

TEST(HoldFilter, WeakSqueezeTrialsRoundTripThroughBlocks) {
  TrialBlock block;
  block.first = 3;
  block.trials.resize(2);
  block.trials[0].status = GraspStatus::kOk;
  block.trials[0].weak_squeeze = true;
  block.trials[1].status = GraspStatus::kOk;
  block.trials[1].force_closure = true;
  TrialBlock back = decodeTrialBlock(encodeTrialBlock(block), 2, "block");
  EXPECT_TRUE(back.trials[0].weak_squeeze);
  EXPECT_FALSE(back.trials[1].weak_squeeze);
  EXPECT_EQ(back.valid(), 1u);
  block.trials[1].weak_squeeze = true;  // a weak squeeze cannot be force closure
  EXPECT_TRUE(testing::throwsError(
      [&] { back = decodeTrialBlock(encodeTrialBlock(block), 2, "block"); }, {"weak-squeeze"}));
}

}  // namespace
}  // namespace taskmap
