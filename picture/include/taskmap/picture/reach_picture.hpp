#pragma once
/// @file reach_picture.hpp
/// The picture of `taskmap reach --png`: robot and scene primitives in three orthographic
/// views (top, front, side) at a few time steps of a rollout (cairo).

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "taskmap/reaching/attractor.hpp"
#include "taskmap/reaching/grasp_planner.hpp"
#include "taskmap/reaching/movement_terms.hpp"

namespace taskmap {

/// Draws the robot at the configurations `frames` (indices into result.q, earliest first,
/// later ones darker) over the environment, the path of `body` (the palm) over every step and
/// the target position, and writes a PNG atomically. target_world: the target pose of `body`
/// in the world frame. Throws Error naming
/// the file when it cannot be written or when the library was built without cairo.
void writeReachPicture(const RobotModel& robot, const ReachResult& result, int body,
                       const std::vector<int>& frames, const Eigen::Isometry3d& target_world,
                       const std::string& path);

/// Where the cost curves of a plan picture go: FILE.png -> FILE_costs.png (else FILE_costs.png
/// after the whole name).
std::string costPicturePath(const std::string& png);

/// The pictures of `taskmap reach --map --png FILE`: the robot at four steps (0, n/3, 2n/3, n)
/// of plan b with the path of `palm` and the grasp (grasp_world: the map's grasp in the world
/// frame), written to png; and the cost curves beside it (costPicturePath(png), Fig. 1.16): the
/// trajectory cost terms and the map terms per iteration, proximity and quality over the final
/// movement against time (dt: control step, seconds). Throws Error as writeReachPicture.
void writeGraspPlanPictures(const RobotModel& robot, const ClusterPlan& b,
                            const MovementTerms& movement, int palm,
                            const Eigen::Isometry3d& grasp_world, double dt,
                            const std::string& png);

}  // namespace taskmap
