// The MJCF reader (mjcf_model.hpp): the real LEAP hand as MuJoCo Menagerie publishes it, every
// form of the test hands (tests/data/hands/mjcf), HandModel::load of an .xml hand, and what it
// refuses (naming the element and its line).
#include "taskmap/hands/mjcf_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>

#include "error_matchers.hpp"
#include "scratch_dir.hpp"
#include "taskmap/core/constants.hpp"
#include "taskmap/hands/hand_model.hpp"

namespace taskmap {
namespace {

const testing::ScratchDir kScratch("mjcf_model");

std::string text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string leapPath() {
  return std::string(TEST_DATA_DIR) + "/real/hands/leap_hand_mjcf/right_hand.xml";
}
std::string formsPath(const std::string& file) {
  return std::string(TEST_DATA_DIR) + "/hands/mjcf/" + file;
}

MjcfModel readFile(const std::string& path) {
  return readMjcfModel(text(path), path);
}

/// Index of the link or joint named `name` in v, -1 if none.
template <class T>
int indexOf(const std::vector<T>& v, const std::string& name) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (v[i].name == name) return static_cast<int>(i);
  return -1;
}

TEST(MjcfModel, ReadsTheLeapHandAsPublished) {
  const MjcfModel m = readFile(leapPath());
  EXPECT_EQ(m.tree.name, "leap_rh");
  ASSERT_EQ(m.tree.links.size(), 17u);
  ASSERT_EQ(m.tree.joints.size(), 16u);
  EXPECT_EQ(m.tree.links[0].name, "palm");
  const std::vector<std::string> order = {
      "if_mcp", "if_rot", "if_pip", "if_dip", "mf_mcp", "mf_rot", "mf_pip", "mf_dip",
      "rf_mcp", "rf_rot", "rf_pip", "rf_dip", "th_cmc", "th_axl", "th_mcp", "th_ipl"};
  std::size_t boxes = 0, meshes = 0;
  for (std::size_t j = 0; j < 16; ++j) {
    const UrdfJoint& joint = m.tree.joints[j];
    EXPECT_EQ(joint.name, order[j]);
    EXPECT_EQ(joint.type, UrdfJointType::kRevolute);
    EXPECT_TRUE(joint.axis.isApprox(Eigen::Vector3d(0, 0, -1)));
    EXPECT_FALSE(joint.mimic);
    EXPECT_EQ(joint.child_link, static_cast<int>(j) + 1);
  }
  EXPECT_DOUBLE_EQ(m.tree.joints[0].limits->lower, -0.314);
  EXPECT_DOUBLE_EQ(m.tree.joints[0].limits->upper, 2.23);
  EXPECT_DOUBLE_EQ(m.tree.joints[15].limits->lower, -1.34);
  double mass = 0.0;
  for (const UrdfLink& l : m.tree.links) {
    ASSERT_TRUE(l.inertial) << l.name;
    mass += l.inertial->mass;
    for (const UrdfShape& s : l.collisions) {
      boxes += s.geometry.type == UrdfGeometry::Type::kBox;
      meshes += s.geometry.type == UrdfGeometry::Type::kMesh;
    }
  }
  EXPECT_EQ(boxes, 67u);
  EXPECT_EQ(meshes, 4u);
  EXPECT_NEAR(mass, 0.746, 1e-12);
  // The eight visual meshes are missing: one warning each, naming the file.
  ASSERT_EQ(m.warnings.size(), 8u);
  for (const auto& w : m.warnings) EXPECT_NE(w.find("visual mesh"), std::string::npos) << w;
  EXPECT_NE(m.warnings[0].find("palm_right.obj"), std::string::npos) << m.warnings[0];
  EXPECT_NE(m.warnings[0].find("line 167"), std::string::npos) << m.warnings[0];
}

TEST(MjcfModel, ReadsTheLeapHandsStatedDynamics) {
  const MjcfModel m = readFile(leapPath());
  const HandDynamics& d = m.dynamics;
  EXPECT_EQ(d.source, "MJCF");
  EXPECT_EQ(d.excluded_pairs.size(), 18u);
  ASSERT_EQ(d.actuators.size(), 16u);
  for (std::size_t j = 0; j < 16; ++j) {
    ASSERT_TRUE(d.actuators[j]) << j;
    const ActuatorDynamics& a = *d.actuators[j];
    EXPECT_EQ(a.name, m.tree.joints[j].name + "_act");
    EXPECT_DOUBLE_EQ(*a.kp, 3.0);
    EXPECT_DOUBLE_EQ(*a.kv, 0.01);
    EXPECT_DOUBLE_EQ((*a.ctrlrange)[0], m.tree.joints[j].limits->lower);
    EXPECT_DOUBLE_EQ((*a.ctrlrange)[1], m.tree.joints[j].limits->upper);
    EXPECT_FALSE(a.forcerange);
    EXPECT_TRUE(a.unused.empty());
    EXPECT_DOUBLE_EQ(*d.joints[j].damping, 0.03);
    EXPECT_DOUBLE_EQ(*d.joints[j].frictionloss, 0.001);
    EXPECT_FALSE(d.joints[j].armature);
  }
  // Geoms: friction 0.2 (0.5 on the tips), the hard contacts of the model's main class.
  const int tip = indexOf(m.tree.links, "if_ds");
  ASSERT_GE(tip, 0);
  const auto& shapes = d.shapes[static_cast<std::size_t>(tip)];
  ASSERT_EQ(shapes.size(), 4u);
  EXPECT_DOUBLE_EQ(*shapes[0].sliding, 0.2);
  EXPECT_DOUBLE_EQ(*shapes[3].sliding, 0.5);
  EXPECT_FALSE(shapes[0].torsional);
  EXPECT_DOUBLE_EQ((*shapes[0].solref)[0], 0.0001);
  EXPECT_DOUBLE_EQ((*shapes[0].solimp)[3], 0.0001);
  const int palm = 0, th_mp = indexOf(m.tree.links, "th_mp");
  EXPECT_NE(
      std::find(d.excluded_pairs.begin(), d.excluded_pairs.end(), std::array<int, 2>{palm, th_mp}),
      d.excluded_pairs.end());
}

TEST(MjcfModel, HandModelLoadsAnMjcfHand) {
  const HandModel h = HandModel::loadKinematics(leapPath());
  EXPECT_EQ(h.modelFormat(), "MJCF");
  EXPECT_EQ(h.jointNames().size(), 16u);
  EXPECT_EQ(h.loadWarnings().size(), 8u);
  EXPECT_EQ(h.dynamics().actuators.size(), h.joints().size());
  // The tip meshes collide as their convex hulls, one shape per geom.
  const HandLink& ds = h.links()[static_cast<std::size_t>(h.linkIndex("if_ds"))];
  ASSERT_EQ(ds.shapes.size(), 4u);
  EXPECT_EQ(ds.shapes[3].type, ShapeType::kConvex);
  EXPECT_GE(ds.shapes[3].points.size(), 4u);
  for (const HandLink& l : h.links())
    EXPECT_EQ(h.dynamics().shapes[static_cast<std::size_t>(&l - h.links().data())].size(),
              l.shapes.size());
  const HandModel urdf =
      HandModel::loadKinematics(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  EXPECT_EQ(urdf.modelFormat(), "URDF");
  EXPECT_TRUE(urdf.dynamics().source.empty());
}

TEST(MjcfModel, ReadsEveryFormOfTheTestHand) {
  const MjcfModel m = readFile(formsPath("forms.xml"));
  ASSERT_EQ(m.files.size(), 2u);  // the include
  std::vector<std::string> links;
  for (const auto& l : m.tree.links) links.push_back(l.name);
  EXPECT_EQ(links, (std::vector<std::string>{"palm", "f1_base/f1_spread", "f1_base", "f1_mid",
                                             "f1_tip", "f2_base", "f2_tip", "thumb", "thumb_tip"}));
  const auto& J = m.tree.joints;
  const auto joint = [&](const char* n) { return J[static_cast<std::size_t>(indexOf(J, n))]; };
  EXPECT_NEAR(joint("f1_spread").limits->upper, 30 * kPi / 180, 1e-15);
  EXPECT_EQ(joint("f1_slide").type, UrdfJointType::kPrismatic);
  EXPECT_DOUBLE_EQ(joint("f1_slide").limits->upper, 0.02);  // metres, not converted
  EXPECT_TRUE(joint("f1_slide").axis.isApprox(Eigen::Vector3d(0, 1, 1).normalized()));
  EXPECT_NEAR(joint("f2_flex").limits->lower, -20 * kPi / 180, 1e-15);  // the element's range
  EXPECT_NEAR(joint("f1_flex").limits->upper, 100 * kPi / 180, 1e-15);  // the class's
  EXPECT_EQ(joint("thumb_roll").type, UrdfJointType::kContinuous);
  EXPECT_EQ(joint("f1_tipj").mimic->joint, "f1_flex");
  EXPECT_DOUBLE_EQ(joint("f1_tipj").mimic->multiplier, 0.7);
  EXPECT_DOUBLE_EQ(joint("f1_tipj").mimic->offset, 0.05);
  EXPECT_EQ(joint("f2_tipj").mimic->joint, "f2_flex");  // the fixed tendon's coupling
  EXPECT_DOUBLE_EQ(joint("f2_tipj").mimic->multiplier, 0.5);
  // The second anchor of a two-joint body: the slide's link frame at the body's origin.
  EXPECT_TRUE(joint("f1_slide").origin.translation().isApprox(Eigen::Vector3d(-0.001, -0.002, 0)));
  const auto& D = m.dynamics;
  const auto servo = [&](const char* n) {
    return *D.actuators[static_cast<std::size_t>(indexOf(J, n))];
  };
  EXPECT_DOUBLE_EQ(*servo("f1_spread").kp, 4.0);  // the main class's
  EXPECT_DOUBLE_EQ((*servo("f1_spread").forcerange)[1], 2.0);
  EXPECT_DOUBLE_EQ(*servo("f1_slide").kp, 200.0);
  EXPECT_DOUBLE_EQ(*servo("f1_flex").kp, 16.0);  // gear 2: kp gear^2
  EXPECT_DOUBLE_EQ((*servo("f1_flex").ctrlrange)[1], 1.5);
  EXPECT_DOUBLE_EQ((*servo("f1_flex").forcerange)[1], 4.0);
  EXPECT_DOUBLE_EQ(*servo("f2_flex").kp, 4.0 * 1.25 * 1.25);  // tendon length 1.25 q
  EXPECT_DOUBLE_EQ((*servo("f2_flex").ctrlrange)[1], 2.0);
  EXPECT_DOUBLE_EQ(*servo("thumb_roll").kp, 6.0);  // a general actuator that is a servo
  EXPECT_DOUBLE_EQ(*servo("thumb_roll").kv, 0.1);
  EXPECT_FALSE(servo("thumb_flex").unused.empty());  // a motor
  EXPECT_EQ(m.warnings.size(), 1u);
  EXPECT_DOUBLE_EQ(*D.joints[0].damping, 0.2);
  EXPECT_DOUBLE_EQ(*D.joints[0].armature, 0.001);
  // Geoms: a capsule of the tip class with the finger class's torsional friction.
  const auto tip = static_cast<std::size_t>(indexOf(m.tree.links, "f1_tip"));
  const UrdfGeometry& capsule = m.tree.links[tip].collisions[0].geometry;
  EXPECT_EQ(capsule.type, UrdfGeometry::Type::kCapsule);
  EXPECT_DOUBLE_EQ(capsule.radius, 0.008);
  EXPECT_NEAR(capsule.length, Eigen::Vector3d(0.002, -0.001, 0.02).norm(), 1e-15);
  EXPECT_DOUBLE_EQ(*D.shapes[tip][0].sliding, 1.2);
  EXPECT_DOUBLE_EQ(*D.shapes[tip][0].torsional, 0.01);
  EXPECT_EQ(m.tree.links[tip].collisions[1].geometry.type, UrdfGeometry::Type::kEllipsoid);
  const auto f2 = static_cast<std::size_t>(indexOf(m.tree.links, "f2_base"));
  EXPECT_TRUE(m.tree.links[f2].collisions[0].geometry.mesh_hull);
  EXPECT_TRUE(m.tree.links[f2].collisions[0].geometry.mesh_scale.isApprox(
      Eigen::Vector3d(0.02, 0.03, 0.04)));
  EXPECT_EQ(D.excluded_pairs, (std::vector<std::array<int, 2>>{{0, 2}}));
  EXPECT_DOUBLE_EQ(m.tree.links[0].inertial->mass, 0.3);
}

TEST(MjcfModel, ReadsFramesAndNewerActuatorAttributes) {
  const MjcfModel m = readFile(formsPath("frames.xml"));
  ASSERT_EQ(m.tree.joints.size(), 1u);
  const UrdfJoint& j = m.tree.joints[0];
  EXPECT_TRUE(j.origin.translation().isApprox(Eigen::Vector3d(0, 0.01, 0.02), 1e-15));
  EXPECT_TRUE(j.origin.linear().col(0).isApprox(Eigen::Vector3d(0, 1, 0), 1e-15));
  EXPECT_TRUE(j.axis.isApprox(Eigen::Vector3d(0, 1, 0)));  // the frame's childclass
  EXPECT_DOUBLE_EQ(j.limits->upper, 1.5);
  const ActuatorDynamics& a = *m.dynamics.actuators[0];
  EXPECT_DOUBLE_EQ(*a.kp, 2.0);
  EXPECT_DOUBLE_EQ(*a.kv, 0.05);
  EXPECT_DOUBLE_EQ((*a.ctrlrange)[0], 0.375);  // inheritrange 0.5 of [0, 1.5]
  EXPECT_DOUBLE_EQ((*a.ctrlrange)[1], 1.125);
  ASSERT_EQ(m.warnings.size(), 2u);  // the free joint; the missing visual mesh, once
  EXPECT_NE(m.warnings[0].find("free joint"), std::string::npos) << m.warnings[0];
  EXPECT_NE(m.warnings[1].find("skin_not_here.stl"), std::string::npos) << m.warnings[1];
}

// Issue 52 item 3: the Barrett hand as URDF and as MJCF (tests/data/hands/barrett_mjcf) is the
// same hand: links, joints, limits, shapes, and forward kinematics over random joint values.
TEST(MjcfModel, TheSameHandAsUrdfAndMjcfHasTheSameKinematics) {
  const HandModel u = HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  const HandModel m =
      HandModel::load(std::string(TEST_DATA_DIR) + "/hands/barrett_mjcf/barrett.xml");
  EXPECT_EQ(m.name(), u.name());
  EXPECT_EQ(m.jointNames(), u.jointNames());
  EXPECT_EQ(m.lowerLimits(), u.lowerLimits());
  EXPECT_EQ(m.upperLimits(), u.upperLimits());
  ASSERT_EQ(m.links().size(), u.links().size());
  for (std::size_t l = 0; l < u.links().size(); ++l) {
    EXPECT_EQ(m.links()[l].name, u.links()[l].name);
    ASSERT_EQ(m.links()[l].shapes.size(), u.links()[l].shapes.size());
    for (std::size_t k = 0; k < u.links()[l].shapes.size(); ++k) {
      EXPECT_EQ(m.links()[l].shapes[k].box_size, u.links()[l].shapes[k].box_size);
      EXPECT_TRUE(m.links()[l].shapes[k].origin.isApprox(u.links()[l].shapes[k].origin, 0.0));
    }
  }
  EXPECT_EQ(m.reach(), u.reach());
  EXPECT_EQ(m.rotationScale(), u.rotationScale());
  std::mt19937_64 rng(52);
  double worst = 0.0;
  for (int t = 0; t < 1000; ++t) {
    Eigen::VectorXd q(u.lowerLimits().size());
    for (Eigen::Index i = 0; i < q.size(); ++i)
      q[i] = std::uniform_real_distribution<double>(u.lowerLimits()[i], u.upperLimits()[i])(rng);
    const auto pu = u.linkPoses(q), pm = m.linkPoses(q);
    for (std::size_t l = 0; l < pu.size(); ++l) {
      worst = std::max(worst, (pu[l].translation() - pm[l].translation()).norm());
      worst = std::max(worst, (pu[l].linear() - pm[l].linear()).norm());
    }
  }
  EXPECT_LE(worst, 1e-9);
  std::printf("Barrett as URDF and as MJCF: largest link pose difference %.3g\n", worst);
}

TEST(MjcfModel, TellsAnMjcfFromAUrdfByItsFirstElement) {
  EXPECT_TRUE(isMjcfText("<?xml version=\"1.0\"?>\n<!-- <robot> -->\n<mujoco model=\"x\">"));
  EXPECT_TRUE(isMjcfText("<mujoco>"));
  EXPECT_FALSE(isMjcfText("<robot name=\"x\"><mujoco/></robot>"));
  EXPECT_FALSE(isMjcfText("<mujocox/>"));
  EXPECT_FALSE(isMjcfText(""));
}

}  // namespace
}  // namespace taskmap
