#pragma once
/// @file map_summary.hpp
/// What `taskmap inspect` reports about a task map: provenance, trial outcomes, quality
/// statistics and the cluster table, as plain data, as text and as JSON.

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap {

/// Minimum, median and maximum of a set of epsilon values (all 0 when count == 0).
struct EpsilonStats {
  std::size_t count = 0;  ///< number of values summarised
  double min = 0.0;       ///< smallest value
  double median = 0.0;    ///< middle value; mean of the two middle values for even counts
  double max = 0.0;       ///< largest value
};

/// One row of the cluster table.
struct ClusterRow {
  int id = 0;                        ///< cluster label 0..K-1
  int size = 0;                      ///< grasps in the cluster
  int representative = -1;           ///< grasp index of the representative (best epsilon)
  Eigen::Matrix<double, 7, 1> pose;  ///< representative pose x y z (m), qw qx qy qz, qw >= 0
  Eigen::Vector3d approach = Eigen::Vector3d::UnitZ();  ///< palm +z axis in the object frame
  double mean_epsilon = 0.0;  ///< mean Ferrari-Canny epsilon of the cluster's grasps
  double best_epsilon = 0.0;  ///< epsilon of the representative
  std::string color;          ///< "#rrggbb", the cluster's colour in pictures (clusterColor)
};

/// Everything `taskmap inspect` prints.
struct MapSummary {
  std::string path;                 ///< the map file
  std::string generator;            ///< program and version that wrote the map
  std::string created_utc;          ///< ISO 8601 time of writing, UTC (may be empty)
  std::string object_name;          ///< the object's name
  std::size_t object_vertices = 0;  ///< vertices of the stored object mesh
  std::size_t object_faces = 0;     ///< triangles of the stored object mesh
  double object_volume = 0.0;       ///< m^3
  Eigen::Vector3d bounds_min = Eigen::Vector3d::Zero();  ///< object vertex bounds, metres
  Eigen::Vector3d bounds_max = Eigen::Vector3d::Zero();  ///< object vertex bounds, metres
  std::string hand_name;                                 ///< the hand's name
  std::size_t hand_joints = 0;                           ///< actuated joints of the hand
  std::string sampler;                                   ///< "volume", "surface", "mixed", ...
  std::uint64_t seed = 0;                                ///< build seed
  std::uint64_t trials = 0;                              ///< trials simulated
  std::map<std::string, std::uint64_t> outcomes;         ///< trials per outcome status
  std::size_t grasps = 0;                                ///< grasps stored in the map
  std::size_t force_closure = 0;                         ///< stored grasps in force closure
  /// Force-closure grasps per simulated trial (per stored grasp when trials == 0).
  double valid_rate = 0.0;
  EpsilonStats epsilon;  ///< over force-closure grasps
  bool contacts_available = true;
  double rotation_scale = 0.0;       ///< rho, metres per radian
  bool clustered = false;            ///< the map holds a clustering
  std::string linkage;               ///< "single", "average", "complete"
  double threshold = 0.0;            ///< cut distance, metres
  int min_size = 0;                  ///< clusters below this size are outliers
  std::size_t outliers = 0;          ///< grasps labelled -1
  std::vector<ClusterRow> clusters;  ///< one row per cluster, by label
};

/// What inspectMap reads.
struct InspectOptions {
  std::string map;  ///< task map file (.h5)
  /// Throws Error("map file '<map>' does not exist; give the path of a task map (.h5)").
  void validate() const;
};

/// A map file read and summarised.
struct InspectResult {
  /// kOk: the map holds a clustering; kNotClustered: it holds none (no cluster table).
  enum class Status { kOk, kNotClustered };
  Status status = Status::kOk;  ///< see Status
  std::string message;          ///< empty, or why the summary lacks a part
  TaskMapData map;              ///< the map as read (readMap)
  MapSummary summary;           ///< summarizeMap(map, options.map)
};

/// Validates options, reads the map (its seal checked) and summarises it. Throws Error naming
/// the file when it is missing or not a task map.
InspectResult inspectMap(const InspectOptions& options);

/// Min / median / max of values (copied and partially sorted).
EpsilonStats epsilonStats(std::vector<double> values);

/// Summarises a map read from path (path is only reported).
MapSummary summarizeMap(const TaskMapData& map, const std::string& path);

/// Human-readable multi-line report.
std::string formatSummary(const MapSummary& summary);

/// The same report as JSON text indented by 2 (what `inspect --json` prints, without the final
/// newline). Keys: path, generator, created_utc, object, hand, sampling, grasps, epsilon,
/// clustering (null or {linkage, threshold, min_size, outliers, clusters[...]}).
std::string summaryJson(const MapSummary& summary);

/// Colour of cluster k as 8-bit RGB: Tableau-10 for k < 10, then golden-angle hues; never
/// grey. Outliers (k < 0) are grey (150, 150, 150).
std::array<std::uint8_t, 3> clusterColor(int k);

/// "#rrggbb" of clusterColor(k).
std::string clusterColorHex(int k);

/// Palm approach axis of a pose in the object frame: the palm frame's +z axis. Maps store
/// no hand geometry, so this is the documented convention for every hand.
Eigen::Vector3d approachAxis(const Pose& palm);

}  // namespace taskmap
