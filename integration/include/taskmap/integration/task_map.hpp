#pragma once
/// @file task_map.hpp
/// The run-time query library (issue 7, docs/METHOD.md §3): a task map loaded once,
/// queried by a motion optimizer once per iteration. Read-only after construction: every
/// const method may be called from many threads at once.
///
/// Frames and units: poses are the hand's palm frame in the object frame (metres, unit
/// quaternion w x y z, q = -q); distances are the pose distance of docs/METHOD.md §4 with the
/// map's rotation scale rho; gradients are 6-vectors (linear 1/m-units, angular 1/rad-units)
/// in the object frame for the perturbation p <- p + dp, R <- exp(dw) R (criteria.hpp).
///
/// The quality criterion is a mixture of Gaussians in the index's 12-D pose embedding
/// (criteria.hpp gaussianDensity): each term is one exp of a weighted squared embedding
/// distance, and the truncated mode sums exactly the samples within the cut-off (the set
/// radius() returns), found by a search of the map's float (p, 2 rho q) bounding-box tree whose
/// candidates are then tested with the index's distance.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/core/pose.hpp"
#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap {

class EvaluationSession;

/// Nearest-neighbour index over the 12-D pose embedding.
enum class IndexKind {
  kExactKdTree,       ///< single kd-tree, exact answers (default)
  kRandomizedForest,  ///< randomized kd-tree forest; nearest/knn visit at most `checks` leaves
};

/// How the quality criterion sums the mixture.
enum class QualityMode {
  kExact,      ///< every sample of the map (or cluster): O(N) per query
  kTruncated,  ///< samples within the cut-off radius found by the index, error bound reported
};

/// What weighs a sample's Gaussian in the quality criterion (w_i of eq. 1.20; docs/METHOD.md
/// §4 "Sample weights").
enum class SampleWeight {
  /// kHoldMargin when the map carries physics hold labels (taskmap validate) for every grasp,
  /// else kEpsilon. Resolved at construction (TaskMap::options()).
  kAuto,
  kEpsilon,  ///< the grasp's Ferrari-Canny epsilon (the paper)
  /// epsilon x hold margin: 0 for a grasp that does not hold; for one that holds
  /// min(1 - d / d_max, 1 - a / a_max) of the object's largest displacement d (m) and rotation a
  /// (rad) in the hold test, with the test's limits d_max, a_max (/validation params_json).
  /// Needs hold labels for every grasp.
  kHoldMargin,
};

/// "auto", "epsilon", "hold_margin".
const char* toString(SampleWeight weight);
/// Parses a sample weight name; throws Error listing the valid names on an unknown one.
SampleWeight sampleWeightFromString(const std::string& name);

/// Options of TaskMap; unset optionals take documented defaults derived from the map.
struct TaskMapOptions {
  IndexKind index = IndexKind::kExactKdTree;
  int trees = 4;     ///< randomized forest: number of trees (>= 1)
  int checks = 256;  ///< randomized forest: leaves checked per nearest/knn query (>= 1)
  /// w_p of W_map in 1/m^2 (> 0).
  double linear_weight = 1.0;
  /// w_r of W_map in 1/rad^2 (> 0); default rho^2 * w_p (docs/METHOD.md §4).
  std::optional<double> angular_weight;
  /// sigma_p of the quality Gaussians, metres (> 0). Default: bandwidth_factor times the
  /// median nearest-neighbour pose distance between map samples (the sampling density).
  std::optional<double> position_sigma;
  /// sigma_r of the quality Gaussians, radians (> 0): the rotation part of the kernel is
  /// (2 sin(theta/2))^2 / sigma_r^2 (criteria.hpp). Default: sigma_p / rho, so that the kernel
  /// is isotropic in the pose metric (Mahalanobis distance = (pose distance / sigma_p)^2).
  std::optional<double> rotation_sigma;
  double bandwidth_factor = 1.0;  ///< scales the default sigma_p (> 0)
  QualityMode quality_mode = QualityMode::kTruncated;
  /// What weighs each sample in the quality criterion (default: hold margin when the map is
  /// fully validated, else epsilon).
  SampleWeight sample_weight = SampleWeight::kAuto;
  /// Truncated mode: bound on the omitted mixture value RELATIVE to the peak density 1/Z,
  /// in (0, 1). The absolute bound tol / Z * (omitted weight / total weight) is reported.
  double quality_tolerance = 1e-3;
  /// Worker threads of the batch functions (0: std::thread::hardware_concurrency()).
  int threads = 0;
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
};

/// One neighbour: grasp index into TaskMapData::grasps and its pose distance (metres).
struct Neighbor {
  std::size_t index = 0;
  double distance = 0.0;
};

/// Proximity criterion (eq. 1.18-1.19) against the nearest sample.
struct ProximityResult {
  double value = 0.0;                ///< g_p = e^T W_map e
  Twist gradient = Twist::Zero();    ///< dg_p/dx, object frame
  Neighbor nearest;                  ///< the sample x_map
  Twist difference = Twist::Zero();  ///< e = (p - p_map, log(R_map^T R))
};

