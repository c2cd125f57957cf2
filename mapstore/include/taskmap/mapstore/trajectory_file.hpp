#pragma once
/// @file trajectory_file.hpp
/// Reaching trajectory files (`taskmap reach --map ... -o trajectory.h5`): the planned joint
/// trajectory with everything needed to replay or render it without the robot's URDF (body
/// poses per step, collision primitives, the object mesh). Sealed HDF5 like the task maps;
/// layout in mapstore/TRAJECTORY.md. Units: metres, radians, seconds; poses are stored as
/// x y z qw qx qy qz.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/core/pose.hpp"
#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap {

/// Schema version of trajectory files this library writes; the reader refuses newer ones.
constexpr int kTrajectorySchemaVersion = 1;

/// Kind of a stored collision primitive (the reaching stage's sphere-swept cores).
enum class TrajectoryShapeType : std::int32_t {
  kCapsule = 0,        ///< sphere-swept segment along axes.col(0), half length half_u
  kSweptRectangle = 1  ///< sphere-swept rectangle spanned by axes.col(0), axes.col(1)
};

/// One collision primitive of a body, in the body frame.
struct TrajectoryShape {
  int body = 0;                                              ///< index into body_names
  TrajectoryShapeType type = TrajectoryShapeType::kCapsule;  ///< kind
  Eigen::Vector3d center = Eigen::Vector3d::Zero();          ///< core centre, metres
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();        ///< columns u, v, u x v
  double half_u = 0.0;                                       ///< metres, >= 0
  double half_v = 0.0;                                       ///< metres, >= 0 (0: capsule)
  double radius = 0.0;                                       ///< sweep radius, metres, >= 0
};

/// Everything a trajectory file holds (mapstore/TRAJECTORY.md). S = steps + 1 rows per
/// time series, D joints, B bodies, I + 1 cost-history rows (iteration 0 first).
struct TrajectoryRecord {
  std::string generator;                 ///< writer name and version
  std::string created_utc;               ///< ISO 8601 UTC or "" (reproducible bytes)
  std::string robot;                     ///< "panda" or the robot URDF path given to the planner
  std::string hand;                      ///< hand name or URDF path ("none" without a hand)
  double dt = 0.01;                      ///< time step between rows, seconds (> 0)
  std::vector<std::string> joint_names;  ///< D joint names, column order of joints
  RowMatrixXd joints;                    ///< S x D joint angles, rad (m for prismatic joints)
  RowMatrixXd palm_world;                ///< S x 7 palm pose in the world
  RowMatrixXd palm_object;               ///< S x 7 palm pose in the object frame
  std::string object_name;               ///< the object body's name in the scene
  Pose object_pose;                      ///< object frame in the world
  RowMatrixXd object_vertices;           ///< V x 3 object mesh (the map's), object frame
  Eigen::Matrix<std::int64_t, Eigen::Dynamic, 3, Eigen::RowMajor> object_faces;  ///< F x 3
  std::string map_path;           ///< task map file the plan used
  std::string map_sha256;         ///< SHA-256 (hex) of that file's bytes
  int start_cluster = -1;         ///< cluster the optimisation started from
  int cluster = -1;               ///< cluster of the final nearest grasp
  std::int64_t grasp_index = -1;  ///< final nearest grasp (row of the map's /grasps)
  /// q*, the scale of the map's quality in the quality columns (w_map,q g_q / q*; 1 in files
  /// written before the planner scaled g_q, whose columns are w_map,q g_q).
  double quality_peak = 1.0;
  /// The map's hand and the chosen grasp's joint values (/plan/grasp, optional: empty in files
  /// written before taskmap recorded them), what `taskmap view` closes the hand to.
  std::string map_hand;                        ///< the map's hand name (its /hand name)
  std::string map_hand_sha256;                 ///< SHA-256 (hex) of that hand's model file
  std::string map_hand_path;                   ///< model path the map's build recorded, or ""
  std::vector<std::string> grasp_joint_names;  ///< J actuated joints of the map's hand
  Eigen::VectorXd grasp_joints;                ///< J joint values of grasp_index, rad (m)
  std::vector<std::string> cost_terms;         ///< names of the cost_history columns
  RowMatrixXd cost_history;                    ///< (I + 1) x terms, one row per iteration
  Eigen::VectorXd proximity_over_movement;     ///< S weighted g_p at the palm pose of each step
  Eigen::VectorXd quality_over_movement;       ///< S weighted g_q at the palm pose of each step
  std::vector<std::string> body_names;         ///< B bodies (robot links, hand, environment)
  std::vector<std::int32_t> body_parents;      ///< B parent body index, -1 for the world
  std::vector<std::int32_t> body_roles;        ///< B: 0 robot, 1 hand, 2 environment
  RowMatrixXd body_poses;               ///< S x 7B world pose of body b at columns 7b .. 7b + 6
  std::vector<TrajectoryShape> shapes;  ///< collision primitives of the bodies

  /// Number of rows of the time series (steps + 1).
  std::size_t rows() const { return static_cast<std::size_t>(joints.rows()); }
  /// World pose of body b at row t.
  Pose bodyPose(std::size_t t, std::size_t b) const;
  /// Throws Error naming the first inconsistency (sizes, non-finite values, bad indices,
  /// non-unit quaternions, dt <= 0).
  void validate() const;
};

/// Writes the record atomically (temporary file beside path, sealed, fsynced, renamed over
/// path). Same record, same bytes. Throws Error naming the path; nothing is left at path on
/// failure.
void writeTrajectory(const std::string& path, const TrajectoryRecord& record);

/// Reads and validates a trajectory file: the seal (length, SHA-256) is checked before HDF5
/// parses any byte, then every dataset against the layout. Throws Error naming the file and
/// the problem (missing, truncated, damaged, not a trajectory file, newer schema, the first
/// inconsistent dataset).
TrajectoryRecord readTrajectory(const std::string& path);

}  // namespace taskmap
