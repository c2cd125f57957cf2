#pragma once
/// @file reach_picture.hpp
/// The picture of `taskmap reach --png`: robot and scene primitives in three orthographic
/// views (top, front, side) at a few time steps of a rollout (cairo).

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "taskmap/reaching/attractor.hpp"

namespace taskmap {

/// Draws the robot at the configurations `frames` (indices into result.q, earliest first,
/// later ones darker) over the environment, the path of `body` (the palm) over every step and
/// the target position, and writes a PNG atomically. target_world: the target pose of `body`
/// in the world frame. Throws Error naming
/// the file when it cannot be written or when the library was built without cairo.
void writeReachPicture(const RobotModel& robot, const ReachResult& result, int body,
                       const std::vector<int>& frames, const Eigen::Isometry3d& target_world,
                       const std::string& path);

}  // namespace taskmap
