#pragma once
/// @file reach_page.hpp
/// `taskmap view reach.h5`: a reaching trajectory (mapstore/TRAJECTORY.md) as a self-contained
/// HTML page: robot and scene primitives moving along the path with a time slider, the map's
/// hand as its own collision shapes on the palm (open in its preshape, closing to the chosen
/// grasp's joint values over the end of the movement), the object mesh, the chosen grasp's palm
/// frame and the cost terms.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/hands/hand_model.hpp"
#include "taskmap/mapstore/trajectory_file.hpp"
#include "taskmap/viz/page_options.hpp"

namespace taskmap {

/// What a reach page shows besides the trajectory.
struct ReachPageInput {
  const TrajectoryRecord* trajectory = nullptr;  ///< the trajectory (required)
  /// The map's hand (inspect's findTrajectoryHand); nullptr draws the hand as the planner's
  /// collision primitives, with `note` saying why.
  const HandModel* hand = nullptr;
  /// The chosen grasp's joint values, hand->jointNames() order, rad (m for prismatic joints);
  /// required with hand.
  Eigen::VectorXd grasp_joints;
  /// Seconds over which the hand closes from its preshape to grasp_joints, ending at the last
  /// step (> 0; a shorter trajectory closes over all of it).
  double close_s = 0.5;
  std::string note;  ///< why there is no hand, shown in the page ("" for none)
};

/// The hand's closing along a trajectory of `rows` steps, dt seconds apart: link poses per
/// closing stage and the stage shown at each step.
struct ReachHandMotion {
  /// Stage shown at each step: 0 (the preshape) before the closing starts, then one more per
  /// step; the last step shows the last stage (grasp_joints).
  std::vector<int> stage;
  /// The step the closing starts from (stage 0, the last step in the preshape); the hand
  /// reaches grasp_joints at the last step, rows - 1.
  std::size_t close_from = 0;
  /// Joint values per stage (jointNames() order): the preshape blended into grasp_joints by a
  /// smoothstep of the closing time, rad (m).
  std::vector<Eigen::VectorXd> joints;
  /// Pose of every link (links() order) in the palm frame per stage: HandModel::linkPoses.
  std::vector<std::vector<Eigen::Isometry3d>> link_poses;
};

/// The closing of `hand` from its preshape to grasp_joints over the last close_s seconds of a
/// trajectory of `rows` steps (>= 1) dt seconds apart. Throws Error when grasp_joints does not
/// fit the hand or close_s, dt are not > 0.
ReachHandMotion reachHandMotion(const HandModel& hand, const Eigen::VectorXd& grasp_joints,
                                std::size_t rows, double dt, double close_s);

/// The page as a string; the body gets data-ready="1" once the first step is drawn and
/// data-hand-meshes="N" (the map's hand's shapes drawn, 0 without the hand). Throws Error on a
/// missing trajectory, an invalid one, or grasp_joints that do not fit the hand.
std::string reachPageHtml(const ReachPageInput& input, const PageOptions& options = {});

/// reachPageHtml without the map's hand (the planner's primitives of the hand only).
std::string reachPageHtml(const TrajectoryRecord& record, const PageOptions& options = {});

/// Writes reachPageHtml atomically; throws Error naming the path.
void writeReachPage(const ReachPageInput& input, const std::string& path,
                    const PageOptions& options = {});

/// Writes reachPageHtml(record) atomically; throws Error naming the path.
void writeReachPage(const TrajectoryRecord& record, const std::string& path,
                    const PageOptions& options = {});

}  // namespace taskmap
