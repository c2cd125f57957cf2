#pragma once
// `taskmap reach --map MAP --object-pose "x y z yaw"`: reaching and grasping with a task map
// (reaching/map_reach.hpp, docs/REACHING.md).

#include <string>

#include <Eigen/Geometry>

#include "taskmap/reaching/trajectory_optimizer.hpp"

namespace taskmap::cli {

/// Options of the map mode of `taskmap reach`.
struct MapReachArgs {
  std::string map;            ///< task map file (palm poses of the mounted hand, object frame)
  std::string object_pose;    ///< "x y z yaw" of the object body in the world (metres, radians)
  bool all_clusters = false;  ///< optimise from every reachable cluster
  int member_tries = 16;      ///< members, then outliers, tried when no representative is reachable
                              ///< or every plan is unsafe
  int iterations = 40;        ///< optimiser iterations
  double proximity_weight = 1.0e4;     ///< w_map,p (docs/REACHING.md "Chosen weights")
  double quality_weight = 3.0e4;       ///< w_map,q (on g_q / q*)
  bool resimulate = true;              ///< re-simulate the final grasp with grasp_sim
  bool hold_test = false;              ///< and test the re-simulated grasp in physics (validate)
  std::string sample_weight = "auto";  ///< quality weights: "auto", "epsilon", "hold_margin"
  std::string descent = "bfgs";        ///< "bfgs" or "gradient"
  std::string output;                  ///< trajectory file to write (mapstore/TRAJECTORY.md), or ""
  std::string glb;                ///< GLB file to write (taskmap/inspect/glb_export.hpp), or ""
  std::string robot = "panda";    ///< --robot, recorded in the trajectory file
  std::string hand = "humanoid";  ///< --hand, recorded in the trajectory file
};

/// Plans problem (palm relative to the object) with the map and prints (text or JSON), draws
/// snapshots to png when given, writes the trajectory file and GLB when asked (also for an
/// unsafe plan, to inspect it); sets the exit code to 1 when the plan is not safe or nothing is
/// reachable.
void runMapReach(const MapReachArgs& args, const TrajectoryProblem& problem, bool json,
                 const std::string& png);

}  // namespace taskmap::cli
