#include "taskmap/hands/hand_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "error_matchers.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

std::string handPath(const std::string& name) {
  return std::string(TASKMAP_HANDS_DIR) + "/" + name + "/" + name + ".urdf";
}
std::string dataPath(const std::string& file) {
  return std::string(TEST_DATA_DIR) + "/hands/" + file;
}

/// Expects HandModel::load to throw an Error whose message contains every given fragment.
void expectLoadError(const std::string& urdf, const std::string& sidecar,
                     std::initializer_list<std::string> fragments) {
  EXPECT_TRUE(testing::throwsError([&] { HandModel::load(urdf, sidecar); }, fragments))
      << urdf << " / " << sidecar;
}

TEST(HandModel, LoadsReferenceHands) {
  for (const char* n : {"panda", "barrett", "humanoid"}) {
    SCOPED_TRACE(n);
    const HandModel h = HandModel::load(handPath(n));
    EXPECT_FALSE(h.name().empty());
    EXPECT_EQ(h.urdfSha256().size(), 64u);
    EXPECT_EQ(h.preshape().size(), static_cast<Eigen::Index>(h.jointNames().size()));
    EXPECT_NEAR(h.approachAxis().norm(), 1.0, 1e-12);
    EXPECT_GT(h.reach(), 0.05);
    EXPECT_LT(h.reach(), 0.25);
    EXPECT_GT(h.rotationScale(), 0.03);
    EXPECT_FALSE(h.closing().empty());
    for (Eigen::Index i = 0; i < h.preshape().size(); ++i) {
      EXPECT_GE(h.preshape()[i], h.lowerLimits()[i]);
      EXPECT_LE(h.preshape()[i], h.upperLimits()[i]);
    }
    for (const auto& l : h.links()) {
      if (l.finger >= 0) {
        EXPECT_FALSE(l.shapes.empty()) << l.name;
      }
    }
  }
  EXPECT_EQ(HandModel::load(handPath("panda")).fingerNames().size(), 2u);
  EXPECT_EQ(HandModel::load(handPath("barrett")).fingerNames().size(), 3u);
  EXPECT_EQ(HandModel::load(handPath("humanoid")).fingerNames().size(), 5u);
}

TEST(HandModel, PandaKinematicsAndDimensions) {
  const HandModel h = HandModel::load(handPath("panda"));
  ASSERT_EQ(h.jointNames().size(), 2u);
  Eigen::VectorXd q(2);
  q << 0.03, 0.01;
  const auto poses = h.linkPoses(q);
  const int left = h.linkIndex("panda_leftfinger"), right = h.linkIndex("panda_rightfinger");
  ASSERT_GE(left, 0);
  ASSERT_GE(right, 0);
  // Palm frame sits at z = 0.0584 of the hand link: finger joint origins are at the palm origin.
  EXPECT_TRUE(poses[static_cast<std::size_t>(left)].translation().isApprox(
      Eigen::Vector3d(0, 0.03, 0), 1e-12));
  EXPECT_TRUE(poses[static_cast<std::size_t>(right)].translation().isApprox(
      Eigen::Vector3d(0, -0.01, 0), 1e-12));
  // Maximum opening 0.08 m between the inner finger faces.
  const auto open = h.linkPoses(h.upperLimits());
  const auto& ls = h.links()[static_cast<std::size_t>(left)].shapes.front();
  const double inner_left =
      (open[static_cast<std::size_t>(left)] * ls.origin).translation().y() - 0.5 * ls.box_size.y();
  EXPECT_NEAR(inner_left, 0.04, 1e-12);
  // Values are clamped to the limits.
  Eigen::VectorXd wild(2);
  wild << 1.0, -1.0;
  const auto clamped = h.linkPoses(wild);
  EXPECT_NEAR(clamped[static_cast<std::size_t>(left)].translation().y(), 0.04, 1e-12);
  EXPECT_NEAR(clamped[static_cast<std::size_t>(right)].translation().y(), 0.0, 1e-12);
  EXPECT_THROW(h.linkPoses(Eigen::VectorXd::Zero(3)), Error);
  EXPECT_DOUBLE_EQ(h.squeeze(), 0.001);
  // Farthest finger point in the open preshape: pad corner (0.01, 0.052, 0.045).
  EXPECT_NEAR(h.rotationScale(), std::sqrt(0.01 * 0.01 + 0.052 * 0.052 + 0.045 * 0.045), 1e-12);
  // Farthest hand point: a corner of the 0.06 x 0.20 x 0.0584 body, 0.0584 below the palm.
  EXPECT_NEAR(h.reach(), std::sqrt(0.03 * 0.03 + 0.1 * 0.1 + 0.0584 * 0.0584), 1e-12);
}

