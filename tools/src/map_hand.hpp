#pragma once
/// @file map_hand.hpp
/// The hand of a task map for its pictures and scene files (`inspect --png`, `export --format
/// ply|glb`): loaded from --hand or found by the map's URDF SHA-256, and its links posed by a
/// grasp of the map.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/core/triangle_mesh.hpp"
#include "taskmap/mapstore/task_map_data.hpp"
#include "taskmap/meshes/hand_model.hpp"

namespace taskmap::cli {

/// The map's hand: `hand` (a URDF path or a bundled hand name) when not empty, else the
/// recorded or bundled URDF with the map's SHA-256 (mapHandUrdf). When that is not found, or
/// its actuated joints differ from the map's, prints "<who>: warning: <reason>; drawing no
/// hand" on stderr and returns nullopt. Throws Error when an explicit `hand` does not load.
std::optional<HandModel> mapHand(const TaskMapData& map, const std::string& hand,
                                 const std::string& who);

/// Grasp i's stored pose (palm frame -> object frame) and joint values (jointNames() order).
struct GraspPosture {
  Eigen::Isometry3d palm_pose;  ///< palm frame -> object frame, metres
  Eigen::VectorXd joints;       ///< radians or metres
};
/// The posture of grasp i; throws Error when i is out of range.
GraspPosture graspPosture(const TaskMapData& map, std::size_t i);

/// Boundary points of every collision shape of `hand` at posture p, in the object frame
/// (shapePoints of each shape, metres), with the index of the shape's link.
struct PosedShapePoints {
  int link;                             ///< index into hand.links()
  std::vector<Eigen::Vector3d> points;  ///< object frame, metres
};
/// Every collision shape of `hand` posed by p (links() order, then shape order).
std::vector<PosedShapePoints> posedShapePoints(const HandModel& hand, const GraspPosture& p);

}  // namespace taskmap::cli
