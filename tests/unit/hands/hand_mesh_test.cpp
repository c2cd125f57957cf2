// Hand collision meshes reduced to convex hulls (qhull) per connected part, checked against the
// cube corners the test meshes are built from; hand names; the real Franka and Allegro hands.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>

#include "taskmap/core/error.hpp"
#include "taskmap/hands/hand_model.hpp"

namespace taskmap {
namespace {

std::string data(const std::string& name) {
  return std::string(TEST_DATA_DIR) + "/hands/" + name;
}
std::string real(const std::string& name) {
  return std::string(TEST_DATA_DIR) + "/real/hands/" + name;
}

TEST(HandMesh, EachConnectedPartBecomesTheHullOfItsCorners) {
  const HandModel h = HandModel::load(data("hull_finger.urdf"));
  const HandLink& finger = h.links()[static_cast<std::size_t>(h.linkIndex("finger_a"))];
  ASSERT_EQ(finger.shapes.size(), 2u);  // two separate cubes in one file
  for (std::size_t k = 0; k < 2; ++k) {
    const CollisionShape& s = finger.shapes[k];
    EXPECT_EQ(s.type, ShapeType::kConvex);
    // 15 file vertices per cube (corners, face centres, an unused centre): the 8 corners stay.
    ASSERT_EQ(s.points.size(), 8u);
    std::set<std::array<long, 3>> corners;
    for (const auto& p : s.points)
      corners.insert(
          {std::lround(p.x() * 100), std::lround(p.y() * 100), std::lround(p.z() * 100)});
    const long x0 = std::lround(s.points.front().x() * 100);
    for (int i = 0; i < 8; ++i)
      EXPECT_EQ(corners.count({x0 + (i & 1), (i >> 1) & 1, (i >> 2) & 1}), 1u) << k << " " << i;
  }
  // Parts in file order: x from 0 and from 0.03 m.
  EXPECT_NEAR(finger.shapes[0].points.front().x(), 0.0, 1e-12);
  EXPECT_NEAR(finger.shapes[1].points.front().x(), 0.03, 1e-12);
}

TEST(HandMesh, GenericRobotNameGivesTheFileStem) {
  // hull_finger.urdf names its robot "gripper": the hand is called by its file.
  const HandModel h = HandModel::load(data("hull_finger.urdf"));
  EXPECT_EQ(h.robotName(), "gripper");
  EXPECT_EQ(h.name(), "hull_finger");
  // A specific robot name is kept.
  EXPECT_EQ(HandModel::load(data("mesh_finger.urdf")).name(), "mesh_finger");
}

TEST(HandMesh, RealFrankaHand) {
  const HandModel h = HandModel::load(real("franka_hand/franka_hand.urdf"));
  EXPECT_EQ(h.name(), "franka_hand");  // the URDF's robot is called "hand"
  EXPECT_EQ(h.jointNames(), std::vector<std::string>{"panda_finger_joint1"});
  const auto it = std::find_if(h.joints().begin(), h.joints().end(),
                               [](const HandJoint& j) { return j.name == "panda_finger_joint2"; });
  ASSERT_NE(it, h.joints().end());
  const HandJoint& j2 = *it;
  EXPECT_TRUE(j2.mimic);
  EXPECT_EQ(j2.driver, 0);
  // The palm collision mesh (200 triangles, 102 vertices) is convex: every vertex is a hull
  // vertex and the shape stays one convex hull.
  const HandLink& palm = h.links()[static_cast<std::size_t>(h.palmLink())];
  ASSERT_EQ(palm.shapes.size(), 1u);
  EXPECT_EQ(palm.shapes[0].points.size(), 102u);
  EXPECT_NEAR(h.palmFrame().translation().z(), 0.0584, 1e-12);
}

TEST(HandMesh, RealAllegroHand) {
  const HandModel h = HandModel::load(real("allegro_right/allegro_hand_description_right.urdf"));
  EXPECT_EQ(h.name(), "allegro_hand_right");
  EXPECT_EQ(h.jointNames().size(), 16u);
  EXPECT_EQ(h.fingerNames().size(), 4u);
  EXPECT_EQ(h.closing().size(), 11u);
}

}  // namespace
}  // namespace taskmap
