// The link mass model shared by the hold test and the closing check (link_inertia.hpp), checked
// against hand-computed values.
#include "taskmap/hands/link_inertia.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "taskmap/core/constants.hpp"

namespace taskmap {
namespace {

CollisionShape box(const Eigen::Vector3d& size, const Eigen::Vector3d& at) {
  CollisionShape s;
  s.type = ShapeType::kBox;
  s.box_size = size;
  s.origin.translation() = at;
  return s;
}

TEST(LinkInertia, ShapeVolumes) {
  EXPECT_DOUBLE_EQ(shapeVolume(box({0.1, 0.2, 0.3}, Eigen::Vector3d::Zero())), 0.006);
  CollisionShape c;
  c.type = ShapeType::kCylinder;
  c.radius = 0.01;
  c.length = 0.1;
  EXPECT_DOUBLE_EQ(shapeVolume(c), kPi * 1e-4 * 0.1);
  CollisionShape s;
  s.type = ShapeType::kSphere;
  s.radius = 0.02;
  EXPECT_DOUBLE_EQ(shapeVolume(s), 4.0 / 3.0 * kPi * 8e-6);
  CollisionShape h;
  h.type = ShapeType::kConvex;
  h.points = {{0, 0, 0}, {0.1, 0, 0}, {0, 0.2, 0}, {0, 0, 0.3}};  // a tetrahedron
  EXPECT_DOUBLE_EQ(shapeVolume(h), 0.5 * 0.006);                  // half its bounding box
}

TEST(LinkInertia, TwoBoxesGiveTheirWeightedCentreAndASphereReachingBoth) {
  HandLink link;
  link.shapes = {box({0.02, 0.02, 0.02}, {0.0, 0.0, 0.0}),
                 box({0.02, 0.02, 0.04}, {0.0, 0.0, 0.03})};
  const LinkInertia m = linkInertia(link, 1000.0);
  const double v1 = 8e-6, v2 = 16e-6;
  EXPECT_NEAR(m.mass, 1000.0 * (v1 + v2), 1e-15);
  EXPECT_NEAR(m.centre.z(), v2 * 0.03 / (v1 + v2), 1e-15);
  const double cz = m.centre.z();  // 0.02: the farther corner is the small box's
  const double r = std::max(cz + std::sqrt(3.0) * 0.01, (0.03 - cz) + std::sqrt(0.0006));
  EXPECT_NEAR(m.inertia, 0.4 * m.mass * r * r, 1e-15);
}

TEST(LinkInertia, ALinkWithoutShapesKeepsTheFloors) {
  const LinkInertia m = linkInertia(HandLink{}, 1000.0);
  EXPECT_EQ(m.mass, 1e-3);
  EXPECT_EQ(m.inertia, 1e-8);
  EXPECT_TRUE(m.centre.isZero());
}

}  // namespace
}  // namespace taskmap
