#pragma once
/// @file map_hand.hpp
/// The hand of a task map for its pictures, pages and scene files (`inspect --png`, `view`,
/// `export --format ply|glb`): the caller's hand, or the map's own found by its URDF SHA-256;
/// and its links posed by a grasp of the map. The same for the map of a reaching trajectory.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/core/triangle_mesh.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/mapstore/recorded_hand.hpp"  // findMapHandUrdf
#include "taskmap/mapstore/task_map_data.hpp"
#include "taskmap/mapstore/trajectory_file.hpp"

namespace taskmap {

/// Where findMapHand looks for the map's hand.
struct MapHandOptions {
  /// URDF of the hand to use (its sidecar beside it); empty: the map's own hand, found below.
  std::string hand;
  /// Folder of bundled hands (`<name>/<name>.urdf`), searched for a URDF with the map's SHA-256
  /// when the path the build recorded does not hold it; empty: only the recorded path is tried.
  std::string hands_dir;
  /// Throws Error when `hand` is given and is not a file.
  void validate() const;
};

/// The map's hand, or why there is none.
struct MapHandResult {
  /// kLoaded: `hand` holds it; kNotFound: no URDF with the map's SHA-256 was found;
  /// kOtherJoints: the hand found or given has other actuated joints than the map's hand.
  enum class Status { kLoaded, kNotFound, kOtherJoints };
  Status status = Status::kNotFound;  ///< see Status
  std::string message;                ///< why there is no hand (empty when kLoaded)
  std::optional<HandModel> hand;      ///< set when kLoaded
};

/// The map's hand: options.hand when given (throws Error when it does not load), else the URDF
/// of findMapHandUrdf (mapstore/recorded_hand.hpp). A hand whose actuated joints differ from the
/// map's is not returned (kOtherJoints): the map's joint values would not fit it.
MapHandResult findMapHand(const TaskMapData& map, const MapHandOptions& options);

/// The map's hand of a reaching trajectory (mapstore/TRAJECTORY.md) and the chosen grasp's
/// joint values: what `taskmap view` of a trajectory closes on the object.
struct TrajectoryHand {
  MapHandResult found;           ///< the hand, or why there is none
  Eigen::VectorXd grasp_joints;  ///< grasp joint values, found.hand's jointNames() order, rad (m)
};

/// The hand of the record's /plan/grasp, found as findMapHand finds a map's (options.hand when
/// given, else the recorded model path or a bundled hand with the recorded SHA-256), with its
/// grasp joint values. A file written before /plan/grasp existed takes both from the map at
/// record.map_path when that file's SHA-256 is still record.map_sha256. Without them found.status
/// is kNotFound and found.message says why. Throws Error when options.hand does not load.
TrajectoryHand findTrajectoryHand(const TrajectoryRecord& record, const MapHandOptions& options);

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

}  // namespace taskmap