/// Quality criterion (eq. 1.20-1.21) with its analytic gradient.
struct QualityCriterion {
  double value = 0.0;              ///< g_q = -sum w_i f_i / sum w_i (0 if all weights are 0)
  Twist gradient = Twist::Zero();  ///< dg_q/dx, object frame
  /// |g_q(truncated) - g_q(exact)| <= value_bound (0 in exact mode). Rigorous: the kernel's
  /// Mahalanobis distance is a weighted squared embedding distance with weights 1/sp^2 and
  /// 1/(rho sr)^2, so every omitted sample has d >= (embedding distance / s)^2 > t_c^2,
  /// s = max(sp, rho sr), t_c = cutoffRadius() / s.
  double value_bound = 0.0;
  /// Euclidean norm of the omitted part of the gradient is <= gradient_bound.
  double gradient_bound = 0.0;
  std::size_t terms = 0;  ///< mixture terms summed
};

/// Everything the optimizer needs per iteration, from one index search.
struct Evaluation {
  ProximityResult proximity;
  QualityCriterion quality;
  /// g_p + g_q.
  double cost() const { return proximity.value + quality.value; }
  /// d(g_p + g_q)/dx, object frame.
  Twist gradient() const { return proximity.gradient + quality.gradient; }
};

/// N x 7 poses, one per row: x y z qw qx qy qz (object frame).
using PoseRows = Eigen::Matrix<double, Eigen::Dynamic, 7, Eigen::RowMajor>;
/// N x 6 gradients, one per row (linear, angular), object frame.
using TwistRows = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;

/// Batch results of evaluate over N poses (row i belongs to pose i).
struct BatchEvaluation {
  Eigen::VectorXd proximity;                               ///< g_p
  TwistRows proximity_gradient;                            ///< dg_p/dx
  Eigen::VectorXd quality;                                 ///< g_q
  TwistRows quality_gradient;                              ///< dg_q/dx
  Eigen::VectorXd quality_bound;                           ///< QualityCriterion::value_bound
  Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> nearest;  ///< grasp index of x_map
  Eigen::VectorXd nearest_distance;                        ///< metres
};

/// A loaded, indexed task map.
class TaskMap {
 public:
  /// Reads the map file (taskmap::readMap), validates it and builds the index. Throws Error
  /// naming the file for unreadable, corrupt or newer-schema files and invalid options.
  static TaskMap load(const std::string& path, const TaskMapOptions& options = {});
  /// Builds from a map in memory; validates what the queries rely on (pose rows, epsilon,
  /// cluster labels) and throws Error naming the first problem.
  static TaskMap fromData(TaskMapData data, const TaskMapOptions& options = {});

  TaskMap(TaskMap&&) noexcept;
  TaskMap& operator=(TaskMap&&) noexcept;
  ~TaskMap();

  /// The map data.
  const TaskMapData& data() const;
  /// Number of samples (grasps).
  std::size_t size() const;
  /// Number of clusters (0 if the map has no clustering).
  int numClusters() const;
  /// Options with every default resolved (sigmas, angular weight).
  const TaskMapOptions& options() const;
  /// rho of the map, metres per radian.
  double rotationScale() const;
  /// Cut-off radius (pose distance, metres) of the truncated quality mode.
  double cutoffRadius() const;
  /// Pose of sample i (canonical sign qw >= 0).
  Pose pose(std::size_t i) const;

  /// Nearest sample, optionally among the samples of one cluster (0..K-1). Throws Error for
  /// an unknown cluster or a map without clustering.
  Neighbor nearest(const Pose& x, std::optional<int> cluster = std::nullopt) const;
  /// The k nearest samples (fewer if the map/cluster is smaller), nearest first; k >= 1.
  std::vector<Neighbor> knn(const Pose& x, int k, std::optional<int> cluster = std::nullopt) const;
  /// Every sample within pose distance r (metres, inclusive), nearest first. Always exact.
  std::vector<Neighbor> radius(const Pose& x, double r,
                               std::optional<int> cluster = std::nullopt) const;

  /// Proximity criterion against the nearest sample (of the cluster, if given).
  ProximityResult proximity(const Pose& x, std::optional<int> cluster = std::nullopt) const;
  /// Quality criterion over the map (or one cluster's samples) in the given mode (default:
  /// options().quality_mode).
  QualityCriterion quality(const Pose& x, std::optional<int> cluster = std::nullopt,
                           std::optional<QualityMode> mode = std::nullopt) const;
  /// Nearest sample, proximity and quality with gradients, sharing one search (truncated mode:
  /// the samples within the cut-off give the mixture and, if there are any, the exact nearest;
  /// with none, a branch and bound finds the exact nearest, or with a randomized forest the
  /// forest's answer, as nearest() gives). Same nearest sample and distance as nearest().
  Evaluation evaluate(const Pose& x, std::optional<int> cluster = std::nullopt) const;

  /// evaluate() for every row of poses, on options().threads threads; identical to calling
  /// evaluate() row by row. Throws Error naming the first invalid row.
  BatchEvaluation evaluateBatch(const PoseRows& poses,
                                std::optional<int> cluster = std::nullopt) const;
  /// nearest() for every row; returns indices and writes distances if not null.
  Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> nearestBatch(
      const PoseRows& poses, Eigen::VectorXd* distances = nullptr,
      std::optional<int> cluster = std::nullopt) const;

 private:
  friend class EvaluationSession;  // reads the sample sets and criteria (evaluation_session.hpp)
  struct Impl;
  explicit TaskMap(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// Poses of an N x 7 matrix; throws Error naming the first row that is not a valid pose.
std::vector<Pose> posesFromRows(const PoseRows& rows);

}  // namespace taskmap
