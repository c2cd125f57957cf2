// The one URDF reader (urdf_model.hpp): the tree depth-first with joints, limits, mimic,
// geometry, inertia; urdfdom's messages quoted with the file; concurrent parses keep their own
// messages (console_bridge's handler is process-global).
#include "taskmap/hands/urdf_model.hpp"

#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

using testing::throwsError;

// Root "base" with two children in URDF order: "b" (revolute, limits, box, cylinder visual,
// inertial) then "c" (continuous, mimics j1), and "d" under "b" (prismatic, mesh, sphere).
const char* kTree = R"(<?xml version="1.0"?>
<robot name="tree">
  <link name="base"/>
  <link name="b">
    <inertial><origin xyz="0.1 0 0"/><mass value="2"/>
      <inertia ixx="1" ixy="0.1" ixz="0.2" iyy="3" iyz="0.3" izz="4"/></inertial>
    <visual><geometry><cylinder radius="0.02" length="0.1"/></geometry></visual>
    <collision><origin xyz="0 0 0.05" rpy="0 0 1.5707963267948966"/>
      <geometry><box size="0.1 0.2 0.3"/></geometry></collision>
  </link>
  <link name="c"/>
  <link name="d">
    <collision><geometry><mesh filename="package://pkg/m.stl" scale="2 2 2"/></geometry></collision>
    <collision><geometry><sphere radius="0.01"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="b"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 2"/>
    <limit lower="-1" upper="1.5" effort="10" velocity="2"/></joint>
  <joint name="j2" type="continuous"><parent link="base"/><child link="c"/><axis xyz="1 0 0"/>
    <mimic joint="j1" multiplier="-0.5" offset="0.1"/></joint>
  <joint name="j3" type="prismatic"><parent link="b"/><child link="d"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="0.04" effort="1" velocity="0.2"/></joint>
</robot>)";

