#pragma once
// Shared helpers of the reaching tests: the shipped Panda with the humanoid hand (alone or in the
// default scene), its ready pose, a side grasp of the default object, random configurations, a
// small URDF with every joint kind written to a temporary file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "taskmap/reaching/reach_scene.hpp"
#include "taskmap/reaching/robot_model.hpp"

namespace taskmap::test {

inline std::string robotsDir() {
  return std::string(TASKMAP_SOURCE_DIR) + "/reaching/robots";
}

inline const RobotModel& pandaWithHand() {
  static const RobotModel robot = RobotModel::pandaWithHumanoidHand(robotsDir(), TASKMAP_HANDS_DIR);
  return robot;
}

/// The Panda with the humanoid hand and the bodies of the default scene (table, "object").
inline RobotModel pandaInDefaultScene() {
  RobotModel robot = pandaWithHand();
  addSceneTo(defaultReachScene(), robot);
  return robot;
}

/// Franka's ready pose.
inline Eigen::VectorXd readyPose() {
  Eigen::VectorXd q(7);
  q << 0.0, -M_PI / 4, 0.0, -3 * M_PI / 4, 0.0, M_PI / 2, M_PI / 4;
  return q;
}

/// Side grasp of the default scene's upright cylinder (object frame): palm 7 cm from its axis
/// facing it, fingers horizontal.
inline Eigen::Isometry3d sideGrasp() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(-0.07, 0.0, 0.02);
  t.linear().col(0) = -Eigen::Vector3d::UnitZ();
  t.linear().col(1) = Eigen::Vector3d::UnitY();
  t.linear().col(2) = Eigen::Vector3d::UnitX();
  return t;
}

/// Uniform configuration inside the limits shrunk by `margin` of each range.
inline Eigen::VectorXd randomConfiguration(const RobotModel& robot, std::mt19937& rng,
                                           double margin = 0.02) {
  std::uniform_real_distribution<double> u(margin, 1.0 - margin);
  Eigen::VectorXd q(robot.dofs());
  for (int i = 0; i < robot.dofs(); ++i)
    q[i] = robot.lower()[i] + u(rng) * (robot.upper()[i] - robot.lower()[i]);
  return q;
}

/// Writes `text` to a file in the test's temporary directory and returns its path.
inline std::string writeTempFile(const std::string& name, const std::string& text) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "taskmap_reaching_test";
  std::filesystem::create_directories(dir);
  const std::filesystem::path p = dir / name;
  std::ofstream(p) << text;
  return p.string();
}

/// A four-joint tree with revolute (tilted axis), prismatic and continuous joints and a branch.
inline std::string mixedJointsUrdf() {
  return R"(<?xml version="1.0"?>
<robot name="mixed">
  <link name="base"/>
  <link name="a"><collision><origin xyz="0 0 0.1"/><geometry><box size="0.05 0.06 0.2"/></geometry></collision></link>
  <link name="b"><collision><origin xyz="0 0 0.1"/><geometry><cylinder radius="0.03" length="0.2"/></geometry></collision></link>
  <link name="c"><collision><geometry><sphere radius="0.04"/></geometry></collision></link>
  <link name="d"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/>
    <origin xyz="0.1 0.0 0.2" rpy="0.3 -0.2 0.5"/><axis xyz="0.2 0.3 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j2" type="prismatic"><parent link="a"/><child link="b"/>
    <origin xyz="0 0.05 0.2" rpy="0.1 0.7 0"/><axis xyz="1 0 1"/>
    <limit lower="-0.1" upper="0.3" effort="1" velocity="0.5"/></joint>
  <joint name="j3" type="continuous"><parent link="b"/><child link="c"/>
    <origin xyz="0.02 0 0.25" rpy="0 0 0.4"/><axis xyz="0 1 0"/></joint>
  <joint name="j4" type="revolute"><parent link="a"/><child link="d"/>
    <origin xyz="-0.1 0 0.15" rpy="1.2 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
)";
}

}  // namespace taskmap::test