TEST(HandModel, BarrettMimicSpreadAndFingerLength) {
  const HandModel h = HandModel::load(handPath("barrett"));
  const int spread = h.jointIndex("f1_spread");
  ASSERT_GE(spread, 0);
  EXPECT_EQ(h.jointIndex("f2_spread"), -1);  // mimic joints are not actuated
  Eigen::VectorXd q = h.preshape();
  const auto p0 = h.linkPoses(q);
  const int f1 = h.linkIndex("f1_distal"), f2 = h.linkIndex("f2_distal");
  const int f3 = h.linkIndex("f3_distal");
  // Open fingers point straight along the approach axis; distal joint 0.07 m above the palm.
  EXPECT_TRUE(p0[static_cast<std::size_t>(f1)].translation().isApprox(
      Eigen::Vector3d(0.025, -0.05, 0.07), 1e-12));
  EXPECT_TRUE(p0[static_cast<std::size_t>(f3)].translation().isApprox(
      Eigen::Vector3d(0.0, 0.05, 0.07), 1e-12));
  // Spread pi/2: F1 turns about +z, F2 (mimic, axis -z) about -z: they close toward each other.
  q[spread] = M_PI / 2;
  Eigen::VectorXd closed = q;
  closed[h.jointIndex("f1_prox")] = 0.5;
  closed[h.jointIndex("f2_prox")] = 0.5;
  const auto pc = h.linkPoses(closed);
  const Eigen::Vector3d d1 =
      pc[static_cast<std::size_t>(f1)].translation() - Eigen::Vector3d(0.025, -0.05, 0);
  const Eigen::Vector3d d2 =
      pc[static_cast<std::size_t>(f2)].translation() - Eigen::Vector3d(-0.025, -0.05, 0);
  EXPECT_NEAR(d1.x(), -0.07 * std::sin(0.5), 1e-12);
  EXPECT_NEAR(d2.x(), 0.07 * std::sin(0.5), 1e-12);
  EXPECT_NEAR(d1.y(), 0.0, 1e-12);
  // Every link of finger 1 is driven by the spread joint and its own closing joints.
  const auto& drv = h.linkDrivers()[static_cast<std::size_t>(f1)];
  EXPECT_EQ(drv.size(), 3u);
  EXPECT_TRUE(h.linkDrivers()[static_cast<std::size_t>(h.palmLink())].empty());
  // Distal closes at a third of the proximal speed.
  for (const auto& c : h.closing()) {
    if (h.jointNames()[static_cast<std::size_t>(c.joint)] == "f1_dist") {
      EXPECT_NEAR(c.speed, 0.3333, 1e-12);
    }
  }
  // Lever of the proximal joint covers the finger (0.125 m plus the half-width).
  EXPECT_GE(h.jointLevers()[static_cast<std::size_t>(h.jointIndex("f1_prox"))], 0.125);
}

TEST(HandModel, HumanoidMimicDistalJoints) {
  const HandModel h = HandModel::load(handPath("humanoid"));
  EXPECT_EQ(h.jointIndex("index_dip"), -1);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(h.preshape().size(), 0.5);
  const Eigen::VectorXd all = h.allJointValues(q);
  int found = 0;
  for (std::size_t j = 0; j < h.joints().size(); ++j) {
    if (h.joints()[j].name == "index_dip") {
      EXPECT_NEAR(all[static_cast<Eigen::Index>(j)], 0.4, 1e-12);
      ++found;
    }
  }
  EXPECT_EQ(found, 1);
}

