#pragma once
// Private to grasp_sim: support points of large convex hull links (docs/METHOD.md §2, "Hull
// support cells"). GJK asks a hull shape for its support point many times per triangle; Bullet
// scans every hull point (102 for the Franka hand's palm). Here the directions are cut into
// cells of a cube map and each cell keeps, in index order, only the points that can be the
// support for some direction in it (by a bound with a margin far above rounding), so the scan
// over a cell returns the point Bullet's full scan returns, ties to the first index included.

#include <memory>
#include <vector>

#include <Eigen/Core>

namespace taskmap {

/// Candidate lists of a point set per cube-map direction cell (Bullet-free part).
class HullSupportCells {
 public:
  /// Cells per cube face edge.
  static constexpr int kCellsPerEdge = 16;
  /// Builds the lists for `points` (local frame). Empty points: no cells.
  explicit HullSupportCells(const std::vector<Eigen::Vector3d>& points);
  /// The candidates (indices into the points, ascending) of the cell holding direction `v`;
  /// null when `v` is zero or not finite (scan everything then).
  const std::vector<int>* cell(double x, double y, double z) const;
  /// Number of cells and the mean candidate count (for the bench and tests).
  std::size_t cellCount() const { return cells_.size(); }
  double meanCandidates() const;

 private:
  std::vector<std::vector<int>> cells_;  // 6 faces x kCellsPerEdge^2
};

/// Test access: a Bullet hull shape and the indexed hull shape built from the same points,
/// asked for the support point of a direction through the path GJK uses.
class HullSupportCheck {
 public:
  explicit HullSupportCheck(const std::vector<Eigen::Vector3d>& points);
  ~HullSupportCheck();
  /// Bullet's full scan (btConvexHullShape).
  Eigen::Vector3d scan(const Eigen::Vector3d& dir) const;
  /// The cell scan (the indexed shape the collision scene uses).
  Eigen::Vector3d indexed(const Eigen::Vector3d& dir) const;
  /// The indexed shape's virtual support (what the culling planes ask).
  Eigen::Vector3d indexedVirtual(const Eigen::Vector3d& dir) const;
  /// Bullet's virtual support.
  Eigen::Vector3d scanVirtual(const Eigen::Vector3d& dir) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> d_;
};

}  // namespace taskmap