TEST(UrdfModel, ReadsTheTreeDepthFirstWithJointsGeometryAndInertia) {
  const UrdfModel m = parseUrdfModel(kTree, "tree.urdf", "URDF");
  EXPECT_EQ(m.name, "tree");
  ASSERT_EQ(m.links.size(), 4u);
  ASSERT_EQ(m.joints.size(), 3u);
  // Depth-first, children in URDF order: base, b, d (under b), c.
  const std::vector<std::string> order{m.links[0].name, m.links[1].name, m.links[2].name,
                                       m.links[3].name};
  EXPECT_EQ(order, (std::vector<std::string>{"base", "b", "d", "c"}));
  for (std::size_t i = 1; i < m.links.size(); ++i) {
    EXPECT_EQ(m.links[i].parent_joint, static_cast<int>(i) - 1);
    EXPECT_EQ(m.joints[i - 1].child_link, static_cast<int>(i));
  }
  EXPECT_EQ(m.links[0].parent_joint, -1);
  const UrdfJoint& j1 = m.joints[0];
  EXPECT_EQ(j1.name, "j1");
  EXPECT_EQ(j1.type, UrdfJointType::kRevolute);
  EXPECT_EQ(j1.parent_link, 0);
  EXPECT_TRUE(j1.axis.isApprox(Eigen::Vector3d(0, 0, 2)));  // as written, not normalised
  EXPECT_TRUE(j1.origin.translation().isApprox(Eigen::Vector3d(0, 0, 0.1)));
  ASSERT_TRUE(j1.limits.has_value());
  EXPECT_EQ(j1.limits->lower, -1.0);
  EXPECT_EQ(j1.limits->upper, 1.5);
  EXPECT_EQ(j1.limits->effort, 10.0);
  EXPECT_EQ(j1.limits->velocity, 2.0);
  EXPECT_FALSE(j1.mimic.has_value());
  EXPECT_EQ(m.joints[1].name, "j3");
  EXPECT_EQ(m.joints[1].type, UrdfJointType::kPrismatic);
  EXPECT_EQ(m.joints[1].parent_link, 1);
  const UrdfJoint& j2 = m.joints[2];
  EXPECT_EQ(j2.type, UrdfJointType::kContinuous);
  ASSERT_TRUE(j2.mimic.has_value());
  EXPECT_EQ(j2.mimic->joint, "j1");
  EXPECT_EQ(j2.mimic->multiplier, -0.5);
  EXPECT_EQ(j2.mimic->offset, 0.1);
  EXPECT_EQ(m.jointIndex("j2"), 2);
  EXPECT_EQ(m.jointIndex("nope"), -1);

  const UrdfLink& b = m.links[1];
  ASSERT_EQ(b.collisions.size(), 1u);
  EXPECT_EQ(b.collisions[0].geometry.type, UrdfGeometry::Type::kBox);
  EXPECT_TRUE(b.collisions[0].geometry.box_size.isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  // rpy (0, 0, pi/2): x of the shape frame is y of the link frame.
  EXPECT_TRUE((b.collisions[0].origin.linear() * Eigen::Vector3d::UnitX())
                  .isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  ASSERT_EQ(b.visuals.size(), 1u);
  EXPECT_EQ(b.visuals[0].geometry.type, UrdfGeometry::Type::kCylinder);
  EXPECT_EQ(b.visuals[0].geometry.radius, 0.02);
  EXPECT_EQ(b.visuals[0].geometry.length, 0.1);
  ASSERT_TRUE(b.inertial.has_value());
  EXPECT_EQ(b.inertial->mass, 2.0);
  EXPECT_TRUE(b.inertial->origin.translation().isApprox(Eigen::Vector3d(0.1, 0, 0)));
  Eigen::Matrix3d inertia;
  inertia << 1, 0.1, 0.2, 0.1, 3, 0.3, 0.2, 0.3, 4;
  EXPECT_TRUE(b.inertial->inertia.isApprox(inertia));
  const UrdfLink& d = m.links[2];
  ASSERT_EQ(d.collisions.size(), 2u);
  EXPECT_EQ(d.collisions[0].geometry.type, UrdfGeometry::Type::kMesh);
  EXPECT_EQ(d.collisions[0].geometry.mesh_file, "package://pkg/m.stl");  // unresolved
  EXPECT_TRUE(d.collisions[0].geometry.mesh_scale.isApprox(Eigen::Vector3d(2, 2, 2)));
  EXPECT_EQ(d.collisions[1].geometry.type, UrdfGeometry::Type::kSphere);
  EXPECT_EQ(d.collisions[1].geometry.radius, 0.01);
  EXPECT_FALSE(m.links[3].inertial.has_value());
}

TEST(UrdfModel, QuotesUrdfdomWithTheFileAndItsRole) {
  EXPECT_TRUE(throwsError(
      [] {
        parseUrdfModel("<robot name=\"r\"><link name=\"a\"></robot>", "bad.urdf", "robot URDF");
      },
      {"cannot parse robot URDF 'bad.urdf': ", "Error reading end tag"}));
  EXPECT_TRUE(throwsError(
      [] {
        parseUrdfModel("<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/></robot>", "two.urdf",
                       "URDF");
      },
      {"cannot parse URDF 'two.urdf': ", "Two root links found"}));
  // A detached cycle: urdfdom finds the one root, the walk refuses the rest.
  const std::string cycle = R"(<robot name="r"><link name="a"/><link name="c"/><link name="d"/>
    <joint name="k" type="fixed"><parent link="c"/><child link="d"/></joint>
    <joint name="l" type="fixed"><parent link="d"/><child link="c"/></joint></robot>)";
  EXPECT_TRUE(throwsError([&] { parseUrdfModel(cycle, "cycle.urdf", "hand URDF"); },
                          {"hand URDF 'cycle.urdf': link(s) 'c', 'd' not reachable from the "
                           "root link 'a'"}));
}

/// A URDF whose revolute joint `joint` has no <limit>: urdfdom's message names the joint.
std::string withoutLimit(const std::string& joint) {
  return "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/><joint name=\"" + joint +
         "\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>"
         "<axis xyz=\"0 0 1\"/></joint></robot>";
}

std::string parseError(const std::string& xml, const std::string& path) {
  try {
    parseUrdfModel(xml, path, "URDF");
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

// console_bridge's output handler is process-global: parses on many threads at once must each
// quote exactly their own urdfdom message (as a parse alone gives it), never another's or none.
TEST(UrdfModel, ConcurrentParsesKeepTheirOwnMessages) {
  constexpr int kThreads = 8;
  constexpr int kRounds = 40;
  std::vector<std::string> expected(kThreads), failures(kThreads);
  for (int t = 0; t < kThreads; ++t) {
    const std::string joint = "joint" + std::to_string(t);
    expected[t] = parseError(withoutLimit(joint), joint + ".urdf");
    ASSERT_NE(expected[t].find("Joint [" + joint + "]"), std::string::npos) << expected[t];
  }
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([t, &expected, &failures] {
      const std::string joint = "joint" + std::to_string(t);
      for (int r = 0; r < kRounds && failures[t].empty(); ++r) {
        if (r % 2 == 0) {
          if (parseUrdfModel(kTree, "tree.urdf", "URDF").links.size() != 4) failures[t] = "tree";
          continue;
        }
        const std::string m = parseError(withoutLimit(joint), joint + ".urdf");
        if (m != expected[t]) failures[t] = m;
      }
    });
  }
  for (auto& th : threads) th.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(failures[t], "") << "thread " << t;
}

}  // namespace
}  // namespace taskmap