TEST(HandModel, MiniGripperSidecarValues) {
  const HandModel h = HandModel::load(dataPath("mini.urdf"));
  EXPECT_EQ(h.name(), "mini");
  EXPECT_TRUE(h.approachAxis().isApprox(Eigen::Vector3d::UnitZ()));  // normalised from [0,0,2]
  ASSERT_EQ(h.jointNames().size(), 2u);                              // ja and jbare; jb mimics ja
  EXPECT_DOUBLE_EQ(h.preshape()[h.jointIndex("ja")], 0.03);
  EXPECT_DOUBLE_EQ(h.preshape()[h.jointIndex("jbare")], 0.0);
  ASSERT_EQ(h.closing().size(), 1u);
  EXPECT_DOUBLE_EQ(h.closing()[0].target, 0.0);
  const auto poses = h.linkPoses(h.preshape());
  // Palm frame 0.01 above the base: the fingers' joint origin is at the palm origin, offset by q.
  EXPECT_TRUE(poses[static_cast<std::size_t>(h.linkIndex("finger_a"))].translation().isApprox(
      Eigen::Vector3d(0.03, 0, 0), 1e-12));
  EXPECT_TRUE(poses[static_cast<std::size_t>(h.linkIndex("finger_b"))].translation().isApprox(
      Eigen::Vector3d(-0.03, 0, 0), 1e-12));
  EXPECT_EQ(h.links()[static_cast<std::size_t>(h.linkIndex("finger_a"))].shapes.front().type,
            ShapeType::kCylinder);
  EXPECT_EQ(h.links()[static_cast<std::size_t>(h.linkIndex("finger_b"))].shapes.front().type,
            ShapeType::kSphere);
  EXPECT_TRUE(h.links()[static_cast<std::size_t>(h.palmLink())].palm);
}

TEST(HandModel, MeshCollisionShapeThroughAssimp) {
  const HandModel h = HandModel::load(dataPath("mesh_finger.urdf"));
  const auto& s = h.links()[static_cast<std::size_t>(h.linkIndex("finger_a"))].shapes;
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].type, ShapeType::kConvex);
  ASSERT_EQ(s[0].points.size(), 4u);
  EXPECT_NEAR(s[0].boundingRadius(), 0.02, 1e-12);  // scaled apex (0, 0, 0.02)
  EXPECT_NEAR(s[0].thickness(), 0.01, 1e-12);
}

TEST(HandModel, BadHandFilesGiveClearErrors) {
  expectLoadError(dataPath("does_not_exist.urdf"), "", {"cannot read URDF", "does_not_exist.urdf"});
  expectLoadError(dataPath("malformed.urdf"), "", {"cannot parse URDF", "malformed.urdf"});
  expectLoadError(dataPath("missing_link.urdf"), "", {"missing_link.urdf", "ghost_finger"});
  expectLoadError(dataPath("bad_mimic.urdf"), "", {"bad_mimic.urdf", "jb", "phantom_joint"});
  const std::string mini = dataPath("mini.urdf");
  expectLoadError(mini, dataPath("unknown_joint.hand.json"),
                  {"unknown_joint.hand.json", "closing[0].joint", "no_such_joint"});
  expectLoadError(mini, dataPath("mimic_closing.hand.json"),
                  {"mimic_closing.hand.json", "'jb'", "not an actuated"});
  expectLoadError(mini, dataPath("unknown_palm.hand.json"),
                  {"unknown_palm.hand.json", "palm_link", "hand_base"});
  expectLoadError(mini, dataPath("no_geometry.hand.json"),
                  {"no_geometry.hand.json", "finger link 'bare'", "no <collision> geometry"});
  expectLoadError(mini, dataPath("bad_json.hand.json"), {"bad_json.hand.json", "invalid JSON"});
  expectLoadError(mini, dataPath("missing_key.hand.json"),
                  {"missing_key.hand.json", "missing required key 'closing'"});
  expectLoadError(mini, dataPath("bad_toward.hand.json"),
                  {"bad_toward.hand.json", "closing[0].toward", "closed"});
  expectLoadError(mini, dataPath("bad_preshape.hand.json"),
                  {"bad_preshape.hand.json", "preshape.ja", "outside the joint limits"});
  expectLoadError(mini, dataPath("absent.hand.json"),
                  {"cannot read hand sidecar", "absent.hand.json"});
}

}  // namespace
}  // namespace taskmap
